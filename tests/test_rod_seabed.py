"""The rod's and the hybrid's seabed and current profile (issue 14 item 1: "seabed contact and
friction from the 3D cable"): cable3d's nodal pieces (:mod:`symcable.models.common.seabed`) on the
rod's nodes.

- rod = cable3d with bending: an isotropic rod with a clamped end carries no twist (its
  reference frame's twist is cancelled by the twist angles), so its bending is cable3d's
  discrete curvature energy exactly and the two Mechanisms are the same discrete problem,
  lying partly on the seabed, under a current profile, with each friction law;
- friction in time: a rod dragged slowly along and across the bed carries mu times its
  grounded weight, as cable3d's (tests/test_cable3d_friction.py);
- the hybrid: a cable3d section on the bed and the rod through the touchdown; the seed's
  cable laid on the bed ending in its low-tension guided end (the benchmark's longer case),
  its statics, a few steps in time and its zones chosen by zones = "auto".
"""
from __future__ import annotations

import math

import numpy as np
import pytest

import symcable as sc
from symcable.api.cable3d_static import cable3d_mechanism
from symcable.api.rod_static import rod_mechanism
from symcable.scene import load_scene
from symcable.solvers.equilibrium import solve_equilibrium
from symcable.solvers.integrate import integrate
from symcable.solvers.options import GeneralizedAlpha, GeneralizedAlphaFirstOrder


def _both(scene_of):
    """Static outputs of ``scene_of("cable3d")`` and ``scene_of("rod")``."""
    out = {}
    for model, build in (("cable3d", cable3d_mechanism), ("rod", rod_mechanism)):
        mech = build(load_scene(scene_of(model)))
        eq = solve_equilibrium(mech, codegen=False)
        assert eq.status == "converged"
        out[model] = eq.outputs
    return out["cable3d"], out["rod"]


def _hose(model: str, **lt) -> dict:
    """A 0.1 m hose of EI = 50 N m^2 (GJ = 40 for the rod)."""
    t = {"EA": 1e6, "EI": 50.0, "mass": 20.0, "diameter": 0.1, "cd_normal": 1.2,
         "cd_tangential": 0.01, "ca_normal": 1.0, **lt}
    if model == "rod":
        t["GJ"] = 0.8 * t["EI"]
    return t


def laid(model: str) -> dict:
    """40 m of hose clamped at 35 m depth pointing down and along x, pinned on the bed at
    50 m (30 m along, 4 m across), in a current (0.2, 0.3, 0) m/s: half of it on the bed."""
    return {"model": model, "environment": {"depth": 50.0, "current": [0.2, 0.3, 0.0]},
            "seabed": {"stiffness": 1e5, "damping": 100.0},
            "line_types": {"t": _hose(model)},
            "sections": [{"type": "t", "length": 40.0, "segments": 20}],
            "end_a": {"condition": "clamped", "position": [0.0, 0.0, -35.0],
                      "direction": [0.6, 0.0, -0.8]},
            "end_b": {"condition": "pinned", "position": [30.0, 4.0, -50.0]}}


def test_rod_on_the_seabed_is_cable3d():
    """Positions within 1e-7 m (measured 8e-14: both solves reach the same discrete
    solution), contact forces and the clamp's force within 1e-6 relative; about half the
    nodes on the bed, the rest suspended; the output is real (it was zero before)."""
    c, r = _both(laid)
    np.testing.assert_allclose(r["positions"], c["positions"], atol=1e-7)
    fc, fr = np.ravel(c["contact_force"]), np.ravel(r["contact_force"])
    np.testing.assert_allclose(fr, fc, rtol=1e-6, atol=1e-6 * fc.max())
    np.testing.assert_allclose(np.ravel(r["end_force_a"]), np.ravel(c["end_force_a"]),
                               rtol=1e-6)
    on = fr > 0.5 * fr.max()
    # the suspended nodes carry only the smooth ramp's tail, k b delta^2 / 4 g at a height g:
    # 7e-4 N (3e-6 of the largest) 10 m up with the 3D lines' 10 % smoothing
    assert 6 <= on.sum() <= 15 and fr[:5].max() < 1e-5 * fr.max()
    assert np.hypot(*np.ravel(r["positions"])[-5:-3]) > 1.0  # swept across by the current


