"""Static solutions checked against the free surface.

symcable has no free surface: every line, free point and free body is loaded as submerged
(its buoyancy, drag and added mass in water of ``environment.water_density``) wherever it
is; the free surface is z = 0 (the README's "A scene file"). What the scene's held ends put
out of the water is refused when the scene is read
(:func:`symcable.scene.checks._check_free_surface`); what the static solve puts there is
checked here, on the solution (a scene in air, ``water_density = 0``, is not checked):

- a free body or free point with buoyancy (``volume > 0``) whose centre of buoyancy ends
  above the surface (a body's ``center_of_buoyancy`` at its solved pose, a point's
  position) is refused, :class:`AboveWaterError`. A body whose centre of buoyancy is above
  z = 0 cannot be displacing its whole volume, yet its whole buoyancy is counted: there is
  no waterplane to lose it as the body rises, so a body lighter than its buoyancy rises
  until its lines stop it, and that pose, and every tension it sets, is not an equilibrium
  of the real body (which would float lower, at its draught). The error is the whole
  buoyancy, not a part of it, and nothing in the solution says so: hence a refusal, not a
  warning. (Below the surface the body may still break it, its shape being unknown: only
  the certain case is refused.)
- a line whose buoyant section (net buoyancy, ``weight < 0``) the solve lifts above the
  surface where nothing holds it (a node above z = 0 higher than its neighbours, or a free
  end, or an end at a free point) is refused, :class:`AboveWaterError`, for the reason a
  buoyant point is: its buoyancy is counted in full above the water, so it rises until the
  rest of the line stops it, and the shape and every tension are not those of the real
  line (which would float at the surface). A buoyant section rising to a held end above
  the water is a line leaving the water, the next case;
- a line with more than half of its length above the surface gets a warning (the
  solution's ``warnings``), naming how much and the weight left out there. The part of a
  line above the water has its weight counted short by its buoyancy, and drag and added
  mass where there is no water: an error in proportion to its length, which is accepted for
  a line rising to a fairlead or towpoint above the surface (no message), and stated when
  the line is mostly in air.
"""
from __future__ import annotations

import dataclasses
from types import MappingProxyType

import numpy as np

from ..errors import SymcableError
from ..scene.bodies import rotation_rpy

__all__ = ["AboveWaterError", "above_water_warnings", "check_above_water",
           "line_above_water"]

#: a line is "mostly out of the water" above this fraction of its unstretched length
MOSTLY = 0.5


class AboveWaterError(SymcableError):
    """A static solve put a free body or free point with buoyancy above the free surface
    (:mod:`symcable.api.above_water`). The message is one line naming the body or point,
    where it ended and what to change; ``solution`` is the solve's result, for inspection
    (not an answer: its pose is not an equilibrium of the real body)."""

    def __init__(self, message: str, solution=None):
        super().__init__(message)
        self.solution = solution


def _z(x: float) -> str:
    return f"{x:+.3g}" if abs(x) < 1e3 else f"{x:+.4g}"


def check_above_water(scene, solution):
    """``solution`` (a static solution of ``scene``; a failed one is returned as it is)
    checked against the free surface (module docstring): raises :class:`AboveWaterError`
    for a free body or free point with buoyancy floated above the surface; else returns the
    solution, with a warning added for each line mostly above the surface, once (the same
    object when there is none).

    Parameters
    ----------
    scene : Scene
    solution : StaticSolution or SystemStaticSolution

    Raises
    ------
    AboveWaterError
        One line: ``bodies.NAME: ...`` or ``points.NAME: ...``.
    """
    if scene.environment.in_air or solution.status != "converged":
        return solution  # a failed solve's partial result is no answer to check
    _check_floating(scene, solution)
    _check_lines_floating(scene, solution)
    new = [(name, text) for name, text in _mostly_up(scene, solution)
           if text not in solution.warnings]  # checked once already: the same solution
    if not new:
        return solution
    warnings = tuple(solution.warnings) + tuple(text for _, text in new)
    if scene.version == 1:  # one line: a StaticSolution
        return dataclasses.replace(solution, warnings=warnings)
    lines = dict(solution.lines)
    for name, text in new:
        lines[name] = dataclasses.replace(lines[name],
                                          warnings=tuple(lines[name].warnings) + (text,))
    return dataclasses.replace(solution, lines=MappingProxyType(lines), warnings=warnings)


