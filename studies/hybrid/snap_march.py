"""The dynamic snap of a coarse twisted loop, marched: does the time march's re-anchoring keep
the rod's link (studies/rod_notes/reanchor14.md)?

A rod of loop.py's properties at 24 segments (2.4 per bending length at the loop's
tension), twisted at fixed ends to R = 20 rad (13 points of ``trace_branch``), then its ends
brought together (``end_b.position``, 1 cm steps) to the last point before the static fold;
from that state, at rest, end B is put at the next centimetre (past the fold) and the rod
marched (first-order generalized-alpha, rho_inf = 0.6, dt = 50 us) for 0.15 s: it snaps.
The link bookkeeping R - Tw - 2 pi Wr (Tw the sum of the vertex twists, Wr the centre line's
writhe, ends extended along x) is constant unless strands pass through each other (then by
4 pi); every change is reported with its time. A re-anchoring that loses a whole turn at a
vertex changes it by 2 pi.

Run: ``python studies/hybrid/snap_march.py [--quick] [--out DIR]`` (quick: 0.05 s of march).
"""
from __future__ import annotations

import math
import sys
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.append(str(HERE.parent))
import study_io  # noqa: E402

from symcable import ConvergenceError, load_scene, trace_branch  # noqa: E402
from symcable.models.rod.rod import build_rod  # noqa: E402
from symcable.models.rod.reanchor import reanchor_hook  # noqa: E402
from symcable.api.rod_contact import writhe  # noqa: E402
from symcable.solvers.integrate import integrate  # noqa: E402
from symcable.solvers.options import GeneralizedAlphaFirstOrder  # noqa: E402

loop = study_io.load_module(HERE / "loop.py", "hybrid_loop")
N, R, DT = 24, 20.0, 5e-5
SHORTEN = np.linspace(0.0, 0.5, 51)  # m


def start():
    """(mechanism, q at the last point before the fold, p past it, the fold's D pair)."""
    mech = build_rod(load_scene(loop.scene(N)))
    p = mech.params.with_values(motion=0.0)
    last = trace_branch(mech, "end_b.twist", np.linspace(0.0, R, 13), p=p).points[-1]
    try:
        br = trace_branch(mech, "end_b.position", loop.L - SHORTEN, component=0, p=last.p,
                          start=last)
    except ConvergenceError as exc:
        br = exc.partial
    if not br.stats["snaps"]:
        raise RuntimeError("no fold along the shortening")
    k = br.stats["snaps"][0][0]
    before, after = br.points[k - 1], br.points[k]
    return mech, before.q, after.p, (loop.L - float(before.value[0]),
                                     loop.L - float(after.value[0]))


def main(argv=None) -> dict:
    args = study_io.parse(__doc__, "0.05 s of march", HERE / "out", argv)
    t0 = time.perf_counter()
    mech, q, p, (d0, d1) = start()
    duration = 0.05 if args.quick else 0.15
    failure = None
    t1 = time.perf_counter()
    try:
        tr = integrate(mech, duration, DT, method=GeneralizedAlphaFirstOrder(rho_inf=0.6),
                       q0=q, p=p, codegen=False, reanchor=reanchor_hook(mech))
    except ConvergenceError as exc:
        tr, failure = exc.partial, str(exc)
    march_time = time.perf_counter() - t1
    tw = tr.outputs["twist"].reshape(tr.time.size, -1)
    total = tw.sum(axis=1)
    link = np.array([R - total[i] - 2.0 * math.pi * writhe(tr.outputs["positions"][i],
                                                            axis=[1.0, 0.0, 0.0])
                     for i in range(tr.time.size)])
    changes = np.flatnonzero(np.abs(np.diff(link)) > 1e-3)
    st = tr.stats
    rows = [{"time": float(tr.time[i]), "link_bookkeeping": float(link[i]),
             "total_twist": float(total[i]), "max_vertex_twist": float(np.max(np.abs(tw[i])))}
            for i in range(tr.time.size)]
    lines = [f"# Dynamic snap, {N} segments, R = {R} rad: march from D = {d0:.3f} m with "
             f"end B at D = {d1:.3f} m, dt = {DT:g} s, {tr.time[-1]:.4g} s "
             f"({st['steps']} steps, {march_time:.1f} s; whole run {time.perf_counter() - t0:.1f} s)",
             "", f"status {tr.status}" + (f": {failure}" if failure else ""),
             f"re-anchorings {st.get('reanchorings')} (shifted by whole turns: "
             f"{st.get('reanchor_shifted')}; refused calls: {st.get('reanchor_refused')}), "
             f"least frame margin {st.get('min_frame_margin'):.3g}",
             f"R - Tw - 2 pi Wr: first {link[0]:.9f} ({link[0] / (4 * math.pi):.6f} x 4 pi), "
             f"range over the run {np.ptp(link):.3g} rad",
             f"largest vertex twist {np.max(np.abs(tw)):.3f} rad; largest change of a vertex "
             f"twist in one step {np.max(np.abs(np.diff(tw, axis=0))):.3f} rad",
             "changes of R - Tw - 2 pi Wr (t s, in units of 2 pi): "
             + (", ".join(f"{tr.time[i + 1]:.5f}: {(link[i + 1] - link[i]) / (2 * math.pi):+.2f}"
                          for i in changes) or "none")]
    study_io.write_tables(args.out, rows, "\n".join(lines) + "\n",
                          ("results_snap_march", "summary_snap_march"))
    return {"link": link, "stats": st}


if __name__ == "__main__":
    main()
