"""Running a sweep: each case an independent task on Dask (``dask.distributed``), each
result saved as it arrives, so that an interrupted sweep resumes where it stopped.

* Where: a local cluster of ``workers`` processes with one thread each (default: one per
  core, at most one per case; at most :func:`max_workers`, four per core), or any Dask
  scheduler by ``scheduler`` address; ``workers=0`` runs the cases one by one in this
  process, without Dask. The local cluster listens on 127.0.0.1 only (its scheduler,
  dashboard and workers).
* Trust: Dask sends tasks and results pickled, and unpickling runs code. A scheduler given
  by address (and its workers) receives every case pickled and returns records the client
  unpickles: use only schedulers and workers you trust.
* Compiled functions: the cases of a sweep usually share one model structure (their
  differences are parameters, inputs of the compiled functions: end and point positions,
  the current). The first case to run is run here, in the client (while the cluster starts
  and its workers import symcable): it compiles what generated C its analysis uses into
  symcable's build cache (:func:`symcable.mechanism.codegen.cache_dir`, keyed by the graph), and its
  result is kept like any other. The other cases run within
  :func:`symcable.mechanism.codegen.cached_only`: local workers share the cache folder and load the
  library from it; a case whose compiled functions differ runs in the virtual machine
  rather than compile on a worker. What changes the graph: another ``dt``, number of
  segments or line type, a cable3d motion's period or amplitude, and on a cable3d line
  pulled taut its reach (its force scale, a constant of the graph, grows with it). Compiling
  takes seconds to tens of seconds per structure, against tenths of a second of virtual
  machine for a short case. ``codegen = true`` in the sweep file compiles every structure
  where it first runs (long cases of many structures), ``false`` compiles nothing. Remote
  workers with their own disk find an empty cache: give them ``codegen = true``. Each case
  records what it loaded (``CaseResult.builds``) and the summary says how many ran in the
  virtual machine.
* Each case builds its scene's Mechanism and Functions (symcable keeps them per scene
  content): a few tenths of a second of a short case, whatever its analysis.
* Files: ``<out>/<case name>-<hash>.json``, one per case, written (atomically) by the client
  as each case finishes; then ``<out>/results.csv`` and ``results.json``, the table. A case
  whose file exists with the same hash is not run again (a failed one neither, unless
  ``retry_failed``). A saved file is used only when it is a regular file within the
  ``file_bytes`` limit holding a JSON object of the case's fields, each of the right type
  and value (:meth:`~symcable.results.sweep.CaseResult.from_dict`, every output of the
  sweep a finite number); any other (edited, truncated, corrupt) runs the case again.
* A case that fails (ConvergenceError, SceneError, any error in its analysis) is recorded
  as failed with its one-line message and no values; the sweep goes on. A worker lost while
  running a case marks it failed without saving it, so a resume runs it again.
"""
from __future__ import annotations

import contextlib
import json
import logging
import os
import tempfile
import time
from contextlib import contextmanager
from pathlib import Path
from typing import Any

from ..errors import SymcableError
from ..limits import check_nesting, current, read_bounded
from ..progress import ProgressBar
from ..results.sweep import FAILED, NOT_RUN, CaseResult, SweepResult
from .case import run_case
from .spec import Sweep, read_sweep

__all__ = ["run_sweep", "max_workers"]

#: file name of the saved table in the results folder (.csv and .json)
TABLE = "results"
#: local worker processes allowed per core (:func:`max_workers`)
WORKERS_PER_CORE = 4
#: the interface the local cluster listens on: this machine only
LOCALHOST = "127.0.0.1"


def max_workers() -> int:
    """The most local worker processes a sweep starts: WORKERS_PER_CORE per core of this
    machine (:func:`os.cpu_count`). More workers than cores only wait on each other; a
    cluster of more machines is a Dask scheduler's (``scheduler``)."""
    return WORKERS_PER_CORE * (os.cpu_count() or 1)


def _distributed():
    """``dask.distributed``, imported now (an optional dependency)."""
    try:
        import distributed
    except ImportError:
        raise SymcableError('a sweep on Dask needs dask.distributed: pip install '
                            '"symcable[sweep]" (or run the cases in this process: workers=0, '
                            'symcable sweep --workers 0)') from None
    return distributed


def _write(path: Path, record: dict) -> None:
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=".tmp-", suffix=".json")
    try:
        with os.fdopen(fd, "w") as fh:
            json.dump(record, fh, indent=1)
        os.replace(tmp, path)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise


