"""The figure of a linearisation (:class:`symcable.results.generic.SceneLinearization`): its
stiffness, damping and mass matrices as maps of their magnitudes."""
from __future__ import annotations

from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np

from .profiles import finish

__all__ = ["plot_matrices"]


def plot_matrices(lin, path: str | Path | None = None):
    """K (N per unit of q), C (N s/m) and M (kg) side by side, each entry's log10 of its
    magnitude (white where zero), rows and columns in the order of ``q_kinds`` and
    ``v_kinds``; saved to ``path`` when given; returns the Figure."""
    fig, axes = plt.subplots(1, 3, figsize=(14.0, 4.6))
    for ax, (name, A, unit) in zip(axes, (("K", lin.K, "N per unit of q"),
                                          ("C", lin.C, "N s/m"), ("M", lin.M, "kg"))):
        A = np.abs(np.asarray(A, float))
        shown = np.where(A > 0, np.log10(np.where(A > 0, A, 1.0)), np.nan)
        im = ax.imshow(shown, cmap="viridis", interpolation="nearest", aspect="auto")
        fig.colorbar(im, ax=ax, label=f"log10 |{name}| ({unit})")
        ax.set_title(f"{name}: {A.shape[0]} x {A.shape[1]}, {np.count_nonzero(A)} non-zero",
                     fontsize=10)
        ax.set_xlabel("column (q)" if name == "K" else "column (v)")
        ax.set_ylabel("row (v)")
    fig.suptitle(f"{lin.scene_name}: linearisation about the static state"
                 + (" (undamped)" if lin.undamped else ""), fontsize=11)
    fig.tight_layout()
    return finish(fig, path)
