"""Points and several lines (issue 12, item 4; scene version 2: ``[points.NAME]``,
``[[lines]]``), ``model = "cable3d"``: the scene layout and its errors, the lines and free
points assembled into one Mechanism, its statics against MoorPy's System (points, lines,
line types) and against its own symmetry and force balance, and a conservative time run.

MoorPy's lines are exact elastic catenaries (seabed contact rigid, no friction) and its free
points are solved to 1e-6 m here; symcable's lines are lumped-mass chains on a penalty seabed
of 1e7 Pa/m (they sink 7e-5 m), so the difference is the discretisation error, second order
in the segments: measured on the clump-and-buoy line below, fairlead tension -0.49, -0.11,
-0.012 % and buoy offset 0.13, 0.028, 0.0024 m at 20, 40, 80 segments per 250 m of chain;
on the two lines meeting at a buoy 0.016 % and 0.007 m at 40 segments.
"""
from __future__ import annotations

import math

import numpy as np
import pytest

import symcable as sc
from symcable.errors import SceneError
from symcable.scene import PointKind, load_scene, scene_to_toml

RHO, G = 1025.0, 9.80665


def _w(mass, d):
    return (mass - RHO * math.pi * d * d / 4) * G


# ----------------------------------------------------------------------------- the scene

def _two_lines() -> dict:
    """Two lines meeting at a buoy: an anchor chain and a rope up to a vessel point."""
    return {"name": "buoyed", "model": "cable3d", "environment": {"depth": 120.0},
            "seabed": {"stiffness": 1e7},
            "line_types": {"chain": {"mass": 60.0, "diameter": 0.09, "EA": 5e8},
                           "rope": {"mass": 6.0, "diameter": 0.11, "EA": 4e7}},
            "points": {"anchor": {"kind": "fixed", "position": [-300.0, -80.0, -120.0]},
                       "buoy": {"kind": "free", "position": [-120.0, 0.0, -50.0],
                                "mass": 400.0, "volume": 4.0, "force": [0.0, 3000.0, 0.0]},
                       "fairlead": {"kind": "vessel", "position": [40.0, 60.0, -8.0]}},
            "lines": [{"name": "lower", "end_a": "anchor", "end_b": "buoy",
                       "sections": [{"type": "chain", "length": 230.0, "segments": 40}]},
                      {"name": "upper", "end_a": "buoy", "end_b": "fairlead",
                       "sections": [{"type": "rope", "length": 170.0, "segments": 40}]}]}


def test_scene_round_trip(tmp_path):
    """Every kind of point and an inline end: the dict and the TOML text load back equal."""
    d = _two_lines()
    d["points"]["fairlead"]["motion"] = {"period": 12.0, "amplitude": [2.0, 0.0, 1.0],
                                         "phase_deg": [0.0, 0.0, 90.0]}
    d["points"]["sphere"] = {"kind": "free", "position": [-150.0, 20.0, -90.0], "mass": 900.0,
                             "volume": 0.5, "diameter": 1.0, "cd": 0.6}
    d["points"]["clump"] = {"kind": "free", "position": [-160.0, 30.0, -100.0], "mass": 0.0,
                            "cd_area": [1.0, 2.0, 3.0], "ca": 0.8}
    d["lines"] += [{"name": "pendant", "end_a": "buoy", "end_b": "sphere",
                    "sections": [{"type": "rope", "length": 50.0, "segments": 5}]},
                   {"end_a": "sphere", "end_b": "clump",
                    "sections": [{"type": "rope", "length": 20.0, "segments": 2},
                                 {"type": "chain", "length": 10.0, "segments": 1}]},
                   {"name": "tail", "end_a": "clump",
                    "end_b": {"condition": "free", "force": [0.0, 0.0, -100.0]},
                    "sections": [{"type": "chain", "length": 10.0, "segments": 2}]}]
    s = load_scene(d)
    assert s.version == 2 and s.sections == () and s.end_a is None
    assert [ln.name for ln in s.lines] == ["lower", "upper", "pendant", "line4", "tail"]
    assert s.points["buoy"].kind is PointKind.FREE and s.points["buoy"].force == (0, 3000, 0)
    sphere = s.points["sphere"]
    assert sphere.ca == 0.5  # a sphere's default
    assert sphere.drag_area == pytest.approx((0.6 * math.pi / 4,) * 3)
    assert sphere.added_volume == pytest.approx(math.pi / 6)
    assert s.points["clump"].ca == 0.8 and s.points["clump"].added_volume == 0.0
    assert s.lines[4].end_b.force == (0.0, 0.0, -100.0)
    assert s.n_nodes == 41 + 41 + 6 + 4 + 3
    assert load_scene(s.to_dict()) == s
    path = tmp_path / "s.toml"
    path.write_text(scene_to_toml(s))
    assert load_scene(path) == s


