"""The cable3d part of the fuzz study's results: running the scenes, counting, the failures to
replay, and the summary section (appended to ``summary.md``)."""
from __future__ import annotations

import collections
import time

import fuzz3d_scenes
import fuzz_pool
import fuzz_report as rep

REF_LIMIT = 300.0   # s: references, the friction twin and the refined solves of one scene


def run(n: int, seed: int, workers: int, solve_limit: float, out, progress=None) -> dict:
    """Generate n cable3d scenes, solve and classify each, write ``results3d.csv``,
    ``results3d.json`` and ``failures3d.json`` to ``out``; return the results."""
    t0 = time.perf_counter()
    items = fuzz3d_scenes.generate(n, seed)
    scenes = {it["id"]: it["scene"] for it in items}
    records = fuzz_pool.run_all(items, workers=workers, solve_limit=solve_limit,
                                ref_limit=REF_LIMIT, progress=progress)
    table, bad = rep.agreement_table(records)
    mp = [r for r in records if r.get("moorpy_solved") is not None]
    res = {"n": n, "seed": seed, "wall_s": time.perf_counter() - t0, "records": records,
           "counts": rep.counts(records),
           "by_class": {k: dict(v) for k, v in rep.by_class(records).items()},
           "agreement": {"table": table, "disagreeing": bad},
           "refused_draws": sum(len(it["refused_draws"]) for it in items),
           "references": dict(collections.Counter(r.get("reference") or "none" for r in records)),
           "moorpy": {"applies": len(mp), "solved": sum(1 for r in mp if r["moorpy_solved"]),
                      "sym_correct": sum(1 for r in mp if r["moorpy_solved"] and r["outcome"] == "correct")}}
    rep.write_csv(records, out / "results3d.csv")
    rep.dump_json(records, out / "results3d.json")
    fails = [failure_entry(r, scenes[r["id"]]) for r in records if r["outcome"] != "correct"]
    rep.dump_json(fails, out / "failures3d.json")
    res["failures"] = len(fails)
    return res


def failure_entry(r: dict, scene: dict) -> dict:
    refs = {}
    for name, v in (r.get("refs") or {}).items():
        if "lines" in v:
            refs[name] = {ln: {k: x.get(k) for k in ("T_A", "T_B", "grounded")}
                          for ln, x in v["lines"].items()}
            refs[name]["points"] = v.get("points")
        else:
            refs[name] = {k: v[k] for k in ("na", "failed") if k in v}
    return {"id": r["id"], "class": r["cls"], "variant": r.get("variant"),
            "outcome": r["outcome"], "group": rep.group_of(r) if r["outcome"] == "wrong" else None,
            "what": rep._detail(r), "traceback_last": r.get("traceback_last"),
            "path": r.get("path"), "start": r.get("start"),
            "solver": {k: r.get(k) for k in ("T_A", "T_B", "grounded", "min_axial_N", "min_strain")},
            "reference": r.get("reference"), "references": refs,
            "moorpy_solved": r.get("moorpy_solved"), "scene": scene, "model": "cable3d"}


def summary_markdown(res: dict) -> str:
    recs = res["records"]
    n = len(recs)
    c = res["counts"]
    shown = [o for o in rep.OUTCOMES if c[o] or o in ("correct", "wrong", "nan", "clean error",
                                                        "ugly error", "hang")]
    L = [f"# cable3d scenes: {n} (seed {res['seed']})", "",
         f"Wall time {res['wall_s']:.0f} s; draws refused by load_scene and redrawn: "
         f"{res['refused_draws']}.", "", "| outcome | scenes | share |", "|---|---|---|"]
    for o in shown:
        L.append(f"| {o} | {c[o]} | {100 * c[o] / max(n, 1):.1f} % |")
    mp = res["moorpy"]
    L += ["", f"MoorPy's System applies to {mp['applies']} scenes and solves {mp['solved']}; "
          f"symcable solves {mp['sym_correct']} of those correctly. Primary references: "
          + ", ".join(f"{k} {v}" for k, v in sorted(res["references"].items())) + ".", "",
          "| class | scenes | " + " | ".join(shown) + " |", "|---|---|" + "---|" * len(shown)]
    for cls, cc in sorted(res["by_class"].items()):
        L.append(f"| {cls} | {sum(cc.values())} | " + " | ".join(str(cc.get(o, 0)) for o in shown) + " |")
    L += ["", "| reference pair | scenes | max dT / T scale | max d grounded / L | max shape / L | beyond |",
          "|---|---|---|---|---|---|"]
    for row in res["agreement"]["table"]:
        L.append(f"| {row['pair']} | {row['n']} | {row['dT']:.2g} | {row['dG']:.2g} | "
                 f"{row['shape']:.2g} | {len(row['bad'])} |")
    L.append("")
    bad = [r for r in recs if r["outcome"] != "correct"]
    if bad:
        L += ["## Not correct", ""]
        for r in bad:
            tail = f" -- `{r['traceback_last']}`" if r.get("traceback_last") else ""
            L.append(f"- `{r['id']}` {r['outcome']} ({r['cls']}, {r.get('variant')}; path "
                     f"{r.get('path')!r}, start {r.get('start')!r}): {rep._detail(r)[:300]}{tail}")
        L.append("")
    noted = [r for r in recs if r["outcome"] == "correct" and r.get("note")]
    if noted:
        L += ["## Correct after refining", ""]
        for r in noted:
            devs = ", ".join(f"{x['segments']}: {x['largest']:.3g}" for x in r.get("refined") or [])
            L.append(f"- `{r['id']}` ({r['cls']}): {r['note']} (largest deviation at {devs})")
        L.append("")
    L += ["## Slowest solves", "", "| scene | class | outcome | s | path |", "|---|---|---|---|---|"]
    for r in rep.slowest(recs):
        L.append(f"| {r['id']} | {r['cls']} | {r['outcome']} | {r['time_s']:.2f} | {r.get('path')} |")
    return "\n".join(L) + "\n"
