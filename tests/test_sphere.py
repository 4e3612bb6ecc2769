"""Seed 003's payload sphere (symcable/data/sphere.toml, sphere127.toml): the scenes, their
statics against the closed form, and the slack and snap of their periodic responses on a
coarse line (5 segments: the studies/sphere convergence table shows the slack fraction and
the snap peak within a few per cent of T0 of the 20-segment scene's there).

The Floquet checks on toys with known multipliers are tests/test_floquet.py.
"""
from __future__ import annotations

import math

import numpy as np
import pytest

import symcable as sc
from symcable.cli.main import main
from symcable.data import names, resolve
from symcable.scene import load_scene

RHO, G = 1025.0, 9.80665
SLACK = 0.02  # T/T0 below which the top is slack (studies/sphere: the slack law's residue)


def _coarse(name, segments=5):
    d = load_scene(str(sc.demo_scene_path(name))).to_dict()
    d["lines"][0]["sections"][0]["segments"] = segments
    return load_scene(d)


def _t0_closed_form():
    """The submerged weight of the cable (18.9 m, 0.0112 kg/m, 1.6 mm) and the sphere
    (12.2 kg, 203.2 mm), N: a vertical line's top carries all of it."""
    cable = (0.0112 - RHO * math.pi * 0.0016 ** 2 / 4) * G * 18.9
    sphere = (12.2 - RHO * math.pi * 0.2032 ** 3 / 6) * G
    return cable + sphere


def test_builtin_scenes_by_name(capsys):
    assert {"sphere", "sphere127", "oc3", "seed001"} <= set(names())
    assert resolve("sphere").endswith("sphere.toml") and resolve("no-such-scene") == "no-such-scene"
    s, r = (load_scene(str(sc.demo_scene_path(n))) for n in ("sphere", "sphere127"))
    assert s.points["top"].motion.period == pytest.approx(1 / 0.807, rel=1e-6)
    assert r.points["top"].motion.period == pytest.approx(1 / 1.27, rel=1e-6)
    sphere = s.points["sphere"]
    assert sphere.mass == 12.2 and sphere.diameter == 0.2032 and sphere.ca == 0.18
    assert sphere.volume == pytest.approx(math.pi * 0.2032 ** 3 / 6, rel=1e-7)
    assert main(["check", "sphere"]) == 0
    assert "payload sphere on a cable" in capsys.readouterr().out
    with pytest.raises(sc.SymcableError, match="sphere127"):
        sc.demo_scene_path("nope")


def test_static_tension_is_submerged_weight():
    """The top tension of the hanging line equals the closed form to 1e-6: the static solve's
    tolerance is 1e-9 of the force scale, and the scene's sphere volume is pi d^3 / 6 to 7
    figures (3e-9 of T0)."""
    st = sc.solve_static(load_scene(str(sc.demo_scene_path("sphere"))))
    T0 = st.lines["cable"].fairlead_tension
    assert T0 == pytest.approx(_t0_closed_form(), rel=1e-6)
    assert 77.0 < T0 < 77.4
    # the sphere hangs straight below the top, 18.9 m plus the stretch T/EA below it
    z = st.points["sphere"].position[2] if hasattr(st.points["sphere"], "position") \
        else st.points["sphere"][2]
    assert -1.0 - z == pytest.approx(18.9 * (1 + T0 / 134.2e3), abs=2e-3)


@pytest.fixture(scope="module")
def coarse_periodic():
    out = {}
    for name in ("sphere", "sphere127"):
        s = _coarse(name)
        T0 = sc.solve_static(s).lines["cable"].fairlead_tension
        out[name] = (s, T0, sc.solve_periodic(s, "shooting", stability=True))
    return out


def test_slack_at_resonance_only(coarse_periodic):
    """At 0.807 Hz the cable stays taut (T/T0 0.6 .. 1.4); at 1.27 Hz it is slack over part of
    the period and snaps to about twice T0."""
    s, T0, per = coarse_periodic["sphere"]
    f = per.lines["cable"].fairlead_tension / T0
    assert np.mean(f <= SLACK) == 0.0 and f.min() > 0.4
    s, T0, per = coarse_periodic["sphere127"]
    f = per.lines["cable"].fairlead_tension / T0
    assert 0.02 < np.mean(f <= SLACK) < 0.5 and 1.6 < f.max() < 2.6
    for _, _, per in coarse_periodic.values():
        assert per.status == "converged"
        assert {"floquet_max", "stable", "floquet_multipliers"} <= set(per.stats)