def _edit(path: str, value):
    def modify(d):
        keys = path.replace("[", ".[").split(".")
        node = d
        for k in keys[:-1]:
            node = node[int(k[1:-1])] if k.startswith("[") else node[k]
        last = keys[-1]
        if value is DELETE:
            del node[last]
        elif last.startswith("["):
            node[int(last[1:-1])] = value
        else:
            node[last] = value
    return modify


DELETE = object()


def _unheld(d):
    """Both lines end free (inline), joined only at the buoy: nothing holds them."""
    del d["points"]["anchor"], d["points"]["fairlead"]
    d["lines"][0]["end_a"] = {"condition": "free"}
    d["lines"][1]["end_b"] = {"condition": "free"}


#: (modifier, fragments of the one-line message: key path, value, what is allowed)
BAD = {
    "unknown point": (_edit("lines[0].end_b", "bouy"),
                      ["lines[0].end_b = 'bouy'", "did you mean 'buoy'?", "'anchor'"]),
    "unused point": (_edit("points.spare", {"kind": "fixed", "position": [0, 0, -50]}),
                     ["points.spare", "no line uses this point"]),
    "free point without mass or volume": (_edit("points.buoy.mass", DELETE),  # volume too, below
                                          ["points.buoy: a free point needs mass", "volume"]),
    "free point moves": (_edit("points.buoy.motion", {"period": 10, "amplitude": [1, 0, 0]}),
                         ["points.buoy.motion", "only a vessel point moves"]),
    "fixed point with mass": (_edit("points.anchor.mass", 100.0),
                              ["points.anchor.mass = 100.0", "only a free point takes mass"]),
    "point kind": (_edit("points.buoy.kind", "floating"),
                   ["points.buoy.kind = 'floating'", "'fixed', 'vessel', 'free'"]),
    "point key": (_edit("points.buoy.mas", 1.0), ["points.buoy.mas", "did you mean 'mass'?"]),
    "point position": (_edit("points.anchor.position", DELETE),
                       ["points.anchor.position: required key missing"]),
    "negative mass": (_edit("points.buoy.mass", -1.0), ["points.buoy.mass = -1.0 kg", ">= 0"]),
    "cd without diameter": (_edit("points.buoy.cd", 0.5), ["points.buoy.cd = 0.5", "cd_area"]),
    "diameter and cd_area": (lambda d: d["points"]["buoy"].update(diameter=1.0, cd_area=[1, 1, 1]),
                             ["points.buoy.cd_area = [1, 1, 1]", "not both"]),
    "cd_area length": (_edit("points.buoy.cd_area", [1.0, 2.0]),
                       ["points.buoy.cd_area = [1.0, 2.0]", "list of 3"]),
    "cd_area negative": (_edit("points.buoy.cd_area", [1.0, -2.0, 0.0]),
                         ["points.buoy.cd_area[1] = -2.0", ">= 0"]),
    "line key": (_edit("lines[1].sectons", []), ["lines[1].sectons", "'sections'"]),
    "line sections": (_edit("lines[1].sections", []),
                      ["lines[1].sections = []", "non-empty array"]),
    "section type": (_edit("lines[1].sections[0].type", "wire"),
                     ["lines[1].sections[0].type = 'wire'", "unknown line type"]),
    "duplicate line name": (_edit("lines[1].name", "lower"),
                            ["lines[1].name = 'lower'", "unique"]),
    "line named as a point": (_edit("lines[1].name", "buoy"),
                              ["lines[1].name = 'buoy'", "point's name"]),
    "top-level sections": (_edit("sections", [{"type": "chain", "length": 1, "segments": 1}]),
                           ["sections = ", "remove the top-level sections"]),
    "points without lines": (_edit("lines", DELETE), ["points", "give [[lines]]"]),
    "planar": (_edit("model", "planar"), ["lines", 'model = "cable3d" only']),
    "lines empty": (_edit("lines", []), ["lines = []", "non-empty array"]),
    "nothing holds": (_unheld, ["lines[0].end_a", "nothing holds them"]),
    "out of reach": (_edit("points.anchor.position", [-900.0, -80.0, -120.0]),
                     ["points.fairlead.position = [40.0, 60.0, -8.0] m", "the ends are", "(lower, upper) stretch to at most"]),
    "held point below the seabed": (_edit("points.anchor.position", [-300.0, -80.0, -130.0]),
                                    ["points.anchor.position = [-300.0, -80.0, -130.0]",
                                     "below the seabed"]),
    "inline end": (_edit("lines[1].end_b", {"condition": "pinned"}),
                   ["lines[1].end_b.position: required key missing"]),
    "vessel too fast": (_edit("points.fairlead.motion", {"period": 1e-3, "amplitude": [5, 0, 0]}),
                        ["points.fairlead.motion.period = 0.001 s", "faster than"]),
}


