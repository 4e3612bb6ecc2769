"""Seabed friction laws of cable3d beyond the regularised Coulomb law (issue 12, item 2): the
bristle law (``seabed.friction_law = "bristle"``: an elastic bristle per node, a first-order
state, that slips only at mu N) and static friction (``seabed.static_friction = "laid"``: a
smooth capped spring from the as-laid shape in statics).

Scenes: a 100 m line of 100 kg/m, 0.1 m, lying straight on a flat bed (depth 50 m) between
two anchors, pulled sideways by a current across it (Cd 1.2: 0.5 rho d Cd U^2 = 61.5 N/m at
1 m/s against mu w = 451 N/m of friction at mu = 0.5); and the line of
tests/test_cable3d_friction.py dragged slowly along and across the bed."""
from __future__ import annotations

import math

import numpy as np
import pytest

import symcable as sc
from symcable.api.cable3d_static import cable3d_mechanism, check_periodic_3d
from symcable.errors import SceneError
from symcable.scene import load_scene
from symcable.solvers.equilibrium import solve_equilibrium
from symcable.solvers.integrate import integrate
from symcable.solvers.options import GeneralizedAlphaFirstOrder

L, MU, RHO = 100.0, 0.5, 1025.0
W = (100.0 - RHO * math.pi * 0.01 / 4) * 9.80665  # N/m submerged
K = 1e5 * 0.1  # N/m per metre of line: friction_stiffness (default: the normal one) x width


def _across(law="bristle", static="none", U=1.0, **seabed):
    d = {"model": "cable3d", "environment": {"depth": 50.0, "current": [0.0, U, 0.0]},
         "seabed": {"stiffness": 1e5, "friction": MU, "friction_law": law,
                    "static_friction": static, **seabed},
         "line_types": {"c": {"mass": 100.0, "diameter": 0.1, "EA": 1e8, "cd_normal": 1.2}},
         "sections": [{"type": "c", "length": L, "segments": 20}],
         "end_a": {"condition": "pinned", "position": [0.0, 0.0, -50.0]},
         "end_b": {"condition": "pinned", "position": [L, 0.0, -50.0]}}
    return load_scene(d)


def _drag_per_node(U):
    return 0.5 * RHO * 0.1 * 1.2 * U * U * (L / 20)


def test_keys_round_trip_and_errors():
    """The keys survive to_dict; each bad value is one SceneError naming its key."""
    s = _across(static="laid", friction_stiffness=2e5)
    assert load_scene(s.to_dict()).seabed == s.seabed
    assert s.seabed.tangential_stiffness == 2e5 and _across().seabed.tangential_stiffness == 1e5
    base = s.to_dict()
    bad = [({"friction_law": "lugre"}, "seabed.friction_law"),
           ({"friction_stiffness": 0.0}, "seabed.friction_stiffness"),
           ({"static_friction": "held"}, "seabed.static_friction"),
           ({"friction_axial": 0.0}, "seabed.friction_law")]
    for change, key in bad:
        d = {**base, "seabed": {**base["seabed"], **change}}
        with pytest.raises(SceneError, match=key):
            load_scene(d)
    d = {**base, "end_b": {"condition": "free"}}
    with pytest.raises(SceneError, match="seabed.static_friction"):
        load_scene(d)
    d = {**base, "model": "planar", "environment": {"depth": 50.0},
         "end_a": {"condition": "pinned", "position": [0.0, -50.0]},
         "end_b": {"condition": "pinned", "position": [L, -50.0]}}
    with pytest.raises(SceneError, match="cable3d option"):
        load_scene(d)


def _static(U, static="laid"):
    """The equilibrium at current U (m/s), one Mechanism for every U (the current is a
    parameter block)."""
    mech = cable3d_mechanism(_across(static=static))
    return solve_equilibrium(mech, p=mech.params.with_values(mech.static_p,
                                                             current=[0.0, U, 0.0]))


