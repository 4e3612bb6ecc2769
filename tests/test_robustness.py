"""Fixes of errors found by trying symcable as a user would (issue 11, item 5): each bad or
edge-case input gets a result or one clear message, never a deep traceback or a NaN passed
off as converged."""
from __future__ import annotations

import math

import casadi as ca
import numpy as np
import pytest

import symcable as sc
from symcable.linalg.sparse import norm_inf
from symcable.models.toys import toys
from symcable.solvers.galpha1 import galpha1_kernel, step_scales
from symcable.solvers.options import GeneralizedAlphaFirstOrder

CHAIN = {"mass": 100.0, "diameter": 0.1, "EA": 1e8}


def _line(segments=10, end_b=None, line_type=None, length=33.0):
    return {"line_types": {"c": dict(line_type or CHAIN)},
            "sections": [{"type": "c", "length": length, "segments": segments}],
            "end_a": {"condition": "pinned", "position": [0.0, 0.0]},
            "end_b": end_b or {"condition": "pinned", "position": [25.0, -15.0]}}


def test_one_segment_line_runs_every_analysis():
    """segments = 1: the per-segment outputs of the dynamics are (n, 1), not scalars (the
    periodic result used to fail in a reshape)."""
    # taut (33.01 m between the ends of a 33 m line): one straight segment cannot hang slack
    scene = _line(1, {"condition": "pinned", "position": [33.0, -0.8],
                      "motion": {"amplitude": [0.05, 0.0], "period": 10.0}})
    st = sc.solve_static(scene, codegen=False)
    assert st.strain.shape == (1,)
    # the ends carry the weight: with one segment the node tension output had 3 entries
    # for 2 nodes (a 1 x 1 SX sliced [:-1] is 1 x 0), which shifted every output after it
    # (the end forces came out as (-W/2, 0) instead of (0, -W/2)); found by studies/fuzz
    weight = 33.0 * (100.0 - 1025.0 * np.pi / 4 * 0.1 ** 2) * 9.80665
    assert -(st.anchor_force[1] + st.fairlead_force[1]) == pytest.approx(weight, rel=1e-9)
    assert st.tension.shape == (2,)
    per = sc.solve_periodic(scene, "shooting", codegen=False)
    assert per.tension_max.shape == (2,)  # on the two nodes
    tr = sc.simulate(scene, 10.0, 0.1, codegen=False)
    assert np.all(np.isfinite(tr.fairlead_tension))


def test_neutral_line_with_unloaded_free_end_is_refused():
    """Weight zero (mass = displaced water, to round-off), a free end without force, no
    current: the shape is undetermined; one SceneError naming the key (was a bare
    StopIteration, then a 'too stiff' message about a load of 5e-13 N)."""
    neutral = dict(CHAIN, mass=1025.0 * math.pi / 4 * 0.1 ** 2)
    with pytest.raises(sc.SceneError, match=r"end_b\.condition = 'free'.*undetermined"):
        sc.load_scene(_line(5, {"condition": "free"}, neutral))
    # with a force on the free end the line is loaded: solved, the force passed through
    s = sc.solve_static(_line(5, {"condition": "free", "force": [1000.0, 0.0]}, neutral),
                        codegen=False)
    assert s.fairlead_tension == pytest.approx(1000.0, rel=1e-9)


def test_weightless_slack_cable_is_refused():
    """No weight, no bending, no current and the ends closer than the length: any slack
    shape is an equilibrium, so the scene is refused (it 'converged' at 32 MN of
    compression before)."""
    neutral = dict(CHAIN, mass=1025.0 * math.pi / 4 * 0.1 ** 2)
    with pytest.raises(sc.SceneError, match=r"end_b\.position.*no determined shape"):
        sc.load_scene(_line(5, None, neutral))


def test_build_model_takes_what_load_scene_takes():
    d = _line(4)
    assert sc.build_model(d).n_w == sc.build_model(sc.load_scene(d)).n_w
    assert sc.build_dynamic_model(d).n_y > 0


def test_norm_inf_is_nan_for_a_nan_entry():
    """CasADi's norm_inf skips NaN (fmax): a NaN residual measured 0 and passed any
    tolerance; ours is not finite (inf or NaN)."""
    x = ca.SX.sym("x", 3)
    f = ca.Function("f", [x], [norm_inf(x), ca.norm_inf(x)])
    ours, casadis = (float(v) for v in f([1.0, float("nan"), -2.0]))
    assert not math.isfinite(ours) and casadis == 2.0
    assert float(f([1.0, -3.0, 2.0])[0]) == 3.0


def test_galpha_judges_its_last_iterate():
    """With one Newton iteration allowed on a linear system, the single correction is large
    (it is the whole step) but lands on the solution: the step must count as converged by
    its last iterate's residual (it was reported as failed, 'residual 2.85e-14')."""
    mech = toys.duffing(cubic=0.0)  # linear: the first Newton iterate is the solution
    opts = GeneralizedAlphaFirstOrder(max_iter=1)
    kern = galpha1_kernel(mech, opts)
    ny = mech.n_q + mech.n_v
    y0 = np.array([0.3, -0.2])
    x0 = np.concatenate([y0, np.zeros(ny)])
    x1, err, _, _, failed = kern(x0, 0.0, 0.01, mech.params.values,
                                 [opts.rho_inf, opts.tol], step_scales(mech))
    assert float(failed) == 0.0 and float(err) <= opts.tol


def test_no_raw_casadi_warnings_from_a_nan_iterate(capfd):
    """A square system whose Newton iterate leaves the domain (sqrt of a negative): CasADi
    printed 'NaN detected for output ...' to stderr from inside periodic solves. The solver
    reports the failure in its result, and nothing reaches stderr."""
    from symcable.solvers.periodic_common import SquareSystem

    w, P = ca.MX.sym("w"), ca.MX.sym("P")
    sys_ = SquareSystem("nan_probe", ca.Function("r", [w, P], [ca.sqrt(w) - P]))
    out = sys_.solve(np.array([-1.0]), np.array([2.0]), solver="newton", tol=1e-10, max_iter=5)
    assert not out["residual"] <= 1e-10  # not converged (NaN or large), and said so
    assert "NaN detected" not in capfd.readouterr().err
