"""Statics of the Kirchhoff rod (``model = "rod"``; issue 14 items 1-3): the discrete elastic
rod of symcable.models.rod.rod solved by the generic solve_equilibrium.

- the tip-loaded elastica clamped along a direction turned 0.7 rad about z, against its
  elliptic-integral closed form, with the order in segments measured;
- the heavy cantilever: small deflections against w L^4 / (8 EI) (order measured), large
  sag against the planar model;
- two principal stiffnesses: the clamp's twist turns which one the plane's bending meets;
- the reference frame's hook: re-anchoring at a solution leaves it a solution;
- the vertex kernel: invariant under rigid motions and a uniform spin, forces and torques
  balanced.
"""
from __future__ import annotations

import math

import casadi as ca
import numpy as np
import pytest

import symcable as sc
from symcable.analytic import cantilever_tip_load, heavy_cantilever_small
from symcable.errors import SceneError
from symcable.models.rod.rod import build_rod
from symcable.models.rod.frames import (reference_director, reference_twist, transport,
                                       vertex_kernel)
from symcable.scene import load_scene
from symcable.solvers.equilibrium import solve_equilibrium

L, EI, GJ, TURN = 2.0, 10.0, 7.0, 0.7
PLANE = np.array([math.cos(TURN), math.sin(TURN)])


def cantilever(*, tip=0.0, weight=0.0, segments=20, EA=None, ei=EI, twist=None,
               model="rod") -> dict:
    """Clamped at the origin along PLANE, free at the other end with a downward dead load
    ``tip`` (N); in air. ``model = "planar"``: the same along +x."""
    lt = {"EA": EA or 1e7 * EI / L**2, "EI": ei, "mass": 1.0, "diameter": 0.02,
          "weight": weight}
    d = {"model": model, "environment": {"water_density": 0.0},
         "line_types": {"beam": lt},
         "sections": [{"type": "beam", "length": L, "segments": segments}],
         "end_a": {"condition": "clamped", "position": [0.0, 0.0, 0.0],
                   "direction": [PLANE[0], PLANE[1], 0.0]},
         "end_b": {"condition": "free", "force": [0.0, 0.0, -tip]}}
    if model == "rod":
        lt["GJ"] = GJ
        if twist is not None:
            d["end_a"]["twist_deg"] = twist
    else:
        d["end_a"] = {"condition": "clamped", "position": [0.0, 0.0], "angle_deg": 0.0}
        d["end_b"]["force"] = [0.0, -tip]
    return d


def solve(d):
    mech = build_rod(load_scene(d))
    eq = solve_equilibrium(mech, codegen=False)
    assert eq.status == "converged"
    return mech, eq


def _in_plane(X) -> tuple[float, float, float]:
    """(horizontal along PLANE, z, largest distance off the vertical plane) of the tip, m."""
    off = X[:, :2] @ np.array([-PLANE[1], PLANE[0]])
    return float(X[-1, :2] @ PLANE), float(X[-1, 2]), float(np.max(np.abs(off)))


@pytest.fixture(scope="module")
def elastica():
    """The tip-loaded cantilever at P L^2 / EI = 5 (about 60 deg of tip rotation) at 10, 20,
    40 segments: (P, [(mech, eq)])."""
    P = 5.0 * EI / L**2
    return P, [solve(cantilever(tip=P, segments=n)) for n in (10, 20, 40)]


def test_tip_loaded_elastica(elastica):
    """Against the elliptic-integral elastica. Measured tip errors (along the plane) 1.85e-3,
    5.93e-4, 1.63e-4 L at 10, 20, 40 segments (orders 1.64, 1.86: second order reached
    from above, as cable3d's bending, which the isotropic untwisted rod reduces to), z
    errors under 7e-4 L. Asserted: both within 2.5e-4 L at 40 (1 % of the deflection is
    5e-3 L), the last order above 1.7; the rod stays in its plane and untwisted to 1e-9
    (round-off of the solve); the clamp's moment P x_tip within 1e-3 (measured 2e-4)."""
    P, runs = elastica
    ref = cantilever_tip_load(L, EI, P)
    errors = []
    for mech, eq in runs:
        x, z, off = _in_plane(eq.outputs["positions"])
        errors.append(abs(x - ref["x_tip"]) / L)
        assert abs(z - ref["z_tip"]) < 7e-4 * L
        assert off < 1e-9 * L
        assert np.max(np.abs(eq.outputs["twist_angles"])) < 1e-9
    assert errors[-1] < 2.5e-4
    assert math.log2(errors[1] / errors[2]) > 1.7, errors
    M0 = np.linalg.norm(runs[-1][1].outputs["bending_moment"][0])
    assert M0 == pytest.approx(P * ref["x_tip"], rel=1e-3)


