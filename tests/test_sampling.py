"""Samples of a long run are never in step with the motion: thinned to about 2,000 saved
samples, their spacing is a number of steps prime to the steps of a period, so the saved
samples visit every phase and the reported range is the response's range. (Every 50th
step of seed001's line at T/100 sampled two phases only: 693.8-845.6 kN for a response of
664.9-865.4 kN, reported as converged.)"""
from __future__ import annotations

import math

import numpy as np
import pytest

import symcable as sc
from symcable.solvers.schedule import save_indices, unaliased_every


def test_a_long_run_reports_the_range_of_every_phase():
    """seed001's line (10 segments), 1,000 periods at T/100: the saved samples of the last
    100 periods span the range of a run saving every step of its last 10 periods, to
    1e-9 relative (the same steps, the same numbers)."""
    d = sc.load_scene("seed001").to_dict()
    d["sections"][0]["segments"] = 10
    run = sc.simulate(d, 10_000.0, dt=0.1)
    late = run.fairlead_tension[run.time > 9000.0]
    dense = sc.simulate(d, 10_000.0, dt=0.1,
                        save_times=np.arange(9900.0, 10_000.0 + 1e-9, 0.1)).fairlead_tension
    assert late.max() == pytest.approx(dense.max(), rel=1e-9)
    assert late.min() == pytest.approx(dense.min(), rel=1e-9)


@pytest.mark.parametrize("every,dt,period,want", [
    (50, 0.1, 10.0, 51),     # T/100: 50 shares 50 with 100 -> 51
    (10, 0.1, 10.0, 11),
    (7, 0.1, 10.0, 7),       # already prime to 100
    (50, 0.1, 10.05, 50),    # not a whole number of steps per period: phases drift anyway
    (50, 0.1, None, 50),     # no motion
    (1, 0.1, 10.0, 1),       # every step saved
])
def test_unaliased_every(every, dt, period, want):
    assert unaliased_every(every, dt, period) == want
    if period and want != every:
        assert math.gcd(want, round(period / dt)) == 1


def test_save_indices_keep_about_the_asked_count():
    idx = save_indices(100_000, 0.1, 10_000.0, None, None, 2000, 10.0)
    assert idx[0] == 0 and idx[-1] == 100_000
    assert 1900 <= idx.size <= 2001 and set(np.diff(idx[:-1])) == {51}


def test_a_repeated_run_builds_no_new_batch(monkeypatch):
    """simulate's second call on the same scene reuses the batched steps its first call built
    (it used to build one batch of all its samples: 0.6 s of ``mapaccum`` on seed 001's line,
    a run of 0.13 s once built). Checked on what is built, not on wall time."""
    from symcable.solvers import march
    first = sc.simulate("seed001", 300.0)
    built, orig = [], march._Stepper.batch

    def batch(self, S, m):
        if (S, m) not in self._batches:
            built.append((S, m))
        return orig(self, S, m)
    monkeypatch.setattr(march._Stepper, "batch", batch)
    second = sc.simulate("seed001", 300.0)
    assert built == []
    # the same steps in other groupings: the same run to round-off
    np.testing.assert_allclose(second.fairlead_tension, first.fairlead_tension, rtol=1e-12)
