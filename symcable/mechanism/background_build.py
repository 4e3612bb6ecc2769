"""Generated C compiled in the background, for the default ``codegen=None``.

The first time a model structure meets the default, compiling its C takes seconds (a
20-segment line's static solve: about 20 s with gcc -O2), far longer than its first answer
in the CasADi virtual machine (about a second). So the default does not wait: the C is
written at once (milliseconds) and a separate process compiles it into the build cache
(:mod:`symcable.mechanism.codegen`), while this analysis runs in the virtual machine (same
results). A later analysis of the same structure, in this process once the build is done
or in any later process, loads the library. ``codegen=True`` still waits for the compiler,
and so does the default within :func:`waiting` (a sweep's first case, whose library every
worker loads) or with ``SYMCABLE_CODEGEN_WAIT=1`` in the environment.

The build runs as ``python -m symcable.mechanism.codegen --build FOLDER KEY SOURCE CC
FLAGS...`` in its own session, so it finishes when the process that started it has
exited; it writes the cache entry as a foreground build does (atomically, its digest
recorded) and removes its build folder, whether it succeeds or not. This module only
starts and watches those processes (:mod:`.codegen` writes the C and the entry).
"""
from __future__ import annotations

import os
import subprocess
import sys
import threading
from contextlib import contextmanager

__all__ = ["finished", "start", "wait", "waiting", "waits"]

_ENV_WAIT = "SYMCABLE_CODEGEN_WAIT"
#: key -> the build process started by this process
_jobs: dict = {}
_policy = threading.local()


def waits(codegen) -> bool:
    """Whether an analysis' ``codegen`` waits for the compiler: True when given True, within
    :func:`waiting` or with ``SYMCABLE_CODEGEN_WAIT=1``; the default (None) does not."""
    if codegen is True or getattr(_policy, "wait", False):
        return True
    return os.environ.get(_ENV_WAIT, "").strip().lower() in ("1", "true", "yes", "on")


@contextmanager
def waiting():
    """Within this block (this thread), the default ``codegen=None`` compiles in the
    foreground, as ``codegen=True`` does."""
    before = getattr(_policy, "wait", False)
    _policy.wait = True
    try:
        yield
    finally:
        _policy.wait = before


def start(key: str, args: list) -> bool:
    """Start ``python -m symcable.mechanism.codegen --build *args`` (the build of the cache
    entry ``key``, its C already written) in a session of its own; False, starting nothing,
    while a build this process started is under way (one at a time: the compiler shares the
    machine with the analysis, which goes on in the virtual machine; a later call starts the
    next)."""
    if any(job.poll() is None for job in _jobs.values()):
        return False
    cmd = [sys.executable, "-m", "symcable.mechanism.codegen", "--build", *map(str, args)]
    _jobs[key] = subprocess.Popen(cmd, stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL,
                                  stderr=subprocess.DEVNULL, start_new_session=True)
    return True


def finished(key: str) -> bool:
    """Whether this process's build of ``key`` has ended (or none was started)."""
    job = _jobs.get(key)
    return job is None or job.poll() is not None


def wait(timeout: float | None = None) -> bool:
    """Wait for this process's builds; True when every one ended with its library built."""
    ok = True
    for job in list(_jobs.values()):
        try:
            ok = job.wait(timeout) == 0 and ok
        except subprocess.TimeoutExpired:
            ok = False
    return ok