def _saved(folder: Path | None, case, retry_failed: bool, outputs: tuple) -> CaseResult | None:
    """The case's result from an earlier run, when its file is there and valid: a regular
    file within the ``file_bytes`` limit, a JSON object of the case's fields of the right
    types and values (:meth:`CaseResult.from_dict`), of the same name and content (hash),
    with every one of ``outputs`` unless it failed, and not a failure to retry. None
    otherwise (the case runs again), never an error."""
    if folder is None:
        return None
    path = folder / f"{case.stem}.json"
    try:
        rec = json.loads(read_bounded(path, "file_bytes", "a saved sweep case").decode("utf-8"))
        check_nesting(rec, f"the saved sweep case {str(path)!r}")
        if not isinstance(rec, dict) or rec.get("hash") != case.hash or \
                rec.get("name") != case.name:
            return None
        result = CaseResult.from_dict(rec, overrides=dict(case.overrides), skipped=True)
    except (OSError, ValueError, RecursionError, SymcableError):
        # missing, unreadable, not a regular file or too large (LimitError), not UTF-8 or
        # JSON, nested too deeply (json recurses: RecursionError; LimitError), a wrong field
        return None
    if result.status == NOT_RUN or (retry_failed and result.status == FAILED):
        return None
    if result.status != FAILED and any(k not in result.values for k in outputs):
        return None
    return result


def _task(sweep: Sweep, case, first: bool = False) -> dict:
    """What :func:`~.case.run_case` takes. Without ``codegen`` in the sweep file, only the
    first case may compile; the others load generated C from the build cache or run in the
    virtual machine (see the module's docstring)."""
    return {"name": case.name, "hash": case.hash, "scene": case.scene,
            "analysis": sweep.analysis, "options": dict(case.options),
            "codegen": sweep.codegen, "cached_only": sweep.codegen is None and not first,
            "limits": current()}


class _Recorder:
    """Saves each record as it arrives and counts it on the progress bar."""

    def __init__(self, sweep: Sweep, folder: Path | None, bar: ProgressBar):
        self.sweep, self.folder, self.bar = sweep, folder, bar
        self.by_name = {c.name: c for c in sweep.cases}
        self.results: dict = {}

    def __call__(self, record: dict, save: bool = True) -> None:
        case = self.by_name[record["name"]]
        record = dict(record, overrides=dict(case.overrides), analysis=self.sweep.analysis)
        if save and self.folder is not None:
            _write(self.folder / f"{case.stem}.json", record)
        self.results[case.name] = CaseResult.from_dict(record)
        self.bar.update(len(self.results))


def _preload() -> None:
    """Nothing: a worker that unpickles this function imports symcable to find it (1-3 s),
    while the client runs the first case."""


@contextmanager
def _dask(workers: int | None, scheduler: Any, n_tasks: int):
    """``(distributed, client, n_workers, label)``: a client of the scheduler at ``scheduler``
    (or the Client given), or of a local cluster of ``workers`` processes started here,
    closed on leaving; its workers import symcable in the background from the start."""
    distributed = _distributed()
    cluster = None
    if scheduler is not None:
        if workers is not None:
            raise SymcableError(f"workers = {workers!r} with scheduler = {scheduler!r}: the "
                                "scheduler's cluster has its own workers; give one or the other")
        own = not isinstance(scheduler, distributed.Client)
        client = distributed.Client(scheduler) if own else scheduler
        n = len(client.scheduler_info().get("workers", {}))
        label = str(getattr(client.scheduler, "address", scheduler))
    else:
        n = workers if workers is not None else max(1, min(os.cpu_count() or 1, n_tasks))
        # this machine only: the scheduler, its dashboard, the nannies and the workers
        cluster = distributed.LocalCluster(n_workers=n, threads_per_worker=1, processes=True,
                                           host=LOCALHOST, dashboard_address=f"{LOCALHOST}:0",
                                           silence_logs=logging.CRITICAL)
        client, own, label = distributed.Client(cluster), True, "local"
    try:
        # not waited for, but held: a future let go is a task cancelled
        preload = [client.submit(_preload, workers=[address], pure=False)
                   for address in client.scheduler_info().get("workers", {})]
        yield distributed, client, n, label
        del preload
    finally:
        if own:
            client.close()
        if cluster is not None:
            cluster.close()


def _submit(distributed, client, sweep, todo, record) -> None:
    """Run ``todo`` (cases) on the client's workers, recording each as it finishes."""
    futures = {}
    try:
        for case in todo:
            fut = client.submit(run_case, _task(sweep, case), key=f"symcable-{case.stem}",
                                pure=False)
            futures[fut] = case
        for fut in distributed.as_completed(list(futures)):
            case = futures[fut]
            try:
                rec = fut.result()
            except Exception as exc:  # the worker died or the task was lost: not saved
                rec = {"name": case.name, "hash": case.hash, "status": FAILED, "values": {},
                       "message": f"{type(exc).__name__}: {' '.join(str(exc).split())} (the "
                                  "worker was lost running it; not saved: a resume runs it "
                                  "again)"}
                record(rec, save=False)
                continue
            record(rec)
    finally:
        for fut in futures:
            fut.cancel()


