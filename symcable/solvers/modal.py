"""Old import path of the modal analysis, kept for code that imports from here.

The solver is :func:`symcable.solvers.linearize.mechanism_modes` (generic over the
Mechanism); :func:`symcable.modal_analysis` runs it on the planar line's dynamics Mechanism
with the undamped parameters; the result class is :class:`symcable.results.ModalSolution`.
Nothing is computed here.
"""
from __future__ import annotations

import numpy as np

from ..results import ModalSolution
from .linearize import MAX_DENSE

__all__ = ["MAX_DENSE", "ModalSolution", "undamped_parameters"]


def undamped_parameters(model) -> np.ndarray:
    """``model.p_undamped`` of a dynamic model: the parameters of its undamped, unforced
    linear model about rest (static state kept; excitation, current and stabilisation off)."""
    return np.asarray(model.p_undamped, dtype=float)
