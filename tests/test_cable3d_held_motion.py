"""A cable3d end driven by a table (issue 12, item 4): its velocity at the table's rows, a run
that does not depend on how the steps were batched, and a first-order scheme that starts with
a moving end (studies/chains found each of these broken on the MoorDyn chain decks: the same
run gave fairlead tensions 25 kN apart, and the first-order scheme could not start)."""
from __future__ import annotations

from pathlib import Path

import casadi as ca
import numpy as np
import pytest

from symcable.api.cable3d_static import cable3d_mechanism
from symcable.scene import load_scene
from symcable.solvers.equilibrium import solve_equilibrium
from symcable.solvers.integrate import integrate
from symcable.solvers.options import GeneralizedAlpha, GeneralizedAlphaFirstOrder

#: ../shared beside the repository: the MoorDyn chain tests' decks and heave tables
REF = Path(__file__).resolve().parents[2] / "shared" / "reference" / "moordyn-chains"
pytestmark = pytest.mark.skipif(not REF.is_dir(), reason="reference decks not present")


def _chain(friction: float | None = None):
    """WD0050 (41 segments, BA/-zeta = -1) with the A1 heave table on its vessel end."""
    d = load_scene(REF / "WD0050_Chain.txt").to_dict()
    d["end_b"]["motion"] = {"kind": "table", "file": str(REF / "ZZP1_A1.txt")}
    if friction is not None:
        d["seabed"]["friction"] = friction
    return cable3d_mechanism(load_scene(d))


def test_table_velocity_is_one_value_at_a_row():
    """At a row, the end's velocity is the mean of the slopes either side, and the same a few
    ulps of t either side of it (the derivative of the interpolant gave the left slope, the
    right one or their mean by the rounding of t); between rows, the interval's slope."""
    from symcable.models.common.elements import held_end

    d = load_scene(REF / "WD0050_Chain.txt").to_dict()
    d["end_b"]["motion"] = {"kind": "table", "file": str(REF / "ZZP1_A1.txt")}
    end = load_scene(d).end_b
    t = ca.SX.sym("t")
    x, v = held_end(end, ca.DM.zeros(3), 1.0, t)
    fx, fv = ca.Function("x", [t], [x]), ca.Function("v", [t], [v])
    rows = np.loadtxt(REF / "ZZP1_A1.txt")
    k = 120  # t = 2.0 s, a row where the slope changes
    tk = rows[k, 0]
    left = (rows[k, 3] - rows[k - 1, 3]) / (rows[k, 0] - rows[k - 1, 0])
    right = (rows[k + 1, 3] - rows[k, 3]) / (rows[k + 1, 0] - rows[k, 0])
    assert abs(right - left) > 1e-2  # a real kink: 0.079 m/s
    ulp = np.spacing(tk)
    for dt in (-4 * ulp, 0.0, 4 * ulp):
        assert float(fv(tk + dt)[2]) == pytest.approx(0.5 * (left + right), abs=1e-8)
    assert float(fv(tk + 0.03)[2]) == pytest.approx(right, abs=1e-12)
    assert float(fv(tk - 0.03)[2]) == pytest.approx(left, abs=1e-12)
    # the position is the linear interpolation, exactly
    for tt in (tk, tk + 0.03, tk - 0.07):
        assert float(fx(tt)[2]) == pytest.approx(np.interp(tt, rows[:, 0], rows[:, 3]), abs=1e-12)


