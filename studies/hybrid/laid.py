"""The seed's cable laid on the seabed over most of its length, its low-tension end a small
fraction of it (issue 14 item 4: "a longer cable where the low-tension zone is a small
fraction ..., where the hybrid's advantage should grow with the ratio of the zones; measure
it"), solved as a pure rod and as the hybrid rod-catenary line.

The line (tests/test_rod_seabed.py::laid_seed, lengthened): seed 000's cable (D = 1 mm,
Table 1; submerged weight 7.689e-3 N/m) pinned on a frictional bed (depth 1 m, stiffness
1e4 N/m^2, Coulomb mu = 0.3 in the time steps; 3D statics are frictionless, symcable's
FRICTIONLESS warning) and running along it to the benchmark's
guided, tension-free right end (tangent 30 deg below the horizontal, 0.01 N normal to it),
which lifts the last ~1 m off the bed. L = 3, 10, 20, 40 m at the same ds = 5 cm (60-800
segments). Models:

- ``rod``: the whole line a rod;
- ``hybrid``: cable3d (EI = 0, the seed's catenary) on [0, L - 0.5], rod on the last 0.5 m
  (the seed's rod zone; rod fraction f = 0.5 / L);
- ``hybrid-td``: the same with the rod on the last 1.5 m, through the touchdown;
- ``auto``: one section, ``zones = "auto"`` (symcable.api.rod_static.hybrid_zones: an
  all-cable3d solve first, rod where sqrt(EI / T) > 0.15 L): its zones and f reported.

Measured per length and model: the static solve (the VM, without the stability verdict, from
one common start: the line laid straight along x on the bed; the default start, hanging
along its load into the bed, fails the rod from 20 m) and the time of 3 first-order
generalized-alpha (rho_inf = 0, Newton to 1e-8 scaled) 1 s steps from it, as medians of
interleaved warm repeats; the Newton iterations; the speed ratio rod / hybrid against the
per-segment cost model 1 / (f + 0.22 (1 - f)) (studies/hybrid/README.md); the hybrid's
difference from the rod:
tension along the line (relative to the rod's peak), node positions, the lifted end.

Run: ``python studies/hybrid/laid.py [--quick] [--out DIR]`` (quick: 3 m at ds = 0.1 m,
rod and hybrid, 1 repeat).
Writes ``results_laid.csv`` and ``summary_laid.md`` to DIR (default studies/hybrid/out/).
Units: m, N, s.
"""
from __future__ import annotations

import sys
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.append(str(HERE.parent))
import study_io  # noqa: E402

# the benchmark study's timing helpers (interleaved warm medians, the static solve without
# its stability verdict), shared rather than copied
bench = study_io.load_module(HERE / "bench.py", "hybrid_bench")
interleaved, no_stability_check = bench.interleaved, bench.no_stability_check

import symcable.solvers.equilibrium as _equilibrium  # noqa: E402
from symcable.errors import SymcableError  # noqa: E402
from symcable.mechanism.mechanism import Start  # noqa: E402
from symcable.api.rod_static import hybrid_zones, rod_mechanism  # noqa: E402
from symcable.scene import load_scene  # noqa: E402
from symcable.solvers.integrate import integrate  # noqa: E402
from symcable.solvers.options import GeneralizedAlphaFirstOrder  # noqa: E402

DS = 0.05         # m: segment length (the laid seed cable's)
ZONE = 0.5        # m: the given hybrid's rod zone, the seed's last 0.5 m
ZONE_TD = 1.5     # m: "hybrid-td"'s rod zone, through the touchdown (~1 m from the end)
C_RATIO = 0.22    # a catenary segment's cost / a rod segment's (studies/hybrid README)
STEPS, DT = 3, 1.0
FRICTION = 0.3    # Coulomb, the test's (the time steps only)
STEP_TOL = 1e-8   # the steps' scaled Newton tolerance (1e-10 stalls at round-off from 6 m)
CABLE = {"EA": 3926.990816987241, "EI": 2.454369260617026e-4, "GJ": 1.9634954084936207e-4,
         "mass": 7.853981633974483e-4, "diameter": 1.0e-3, "cd_normal": 1.0,
         "cd_tangential": 0.3141592653589793, "ca_normal": 0.0, "ca_tangential": 0.0}


