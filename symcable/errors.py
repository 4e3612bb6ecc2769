"""Error types raised by symcable.

Every error a user can trigger derives from :class:`SymcableError`, so the CLI can turn
any of them into a one-line message without a traceback.
"""
from __future__ import annotations

from typing import Any


class SymcableError(Exception):
    """Base class of every error symcable raises on purpose."""


class SceneError(SymcableError, ValueError):
    """A scene (TOML file or dict) is invalid.

    The message is one line naming the key, the value received and what is allowed, e.g.
    ``sections[0].length = -3.0 m: must be > 0``.
    """


class LimitError(SymcableError, ValueError):
    """An input is over one of symcable's resource limits (:mod:`symcable.limits`): a scene
    of too many segments, a run of too many steps, a sweep of too many cases, a file too
    large or not a regular file, input nested too deeply.

    The message names the value, the limit and the option that raises it, e.g.
    ``the scene's segments = 10,000,000: more than the limit of 20,000 (...); raise it with
    sc.limits(segments=...) in Python or --max-segments on the command line``.
    """


class ModelNote(UserWarning):
    """A note on how an analysis was run that the user did not ask for but should know: e.g.
    a planar line resting on the seabed whose dynamics run as the 3D cable in its plane.
    Shown once, like a warning; filter it with ``warnings.simplefilter("ignore",
    sc.ModelNote)``."""


class ConvergenceError(SymcableError, RuntimeError):
    """A solver did not converge.

    Attributes
    ----------
    partial : object or None
        The last iterate wrapped as the solver's usual result object (its ``status`` says
        it did not converge), so a user can inspect or plot where the solver stopped.
    diagnostics : dict
        Iteration history and the reason for stopping (residual norms in N, step sizes,
        continuation parameters reached).
    """

    def __init__(self, message: str, partial: Any = None, diagnostics: dict | None = None):
        super().__init__(message)
        self.partial = partial
        self.diagnostics = dict(diagnostics or {})