PROFILE = [[-60.0, 0.0, 0.1, 0.0], [-52.0, 0.4, 0.6, 0.0], [-45.0, 0.5, 1.0, 0.0]]


def profiled(model: str) -> dict:
    """tests/test_rod_vs_cable3d.py's 10 m hose hanging from a clamp at 50 m, in a current
    profile that turns and weakens with depth over its length."""
    return {"model": model, "environment": {"depth": 100.0, "current_profile": PROFILE},
            "line_types": {"t": _hose(model)},
            "sections": [{"type": "t", "length": 10.0, "segments": 20}],
            "end_a": {"condition": "clamped", "position": [0.0, 0.0, -50.0],
                      "direction": [0.0, 0.0, -1.0]},
            "end_b": {"condition": "free"}}


def test_rod_in_a_current_profile_is_cable3d():
    """As the uniform current's rod = cable3d (tests/test_rod_vs_cable3d.py): positions
    within 1e-6 m, the clamp's force within 1e-6 relative; the tip swept 0.57 m at 61 deg
    from x (measured), between the profile's directions at its ends (63 deg at the
    clamp, 90 deg below the tip): the profile acts."""
    c, r = _both(profiled)
    np.testing.assert_allclose(r["positions"], c["positions"], atol=1e-6)
    np.testing.assert_allclose(np.ravel(r["end_force_a"]), np.ravel(c["end_force_a"]),
                               rtol=1e-6)
    tip = np.ravel(r["positions"])[-3:]
    assert 0.9 < math.atan2(tip[1], tip[0]) < 1.1 and np.hypot(*tip[:2]) > 0.4


def across(law: str, static: str):
    """cable3d's bristle case (tests/test_cable3d_bristle.py) as a bending line: 100 m of
    line laid straight on the bed between pins, a cross current of 0.3 m/s."""
    def scene_of(model):
        return {"model": model, "environment": {"depth": 50.0, "current": [0.0, 0.3, 0.0]},
                "seabed": {"stiffness": 1e5, "friction": 0.5, "friction_law": law,
                           "static_friction": static},
                "line_types": {"c": _hose(model, EA=1e8, EI=100.0, mass=100.0, cd_normal=1.2,
                                          cd_tangential=0.5, ca_normal=1.0)},
                "sections": [{"type": "c", "length": 100.0, "segments": 20}],
                "end_a": {"condition": "pinned", "position": [0.0, 0.0, -50.0]},
                "end_b": {"condition": "pinned", "position": [100.0, 0.0, -50.0]}}
    return scene_of


@pytest.mark.parametrize("law, static", [("bristle", "none"), ("coulomb", "laid")])
def test_rod_friction_laws_statics_are_cable3d(law, static):
    """Each friction law's statics on the rod are cable3d's (positions within 1e-7 m,
    friction forces within 1e-6 of mu N): the bristle law's deflections are the rod's
    first-order states (at rest b = 0: no friction, the line swept 0.6 m across); static
    friction "laid" holds the line at its laid shape (within mm)."""
    c, r = _both(across(law, static))
    np.testing.assert_allclose(r["positions"], c["positions"], atol=1e-7)
    muN = 0.5 * float(np.max(r["contact_force"]))
    np.testing.assert_allclose(r["friction_force"], c["friction_force"], atol=1e-6 * muN)
    sweep = float(np.max(np.abs(np.asarray(r["positions"])[:, 1])))
    assert (sweep > 0.3) if static == "none" else (sweep < 1e-2)


L, T, A, EPS = 40.0, 200.0, 5.0, 0.01