def _check_floating(scene, solution) -> None:
    """Raise AboveWaterError for the first free body or free point with buoyancy whose
    centre of buoyancy the solution puts above z = 0."""
    env = scene.environment
    rho_g = env.water_density * env.gravity
    for name, body in scene.bodies.items():
        if not (body.is_free and body.volume > 0):
            continue
        st = solution.bodies[name]
        R = rotation_rpy(np.asarray(st.roll_pitch_yaw, float))
        cb = np.asarray(st.position, float) + R @ np.asarray(body.center_of_buoyancy, float)
        if cb[-1] > 0.0:
            where = (f"its centre of buoyancy at z = {_z(cb[-1])} m" if any(
                body.center_of_buoyancy) else f"z = {_z(cb[-1])} m")
            raise AboveWaterError(
                f"bodies.{name}: the static solve floats it to {where}, above the free "
                f"surface (z = 0), with its buoyancy (volume {body.volume:g} m^3, "
                f"{rho_g * body.volume:.4g} N) still counted in full: symcable has no "
                "waterplane, a body's buoyancy is constant wherever it is, so this is not "
                "an equilibrium of the real body (it would float lower); give it more mass "
                "or less volume, shorter lines, or hold it (kind = 'fixed'; MoorDyn "
                "'Coupled')", solution)
    for name, pt in scene.points.items():
        if not (pt.is_free and pt.volume > 0):
            continue
        z = float(np.ravel(solution.points[name].position)[-1])
        if z > 0.0:
            raise AboveWaterError(
                f"points.{name}: the static solve floats it to z = {_z(z)} m, above the "
                f"free surface (z = 0), with its buoyancy (volume {pt.volume:g} m^3, "
                f"{rho_g * pt.volume:.4g} N) still counted in full: symcable has no free "
                "surface, a point's buoyancy is constant wherever it is, so this is not an "
                "equilibrium of the real buoy (it would float lower); give it more mass or "
                "less volume (volume = 0 for a point in air), shorter lines, or hold it "
                "(kind = 'vessel' or 'fixed')", solution)


def _loose_ends(scene, name) -> tuple[bool, bool]:
    """Whether end A / B of a line (``name``; None: the one line) is free to rise: a free
    end, or an end at a free point."""
    if name is None:
        return tuple(e.condition.name == "FREE" for e in (scene.end_a, scene.end_b))
    line = next(ln for ln in scene.lines if ln.name == name)
    out = []
    for end in (line.end_a, line.end_b):
        if isinstance(end, str):
            out.append(bool(scene.points[end].is_free))
        else:
            cond = getattr(end, "condition", None)
            out.append(cond is not None and cond.name == "FREE")
    return tuple(out)


def _check_lines_floating(scene, solution) -> None:
    """Raise AboveWaterError for the first line with a buoyant section floated above z = 0
    (module docstring): a node of a buoyant section above the surface and no lower than
    its neighbours, not a held end."""
    for name, label, sections, sol in _line_solutions(scene, solution):
        weights = np.array([sec.line_type.weight for sec in sections])
        if not np.any(weights < 0):
            continue
        z = np.asarray(sol.positions, float)[:, -1]
        s = np.asarray(sol.s, float)
        n = z.size
        if n < 2 or not np.any(z > 0):
            continue
        edges = np.cumsum([sec.length for sec in sections])
        mid = np.minimum(np.searchsorted(edges, 0.5 * (s[:-1] + s[1:])), len(sections) - 1)
        seg_buoyant = weights[mid] < 0
        buoyant = np.zeros(n, bool)
        buoyant[:-1] |= seg_buoyant
        buoyant[1:] |= seg_buoyant
        up_a = np.r_[True, z[1:] >= z[:-1]]
        up_b = np.r_[z[:-1] >= z[1:], True]
        peak = (z > 0) & buoyant & up_a & up_b
        loose = _loose_ends(scene, name)
        peak[0] &= loose[0]
        peak[-1] &= loose[-1]
        if not peak.any():
            continue
        i = int(np.flatnonzero(peak)[np.argmax(z[peak])])
        k = int(mid[min(i, n - 2)] if seg_buoyant[min(i, n - 2)] else mid[max(i - 1, 0)])
        sec = sections[k]
        raise AboveWaterError(
            f"{label}: the static solve floats its buoyant sections[{k}] (net buoyancy "
            f"{-sec.line_type.weight:.4g} N/m) to z = {_z(z[i])} m at s = {s[i]:.4g} m, above "
            "the free surface (z = 0), with its buoyancy still counted in full: symcable has "
            "no free surface, so this is not an equilibrium of the real line (it would float "
            "at the surface); shorten or weigh down the buoyant section, or lower the line",
            solution)


