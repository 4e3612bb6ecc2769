"""MoorDyn (the ``moordyn`` Python package, 2.7.2) driven step by step from Python: what
studies/chains/peers.py, studies/moordyn_live3d/case.py and
studies/performance/moordyn_line.py share.

A run is::

    with moordyn_driver.session({"deck.txt": text}, "deck.txt", x0, v0) as s:
        held_s, F_static = moordyn_driver.settle(s, x0, v0, max_time=200.0, tol=1e-6, window=10)
        run = moordyn_driver.drive(s, calls, read=lambda: md.GetLineFairTen(line))

:func:`session` writes the deck (and any file it reads, e.g. ``current_profile.txt``) into a
temporary folder, works there (MoorDyn resolves ``fileIC`` and the current profile against
the working directory or the deck's folder), sends MoorDyn's own output (its banner and log
lines, written from C++ to the process's stdout/stderr) to a log file, and calls ``Create``
and ``Init`` with the coupled points at rest or moving at ``x0`` (m) / ``v0`` (m/s): the
coupled points' coordinates in MoorDyn's order, 3 per point. A failure of Create, Init or of
anything inside the ``with`` block (``Step`` above MoorDyn's stability limit) is a
``RuntimeError`` whose message ends with the tail of MoorDyn's log.

MoorDyn behaviours the callers rely on (read in its source, measured in the studies):

* ``Init`` (its initial-condition solve) ignores a current: :func:`settle` holds the coupled
  points while the line settles in it, in 1 s calls;
* ``Step(x, v, t, dt)`` moves each coupled point along ``x + v (t' - t)`` within the call, from
  the values at its start; it returns the net force on the coupled points (N; the end node's
  tension, weight, drag and seabed force, no inertia) at the scheme's last stage (RK2: the
  midpoint, ``dt/2`` before the call's end when one call is one MoorDyn step).

Units: SI throughout (m, m/s, s, N). Wall times are ``time.perf_counter`` seconds.
"""
from __future__ import annotations

import contextlib
import os
import sys
import tempfile
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable, Iterable, Sequence

import numpy as np


def moordyn():
    """The ``moordyn`` module, or an ImportError saying how to install it."""
    try:
        import moordyn as md
    except ImportError as exc:  # pragma: no cover - depends on the environment
        raise ImportError('MoorDyn is missing: pip install "symcable[bench]" (moordyn==2.7.2)') from exc
    return md


@contextlib.contextmanager
def quiet(log: Path):
    """The process's stdout and stderr (file descriptors 1 and 2: MoorDyn writes from C++)
    appended to the file ``log`` while the block runs."""
    sys.stdout.flush()
    sys.stderr.flush()
    saved = [os.dup(1), os.dup(2)]
    with open(log, "ab") as sink:
        try:
            os.dup2(sink.fileno(), 1)
            os.dup2(sink.fileno(), 2)
            yield
        finally:
            for fd, old in ((1, saved[0]), (2, saved[1])):
                os.dup2(old, fd)
                os.close(old)


@dataclass
class Session:
    """A created and initialised MoorDyn system (yielded by :func:`session`).

    ``md`` the moordyn module, ``system`` its instance, ``folder`` the working folder (the deck
    and the log are there), ``started`` (perf_counter s, just before ``Create``),
    ``ic_time`` (s, ``Init`` alone), ``init_time`` (s, ``Create`` + ``Init``)."""
    md: object
    system: object
    folder: Path
    started: float
    ic_time: float
    init_time: float
    log: Path = field(repr=False, default=None)

    def log_tail(self, chars: int = 1500) -> str:
        """The last ``chars`` characters MoorDyn printed."""
        return _tail(self.log, chars)

    def dt(self) -> float:
        """MoorDyn's own step dtM (s), from its dtM or CFL option (``moordyn.GetDt`` returns
        None in 2.7.2, hence ``cmoordyn``)."""
        import cmoordyn
        return cmoordyn.get_dt(self.system)

    def cfl(self) -> float:
        """MoorDyn's CFL factor for its step (-)."""
        import cmoordyn
        return cmoordyn.get_cfl(self.system)


def _tail(log: Path | None, chars: int = 1500) -> str:
    try:
        return log.read_text(errors="replace")[-chars:]
    except (OSError, AttributeError):
        return ""


