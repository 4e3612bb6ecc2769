"""The sweep study's --quick mode (studies/sweep): the same 4 short cases in this process, on
1 and on 2 local Dask workers give the same table; the speed-up is reported, not asserted (no
wall-clock assertions)."""
from __future__ import annotations

import pytest

from conftest import load_study


def test_sweep_study_quick(tmp_path):
    pytest.importorskip("distributed")
    study = load_study("sweep")
    res = study.main(["--quick", "--out", str(tmp_path)])
    for name in ("results.csv", "summary.md", "CASES.toml", "line.toml"):
        assert (tmp_path / name).is_file() and (tmp_path / name).stat().st_size > 0, name
    runs = [r for r in res["rows"] if r["measure"] == "sweep"]
    assert sorted(r["workers"] for r in runs) == [0, 1, 2]
    assert all(r["cases"] == 4 and r["failed"] == 0 for r in runs)
    # the same cases, the same code, the same inputs: the same numbers in every run (measured
    # 0.0; the bound allows a case solved again in one process, whose static solve may start
    # from the cached solution and stop elsewhere within its tolerance, 1e-9 of the force scale)
    assert all(r["max_rel_difference"] <= 1e-9 for r in runs)
    assert res["speedup"] > 0 and "Speed-up from 1 to 2 workers" in res["summary"]