def test_guided_end_is_two_half_cantilevers():
    """Clamped at A, end B guided (condition = "guided": free, its tangent held along the
    clamp's) under a tip load P = 20 EI / L^2: antisymmetric about the midpoint, an
    inflection, so each half is the cantilever of length L / 2 under P (P (L/2)^2 / EI = 5,
    the elastica above), and the tip is at twice its closed-form tip. Measured errors along
    the plane 1.85e-3, 5.93e-4 L at 20, 40 segments (the 10- and 20-segment cantilever's),
    z errors 6.9e-4, 4.2e-5 L. Asserted: within 1e-3 L at 40 (1 % of the deflection is 7e-3
    L), in the plane to 1e-9 L; the guide takes no force (the rod's force on end B is the
    applied load's reaction, to 1e-6 of P: the solve's tolerance)."""
    P = 20.0 * EI / L**2
    half = cantilever_tip_load(L / 2, EI, P)
    d = cantilever(tip=P, segments=40)
    d["end_b"] = {"condition": "guided", "direction": [PLANE[0], PLANE[1], 0.0],
                  "force": [0.0, 0.0, -P]}
    _, eq = solve(d)
    x, z, off = _in_plane(eq.outputs["positions"])
    assert abs(x - 2 * half["x_tip"]) < 1e-3 * L
    assert abs(z - 2 * half["z_tip"]) < 1e-3 * L
    assert off < 1e-9 * L
    np.testing.assert_allclose(np.ravel(eq.outputs["end_force_b"]), [0.0, 0.0, P], atol=1e-6 * P)


def test_small_deflection_heavy_cantilever_second_order():
    """w L^3 / EI = 1e-4: the geometric nonlinearity (~1e-8 relative) and the strain (EA is
    1e8 w L) are far below the discretisation error. The tip against w L^4 / (8 EI) at 8,
    16, 32 segments: measured relative errors 1 / N^2 (order 2.000, the mirror-ghost clamp
    of cable3d); asserted within 0.01 of 2 and under 1e-3 at 32 (well inside 1 %)."""
    w = 1e-4 * EI / L**3
    ref = heavy_cantilever_small(L, EI, w)
    errors = []
    for n in (8, 16, 32):
        _, eq = solve(cantilever(weight=w, EA=1e8 * w * L, segments=n))
        errors.append(abs(-_in_plane(eq.outputs["positions"])[1] / ref - 1.0))
    orders = np.log2(np.array(errors[:-1]) / np.array(errors[1:]))
    assert np.all(np.abs(orders - 2.0) < 0.01), (errors, orders)
    assert errors[-1] < 1e-3


def test_heavy_cantilever_matches_the_planar_model():
    """Large sag (EI / (w L^3) = 0.1, as cable3d's test): the rod at 20 segments against
    the planar model, tips within 5e-4 L (each model's discretisation error; cable3d
    measured 2.6e-4 L at 20), through sc.solve_static (symcable.api.rod_static): the clamp
    carries the weight w L (1e-9 relative)."""
    w = EI / (0.1 * L**3)
    st = sc.solve_static(cantilever(weight=w), codegen=False)
    assert st.status == "converged"
    planar = sc.solve_static(cantilever(weight=w, model="planar"), codegen=False)
    x, z, off = _in_plane(st.positions)
    np.testing.assert_allclose(st.anchor_force, [0.0, 0.0, -w * L], atol=1e-9 * w * L)
    assert abs(x - planar.positions[-1, 0]) < 5e-4 * L
    assert abs(z - planar.positions[-1, 1]) < 5e-4 * L
    assert off < 1e-9 * L


def test_principal_stiffnesses_follow_the_clamps_twist():
    """EI = [EI_1, EI_2] = [4 EI, EI]: with the clamp's material director m1 vertical
    (twist 0; the reference director of a horizontal direction is z), bending in the
    vertical plane turns about m2 and meets EI_2; with the clamp turned 90 deg it meets
    EI_1. Each against the isotropic rod of that stiffness at the same 10 segments: the
    same discrete equations, so to 1e-9 L (the solves' tolerance)."""
    P = 5.0 * EI / L**2
    for twist, ei in ((0.0, EI), (90.0, 4 * EI)):
        _, eq = solve(cantilever(tip=P, segments=10, ei=[4 * EI, EI], twist=twist))
        _, iso = solve(cantilever(tip=P, segments=10, ei=ei))
        np.testing.assert_allclose(eq.outputs["positions"], iso.outputs["positions"],
                                   atol=1e-9 * L)


