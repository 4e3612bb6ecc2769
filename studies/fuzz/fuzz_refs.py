"""Independent references of a fuzz scene, and how well they agree with each other.

Every reference returns the same record: end forces ``F_A`` and ``F_B`` (N, the force the line
exerts on end A and on end B, global x and z), tensions ``T_A``, ``T_B`` (N, their
magnitudes), ``grounded`` (m, unstretched length on the seabed), ``pile`` (the grounded part
is slack, H = 0, so its shape on the bed is not unique), and the continuous ``profile``
(M x 2, m) at arc lengths ``s``. A reference that does not apply gives ``{"na": why}``; one
that applies but fails, ``{"failed": why}``.

* ``piecewise`` -- the study's own closed form, :mod:`fuzz_catenary` (any sections, seabed,
  free ends; no bending, no current);
* ``catenary`` -- ``symcable.analytic.elastic_catenary`` (one section, pinned-pinned, seabed
  at the lower end or untouched; no bending, no current);
* ``moorpy`` -- ``moorpy.Catenary.catenary`` (one section, pinned-pinned, seabed at the
  anchor, or below both ends, including U-shaped lines touching down; no bending, no current);
* ``ode`` -- :mod:`fuzz_ode`, shooting on the cable equations (any sections, current, free
  ends; no bending, no seabed contact, no slack fold).

Scenes with bending (EI > 0 anywhere) have no reference here: their answers are judged by
the physical checks of :mod:`fuzz_classify` only.
"""
from __future__ import annotations

import contextlib
import io
import math
import os
import warnings

import numpy as np

import fuzz_bvp as bvp
import fuzz_catenary as pw
import fuzz_ode as ode

os.environ.setdefault("PYTHONBREAKPOINT", "0")   # MoorPy calls breakpoint() on some errors
ORDER = ("piecewise", "catenary", "ode", "moorpy", "bvp")
#: agreement between two references, the largest measured disagreement times about 10 (see
#: the README): tensions over the tension scale, grounded length and shape over the length
AGREE_T, AGREE_G, AGREE_SHAPE = 1e-5, 1e-4, 1e-4
MOORPY_NODES = 401
MOORPY_TOL = 1e-9          # m; MoorPy's default 1e-6 leaves 1.5e-5 of the tension on nearly taut lines


class Info:
    """What the references need of a scene, read with ``symcable.load_scene`` (which only
    parses: the weights are the ones the solver uses)."""

    def __init__(self, scene: dict):
        import symcable as sc
        s = sc.load_scene(scene)
        env = s.environment
        self.rho = env.water_density
        self.current = tuple(env.current) if self.rho > 0 else (0.0, 0.0)
        self.drag = any(u != 0.0 for u in self.current)
        self.depth = env.depth
        self.secs = [{"length": x.length, "w": x.line_type.weight, "EA": x.line_type.EA,
                      "EI": x.line_type.EI, "d": x.line_type.diameter,
                      "cdn": x.line_type.cd_normal, "cdt": x.line_type.cd_tangential,
                      "segments": x.segments, "k_bed": s.seabed.stiffness if s.seabed else None}
                     for x in s.sections]
        self.L = sum(x["length"] for x in self.secs)
        self.bending = any(x["EI"] > 0 for x in self.secs)
        self.ends = {}
        for name, e in (("A", s.end_a), ("B", s.end_b)):
            self.ends[name] = {"cond": e.condition.value, "pos": e.position,
                               "force": tuple(e.force) if e.force is not None else (0.0, 0.0),
                               "angle_deg": e.angle_deg}
        self.free = [k for k, e in self.ends.items() if e["cond"] == "free"]
        self.W = sum(abs(x["w"]) * x["length"] for x in self.secs)
        self.F_applied = sum(math.hypot(*e["force"]) for e in self.ends.values())
        self.force_scale = self.W + self.F_applied
        self.segments = sum(x["segments"] for x in self.secs)

    def line(self) -> pw.Line:
        return pw.Line([x["length"] for x in self.secs], [x["w"] for x in self.secs],
                       [x["EA"] for x in self.secs])

    def pinned_pinned(self) -> bool:
        return not self.free and all(e["cond"] == "pinned" for e in self.ends.values())


