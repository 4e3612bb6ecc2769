"""Resource limits: bounds on what an input may make symcable read, allocate or run.

A 600-byte scene file can ask for ten million segments, a sweep file for four million
cases, a motion table can name ``/dev/zero``. Each such input is refused before anything
is built, with one :class:`~symcable.errors.LimitError` that names the value, the limit
and how to raise it. The limits are generous for real work (a 10,000-segment line, a
three-hour storm at 0.011 s, ten thousand sweep cases) and each is an explicit option:

* Python: ``with sc.limits(segments=50_000): ...`` (:func:`limits`), within the block, in
  this thread or task (a :mod:`contextvars` variable); :func:`current` reads them.
* Command line: ``--max-segments``, ``--max-steps``, ``--max-cases``, ``--max-file-mb``,
  ``--max-table-mb``, ``--max-nesting`` on every subcommand.

Files symcable reads (scene files, MoorDyn decks, motion tables, sweep files, a sweep's
saved results) are read by :func:`read_bounded`: a regular file (not a FIFO, a device or a
folder) no larger than its limit, opened without blocking.
"""
from __future__ import annotations

import contextvars
import errno
import dataclasses
import os
import stat
import time
from contextlib import contextmanager
from dataclasses import dataclass
from collections.abc import Mapping
from typing import Any, Iterator

from .errors import LimitError

__all__ = ["Limits", "current", "limits", "check", "read_bounded", "check_nesting",
           "check_toml_nesting", "OPTIONS"]

_MB = 1 << 20


@dataclass(frozen=True)
class Limits:
    """Resource limits (each an integer > 0).

    Attributes
    ----------
    segments : int
        Segments of one scene, all lines and sections together. A cable segment costs tens
        of kB of symbolic graph and Functions.
    rod_segments : int
        Segments of one scene's rod sections (``model = "rod"``, a hybrid's rod sections, or
        every section of a hybrid whose zones are chosen automatically): a rod segment, with
        its bending, torsion and frames, costs about 0.7 MB in a static solve.
    steps : int
        Time steps of one run (``duration / dt``: a three-hour record at 0.011 s), or
        offsets of one offset sweep.
    sweep_cases : int
        Cases of one sweep, counted before the grid is expanded.
    file_bytes : int
        Size of a scene file, MoorDyn deck, sweep file or saved sweep case, bytes.
    table_bytes : int
        Size of a motion table file, bytes.
    nesting : int
        Depth of nested arrays and tables in a scene or sweep (TOML or dict).
    solve_seconds : int
        Wall time of one periodic solve, s: of a whole ``solve_periodic`` call (its
        attempts, fallbacks and error estimate together, :func:`call_deadline`), and of
        each solve's iterations within it (shooting's periods, IPOPT's iterations). A
        response with no period (a line that snaps, a subharmonic) is said so within it
        rather than iterated on for hours.
    """

    segments: int = 20_000
    rod_segments: int = 2_000
    steps: int = 1_000_000
    sweep_cases: int = 10_000
    file_bytes: int = 16 * _MB
    table_bytes: int = 16 * _MB
    nesting: int = 32
    solve_seconds: int = 600

    def __post_init__(self):
        for f in dataclasses.fields(self):
            v = getattr(self, f.name)
            if isinstance(v, bool) or not isinstance(v, int) or v < 1:
                raise LimitError(f"limits.{f.name} = {v!r}: must be an integer >= 1")


#: each limit's command-line option, the factor from the option's value to the limit's
#: unit, and what it bounds
OPTIONS = {"segments": ("--max-segments", 1, "segments of a scene, all lines together"),
           "rod_segments": ("--max-rod-segments", 1, "segments of a scene's rod sections"),
           "steps": ("--max-steps", 1, "time steps of a run (duration / dt), offsets of a sweep"),
           "sweep_cases": ("--max-cases", 1, "cases of a sweep"),
           "file_bytes": ("--max-file-mb", _MB, "size of a scene file, deck or sweep file"),
           "table_bytes": ("--max-table-mb", _MB, "size of a motion table file"),
           "nesting": ("--max-nesting", 1, "nesting of arrays and tables in a scene or sweep"),
           "solve_seconds": ("--max-solve-seconds", 1, "wall time of a periodic solve, s")}

