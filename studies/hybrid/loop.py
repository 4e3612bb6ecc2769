"""The loop (hockle) of a twisted rod whose ends are brought together, by static continuation
(issue 14 item 3), against the localized (homoclinic) solution of an infinite twisted rod
under tension (Love; Coyne 1990; Thompson & Champneys 1996).

A rod (L = 1 m, B = 1 N m^2, C = GJ = 0.8 N m^2, EA = 1e6 N, diameter 1 cm) clamped at
both ends along x is first twisted at fixed end distance L to the end rotation R = 37.5 rad
(``trace_branch`` in ``end_b.twist``: it leaves the straight branch at Greenhill's moment and
follows the buckle, which the stretch holds at M = M_cr(T)), then, at that R, its end B is
moved towards A by D (``trace_branch`` in ``end_b.position[0]``): rigid loading, end rotation
and end distance held. The buckle localizes into a loop.

Theory (isotropic, inextensible, infinite rod, far field straight along the axis with
tension T and moment M, m = M / sqrt(B T) < 2): 1 - cos(theta) = 2 (1 - m^2/4)
sech^2(k s), k = sqrt(T / B) sqrt(1 - m^2/4); the loop takes up the end shortening
D = 2 sqrt(4 - m^2) sqrt(B / T) and the end rotation (writhe) dR = 4 arccos(m / 2) beyond the
twist's M L / C. Given R and D these fix (M, T); along the path the loop forms where the
straight rod turns unstable, m = 2 (Greenhill's tension criterion M^2 = 4 B T), and D(m) at
fixed R has a maximum D* (a fold: there the infinite rod jumps, to self-contact in an
experiment; Neukirch, van der Heijden & Thompson 2002). Self-contact is not modelled here:
``self_contact`` reports the strands' least distance.

Run: ``python studies/hybrid/loop.py [--quick] [--out DIR]`` (quick: 40 segments only).
Writes ``results_loop.csv``, ``summary_loop.md`` and ``loop.png`` to DIR (default
studies/hybrid/out/).
"""
from __future__ import annotations

import math
import sys
import time
from pathlib import Path

import numpy as np
from scipy.optimize import brentq, minimize_scalar

HERE = Path(__file__).resolve().parent
sys.path.append(str(HERE.parent))
import study_io  # noqa: E402

from symcable import ConvergenceError, load_scene, self_contact, trace_branch  # noqa: E402
from symcable.api.rod_contact import writhe  # noqa: E402
from symcable.analytic import greenhill_moment, twisted_loop  # noqa: E402
from symcable.models.rod.rod import build_rod  # noqa: E402

L, B, C, EA, DIAM = 1.0, 1.0, 0.8, 1e6, 0.01
R0 = 37.5  # rad: M = 30 N m at fixed ends, T ~ 210 N, L sqrt(T / B) ~ 15
SHORTEN = np.r_[np.linspace(0.0, 0.14, 15), np.linspace(0.1425, 0.16, 8)]  # m


def scene(n: int) -> dict:
    return {"model": "rod", "environment": {"water_density": 0.0},
            "line_types": {"r": {"EA": EA, "EI": B, "GJ": C, "mass": 1.0, "diameter": DIAM,
                                 "weight": 0.0}},
            "sections": [{"type": "r", "length": L, "segments": n}],
            "end_a": {"condition": "clamped", "position": [0.0, 0.0, 0.0],
                      "direction": [1.0, 0.0, 0.0]},
            "end_b": {"condition": "clamped", "position": [L, 0.0, 0.0],
                      "direction": [1.0, 0.0, 0.0]}}


def homoclinic(m: float, R: float = R0) -> dict:
    """The infinite rod's loop at m = M / sqrt(B T) for the end rotation R (rad): M (N m)
    from R = M L / C + 4 arccos(m / 2), T (N), the shortening D (m)."""
    M = C * (R - 4.0 * math.acos(m / 2.0)) / L
    T = M * M / (B * m * m)
    return {"M": M, "T": T, "D": 2.0 * math.sqrt(4.0 - m * m) * math.sqrt(B / T)}


def fold(R: float = R0) -> dict:
    r = minimize_scalar(lambda m: -homoclinic(m, R)["D"], bounds=(0.05, 1.99),
                        method="bounded", options={"xatol": 1e-10})
    return {"m": r.x, **homoclinic(r.x, R)}


