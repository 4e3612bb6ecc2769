"""The report figures: what each plot promises is drawn, and what it draws is labelled.

The static figures come from real (small, fast) solves; the dynamic ones from result objects
filled with synthetic arrays, so that the slack and mode-count cases cost nothing to build.
"""
from __future__ import annotations

import re

import matplotlib

matplotlib.use("Agg")
import numpy as np  # noqa: E402
import pytest  # noqa: E402

import symcable as sc  # noqa: E402
from symcable.plotting import profiles as plotting
from symcable.plotting import view3d as plotting3d  # noqa: E402
from symcable.results.periodic import PeriodicSolution  # noqa: E402
from symcable.results.trajectory import Trajectory  # noqa: E402
from symcable.results.static import ModalSolution  # noqa: E402

from conftest import two_point  # noqa: E402

UNIT = re.compile(r"\((?:m|kN|kN m|s|-)\)")


def _titles(fig) -> list[str]:
    return [ax.get_title() for ax in fig.get_axes()]


def _legend_labels(ax) -> list[str]:
    leg = ax.get_legend()
    return [] if leg is None else [t.get_text() for t in leg.get_texts()]


def _assert_units(fig) -> None:
    """Every drawn axis names its unit in brackets, on both coordinates."""
    for ax in fig.get_axes():
        if not ax.axison:
            continue
        for label in (ax.get_xlabel(), ax.get_ylabel()):
            if label:  # an axis sharing x with the one below has its x label there
                assert UNIT.search(label), (ax.get_title(), label)


def two_sections(EI_upper: float) -> dict:
    """Chain on the seabed, then a wire (bending stiffness ``EI_upper``) up to 10 m depth."""
    return {
        "name": "chain and wire",
        "environment": {"water_density": 1025.0, "depth": 100.0},
        "seabed": {"stiffness": 1e5},
        "line_types": {"chain": {"EA": 5e8, "EI": 0.0, "mass": 80, "diameter": 0.09, "weight": 700.0},
                       "wire": {"EA": 2e8, "EI": EI_upper, "mass": 20, "diameter": 0.1, "weight": 150.0}},
        "sections": [{"type": "chain", "length": 60, "segments": 12},
                     {"type": "wire", "length": 100, "segments": 20}],
        "end_a": {"condition": "pinned", "position": [0.0, -100.0]},
        "end_b": {"condition": "pinned", "position": [120.0, -10.0]},
    }


# ---------------------------------------------------------------------------- statics
@pytest.mark.parametrize("EI", [0.0, 1e4])
def test_static_plot_draws_moment_only_with_bending(tmp_path, EI):
    """The bending moment is drawn, and a title names it, exactly when EI > 0 somewhere;
    the sections meet at a marked boundary with both line type names; the free surface
    (z = 0) and seabed (z = -depth) are drawn; the profile states its scale; units on
    every axis."""
    scene = sc.load_scene(two_sections(EI))
    fig = sc.solve_static(scene).plot(tmp_path / "s.png", scene=scene)
    try:
        titles = _titles(fig)
        assert any("moment" in t for t in titles) == (EI > 0), titles
        assert len(fig.get_axes()) == (3 if EI > 0 else 2)
        profile = fig.get_axes()[0]
        labels = _legend_labels(profile)
        assert "section boundary" in labels
        assert any("'chain'" in lb for lb in labels) and any("'wire'" in lb for lb in labels)
        assert "chain | wire" in [t.get_text() for t in profile.texts]
        assert "free surface, z = 0 m" in labels and "seabed, z = -100 m" in labels
        hlines = {round(ln.get_ydata()[0], 6) for ln in profile.get_lines()
                  if len(set(ln.get_ydata())) == 1 and len(ln.get_ydata()) == 2}
        assert {0.0, -100.0} <= hlines
        assert "true scale" in profile.get_title() or "vertical exaggeration" in profile.get_title()
        _assert_units(fig)
        assert (tmp_path / "s.png").stat().st_size > 0
    finally:
        plotting.close(fig)


def test_static_plot_states_exaggeration_when_not_to_scale():
    """A long shallow line is not drawn at true scale, and its title says by how much the
    vertical is stretched (the factor the axes really have)."""
    d = two_point((0.0, -50.0), (400.0, -48.0), length=401.0, segments=20, EA=1e9)
    d["environment"]["water_density"] = 0.0  # in air: no free surface to take into the frame
    scene = sc.load_scene(d)
    fig = sc.solve_static(scene).plot(scene=scene)
    try:
        profile = fig.get_axes()[0]
        m = re.search(r"vertical exaggeration x([\d.e+]+)", profile.get_title())
        assert m, profile.get_title()
        assert not any("free surface" in lb for lb in _legend_labels(profile))
        fig.canvas.draw()
        box = profile.get_window_extent()
        (x0, x1), (z0, z1) = profile.get_xlim(), profile.get_ylim()
        actual = (box.height / (z1 - z0)) / (box.width / (x1 - x0))
        assert float(m[1]) == pytest.approx(actual, rel=0.06)
        assert actual > plotting.EQUAL_ASPECT_FACTOR
    finally:
        plotting.close(fig)