@pytest.mark.parametrize("case", sorted(BAD))
def test_each_bad_key_is_one_scene_error(case):
    edit, fragments = BAD[case]
    d = _two_lines()
    if case == "free point without mass or volume":
        del d["points"]["buoy"]["volume"]
    edit(d)
    with pytest.raises(SceneError) as info:
        load_scene(d)
    msg = str(info.value)
    assert "\n" not in msg
    for fragment in fragments:
        assert fragment in msg, msg


def test_massless_joint_is_allowed():
    d = _two_lines()
    d["points"]["buoy"] = {"kind": "free", "position": [-120.0, 0.0, -50.0], "mass": 0.0}
    assert load_scene(d).points["buoy"].mass == 0.0


# ----------------------------------------------------------------------------- statics

def test_one_line_as_version_2_equals_version_1():
    """The OC3-like line as a version-1 scene (the single-line path, unchanged) and as one
    [[lines]] entry between two fixed points (the assembly): the same numbers."""
    common = {"model": "cable3d", "environment": {"depth": 320.0},
              "line_types": {"chain": {"mass": 77.7066, "diameter": 0.09, "EA": 3.84243e8}}}
    sections = [{"type": "chain", "length": 902.2, "segments": 30}]
    a, b = [-853.87, 0.0, -320.0], [-5.2, 0.0, -70.0]
    v1 = sc.solve_static({**common, "sections": sections,
                          "end_a": {"condition": "pinned", "position": a},
                          "end_b": {"condition": "pinned", "position": b}})
    v2 = sc.solve_static({**common, "points": {"A": {"kind": "fixed", "position": a},
                                               "B": {"kind": "fixed", "position": b}},
                          "lines": [{"name": "oc3", "end_a": "A", "end_b": "B",
                                     "sections": sections}]})
    assert list(v1.lines) == ["line"] and dict(v1.points) == {}  # the one-line fields stay
    line = v2.lines["oc3"]
    assert line.fairlead_tension == pytest.approx(v1.fairlead_tension, rel=1e-9)
    assert line.anchor_tension == pytest.approx(v1.anchor_tension, rel=1e-9)
    assert line.grounded_length == pytest.approx(v1.grounded_length, abs=1e-6)
    np.testing.assert_allclose(line.positions, v1.positions, atol=1e-6)
    np.testing.assert_allclose(v2.points["B"].force, v1.fairlead_force, rtol=1e-9)
    np.testing.assert_allclose(v2.points["A"].position, a)


def _moorpy_types(ms, types):
    for name, lt in types.items():
        ms.setLineType(name=name, mass=lt["mass"], d_vol=lt["diameter"], EA=lt["EA"],
                       w=_w(lt["mass"], lt["diameter"]), dnommm=1000 * lt["diameter"])


