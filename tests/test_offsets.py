"""The offset sweep of a moored body (issue 13, item 6; symcable/api/offsets.py): the restoring
force on the OC3-like submerged spar of test_bodies_moored held at a sweep of offsets, in
one batched call, against separate static solves of the body held there, against MoorPy's
lines, and its exact stiffness against linearize's."""
from __future__ import annotations

import math

import numpy as np
import pytest

import symcable as sc
from symcable.api.offsets import offsets_along
from test_bodies_moored import CHAIN, DEPTH, G, LENGTH, R_ANCHOR, R_FAIR, RHO, _moored


@pytest.fixture(scope="module")
def surge():
    return sc.offset_sweep(_moored(10), "spar", offsets_along("surge", -2.0, 2.0, 9),
                           codegen=False)


def test_each_offset_is_the_static_solve_of_the_body_held_there(surge):
    """Every offset solved in the batch (no fallback), each equal to sc.solve_static of the
    scene with the body fixed at that pose, to 1e-7 of the force (both solves' tolerance,
    1e-9 of the force scale, over a force of 1e5-1e6 N); the restoring force zero at the
    equilibrium (its static tolerance, 3.4e-3 N); the lines' force balance to round-off
    (measured 7e-10)."""
    r = surge
    assert r.converged.all() and set(r.path) == {"batch"} and r.stats["fallbacks"] == 0
    assert np.max(np.abs(r.force[4])) < 10 * r.stats["tolerance"]
    assert np.nanmax(r.balance) < 1e-8
    for k in (0, 6, 8):
        d = _moored(10)
        d["bodies"]["spar"] = {"kind": "fixed", "position": list(r.base_pose[:3] + r.offsets[k, :3]),
                               "orientation": list(r.base_pose[3:] + r.offsets[k, 3:])}
        b = sc.solve_static(d, codegen=False)
        ref = np.r_[b.bodies["spar"].force, b.bodies["spar"].moment]
        np.testing.assert_allclose(r.line_force[k], ref, atol=1e-7 * np.max(np.abs(ref)))
        assert r.tension_b[k, 0] == pytest.approx(b.lines["chain0"].fairlead_tension, rel=1e-8)


def test_stiffness_is_linearize_and_the_sweep_slope(surge):
    """The sweep's exact stiffness at the base (the lines' by the implicit function theorem,
    the body's own loads by their derivative) equals linearize's body_stiffness (the same
    derivative condensed another way; measured 3e-12 relative to the diagonal, against
    1e-6 allowed for the two solves' tolerance), and the sweep's own central differences at
    +-1 mm (surge) and +-1e-3 deg (pitch) agree with it to 1e-5 (the differences'
    truncation and the solves' tolerance, as in test_bodies_moored)."""
    K = sc.linearize(_moored(10)).body_stiffness["spar"]
    d = np.sqrt(np.abs(np.outer(np.diag(K), np.diag(K))))
    assert np.max(np.abs(surge.stiffness - K) / d) < 1e-6
    for dof, h in (("surge", 1e-3), ("pitch", 1e-3)):
        r = sc.offset_sweep(_moored(10), "spar", offsets_along(dof, -h, h, 3), codegen=False)
        j = r.dof()
        step = 2 * h * (math.pi / 180 if j >= 3 else 1.0)
        fd = -(r.force[2] - r.force[0]) / step
        assert np.max(np.abs(fd - K[:, j]) / np.sqrt(np.abs(np.diag(K)) * abs(K[j, j]))) < 1e-5


def test_against_moorpy_lines():
    """The lines' force on the body over a surge and a pitch sweep against MoorPy's exact
    elastic catenaries (the body coupled at each pose, each line's staticSolve, getForces
    with lines_only), 20 segments: within 0.5 % of the largest force of the sweep (the
    lumped-mass chain's discretisation, second order in the segments: measured 0.13 % of
    it at 20 segments on the stiffness in test_bodies_moored; measured 2.7e-4 in surge to
    3 m, 6.8e-4 in pitch to 5 deg)."""
    mp = pytest.importorskip("moorpy")
    d = _moored(20)
    for dof, a in (("surge", 3.0), ("pitch", 5.0)):
        r = sc.offset_sweep(d, "spar", offsets_along(dof, -a, a, 7), codegen=False)
        ms = mp.System(depth=DEPTH, rho=RHO, g=G)
        w = (CHAIN["mass"] - RHO * math.pi * CHAIN["diameter"] ** 2 / 4) * G
        ms.setLineType(name="chain", mass=CHAIN["mass"], d_vol=CHAIN["diameter"],
                       EA=CHAIN["EA"], w=w, dnommm=90)
        body = ms.addBody(-1, np.r_[r.base_pose[:3], 0, 0, 0])
        for k in range(3):
            th = math.radians(120 * k)
            ms.addPoint(1, [R_ANCHOR * math.cos(th), R_ANCHOR * math.sin(th), -DEPTH])
            ms.addPoint(1, [R_FAIR * math.cos(th), R_FAIR * math.sin(th), -5.0], body=1)
            ms.addLine(LENGTH, "chain", pointA=2 * k + 1, pointB=2 * k + 2)
        ms.initialize()
        ref = []
        for o in r.offsets:
            body.setPosition(np.r_[r.base_pose[:3] + o[:3], np.radians(o[3:])])
            for ln in ms.lineList:
                ln.staticSolve()
            ref.append(body.getForces(lines_only=True))
        ref = np.array(ref)
        scale = np.max(np.abs(ref), axis=0)
        big = scale > 1e-3 * np.max(scale[:3])
        err = np.max(np.abs(r.line_force - ref)[:, big] / scale[big])
        assert err < 5e-3, (dof, err)