def test_static_plot_without_scene_still_works():
    """Without the scene the figure draws the moment when the model had a bending term, and
    marks no sections."""
    sol = sc.solve_static(two_point((0.0, 0.0), (80.0, 10.0), EI=1e4))
    fig = sol.plot()
    try:
        assert any("moment" in t for t in _titles(fig))
        assert "section boundary" not in _legend_labels(fig.get_axes()[0])
    finally:
        plotting.close(fig)


# ---------------------------------------------------------------------------- dynamics
def _trajectory(slack: bool) -> Trajectory:
    t = np.linspace(0.0, 30.0, 301)
    s = np.linspace(5.0, 95.0, 10)
    wave = np.sin(2 * np.pi * t / 10.0)[:, None]
    tension = 5e4 + 4e4 * wave * (s / 100.0)[None, :]
    n = len(t)
    warns = (("slack: the total tension is <= 0 at t = 2.5 s, s = 95 m (segment 9; 3 of 301 "
              "samples slack, from t = 2.5 to 22.5 s): the dynamics linearised about the taut "
              "static state is invalid there",) if slack else ())
    return Trajectory(scene_name="synthetic line", time=t, s=s, states=np.zeros((n, 1)),
                      fairlead_tension=tension[:, -1], anchor_tension=tension[:, 0],
                      fairlead_force=np.zeros((n, 2)), anchor_force=np.zeros((n, 2)),
                      tension=tension, strain=np.zeros_like(tension), angle=np.zeros_like(tension),
                      method="generalized-alpha", dt=0.1, status="slack" if slack else "converged",
                      warnings=warns)


@pytest.mark.parametrize("slack", [False, True])
def test_trajectory_plot_title_legend_and_slack(slack):
    """The title names the scene, method and time step; the legends sit outside the data
    (right of the axes); a slack result gets a red SLACK note and the zero-tension line."""
    fig = _trajectory(slack).plot()
    try:
        ax_t, ax_e = fig.get_axes()
        assert "synthetic line" in ax_t.get_title()
        assert "generalized-alpha" in ax_t.get_title() and "dt = 0.1 s" in ax_t.get_title()
        fig.canvas.draw()
        for ax in (ax_t, ax_e):
            assert ax.get_legend().get_window_extent().x0 > ax.get_window_extent().x1
        assert ("SLACK" in ax_e.get_title()) == slack
        zero = [ln for ln in ax_e.get_lines() if ln.get_label() == "zero tension (slack)"]
        assert len(zero) == int(slack)
        if slack:
            assert "t = 2.5 s, s = 95 m" in ax_e.get_title()
            assert ax_e.get_ylim()[0] <= 0.0
        _assert_units(fig)
    finally:
        plotting.close(fig)


def _periodic(status: str) -> PeriodicSolution:
    n, T = 64, 10.0
    t = np.arange(n) / n * T
    ft = 6e5 + 2e5 * np.cos(2 * np.pi * t / T)
    warns = (("slack: the total tension is <= 0 at t = 3.8 s, s = 879.645 m (segment 49; 2 of 64 "
              "samples slack, from t = 3.8 to 4 s): the dynamics linearised about the taut static "
              "state is invalid there",) if status == "slack" else ())
    return PeriodicSolution(
        scene_name="synthetic periodic line", method="harmonic-balance", period=T, time=t,
        states=np.zeros((n, 1)), fairlead_tension=ft, fairlead_force=np.zeros((n, 2)),
        tension_min=np.linspace(5e5, 4e4, 50), tension_max=np.linspace(7e5, 9e5, 50),
        fairlead_tension_harmonics_amplitude=np.array([6e5, 2e5, 1e3, 10.0]),
        fairlead_tension_harmonics_phase=np.zeros(4), status=status, warnings=warns)


