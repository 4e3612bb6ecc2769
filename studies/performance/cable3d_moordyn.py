"""symcable's cable3d against MoorDyn at equal accuracy (issue 12, item 8: performance).

Question: on a chain with seabed contact and friction driven by a motion table (MoorDyn's
WD0050 deck under the ZZP1_A1 heave, run for 80 s) and on the seed-001 line in 3D, how long
does symcable take against MoorDyn when both are equally accurate?

Cases
-----
* ``WD0050``: the scene of ``studies/chains/cases.py`` (the deck read by symcable's loader,
  the heave table on the vessel end), the table continued periodically (10 s) to 90 s; both
  codes start at rest at its first row, t = -10 s, and run to t = 80 s. Compared: the top
  segment's tension (symcable ``axial_force[-1]``; MoorDyn ``GetLineNodeTen`` of the
  fairlead node, its FairTen), both with the deck's axial damping, at the table's rows
  (every 0.1 s) over 0..80 s.
* ``seed001``: ``symcable/data/seed001.toml`` as a cable3d scene in the x-z plane (y = 0:
  ends, current and the elliptic fairlead motion the planar ones with a zero y component)
  with the axial damping MoorDyn's RK2 needs to be stable (``damping = -1``: 100 % of each
  segment's critical damping, ``BA/-zeta = -1`` in MoorDyn's deck, read alike by both), 30
  periods (300 s). Compared: the force on the fairlead (symcable ``|end_force_b|``;
  MoorDyn ``|F - M a|``, dated half a MoorDyn step earlier: ``moordyn_line.py``) every 0.1 s
  over 0..300 s. MoorDyn's deck and driver: ``moordyn_line.py`` (its volume-equivalent
  diameter and coefficients).

CableDyn (issue 12 asks for it beside symcable here too) runs on WD0050 when installed
(``pip install cabledyn``): the deck as ``studies/chains/peers.py`` edits it, the fairlead
driven by the same table, at a ladder of steps. Its model is not MoorDyn's (it holds the
grounded chain differently: ``studies/chains/README.md``), so its accuracy is its error
against its own converged run (``cd_ref``), set against the same bound as symcable's
(MoorDyn's error at CFL 0.1): each code at its own equal-accuracy step, each against its
own model. Not run on seed001 (its deck and elliptic motion would need a CableDyn driver of
their own).

Accuracy: every run's max (and rms) error against symcable's converged run (``ref_dt``;
its own convergence is shown by the run at twice that step), % of that run's range. MoorDyn
runs its default scheme (RK2) at CFL 0.1, 0.2 and 0.4 (its ``cfl`` option: dtM = CFL x its
estimate of a segment's axial period) and at the largest CFL found stable (``MD_CFL_MAX``);
an unstable one is a row "unstable". symcable runs ``simulate`` (first-order generalized-alpha,
rho_inf = 0, generated C) on a ladder of steps; its equal-accuracy step is the largest whose
max error is no larger than MoorDyn's at CFL 0.1, with every smaller rung's too (WD0050:
the ladder itself; seed001: T/n, n from the measured second order, raised until it holds).

Wall time: symcable ``sc.simulate`` from the Scene (static solve + run; the Mechanism
cached, the C compiled: one untimed run first); MoorDyn Create + Init (its IC solve; for
seed001 also settling in the current, which its IC ignores) + stepping. Medians of
``repeats`` interleaved rounds (the machine is shared); ratios symcable / MoorDyn.

``--quick`` (the test): 10 s of WD0050 and 3 periods of seed001, the CasADi virtual machine
(no compiling), one round.

Run: ``python studies/performance/cable3d_moordyn.py [--quick] [--out DIR]``; writes
``cable3d_moordyn.json`` and ``cable3d_moordyn.md``.
"""
from __future__ import annotations

import argparse
import json
import math
import sys
import time
from pathlib import Path
from typing import NamedTuple

import numpy as np

import symcable as sc
from symcable.scene import load_scene

HERE = Path(__file__).resolve().parent
if str(HERE.parent) not in sys.path:
    sys.path.append(str(HERE.parent))
