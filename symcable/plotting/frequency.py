"""The figure of a frequency-domain result (:class:`symcable.results.frequency.FrequencyResponse`):
end B's axial-force spectrum per line with the sea's, and the axial force's standard deviation
along each line."""
from __future__ import annotations

from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np

from .profiles import finish

__all__ = ["plot_frequency"]


def _bins(omega: np.ndarray) -> np.ndarray:
    """Each component's share of the frequency axis, rad/s (half the gaps either side)."""
    if omega.size == 1:
        return np.ones(1)
    gaps = np.diff(omega)
    return 0.5 * (np.concatenate([[gaps[0]], gaps]) + np.concatenate([gaps, [gaps[-1]]]))


def plot_frequency(res, path: str | Path | None = None):
    """Two panels: end B's axial-force spectrum of each line (kN^2 s/rad; a regular wave's
    amplitude, kN, as a bar) with the sea's elevation spectrum (m^2 s/rad) on a second axis,
    and each line's axial-force standard deviation and mean along it (kN); saved to ``path``
    when given; returns the figure."""
    fig, (a, b) = plt.subplots(1, 2, figsize=(12, 4.5))
    w, amp = res.omega, res.amplitude
    regular = w.size == 1
    dw = _bins(w)
    order = np.argsort(w)
    styles = ("-", "--", ":", "-.")
    for k, (name, ln) in enumerate(res.lines.items()):
        T = np.abs(ln.rao[:, -1]) * amp
        ls = styles[k % len(styles)]
        if regular:
            a.bar(w, T / 1e3, width=0.02 * w[0], label=name)
        else:
            a.plot(w[order], (T ** 2 / (2 * dw))[order] / 1e6, ls=ls, label=f"{name}: std "
                   f"{ln.std[-1] / 1e3:.3g} kN")
        s_mid = 0.5 * (ln.s[1:] + ln.s[:-1])
        b.plot(s_mid, ln.std / 1e3, ls=ls, label=name)
    a.set_xlabel("angular frequency (rad/s)")
    a.set_ylabel("end B axial force amplitude (kN)" if regular
                 else "end B axial force spectrum (kN² s/rad)")
    a.grid(alpha=0.3)
    a.legend(fontsize=8, loc="upper right")
    if not regular:
        sea = a.twinx()
        sea.plot(w[order], (amp ** 2 / (2 * dw))[order], color="0.6", ls="--")
        sea.set_ylabel("wave spectrum (m² s/rad), dashed", color="0.4")
    b.set_xlabel("arc length from end A (m)")
    b.set_ylabel("axial force standard deviation (kN)")
    b.grid(alpha=0.3)
    b.legend(fontsize=8)
    fig.suptitle(f"{res.scene_name}: frequency-domain response "
                 f"({res.stats.get('linearisation', '')} drag linearisation)")
    fig.tight_layout()
    return finish(fig, path)