@pytest.mark.parametrize("status", ["converged", "slack"])
def test_periodic_plot_names_scene_method_period_and_slack(status):
    """The figure's title has the scene name, method, period and status; a slack result is
    marked in red with where it went slack, and the zero-tension line is drawn."""
    s_mid = np.linspace(9.0, 893.0, 50)
    fig = plotting.plot_periodic(_periodic(status), s_mid=s_mid)
    try:
        title = fig._suptitle.get_text()
        assert "synthetic periodic line" in title and "harmonic-balance" in title
        assert "T = 10 s" in title and f"status {status}" in title
        env = fig.get_axes()[-1]
        slack = status == "slack"
        assert ("SLACK" in env.get_title()) == slack
        assert (fig._suptitle.get_color() == plotting.SLACK_COLOR) == slack
        zero = [ln for ax in fig.get_axes() for ln in ax.get_lines()
                if ln.get_label() == "zero tension (slack)"]
        assert len(zero) == (2 if slack else 0)
        if slack:
            assert "s = 879.645 m" in env.get_title()
            assert "first slack point (axial force <= 0)" in _legend_labels(env)
        _assert_units(fig)
    finally:
        plotting.close(fig)


def _modal(n_modes: int) -> ModalSolution:
    s = np.linspace(0.0, 100.0, 21)
    pos = np.column_stack([s, -50.0 + 0.002 * (s - 50.0) ** 2])
    f = 0.1 * np.arange(1, n_modes + 1)
    shapes = np.stack([np.column_stack([0 * s, np.sin((k + 1) * np.pi * s / 100.0)])
                       for k in range(n_modes)])
    return ModalSolution(scene_name="synthetic modes", s=s, positions=pos, frequencies=f,
                         periods=1.0 / f, real_parts=np.zeros(n_modes), shapes=shapes)


@pytest.mark.parametrize("n", [None, 4])
def test_modes_plot_legend_has_every_mode_drawn(n):
    """Every mode asked for is drawn (all by default), and the legend has one entry per
    mode with its number, frequency (Hz) and period (s); the title says which are drawn."""
    modal = _modal(6)
    fig = plotting.plot_modes(modal, n=n)
    try:
        drawn = 6 if n is None else n
        labels = [t.get_text() for t in fig.legends[0].get_texts()]
        assert len(labels) == drawn
        for k, lb in enumerate(labels, start=1):
            f = 0.1 * k
            assert lb == f"mode {k}: {f:.4g} Hz, period {1 / f:.4g} s"
        assert len([ax for ax in fig.get_axes() if ax.axison]) == drawn
        title = fig._suptitle.get_text()
        assert "synthetic modes" in title
        assert ("all 6 modes" in title) if n is None else ("modes 1-4 of the 6" in title)
        _assert_units(fig)
    finally:
        plotting.close(fig)


# ---------------------------------------------------------------------------- mechanisms in space
A3, B3 = np.array([0.0, 0.0, -20.0]), np.array([30.0, 12.0, 0.0])


@pytest.fixture(scope="module")
def chain3d():
    """A 3D chain of 5 masses hanging between two prescribed points offset laterally (y),
    its equilibrium, and 2 s of motion with the upper end swaying in y."""
    mech = sc.toys.hanging_chain(5, A3, B3, mass=5.0, stiffness=2e4, length=45.0, drag=5.0,
                                 amplitude=[0.0, 3.0, 0.0], omega=2.0)
    eq = sc.solve_equilibrium(mech)
    tr = sc.integrate(mech, 2.0, 0.02, start=eq)
    return mech, eq, tr


def _drawn(ax, gid: str):
    """The (n, 2) or (n, 3) data of the line drawn with ``gid``."""
    (line,) = [ln for ln in ax.get_lines() if ln.get_gid() == gid]
    data = line.get_data_3d() if hasattr(line, "get_data_3d") else line.get_data()
    return np.column_stack([np.asarray(d, dtype=float) for d in data])


