"""The 3D mode plot (symcable.plotting.line3d.plot_modes_3d): each line of a scene drawn on
its own, every mode of the solution, plan, elevation and end view, the seabed."""
from __future__ import annotations

import symcable as sc
from test_bodies_moored import _moored


def test_mode_plots_draw_each_line_apart_and_every_mode(tmp_path):
    """A body moored by three chains: each chain drawn on its own (no segment from one
    line's fairlead to the next line's anchor: every drawn line has as many points as its own
    nodes), every mode of the solution drawn, in three views, the seabed dotted."""
    from symcable.plotting.line3d import plot_modes_3d
    scene = sc.load_scene(_moored(6))
    modal = sc.modal_analysis(scene, 5)
    fig = plot_modes_3d(modal, tmp_path / "m.png", seabed=-scene.environment.depth)
    assert len(fig.axes) == 3 * 5 and (tmp_path / "m.png").stat().st_size > 50_000
    sizes = {b - a for a, b in modal.stats["lines"].values()}
    for ax in fig.axes:
        drawn = [len(line.get_xdata()) for line in ax.get_lines()
                 if line.get_label() != "seabed"]
        assert drawn and set(drawn) <= sizes, drawn
    assert any(line.get_label() == "seabed" for line in fig.axes[1].get_lines())
