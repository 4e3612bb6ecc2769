"""Statics of the stiff-EA rod and of the exact-constraint rod (study code): the scenes, one
Newton solve measured (iterations, wall time, condition number of the Jacobian at the
solution) and the profiles compared.

Units: m, N, s. Both mechanisms are solved by the same Newton on the Mechanism's own static
residual and its exact Jacobian (``derive.functions(mech).static_step``: sparse QR): plain
full steps (:func:`plain_newton`), or the library's damped Newton
(:func:`symcable.solvers.newton.newton`: Armijo line search, each unknown's step bounded by
its scale, as ``solve_equilibrium``'s damped attempt), from the same start and to the same
tolerance, so the iteration counts and times compare the formulations, not two solvers.
"""
from __future__ import annotations

import time

import casadi as ca
import numpy as np

from symcable.data import scene_path
from symcable.mechanism.functions import functions
from symcable.models.rod.rod import rod_table
from symcable.api.rod_static import rod_mechanism
from symcable.scene import load_scene
from symcable.solvers.equilibrium import _x_scale, solve_equilibrium
from symcable.solvers.newton import newton

from inext_constrained import constrained


def benchmark(n: int, ea_factor: float = 1.0):
    """Seed 000's benchmark rod (symcable/data/seed000_rod.toml) at ``n`` segments with its EA
    multiplied by ``ea_factor``."""
    d = load_scene(str(scene_path("seed000_rod"))).to_dict()
    d["sections"][0]["segments"] = n
    d["line_types"]["cable"]["EA"] *= ea_factor
    return load_scene(d)


def hanging(n: int, ea: float, length: float = 2.0, tip: float = 0.05):
    """The closed form: the benchmark's cable (its EI, GJ, mass, d, water) hanging from a pin,
    a downward force ``tip`` N at its free end, ``n`` segments, axial stiffness ``ea`` N. It
    hangs straight; edge j carries T_j = P + w (L - s_j) (s_j its midpoint, w the weight per
    metre: the lumped node weights below the edge sum to exactly that), the constrained tip
    is at z = -L, the stiff one at z = -(L + (P L + w L^2 / 2) / EA) exactly (the linear law:
    sum of T_j ds / EA)."""
    d = load_scene(str(scene_path("seed000_rod"))).to_dict()
    d["line_types"]["cable"]["EA"] = ea
    d["sections"][0].update(length=length, segments=n)
    d["end_a"] = {"condition": "pinned", "position": [0.0, 0.0, 0.0]}
    d["end_b"] = {"condition": "free", "force": [0.0, 0.0, -tip]}
    return load_scene(d)


def pair(scene, soft: float = 1e-6):
    """(stiff rod Mechanism, its exact-constraint variant, rest lengths ds). The constrained
    variant is built on the rod with EA x ``soft``: its axial term cancels algebraically
    whatever EA is, and a small one keeps the cancelled terms' round-off (EA e t, e ~ eps /
    ds) and the residual floor the Mechanism reports at the constraint's own size."""
    rod = rod_mechanism(scene)
    ds = rod_table(scene)["ds"]
    d = scene.to_dict()
    for lt in d["line_types"].values():
        lt["EA"] *= soft
    return rod, constrained(rod_mechanism(load_scene(d)), ds), ds


def multipliers(mech, q, p) -> np.ndarray:
    """Least-squares multipliers at q: z minimising |f(q, 0, z)| (the constraint forces that
    best balance the rest at the start), N; empty for an unconstrained Mechanism."""
    if not mech.n_z:
        return np.zeros(0)
    F = functions(mech)
    z0 = np.zeros(mech.n_z)
    r_f, _ = F.acc_residual(q, np.zeros(mech.n_v), np.zeros(mech.n_v), z0, 0.0, p)
    B = np.array(ca.DM(F.tangents(q, np.zeros(mech.n_v), z0, 0.0, p)[3]).full())
    # r_f = -f = -(f0 - B^T z): f0 + ... = B^T z
    return np.linalg.lstsq(B.T, -np.asarray(r_f).ravel(), rcond=None)[0]


def cond(J: np.ndarray, equilibrate: bool = False) -> float:
    """2-norm condition number of a dense matrix; ``equilibrate``: after scaling its rows and
    columns to unit largest entry (Ruiz, 10 passes), the part no diagonal scaling removes."""
    A = np.array(J, float)
    if equilibrate:
        for _ in range(10):
            r = np.sqrt(np.max(np.abs(A), axis=1))
            c = np.sqrt(np.max(np.abs(A), axis=0))
            A = A / r[:, None] / c[None, :]
    s = np.linalg.svd(A, compute_uv=False)
    return float(s[0] / s[-1])


