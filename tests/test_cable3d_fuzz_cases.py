"""cable3d statics that the fuzz study (studies/fuzz, its cable3d scenes) found returned wrong
as "converged", and what they must give now:

- a free end with an applied force reported its end force as the node's residual (zero)
  instead of the force the line exerts there (minus the applied force), so its
  ``fairlead_tension`` read 2e-8 N for a 7.9 kN pull (fuzz scene c11-0001);
- a free point (a clump weight) had no seabed contact of its own: resting on the bed, it sank
  through the contact of the line nodes beside it, 24 m under a 1e4 Pa/m bed (c11-0008); it
  now rests on the bed as the lines do (``cable3d_system.point_contact``), in statics and in
  the dynamics (contact, damper, friction);
- a light line lying on the bed up to a heavy clump resting there took, through its end
  node's contact, the clump's penetration, and reported 55.6 kN at the clump where it pulls
  2.5 kN (c11-0007): while a free point touches the bed, the half segment of each line beside
  it now rests where the line's neighbour node does (as a held end on the bed);
- a short stiff wire far from the origin (t33-0337): its round-off floor (10 x, 4.1 N) was
  above a node's weight (1.06 N), so the start, every segment at zero tension, passed as
  converged and the ends read 0.53 N for 40 and 60 N.
"""
from __future__ import annotations

import copy
import math

import casadi as ca
import numpy as np
import pytest

import symcable as sc
from symcable.analytic.catenary import elastic_catenary
from symcable.scene import load_scene

RHO, G = 1025.0, 9.80665


def test_free_end_force_is_the_lines_pull():
    """A rope hanging from a pinned end with a 3D force on its free end (out of every
    vertical plane through the ends): the line exerts minus that force on the free end, so
    the free end's tension is |force|, and the pinned end carries force plus weight (to the
    solver's tolerance)."""
    F = np.array([-7694.2, -1789.0, -124.2])
    lt = {"rope": {"mass": 23.74, "diameter": 0.1539, "EA": 3.956e7}}
    d = {"model": "cable3d", "line_types": lt,
         "sections": [{"type": "rope", "length": 764.2, "segments": 16}],
         "end_a": {"condition": "pinned", "position": [398.5, 985.9, -84.3]},
         "end_b": {"condition": "free", "force": F.tolist()}}
    st = sc.solve_static(d)
    tol = 10 * st.stats["tolerance"]
    np.testing.assert_allclose(st.fairlead_force, -F, atol=tol)
    assert st.fairlead_tension == pytest.approx(np.linalg.norm(F), abs=tol)
    assert st.tension[-1] == pytest.approx(np.linalg.norm(F), abs=tol)
    w = (23.74 - RHO * math.pi * 0.1539 ** 2 / 4) * G * 764.2
    np.testing.assert_allclose(st.anchor_force, F + np.array([0.0, 0.0, -w]), atol=tol)
    # the same line from the other end: the same numbers, ends swapped
    flipped = dict(d, end_a=d["end_b"], end_b=d["end_a"])
    st2 = sc.solve_static(flipped)
    assert st2.anchor_tension == pytest.approx(np.linalg.norm(F), abs=tol)
    assert st2.fairlead_tension == pytest.approx(st.anchor_tension, rel=1e-9)


def _clump(segments=(24, 22)) -> dict:
    """An anchor chain, a 5 t clump weight and a chain up to a fixed point out of the
    anchor's vertical plane; slack enough that the clump rests on the bed."""
    return {"model": "cable3d", "environment": {"depth": 50.0}, "seabed": {"stiffness": 1e6},
            "line_types": {"chain": {"mass": 100.0, "diameter": 0.1, "EA": 8e8}},
            "points": {"anchor": {"kind": "fixed", "position": [-100.0, 0.0, -50.0]},
                       "clump": {"kind": "free", "position": [0.0, 10.0, -45.0],
                                 "mass": 5000.0, "volume": 0.6},
                       "fairlead": {"kind": "fixed", "position": [90.0, 30.0, -10.0]}},
            "lines": [{"name": "lower", "end_a": "anchor", "end_b": "clump",
                       "sections": [{"type": "chain", "length": 120.0, "segments": segments[0]}]},
                      {"name": "upper", "end_a": "clump", "end_b": "fairlead",
                       "sections": [{"type": "chain", "length": 110.0, "segments": segments[1]}]}]}


