"""A submerged buoyant body moored by three chains at 120 degrees (issue 13, parts 1 and 6:
the OC3 spar's layout at a quarter of its size, the chains fully suspended): its static
equilibrium and its exact 6x6 mooring stiffness (``linearize``) against MoorPy's and against
central differences of the static force on the body held at offsets; the equilibrium of a
rotated scene; a time run.

MoorPy's lines are exact elastic catenaries, symcable's lumped-mass chains: the difference
is the discretisation error, second order in the segments (measured on the stiffness's
diagonal: 1.7e-3, 7.6e-4, 4.3e-4, 1.9e-4 at 20, 30, 40, 60 segments). With the chains'
ends on the seabed, the tangent stiffness of a discrete chain sees a fixed set of nodes in
contact (the touchdown does not move to first order) and differs from the continuous
catenary's by some per cent that more segments do not remove (+-10 % at 20-120 segments on
this layout with 55-150 m on the bed, 1.2 % at any segment count with a stiffer bed): the
comparison is made where no chain touches the bed.
"""
from __future__ import annotations

import math

import numpy as np
import pytest

import symcable as sc
from symcable.scene.bodies import rotation_rpy

RHO, G = 1025.0, 9.80665
DEPTH, R_ANCHOR, R_FAIR, LENGTH = 80.0, 213.5, 5.0, 215.0
MASS, VOLUME, CG, CB = 2.0e5, 250.0, (0.0, 0.0, -3.0), (0.0, 0.0, 1.0)
CHAIN = {"mass": 77.7, "diameter": 0.09, "EA": 3.84e8}


def _moored(n: int = 20, yaw: float = 0.0) -> dict:
    points, lines = {}, []
    for k in range(3):
        th = math.radians(yaw + 120 * k)
        points[f"anchor{k}"] = {"kind": "fixed", "position": [R_ANCHOR * math.cos(th),
                                                             R_ANCHOR * math.sin(th), -DEPTH]}
        tb = math.radians(120 * k)
        lines.append({"name": f"chain{k}", "end_a": f"anchor{k}",
                      "end_b": f"spar@[{R_FAIR * math.cos(tb)}, {R_FAIR * math.sin(tb)}, -5.0]",
                      "sections": [{"type": "chain", "length": LENGTH, "segments": n}]})
    return {"model": "cable3d", "environment": {"depth": DEPTH, "gravity": G},
            "seabed": {"stiffness": 1e8}, "line_types": {"chain": CHAIN}, "points": points,
            "bodies": {"spar": {"mass": MASS, "volume": VOLUME, "inertia": [4e6, 4e6, 1e6],
                                "position": [0.0, 0.0, -30.0], "orientation": [0, 0, yaw],
                                "center_of_gravity": list(CG),
                                "center_of_buoyancy": list(CB)}},
            "lines": lines}


@pytest.fixture(scope="module")
def moored():
    d = _moored()
    return sc.solve_static(d, codegen=False), sc.linearize(d)


def _relative(K, ref):
    """Entry-wise difference relative to the diagonal's scale sqrt(|K_ii K_jj|)."""
    d = np.sqrt(np.abs(np.outer(np.diag(ref), np.diag(ref))))
    return np.abs(K - ref) / d


def test_stiffness_against_moorpy(moored):
    """MoorPy's System with the same body (mass at the centre of gravity, buoyancy at the
    centre of buoyancy as its metacentre rM, no waterplane) and lines, solved to 1e-8:
    the body's pose within 2 cm (measured 8.1 mm, in heave), the fairlead tension within
    0.1 % (measured 0.012 %), and symcable's 6x6 mooring stiffness (lines condensed, weight
    and buoyancy included, global axes) within 1 % of MoorPy's analytic getStiffnessA entry
    by entry relative to the diagonal (measured 1.8e-3 at 20 segments: the discretisation,
    module docstring), symmetric to round-off (measured 1.1e-13 of the diagonal: it is the
    Hessian of the potential energy at an equilibrium)."""
    mp = pytest.importorskip("moorpy")
    st, lin = moored
    ms = mp.System(depth=DEPTH, rho=RHO, g=G)
    w = (CHAIN["mass"] - RHO * math.pi * CHAIN["diameter"] ** 2 / 4) * G
    ms.setLineType(name="chain", mass=CHAIN["mass"], d_vol=CHAIN["diameter"], EA=CHAIN["EA"],
                   w=w, dnommm=90)
    body = ms.addBody(0, [0, 0, -30.0, 0, 0, 0], m=MASS, v=VOLUME, rCG=list(CG), rM=list(CB))
    for k in range(3):
        th = math.radians(120 * k)
        ms.addPoint(1, [R_ANCHOR * math.cos(th), R_ANCHOR * math.sin(th), -DEPTH])
        ms.addPoint(1, [R_FAIR * math.cos(th), R_FAIR * math.sin(th), -5.0], body=1)
        ms.addLine(LENGTH, "chain", pointA=2 * k + 1, pointB=2 * k + 2)
    ms.initialize()
    ms.solveEquilibrium(tol=1e-8)
    spar = st.bodies["spar"]
    assert np.linalg.norm(spar.position - body.r6[:3]) < 2e-2
    np.testing.assert_allclose(spar.roll_pitch_yaw, 0.0, atol=1e-9)
    assert max(ln.LBot for ln in ms.lineList) == 0.0  # fully suspended (module docstring)
    assert st.lines["chain0"].fairlead_tension == pytest.approx(
        np.linalg.norm(ms.lineList[0].fB), rel=1e-3)
    K, KA = lin.body_stiffness["spar"], body.getStiffnessA(lines_only=False)
    assert np.max(_relative(K, KA)) < 1e-2, _relative(K, KA)
    assert np.max(_relative(K, K.T)) < 1e-12
    # the body's net force is zero at equilibrium, to the solver's tolerance
    assert np.max(np.abs(spar.net_force)) < 10 * st.stats["tolerance"]


