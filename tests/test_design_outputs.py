"""The design outputs (``LINE.fairlead_utilisation``, ``LINE.grounded_length``,
``LINE.anchor_uplift``, ``NAME.horizontal_force``) and their exact derivatives through a
line-type family's arithmetic; load cases and a callable scene in ``sc.optimize``; slopes
reused across load cases only where they hold."""
from __future__ import annotations

import copy
import math

import numpy as np
import pytest

import symcable as sc
from symcable.api.optimize import _apply
from symcable.api.sensitivity import design_sensitivity, grounded_length, static_values
from symcable.errors import SymcableError

HEADINGS = (180.0, 300.0, 60.0)


def mooring(v: dict, offset=(0.0, 0.0), segments: int = 8) -> dict:
    """Three studless chains from anchors at radius R_k to a held body's fairleads (5.2 m
    out, 70 m down) in 200 m of water; line k is R_k - 5.2 + s_k long."""
    points, lines, types = {}, [], {}
    for k, th in enumerate(HEADINGS):
        c, s = math.cos(math.radians(th)), math.sin(math.radians(th))
        R = v[f"R{k}"]
        types[f"chain{k}"] = {"family": "studless_chain", "nominal_diameter": v[f"d{k}"]}
        points[f"anchor{k}"] = {"kind": "fixed", "position": [R * c, R * s, -200.0]}
        lines.append({"name": f"line{k}", "end_a": f"anchor{k}",
                      "end_b": f"hull@[{5.2 * c}, {5.2 * s}, -70.0]",
                      "sections": [{"type": f"chain{k}", "length": R - 5.2 + v[f"s{k}"],
                                    "segments": segments}]})
    return {"name": "design", "model": "cable3d", "environment": {"depth": 200.0},
            "seabed": {"stiffness": 1e6}, "line_types": types, "points": points,
            "bodies": {"hull": {"kind": "fixed", "position": [offset[0], offset[1], 0.0]}},
            "lines": lines}


BASE = {"s0": 53.0, "s1": 90.0, "s2": 60.0, "d0": 0.1, "d1": 0.09, "d2": 0.11,
        "R0": 600.0, "R1": 550.0, "R2": 500.0}
NAMES = list(BASE)
OUTS = ["line0.fairlead_utilisation", "line0.grounded_length", "line2.grounded_length",
        "line0.anchor_uplift", "hull.horizontal_force"]


def sens(offset, reuse=None, outs=OUTS):
    def at(j, value):
        v = dict(BASE)
        v[NAMES[j]] = value
        return mooring(v, offset)
    return design_sensitivity(mooring(BASE, offset), None, outs, NAMES, list(BASE.values()),
                              [lambda value, j=j: at(j, value) for j in range(9)],
                              reuse=reuse, raw_of=lambda w: mooring(dict(zip(NAMES, w)),
                                                                    offset))


def test_outputs_and_derivatives_against_whole_solves():
    """At a 40 m offset line0 is lifted off its anchor (grounded length < 0, uplift > 0);
    every derivative equals central differences of whole solves (relative steps 1e-4 and
    2e-4) within 1e-5 of its row's largest entry or 3 times the differences' own change:
    the differences carry the static solve's tolerance (1e-9 of the force scale) over a
    step of 1e-4. The grounded length equals the static solution's own (its nodes on the
    bed) to within one segment, and -uplift / weight where lifted to 1e-4 (measured 9e-6:
    the smoothed contact's tail still carries nodes just above the bed)."""
    s = sens((40.0, 0.0))
    got = dict(zip(s.outputs, s.values))
    assert got["line0.grounded_length"] < 0 < got["line0.anchor_uplift"]
    w = sc.load_scene(mooring(BASE)).line_types["chain0"].weight
    assert got["line0.grounded_length"] == pytest.approx(-got["line0.anchor_uplift"] / w,
                                                         rel=1e-4)
    assert got["line2.grounded_length"] > 0
    sol = sc.solve_static(mooring(BASE, (40.0, 0.0)))
    seg = (BASE["R2"] - 5.2 + BASE["s2"]) / 8
    assert abs(sol.lines["line2"].grounded_length - got["line2.grounded_length"]) < seg
    mbl = sc.load_scene(mooring(BASE)).line_types["chain0"].breaking_load
    assert got["line0.fairlead_utilisation"] == pytest.approx(
        sol.lines["line0"].fairlead_tension / mbl, rel=1e-6)
    for j, name in enumerate(NAMES):
        fd = {}
        for k in (1, 2):
            h = k * 1e-4 * BASE[name]
            up, dn = (static_values(mooring({**BASE, name: BASE[name] + sg * h}, (40.0, 0.0)),
                                    OUTS) for sg in (1, -1))
            fd[k] = np.array([(up[o] - dn[o]) / (2 * h) for o in s.outputs])
        row = np.abs(s.jacobian).max(axis=1)
        allowed = np.maximum(1e-5 * row, 3 * np.abs(fd[1] - fd[2]))
        assert np.all(np.abs(s.jacobian[:, j] - fd[1]) <= allowed), (name, s.jacobian[:, j],
                                                                      fd[1])


