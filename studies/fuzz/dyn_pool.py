"""Long-lived worker processes for the dynamic fuzz study (:mod:`dyn_fuzz`), in the manner
of :mod:`fuzz_pool` (whose worker runs the static study's stages): each worker (``spawn``,
so it imports symcable fresh) takes one scene at a time and announces each stage before it
starts, with the record so far; the parent gives each stage its own deadline
(``KILL_AFTER``). A worker past it is killed (by the pid the parent started) and replaced;
the scene keeps its record up to that stage, the stage's call marked ``killed``. A worker
that dies marks its stage's call ``crash``.
"""
from __future__ import annotations

import multiprocessing as mp
import os
import sys
import time
import traceback
from collections import deque
from multiprocessing.connection import wait

HERE = os.path.dirname(os.path.abspath(__file__))

#: stage -> (the record's key for its call, s after which the worker is killed). The calls
#: under test count as hangs past dyn_classify.BOUND (180 s) whatever these are; the kill
#: only bounds the study
KILL_AFTER = {"simulate": ("sim", 600.0), "reference": ("b", 1500.0),
              "periodic": ("per", 600.0), "reference16": ("b16", 2400.0),
              "reference_long": ("bL", 2400.0)}


def _worker(conn) -> None:
    os.environ["PYTHONBREAKPOINT"] = "0"
    os.environ.setdefault("SYMCABLE_CODEGEN", "0")
    if HERE not in sys.path:
        sys.path.insert(0, HERE)
    import dyn_work
    while True:
        item = conn.recv()
        if item is None:
            return
        try:
            rec = dyn_work.run_scene(item, notify=lambda *msg: conn.send(("stage", *msg)))
        except Exception:  # noqa: BLE001 - a harness bug is reported, not raised
            rec = {"id": item["id"], "cls": item["class"], "variant": item["variant"],
                   "harness_error": traceback.format_exc()[-1500:]}
        conn.send(("done", rec))


class _Slot:
    def __init__(self, ctx):
        self.ctx = ctx
        self.item = None
        self._start()

    def _start(self):
        self.conn, child = self.ctx.Pipe()
        self.proc = self.ctx.Process(target=_worker, args=(child,), daemon=True)
        self.proc.start()
        child.close()

    def restart(self):
        if self.proc.is_alive():
            self.proc.kill()
        self.proc.join(5)
        self.conn.close()
        self._start()

    def give(self, item):
        self.item, self.stage, self.partial = item, "simulate", None
        self.t0 = self.t_stage = time.perf_counter()
        self.deadline = self.t0 + KILL_AFTER["simulate"][1]
        self.conn.send(item)

    def close(self):
        try:
            self.conn.send(None)
        except OSError:
            pass
        self.proc.join(5)
        if self.proc.is_alive():
            self.proc.kill()


def _stopped(s, outcome: str, error: str) -> dict:
    """The record of a scene whose worker was killed or died in stage ``s.stage``."""
    rec = dict(s.partial or {"id": s.item["id"], "cls": s.item["class"],
                             "variant": s.item["variant"], "period": s.item["period"],
                             "segments": s.item["segments"]})
    key = KILL_AFTER[s.stage][0]
    rec[key] = {"outcome": outcome, "wall": time.perf_counter() - s.t_stage, "error": error}
    return rec


def run_all(items, workers: int = 2, progress=None, budget_s: float | None = None) -> list[dict]:
    """Run every item (no new scene is started after ``budget_s`` s); returns the records
    of the scenes run, in the items' order, with ``scene_wall`` (s) each."""
    ctx = mp.get_context("spawn")
    pending = deque(items)
    slots = [_Slot(ctx) for _ in range(min(workers, len(items)) or 1)]
    out = {}
    start = time.perf_counter()
    try:
        while pending or any(s.item is not None for s in slots):
            if budget_s is not None and time.perf_counter() - start > budget_s:
                pending.clear()
            for s in slots:
                if s.item is None and pending:
                    s.give(pending.popleft())
            busy = [s for s in slots if s.item is not None]
            if not busy:
                break
            timeout = max(0.0, min(s.deadline for s in busy) - time.perf_counter())
            ready = wait([s.conn for s in busy], timeout=min(timeout, 30.0))
            for s in busy:
                if s.conn in ready:
                    try:
                        msg = s.conn.recv()
                    except (EOFError, OSError):
                        rec = _stopped(s, "crash", f"worker died (exit code {s.proc.exitcode})")
                        rec["scene_wall"] = time.perf_counter() - s.t0
                        out[rec["id"]] = rec
                        s.item = None
                        s.restart()
                        continue
                    if msg[0] == "stage":
                        s.stage, s.partial = msg[1], msg[2]
                        s.t_stage = time.perf_counter()
                        s.deadline = s.t_stage + KILL_AFTER[s.stage][1]
                    else:
                        msg[1]["scene_wall"] = time.perf_counter() - s.t0
                        out[msg[1]["id"]] = msg[1]
                        s.item = None
                elif time.perf_counter() > s.deadline:
                    rec = _stopped(s, "killed", f"no answer within {KILL_AFTER[s.stage][1]:g} s")
                    rec["scene_wall"] = time.perf_counter() - s.t0
                    out[rec["id"]] = rec
                    s.item = None
                    s.restart()
            if progress:
                progress(out, len(items))
    finally:
        for s in slots:
            s.close()
    return [out[it["id"]] for it in items if it["id"] in out]
