"""Statics of the 3D position-vector cable (``model = "cable3d"``, issue 12, first step):

- planar = 3D: the OC3 line solved by ``planar`` and by ``cable3d``, in the x-z plane and in
  a vertical plane turned about z. In its plane the 3D line has the planar line's nodes,
  lumping, tension-only law and penalty seabed, so the two agree to the solver tolerance, far
  inside the discretisation error the issue allows (measured 5e-10 on the fairlead tension);
- the closed-form elastic catenary in a turned vertical plane (second order in segments);
- seed 003's argument: a rigid rotation of a stretched element changes no strain;
- a current across the line's plane carries it downstream, and the ends hold it.
"""
from __future__ import annotations

import math

import numpy as np
import pytest

import symcable as sc
from symcable.analytic import elastic_catenary
from symcable.models.common.elements import element_kernel


def _oc3_3d(angle: float) -> dict:
    """The OC3 demo scene as a cable3d dict, its vertical plane turned by ``angle`` about z
    (its motion dropped: statics only)."""
    d = sc.load_scene(sc.demo_scene_path("oc3")).to_dict()
    c, s = math.cos(angle), math.sin(angle)
    d["model"] = "cable3d"
    for end in ("end_a", "end_b"):
        x, z = d[end]["position"]
        d[end]["position"] = [x * c, x * s, z]
        d[end].pop("motion", None)
    cur = d.get("environment", {}).get("current")
    if cur is not None:
        d["environment"]["current"] = [cur[0] * c, cur[0] * s, cur[1]]
    return d


@pytest.fixture(scope="module")
def planar_oc3():
    return sc.solve_static(sc.demo_scene_path("oc3"))


@pytest.mark.parametrize("angle", [0.0, 0.7])
def test_planar_equals_3d_on_oc3(planar_oc3, angle, monkeypatch):
    """With the planar line's contact smoothing (1 % of the penetration under the line's
    weight; the 3D lines' default is 10 %, :data:`symcable.models.common.seabed.CONTACT_SMOOTHING`)
    cable3d is the same discrete line as the planar one; with its own default it differs by
    the smoothing alone: 2.3e-5 of the fairlead tension, far below the discretisation error
    (the test below it)."""
    from collections import OrderedDict

    import symcable.api.cable3d_static as c3s
    from symcable.models.common import seabed as seabed3d
    default = sc.solve_static(_oc3_3d(angle))
    assert default.fairlead_tension == pytest.approx(planar_oc3.fairlead_tension, rel=1e-4)
    assert default.grounded_length == pytest.approx(planar_oc3.grounded_length, abs=0.1)
    monkeypatch.setattr(seabed3d, "CONTACT_SMOOTHING", 0.01)
    monkeypatch.setattr(c3s, "_CACHE", OrderedDict())  # a Mechanism built with it
    st = sc.solve_static(_oc3_3d(angle))
    assert st.status == "converged"
    assert st.positions.shape[1] == 3
    # the same discrete line: to the solver's tolerance (1e-9 of the force scale), not
    # merely the discretisation error
    assert st.fairlead_tension == pytest.approx(planar_oc3.fairlead_tension, rel=1e-7)
    assert st.anchor_tension == pytest.approx(planar_oc3.anchor_tension, rel=1e-7)
    assert st.grounded_length == pytest.approx(planar_oc3.grounded_length, abs=1e-4)
    # every node in the turned vertical plane, at the planar line's (x, z)
    u = np.array([math.cos(angle), math.sin(angle)])
    horiz = st.positions[:, :2] @ u
    np.testing.assert_allclose(horiz, planar_oc3.positions[:, 0], atol=1e-6)
    np.testing.assert_allclose(st.positions[:, 2], planar_oc3.positions[:, 1], atol=1e-6)
    off_plane = st.positions[:, :2] @ np.array([-u[1], u[0]])
    assert np.max(np.abs(off_plane)) < 1e-8


