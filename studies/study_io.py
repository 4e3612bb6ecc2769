"""What every study's ``main`` does after its run: the command line, and the outputs written
side by side (``results.csv`` one row per measurement, ``summary.md`` the tables printed, the
figure, and optionally a copy of the figure elsewhere, e.g. into the study's README folder).

Studies are scripts, not a package; each puts this folder on ``sys.path`` (after its own) to
import this one module, whose name shadows nothing installed."""
from __future__ import annotations

import argparse
import csv
from pathlib import Path
from typing import Callable


def parse(doc: str, quick_help: str, default_out: Path, argv=None,
          extra: Callable[[argparse.ArgumentParser], None] | None = None) -> argparse.Namespace:
    """The common command line: ``--quick``, ``--out DIR`` (created), ``--figure PATH``."""
    ap = argparse.ArgumentParser(description=doc.split("\n\n")[0])
    ap.add_argument("--quick", action="store_true", help=quick_help)
    ap.add_argument("--out", type=Path, default=default_out, help="output directory")
    ap.add_argument("--figure", type=Path, help="also write the figure to this path")
    if extra is not None:
        extra(ap)
    args = ap.parse_args(argv)
    args.out.mkdir(parents=True, exist_ok=True)
    return args


def write(args: argparse.Namespace, rows: list[dict], text: str,
          plot: Callable[[Path], None], figure_name: str) -> None:
    """Write results.csv, summary.md and the figure into ``args.out`` (and the figure to
    ``args.figure`` if given), then print the summary."""
    with open(args.out / "results.csv", "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=list(rows[0]))
        writer.writeheader()
        writer.writerows(rows)
    (args.out / "summary.md").write_text(text)
    plot(args.out / figure_name)
    if args.figure is not None:
        args.figure.parent.mkdir(parents=True, exist_ok=True)
        plot(args.figure)
    print(text)