def plain_newton(step, x, p, tol: float, max_iter: int = 60, polish: int = 4):
    """Full Newton steps, no line search or step bound: (x, iterations to max |r| <= tol,
    max |r|, converged). Once converged, up to ``polish`` more steps (not counted) keep the
    iterate of least residual: the solution at the formulation's round-off floor, which the
    accuracy comparison needs (the tolerance alone leaves the stiff rod's tension as
    uncertain as its residual over EA / ds)."""
    for it in range(max_iter + 1):
        try:
            r, dx = step(x, p)
        except RuntimeError:  # CasADi's QR refuses a singular Jacobian: a failed solve
            return x, it, float("nan"), False
        nr = float(np.max(np.abs(np.asarray(r))))
        if not np.isfinite(nr):
            return x, it, nr, False
        if nr <= tol:
            best = (nr, x)
            for _ in range(polish):
                x = x + np.asarray(dx).ravel()
                try:
                    r, dx = step(x, p)
                except RuntimeError:
                    break
                nr = float(np.max(np.abs(np.asarray(r))))
                best = min(best, (nr, x), key=lambda b: b[0])
            return best[1], it, best[0], True
        if it < max_iter:
            x = x + np.asarray(dx).ravel()
    return x, max_iter, nr, False


def solve(mech, q0, p, tol: float, z0=None, damped: bool = False) -> dict:
    """Newton from (q0, z0) (z0 default: :func:`multipliers`) to max |R| <= tol N: plain
    (full steps) or ``damped`` (the library's :func:`~symcable.solvers.newton.newton`, Armijo
    line search and each unknown's step bounded by its scale, as ``solve_equilibrium``'s
    damped attempt). Returns x, iterations, residual, wall time (s, the solves only: the
    Functions are built and warmed before the clock starts), converged."""
    F = functions(mech)
    z0 = multipliers(mech, q0, p) if z0 is None else z0
    x0 = np.concatenate([q0, z0])
    step = F.static_step
    step(x0, p)  # build and warm
    t0 = time.perf_counter()
    if damped:
        res = newton(step, x0, p, tol=tol, max_iter=100, x_scale=_x_scale(F))
        x, its, nr, ok = res.x, res.iterations, res.residual_norm, res.converged
    else:
        x, its, nr, ok = plain_newton(step, x0, p, tol)
    wall = time.perf_counter() - t0
    return {"x": x, "iterations": its, "residual": nr, "time": wall, "converged": ok}


def profile(mech, x, p) -> dict:
    """Outputs at the static state x = (q, z): positions (N+1, 3) m, tension per edge N (the
    stiff rod's EA e, the constrained rod's z), the seed's tension f . t per edge (N), the
    edge lengths' relative error, the Jacobian's condition numbers."""
    F = functions(mech)
    q, z = x[:mech.n_q], x[mech.n_q:]
    out = F.unpack(np.asarray(F.outputs(q, np.zeros(mech.n_v), z, 0.0, p)).ravel())
    X = out["positions"]
    dx = np.diff(X, axis=0)
    ell = np.linalg.norm(dx, axis=1)
    f = out["internal_force"]
    J = np.array(ca.DM(F.static_jacobian(x, p)[1]).full())
    return {"X": X, "T": np.asarray(out["axial_force"]).ravel(),
            "ft": np.sum(f * dx / ell[:, None], axis=1), "ell": ell,
            "cond": cond(J), "cond_eq": cond(J, True), "n": J.shape[0]}


def static_pair(rod, con, load: float = 1.0, tol_rel: float = 1e-9):
    """(x_stiff, x_constrained), x = (q, z), the benchmark at ``load`` x its loads: the stiff
    rod by plain Newton from its first start (the line hanging straight along its load), the
    constrained rod by plain Newton from the stiff rod's solution with least-squares
    multipliers; where plain Newton fails, from the library's ``solve_equilibrium``."""
    st = next(iter(rod.starts()))
    out = []
    for mech in (rod, con):
        p = mech.params.with_values(mech.static_p, load=load)
        q0 = st.q if mech is rod else out[0][:rod.n_q]
        tol = max(tol_rel * rod.scales.force, 10 * mech.scales.residual_floor)
        sol = solve(mech, q0, p, tol)
        if not sol["converged"]:  # the library's solve (line search, continuations)
            eq = solve_equilibrium(mech, p, tol=tol)
            sol = solve(mech, eq.q, p, tol, z0=eq.z)
        out.append(sol["x"])
    return out


