"""simulate(tol=...): the step chosen for the end tensions' error, verified by runs at two
steps (symcable.api.time_tolerance).

The refinement logic is checked on synthetic runs whose error is known exactly (a sampled
tension plus C h^p of an error shape), then through the public API against a much finer
run on the planar built-in line and a 3D line."""
from __future__ import annotations

import dataclasses
import math
import warnings

import numpy as np
import pytest

import symcable as sc
from symcable.api import time_tolerance as tt
from symcable.errors import ConvergenceError, SymcableError

T_END, PERIOD = 40.0, 10.0


@dataclasses.dataclass(frozen=True)
class FakeRun:
    time: np.ndarray
    fairlead_tension: np.ndarray
    anchor_tension: np.ndarray
    dt: float
    stats: dict
    warnings: tuple = ()


def exact(t):
    return 1e5 + 3e4 * np.sin(2 * math.pi * t / PERIOD)


def fake(order: float, C: float = 1.0, fail_above: float | None = None, floor: float = 0.0,
         h0: float = 0.1):
    """run(h): every step's samples, the exact tension plus C (h / h0)^order of its range
    times an error shape, plus ``floor`` of the range that no step removes (a wave whose
    phase turns by a quarter period at each halving: runs differ by as much at every
    step); ConvergenceError above ``fail_above`` s."""
    calls = []

    def run(h):
        h = h0 if h is None else h
        if fail_above is not None and h > fail_above:
            raise ConvergenceError(f"step {h} failed")
        calls.append(h)
        n = int(round(T_END / h))
        t = np.linspace(0.0, T_END, n + 1)
        shape = np.cos(2 * math.pi * t / PERIOD + 0.3)
        err = 6e4 * (C * (h / h0) ** order * shape
                     + floor * np.sin(2 * math.pi * t / 3.0 + 0.5 * math.pi * math.log2(0.2 / h)))
        f = exact(t) + err
        return FakeRun(t, f, 0.5 * f, h, {"error_estimate": 0.5},
                       ("generalized-alpha: the time step is too coarse: ...",))
    return run, calls


def true_error(traj) -> float:
    return float(np.max(np.abs(traj.fairlead_tension - exact(traj.time)))) / 6e4


@pytest.mark.parametrize("order,C", [(2.0, 0.3), (1.0, 0.3), (0.6, 0.05)])
def test_accepted_run_is_within_tol(order, C):
    """Orders 2 (smooth motion), 1 (a seabed landing) and 0.6: the accepted run's true
    error is at most tol, and its reported bound at least the true error (the bound is d
    for order >= 1, d / (2^p - 1) from three runs below 1)."""
    tol = 0.02
    run, calls = fake(order, C=C)
    out = tt.run_to_tolerance(run, tol)
    err = true_error(out)
    assert out.stats["error_measured"] is not None
    assert err <= tol
    # (within 5 %: the comparison reads the coarser run's samples, relative to the finer
    # run's own range, which includes its error; exact in the limit of fine sampling)
    assert out.stats["error_measured"] >= 0.95 * err
    # the run's own step warning is superseded by the verified comparison
    assert not any(tt.OWN_ESTIMATE_MARK in w for w in out.warnings)
    # every run is half the one before (the partner at twice the default first)
    assert calls[0] == 0.1 and calls[1] == 0.2
    chain = [calls[0]] + calls[2:]
    assert all(abs(b / a - 0.5) < 1e-12 for a, b in zip(chain, chain[1:]))
    assert out.stats["dt_runs"][0][0] == pytest.approx(0.2)


def test_loose_tol_takes_the_default_step():
    """A tolerance the default already meets costs the default run and its coarse partner."""
    run, calls = fake(2.0, C=0.001)
    out = tt.run_to_tolerance(run, 0.01)
    assert out.dt == 0.1 and calls == [0.1, 0.2]