_current: contextvars.ContextVar = contextvars.ContextVar("symcable_limits", default=Limits())


def current() -> Limits:
    """The limits in force here (:func:`limits` changes them for a block)."""
    return _current.get()


_deadline: contextvars.ContextVar = contextvars.ContextVar("symcable_deadline", default=None)


@contextmanager
def call_deadline() -> Iterator[None]:
    """Within the block, every periodic solve shares one deadline: ``solve_seconds`` from
    the block's start (:func:`remaining_seconds`). Nested blocks keep the outer deadline."""
    if _deadline.get() is not None:
        yield
        return
    token = _deadline.set(time.perf_counter() + current().solve_seconds)
    try:
        yield
    finally:
        _deadline.reset(token)


def remaining_seconds() -> float:
    """Seconds a periodic solve starting now may take: ``solve_seconds``, or what is left of
    the enclosing :func:`call_deadline` when that is less (0 once it has passed)."""
    top = float(current().solve_seconds)
    end = _deadline.get()
    return top if end is None else max(0.0, min(top, end - time.perf_counter()))


def past_deadline() -> bool:
    """Whether the enclosing :func:`call_deadline` has passed (False outside one)."""
    end = _deadline.get()
    return end is not None and time.perf_counter() >= end


@contextmanager
def limits(value: Limits | None = None, **changes: int) -> Iterator[Limits]:
    """Change the resource limits within a ``with`` block (this thread or task only).

    ``with sc.limits(segments=50_000, steps=10**7): ...``, or ``sc.limits(Limits(...))``.
    The limits in force before the block are restored when it ends.

    Parameters
    ----------
    value : Limits, optional
        The limits to start from. Default None: those in force here (:func:`current`; the
        defaults of :class:`Limits` outside any block).
    **changes : int
        Limits to change from ``value``, by the names of :class:`Limits`' fields
        (``segments``, ``rod_segments``, ``steps``, ``sweep_cases``, ``file_bytes`` and
        ``table_bytes`` in bytes, ``nesting``, ``solve_seconds`` in s), each an integer
        >= 1.

    Yields
    ------
    Limits
        The limits in force within the block (``with sc.limits(...) as lim``).

    Raises
    ------
    LimitError
        ``value`` is not a :class:`Limits`, a name in ``changes`` is not a limit, or a
        changed value is not an integer >= 1.
    """
    base = current() if value is None else value
    if not isinstance(base, Limits):
        raise LimitError(f"limits = {base!r}: must be a symcable.Limits")
    names = {f.name for f in dataclasses.fields(Limits)}
    for key in changes:
        if key not in names:
            raise LimitError(f"limits: unknown limit {key!r} (allowed: {', '.join(sorted(names))})")
    new = dataclasses.replace(base, **changes)
    token = _current.set(new)
    try:
        yield new
    finally:
        _current.reset(token)


def _how(name: str) -> str:
    option, factor, _ = OPTIONS[name]
    unit = " (MB)" if factor != 1 else ""
    return f"raise it with sc.limits({name}=...) in Python or {option}{unit} on the command line"


def check(name: str, value: int | float, what: str, why: str) -> None:
    """Raise :class:`LimitError` when ``value`` exceeds the limit ``name`` of
    :func:`current`; ``what`` says what was counted (``"the scene's segments"``), ``why``
    what it would cost."""
    top = getattr(current(), name)
    if value > top:
        try:
            shown = f"{value:,.0f}" if value < 1e15 else f"{float(value):.3g}"
        except OverflowError:  # an int beyond float's range
            shown = f"about 1e{len(str(int(value))) - 1}"
        raise LimitError(f"{what} = {shown}: more than the limit of {top:,} ({why}); "
                         f"{_how(name)}")


