"""The time integrators' cache: what is built once per Mechanism (step Functions, their
compiled libraries, stability limits), kept in one explicit object, and the choice of
generated C for a step Function.

The entries live on the Mechanism (:class:`~symcable.mechanism.attached.Attached`): a
Mechanism that is no longer used frees them with it, even when an entry refers back to it.
"""
from __future__ import annotations

import itertools
from typing import Callable

from ..mechanism.attached import Attached
from ..mechanism import background_build
from ..mechanism.codegen import (DEFAULT_MAX_SIZE, compile_functions, graph_size, last_build,
                                  use_codegen)

__all__ = ["STEP_CACHE", "StepCache", "maybe_compiled", "structure_owner"]


class StepCache:
    """``get(mech, key, build)``: the value stored for ``(mech, key)``, built by ``build()``
    on first use. Keys are tuples naming what the value depends on beyond the Mechanism."""

    _ids = itertools.count()

    def __init__(self):
        #: ``store[mech]``: the dict of mech's entries by key
        self.store = Attached(f"steps{next(self._ids)}")

    def get(self, mech, key: tuple, build: Callable):
        entries = self.store.setdefault(mech, dict)
        if key not in entries:
            entries[key] = build()
        return entries[key]

    def find(self, mech, key: tuple):
        """The value stored for ``(mech, key)``, or None (nothing built)."""
        entries = self.store.get(mech)
        return None if entries is None else entries.get(key)

    def put(self, mech, key: tuple, value) -> None:
        self.store.setdefault(mech, dict)[key] = value

    def __len__(self) -> int:
        return sum(len(v) for _, v in self.store.items())

    def clear(self) -> None:
        self.store.clear()


#: the integrators' cache
STEP_CACHE = StepCache()


def structure_owner(mech):
    """The Mechanism on which to keep what is built from ``mech``'s expressions alone: the
    Mechanism whose expressions it shares (``mech.functions_of``, a scene of the same
    structure: :mod:`symcable.models.structure`), so a scene with other numbers reuses the
    step; ``mech`` itself where it has an element form whose constants are numbers of the
    scene alone (not parameters: they enter the step built from it)."""
    owner = getattr(mech, "functions_of", None)
    form = getattr(mech, "elements", None)
    if owner is None or (form is not None and getattr(form, "parametric", None) is None):
        return mech
    return owner


def maybe_compiled(mech, key: tuple, vm, codegen: bool | None, what: str, size=None):
    """``vm`` (a Function built for ``mech``), or its generated C when ``codegen`` resolves
    to True (:func:`symcable.mechanism.codegen.use_codegen`; ``size()`` the graph size it judges, by
    default the serialised length of ``vm``), compiled once per Mechanism and ``key`` with
    the one-line notice ``compiling <what> for this model (once, cached) …``; the default
    (None) does not wait for the compiler (:mod:`symcable.mechanism.background_build`): ``vm``
    until the library is built."""
    def judged():
        if size is not None:
            return size()
        return STEP_CACHE.get(mech, ("graph_size",) + key, lambda: graph_size([vm], DEFAULT_MAX_SIZE))
    if not use_codegen(codegen, judged):
        return vm
    done = STEP_CACHE.find(mech, ("compiled",) + key)
    if done is not None:
        return done
    pending = STEP_CACHE.get(mech, ("pending",) + key, lambda: [""])
    if not background_build.finished(pending[0]):
        return vm  # (its C is being compiled in the background)
    fn = compile_functions([vm], what=what, wait=background_build.waits(codegen))[vm.name()]
    if last_build.get("action") == "background":
        pending[0] = last_build["key"]
        return vm
    STEP_CACHE.put(mech, ("compiled",) + key, fn)
    return fn