# ----------------------------------------------------------------------------- references
def ref_piecewise(info: Info) -> dict:
    if info.bending or info.drag:
        return {"na": "bending or current"}
    line = info.line()
    if info.free:
        fixed = "A" if info.free == ["B"] else "B"
        return pw.free_line(line, info.ends[fixed]["pos"], info.ends[info.free[0]]["force"],
                            info.free == ["B"], info.depth)
    return pw.pinned_line(line, info.ends["A"]["pos"], info.ends["B"]["pos"], info.depth)


def _single_pinned(info: Info) -> str | None:
    """Why a one-section pinned-pinned catenary reference does not apply (None if it does)."""
    if info.bending or info.drag:
        return "bending or current"
    if len(info.secs) != 1 or not info.pinned_pinned():
        return "not a single pinned-pinned section"
    if info.secs[0]["w"] == 0.0:
        return "weightless"
    return None


def ref_catenary(info: Info) -> dict:
    from symcable.analytic import elastic_catenary
    why = _single_pinned(info)
    if why:
        return {"na": why}
    sec, L = info.secs[0], info.L
    w = sec["w"]
    pa, pb = np.array(info.ends["A"]["pos"]), np.array(info.ends["B"]["pos"])
    tol = 1e-9 * L
    reverse = False
    seabed = False
    if info.depth is not None and w > 0:
        on_a, on_b = pa[1] + info.depth < tol, pb[1] + info.depth < tol
        seabed = on_a or on_b
        reverse = on_b and not on_a
    if reverse:
        pa, pb = pb, pa
    sx, sz = (1.0 if pb[0] >= pa[0] else -1.0), (1.0 if w > 0 else -1.0)
    sol = elastic_catenary(abs(pb[0] - pa[0]), sz * (pb[1] - pa[1]), L, sec["EA"], abs(w),
                           seabed=seabed)
    s = np.linspace(0.0, L, pw.N_PROFILE)
    pos = sol.positions(s) * [sx, sz] + pa
    if info.depth is not None and pos[:, 1].min() < -info.depth - tol:
        return {"na": "touches the seabed between two ends above it"}
    r = {"F_A": [sx * sol.H, sz * sol.V_a], "F_B": [-sx * sol.H, -sz * sol.V_b],
         "T_A": sol.anchor_tension, "T_B": sol.fairlead_tension,
         "grounded": sol.grounded_length, "pile": sol.H == 0.0 and sol.grounded_length > 0,
         "regime": "analytic", "profile": pos, "s": s}
    if reverse:
        r = pw._reverse(r, info.line())
    return r


def ref_moorpy(info: Info) -> dict:
    """MoorPy's catenary, at Tol = MOORPY_TOL and, if that answer fails its own checks, at
    MoorPy's default Tol (its U-shaped solve can break down at the tight one)."""
    why = _single_pinned(info)
    if why:
        return {"na": why}
    first = _moorpy_call(info, MOORPY_TOL)
    if "failed" not in first:
        return first
    second = _moorpy_call(info, 1e-6)
    return second if "failed" not in second else first