@contextlib.contextmanager
def session(files: dict, deck: str, x0: Sequence[float], v0: Sequence[float], *,
            prefix: str = "moordyn_"):
    """Write ``files`` ({name: str or bytes}) into a new temporary folder, make it the working
    directory, ``Create`` the system from ``files[deck]`` there (verbosity: errors only) and
    ``Init`` it with the coupled points at ``x0`` (m) moving at ``v0`` (m/s); yield a
    :class:`Session`; ``Close`` it, return to the previous directory and remove the folder.

    MoorDyn's output goes to ``moordyn.log`` in the folder; every RuntimeError raised in the
    block (Create, Init, Step) carries its tail."""
    md = moordyn()
    cwd = os.getcwd()
    with tempfile.TemporaryDirectory(prefix=prefix) as tmp:
        folder = Path(tmp)
        for name, content in files.items():
            path = folder / name
            if isinstance(content, bytes):
                path.write_bytes(content)
            else:
                path.write_text(content, encoding="utf-8")
        log = folder / "moordyn.log"
        os.chdir(folder)
        try:
            with quiet(log):
                started = time.perf_counter()
                system = md.Create(str(folder / deck))
                if system is None:
                    raise RuntimeError(f"moordyn.Create failed on {deck}")
                try:
                    md.SetVerbosity(system, md.LEVEL_ERR)
                    t1 = time.perf_counter()
                    if md.Init(system, list(x0), list(v0)) != md.ERRCODE_SUCCESS:
                        raise RuntimeError(f"moordyn.Init failed on {deck}")
                    t2 = time.perf_counter()
                    yield Session(md, system, folder, started, t2 - t1, t2 - started, log)
                finally:
                    md.Close(system)
        except RuntimeError as exc:
            raise RuntimeError(f"{exc}; MoorDyn printed:\n{_tail(log)}") from exc
        finally:
            os.chdir(cwd)


def settle(s: Session, x: Sequence[float], v: Sequence[float], *, max_time: float, tol: float,
           window: int, t_start: float = 0.0, first: float | None = None) -> tuple[float, float]:
    """Hold the coupled points at ``x`` (m, velocity ``v`` m/s) in 1 s ``Step`` calls from
    ``t_start`` (s) until the magnitude of the returned force (N) changes by less than ``tol``
    of itself over the last ``window`` calls, or ``max_time`` s have been simulated.
    ``first`` (N), if given, is the force before the first call (counted in the window).

    Returns (seconds simulated, the last force magnitude in N)."""
    step = s.md.Step
    hist = [] if first is None else [first]
    held, t = 0.0, 0
    x, v = list(x), list(v)
    while held < max_time:
        hist.append(float(np.linalg.norm(step(s.system, x, v, t_start + t, 1.0))))
        t += 1
        held = float(t)
        if len(hist) > window and abs(hist[-1] - hist[-1 - window]) < tol * hist[-1]:
            break
    return held, hist[-1]


@dataclass
class Drive:
    """What :func:`drive` returns: ``force`` (n, k) N, the forces ``Step`` returned (k = 3 per
    coupled point), ``reads`` (list of n + 1 values of ``read()``: before the first call and
    after each; empty without ``read``), ``wall`` (s, the loop alone)."""
    force: np.ndarray
    reads: list
    wall: float


def drive(s: Session, calls: Iterable[tuple], read: Callable[[], object] | None = None) -> Drive:
    """One ``Step`` per item ``(x, v, t, dt)`` of ``calls``: the coupled points' position (m)
    and velocity (m/s) at the call's start ``t`` (s), over ``dt`` (s). ``read`` (optional) is
    called before the first call and after each (e.g. a line's tensions)."""
    step, system = s.md.Step, s.system
    forces, reads = [], []
    t0 = time.perf_counter()
    if read is not None:
        reads.append(read())
    for x, v, t, dt in calls:
        forces.append(step(system, x, v, t, dt))
        if read is not None:
            reads.append(read())
    wall = time.perf_counter() - t0
    force = np.asarray(forces, dtype=float).reshape(len(forces), -1) if forces else np.empty((0, 3))
    return Drive(force, reads, wall)