def _drag_scene(direction, mu_a, mu_l, law) -> dict:
    """A 20-segment rod laid on the bed, both ends moved together along ``direction``."""
    amp = [A * direction[0], A * direction[1], 0.0]
    motion = {"kind": "harmonic", "period": T, "amplitude": amp, "phase_deg": [0.0, 0.0, 0.0]}
    d = {"model": "rod", "environment": {"depth": 50.0},
         "seabed": {"stiffness": 1e6, "friction_axial": mu_a, "friction_lateral": mu_l,
                    "friction_velocity": EPS, "friction_law": law},
         "line_types": {"c": {"mass": 100.0, "diameter": 0.1, "EA": 1e8, "EI": 10.0,
                              "GJ": 8.0, "cd_normal": 0.0, "cd_tangential": 0.0,
                              "ca_normal": 0.0}},
         "sections": [{"type": "c", "length": L, "segments": 20}],
         "end_a": {"condition": "pinned", "position": [0.0, 0.0, -50.0], "motion": motion},
         "end_b": {"condition": "pinned", "position": [L * (1 + 5e-4), 0.0, -50.0],
                   "motion": motion}}
    return d


def _drag(direction, mu_a, mu_l, law="coulomb"):
    """tests/test_cable3d_friction.py's drag with a rod (EI = 10 N m^2, small: the line
    bows only when dragged across): both ends move together, 5 m over 200 s; at t = 1.75 T
    the ends move at their fastest (no acceleration). Returns (the end forces' sum, N; the
    friction mu = 1 of the grounded weight at that speed, N: the regularised Coulomb law's
    N v / sqrt(v^2 + v_eps^2), the bristle law's N). The bristle law's states take the
    first-order generalized-alpha (rho_inf = 0, as cable3d's bristle tests), at 1 s."""
    d = _drag_scene(direction, mu_a, mu_l, law)
    mech = rod_mechanism(load_scene(d))
    eq = solve_equilibrium(mech, codegen=False)
    method = GeneralizedAlphaFirstOrder(rho_inf=0.0) if law == "bristle" else None
    tr = integrate(mech, 1.75 * T, 1.0, start=eq, p=mech.params.values, method=method,
                   progress=False)
    assert tr.status == "converged"
    n = len(tr.time)
    total = (np.asarray(tr.outputs["end_force_a"]).reshape(n, -1)
             + np.asarray(tr.outputs["end_force_b"]).reshape(n, -1))[-1]
    N = float(np.sum(np.asarray(tr.outputs["contact_force"]).reshape(n, -1)[-1]))
    v = A * 2 * math.pi / T
    return total, N * (v / math.sqrt(v * v + EPS * EPS) if law == "coulomb" else 1.0)


@pytest.mark.parametrize("law", ["coulomb", "bristle"])
def test_rod_dragged_along_carries_axial_friction(law):
    """Along its length: mu_axial (0.5, not the lateral 1.0) times the grounded weight
    within 5e-3 (cable3d's tolerance: the residual axial waves of the 1 s steps; measured
    3e-6 Coulomb, 4e-6 bristle), nothing across."""
    total, friction = _drag((1.0, 0.0), 0.5, 1.0, law)
    assert total[0] == pytest.approx(-0.5 * friction, rel=5e-3)
    assert abs(total[1]) < 1e-6 * friction


@pytest.mark.parametrize("law", ["coulomb", "bristle"])
def test_rod_dragged_across_carries_lateral_friction(law):
    """Across, one coefficient both ways: the line bows and slides at the ends' speed;
    within 1 % (cable3d's tolerance; measured 0.6 % more with the Coulomb law, as
    cable3d's: the bow's own motion; 4e-6 with the bristle law)."""
    total, friction = _drag((0.0, 1.0), 0.8, 0.8, law)
    assert total[1] == pytest.approx(-0.8 * friction, rel=1e-2)
    assert abs(total[0]) < 1e-6 * friction


def touchdown(model: str) -> dict:
    """60 m of line from a pin on the bed at 50 m depth to a pin 55 m along at 35 m (a
    catenary of about 25 m, taut on the bed: its grounded part straight), the first 25 m
    a cable3d section on the bed, the last 35 m the rod through the touchdown (near 29 m);
    ``model = "rod"``: the same line all rod."""
    lt = {"mass": 20.0, "diameter": 0.1, "EA": 1e7, "EI": 200.0, "GJ": 150.0,
          "cd_normal": 1.2}
    d = {"model": model, "environment": {"depth": 50.0},
         "seabed": {"stiffness": 1e5, "friction": 0.5},
         "line_types": {"c": lt},
         "sections": [{"type": "c", "length": 25.0, "segments": 10},
                      {"type": "c", "length": 35.0, "segments": 14}],
         "end_a": {"condition": "pinned", "position": [0.0, 0.0, -50.0]},
         "end_b": {"condition": "pinned", "position": [55.0, 0.0, -35.0]}}
    if model == "hybrid":
        d["sections"][0]["model"], d["sections"][1]["model"] = "cable3d", "rod"
    return d