def compare(n: int, ea_factors, tol_rel: float = 1e-9, damped: bool = True) -> list[dict]:
    """The benchmark at ``n`` segments: the constrained rod and the stiff rod at each EA
    factor. Newton iterations and wall time (plain Newton) from two starts: ``cold``, the
    rod's own first start (the line hanging straight along its load; multipliers by least
    squares; also ``damped``, -1 when not run), and ``warm``, each model's solution at 0.9 x
    the loads (a continuation step). Tolerance max(tol_rel x force scale, 10 x the
    Mechanism's residual floor), as ``solve_equilibrium``'s default. Rows: model, EA,
    iterations, times, condition numbers of the static Jacobian at the solution (raw: rows in N, the
    constraint's scaled to N by the library's force / q_ref; equilibrated), and against the
    constrained solution the largest tension difference (relative to the peak tension) and
    position difference (m); T/EA (the peak tension over EA)."""
    rows, ref = [], None
    start = next(iter(pair(benchmark(n))[0].starts()))
    for fac in [None] + list(ea_factors):
        s = benchmark(n, 1.0 if fac is None else fac)
        rod, con, ds = pair(s)
        mech = con if fac is None else rod
        p = mech.static_p
        tol = max(tol_rel * rod.scales.force, 10 * mech.scales.residual_floor)
        cold = solve(mech, start.q, p, tol)
        damped_ = solve(mech, start.q, p, tol, damped=True) if damped else \
            {"iterations": -1, "converged": False}
        x9 = static_pair(rod, con, 0.9)[1 if mech is con else 0]
        sol = solve(mech, x9[:mech.n_q], p, tol, z0=x9[mech.n_q:])
        pr = profile(mech, sol["x"], p)
        row = {"case": "benchmark", "segments": n, "model": "constrained" if fac is None else
               "stiff EA", "EA_factor": fac if fac is not None else float("nan"),
               "EA": float(s.line_types["cable"].EA) if fac is not None else float("inf"),
               "unknowns": pr["n"], "tol": tol,
               "cold_iterations": cold["iterations"], "cold_converged": cold["converged"],
               "damped_iterations": damped_["iterations"],
               "damped_converged": damped_["converged"],
               "iterations": sol["iterations"], "converged": sol["converged"],
               "residual": sol["residual"], "time": sol["time"],
               "time_per_iteration": sol["time"] / max(sol["iterations"], 1),
               "cond": pr["cond"], "cond_eq": pr["cond_eq"],
               "strain_max": float(np.max(np.abs(pr["ell"] / ds - 1.0)))}
        if ref is None:
            ref = pr
            row.update(dT=0.0, dft=0.0, dX=0.0, tip_dX=0.0, T_over_EA=0.0)
        else:
            peak = float(np.max(np.abs(ref["T"])))
            row.update(dT=float(np.max(np.abs(pr["T"] - ref["T"]))) / peak,
                       dft=float(np.max(np.abs(pr["ft"] - ref["ft"]))) / peak,
                       dX=float(np.max(np.abs(pr["X"] - ref["X"]))),
                       tip_dX=float(np.linalg.norm(pr["X"][-1] - ref["X"][-1])),
                       T_over_EA=peak / row["EA"])
        row["T_peak"] = float(np.max(np.abs(pr["T"])))
        rows.append(row)
    return rows


def closed_form(n: int, ea: float, tip: float = 0.05, length: float = 2.0) -> dict:
    """The hanging rod (:func:`hanging`), both models against the closed form: tension error
    (N, max over edges), tip z error (m), and the stiff rod's stretch against
    (P L + w L^2 / 2) / EA."""
    s = hanging(n, ea, length, tip)
    rod, con, ds = pair(s)
    seg = rod_table(s)
    w = float(seg["w"][0])  # N/m, the scene's submerged weight (the benchmark's rho_f = 1)
    smid = 0.5 * (seg["s"][:-1] + seg["s"][1:])
    T_exact = tip + w * (length - smid)
    stretch = (tip * length + w * length ** 2 / 2) / ea
    out = {"segments": n, "EA": ea, "stretch_exact": stretch}
    for name, mech in (("stiff", rod), ("constrained", con)):
        p = mech.static_p
        # the straight start at rest length carries no tension: its Jacobian is singular
        # (the rigid rotation about the pin); stretched by the mean strain, it is not
        q0 = next(iter(rod.starts())).q * (1.0 + stretch / length)
        sol = solve(mech, q0, p, max(1e-12 * rod.scales.force, 10 * mech.scales.residual_floor))
        pr = profile(mech, sol["x"], p)
        out[name] = {"iterations": sol["iterations"], "converged": sol["converged"],
                     "T_err": float(np.max(np.abs(pr["T"] - T_exact))),
                     "tip_z": float(pr["X"][-1, 2]), "T": pr["T"],
                     "length_err": float(np.max(np.abs(pr["ell"] - ds)))}
    out["T_exact_max"] = float(T_exact.max())
    out["constrained"]["tip_err"] = out["constrained"]["tip_z"] + length
    out["stiff"]["stretch"] = -out["stiff"]["tip_z"] - length
    return out


def pendulum_scene(length: float = 2.0, ea_factor: float = 1.0):
    """One edge of the benchmark's cable, pinned at the origin, its other end free: no water
    (no drag, no added mass), a simple pendulum of length ``length`` m whose mass is the
    lumped half edge at its tip (the pinned node's is held). Its weight is the line type's
    as written in the benchmark's scene (the submerged weight with rho_f = 1: the dict
    carries it), so the pendulum's g is the tip weight over the tip mass (9.79 m/s^2).
    EA x ``ea_factor``."""
    d = load_scene(str(scene_path("seed000_rod"))).to_dict()
    d["environment"]["water_density"] = 0.0
    lt = d["line_types"]["cable"]
    lt.update(cd_normal=0.0, cd_tangential=0.0, EA=lt["EA"] * ea_factor)
    d["sections"][0].update(segments=1, length=length)
    d["end_a"] = {"condition": "pinned", "position": [0.0, 0.0, 0.0]}
    d["end_b"] = {"condition": "free", "force": [0.0, 0.0, 0.0]}
    return load_scene(d)
