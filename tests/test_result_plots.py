"""Every analysis's result draws its own figure through ``result.plot(path)``: the modes of a
planar line and of a 3D scene, a planar periodic solution, a linearisation (also through
``symcable linearize --plot``)."""
from __future__ import annotations

import symcable as sc
from symcable.cli.main import main
from test_cli_results import tmp_scene


def _small(name: str, segments: int) -> dict:
    d = sc.load_scene(name).to_dict()
    (d["sections"] if "sections" in d else d["lines"][0]["sections"])[0]["segments"] = segments
    return d


def test_results_plot_themselves(tmp_path):
    planar = _small("seed001", 10)
    figures = {"modes2d": sc.modal_analysis(planar, 3).plot(tmp_path / "modes2d.png"),
               "modes3d": sc.modal_analysis("sphere", 3).plot(tmp_path / "modes3d.png",
                                                              seabed=-30.0),
               "periodic": sc.solve_periodic(planar, steps=40).plot(tmp_path / "periodic.png"),
               "linearize": sc.linearize(planar).plot(tmp_path / "linearize.png")}
    for name, fig in figures.items():
        assert fig.axes, name
        assert (tmp_path / f"{name}.png").stat().st_size > 20_000, name  # drawn, not blank
    assert len(figures["modes3d"].axes) == 9  # 3 modes x plan, elevation, end view


def test_cli_linearize_plots(tmp_path, capsys):
    path = tmp_scene(_small("seed001", 6))
    assert main(["linearize", path, "--plot", str(tmp_path / "lin.png")]) == 0
    assert "plot              " in capsys.readouterr().out
    assert (tmp_path / "lin.png").stat().st_size > 20_000