def test_moorpy_multi_section_line_with_clump_and_buoy():
    """Anchor - 250 m chain - clump (1500 kg, 0.2 m^3) - 120 m rope + 60 m chain - buoy
    (800 kg, 6 m^3) - 140 m rope - fairlead, out of the x-z plane, against MoorPy (the
    rope-chain joint a massless free point there): fairlead tension within 0.5 % (measured
    -0.11 %), anchor tension likewise, the clump, buoy and joint within 0.1 m (measured 0.028
    m: the discretisation error, module docstring), the grounded length within 0.5 m."""
    mp = pytest.importorskip("moorpy")
    depth = 200.0
    types = {"chain": dict(mass=80.0, diameter=0.1, EA=6e8),
             "rope": dict(mass=8.0, diameter=0.12, EA=5e7)}
    anchor, fair = [-500.0, -50.0, -depth], [0.0, 0.0, -12.0]
    clump0, joint0, buoy0 = [-300.0, -35.0, -120.0], [-180.0, -25.0, -70.0], [-150.0, -20.0, -60.0]
    d = {"model": "cable3d", "environment": {"depth": depth}, "seabed": {"stiffness": 1e7},
         "line_types": types,
         "points": {"anchor": {"kind": "fixed", "position": anchor},
                    "clump": {"kind": "free", "position": clump0, "mass": 1500.0, "volume": 0.2},
                    "buoy": {"kind": "free", "position": buoy0, "mass": 800.0, "volume": 6.0},
                    "fairlead": {"kind": "vessel", "position": fair}},
         "lines": [{"name": "bottom", "end_a": "anchor", "end_b": "clump",
                    "sections": [{"type": "chain", "length": 250.0, "segments": 40}]},
                   {"name": "middle", "end_a": "clump", "end_b": "buoy",
                    "sections": [{"type": "rope", "length": 120.0, "segments": 20},
                                 {"type": "chain", "length": 60.0, "segments": 10}]},
                   {"name": "top", "end_a": "buoy", "end_b": "fairlead",
                    "sections": [{"type": "rope", "length": 140.0, "segments": 20}]}]}
    st = sc.solve_static(d)
    assert st.status == "converged"
    ms = mp.System(depth=depth, rho=RHO, g=G)
    _moorpy_types(ms, types)
    ms.addPoint(1, anchor)
    ms.addPoint(0, clump0, m=1500.0, v=0.2)
    ms.addPoint(0, joint0)
    ms.addPoint(0, buoy0, m=800.0, v=6.0)
    ms.addPoint(1, fair)
    for length, name, a, b in ((250.0, "chain", 1, 2), (120.0, "rope", 2, 3),
                               (60.0, "chain", 3, 4), (140.0, "rope", 4, 5)):
        ms.addLine(length, name, pointA=a, pointB=b)
    ms.initialize()
    ms.solveEquilibrium(tol=1e-6)
    lines, points = ms.lineList, ms.pointList
    assert st.lines["top"].fairlead_tension == pytest.approx(np.linalg.norm(lines[3].fB), rel=5e-3)
    assert st.lines["bottom"].anchor_tension == pytest.approx(np.linalg.norm(lines[0].fA), rel=5e-3)
    assert np.linalg.norm(st.points["clump"].position - points[1].r) < 0.1
    assert np.linalg.norm(st.lines["middle"].positions[20] - points[2].r) < 0.1
    assert np.linalg.norm(st.points["buoy"].position - points[3].r) < 0.1
    assert st.lines["bottom"].grounded_length == pytest.approx(lines[0].LBot, abs=0.5)
    # the fixed and vessel points take what the lines pull with
    np.testing.assert_allclose(st.points["fairlead"].force, st.lines["top"].fairlead_force)
    np.testing.assert_allclose(st.points["anchor"].force, st.lines["bottom"].anchor_force)


@pytest.fixture(scope="module")
def two_lines():
    return sc.solve_static(_two_lines())


