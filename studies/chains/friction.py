"""Seabed friction laws on the MoorDyn chain decks: what each law costs and how far each is
from the others and from OrcaFlex, at the fairlead and at the anchor (issue 12, item 2).

Question
--------
symcable's cable3d has two friction laws (``seabed.friction_law``,
:mod:`symcable.models.common.friction`): the regularised Coulomb law
-mu N v / sqrt(|v|^2 + v_eps^2), no state, which creeps under any load below mu N; and the
bristle law, an elastic bristle per node (first-order states) that holds force at rest and
slips at mu N. On the three chains (WD0050, WD0200, WD0600) under both heaves (ZZP1_A1, A2),
with symcable's default scheme (``simulate``'s: first-order generalized-alpha, rho_inf = 0) at
dt = 0.1 s in generated C, what does each law cost (wall time of static solve plus run,
Newton iterations per step), how far is each from OrcaFlex (max and rms fairlead and anchor
tension error, % of OrcaFlex's range; the study README: the anchor is 24-158 % off with the
Coulomb law as the decks map MoorDyn's friction, the grounded chain sliding almost freely),
and how far are the laws from each other? Which should be the default?

Variants (``VARIANTS``): the Coulomb law as the loader reads the decks (v_eps = w ds /
FricDamp = 166 m/s: MoorDyn's viscous 0.5 x 200 N s/m per node, far below its cap), the
Coulomb law at symcable's default v_eps = 0.01 m/s, and the bristle law at the decks' normal
stiffness (kBot = 1e5 Pa/m, the default ``friction_stiffness``, OrcaFlex's default shear
stiffness: mobilisation length mu N / k = 6.6 cm) and at 1e6 Pa/m (6.6 mm, within the
1-10 mm the research note suggests).

Beside them, where it is installed (``pip install cabledyn``), CableDyn at the same step
with its own model (row ``CABLEDYN``, timed in the same interleaved rounds): which friction
reading reaches CableDyn's accuracy, and at what share of its wall time.

Everything else as ``run.py`` (``cases.py``): the deck with the extended table on the
fairlead, at rest in its static state at t = -10 s; errors over t = 0..20 s at the
reference's samples; the wall time the median of ``repeats`` rounds after a first (warming)
run, the variants interleaved.

Run
---
    python studies/chains/friction.py            # full: six cases x four variants, C
    python studies/chains/friction.py --quick    # WD0050 A1 over 0..5 s, two laws, VM

Writes into ``--out`` (default ``studies/chains/out/friction/``) ``results.json``,
``results.csv``, ``summary.md`` and ``friction_anchor.png`` (anchor tension, OrcaFlex and the
variants, six cases). ``main(argv)`` returns the result dict.
"""
from __future__ import annotations

import importlib.util
import json
import sys
import time
from pathlib import Path

import numpy as np

from symcable.api.cable3d_static import cable3d_mechanism
from symcable.errors import SymcableError
from symcable.scene import load_scene
from symcable.solvers.equilibrium import solve_equilibrium
from symcable.solvers.integrate import integrate
from symcable.solvers.options import GeneralizedAlphaFirstOrder

HERE = Path(__file__).resolve().parent
if str(HERE.parent) not in sys.path:
    sys.path.append(str(HERE.parent))
import study_io  # noqa: E402  (studies/study_io.py)


