"""The coupling study's quick mode (studies/coupling/run.py --quick): a host moving a spar
steps symcable's three chains through ``sc.Coupling`` and through the C library, each equal
to ``simulate`` of the motion, and MoorDyn's own coupling run live on the same deck agrees
with symcable within MoorDyn's own change from N to 2N segments."""
from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

STUDY = Path(__file__).resolve().parents[1] / "studies" / "coupling"


def test_quick_mode():
    """8 and 16 segments, 2 periods. The couplings (the spar as one body; its three
    fairleads as points; the C library) equal simulate to 1e-8 of the force range (measured
    1.5e-12 to 1.6e-12: the same steps). symcable at 8 segments is within MoorDyn's own
    change from 8 to 16 segments of MoorDyn at 8 (measured 4.1 % against 5.9 % of the surge
    force's range). Deterministic runs: the same numbers on any machine."""
    subprocess.run([sys.executable, "run.py", "--quick"], cwd=STUDY, check=True,
                   capture_output=True, timeout=900)
    res = json.loads((STUDY / "out" / "results_quick.json").read_text())
    for key in ("coupling_body_vs_simulate", "coupling_points_vs_simulate", "c_vs_simulate"):
        assert res[key] < 1e-8, (key, res[key])
    assert res["c_restore_check"] == "restore_check = 0"
    assert res["surge_force_range_N"] > 0
    assert res["symcable_N_vs_moordyn_N"] <= res["moordyn_N_vs_2N"], res