def run_sweep(cases, out=None, *, workers: int | None = None, scheduler: Any = None,
              progress: bool | None = None, limit: int | None = None,
              retry_failed: bool = False) -> SweepResult:
    """Run a sweep's cases as independent tasks on Dask; see :mod:`symcable.sweep`.

    Parameters
    ----------
    cases : path, dict or Sweep
        The sweep file (``CASES.toml``), a dict in its layout, or :func:`read_sweep`'s Sweep.
    out : path, optional
        The results folder (created): one ``<case>-<hash>.json`` per case and the table
        ``results.csv``/``results.json``. Default: ``<CASES>-results`` beside a sweep file; no
        files for a dict (nothing to resume from).
    workers : int, optional
        Local worker processes, one thread each (default: one per core, at most one per case
        to run; at most :func:`max_workers`); 0 runs the cases one by one in this process,
        without Dask. The local cluster listens on 127.0.0.1 only.
        A script that starts local workers must do so under ``if __name__ ==
        "__main__":`` (the workers are new processes that import the script).
    scheduler : str or distributed.Client, optional
        A Dask scheduler's address (``"tcp://host:8786"``) or a Client, instead of a local
        cluster; not with ``workers``. It receives the cases pickled and the client unpickles
        what it returns: give only a scheduler (and workers) you trust.
    progress : bool, optional
        The progress bar (tqdm, on stderr): True, False, or None on a terminal only.
    limit : int, optional
        Run at most this many of the cases not yet done, then stop (the rest are "not run";
        running again resumes).
    retry_failed : bool
        Run again the cases saved as failed.

    Returns
    -------
    SweepResult
        Every case of the sweep, in its order.

    Raises
    ------
    SceneError
        The sweep file is invalid (one line naming the key, the value and what is allowed).
    SymcableError
        Dask is not installed (``pip install "symcable[sweep]"``), or bad arguments (one
        line: the argument, its value and what is allowed).
    LimitError
        The sweep is over a limit of :mod:`symcable.limits` (cases, file size, nesting).
    """
    started = time.perf_counter()
    for key, v in (("workers", workers), ("limit", limit)):
        if v is not None and (isinstance(v, bool) or not isinstance(v, int) or v < 0):
            raise SymcableError(f"{key} = {v!r}: must be an integer >= 0")
    top = max_workers()
    if workers is not None and workers > top:
        raise SymcableError(f"workers = {workers:,}: more than {WORKERS_PER_CORE} per core of "
                            f"this machine ({os.cpu_count() or 1} cores): at most {top} local "
                            "worker processes (for more, start a Dask cluster and give its "
                            "scheduler's address)")
    sweep = read_sweep(cases)
    folder = Path(out) if out is not None else sweep.out
    if folder is not None:
        folder.mkdir(parents=True, exist_ok=True)
    done = {c.name: r for c in sweep.cases
            if (r := _saved(folder, c, retry_failed, sweep.outputs)) is not None}
    pending = [c for c in sweep.cases if c.name not in done]
    todo = pending if limit is None else pending[:limit]
    n_workers, label = 0, "in-process"
    with ProgressBar(len(todo), progress, label=sweep.name, unit="case") as bar:
        record = _Recorder(sweep, folder, bar)
        runnable = []
        for case in todo:  # a case whose scene is invalid fails here, without a task
            if case.scene is None:
                record({"name": case.name, "hash": case.hash, "status": FAILED, "values": {},
                        "message": case.error, "wall_time": 0.0, "worker": "", "builds": {}})
            else:
                runnable.append(case)
        # the first case here: it compiles into the build cache the workers read, while
        # the cluster's workers import symcable
        with (_dask(workers, scheduler, len(runnable) - 1) if workers != 0 and
              len(runnable) > 1 else contextlib.nullcontext()) as dask:
            if runnable:
                record(run_case(_task(sweep, runnable[0], first=True)))
            if dask is not None:
                distributed, client, n_workers, label = dask
                _submit(distributed, client, sweep, runnable[1:], record)
            else:
                for case in runnable[1:]:
                    record(run_case(_task(sweep, case)))
    results = {**done, **record.results}
    rows = tuple(results.get(c.name) or CaseResult(c.name, c.hash, dict(c.overrides), NOT_RUN)
                 for c in sweep.cases)
    first = runnable[0].name if runnable else None
    stats = {"wall_time": time.perf_counter() - started, "ran": len(record.results),
             "skipped": len(done), "failed": sum(r.status == FAILED for r in rows),
             "not_run": sum(r.status == NOT_RUN for r in rows), "workers": n_workers,
             "scheduler": label, "out": str(folder) if folder is not None else None,
             "compiled_in_workers": sum(bool(r.builds.get("compiled")) for r in
                                        record.results.values() if r.name != first),
             "vm_fallback": sum(bool(r.builds.get("vm")) for r in record.results.values())}
    result = SweepResult(sweep.name, sweep.analysis, sweep.outputs, sweep.keys, rows, stats)
    if folder is not None:
        result.save(folder / f"{TABLE}.csv")
        result.save(folder / f"{TABLE}.json")
    return result
