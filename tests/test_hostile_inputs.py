"""The hostile-input suite: every case of ``hostile.py`` (names, sizes, special files,
nesting, bad numbers, on every subcommand) through the ``symcable`` command line.

A refused input exits with status 2 and one line on stderr (``symcable: <Error>: ...``), no
traceback and no "internal error"; argparse's refusals print their usage and one error
line; valid odd input exits 0. No case may hang (``hostile_runner.TIMEOUT``). The refused
cases run in one process, whose peak resident memory must stay under 1 GB: every rejected
input is rejected before it allocates (a 10^7-segment scene allocated 5.6 GB, a 2000 x 2000
sweep grid 2.2 GB, a motion table on /dev/zero 2.7 GB before these limits; symcable itself,
CasADi and NumPy take about 0.2 GB).
"""
from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
import hostile  # noqa: E402

#: peak resident memory of the process running every refused case, bytes
MEMORY_BOUND = 1 << 30


@pytest.fixture(scope="module")
def corpus(tmp_path_factory):
    folder = tmp_path_factory.mktemp("hostile")
    return folder, hostile.build(folder)


def _run(folder: Path, cases: list) -> dict:
    todo, done = folder / "todo.json", folder / "done.json"
    todo.write_text(json.dumps(cases))
    env = dict(os.environ, SYMCABLE_CODEGEN="0", MPLBACKEND="Agg",
               SYMCABLE_CACHE_DIR=str(folder / "cache"))
    proc = subprocess.run([sys.executable, str(HERE / "hostile_runner.py"), str(todo),
                           str(done)], cwd=folder, env=env, capture_output=True, text=True,
                          timeout=3600)
    assert proc.returncode == 0, proc.stderr[-3000:]
    return json.loads(done.read_text())


def _problems(result: dict, expect: dict) -> list:
    bad = []
    for r in result["cases"]:
        want, err = expect[r["id"]], r["stderr"]
        lines = [ln for ln in err.splitlines() if ln.strip()]
        why = None
        if r["escaped"] is not None:
            why = f"escaped main: {r['escaped'][-600:]}"
        elif "Traceback" in err or "internal error" in err:
            why = f"traceback or internal error: {err[-600:]}"
        elif want == "refused" and (r["rc"] != 2 or len(lines) != 1
                                    or not lines[0].startswith("symcable: ")):
            why = f"exit {r['rc']}, stderr {err[-400:]!r}: want exit 2 and one line"
        elif want == "usage" and (r["rc"] != 2 or not lines or "error:" not in lines[-1]):
            why = f"exit {r['rc']}, stderr {err[-400:]!r}: want argparse's refusal"
        elif want == "ok" and r["rc"] != 0:
            why = f"exit {r['rc']}, stderr {err[-400:]!r}: want exit 0"
        if why:
            bad.append(f"{r['id']}: {why}")
    return bad


def test_refused_inputs_are_one_line_and_allocate_little(corpus):
    """Every refused case: exit 2, one line, no traceback, no hang; the process that ran
    them all peaked under MEMORY_BOUND."""
    folder, cases = corpus
    mine = [c for c in cases if c["expect"] in ("refused", "usage")]
    result = _run(folder, mine)
    assert len(result["cases"]) == len(mine) > 80
    bad = _problems(result, {c["id"]: c["expect"] for c in mine})
    assert not bad, "\n".join(bad)
    assert result["maxrss"] < MEMORY_BOUND, f"peak memory {result['maxrss'] / 1e6:.0f} MB"
    assert not (folder / "PWNED").exists()


def test_odd_but_valid_inputs_run(corpus):
    """Names the rule allows (``-``, ``__``, a leading or trailing ``_``, digits only,
    CasADi's keywords) run check, static and simulate; scene names with C comment markers,
    ``$`` and non-ASCII are plotted as written; no file the scene names is created."""
    folder, cases = corpus
    mine = [c for c in cases if c["expect"] == "ok"]
    result = _run(folder, mine)
    bad = _problems(result, {c["id"]: c["expect"] for c in mine})
    assert not bad, "\n".join(bad)
    plots = [c["argv"][-1] for c in mine if "--plot" in c["argv"]]
    assert plots and all((folder / p).stat().st_size > 10_000 for p in plots)
    assert not (folder / "PWNED").exists()