def read_bounded(path: str | os.PathLike, limit: str, what: str) -> bytes:
    """The bytes of the regular file ``path``, at most the limit ``limit`` of
    :func:`current` (``"file_bytes"`` or ``"table_bytes"``).

    The file is opened without blocking (a FIFO does not hang) and must be a regular file;
    its size is checked before reading and the read stops one byte past the limit (a file
    that grows while read is still refused).

    Raises
    ------
    OSError
        The file cannot be opened (missing, no permission), as :func:`open` raises it, or
        is not a regular file (``strerror`` says what it is).
    LimitError
        The file is larger than the limit.
    """
    top = getattr(current(), limit)
    name = os.fspath(path)
    fd = os.open(name, os.O_RDONLY | getattr(os, "O_NONBLOCK", 0) | getattr(os, "O_CLOEXEC", 0))
    try:
        st = os.fstat(fd)
        if not stat.S_ISREG(st.st_mode):
            kind = ("a folder" if stat.S_ISDIR(st.st_mode) else "a FIFO (named pipe)"
                    if stat.S_ISFIFO(st.st_mode) else "a device" if stat.S_ISCHR(st.st_mode)
                    or stat.S_ISBLK(st.st_mode) else "a socket" if stat.S_ISSOCK(st.st_mode)
                    else "not a regular file")
            raise OSError(errno.EISDIR if stat.S_ISDIR(st.st_mode) else errno.EINVAL,
                          f"{kind}, not a regular file: symcable reads regular files only")
        if st.st_size > top:
            check(limit, st.st_size, f"{what} {name!r}: its size, bytes", "a guard against "
                  "files that exhaust memory")
        chunks, size = [], 0
        while True:
            chunk = os.read(fd, min(1 << 20, top + 1 - size))
            if not chunk:
                break
            chunks.append(chunk)
            size += len(chunk)
            if size > top:
                check(limit, size, f"{what} {name!r}: its size, bytes (it grew while read)",
                      "a guard against files that exhaust memory")
        return b"".join(chunks)
    finally:
        os.close(fd)


def _open_brackets(text: str) -> int:
    """The deepest nesting of ``[`` and ``{`` in TOML text, outside strings and comments
    (table headers count one or two, as ``[a]`` and ``[[a]]``)."""
    depth = top = 0
    i, n = 0, len(text)
    while i < n:
        c = text[i]
        if c == "#":
            j = text.find("\n", i)
            i = n if j < 0 else j + 1
            continue
        if c in "\"'":
            triple = text.startswith(c * 3, i)
            end = c * 3 if triple else c
            j = i + len(end)
            while j < n:
                if c == '"' and text[j] == "\\":
                    j += 2
                    continue
                if text.startswith(end, j):
                    break
                if not triple and text[j] == "\n":  # an unterminated string: the parser says so
                    break
                j += 1
            i = j + len(end)
            continue
        if c in "[{":
            depth += 1
            top = max(top, depth)
        elif c in "]}":
            depth = max(0, depth - 1)
        i += 1
    return top


def check_toml_nesting(text: str, what: str) -> None:
    """Refuse TOML text nested deeper than the ``nesting`` limit, before it is parsed (the
    parser recurses once per level)."""
    depth = _open_brackets(text)
    check("nesting", depth, f"{what}: nesting of arrays and inline tables",
          "deeper input is refused before it is parsed")


_LEAVES = (float, int, str, bool, type(None))


def check_nesting(data: Any, what: str) -> None:
    """Refuse a dict or list nested deeper than the ``nesting`` limit (a dict that holds
    itself included); walked without recursion."""
    top = current().nesting

    def kids(node):
        vals = node.values() if isinstance(node, Mapping) else node
        # (numbers and text, the bulk of a scene, ruled out by the cheap test first)
        return iter([c for c in vals if not isinstance(c, _LEAVES)
                     and isinstance(c, (Mapping, list, tuple))])

    def refuse(depth):
        check("nesting", depth, f"{what}: nesting of arrays and tables", "deeper input is "
              "refused before it is read")

    if not isinstance(data, (Mapping, list, tuple)):
        return
    height: dict = {}  # id -> levels below and including it, of containers walked already
    path = {id(data)}
    stack = [(data, kids(data), 1)]  # depth-first; a container shared twice is walked once
    while stack:
        node, it, depth = stack[-1]
        child = next(it, None)
        if child is None:
            stack.pop()
            path.discard(id(node))
            height[id(node)] = max([1] + [1 + height.get(id(c), 0) for c in kids(node)])
            continue
        if id(child) in path:
            raise LimitError(f"{what}: a table or array that holds itself (nesting without "
                             "end): give plain nested data")
        if id(child) in height:
            if depth + height[id(child)] > top:
                refuse(depth + height[id(child)])
            continue
        if depth + 1 > top:
            refuse(depth + 1)
        path.add(id(child))
        stack.append((child, kids(child), depth + 1))