def test_failed_partner_is_skipped():
    """A coarse partner that fails (a step too large for Newton) is skipped: the default
    run is compared with half its step instead."""
    run, calls = fake(2.0, C=0.001, fail_above=0.15)
    out = tt.run_to_tolerance(run, 0.01)
    assert out.dt == pytest.approx(0.05) and calls == [0.1, 0.05]
    assert out.stats["dt_runs"][0] == [0.1, None]


def test_no_convergence_is_warned_not_claimed():
    """Runs whose difference does not fall with the step (a noise the steps do not remove):
    nothing is claimed (error_measured None), a warning says so, and halving stops after
    STALLED comparisons without convergence instead of running all MAX_HALVINGS."""
    run, calls = fake(2.0, C=0.0, floor=0.05)
    out = tt.run_to_tolerance(run, 0.01)
    assert out.stats["error_measured"] is None
    assert "not reached" in out.warnings[0] and "does not fall" in out.warnings[0]
    assert len(calls) == 2 + tt.STALLED  # (the first comparison gives no order)
    # the runs' own (local) estimate is not repeated beside the comparison that measured more
    assert not any(tt.OWN_ESTIMATE_MARK in w for w in out.warnings)


def test_slow_convergence_not_reached_says_its_bound():
    """Runs that converge slowly (order 0.4) past MAX_HALVINGS: the warning gives the bound
    d / (2^p - 1) that exceeds tol, not the bare difference, which may be below it."""
    run, calls = fake(0.4, C=0.2)
    out = tt.run_to_tolerance(run, 0.003)
    assert out.stats["error_measured"] is None
    d = out.stats["dt_runs"][-1][1]
    assert "not reached" in out.warnings[0] and "bounds its error at" in out.warnings[0]
    bound = float(out.warnings[0].split("bounds its error at ")[1].split(" %")[0]) / 100
    assert bound > d and bound > 0.003


def test_without_partner_the_default_is_compared_with_half_it():
    """``partner=False`` (runs saved at given times, which a coarser run's steps would not
    contain): the default step's run is compared with half its step first."""
    run, calls = fake(2.0, C=0.001)
    out = tt.run_to_tolerance(run, 0.01, partner=False)
    assert calls == [0.1, 0.05] and out.dt == pytest.approx(0.05)
    assert out.stats["dt_runs"][0] == [0.1, None]


def test_bad_tolerances_refused():
    for bad in (0, 1.0, -0.1, "x", True, float("nan"), None if False else [0.1]):
        with pytest.raises(SymcableError, match="tol = "):
            tt.check_tol(bad)
    with pytest.raises(SymcableError, match="not both"):
        tt.step_tolerance(0.01, 0.1, None, "generalized-alpha")
    assert tt.step_tolerance(0.02, None, [1.0, 2.0], "generalized-alpha") == 0.02
    with pytest.raises(SymcableError, match="rk4"):
        tt.step_tolerance(0.01, None, None, "rk4")
    assert tt.step_tolerance(None, None, None, "generalized-alpha") == tt.DEFAULT_TOL
    assert tt.step_tolerance(None, 0.1, None, "generalized-alpha") is None
    assert tt.step_tolerance(None, None, [1.0], "generalized-alpha") is None
    assert tt.step_tolerance(None, None, None, "rk4") is None


def test_simulate_tol_refusals_through_api():
    scene = sc.load_scene(sc.demo_scene_path("seed001"))
    with pytest.raises(SymcableError, match="not both"):
        sc.simulate(scene, 20.0, dt=0.1, tol=0.01)
    with pytest.raises(SymcableError, match="tol = 2"):
        sc.simulate(scene, 20.0, tol=2)


def test_tol_at_save_times():
    """With save_times (a window after the start-up), every run is saved at the first run's
    samples and compared there: the result's samples are those times, its bound the
    difference at them."""
    scene = sc.load_scene(sc.demo_scene_path("seed001"))
    times = np.arange(10.0, 30.0 + 1e-9, 0.5)
    out = sc.simulate(scene, 30.0, tol=0.01, save_times=times, codegen=False)
    assert np.allclose(out.time, times, atol=1e-9)
    assert out.stats["dt_runs"][0][1] is None and len(out.stats["dt_runs"]) >= 2
    assert out.stats["error_measured"] is not None and out.stats["error_measured"] <= 0.01