def test_static_friction_holds_below_mu_N():
    """Statics with the capped spring from the laid (straight) shape: at 1 m/s the current's
    drag, 14 % of mu N per node, is held by friction node by node away from the anchors
    (1e-4 of the drag; measured 1e-7: the tension near the anchors takes 0.7 % of it), and
    the line moves sideways by about drag / k (2 %: the cap softens the spring by 0.9 % at
    this utilisation and chi = N / N_e = 0.995 by 0.5 %; measured 1.5 %) instead of the
    1.4 m it bows without friction; solve_static does not warn of frictionless statics
    then."""
    eq = _static(1.0)
    f = np.asarray(eq.outputs["friction_force"])
    drag = _drag_per_node(1.0)
    assert np.allclose(f[3:-3, 1], -drag, rtol=1e-4)
    y = np.asarray(eq.outputs["positions"])[:, 1]
    assert np.max(y) == pytest.approx(drag / (K * L / 20), rel=0.02)
    assert np.max(np.asarray(_static(1.0, "none").outputs["positions"])[:, 1]) > 1.0
    assert not sc.solve_static(_across(static="laid"), estimate=False).warnings
    assert "static_friction" in sc.solve_static(_across(), estimate=False).warnings[0]


def test_static_friction_never_exceeds_mu_N():
    """Currents past the friction (2.7 m/s: 100 %, 3 m/s: 122 %, 5 m/s: 340 % of mu N): the
    line slides until its tension takes the rest, and no node's friction exceeds mu N (the
    capped spring is below it by construction: 1e-12 for round-off); sliding, the grounded
    interior nodes are at 99 % of it or more."""
    for U in (2.7, 3.0, 5.0):
        eq = _static(U)
        f = np.linalg.norm(np.asarray(eq.outputs["friction_force"]), axis=1)
        N = np.ravel(eq.outputs["contact_force"])
        assert np.all(f <= MU * N * (1 + 1e-12)), U
        if U > 2.71:
            assert np.all(f[1:-1] >= 0.99 * MU * N[1:-1]), U


def _run(scene, duration, dt, still_start):
    mech = cable3d_mechanism(scene)
    p0 = mech.static_p
    if still_start:  # statics in still water, then the current from t = 0
        p0 = mech.params.with_values(p0, current=np.zeros(3))
    eq = solve_equilibrium(mech, p=p0)
    tr = integrate(mech, duration, dt, start=eq, p=mech.params.values,
                   method=GeneralizedAlphaFirstOrder(rho_inf=0.0), progress=False)
    assert tr.status == "converged"
    n = len(tr.time)
    return tr, np.asarray(tr.outputs["positions"]).reshape(n, -1, 3)[:, 10, 1]


def test_bristle_holds_where_coulomb_creeps():
    """The current switched on at t = 0 on the line at rest: the bristle law holds it after
    a sideways step of drag / k (2 %: chi = N / N_e = 0.995 makes the bristle 0.5 % softer;
    measured 1.0 %) and does not move after that (1e-9 m
    over 300 s: the slip's factor at utilisation 0.14 is 0.14^8 of the motion, and the
    motion has stopped); the regularised Coulomb law creeps at v_eps F / (mu N) =
    1.37 mm/s (2 %), without end."""
    _, y = _run(_across("bristle"), 400.0, 1.0, True)
    assert y[100] == pytest.approx(_drag_per_node(1.0) / (K * L / 20), rel=0.02)
    assert abs(y[-1] - y[100]) < 1e-9
    _, yc = _run(_across("coulomb"), 400.0, 0.1, True)
    ratio = _drag_per_node(1.0) / (MU * W * L / 20)
    creep = 0.01 * ratio / math.sqrt(1 - ratio ** 2)
    assert (yc[-1] - yc[1000]) / 300.0 == pytest.approx(creep, rel=0.02)