def test_save_load_plot_and_errors(tmp_path, surge):
    r = surge
    for suffix in (".json", ".npz"):
        back = type(r).load(r.save(tmp_path / f"sweep{suffix}"))
        np.testing.assert_array_equal(back.force, r.force)
        assert back.status == r.status and back.line_names == r.line_names
    assert "surge" in r.summary()
    import matplotlib
    matplotlib.use("Agg")
    fig = r.plot()
    assert len(fig.axes) == 6
    with pytest.raises(sc.SceneError, match="body = 'hull': no such body"):
        sc.offset_sweep(_moored(5), "hull", np.zeros((1, 6)))
    with pytest.raises(sc.SymcableError, match=r"offsets: shape \(3, 5\)"):
        sc.offset_sweep(_moored(5), "spar", np.zeros((3, 5)))
    with pytest.raises(sc.SymcableError, match="dof = 'surf'"):
        offsets_along("surf", -1, 1, 3)
    for start in ("x", None, True, float("inf")):  # one line each, never a bare TypeError
        with pytest.raises(sc.SymcableError, match=r"^start, stop = .*must be finite numbers"):
            offsets_along("surge", start, 1.0, 3)


def test_cli_offsets(tmp_path, capsys):
    """``symcable offsets``: the summary, the figure and the saved sweep; a bad body is one
    line and exit status 2."""
    from symcable.cli.main import main
    from symcable.scene import load_scene, scene_to_toml

    p = tmp_path / "spar.toml"
    p.write_text(scene_to_toml(load_scene(_moored(5))))
    assert main(["offsets", str(p), "--body", "spar", "--dof", "heave", "--range", "-1", "1",
                 "--n", "5", "--plot", str(tmp_path / "f.png"),
                 "--save", str(tmp_path / "s.json")]) == 0
    out = capsys.readouterr().out
    assert "5 along heave -1 .. 1 m, 5 converged" in out
    assert (tmp_path / "f.png").stat().st_size > 0
    assert sc.OffsetSweep.load(tmp_path / "s.json").force.shape == (5, 6)
    assert main(["offsets", str(p), "--body", "hull"]) == 2
    assert "body = 'hull'" in capsys.readouterr().err


def test_no_casadi_notice_and_round_off_drawn_flat(tmp_path):
    """The sweep hands NumPy only NumPy arrays (no CasADi FutureWarning reaches the user),
    and a panel whose force varies by round-off only (a surge sweep's Fy, Mx, Mz) spans at
    least 1e-3 of the sweep's largest force or moment instead of magnifying the noise."""
    import warnings
    with warnings.catch_warnings():
        warnings.simplefilter("error", FutureWarning)
        res = sc.offset_sweep(_moored(6), "spar", offsets_along("surge", -5.0, 5.0, 5))
    fig = res.plot(tmp_path / "o.png")
    fy, mx = fig.axes[1], fig.axes[3]
    assert np.ptp(res.force[:, 1]) < 1e-6 * np.max(np.abs(res.force[:, :3]))  # round-off
    lo, hi = fy.get_ylim()
    assert hi - lo >= 1e-3 * np.max(np.abs(res.force[:, :3])) / 1e3  # kN
    lo, hi = mx.get_ylim()
    assert hi - lo >= 1e-3 * np.max(np.abs(res.force[:, 3:])) / 1e6  # MN m


def test_a_sweep_of_one_held_scene_then_another_of_its_structure():
    """Two scenes whose fixed spar sits at other positions (or whose chains are longer)
    share one structure (the body's position and the lines' numbers are parameters); a
    sweep of the second after the first is the second's, not the first's built-in pose:
    its line force at zero offset equals the second scene's static body force and moment
    (to 1e-7 of the force, the solves' tolerance)."""
    import copy
    d = _moored(6)
    d["bodies"]["spar"] = {"kind": "fixed", "position": [0.0, 0.0, -30.0]}
    moved = copy.deepcopy(d)
    moved["bodies"]["spar"]["position"] = [8.0, 0.0, -30.0]
    longer = copy.deepcopy(d)
    for ln in longer["lines"]:
        ln["sections"][0]["length"] += 5.0
    zero = np.zeros((1, 6))
    sc.offset_sweep(d, "spar", zero, codegen=False)
    for other in (moved, longer):
        r = sc.offset_sweep(other, "spar", zero, codegen=False)
        st = sc.solve_static(other, codegen=False, estimate=False)
        ref = np.r_[st.bodies["spar"].force, st.bodies["spar"].moment]
        np.testing.assert_allclose(r.line_force[0], ref, atol=1e-7 * np.max(np.abs(ref)))
