"""Error types raised by symcable.

Every error a user can trigger derives from :class:`SymcableError`, so the CLI can turn
any of them into a one-line message without a traceback.
"""
from __future__ import annotations

from typing import Any


class SymcableError(Exception):
    """Base class of every error symcable raises on purpose.

    Raised as itself for a bad argument to a function or option class (a value out of
    range, an unknown name or choice, an array of the wrong shape, an option that does not
    apply to the scene, an output file of the wrong type); its subclasses
    :class:`SceneError`, :class:`LimitError` and :class:`ConvergenceError` say more. Catch
    ``sc.SymcableError`` to catch them all. The message is one line; the command line
    prints it as ``symcable: <class name>: <message>``, without a traceback, and exits with
    status 2. It has no attributes beyond the message (``str(exc)``).
    """


class SceneError(SymcableError, ValueError):
    """A scene (TOML file or dict) is invalid.

    The message is one line naming the key, the value received and what is allowed, e.g.
    ``sections[0].length = -3.0 m: must be > 0``.

    Raised when a scene is read (:func:`~symcable.load_scene`, and every analysis given a
    scene file, a dict or a built-in scene's name): a file that is missing, unreadable or
    not valid TOML, an unknown or missing key, a value of the wrong type or out of range,
    an inconsistent geometry; also for a bad MoorDyn deck (the message then starts with
    ``<deck>:<line number>:``) and a bad sweep file. It is a :class:`ValueError` too. It
    has no attributes beyond the message.
    """


class LimitError(SymcableError, ValueError):
    """An input is over one of symcable's resource limits (:mod:`symcable.limits`): a scene
    of too many segments, a run of too many steps, a sweep of too many cases, a file too
    large, input nested too deeply.

    The message names the value, the limit and the option that raises it, e.g.
    ``the scene's segments = 10,000,000: more than the limit of 20,000 (...); raise it with
    sc.limits(segments=...) in Python or --max-segments on the command line``.

    Raised before anything is built or read in full, when a scene has more segments (or rod
    segments) than its limit, a run more time steps (or an offset sweep more offsets), a
    sweep more cases, a file more bytes, or input more levels of nesting (or a dict that
    holds itself); also for a bad argument to ``sc.limits`` (an unknown limit, a
    value not an integer >= 1). A file that is not a regular file is refused with an
    :class:`OSError` (a :class:`SceneError` for a scene file), not with this error. It is a
    :class:`ValueError` too. It has no attributes beyond the message.
    """


class ModelNote(UserWarning):
    """A note on how an analysis was run that the user did not ask for but should know: e.g.
    a planar line resting on the seabed whose dynamics run as the 3D cable in its plane.
    Shown once, like a warning; filter it with ``warnings.simplefilter("ignore",
    sc.ModelNote)``.

    A warning (issued with :func:`warnings.warn`), not an error: the analysis runs. Today it
    is issued by :func:`~symcable.simulate`, :func:`~symcable.solve_periodic`,
    :func:`~symcable.sweep_periodic`, :func:`~symcable.modal_analysis` and
    :func:`~symcable.linearize` for a ``model = "planar"`` scene with a seabed whose static
    line rests on it: the linearised planar dynamics do not model the seabed, so the
    dynamics run as ``model = "cable3d"`` in the line's plane (positions ``[x, 0, z]``). The
    command line prints it as one line, ``symcable: warning: <message>``.
    """


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
