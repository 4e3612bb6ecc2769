"""Bending of the cable3d line (EI > 0; issue 12 item 1): the discrete curvature energy
EI |kb|^2 / (2 lbar) on node triplets (symcable.models.common.bending).

- small deflections: the cantilever under a tip load and under its own weight, clamped
  along a direction turned 0.7 rad about z, against Euler-Bernoulli's P L^3 / (3 EI) and
  w L^4 / (8 EI), with the order measured over 8..64 segments (second: the clamp's ghost
  node is the mirror-ghost clamp of finite differences);
- a taut string with bending between pinned ends: the modal analysis against the tensioned
  beam's omega_n = (n pi / L) sqrt(T / m) sqrt(1 + EI n^2 pi^2 / (T L^2)), second order;
- large deflections in a vertical plane turned about z: the tip-loaded elastica against
  its elliptic-integral closed form and the planar model, the heavy cantilever against the
  planar model;
- a rigid motion changes no bending energy; the forces are the energy's gradient.
"""
from __future__ import annotations

import math

import casadi as ca
import numpy as np
import pytest

import symcable as sc
from symcable.analytic import (cantilever_tip_load, cantilever_tip_load_small,
                               heavy_cantilever_small)
from symcable.api.cable3d_static import cable3d_mechanism
from symcable.models.common.bending import bending_kernel
from symcable.scene import load_scene
from symcable.solvers.equilibrium import solve_equilibrium
from symcable.solvers.linearize import mechanism_modes

L, EI, TURN = 2.0, 10.0, 0.7
PLANE = np.array([math.cos(TURN), math.sin(TURN)])  # the cantilever's horizontal direction


def cantilever(*, tip=0.0, weight=0.0, segments=40, EA=None, planar=False) -> dict:
    """Clamped at the origin along PLANE (cable3d) or +x (planar), free at the other end
    with a downward dead load ``tip`` (N); in air."""
    d = {"model": "cable3d", "environment": {"water_density": 0.0},
         "line_types": {"beam": {"EA": EA or 1e7 * EI / L**2, "EI": EI, "mass": 1.0,
                                 "diameter": 0.02, "weight": weight}},
         "sections": [{"type": "beam", "length": L, "segments": segments}],
         "end_a": {"condition": "clamped", "position": [0.0, 0.0, 0.0],
                   "direction": [PLANE[0], PLANE[1], 0.0]},
         "end_b": {"condition": "free", "force": [0.0, 0.0, -tip]}}
    if planar:
        d.update(model="planar")
        d["end_a"] = {"condition": "clamped", "position": [0.0, 0.0], "angle_deg": 0.0}
        d["end_b"]["force"] = [0.0, -tip]
    return d


def _in_plane(st) -> tuple[float, float, float]:
    """(horizontal along PLANE, z, largest distance off the vertical plane) of the tip, m."""
    tip = st.positions[-1]
    off = st.positions[:, :2] @ np.array([-PLANE[1], PLANE[0]])
    return float(tip[:2] @ PLANE), float(tip[2]), float(np.max(np.abs(off)))


@pytest.mark.parametrize("load", ["tip", "weight"])
def test_small_deflection_cantilever_second_order(load):
    """P L^2 / EI (or w L^3 / EI) = 1e-4, so the geometric nonlinearity (relative ~1e-8) and
    the strain (1e-8: EA is 1e8 times the load, inside the loader's 1e9) are far below the
    discretisation error. Measured relative tip errors 1 / (2 N^2) (tip load) and 1 / N^2
    (weight) exactly, order 2.0000: asserted within 0.01 of 2, and the error at 64 segments
    under 3e-4."""
    if load == "tip":
        P = 1e-4 * EI / L**2
        ref, make = cantilever_tip_load_small(L, EI, P), dict(tip=P, EA=1e8 * P)
    else:
        w = 1e-4 * EI / L**3
        ref, make = heavy_cantilever_small(L, EI, w), dict(weight=w, EA=1e8 * w * L)
    errors = []
    for n in (8, 16, 32, 64):
        st = sc.solve_static(cantilever(segments=n, **make), codegen=False)
        assert st.status == "converged"
        errors.append(abs(-_in_plane(st)[1] / ref - 1.0))
    orders = np.log2(np.array(errors[:-1]) / np.array(errors[1:]))
    assert np.all(np.abs(orders - 2.0) < 0.01), (errors, orders)
    assert errors[-1] < 3e-4


