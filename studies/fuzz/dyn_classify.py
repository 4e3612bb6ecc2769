"""The dynamic fuzz study's numbers and verdicts (:mod:`dyn_fuzz`).

:func:`numbers` reduces the runs of one scene (``a`` the time run at its default step,
``c`` the periodic solve, ``b`` and ``b16`` the reference runs at dt / 8 and dt / 16 over
the same 8 periods, ``bL`` a long reference at dt / 8 over 20 periods, its last two kept)
to per line end numbers; :func:`classify` turns them into the verdicts, so that they can
be made again from ``results.json`` without running anything.

True errors (each the largest over every line end; the normalisation of each is that of
the estimate it is compared with):

- ``true_sim``: the time run's least and largest tension over its last period against the
  reference's at the same sample times (every 8th or 16th reference step: the
  discretisation error alone, no sampling difference), relative to the end's tension range
  over the reference run, at least 1e-3 of the largest end tension of the run (simulate's
  estimate is "% of the range of the end tensions over the run", with that floor);
  ``true_sim_end`` the same relative to the end's range over the last period, at least 1 %
  of its largest tension there (the issue's wording; what solve_periodic uses);
- ``true_sim_run``: the largest difference over the whole run, sample by sample, relative
  to the same range as ``true_sim`` (what the time_error study validated the estimate on);
- ``true_per``: the periodic solution's extremes against the reference's last period
  (every reference sample; the long reference when the 8-period one had not settled),
  relative to the end's range over that period, at least 1 % of its largest tension there
  (solve_periodic's own normalisation) and at least 1e-3 of the largest end tension of the
  scene (simulate's floor; without it an end lying on the bed at 0.1 N, in a line pulled
  at 134 kN, read a difference of 0.013 N as 1300 %: ``true_per_nofloor`` keeps that
  reading). ``true_sim_end``, ``settle`` and ``ref_conv_per`` are normalised the same way;
- ``settle``: that reference's last period against the one before it, the same way (the
  run has settled into a period when this is at most SETTLE);
- ``ref_conv``: the dt / 8 run against the dt / 16 run (how far the reference itself is
  from converged; the finest is the reference). The time run's verdict takes its distance
  to both runs (``true_sim_b8`` and ``true_sim``); the periodic one's margin widens by
  ``ref_conv_per`` (the same, normalised as ``true_per``).
"""
from __future__ import annotations

import math

import numpy as np

#: the warning threshold of both estimates (ERROR_TARGET, TIME_ACCURACY)
TARGET = 0.01
#: an unwarned answer is a silent wrong answer above this (between TARGET and SILENT:
#: "quiet"): the estimate only has to be within a factor of 3, and an estimate just under
#: the 1 % at which it warns is within a factor of 2 of a true error up to 2 %
SILENT = 0.02
#: the reference has settled into a period when its last two periods differ by at most this
SETTLE = 0.005
#: the wall-time bound of one call under test, s (a call past it counts as a hang)
BOUND = 180.0
FACTOR = 3.0

SIM_CLASSES = ("correct", "warned", "quiet 1-2 %", "silent wrong", "unsure (reference)",
               "no reference", "clean error", "crash", "hang")
PER_CLASSES = ("correct", "warned", "quiet 1-2 %", "silent wrong", "unsure (reference)",
               "no period: warned", "no period: answered", "no reference", "clean error",
               "crash", "hang")


# ----------------------------------------------------------------------------- numbers
def _window(t, t0, t1):
    h = (t[1] - t[0]) if t.size > 1 else 1.0
    return (t >= t0 - 1e-6 * h) & (t <= t1 + 1e-6 * h)


def _index(t_ref, t):
    """Indices of the samples of ``t_ref`` at the times ``t`` (nearest) and the largest
    misfit, s."""
    idx = np.rint(np.interp(t, t_ref, np.arange(t_ref.size))).astype(int)
    return idx, float(np.max(np.abs(t_ref[idx] - t))) if t.size else 0.0


