"""The MoorDyn chain decks against OrcaFlex: symcable's cable3d at several time steps beside
MoorDyn and CableDyn run live, each with its error and its wall time (issue 12, studies).

Question
--------
On the three chains of MoorDyn's validation tests (WD0050, WD0200, WD0600: a chain from an
anchor on the seabed to a fairlead at the surface, 41/76/170 segments) under the two heave
motions (ZZP1_A1, ZZP1_A2: 2 m and 5 m, 10 s, a table from t = -10 s), how far is symcable's
fairlead and anchor tension from OrcaFlex's over t = 0..20 s (max and rms error, % of the
reference's range), at dt = 0.2, 0.1, 0.05 and 0.02 s, how much of that is the time step
(against symcable's own converged run) and how much the model, and how does it compare with
MoorDyn (its default scheme, CFL 0.1 as in the decks) and CableDyn (its default scheme) in
accuracy and in wall time? The issue's target: a max fairlead error no larger than MoorDyn's
at a step of at least 0.05 s with at most a quarter of MoorDyn's wall time (static solve plus
run, generated C), and CableDyn's accuracy at half its wall time or less.

Cases, scenes and runs: ``cases.py`` (the deck as MoorDyn reads it, the table extended past
20 s, the two symcable schemes); the peers: ``peers.py``. Every code starts at rest in its
static state at t = -10 s, where the table starts (at full heave speed). Errors are taken at
the reference's samples (every 0.1 s over [0, t_end]); symcable's series are interpolated
linearly between its steps. Wall times: the median of ``repeats`` rounds, each running every
code of the case once in turn (interleaved: the machine is shared and noisy), after a first
untimed run (symcable's caches: the generated C, the mapped step batches); symcable's is the
static solve plus the run (the Mechanism is built before, once per scene: about 0.1 s for
WD0050).

``--replot`` redraws the figures and tables from the out dir's ``results.json``.

``--quick`` (the test): WD0050 under A1 over t = 0..5 s, the second-order scheme at 0.1 s
against the first-order one at 0.01 s (the own reference), both in the virtual machine, one
repeat (its series must equal the first run's: the determinism check), the peers if
installed.

Run
---
    python studies/chains/run.py              # full: about 30 minutes on 2 shared cores
                                              # (compiling C for three decks included)
    python studies/chains/run.py --quick      # about 15 s
    options: --out DIR (default studies/chains/out/), --figure PATH (extra copy of the
    fairlead figure), --moordyn-ic DIR (the decks' fileIC start files <deck>.txt.ic, from
    MoorDyn's repository, tests/Mooring/: MoorDyn then starts from them, as in its own test)

Writes ``results.json`` (rows, series, configuration), ``results.csv`` (one row per run),
``summary.md`` (the tables), ``chains_fairlead.png`` (the six fairlead series),
``chains_anchor.png`` and ``chains_accuracy.png`` (max error against wall time). ``main(argv)``
returns the result dict.
"""
from __future__ import annotations

import importlib.util
import json
import sys
from pathlib import Path
from typing import NamedTuple

import numpy as np

from symcable.errors import SymcableError

HERE = Path(__file__).resolve().parent
if str(HERE.parent) not in sys.path:
    sys.path.append(str(HERE.parent))
import study_io  # noqa: E402  (studies/study_io.py)