def test_hybrid_cable_on_the_bed_rod_through_the_touchdown():
    """The hybrid converges; the grounded nodes 3-8 of the cable3d section (s = 7.5-20 m)
    carry their weight w ds to 1e-4 (measured 5e-5: nearer the pin, which holds end A 12
    mm above where the weight presses the line, the first segments slope; nearer the
    touchdown its catenary takes a growing share, 1.2e-4 at node 9, 6.5 m from it); the bed's
    reaction is the weight less what the ends hold (vertical balance, to the solve's
    tolerance); the touchdown (first suspended node) is in the rod section; and the shape
    is the all-rod line's within 1e-5 m, its end force within 1e-6 relative (measured
    7.8e-7 m, 7.5e-8: the joint, on the flat bed 5 m before the touchdown, releases the
    rod's 0.03 N m there)."""
    sc = load_scene(touchdown("hybrid"))
    mech = rod_mechanism(sc)
    assert mech.name == "hybrid" and "seabed" in mech.terms
    eq = solve_equilibrium(mech, codegen=False)
    assert eq.status == "converged"
    o = eq.outputs
    c = np.ravel(o["contact_force"])
    w = sc.line_types["c"].weight
    np.testing.assert_allclose(c[3:9], w * 2.5, rtol=1e-4)
    fa, fb = np.ravel(o["end_force_a"]), np.ravel(o["end_force_b"])
    assert c.sum() == pytest.approx(w * 60.0 + fa[2] + fb[2], rel=1e-6)
    lift = int(np.argmax(c < 1e-3 * c.max()))
    assert 10 < lift < 24  # beyond the joint (node 10), in the rod section
    rod = solve_equilibrium(rod_mechanism(load_scene(touchdown("rod"))), codegen=False)
    np.testing.assert_allclose(o["positions"], rod.outputs["positions"], atol=1e-5)
    np.testing.assert_allclose(fb, np.ravel(rod.outputs["end_force_b"]), rtol=1e-6)


def laid_seed(length: float = 3.0, zone: float = 0.5, ds: float = 0.05) -> dict:
    """The seed's cable (symcable/data's benchmark: D = 1 mm, Table 1) laid on a frictional
    bed (mu = 0.3) from a pin, its last ``zone`` m a rod ending at the benchmark's guided,
    tension-free end lifted by 0.01 N normal to its 30 deg tangent: the longer case of the
    benchmark (issue 14 item 4), whose low-tension zone is a small fraction of the line."""
    cable = {"EA": 3926.990816987241, "EI": 2.454369260617026e-4,
             "GJ": 1.9634954084936207e-4, "mass": 7.853981633974483e-4, "diameter": 1.0e-3,
             "cd_normal": 1.0, "cd_tangential": 0.3141592653589793, "ca_normal": 0.0,
             "ca_tangential": 0.0}
    cat = {k: v for k, v in cable.items() if k != "GJ"}
    cat["EI"] = 0.0
    return {"model": "hybrid", "environment": {"gravity": 9.8, "water_density": 1.0,
                                               "depth": 1.0},
            "seabed": {"stiffness": 1e4, "friction": 0.3},
            "line_types": {"cable": cable, "catenary": cat},
            "sections": [{"type": "catenary", "length": length - zone,
                          "segments": round((length - zone) / ds), "model": "cable3d"},
                         {"type": "cable", "length": zone, "segments": round(zone / ds),
                          "model": "rod"}],
            "end_a": {"condition": "pinned", "position": [0.0, 0.0, -1.0]},
            "end_b": {"condition": "guided", "direction": [0.8660254037844387, 0.0, -0.5],
                      "force": [0.005, 0.0, 0.008660254037844387]}}


