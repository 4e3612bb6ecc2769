"""Values kept on an object for as long as the object lives: the per-Mechanism caches.

A ``weakref.WeakKeyDictionary`` whose values refer back to their key (a Mechanism's
Functions hold the Mechanism; a compiled step closes over it) never frees an entry: the
value, held strongly by the dictionary, keeps the key alive. A process solving many scenes
then kept every Mechanism it ever built (80 MB a scene on the dynamic fuzz study's, until
the system killed it). :class:`Attached` stores the value in the object's own ``__dict__``
instead, so object and value form one cycle that the garbage collector frees together once
nothing else holds the object; a ``WeakSet`` of the objects (weak references only) lets the
cache be counted, listed and cleared.
"""
from __future__ import annotations

import weakref
from typing import Callable

__all__ = ["Attached"]


class Attached:
    """A cache of one value per object, stored on the object (under a private attribute
    named after ``name``). The object needs a ``__dict__`` and identity hashing (a
    Mechanism: a frozen dataclass with ``eq=False``; its ``dataclasses.replace`` copies do
    not inherit the value)."""

    def __init__(self, name: str):
        self._attr = f"_symcable_cache_{name}"
        self._owners: "weakref.WeakSet" = weakref.WeakSet()

    def get(self, obj, default=None):
        return vars(obj).get(self._attr, default)

    def set(self, obj, value) -> None:
        vars(obj)[self._attr] = value  # vars(): a frozen dataclass refuses setattr
        self._owners.add(obj)

    def setdefault(self, obj, build: Callable):
        """The value of ``obj``, ``build()`` stored on first use."""
        d = vars(obj)
        if self._attr not in d:
            d[self._attr] = build()
            self._owners.add(obj)
        return d[self._attr]

    def __contains__(self, obj) -> bool:
        return self._attr in vars(obj)

    def __getitem__(self, obj):
        return vars(obj)[self._attr]

    def items(self) -> list:
        """``[(object, value)]`` of the live objects holding a value."""
        return [(o, vars(o)[self._attr]) for o in list(self._owners) if self._attr in vars(o)]

    def __len__(self) -> int:
        return len(self.items())

    def clear(self) -> None:
        for o in list(self._owners):
            vars(o).pop(self._attr, None)
        self._owners.clear()