def test_3d_equilibrium_view_and_projections_draw_the_nodes(chain3d, tmp_path):
    """One figure, three axes (a 3D view, plan x-y, elevation x-z); every part's drawn
    coordinates are its nodes' (free nodes from q, prescribed ones at their joints'
    positions); the plan draws their x-y and the elevation their x-z; the prescribed ends
    are marked at A and B; legend, units and equal scales; the file is written."""
    mech, eq, _ = chain3d
    fig = eq.plot(tmp_path / "eq3d.png", mechanism=mech, seabed=-25.0, surface=True)
    try:
        ax3, plan, elev = fig.get_axes()
        assert ax3.name == "3d" and (plan.name, elev.name) == ("rectilinear", "rectilinear")
        assert plan.get_title() == "plan (x-y)" and elev.get_title() == "elevation (x-z)"
        pos = plotting3d.node_positions(eq, mech)
        assert set(pos) == {f"m{i}" for i in range(1, 6)} | {f"k{i}" for i in range(6)}
        q = eq.q
        for name, p in pos.items():
            part = mech.layout.parts[name]
            free = part.node_q[:, 0] >= 0
            np.testing.assert_array_equal(p[0][free], q[part.node_q[free]])
            np.testing.assert_array_equal(_drawn(ax3, f"{name}@0"), p[0])
            np.testing.assert_array_equal(_drawn(plan, f"{name}@0"), p[0][:, [0, 1]])
            np.testing.assert_array_equal(_drawn(elev, f"{name}@0"), p[0][:, [0, 2]])
        np.testing.assert_allclose(pos["k0"][0, 0], A3)
        np.testing.assert_allclose(pos["k5"][0, 1], B3)
        marked = np.vstack([c.get_offsets() for c in plan.collections])
        np.testing.assert_allclose(np.sort(marked, axis=0), np.sort([A3[:2], B3[:2]], axis=0))
        # the chain sags below the straight line between its ends
        assert pos["m3"][0, 0, 2] < 0.5 * (A3[2] + B3[2]) - 1.0
        labels = [t.get_text() for t in fig.legends[0].get_texts()]
        assert labels[:2] == ["m1-m5 (5 points)", "k0-k5 (6 elements)"]
        assert "prescribed node" in labels and "seabed, z = -25 m" in labels
        hlines = {ln.get_ydata()[0] for ln in elev.get_lines() if ln.get_gid() is None}
        assert {0.0, -25.0} <= hlines
        assert plan.get_aspect() == 1.0 and elev.get_aspect() == 1.0
        assert ax3.get_zlabel() == "z (m)"
        _assert_units(fig)
        assert "equilibrium" in fig._suptitle.get_text()
        assert (tmp_path / "eq3d.png").stat().st_size > 0
    finally:
        plotting.close(fig)


def test_3d_trajectory_snapshots_fade_and_envelope_draws_paths(chain3d):
    """Snapshots: ``snapshots`` states from first to last, the earlier fainter, each drawn
    where the trajectory has its nodes at that time (the moving end included); the envelope
    draws every distinct node's path over the run."""
    mech, _, tr = chain3d
    fig = tr.plot(mechanism=mech, snapshots=3)
    try:
        _, plan, elev = fig.get_axes()
        picks = [0, (tr.time.size - 1) // 2, tr.time.size - 1]
        pos = plotting3d.node_positions(tr, mech)
        alphas = []
        for i in picks:
            np.testing.assert_allclose(_drawn(elev, f"k5@{i}"), pos["k5"][i][:, [0, 2]])
            alphas.append([ln.get_alpha() for ln in plan.get_lines() if ln.get_gid() == f"k5@{i}"][0])
        assert alphas[0] < alphas[1] < alphas[2] == 1.0
        y_end = [_drawn(plan, f"k5@{i}")[1, 1] for i in picks]
        np.testing.assert_allclose(y_end, B3[1] + 3.0 * np.sin(2.0 * tr.time[picks]), atol=1e-12)
        assert "t = 2 s" in fig._suptitle.get_text()
    finally:
        plotting.close(fig)
    fig = tr.plot(mechanism=mech, envelope=True)
    try:
        _, plan, _ = fig.get_axes()
        paths = [ln for ln in plan.get_lines() if ln.get_gid() is None]
        assert len(paths) == 5 + 2          # each distinct node once: 5 masses, 2 ends
        longest = max(paths, key=lambda ln: np.ptp(ln.get_ydata()))
        assert len(longest.get_xdata()) == tr.time.size
        assert "node paths" in fig._suptitle.get_text()
    finally:
        plotting.close(fig)


def test_2d_mechanism_and_refusals():
    """A planar mechanism gets the elevation alone, from its q; the planar statics (whose
    unknowns are angles and strains) from its positions output; a result without its
    mechanism, or an envelope of one state, is refused with a message."""
    chain = sc.toys.spring_chain(4, gravity=9.81)
    eq = sc.solve_equilibrium(chain)
    fig = eq.plot(mechanism=chain)
    try:
        (elev,) = fig.get_axes()
        np.testing.assert_array_equal(_drawn(elev, "m2@0"), eq.q[chain.layout.parts["m2"].node_q])
        _assert_units(fig)
    finally:
        plotting.close(fig)
    from symcable.models.planar.static import static_mechanism
    scene = sc.load_scene(two_point((0.0, 0.0), (80.0, 10.0)))
    mech = static_mechanism(sc.build_model(scene))
    st = sc.solve_equilibrium(mech)
    fig = st.plot(mechanism=mech.layout)
    try:
        np.testing.assert_allclose(_drawn(fig.get_axes()[0], "line@0"), st.outputs["positions"])
    finally:
        plotting.close(fig)
    with pytest.raises(sc.SymcableError, match="mechanism = None"):
        eq.plot()
    with pytest.raises(sc.SymcableError, match="envelope"):
        eq.plot(mechanism=chain, envelope=True)