def test_taut_string_with_bending_modes():
    """A string of EA 1e6 N stretched 0.1 % (T = 1000 N) between pinned ends on a diagonal,
    EI such that EI pi^2 / (T L^2) = 0.5: the first four transverse frequencies (each twice,
    one per transverse plane, equal to 1e-10) against the tensioned, simply supported beam,
    with L the stretched length, m the mass per stretched metre and EI (1 + strain) (the
    curvature is measured per unstretched metre). Measured errors at 20, 40, 80 segments
    fall by 4 per halving (orders 1.986-1.9998): asserted within 0.05 of 2, and under 0.2 %
    at 80 segments."""
    L0, m, EA, s = 10.0, 1.0, 1e6, 1e-3
    T = EA * s
    ei = 0.5 * T * L0**2 / math.pi**2
    Lp, mp, eip = L0 * (1 + s), m / (1 + s), ei * (1 + s)
    n = np.arange(1, 5)
    ref = (n * math.pi / Lp * math.sqrt(T / mp)
           * np.sqrt(1 + eip * (n * math.pi) ** 2 / (T * Lp**2)) / (2 * math.pi))
    errors = []
    for N in (20, 40, 80):
        d = {"model": "cable3d", "environment": {"water_density": 0.0},
             "line_types": {"s": {"mass": m, "diameter": 0.01, "EA": EA, "weight": 0.0,
                                  "EI": ei}},
             "sections": [{"type": "s", "length": L0, "segments": N}],
             "end_a": {"condition": "pinned", "position": [0.0, 0.0, 0.0]},
             "end_b": {"condition": "pinned", "position": [Lp * 0.6, Lp * 0.48, Lp * 0.64]}}
        mech = cable3d_mechanism(load_scene(d))
        f = np.sort(mechanism_modes(mech, solve_equilibrium(mech, codegen=False)).frequencies)
        np.testing.assert_allclose(f[1:8:2], f[0:8:2], rtol=1e-10)
        errors.append(np.abs(f[0:8:2] / ref - 1.0))
    orders = np.log2(errors[0] / errors[1]), np.log2(errors[1] / errors[2])
    assert np.all(np.abs(np.array(orders) - 2.0) < 0.05), (errors, orders)
    assert np.max(errors[-1]) < 2e-3


@pytest.fixture(scope="module")
def elastica():
    """The tip-loaded cantilever at P L^2 / EI = 5 (about 60 deg of tip rotation), 40
    segments, by cable3d in the turned plane and by the planar model."""
    P = 5.0 * EI / L**2
    return (P, sc.solve_static(cantilever(tip=P), codegen=False),
            sc.solve_static(cantilever(tip=P, planar=True), codegen=False))


def test_tip_loaded_elastica_in_a_turned_plane(elastica):
    """Against the elliptic-integral elastica: tip within 2.5e-4 L at 40 segments (measured
    1.6e-4 L; second order: 5.9e-4 L at 20); the clamp's moment P x_tip within 1e-3
    (measured 2.7e-4); the line stays in its vertical plane (to 1e-7 L: the solver's
    tolerance)."""
    P, st, _ = elastica
    ref = cantilever_tip_load(L, EI, P)
    x, z, off = _in_plane(st)
    assert st.status == "converged"
    assert abs(x - ref["x_tip"]) < 2.5e-4 * L
    assert abs(z - ref["z_tip"]) < 2.5e-4 * L
    assert off < 1e-7 * L
    assert st.moment[0] == pytest.approx(P * ref["x_tip"], rel=1e-3)
    assert st.moment[-1] == 0.0  # a free end carries none: no term is built there


def test_elastica_matches_the_planar_model(elastica):
    """cable3d (positions, discrete curvature) and planar (angles and strains) discretise
    differently: at 40 segments their tips agree within the sum of their errors against the
    closed form (each under 2.5e-4 L; measured difference 2.7e-4 L)."""
    _, st, planar = elastica
    x, z, _ = _in_plane(st)
    assert abs(x - planar.positions[-1, 0]) < 5e-4 * L
    assert abs(z - planar.positions[-1, 1]) < 5e-4 * L


