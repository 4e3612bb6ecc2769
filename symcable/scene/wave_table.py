"""The reader of ``[environment.waves]`` (:class:`~.waves.Waves`): one clear message per bad
key."""
from __future__ import annotations

from typing import Any

from ..errors import SceneError
from .checks import _choice, _err, _get, _integer, _num_reader, _number, _table
from .waves import STRETCHING, WAVE_KINDS, Waves

__all__ = ["MAX_WAVE_COMPONENTS", "read_waves"]

#: most components of one sea: each costs its arithmetic at every element and time step
MAX_WAVE_COMPONENTS = 2000

_COMMON = ("kind", "direction_deg", "stretching", "ramp")
_KEYS = {"regular": ("height", "period", "phase_deg"),
         "jonswap": ("hs", "tp", "gamma", "components", "band", "seed"),
         "pierson-moskowitz": ("hs", "tp", "components", "band", "seed"),
         "components": ("amplitudes", "omegas", "phases_deg", "directions_deg")}
_PATH = "environment.waves"


def read_waves(raw: Any, dim: int, water_density: float) -> Waves | None:
    """``[environment.waves]`` as :class:`Waves` (None when absent); ``dim`` the scene's
    dimension (waves are a 3D option), ``water_density`` (kg/m^3; 0 is air, with no waves)."""
    if raw is None:
        return None
    if not isinstance(raw, dict):
        raise _err(_PATH, raw, "", "must be a table with key kind (one of "
                                   f"{', '.join(map(repr, WAVE_KINDS))}) and its numbers")
    kind = _choice(f"{_PATH}.kind", _get(raw, "kind", "regular"), WAVE_KINDS, "kind of waves")
    t = _table(_PATH, raw, _COMMON + _KEYS[kind])
    if dim != 3:
        raise _err(_PATH, kind, "", "waves act on 3D lines, points and bodies (model = "
                                    "'cable3d' or a scene of [[lines]]); a planar line takes "
                                    "a current and end motions")
    if water_density == 0.0:
        raise _err(_PATH, kind, "", "a scene in air (environment.water_density = 0) has no "
                                    "waves: give the water's density or remove the waves")
    num = _num_reader(_PATH, t)
    common = dict(direction_deg=num("direction_deg", "deg", 0.0),
                  stretching=_choice(f"{_PATH}.stretching", _get(t, "stretching", "vertical"),
                                     STRETCHING, "stretching"),
                  ramp=None if _get(t, "ramp") is None else num("ramp", "s", gt=0))
    if kind == "regular":
        return Waves(kind=kind, height=num("height", "m", ge=0), period=num("period", "s", gt=0),
                     phase_deg=num("phase_deg", "deg", 0.0), **common)
    if kind == "components":
        return Waves(kind=kind, **_components(t), **common)
    n = _integer(f"{_PATH}.components", _get(t, "components", 200), ge=1)
    if n > MAX_WAVE_COMPONENTS:
        raise _err(f"{_PATH}.components", n, "", f"must be at most {MAX_WAVE_COMPONENTS} "
                   "(each component is evaluated at every element and time step)")
    tp = num("tp", "s", gt=0)
    band = _get(t, "band")
    if band is not None:
        band = _band(band)
    return Waves(kind=kind, hs=num("hs", "m", ge=0), tp=tp,
                 gamma=num("gamma", "", 3.3, ge=1) if kind == "jonswap" else 1.0,
                 components=n, band=band,
                 seed=_integer(f"{_PATH}.seed", _get(t, "seed", 0), ge=0), **common)


def _band(raw) -> tuple[float, float]:
    key = f"{_PATH}.band"
    if not isinstance(raw, (list, tuple)) or len(raw) != 2:
        raise _err(key, raw, "rad/s", "must be [low, high], angular frequencies with "
                                      "0 < low < high")
    lo, hi = (_number(f"{key}[{i}]", v, "rad/s", gt=0) for i, v in enumerate(raw))
    if not lo < hi:
        raise _err(key, raw, "rad/s", "must be [low, high] with low < high")
    return lo, hi


def _components(t) -> dict:
    """``kind = "components"``: equal-length lists, at least one component."""
    lists = {}
    for key, unit, lower in (("amplitudes", "m", "ge"), ("omegas", "rad/s", "gt"),
                             ("phases_deg", "deg", None), ("directions_deg", "deg", None)):
        raw = _get(t, key)
        if raw is None:
            if key == "directions_deg":
                continue
            raise SceneError(f"{_PATH}.{key}: required key missing (a list of numbers, {unit}, "
                             "one per component)")
        if hasattr(raw, "tolist"):
            raw = raw.tolist()
        if not isinstance(raw, (list, tuple)) or not raw:
            raise _err(f"{_PATH}.{key}", raw, unit, "must be a non-empty list of numbers, one "
                                                   "per component")
        bound = {lower: 0.0} if lower else {}
        lists[key] = tuple(_number(f"{_PATH}.{key}[{i}]", v, unit, **bound)
                           for i, v in enumerate(raw))
    n = len(lists["amplitudes"])
    if n > MAX_WAVE_COMPONENTS:
        raise _err(f"{_PATH}.amplitudes", f"<{n} values>", "m",
                   f"at most {MAX_WAVE_COMPONENTS} components")
    for key, values in lists.items():
        if len(values) != n:
            raise _err(f"{_PATH}.{key}", f"<{len(values)} values>", "",
                       f"must have one value per component: {n}, as amplitudes")
    return lists
