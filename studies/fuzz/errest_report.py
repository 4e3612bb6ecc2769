"""Tables of the error-estimate study (:mod:`error_estimate`): each scene's category, the
factor estimate / true error, the counts, the factor distribution, false alarms, the cost,
the summary (``summary.md``) and ``results.csv``."""
from __future__ import annotations

import collections
import csv
import statistics

import errest_work

OUTCOMES = ("correct", "warned", "quiet 1-2 %", "silent wrong", "clean error", "crash", "hang",
            "no reference")
ACCURACY = errest_work.ACCURACY
#: an unwarned answer off MoorPy by more than ACCURACY but at most this, whose estimate is
#: within a factor of 3 of its true error (so just under the 1 % at which it warns), is
#: "quiet", not silent (the dynamic study's rule, dyn_classify.SILENT)
QUIET = 0.02
BINS = ((0.0, 0.1, "< 1/10"), (0.1, 1 / 3, "1/10 - 1/3"), (1 / 3, 1.0, "1/3 - 1"),
        (1.0, 3.0, "1 - 3"), (3.0, 10.0, "3 - 10"), (10.0, float("inf"), "> 10"))


def category(r: dict) -> str:
    o = r.get("outcome")
    if o in ("hang", "crash", "clean error"):
        return o
    if o == "harness error":
        return "crash"
    if r.get("true") is None:
        return "no reference"
    if r["true"] <= ACCURACY:
        return "correct"
    if r.get("warned") or r.get("no_estimate"):
        return "warned"
    return "quiet 1-2 %" if r["true"] <= QUIET and within(factor(r)) else "silent wrong"


def factor(r: dict):
    est, true = r.get("estimate"), r.get("true")
    if est is None or not true:
        return None
    return est / true


def within(f) -> bool:
    return f is not None and 1 / 3 <= f <= 3


def cause(r: dict) -> str | None:
    """Of a suspicious scene (errest_work.suspicious): whether its error vs MoorPy falls when
    the segments are multiplied (a discretisation error) or persists (a modelling
    difference, e.g. the penalty seabed against MoorPy's rigid one)."""
    ref = r.get("refined") or {}
    if ref.get("true") is None or not r.get("true"):
        return None
    return "discretisation" if ref["true"] <= 0.5 * r["true"] else "persists"


def failure_kind(r: dict) -> str | None:
    c = category(r)
    if c in ("silent wrong", "crash", "hang"):
        return c
    if c == "warned" and not within(factor(r)):
        return "factor outside [1/3, 3]"
    return None


# ----------------------------------------------------------------------------- tables
def _counts(recs) -> dict:
    c = collections.Counter(category(r) for r in recs)
    return {k: c.get(k, 0) for k in OUTCOMES}


def _factor_table(recs, threshold: float) -> dict:
    sel = [r for r in recs if r.get("true") is not None and r["true"] > threshold
           and category(r) not in ("clean error", "crash", "hang")]
    rows = collections.Counter()
    for r in sel:
        f = factor(r)
        if f is None:
            rows["no estimate"] += 1
            continue
        rows[next(name for lo, hi, name in BINS if lo <= f < hi)] += 1
    return {"scenes": len(sel), "within": sum(1 for r in sel if within(factor(r))),
            "bins": {name: rows.get(name, 0) for *_, name in BINS} | {"no estimate": rows.get("no estimate", 0)}}


def _median(xs):
    xs = [x for x in xs if x is not None]
    return statistics.median(xs) if xs else None


def _cost(recs) -> dict:
    sub = [r for r in recs if r.get("t_cold_with") and r.get("t_cold_without")]
    ratios = [r["t_cold_with"] / r["t_cold_without"] for r in sub]
    inner = [r["t_solve"] / (r["t_solve"] - r["t_est"]) for r in recs
             if r.get("t_est") is not None and r["t_solve"] > r["t_est"]]
    return {"subsample": len(sub), "median_with": _median([r["t_cold_with"] for r in sub]),
            "median_without": _median([r["t_cold_without"] for r in sub]),
            "median_ratio": _median(ratios), "max_ratio": max(ratios) if ratios else None,
            "median_ratio_all": _median(inner), "scenes_all": len(inner)}


SEG_BINS = ((1, 3), (4, 7), (8, 15), (16, 39), (40, 100), (101, 10**9))