def test_reanchoring_keeps_the_solution(elastica):
    """The reference frame's hook (symcable.models.rod.rod): anchors := the output
    reference_frame at a solution, twists unchanged, is the same material frame, so the
    same q is still a solution (residual at the solver's tolerance) and Newton stays put
    (to 1e-10 L)."""
    _, runs = elastica
    mech, eq = runs[0]
    p = mech.params.with_values(eq.p, frame=np.asarray(eq.outputs["reference_frame"]).ravel())
    assert not np.allclose(p, eq.p)  # the anchors moved (the rod bent 60 deg)
    again = solve_equilibrium(mech, p, codegen=False)
    assert again.status == "converged"
    np.testing.assert_allclose(again.q, eq.q, atol=1e-10 * L)


def test_vertex_kernel_invariances():
    """The energy of a vertex is unchanged by a rigid rotation (anchors rotated with it) and
    translation; its forces sum to zero; for isotropic bending, a uniform spin (both twists
    turned alike) changes nothing (GJ sees their difference, and the bending no frame), so
    its two torques cancel (with EI_1 != EI_2 they do not: the spin turns the stiff axis);
    a straight, untwisted vertex has no energy (1e-12 relative: round-off)."""
    k = vertex_kernel()
    rng = np.random.default_rng(3)
    X = rng.normal(size=(3, 3))
    t0p, t0n = X[1] - X[0], X[2] - X[1]
    t0p, t0n = t0p / np.linalg.norm(t0p), t0n / np.linalg.norm(t0n)
    args = dict(xp=X[0], x=X[1], xn=X[2], thp=0.3, thn=-0.2, t0p=t0p,
                u0p=reference_director(t0p), t0n=t0n, u0n=reference_director(t0n),
                Bp=[2.0, 3.0], Bn=[2.0, 3.0], GJ=1.5, lbar=0.7)
    ref = k(**args)
    E0 = float(ref["E"])
    f = np.stack([np.asarray(ref[n], float).ravel() for n in ("fp", "f", "fn")])
    np.testing.assert_allclose(f.sum(axis=0), 0.0, atol=1e-12 * np.abs(f).max())
    iso = dict(args, Bp=[2.0, 2.0], Bn=[2.0, 2.0])
    out = k(**iso)
    assert float(out["qp"]) + float(out["qn"]) == pytest.approx(0.0, abs=1e-12 * float(out["E"]))
    spun = k(**dict(iso, thp=1.3, thn=0.8))
    assert float(spun["E"]) == pytest.approx(float(out["E"]), rel=1e-12)
    assert float(k(**dict(args, thp=1.3, thn=0.8))["E"]) != pytest.approx(E0, rel=1e-6)
    R, _ = np.linalg.qr(rng.normal(size=(3, 3)))
    R *= np.sign(np.linalg.det(R))
    Y = X @ R.T + rng.normal(size=3)
    moved = k(**dict(args, xp=Y[0], x=Y[1], xn=Y[2], t0p=R @ t0p, t0n=R @ t0n,
                     u0p=R @ args["u0p"], u0n=R @ args["u0n"]))
    assert float(moved["E"]) == pytest.approx(E0, rel=1e-12)
    straight = k(**dict(args, xp=[0.0, 0, 0], x=[1.0, 0, 0], xn=[2.0, 0, 0], t0p=[1.0, 0, 0],
                        t0n=[1.0, 0, 0], u0p=[0.0, 0, 1], u0n=[0.0, 0, 1], thp=0.0, thn=0.0))
    assert float(straight["E"]) == 0.0


def test_transport_is_the_smallest_rotation():
    """transport(a, b, u) for u perpendicular to a: perpendicular to b, unit, and the
    rotation about a x b (it keeps a x b fixed), to 1e-14."""
    rng = np.random.default_rng(5)
    for _ in range(5):
        a, b = (v / np.linalg.norm(v) for v in rng.normal(size=(2, 3)))
        u = reference_director(a)
        w = np.asarray(transport(ca.DM(a), ca.DM(b), ca.DM(u)), float).ravel()
        assert abs(w @ b) < 1e-14 and abs(np.linalg.norm(w) - 1.0) < 1e-14
        k = np.cross(a, b) / np.linalg.norm(np.cross(a, b))
        assert w @ k == pytest.approx(u @ k, abs=1e-14)