def test_seed_cable_laid_on_the_bed_with_a_low_tension_end():
    """Statics converge: the line lies on the bed up to about 1 m before its end, the bed
    carries the weight less the end force's lift and the pin's pull (the pin holds end A
    on the bed's surface, 0.8 mm above where the line rests: 9e-5 N down) to 1e-6
    relative, the end holds its
    tangent (the last edge within 0.3 rad of it: measured 0.19, half a segment's turn
    under the end's moment, kappa = M / EI ~ 8 /m); the generic integrator
    (generalized-alpha, second and first order, rho_inf = 0) takes 5 steps of 1 s (the
    seed's dt) from it, staying at rest (1e-6 m)."""
    sc = load_scene(laid_seed())
    mech = rod_mechanism(sc)
    eq = solve_equilibrium(mech, codegen=False)
    assert eq.status == "converged"
    X, c = np.asarray(eq.outputs["positions"]), np.ravel(eq.outputs["contact_force"])
    W = sc.line_types["cable"].weight * sc.length
    fa, fb = np.ravel(eq.outputs["end_force_a"]), np.ravel(eq.outputs["end_force_b"])
    np.testing.assert_allclose(fb, [-0.005, 0.0, -0.008660254037844387], atol=1e-9)
    assert c.sum() == pytest.approx(W + fa[2] + fb[2], rel=1e-6)
    on = np.flatnonzero(c > 0.5 * c.max())
    assert 1.5 < X[on[-1], 0] < 2.5 and X[-1, 2] > -0.8
    t_end = (X[-1] - X[-2]) / np.linalg.norm(X[-1] - X[-2])
    assert math.acos(t_end @ [0.8660254037844387, 0.0, -0.5]) < 0.3
    for method in (GeneralizedAlpha(rho_inf=0.0), GeneralizedAlphaFirstOrder(rho_inf=0.0)):
        tr = integrate(mech, 5.0, 1.0, method=method, start=eq, p=mech.params.values,
                       progress=False)
        assert tr.status == "converged"
        n = len(tr.time)
        Xt = np.asarray(tr.outputs["positions"]).reshape(n, -1, 3)
        assert np.abs(Xt - X).max() < 1e-6


def test_zones_auto_on_the_laid_seed_cable():
    """zones = "auto" on the same 3 m line (one section, the rod's line type): the
    all-cable3d solve on the bed marks the low-tension lift-off and end (bending length
    above 0.15 L) and leaves the grounded part, under the end force's 5 mN, a cable3d
    section (measured: rod on 2.25-3 m); the hybrid then solves on the bed (the first
    half carrying its weight, within 20 %: the cable3d section's own bending shares it
    near the pin and the touchdown), the last nodes lifted."""
    d = laid_seed()
    d["zones"] = "auto"
    d["sections"] = [{"type": "cable", "length": 3.0, "segments": 60}]
    s = sc.solve_static(load_scene(d))
    assert s.status == "converged"
    (s0, s1), = s.stats["zones"]["zones"]
    assert 1.8 < s0 < 2.6 and s1 == pytest.approx(3.0)
    c = np.ravel(s.stats["outputs"]["contact_force"])
    wds = 7.6892e-3 * 0.05  # N: a node's submerged weight
    assert c[3:30].min() > 0.8 * wds and c[-5:].max() < 1e-3 * wds


def test_rod_with_bristle_friction_runs_through_simulate():
    """The bristle law's first-order states ride along the rod's twist dynamics at user level
    (sc.simulate adds the reference frames' spin, which once refused any Mechanism with
    kinematics): dragged along, the ends carry the same friction as the bare Mechanism's run
    above, within 5e-3 of mu N (the drag test's tolerance: nothing turns, so the spin adds
    nothing but round-off)."""
    d = _drag_scene((1.0, 0.0), 0.5, 1.0, "bristle")
    tr = sc.simulate(d, 1.75 * T, dt=1.0, codegen=False)
    assert tr.status == "converged"
    total = np.asarray(tr.anchor_force)[-1] + np.asarray(tr.fairlead_force)[-1]
    ref, friction = _drag((1.0, 0.0), 0.5, 1.0, "bristle")
    assert np.max(np.abs(total - ref)) < 5e-3 * friction
