"""Did the one-path reshaping cost time? The same analyses timed in two checkouts of
symcable, interleaved: the checkout under test and a baseline (another commit's tree).

    python studies/performance/one_path.py --baseline /path/to/old/checkout [--repeats 7]

Each case runs once to warm up (the build of its symbolic model and functions, which is the
first call's cost and is reported apart), then ``--repeats`` times; the two checkouts
alternate in fresh processes, case by case, and the ratio new / old is taken from the
medians. The cases go through the public API with its defaults.
"""
from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parents[1]
CHAIN = ROOT.parent / "shared" / "reference" / "moordyn-chains" / "WD0050_Chain.txt"

#: case name -> Python statement run with ``sc`` (symcable) and ``scene`` (its input) bound
CASES = {
    "planar static (seed001)": ("seed001", "sc.solve_static(scene)"),
    "planar simulate 30 T (seed001)": ("seed001", "sc.simulate(scene, 300.0)"),
    "planar periodic shooting (seed001)": ("seed001", "sc.solve_periodic(scene)"),
    "planar modes (seed001)": ("seed001", "sc.modal_analysis(scene, 6)"),
    "cable3d static (WD0050 deck)": (str(CHAIN), "sc.solve_static(scene)"),
    "cable3d simulate 20 s (WD0050 deck)": (str(CHAIN), "sc.simulate(scene, 20.0, dt=0.1)"),
    "system static (sphere)": ("sphere", "sc.solve_static(scene)"),
    "system simulate 5 s (sphere)": ("sphere", "sc.simulate(scene, 5.0)"),
}

_CHILD = r"""
import json, sys, time, warnings
warnings.simplefilter("ignore")
import symcable as sc
name, stmt, repeats = sys.argv[1], sys.argv[2], int(sys.argv[3])
scene = name if name.endswith(".txt") else str(sc.demo_scene_path(name))
t = time.perf_counter(); eval(stmt); first = time.perf_counter() - t
times = []
for _ in range(repeats):
    t = time.perf_counter(); eval(stmt); times.append(time.perf_counter() - t)
print(json.dumps({"first": first, "times": times}))
"""


def run(tree: Path, name: str, stmt: str, repeats: int) -> dict:
    """One case in a fresh process importing symcable from ``tree``."""
    env = dict(os.environ, PYTHONPATH=str(tree), MPLBACKEND="Agg")
    out = subprocess.run([sys.executable, "-c", _CHILD, name, stmt, str(repeats)], env=env,
                         capture_output=True, text=True, check=True, cwd=tree)
    return json.loads(out.stdout.strip().splitlines()[-1])


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--baseline", required=True, type=Path, help="the other checkout")
    ap.add_argument("--repeats", type=int, default=7)
    ap.add_argument("--rounds", type=int, default=2, help="alternations per case")
    args = ap.parse_args(argv)
    rows = []
    for case, (name, stmt) in CASES.items():
        new, old = {"first": [], "times": []}, {"first": [], "times": []}
        for _ in range(args.rounds):
            for tree, acc in ((ROOT, new), (args.baseline, old)):
                r = run(tree, name, stmt, args.repeats)
                acc["first"].append(r["first"])
                acc["times"] += r["times"]
        m_new, m_old = statistics.median(new["times"]), statistics.median(old["times"])
        f_new, f_old = statistics.median(new["first"]), statistics.median(old["first"])
        rows.append((case, m_new, m_old, f_new, f_old))
        print(f"{case:38s} repeat {1e3 * m_new:9.1f} ms / {1e3 * m_old:9.1f} ms = "
              f"{m_new / m_old:5.2f}   first {f_new:6.2f} s / {f_old:6.2f} s = "
              f"{f_new / f_old:5.2f}", flush=True)
    (HERE / "one_path.json").write_text(json.dumps(
        [dict(zip(("case", "repeat_new_s", "repeat_old_s", "first_new_s", "first_old_s"), r))
         for r in rows], indent=1))
    return 0


if __name__ == "__main__":
    sys.exit(main())
