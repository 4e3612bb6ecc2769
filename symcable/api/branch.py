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
    """Static continuation of ``mech`` along ``values`` of its parameter block ``block``.

    The generic solver (:func:`symcable.solvers.branch.trace_branch`, whose module
    docstring says how each step is taken) with the formulation's re-anchoring of a rod's
    material frames. Every point's stability is judged; an unstable point is left along
    its unstable mode unless ``leave_unstable`` is False.

    Parameters
    ----------
    mech : Mechanism
        The scene's statics (:func:`symcable.build_mechanism`).
    block : str
        A parameter block of ``mech`` (a rod's ``"end_b.twist"`` in rad,
        ``"end_b.position"`` in m, ``"load"`` ...).
    values : array_like (K,) or (K, size)
        The block's values at the K >= 2 points, in its units; (K,) for a block of one
        entry, or with ``component`` = i the values of its entry i.
    component : int, optional
        Vary only entry i of the block (the other entries as in ``p``). Default None: the
        whole block.
    p : ndarray (n_p,), optional
        The other parameters. Default None: the mechanism's static parameters.
    start : Equilibrium or BranchPoint, optional
        An equilibrium at the first value. Default None: solved there by
        :func:`symcable.solve_equilibrium` (the stable one it finds).
    leave_unstable : bool
        True (default): where a point is unstable, leave along its unstable eigenvector to
        a stable equilibrium at the same parameters (``left`` = True); False: follow the
        unstable branch and flag it.
    reanchor : bool or Reanchor
        True (the default) re-anchors the material frames of a Mechanism that has them (a
        rod or hybrid) between steps, by the rod's hook
        (:func:`~symcable.models.rod.reanchor.reanchor_hook`; none for a Mechanism without
        anchored frames); False never; or a :class:`~symcable.mechanism.mechanism.Reanchor`.
    tol : float, optional
        Static residual tolerance, N. Default None: the mechanism's
        (``mech.scales.static_tolerance()``).
    max_iter : int
        Newton iterations per attempt. Default 30.
    max_halvings : int
        Halvings of a failed step before it is relaxed past a fold or given up. Default 6.
    codegen : bool, optional
        The static solve in generated C (as :func:`symcable.solve_equilibrium`). Default
        False: CasADi's virtual machine; None: automatic.

    Returns
    -------
    Branch
        One :class:`~symcable.solvers.branch.BranchPoint` per value (``Branch.values``
        (K,), ``Branch.output(name)`` (K, ...)); ``stats`` as documented there.

    Raises
    ------
    SymcableError
        An unknown block, values of the wrong shape, not finite or fewer than two, a bad
        component, ``p`` of the wrong size.
    ConvergenceError
        A step failed after ``max_halvings`` halvings and no relaxation found a stable state
        there (``partial``: the branch so far; ``diagnostics["reached"]``: the last value
        solved).
    """
    hook = reanchor_hook(mech) if reanchor is True else (reanchor or None)
    return _trace_branch(mech, block, values, component=component, p=p, start=start,
                         leave_unstable=leave_unstable, reanchor=hook, tol=tol,
                         max_iter=max_iter, max_halvings=max_halvings, codegen=codegen)
