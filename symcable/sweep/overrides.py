"""Overrides of a scene's keys by dotted path, as a sweep's cases give them.

A path names a key of the scene file's layout: table keys joined by dots, list entries by
``[index]`` (0-based), as symcable's error messages write them::

    "end_b.motion.period"          "environment.current"
    "sections[0].length"           "lines[1].sections[0].segments"
    "points.fairlead1.position"    "line_types.chain.EA"

Keys are bare (letters, digits, ``_`` and ``-``); a key the scene file does not have yet is
added (with its tables), an entry of a list must exist. Whether the result is a valid scene
is :func:`symcable.load_scene`'s to say.
"""
from __future__ import annotations

import copy
import re
from typing import Any, Mapping

from ..errors import SceneError

__all__ = ["apply_overrides", "parse_path", "plain"]

_STEP = re.compile(r"([A-Za-z0-9_-]+)((?:\[\d+\])*)")
_INDEX = re.compile(r"\[(\d+)\]")


def parse_path(path: Any, where: str) -> tuple:
    """The steps of a dotted path: str keys and int list indices; ``where`` names the path in
    the message of the SceneError a malformed one raises."""
    if not isinstance(path, str) or not path:
        raise SceneError(f"{where} = {path!r}: a scene key must be a dotted path such as "
                         "'end_b.motion.period' or 'sections[0].length'")
    steps: list = []
    for part in path.split("."):
        m = _STEP.fullmatch(part)
        if m is None:
            raise SceneError(f"{where}: {part!r} in {path!r} is not a key: keys are bare "
                             "(letters, digits, '_', '-'), list entries [index], joined by '.' "
                             "(e.g. 'sections[0].length')")
        steps.append(m.group(1))
        steps.extend(int(i) for i in _INDEX.findall(m.group(2)))
    return tuple(steps)


def _show(steps) -> str:
    out = ""
    for s in steps:
        out += f"[{s}]" if isinstance(s, int) else (f".{s}" if out else s)
    return out


def plain(value: Any) -> Any:
    """``value`` with every mapping made a dict and every tuple a list (a deep copy): the
    scene dict as TOML or JSON would give it."""
    if isinstance(value, Mapping):
        return {str(k): plain(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [plain(v) for v in value]
    return copy.deepcopy(value)


def apply_overrides(data: Mapping, overrides: Mapping[str, Any], where: str) -> dict:
    """A deep copy of the scene dict ``data`` with each ``path: value`` of ``overrides`` set.

    Raises
    ------
    SceneError
        A path that cannot be followed (a list index out of range, a step into a number or
        a string), naming ``where`` (the case), the path and what the scene has there.
    """
    out = plain(data)
    for path, value in overrides.items():
        steps = parse_path(path, where)
        node: Any = out
        for k, step in enumerate(steps):
            last = k == len(steps) - 1
            here = _show(steps[:k]) or "the scene"
            if isinstance(step, int):
                if not isinstance(node, list):
                    raise SceneError(f"{where}: {path!r}: {here} is not a list "
                                     f"(got {type(node).__name__}): [{step}] cannot index it")
                if step >= len(node):
                    raise SceneError(f"{where}: {path!r}: {here} has {len(node)} entries: "
                                     f"index [{step}] must be < {len(node)}")
            elif isinstance(node, list):
                raise SceneError(f"{where}: {path!r}: {here} is a list, not a table: it has no "
                                 f"key {step!r} (index it: {here}[0].{step})")
            elif not isinstance(node, dict):
                raise SceneError(f"{where}: {path!r}: {here} is a value, not a table: it has "
                                 f"no key {step!r}")
            if last:
                node[step] = plain(value)
            else:
                if isinstance(step, str) and node.get(step) is None:
                    node[step] = {}
                node = node[step]
    return out
