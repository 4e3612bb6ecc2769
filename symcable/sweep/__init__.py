"""Sweeps: a table of cases (one scene, one analysis, the scene's keys changed case by case)
run as independent solves on Dask, each result saved as it finishes so that an interrupted
sweep resumes where it stopped (``symcable sweep CASES.toml``, :func:`run_sweep`).

:mod:`.spec` reads the sweep file (its layout is documented there), :mod:`.case` runs one
case and lists the outputs, :mod:`.run` runs them all; the table is a
:class:`~symcable.results.sweep.SweepResult`. Dask (``pip install "symcable[sweep]"``) is
imported only when a sweep runs on it.
"""
from __future__ import annotations

from .case import OUTPUTS, available_outputs, run_case
from .run import run_sweep
from .spec import Case, Sweep, read_sweep

__all__ = ["OUTPUTS", "Case", "Sweep", "available_outputs", "read_sweep", "run_case", "run_sweep"]