def test_run_does_not_depend_on_the_batching():
    """The same run saved every step and every third step (its steps chained in batches of
    1 and 3, so the times of the steps that land on the table's rows round differently):
    the same fairlead force, to the Newton tolerance. With the end's velocity taken from the
    derivative of the interpolant the two differed by 7.2 kN within 3 s (measured), and a
    run's batching follows its wall time, so two identical runs did not agree."""
    mech = _chain(friction=0.0)
    eq = solve_equilibrium(mech)
    runs = [integrate(mech, 3.0, 0.05, t0=-10.0, start=eq, method=GeneralizedAlpha(),
                      save_every=k, codegen=False) for k in (1, 3)]
    a, b = (np.linalg.norm(r.outputs["end_force_b"], axis=-1) for r in runs)
    np.testing.assert_allclose(runs[0].time[::3], runs[1].time, atol=1e-12)
    # force scale ~1e6 N, Newton tolerance 1e-10 of it: 1 N is far above round-off and far
    # below the 7.2 kN the bug gave
    assert np.max(np.abs(a[::3] - b)) < 1.0


def test_the_first_order_scheme_starts_with_a_moving_end():
    """The element at a moving held end turns with it, so the mass depends on t as well as
    q (the Mechanism's mass is an expression of (q, t, p)); the first-order generalized-alpha's
    start (M^-1 f at t0) takes t (before, CasADi refused the mass Function: 't is free')."""
    mech = _chain(friction=0.0)  # (the deck's friction at the default regularisation is stiff)
    assert ca.depends_on(ca.vec(mech.mass), mech.t)  # the end element's added mass turns
    assert ca.depends_on(ca.vec(mech.mass), mech.q)  # and follows the line
    eq = solve_equilibrium(mech)
    tr = integrate(mech, 0.5, 0.05, t0=-10.0, start=eq, codegen=False,
                   method=GeneralizedAlphaFirstOrder())
    assert tr.status == "converged"
    # from the static state (the table starts at full heave speed: the force jumps by the
    # material damping of the top segment at t0, not checked here) to a finite run
    np.testing.assert_array_equal(tr.q[0], eq.q)
    assert np.all(np.isfinite(tr.q)) and tr.time[-1] == pytest.approx(-9.5)


def test_table_is_held_outside_its_rows_and_costs_the_same_at_any_length(tmp_path):
    """Before the first row and after the last the end holds the row's displacement at zero
    velocity; in between, the linear interpolation. The table is a lookup in the graph (two
    CasADi interpolants): its instructions do not grow with the rows (a sum of ramps over the
    rows cost about ten per row: 3,444 for the 301-row heave table)."""
    from symcable.models.common.elements import held_end

    def held(n):
        tk = np.linspace(0.0, 10.0, n)
        rows = np.column_stack([tk, np.sin(tk), 0.5 * tk, np.cos(tk)])
        path = tmp_path / f"t{n}.txt"
        np.savetxt(path, rows)
        d = {"model": "cable3d", "line_types": {"c": {"EA": 1e7, "mass": 10.0,
                                                      "diameter": 0.05}},
             "sections": [{"type": "c", "length": 20.0, "segments": 4}],
             "end_a": {"condition": "pinned", "position": [0.0, 0.0, -10.0]},
             "end_b": {"condition": "pinned", "position": [15.0, 0.0, 0.0],
                       "motion": {"kind": "table", "file": str(path)}}}
        t = ca.SX.sym("t")
        x, v = held_end(load_scene(d).end_b, ca.DM.zeros(3), 1.0, t)
        return rows, ca.Function("f", [t], [x, v])

    rows, f = held(41)
    for tt, r in ((-3.0, rows[0]), (25.0, rows[-1])):
        x, v = (np.ravel(a) for a in f(tt))
        np.testing.assert_allclose(x, r[1:], atol=1e-12)
        np.testing.assert_allclose(v, 0.0, atol=1e-12)
    for tt in (0.1, 3.33, 9.99):
        x, v = (np.ravel(a) for a in f(tt))
        want = [np.interp(tt, rows[:, 0], rows[:, c]) for c in (1, 2, 3)]
        np.testing.assert_allclose(x, want, atol=1e-12)
        assert v[1] == pytest.approx(0.5, abs=1e-9)  # the y column's slope
    assert held(11)[1].n_instructions() == held(1001)[1].n_instructions()
