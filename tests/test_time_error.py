"""The run error estimate of generalized-alpha (``stats["error_estimate"]``) on a toy: reported
for both schemes with fixed and adapted steps (None with RK4), the same whichever steps are
saved, a warning with the dt that should do when it exceeds 1 %, and the leaky sum it is made
of. The estimate against the true error is studies/time_error (tests/test_study_time_error.py)."""
from __future__ import annotations

import math
import re

import numpy as np
import pytest

from symcable.models.toys.toys import duffing
from symcable.solvers.integrate import ERROR_TARGET, accurate_dt, integrate
from symcable.solvers.march import leaky_sum
from symcable.solvers.options import RK4, GeneralizedAlpha, GeneralizedAlphaFirstOrder

P = 2 * math.pi / 1.2  # the Duffing toy's forcing period, s


@pytest.fixture(scope="module")
def mech():
    return duffing(damping=1.0)


@pytest.mark.parametrize("method", [GeneralizedAlphaFirstOrder(), GeneralizedAlpha()])
def test_estimate_reported_and_independent_of_saving(mech, method):
    runs = [integrate(mech, 4 * P, P / 50, method=method, period=P, codegen=False, **kw)
            for kw in ({}, {"save_every": 7}, {"save_times": [1.0, 4 * P]}, {"max_samples": 5})]
    est = [r.stats["error_estimate"] for r in runs]
    assert 0 < est[0] < ERROR_TARGET and not runs[0].warnings
    np.testing.assert_allclose(est, est[0], rtol=1e-9)
    np.testing.assert_allclose([r.stats["motion_range"] for r in runs], runs[0].stats["motion_range"],
                               rtol=1e-9)
    st = runs[0].stats
    assert st["error_memory"] == pytest.approx(P / (2 * math.pi))
    assert st["error_estimate_scaled"] == pytest.approx(est[0] * st["motion_range"])
    assert st["dt_accurate"] == pytest.approx(accurate_dt(st["dt"], est[0]))
    # adapted steps report it too (their step control is unchanged)
    ad = integrate(mech, 4 * P, P / 50, method=method, period=P, tol=1e-6, codegen=False)
    assert 0 < ad.stats["error_estimate"] < est[0] and ad.stats["dt_accurate"] is None


@pytest.mark.parametrize("method", [GeneralizedAlphaFirstOrder(), GeneralizedAlpha()])
def test_coarse_run_warns_with_a_step(mech, method):
    r = integrate(mech, 4 * P, P / 8, method=method, period=P, codegen=False)
    est = r.stats["error_estimate"]
    assert r.status == "converged" and est > ERROR_TARGET
    assert len(r.warnings) == 1 and "too coarse" in r.warnings[0]
    assert f"about {100 * est:.2g} %" in r.warnings[0] and "(dt = " in r.warnings[0]
    # the step it suggests: a whole number of steps per period, at most dt_accurate
    n = int(re.search(r"= T/(\d+) should bring it under 1 %", r.warnings[0]).group(1))
    assert P / n <= r.stats["dt_accurate"] < P / (n - 1)
    # which, run, meets the target (the estimate falls at least as dt^2)
    ok = integrate(mech, 4 * P, P / n, method=method, period=P, codegen=False)
    assert ok.stats["error_estimate"] < ERROR_TARGET and not ok.warnings
    # without a period, the suggestion is in seconds only
    r2 = integrate(mech, 4 * P, P / 8, method=method, codegen=False)
    assert f"dt <= {r2.stats['dt_accurate']:.3g} s should" in r2.warnings[0]


def test_rk4_has_no_estimate(mech):
    r = integrate(mech, 2 * P, P / 50, method=RK4(), period=P, codegen=False)
    assert r.stats["error_estimate"] is None and "error_memory" not in r.stats


def test_period_is_checked(mech):
    with pytest.raises(Exception, match="period = -1"):
        integrate(mech, P, P / 10, method=GeneralizedAlpha(), period=-1, codegen=False)


@pytest.mark.parametrize("a", [0.0, 1e-3, 0.5, 40.0])
def test_leaky_sum_is_the_recursion(a):
    d = np.random.default_rng(1).random(700)
    want, E = [], 0.3
    for x in d:
        E = math.exp(-a) * E + x
        want.append(E)
    np.testing.assert_allclose(leaky_sum(0.3, d, a), want, rtol=1e-12)
