"""The rod's user level (issue 14 item 3): ``sc.modal_analysis``, ``sc.simulate``,
``sc.linearize``, ``sc.end_stiffness`` and the CLI on a ``model = "rod"`` scene, through the
cable3d user level with the rod's Mechanism and static state
(:func:`symcable.api.scene3d.scene_mechanism`, :func:`~symcable.api.scene3d.scene_equilibrium`).
"""
from __future__ import annotations

import json
import math

import numpy as np
import pytest

import symcable as sc
from test_rod_greenhill import B, FRACTIONS, GJ, GREENHILL, L, critical_moment, twisted_rod



def _greenhill_scene(segments: int, M: float) -> dict:
    """The Greenhill rod of tests/test_rod_greenhill.py with end B's clamp turned by
    Phi = M L / GJ about the axis (``twist_deg``): the twisting moment M (N m)."""
    d = twisted_rod(segments)
    d["end_b"]["twist_deg"] = math.degrees(M * L / GJ)
    return d


def test_greenhill_through_modal_analysis():
    """The lowest frequency of ``sc.modal_analysis`` at M = 0.9, 0.95, 0.98 of Greenhill's
    8.98682 B / L (20 segments: the user level is what is tested here; the 1 % at 40
    segments and the order are tests/test_rod_greenhill.py's), its square fitted by a
    quadratic in M^2 and the root: the M_cr of mechanism_modes on the same Mechanism and
    static states (9.121 B / L, 1.5 % high) to 1e-6 (the static solves' tolerance), within
    2 % of Greenhill's; the two bending planes give one frequency (to 1e-6)."""
    rows = []
    for frac in FRACTIONS:
        M = frac * GREENHILL * B / L
        modal = sc.modal_analysis(_greenhill_scene(20, M), 2)
        f = modal.frequencies
        assert f[1] == pytest.approx(f[0], rel=1e-6)
        assert modal.shapes.shape == (2, 21, 3)
        rows.append((M, f[0]))
    M, f = np.array(rows).T
    roots = np.roots(np.polyfit(M**2, f**2, 2))
    roots = roots[np.isreal(roots) & (roots.real > 0)].real
    M_cr = float(np.sqrt(np.min(roots))) * L / B
    assert abs(M_cr / GREENHILL - 1.0) < 0.02, M_cr
    assert M_cr == pytest.approx(critical_moment(20)[0], rel=1e-6)


def _cantilever(motion: dict | None = None, damping: float = 0.0) -> dict:
    """tests/test_rod_dynamics.py's cantilever (two principal stiffnesses, its clamp's frame
    turned 30 deg, in air, w L^3 / EI = 2), its clamp moved by ``motion``."""
    L_, EI = 2.0, 10.0
    d = {"model": "rod", "environment": {"water_density": 0.0},
         "line_types": {"beam": {"EA": 1e4 * EI / L_**2, "EI": [EI, 2 * EI], "GJ": 7.0,
                                 "mass": 1.0, "diameter": 0.02, "weight": 2.0 * EI / L_**3,
                                 "damping": damping}},
         "sections": [{"type": "beam", "length": L_, "segments": 8}],
         "end_a": {"condition": "clamped", "position": [0.0, 0.0, 0.0],
                   "direction": [math.cos(0.7), math.sin(0.7), 0.0], "twist_deg": 30.0},
         "end_b": {"condition": "free"}}
    if motion is not None:
        d["end_a"]["motion"] = motion
    return d


@pytest.fixture(scope="module")
def kick(tmp_path_factory):
    """A motion table that moves the clamp by 5 cm over 0.1 s and then holds it."""
    path = tmp_path_factory.mktemp("rod") / "kick.txt"
    path.write_text("0 0 0 0\n0.05 0 0.02 0.01\n0.1 0 0.05 0\n")
    return {"kind": "table", "file": str(path)}


def _energy_drift(d: dict, dt: float) -> tuple[float, object]:
    """The largest change of the energy (the rod's outputs kinetic_energy + potential_energy,
    in ``stats["outputs"]``) after the clamp stops (t >= 0.12 s) over the largest kinetic
    energy then, of ``sc.simulate`` at rho_inf = 1."""
    tr = sc.simulate(d, 0.5, dt=dt, rho_inf=1.0, codegen=False)
    o = tr.stats["outputs"]
    K = o["kinetic_energy"].ravel()
    E = K + o["potential_energy"].ravel()
    late = tr.time >= 0.12 - 1e-9
    return float(np.max(np.abs(E[late] - E[late][0])) / np.max(K[late])), tr


def test_energy_through_simulate(kick):
    """The undamped rod, its clamp kicked and then held, through ``sc.simulate`` (first-
    order generalized-alpha, rho_inf = 1): the energy is conserved once the clamp is still,
    to second order in dt. Measured 3.9e-3, 8.0e-4, 2.1e-4 of the largest kinetic energy at
    dt = 4, 2, 1 ms (orders 2.3, 1.9). Asserted at 4 and 2 ms: the order within 0.5 of 2,
    the drift below 2e-3 at 2 ms. The run is a LineTrajectory with the rod's series in
    ``stats["outputs"]`` (twists, curvatures, moments, internal force) and no slack report
    (a rod carries compression)."""
    e4, _ = _energy_drift(_cantilever(kick), 4e-3)
    e2, tr = _energy_drift(_cantilever(kick), 2e-3)
    assert abs(math.log2(e4 / e2) - 2.0) < 0.5, (e4, e2)
    assert e2 < 2e-3
    n_t = tr.time.size
    o = tr.stats["outputs"]
    assert o["internal_force"].shape == (n_t, 8 * 3) and o["twist_angles"].shape == (n_t, 8)
    assert o["bending_moment"].shape == (n_t, 9 * 3) and "snaps" not in tr.stats
    # the seed's tension f . t and shear from the internal force: they make up |f|; the
    # tension is the stiff axial force EA e (the bending forces straddling a cut act normal
    # to its edge: measured equal to 2e-14 N of 87 N), the shear up to 24 N
    f = o["internal_force"].reshape(n_t, 8, 3)
    assert o["tension"].shape == o["shear"].shape == (n_t, 8)
    assert np.allclose(np.hypot(o["tension"], o["shear"]), np.linalg.norm(f, axis=2))
    assert np.allclose(o["tension"], tr.axial_force, rtol=0, atol=1e-9 * np.max(np.abs(f)))
    assert np.max(o["shear"]) > 0.1 * np.max(np.abs(tr.axial_force))
    assert tr.positions.shape == (n_t, 9, 3) and tr.stats["start"] == "rest"


