"""The design study's quick mode (studies/design/run.py --quick): a three-chain mooring in
200 m of water designed over four load cases with exact gradients converges to one optimum
from two starts, no feasible design around it is lighter, and its sensitivities equal
central differences of whole solves."""
from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

STUDY = Path(__file__).resolve().parents[1] / "studies" / "design"


def test_quick_mode():
    """8 segments a line. The two optima agree to 1e-6 of each variable's range and of the
    mass, SLSQP's tolerance (measured 3e-11 and 7e-11 here, 3.5e-7 of the mass on CI's
    machine, whose arithmetic takes another path to the same optimum); none of the 46
    designs around it (each variable moved by 0.5 and 2 % of its range, and 10 random
    within 1 %) is feasible and lighter; the sensitivities at the optimum equal Richardson-
    extrapolated central differences of tight solves within 1e-6 of their row's largest
    entry, or three times the differences' own error where that is larger. The grounded
    length from the line's vertical balance is within one segment of the nodes on the bed.
    """
    run = subprocess.run([sys.executable, str(STUDY / "run.py"), "--quick"],
                         capture_output=True, text=True, timeout=900)
    assert run.returncode == 0, run.stderr[-3000:]
    r = json.loads((STUDY / "out" / "results.json").read_text())
    assert r["spread_over_starts_of_range"] < 1e-6
    assert r["mass_spread"] < 1e-6  # SLSQP's tolerance on the objective's change
    n = r["neighbourhood"]
    assert n["feasible_lighter"] == 0 and n["feasible"] > 0
    # every entry within 1e-6 of its row's largest, or 3 times the differences' own error
    assert r["sensitivities"]["worst_excess_over_allowance"] <= 0.0
    segment = max(r["optimum_lengths"].values()) / r["segments"]
    for case in r["grounded_length"].values():  # vertical balance against the nodes on the
        for mine, nodes in case:                # bed: within one segment
            assert abs(mine - nodes) <= segment
