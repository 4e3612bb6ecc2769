"""Progress bars (tqdm) on stderr for long runs, and one-line notices of long one-off work
(compiling generated C).

Library code never prints; the bar and :func:`notice` are the exceptions. The bar only
shows when asked (``progress=True``) or, with ``progress=None``, when stderr is a terminal
and the run has lasted longer than :data:`LONG_RUN` seconds (tqdm's ``delay``); a notice only when
stderr is a terminal, or when :func:`show_notices` turned notices on (the ``symcable``
command does). Tests and CI (stderr not a TTY) stay silent.
"""
from __future__ import annotations

import sys
from typing import TextIO

from tqdm import tqdm

__all__ = ["LONG_RUN", "ProgressBar", "notice", "show_notices"]

#: with ``progress=None`` on a TTY, a bar appears once a run has lasted this long (s)
LONG_RUN = 1.0

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
    """A tqdm bar counting units of work (time steps) up to ``total``.

    Parameters
    ----------
    total : int
        Units of work in the run.
    enabled : bool or None
        True: always show; False: never; None: only on a TTY, after :data:`LONG_RUN` s.
    label : str
        Text in front of the bar.
    stream : file-like, optional
        Where to write (default ``sys.stderr``).
    min_interval : float
        Least time between two redraws, s.
    """

    def __init__(self, total: int, enabled: bool | None = None, label: str = "",
                 stream: TextIO | None = None, min_interval: float = 0.1, unit: str = "step"):
        stream = sys.stderr if stream is None else stream
        if enabled is None:
            try:
                enabled = bool(stream.isatty())
            except (AttributeError, ValueError):
                enabled = False
            delay = LONG_RUN
        else:
            delay = 0.0
        self.total = max(int(total), 1)
        self._done = 0
        self._bar = tqdm(total=self.total, desc=label, file=stream, disable=not enabled,
                         mininterval=min_interval, delay=delay, unit=unit, leave=True,
                         dynamic_ncols=True)

    def update(self, done: int) -> None:
        """Record that ``done`` units of the total are finished."""
        done = min(max(int(done), 0), self.total)
        if done > self._done:
            self._bar.update(done - self._done)
            self._done = done

    def close(self) -> None:
        self._bar.close()

    def __enter__(self) -> "ProgressBar":
        return self

    def __exit__(self, *exc) -> None:
        self.close()