def test_rod_scene_keys():
    """EI = [EI_1, EI_2], GJ, a clamp's twist_deg and a guided end are read for model =
    "rod", written back by to_dict, and refused (naming the key) elsewhere."""
    d = cantilever(tip=1.0, ei=[4.0, 5.0], twist=30.0)
    s = load_scene(d)
    lt = s.line_types["beam"]
    assert (lt.EI, lt.EI_2, lt.GJ, s.end_a.twist_deg) == (4.0, 5.0, GJ, 30.0)
    assert load_scene(s.to_dict()) == s
    for key, change in (("line_types.beam.EI", lambda x: x["line_types"]["beam"].pop("GJ")),
                        ("line_types.beam.GJ", lambda x: x["line_types"]["beam"].update(EI=4.0)),
                        ("end_a.twist_deg", lambda x: x["line_types"]["beam"].update(
                            EI=4.0, GJ=0.0))):
        bad = cantilever(tip=1.0, ei=[4.0, 5.0], twist=30.0)
        bad["model"] = "cable3d"
        change(bad)
        with pytest.raises(SceneError, match=key.replace(".", r"\.")):
            load_scene(bad)
    d["end_b"] = {"condition": "guided", "direction": [0.0, 0.0, -2.0]}
    s = load_scene(d)
    assert s.end_b.guided and s.end_b.direction == (0.0, 0.0, -1.0)
    assert load_scene(s.to_dict()) == s
    bad = cantilever(tip=1.0)
    bad["model"] = "cable3d"
    del bad["line_types"]["beam"]["GJ"]
    bad["end_b"] = {"condition": "guided", "direction": [1.0, 0.0, 0.0]}
    with pytest.raises(SceneError, match=r"end_b\.direction.*guided"):
        load_scene(bad)
    bad = cantilever(tip=1.0)
    bad["line_types"]["beam"]["EI"] = [1.0, 2.0, 3.0]
    with pytest.raises(SceneError, match=r"line_types\.beam\.EI"):
        load_scene(bad)


def test_isotropic_kernel_is_the_general_one():
    """vertex_kernel(isotropic=True) (bending without the frames, the cheaper tangent) gives
    the general kernel's energy, forces and torques when EI_1 = EI_2 (1e-12 relative)."""
    rng = np.random.default_rng(11)
    X = rng.normal(size=(3, 3))
    t0 = np.array([1.0, 0.0, 0.0])
    args = dict(xp=X[0], x=X[1], xn=X[2], thp=0.4, thn=-0.3, t0p=t0, u0p=[0.0, 0.0, 1.0],
                t0n=t0, u0n=[0.0, 0.0, 1.0], Bp=[2.0, 2.0], Bn=[3.0, 3.0], GJ=1.5, lbar=0.7)
    general, iso = vertex_kernel()(**args), vertex_kernel(isotropic=True)(**args)
    for key in ("E", "fp", "f", "fn", "qp", "qn"):
        ref = np.asarray(general[key], float)
        np.testing.assert_allclose(np.asarray(iso[key], float), ref,
                                   rtol=1e-12, atol=1e-12 * float(np.abs(ref).max()))


def test_reference_twist_is_the_transports_angle():
    """rod_frames.reference_twist (solid angles of the loop through the anchors) equals its
    definition, the angle about t2 from P(t1 -> t2) P(t0p -> t1) u0p to P(t0n -> t2) u0n, on
    random frames within a hemisphere of each other (to 1e-13 rad: round-off)."""
    rng = np.random.default_rng(2)

    def unit(v):
        return v / np.linalg.norm(v)
    for _ in range(30):
        t0p = unit(rng.normal(size=3))
        t0n = unit(t0p + 0.5 * rng.normal(size=3))
        t1 = unit(t0p + 0.7 * rng.normal(size=3))
        t2 = unit(t1 + 0.4 * rng.normal(size=3))
        u0p, u0n = reference_director(t0p), reference_director(t0n)
        d1p = transport(ca.DM(t0p), ca.DM(t1), ca.DM(u0p))
        d1n = np.asarray(transport(ca.DM(t0n), ca.DM(t2), ca.DM(u0n)), float).ravel()
        moved = np.asarray(transport(ca.DM(t1), ca.DM(t2), d1p), float).ravel()
        want = math.atan2(np.cross(moved, d1n) @ t2, moved @ d1n)
        got = float(reference_twist(*(ca.DM(v) for v in (t1, t2, t0p, u0p, t0n, u0n))))
        assert abs((got - want + math.pi) % (2 * math.pi) - math.pi) < 1e-13