def test_moorpy_two_lines_meeting_at_a_buoy(two_lines):
    """An anchor chain and a rope to a vessel point meet at a buoy (400 kg, 4 m^3) pulled
    sideways by 3 kN, so nothing lies in one vertical plane: fairlead and anchor tension
    within 0.5 % of MoorPy's (measured 0.016 %), the buoy within 0.05 m (measured 0.007 m),
    the grounded length within 0.5 m."""
    mp = pytest.importorskip("moorpy")
    d = _two_lines()
    st = two_lines
    ms = mp.System(depth=120.0, rho=RHO, g=G)
    _moorpy_types(ms, d["line_types"])
    pts = d["points"]
    ms.addPoint(1, pts["anchor"]["position"])
    ms.addPoint(0, pts["buoy"]["position"], m=400.0, v=4.0, fExt=np.array([0.0, 3000.0, 0.0]))
    ms.addPoint(1, pts["fairlead"]["position"])
    ms.addLine(230.0, "chain", pointA=1, pointB=2)
    ms.addLine(170.0, "rope", pointA=2, pointB=3)
    ms.initialize()
    ms.solveEquilibrium(tol=1e-6)
    lower, upper = ms.lineList
    assert st.lines["upper"].fairlead_tension == pytest.approx(np.linalg.norm(upper.fB), rel=5e-3)
    assert st.lines["lower"].anchor_tension == pytest.approx(np.linalg.norm(lower.fA), rel=5e-3)
    assert np.linalg.norm(st.points["buoy"].position - ms.pointList[1].r) < 0.05
    assert abs(st.points["buoy"].position[1]) > 1.0  # pulled out of the anchor-fairlead plane
    assert st.lines["lower"].grounded_length == pytest.approx(lower.LBot, abs=0.5)


def test_free_point_force_balance(two_lines):
    """On the solution the buoy's loads balance: the two lines' end forces on it plus its
    buoyancy less its weight plus the applied 3 kN, to the solver's tolerance; the net-force
    output says the same."""
    st = two_lines
    own = np.array([0.0, 3000.0, (RHO * 4.0 - 400.0) * G])
    lines = st.lines["lower"].fairlead_force + st.lines["upper"].anchor_force
    tol = 10 * st.stats["tolerance"]
    assert np.max(np.abs(lines + own)) < tol
    np.testing.assert_allclose(st.points["buoy"].force, lines, atol=1e-9 * np.max(np.abs(own)))
    assert np.max(np.abs(st.points["buoy"].net_force)) < tol
    assert st.points["buoy"].kind == "free" and st.points["anchor"].net_force is None


def test_outputs_are_namespaced():
    from symcable.api.cable3d_static import cable3d_mechanism

    mech = cable3d_mechanism(load_scene(_two_lines()))
    for name in ("lower.axial_force", "lower.end_force_b", "upper.positions", "buoy.position",
                 "buoy.force", "buoy.net_force", "buoy.own_force", "anchor.force",
                 "fairlead.position", "kinetic_energy", "potential_energy"):
        assert name in mech.outputs, name
    assert mech.outputs["lower.axial_force"].owner == "lower"
    assert mech.n_q == 3 * (39 + 39 + 1)  # interior nodes of both lines and the buoy


def test_mirror_image_gives_symmetric_answers():
    """Two chains from anchors mirrored in the x-z plane (y -> -y) hold a buoy in a current
    along x; started off the mirror plane, the buoy comes to it (to 1e-6 m), the lines'
    shapes are each other's mirror image and their end tensions equal (to 1e-7)."""
    lt = {"chain": {"mass": 40.0, "diameter": 0.08, "EA": 3e8}}
    d = {"model": "cable3d", "environment": {"depth": 100.0, "current": [0.5, 0.0, 0.0]},
         "line_types": lt,
         "points": {"a1": {"kind": "fixed", "position": [-150.0, 120.0, -100.0]},
                    "a2": {"kind": "fixed", "position": [-150.0, -120.0, -100.0]},
                    "buoy": {"kind": "free", "position": [-60.0, 15.0, -40.0], "mass": 300.0,
                             "volume": 3.0, "diameter": 1.8}},
         "lines": [{"name": "port", "end_a": "a1", "end_b": "buoy",
                    "sections": [{"type": "chain", "length": 200.0, "segments": 20}]},
                   {"name": "starboard", "end_a": "a2", "end_b": "buoy",
                    "sections": [{"type": "chain", "length": 200.0, "segments": 20}]}]}
    st = sc.solve_static(d)
    port, stbd = st.lines["port"], st.lines["starboard"]
    assert abs(st.points["buoy"].position[1]) < 1e-6
    assert st.points["buoy"].position[0] > -150.0  # the current carries it downstream
    mirror = port.positions * np.array([1.0, -1.0, 1.0])
    np.testing.assert_allclose(stbd.positions, mirror, atol=1e-6)
    assert stbd.fairlead_tension == pytest.approx(port.fairlead_tension, rel=1e-7)
    assert stbd.anchor_tension == pytest.approx(port.anchor_tension, rel=1e-7)
    # a segment's axial force is an end force plus the nodal residuals between: each line's
    # agrees to its segments times the solver's tolerance (measured 1e-3 N of 1.4 kN)
    np.testing.assert_allclose(stbd.axial_force, port.axial_force,
                               atol=20 * st.stats["tolerance"])


