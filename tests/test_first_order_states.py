"""A Mechanism with a first-order state (``Mechanism.rest``; issue 12, the seabed friction's
bristles use it): a mass m on a spring k1 beside a Maxwell element (spring k2 in series with
a dashpot c, the dashpot's end at s), loaded by F:

    m x'' = F - k1 x - k2 (x - s),    s' = k2 (x - s) / c,

whose statics (s' = 0: the rest row k2 (s - x) = 0) are x = s = F / k1. Checked: the static
solve, the sensitivity dx/dF = 1 / k1, a run from rest that creeps to the static state (the
standard linear solid's relaxation), the modes (the Maxwell element relaxed: sqrt(k1 / m))
and the refusal of rest rows where there is no first-order state."""
from __future__ import annotations

import math

import casadi as ca
import numpy as np
import pytest

from symcable.errors import SymcableError
from symcable.mechanism.mechanism import (Layout, Mechanism, Output, ParamBlocks, PartLayout,
                                          Scales, Start)
from symcable.solvers.equilibrium import solve_equilibrium
from symcable.solvers.integrate import integrate
from symcable.solvers.linearize import mechanism_modes, output_sensitivity
from symcable.solvers.options import GeneralizedAlphaFirstOrder

M, K1, K2, C, F0 = 2.0, 100.0, 300.0, 50.0, 10.0


def _solid(rest=True) -> Mechanism:
    q, v = ca.SX.sym("q", 2), ca.SX.sym("v", 1)
    x, s = q[0], q[1]
    t, z = ca.SX.sym("t"), ca.SX.sym("z", 0)
    params = ParamBlocks(("force",), (1,), np.array([F0]))
    p = ca.SX.sym("p", 1)
    idx = np.zeros((1, 1), dtype=int)
    return Mechanism(
        name="solid", q=q, v=v, z=z, t=t, p=p, params=params, mass=M * ca.SX.eye(1),
        force=ca.reshape(p[0] - K1 * x - K2 * (x - s), 1, 1), constraint=ca.SX.zeros(0, 1),
        kinematics=ca.vertcat(v, K2 * (x - s) / C),
        rest=ca.reshape(K2 * (s - x), 1, 1) if rest else None,
        scales=Scales(q=np.full(2, 0.1), v=np.ones(1), z=np.zeros(0), force=F0, mass=M),
        starts=lambda: [Start(np.zeros(2), np.zeros(0), params.values, "zero")],
        outputs={"x": Output(x, "m", "solid", "position")},
        layout=Layout(1, {"solid": PartLayout("point", np.zeros(1), idx, idx)}),
        stability_coordinates=np.array([0]))


def test_statics_with_a_first_order_state():
    """x = s = F / k1 to the solver's tolerance (1e-9 of F over k1); dx/dF exact; the
    stiffness judged with s following x through its rest row (the Schur complement
    k1 + k2 - k2 k2 / k2) is k1."""
    mech = _solid()
    eq = solve_equilibrium(mech)
    assert eq.q == pytest.approx([F0 / K1, F0 / K1], abs=1e-9 * F0 / K1 * 10)
    assert eq.stats["stable"] is True
    assert eq.stats["min_stiffness"] == pytest.approx(K1, rel=1e-12)
    dxdF = output_sensitivity(mech, eq, "x", "force")
    assert float(dxdF[0, 0]) == pytest.approx(1.0 / K1, rel=1e-12)


def test_run_relaxes_to_the_static_state():
    """From rest at x = s = 0 with F applied: the first-order scheme's run ends at F / k1
    (after 40 relaxation times c (k1 + k2) / (k1 k2) = 0.67 s, the transient is e^-40;
    1e-6 m: the Newton tolerance of the steps)."""
    mech = _solid()
    tr = integrate(mech, 30.0, 0.01, q0=np.zeros(2), v0=np.zeros(1), p=mech.params.values,
                   method=GeneralizedAlphaFirstOrder(rho_inf=0.5))
    assert tr.status == "converged"
    assert float(np.ravel(tr.outputs["x"])[-1]) == pytest.approx(F0 / K1, abs=1e-6)


def test_modes_with_the_state_relaxed():
    """About rest the Maxwell element carries no static load and its state follows the
    velocity (G = [1, 0]^T at rest, H = -k2/c on s): the state matrix's oscillating pair is
    that of m on k1 + k2 damped by the dashpot; undamped reading: between sqrt(k1/m) and
    sqrt((k1 + k2)/m) rad/s."""
    mech = _solid()
    eq = solve_equilibrium(mech)
    modes = mechanism_modes(mech, eq, 1)
    w = 2 * math.pi * float(modes.frequencies[0])
    assert math.sqrt(K1 / M) * 0.999 < w < math.sqrt((K1 + K2) / M) * 1.001


def test_rest_rows_need_first_order_states():
    """Rest rows on a mechanism whose q all have velocities: refused at construction."""
    q, v = ca.SX.sym("q", 1), ca.SX.sym("v", 1)
    with pytest.raises(SymcableError, match="rest rows"):
        Mechanism(name="bad", q=q, v=v, z=ca.SX.sym("z", 0), t=ca.SX.sym("t"), p=ca.SX.sym("p", 0),
                  params=ParamBlocks(), mass=ca.SX.eye(1), force=-q, constraint=ca.SX.zeros(0, 1),
                  rest=ca.reshape(q, 1, 1),
                  scales=Scales(q=np.ones(1), v=np.ones(1), z=np.zeros(0), force=1.0),
                  starts=tuple)