def _segments_above(s, positions) -> np.ndarray:
    """(n - 1,) the unstretched length of each segment above z = 0, m: a segment crossing
    the surface cut where it does (z linear along it)."""
    z = np.asarray(positions, float)[:, -1]
    za, zb = z[:-1], z[1:]
    with np.errstate(divide="ignore", invalid="ignore"):
        cut = np.nan_to_num(np.where(za > 0, za, zb) / np.abs(za - zb))
    frac = np.where((za > 0) & (zb > 0), 1.0,
                    np.where((za > 0) | (zb > 0), np.clip(cut, 0.0, 1.0), 0.0))
    return frac * np.diff(np.asarray(s, float))


def line_above_water(sections, s, positions, gravity: float) -> tuple[float, float]:
    """``(length, short)`` of a solved line: its unstretched length above the free surface
    (m) and the weight counted short there (N): (mass g - weight) per metre of each section,
    its buoyancy for the default submerged weight.

    ``sections`` are the line's (from end A), ``s`` (n,) the nodes' unstretched arc length
    from end A and ``positions`` (n, dim) their positions, z last."""
    s = np.asarray(s, float)
    up = _segments_above(s, positions)
    edges = np.cumsum([sec.length for sec in sections])
    k = np.minimum(np.searchsorted(edges, 0.5 * (s[:-1] + s[1:])), len(sections) - 1)
    per_m = np.array([max(sec.line_type.mass * gravity - sec.line_type.weight, 0.0)
                      for sec in sections])
    return float(np.sum(up)), float(np.sum(up * per_m[k]))


def _line_solutions(scene, solution):
    """``[(name, label, sections, StaticSolution)]``, one per line (name None: one line)."""
    if scene.version == 1:
        return [(None, "the line", scene.sections, solution)]
    return [(ln.name, f"lines[{i}] ({ln.name!r})", ln.sections, solution.lines[ln.name])
            for i, ln in enumerate(scene.lines)]


def _mostly_up(scene, solution) -> list:
    """``[(name, text)]``: the warning of each line more than MOSTLY above the surface."""
    out = []
    for name, label, sections, sol in _line_solutions(scene, solution):
        length = sum(sec.length for sec in sections)
        up, short = line_above_water(sections, sol.s, sol.positions,
                                     scene.environment.gravity)
        if not up > MOSTLY * length:
            continue
        top = float(np.max(np.asarray(sol.positions, float)[:, -1]))
        out.append((name, f"{label}: {up:.4g} m of its {length:.4g} m "
                          f"({100 * up / length:.0f} %) lies above the free surface (z = 0, "
                          f"up to z = {_z(top)} m) yet is loaded as submerged (symcable has "
                          f"no free surface): its weight there is counted {short:.4g} N short "
                          "(dry less submerged weight), with drag and added mass where there "
                          "is no water; lower the line into the water, or set "
                          "environment.water_density = 0 for a line in air"))
    return out


def above_water_warnings(scene, solution) -> tuple:
    """The warnings :func:`check_above_water` adds to ``solution``: one per line with more
    than half of its length above the free surface (none in air)."""
    if scene.environment.in_air:
        return ()
    return tuple(text for _, text in _mostly_up(scene, solution))
