"""Exact save and load of result trees: nested dicts, lists, tuples, NumPy arrays and plain
numbers, to ``.json`` or ``.npz``, read back equal (arrays with their dtype and shape, NaN and
infinities, tuples as tuples, floats bit for bit).

JSON has no arrays, NaN or tuples, so they are written as small tagged objects:
``{"__ndarray__": nested lists, "dtype": "<f8", "shape": [..]}`` (a non-finite entry as the
string ``"nan"``, ``"inf"`` or ``"-inf"``), ``{"__float__": "nan"}``,
``{"__tuple__": [...]}``, and ``{"__dict__": [[key, value], ...]}`` for a dict whose keys
are not all plain strings. In ``.npz`` every array is stored as an array of the archive
(``{"__array__": "a3"}`` in the tree), the tree as JSON in ``__tree__``.
"""
from __future__ import annotations

import json
import math
from pathlib import Path
from types import MappingProxyType

import numpy as np

from ..errors import SymcableError

__all__ = ["decode", "encode", "force_text", "force_unit", "read_tree", "write_tree"]

_NONFINITE = {"nan": math.nan, "inf": math.inf, "-inf": -math.inf}

#: the prefixes a printed force (or moment, stiffness) takes by its magnitude
_PREFIXES = ((1e9, "G"), (1e6, "M"), (1e3, "k"))


def force_unit(values, unit: str = "N") -> tuple[float, str]:
    """``(factor, unit text)`` to print ``values`` (in ``unit``: N, N m, N/m, N m/rad) with:
    G, M or k as their largest finite magnitude reaches 1e9, 1e6 or 1e3, else the unit
    itself (a rod's 0.01 N stays in N, not "0.0000 kN"). Values printed together share it."""
    a = np.abs(np.asarray(values, dtype=float)).ravel()
    a = a[np.isfinite(a)]
    big = float(a.max()) if a.size else 0.0
    for factor, prefix in _PREFIXES:
        if big >= factor:
            return factor, prefix + unit
    return 1.0, unit


def force_text(values, unit: str = "N", spec: str = ".4g", sep: str = " .. ",
               names=None) -> str:
    """``values`` (one number, or several: a range ``lo .. hi``, components) in the unit
    :func:`force_unit` chooses, each formatted with ``spec`` and joined by ``sep`` (with
    ``names``, each preceded by its name: ``"Fx 1.2, Fz 3.4 kN"``). A fixed-point ``spec``
    (``".4f"``) keeps its decimals while the largest value is at least 1 in the unit chosen,
    and below that (forces under 1 N) takes as many as give the largest 4 significant
    figures (down to 1e-6; below, 4 significant figures each); a value that rounds to zero
    prints without its sign."""
    v = np.atleast_1d(np.asarray(values, dtype=float)).ravel()
    factor, text = force_unit(v, unit)
    a = np.abs(v[np.isfinite(v)]) / factor
    big = float(a.max()) if a.size else 0.0
    if spec.endswith("f") and big < 1.0:
        spec = f".{3 - math.floor(math.log10(big))}f" if big >= 1e-6 else ".4g"
    parts = [format(x / factor, spec) for x in v]
    parts = [p[1:] if p.startswith("-") and not p.strip("-0.") else p for p in parts]
    if names is not None:
        parts = [f"{n} {p}" for n, p in zip(names, parts)]
    return f"{sep.join(parts)} {text}"


def _float_tag(x: float):
    """``x`` as JSON: itself when finite, else its tag string."""
    if math.isfinite(x):
        return x
    return "nan" if math.isnan(x) else ("inf" if x > 0 else "-inf")


def _nested(a: np.ndarray):
    """An array's entries as nested lists, non-finite floats as tag strings; a complex
    array as [real part, imaginary part]."""
    if a.dtype.kind == "c":
        return [_nested(a.real), _nested(a.imag)]
    if a.dtype.kind == "f" and not np.all(np.isfinite(a)):
        return np.array([_float_tag(float(x)) for x in a.ravel()], dtype=object) \
            .reshape(a.shape).tolist()
    return a.tolist()


def _untag(data):
    """Nested lists with the tag strings of :func:`_float_tag` back to floats."""
    if isinstance(data, list):
        return [_untag(x) for x in data]
    return _NONFINITE[data] if isinstance(data, str) else data