def test_run_starts_holding_what_statics_held():
    """With static friction the bristles start at the static spring's deflection: a run in
    the same current does not move (1e-9 m over 100 s); the Coulomb law starts without the
    static spring and creeps (more than 10 cm in 100 s)."""
    _, y = _run(_across("bristle", "laid"), 100.0, 1.0, False)
    assert y[0] > 5e-3 and np.max(np.abs(y - y[0])) < 1e-9
    _, yc = _run(_across("coulomb", "laid"), 100.0, 0.1, False)
    assert yc[-1] - yc[0] > 0.1


LD, T, A = 40.0, 200.0, 5.0


def _drag(direction, mu_a, mu_l):
    """As tests/test_cable3d_friction.py: both ends dragged together at 5 m amplitude over
    200 s, pre-stretched 5e-4; the first-order scheme at 0.1 s (its 350 s run)."""
    amp = [A * direction[0], A * direction[1], 0.0]
    motion = {"kind": "harmonic", "period": T, "amplitude": amp, "phase_deg": [0.0, 0.0, 0.0]}
    d = {"model": "cable3d", "environment": {"depth": 50.0},
         "seabed": {"stiffness": 1e6, "friction_axial": mu_a, "friction_lateral": mu_l,
                    "friction_law": "bristle"},
         "line_types": {"c": {"mass": 100.0, "diameter": 0.1, "EA": 1e8, "cd_normal": 0.0,
                              "cd_tangential": 0.0, "ca_normal": 0.0}},
         "sections": [{"type": "c", "length": LD, "segments": 20}],
         "end_a": {"condition": "pinned", "position": [0.0, 0.0, -50.0], "motion": motion},
         "end_b": {"condition": "pinned", "position": [LD * (1 + 5e-4), 0.0, -50.0],
                   "motion": motion}}
    tr, _ = _run(load_scene(d), 1.75 * T, 0.1, False)
    n = len(tr.time)
    total = (np.asarray(tr.outputs["end_force_a"]).reshape(n, -1)
             + np.asarray(tr.outputs["end_force_b"]).reshape(n, -1))[-1]
    return total, float(np.sum(np.asarray(tr.outputs["contact_force"]).reshape(n, -1)[-1]))


@pytest.mark.parametrize("mu_a, mu_l", [(0.5, 1.0), (1.0, 0.5)])
def test_bristle_axial_friction(mu_a, mu_l):
    """Dragged along its length at 0.157 m/s: the ends carry mu_a times the grounded
    weight, whatever mu_l (1e-3: the slip factor's excess at 157 times BRISTLE_SPEED is
    4e-5, the rest the axial waves of the 0.1 s steps; measured 4e-6). Unlike the Coulomb
    law's v / sqrt(v^2 + v_eps^2), no regularisation factor: the bristle slides at mu N."""
    total, N = _drag((1.0, 0.0), mu_a, mu_l)
    assert total[0] == pytest.approx(-mu_a * N, rel=1e-3)
    assert abs(total[1]) < 1e-6 * N


def test_bristle_lateral_friction():
    """Dragged across with mu_lateral = 1, mu_axial = 0.5: the bowed line's ends slide partly
    along themselves, so between the two coefficients, nearer the lateral one (as the
    Coulomb law); isotropic 0.8: 0.8 to 1 % (the bow's own motion, as for Coulomb)."""
    total, N = _drag((0.0, 1.0), 0.5, 1.0)
    assert 0.85 * N < -total[1] < 1.0 * N
    total, N = _drag((0.0, 1.0), 0.8, 0.8)
    assert total[1] == pytest.approx(-0.8 * N, rel=1e-2)


def test_modes_with_the_bed_holding():
    """Modes about rest: the bristles' stiffness holds the grounded nodes (K G symmetric:
    the bristle force -k chi b with b' = chi v at rest), so the lowest frequency is above
    the frictionless (Coulomb: no force at rest) one."""
    hang = {"end_b": {"condition": "pinned", "position": [90.0, 0.0, 0.0]},
            "sections": [{"type": "c", "length": 120.0, "segments": 20}]}
    f = {}
    for law in ("coulomb", "bristle"):
        d = {**_across(law, U=0.0).to_dict(), **hang}
        f[law] = sc.modal_analysis(load_scene(d), 2).frequencies
    assert f["bristle"][0] > 1.5 * f["coulomb"][0]


