"""Long-lived worker processes that run fuzz scenes with a time limit per stage, so a hang
or a crash is counted, not fatal.

Each worker (started with the ``spawn`` method, so it imports symcable fresh) takes one scene
at a time and reports each stage to the parent before starting it: ``("stage", "solve")``,
then ``("stage", "refs", partial)`` with the solve's outcome, then ``("done", record)``. The
parent gives each stage its own deadline; a worker past it is killed (by its own pid, which
the parent started) and replaced, and the scene is recorded as a ``hang`` (solve stage) or
keeps its solve outcome with ``reference_timeout`` (reference stage). A worker that dies is
recorded as a ``crash``.
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


def _worker(conn) -> None:
    os.environ["PYTHONBREAKPOINT"] = "0"
    if HERE not in sys.path:
        sys.path.insert(0, HERE)
    import fuzz_classify as fc
    import fuzz_refine
    while True:
        item = conn.recv()
        if item is None:
            return
        try:
            if item.get("job") == "refine":
                rec = fuzz_refine.run(item)
            elif item.get("model") == "cable3d":
                import fuzz3d_classify
                rec = fuzz3d_classify.run_scene(item, notify=lambda *msg: conn.send(("stage", *msg)))
            else:
                rec = fc.run_scene(item, notify=lambda *msg: conn.send(("stage", *msg)))
        except Exception:  # noqa: BLE001 - a harness bug is reported, not raised
            rec = {"id": item["id"], "cls": item["class"], "variant": item["variant"],
                   "outcome": "harness error", "error": traceback.format_exc()[-1500:]}
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

    def give(self, item, limit):
        self.item, self.stage, self.partial = item, "solve", None
        self.t0 = time.perf_counter()
        self.deadline = self.t0 + limit
        self.conn.send(item)

    def close(self):
        try:
            self.conn.send(None)
        except OSError:
            pass
        self.proc.join(5)
        if self.proc.is_alive():
            self.proc.kill()


def _base(item) -> dict:
    return {"id": item["id"], "cls": item["class"], "variant": item["variant"]}


def run_all(items, workers: int = 2, solve_limit: float = 30.0, ref_limit: float = 120.0,
            progress=None) -> list[dict]:
    """Run every item; returns the records in the items' order."""
    ctx = mp.get_context("spawn")
    pending = deque(items)
    slots = [_Slot(ctx) for _ in range(min(workers, len(items)) or 1)]
    out = {}
    try:
        while pending or any(s.item is not None for s in slots):
            for s in slots:
                if s.item is None and pending:
                    s.give(pending.popleft(), solve_limit)
            busy = [s for s in slots if s.item is not None]
            timeout = max(0.0, min(s.deadline for s in busy) - time.perf_counter())
            ready = wait([s.conn for s in busy], timeout=timeout)
            for s in busy:
                if s.conn in ready:
                    try:
                        msg = s.conn.recv()
                    except (EOFError, OSError):
                        rec = _base(s.item)
                        rec.update(outcome="crash", error=f"worker died (exit code {s.proc.exitcode})",
                                   time_s=time.perf_counter() - s.t0)
                        out[rec["id"]] = rec
                        s.item = None
                        s.restart()
                        continue
                    if msg[0] == "stage":
                        s.stage, s.partial = "refs", msg[2] if len(msg) > 2 else None
                        s.deadline = time.perf_counter() + ref_limit
                    else:
                        out[msg[1]["id"]] = msg[1]
                        s.item = None
                elif time.perf_counter() > s.deadline:
                    rec = _base(s.item)
                    if s.stage == "solve":
                        rec.update(outcome="hang", error=f"no answer within {solve_limit:g} s",
                                   time_s=solve_limit)
                    else:
                        rec.update(s.partial or {}, reference_timeout=True)
                    out[rec["id"]] = rec
                    s.item = None
                    s.restart()
            if progress:
                progress(len(out), len(items))
    finally:
        for s in slots:
            s.close()
    return [out[it["id"]] for it in items]
