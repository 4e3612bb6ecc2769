"""Figures of studies/hybrid/run.py: the seed's Figs. 5-8 (shape, tension, shear, moment along
the line) for the pure rod, the hybrid and the pure cable3d, and the speed figure."""
from __future__ import annotations

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

STYLE = {"rod": dict(color="k", ls="--", label="pure rod"),
         "hybrid": dict(color="C3", ls="-", label="hybrid (rod on the last 0.5 m)"),
         "cable3d": dict(color="C0", ls=":", label="pure cable3d (EI = 0)")}


def profiles_figure(st, counts, rx, path) -> None:
    """Shape (Fig. 5), tension (Fig. 6), shear (Fig. 7) and moment (Fig. 8) at the finest
    count; the relaxed rod's tension and moment as dots."""
    n = counts[-1]
    fig, ax = plt.subplots(2, 2, figsize=(11, 7.5))
    for m, sty in STYLE.items():
        r = st[m].get(n)
        if r is None:
            continue
        p = r["profile"]
        ax[0, 0].plot(p["X"][:, 0], p["X"][:, 2], **sty)
        ax[0, 1].plot(p["s_edge"], 1e3 * p["T"], **sty)
        ax[1, 0].plot(p["s_edge"], 1e3 * p["shear"], **sty)
        ax[1, 1].plot(p["s_node"], 1e3 * p["M"], **sty)
    if "profile" in rx.get("rod", {}):
        p = rx["rod"]["profile"]
        k = max(1, len(p["s_edge"]) // 40)
        lab = f"rod relaxed from straight ({len(p['s_edge'])} segments)"
        ax[0, 0].plot(p["X"][::k, 0], p["X"][::k, 2], "o", ms=3, mfc="none", color="C2", label=lab)
        ax[0, 1].plot(p["s_edge"][::k], 1e3 * p["T"][::k], "o", ms=3, mfc="none", color="C2")
        ax[1, 0].plot(p["s_edge"][::k], 1e3 * p["shear"][::k], "o", ms=3, mfc="none", color="C2")
        ax[1, 1].plot(p["s_node"][::k], 1e3 * p["M"][::k], "o", ms=3, mfc="none", color="C2")
    ax[0, 0].set(xlabel="x (m)", ylabel="z (m)", title=f"final shape (Fig. 5), {n} segments")
    ax[0, 0].set_aspect("equal")
    # one legend for the four panels, below them (inside the shape panel it hid the curves)
    handles, labels = ax[0, 0].get_legend_handles_labels()
    fig.legend(handles, labels, loc="lower center", ncol=len(labels), fontsize=9, frameon=False)
    ax[0, 1].set(xlabel="s (m)", ylabel="tension (mN)", title="tension (Fig. 6)")
    ax[1, 0].set(xlabel="s (m)", ylabel="shear force (mN)", title="shear (Fig. 7)")
    ax[1, 1].set(xlabel="s (m)", ylabel="bending moment (mN m)", title="moment (Fig. 8)")
    for a in (ax[0, 1], ax[1, 0], ax[1, 1]):
        a.axvline(1.5, color="0.7", lw=0.8)
        a.grid(alpha=0.3)
    fig.tight_layout(rect=(0, 0.04, 1, 1))
    fig.savefig(path, dpi=120)
    plt.close(fig)


def speed_figure(st, lg, path) -> None:
    """Warm static solve time against segments (2 m line), and the per-step time of the
    1 s step against the low-tension zone's fraction (longer lines)."""
    fig, ax = plt.subplots(1, 2, figsize=(11, 4))
    for m, sty in STYLE.items():
        pts = [(r["n_q"], r["warm"]) for r in st[m].values() if r is not None]
        if pts:
            x, y = np.array(pts).T
            ax[0].loglog(x, y, marker="o", **sty)
        pts = [(r["zone_fraction"], r["us_per_step"]) for r in lg
               if r["model"] == m and r["status"] == "ok"]
        if pts:
            x, y = np.array(pts).T
            ax[1].loglog(x, 1e-3 * y, marker="o", **sty)
    ax[0].set(xlabel="unknowns", ylabel="static solve, warm median (s)",
              title="2 m benchmark: static solve")
    ax[1].set(xlabel="low-tension zone / line length", ylabel="ms per 1 s step",
              title="longer lines, same ds: 1 s generalized-alpha step (VM)")
    for a in ax:
        a.grid(alpha=0.3, which="both")
        a.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def relaxation_figure(rx, path) -> None:
    """The relaxation from straight: kinetic energy (J) against time for each model that
    ran (the release's small steps, then the seed's 1 s steps), and the relaxed shape
    against the static one."""
    fig, ax = plt.subplots(1, 2, figsize=(11, 4))
    for m, sty in STYLE.items():
        r = rx.get(m, {})
        if "K" not in r:
            continue
        ax[0].semilogy(r["t"], np.maximum(r["K"], 1e-30), **sty)
        if "profile" in r:
            p, q = r["profile"], r["static"]
            ax[1].plot(q["X"][:, 0], q["X"][:, 2], **sty)
            k = max(1, len(p["X"]) // 30)
            ax[1].plot(p["X"][::k, 0], p["X"][::k, 2], "o", ms=3, mfc="none",
                       color=sty["color"])
    ax[0].axvline(1.0, color="0.7", lw=0.8)
    ax[0].set(xlabel="t (s)", ylabel="kinetic energy (J)",
              title="relaxation from straight: release, then dt = 1 s (rho_inf = 0)")
    ax[1].set(xlabel="x (m)", ylabel="z (m)",
              title="relaxed (circles) against static (lines)")
    ax[1].set_aspect("equal")
    for a in ax:
        a.grid(alpha=0.3)
        a.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)