@pytest.fixture(scope="module")
def clump():
    return sc.solve_static(_clump())


def test_clump_rests_on_the_seabed(clump):
    """The clump sinks into the bed no deeper than the chain under its own weight,
    |w| / (k d) = 8.3 mm (before: 24 m under a softer bed; here 1.7 mm measured), the seabed
    carries it (the lines' pull on it plus its weight less buoyancy is upward support), and
    its net force is zero."""
    st = clump
    w = (100.0 - RHO * math.pi * 0.01 / 4) * G
    sink = w / (1e6 * 0.1)
    z = st.points["clump"].position[2]
    assert -50.0 - sink <= z <= -50.0
    own = np.array([0.0, 0.0, -(5000.0 - RHO * 0.6) * G])
    support = -(st.points["clump"].force + own)
    assert abs(support[0]) + abs(support[1]) < 1e-6 * abs(own[2])
    assert 0.9 * abs(own[2]) < support[2] < 1.2 * abs(own[2])
    assert np.max(np.abs(st.points["clump"].net_force)) < 10 * st.stats["tolerance"]
    for line in st.lines.values():
        assert line.positions[:, 2].min() >= -50.0 - 3 * sink


def test_clump_on_the_seabed_against_moorpy():
    """MoorPy's System with the clump resting on its rigid bed (its point support ramped
    over 1 mm): the clump's place within 0.05 m, fairlead tension and the upper chain's
    grounded length converging to MoorPy's at first order (a touchdown between nodes):
    measured 4.8, 1.7, 0.33 % and 4.0, 1.7, 0.65 m at 24/22, 48/44, 96/88 segments; here the
    finest, within 1 % and 1.5 m."""
    mp = pytest.importorskip("moorpy")
    st = sc.solve_static(_clump((96, 88)))
    ms = mp.System(depth=50.0, rho=RHO, g=G)
    w = (100.0 - RHO * math.pi * 0.01 / 4) * G
    ms.setLineType(name="chain", mass=100.0, d_vol=0.1, EA=8e8, w=w, dnommm=100)
    ms.addPoint(1, [-100.0, 0.0, -50.0])
    ms.addPoint(0, [0.0, 10.0, -45.0], m=5000.0, v=0.6).zTol = 1e-3
    ms.addPoint(1, [90.0, 30.0, -10.0])
    ms.addLine(120.0, "chain", pointA=1, pointB=2)
    ms.addLine(110.0, "chain", pointA=2, pointB=3)
    ms.initialize()
    ms.solveEquilibrium(tol=1e-6)
    assert np.linalg.norm(st.points["clump"].position - ms.pointList[1].r) < 0.05
    assert st.lines["upper"].fairlead_tension == pytest.approx(
        np.linalg.norm(ms.lineList[1].fB), rel=0.01)
    assert st.lines["upper"].grounded_length == pytest.approx(ms.lineList[1].LBot, abs=1.5)


def test_point_contact_damper_and_friction():
    """The clump's own loads at a node 1 cm under the bed, moving: the contact pushes up
    (the spring, by the point's stiffness from ``point_contact``), the damper resists the
    vertical speed, and friction -mu N v_h / sqrt(|v_h|^2 + v_eps^2) opposes the sliding; a
    point well above the bed feels none of it (but the smooth ramp's tail)."""
    from symcable.models.system import point_contact, point_part
    d = _clump()
    d["seabed"].update(friction=0.6, damping=2e4, friction_velocity=0.01)
    scene = load_scene(d)
    pt = scene.points["clump"]
    K, width = point_contact(scene, "clump")
    mech = point_part(pt, scene.environment, scene.seabed, (K, width))
    f = ca.Function("f", [mech.q, mech.v, mech.p], [mech.outputs["own_force"].expr,
                                                     mech.outputs["contact_force"].expr])
    weight = (5000.0 - RHO * 0.6) * G
    v = np.array([0.3, -0.4, -0.05])
    def loads(z):
        own, normal = f([0.0, 0.0, z], v, mech.params.values)
        return np.ravel(own), float(np.ravel(normal)[0])

    own, normal = loads(-50.01)
    # the smooth ramp (g + sqrt(g^2 + width^2)) / 2 of the penetration g = 1 cm
    assert normal == pytest.approx(K * 0.5 * (0.01 + math.hypot(0.01, width)), rel=1e-9)
    on = 0.5 * (1.0 + 0.01 / math.hypot(0.01, width))   # the contact's smooth on-off factor
    damper = 2e4 * K / 1e6 * 0.05 * on
    assert own[2] == pytest.approx(-weight + normal + damper, rel=1e-6)
    slip = math.hypot(0.3, -0.4)
    np.testing.assert_allclose(own[:2], -0.6 * normal * v[:2] / math.sqrt(slip ** 2 + 1e-4),
                               rtol=1e-9)
    # 10 m above the bed only the smooth ramp's tail K width^2 / (4 * 10 m) is left (the
    # lines' contact has the same ramp, 10 times wider): 1.3e-7 of the weight
    own, normal = loads(-40.0)
    assert normal == pytest.approx(K * width ** 2 / 40.0, rel=1e-6)
    assert abs(normal) < 1e-6 * weight and abs(own[0]) < 1e-6 * weight
    # the stiffness lets what can press the clump down sink it by the chain's own penetration
    press = weight + (120.0 + 110.0) * (100.0 - RHO * math.pi * 0.01 / 4) * G
    assert K == pytest.approx(press / ((100.0 - RHO * math.pi * 0.01 / 4) * G / (1e6 * 0.1)))