def _moorpy_call(info: Info, tol: float) -> dict:
    from moorpy.Catenary import catenary
    sec, L = info.secs[0], info.L
    pa, pb = np.array(info.ends["A"]["pos"]), np.array(info.ends["B"]["pos"])
    sx = 1.0 if pb[0] >= pa[0] else -1.0
    cb = -(1e3 * L + 1e3)           # no seabed: far below
    if info.depth is not None and sec["w"] > 0:
        h_a = pa[1] + info.depth
        cb = 0.0 if h_a < 1e-9 * L else -h_a
    with contextlib.redirect_stdout(io.StringIO()), warnings.catch_warnings():
        warnings.simplefilter("ignore")
        fah, fav, fbh, fbv, out = catenary(abs(pb[0] - pa[0]), pb[1] - pa[1], L, sec["EA"],
                                           sec["w"], CB=cb, nNodes=MOORPY_NODES, plots=1, Tol=tol)
    prof = np.stack([pa[0] + sx * np.asarray(out["X"]), pa[1] + np.asarray(out["Z"])], axis=1)
    ptype = out.get("ProfileType")
    rec = {"F_A": [sx * float(fah), float(fav)], "F_B": [sx * float(fbh), float(fbv)],
           "T_A": math.hypot(fah, fav), "T_B": math.hypot(fbh, fbv),
           "grounded": float(out.get("LBot", 0.0)), "pile": ptype in (4, 5),
           "regime": f"moorpy profile {ptype}, Tol {tol:g}", "profile": prof,
           "s": np.asarray(out["s"]), "shape_comparable": ptype not in (4, 5, 6)}
    # its own answer must balance (the seabed carries w LBot) and its profile end at B
    scale = max(rec["T_A"], rec["T_B"], abs(sec["w"]) * L)
    vertical = [fav + fbv]
    if ptype == 6:   # its vertical profile gets the sign of a folded end's force wrong at times
        vertical = [sa * abs(fav) + sb * abs(fbv) for sa in (1, -1) for sb in (1, -1)]
    unbalanced = max(abs(fah + fbh), min(abs(v + sec["w"] * (L - rec["grounded"]))
                                         for v in vertical)) / scale
    end_miss = float(np.hypot(*(prof[-1] - pb))) / L
    if not unbalanced <= 1e-6 or not end_miss <= 1e-6:
        return {"failed": f"MoorPy profile {ptype}: its end forces are off balance by "
                          f"{unbalanced:.2g} of the tension scale, its profile misses end B "
                          f"by {end_miss:.2g} L"}
    if info.depth is not None and ptype == 1:
        for p, fv in ((pa, fav), (pb, fbv)):
            if p[1] + info.depth < 1e-9 * L and fv < -1e-9 * scale:
                return {"failed": f"MoorPy returned a free catenary (profile 1) that pulls the end "
                                  f"on the seabed down ({fv:.4g} N): it goes through its seabed"}
    if ptype == 6 and pb[0] != pa[0]:
        rec["approximate"] = (f"MoorPy treats the line as exactly vertical (profile 6) at "
                              f"span/L = {abs(pb[0] - pa[0]) / L:.2g}")
    return rec


def ref_ode(info: Info, guess=None) -> dict:
    if info.bending:
        return {"na": "bending"}
    if not info.pinned_pinned() and len(info.free) != 1:
        return {"na": "end conditions"}
    cable = ode.Cable(info.secs, info.rho, info.current)
    if info.free:
        fixed = "A" if info.free == ["B"] else "B"
        r = ode.free(cable, info.ends[fixed]["pos"], info.ends[info.free[0]]["force"],
                     info.free == ["B"])
    else:
        r = ode.pinned(cable, info.ends["A"]["pos"], info.ends["B"]["pos"], guess)
    if info.depth is not None and r["profile"][:, 1].min() < -info.depth - 1e-9 * info.L:
        return {"na": "touches the seabed"}
    return r


def ref_bvp(info: Info) -> dict:
    if not info.bending:
        return {"na": "no bending"}
    cable = None
    try:   # the start: the same line without bending, current or seabed
        if info.free:
            fixed = "A" if info.free == ["B"] else "B"
            cable = pw.free_line(info.line(), info.ends[fixed]["pos"],
                                 info.ends[info.free[0]]["force"], info.free == ["B"], None)
        else:
            cable = pw.pinned_line(info.line(), info.ends["A"]["pos"], info.ends["B"]["pos"], None)
    except pw.NoReference:
        cable = None
    return bvp.elastica(info, cable)


def references(scene: dict) -> dict:
    """Every reference of a scene (name -> record), with ``agreement`` between them."""
    info = Info(scene)
    refs = {}
    for name, fn in (("piecewise", ref_piecewise), ("catenary", ref_catenary),
                     ("moorpy", ref_moorpy)):
        refs[name] = guard(fn, info)
    pw_ok = "T_A" in refs["piecewise"]
    guess = refs["piecewise"]["F_A"] if pw_ok else None
    refs["ode"] = guard(ref_ode, info, guess)
    refs["bvp"] = guard(ref_bvp, info)
    return {"refs": refs, "agreement": agreement(info, refs)}


FUNCTIONS = {"piecewise": ref_piecewise, "catenary": ref_catenary, "moorpy": ref_moorpy,
             "ode": ref_ode, "bvp": ref_bvp}


def guard(fn, *args) -> dict:
    try:
        with np.errstate(all="ignore"):
            return fn(*args)
    except pw.NoReference as exc:
        return {"failed" if "converge" in str(exc) else "na": str(exc)}
    except Exception as exc:  # noqa: BLE001 - a reference failing is data, not a crash
        return {"failed": f"{type(exc).__name__}: {exc}"[:300]}