def test_stability_taut_and_slack(coarse_periodic):
    """Taut at 0.807 Hz: stable. Slack at 1.27 Hz: the vertical response is unstable to a
    lateral perturbation (a slack cable buckles sideways; studies/sphere)."""
    assert coarse_periodic["sphere"][2].stats["stable"] is True
    assert coarse_periodic["sphere"][2].stats["floquet_max"] < 1.0
    assert coarse_periodic["sphere127"][2].stats["stable"] is False


def test_periodic_equals_time_run(coarse_periodic):
    """Shooting at 100 steps against the last of 15 periods of a time run at the same step
    (T/100, its own first-order scheme), within 2 % of the tension range: the issue's
    criterion. Both carry O(h^2) errors of about 1 % of the range at T/100 in the slack case
    (studies/sphere), of opposite schemes, so 2 % is what the criterion allows, not slack."""
    for name in ("sphere", "sphere127"):
        s, T0, per = coarse_periodic[name]
        P = s.points["top"].motion.period
        tr = sc.simulate(s, 15 * P, P / 100)
        t = tr.time
        sel = t >= t[-1] - P - 1e-9
        run = tr.lines["cable"].fairlead_tension[sel][:-1]
        pt = per.time
        ten = per.lines["cable"].fairlead_tension
        ref = np.interp(t[sel][:-1] - (t[-1] - P), np.r_[pt, P], np.r_[ten, ten[0]])
        rng = run.max() - run.min()
        assert np.max(np.abs(ref - run)) / rng < 0.02, name


def test_cli_periodic_prints_stability(tmp_path, capsys):
    """``symcable periodic`` on a cable3d scene ends with the stability line (the 5-segment
    line at 0.807 Hz: taut, stable)."""
    from symcable.scene import scene_to_toml
    path = tmp_path / "sphere5.toml"
    path.write_text(scene_to_toml(_coarse("sphere")))
    assert main(["periodic", str(path)]) == 0
    out = capsys.readouterr().out.splitlines()
    # the largest multiplier is the sphere's lateral pendulum, damped only by drag and the
    # integrator: 0.995 at rho_inf 0.5, 0.969 at cable3d's rho_inf 0 (measured)
    assert out[-1].startswith("stable: yes, largest Floquet multiplier |mu| = ")
    mu = float(out[-1].split("|mu| = ")[1].split()[0])
    assert 0.9 < mu < 1.0
    assert main(["periodic", str(path), "--no-stability"]) == 0
    assert "Floquet" not in capsys.readouterr().out


def test_cli_plots_the_tension_over_t0(tmp_path, capsys):
    """``symcable simulate --plot`` on a scene of points and lines (the sphere hangs from the
    point ``top``): every line's end tensions over their static T0, slack spans shaded. The
    figure's first curve starts at T/T0 = 1 (the run starts from the static solution) and
    reaches the slack zero and the snap above 1.5 T0 of the 1.27 Hz case."""
    from symcable.scene import scene_to_toml
    path = tmp_path / "sphere127_5.toml"
    path.write_text(scene_to_toml(_coarse("sphere127")))
    png = tmp_path / "t.png"
    assert main(["simulate", str(path), "--duration", "4", "--plot", str(png)]) == 0
    assert png.stat().st_size > 20_000
    capsys.readouterr()
    tr = sc.simulate(_coarse("sphere127"), 4.0)
    st = sc.solve_static(_coarse("sphere127"))
    t0 = {n: (st.lines[n].anchor_tension, st.lines[n].fairlead_tension) for n in tr.line_names}
    fig = tr.plot(kind="tensions", t0=t0)
    y = fig.axes[0].lines[0].get_ydata()
    assert y[0] == pytest.approx(1.0, abs=1e-6) and y.min() < 0.05 and y.max() > 1.5
    assert "T0 =" in fig.axes[0].get_legend().get_texts()[0].get_text()
    with pytest.raises(sc.SymcableError, match="kind = 'x'"):
        tr.plot(kind="x")
