"""Floquet multipliers (symcable.solvers.floquet) on toys with known answers.

- A linear damped oscillator m x'' + c x' + k x = F cos(w t): the monodromy of the exact flow
  is exp(A T), its multipliers exp(lambda T) with lambda = -c/2m +- i sqrt(k/m - (c/2m)^2),
  whatever the forcing. The period map is generalized-alpha's, second order: the multipliers
  differ from exp(lambda T) by O(h^2) (measured 3.0e-3, 7.5e-4, 1.9e-4, 4.7e-5 at 50, 100,
  200, 400 steps, a factor 4.00 per halving), so at 100 steps 1.5e-3 (twice the measured
  error), and the order between 100 and 200 steps within 0.1 of 2.
- The Duffing oscillator x'' + 0.1 x' + x + x^3 = cos(1.9 t) has three periodic solutions
  (first-harmonic balance: amplitudes 0.400, 1.646, 2.022); each found by harmonic balance
  and by collocation from its first-harmonic approximation. The middle one is a saddle (a
  real multiplier > 1), the other two stable. Liouville: det of the monodromy of the flow
  is exp(-c T / m) (the trace of the linearised vector field is -c/m everywhere), so the
  two multipliers' product is exp(-c T) on every branch; the discrete map's to 1e-3
  (its O(h^2) error at 200 steps: measured 2.1e-5, 8.5e-5, 1.2e-4 on the three).
"""
from __future__ import annotations

import math

import numpy as np
import pytest

from symcable.errors import SymcableError
from symcable.models.toys import toys
from symcable.results.periodic_generic import MechanismPeriodic
from symcable.solvers.floquet import STABILITY_MARGIN, floquet
from symcable.solvers.options import Collocation, HarmonicBalance, Shooting
from symcable.solvers.periodic_mech import solve_periodic_mech


def _exact(c, k, T):
    lam = -c / 2 + 1j * math.sqrt(k - c * c / 4)
    return np.exp(np.array([lam, lam.conjugate()]) * T)


def _distance(mu, ref):
    """Largest distance between two pairs of complex conjugates (matched by sorting)."""
    return float(np.max(np.abs(np.sort_complex(np.asarray(mu)) - np.sort_complex(ref))))


def test_linear_oscillator_multipliers():
    c, k, w = 0.2, 1.0, 1.2
    T = 2 * math.pi / w
    mech = toys.duffing(cubic=0.0, damping=c, stiffness=k, omega=w)
    errs = []
    for steps in (100, 200):
        per = solve_periodic_mech(mech, T, Shooting(steps=steps))
        f = floquet(mech, per)
        assert f.steps == steps and f.refinements == 0  # shooting's own state: exact already
        errs.append(_distance(f.multipliers, _exact(c, k, T)))
        assert f.stable and f.multipliers.size == 2
        assert f.dropped_max < 1e-8  # the integrator's memory (a, abar) damped away
    assert errs[0] < 1.5e-3
    assert abs(math.log2(errs[0] / errs[1]) - 2.0) < 0.1
    # from another method's solution: the same map at (nearly) the same state
    col = solve_periodic_mech(mech, T, Collocation())
    f = floquet(mech, col, steps=200)
    assert _distance(f.multipliers, _exact(c, k, T)) == pytest.approx(errs[1], rel=1e-3)
    st = f.stats()
    assert st["floquet_multipliers"].shape == (2, 2) and st["stable"] is True
    assert st["floquet_max"] == pytest.approx(math.exp(-c * T / 2), abs=1.5e-3)
    assert "stable: yes, largest Floquet multiplier |mu| = 0.592" in f.summary()


C, F, W = 0.1, 1.0, 1.9


def _branches():
    """First-harmonic amplitudes of the three solutions at (C, F, W), smallest first."""
    a = 1 - W * W
    roots = np.roots([0.5625, 1.5 * a, a * a + (C * W) ** 2, -F * F])
    return np.sqrt(np.sort(roots[(np.abs(roots.imag) < 1e-9) & (roots.real > 0)].real))


def _harmonic_start(mech, A, T, m=64):
    phi = math.atan2(C * W * A, (1 - W * W + 0.75 * A * A) * A)
    t = T * np.arange(m) / m
    q = A * np.cos(W * t - phi)[:, None]
    v = -A * W * np.sin(W * t - phi)[:, None]
    return MechanismPeriodic(mechanism=mech.name, period=T, time=t, q=q, v=v,
                             z=np.zeros((m, 0)), p=mech.params.values, outputs={},
                             method="harmonic-balance", status="converged")


@pytest.mark.parametrize("method", [HarmonicBalance(harmonics=9), Collocation(solver="newton")],
                         ids=["harmonic-balance", "collocation"])
def test_duffing_branches(method):
    mech = toys.duffing(damping=C, force=F, omega=W)
    T = 2 * math.pi / W
    amps = _branches()
    assert amps.size == 3 and amps[0] < 0.41 and 1.6 < amps[1] < 1.7 and amps[2] > 2.0
    seen = []
    for A in amps:
        per = solve_periodic_mech(mech, T, method, start=_harmonic_start(mech, A, T))
        f = floquet(mech, per, steps=200)
        seen.append((float(np.max(np.abs(per.q))), f))
        assert abs(np.prod(f.multipliers) - math.exp(-C * T)) < 1e-3
    peaks = [s[0] for s in seen]
    assert peaks[0] < peaks[1] < peaks[2]  # three distinct solutions
    low, mid, high = (s[1] for s in seen)
    assert low.stable and high.stable and not mid.stable
    assert mid.max_modulus > 2.0  # a saddle: one real multiplier well beyond 1
    assert abs(mid.multipliers[0].imag) < 1e-9 and mid.multipliers[0].real > 1 + STABILITY_MARGIN
    # stable branches: both multipliers on the circle of radius exp(-c T / 2) (a complex pair)
    for f in (low, high):
        assert np.allclose(np.abs(f.multipliers), math.exp(-C * T / 2), atol=1e-3)


def test_floquet_refuses_other_mechanism():
    mech = toys.duffing()
    per = solve_periodic_mech(mech, 2 * math.pi / 1.2, Shooting(steps=50))
    with pytest.raises(SymcableError, match="periodic solution of 1 coordinates"):
        floquet(toys.spring_chain(3), per)
    with pytest.raises(SymcableError, match="margin"):
        floquet(mech, per, margin=-1.0)
