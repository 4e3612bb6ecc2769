"""Bodies in the 3D, plan and elevation views (symcable/plotting/bodies.py and
plot_mechanism): the moored spar of test_bodies_moored drawn as a box spanning its
attachment points, its axes and those points, at its pose; its Mechanism part is not drawn
as nodes."""
from __future__ import annotations

import matplotlib

matplotlib.use("Agg")

import numpy as np  # noqa: E402

import symcable as sc  # noqa: E402
from symcable.api.cable3d_static import static_equilibrium  # noqa: E402
from symcable.plotting.bodies import body_attachments, body_poses, plot_system  # noqa: E402
from symcable.scene import load_scene  # noqa: E402
from test_bodies_moored import R_FAIR, _moored  # noqa: E402


def _box_lines(fig):
    """The 2D views' line artists drawn in the body colour (box edges)."""
    return [ln for ax in fig.axes[1:3] for ln in ax.get_lines() if ln.get_color() == "0.25"]


def test_attachments_and_poses():
    scene = load_scene(_moored(5, yaw=30.0))
    att = body_attachments(scene)
    assert att["spar"].shape == (3, 3)
    np.testing.assert_allclose(np.linalg.norm(att["spar"][:, :2], axis=1), R_FAIR)
    st = sc.solve_static(scene, codegen=False)
    out = {"spar.position": st.bodies["spar"].position,
           "spar.orientation": st.bodies["spar"].orientation}
    X, R = body_poses(out)["spar"]
    np.testing.assert_allclose(X[0], st.bodies["spar"].position)
    np.testing.assert_allclose(R[0] @ R[0].T, np.eye(3), atol=1e-12)
    # the yaw of 30 degrees turns body x to (cos 30, sin 30, 0)
    np.testing.assert_allclose(R[0][:, 0], [np.cos(np.pi / 6), np.sin(np.pi / 6), 0.0],
                               atol=1e-8)


def test_plot_mechanism_draws_the_body_not_its_coordinates(tmp_path):
    scene = load_scene(_moored(5))
    mech, eq = static_equilibrium(scene)
    fig = eq.plot(tmp_path / "eq.png", mechanism=mech, bodies=body_attachments(scene))
    gids = {ln.get_gid() for ax in fig.axes for ln in ax.get_lines()}
    assert "spar@0" not in gids and "chain0@0" in gids
    assert len(_box_lines(fig)) == 24  # 12 edges in each of the two views
    labels = [t.get_text() for t in fig.legends[0].get_texts()]
    assert "attachment point" in labels and not any(lab.startswith("spar") for lab in labels)
    # the attachment points where the chains end
    pts = np.vstack([c.get_offsets() for c in fig.axes[1].collections
                     if c.get_offsets().shape[0] == 3])
    ends = np.array([st[-1, :2] for st in (np.asarray(eq.outputs[f"chain{k}.positions"])
                                           for k in range(3))])
    assert np.allclose(np.sort(pts, axis=0), np.sort(ends, axis=0), atol=1e-6)


def test_plot_system_static_and_trajectory(tmp_path):
    d = _moored(5)
    st = sc.solve_static(d, codegen=False)
    fig = plot_system(st, tmp_path / "st.png", scene=d, seabed=-80.0)
    assert (tmp_path / "st.png").stat().st_size > 0 and len(_box_lines(fig)) == 24
    tr = sc.simulate(d, 1.0, 0.1)
    fig = plot_system(tr, tmp_path / "tr.png", scene=d, snapshots=3)
    assert len(_box_lines(fig)) == 3 * 24
    assert any("earlier: t =" in t.get_text() for t in fig.legends[0].get_texts())
