"""The command line, result export and plots."""
from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import symcable as sc
from symcable.cli.main import main

from conftest import OC3, two_point


def _write_scene(tmp_path, text):
    p = tmp_path / "scene.toml"
    p.write_text(text)
    return p


GOOD = """
name = "small"
[environment]
water_density = 1025.0
[line_types.rope]
EA = 1e7
mass = 20.0
diameter = 0.05
[[sections]]
type = "rope"
length = 100.0
segments = 20
[end_a]
condition = "pinned"
position = [0.0, 0.0]
[end_b]
condition = "pinned"
position = [80.0, 10.0]
"""


def test_cli_check_and_static_json(tmp_path, capsys):
    """`check` reports what the scene builds; `static --json` prints the same numbers as the
    Python object (to JSON round-off) and writes the plot it was asked for."""
    path = _write_scene(tmp_path, GOOD)
    assert main(["check", str(path)]) == 0
    out = capsys.readouterr().out
    assert "terms: elastic, weight" in out and "ok" in out
    png = tmp_path / "static.png"
    assert main(["static", str(path), "--json", "--plot", str(png)]) == 0
    d = json.loads(capsys.readouterr().out)
    st = sc.solve_static(path)
    assert d["fairlead_tension"] == pytest.approx(st.fairlead_tension, rel=1e-12)
    assert d["status"] == "converged"
    assert png.stat().st_size > 10_000


@pytest.mark.parametrize("text, key", [
    (GOOD.replace("length = 100.0", "length = -3.0"), "sections[0].length = -3.0"),
    (GOOD.replace("diameter = 0.05", "diamter = 0.05"), "did you mean 'diameter'"),
    (GOOD.replace("[80.0, 10.0]", "[500.0, 10.0]"), "end_b.position"),
])
def test_cli_errors_are_one_line(tmp_path, capsys, text, key):
    """Bad input: exit status 2 and one line on stderr naming the key, no traceback."""
    path = _write_scene(tmp_path, text)
    assert main(["static", str(path)]) == 2
    err = capsys.readouterr().err.strip()
    assert "\n" not in err and "Traceback" not in err
    assert err.startswith("symcable: SceneError:") and key in err


def test_cli_missing_file(capsys):
    assert main(["check", "/nonexistent/scene.toml"]) == 2
    assert "/nonexistent/scene.toml" in capsys.readouterr().err


def test_console_script_demo(tmp_path):
    """`symcable demo` (the installed console script) solves the built-in OC3 scene and
    writes its plot, with no input."""
    script = Path(sys.executable).parent / "symcable"
    assert script.exists(), "the package's console script is not installed beside python"
    exe = [str(script)]
    out = subprocess.run(exe + ["demo", "--plot", str(tmp_path / "d.png")], capture_output=True,
                         text=True, cwd=tmp_path, timeout=300)
    assert out.returncode == 0, out.stderr
    assert "fairlead tension" in out.stdout and (tmp_path / "d.png").exists()


@pytest.mark.parametrize("suffix", [".npz", ".json"])
def test_save_and_load_round_trip(tmp_path, suffix):
    """A saved solution reloads with the same arrays and stats (exact for NPZ; JSON keeps
    17 significant digits, so exact too)."""
    st = sc.solve_static(OC3)
    path = st.save(tmp_path / f"sol{suffix}")
    back = sc.StaticSolution.load(path)
    for name in ("positions", "tension", "moment", "strain", "fairlead_force"):
        np.testing.assert_array_equal(getattr(back, name), getattr(st, name))
    assert back.fairlead_tension == st.fairlead_tension
    assert back.stats["iterations"] == st.stats["iterations"]
    assert back.status == "converged"


def test_summary_has_units():
    text = sc.solve_static(two_point((0, 0), (80, 10))).summary()
    assert "kN" in text and " m" in text and " N (tol" in text


def test_plot_has_profile_and_forces(tmp_path):
    """The report figure has the profile (equal axes) and tension/moment panels."""
    d = two_point((0.0, 0.0), (80.0, 10.0), EI=1e4)
    fig = sc.solve_static(d).plot(tmp_path / "p.png")
    axes = fig.get_axes()
    assert len(axes) == 3  # profile, tension, moment (twin axis)
    assert axes[0].get_xlabel() == "x (m)" and "kN" in axes[1].get_ylabel()
    assert (tmp_path / "p.png").exists()


@pytest.fixture
def small_seed001(tmp_path):
    """The built-in seed-001 scene cut to 20 segments, as a TOML file."""
    from symcable.scene import scene_to_toml
    d = sc.load_scene(sc.demo_scene_path("seed001")).to_dict()
    d["sections"][0]["segments"] = 20
    path = tmp_path / "seed001.toml"
    path.write_text(scene_to_toml(sc.load_scene(d)))
    return path


