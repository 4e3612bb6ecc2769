"""Scenes of one structure share one Mechanism's expressions and Functions
(:mod:`symcable.models.structure`): a scene rebound to a template must be the scene's own
Mechanism in every number and every value, and whatever changes the structure must build
afresh."""
from __future__ import annotations

import copy
import math

import numpy as np
import pytest

import symcable as sc
from symcable.mechanism.bounds import bound_numbers
from symcable.api.cable3d_static import cable3d_mechanism
from symcable.mechanism.functions import functions
from symcable.models import build_mechanism, structure
from symcable.models.cable3d.line import build_cable3d
from symcable.models.system import build_system

ENV = {"gravity": 9.80665, "water_density": 1025.0, "depth": 320.0, "current": [0.3, 0.1, 0.0]}
CHAIN = {"EA": 3.84243e8, "mass": 77.7066, "diameter": 0.09, "cd_normal": 1.6,
         "cd_tangential": 0.1, "ca_normal": 1.0}


def _three_lines(n: int = 12) -> dict:
    points, lines = {}, []
    for i, ang in enumerate((0.0, 120.0, 240.0)):
        a = math.radians(ang)
        points[f"anchor{i}"] = {"kind": "fixed",
                                "position": [853.87 * math.cos(a), 853.87 * math.sin(a), -320.0]}
        points[f"fair{i}"] = {"kind": "fixed",
                              "position": [5.2 * math.cos(a), 5.2 * math.sin(a), -70.0]}
        lines.append({"name": f"line{i}", "end_a": f"anchor{i}", "end_b": f"fair{i}",
                      "sections": [{"type": "chain", "length": 902.2, "segments": n}]})
    return {"model": "cable3d", "environment": ENV, "seabed": {"stiffness": 1e5},
            "line_types": {"chain": dict(CHAIN)}, "points": points, "lines": lines}


def _clump() -> dict:
    """Two lines meeting at a free clump on the seabed, friction and damping on the bed."""
    return {"model": "cable3d", "environment": ENV,
            "seabed": {"stiffness": 1e5, "friction": 0.6, "damping": 2e3},
            "line_types": {"chain": dict(CHAIN, damping=-0.8),
                           "wire": {"EA": 6e8, "mass": 30.0, "diameter": 0.08,
                                    "cd_normal": 1.2, "cd_tangential": 0.01}},
            "points": {"anchor": {"kind": "fixed", "position": [-600.0, 0.0, -320.0]},
                       "clump": {"kind": "free", "position": [-250.0, 0.0, -315.0],
                                 "mass": 8000.0, "volume": 1.0},
                       "fair": {"kind": "fixed", "position": [0.0, 0.0, -20.0]}},
            "lines": [{"name": "lower", "end_a": "anchor", "end_b": "clump",
                       "sections": [{"type": "chain", "length": 360.0, "segments": 9}]},
                      {"name": "upper", "end_a": "clump", "end_b": "fair",
                       "sections": [{"type": "chain", "length": 120.0, "segments": 4},
                                    {"type": "wire", "length": 260.0, "segments": 6}]}]}


def _one_line() -> dict:
    return {"model": "cable3d", "environment": ENV, "seabed": {"stiffness": 1e5},
            "line_types": {"chain": dict(CHAIN)},
            "sections": [{"type": "chain", "length": 902.2, "segments": 15}],
            "end_a": {"condition": "pinned", "position": [-853.87, 0.0, -320.0]},
            "end_b": {"condition": "pinned", "position": [-5.2, 0.0, -70.0]}}