def _by_segments(recs) -> dict:
    """Per bin of the fewest segments of a line in the scene: scenes off by > 1 %, how many
    warned, and their factors (within [1/3, 3], above 3, below 1/3)."""
    out = {}
    for lo, hi in SEG_BINS:
        sel = [r for r in recs if lo <= min(r["segments"].values()) <= hi
               and r.get("true") is not None and category(r) in OUTCOMES[:4]]
        off = [r for r in sel if r["true"] > ACCURACY]
        fs = [factor(r) for r in off]
        if sel:
            out[f"{lo}-{hi}" if hi < 10**9 else f">= {lo}"] = {
                "scenes": len(sel), "off": len(off),
                "silent": sum(1 for r in off if category(r) == "silent wrong"),
                "within": sum(1 for f in fs if within(f)),
                "over": sum(1 for f in fs if f is not None and f > 3),
                "under": sum(1 for f in fs if f is not None and f < 1 / 3)}
    return out


def summarise(recs: list[dict], meta: dict) -> dict:
    out = {"meta": meta, "by_dim": {}}
    for dim in (2, 3):
        rs = [r for r in recs if r.get("dim") == dim]
        if not rs:
            continue
        alarms = [r for r in rs if r.get("warned") and r.get("true") is not None
                  and r["true"] <= ACCURACY]
        by_class = {}
        for cls in sorted({r["cls"] for r in rs}):
            cr = [r for r in rs if r["cls"] == cls]
            f = [factor(r) for r in cr if category(r) == "warned"]
            by_class[cls] = {**_counts(cr), "scenes": len(cr),
                             "max_true": max([r["true"] for r in cr if r.get("true") is not None], default=None),
                             "median_factor": _median(f)}
        slow = sorted([r for r in rs if r.get("t_solve")], key=lambda r: -r["t_solve"])[:5]
        out["by_dim"][dim] = {
            "scenes": len(rs), "counts": _counts(rs),
            "factor_1pct": _factor_table(rs, ACCURACY), "factor_03pct": _factor_table(rs, 0.003),
            "silent_persisting": sum(1 for r in rs if category(r) == "silent wrong"
                                     and cause(r) == "persists"),
            "silent_slack_warning": sum(1 for r in rs if category(r) == "silent wrong"
                                        and r.get("slack_warning")),
            "false_alarms": len(alarms), "by_segments": _by_segments(rs),
            "scale_floored": sum(1 for r in rs if r.get("ref") and r.get("force_scale") and max(
                max(v[0], v[1]) for v in r["ref"].values()) < errest_work.SCALE_FLOOR * r["force_scale"]),
            "false_alarms_factor_over_3": sum(1 for r in alarms if (factor(r) or 0) > 3),
            "cost": _cost(rs), "by_class": by_class,
            "slowest": [{k: r.get(k) for k in ("id", "cls", "variant", "t_solve", "t_est")}
                        | {"segments": sum(r["segments"].values()), "lines": len(r["segments"])}
                        for r in slow],
            "median_t_solve": _median([r.get("t_solve") for r in rs])}
    out["failures"] = [{"id": r["id"], "kind": failure_kind(r)} for r in recs if failure_kind(r)]
    return out


def _f(x, fmt="{:.3g}"):
    return "" if x is None else fmt.format(x)


