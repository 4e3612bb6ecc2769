"""What counts as working, for the conformance matrix (matrix.py): a result without NaN, its
``summary()`` a str, its figure written and not blank, its save/load round trip exact."""
from __future__ import annotations

import dataclasses
import shutil
from pathlib import Path
from typing import Callable, Mapping

import numpy as np


class Failure(Exception):
    """A check that failed after the analysis ran (always FAIL, never a refusal)."""


def _items(obj):
    """The named parts of a result: dataclass fields, mapping items, sequence elements."""
    if dataclasses.is_dataclass(obj) and not isinstance(obj, type):
        return [(f.name, getattr(obj, f.name)) for f in dataclasses.fields(obj)]
    if isinstance(obj, Mapping):
        return [(str(k), v) for k, v in obj.items()]
    if isinstance(obj, (list, tuple)):
        return [(str(k), v) for k, v in enumerate(obj)]
    return None


def nan_paths(obj, path: str = "", depth: int = 0) -> list[str]:
    """Where a result holds a NaN (field paths such as ``lines.cable.tension``)."""
    if isinstance(obj, np.ndarray) and obj.dtype.kind in "fc":
        return [path or "result"] if np.isnan(obj).any() else []
    if isinstance(obj, (float, np.floating)):
        return [path or "result"] if np.isnan(obj) else []
    items = _items(obj) if depth < 8 else None
    if not items:
        return []
    return [p for k, v in items for p in nan_paths(v, f"{path}.{k}" if path else k, depth + 1)]


def _kind(a: np.ndarray) -> str:
    return {"u": "i"}.get(a.dtype.kind, a.dtype.kind)


def first_difference(a, b, path: str = "result") -> str | None:
    """Where ``b`` (read back) differs from ``a`` (saved): None when equal exactly, NaN
    equal to NaN; an array must come back an array of the same kind (bool, int, float),
    except in ``stats`` (plain JSON inside a saved file), where a list of the same values
    will do."""
    if isinstance(a, np.ndarray) and isinstance(b, (list, tuple)) and in_stats(path):
        b = np.asarray(b, dtype=a.dtype if a.dtype.kind in "biufc" else None)
    if isinstance(a, np.ndarray):
        if not isinstance(b, np.ndarray):
            return f"{path}: array came back as {type(b).__name__}"
        if a.shape != b.shape or _kind(a) != _kind(b):
            return f"{path}: {a.dtype}{a.shape} came back as {b.dtype}{b.shape}"
        if a.dtype.kind in "biufc":
            same = np.array_equal(a, b, equal_nan=a.dtype.kind in "fc")
        else:
            same = a.tolist() == b.tolist()
        return None if same else f"{path}: values differ"
    items_a, items_b = _items(a), _items(b)
    if items_a is not None:
        if items_b is None:
            return f"{path}: {type(a).__name__} came back as {type(b).__name__}"
        keys_a, keys_b = [k for k, _ in items_a], [k for k, _ in items_b]
        if keys_a != keys_b:
            return f"{path}: keys {keys_a[:6]} came back as {keys_b[:6]}"
        for (k, va), (_, vb) in zip(items_a, items_b):
            d = first_difference(va, vb, f"{path}.{k}")
            if d:
                return d
        return None
    if isinstance(b, np.ndarray) and isinstance(a, (list, tuple)):  # a list read as an array
        same = np.asarray(a).shape == b.shape and all(
            first_difference(x, y) is None for x, y in zip(np.ravel(a).tolist(), b.ravel()))
        return None if same else f"{path}: values differ"
    if _number(a) and _number(b):
        same = a == b or (np.isnan(a) and np.isnan(b))
    elif isinstance(a, (bool, np.bool_)) and isinstance(b, (bool, np.bool_)):
        same = bool(a) == bool(b)
    else:
        same = type(a) is type(b) and a == b
    return None if same else f"{path}: {a!r} came back as {b!r}"