from study_io import load_module  # noqa: E402  (studies/study_io.py)


cases = load_module(HERE.parent / "chains" / "cases.py", "chains_cases")
peers = load_module(HERE.parent / "chains" / "peers.py", "chains_peers")
mdl = load_module(HERE / "moordyn_line.py", "performance_moordyn_line")

#: MoorDyn's CFL numbers asked for, and the largest found stable on each case (RK2; found by
#: runs at steps of 0.01-0.02 in CFL: WD0050 runs at 0.16 and fails at 0.18, seed001 runs at
#: 0.13 and fails at 0.2, its measured limit dtM 0.0222 s being CFL 0.138)
MD_CFLS = (0.1, 0.2, 0.4)
MD_CFL_MAX = {"WD0050": 0.16, "seed001": 0.13}


class Config(NamedTuple):
    wd_end: float  # s: WD0050 runs from -10 s to this
    wd_dts: tuple  # s: symcable's ladder on WD0050
    wd_ref: float  # s: its converged run
    s1_periods: int
    s1_ns: tuple  # steps per period of symcable's ladder on seed001
    s1_ref: int  # steps per period of its converged run
    repeats: int
    codegen: bool
    cd_dts: tuple = (0.2, 0.1, 0.05, 0.025)  # s: CableDyn's ladder on WD0050
    cd_ref: float = 0.00625  # s: CableDyn's converged run


FULL = Config(80.0, (0.2, 0.1, 0.05, 0.025), 0.00125, 30, (25, 50, 100, 200), 1600, 9, True)
QUICK = Config(10.0, (0.2, 0.1), 0.01, 3, (50, 100), 400, 1, False, (0.2, 0.1), 0.025)


def periodic_table(out: Path, t_end: float) -> Path:
    """ZZP1_A1 continued with its 10 s period to ``t_end`` s, written into ``out``."""
    rows = cases.motion_rows("A1")
    per = int(round(cases.PERIOD / (rows[1, 0] - rows[0, 0])))  # rows per period
    assert np.allclose(rows[per:, 1:], rows[:-per, 1:]), "ZZP1_A1 is not periodic"
    k = np.arange(int(round((t_end - rows[0, 0]) / (rows[1, 0] - rows[0, 0]))) + 1)
    table = np.column_stack([np.round(rows[0, 0] + k * (rows[1, 0] - rows[0, 0]), 10),
                             rows[k % per, 1:]])
    path = Path(out) / f"ZZP1_A1_to{t_end:g}.txt"
    np.savetxt(path, table, fmt="%.10g")
    return path


def seed001_3d() -> dict:
    """The seed-001 scene as a cable3d dict in the x-z plane, with MoorDyn's damping."""
    d = load_scene(sc.demo_scene_path("seed001")).to_dict()
    d["model"] = "cable3d"
    for end in ("end_a", "end_b"):
        x, z = d[end]["position"]
        d[end]["position"] = [x, 0.0, z]
    m = d["end_b"]["motion"]
    m["amplitude"] = [m["amplitude"][0], 0.0, m["amplitude"][1]]
    m["phase_deg"] = [m["phase_deg"][0], 0.0, m["phase_deg"][1]]
    ux, uz = d["environment"]["current"]
    d["environment"]["current"] = [ux, 0.0, uz]
    (lt,) = d["line_types"].values()
    lt["damping"] = -1.0  # MoorDyn's BA/-zeta = -1 (moordyn_line.run's default zeta = 1)
    return d


def error(t_grid, t, series, ref) -> tuple[float, float]:
    """(max, rms) of ``series`` (at times ``t``) minus ``ref`` on ``t_grid``, % of ref's range
    there; both interpolated linearly."""
    d = np.interp(t_grid, t, series) - ref
    rng = float(np.ptp(ref))
    return 100 * float(np.max(np.abs(d))) / rng, 100 * float(np.sqrt(np.mean(d * d))) / rng


