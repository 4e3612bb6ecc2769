"""The time-error study's --quick mode: generalized-alpha's run error estimate tracks the true
error of the fairlead tension on the built-in scene within a factor of 3 (issue 11) on the
quick steps from T/100 to T/4, and the run at T/2 warns, saying how far off it is and which
dt would do. No wall-clock assertions."""
from __future__ import annotations

import re

from conftest import load_study


def test_time_error_quick(tmp_path):
    study = load_study("time_error")
    res = study.main(["--quick", "--out", str(tmp_path)])

    for name in ("results.csv", "summary.md", "time_error.png"):
        assert (tmp_path / name).is_file() and (tmp_path / name).stat().st_size > 0, name
    rows = {r["steps_per_period"]: r for r in res["rows"] if r["case"] == "seed001"}
    assert sorted(rows) == sorted(study.QUICK.steps)

    # the estimate within a factor of 3 of the true error, T/100 .. T/4
    for n in (100, 25, 4):
        r = rows[n]
        assert r["status"] == "converged"
        assert 1 / 3 <= r["ratio"] <= 3, (n, r["true_error"], r["estimate"])
    # under 1 % no warning; over it, a warning
    assert not rows[100]["warned"] and rows[100]["estimate"] < 0.01
    assert rows[25]["warned"] and rows[4]["warned"]

    # T/2 (50 % off): still a solution of the step equations, but it says so
    coarse = rows[2]
    assert coarse["true_error"] > 0.3 and coarse["estimate"] > 0.3
    assert coarse["warned"]
    msg = coarse["warning"]
    pct = float(re.search(r"about ([0-9.e+]+) %", msg).group(1))
    assert pct >= 30.0, msg
    # the dt it suggests is a whole number of steps per period that meets 1 % (T/25 is
    # already at 1.3 %, T/50 at 0.45 %)
    n_ok = int(re.search(r"= T/(\d+) should", msg).group(1))
    assert 25 < n_ok <= 60, msg


def test_tolerance_quick(tmp_path):
    """studies/time_error/tolerance.py --quick: simulate at its defaults on the built-in
    scene, two periods, against a run at a quarter of its step: within its tolerance, and
    its bound at least 0.8 of the true error (the reference's own error, a sixteenth of the
    answer's at order 2, aside)."""
    study = load_study("time_error", "tolerance.py")
    res = study.main(["--quick", "--out", str(tmp_path)])
    assert (tmp_path / "tolerance.md").stat().st_size > 0
    (row,) = res["rows"]
    assert row["scene"] == "seed001" and row["runs"] >= 2
    assert row["error_measured"] is not None and row["true_error"] <= 0.01
    assert row["error_measured"] >= 0.8 * row["true_error"]