def markdown(s: dict, recs: list[dict]) -> str:
    m = s["meta"]
    L = [f"# Error-estimate fuzz study: {m['n2']} planar + {m['n3']} 3D scenes",
         "", (f"symcable {m['symcable']}; seed {m['seed']}, {m['workers']} workers, solve limit "
              f"{m['limit']:g} s; wall time {m['wall_s']:.0f} s."), "",
         "| outcome | " + " | ".join(f"{'planar' if d == 2 else '3D'}" for d in s["by_dim"]) + " |",
         "|---|" + "---|" * len(s["by_dim"])]
    for k in OUTCOMES:
        L.append(f"| {k} | " + " | ".join(str(v["counts"][k]) for v in s["by_dim"].values()) + " |")
    L += ["", "Estimate / true error (scenes off MoorPy by more than the threshold):", "",
          "| | " + " | ".join(f"{'planar' if d == 2 else '3D'} > {t}" for d in s["by_dim"]
                                for t in ("1 %", "0.3 %")) + " |",
          "|---|" + "---|" * (2 * len(s["by_dim"]))]
    cols = [(v["factor_1pct"], v["factor_03pct"]) for v in s["by_dim"].values()]
    for name in [b[2] for b in BINS] + ["no estimate"]:
        L.append(f"| {name} | " + " | ".join(f"{a['bins'][name]} | {b['bins'][name]}" for a, b in cols) + " |")
    L.append("| **within [1/3, 3]** | " + " | ".join(
        f"**{a['within']} / {a['scenes']}** | **{b['within']} / {b['scenes']}**" for a, b in cols) + " |")
    L += ["", "| | " + " | ".join(f"{'planar' if d == 2 else '3D'}" for d in s["by_dim"]) + " |",
          "|---|" + "---|" * len(s["by_dim"])]
    rows = [("silent wrong whose error persists at k x segments (not discretisation)",
             lambda v: v["silent_persisting"]),
            ("silent wrong warned of slack segments (not of a discretisation error)",
             lambda v: v["silent_slack_warning"]),
            ("false alarms (warned, true <= 1 %)", lambda v: v["false_alarms"]),
            ("of those, estimate > 3 x true", lambda v: v["false_alarms_factor_over_3"]),
            ("scenes whose tension scale is the floor (1e-3 of the weight)", lambda v: v["scale_floored"]),
            ("median solve with estimate, s", lambda v: _f(v["median_t_solve"])),
            ("cost subsample (scenes)", lambda v: v["cost"]["subsample"]),
            ("median first solve in a fresh process, with / without estimate, s",
             lambda v: f"{_f(v['cost']['median_with'])} / {_f(v['cost']['median_without'])}"),
            ("median cost ratio (with / without)", lambda v: _f(v["cost"]["median_ratio"])),
            ("largest cost ratio", lambda v: _f(v["cost"]["max_ratio"])),
            ("median ratio, every scene (stats wall_time)", lambda v: _f(v["cost"]["median_ratio_all"]))]
    for name, fn in rows:
        L.append(f"| {name} | " + " | ".join(str(fn(v)) for v in s["by_dim"].values()) + " |")
    for d, v in s["by_dim"].items():
        L += ["", f"### {'Planar' if d == 2 else '3D'} by the fewest segments of a line", "",
              "| segments | scenes | off > 1 % | silent | factor in [1/3, 3] | > 3 | < 1/3 |",
              "|---|---|---|---|---|---|---|"]
        L += [f"| {k} | {b['scenes']} | {b['off']} | {b['silent']} | {b['within']} | {b['over']} | "
              f"{b['under']} |" for k, b in v["by_segments"].items()]
        L += ["", f"### {'Planar' if d == 2 else '3D'} by class", "",
              "| class | scenes | correct | warned | quiet | silent wrong | clean | crash | hang | no ref | max true | median factor (warned) |",
              "|---|---|---|---|---|---|---|---|---|---|---|---|"]
        for cls, c in v["by_class"].items():
            L.append(f"| {cls} | {c['scenes']} | {c['correct']} | {c['warned']} | "
                     f"{c['quiet 1-2 %']} | {c['silent wrong']} | "
                     f"{c['clean error']} | {c['crash']} | {c['hang']} | {c['no reference']} | "
                     f"{_f(c['max_true'], '{:.2%}')} | {_f(c['median_factor'])} |")
        L += ["", "Slowest solves (with the estimate): " + "; ".join(
            f"{x['id']} {x['cls']} ({x['lines']} line(s), {x['segments']} segments) {x['t_solve']:.1f} s"
            for x in v["slowest"])]
    byid = {r["id"]: r for r in recs}
    if s["failures"]:
        L += ["", "### Failures (replay: `--replay failures.json ID`)", "",
              "| id | class | kind | true | estimate | segments | at k x segments: true | cause | penalty bed dT | detail |",
              "|---|---|---|---|---|---|---|---|---|---|"]
        for fl in s["failures"]:
            r = byid[fl["id"]]
            ref = r.get("refined") or {}
            L.append(f"| {r['id']} | {r['cls']} | {fl['kind']} | {_f(r.get('true'), '{:.2%}')} | "
                     f"{_f(r.get('estimate'), '{:.2%}')} | {sum(r['segments'].values())} | "
                     f"{_f(ref.get('factor'), '{:g}')}: {_f(ref.get('true'), '{:.2%}')} | "
                     f"{cause(r) or ''} | {_f(r.get('penalty'), '{:.2%}')} | {(r.get('error') or r.get('variant') or '')[:80]} |")
    return "\n".join(L) + "\n"


CSV_COLS = ("id", "dim", "cls", "variant", "category", "true", "estimate", "factor", "warned",
            "no_estimate", "segments", "min_line_segments", "lines", "ref_kind", "t_solve",
            "t_est", "t_cold_with", "t_cold_without", "refined_factor", "refined_true",
            "penalty", "cause", "error")


def write_csv(recs, path) -> None:
    with open(path, "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=CSV_COLS)
        w.writeheader()
        for r in recs:
            seg = r.get("segments") or {}
            w.writerow({**{k: r.get(k) for k in CSV_COLS if k in r and not isinstance(r[k], (dict, list))},
                        "category": category(r), "factor": factor(r),
                        "segments": sum(seg.values()), "min_line_segments": min(seg.values(), default=None),
                        "lines": len(seg), "refined_factor": (r.get("refined") or {}).get("factor"),
                        "refined_true": (r.get("refined") or {}).get("true"), "cause": cause(r),
                        "error": (r.get("error") or "")[:200].replace("\n", " ")})