def _perturbed(d: dict, rng) -> dict:
    """Every number the parameters carry moved at random (lengths, line types, positions,
    current), the structure kept."""
    d = copy.deepcopy(d)
    f = lambda: float(rng.uniform(0.9, 1.1))  # noqa: E731
    for lt in d["line_types"].values():
        for k in ("EA", "mass", "diameter", "cd_normal", "cd_tangential", "ca_normal"):
            if k in lt:
                lt[k] *= f()
    for sec in d.get("sections", []) + [s for ln in d.get("lines", []) for s in ln["sections"]]:
        sec["length"] *= f()
    def moved(pos):  # horizontally, and up where above the bed (at most 3 m)
        return [pos[0] + float(rng.uniform(-3.0, 3.0)), pos[1] + float(rng.uniform(-3.0, 3.0)),
                pos[2] + (float(rng.uniform(0.0, 3.0)) if pos[2] < -325.0 + 30.0 else 0.0)
                if pos[2] > -310.0 else pos[2]]
    for pt in d.get("points", {}).values():
        pt["position"] = moved(pt["position"])
    for end in ("end_a", "end_b"):
        if end in d:
            d[end]["position"] = moved(d[end]["position"])
    d["environment"] = dict(d["environment"],
                            current=[u * f() for u in d["environment"]["current"]])
    return d


def _fresh(scene):
    return (build_system if scene.version == 2 else build_cable3d)(scene)


CASES = {"three lines": _three_lines, "clump, friction, damping": _clump,
         "one line": _one_line}


@pytest.mark.parametrize("case", list(CASES))
def test_rebound_mechanism_is_the_scenes_own(case):
    """A scene rebound to the template of another scene of its structure has the numbers
    (parameters, scales, bounds' limits, starts, arc lengths) and the values (static
    residual, its Jacobian, outputs, bounds) of the scene's own Mechanism built afresh. The
    same arithmetic on the same parameter values: agreement to round-off (1e-9 relative)."""
    rng = np.random.default_rng(34)
    structure.TEMPLATES.clear()
    template = build_mechanism(sc.load_scene(CASES[case]()))
    for _ in range(3):
        scene = sc.load_scene(_perturbed(CASES[case](), rng))
        mech = build_mechanism(scene)
        assert mech.functions_of is template, "the scene did not share its structure's template"
        own = _fresh(scene)
        np.testing.assert_array_equal(mech.params.values, own.params.values)
        assert mech.params.names == own.params.names
        for k in ("q", "v"):
            np.testing.assert_array_equal(getattr(mech.scales, k), getattr(own.scales, k))
        assert (mech.scales.force, mech.scales.mass) == (own.scales.force, own.scales.mass)
        np.testing.assert_array_equal(bound_numbers(mech), bound_numbers(own))
        for part, lay in own.layout.parts.items():
            np.testing.assert_array_equal(mech.layout.parts[part].s, lay.s)
        s_m, s_o = next(iter(mech.starts())), next(iter(own.starts()))
        np.testing.assert_array_equal(s_m.q, s_o.q)
        np.testing.assert_array_equal(s_m.p, s_o.p)
        p = mech.static_p
        F_m, F_o = functions(mech), functions(own)
        assert F_m is functions(template) and F_o is not F_m
        x = np.asarray(s_o.q, float) + rng.normal(0.0, 0.5, own.n_q)
        r_m, J_m = F_m.static_jacobian(x, p)
        r_o, J_o = F_o.static_jacobian(x, p)
        scale = float(np.max(np.abs(np.asarray(r_o))))
        np.testing.assert_allclose(np.asarray(r_m), np.asarray(r_o), rtol=1e-9, atol=1e-9 * scale)
        np.testing.assert_allclose(J_m.full(), J_o.full(), rtol=1e-9,
                                   atol=1e-9 * float(np.max(np.abs(J_o.full()))))
        args = (x, np.zeros(own.n_v), np.zeros(0), 0.0, p)
        y_m, y_o = (np.asarray(F.outputs(*args), float) for F in (F_m, F_o))
        np.testing.assert_allclose(y_m, y_o, rtol=1e-9, atol=1e-9 * float(np.max(np.abs(y_o))))
        b_m, b_o = (np.asarray(F.bound_values(*args), float) for F in (F_m, F_o))
        np.testing.assert_allclose(b_m, b_o, rtol=1e-9, atol=1e-9 * float(np.max(np.abs(b_o))))