def test_slopes_reused_only_where_they_hold():
    """Another offset of the same design takes the first case's slopes (its Jacobian equal
    to a fresh one's to 1e-12 of each row); slopes off by 0.1 % are not taken."""
    a = sens((0.0, 0.0), outs=OUTS[:-1])
    fresh = sens((30.0, 0.0))
    again = sens((30.0, 0.0), reuse=a.stats["slopes"])
    assert again.stats["slopes_reused"] and not fresh.stats["slopes_reused"]
    row = np.abs(fresh.jacobian).max(axis=1, keepdims=True)
    assert np.all(np.abs(again.jacobian - fresh.jacobian) <= 1e-12 * row)
    wrong = sens((30.0, 0.0), reuse=a.stats["slopes"] * 1.001)
    assert not wrong.stats["slopes_reused"]


def test_grounded_length_by_hand():
    """Two sections (end A 100 m of 1000 N/m, end B 50 m of 500 N/m): a lift of 25 kN hangs
    the upper 50 m (25 kN) and nothing more: 100 m grounded; 75 kN hangs 50 m more: 50 m;
    a lift past the whole weight (150 kN) lifts the anchor: -(175 - 125) kN / 1000 N/m."""
    secs = [(100.0, 1000.0), (50.0, 500.0)]
    assert grounded_length(25e3, secs) == pytest.approx(100.0, rel=1e-14)
    assert grounded_length(75e3, secs) == pytest.approx(50.0, rel=1e-14)
    assert grounded_length(175e3, secs) == pytest.approx(-50.0, rel=1e-14)


def test_optimize_over_load_cases_with_a_callable_scene():
    """Line 0 alone varies (its slack s0 and diameter d0): the lightest chain whose
    fairlead tension is at most 0.2 of its breaking load, with at least 20 m on the bed, at
    rest and with the body 30 m away from its anchor. The optimum: the thinnest chain (d0 on
    its bound) at the slack where the offset's tension meets its bound (measured 48.26 m,
    the bound met to 3e-8); the same from two starts to 1e-5; first-order optimal. The
    refusals name the problem."""
    fixed = {k: v for k, v in BASE.items() if k not in ("s0", "d0")}

    def make(v):
        return mooring({**fixed, **v})
    cases = {"mean": {}, "far": {"bodies.hull.position": [30.0, 0.0, 0.0]}}
    cons = [("line0.fairlead_utilisation", "<=", 0.2), ("line0.grounded_length", ">=", 20.0)]
    bounds = {"s0": (40.0, 200.0), "d0": (0.04, 0.14)}
    a = sc.optimize(make, bounds, "mass", cons, cases=cases, start={"s0": 150.0, "d0": 0.12})
    b = sc.optimize(make, bounds, "mass", cons, cases=cases, start={"s0": 60.0, "d0": 0.06})
    assert a.variables == pytest.approx(b.variables, rel=1e-5)
    assert a.variables["d0"] == pytest.approx(0.04, abs=1e-9)
    assert a.constraints["far:line0.fairlead_utilisation <= 0.2"] == pytest.approx(0.2,
                                                                                   abs=1e-6)
    assert a.constraints["far:line0.grounded_length >= 20"] > 20.0
    assert a.stats["kkt_residual"] < 1e-3
    with pytest.raises(SymcableError, match="no load case 'storm'"):
        sc.optimize(make, bounds, "mass", [("storm:line0.grounded_length", ">=", 1.0)],
                    cases=cases)
    with pytest.raises(SymcableError, match="is refused by the scene"):
        sc.optimize(make, {"s0": (-400.0, 200.0), "d0": (0.04, 0.14)}, "mass", cons,
                    cases=cases, start={"s0": -399.0, "d0": 0.1})
    even = {k: {"s": 100.0, "d": 0.1, "R": 600.0}[k[0]] for k in BASE}
    with pytest.raises(SymcableError, match="a magnitude at zero has no derivative"):
        sc.sensitivity(mooring(even), "hull.horizontal_force",  # three equal lines: zero
                       "line_types.chain0.nominal_diameter")
    with pytest.raises(SymcableError, match="breaking load"):
        d = mooring(BASE)
        d["line_types"]["chain0"] = {"mass": 150.0, "diameter": 0.18, "EA": 8e8}
        static_values(_apply(d, {}), ["line0.fairlead_utilisation"])