def _number(x) -> bool:
    return isinstance(x, (int, float, np.integer, np.floating)) and not isinstance(x, bool)


def check_plot(path: Path) -> None:
    """The figure file exists, is a readable image and is not one flat colour."""
    if not path.is_file() or path.stat().st_size == 0:
        raise Failure(f"plot not written: {path.name}")
    import matplotlib.image as mpimg
    img = mpimg.imread(path)
    if np.ptp(img[..., :3]) == 0:
        raise Failure(f"plot {path.name} is blank (one colour)")


def check_result(result, stem: Path) -> list[str]:
    """Checks of an API result after the analysis ran: no NaN, ``summary()`` a str, ``plot``
    writes a file, ``save``/``load`` exact for .npz and .json. Raises Failure; returns notes."""
    notes = []
    if isinstance(result, np.ndarray):
        if result.ndim != 2 or result.shape[0] != result.shape[1] or \
                not np.all(np.isfinite(result)):
            raise Failure(f"stiffness not a finite square matrix: shape {result.shape}")
        return notes
    if isinstance(result, list):  # export_scene: the files written
        empty = [str(p) for p in result if not Path(p).is_file() or Path(p).stat().st_size == 0]
        if empty or not result:
            raise Failure(f"export wrote no or empty files: {empty}")
        return notes
    nans = nan_paths(result)
    if [p for p in nans if not in_stats(p)]:
        raise Failure(f"NaN in the result: {', '.join(nans[:4])}")
    notes += [f"NaN in {p}" for p in nans]
    if not hasattr(result, "summary"):
        notes.append(f"{type(result).__name__} has no summary()")
    elif not isinstance(result.summary(), str):
        raise Failure(f"{type(result).__name__}.summary() is not a str")
    if not hasattr(result, "plot"):
        notes.append(f"{type(result).__name__} has no plot()")
    else:
        png = fresh(stem.with_suffix(".png"))
        close_figures(guarded(f"{type(result).__name__}.plot(path)", lambda: result.plot(png)))
        check_plot(png)
    if hasattr(result, "save"):
        for suffix in (".npz", ".json"):
            path = fresh(stem.with_name(stem.name + "_api" + suffix))
            back = guarded(f"{type(result).__name__}.save/load({suffix})",
                         lambda: (result.save(path), type(result).load(path))[1])
            diff = first_difference(result, back)
            if diff:
                raise Failure(f"{suffix} round trip not exact: {diff}")
    return notes


def fresh(path: Path) -> Path:
    """``path`` with no file or folder left there from an earlier run (which would pass for
    written)."""
    if path.is_dir():
        shutil.rmtree(path)
    path.unlink(missing_ok=True)
    return path


def in_stats(path: str) -> bool:
    """A NaN in a result's ``stats`` (a number not computed) is a note, not a FAIL (its
    round trip still has to be exact)."""
    return "stats" in path.split(".")


def guarded(what: str, fn: Callable):
    """``fn()``; any exception, even a SymcableError, is a Failure naming ``what``."""
    try:
        return fn()
    except Exception as exc:
        raise Failure(f"{what}: {type(exc).__name__}: {one_line(exc)}") from exc


def close_figures(fig) -> None:
    import matplotlib.pyplot as plt
    plt.close(fig if fig is not None else "all")


def one_line(exc) -> str:
    return " ".join(str(exc).split()) or repr(exc)


def trace_ends(tb: str) -> str:
    """A traceback's first frame and last lines (where it was raised)."""
    lines = [ln for ln in tb.strip().splitlines() if ln.strip()]
    return "\n".join(lines[:3] + ["..."] + lines[-4:]) if len(lines) > 8 else "\n".join(lines)


def stray_notes(lines: list[str]) -> list[str]:
    """A note on what else was written to stderr (its first line and its length)."""
    lines = [ln for ln in lines if ln.strip()]
    return [f"stderr: {lines[0].strip()[:160]!r}" + (f" (+{len(lines) - 1} lines)"
                                                     if len(lines) > 1 else "")] if lines else []
