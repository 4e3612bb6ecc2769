"""The seed-000 benchmark's pieces for studies/hybrid/run.py: the scenes (pure rod, pure
cable3d, hybrid) at any segment count and length, the profiles along the line (tension,
shear, moment), their differences, and the timed solves and runs.

Units: m, N, N m, s. Profiles are on arc length s (m) from the pin: tension and shear at
each edge's midpoint, the moment at each node.
"""
from __future__ import annotations

import contextlib
import copy
import statistics
import time

import casadi as ca
import numpy as np

import symcable as sc
import symcable.solvers.equilibrium as _equilibrium
from symcable.api.cable3d_static import cable3d_mechanism
from symcable.data import scene_path
from symcable.errors import SymcableError
from symcable.models.rod.reanchor import reanchor_hook
from symcable.api.rod_static import rod_mechanism
from symcable.scene import load_scene
from symcable.solvers.integrate import integrate
from symcable.solvers.options import GeneralizedAlpha, GeneralizedAlphaFirstOrder

ROD_ZONE = 0.5      # m: the seed's rod sub-domain, the last 0.5 m (s_j = 1.5 m on 2 m)
HYBRID_PENDING = "pending: model = 'hybrid' is not on main yet (helper hybrid14)"


def base() -> dict:
    """The pure-rod benchmark scene (symcable/data/seed000_rod.toml) as a dict."""
    return load_scene(str(scene_path("seed000_rod"))).to_dict()


def scene(model: str, n: int, length: float = 2.0, zone: float = ROD_ZONE,
          bending: bool = False):
    """The benchmark line of ``length`` m (the seed's 2 m; longer: the same cable with the
    same right end, so the low-tension zone is a smaller fraction) at ``n`` segments
    (ds = length / n), as ``model`` = "rod", "cable3d" (EI = 0: the seed's catenary; its
    free end holds no direction, so the force simply pulls along its tangent) or "hybrid"
    (cable3d on [0, length - zone], rod on the last ``zone`` m, the segment size kept;
    ``bending``: the cable3d section keeps the cable's EI, cable3d's own bending, as
    hybrid14's "bending" variant: no tension-only corner, which the release from straight
    needs). Raises SymcableError (a SceneError) where the model is not available."""
    d = base()
    sec = d["sections"][0]
    sec["length"], sec["segments"] = length, n
    if model == "rod":
        return load_scene(d)
    cab = copy.deepcopy(d["line_types"]["cable"])
    cab["EI"] = 0.0
    cab.pop("GJ", None)
    if model == "cable3d":
        d["model"] = "cable3d"
        d["line_types"] = {"cable": cab}
        d["end_b"] = {"condition": "free", "force": d["end_b"]["force"]}
        return load_scene(d)
    if model == "hybrid":
        n_rod = max(1, round(n * zone / length))
        d["model"] = "hybrid"
        d["line_types"]["catenary"] = dict(cab, EI=d["line_types"]["cable"]["EI"]) \
            if bending else cab
        d["sections"] = [{"type": "catenary", "length": length - zone, "segments": n - n_rod,
                          "model": "cable3d"},
                         {"type": "cable", "length": zone, "segments": n_rod, "model": "rod"}]
        return load_scene(d)
    raise ValueError(model)


def scene_or_none(model, n, length=2.0, zone=ROD_ZONE):
    """``scene(...)``, or None (the hybrid before it lands on main)."""
    try:
        return scene(model, n, length, zone)
    except SymcableError:
        if model != "hybrid":
            raise
        return None


def mechanism(s):
    """The Mechanism of a rod, cable3d or hybrid scene."""
    if s.model.value == "cable3d":
        return cable3d_mechanism(s)
    return rod_mechanism(s)  # rod, and hybrid (helper hybrid14: the rod with a mask)


@contextlib.contextmanager
def no_stability_check():
    """The static solve without its stability verdict (a dense eigenvalue solve of the
    reduced stiffness, n^3: 6.3 of the 7.1 s of a warm 200-segment rod solve); the Newton
    iterations are what the formulations are compared on."""
    old = _equilibrium.STABILITY_MAX_N
    _equilibrium.STABILITY_MAX_N = 0
    try:
        yield
    finally:
        _equilibrium.STABILITY_MAX_N = old


