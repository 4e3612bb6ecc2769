"""Scenes with more or fewer segments: the same cable, discretised afresh.

Used to estimate a static answer's discretisation error (a second solve at other segment
counts) and to refine a line until that error meets a tolerance.
"""
from __future__ import annotations

import dataclasses
from typing import Mapping

from .model import Scene

__all__ = ["scaled_segments", "line_segments"]

#: the name of a one-line scene's line in per-line results (``solution.lines``)
ONE_LINE = "line"


def line_segments(scene: Scene) -> dict:
    """Segments per line, ``{name: n}`` (a one-line scene's line is ``"line"``)."""
    if scene.version == 1:
        return {ONE_LINE: sum(s.segments for s in scene.sections)}
    return {ln.name: ln.n_segments for ln in scene.lines}


def _scaled(sections, factor: float) -> tuple:
    return tuple(dataclasses.replace(s, segments=max(1, int(round(s.segments * factor))))
                 for s in sections)


def scaled_segments(scene: Scene, factors: float | Mapping[str, float]) -> Scene:
    """``scene`` with each section's segment count multiplied by a factor (rounded, at least
    1): one factor for every line, or ``{line name: factor}`` (lines not named keep theirs;
    a one-line scene's line is ``"line"``). Lengths, types and ends are unchanged."""
    def factor(name):
        if isinstance(factors, Mapping):
            return factors.get(name, 1.0)
        return float(factors)
    if scene.version == 1:
        return dataclasses.replace(scene, sections=_scaled(scene.sections, factor(ONE_LINE)))
    lines = tuple(dataclasses.replace(ln, sections=_scaled(ln.sections, factor(ln.name)))
                  for ln in scene.lines)
    return dataclasses.replace(scene, lines=lines)
