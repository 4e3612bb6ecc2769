"""The chain study's tolerance runs (studies/chains/tolerance.py --quick): WD0050 under the
A1 heave through sc.simulate(scene, tol=...) with OrcaFlex's sample times, beside MoorDyn
when installed. It runs, writes its table, and its rows say what the tolerance did. No
wall-clock assertion."""
from __future__ import annotations

import json

import numpy as np
import pytest
from conftest import load_study

pytestmark = pytest.mark.skipif(
    not (load_study("chains").cases.REF_DIR / "WD0050_Chain.txt").is_file(),
    reason="reference decks not present")


def test_tolerance_quick(tmp_path):
    study = load_study("chains", "tolerance.py")
    res = study.main(["--quick", "--tols", "0.05", "--out", str(tmp_path)])
    assert (tmp_path / "tolerance.md").stat().st_size > 0
    rows = json.loads((tmp_path / "tolerance.json").read_text())["rows"]
    (row,) = rows
    assert row["tol"] == 0.05 and row["deck"] == res["rows"][0]["deck"] == "WD0050"
    # the runs halve from the default step (the table's 0.1 s rows), compared at the
    # OrcaFlex times only (no coarser partner); the max error is a percentage of a range
    steps = [r[0] for r in row["dt_runs"]]
    assert steps[0] == pytest.approx(0.1) and np.allclose(np.diff(np.log2(steps)), -1.0)
    assert 0.0 < row["fair_seg_max"] < 100.0
    assert (row["error_measured"] is None) == any("not reached" in w for w in row["warnings"])