def numbers(series: dict, T: float) -> dict:
    """Per line end numbers of the runs in ``series`` ({"a"|"c"|"b"|"b16"|"bL": (time,
    {end: tension})}); every reference present is compared with every answer (the long
    reference ``bL``, two periods only, with the periodic answer alone)."""
    out, misfit = {}, 0.0
    refs = [k for k in ("b", "b16", "bL") if k in series]
    for R in refs:
        tr, fr = series[R]
        t_end = float(tr[-1])
        last, prev = _window(tr, t_end - T, t_end), _window(tr, t_end - 2 * T, t_end - T)
        for end, f in fr.items():
            e = out.setdefault(end, {})
            e.update({f"{R}_lo": float(f[last].min()), f"{R}_hi": float(f[last].max()),
                      f"{R}p_lo": float(f[prev].min()), f"{R}p_hi": float(f[prev].max()),
                      f"{R}_ptp_run": float(np.ptp(f)), f"{R}_max_run": float(f.max())})
        if "a" in series and R != "bL":   # the long run keeps its last two periods only
            ta, fa = series["a"]
            idx, m = _index(tr, ta)
            misfit = max(misfit, m)
            la = _window(ta, t_end - T, t_end)
            for end, f in fa.items():
                if end not in fr:
                    continue
                g = fr[end][idx]
                e = out[end]
                e.update({"a_lo": float(f[la].min()), "a_hi": float(f[la].max()),
                          f"{R}a_lo": float(g[la].min()), f"{R}a_hi": float(g[la].max()),
                          f"pw_a{R}": float(np.max(np.abs(f - g))),
                          "a_max_run": float(f.max())})
        if "c" in series:
            tc, fc = series["c"]
            idx, m = _index(tr, t_end - T + tc)
            misfit = max(misfit, m)
            for end, f in fc.items():
                if end in fr:
                    out[end].update({"c_lo": float(f.min()), "c_hi": float(f.max()),
                                     f"pw_c{R}": float(np.max(np.abs(f - fr[end][idx])))})
    if "b" in refs and "b16" in refs:
        tb, fb = series["b"]
        idx, m = _index(series["b16"][0], tb)
        misfit = max(misfit, m)
        for end, f in fb.items():
            out[end]["pw_bb16"] = float(np.max(np.abs(f - series["b16"][1][end][idx])))
    return {"ends": out, "time_misfit": misfit, "refs": refs}


# ----------------------------------------------------------------------------- errors
def _scale(e, R, floor=0.0):
    """An end's tension range over the last period of run R, at least 1 % of its largest
    tension there (solve_periodic's normalisation) and at least ``floor``."""
    lo, hi = e[f"{R}_lo"], e[f"{R}_hi"]
    return max(hi - lo, 0.01 * max(abs(hi), abs(lo)), floor, 1e-300)


def _worst(ends: dict, fn):
    """(largest value of fn(end numbers), its end); ends fn returns None for are skipped."""
    best, where = None, None
    for k, e in ends.items():
        v = fn(e)
        if v is not None and (best is None or v > best):
            best, where = v, k
    return best, where


def _ext(e, x, rx, scale):
    """The larger difference of the least and largest tensions of ``x`` and ``rx`` over
    ``scale``; None when either is missing."""
    if f"{x}_lo" not in e or f"{rx}_lo" not in e:
        return None
    return max(abs(e[f"{x}_lo"] - e[f"{rx}_lo"]), abs(e[f"{x}_hi"] - e[f"{rx}_hi"])) / scale


