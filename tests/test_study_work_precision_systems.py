"""The body-and-tow rows of the work-precision study, --quick
(studies/work_precision/run_systems.py): it runs, writes its outputs, and shows what it is
for. No wall-clock assertions (speed is measured in
the studies)."""
from __future__ import annotations

import csv

import pytest

from conftest import load_study


@pytest.fixture(scope="module")
def work_precision(tmp_path_factory):
    out = tmp_path_factory.mktemp("wp_systems")
    return out, load_study("work_precision", "run_systems.py").main(["--quick", "--out", str(out)])


def _rows(res, case, method):
    return sorted((r for r in res["rows"] if r["case"] == case and r["method"] == method),
                  key=lambda r: r["resolution"])


def test_work_precision_writes_outputs(work_precision):
    out, res = work_precision
    for name in ("results.csv", "summary.md", "work_precision_systems.png"):
        assert (out / name).is_file() and (out / name).stat().st_size > 0, name
    with open(out / "results.csv", newline="") as fh:
        assert len(list(csv.DictReader(fh))) == len(res["rows"]) > 0


def test_module_time_runs_converge_with_the_step(work_precision):
    """simulate's generalized-alpha on the body: the error against the same period of a run
    at T/2048 falls at second order from T/50 to T/100 (at least 3 times; 4.0 measured) and
    keeps falling to T/200 (the quick mode's 4 periods from rest leave about 1e-3 of the
    range there; the full mode's 8 periods show second order down to T/800)."""
    _, res = work_precision
    rs = _rows(res, "module", "ga1")
    errs = [r["error_disc"] for r in rs]
    assert len(errs) == 3 and all(r["status"] == "converged" for r in rs)
    assert errs[0] / errs[1] > 3.0 and errs[1] > errs[2], errs


def test_module_periodic_solvers_agree_with_the_reference(work_precision):
    """Shooting and coarse collocation against collocation K=30, d=4: within 1 % of the
    tension range (shooting at T/50 is 0.5 % off, second order; collocation K=20 0.06 %)."""
    _, res = work_precision
    for meth in ("shooting", "collocation"):
        for r in _rows(res, "module", meth):
            assert r["status"] == "converged" and r["error"] < 1e-2, (meth, r["config"], r["error"])


def test_tow_error_falls_with_the_step_and_estimates_track_it(work_precision):
    """The tow at 2, 1 and 1/2 of the default step: the towpoint tension's error against
    1/8 of it falls with the step, and simulate's own estimate is within a factor of 3 of
    it wherever the error stands clear of the reference's own (first-order) error."""
    _, res = work_precision
    rs = _rows(res, "tow", "ga1")
    errs = [r["error"] for r in rs]
    assert errs[0] > errs[1] > errs[2], errs  # the step halves along rs
    floor = 3 * res["tow"]["ref_error"]
    for r in rs:
        if r["error"] > floor:
            assert 1 / 3 <= r["estimate"] / r["error"] <= 3, (r["config"], r["estimate"], r["error"])