def test_stiffness_against_central_differences():
    """The same layout at 5 segments: the stiffness from linearize against central
    differences (1 mm, 1e-3 degree) of the static force and moment on the body held fixed at
    offsets (the lines' through BodyState.force and .moment, its own weight and buoyancy
    added), within 1e-5 relative to the diagonal (measured 3e-7: the differences' truncation
    and the solves' tolerance)."""
    d = _moored(5)
    st = sc.solve_static(d, codegen=False)
    K = sc.linearize(d).body_stiffness["spar"]
    x0 = np.asarray(st.bodies["spar"].position)

    def net(dx, drpy):
        dd = _moored(5)
        dd["bodies"]["spar"] = {"kind": "fixed", "position": list(x0 + dx),
                                "orientation": list(drpy)}
        b = sc.solve_static(dd, codegen=False).bodies["spar"]
        R = rotation_rpy(drpy)
        f = np.r_[b.force, b.moment]
        for load, at in ((np.array([0, 0, -MASS * G]), CG),
                         (np.array([0, 0, RHO * G * VOLUME]), CB)):
            f += np.r_[load, np.cross(R @ np.asarray(at), load)]
        return f

    fd = np.zeros((6, 6))
    for j in range(6):
        e = np.eye(3)[j % 3]
        if j < 3:
            fd[:, j] = -(net(1e-3 * e, np.zeros(3)) - net(-1e-3 * e, np.zeros(3))) / 2e-3
        else:
            fd[:, j] = -(net(np.zeros(3), 1e-3 * e) - net(np.zeros(3), -1e-3 * e)) \
                / (2 * math.radians(1e-3))
    assert np.max(_relative(fd, K)) < 1e-5, _relative(fd, K)


def _asymmetric(angle: float) -> dict:
    """Three chains of different lengths at uneven angles to a body whose centre of gravity
    is off its axis, the whole turned by ``angle`` degrees about the vertical."""
    d = _moored(10, yaw=0.0)
    spar = d["bodies"]["spar"]
    spar.update(center_of_gravity=[0.4, -0.3, -3.0], orientation=[0.0, 0.0, angle])
    for k, (th, length) in enumerate(((10.0, 214.0), (135.0, 216.0), (250.0, 215.0))):
        t = math.radians(th + angle)
        d["points"][f"anchor{k}"]["position"] = [R_ANCHOR * math.cos(t), R_ANCHOR * math.sin(t),
                                                 -DEPTH]
        d["lines"][k]["sections"][0]["length"] = length
    c, s = math.cos(math.radians(angle)), math.sin(math.radians(angle))
    spar["position"] = [c * 3.0 - s * 2.0, s * 3.0 + c * 2.0, -30.0]
    return d


def test_rotated_scene_gives_the_rotated_equilibrium():
    """Anchors, the body's start and its orientation turned by 40 degrees about z: the body
    comes to rest at the first equilibrium turned by 40 degrees (position within 1e-6 m,
    rotation matrix within 1e-8, tensions within 1e-8: the static tolerance, 3.4e-3 N, over
    the softest stiffness, 4.3e4 N/m, is 8e-8 m; measured 2.6e-11 m, 5.7e-14 and 1.5e-12)."""
    a = sc.solve_static(_asymmetric(0.0), codegen=False)
    b = sc.solve_static(_asymmetric(40.0), codegen=False)
    Rz = rotation_rpy((0.0, 0.0, 40.0))
    pa, pb = a.bodies["spar"], b.bodies["spar"]
    assert np.linalg.norm(pa.roll_pitch_yaw[:2]) > 0.1  # the offset centre of gravity tilts it
    np.testing.assert_allclose(pb.position, Rz @ pa.position, atol=1e-6)
    np.testing.assert_allclose(rotation_rpy(pb.roll_pitch_yaw),
                               Rz @ rotation_rpy(pa.roll_pitch_yaw), atol=1e-8)
    for k in range(3):
        assert b.lines[f"chain{k}"].fairlead_tension == pytest.approx(
            a.lines[f"chain{k}"].fairlead_tension, rel=1e-8)


