"""Names kept for code that imports them from here: the buffered caller of a Function
(:class:`symcable.codegen.FastCall`) and the sizes of the fused static solve
(:mod:`symcable.derive_static`). The static Functions of a model are those of its Mechanism
(:meth:`symcable.derive.MechanismFunctions.static_solver`)."""
from __future__ import annotations

from .codegen import FastCall
from .derive_static import LINSOL, SOLVE_MAX_ITER, SXLU_MAX_UNKNOWNS

__all__ = ["FastCall", "LINSOL", "SOLVE_MAX_ITER", "SXLU_MAX_UNKNOWNS"]