def test_cli_simulate_periodic_modes_json(small_seed001, tmp_path, capsys):
    """`simulate`, `periodic` and `modes` print JSON with the numbers the Python API gives
    (to round-off of the same computation) and write their plots."""
    assert main(["simulate", str(small_seed001), "--duration", "20", "--dt", "0.1", "--json",
                 "--plot", str(tmp_path / "s.png")]) == 0
    d = json.loads(capsys.readouterr().out)
    tr = sc.simulate(small_seed001, 20.0, dt=0.1)
    np.testing.assert_allclose(d["fairlead_tension"], tr.fairlead_tension, rtol=1e-12)
    assert (tmp_path / "s.png").exists()

    assert main(["periodic", str(small_seed001), "--method", "harmonic-balance", "--json",
                 "--plot", str(tmp_path / "p.png")]) == 0
    d = json.loads(capsys.readouterr().out)
    per = sc.solve_periodic(small_seed001, method="harmonic-balance")
    np.testing.assert_allclose(d["fairlead_tension"], per.fairlead_tension, rtol=1e-9)
    assert d["status"] == "converged" and (tmp_path / "p.png").exists()

    assert main(["modes", str(small_seed001), "--n", "3", "--json"]) == 0
    d = json.loads(capsys.readouterr().out)
    np.testing.assert_allclose(d["frequencies"], sc.modal_analysis(small_seed001, 3).frequencies,
                               rtol=1e-9)


def test_cli_check_reports_how_the_dynamics_run(capsys):
    """`check` on a scene with a motion also says whether and how that motion runs: the
    built-in OC3 scene rests 135 m on the seabed, which the linearised planar dynamics do
    not model, so `check` says its dynamics run as the 3D cable in its plane ("ok"); the
    suspended seed-001 scene runs linearised ("ok"); a scene whose two ends move at
    different periods is refused with the reason, exit 1."""
    assert main(["check", str(sc.demo_scene_path("oc3"))]) == 0
    out = capsys.readouterr().out
    assert "dynamics   ok: the static line rests" in out and "model = 'cable3d'" in out
    assert out.rstrip().endswith("\nok")
    assert main(["check", str(sc.demo_scene_path("seed001"))]) == 0
    out = capsys.readouterr().out
    assert "dynamics   ok: linearised" in out and out.rstrip().endswith("\nok")
    d = sc.load_scene("seed001").to_dict()
    d["end_a"]["motion"] = dict(d["end_b"]["motion"], period=7.0)
    path = tmp_scene(d)
    assert main(["check", path]) == 1
    out = capsys.readouterr().out
    assert "dynamics   refused:" in out and "same period" in out and "not ok" in out


def tmp_scene(data: dict) -> str:
    """``data`` written as a TOML scene file in a fresh temporary folder; its path."""
    import tempfile

    import tomli_w
    folder = tempfile.mkdtemp()
    path = f"{folder}/scene.toml"
    with open(path, "wb") as f:
        tomli_w.dump(data, f)
    return path


def test_time_series_plots_show_compression(tmp_path):
    """A time run and a periodic solution of the seed-001 line (20 segments) at 10 times its
    amplitude, where the top segments go into compression (the signed axial force reaches
    about -160 kN; the tension magnitudes stay above 50 kN): their time-series panel draws
    the least axial force along the line, which goes below the dashed zero line, with the
    compressive part shaded. The periodic envelope is on the nodes (21 points, from s = 0)."""
    from matplotlib.collections import PolyCollection
    from symcable.plotting.profiles import close, plot_periodic, plot_trajectory

    d = sc.load_scene(sc.demo_scene_path("seed001")).to_dict()
    d["sections"][0]["segments"] = 20
    d["end_b"]["motion"]["amplitude"] = [12.0, 6.0]
    scene = sc.load_scene(d)
    model = sc.build_dynamic_model(scene)
    tr = sc.simulate(scene, 20.0, dt=0.1, model=model)
    per = sc.solve_periodic(scene, "harmonic-balance", harmonics=4, model=model)
    for result, figure in ((tr, plot_trajectory(tr, tmp_path / "t.png")),
                           (per, plot_periodic(per, tmp_path / "p.png"))):
        assert result.status == "slack" and np.min(result.axial_force) < -1e5
        assert np.min(result.fairlead_tension) > 0.0  # the magnitudes hide it
        ax = figure.get_axes()[0]
        zero = [ln for ln in ax.get_lines() if ln.get_linestyle() == "--"
                and np.all(np.asarray(ln.get_ydata()) == 0.0)]
        least = [ln for ln in ax.get_lines() if ln.get_label().startswith("least axial force")]
        assert zero and least and np.min(least[0].get_ydata()) < -100.0  # kN
        shaded = [c for c in ax.collections if isinstance(c, PolyCollection)
                  and c.get_label() == "compression"]
        assert shaded and ax.get_ylim()[0] < np.min(least[0].get_ydata())
        close(figure)
    env = plot_periodic(per).get_axes()[-1]
    xs = np.concatenate([np.asarray(p.vertices)[:, 0] for c in env.collections for p in c.get_paths()])
    assert xs.min() == 0.0 and xs.max() == pytest.approx(902.2)


def test_solution_repr_is_short():
    """repr of a result is one line with the class, status, key scalars and array shapes,
    not every array (it printed 17 arrays of 50 numbers each)."""
    st = sc.solve_static(OC3)
    text = repr(st)
    assert "\n" not in text and len(text) < 600
    assert text.startswith("StaticSolution(status='converged'")
    assert "fairlead_tension=911428" in text and "positions=<51x2>" in text
    assert "grounded_length=134.5" in text


def test_results_per_part_for_a_one_line_scene():
    """Every result has .lines[name], .points and .bodies; a one-line scene's only line is
    the result itself (same fields), and it has no points or bodies."""
    st = sc.solve_static(OC3)
    assert list(st.lines) == ["line"] and st.lines["line"] is st
    assert st.lines["line"].fairlead_tension == st.fairlead_tension
    assert dict(st.points) == {} and dict(st.bodies) == {}
    assert "lines" not in st.to_dict()  # views, not exported fields
