"""``symcable sweep CASES.toml``: the sweep subcommand's options and what it prints.

Exit status 0 when every case has a result, 1 when some failed or were not run (the table
says which), 2 on an error of the sweep file (one line on stderr), 130 when interrupted
(the cases finished so far are saved: the same command resumes).
"""
from __future__ import annotations

import argparse
import json
import sys


def add_parser(sub) -> argparse.ArgumentParser:
    """Add ``sweep`` to the ``symcable`` command's subparsers ``sub``."""
    p = sub.add_parser("sweep", help="run a table of cases on Dask (local cluster or a "
                       "scheduler), saved case by case: an interrupted sweep resumes")
    p.add_argument("cases", help="the sweep file (TOML: scene, analysis, outputs, cases)")
    p.add_argument("--out", metavar="DIR", help="results folder (default: CASES-results beside "
                   "the file): one JSON per case, results.csv, results.json")
    p.add_argument("--workers", type=int, metavar="N", help="local worker processes (default: "
                   "one per core; at most 4 per core), listening on 127.0.0.1 only; 0: one by "
                   "one in this process, without Dask")
    p.add_argument("--scheduler", metavar="ADDRESS", help="a Dask scheduler's address "
                   "(tcp://host:8786) instead of a local cluster; it receives the cases "
                   "pickled and runs what it is sent: give only one you trust")
    p.add_argument("--limit", type=int, metavar="N", help="run at most N of the cases not yet "
                   "done, then stop (run again to resume)")
    p.add_argument("--retry-failed", action="store_true", help="run again the cases saved as "
                   "failed")
    p.add_argument("--json", action="store_true", help="print the table as JSON (SI units)")
    return p


def main(args) -> int:
    """Run the sweep ``args`` describes; print the summary (or JSON); the exit status."""
    from .run import run_sweep

    try:
        result = run_sweep(args.cases, out=args.out, workers=args.workers,
                           scheduler=args.scheduler, limit=args.limit,
                           retry_failed=args.retry_failed)
    except KeyboardInterrupt:
        print("symcable: sweep interrupted: the cases finished so far are saved; run the same "
              "command to resume", file=sys.stderr)
        return 130
    print(json.dumps(result.to_dict(), indent=1, default=str) if args.json else result.summary())
    return 0 if all(c.ok for c in result.cases) else 1
