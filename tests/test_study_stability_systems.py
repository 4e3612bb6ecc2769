"""The body-and-tow rows of the stability study, --quick (studies/stability/run_systems.py):
every cell runs and is compared with its reference. No wall-clock assertions (speed is measured in
the studies)."""
from __future__ import annotations

import math

import pytest

from conftest import load_study


@pytest.fixture(scope="module")
def stability(tmp_path_factory):
    out = tmp_path_factory.mktemp("stability_systems")
    return out, load_study("stability", "run_systems.py").main(["--quick", "--out", str(out)])


def test_stability_rows_run_and_compare(stability):
    out, res = stability
    assert (out / "summary.md").is_file() and (out / "results.csv").is_file()
    for r in res["rows"]:
        assert r["refs"].get("ref") is not None, r["row"]
        for key, c in r["cells"].items():
            assert c["ok"], (r["row"], key, c.get("message"))
            assert math.isfinite(c["error"]) and c["error"] < 0.05, (r["row"], key, c["error"])