def _small_moving(law="bristle"):
    """The line across the current, 5 segments, still water, end B moved harmonically."""
    d = _across(law, U=0.0).to_dict()
    d["sections"][0]["segments"] = 5
    d["end_b"]["motion"] = {"kind": "harmonic", "period": 10.0, "amplitude": [1.0, 0.0, 0.0],
                            "phase_deg": [0.0, 0.0, 0.0]}
    return load_scene(d)


def test_periodic_solves_refuse_the_bristle():
    """A bristle that never slips keeps any deflection, so the periodic states form a
    family: every periodic method refuses a bristle scene with one message naming the key,
    its value, why and what to use instead; a sweep fails with it on every period."""
    s = _small_moving()
    expected = r'seabed\.friction_law = "bristle".*family.*friction_law = "coulomb"'
    for method in ("collocation", "harmonic_balance", "shooting"):
        with pytest.raises(sc.SymcableError, match=expected):
            sc.solve_periodic(s, method)
    with pytest.raises(sc.SymcableError, match=expected):
        sc.sweep_periodic(s, [8.0, 10.0])
    with pytest.raises(sc.SymcableError, match=expected):
        check_periodic_3d(s)
    check_periodic_3d(_small_moving("coulomb"))  # no first-order states: accepted


def test_bristle_states_named():
    """The bristle deflections are named after their node and direction (m), after the
    nodes' coordinates; the velocities are the nodes' alone."""
    mech = cable3d_mechanism(_small_moving())
    q, v = mech.coordinate_names()
    assert len(q) == mech.n_q and len(v) == mech.n_v == 12
    assert q[:3] == v[:3] == ("node1.x", "node1.y", "node1.z") and q[:12] == v
    assert q[12:] == tuple(f"node{i}.bristle.{c}" for i in range(6) for c in "xy")
    assert mech.layout.states.unit == "m"
    assert cable3d_mechanism(_small_moving("coulomb")).layout.states is None


def test_linearize_names_bristle_states():
    """sc.linearize labels the bristle states, and names only the velocities in v_kinds."""
    lin = sc.linearize(_small_moving())
    assert lin.q_kinds[-2:] == ("node5.bristle.x", "node5.bristle.y")
    assert len(lin.v_kinds) == lin.M.shape[0] == 12


def test_isotropic_bristle_needs_no_frame():
    """With mu_axial = mu_lateral the bristle is written in x and y, without the line's
    frame: its force and rates equal the framed law's (anisotropic by 1e-12, so the frame
    path) to 1e-9 relative (the frame's regularisation and the 1e-12 ratio, far below), and a
    node's rates depend on its own node only (block per node: what lets the step eliminate
    them)."""
    import dataclasses

    import casadi as ca

    from symcable.models.common.friction import friction
    sb = _across().seabed
    framed = dataclasses.replace(sb, friction_lateral=MU * (1 + 1e-12))
    n = 6
    rng = np.random.default_rng(3)
    X, V = ca.SX.sym("X", 3, n), ca.SX.sym("V", 3, n)
    b, N = ca.SX.sym("b", 2 * n), ca.SX.sym("N", 1, n)
    area, weight = np.full(n, 0.5), np.full(n, 450.0)
    out = {}
    for name, s in (("iso", sb), ("framed", framed)):
        fr = friction(s, X, V, N, area, weight, state=b)
        out[name] = ca.Function(name, [X, V, b, N], [ca.vec(fr.force), fr.rate])
    Xv = np.vstack([np.linspace(0, 25, n), 0.3 * rng.standard_normal(n), np.full(n, -50.0)])
    for _ in range(5):
        args = (Xv, 0.2 * rng.standard_normal((3, n)), 0.05 * rng.standard_normal(2 * n),
                rng.uniform(0, 400, (1, n)))
        for a, c in zip(out["iso"](*args), out["framed"](*args)):
            a, c = np.asarray(a).ravel(), np.asarray(c).ravel()
            assert np.max(np.abs(a - c)) <= 1e-9 * np.max(np.abs(c))
    rate = friction(sb, X, V, N, area, weight, state=b).rate
    dep = np.asarray(ca.DM(ca.jacobian(rate, ca.vertcat(ca.vec(X), ca.vec(V), b)).sparsity(),
                           1))
    for i in range(n):
        cols = np.flatnonzero(dep[2 * i:2 * i + 2].any(axis=0))
        own = set(range(3 * i, 3 * i + 3)) | set(range(3 * n + 3 * i, 3 * n + 3 * i + 3)) \
            | {6 * n + 2 * i, 6 * n + 2 * i + 1}
        assert set(cols) <= own, (i, cols)


