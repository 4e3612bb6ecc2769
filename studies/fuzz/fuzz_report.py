"""Counting, grouping and writing the fuzz study's results: the CSV, the summary tables, the
failures to replay, and the curated regression cases."""
from __future__ import annotations

import collections
import csv
import json
import math

import numpy as np

OUTCOMES = ("correct", "wrong", "other equilibrium", "nan", "clean error", "rejected",
            "ugly error", "hang", "crash", "harness error")
NOT_CLEAN = ("wrong", "nan", "ugly error", "hang", "crash")


def counts(records) -> dict:
    c = collections.Counter(r["outcome"] for r in records)
    return {o: c.get(o, 0) for o in OUTCOMES}


def by_class(records) -> dict:
    out = collections.defaultdict(collections.Counter)
    for r in records:
        out[r["cls"]][r["outcome"]] += 1
    return out


def group_of(r: dict) -> str:
    """The kind of a wrong answer, from its first (most telling) problem."""
    text = " | ".join(r.get("problems", []))
    regime = (r.get("refs", {}).get(r.get("reference") or "", {}) or {}).get("regime", "")
    if "negative segment length" in text:
        return "negative segment length (strain <= -1)"
    if "through the seabed" in text:
        return "through the seabed"
    if "compressed straight strut" in text:
        return "compressed straight strut (rod)"
    if "compressed rod" in text:
        return "rod compressed beyond buckling"
    if "force balance" in text and r.get("n_segments") == 1:
        return "one segment: end forces wrong (global force balance off)"
    if "cable in compression" in text:
        if regime in ("fully slack", "free end on the bed") or "moorpy profile 4" in regime:
            kind = "slack chain on the bed, compressed"
        elif regime == "vertical" or r["cls"] in ("vertical", "near_vertical"):
            kind = "folded vertical line, compressed"
        else:
            kind = "compressed cable"
        slight = (r.get("compression_over_segment_weight") or math.inf) < 1.0
        return kind + (" by less than one segment's weight" if slight else "")
    if "force balance" in text:
        return "global force balance off"
    if "off the" in text:
        kinds = [k for k in ("T_A", "T_B", "grounded", "shape") if k in text]
        return "off the reference (" + ", ".join(kinds) + ")"
    return "other"


def agreement_table(records) -> tuple[list[dict], list[str]]:
    """Per pair of references: scenes compared, worst deviations, pairs beyond tolerance."""
    pairs = collections.defaultdict(lambda: {"n": 0, "dT": 0.0, "dG": 0.0, "shape": 0.0, "bad": []})
    for r in records:
        for p in (r.get("agreement") or {}).get("pairs", []):
            row = pairs[p["pair"]]
            row["n"] += 1
            row["dT"] = max(row["dT"], p["dT"])
            row["dG"] = max(row["dG"], p["dG"])
            if p["shape"] == p["shape"]:
                row["shape"] = max(row["shape"], p["shape"])
            if not p["ok"]:
                row["bad"].append(r["id"])
    table = [{"pair": k, **v} for k, v in sorted(pairs.items())]
    bad = sorted({i for row in table for i in row["bad"]})
    return table, bad


def write_csv(records, path) -> None:
    cols = ["id", "cls", "variant", "outcome", "group", "reference", "time_s", "ref_time_s",
            "dT_A", "dT_B", "dG", "shape", "tol_T", "tol_shape", "tol_G", "path", "start",
            "moorpy_solved", "agreement_ok", "detail"]
    with open(path, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=cols)
        w.writeheader()
        for r in records:
            dev, tol = r.get("deviation") or {}, r.get("tolerance") or {}
            w.writerow({"id": r["id"], "cls": r["cls"], "variant": r.get("variant"),
                        "outcome": r["outcome"],
                        "group": group_of(r) if r["outcome"] == "wrong" else "",
                        "reference": r.get("reference"), "time_s": _f(r.get("time_s")),
                        "ref_time_s": _f(r.get("ref_time_s")),
                        **{k: _f(dev.get(k)) for k in ("dT_A", "dT_B", "dG", "shape")},
                        "tol_T": _f(tol.get("T")), "tol_shape": _f(tol.get("shape")),
                        "tol_G": _f(tol.get("G")), "path": r.get("path"), "start": r.get("start"),
                        "moorpy_solved": r.get("moorpy_solved"),
                        "agreement_ok": (r.get("agreement") or {}).get("ok"),
                        "detail": _detail(r)[:300]})


def _f(x):
    return "" if x is None else f"{x:.6g}"


def _detail(r) -> str:
    if r.get("problems"):
        return "; ".join(r["problems"])
    return (r.get("error") or "").split("\n")[0]


