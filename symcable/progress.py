"""A tiny dependency-free progress bar on stderr, for long runs only, and one-line notices
of long one-off work (compiling generated C).

Library code never prints; this bar and :func:`notice` are the exceptions. The bar only
writes when asked (``progress=True``) or, with ``progress=None``, when stderr is a terminal
and the run is expected to take longer than :data:`LONG_RUN` seconds; a notice only when
stderr is a terminal, or when :func:`show_notices` turned notices on (the ``symcable``
command does). Tests and CI (stderr not a TTY) stay silent.
"""
from __future__ import annotations

import sys
import time
from typing import TextIO

__all__ = ["LONG_RUN", "ProgressBar", "notice", "show_notices"]

#: A run expected to take longer than this (s) shows a bar when ``progress=None`` on a TTY.
LONG_RUN = 2.0

_notices: bool | None = None


def show_notices(enabled: bool | None) -> None:
    """Notices on stderr: True always, False never, None (the default) on a terminal only."""
    global _notices
    _notices = enabled


def notice(message: str, stream: TextIO | None = None) -> None:
    """One line on stderr (``stream``) announcing long one-off work, e.g.
    ``compiling the generalized-α step for this model (once, cached) …``; shown as
    :func:`show_notices` says."""
    stream = sys.stderr if stream is None else stream
    enabled = _notices
    if enabled is None:
        try:
            enabled = bool(stream.isatty())
        except (AttributeError, ValueError):
            enabled = False
    if enabled:
        stream.write(message + "\n")
        stream.flush()


class ProgressBar:
    """``label |#####-----|  45%  900/2000 steps  1.2 s left`` on one line of stderr.

    Parameters
    ----------
    total : int
        Units of work (time steps) in the run.
    enabled : bool or None
        True: always show; False: never; None: show only on a TTY for a long run (decided
        at the first :meth:`update`, from the rate measured so far).
    label : str
        Text in front of the bar.
    stream : file-like, optional
        Where to write (default ``sys.stderr``, looked up when the bar is made).
    min_interval : float
        Least time between two redraws, s.
    """

    def __init__(self, total: int, enabled: bool | None = None, label: str = "",
                 stream: TextIO | None = None, min_interval: float = 0.1):
        self.total = max(int(total), 1)
        self.label = label
        self.stream = sys.stderr if stream is None else stream
        self.min_interval = min_interval
        self._enabled = enabled
        self._start = time.perf_counter()
        self._last_draw = -float("inf")
        self._shown = False
        self._decided = enabled is not None

    def _tty(self) -> bool:
        try:
            return bool(self.stream.isatty())
        except (AttributeError, ValueError):
            return False

    def update(self, done: int) -> None:
        """Record that ``done`` units of the total are finished, and redraw if due."""
        now = time.perf_counter()
        elapsed = now - self._start
        if not self._decided and done > 0:
            expected = elapsed / done * self.total
            self._enabled = self._tty() and expected > LONG_RUN
            self._decided = True
        if not self._enabled:
            return
        if now - self._last_draw < self.min_interval and done < self.total:
            return
        self._last_draw = now
        frac = min(max(done / self.total, 0.0), 1.0)
        width = 30
        fill = int(round(frac * width))
        left = elapsed / done * (self.total - done) if done > 0 else float("nan")
        text = (f"\r{self.label} |{'#' * fill}{'-' * (width - fill)}| {100 * frac:3.0f}%  "
                f"{done}/{self.total} steps  {left:.1f} s left ")
        self.stream.write(text)
        self.stream.flush()
        self._shown = True

    def close(self) -> None:
        """End the line the bar was drawn on (nothing when it was never shown)."""
        if self._shown:
            self.stream.write("\n")
            self.stream.flush()
            self._shown = False

    def __enter__(self) -> "ProgressBar":
        return self

    def __exit__(self, *exc) -> None:
        self.close()
