"""Reading a line type's drag law (``drag_law``, ``[line_types.NAME.loading]``; the law:
:mod:`.loading`), every key checked into a one-line SceneError."""
from __future__ import annotations

from typing import Any, Mapping

import numpy as np

from ..errors import SceneError
from .checks import _choice, _err, _get, _key, _num_reader, _number, _table
from .loading import DRAG_LAWS, LOADING_KEYS, MAX_HARMONIC, PRESETS, LoadingFunctions

__all__ = ["read_drag_law", "read_loading"]

#: angles (deg) where a law is checked to be >= 0
_CHECK_DEG = np.linspace(0.0, 90.0, 181)


def read_drag_law(path: str, t: Mapping, dim: int):
    """(``drag_law``, its LoadingFunctions or None) of a line type's table ``t``."""
    law = _choice(_key(path, "drag_law"), _get(t, "drag_law", "morison"), DRAG_LAWS, "drag law")
    raw = _get(t, "loading")
    if law == "morison":
        if raw is not None:
            raise _err(_key(path, "loading"), raw, "", 'read only with drag_law = '
                       '"loading-functions" (this line type\'s drag is Morison\'s, from '
                       "cd_normal and cd_tangential): set drag_law, or remove the table")
        return law, None
    if dim != 3:
        raise _err(_key(path, "drag_law"), law, "", 'loading functions are a cable3d option '
                   '(model = "cable3d"); the planar line takes "morison"')
    return law, read_loading(_key(path, "loading"), raw)


def _coefficients(path: str, raw: Any, first: int) -> tuple[float, ...]:
    """A list of at most MAX_HARMONIC + 1 - first finite numbers (k = first, first + 1, ...)."""
    most = MAX_HARMONIC + 1 - first
    what = (f"must be a list of at most {most} numbers, the coefficients of "
            f"{'cos' if first == 0 else 'sin'}(k psi) for k = {first}, {first + 1}, ... "
            f"(dimensionless; up to k = {MAX_HARMONIC})")
    if hasattr(raw, "tolist") and not isinstance(raw, (str, bytes)):
        raw = raw.tolist()
    if not isinstance(raw, (list, tuple)) or len(raw) > most:
        raise _err(path, raw, "", what)
    out = []
    for i, v in enumerate(raw):
        try:
            out.append(_number(f"{path}[{i}]", v))
        except SceneError:
            raise _err(path, list(raw), "", what) from None
    return tuple(out)


def read_loading(path: str, raw: Any) -> LoadingFunctions:
    """``[line_types.NAME.loading]`` at key path ``path`` (``line_types.NAME.loading``) as
    :class:`LoadingFunctions`, every key checked (module docstring)."""
    if raw is None:
        raise SceneError(f"{path}: required key missing (a table with cd, normal_cos / "
                         "normal_sin and tangential_cos / tangential_sin: the Fourier "
                         'coefficients of the loading functions, read with drag_law = '
                         '"loading-functions")')
    if isinstance(raw, str) or (isinstance(raw, Mapping) and "preset" in raw):
        return _preset(path, raw)
    t = _table(path, raw, LOADING_KEYS)
    if _get(t, "cd") is None:
        raise SceneError(f"{_key(path, 'cd')}: required key missing (the reference drag "
                         "coefficient, dimensionless, >= 0: the seed's D_0, Pode's C_R; the "
                         "drag is 0.5 rho d cd |u|^2 f(psi) per metre)")
    cd = _num_reader(path, t)("cd", "", ge=0)
    lists = {k: _coefficients(_key(path, k), _get(t, k, []), 0 if k.endswith("cos") else 1)
             for k in LOADING_KEYS[1:]}
    law = LoadingFunctions(cd, **lists)
    psi = np.radians(_CHECK_DEG)
    for side, f in (("normal", law.f_normal), ("tangential", law.f_tangential)):
        cos, sin = f"{side}_cos", f"{side}_sin"
        if not lists[cos] and not lists[sin]:
            raise SceneError(f"{_key(path, cos)}: required key missing (the cosine "
                             f"coefficients of f_{side[0]}(psi) from k = 0, or {sin}: a loading "
                             "function for each direction; [0.0] for none)")
        values = f(psi)
        scale = sum(abs(v) for v in lists[cos] + lists[sin])
        worst = int(np.argmin(values))
        if values[worst] < -1e-9 * scale:
            key = cos if lists[cos] else sin
            raise _err(_key(path, key), list(lists[key]), "",
                       f"f_{side[0]}({_CHECK_DEG[worst]:g} deg) = {values[worst]:.4g} < 0: a drag "
                       "law must not drive the line (f_n and f_t >= 0 for 0 <= psi <= 90 deg, "
                       "psi the acute angle between the flow and the line)")
    return law


def _preset(path: str, raw: Any) -> LoadingFunctions:
    """A named law (``loading = "NAME"``) or ``{preset = "NAME", cd = ...}``."""
    t = {"preset": raw} if isinstance(raw, str) else _table(path, raw, ("preset", "cd"))
    key = path if isinstance(raw, str) else _key(path, "preset")
    name = t["preset"]
    if name not in PRESETS:
        raise _err(key, name, "", "must be one of " + ", ".join(repr(n) for n in PRESETS)
                   + " (symcable.scene.loading.PRESETS), or a table of coefficients")
    law = PRESETS[name]
    if _get(t, "cd") is None:
        return law
    return LoadingFunctions(_num_reader(path, t)("cd", "", ge=0), law.normal_cos,
                            law.normal_sin, law.tangential_cos, law.tangential_sin)