def scene(model: str, length: float, zone: float = ZONE, ds: float = DS):
    """The laid seed cable of ``length`` m as ``model`` = "rod", "hybrid" (rod on the last
    ``zone`` m, EI = 0 cable3d before), "hybrid-td" (the same, rod on the last ZONE_TD m) or
    "auto" (zones = "auto" on one section)."""
    cat = {k: v for k, v in CABLE.items() if k != "GJ"}
    cat["EI"] = 0.0
    d = {"model": "rod" if model == "rod" else "hybrid",
         "environment": {"gravity": 9.8, "water_density": 1.0, "depth": 1.0},
         "seabed": {"stiffness": 1e4, "friction": FRICTION},
         "line_types": {"cable": dict(CABLE)},
         "sections": [{"type": "cable", "length": length, "segments": round(length / ds)}],
         "end_a": {"condition": "pinned", "position": [0.0, 0.0, -1.0]},
         "end_b": {"condition": "guided", "direction": [0.8660254037844387, 0.0, -0.5],
                   "force": [0.005, 0.0, 0.008660254037844387]}}
    if model == "hybrid-td":
        model, zone = "hybrid", ZONE_TD
    if model == "hybrid":
        d["line_types"]["catenary"] = cat
        d["sections"] = [{"type": "catenary", "length": length - zone,
                          "segments": round((length - zone) / ds), "model": "cable3d"},
                         {"type": "cable", "length": zone, "segments": round(zone / ds),
                          "model": "rod"}]
    elif model == "auto":
        d["zones"] = "auto"
    elif model != "rod":
        raise ValueError(model)
    return load_scene(d)


def flat_start(mech, s) -> Start:
    """The common start: every node on the bed's surface at (s_i, 0, -depth), twists 0 (the
    mechanism's own first start's multipliers and parameters)."""
    st = next(iter(mech.starts()))
    n = sum(x.segments for x in s.sections)
    X = np.outer(np.linspace(0.0, s.length, n + 1), [1.0, 0.0, 0.0])
    X[:, 2] = -s.environment.depth
    node_q = next(p.node_q for p in mech.layout.parts.values() if p.kind == "line")
    q = np.zeros_like(np.asarray(st.q, float))
    for i, idx in enumerate(np.asarray(node_q)):
        if idx[0] >= 0:
            q[idx] = X[i]
    return Start(q, st.z, st.p, "laid straight on the bed")


def case(model: str, length: float, ds: float = DS) -> dict:
    """Build, solve once (cold) and warm the 1 s steps of one model at one length: a dict
    with the Mechanism, the solution, the rod fraction and callables for the timed parts."""
    s = scene(model, length, ds=ds)
    t0 = time.perf_counter()
    zones = None
    if model == "auto":
        s, rep = hybrid_zones(s)  # the all-cable3d pre-solve
        zones = rep["zones"]
    mech = rod_mechanism(s)
    starts = [flat_start(mech, s)]

    def static():
        return _equilibrium.solve_equilibrium(mech, codegen=False, starts=starts)

    with no_stability_check():
        eq = static()
    cold = time.perf_counter() - t0
    method = GeneralizedAlphaFirstOrder(rho_inf=0.0, tol=STEP_TOL)

    def steps():
        return integrate(mech, STEPS * DT, DT, method=method, start=eq, p=mech.params.values,
                         codegen=False, progress=False)

    tr = steps()
    if tr.status != "converged":
        raise SymcableError(f"{model} {length} m: the 1 s steps failed ({tr.status})")
    n = len(tr.time)
    X0 = np.asarray(eq.outputs["positions"])
    drift = float(np.abs(np.asarray(tr.outputs["positions"]).reshape(n, -1, 3) - X0).max())
    rod_len = sum(x.length for x in s.sections if (x.model or s.model.value) == "rod")
    return {"model": model, "length": length, "mech": mech, "eq": eq, "static": static,
            "steps": steps, "cold": cold, "n_q": mech.n_q, "f": rod_len / length,
            "zones": zones, "iterations": eq.stats["iterations"], "drift": drift,
            "step_iterations": tr.stats.get("newton_iterations", float("nan")),
            "segments": round(length / ds)}


def tension(out) -> tuple[np.ndarray, np.ndarray]:
    """(s at each edge's midpoint, tension = internal force along the edge), m and N."""
    X = np.asarray(out["positions"], float)
    dx = np.diff(X, axis=0)
    ell = np.linalg.norm(dx, axis=1)
    s = np.concatenate([[0.0], np.cumsum(ell)])
    T = np.einsum("ij,ij->i", np.asarray(out["internal_force"], float), dx / ell[:, None])
    return 0.5 * (s[1:] + s[:-1]), T


def compare(a, ref) -> dict:
    """The difference of solution ``a`` from ``ref`` (same nodes): tension relative to ref's
    peak, positions (m), the lifted end (m), and where ``ref`` lifts off the bed."""
    oa, orf = a.outputs, ref.outputs
    _, Ta = tension(oa)
    s, Tr = tension(orf)
    Xa, Xr = np.asarray(oa["positions"]), np.asarray(orf["positions"])
    c = np.ravel(orf["contact_force"])
    lift = float(s[np.flatnonzero(c[1:] > 0.5 * c.max())[-1]]) if c.max() > 0 else float("nan")
    return {"tension_err": float(np.abs(Ta - Tr).max() / np.abs(Tr).max()),
            "pos_err": float(np.abs(Xa - Xr).max()),
            "end_err": float(np.linalg.norm(Xa[-1] - Xr[-1])), "T_peak": float(Tr.max()),
            "touchdown_s": lift}


