"""What every study's ``main`` does after its run: the command line, and the outputs written
side by side (``results.csv`` one row per measurement, ``summary.md`` the tables printed, the
figure, and optionally a copy of the figure elsewhere, e.g. into the study's README folder);
and helpers several studies share: importing a study module by its file path
(:func:`load_module`), the trigonometric interpolant of one period of samples
(:func:`trig_interp`) and a warm-cache median wall time (:func:`warm_median`).

Studies are scripts, not a package; each puts this folder on ``sys.path`` (after its own) to
import this one module, whose name shadows nothing installed."""
from __future__ import annotations

import argparse
import csv
import importlib.util
import statistics
import time
from pathlib import Path
from typing import Callable

import numpy as np


def load_module(path: Path, name: str):
    """The study module at ``path``, imported by its file path under the module name
    ``name`` (studies/ is not a package, and putting a study's folder on ``sys.path`` would
    let its modules, run.py and the like, shadow installed ones)."""
    spec = importlib.util.spec_from_file_location(name, path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def warm_median(call: Callable, repeats: int, cheap_s: float = 2.0) -> tuple:
    """(result, median wall s, n) of ``call()``; a call that compiled something new into
    symcable's build cache is not timed but made again (warm cache); repeated ``repeats``
    times while the first timed call took under ``cheap_s`` s."""
    from symcable.mechanism.codegen import cache_info
    runs = []
    while True:
        before = cache_info()["entries"]
        t0 = time.perf_counter()
        out = call()
        wall = time.perf_counter() - t0
        if cache_info()["entries"] != before:
            continue
        runs.append((wall, out))
        if len(runs) >= repeats or runs[0][0] >= cheap_s:
            break
    runs.sort(key=lambda r: r[0])
    return runs[(len(runs) - 1) // 2][1], statistics.median(w for w, _ in runs), len(runs)


def trig_interp(x: np.ndarray, m: int) -> np.ndarray:
    """Trigonometric interpolant of one period of uniform samples x (n,) at m uniform points."""
    n = x.size
    c = np.fft.rfft(x)
    cf = np.zeros(m // 2 + 1, dtype=complex)
    k = min(c.size, cf.size)
    cf[:k] = c[:k]
    if n % 2 == 0 and n // 2 < m // 2:
        cf[n // 2] *= 0.5  # the Nyquist term of n samples is split between +-n/2
    return np.fft.irfft(cf, m) * (m / n)


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


def write_tables(out: Path, rows: list[dict], text: str, stem: tuple = ("results", "summary")):
    """Write ``rows`` to ``out / <stem[0]>.csv`` (one row per measurement; the columns are
    every key of any row, in order of appearance, empty where a row lacks one) and ``text``
    to ``out / <stem[1]>.md``, then print the text."""
    cols: list = []
    for r in rows:
        cols += [k for k in r if k not in cols]
    with open(out / f"{stem[0]}.csv", "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=cols, restval="")
        writer.writeheader()
        writer.writerows(rows)
    (out / f"{stem[1]}.md").write_text(text)
    print(text)


def write(args: argparse.Namespace, rows: list[dict], text: str,
          plot: Callable[[Path], None], figure_name: str) -> None:
    """Write results.csv, summary.md and the figure into ``args.out`` (and the figure to
    ``args.figure`` if given), then print the summary."""
    plot(args.out / figure_name)
    if args.figure is not None:
        args.figure.parent.mkdir(parents=True, exist_ok=True)
        plot(args.figure)
    write_tables(args.out, rows, text)