def test_a_solve_with_changed_numbers_reuses_the_functions_and_equals_a_fresh_one():
    """The three-line mooring solved, then again with the lines 3 m longer and a fairlead
    moved 5 m: the second solve builds no Function (the template's static solve serves it)
    and its answer is the fresh build's to round-off (the same arithmetic)."""
    structure.TEMPLATES.clear()
    sc.solve_static(_three_lines())
    template = structure.TEMPLATES[structure.structure_key(sc.load_scene(_three_lines()))]
    built = functions(template).__dict__["_static_solver"]["vm"]
    changed = _three_lines()
    for ln in changed["lines"]:
        ln["sections"][0]["length"] += 3.0
    changed["points"]["fair0"]["position"][0] += 5.0
    got = sc.solve_static(changed)
    mech = cable3d_mechanism(sc.load_scene(changed))
    assert mech.functions_of is template and functions(mech) is functions(template)
    assert functions(mech).static_solver(False) is built  # the first scene's, not rebuilt
    structure.TEMPLATES.clear()
    ref = sc.solve_static(_three_lines() | {"lines": changed["lines"], "points": changed["points"]})
    for name, line in ref.lines.items():
        np.testing.assert_allclose(got.lines[name].positions, line.positions, rtol=0, atol=1e-9)
        assert got.lines[name].fairlead_tension == pytest.approx(line.fairlead_tension, rel=1e-12)


def test_what_the_parameters_do_not_carry_changes_the_structure():
    """Segment counts, depth, seabed stiffness, a drag coefficient set to zero (a term
    dropped) and a held end lowered onto the bed (its contact then takes its neighbour's
    penetration) each give another structure; bodies and bending are not shared."""
    base = structure.structure_key(sc.load_scene(_one_line()))
    assert base is not None
    changes = []
    d = _one_line()
    d["sections"][0]["segments"] = 16
    changes.append(d)
    d = _one_line()
    d["environment"] = dict(ENV, depth=330.0)
    changes.append(d)
    d = _one_line()
    d["seabed"] = {"stiffness": 2e5}
    changes.append(d)
    d = _one_line()
    d["line_types"]["chain"]["cd_tangential"] = 0.0
    changes.append(d)
    d = _one_line()
    d["end_b"]["position"] = [-5.2, 0.0, -320.0]
    changes.append(d)
    keys = [structure.structure_key(sc.load_scene(c)) for c in changes]
    assert base not in keys and len(set(keys)) == len(keys)
    same = _one_line()
    same["sections"][0]["length"] = 950.0
    same["end_a"]["position"] = [-900.0, 10.0, -320.0]
    assert structure.structure_key(sc.load_scene(same)) == base
    bent = _one_line()
    bent["line_types"]["chain"]["EI"] = 1e4
    assert structure.structure_key(sc.load_scene(bent)) is None


def test_lines_of_one_structure_in_a_system_share_a_part_and_keep_their_own_numbers():
    """The three lines of a mooring, each with its own length and anchor (one structure:
    their parts share one graph, :func:`symcable.models.system.build_system`), solved as one
    system equal each line solved alone as a one-line scene (fixed ends: the lines do not
    meet), node for node to the solver's tolerance (1e-9 of the force scale: 1e-6 m here)."""
    rng = np.random.default_rng(5)
    structure.TEMPLATES.clear()
    d = _perturbed(_three_lines(), rng)
    for ln in d["lines"]:
        ln["sections"][0]["length"] *= float(rng.uniform(0.97, 1.03))
    system = sc.solve_static(d)
    for ln in d["lines"]:
        alone = {"model": "cable3d", "environment": d["environment"], "seabed": d["seabed"],
                 "line_types": d["line_types"], "sections": ln["sections"],
                 "end_a": {"condition": "pinned", "position": d["points"][ln["end_a"]]["position"]},
                 "end_b": {"condition": "pinned", "position": d["points"][ln["end_b"]]["position"]}}
        one = sc.solve_static(alone)
        np.testing.assert_allclose(system.lines[ln["name"]].positions, one.positions, rtol=0,
                                   atol=1e-6)