def errors(nums: dict) -> dict:
    """The true errors of one scene (see the module docstring): the time run's against the
    finest of the dt / 8 and dt / 16 runs, each end's error relative to its tension range
    over that run, at least 1e-3 of the largest end tension of the run (the normalisation
    of simulate's own estimate); the periodic solution's against the long reference (20
    periods) when there is one, else the same, relative to each end's range over the last
    period, at least 1 % of its largest tension there (solve_periodic's)."""
    ends = nums["ends"]
    short = [k for k in nums["refs"] if k != "bL"]
    if not short:
        return {}
    R = short[-1]
    P = "bL" if "bL" in nums["refs"] else R
    floor = 1e-3 * max([e.get(f"{R}_max_run", 0.0) for e in ends.values()] + [0.0])
    run = lambda e: max(e.get(f"{R}_ptp_run", 0.0), floor, 1e-300)
    per = lambda e, X: _scale(e, X, floor)
    out = {"ref": R, "ref_per": P}
    out["true_sim"], out["where_sim"] = _worst(ends, lambda e: _ext(e, "a", f"{R}a", run(e)))
    out["true_sim_end"], _ = _worst(ends, lambda e: _ext(e, "a", f"{R}a", per(e, R)))
    out["true_sim_run"], _ = _worst(ends, lambda e: e[f"pw_a{R}"] / run(e)
                                    if f"pw_a{R}" in e else None)
    out["true_per"], out["where_per"] = _worst(ends, lambda e: _ext(e, "c", P, per(e, P)))
    out["true_per_nofloor"], _ = _worst(ends, lambda e: _ext(e, "c", P, _scale(e, P)))
    out["settle"], _ = _worst(ends, lambda e: _ext(e, f"{P}p", P, per(e, P)))
    out["settle_8"], _ = _worst(ends, lambda e: _ext(e, f"{R}p", R, per(e, R)))
    if "b16" in nums["refs"]:
        out["ref_conv"], _ = _worst(ends, lambda e: _ext(e, "b", "b16", run(e)))
        out["ref_conv_per"], _ = _worst(ends, lambda e: _ext(e, "b", "b16", per(e, "b16")))
        out["true_sim_b8"], _ = _worst(ends, lambda e: _ext(e, "a", "ba", run(e)))
        out["true_sim_end_b8"], _ = _worst(ends, lambda e: _ext(e, "a", "ba", per(e, "b")))
    return out


# ----------------------------------------------------------------------------- verdicts
#: the warnings of a time run whose error is not known to be within 1 %: its own estimate's
#: (a fixed step), or a tolerance that the step halvings did not reach or verify
SIM_WARNINGS = ("time step is too coarse", "not reached by dt", "not verified")


def _warned_sim(call: dict) -> tuple:
    w = call.get("warnings") or []
    return (any(m in x for x in w for m in SIM_WARNINGS),
            any("snapped taut" in x for x in w))


def _warned_per(call: dict) -> bool:
    """The warning of an estimate over 1 %, or the note that there is no estimate (the
    solves to compare with failed): either says the error is not known to be small."""
    return any("time-discretisation error" in x for x in call.get("warnings") or [])


def _est_sim(call):
    """The run's error estimate: its verified bound when its step was chosen for a
    tolerance (``error_measured``), else its own estimate."""
    st = call.get("stats") or {}
    return st.get("error_measured") if st.get("error_measured") is not None \
        else st.get("error_estimate")


def _est_per(call):
    tde = (call.get("stats") or {}).get("time_discretisation_error") or {}
    return tde.get("relative")


def _call_class(call: dict | None):
    """"clean error", "crash", "hang" or None (an answer within the bound)."""
    if call is None:
        return None
    if call.get("outcome") in ("hang", "killed") or (call.get("wall") or 0.0) > BOUND:
        return "hang"
    if call["outcome"] == "clean error":
        return "clean error"
    if call["outcome"] in ("ugly error", "crash"):
        return "crash"
    return None


