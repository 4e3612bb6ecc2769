"""Slack and snap in time (issue 12: "a slack segment and a snap are handled and reported,
not a crash"): a light rope whose fairlead is jerked into MoorDyn's heave table (its velocity
jumps from 0 to 1.26 m/s at the first row) goes slack and snaps taut."""
from __future__ import annotations

import math

import numpy as np

import symcable as sc
from test_motion_table import REF, _scene


def _rope(damping: float) -> dict:
    d = _scene({"kind": "table", "file": REF})
    d["line_types"]["rope"]["damping"] = damping
    return d


def test_an_undamped_snap_runs_through():
    """Without material damping the snap's axial waves ring on; at dt = 0.1 s every step
    converges whole (measured: 0 substepped, 962 Newton iterations; before the predictors
    and the refactorising chord iterations of galpha1.py, 3 steps converged only as 2
    substeps, and earlier still the run stopped)."""
    tr = sc.simulate(_rope(0.0), 30.0, dt=0.1, codegen=True)
    st = tr.stats
    assert tr.status == "converged" and tr.time[0] == -10.0  # starts at the table's first row
    assert st["snaps"] >= 1 and 0 < st["slack_fraction"] < 1
    assert any("snapped" in w for w in tr.warnings)
    assert np.all(np.isfinite(tr.fairlead_tension))
    assert np.min(tr.axial_force) > -1e-3 * np.max(tr.axial_force)  # a rope: no compression


def test_the_snap_peak_converges_in_dt():
    """With MoorDyn's damping (BA/-zeta = -1) the peak fairlead tension of the snap at the
    start is 31.1 kN at dt = 0.05 s and 29.2 kN at 0.0025 s (measured): within 10 %, the
    size of a snap peak's time error at a step 20 times coarser."""
    peaks = {dt: sc.simulate(_rope(-1.0), 2.0, dt=dt, codegen=True).fairlead_tension.max()
             for dt in (0.05, 0.0025)}
    assert abs(peaks[0.05] / peaks[0.0025] - 1) < 0.10, peaks
    static = sc.solve_static(dict(_rope(-1.0), end_b={k: v for k, v in _rope(-1.0)["end_b"].items()
                                                       if k != "motion"}))
    assert peaks[0.0025] > 2 * static.fairlead_tension  # 2.6 times: a snap, not a gentle pull


def test_batches_with_a_failed_step_equal_single_steps(monkeypatch):
    """A batch of steps in which one fails skips its later steps, is replayed from its last
    good sample, and batching resumes after the substeps: the run is the one that calls the
    step one sample at a time (the same steps in the same order), with the same substeps
    and Newton iteration count, and where a sample is one step, no step taken twice. Not to
    the last bit: a batch forms the steps' times as t0 + (S h) j + h i, a single call as
    t0 + k h (ulps apart; measured 1e-12 of the peak tension after the snaps), so 1e-9 of
    the peak. The first-order step as it was before
    its predictors and refactorising chord iterations (the first predictor always, chord
    iterations regardless of their progress), under which 3 steps of this run fail whole
    and converge as 2 substeps (the current step takes them whole)."""
    from symcable.solvers import galpha1, march, newton
    from symcable.solvers.stepcache import STEP_CACHE
    monkeypatch.setattr(galpha1, "CHORD_CONTRACTION", math.inf)
    monkeypatch.setattr(newton, "PREDICTOR_TRUST", math.inf)
    STEP_CACHE.clear()  # the steps built by the other tests are the current ones
    batched = sc.simulate(_rope(0.0), 30.0, dt=0.1, codegen=True)
    monkeypatch.setattr(march, "_CALL_TARGET", 0.0)  # one sample per call
    calls, run = [], march._Stepper.run

    def spy(self, S, m, x, t0, h, p):
        calls.append((S, m, round(t0, 9), h))
        return run(self, S, m, x, t0, h, p)

    monkeypatch.setattr(march._Stepper, "run", spy)
    single = sc.simulate(_rope(0.0), 30.0, dt=0.1, codegen=True)
    # a failed step (samples of one step here) is taken once: its replay starts from the
    # batch's outputs (it would fail again, after as many Newton iterations); only its
    # substeps follow, at h / 2
    whole = [(t0, h) for S, m, t0, h in calls if h == 0.1]
    assert len(whole) == len(set(whole)) and all(S == 1 for S, _, _, h in calls if h == 0.1)
    assert any(h < 0.1 for *_, h in calls)
    assert batched.stats["substepped_steps"] > 0
    for key in ("substepped_steps", "max_substeps", "newton_iterations", "steps"):
        assert batched.stats[key] == single.stats[key], key
    peak = np.max(batched.fairlead_tension)
    assert np.max(np.abs(batched.fairlead_tension - single.fairlead_tension)) <= 1e-9 * peak
    STEP_CACHE.clear()  # no step of the old kind left for later tests