def test_friction_and_motion_change_nothing_in_statics(clump):
    """Statics apply neither seabed friction nor a vessel's motion: the clump scene with
    both gives the same answer to round-off."""
    d = _clump()
    d["seabed"]["friction"] = 0.8
    d["points"]["fairlead"] = {"kind": "vessel", "position": [90.0, 30.0, -10.0],
                               "motion": {"period": 12.0, "amplitude": [2.0, 1.0, 1.0]}}
    st = sc.solve_static(copy.deepcopy(d))
    np.testing.assert_allclose(st.points["clump"].position, clump.points["clump"].position,
                               atol=1e-9)
    assert st.lines["upper"].fairlead_tension == pytest.approx(
        clump.lines["upper"].fairlead_tension, rel=1e-9)


def test_one_segment_between_held_ends_has_a_start():
    """A line of one segment between two held ends has no unknowns; its start is the empty
    vector (the start's indexing raised an IndexError on the empty list of moving nodes,
    fuzz scene c11-0030)."""
    from symcable.models.cable3d.line import build_cable3d
    d = {"model": "cable3d", "line_types": {"chain": {"mass": 71.0, "diameter": 0.06, "EA": 1.1e8}},
         "sections": [{"type": "chain", "length": 24.0, "segments": 1}],
         "end_a": {"condition": "pinned", "position": [-117.2, -847.7, -25.8]},
         "end_b": {"condition": "pinned", "position": [-108.0, -854.9, -45.7]}}
    mech = build_cable3d(load_scene(d))
    assert mech.n_q == 0
    starts = list(mech.starts())
    assert starts and all(np.asarray(s.q).size == 0 for s in starts)


def test_light_line_at_a_clump_on_the_bed_against_moorpy():
    """A 66 t clump resting on a soft default bed (1e5 Pa/m: it sinks 0.2 m) held by a chain
    and two ropes, the ropes lying on the bed up to it (fuzz scene c11-0007, rounded): each
    line's tensions within 3 % of its largest tension from MoorPy's (measured: 1.0 % on each
    line at the clump; before, the first rope read 55.6 kN there for MoorPy's 2.5 kN), the
    clump within 0.5 m (measured 0.3 m)."""
    mp = pytest.importorskip("moorpy")
    types = {"rope0": {"mass": 70.88, "diameter": 0.285, "EA": 9.911e7},
             "rope1": {"mass": 6.42, "diameter": 0.0797, "EA": 2.471e8},
             "chain2": {"mass": 303.5, "diameter": 0.1235, "EA": 2.667e9}}
    ends = [[-87.04, -409.97, -4.63], [517.36, -346.25, -44.82], [84.27, -11.95, -230.67]]
    lengths, segs = [401.38, 577.47, 199.74], [17, 18, 16]
    names = ["rope0", "rope1", "chain2"]
    d = {"model": "cable3d", "environment": {"depth": 230.67}, "seabed": {}, "line_types": types,
         "points": {**{f"end{k}": {"kind": "fixed", "position": e} for k, e in enumerate(ends)},
                    "P": {"kind": "free", "position": [118.2, -129.0, -122.3], "mass": 67116.0}},
         "lines": [{"name": f"line{k}", "end_a": f"end{k}", "end_b": "P",
                    "sections": [{"type": names[k], "length": lengths[k], "segments": segs[k]}]}
                   for k in range(3)]}
    st = sc.solve_static(d)
    ms = mp.System(depth=230.67, rho=RHO, g=G)
    for n, lt in types.items():
        w = (lt["mass"] - RHO * math.pi * lt["diameter"] ** 2 / 4) * G
        ms.setLineType(name=n, mass=lt["mass"], d_vol=lt["diameter"], EA=lt["EA"], w=w,
                       dnommm=1000 * lt["diameter"])
    for e in ends:
        ms.addPoint(1, e)
    ms.addPoint(0, [118.2, -129.0, -122.3], m=67116.0).zTol = 1e-3
    for k in range(3):
        ms.addLine(lengths[k], names[k], pointA=k + 1, pointB=4)
    ms.initialize()
    ms.solveEquilibrium(tol=1e-6)
    for k in range(3):
        line, ref = st.lines[f"line{k}"], ms.lineList[k]
        scale = max(np.linalg.norm(ref.fA), np.linalg.norm(ref.fB))
        assert abs(line.fairlead_tension - np.linalg.norm(ref.fB)) < 0.03 * scale, k
        assert abs(line.anchor_tension - np.linalg.norm(ref.fA)) < 0.03 * scale, k
    assert np.linalg.norm(st.points["P"].position - ms.pointList[3].r) < 0.5