def usable(r: dict) -> bool:
    """A reference that answered, and not by a known approximation."""
    return "T_A" in r and not r.get("approximate")


def primary(refs: dict):
    """(name, record) of the first usable reference in ORDER, or (None, None)."""
    for name in ORDER:
        if usable(refs.get(name, {})):
            return name, refs[name]
    return None, None


# ----------------------------------------------------------------------------- comparing
def curve_distance(points: np.ndarray, curve: np.ndarray) -> np.ndarray:
    """Distance of each point (n x dim) to the polyline ``curve`` (m x dim), in 2D or 3D."""
    a, b = curve[:-1], curve[1:]
    ab = b - a
    l2 = np.einsum("ij,ij->i", ab, ab)
    out = np.empty(len(points))
    for k, p in enumerate(points):
        t = np.clip(np.einsum("ij,ij->i", p - a, ab) / np.where(l2 > 0, l2, 1.0), 0.0, 1.0)
        out[k] = np.sqrt(np.min(np.sum((a + t[:, None] * ab - p) ** 2, axis=1)))
    return out


def bed_aware_distance(points, ref: dict, depth) -> np.ndarray:
    """Distance to the reference profile; where the reference's grounded part is slack (its
    shape on the bed not unique), a point lying on the bed counts as on it."""
    d = curve_distance(points, ref["profile"])
    if ref.get("pile") and depth is not None:
        d = np.minimum(d, np.abs(np.asarray(points)[:, 1] + depth))
    return d


def tension_scale(info: Info, ref: dict) -> float:
    return max(ref["T_A"], ref["T_B"], info.force_scale, 1e-12)


def compare(info: Info, ref: dict, T_A, T_B, grounded, points, shape_ok=True) -> dict:
    """Deviations of an answer from a reference: tensions over the tension scale, grounded
    length and the largest distance of the answer's points from the reference profile over
    the line length."""
    scale = tension_scale(info, ref)
    out = {"dT_A": abs(T_A - ref["T_A"]) / scale, "dT_B": abs(T_B - ref["T_B"]) / scale,
           "dG": abs(grounded - ref["grounded"]) / info.L, "shape": math.nan}
    if shape_ok and points is not None:
        d = float(bed_aware_distance(np.asarray(points), ref, info.depth).max())
        if ref.get("mirror"):   # a buckled rod's mirror twin is as good an answer
            twin = dict(ref, profile=bvp.reflect(ref["profile"], ref["mirror"]))
            d = min(d, float(bed_aware_distance(np.asarray(points), twin, info.depth).max()))
        out["shape"] = d / info.L
    return out


def agreement(info: Info, refs: dict) -> dict:
    """Pairwise agreement of the references that answered: the largest deviation of each kind
    over the pairs, and whether every pair is within AGREE_*."""
    names = [n for n in ORDER if usable(refs.get(n, {}))]
    worst = {"dT": 0.0, "dG": 0.0, "shape": 0.0}
    pairs = []
    for i, a in enumerate(names):
        for b in names[i + 1:]:
            ra, rb = refs[a], refs[b]
            shape_ok = ra.get("shape_comparable", True) and rb.get("shape_comparable", True)
            sub = rb["profile"][:: max(1, len(rb["profile"]) // 200)]
            c = compare(info, ra, rb["T_A"], rb["T_B"], rb["grounded"], sub, shape_ok)
            dT = max(c["dT_A"], c["dT_B"])
            ok = dT <= AGREE_T and c["dG"] <= AGREE_G and not (c["shape"] > AGREE_SHAPE)
            pairs.append({"pair": f"{a}-{b}", "dT": dT, "dG": c["dG"], "shape": c["shape"], "ok": ok})
            worst["dT"] = max(worst["dT"], dT)
            worst["dG"] = max(worst["dG"], c["dG"])
            if c["shape"] == c["shape"]:
                worst["shape"] = max(worst["shape"], c["shape"])
    return {"names": names, "pairs": pairs, "worst": worst,
            "ok": all(p["ok"] for p in pairs)}


def strip(refs: dict) -> dict:
    """The references without their profiles (for JSON)."""
    out = {}
    for name, r in refs.items():
        out[name] = {k: v for k, v in r.items() if k not in ("profile", "s")}
    return out