# ----------------------------------------------------------------------------- dynamics

def test_energy_conserved_with_a_free_point():
    """Two weightless strings (1 % stretched, in air) joined at a 2 kg free point, released
    from a bowed shape: generalized-alpha with rho_inf = 1 conserves the system's energy (the
    Mechanism's kinetic and potential energy outputs, the point's included) to second order
    in dt (measured drifts 1.51, 0.383, 0.098 %)."""
    from symcable.api.cable3d_static import cable3d_mechanism
    from symcable.solvers.equilibrium import solve_equilibrium
    from symcable.solvers.integrate import integrate
    from symcable.solvers.options import GeneralizedAlpha

    L = 5.0
    lt = {"s": {"mass": 1.0, "diameter": 0.01, "EA": 1e5, "weight": 0.0}}
    d = {"model": "cable3d", "environment": {"water_density": 0.0}, "line_types": lt,
         "points": {"a": {"kind": "fixed", "position": [0.0, 0.0, 0.0]},
                    "b": {"kind": "fixed", "position": [2.02 * L, 0.0, 0.0]},
                    "m": {"kind": "free", "position": [1.01 * L, 0.0, 0.0], "mass": 2.0}},
         "lines": [{"name": "left", "end_a": "a", "end_b": "m",
                    "sections": [{"type": "s", "length": L, "segments": 5}]},
                   {"name": "right", "end_a": "m", "end_b": "b",
                    "sections": [{"type": "s", "length": L, "segments": 5}]}]}
    mech = cable3d_mechanism(load_scene(d))
    nodes = np.array(solve_equilibrium(mech).q, float).reshape(-1, 3)
    x = nodes[:, 0] / (2.02 * L)
    nodes[:, 1] += 0.3 * np.sin(math.pi * x)
    nodes[:, 2] += 0.2 * np.sin(2 * math.pi * x)
    drifts = []
    for dt in (0.02, 0.01, 0.005):
        tr = integrate(mech, 2.0, dt, method=GeneralizedAlpha(rho_inf=1.0), q0=nodes.ravel(),
                       v0=np.zeros(nodes.size), p=mech.params.values)
        assert tr.status == "converged"
        E = np.ravel(tr.outputs["kinetic_energy"]) + np.ravel(tr.outputs["potential_energy"])
        drifts.append(float(np.max(np.abs(E - E[0])) / E[0]))
    orders = [math.log2(a / b) for a, b in zip(drifts[:-1], drifts[1:])]
    assert all(1.8 < o < 2.2 for o in orders), (drifts, orders)
    assert drifts[-1] < 2e-3
    # the point's node moves: it is shared by both lines' end nodes
    m_pos = np.asarray(tr.outputs["m.position"]).reshape(len(tr.time), 3)
    np.testing.assert_allclose(m_pos, np.asarray(tr.outputs["left.positions"])
                               .reshape(len(tr.time), -1, 3)[:, -1])
    assert np.ptp(m_pos[:, 1]) > 0.1


# ----------------------------------------------------------------------------- MoorDyn decks