def test_internal_force_is_the_load_beyond_the_cut(elastica):
    """The output internal_force (the seed's f: the force across each edge on the part
    towards end A) equals the external load on the part beyond the cut: the tip load P on
    the weightless elastica, w (L - s) on the heavy cantilever (s the edge's midpoint, the
    weight lumped half a segment each side); exact in the discrete statics, so within the
    nodes' summed residuals (N times the solve's tolerance)."""
    P, runs = elastica
    _, eq = runs[0]
    tol = 10 * eq.stats["tolerance"]
    np.testing.assert_allclose(eq.outputs["internal_force"],
                               np.tile([0.0, 0.0, -P], (10, 1)), atol=tol)
    w = EI / (0.1 * L**3)
    _, eq = solve(cantilever(weight=w, segments=10))
    mid = (np.arange(10) + 0.5) * L / 10
    want = np.column_stack([np.zeros(10), np.zeros(10), -w * (L - mid)])
    np.testing.assert_allclose(eq.outputs["internal_force"], want,
                               atol=10 * eq.stats["tolerance"])


def _moment_cantilever(n, moment, EI_=2.0, GJ_=1.5):
    """A weightless 1 m cantilever clamped along +x at the origin, end B free with an applied
    moment (N m)."""
    return {"model": "rod", "environment": {"water_density": 0.0},
            "line_types": {"b": {"EA": 1e7, "EI": EI_, "GJ": GJ_, "mass": 1.0,
                                 "diameter": 0.01, "weight": 0.0}},
            "sections": [{"type": "b", "length": 1.0, "segments": n}],
            "end_a": {"condition": "clamped", "position": [0.0, 0.0, 0.0],
                      "direction": [1.0, 0.0, 0.0]},
            "end_b": {"condition": "free", "moment": list(moment)}}


def test_end_moment_bends_an_arc_and_twists():
    """A free end's applied moment ([end_b] moment): about -y, M L / EI = 1, the rod bends
    into the arc of radius EI / M (tip at (sin 1, 1 - cos 1) R): measured tip errors
    4.19e-4, 1.07e-4 m at 20, 40 segments (order 1.97; 1.6e-3 at 10); asserted second order
    within 0.1 and under 1.5e-4 at 40. About the axis, M_t = 0.3 N m: the last edge turns by
    exactly M_t (L - ds / 2) / GJ (the discrete twist is exact for uniform twist: to 1e-12),
    and the line stays straight."""
    EI_, GJ_ = 2.0, 1.5
    R = EI_ / 2.0
    exact = np.array([R * math.sin(1.0), 0.0, R * (1.0 - math.cos(1.0))])
    errors = []
    for n in (20, 40):
        _, eq = solve(_moment_cantilever(n, [0.0, -2.0, 0.0]))
        errors.append(float(np.linalg.norm(eq.outputs["positions"][-1] - exact)))
    order = math.log2(errors[0] / errors[1])
    assert abs(order - 2.0) < 0.1 and errors[1] < 1.5e-4, (errors, order)
    _, eq = solve(_moment_cantilever(20, [0.3, 0.0, 0.0]))
    assert abs(float(np.ravel(eq.outputs["twist_angles"])[-1]) - 0.3 * 0.975 / GJ_) < 1e-12
    np.testing.assert_allclose(eq.outputs["positions"][-1], [1.0, 0.0, 0.0], atol=1e-12)


def test_end_moment_in_3d_is_the_rotating_tangent():
    """A moment with a twisting part, M = (0.8, 0, -2.4) N m, on the cantilever along +x:
    with no force the internal moment is M everywhere, so the tangent turns about M at
    |M| / B per metre (a helix about M's axis; the tip in closed form) and the twisting
    moment is M . t = 0.8 N m throughout (this checks the reference director's spin in the
    applied moment's work). Measured tip errors 7.3e-4, 1.85e-4 m at 20, 40 segments
    (second order); asserted under 3e-4 m at 40, the twisting moment to 1e-4 N m."""
    M = np.array([0.8, 0.0, -2.4])
    w, axis = np.linalg.norm(M) / 2.0, M / np.linalg.norm(M)
    along = axis[0] * axis
    perp = np.array([1.0, 0.0, 0.0]) - along
    tip = along + perp * math.sin(w) / w + np.cross(axis, perp) * (1.0 - math.cos(w)) / w
    _, eq = solve(_moment_cantilever(40, M))
    assert np.linalg.norm(eq.outputs["positions"][-1] - tip) < 3e-4
    Mt = np.ravel(eq.outputs["twisting_moment"])[1:-1]
    np.testing.assert_allclose(Mt, 0.8, atol=1e-4)