def test_linearize_and_end_stiffness():
    """``sc.linearize`` on a rod pinned at both ends (sagging under its weight): K, C, M in
    the positions and twists (the twists named ``edge{j}.twist``), the mass matrix
    symmetric positive definite, K symmetric at the equilibrium (a conservative system: to
    1e-8 of its largest entry), and end B's stiffness equal to ``sc.end_stiffness``'s."""
    d = _cantilever()
    d["end_a"] = {"condition": "pinned", "position": [0.0, 0.0, 0.0]}
    d["end_b"] = {"condition": "pinned", "position": [1.9, 0.0, -0.2]}
    lin = sc.linearize(d)
    assert lin.K.shape == (lin.M.shape[0], lin.M.shape[0]) == (7 * 3 + 7, 7 * 3 + 7)
    assert sum(k.endswith(".twist") for k in lin.q_kinds) == 7 and "node1.x" in lin.q_kinds
    assert np.allclose(lin.M, lin.M.T) and np.min(np.linalg.eigvalsh(lin.M)) > 0
    assert np.max(np.abs(lin.K - lin.K.T)) < 1e-8 * np.max(np.abs(lin.K))
    Kb = sc.end_stiffness(d, "b")
    assert np.allclose(Kb, lin.end_stiffness["b"], rtol=1e-9, atol=1e-9 * np.max(np.abs(Kb)))


def test_periodic_rod():
    """``sc.solve_periodic`` on a damped rod whose clamp heaves (2 cm, 1 s): shooting and
    collocation agree on the tip's heave range and the largest tension at end B (measured
    0.056 m both, tensions 0.1479 and 0.1478 N; harmonic balance, not run here for time,
    0.0559 m, 0.1478 N). Asserted within 1 %."""
    d = _cantilever({"kind": "harmonic", "amplitude": [0.0, 0.0, 0.02], "period": 1.0},
                    damping=5.0)
    runs = {m: sc.solve_periodic(d, m) for m in ("shooting", "collocation")}
    heave = {m: float(np.ptp(r.positions[:, -1, 2])) for m, r in runs.items()}
    assert all(r.status == "converged" for r in runs.values())
    assert heave["shooting"] == pytest.approx(heave["collocation"], rel=0.01)
    assert runs["shooting"].fairlead_tension.max() == pytest.approx(
        runs["collocation"].fairlead_tension.max(), rel=0.01)
    assert "outputs" in runs["collocation"].stats


def test_cli_simulate_rod(kick, tmp_path, capsys):
    """``symcable check``, ``simulate`` and ``modes`` on a rod scene file, with --json."""
    from symcable.cli.main import main
    from symcable.scene import load_scene, scene_to_toml
    p = tmp_path / "rod.toml"
    p.write_text(scene_to_toml(load_scene(_cantilever(kick))))
    assert main(["check", str(p)]) == 0
    assert "rod" in capsys.readouterr().out
    assert main(["simulate", str(p), "--duration", "0.2", "--dt", "0.005", "--json"]) == 0
    d = json.loads(capsys.readouterr().out)
    assert d["status"] == "converged" and len(d["time"]) == 41
    assert len(d["stats"]["outputs"]["twist_angles"][0]) == 8
    assert main(["modes", str(p), "--n", "2", "--json"]) == 0
    d = json.loads(capsys.readouterr().out)
    assert len(d["frequencies"]) == 2 and len(d["stats"]["twist_shapes"][0]) == 8


def test_hybrid_scenes_take_every_analysis():
    """A hybrid (tests/test_hybrid.py's taut hose: cable3d, rod, cable3d sections; its end B
    heaving) through ``sc.modal_analysis`` (twist shapes zero on the cable3d edges),
    ``sc.linearize`` (the rod edges' twists named) and ``sc.simulate`` (re-anchoring and
    the frames' spin on the rod edges only); an all-cable3d hybrid is cable3d's
    Mechanism and runs without either."""
    from test_hybrid import taut
    d = taut("hybrid", (None, "rod", None))
    d["end_b"]["motion"] = {"kind": "harmonic", "amplitude": [0.0, 0.0, 0.05], "period": 2.0}
    modal = sc.modal_analysis(d, 3)
    tw = np.asarray(modal.stats["twist_shapes"])
    assert tw.shape == (3, 18) and np.all(tw[:, :6] == 0) and np.all(tw[:, 12:] == 0)
    lin = sc.linearize(d)
    assert sorted(k for k in lin.q_kinds if k.endswith(".twist")) == sorted(
        f"edge{j}.twist" for j in range(7, 12))
    tr = sc.simulate(d, 0.5, dt=0.01, codegen=False)
    assert tr.status == "converged" and tr.stats["outputs"]["twist_angles"].shape == (51, 18)
    flat = sc.simulate(taut("hybrid") | {"end_b": d["end_b"]}, 0.5, dt=0.01, codegen=False)
    assert flat.status == "converged" and "reanchorings" not in flat.stats