class Case:
    """One case's runners: ``symcable(dt)`` and ``moordyn(cfl)`` -> (time s, series N or kN,
    wall s, detail dict); ``grid`` the times the errors are taken at."""

    def __init__(self, name: str, cfg: Config, out: Path):
        self.name, self.cfg = name, cfg
        if name == "WD0050":
            self.table = periodic_table(out, cfg.wd_end + cases.PERIOD)
            self.scene = cases.chain_scene("WD0050", self.table)
            self.duration = cfg.wd_end - cases.T0
            self.grid = np.round(np.arange(0.0, cfg.wd_end + 1e-9, 0.1), 10)
            self.rows = np.loadtxt(self.table)
        else:
            self.scene = load_scene(seed001_3d())
            self.period = self.scene.end_b.motion.period
            self.duration = cfg.s1_periods * self.period
            self.grid = np.round(np.arange(0.0, self.duration + 1e-9, 0.1), 10)
            self.params = mdl.scene_parameters()

    def symcable(self, dt: float):
        c0, t0 = time.process_time(), time.perf_counter()
        tr = sc.simulate(self.scene, self.duration, dt=dt, codegen=self.cfg.codegen, progress=False)
        wall, cpu = time.perf_counter() - t0, time.process_time() - c0
        s = tr.stats
        series = np.asarray(tr.axial_force)[:, -1] if self.name == "WD0050" else tr.fairlead_tension
        return tr.time, series, wall, {"static_s": s["static_time"], "steps_s": s["step_time"],
                                       "newton_per_step": s["newton_iterations"] / s["steps"],
                                       "compiled": s["compiled"], "cpu_s": cpu}

    def cabledyn(self, dt: float):
        """CableDyn on WD0050 at the step ``dt`` (s): its FairTen1 (N)."""
        c0 = time.process_time()
        r = peers.run_cabledyn(cases.deck_path("WD0050"), self.rows, dt, self.cfg.wd_end)
        steps = max(1, r["time"].size - 1)
        return r["time"], 1e3 * r["fairlead"], r["wall"], {
            "init_s": r["init"], "newton_per_step": r["newton"] / steps,
            "cpu_s": time.process_time() - c0}

    def moordyn(self, cfl: float):
        c0 = time.process_time()
        if self.name == "WD0050":
            r = peers.run_moordyn(cases.deck_path("WD0050"), self.rows, self.cfg.wd_end, cfl=cfl)
            return r["time"], 1e3 * r["fairlead"], r["wall"], {
                "dtM": r["dtM"], "init_s": r["init"], "cpu_s": time.process_time() - c0}
        r = mdl.run(self.duration, mdl.cfl_dt(self.params, cfl))
        return (r["time"] - r["lag"], r["fairlead_tension"], r["init_time"] + r["wall_time"],
                {"dtM": r["dtM"], "init_s": r["init_time"], "cpu_s": time.process_time() - c0})