def _coupled_rod(n, end_b, K=30.0):
    """A weightless 1 m rod (EA 1000 N, GJ 2 N m^2, tension_twist K N m: K^2 / (EA GJ) =
    0.45, a strong coupling) clamped along +x at the origin."""
    return {"model": "rod", "environment": {"water_density": 0.0},
            "line_types": {"b": {"EA": 1000.0, "EI": 1.0, "GJ": 2.0, "tension_twist": K,
                                 "mass": 1.0, "diameter": 0.01, "weight": 0.0}},
            "sections": [{"type": "b", "length": 1.0, "segments": n}],
            "end_a": {"condition": "clamped", "position": [0.0, 0.0, 0.0],
                      "direction": [1.0, 0.0, 0.0]},
            "end_b": end_b}


def test_tension_torsion_coupling():
    """line_types.X.tension_twist = K: T = EA e + K tau, M_t = GJ tau + K e.

    - clamped at both ends, stretched by 1 %, twists held: e = 0.01 and tau = 0 on every
      edge, the axial force EA e and the twisting moment K e at every vertex (exact: to
      1e-9);
    - clamped-free, pulled by P = 50 N with no torque: e = P GJ / (EA GJ - K^2), tau =
      -K e / GJ. Measured at 20 segments: from the clamp to the middle both to 3e-8
      relative; at the free end the last half edge has no vertex, so it carries no coupling
      (its strain 0.0674 against 0.0909): the tip 1.38e-3, 2.76e-3 m short at 20, 10
      segments (first order, local to a free end). Asserted: 1e-6 on the first half, the
      tip error under 2e-3 m at 20 and halving (order 1 within 0.1).
    """
    _, eq = solve(_coupled_rod(10, {"condition": "clamped", "position": [1.01, 0.0, 0.0],
                                    "direction": [1.0, 0.0, 0.0]}))
    np.testing.assert_allclose(np.ravel(eq.outputs["strain"]), 0.01, atol=1e-12)
    np.testing.assert_allclose(np.ravel(eq.outputs["twist_angles"]), 0.0, atol=1e-12)
    np.testing.assert_allclose(np.ravel(eq.outputs["twisting_moment"]), 0.3, atol=1e-9)
    np.testing.assert_allclose(np.ravel(eq.outputs["axial_force"]), 10.0, atol=1e-9)
    P, EA_, GJ_, K = 50.0, 1000.0, 2.0, 30.0
    e = P * GJ_ / (EA_ * GJ_ - K * K)
    tau = -K * e / GJ_
    tips = []
    for n in (10, 20):
        mech, eq = solve(_coupled_rod(n, {"condition": "free", "force": [P, 0.0, 0.0]}))
        tips.append(abs(float(eq.outputs["positions"][-1][0]) - (1.0 + e)))
    assert "tension-torsion coupling" in mech.terms
    strain, th = np.ravel(eq.outputs["strain"]), np.ravel(eq.outputs["twist_angles"])
    np.testing.assert_allclose(strain[:10], e, rtol=1e-6)
    np.testing.assert_allclose(np.diff(th)[:10] / 0.05, tau, rtol=1e-6)
    assert tips[1] < 2e-3 and abs(math.log2(tips[0] / tips[1]) - 1.0) < 0.1, tips


def test_tension_twist_key():
    """tension_twist is read for model = "rod" (written back), refused elsewhere and when the
    axial-torsional stiffness is not positive definite, naming the key."""
    d = _coupled_rod(4, {"condition": "free", "force": [1.0, 0.0, 0.0]})
    s = load_scene(d)
    assert s.line_types["b"].tension_twist == 30.0 and load_scene(s.to_dict()) == s
    d["line_types"]["b"]["tension_twist"] = 50.0
    with pytest.raises(SceneError, match=r"line_types\.b\.tension_twist = 50\.0 N m.*EA GJ"):
        load_scene(d)
    d = cantilever(tip=1.0, model="cable3d")
    d["line_types"]["beam"]["tension_twist"] = 1.0
    d["line_types"]["beam"]["GJ"] = 7.0
    with pytest.raises(SceneError, match=r"line_types\.beam\.(GJ|tension_twist)"):
        load_scene(d)