def _verdict(dists, warned, ref_conv=None):
    """The verdict of an answer off the reference runs by ``dists`` (relative; None or an
    empty list: no reference), ``warned`` or not: correct when within TARGET of every one,
    silent wrong when off every one by more than SILENT, quiet when off every one by more
    than TARGET and within SILENT of every one, else unsure (the references disagree across
    a verdict line). A warned answer is correct or warned by the finest reference. An
    unwarned answer off by more than TARGET while the references themselves (dt / 8 against
    dt / 16: ``ref_conv``) differ by more than TARGET is unsure: no reference is known to 1 %
    (the undamped stiff modes of q33-0005 and d33-0053 grow as the step shrinks; a finer run
    does not settle within the study's budget)."""
    if not dists:
        return "no reference"
    if warned:
        return "correct" if dists[-1] <= TARGET else "warned"
    lo, hi = min(dists), max(dists)
    if hi <= TARGET:
        return "correct"
    if ref_conv is not None and ref_conv > TARGET:
        return "unsure (reference)"
    if lo > SILENT:
        return "silent wrong"
    if lo > TARGET and hi <= SILENT:
        return "quiet 1-2 %"
    return "unsure (reference)"


def classify(rec: dict) -> dict:
    """Add the verdicts (``sim_class``, ``per_class``), true errors, estimates and factors
    to a scene record (in place; returns it)."""
    if rec.get("harness_error"):
        rec.update(sim_class="crash", per_class="crash")
        return rec
    nums = rec.get("numbers")
    err = errors(nums) if nums and nums.get("ends") else {}
    rec.update({k: v for k, v in err.items()})
    sim, per = rec.get("sim"), rec.get("per")

    cc = _call_class(sim)
    coarse, snap = _warned_sim(sim or {})
    rec["est_sim"] = _est_sim(sim or {})
    rec["warned_sim"], rec["snap_warned_sim"] = coarse, snap
    dists = [d for d in (err.get("true_sim_b8"), err.get("true_sim")) if d is not None]
    rec["sim_class"] = cc or _verdict(dists, coarse, err.get("ref_conv"))
    dists = [d for d in (err.get("true_sim_end_b8"), err.get("true_sim_end")) if d is not None]
    rec["sim_class_end"] = cc or _verdict(dists, coarse, err.get("ref_conv_per"))

    cc = _call_class(per)
    rec["est_per"] = _est_per(per or {})
    rec["warned_per"] = _warned_per(per or {})
    if cc:
        rec["per_class"] = cc
    elif err.get("settle") is None or err.get("true_per") is None:
        rec["per_class"] = "no reference"
    elif err["settle"] > SETTLE:
        rec["per_class"] = "no period: warned" if rec["warned_per"] else "no period: answered"
    else:
        t, u = err["true_per"], err.get("ref_conv_per") or 0.0
        rec["per_class"] = _verdict([max(t - u, 0.0), t + u, t], rec["warned_per"])

    for key, t, e in (("sim", err.get("true_sim"), rec["est_sim"]),
                      ("sim_run", err.get("true_sim_run"), rec["est_sim"]),
                      ("per", err.get("true_per"), rec["est_per"])):
        ok = t is not None and e is not None and t > 0 and math.isfinite(e)
        rec[f"factor_{key}"] = (e / t) if ok and e > 0 else (0.0 if ok else None)
    return rec


def in_factor(f) -> bool:
    return f is not None and 1.0 / FACTOR <= f <= FACTOR


def needs_finer(rec: dict, series: dict, T: float) -> bool:
    """Whether a scene's verdict could depend on the error of the dt / 8 reference: an
    answer off it by more than half the target without a warning, or an estimate more than
    a factor 2 off a true error above the target (or a periodic verdict near the settling
    line)."""
    if "b" not in series:
        return False
    r = classify(dict(rec, numbers=numbers(series, T)))
    for t, e, warned in ((r.get("true_sim"), r.get("est_sim"), r.get("warned_sim")),
                         (r.get("true_per"), r.get("est_per"), r.get("warned_per"))):
        if t is None:
            continue
        if t > 0.5 * TARGET and not warned:
            return True
        if t > TARGET and e is not None and not 0.5 <= e / t <= 2.0:
            return True
    s = r.get("settle")
    return s is not None and 0.5 * SETTLE < s <= 2 * SETTLE
