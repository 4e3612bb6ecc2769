"""Every static answer carries its discretisation error (symcable.api.static_error).

The reference for a slack chain standing up from the seabed is MoorPy's exact elastic
catenary with seabed (a line of the same weight, EA and length between the same ends); the
reference for a smooth suspended line is the same line at 16 times the segments.
"""
import math

import pytest

import symcable as sc
from symcable.errors import SymcableError
from symcable.scene import scene_to_dict
from test_cable3d_points import _two_lines as _points_scene

W = 698.094          # N/m, OC3's chain, submerged
DEPTH = 100.0        # m


def _slack(n: int, model: str = "planar") -> dict:
    """OC3's chain, 400 m between an anchor on the bed and a point 95 m above it, 150 m
    away: most of it piled on the bed, the rest standing straight up (a corner at the
    touchdown: the error depends on where the corner falls within a segment)."""
    d = scene_to_dict(sc.load_scene("oc3"))
    d["sections"][0].update(length=400.0, segments=n)
    d["environment"]["depth"] = DEPTH
    d["end_b"].pop("motion", None)
    if model == "planar":
        d["end_a"]["position"], d["end_b"]["position"] = [0.0, -DEPTH], [150.0, -5.0]
    else:
        d["model"] = "cable3d"
        d["environment"]["current"] = [0.0, 0.0, 0.0]
        d["end_a"]["position"], d["end_b"]["position"] = [0.0, 0.0, -DEPTH], [150.0, 0.0, -5.0]
    return d


@pytest.fixture(scope="module")
def moorpy_slack():
    """MoorPy's fairlead and anchor tensions of :func:`_slack`, N."""
    mp = pytest.importorskip("moorpy")
    ms = mp.System(depth=DEPTH)
    ms.setLineType(name="c", mass=W / 9.80665 + 1025.0 * math.pi * 0.09 ** 2 / 4.0, d_vol=0.09,
                   EA=3.84243e8, w=W, dnommm=90.0)
    ms.addPoint(1, [0.0, 0.0, -DEPTH])
    ms.addPoint(1, [150.0, 0.0, -5.0])
    ms.addLine(400.0, "c", nSegs=40, pointA=1, pointB=2)
    ms.initialize()
    ms.solveEquilibrium()
    line = ms.lineList[0]
    return line.TB, line.TA


def _true(sol, ref) -> float:
    tb, ta = ref
    return max(abs(sol.fairlead_tension - tb), abs(sol.anchor_tension - ta)) / max(ta, tb)


@pytest.mark.parametrize("model", ["planar", "cable3d"])
def test_slack_corner_is_warned_with_its_size(model, moorpy_slack):
    """At 80 segments the standing chain is about 2 % off MoorPy (the corner's segment is
    5 m of chain, 3.5 kN, 5 % of the tension): the answer warns, and its estimate is within
    a factor of 3 of the true error (the issue's bound; the estimate is the corner's half
    segment weight or the Richardson difference, whichever is larger)."""
    sol = sc.solve_static(_slack(80, model))
    true = _true(sol, moorpy_slack)
    assert true > 0.01
    est = sol.stats["discretisation_error"]["max_relative"]
    assert true / 3 <= est <= 3 * true, (est, true)
    msg = [w for w in sol.warnings if "discretisation error" in w]
    assert len(msg) == 1 and "segments would bring it under 1 %" in msg[0], sol.warnings
    assert "discretisation" in sol.summary()


def test_accuracy_refines_until_met(moorpy_slack):
    """accuracy=0.01 adds segments until the estimate is under 1 %; the answer is then
    within 1 % of MoorPy (the estimate bounds the corner's error from above)."""
    sol = sc.solve_static(_slack(40), accuracy=0.01)
    rep = sol.stats["discretisation_error"]
    assert rep["rounds"] >= 1 and rep["segments"]["line"] > 40
    assert rep["max_relative"] <= 0.01
    assert _true(sol, moorpy_slack) <= 0.01
    assert not [w for w in sol.warnings if "discretisation error" in w]


def test_smooth_line_estimate_tracks_the_error():
    """seed 001's line hangs clear of the seabed (smooth, second order): the Richardson
    estimate at 50 segments against 25 equals the change to 800 segments within 20 %
    (second-order convergence holds to that on this line), and nothing warns."""
    sol = sc.solve_static("seed001")
    d = scene_to_dict(sc.load_scene("seed001"))
    d["sections"][0]["segments"] *= 16
    fine = sc.solve_static(d, estimate=False)
    true = max(abs(sol.fairlead_tension - fine.fairlead_tension),
               abs(sol.anchor_tension - fine.anchor_tension))
    e = sol.stats["discretisation_error"]["lines"]["line"]
    assert e["order"] == 2
    assert 0.8 * true <= e["error"] <= 1.25 * true, (e, true)
    assert not [w for w in sol.warnings if "discretisation error" in w]


def _two_lines(n: int) -> dict:
    """tests/test_cable3d_points.py's two lines meeting at a free buoy (an anchor chain
    partly on the seabed, a rope up to a vessel point), ``n`` segments a line."""
    d = _points_scene()
    for line in d["lines"]:
        line["sections"][0]["segments"] = n
    return d


def test_system_reports_each_line():
    """A scene of several lines reports each line's estimate. Against the same scene at 160
    segments a line, the estimate never falls below a third of the true error at 5, 10 or
    20 segments (it may exceed it: at such coarse meshes the convergence is irregular, 2.2
    kN, 0.43 kN, 9 N on the chain, and Richardson's second order overstates the last), and
    at 40 segments nothing warns. The summary lists each line."""
    fine = sc.solve_static(_two_lines(160), estimate=False)
    for n in (5, 10, 20, 40):
        sol = sc.solve_static(_two_lines(n))
        rep = sol.stats["discretisation_error"]
        assert set(rep["lines"]) == {"lower", "upper"}
        for name, e in rep["lines"].items():
            a, b = sol.lines[name], fine.lines[name]
            true = max(abs(a.fairlead_tension - b.fairlead_tension),
                       abs(a.anchor_tension - b.anchor_tension))
            assert e["error"] >= true / 3, (n, name, e, true)
    assert not [w for w in sol.warnings if "discretisation error" in w]
    text = sol.summary()
    assert "error lower" in text and "error upper" in text


@pytest.mark.parametrize("bad", [0.0, -0.01, 1.5, float("nan")])
def test_bad_accuracy_is_one_line(bad):
    with pytest.raises(SymcableError, match="accuracy = .*between 0 and 1"):
        sc.solve_static("oc3", accuracy=bad)


def test_estimate_off():
    sol = sc.solve_static("oc3", estimate=False)
    assert "discretisation_error" not in sol.stats
    with pytest.raises(SymcableError, match="accuracy needs the error estimate"):
        sc.solve_static("oc3", estimate=False, accuracy=0.01)
