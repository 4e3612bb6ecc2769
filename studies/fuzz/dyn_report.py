"""Tables of the dynamic fuzz study (:mod:`dyn_fuzz`): counts per verdict, the estimate /
true factors, wall times, the reference's own checks, and a line for every scene that needs
a look; ``results.csv`` and ``failures.json``."""
from __future__ import annotations

import collections
import csv
import json
import math

import dyn_classify as dc
import numpy as np

CSV_COLUMNS = ("id", "cls", "variant", "period", "segments", "dt", "sim_class", "per_class",
               "sim_class_end", "true_sim", "true_sim_b8", "true_sim_end", "true_sim_run",
               "est_sim", "factor_sim", "factor_sim_run",
               "true_per", "est_per", "factor_per", "settle", "settle_8", "ref_conv", "ref_conv_per", "ref", "ref_per",
               "where_sim", "where_per", "warned_sim", "snap_warned_sim", "warned_per",
               "sim_wall", "b_wall", "per_wall", "b16_wall", "bL_wall", "scene_wall", "sim_status",
               "per_status", "sim_error", "per_error")


def _wall(r, k):
    return (r.get(k) or {}).get("wall")


def row(r: dict) -> dict:
    sim, per = r.get("sim") or {}, r.get("per") or {}
    out = {k: r.get(k) for k in CSV_COLUMNS}
    out.update(dt=(sim.get("stats") or {}).get("dt"), sim_status=sim.get("status"),
               per_status=per.get("status"), sim_error=(sim.get("error") or "")[:200],
               per_error=(per.get("error") or "")[:200])
    for k in ("sim", "b", "per", "b16", "bL"):
        out[f"{k}_wall"] = _wall(r, k)
    return out