def encode(v, arrays: dict | None = None):
    """``v`` as plain JSON values, tagged where JSON cannot say it exactly; arrays go to
    ``arrays`` (name -> ndarray, for ``.npz``) when it is given, else inline."""
    if isinstance(v, np.ndarray):
        if v.dtype == object:
            raise SymcableError("cannot save an array of Python objects")
        if arrays is not None:
            key = f"a{len(arrays)}"
            arrays[key] = v
            return {"__array__": key}
        return {"__ndarray__": _nested(v), "dtype": v.dtype.str, "shape": list(v.shape)}
    if isinstance(v, np.generic):
        v = v.item()
    if isinstance(v, float):
        return v if math.isfinite(v) else {"__float__": _float_tag(v)}
    if isinstance(v, tuple):
        return {"__tuple__": [encode(x, arrays) for x in v]}
    if isinstance(v, list):
        return [encode(x, arrays) for x in v]
    if isinstance(v, (dict, MappingProxyType)):
        if all(isinstance(k, str) and not k.startswith("__") for k in v):
            return {k: encode(x, arrays) for k, x in v.items()}
        return {"__dict__": [[encode(k, arrays), encode(x, arrays)] for k, x in v.items()]}
    if v is None or isinstance(v, (str, bool, int)):
        return v
    raise SymcableError(f"cannot save a value of type {type(v).__name__}")


def _array_from(data, dtype: str, shape) -> np.ndarray:
    """The array of a ``__ndarray__`` tag."""
    dt = np.dtype(dtype)
    if dt.kind == "c":
        re, im = (np.asarray(_untag(x), dtype=float).reshape(shape) for x in data)
        return (re + 1j * im).astype(dt)
    if dt.kind == "f":
        data = _untag(data)
    return np.asarray(data, dtype=dt).reshape(shape)


def decode(v, arrays=None):
    """The value :func:`encode` encoded (``arrays``: the ``.npz`` archive's arrays)."""
    if isinstance(v, list):
        return [decode(x, arrays) for x in v]
    if not isinstance(v, dict):
        return v
    if "__ndarray__" in v:
        return _array_from(v["__ndarray__"], v["dtype"], tuple(v["shape"]))
    if "__array__" in v:
        return np.asarray(arrays[v["__array__"]])
    if "__float__" in v:
        return _NONFINITE[v["__float__"]]
    if "__tuple__" in v:
        return tuple(decode(x, arrays) for x in v["__tuple__"])
    if "__dict__" in v:
        return {decode(k, arrays): decode(x, arrays) for k, x in v["__dict__"]}
    return {k: decode(x, arrays) for k, x in v.items()}


def write_tree(path: str | Path, tree: dict) -> Path:
    """Write ``tree`` (a dict of result fields) to ``path``: ``.json`` or ``.npz`` by
    suffix; :func:`read_tree` reads it back equal."""
    path = Path(path)
    if path.suffix == ".json":
        path.write_text(json.dumps(encode(tree), indent=1, allow_nan=False))
    elif path.suffix == ".npz":
        arrays: dict = {}
        text = json.dumps(encode(tree, arrays), allow_nan=False)
        np.savez(path, __tree__=np.array(text), **arrays)
    else:
        raise SymcableError(f"save path = '{path}': suffix must be .npz or .json")
    return path


def read_tree(path: str | Path) -> dict:
    """The tree :func:`write_tree` wrote (or a file of the earlier format: plain JSON, or an
    ``.npz`` with its non-array fields as JSON in ``__meta__``)."""
    path = Path(path)
    if path.suffix == ".json":
        return decode(json.loads(path.read_text()))
    if path.suffix != ".npz":
        raise SymcableError(f"load path = '{path}': suffix must be .npz or .json")
    with np.load(path, allow_pickle=False) as z:
        if "__tree__" in z.files:
            arrays = {k: z[k] for k in z.files if k != "__tree__"}
            return decode(json.loads(str(z["__tree__"])), arrays)
        d = json.loads(str(z["__meta__"]))
        d.update({k: z[k] for k in z.files if k != "__meta__"})
        return d
