"""The error-estimate fuzz study's --quick mode (studies/fuzz/error_estimate.py: 20 planar and
10 3D scenes that MoorPy solves exactly, each solved with symcable's discretisation-error
estimate and compared with MoorPy): no crash, no hang, no silent wrong answer (an answer off
MoorPy by more than 1 % of its largest tension without a warning of its discretisation or
seabed error, unless "quiet": at most 2 % off with its estimate within a factor of 3), and
its outputs written. No wall-clock assertions (the cost is measured in the study)."""
from __future__ import annotations

import csv
import json

import pytest
from conftest import load_study


@pytest.fixture(scope="module")
def study(tmp_path_factory):
    out = tmp_path_factory.mktemp("errest")
    mod = load_study("fuzz", "error_estimate.py")
    return out, mod.main(["--quick", "--out", str(out)])


def test_outputs(study):
    out, res = study
    for name in ("results.csv", "results.json", "failures.json", "summary.md"):
        assert (out / name).is_file() and (out / name).stat().st_size > 0, name
    with open(out / "results.csv", newline="") as fh:
        rows = list(csv.DictReader(fh))
    assert len(rows) == 30
    assert {r["dim"] for r in rows} == {"2", "3"}
    # every failure carries its scene dict, to replay
    fails = json.loads((out / "failures.json").read_text())
    assert len(fails) == len(res["failures"])
    assert all("scene" in f and f["kind"] for f in fails)


def test_every_scene_classified(study):
    _, res = study
    by_dim = res["by_dim"]
    assert sum(by_dim[2]["counts"].values()) == 20
    assert sum(by_dim[3]["counts"].values()) == 10
    # MoorPy answers most scenes (it may fail on a few, or not apply: a vertical section at
    # a joint, a line ending above the water)
    for dim in (2, 3):
        c = by_dim[dim]["counts"]
        assert c["no reference"] <= 0.35 * sum(c.values()), (dim, c)


@pytest.mark.parametrize("dim", [2, 3])
def test_no_crash_hang_or_silent_wrong_answer(study, dim):
    _, res = study
    c = res["by_dim"][dim]["counts"]
    assert c["crash"] == 0 and c["hang"] == 0, (dim, c, res["failures"])
    assert c["silent wrong"] == 0, (dim, c, res["failures"])