def test_heavy_cantilever_matches_the_planar_model():
    """The heavy cantilever with large sag (EI / (w L^3) = 0.1, as the planar bending test):
    cable3d against planar at 40 segments, tips within 5e-4 L (each model's discretisation
    error; measured 9e-5 L, and 2.6e-4 L at 20 segments)."""
    w = EI / (0.1 * L**3)
    st = sc.solve_static(cantilever(weight=w), codegen=False)
    planar = sc.solve_static(cantilever(weight=w, planar=True), codegen=False)
    x, z, off = _in_plane(st)
    assert abs(x - planar.positions[-1, 0]) < 5e-4 * L
    assert abs(z - planar.positions[-1, 1]) < 5e-4 * L
    assert off < 1e-7 * L


def test_rigid_motion_changes_no_bending_energy():
    """Seed 003's argument, for bending: the energy of a bent triplet is invariant under
    rigid rotations and translations (to 1e-13 relative: round-off), its forces turn with
    it and sum to zero, and a straight triplet has none."""
    k = bending_kernel()
    rng = np.random.default_rng(7)
    X = rng.normal(size=(3, 3))
    ref = k(xp=X[0], x=X[1], xn=X[2], EI=3.0, lbar=0.8)
    E0 = float(ref["E"])
    assert E0 > 0
    forces = np.stack([np.asarray(ref[f], float).ravel() for f in ("fp", "f", "fn")])
    np.testing.assert_allclose(forces.sum(axis=0), 0.0, atol=1e-12 * np.abs(forces).max())
    for _ in range(5):
        R, _ = np.linalg.qr(rng.normal(size=(3, 3)))
        R *= np.sign(np.linalg.det(R))
        shift = rng.normal(size=3)
        Y = X @ R.T + shift
        out = k(xp=Y[0], x=Y[1], xn=Y[2], EI=3.0, lbar=0.8)
        assert float(out["E"]) == pytest.approx(E0, rel=1e-13)
        for key, f0 in zip(("fp", "f", "fn"), forces):
            np.testing.assert_allclose(np.asarray(out[key], float).ravel(), R @ f0,
                                       atol=1e-12 * np.abs(forces).max())
    straight = k(xp=[0.0, 0, 0], x=[1.0, 1, 1], xn=[3.0, 3, 3], EI=3.0, lbar=0.8)
    assert float(straight["E"]) == 0.0


def test_bending_forces_are_the_energy_gradient():
    """On a weightless beam in air clamped at one end, pinned at the other, of two
    sections with different EI (the joint's harmonic mean): the Mechanism's force is minus
    the gradient of its potential-energy output at a bent shape (1e-9 relative: the forces
    are conservative, and the energy output counts the bending)."""
    d = {"model": "cable3d", "environment": {"water_density": 0.0},
         "line_types": {"a": {"EA": 1e5, "EI": 50.0, "mass": 1.0, "diameter": 0.02,
                              "weight": 0.0},
                        "b": {"EA": 1e5, "EI": 5.0, "mass": 1.0, "diameter": 0.02,
                              "weight": 0.0}},
         "sections": [{"type": "a", "length": 1.0, "segments": 4},
                      {"type": "b", "length": 1.5, "segments": 5}],
         "end_a": {"condition": "clamped", "position": [0.0, 0.0, 0.0],
                   "direction": [0.0, 1.0, 0.0]},
         "end_b": {"condition": "pinned", "position": [0.3, 2.3, 0.2]}}
    mech = cable3d_mechanism(load_scene(d))
    assert "bending" in mech.terms
    U = mech.outputs["potential_energy"].expr
    # (at rest: the drag on v stays in the force with its Cd a parameter, here 0)
    f = ca.Function("f", [mech.q, mech.t, mech.p], ca.substitute(
        [mech.force, -ca.gradient(U, mech.q)], [mech.v], [ca.DM.zeros(mech.n_v)]))
    s = np.linspace(0, 1, 10)[1:-1]
    q = np.column_stack([0.3 * s ** 2, 2.3 * s + 0.05 * np.sin(7 * s), 0.2 * s ** 3]).ravel()
    force, grad = (np.asarray(x, float).ravel() for x in f(q, 0.0, mech.params.values))
    np.testing.assert_allclose(force, grad, rtol=0, atol=1e-9 * np.abs(grad).max())