def run_case(name: str, cfg: Config, out: Path) -> dict:
    """Errors of every run, the equal-accuracy step, and the interleaved wall times."""
    case = Case(name, cfg, out)
    ref_dt = cfg.wd_ref if name == "WD0050" else case.period / cfg.s1_ref
    t, s, _, _ = case.symcable(ref_dt)
    ref = np.interp(case.grid, t, s)
    rows, runs = [], {}

    def add(code, step, res, **extra):
        t_, s_, wall, det = res
        mx, rms = error(case.grid, t_, s_, ref)
        rows.append(dict(case=name, code=code, step=step, status="ok", max_pct=mx, rms_pct=rms,
                         first_wall_s=wall, **det, **extra))
        return mx

    add("symcable", 2 * ref_dt, case.symcable(2 * ref_dt), role="reference check")
    for cfl in sorted(set(MD_CFLS) | {MD_CFL_MAX[name]}):
        try:
            add("MoorDyn", cfl, case.moordyn(cfl))
            runs[("MoorDyn", cfl)] = lambda cfl=cfl: case.moordyn(cfl)
        except RuntimeError as exc:  # RK2 above its stability limit
            rows.append(dict(case=name, code="MoorDyn", step=cfl, status="unstable",
                             note=str(exc).split(";")[0]))
    md_err = next(r["max_pct"] for r in rows if r["code"] == "MoorDyn" and r["step"] == 0.1)
    dts = (cfg.wd_dts if name == "WD0050" else tuple(case.period / n for n in cfg.s1_ns))
    errs = {}
    for dt in sorted(dts):
        errs[dt] = add("symcable", dt, case.symcable(dt))
    ok = [dt for dt in sorted(errs) if all(errs[d] <= md_err for d in errs if d <= dt)]
    equal = ok[-1] if ok else min(errs)
    if name == "seed001" and ok and case.period / 100 in errs:
        # T/n between the ladder's rungs: n from the second order at T/100, raised until
        # the error is no larger than MoorDyn's (or n reaches the rung that holds)
        n_hold = int(round(case.period / equal))
        n = int(math.ceil(100 * math.sqrt(errs[case.period / 100] / md_err)))
        while n < n_hold:
            if add("symcable", case.period / n, case.symcable(case.period / n)) <= md_err:
                equal = case.period / n
                break
            n += 2
    for r in rows:
        if r["code"] == "symcable" and r["step"] == equal and r.get("role") is None:
            r["role"] = "equal accuracy"
    runs[("symcable", equal)] = lambda: case.symcable(equal)
    base = 0.1 if name == "WD0050" else case.period / 100
    runs[("symcable", base)] = lambda: case.symcable(base)
    cd_equal = None
    if name == "WD0050" and peers.available()["CableDyn"]:
        cd_equal = _cabledyn_rows(case, cfg, md_err, rows)
        if cd_equal is not None:
            runs[("CableDyn", cd_equal)] = lambda: case.cabledyn(cd_equal)
    walls = interleaved(runs, cfg.repeats)
    for r in rows:
        w = walls.get((r["code"], r["step"]))
        if w is not None:
            r["wall_s"], r["cpu_s"], r["repeats"] = w[0], w[1], cfg.repeats
    return {"case": name, "ref_dt": ref_dt, "moordyn_max_pct": md_err, "equal_dt": equal,
            "equal_holds": bool(ok), "base_dt": base, "cabledyn_equal_dt": cd_equal,
            "rows": rows}


def _cabledyn_rows(case: Case, cfg: Config, bound: float, rows: list) -> float:
    """CableDyn's ladder against its own converged run (appended to ``rows``; a run that
    fails is a row "failed" with its message); its equal-accuracy step: the largest whose
    max error, and every smaller rung's, is at most ``bound`` (else its smallest); None
    when no run came through."""
    try:
        t, s, _, _ = case.cabledyn(cfg.cd_ref)
    except Exception as exc:  # noqa: BLE001  (CableDyn's own errors, as chains/run.py)
        rows.append(dict(case=case.name, code="CableDyn", step=cfg.cd_ref, status="failed",
                         note=str(exc).splitlines()[0] if str(exc) else type(exc).__name__))
        return None
    ref = np.interp(case.grid, t, s)
    errs = {}
    for dt in sorted(cfg.cd_dts):
        try:
            t_, s_, wall, det = case.cabledyn(dt)
        except Exception as exc:  # noqa: BLE001
            rows.append(dict(case=case.name, code="CableDyn", step=dt, status="failed",
                             note=str(exc).splitlines()[0] if str(exc) else type(exc).__name__))
            continue
        mx, rms = error(case.grid, t_, s_, ref)
        errs[dt] = mx
        rows.append(dict(case=case.name, code="CableDyn", step=dt, status="ok", max_pct=mx,
                         rms_pct=rms, first_wall_s=wall, reference_dt=cfg.cd_ref, **det))
    if not errs:
        return None
    ok = [dt for dt in sorted(errs) if all(errs[d] <= bound for d in errs if d <= dt)]
    equal = ok[-1] if ok else min(errs)
    for r in rows:
        if r["code"] == "CableDyn" and r["step"] == equal and r["status"] == "ok":
            r["role"] = "equal accuracy" if ok else "its smallest step (no rung holds)"
    return equal