def test_planar_equals_3d_at_the_seed_001_stiffness(monkeypatch):
    """The OC3 line's other EA, seed 001's 3.84243e7 N (ten times softer), in a plane turned
    by 2 rad: with equal contact smoothing the same discrete line as the planar one, to the
    solver's tolerance (1e-7 of the fairlead and anchor tensions, 1e-4 m of grounded length,
    as above)."""
    from collections import OrderedDict

    import symcable.api.cable3d_static as c3s
    from symcable.models.common import seabed as seabed3d
    planar = sc.load_scene(sc.demo_scene_path("oc3")).to_dict()
    planar["line_types"]["chain"]["EA"] = 3.84243e7
    flat = sc.solve_static(planar)
    d = _oc3_3d(2.0)
    d["line_types"]["chain"]["EA"] = 3.84243e7
    monkeypatch.setattr(seabed3d, "CONTACT_SMOOTHING", 0.01)
    monkeypatch.setattr(c3s, "_CACHE", OrderedDict())
    st = sc.solve_static(d)
    assert st.status == flat.status == "converged"
    assert st.fairlead_tension == pytest.approx(flat.fairlead_tension, rel=1e-7)
    assert st.anchor_tension == pytest.approx(flat.anchor_tension, rel=1e-7)
    assert st.grounded_length == pytest.approx(flat.grounded_length, abs=1e-4)


def test_elastic_catenary_in_a_turned_plane():
    """A suspended line between (0, 0, 0) and a point 300 m away at 35° from x and 80 m
    up: the fairlead and anchor tensions of the elastic catenary within 4 / N^2 (second
    order, the planar line's measured constant is under 2; N = 40)."""
    L, EA, mass, d = 400.0, 5e8, 100.0, 0.1
    w = (mass - 1025.0 * math.pi * d * d / 4) * 9.80665
    span, height, th = 300.0, 80.0, math.radians(35.0)
    scene = {"model": "cable3d",
             "line_types": {"chain": {"mass": mass, "diameter": d, "EA": EA}},
             "sections": [{"type": "chain", "length": L, "segments": 40}],
             "end_a": {"condition": "pinned", "position": [0.0, 0.0, -200.0]},
             "end_b": {"condition": "pinned",
                       "position": [span * math.cos(th), span * math.sin(th), -120.0]}}
    st = sc.solve_static(scene)
    ref = elastic_catenary(span, height, L, EA, w)
    tol = 4 / 40 ** 2 * ref.fairlead_tension
    assert abs(st.fairlead_tension - ref.fairlead_tension) <= tol
    assert abs(st.anchor_tension - ref.anchor_tension) <= tol
    # the line's weight on the two ends
    assert -(st.anchor_force[2] + st.fairlead_force[2]) == pytest.approx(w * L, rel=1e-9)


def test_rigid_rotation_makes_no_strain():
    """Seed 003's argument for the position-vector element: strain from the current length
    against the rest length is invariant under any rigid rotation (and the axial force
    turns with the element)."""
    k = element_kernel()
    rng = np.random.default_rng(3)
    xa, xb = rng.normal(size=3), rng.normal(size=3)
    L0 = 0.9 * float(np.linalg.norm(xb - xa))
    args = dict(va=np.zeros(3), vb=np.zeros(3), u=np.zeros(3), L0=L0, EA=1e7, BA=0.0,
                EAs=1e-3, delta=1e-9, wall=1.0, w=0.0, d=0.1, cdn=1.2, cdt=0.1, rho=0.0,
                load=1.0)
    ref = {key: np.asarray(val, float).ravel() for key, val in k(xa=xa, xb=xb, **args).items()}
    for _ in range(5):
        R, _ = np.linalg.qr(rng.normal(size=(3, 3)))
        R *= np.sign(np.linalg.det(R))
        out = {key: np.asarray(val, float).ravel()
               for key, val in k(xa=R @ xa, xb=R @ xb, **args).items()}
        assert out["e"][0] == pytest.approx(ref["e"][0], abs=1e-14)
        assert out["T"][0] == pytest.approx(ref["T"][0], rel=1e-13)
        np.testing.assert_allclose(out["fa"], R @ ref["fa"], atol=1e-6)