def test_no_bending_term_where_ei_is_zero():
    """A cable (EI = 0) builds no bending term and no moment output; a section of EI = 0
    beside one with EI > 0 makes the joint a hinge (no term at that node)."""
    from symcable.models.common.bending import bending_nodes
    from symcable.models.common.segments import segment_table
    d = cantilever(weight=1.0)
    d["line_types"]["cable"] = dict(d["line_types"]["beam"], EI=0.0)
    d["sections"] = [{"type": "beam", "length": 1.0, "segments": 3},
                     {"type": "cable", "length": 1.0, "segments": 3}]
    d["end_b"] = {"condition": "pinned", "position": [1.5, 0.0, -1.0]}
    scene = load_scene(d)
    nodes = [i for i, _, _ in bending_nodes(scene, segment_table(scene))]
    assert nodes == [0, 1, 2]  # the clamp and the beam's interior nodes, not the joint (3)
    d["line_types"]["beam"]["EI"] = 0.0
    d["end_a"] = {"condition": "pinned", "position": [0.0, 0.0, 0.0]}
    mech = cable3d_mechanism(load_scene(d))
    assert "bending" not in mech.terms and "bending_moment" not in mech.outputs


def test_bending_energy_conserved_to_second_order():
    """A weightless cantilever in air (10 segments), bent by a tip force in statics and
    released (the force off): with no drag, damping or moving end, generalized-alpha with
    rho_inf = 1 conserves its energy (kinetic plus potential, bending included) to its
    order over 1 s. Measured largest drifts 1.1e-3, 2.7e-4, 6.1e-5 of the energy at dt =
    16, 8, 4 ms (orders 2.02, 2.17): asserted orders within 1.8-2.4 and 1e-4 at 4 ms."""
    from symcable.solvers.integrate import integrate
    from symcable.solvers.options import GeneralizedAlpha
    d = {"model": "cable3d", "environment": {"water_density": 0.0},
         "line_types": {"b": {"EA": 1e5, "EI": 10.0, "mass": 1.0, "diameter": 0.02,
                              "weight": 0.0}},
         "sections": [{"type": "b", "length": L, "segments": 10}],
         "end_a": {"condition": "clamped", "position": [0.0, 0.0, 0.0],
                   "direction": [0.6, 0.8, 0.0]},
         "end_b": {"condition": "free", "force": [0.3, -0.4, -8.0]}}
    mech = cable3d_mechanism(load_scene(d))
    q0 = np.array(solve_equilibrium(mech).q, float)
    p = mech.params.with_values(load=0.0)
    drifts = []
    for dt in (0.016, 0.008, 0.004):
        tr = integrate(mech, 1.0, dt, method=GeneralizedAlpha(rho_inf=1.0), q0=q0,
                       v0=np.zeros_like(q0), p=p)
        assert tr.status == "converged"
        E = np.ravel(tr.outputs["kinetic_energy"]) + np.ravel(tr.outputs["potential_energy"])
        drifts.append(float(np.max(np.abs(E - E[0])) / E[0]))
    orders = np.log2(np.array(drifts[:-1]) / np.array(drifts[1:]))
    assert np.all((orders > 1.8) & (orders < 2.4)), (drifts, orders)
    assert drifts[-1] < 1e-4


def test_version_2_line_with_a_clamped_inline_end():
    """The tip-loaded cantilever as one [[lines]] entry: its clamped inline end_a and a free
    point carrying the tip force (mass and volume 0) give the version-1 line's tip and clamp
    moment to the solver's tolerance (1e-9 relative: the same discrete equations); a clamped
    inline end on a cable (EI = 0) is refused."""
    P = 2.0 * EI / L**2
    v1 = sc.solve_static(cantilever(tip=P, segments=20), codegen=False)
    d = cantilever(tip=P, segments=20)
    d["points"] = {"tip": {"kind": "free", "position": [L * PLANE[0], L * PLANE[1], 0.0],
                           "mass": 0.0, "volume": 0.0, "force": [0.0, 0.0, -P]}}
    d["lines"] = [{"name": "beam", "end_a": d.pop("end_a"), "end_b": "tip",
                   "sections": d.pop("sections")}]
    d.pop("end_b")
    v2 = sc.solve_static(d, codegen=False)
    line = v2.lines["beam"]
    np.testing.assert_allclose(line.positions, v1.positions, atol=1e-9 * L)
    assert line.moment[0] == pytest.approx(v1.moment[0], rel=1e-9)
    d["line_types"]["beam"]["EI"] = 0.0
    with pytest.raises(sc.SceneError, match=r"lines\[0\]\.end_a\.condition = 'clamped'.*EI > 0"):
        load_scene(d)
