"""Run hostile-input cases (``hostile.py``) through ``symcable.cli.main.main`` in this process.

    python hostile_runner.py CASES.json RESULTS.json

Each case runs in the corpus folder (the current folder) with its stdout and stderr caught,
under an alarm of ``TIMEOUT`` seconds (a hang is reported, not waited for). RESULTS.json has
each case's exit status, stderr, seconds and whether an exception escaped ``main``, and the
process's peak resident memory (:func:`peak_memory`, bytes) at the end: the largest any
case reached.
"""
from __future__ import annotations

import contextlib
import io
import json
import resource
import signal
import sys
import time
import traceback

#: seconds after which a case counts as hung
TIMEOUT = 120


class Hung(BaseException):
    """Raised by the alarm (a BaseException: ``main`` must not turn it into a message)."""


def _alarm(signum, frame):
    raise Hung()


def run(cases: list) -> dict:
    from symcable.cli.main import main

    signal.signal(signal.SIGALRM, _alarm)
    out = []
    for case in cases:
        err, std = io.StringIO(), io.StringIO()
        escaped, t0 = None, time.perf_counter()
        signal.alarm(TIMEOUT)
        try:
            with contextlib.redirect_stderr(err), contextlib.redirect_stdout(std):
                try:
                    rc = main(case["argv"])
                except SystemExit as exc:  # argparse
                    rc = exc.code
        except Hung:
            rc, escaped = None, f"hung: no answer in {TIMEOUT} s"
        except BaseException as exc:  # noqa: BLE001 - reported, the test fails on it
            rc, escaped = None, "".join(traceback.format_exception(exc))
        finally:
            signal.alarm(0)
        out.append({"id": case["id"], "rc": rc, "stderr": err.getvalue(),
                    "seconds": time.perf_counter() - t0, "escaped": escaped})
    return {"cases": out, "maxrss": peak_memory()}


def peak_memory() -> int:
    """This process's peak resident memory, bytes: ``VmHWM`` of /proc/self/status on Linux
    (the image since exec: ``ru_maxrss`` keeps the peak of the process that forked it, a
    pytest worker of gigabytes), else ``ru_maxrss``."""
    try:
        with open("/proc/self/status") as fh:
            for line in fh:
                if line.startswith("VmHWM:"):
                    return int(line.split()[1]) * 1024
    except OSError:
        pass
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024


if __name__ == "__main__":
    with open(sys.argv[1]) as fh:
        todo = json.load(fh)
    with open(sys.argv[2], "w") as fh:
        json.dump(run(todo), fh)
