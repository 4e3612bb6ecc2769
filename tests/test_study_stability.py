"""The stability study's --quick mode (studies/stability/run.py): it runs, writes its outputs,
and shows what the study is for: RK4 above its stability limit fails with a ConvergenceError
while generalized-alpha at the same dt converges. No wall-clock assertions (speed is measured in studies)."""
from __future__ import annotations

import csv
import math

import pytest

from conftest import load_study


@pytest.fixture(scope="module")
def stability(tmp_path_factory):
    out = tmp_path_factory.mktemp("stability")
    res = load_study("stability").main(["--quick", "--out", str(out)])
    return out, res


def _case(res, name):
    return next(r for r in res["cases"] if r["case"] == name)


def test_stability_writes_outputs(stability):
    out, res = stability
    for name in ("results.csv", "summary.md"):
        assert (out / name).is_file() and (out / name).stat().st_size > 0, name
    with open(out / "results.csv", newline="") as fh:
        rows = list(csv.DictReader(fh))
    assert len(rows) == len(res["rows"]) > 0
    assert "FAILED: ConvergenceError" in (out / "summary.md").read_text()


def test_rk4_above_its_limit_fails_and_generalized_alpha_does_not(stability):
    """The dt case runs RK4 and generalized-alpha at 1.2 times RK4's stability limit: RK4
    must blow up and say so with a ConvergenceError (one line, naming the limit); the
    A-stable generalized-alpha must converge at the same dt."""
    _, res = stability
    r = _case(res, "dt = 1.2 x RK4 limit")
    rk4, ga = r["cells"]["rk4_given"], r["cells"]["ga"]
    assert not rk4["ok"] and rk4["exc_type"] == "ConvergenceError"
    assert rk4["reason"] == "blowup" and "stable here only for dt <" in rk4["message"]
    assert ga["ok"] and ga["status"] == "converged"
    assert ga["dt"] == pytest.approx(1.2 * r["dt_stable_s"], rel=1e-2)
    assert ga["dt"] > r["dt_stable_s"]


def test_every_converged_cell_has_a_finite_error(stability):
    """Every cell that converged was compared with its case's reference."""
    _, res = stability
    n_ok = 0
    for r in res["cases"]:
        assert r["reference"] is not None, r["case"]
        for key, c in r["cells"].items():
            if c["ok"]:
                n_ok += 1
                assert math.isfinite(c["error"]), (r["case"], key)
    assert n_ok >= 5


def test_stability_cable3d_quick(tmp_path):
    """The cable3d stability study's --quick mode (studies/stability/run3d.py): the base row
    and the row at 30 times MoorDyn's CFL step. At that step (36 ms, 7 times RK4's limit of
    5.2 ms) generalized-alpha runs in both forms, without substeps, within 1 % of the
    reference (measured 0.39 and 0.5 %), and RK4 blows up with a one-line ConvergenceError."""
    res = load_study("stability", "run3d.py").main(["--quick", "--out", str(tmp_path)])
    for name in ("results.csv", "summary.md"):
        assert (tmp_path / name).is_file() and (tmp_path / name).stat().st_size > 0, name
    row = next(r for r in res["rows"] if r["row"] == "dt = 30 x MoorDyn CFL")
    assert row["param"].startswith("dt = 0.03615 s")
    for key in ("ga1", "ga2"):
        c = row["cells"][key]
        assert c["ok"] and c["status"] == "converged" and not c["substeps"], key
        assert c["error"] < 0.01, (key, c["error"])
    rk4 = row["cells"]["rk4"]
    assert not rk4["ok"] and rk4["exc_type"] == "ConvergenceError" and rk4["reason"] == "blowup"
    base = next(r for r in res["rows"] if r["row"] == "base")
    assert all(c["ok"] and c["error"] < 0.02 for c in base["cells"].values()), base["cells"]
