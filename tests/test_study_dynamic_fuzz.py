"""The dynamic fuzz study's --quick mode (studies/fuzz/dyn_fuzz.py, 4 small random dynamic
scenes): simulate and solve_periodic at their defaults against a run at dt / 8. It runs,
writes its outputs, classifies every scene, and finds no crash, no hang (a call past the
stated bound) and no silent wrong answer from either. No other wall-clock assertion."""
from __future__ import annotations

import csv
import json

import pytest
from conftest import load_study


@pytest.fixture(scope="module")
def dyn(tmp_path_factory):
    out = tmp_path_factory.mktemp("dyn_fuzz")
    res = load_study("fuzz", "dyn_fuzz.py").main(["--quick", "--out", str(out)])
    return out, res


def test_dynamic_fuzz_writes_outputs(dyn):
    out, res = dyn
    for name in ("results.csv", "results.json", "failures.json", "summary.md"):
        assert (out / name).is_file() and (out / name).stat().st_size > 0, name
    with open(out / "results.csv", newline="") as fh:
        rows = list(csv.DictReader(fh))
    assert len(rows) == res["n"] == 4
    # every scene replays from its saved scene dict
    saved = json.loads((out / "results.json").read_text())["records"]
    assert all("scene" in r and r["period"] > 0 for r in saved)
    fails = json.loads((out / "failures.json").read_text())
    assert len(fails) == res["failures"] and all("scene" in f for f in fails)


def test_dynamic_fuzz_no_silent_wrong_answers(dyn):
    _, res = dyn
    import dyn_classify as dc
    recs = res["records"]
    assert {r["sim_class"] for r in recs} <= set(dc.SIM_CLASSES)
    assert {r["per_class"] for r in recs} <= set(dc.PER_CLASSES)
    for key in ("sim_class", "per_class"):
        bad = [(r["id"], r[key]) for r in recs
               if r[key] in ("crash", "hang", "silent wrong")]
        assert not bad, bad
    # every time run was compared with its reference
    assert all(r.get("true_sim") is not None for r in recs if r["sim_class"] not in
               ("clean error",)), [r["id"] for r in recs if r.get("true_sim") is None]