def failure_entry(r: dict, scene: dict) -> dict:
    refs = {k: {kk: v.get(kk) for kk in ("T_A", "T_B", "grounded", "regime", "na", "failed")
                if v.get(kk) is not None}
            for k, v in (r.get("refs") or {}).items() if k != "penalty"}
    return {"id": r["id"], "class": r["cls"], "variant": r.get("variant"),
            "outcome": r["outcome"], "group": group_of(r) if r["outcome"] == "wrong" else None,
            "what": _detail(r), "traceback_last": r.get("traceback_last"),
            "path": r.get("path"), "start": r.get("start"),
            "solver": {k: r.get(k) for k in ("T_A", "T_B", "grounded", "min_axial_N", "min_strain")},
            "reference": r.get("reference"), "references": refs,
            "moorpy_solved": r.get("moorpy_solved"), "scene": scene}


def failures(records, scenes: dict) -> list[dict]:
    """Every scene not solved correctly (clean errors included), with its scene dict."""
    return [failure_entry(r, scenes[r["id"]]) for r in records if r["outcome"] != "correct"]


def curate(fails: list[dict], per_group: int = 2, clean_per_class: int = 1) -> list[dict]:
    """A small regression set: up to ``per_group`` wrong answers of each kind (lines of 8 to
    30 segments first, fewest first: typical, not degenerate, quick to replay), every ugly
    error kind, NaN and hang, and one clean error per class where a reference has the answer."""
    out, seen = [], collections.Counter()

    def key(f):
        n = sum(s["segments"] for s in f["scene"]["sections"])
        return (not 8 <= n <= 30, n)
    order = sorted(fails, key=key)
    for f in order:
        if f["outcome"] == "wrong":
            key = f["group"]
            limit = per_group
        elif f["outcome"] in ("ugly error",):
            key = "ugly: " + (f["what"].split(":")[0])
            limit = 2
        elif f["outcome"] in ("nan", "hang", "crash", "other equilibrium"):
            key, limit = f["outcome"], per_group
        elif f["outcome"] == "clean error" and f["reference"]:
            key, limit = "clean error with a reference: " + f["class"], clean_per_class
        else:
            continue
        if seen[key] < limit:
            seen[key] += 1
            out.append(dict(f, case=key))
    return out


def slowest(records, k=10):
    return sorted((r for r in records if r.get("time_s") is not None),
                  key=lambda r: -r["time_s"])[:k]


def summary_markdown(res: dict) -> str:
    recs = res["records"]
    n = len(recs)
    c = res["counts"]
    L = [f"# Fuzz study: {n} planar scenes (seed {res['seed']}, {res['mode']})", "",
         f"symcable: {res['symcable']}.", "",
         f"Wall time {res['wall_s']:.0f} s on {res['workers']} workers; solve_static with "
         f"codegen=False; time limit {res['solve_limit']:g} s per solve.", "",
         "| outcome | scenes | share |", "|---|---|---|"]
    for o in OUTCOMES:
        if c[o] or o in ("correct", "wrong", "nan", "clean error", "ugly error", "hang"):
            L.append(f"| {o} | {c[o]} | {100 * c[o] / max(n, 1):.1f} % |")
    mp = res["moorpy"]
    L += ["", f"MoorPy applies to {mp['applies']} scenes and solves {mp['solved']}; of those "
          f"symcable solves {mp['sym_correct']} correctly, {mp['sym_clean']} end in a clean "
          f"error, {mp['sym_other']} otherwise.", "", "## By class", "",
          "| class | scenes | " + " | ".join(o for o in OUTCOMES if c[o]) + " |",
          "|---|---|" + "---|" * sum(1 for o in OUTCOMES if c[o])]
    for cls, cc in sorted(res["by_class"].items()):
        L.append(f"| {cls} | {sum(cc.values())} | " +
                 " | ".join(str(cc.get(o, 0)) for o in OUTCOMES if c[o]) + " |")
    L += ["", "## Reference agreement", "",
          "| pair | scenes | max dT / T scale | max d grounded / L | max shape / L | beyond tolerance |",
          "|---|---|---|---|---|---|"]
    for row in res["agreement"]["table"]:
        L.append(f"| {row['pair']} | {row['n']} | {row['dT']:.2g} | {row['dG']:.2g} | "
                 f"{row['shape']:.2g} | {len(row['bad'])} |")
    L += ["", f"References answering per scene: {res['ref_counts']}.", ""]
    L += ["## Wrong answers by kind", ""]
    groups = collections.defaultdict(list)
    for r in recs:
        if r["outcome"] == "wrong":
            groups[group_of(r)].append(r)
    for g, rs in sorted(groups.items(), key=lambda kv: -len(kv[1])):
        L.append(f"### {g}: {len(rs)}")
        L.append("")
        for r in rs:
            L.append(f"- `{r['id']}` ({r['cls']}, {r.get('variant')}; path {r.get('path')!r}, "
                     f"start {r.get('start')!r}): {_detail(r)[:260]}")
        L.append("")
    other = [r for r in recs if r["outcome"] in ("other equilibrium", "nan", "hang", "crash",
                                                 "ugly error", "rejected", "harness error")]
    if other:
        L += ["## Other failures", ""]
        for r in other:
            tail = f" -- `{r['traceback_last']}`" if r.get("traceback_last") else ""
            L.append(f"- `{r['id']}` {r['outcome']} ({r['cls']}, {r.get('variant')}): "
                     f"{_detail(r)[:260]}{tail}")
        L.append("")
    noted = [r for r in recs if r["outcome"] == "correct" and r.get("note")]
    if noted:
        L += ["## Correct after refining", "",
              "Off the reference at the scene's segments, within its tolerance with 4 times "
              "as many, the deviation falling by at least 1.5 per doubling:", ""]
        for r in noted:
            devs = ", ".join(f"{x['segments']}: {max(v for v in x['deviation'].values() if v == v):.3g}"
                             for x in r.get("refined") or [])
            L.append(f"- `{r['id']}` ({r['cls']}): {r['note']} (largest deviation at {devs})")
        L.append("")
    ce = collections.Counter(r["cls"] for r in recs if r["outcome"] == "clean error")
    ce_ref = collections.Counter(r["cls"] for r in recs
                                 if r["outcome"] == "clean error" and r.get("reference"))
    L += ["## Clean errors", "", "| class | clean errors | of which a reference has the answer |",
          "|---|---|---|"]
    for cls in sorted(ce):
        L.append(f"| {cls} | {ce[cls]} | {ce_ref.get(cls, 0)} |")
    L += ["", "## Slowest solves", "", "| scene | class | outcome | s | path |", "|---|---|---|---|---|"]
    for r in slowest(recs):
        L.append(f"| {r['id']} | {r['cls']} | {r['outcome']} | {r['time_s']:.2f} | {r.get('path')} |")
    if res.get("refine"):
        L += ["", "## Discretisation error by refining", "",
              "Largest measured constant over the scenes that converge to their reference "
              "(deviation = constant x error scale; levels whose answer fails a physical check "
              "left out), against the tolerance's constant:", "",
              "| term | measured | tolerance |", "|---|---|---|"]
        for k, (m, t) in res["refine"]["constants"].items():
            L.append(f"| {k} | {m:.3g} | {t:.3g} |")
        L.append(f"\n{res['refine']['converging']} of {res['refine']['scenes']} refined scenes "
                 "converge to their reference.")
    return "\n".join(L) + "\n"


