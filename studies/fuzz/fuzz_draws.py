"""Random draws for the fuzz study's scene generator (:mod:`fuzz_scenes`): line types by
family, EA within the documented scene checks, segment counts, geometry and loads."""
from __future__ import annotations

import math

import numpy as np

RHO, G = 1025.0, 9.80665
MAX_STRAIN = 0.1          # the scene default (reach check)
WEIGHT_STRAIN = 0.05      # largest |w| L / EA drawn
EA_RANGE = (1e5, 1e10)


def log_uniform(rng, lo, hi):
    return float(math.exp(rng.uniform(math.log(lo), math.log(hi))))


def segments(rng) -> int:
    """1 (3 %), 2 (3 %), 3 (2 %), else log-uniform in 4..60."""
    u = rng.uniform()
    if u < 0.03:
        return 1
    if u < 0.06:
        return 2
    if u < 0.08:
        return 3
    return int(round(log_uniform(rng, 4, 60)))


def line_type(rng, family: str, in_air: bool = False) -> dict:
    """Mass (kg/m) and diameter (m) of a line family; ``weight`` (N/m) only where it must be
    given (weightless lines). EA and EI are added by the caller."""
    if family == "chain":
        d = rng.uniform(0.02, 0.2)
        return {"mass": 19900.0 * d * d, "diameter": d}
    if family == "wire":
        d = rng.uniform(0.02, 0.15)
        return {"mass": 5000.0 * d * d, "diameter": d}
    displaced = RHO * math.pi / 4.0
    if family == "rope":
        d = rng.uniform(0.05, 0.3)
        return {"mass": displaced * d * d * rng.uniform(1.05, 1.4), "diameter": d}
    if family == "neutral":
        d = rng.uniform(0.05, 0.3)
        delta = log_uniform(rng, 1e-4, 1e-2) * (1.0 if rng.uniform() < 0.6 else -1.0)
        return {"mass": displaced * d * d * (1.0 + delta), "diameter": d}
    if family == "buoyant":
        d = rng.uniform(0.1, 0.6)
        return {"mass": displaced * d * d * rng.uniform(0.3, 0.9), "diameter": d}
    if family == "weightless":
        return {"mass": rng.uniform(1.0, 50.0), "diameter": rng.uniform(0.02, 0.2), "weight": 0.0}
    if family == "rod":
        d = rng.uniform(0.05, 0.6)
        return {"mass": displaced * d * d * rng.uniform(1.1, 4.0), "diameter": d}
    raise ValueError(family)


def weight_of(lt: dict, rho: float = RHO) -> float:
    """Submerged weight per length, N/m, as symcable computes it."""
    if "weight" in lt:
        return float(lt["weight"])
    return (lt["mass"] - rho * math.pi * lt["diameter"] ** 2 / 4.0) * G


def draw_ea(rng, w_abs_l: float, load: float) -> float | None:
    """EA log-uniform in EA_RANGE, within |w| L / EA <= WEIGHT_STRAIN and EA <= 0.5e9 load
    (``w_abs_l`` the section's |w| L, ``load`` the line's); None if the range is empty."""
    lo = max(EA_RANGE[0], w_abs_l / WEIGHT_STRAIN)
    hi = EA_RANGE[1] if load <= 0.0 else min(EA_RANGE[1], 0.5e9 * load)
    return log_uniform(rng, lo, hi) if lo < hi else None


class Redraw(Exception):
    """The draws do not make a valid scene: draw again."""


def finish_types(rng, types: dict, lengths: dict, extra_load: float = 0.0,
                 rho: float = RHO) -> None:
    """Give every line type its EA (in place), from its |w| L and the line's total load."""
    load = sum(abs(weight_of(lt, rho)) * lengths[n] for n, lt in types.items()) + extra_load
    for name, lt in types.items():
        ea = draw_ea(rng, abs(weight_of(lt, rho)) * lengths[name], load)
        if ea is None:
            raise Redraw(f"no EA for {name}")
        lt["EA"] = ea


