"""3D static solutions save, load and plot like the planar ones: a scene of points and lines
(SystemStaticSolution) round-trips exactly through NPZ and JSON, and both it and a one-line
3D solution draw their figure, through the Python API and ``symcable static --plot --save``."""
from __future__ import annotations

from pathlib import Path

import numpy as np

import symcable as sc
from symcable.cli.main import main

DECK = Path(__file__).resolve().parents[2] / "shared" / "reference" / "moordyn-chains"


def _same(a, b):
    """Every line's arrays, every point's and body's fields, status and stats equal."""
    assert a.summary() == b.summary()
    for name in a.lines:
        for f in ("positions", "tension", "s"):
            assert np.array_equal(getattr(a.lines[name], f), getattr(b.lines[name], f)), f
    for name in a.points:
        assert np.array_equal(a.points[name].position, b.points[name].position)
        assert np.array_equal(a.points[name].force, b.points[name].force)
    assert a.status == b.status
    # a stat that is not a number ("not judged") reads back as NaN, in JSON too (tagged)
    nan = {k for k, v in a.stats.items() if isinstance(v, float) and v != v}
    assert {k: v for k, v in a.stats.items() if k not in nan} == \
        {k: v for k, v in b.stats.items() if k not in nan}
    assert all(isinstance(b.stats[k], float) and b.stats[k] != b.stats[k] for k in nan)


def test_system_solution_round_trips_and_plots(tmp_path):
    sol = sc.solve_static(str(sc.demo_scene_path("sphere")))
    assert isinstance(sol, sc.SystemStaticSolution)
    for suffix in (".npz", ".json"):
        path = sol.save(tmp_path / f"s{suffix}")
        _same(sol, sc.SystemStaticSolution.load(path))
    fig = sol.plot(tmp_path / "s.png", scene=str(sc.demo_scene_path("sphere")))
    assert (tmp_path / "s.png").stat().st_size > 20_000
    # the plan view spans the scene (18.9 m of line), not its round-off across y
    plan = fig.axes[1]
    assert plan.get_title() == "plan (x-y)" and np.ptp(plan.get_ylim()) > 10.0


def test_cli_static_plot_and_save_in_3d(tmp_path, capsys):
    """Every 3D scene's static solve plots and saves from the command line: a scene of
    points (sphere), one with a body (towed_body) and a one-line MoorDyn chain deck."""
    for scene in ("sphere", "towed_body", str(DECK / "WD0050_Chain.txt")):
        stem = Path(scene).stem
        plot, save = tmp_path / f"{stem}.png", tmp_path / f"{stem}.npz"
        assert main(["static", scene, "--plot", str(plot), "--save", str(save)]) == 0, \
            capsys.readouterr().err
        assert plot.stat().st_size > 20_000 and save.stat().st_size > 1000
    one = sc.StaticSolution.load(tmp_path / "WD0050_Chain.npz")
    assert one.positions.shape[1] == 3