def refine_constants(results: list[dict], tol: dict) -> dict:
    """Largest deviation / error-scale ratio per term over the converging refined scenes,
    each level's deviation attributed to one term: the rod term where there is bending, else
    the first-order term where the reference is unresolved, else the penalty term, else the
    second-order one (the other terms at the tolerance's constants subtracted first)."""
    rows = [x for r in results if r.get("converges") for x in r["rows"]
            if x["outcome"] == "solved" and not x["physical"]]
    m = {k: 0.0 for k in ("T2", "T1", "TB", "TC", "Tpen", "S2", "S1", "SB", "Spen", "G1", "Gpen")}

    def attribute(kind, dev, terms):
        # terms: [(constant name, scale)] in priority order; the first nonzero one takes it
        dev -= tol["floor"]
        for name, scale in terms:
            if scale > 0:
                rest = sum(tol[n] * v for n, v in terms if n != name)
                m[name] = max(m[name], (dev - rest) / scale)
                return

    for x in rows:
        shape = x["shape"] if x["shape"] == x["shape"] else 0.0
        attribute("T", max(x["dT_A"], x["dT_B"]),
                  [("TC", x["tol_ec"]), ("TB", x["tol_eb"]), ("T1", x["tol_e1_T"]),
                   ("Tpen", x["tol_pen_T"]), ("T2", x["tol_e2"])])
        attribute("S", shape,
                  [("SB", x["tol_eb"]), ("S1", x["tol_e1_L"]), ("Spen", x["tol_pen_L"]), ("S2", x["tol_e2"])])
        attribute("G", x["dG"], [("G1", x["tol_g1"]), ("Gpen", x["tol_pen_G"])])
    return {k: (v, tol[k]) for k, v in m.items()}


def dump_json(obj, path) -> None:
    with open(path, "w") as f:
        json.dump(obj, f, indent=1, default=_json_default)


def _json_default(o):
    if isinstance(o, (np.floating, np.integer, np.bool_)):
        return o.item()
    if isinstance(o, np.ndarray):
        return o.tolist()
    if isinstance(o, float) and not math.isfinite(o):
        return None
    raise TypeError(type(o))


if __name__ == "__main__":   # python fuzz_report.py curate out/failures.json cases.json
    import sys
    if len(sys.argv) == 4 and sys.argv[1] == "curate":
        dump_json(curate(json.load(open(sys.argv[2]))), sys.argv[3])