def _load_helper(name: str):
    spec = importlib.util.spec_from_file_location(f"chains_{name}", HERE / f"{name}.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


cases = _load_helper("cases")
peers = _load_helper("peers")

#: name -> (seabed keys over the deck's, what it is)
VARIANTS = {
    "coulomb (deck)": ({}, "regularised Coulomb, v_eps = w ds / FricDamp = 166 m/s (the loader's "
                           "reading of MoorDyn's friction)"),
    "coulomb 0.01": ({"friction_velocity": 0.01}, "regularised Coulomb, v_eps = 0.01 m/s "
                                                  "(symcable's default)"),
    "bristle": ({"friction_law": "bristle"}, "bristle, friction_stiffness = kBot = 1e5 Pa/m "
                                             "(the default; mobilisation 6.6 cm)"),
    "bristle 1e6": ({"friction_law": "bristle", "friction_stiffness": 1e6},
                    "bristle, friction_stiffness = 1e6 Pa/m (mobilisation 6.6 mm)"),
}
BASE = "coulomb (deck)"
DT = 0.1
RHO_INF = 0.0  # simulate's default for cable3d (symcable.api.cable3d.RHO_INF)
MAX_ITER = 30  # the start from rest into the table's full speed (cases.MAX_ITER_GA1)
FULL = dict(decks=cases.DECKS, motions=cases.MOTIONS, variants=tuple(VARIANTS), t_end=20.0,
            repeats=3, codegen=True, cabledyn=True)
QUICK = dict(decks=("WD0050",), motions=("A1",), variants=(BASE, "bristle"), t_end=5.0,
             repeats=1, codegen=False, cabledyn=True)
#: the row of CableDyn (the peer, run as in run.py at DT, with its own friction model)
CABLEDYN = "CableDyn (peer)"


def variant_scene(deck: str, table: Path, variant: str):
    d = cases.chain_scene(deck, table).to_dict()
    d["seabed"].update(VARIANTS[variant][0])
    return load_scene(d)


class Run:
    """One variant of one case: ``once()`` -> (trajectory, static s, run s)."""

    def __init__(self, scene, t_end: float, codegen: bool):
        self.mech = cable3d_mechanism(scene)
        self.t_end, self.codegen = t_end, codegen
        self.method = GeneralizedAlphaFirstOrder(rho_inf=RHO_INF, max_iter=MAX_ITER)

    def once(self):
        t0 = time.perf_counter()
        eq = solve_equilibrium(self.mech, codegen=self.codegen)
        t1 = time.perf_counter()
        tr = integrate(self.mech, self.t_end - cases.T0, DT, t0=cases.T0, start=eq,
                       p=self.mech.params.values, method=self.method, codegen=self.codegen,
                       period=cases.PERIOD, progress=False)
        return tr, t1 - t0, time.perf_counter() - t1


def _errors(ser, ref, t_end) -> dict:
    m = ref[:, 0] <= t_end + 1e-9
    t = ref[m, 0]
    out = {}
    for key, col, name in (("fairlead", 3, "fair"), ("fairlead_segment", 3, "seg"),
                           ("anchor", 4, "anch")):
        e = cases.errors(ser["time"], ser[key], t, ref[m, col], float(np.ptp(ref[m, col])))
        out.update({f"{name}_max": e["max"], f"{name}_rms": e["rms"], f"{name}_mean": e["mean"]})
    return out


def _difference(ser, base, ref, t_end) -> dict:
    """Max |this - base| at the reference's samples, % of OrcaFlex's range."""
    m = ref[:, 0] <= t_end + 1e-9
    t = ref[m, 0]
    out = {}
    for key, col, name in (("fairlead", 3, "fair"), ("anchor", 4, "anch")):
        d = np.interp(t, ser["time"], ser[key]) - np.interp(t, base["time"], base[key])
        out[f"{name}_vs_base"] = 100 * float(np.max(np.abs(d))) / float(np.ptp(ref[m, col]))
    return out


def run_case(deck, motion, cfg, out: Path) -> tuple[list, dict]:
    table = cases.extended_table(motion, out)
    ref = cases.reference(deck, motion)
    rows, series, runs = [], {"OrcaFlex": {"time": ref[:, 0].tolist(),
                                            "anchor": ref[:, 4].tolist()}}, {}
    for v in cfg["variants"]:
        row = {"deck": deck, "motion": motion, "variant": v, "law": VARIANTS[v][1],
               "dt_s": DT, "status": "ok"}
        runner = Run(variant_scene(deck, table, v), cfg["t_end"], cfg["codegen"])
        try:
            tr, s0, r0 = runner.once()
        except SymcableError as exc:  # a step's Newton failed
            rows.append(dict(row, status="failed", note=str(exc).split(": try")[0][:160]))
            continue
        ser = cases.tensions(tr)
        st = tr.stats
        row.update(_errors(ser, ref, cfg["t_end"]), first_wall_s=s0 + r0,
                   compiled=st["compiled"], states=runner.mech.n_q + runner.mech.n_v,
                   newton_per_step=(st.get("newton_iterations") or 0) / st["steps"],
                   newton_max=st.get("newton_iterations_max"))
        rows.append(row)
        series[v] = {k: np.asarray(ser[k]).tolist() for k in ("time", "fairlead", "anchor")}
        runs[v] = (runner.once, len(rows) - 1)
    if cfg.get("cabledyn") and peers.available()["CableDyn"]:
        _cabledyn_row(deck, motion, cfg, ref, rows, series, runs)
    if BASE in series:
        for r in rows:
            if r["status"] == "ok":
                r.update(_difference(series[r["variant"]], series[BASE], ref, cfg["t_end"]))
    walls = {v: [] for v in runs}
    for _ in range(cfg["repeats"]):
        for v, (call, _) in runs.items():
            _, s, r = call()
            walls[v].append((s + r, s, r))
    for v, w in walls.items():
        a = np.median(np.array(w), axis=0)
        rows[runs[v][1]].update(wall_s=float(a[0]), static_s=float(a[1]), run_s=float(a[2]))
    return rows, series


def summary(res: dict) -> str:
    cfg = res["config"]
    f = lambda x, p=1: "-" if x is None else f"{x:.{p}f}"  # noqa: E731
    lines = ["# Seabed friction laws on the chain decks", "",
             f"First-order generalized-alpha (rho_inf = {RHO_INF:g}) at dt = {DT} s, "
             f"{'generated C' if cfg['codegen'] else 'virtual machine'}; errors over "
             f"t = 0..{cfg['t_end']:g} s, % of OrcaFlex's range (fair: the line's force on the "
             "fairlead; seg: the top segment's tension; anch: the anchor; mean: the mean "
             "error); vs coulomb (deck): max difference from that variant's series, % of "
             f"OrcaFlex's range. Wall: static + run, median of {cfg['repeats']} rounds after a "
             "first run.", "",
             "| case | law | fair max / rms | seg max | anch max / rms / mean | "
             "vs coulomb (deck): fair / anch | Newton / step (max) | states | wall (s) |",
             "|" + "---|" * 9]
    for r in res["rows"]:
        case = f"{r['deck']} {r['motion']}"
        if r["status"] != "ok":
            lines.append(f"| {case} | {r['variant']} | failed: {r.get('note', '')} |"
                         + " |" * 6)
            continue
        lines.append(
            f"| {case} | {r['variant']} | {f(r['fair_max'])} / {f(r['fair_rms'])} | "
            f"{f(r['seg_max'])} | {f(r['anch_max'])} / {f(r['anch_rms'])} / "
            f"{f(r['anch_mean'])} | {f(r.get('fair_vs_base'))} / {f(r.get('anch_vs_base'))} | "
            f"{f(r['newton_per_step'], 2)} ({r.get('newton_max') or '-'}) | "
            f"{r['states'] or '-'} | "
            f"{f(r.get('wall_s'), 3)} |")
    lines += ["", "Variants:", ""] + [f"- {k}: {v[1]}" for k, v in VARIANTS.items()
                                      if k in cfg["variants"]]
    if any(r["variant"] == CABLEDYN for r in res["rows"]):
        lines.append(f"- {CABLEDYN}: CableDyn at dt = {DT} s with its own model (as run.py "
                     "runs it; its FairTen1 in both fairlead columns), timed in the same rounds")
    return "\n".join(lines) + "\n"


def plot_anchor(res: dict, path: Path) -> None:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    cases_ = list(res["series"])
    fig, axes = plt.subplots(len(cases_), 1, figsize=(9, 2.3 * len(cases_)), squeeze=False)
    t_end = res["config"]["t_end"]
    for ax, case in zip(axes[:, 0], cases_):
        for name, s in res["series"][case].items():
            t = np.asarray(s["time"])
            m = (t >= 0) & (t <= t_end)
            ax.plot(t[m], np.asarray(s["anchor"])[m], "k" if name == "OrcaFlex" else "-",
                    lw=2.0 if name == "OrcaFlex" else 1.0, label=name)
        ax.set_title(f"{case}: anchor tension", fontsize=9)
        ax.set_ylabel("kN")
    axes[0, 0].legend(fontsize=7, ncol=3)
    axes[-1, 0].set_xlabel("t (s)")
    fig.tight_layout()
    fig.savefig(path, dpi=90)
    plt.close(fig)


def _cabledyn_row(deck, motion, cfg, ref, rows, series, runs) -> None:
    """CableDyn at DT beside the variants (as ``run.py`` runs it: its FairTen1 stands for
    both fairlead columns), timed in the same interleaved rounds: appended to ``rows``,
    ``series`` and ``runs``."""
    row = {"deck": deck, "motion": motion, "variant": CABLEDYN, "law": "CableDyn's own model",
           "dt_s": DT, "status": "ok"}

    def call():
        r = peers.run_cabledyn(cases.deck_path(deck), cases.motion_rows(motion), DT,
                               cfg["t_end"])
        return r, r["init"], r["wall"] - r["init"]

    try:
        r, s0, r0 = call()
    except Exception as exc:  # noqa: BLE001  (its ConvergenceError or CableDynError, as run.py)
        rows.append(dict(row, status="failed", note=(str(exc).splitlines() or [""])[0][:160]))
        return
    ser = {"time": r["time"], "fairlead": r["fairlead"], "fairlead_segment": r["fairlead"],
           "anchor": r["anchor"]}
    row.update(_errors(ser, ref, cfg["t_end"]), first_wall_s=s0 + r0, states=None,
               newton_per_step=r["newton"] / max(1, r["time"].size - 1), newton_max=None)
    rows.append(row)
    series[CABLEDYN] = {k: np.asarray(ser[k]).tolist() for k in ("time", "fairlead", "anchor")}
    runs[CABLEDYN] = (call, len(rows) - 1)


def main(argv=None) -> dict:
    args = study_io.parse(__doc__, "WD0050 A1 over 5 s, two laws, the virtual machine",
                          HERE / "out" / "friction", argv)
    cfg = QUICK if args.quick else FULL
    rows, series = [], {}
    for deck in cfg["decks"]:
        for motion in cfg["motions"]:
            r, s = run_case(deck, motion, cfg, args.out)
            rows += r
            series[f"{deck} {motion}"] = s
            print(f"{deck} {motion}: {len(r)} runs", flush=True)
    res = {"rows": rows, "series": series, "config": dict(cfg, dt=DT, rho_inf=RHO_INF),
           "quick": bool(args.quick)}
    (args.out / "results.json").write_text(json.dumps(res, default=float))
    study_io.write(args, rows, summary(res), lambda p: plot_anchor(res, p), "friction_anchor.png")
    return res


if __name__ == "__main__":
    main()