def theory_at(D: float, R: float = R0) -> dict | None:
    """(M, T, m) of the infinite rod's loop with shortening D on the branch from m = 2 to
    the fold (None beyond the fold)."""
    f = fold(R)
    if D >= f["D"]:
        return None
    m = brentq(lambda m: homoclinic(m, R)["D"] - D, f["m"], 2.0 - 1e-12, xtol=1e-13)
    return {"m": m, **homoclinic(m, R)}


def run(n: int) -> dict:
    t0 = time.perf_counter()
    mech = build_rod(load_scene(scene(n)))
    p = mech.params.with_values(motion=0.0)
    tw = trace_branch(mech, "end_b.twist", np.linspace(0.0, R0, 13), p=p)
    last = tw.points[-1]
    stall = None
    try:
        br = trace_branch(mech, "end_b.position", L - SHORTEN, component=0, p=last.p,
                          start=last)
    except ConvergenceError as exc:
        br, stall = exc.partial, L - float(np.ravel(exc.diagnostics["reached"])[0])
    rows = []
    skip = max(1, n // 8)  # strands an eighth of the rod apart (~2 sqrt(B / T)) and more
    for pt in br.points:
        D = L - float(pt.value[0])
        T = -float(pt.outputs["end_force_b"][0])
        M = float(np.mean(pt.outputs["twisting_moment"]))
        m = M / math.sqrt(B * T)
        X = np.asarray(pt.outputs["positions"])
        th = theory_at(D) if D > 0 else None
        lp = twisted_loop(B, T, M) if m < 2.0 else None  # the loop at the measured (T, M)
        rows.append({"segments": n, "D": D, "T": T, "M": M, "m": m, "stable": pt.stable,
                     "left": pt.left, "loop_rotation": R0 - M * L / C,
                     "loop_rotation_theory": lp.rotation if lp else 0.0,
                     "D_from_MT": lp.shortening if lp else 0.0,
                     "T_theory": th["T"] if th else math.nan,
                     "M_theory": th["M"] if th else math.nan,
                     "writhe_rotation": 2.0 * math.pi * writhe(X, axis=[1.0, 0.0, 0.0]),
                     "crossings": 0.0,  # below: (R - M L / C - 2 pi Wr) / 4 pi
                     "strand_distance": self_contact(X, DIAM, skip=skip).min_distance,
                     "amplitude": float(np.max(np.linalg.norm(X[:, 1:], axis=1)))})
    for w in rows:  # Lk = R / 2 pi = Tw + Wr: what is left over is self-crossings (each 2)
        w["crossings"] = (w["loop_rotation"] - w["writhe_rotation"]) / (4.0 * math.pi)
    return {"n": n, "rows": rows, "greenhill_at_D0": greenhill_moment(B, L, rows[0]["T"]),
            "positions": [np.asarray(pt.outputs["positions"]) for pt in br.points],
            "stall_after": stall, "reanchored": br.stats["reanchored"],
            "snaps": [(L - float(np.ravel(v)[0]), float(SHORTEN[k]))
                      for k, v in br.stats["snaps"]],
            "twist_left": [float(pt.value[0]) for pt in tw.points if pt.left],
            "wall_time": time.perf_counter() - t0}


def summary(runs: list) -> str:
    f = fold()
    lines = [f"Infinite-rod fold at R = {R0} rad: D* = {f['D']:.5f} m (m = {f['m']:.4f}, "
             f"T = {f['T']:.2f} N, M = {f['M']:.3f} N m)", ""]
    for r in runs:
        lines += [f"### {r['n']} segments ({r['wall_time']:.1f} s; left the straight branch "
                  f"at twist {r['twist_left']} rad; last solved D = "
                  f"{r['stall_after'] if r['stall_after'] is not None else 'end of path'} m; "
                  f"snaps (last D solved, D after): {r['snaps']})",
                  "", f"At D = 0: T = {r['rows'][0]['T']:.3f} N, M = {r['rows'][0]['M']:.4f} "
                  f"N m, m = {r['rows'][0]['m']:.4f}; the clamped closed form's M_cr(T) = "
                  f"{r['greenhill_at_D0']:.4f} N m (m = "
                  f"{r['greenhill_at_D0'] / math.sqrt(B * r['rows'][0]['T']):.4f}; infinite "
                  "rod: 2)",
                  "", "| D m | T N | T theory | M N m | M theory | m | loop rotation rad | "
                  "4 arccos(m/2) | 2 pi Wr | crossings | D from (M, T) | strand distance m |",
                  "|---|---|---|---|---|---|---|---|---|---|---|---|"]
        for w in r["rows"]:
            lines.append(f"| {w['D']:.4f} | {w['T']:.2f} | {w['T_theory']:.2f} | "
                         f"{w['M']:.4f} | {w['M_theory']:.4f} | {w['m']:.4f} | "
                         f"{w['loop_rotation']:.4f} | {w['loop_rotation_theory']:.4f} | "
                         f"{w['writhe_rotation']:.4f} | {w['crossings']:.3f} | "
                         f"{w['D_from_MT']:.4f} | {w['strand_distance']:.4f} |")
        lines.append("")
    return "\n".join(lines) + "\n"


def figure(runs: list, path: Path) -> None:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    r = runs[-1]
    fig = plt.figure(figsize=(12, 8.5))
    ax3 = fig.add_subplot(2, 2, 1, projection="3d")
    ax_end = fig.add_subplot(2, 2, 2)
    ax_t = fig.add_subplot(2, 2, 3)
    ax_m = fig.add_subplot(2, 2, 4)
    Ds = np.array([w["D"] for w in r["rows"]])
    jumps = [k for k, w in enumerate(r["rows"]) if w["left"] and k > 0]
    ends = [jumps[0] - 1, jumps[0]] if jumps else [len(Ds) - 1]
    picks = sorted({int(np.argmin(abs(Ds - d))) for d in (0.0, 0.05, 0.1)} | set(ends))
    cmap = plt.get_cmap("viridis")
    for i, k in enumerate(picks):
        X = r["positions"][k]
        c = cmap(i / max(len(picks) - 1, 1))
        after = " (after the snap)" if k in jumps else ""
        ax3.plot(X[:, 0], X[:, 1], X[:, 2], color=c, ls="--" if after else "-",
                 label=f"D = {Ds[k]:.4f} m{after}")
        ax_end.plot(X[:, 1], X[:, 2], color=c, ls="--" if after else "-")
    ax3.set_xlabel("x m"), ax3.set_ylabel("y m"), ax3.set_zlabel("z m")
    ax3.set_title(f"shapes along the shortening, R = {R0} rad, {r['n']} segments")
    ax3.legend(fontsize=7)
    ax_end.set_aspect("equal")
    ax_end.set_xlabel("y m"), ax_end.set_ylabel("z m")
    ax_end.set_title("end view (along x): the loop")
    f = fold()
    ms = np.linspace(f["m"], 1.999, 300)
    th = [homoclinic(m) for m in ms]
    for rr in runs:  # the branch up to its fold (the points after a snap: crosses)
        cut = next((k for k, w in enumerate(rr["rows"]) if w["left"] and k > 0),
                   len(rr["rows"]))
        D = [w["D"] for w in rr["rows"]]
        line, = ax_t.plot(D[:cut], [w["T"] for w in rr["rows"][:cut]], "o-", ms=3,
                          label=f"rod, {rr['n']} seg.")
        ax_t.plot(D[cut:], [w["T"] for w in rr["rows"][cut:]], "x", color=line.get_color())
        line, = ax_m.plot(D[:cut], [w["loop_rotation"] for w in rr["rows"][:cut]], "o-", ms=3,
                          label=f"R - M L / C, {rr['n']} seg.")
        ax_m.plot(D[:cut], [w["writhe_rotation"] for w in rr["rows"][:cut]], "+",
                  color="k", ms=5)
    ax_t.plot([t["D"] for t in th], [t["T"] for t in th], "k--", label="homoclinic loop")
    ax_t.axvline(f["D"], color="grey", lw=0.8, ls=":")
    ax_t.set_xlabel("end shortening D m (x: after the snap past the fold)")
    ax_t.set_ylabel("tension T N")
    ax_t.legend(fontsize=7)
    ax_m.plot([t["D"] for t in th], [4 * math.acos(m / 2) for m in ms], "k--",
              label="4 arccos(m / 2), homoclinic")
    ax_m.axvline(f["D"], color="grey", lw=0.8, ls=":")
    ax_m.set_xlabel("end shortening D m (+: 2 pi Wr of the rod's shape)")
    ax_m.set_ylabel("end rotation in the loop rad")
    ax_m.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def main(argv=None) -> dict:
    args = study_io.parse(__doc__, "40 segments only", HERE / "out", argv)
    counts = (40,) if args.quick else (60, 120, 240)
    runs = [run(n) for n in counts]
    rows = [w for r in runs for w in r["rows"]]
    text = summary(runs)
    figure(runs, args.out / "loop.png")
    if args.figure is not None:
        figure(runs, args.figure)
    study_io.write_tables(args.out, rows, text, ("results_loop", "summary_loop"))
    return {"runs": runs, "fold": fold()}


if __name__ == "__main__":
    main()