def solve(s):
    """(StaticSolution, cold wall time) of ``sc.solve_static`` (the generated C where the
    solver's own policy compiles); the warm time is :func:`interleaved`'s."""
    with no_stability_check():
        t0 = time.perf_counter()
        sol = sc.solve_static(s)
    return sol, time.perf_counter() - t0


def interleaved(jobs: dict, repeats: int) -> dict:
    """Median wall time (s) of each job (name -> callable, already warm), the jobs taken in
    turn within each of ``repeats`` rounds, so that a shared machine's load drifts over all
    of them alike."""
    times = {k: [] for k in jobs}
    with no_stability_check():
        for _ in range(repeats):
            for k, f in jobs.items():
                t0 = time.perf_counter()
                f()
                times[k].append(time.perf_counter() - t0)
    return {k: statistics.median(v) for k, v in times.items()}


def profiles(sol) -> dict:
    """Tension, shear (edges) and moment (nodes) along the line from a static solution (or
    a dict of outputs: positions, internal_force, bending_moment). cable3d: the axial force
    along each segment, no shear, no moment."""
    out = sol if isinstance(sol, dict) else sol.stats.get("outputs") or {
        "positions": sol.positions, "axial_force": sol.axial_force}
    X = np.asarray(out["positions"], float)
    dx = np.diff(X, axis=0)
    ell = np.linalg.norm(dx, axis=1)
    t = dx / ell[:, None]
    s_node = np.concatenate([[0.0], np.cumsum(ell)])
    s_edge = 0.5 * (s_node[1:] + s_node[:-1])
    if "internal_force" in out:
        f = np.asarray(out["internal_force"], float)
        T = np.einsum("ij,ij->i", f, t)
        shear = np.linalg.norm(f - T[:, None] * t, axis=1)
    else:
        T = np.ravel(np.asarray(out["axial_force"], float))
        shear = np.zeros_like(T)
    M = np.linalg.norm(np.asarray(out["bending_moment"], float), axis=1) \
        if "bending_moment" in out else np.zeros(len(X))
    return {"X": X, "s_edge": s_edge, "s_node": s_node, "T": T, "shear": shear, "M": M,
            "t_end": t[-1]}


def compare(a: dict, ref: dict, length: float = 2.0, zone: float = ROD_ZONE) -> dict:
    """Differences of profile ``a`` from ``ref`` (interpolated onto ref's points): tension
    over the whole line relative to ref's peak tension; shear and moment in the rod zone
    (s >= length - zone) relative to their peaks there; the right end's position."""
    s0 = length - zone
    dT = np.interp(ref["s_edge"], a["s_edge"], a["T"]) - ref["T"]
    z_e, z_n = ref["s_edge"] >= s0, ref["s_node"] >= s0
    dS = np.interp(ref["s_edge"], a["s_edge"], a["shear"])[z_e] - ref["shear"][z_e]
    dM = np.interp(ref["s_node"], a["s_node"], a["M"])[z_n] - ref["M"][z_n]
    return {"tension_err": float(np.max(np.abs(dT)) / np.max(ref["T"])),
            "shear_err": float(np.max(np.abs(dS)) / max(np.max(ref["shear"][z_e]), 1e-300)),
            "moment_err": float(np.max(np.abs(dM)) / max(np.max(ref["M"][z_n]), 1e-300)),
            "end_err": float(np.linalg.norm(a["X"][-1] - ref["X"][-1]))}


def straight_q(mech, s) -> np.ndarray:
    """The straight horizontal start (the seed's initial state) in the mechanism's q: each
    moving node at (s_i, 0, 0), each twist 0 (rod and hybrid order q node by node)."""
    n = sum(x.segments for x in s.sections)
    X = np.outer(np.linspace(0.0, s.length, n + 1), [1.0, 0.0, 0.0])
    node_q = next(p.node_q for p in mech.layout.parts.values() if p.kind == "line")
    q = np.zeros(mech.n_q)
    for i, idx in enumerate(np.asarray(node_q)):
        if idx[0] >= 0:
            q[idx] = X[i]
    return q


