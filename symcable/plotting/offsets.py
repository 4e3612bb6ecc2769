"""The figure of an offset sweep (:class:`symcable.results.offsets.OffsetSweep`): the
restoring force and moment on a body against its offset."""
from __future__ import annotations

from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np

from .profiles import finish

__all__ = ["plot_offsets"]

_NAMES = ("surge", "sway", "heave", "roll", "pitch", "yaw")
_UNITS = ("m", "m", "m", "deg", "deg", "deg")
_FORCE = ("Fx", "Fy", "Fz", "Mx", "My", "Mz")


def plot_offsets(sweep, dof: int, path: str | Path | None = None, *, ax=None):
    """Six panels, Fx, Fy, Fz (kN) and Mx, My, Mz (MN m) against the offset along column
    ``dof`` of ``sweep.offsets`` (m or deg), the static solves as dots joined in the order
    of that offset, and the linear stiffness at the origin dashed; saved to ``path`` when
    given; returns the figure."""
    if ax is None:
        _, ax = plt.subplots(2, 3, figsize=(12, 6.5), sharex=True)
    fig = np.ravel(ax)[0].figure
    x = sweep.offsets[:, dof]
    order = np.argsort(x)
    tan = sweep.tangent + sweep.force[np.argmin(np.linalg.norm(sweep.offsets, axis=1))]
    have_k = np.all(np.isfinite(sweep.stiffness))
    # the least span of a panel: a force that varies by round-off only is drawn flat, not
    # magnified into a zig-zag (1e-3 of the largest force, or moment, of the sweep)
    floor = [1e-3 * max(float(np.nanmax(np.abs(sweep.force[:, g]), initial=0.0)), 1e-9)
             for g in (slice(0, 3), slice(3, 6))]
    for k, a in enumerate(np.ravel(ax)):
        scale = 1e3 if k < 3 else 1e6
        a.plot(x[order], sweep.force[order, k] / scale, "o-", ms=3, label="static solves")
        if have_k:
            a.plot(x[order], tan[order, k] / scale, "--", color="0.4", label="linear stiffness")
        y = sweep.force[:, k][np.isfinite(sweep.force[:, k])] / scale
        if y.size:
            mid, half = 0.5 * (y.max() + y.min()), 0.5 * max(np.ptp(y), floor[k >= 3] / scale)
            a.set_ylim(mid - 1.1 * half, mid + 1.1 * half)
        a.set_title(_FORCE[k])
        a.set_ylabel("kN" if k < 3 else "MN m")
        a.grid(alpha=0.3)
        if k >= 3:
            a.set_xlabel(f"{_NAMES[dof]} offset ({_UNITS[dof]})")
    np.ravel(ax)[0].legend(fontsize=8)
    fig.suptitle(f"{sweep.scene_name}: restoring force on {sweep.body}")
    fig.tight_layout()
    return finish(fig, path)