def interleaved(runs: dict, repeats: int) -> dict:
    """Median (wall, CPU) times (s) of each run over ``repeats`` interleaved rounds."""
    walls = {k: [] for k in runs}
    for _ in range(repeats):
        for k, call in runs.items():
            res = call()
            walls[k].append((res[2], res[3]["cpu_s"]))
    return {k: tuple(np.median(np.array(v), axis=0)) for k, v in walls.items()}


def summary(results: list) -> str:
    out = []
    for res in results:
        rows = res["rows"]
        sym = {r["step"]: r for r in rows if r["code"] == "symcable" and "wall_s" in r}
        md = {r["step"]: r for r in rows if r["code"] == "MoorDyn" and "wall_s" in r}
        cd = {r["step"]: r for r in rows if r["code"] == "CableDyn" and "wall_s" in r}
        eq, base = sym[res["equal_dt"]], sym[res["base_dt"]]
        out += [f"### {res['case']}", "",
                "| run | step | max error % | rms error % | wall s (median) | static / init s | "
                "Newton per step |", "|---|---|---|---|---|---|---|"]
        for r in rows:
            if r["code"] == "CableDyn" and r["status"] == "ok":
                r = dict(r, code="CableDyn (error against its own run at "
                                 f"{r['reference_dt']:g} s)")
            step = (f"CFL {r['step']:g} (dtM {r['dtM'] * 1e3:.2f} ms)" if r["code"] == "MoorDyn"
                    and r["status"] == "ok" else f"CFL {r['step']:g}" if r["code"] == "MoorDyn"
                    else f"dt {r['step']:.4g} s")
            if r["status"] != "ok":
                out.append(f"| {r['code']} | {step} | {r['status']} | | | | |")
                continue
            wall = (f"{r['wall_s']:.3f} (CPU {r['cpu_s']:.3f})" if "wall_s" in r
                    else f"({r['first_wall_s']:.3f}, once)")
            init = r.get("static_s", r.get("init_s"))
            role = f" ({r['role']})" if r.get("role") else ""
            out.append(f"| {r['code']}{role} | {step} | {r['max_pct']:.3f} | {r['rms_pct']:.3f} | "
                       f"{wall} | {init:.3f} | {r.get('newton_per_step', float('nan')):.2f} |")
        held = "" if res["equal_holds"] else " (no rung holds: the smallest step)"
        out += ["", "| ratio of medians | wall | CPU |", "|---|---|---|"]
        for cfl, m in sorted(md.items()):
            for label, r in ((f"equal accuracy (dt {res['equal_dt']:.4g} s){held}", eq),
                             (f"dt {res['base_dt']:.4g} s", base))[:1 if eq is base else 2]:
                out.append(f"| symcable at {label} / MoorDyn CFL {cfl:g} | "
                           f"{r['wall_s'] / m['wall_s']:.2f} | {r['cpu_s'] / m['cpu_s']:.2f} |")
        for step, c in cd.items():
            out.append(f"| symcable at equal accuracy (dt {res['equal_dt']:.4g} s){held} / "
                       f"CableDyn at {c.get('role', 'its step')} (dt {step:g} s) | "
                       f"{eq['wall_s'] / c['wall_s']:.2f} | {eq['cpu_s'] / c['cpu_s']:.2f} |")
        out.append("")
    return "\n".join(out)


def main(argv=None) -> list:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--quick", action="store_true", help="short runs in the virtual machine, one round")
    ap.add_argument("--out", type=Path, default=HERE / "out")
    ap.add_argument("--cases", nargs="+", default=["WD0050", "seed001"])
    args = ap.parse_args(argv)
    args.out.mkdir(parents=True, exist_ok=True)
    cfg = QUICK if args.quick else FULL
    results = []
    for name in args.cases:
        results.append(run_case(name, cfg, args.out))
        print(f"{name} done", flush=True)
    text = summary(results)
    (args.out / "cable3d_moordyn.json").write_text(json.dumps(
        {"quick": args.quick, "config": cfg._asdict(), "results": results}, indent=1, default=float))
    (args.out / "cable3d_moordyn.md").write_text(text)
    print(text)
    return results


if __name__ == "__main__":
    main()
