"""Static continuation of a scene's Mechanism (:func:`trace_branch`): the generic solver
(:func:`symcable.solvers.branch.trace_branch`) with the formulation's re-anchoring of its
material frames, where it has them (a rod's, :mod:`symcable.models.rod.reanchor`)."""
from __future__ import annotations

from ..mechanism.mechanism import Mechanism
from ..models.rod.reanchor import reanchor_hook
from ..solvers.branch import Branch
from ..solvers.branch import trace_branch as _trace_branch

__all__ = ["trace_branch"]


def trace_branch(mech: Mechanism, block: str, values, *, component: int | None = None,
                 p=None, start=None, leave_unstable: bool = True, reanchor=True,
                 tol: float | None = None, max_iter: int = 30, max_halvings: int = 6,
                 codegen: bool | None = False) -> Branch:
    """Static continuation of ``mech`` along ``values`` of its parameter block ``block``
    (:func:`symcable.solvers.branch.trace_branch`, which documents every argument).

    ``reanchor``: True (the default) re-anchors the material frames of a Mechanism that has
    them (a rod or hybrid) between steps, by the rod's hook
    (:func:`~symcable.models.rod.reanchor.reanchor_hook`; none for a Mechanism without
    anchored frames); False never; or a :class:`~symcable.mechanism.mechanism.Reanchor`.
    """
    hook = reanchor_hook(mech) if reanchor is True else (reanchor or None)
    return _trace_branch(mech, block, values, component=component, p=p, start=start,
                         leave_unstable=leave_unstable, reanchor=hook, tol=tol,
                         max_iter=max_iter, max_halvings=max_halvings, codegen=codegen)
