"""sc.simulate on a scene of several lines and points (scene version 2): a buoy between two
ropes, the upper one moved at its fairlead; per-line results, point forces, save/load."""
from __future__ import annotations

import numpy as np
import pytest

import symcable as sc
from symcable.results.line3d import SystemTrajectory

T = 8.0


def _scene() -> dict:
    return {"model": "cable3d", "environment": {"depth": 50.0},
            "line_types": {"rope": {"mass": 30.0, "diameter": 0.06, "EA": 1e7, "damping": -0.5}},
            "points": {"anchor": {"kind": "fixed", "position": [0.0, 0.0, -50.0]},
                       "buoy": {"kind": "free", "position": [40.0, 0.0, -30.0], "mass": 100.0,
                                "volume": 0.5},
                       "fair": {"kind": "vessel", "position": [80.0, 0.0, -5.0],
                                "motion": {"kind": "harmonic", "period": T,
                                           "amplitude": [1.0, 0.5, 1.0], "phase_deg": [0, 0, 0]}}},
            "lines": [{"name": "lower", "end_a": "anchor", "end_b": "buoy",
                       "sections": [{"type": "rope", "length": 50.0, "segments": 8}]},
                      {"name": "upper", "end_a": "buoy", "end_b": "fair",
                       "sections": [{"type": "rope", "length": 50.0, "segments": 8}]}]}


def test_system_run_gives_each_line_and_point(tmp_path):
    tr = sc.simulate(_scene(), 2 * T, codegen=True)
    assert isinstance(tr, SystemTrajectory) and tr.status == "converged"
    assert set(tr.lines) == {"lower", "upper"} and set(tr.points) == {"anchor", "buoy", "fair"}
    up, lo = tr.lines["upper"], tr.lines["lower"]
    assert up.positions.shape == (tr.time.size, 9, 3)
    # the lines meet at the buoy, which carries both ends (round-off of one shared node)
    assert np.max(np.abs(up.positions[:, 0] - lo.positions[:, -1])) < 1e-9
    assert np.allclose(tr.points["buoy"]["position"], up.positions[:, 0], atol=1e-9)
    # the force on the fairlead point is the upper line's pull on its end B
    f = tr.points["fair"]["force"]
    assert np.allclose(f, up.fairlead_force, rtol=1e-9, atol=1e-6 * np.max(np.abs(f)))
    # at t = 0 the static solve's tensions (the run starts at rest from it)
    st = sc.solve_static(_scene())
    assert up.fairlead_tension[0] == pytest.approx(st.lines["upper"].fairlead_tension, rel=1e-8)
    back = SystemTrajectory.load(tr.save(tmp_path / "run.json"))
    assert np.array_equal(back.lines["lower"].axial_force, lo.axial_force)
    assert "line upper" in tr.summary()


def test_system_modes_and_stiffness():
    """Modes of the two ropes and the buoy: the generalized eigenvalues of linearize's K and M
    (scipy, to 1e-8); the fairlead point's stiffness is the central difference of the static
    force the lines exert on it (to 1e-4 of its largest entry: the difference's truncation
    error at 1 mm)."""
    import math

    import scipy.linalg

    d = _scene()
    modes = sc.modal_analysis(d, 4)
    lin = sc.linearize(d, undamped=True)
    w2 = scipy.linalg.eigh(0.5 * (lin.K + lin.K.T), lin.M, eigvals_only=True)
    np.testing.assert_allclose(modes.frequencies, np.sqrt(np.sort(w2[w2 > 0])[:4]) / (2 * math.pi),
                               rtol=1e-8)
    assert modes.shapes.shape == (4, 18, 3) and modes.stats["lines"] == {"lower": [0, 9],
                                                                         "upper": [9, 18]}
    assert "buoy.x" in lin.q_kinds and "upper.node4.z" in lin.q_kinds
    K = lin.end_stiffness["fair"]
    fd = np.zeros((3, 3))
    h = 1e-3
    for j in range(3):
        f = []
        for sgn in (1, -1):
            dd = _scene()
            dd["points"]["fair"]["position"][j] += sgn * h
            f.append(np.asarray(sc.solve_static(dd).points["fair"].force))
        fd[:, j] = -(f[0] - f[1]) / (2 * h)
    assert np.max(np.abs(K - fd)) < 1e-4 * np.max(np.abs(K))


def test_system_sweep_periodic_takes_the_moving_end():
    """sweep_periodic on two ropes and a buoy: by default the line ending at the moving
    point ("upper", end B); each period's series equals solve_periodic's at that period (the
    same solve, to round-off on the sweep's grid); a line that is not in the scene is one
    clear error."""
    d = _scene()
    for ln in d["lines"]:
        ln["sections"][0]["segments"] = 4
    opts = dict(intervals=40, solver="newton")
    sw = sc.sweep_periodic(d, [8.0, 10.0], "collocation", **opts)
    assert sw.status == "converged" and sw.stats["swept"] == "line upper, end B"
    per = sc.solve_periodic(d, "collocation", **opts)
    f = per.lines["upper"].fairlead_tension
    g = np.interp(sw.normalised_time * T, np.r_[per.time, T], np.r_[f, f[0]])
    np.testing.assert_allclose(sw.fairlead_tension[0], g, rtol=1e-8, atol=1e-6 * np.ptp(f))
    low = sc.sweep_periodic(d, [8.0], "collocation", line="lower", **opts)
    assert low.stats["swept"] == "line lower, end B"
    assert np.ptp(low.fairlead_tension[0]) < np.ptp(sw.fairlead_tension[0])
    with pytest.raises(sc.SymcableError, match="line = 'middle'"):
        sc.sweep_periodic(d, [8.0], line="middle")