def draw_sections(rng, fams, lo: float, hi: float, drag: bool = False) -> tuple[dict, dict, list]:
    """``(types, lengths, sections)`` of one section per family in ``fams`` (from end A),
    section k's type named ``f"{fam}{k}"``: its line type (with drag coefficients if
    ``drag``), its length log-uniform in [lo, hi] m and its segment count; EA is left to
    :func:`finish_types`."""
    types, lengths, secs = {}, {}, []
    for k, fam in enumerate(fams):
        name = f"{fam}{k}"
        types[name] = line_type(rng, fam)
        if drag:
            drag_coefficients(rng, types[name])
        lengths[name] = log_uniform(rng, lo, hi)
        secs.append({"type": name, "length": lengths[name], "segments": segments(rng)})
    return types, lengths, secs


def free_end_line(rng) -> tuple[str, float, str, dict, float]:
    """The draws a free-end scene starts with: ``(variant, L m, family, types, |w| L N)``; the
    variant one of hanging, end force (twice as likely), current, seabed, weightless with an
    end force and weightless with none."""
    variant = str(rng.choice(["hanging", "end force", "end force", "current", "seabed",
                              "weightless, end force", "weightless, no end force"]))
    L = log_uniform(rng, 5.0, 1000.0)
    fam = "weightless" if variant.startswith("weightless") else str(rng.choice(["chain", "wire", "rope"]))
    types = {fam: line_type(rng, fam)}
    return variant, L, fam, types, abs(weight_of(types[fam])) * L


def polar(d: float, theta: float) -> np.ndarray:
    return np.array([d * math.cos(theta), d * math.sin(theta)])


def pinned(p) -> dict:
    return {"condition": "pinned", "position": [float(p[0]), float(p[1])]}


def single(types: dict, name: str, length: float, n: int, a: dict, b: dict, **extra) -> dict:
    scene = {"line_types": types, "sections": [{"type": name, "length": length, "segments": n}],
             "end_a": a, "end_b": b}
    scene.update(extra)
    return scene


def weight_strain(types: dict, name: str, length: float, rho: float = RHO) -> float:
    return abs(weight_of(types[name], rho)) * length / types[name]["EA"]


def taut_ratio(rng, c: float) -> float:
    """Chord over length of a taut or nearly taut line whose weight strain is ``c``."""
    u = rng.uniform()
    if u < 0.4:
        return rng.uniform(0.97, 0.999)
    if u < 0.6:
        return rng.uniform(0.999, 1.0)
    return 1.0 + min(c * log_uniform(rng, 0.1, 20.0), 0.5 * MAX_STRAIN)


def origin(rng) -> np.ndarray:
    return np.array([rng.uniform(-1000.0, 1000.0), rng.uniform(-500.0, 0.0)])


def env_seabed(rng, depth: float) -> dict:
    extra = {"environment": {"depth": float(depth)}}
    if rng.uniform() < 0.7:
        extra["seabed"] = {"stiffness": log_uniform(rng, 1e4, 1e7)}
    return extra


def flip_ends(scene: dict) -> dict:
    """The same line described from the other end (sections reversed, ends swapped)."""
    scene["sections"] = scene["sections"][::-1]
    scene["end_a"], scene["end_b"] = scene["end_b"], scene["end_a"]
    return scene


def current_env(rng) -> dict:
    u = rng.uniform(0.1, 2.0) * rng.choice([-1.0, 1.0])
    uz = rng.uniform(-0.2, 0.2) if rng.uniform() < 0.3 else 0.0
    return {"current": [float(u), float(uz)]}


def drag_coefficients(rng, lt: dict) -> None:
    lt["cd_normal"] = rng.uniform(0.8, 2.5)
    lt["cd_tangential"] = rng.uniform(0.0, 0.5)


def bending_stiffness(rng, w_abs: float, L: float) -> float:
    return float(np.clip(max(w_abs, 1.0) * L ** 3 * log_uniform(rng, 1e-8, 1.0), 10.0, 1e9))


def end_force(rng, scale: float) -> list:
    return [float(v) for v in polar(scale * log_uniform(rng, 0.1, 10.0), rng.uniform(-math.pi, math.pi))]