def _max_error(run, ref) -> float:
    """The end tensions' largest difference to ``ref`` relative to their range."""
    return tt.tension_difference(run, ref)


def test_planar_line_tol_against_fine_run():
    """The seed-001 line (T = 10 s), 3 periods: the run chosen for tol = 0.3 % is within it
    of a run at 1/16 of the default step (whose own error is under 1e-4 of the range: order
    2 from the default's 0.5 %), and its bound is at least that true error."""
    scene = sc.load_scene(sc.demo_scene_path("seed001"))
    tol = 0.003
    out = sc.simulate(scene, 30.0, tol=tol, codegen=False)
    ref = sc.simulate(scene, 30.0, dt=0.1 / 16, codegen=False)
    err = _max_error(out, ref)
    assert out.stats["error_measured"] is not None and out.dt < 0.1
    assert err <= tol
    assert out.stats["error_measured"] >= 0.8 * err  # (the reference's own error aside)


def test_cable3d_default_is_a_verified_tolerance():
    """A 3D line with a moving fairlead at simulate's defaults: two runs (the default step
    and twice it), and the returned run within DEFAULT_TOL of a run at 1/8 of its step."""
    d = {"model": "cable3d", "environment": {"water_density": 1025.0},
         "line_types": {"rope": {"EA": 2e6, "mass": 5.0, "diameter": 0.04, "cd_normal": 1.2}},
         "sections": [{"type": "rope", "length": 60.0, "segments": 12}],
         "end_a": {"condition": "pinned", "position": [0.0, 0.0, -50.0]},
         "end_b": {"condition": "pinned", "position": [30.0, 0.0, 0.0],
                   "motion": {"kind": "harmonic", "period": 8.0, "amplitude": [1.0, 0.0, 0.5]}}}
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        out = sc.simulate(d, 24.0, codegen=False)
        ref = sc.simulate(d, 24.0, dt=out.dt / 8, codegen=False)
    assert out.stats["tol"] == tt.DEFAULT_TOL
    assert len(out.stats["dt_runs"]) >= 2
    assert out.stats["error_measured"] is not None
    assert _max_error(out, ref) <= tt.DEFAULT_TOL


def test_cli_tol(tmp_path, capsys):
    """`symcable simulate --tol`: the step chosen for it (the JSON stats say so); with --dt,
    or out of (0, 1), one line naming the option and exit status 2."""
    import json

    from symcable.cli.main import main
    from symcable.scene import load_scene, scene_to_toml
    p = tmp_path / "line.toml"
    p.write_text(scene_to_toml(load_scene(sc.demo_scene_path("seed001"))))
    assert main(["simulate", str(p), "--duration", "20", "--tol", "0.05", "--json"]) == 0
    stats = json.loads(capsys.readouterr().out)["stats"]
    assert stats["tol"] == 0.05 and stats["error_measured"] <= 0.05
    for bad in (["--tol", "0.01", "--dt", "0.1"], ["--tol", "1.5"]):
        assert main(["simulate", str(p), "--duration", "20", *bad]) == 2
        err = capsys.readouterr().err.strip()
        assert err.count("\n") == 0 and "--tol" in err, err


def test_thinned_samples_are_kept_by_every_run():
    """A run of more steps than the planar line keeps (2000: its samples thinned) is compared
    at its own samples: no coarser partner (whose steps would not hold them), the finer run
    saved at exactly those times, so no interpolated value is compared."""
    scene = sc.load_scene(sc.demo_scene_path("seed001"))
    out = sc.simulate(scene, 250.0, codegen=False)
    assert len(out.time) < 2500 and not tt.every_step(out)
    assert out.stats["dt_runs"][0] == [pytest.approx(0.1), None]
    assert out.stats["error_measured"] is not None and out.stats["error_measured"] <= 0.01