def _two_lines(law):
    """The line of ``_across`` as two lines of 10 segments meeting at a free point of 1 kg on
    the bed (scene version 2)."""
    d = _across(law).to_dict()
    for key in ("sections", "end_a", "end_b"):
        d.pop(key, None)
    d["points"] = {"p1": {"kind": "fixed", "position": [0.0, 0.0, -50.0]},
                   "mid": {"kind": "free", "position": [L / 2, 0.0, -50.0], "mass": 1.0},
                   "p2": {"kind": "fixed", "position": [L, 0.0, -50.0]}}
    d["lines"] = [{"name": name, "end_a": a, "end_b": b,
                   "sections": [{"type": "c", "length": L / 2, "segments": 10}]}
                  for name, a, b in (("a", "p1", "mid"), ("b", "mid", "p2"))]
    return load_scene(d)


def test_bristle_on_several_lines():
    """The bristle law on a scene of several lines: each line's nodes carry their bristles
    (named after their line), the current switched on at t = 0 moves line a's middle node
    sideways by drag / k (as the one line's, 1 %) and the bristles then hold it (1e-9 m over
    300 s) where the Coulomb law creeps (more than 0.1 m); the system's periodic solve
    refuses the bristle by its states' names; static friction stays one-line."""
    from symcable.solvers.options import GeneralizedAlphaFirstOrder as GA1
    out = {}
    for law, dt in (("bristle", 1.0), ("coulomb", 0.1)):
        mech = cable3d_mechanism(_two_lines(law))
        p0 = mech.params.with_values(mech.static_p, **{k: np.zeros(3) for k in
                                                       mech.params.names if k.endswith("current")})
        tr = integrate(mech, 400.0, dt, start=solve_equilibrium(mech, p=p0),
                       p=mech.params.values, method=GA1(rho_inf=0.0), progress=False)
        assert tr.status == "converged"
        n = len(tr.time)
        out[law] = (np.asarray(tr.outputs["a.positions"]).reshape(n, -1, 3)[:, 5, 1],
                    int(round(100.0 / dt)), mech)
    y, k100, mech = out["bristle"]
    assert mech.layout.states.names[:2] == ("a.node0.bristle.x", "a.node0.bristle.y")
    assert mech.layout.states.names[-1] == "b.node10.bristle.y"
    assert y[k100] == pytest.approx(_drag_per_node(1.0) / (K * L / 20), rel=0.02)
    assert abs(y[-1] - y[k100]) < 1e-9
    yc, kc, _ = out["coulomb"]
    assert yc[-1] - yc[kc] > 0.1
    with pytest.raises(sc.SymcableError, match=r'"bristle".*a\.node0\.bristle\.x'):
        check_periodic_3d(_two_lines("bristle"))
    d = _two_lines("bristle").to_dict()
    d["seabed"]["static_friction"] = "laid"
    with pytest.raises(SceneError, match="seabed.static_friction.*one-line scenes"):
        load_scene(d)