def test_review_refusals_and_keys():
    """Slopes that hold along the check's direction only in the units that dominate are not
    taken (a case moving an anchor that a variable also moves); a grounded length needs
    its anchor at end A; a load case's path names a table; an RAO vessel's structure is not shared (its
    motion is compiled from the sea). A fixed body's position, which is its lines' ends'
    numbers, has an exact derivative."""
    import sys
    from pathlib import Path
    sys.path.insert(0, str(Path(__file__).parent))
    from test_vessel import _spar

    from symcable.models.structure import structure_key

    def sens_case(change, reuse=None):
        def at(j, value):
            v = dict(BASE)
            v[NAMES[j]] = value
            return _apply(mooring(v, (30.0, 0.0)), change)
        return design_sensitivity(
            _apply(mooring(BASE, (30.0, 0.0)), change), None, OUTS[:3], NAMES,
            list(BASE.values()), [lambda value, j=j: at(j, value) for j in range(9)],
            reuse=reuse, raw_of=lambda w: _apply(mooring(dict(zip(NAMES, w)), (30.0, 0.0)),
                                                 change))
    first = sens_case({})
    moved = sens_case({"points.anchor0.position": [-600.0, 0.0, -200.0]},
                      reuse=first.stats["slopes"])
    assert not moved.stats["slopes_reused"]
    # a fixed body's position is a number of its lines' ends: its derivative is exact (the
    # moment's reference point moves with it), as central differences of whole solves at
    # two steps say (to 1e-6 of the largest entry, or 3 times the differences' own change)
    held = mooring(BASE, (10.0, 0.0), segments=4)
    got = sc.sensitivity(held, ["hull.moment", "hull.force"], ["bodies.hull.position[1]"])

    def solved(y):
        d = copy.deepcopy(held)
        d["bodies"]["hull"]["position"][1] = y
        st = sc.solve_static(d, tol=1e-6, estimate=False)
        return np.concatenate([st.bodies["hull"].moment, st.bodies["hull"].force])
    fd = {h: (solved(h) - solved(-h)) / (2 * h) for h in (0.05, 0.1)}
    allowed = np.maximum(1e-6 * np.max(np.abs(fd[0.05])), 3.0 * np.abs(fd[0.05] - fd[0.1]))
    assert np.all(np.abs(got.jacobian[:, 0] - fd[0.05]) <= allowed), (got.jacobian, fd)
    d = mooring(BASE, segments=4)
    ln = d["lines"][0]
    ln["end_a"], ln["end_b"] = ln["end_b"], ln["end_a"]
    with pytest.raises(SymcableError, match="end A must be its anchor"):
        static_values(d, ["line0.grounded_length"])
    with pytest.raises(SymcableError, match="load case path 'points.nowhere.force'"):
        _apply(mooring(BASE), {"points.nowhere.force": [1.0, 0.0, 0.0]})
    rao = {"kind": "rao", "omegas": [0.2, 1.0], "amplitude": [[1, 0, 1, 0, 1, 0]] * 2,
           "phase_deg": [[0] * 6] * 2}
    sea = {"kind": "regular", "height": 4.0, "period": 10.0}
    assert structure_key(sc.load_scene(_spar(rao, sea, segments=4))) is None
    assert structure_key(sc.load_scene(mooring(BASE))) is not None


def test_reused_slopes_are_checked_row_by_row():
    """Slopes another load case took are reused when the scene's numbers, or the equations
    and outputs they drive, move as the slopes predict; one block of one column off by
    1e-5 (line2's numbers in the d2 column) moves line2's rows by 1e-5 of their own move,
    which the row-by-row check refuses (a check against the largest row's move would take
    it: the grounded length's derivative then came out 50 % off)."""
    from symcable.api.cable3d_static import cable3d_mechanism
    first = sens((40.0, 0.0))
    again = sens((40.0, 0.0), reuse=first.stats["slopes"])
    assert again.stats["slopes_reused"]
    dP = np.array(first.stats["slopes"], float)
    mech = cable3d_mechanism(sc.load_scene(mooring(BASE, (40.0, 0.0))))
    dP[mech.params.slice("line2.line"), NAMES.index("d2")] *= 1.0 + 1e-5
    off = sens((40.0, 0.0), reuse=dP)
    assert not off.stats["slopes_reused"]
    np.testing.assert_allclose(off.jacobian, first.jacobian, rtol=0, atol=1e-12 * np.max(
        np.abs(first.jacobian)))