def test_time_run_of_the_moored_body():
    """sc.simulate on the moored body in a 0.5 m/s current (drag and added mass on the body)
    pulled by a fourth line from a vessel point moving harmonically: a SystemTrajectory whose
    .bodies give the pose, velocities and the lines' force; at t = 0 the static solution (the
    run starts at rest from it); the body moves; the force on it is the sum of its lines'
    end forces at every sample."""
    d = _moored(8)
    d["environment"]["current"] = [0.5, 0.0, 0.0]
    d["bodies"]["spar"].update(cd_area=[20.0, 20.0, 10.0], ca_volume=[100.0, 100.0, 150.0])
    d["points"]["ship"] = {"kind": "vessel", "position": [60.0, 0.0, -5.0],
                           "motion": {"period": 8.0, "amplitude": [2.0, 0.0, 0.5],
                                      "phase_deg": [0.0, 0.0, 0.0]}}
    d["line_types"]["rope"] = {"mass": 5.0, "diameter": 0.08, "EA": 5e7}
    d["lines"].append({"name": "tow", "end_a": "spar@[0.0, 0.0, 2.0]", "end_b": "ship",
                       "sections": [{"type": "rope", "length": 58.0, "segments": 6}]})
    st = sc.solve_static(d)
    tr = sc.simulate(d, 8.0, 0.05)
    assert tr.status == "converged" and tr.body_names == ("spar",)
    b = tr.bodies["spar"]
    assert set(b) == {"position", "orientation", "roll_pitch_yaw", "velocity",
                      "angular_velocity", "force", "moment"}
    np.testing.assert_allclose(b["position"][0], st.bodies["spar"].position, atol=1e-7)
    np.testing.assert_allclose(b["roll_pitch_yaw"][0], st.bodies["spar"].roll_pitch_yaw,
                               atol=1e-6)
    assert np.ptp(b["position"][:, 0]) > 0.01
    lines = tr.lines
    ends = sum(lines[f"chain{k}"].fairlead_force for k in range(3)) + lines["tow"].anchor_force
    np.testing.assert_allclose(b["force"], ends, atol=1e-9 * np.max(np.abs(ends)))
    np.testing.assert_allclose(np.linalg.norm(b["orientation"], axis=1), 1.0, atol=1e-12)
    assert "body spar" in tr.summary()


def test_periodic_response_with_a_free_body_equals_the_long_run():
    """The moored body pulled by a taut rope (60 kg/m, EA 5e7 N, 37 kN at rest) from a vessel
    point moving 2 m in surge and 0.6 m in heave with a period of 12 s (away from the
    system's modes at 17.6 and 7.9 s), 4 segments per line. The free body's quaternion norm
    is neutral in time; the periodic solvers make it relax (``spar.norm_rate``), so the
    periodic state is isolated. Shooting (at simulate's rho_inf and step, T/100) against the
    last period of a 20-period run from rest: measured 7e-5 of the rope's tension range
    (13.6 kN), 1e-3 allowed for what is left of the start-up transient of the slowest mode
    (17.6 s, damped by the current's drag on the body); the body moves (0.16 m in surge)
    and its quaternion keeps unit norm."""
    T = 12.0
    d = _moored(4)
    d["environment"]["current"] = [0.5, 0.0, 0.0]
    d["bodies"]["spar"].update(cd_area=[20.0, 20.0, 10.0], ca_volume=[100.0, 100.0, 150.0])
    d["points"]["ship"] = {"kind": "vessel", "position": [60.0, 0.0, -5.0],
                           "motion": {"period": T, "amplitude": [2.0, 0.0, 0.6],
                                      "phase_deg": [0.0, 0.0, 0.0]}}
    d["line_types"]["rope"] = {"mass": 60.0, "diameter": 0.08, "EA": 5e7}
    d["lines"].append({"name": "tow", "end_a": "spar@[0.0, 0.0, 2.0]", "end_b": "ship",
                       "sections": [{"type": "rope", "length": 66.0, "segments": 4}]})
    per = sc.solve_periodic(d, "shooting")
    assert per.status == "converged"
    b = per.bodies["spar"]
    np.testing.assert_allclose(np.linalg.norm(b["orientation"], axis=1), 1.0, atol=1e-12)
    assert np.ptp(b["position"][:, 0]) > 0.1
    tension = per.lines["tow"].fairlead_tension
    tr = sc.simulate(d, 20 * T, T / 100)
    last = tr.time >= 19 * T - 1e-9
    run = tr.lines["tow"].fairlead_tension[last]
    ref = np.interp(tr.time[last] - 19 * T, np.r_[per.time, T], np.r_[tension, tension[0]])
    assert np.max(np.abs(run - ref)) < 1e-3 * np.ptp(tension)