def test_current_across_the_plane():
    """A 1 m/s current along +y across a line hanging in the x-z plane: every interior node
    moves downstream (+y), the ends are pulled downstream, and the line's horizontal
    across-current balance holds (the ends' y forces sum to the total drag, which the
    solver's force balance checks; here: it is positive and no more than the drag on the
    line held straight across the current, 0.5 rho d Cd U^2 L)."""
    L, d, cdn = 150.0, 0.1, 1.2
    scene = {"model": "cable3d", "environment": {"current": [0.0, 1.0, 0.0]},
             "line_types": {"chain": {"mass": 60.0, "diameter": d, "EA": 5e8,
                                      "cd_normal": cdn}},
             "sections": [{"type": "chain", "length": L, "segments": 30}],
             "end_a": {"condition": "pinned", "position": [0.0, 0.0, -100.0]},
             "end_b": {"condition": "pinned", "position": [120.0, 0.0, -20.0]}}
    st = sc.solve_static(scene)
    assert st.status == "converged"
    assert np.all(st.positions[1:-1, 1] > 0.0)
    pull = st.anchor_force[1] + st.fairlead_force[1]
    assert 0.0 < pull <= 0.5 * 1025.0 * d * cdn * 1.0 * L * (1 + 1e-3)


def test_moorpy_line_out_of_the_xz_plane():
    """The OC3 line with its anchor at 35° from x and its fairlead 848.67 m from the anchor
    at 20° (neither end in the x-z plane), against MoorPy's 3D System: fairlead tension
    within 0.5 % (the issue's criterion; measured 0.04 %: the penalty seabed and 50
    segments) and grounded length within 1 % (measured 0.17 %); the fairlead force's
    direction within 1e-3 rad."""
    import moorpy as mp

    th, ph = math.radians(35.0), math.radians(20.0)
    mass, d, EA = 77.7066, 0.09, 3.84243e8
    w = (mass - 1025.0 * math.pi * d * d / 4) * 9.80665
    pa = np.array([-853.87 * math.cos(th), -853.87 * math.sin(th), -320.0])
    pb = np.array([pa[0] + 848.67 * math.cos(ph), pa[1] + 848.67 * math.sin(ph), -70.0])
    ms = mp.System(depth=320.0, rho=1025.0, g=9.80665)
    lt = ms.setLineType(name="chain", mass=mass, d_vol=d, EA=EA, w=w, dnommm=90.0)
    ms.addPoint(1, pa)
    ms.addPoint(1, pb)
    ms.addLine(902.2, lt, pointA=1, pointB=2)
    ms.initialize()
    ms.solveEquilibrium()
    line = ms.lineList[0]
    scene = {"model": "cable3d", "environment": {"depth": 320.0}, "seabed": {"stiffness": 1e5},
             "line_types": {"chain": {"mass": mass, "diameter": d, "EA": EA}},
             "sections": [{"type": "chain", "length": 902.2, "segments": 50}],
             "end_a": {"condition": "pinned", "position": pa.tolist()},
             "end_b": {"condition": "pinned", "position": pb.tolist()}}
    st = sc.solve_static(scene)
    assert st.fairlead_tension == pytest.approx(float(np.linalg.norm(line.fB)), rel=5e-3)
    assert st.grounded_length == pytest.approx(float(line.LBot), rel=1e-2)
    cos = np.dot(st.fairlead_force, line.fB) / (st.fairlead_tension * np.linalg.norm(line.fB))
    assert math.acos(min(1.0, cos)) < 1e-3