def _load_helper(name: str):
    """Import ``HERE/<name>.py`` by its file path (studies/ is not a package; a folder on
    ``sys.path`` would let its modules shadow installed ones)."""
    spec = importlib.util.spec_from_file_location(f"chains_{name}", HERE / f"{name}.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


cases = _load_helper("cases")
peers = _load_helper("peers")
plots = _load_helper("plots")

#: the issue's MoorDyn 2.7.2 max fairlead errors (% of range), measured there
ISSUE_MOORDYN = {("WD0050", "A1"): 14.1, ("WD0050", "A2"): 11.1, ("WD0200", "A1"): 10.0,
                 ("WD0200", "A2"): 9.5, ("WD0600", "A1"): 10.1, ("WD0600", "A2"): 11.7}
#: the issue's CableDyn max fairlead errors at dt = 0.1 s
ISSUE_CABLEDYN = {("WD0050", "A1"): 17.6, ("WD0050", "A2"): 6.8, ("WD0200", "A1"): 9.7,
                  ("WD0200", "A2"): 9.3, ("WD0600", "A1"): 7.1, ("WD0600", "A2"): 10.9}


class Config(NamedTuple):
    decks: tuple
    motions: tuple
    dts: tuple  # s: symcable's steps
    schemes: tuple  # keys of cases.SCHEMES
    ref_dt: float  # s: symcable's own converged run
    ref_scheme: str
    t_end: float  # s: the errors are over [0, t_end]
    repeats: int  # timed rounds after the first run
    codegen: bool
    cabledyn_dts: tuple


FULL = Config(cases.DECKS, cases.MOTIONS, (0.2, 0.1, 0.05, 0.02),
              ("GA2", "GA1", "GA1-rho0.2"), 0.0025, "GA1", 20.0, 3, True, (0.2, 0.1, 0.05, 0.02))
QUICK = Config(("WD0050",), ("A1",), (0.1,), ("GA2",), 0.01, "GA1", 5.0, 1, False, (0.1,))


def _err_fields(prefix, series, key, t_ref, F_ref, rng):
    e = cases.errors(series["time"], series[key], t_ref, F_ref, rng)
    return {f"{prefix}_max": e["max"], f"{prefix}_rms": e["rms"], f"{prefix}_mean": e["mean"]}


def _row(deck, motion, code, scheme, dt, series, ref, t_end, **extra) -> dict:
    """One result row: errors of ``series`` against OrcaFlex (``ref``) over [0, t_end]."""
    m = ref[:, 0] <= t_end + 1e-9
    t, Ff, Fa = ref[m, 0], ref[m, 3], ref[m, 4]
    rf, ra = float(np.ptp(Ff)), float(np.ptp(Fa))
    row = {"deck": deck, "motion": motion, "code": code, "scheme": scheme, "dt_s": dt,
           "status": "ok"}
    if series is None:
        return dict(row, **extra)
    row.update(_err_fields("fair", series, "fairlead", t, Ff, rf))
    row.update(_err_fields("anch", series, "anchor", t, Fa, ra))
    if "fairlead_segment" in series:
        row.update(_err_fields("fairseg", series, "fairlead_segment", t, Ff, rf))
    return dict(row, **extra)


def _sample(series, keys, every=None) -> dict:
    """A series as lists for the JSON (optionally thinned to one sample per ``every`` s)."""
    t = np.asarray(series["time"])
    idx = slice(None)
    if every is not None and t.size > 1 and t[1] - t[0] < every:
        idx = slice(None, None, max(1, int(round(every / (t[1] - t[0])))))
    return {k: np.asarray(series[k])[idx].tolist() for k in ("time", *keys) if k in series}


def run_case(deck, motion, cfg: Config, out: Path, have: dict, ic_dir) -> tuple[list, dict]:
    """Rows and plot series of one deck under one motion."""
    table = cases.extended_table(motion, out)
    scene = cases.chain_scene(deck, table)
    ref = cases.reference(deck, motion)
    rows, series = [], {"orcaflex": {"time": ref[:, 0].tolist(), "fairlead": ref[:, 3].tolist(),
                                     "anchor": ref[:, 4].tolist()}}
    keys = ("fairlead", "anchor", "fairlead_segment")
    own = cases.SymcableRun(scene, cfg.ref_dt, cfg.t_end, cfg.ref_scheme, cfg.codegen)
    tr, s0, r0 = own.once()
    own_ser = cases.tensions(tr)
    series[f"symcable {cfg.ref_scheme} {cfg.ref_dt}"] = _sample(own_ser, keys, every=0.01)
    rows.append(_row(deck, motion, "symcable", cfg.ref_scheme, cfg.ref_dt, own_ser, ref, cfg.t_end,
                     reference=True, first_wall_s=s0 + r0, compiled=tr.stats["compiled"]))
    m = ref[:, 0] <= cfg.t_end + 1e-9
    t_ref = ref[m, 0]
    timed = {}  # label -> (callable, row index, first series)
    for scheme in cfg.schemes:
        for dt in cfg.dts:
            runner = cases.SymcableRun(scene, dt, cfg.t_end, scheme, cfg.codegen)
            try:
                tr, s0, r0 = runner.once()
            except SymcableError as exc:  # ConvergenceError: a step's Newton failed
                rows.append(_row(deck, motion, "symcable", scheme, dt, None, ref, cfg.t_end,
                                 status="failed", note=str(exc).split(": try")[0]))
                continue
            ser = cases.tensions(tr)
            series[f"symcable {scheme} {dt}"] = _sample(ser, keys)
            terr = {}
            for key, name in (("fairlead", "time_err"), ("fairlead_segment", "time_errseg")):
                e = cases.errors(ser["time"], ser[key], t_ref,
                                 np.interp(t_ref, own_ser["time"], own_ser[key]),
                                 float(np.ptp(ref[m, 3])))
                terr[f"{name}_max"], terr[f"{name}_rms"] = e["max"], e["rms"]
            st = tr.stats
            rows.append(_row(deck, motion, "symcable", scheme, dt, ser, ref, cfg.t_end, **terr,
                             first_wall_s=s0 + r0, compiled=st["compiled"],
                             newton_per_step=(st.get("newton_iterations") or 0) / st["steps"],
                             error_estimate=st["error_estimate"],
                             warned=any("too coarse" in w for w in tr.warnings)))
            timed[f"symcable {scheme} {dt}"] = (runner.once, len(rows) - 1, ser)
    if have.get("MoorDyn"):
        rows_md = cases.motion_rows(motion)
        # with the decks' start files (when given: MoorDyn's own test starts from them) and
        # without (MoorDyn's dynamic relaxation from its catenary guess)
        for ic in ((ic_dir, None) if ic_dir is not None else (None,)):
            call = (lambda ic=ic: peers.run_moordyn(cases.deck_path(deck), rows_md, cfg.t_end, ic))
            res = call()
            label = "MoorDyn" if ic is not None or ic_dir is None else "MoorDyn no-IC-file"
            series[label] = _sample(res, ("fairlead", "anchor"))
            rows.append(_row(deck, motion, "MoorDyn", f"RK2, dtM {res['dtM']:.4g} s (CFL 0.1), "
                             f"start: {res['ic']}", 0.1, res, ref, cfg.t_end, init_s=res["init"],
                             start=res["ic"], issue_fair_max=ISSUE_MOORDYN.get((deck, motion))))
            timed[label] = (call, len(rows) - 1, None)
    else:
        rows.append(_row(deck, motion, "MoorDyn", "-", None, None, ref, cfg.t_end,
                         status="not installed"))
    if have.get("CableDyn"):
        for dt in cfg.cabledyn_dts:
            call = (lambda dt=dt: peers.run_cabledyn(cases.deck_path(deck), cases.motion_rows(motion),
                                                     dt, cfg.t_end))
            try:
                res = call()
            except Exception as exc:  # noqa: BLE001  (its ConvergenceError or CableDynError)
                rows.append(_row(deck, motion, "CableDyn", "default", dt, None, ref, cfg.t_end,
                                 status="failed", note=str(exc)[:200]))
                continue
            series[f"CableDyn {dt}"] = _sample(res, ("fairlead", "anchor"))
            rows.append(_row(deck, motion, "CableDyn", "default (generalized-alpha)", dt, res,
                             ref, cfg.t_end, init_s=res["init"],
                             newton_per_step=res["newton"] / max(1, len(res["time"]) - 1),
                             issue_fair_max=ISSUE_CABLEDYN.get((deck, motion)) if dt == 0.1 else None))
            timed[f"CableDyn {dt}"] = (call, len(rows) - 1, None)
    else:
        rows.append(_row(deck, motion, "CableDyn", "-", None, None, ref, cfg.t_end,
                         status="not installed"))
    _time_rounds(timed, rows, cfg.repeats)
    return rows, series


def _time_rounds(timed: dict, rows: list, repeats: int) -> None:
    """Interleaved timed rounds; writes ``wall_s`` (and symcable's ``static_s``, ``run_s``,
    ``repeat_diff_kN``: the largest change of its fairlead series from the first run)."""
    walls = {k: [] for k in timed}
    for _ in range(repeats):
        for label, (call, i, first) in timed.items():
            res = call()
            if label.startswith("symcable"):
                tr, s, r = res
                walls[label].append((s + r, s, r))
                ser = cases.tensions(tr)
                diff = float(np.max(np.abs(ser["fairlead"] - first["fairlead"])))
                rows[i]["repeat_diff_kN"] = max(rows[i].get("repeat_diff_kN", 0.0), diff)
            else:
                walls[label].append((res["wall"], res["init"], res["wall"] - res["init"]))
    for label, w in walls.items():
        if w:
            a = np.median(np.array(w), axis=0)
            rows[timed[label][1]].update(wall_s=float(a[0]), static_s=float(a[1]), run_s=float(a[2]))


def run_study(cfg: Config, out: Path, ic_dir=None) -> dict:
    have = peers.available()
    rows, series = [], {}
    for deck in cfg.decks:
        for motion in cfg.motions:
            r, s = run_case(deck, motion, cfg, out, have, ic_dir)
            rows += r
            series[f"{deck} {motion}"] = s
            print(f"{deck} {motion}: {len(r)} runs", flush=True)
    return {"rows": rows, "series": series, "peers": have, "config": cfg._asdict(),
            "verdicts": verdicts(rows, cfg)}


def verdicts(rows: list, cfg: Config) -> list:
    """Per case: the issue's criteria. For each scheme and tension (the force on the
    fairlead, the top segment's), symcable's cheapest run at dt >= 0.05 s whose max error is
    no larger than MoorDyn's (live, unrounded; ``meets``), else its most accurate run there."""
    out = []
    for deck in cfg.decks:
        for motion in cfg.motions:
            rs = [r for r in rows if (r["deck"], r["motion"]) == (deck, motion)]
            md = next((r for r in rs if r["code"] == "MoorDyn" and r["status"] == "ok"), None)
            cd = next((r for r in rs if r["code"] == "CableDyn" and r["dt_s"] == 0.1
                       and r["status"] == "ok"), None)
            own = next(r for r in rs if r.get("reference"))
            md_own = next((r for r in rs if r["code"] == "MoorDyn" and r["status"] == "ok"
                           and r.get("start") == "its IC solve"), None)
            v = {"deck": deck, "motion": motion, "issue_moordyn_max": ISSUE_MOORDYN[(deck, motion)],
                 "moordyn_max": md and md["fair_max"], "moordyn_wall": md and md.get("wall_s"),
                 "moordyn_wall_own": md_own and md_own.get("wall_s"),
                 "cabledyn_max": cd and cd["fair_max"], "cabledyn_wall": cd and cd.get("wall_s"),
                 "model_error": own["fair_max"], "model_error_seg": own["fairseg_max"]}
            for scheme in cfg.schemes:
                for key in ("fair", "fairseg"):
                    ok = [r for r in rs if r["code"] == "symcable" and r["scheme"] == scheme
                          and r["status"] == "ok" and not r.get("reference") and r["dt_s"] >= 0.05]
                    if not ok:
                        continue
                    meets = [r for r in ok if md and r[f"{key}_max"] <= md["fair_max"]]
                    best = (min(meets, key=lambda r: r.get("wall_s") or np.inf) if meets
                            else min(ok, key=lambda r: r[f"{key}_max"]))
                    v[f"{scheme} {key}"] = {"dt": best["dt_s"], "max": best[f"{key}_max"],
                                            "wall": best.get("wall_s"), "meets": bool(meets)}
            out.append(v)
    return out


def main(argv=None) -> dict:
    def extra(ap):
        ap.add_argument("--moordyn-ic", type=Path, default=None,
                        help="folder with the decks' fileIC start files (<deck>.txt.ic)")
        ap.add_argument("--replot", action="store_true",
                        help="redraw the figures and tables from the out dir's results.json")
    args = study_io.parse(__doc__, "WD0050 under A1 over 5 s, one step, the virtual machine",
                          HERE / "out", argv, extra)
    if args.replot:
        res = json.loads((args.out / "results.json").read_text())
        res["verdicts"] = verdicts(res["rows"], Config(**res["config"]))
    else:
        cfg = QUICK if args.quick else FULL
        res = run_study(cfg, args.out, args.moordyn_ic)
        res["quick"] = bool(args.quick)
        (args.out / "results.json").write_text(json.dumps(res, default=float))
    plots.anchor(res, args.out / "chains_anchor.png")
    plots.accuracy(res, args.out / "chains_accuracy.png")
    study_io.write(args, res["rows"], plots.summary(res), lambda p: plots.fairlead(res, p),
                   "chains_fairlead.png")
    return res


if __name__ == "__main__":
    main()