def test_one_segment_between_held_ends_has_no_unknowns():
    """A cable3d line of one segment between two held ends has no unknowns: its check still
    gives scalars (an IndexError before, 7 fuzz scenes); a slack segment carries no tension,
    so each end takes half its submerged weight (to 1e-8: the tension-only law leaves a slack
    segment 1.3e-6 N of its smooth tail, measured)."""
    import symcable as sc

    d = {"model": "cable3d", "line_types": {"r": {"mass": 10.0, "diameter": 0.05, "EA": 1e7}},
         "sections": [{"type": "r", "length": 10.0, "segments": 1}],
         "end_a": {"condition": "pinned", "position": [0.0, 0.0, 0.0]},
         "end_b": {"condition": "pinned", "position": [9.0, 0.0, -2.0]}}
    st = sc.solve_static(d)
    w = sc.load_scene(d).line_types["r"].weight
    assert st.status == "converged"
    assert abs(st.fairlead_tension - 0.5 * w * 10.0) < 1e-8 * w * 10.0


def test_short_stiff_wire_far_from_the_origin_keeps_its_tension():
    """A 5.2 m wire (EA 1.85e9 N, 92 segments, node weight 1.06 N) between pinned ends 550 m
    from the origin, against the elastic catenary: the default tolerance now stays below a
    hundredth of a node's weight, so the end tensions (40.2 and 59.9 N) are right to the
    discretisation of a smooth catenary at 92 segments (1e-3 relative is 10 x that; before,
    both ends read 0.53 N)."""
    a = np.array([-69.0576566973566, -552.1753903544461, -342.0892780152257])
    b = np.array([-67.47065461146387, -554.2803273361055, -341.0327352376603])
    wire = {"mass": 2.2676115415835305, "diameter": 0.021296063211699624, "EA": 1853687391.7373426}
    L = 5.212212781090386
    d = {"model": "cable3d", "line_types": {"wire": wire},
         "sections": [{"type": "wire", "length": L, "segments": 92}],
         "end_a": {"condition": "pinned", "position": a.tolist()},
         "end_b": {"condition": "pinned", "position": b.tolist()}}
    r = sc.solve_static(d, estimate=False)
    w = (wire["mass"] - RHO * math.pi * wire["diameter"] ** 2 / 4) * G
    ref = elastic_catenary(float(np.hypot(*(b - a)[:2])), float(b[2] - a[2]), L,
                              wire["EA"], w)
    # the tolerance: a fiftieth of the round-off floor, 8 mN, under 1 % of a node's weight
    assert r.stats["residual_norm"] <= r.stats["tolerance"] < 0.01 * w * L / 92
    ta = math.hypot(ref.H, ref.V_a)
    tb = math.hypot(ref.H, ref.V_b)
    assert r.anchor_tension == pytest.approx(ta, rel=1e-3)
    assert r.fairlead_tension == pytest.approx(tb, rel=1e-3)