def predicted(f: float) -> float:
    """The per-segment cost model's speed-up of the hybrid over the rod at rod fraction f."""
    return 1.0 / (f + C_RATIO * (1.0 - f))


def run(length: float, repeats: int, models=("rod", "hybrid", "auto"), ds: float = DS
        ) -> list[dict]:
    """One length: each model built and solved, then its static solve and its 1 s steps
    timed interleaved; rows with the ratios and the differences from the rod."""
    cases = {}
    for m in models:
        try:
            cases[m] = case(m, length, ds)
        except SymcableError as exc:
            print(f"  {length:g} m {m}: failed: {str(exc)[:200]}")
    jobs = {}
    for m, c in cases.items():
        jobs[(m, "static")] = c["static"]
        jobs[(m, "step")] = c["steps"]
    t = interleaved(jobs, repeats)
    if "rod" not in cases:
        return []
    rod = cases["rod"]
    rows = []
    for m, c in cases.items():
        r = {k: c[k] for k in ("length", "model", "segments", "n_q", "f", "iterations",
                               "step_iterations", "cold", "drift")}
        r["zones"] = "" if c["zones"] is None else \
            ";".join(f"{a:.3g}-{b:.3g}" for a, b in c["zones"])
        r["static_s"], r["step_s"] = t[(m, "static")], t[(m, "step")] / STEPS
        r["static_ratio"] = t[("rod", "static")] / t[(m, "static")]
        r["step_ratio"] = t[("rod", "step")] / t[(m, "step")]
        r["predicted"] = predicted(c["f"])
        # per Newton iteration: the cost model's unit (the paths' iteration counts differ)
        r["static_it_ratio"] = r["static_ratio"] * c["iterations"] / rod["iterations"]
        r["step_it_ratio"] = r["step_ratio"] * c["step_iterations"] / rod["step_iterations"]
        r.update(compare(c["eq"], rod["eq"]))
        rows.append(r)
        print(f"  {length:g} m {m:6s} f={c['f']:.4f} n_q={c['n_q']} static "
              f"{r['static_s']:.3f} s ({r['iterations']} it) step {r['step_s']:.3f} s "
              f"ratios {r['static_ratio']:.2f} / {r['step_ratio']:.2f} (model "
              f"{r['predicted']:.2f}) per iteration {r['static_it_ratio']:.2f} / "
              f"{r['step_it_ratio']:.2f} (step its {r['step_iterations']}) "
              f"dT {r['tension_err']:.2e} dX {r['pos_err']:.2e}",
              flush=True)
    return rows


def table(rows: list[dict]) -> str:
    """The summary's markdown table, one row per (length, model)."""
    cols = ("L (m)", "model", "segments", "unknowns", "rod fraction f", "rod zones (m)",
            "static Newton it", "static warm (s)", "per 1 s step (s)", "step Newton it",
            "speed-up static", "speed-up step", "per iteration: static, step", "cost model",
            "tension diff / peak", "max position diff (m)", "end diff (m)")
    head = "| " + " | ".join(cols) + " |\n|" + "---|" * len(cols) + "\n"
    body = "".join(
        f"| {r['length']:g} | {r['model']} | {r['segments']} | {r['n_q']} | {r['f']:.4f} | "
        f"{r['zones'] or '-'} | {r['iterations']} | {r['static_s']:.3f} | {r['step_s']:.4f} |"
        f" {r['step_iterations']} | {r['static_ratio']:.2f} | {r['step_ratio']:.2f} | "
        f"{r['static_it_ratio']:.2f}, {r['step_it_ratio']:.2f} | {r['predicted']:.2f} | "
        f"{r['tension_err']:.2e} | {r['pos_err']:.2e} | {r['end_err']:.2e} |\n"
        for r in rows)
    return head + body


def main(argv=None) -> dict:
    args = study_io.parse(__doc__, "3 m at ds = 0.1 m, rod and hybrid, 1 repeat",
                          HERE / "out", argv)
    lengths, repeats = ((3.0,), 1) if args.quick else ((3.0, 10.0, 20.0, 40.0), 5)
    ds = 0.1 if args.quick else DS
    models = ("rod", "hybrid") if args.quick else ("rod", "hybrid", "hybrid-td", "auto")
    rows = []
    for L in lengths:
        rows += run(L, repeats, models, ds)
    text = ("# The seed cable laid on the bed: rod vs hybrid against the rod fraction\n\n"
            f"Medians of {repeats} interleaved warm repeats; ds = {ds} m; {STEPS} steps of "
            f"{DT} s (first-order generalized-alpha, rho_inf = 0) per timing; the VM "
            "throughout.\n\n"
            + table(rows))
    print(text)
    study_io.write_tables(args.out, rows, text, ("results_laid", "summary_laid"))
    return {"rows": rows}


if __name__ == "__main__":
    main()
