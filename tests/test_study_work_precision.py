"""The work-precision study's --quick mode: it runs, writes its outputs, every method converges
over its (quick) grid, the periodic solvers agree with the reference, and shooting's error is
second order in its step. No wall-clock assertions (speed is measured in studies,
never asserted in a test)."""
from __future__ import annotations


import numpy as np

from conftest import load_study


def test_work_precision_quick(tmp_path):
    study = load_study("work_precision")
    res = study.main(["--quick", "--out", str(tmp_path)])

    for name in ("results.csv", "summary.md", "work_precision.png"):
        assert (tmp_path / name).is_file() and (tmp_path / name).stat().st_size > 0, name
    rows = res["rows"]
    assert {r["method"] for r in rows} == set(study.METHODS)
    assert all(r["status"] == "converged" for r in rows), [(r["config"], r["status"]) for r in rows]

    # each line of the plot (a method at fixed settings) gets more accurate as its resolution
    # grows: periods simulated (RK4), steps per period (generalized-alpha), harmonics,
    # collocation intervals
    for family in {r["family"] for r in rows}:
        errs = [r["error"] for r in sorted((r for r in rows if r["family"] == family),
                                           key=lambda r: r["resolution"])]
        assert np.all(np.diff(errs) < 0), (family, errs)

    # the finest quick collocation and harmonic balance are within 1 % of the tension range
    # of the (coarse) reference, and so is the reference's check (the largest H)
    for method in ("collocation-newton", "collocation-ipopt", "harmonic-balance"):
        best = min(r["error"] for r in rows if r["method"] == method)
        assert best < 1e-2, (method, best)
    assert res["reference_check"]["error"] < 1e-2

    # shooting is the fixed point of generalized-alpha's period map, so its error is that
    # integrator's, second order in dt: the first-harmonic amplitude's error (the cleanest of
    # the three; the coarse reference's own is ~1e-6 of the range) falls 3 to 5 times per
    # doubling of the steps per period (measured: 4.1 and 4.0 from T/25 to T/100)
    shots = sorted((r for r in rows if r["method"] == "shooting"), key=lambda r: r["resolution"])
    assert [r["resolution"] for r in shots] == list(study.QUICK.shoot_steps)
    for a, b in zip(shots, shots[1:]):
        assert b["resolution"] == 2 * a["resolution"]
        ratio = abs(a["err_a1"]) / abs(b["err_a1"])
        assert 3.0 <= ratio <= 5.0, (a["config"], b["config"], ratio)
    # the summary names the fastest periodic method to 0.1 % (which one is not asserted: it
    # is a wall-clock result)
    assert res["periodic_winner"]["method"] in study.PERIODIC