#: the release from straight before the seed's 1 s steps: (step, duration) s. The straight
#: start is a 30 deg kink at the guided end (accelerations of 1e4 m/s^2 on its node at 80
#: segments) and a line in free fall: from there the first 1 s step's Newton (from any
#: predictor, with or without a line search or step bounds) wanders among iterates whose
#: axial penalty is stretched by metres at 80 segments (it converges at 20); one second
#: of 0.01 s then 0.1 s steps takes the line past it
RELEASE = ((0.01, 0.1), (0.1, 0.9))


def relax(s, duration: float, dt: float = 1.0, release=RELEASE):
    """The dynamic relaxation from straight by generalized-alpha (second order in time,
    rho_inf = 0, the most numerical dissipation: a relaxation, as the seed's; CasADi's
    Newton, substeps where a step fails), the rod's frames re-anchored where an edge turns
    far from its anchor (``reanchor_hook``: without it a rod edge that swings to the half
    turn from its anchor meets the chart's singularity, where the step fails at any size:
    what stopped the seed's catenary hybrid at t = 0.23 s before). ``release`` (step,
    duration) legs from straight, then ``duration`` s at the seed's ``dt``. Returns a dict:
    the final outputs, the kinetic energy history, the wall times (the release's and the
    1 s steps'), step counts and substepped steps."""
    mech = mechanism(s)
    hook = reanchor_hook(mech)
    q = straight_q(mech, s)
    v, p = np.zeros_like(q), mech.params.values
    ts, Ks, t_now, wall1, steps1, sub1 = [], [], 0.0, 0.0, 0, 0
    method = GeneralizedAlpha(rho_inf=0.0)
    for h, dur in tuple(release) + ((dt, duration),):
        t0 = time.perf_counter()
        tr = integrate(mech, dur, h, method=method, q0=q, v0=v, p=p, progress=False,
                       reanchor=hook)
        wall = time.perf_counter() - t0
        if h != dt:
            wall1, steps1 = wall1 + wall, steps1 + tr.stats["steps"]
            sub1 += tr.stats.get("substepped_steps", 0)
        ts.append(t_now + np.asarray(tr.time))
        Ks.append(np.ravel(tr.outputs["kinetic_energy"]))
        t_now += dur
        q, v, p = np.asarray(tr.q)[-1], np.asarray(tr.v)[-1], _final_p(tr, p)
    last = {k: np.asarray(v)[-1] for k, v in tr.outputs.items()
            if k in ("positions", "internal_force", "bending_moment", "axial_force")}
    return {"last": last, "t": np.concatenate(ts), "K": np.concatenate(Ks),
            "release_wall": wall1, "release_steps": steps1, "release_substepped": sub1,
            "wall": wall, "steps": tr.stats["steps"],
            "substepped": tr.stats.get("substepped_steps", 0),
            "max_substeps": tr.stats.get("max_substeps", 1),
            "us_per_step": 1e6 * wall / tr.stats["steps"], "n_q": mech.n_q}


def _final_p(tr, p) -> np.ndarray:
    """The parameters at a run's end: re-anchored frames (the next leg's q is in their
    chart), else ``p``."""
    return np.asarray(tr.stats.get("p_final", p), float)


def step_runner(s, steps: int = 10, dt: float = 1.0, codegen: bool | None = False):
    """(sizes, run): the unknowns and the Jacobian's nonzeros (d force / d q), and a
    callable running ``steps`` first-order generalized-alpha steps of ``dt`` from the static
    state (warmed once here; ``codegen`` as ``integrate``'s, default the virtual machine)."""
    mech = mechanism(s)
    with no_stability_check():
        q = _equilibrium.solve_equilibrium(mech, require_stable=False).q
    method = GeneralizedAlphaFirstOrder(rho_inf=0.0)
    run = lambda: integrate(mech, steps * dt, dt, method=method, q0=q,  # noqa: E731
                            v0=np.zeros_like(q), codegen=codegen, progress=False)
    run()
    nnz = ca.jacobian(mech.force, mech.q).nnz()
    return {"n_q": mech.n_q, "jac_nnz": int(nnz)}, run