def write_csv(path, recs) -> None:
    with open(path, "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=CSV_COLUMNS)
        w.writeheader()
        for r in recs:
            w.writerow(row(r))


def needs_look(r: dict) -> bool:
    """A scene with anything but correct or warned answers, or an estimate out of its factor."""
    if r.get("harness_error"):
        return True
    if r["sim_class"] not in ("correct", "warned") or r["per_class"] not in (
            "correct", "warned", "no period: warned", "clean error"):
        return True
    for key in ("sim", "per"):
        t, f = r.get(f"true_{key}"), r.get(f"factor_{key}")
        if t is not None and t > dc.TARGET and not dc.in_factor(f):
            return True
    return False


def write_failures(path, recs) -> int:
    """Every scene to look at (:func:`needs_look`), its record with its scene, to replay."""
    out = [r for r in recs if needs_look(r)]
    with open(path, "w") as fh:
        json.dump(out, fh, indent=1, default=float)
    return len(out)


def _f(x, pct=True):
    if x is None or (isinstance(x, float) and not math.isfinite(x)):
        return "-"
    return f"{100 * x:.3g} %" if pct else f"{x:.3g}"


def counts(recs, key, classes) -> dict:
    c = collections.Counter(r[key] for r in recs)
    return {k: c.get(k, 0) for k in classes if c.get(k, 0) or k in ("correct", "silent wrong",
                                                                     "crash", "hang")}


def _certain(r, key: str) -> bool:
    """The reference is converged well enough to judge the factor: the dt / 8 and dt / 16
    runs (when both ran) differ by at most half the true error; for the periodic answer,
    the reference had also settled into a period."""
    conv = r.get("ref_conv_per" if key == "per" else "ref_conv")
    ok = conv is None or conv <= 0.5 * r[f"true_{key}"]
    return ok and not (key == "per" and (r.get("settle") or 0.0) > dc.SETTLE)


def factor_stats(recs, key: str, est_key: str) -> dict:
    """Over the answers whose true error exceeds the target: how many, the median, least
    and largest estimate / true, and how many within [1/3, 3] (of all; of those whose
    reference is certain, :func:`_certain`); and the false alarms (an estimate over the
    target, true error under it)."""
    sel = [r for r in recs if r.get(f"true_{key}") is not None and r[f"true_{key}"] > dc.TARGET
           and r.get(f"factor_{key}") is not None]
    fs = [r[f"factor_{key}"] for r in sel]
    sure = [r[f"factor_{key}"] for r in sel if _certain(r, key)]
    alarms = [r for r in recs if (r.get(est_key) or 0) > dc.TARGET
              and r.get(f"true_{key}") is not None and r[f"true_{key}"] <= dc.TARGET]
    out = {"n": len(fs), "within": sum(1 for f in fs if dc.in_factor(f)), "n_sure": len(sure),
           "within_sure": sum(1 for f in sure if dc.in_factor(f)),
           "below": sum(1 for f in fs if f < 1 / dc.FACTOR),
           "above": sum(1 for f in fs if f > dc.FACTOR)}
    if fs:
        out.update(median=float(np.median(fs)), least=float(min(fs)), largest=float(max(fs)))
    out["false_alarms"] = len(alarms)
    return out


def summary(res: dict) -> str:
    recs = res["records"]
    L = ["# Dynamic scenes: time runs and periodic solves against a finer run",
         "", f"symcable: {res['version']}; command: `{res['command']}`",
         f"{len(recs)} scenes (seed {res['seed']}, {res['workers']} workers, "
         f"{res['wall_min']:.1f} min wall; machine load average at the start "
         f"{res.get('load', '?')}); every call in the CasADi virtual machine.", ""]
    L += ["## Verdicts", "",
          f"correct: true error <= {100 * dc.TARGET:g} % of the tension range; warned: above it "
          "with the warning naming the error; quiet: 1-2 % without it; silent wrong: above "
          f"{100 * dc.SILENT:g} % without it; hang: a call past {dc.BOUND:g} s.", "",
          "simulate's true error is relative to each end's tension range over the run, at "
          "least 1e-3 of the run's largest end tension (its estimate's normalisation); the "
          "column 'per-end floor' relative to the end's range over the last period, at least "
          "1 % of its tension (solve_periodic's normalisation, the issue's wording).", "",
          "| verdict | simulate | simulate, per-end floor | solve_periodic |",
          "|---|---|---|---|"]
    cs, cp = collections.Counter(r["sim_class"] for r in recs), collections.Counter(
        r["per_class"] for r in recs)
    ce = collections.Counter(r.get("sim_class_end") for r in recs)
    for k in dict.fromkeys(dc.SIM_CLASSES + dc.PER_CLASSES):
        if cs.get(k) or cp.get(k) or ce.get(k) or k in ("correct", "silent wrong", "crash",
                                                          "hang"):
            L.append(f"| {k} | {cs.get(k, 0)} | {ce.get(k, 0)} | {cp.get(k, 0)} |")
    L += ["", "Per scene class (simulate / solve_periodic: correct, warned, other):", "",
          "| class | scenes | simulate c/w/other | periodic c/w/other |", "|---|---|---|---|"]
    by = collections.defaultdict(list)
    for r in recs:
        by[r["cls"]].append(r)
    for cls, rs in sorted(by.items()):
        def cwo(key, rs=rs):
            c = collections.Counter(r[key] for r in rs)
            w = c.get("warned", 0) + c.get("no period: warned", 0)
            return f"{c.get('correct', 0)}/{w}/{len(rs) - c.get('correct', 0) - w}"
        L.append(f"| {cls} | {len(rs)} | {cwo('sim_class')} | {cwo('per_class')} |")
    L += ["", "## Estimate / true error", "",
          "Over the answers whose true error exceeds 1 % (and false alarms: estimate over "
          "1 %, true error under it).", "",
          "| estimate | against | answers > 1 % | median | least | largest | within [1/3, 3] "
          "| below / above | reference certain: within | false alarms |",
          "|---|---|---|---|---|---|---|---|---|---|"]
    for key, est, what in (("sim", "est_sim", "simulate: last period's extremes"),
                           ("sim_run", "est_sim", "simulate: whole run, sample by sample"),
                           ("per", "est_per", "solve_periodic: extremes")):
        st = factor_stats(recs, key, est)
        L.append(f"| {what.split(':')[0]} | {what.split(': ')[1]} | {st['n']} | "
                 f"{_f(st.get('median'), False)} | {_f(st.get('least'), False)} | "
                 f"{_f(st.get('largest'), False)} | {st['within']} | "
                 f"{st['below']} / {st['above']} | {st['within_sure']} of {st['n_sure']} | "
                 f"{st['false_alarms']} |")
    L += ["", "Reference certain: dt / 8 and dt / 16 within half the true error of each other "
          "(when both ran), and for the periodic answer a reference settled into a period."]
    L += ["", "## Wall times (s)", "", "| call | median | largest | over the bound |",
          "|---|---|---|---|"]
    for k, what in (("sim", "simulate (8 periods, T/100)"), ("per", "solve_periodic"),
                    ("b", "reference, dt / 8"), ("b16", "reference, dt / 16"),
                    ("bL", "long reference, dt / 8, 20 periods")):
        w = [_wall(r, k) for r in recs if _wall(r, k) is not None]
        if w:
            over = sum(1 for x in w if x > dc.BOUND) if k in ("sim", "per") else "-"
            L.append(f"| {what} | {np.median(w):.3g} | {max(w):.3g} | {over} |")
    slow = sorted(recs, key=lambda r: -(r.get("scene_wall") or 0))[:8]
    L += ["", "Slowest scenes:", "", "| id | class | segments | T (s) | scene | simulate | "
          "periodic | ref dt/8 | ref dt/16 | long ref |", "|---|---|---|---|---|---|---|---|---|---|"]
    for r in slow:
        L.append(f"| {r['id']} | {r['cls']} | {r['segments']} | {r['period']:.3g} | "
                 f"{r.get('scene_wall', 0):.0f} | " + " | ".join(
                     f"{_wall(r, k):.0f}" if _wall(r, k) is not None else "-"
                     for k in ("sim", "per", "b", "b16", "bL")) + " |")
    conv = [r["ref_conv"] for r in recs if r.get("ref_conv") is not None]
    sett = [r["settle_8"] for r in recs if r.get("settle_8") is not None]
    sett_l = [r["settle"] for r in recs if r.get("ref_per") == "bL"]
    L += ["", "## The reference", "",
          f"dt / 16 run on {len(conv)} scenes; dt / 8 against dt / 16 (extremes, relative): "
          + (f"median {_f(float(np.median(conv)))}, largest {_f(max(conv))}; "
             f"{sum(1 for c in conv if c > 0.005)} above 0.5 %" if conv else "-") + ".",
          f"Last two periods of the reference differ by more than {100 * dc.SETTLE:g} % "
          f"after 8 periods: {sum(1 for s in sett if s > dc.SETTLE)} of {len(sett)} scenes; "
          f"those with a periodic answer ran {len(sett_l)} long references (20 periods), "
          f"{sum(1 for s in sett_l if s > dc.SETTLE)} of which had not settled either "
          "(no period: the periodic answer judged by whether it warned).", ""]
    look = [r for r in recs if needs_look(r)]
    L += ["## Scenes to look at", "",
          "| id | class | variant | seg | T (s) | simulate | true | est | periodic | true | est "
          "| settle | ref conv |", "|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in look:
        L.append(f"| {r['id']} | {r['cls']} | {r['variant'][:40]} | {r['segments']} | "
                 f"{r['period']:.3g} | {r['sim_class']} | {_f(r.get('true_sim'))} | "
                 f"{_f(r.get('est_sim'))} | {r['per_class']} | {_f(r.get('true_per'))} | "
                 f"{_f(r.get('est_per'))} | {_f(r.get('settle'))} | {_f(r.get('ref_conv'))} |")
    errs = [r for r in recs if r["sim_class"] in ("clean error", "crash", "hang")
            or r["per_class"] in ("clean error", "crash", "hang")]
    if errs:
        L += ["", "Errors and hangs:", ""]
        for r in errs:
            for k in ("sim", "per"):
                c = r.get(k) or {}
                if c.get("outcome") != "ok" or (c.get("wall") or 0) > dc.BOUND:
                    L.append(f"- {r['id']} {k} ({c.get('outcome')}, {c.get('wall') or 0:.0f} s): "
                             f"{(c.get('error') or '').splitlines()[0][:300] if c.get('error') else ''}")
    return "\n".join(L) + "\n"