def _moving_mooring(n: int, extra: float) -> dict:
    d = _three_lines(n)
    for ln in d["lines"]:
        ln["sections"][0]["length"] += extra
    d["points"]["fair0"]["kind"] = "vessel"
    d["points"]["fair0"]["motion"] = {"kind": "harmonic", "period": 10.0,
                                      "amplitude": [2.0, 0.0, 1.0], "phase_deg": [0.0, 0.0, -90.0]}
    return d


def test_simulate_with_changed_numbers_reuses_the_step_and_equals_a_fresh_run():
    """A time run of the mooring with a moving fairlead, then of the same mooring with its
    lines 2 m longer: the second takes the first's generalized-alpha step (built from the
    expressions alone; the scene's scales enter as inputs) and its fairlead tension history
    equals a run built afresh to round-off (1e-9 of the tension range: the same arithmetic)."""
    from symcable.solvers.stepcache import STEP_CACHE
    structure.TEMPLATES.clear()
    sc.simulate(_moving_mooring(8, 0.0), 20.0, dt=0.2, codegen=False)
    template = structure.TEMPLATES[structure.structure_key(sc.load_scene(_moving_mooring(8, 0.0)))]
    steps = {k for k in STEP_CACHE.store.setdefault(template, dict) if k[0] == "ga1_unrolled"}
    assert steps, "the first run kept no step on its structure's template"
    got = sc.simulate(_moving_mooring(8, 2.0), 20.0, dt=0.2, codegen=False)
    assert {k for k in STEP_CACHE.store.setdefault(template, dict)
            if k[0] == "ga1_unrolled"} == steps  # no step built again
    structure.TEMPLATES.clear()
    from symcable.api import cable3d_static
    cable3d_static._CACHE.clear()
    ref = sc.simulate(_moving_mooring(8, 2.0), 20.0, dt=0.2, codegen=False)
    a, b = (np.asarray(r.outputs["fair0.force"], float) for r in (got, ref))
    np.testing.assert_allclose(a, b, rtol=0, atol=1e-9 * float(np.ptp(b)))


@pytest.mark.parametrize("segments", [12, 80])
def test_a_single_line_in_time_shares_its_step_across_numbers(segments):
    """One line with a moving fairlead, in time, then the same line 5 m longer and 5 % heavier:
    the second run takes the first's step (its element form's constants are expressions of
    the ``line`` parameters, so the step built from them holds for any numbers: at 80
    segments the step's matrix comes from the element form, at 12 it is written out) and
    equals a run built afresh to round-off (1e-9 of the tension range)."""
    from symcable.api import cable3d_static
    from symcable.solvers.stepcache import STEP_CACHE

    def line(extra: float, heavier: float) -> dict:
        d = _one_line()
        d["sections"][0]["segments"] = segments
        d["sections"][0]["length"] += extra
        d["line_types"]["chain"]["mass"] *= heavier
        d["end_b"]["motion"] = {"kind": "harmonic", "period": 10.0,
                                "amplitude": [2.0, 0.0, 1.0], "phase_deg": [0.0, 0.0, -90.0]}
        return d
    structure.TEMPLATES.clear()
    sc.simulate(line(0.0, 1.0), 12.0, dt=0.2, codegen=False)
    template = structure.TEMPLATES[structure.structure_key(sc.load_scene(line(0.0, 1.0)))]
    steps = {k for k in STEP_CACHE.store.setdefault(template, dict) if k[0] == "ga1_unrolled"}
    assert steps
    got = sc.simulate(line(5.0, 1.05), 12.0, dt=0.2, codegen=False)
    assert {k for k in STEP_CACHE.store.setdefault(template, dict)
            if k[0] == "ga1_unrolled"} == steps
    structure.TEMPLATES.clear()
    cable3d_static._CACHE.clear()
    ref = sc.simulate(line(5.0, 1.05), 12.0, dt=0.2, codegen=False)
    a, b = np.asarray(got.fairlead_tension, float), np.asarray(ref.fairlead_tension, float)
    np.testing.assert_allclose(a, b, rtol=0, atol=1e-9 * float(np.ptp(b)))