DECK = """--------------------- MoorDyn Input File ------------------------------------
Two lines meeting at a subsurface buoy
----------------------- LINE TYPES ------------------------------------------
TypeName   Diam    Mass/m     EA         BA/-zeta    EI         Cd     Ca     CdAx    CaAx
(name)     (m)     (kg/m)     (N)        (N-s/-)     (N-m^2)    (-)    (-)    (-)     (-)
chain      0.09    60         5.0e8      -1.0        0          1.2    1.0    0.4     0.0
rope       0.11    6          4.0e7      -1.0        0          1.2    1.0    0.1     0.0
---------------------- POINTS --------------------------------
ID    Type      X       Y       Z       Mass   Volume  CdA    Ca
(#)   (-)       (m)     (m)     (m)     (kg)   (m^3)   (m^2)  (-)
1     Fixed     -300    -80     -120    0      0       0      0
2     Vessel    40      60      -8      0      0       0      0
3     Free      -120    0       -50     400    4       1.5    0.5
---------------------- LINES ----------------------------------------
ID   LineType   AttachA  AttachB  UnstrLen  NumSegs  LineOutputs
(#)   (name)     (#)      (#)       (m)       (-)     (-)
1     chain      1        3         230       40      -
2     rope       3        2         170       40      -
---------------------- OPTIONS -----------------------------------------
1.0e7                kBot                 bottom stiffness (Pa/m)
1025.0               WtrDnsty             water density (kg/m^3)
120                  WtrDpth              water depth (m)
------------------------- need this line --------------------------------------
"""


def test_moordyn_deck_of_two_lines_and_a_free_point(tmp_path):
    """A MoorDyn v2 deck of two lines meeting at a Free point loads as a version-2 scene
    (points "1", "2", "3", lines "line1", "line2"), round-trips, and solves to MoorPy's
    System read from the same deck: fairlead tension within 0.5 % (measured 0.036 %), the
    buoy within 0.05 m (measured 0.010 m)."""
    path = tmp_path / "buoy.dat"
    path.write_text(DECK)
    s = load_scene(path)
    assert s.version == 2 and s.name == "buoy"
    assert [ln.name for ln in s.lines] == ["line1", "line2"]
    assert [(ln.end_a, ln.end_b) for ln in s.lines] == [("1", "3"), ("3", "2")]
    buoy = s.points["3"]
    assert (buoy.kind, buoy.mass, buoy.volume, buoy.cd_area, buoy.ca) == \
        (PointKind.FREE, 400.0, 4.0, (1.5, 1.5, 1.5), 0.5)
    assert s.points["2"].kind is PointKind.VESSEL and s.points["1"].kind is PointKind.FIXED
    assert load_scene(s.to_dict()) == s
    toml = tmp_path / "buoy.toml"
    toml.write_text(scene_to_toml(s))
    assert load_scene(toml) == s
    # a point's applied force (the 12-column rows) and a bad row, located on the deck line
    forced = DECK.replace("Mass   Volume  CdA", "Mass   Volume  Fx  Fy  Fz  CdA").replace(
        "(kg)   (m^3)", "(kg)   (m^3) (N) (N) (N)").replace(
        "-50     400    4       1.5", "-50     400    4   0  3000  0   1.5")
    for row in ("1     Fixed     -300    -80     -120    0      0       0      0",
                "2     Vessel    40      60      -8      0      0       0      0"):
        forced = forced.replace(row, row[:-22] + "0      0   0  0  0   0      0")
    path.write_text(forced)
    assert load_scene(path).points["3"].force == (0.0, 3000.0, 0.0)
    path.write_text(DECK.replace("1     chain      1        3", "1     chain      1        4"))
    with pytest.raises(SceneError, match=r"buoy.dat:17: .*attaches to point 4, which POINTS"):
        load_scene(path)

    mp = pytest.importorskip("moorpy")
    path.write_text(DECK)
    st = sc.solve_static(s)
    ms = mp.System(file=str(path))
    ms.initialize()
    ms.solveEquilibrium(tol=1e-6)
    assert st.lines["line2"].fairlead_tension == pytest.approx(
        np.linalg.norm(ms.lineList[1].fB), rel=5e-3)
    assert st.lines["line1"].anchor_tension == pytest.approx(
        np.linalg.norm(ms.lineList[0].fA), rel=5e-3)
    assert np.linalg.norm(st.points["3"].position - ms.pointList[2].r) < 0.05