def test_a_long_lines_estimate_scenes_are_not_kept(monkeypatch):
    """The error estimate's comparison scene (half the segments) of a line longer than
    RELEASE_SEGMENTS is forgotten after its solve (a 2000-segment line's held 0.1 GB), the
    solved scene's own Mechanism kept; below the bound the comparison is kept, so that a
    re-solve with changed numbers reuses it (the design-loop case)."""
    from symcable.api import cable3d_static as cs
    from symcable.api.static_error import _other
    scene = sc.load_scene(_three_lines(12))
    coarse, _ = _other(scene)  # the estimate's comparison scene
    for bound, kept in ((1000, True), (10, False)):
        monkeypatch.setattr(cs, "RELEASE_SEGMENTS", bound)
        cs._CACHE.clear()
        structure.TEMPLATES.clear()
        sol = sc.solve_static(scene)
        assert sol.stats["discretisation_error"]["max_relative"] is not None
        assert repr(scene.to_dict()) in cs._CACHE
        assert (repr(coarse.to_dict()) in cs._CACHE) is kept
        assert (structure.structure_key(coarse) in structure.TEMPLATES) is kept


@pytest.mark.parametrize("make", [_three_lines, _clump], ids=["three lines", "clump"])
def test_an_error_estimates_solve_starts_from_the_answer_and_lands_where_a_cold_one_does(make):
    """The half-segment scene of the error estimate starts from the answer, its lines'
    nodes interpolated along their arc length (a free clump copied); from there it finds
    the equilibrium the scene's own starts find (to the solver's tolerance, 1e-9 of the
    force scale, on positions of hundreds of metres: 1e-6 m). The three lines' coarse
    solve converges from it; the clump's coarse lines (4 and 5 segments on the bed) do not
    converge by Newton from any start but the relaxed one, which then serves, as it does
    cold."""
    from symcable.api.cable3d_static import static_equilibrium, transferred_state
    from symcable.scene.refine import line_segments, scaled_segments
    scene = sc.load_scene(make())
    sol = sc.solve_static(scene, estimate=False)
    half = scaled_segments(scene, {k: 0.5 for k in line_segments(scene)})
    q, z = transferred_state(half, sol)
    mech = cable3d_mechanism(half)
    for name, line in sol.lines.items():  # a node at a shared arc length sits where it was
        idx = np.asarray(mech.layout.parts[name].node_q, int)
        s_half = np.asarray(mech.layout.parts[name].s)
        for i in np.flatnonzero(idx[:, 0] >= 0):
            j = int(np.argmin(np.abs(line.s - s_half[i])))
            if abs(line.s[j] - s_half[i]) < 1e-9:
                np.testing.assert_allclose(q[idx[i]], line.positions[j], atol=1e-9)
    _, warm = static_equilibrium(half, start=(q, z))
    _, cold = static_equilibrium(half)
    if make is _three_lines:
        assert warm.stats["start"] == "a nearby design's state"
    np.testing.assert_allclose(warm.q, cold.q, atol=1e-6)
    est = sc.solve_static(scene).stats["discretisation_error"]
    assert est["lines"] and all(e["compared_with"] < e["segments"] for e in est["lines"].values())
