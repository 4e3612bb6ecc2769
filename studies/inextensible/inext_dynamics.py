"""Dynamics of the stiff-EA rod and of the exact-constraint rod (study code): the
generalized-alpha step of Arnold & Bruels (2007) with a Newton loop that counts its
iterations, on the benchmark perturbed from rest and on a pendulum (closed form).

The step is the library's (:mod:`symcable.solvers.steps`, ``galpha_step``): the same
pseudo-acceleration update, the equations of motion and the position-level constraints
imposed at t1 (the index-3 form), unknowns w = (a1, z1), the force rows over the force scale
and the constraint rows times m / (beta h^2 F) (the scaling that keeps the iteration matrix
O(1) as h -> 0); only the Newton loop is written out here (sparse LU per iteration, the
exact Jacobian from CasADi) so that the iterations and the Jacobian's condition number can
be read. Convergence as the library's: the residual in the rows' own units (forces over the
force scale, constraint rows over their scale) below ``tol``. Units: m, N, s.
"""
from __future__ import annotations

import math
import time

import casadi as ca
import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spl
from scipy.special import ellipj, ellipk

from symcable.mechanism.functions import functions
from symcable.solvers.galpha1 import galpha1_kernel, step_scales
from symcable.solvers.options import GeneralizedAlpha, GeneralizedAlphaFirstOrder

from symcable.models.rod.rod import rod_table

from inext_statics import benchmark, cond, pair, pendulum_scene, static_pair


#: the library's second-order generalized-alpha tolerance (GeneralizedAlpha().tol)
STEP_TOL = GeneralizedAlpha().tol


class Stepper:
    """One Mechanism's generalized-alpha step, Newton written out (module docstring)."""

    def __init__(self, mech, rho_inf: float, tol: float = 1e-10, scale_constraints=True):
        self.mech, self.tol = mech, tol
        F = functions(mech)
        am, af, gamma, beta = GeneralizedAlpha(rho_inf=rho_inf).coefficients
        self.beta = beta
        nq, nv, nz = mech.n_q, mech.n_v, mech.n_z
        self.n = (nq, nv, nz)
        fs, ms = mech.scales.force, mech.scales.mass
        x0 = ca.MX.sym("x", nq + 3 * nv + nz)
        q0, v0, a0, ab0 = (x0[i * nv:(i + 1) * nv] for i in range(4))
        t, h, p = ca.MX.sym("t"), ca.MX.sym("h"), ca.MX.sym("p", mech.params.n)
        w = ca.MX.sym("w", nv + nz)
        a1, z1 = w[:nv], w[nv:]
        ab1 = ((1 - af) * a1 + af * a0 - am * ab0) / (1 - am)
        q1 = q0 + h * v0 + h ** 2 * ((0.5 - beta) * ab0 + beta * ab1)
        v1 = v0 + h * ((1 - gamma) * ab0 + gamma * ab1)
        r_f, r_g = F.acc_residual(q1, v1, a1, z1, t + h, p)
        gsc = ms / (beta * h ** 2 * fs) if scale_constraints else 1.0 / fs
        r = ca.vertcat(r_f / fs, r_g * gsc)
        err = ca.vertcat(r_f / fs, r_g / ca.DM(mech.scales.g_scale()))
        self.res = ca.Function("res", [w, x0, t, h, p], [r, ca.jacobian(r, w), err])
        self.state = ca.Function("state", [w, x0, h], [ca.vertcat(q1, v1, a1, ab1, z1)])

    def step(self, x0, t, h, p, max_iter: int = 50):
        """(x1, Newton iterations, converged): one step of size h from (x0, t)."""
        nq, nv, nz = self.n
        w = np.concatenate([x0[nq + nv:nq + 2 * nv], x0[nq + 3 * nv:]])
        for it in range(max_iter + 1):
            r, J, err = self.res(w, x0, t, h, p)
            e = float(np.max(np.abs(np.asarray(err))))
            if not np.isfinite(e):
                return None, it, False
            if e <= self.tol:
                return np.asarray(self.state(w, x0, h)).ravel(), it, True
            if it == max_iter:
                break
            w = w - spl.spsolve(_csc(J), np.asarray(r).ravel())
        return np.asarray(self.state(w, x0, h)).ravel(), max_iter, False

    def jacobian_cond(self, x0, t, h, p) -> tuple[float, float]:
        """Condition numbers (2-norm; raw, and equilibrated: rows and columns scaled to unit
        largest entry) of the step's Newton matrix at the start of the step."""
        nq, nv, nz = self.n
        w = np.concatenate([x0[nq + nv:nq + 2 * nv], x0[nq + 3 * nv:]])
        J = np.array(ca.DM(self.res(w, x0, t, h, p)[1]).full())
        return cond(J), cond(J, True)


def _csc(J):
    J = ca.DM(J)
    rows, cols = J.sparsity().get_triplet()
    return sp.csc_matrix((np.array(J.nonzeros()), (rows, cols)), shape=J.shape)


def initial_state(mech, q, v, p, z_guess=None) -> np.ndarray:
    """x = (q, v, a, abar, z) at (q, v), t = 0: a and z consistent with the state (the
    library's ``consistent_acceleration``; without constraints a = M^-1 f), abar = a."""
    F = functions(mech)
    nz = mech.n_z
    zg = np.zeros(nz) if z_guess is None else z_guess
    if nz:
        a, z = (np.asarray(x).ravel() for x in F.consistent_acceleration(q, v, zg, 0.0, p))
    else:
        r_f, _ = F.acc_residual(q, v, np.zeros(mech.n_v), np.zeros(0), 0.0, p)
        M = np.array(ca.DM(F.tangents(q, v, np.zeros(0), 0.0, p)[2]).full())
        a, z = np.linalg.solve(M, -np.asarray(r_f).ravel()), np.zeros(0)
    return np.concatenate([q, v, a, a, z])


def run(mech, x0, p, dt: float, duration: float, rho_inf: float, tol: float = 1e-10,
        sample=None, scale_constraints: bool = True) -> dict:
    """March from x0 over ``duration`` with steps ``dt``; ``sample(x) -> array`` (default:
    the tension per edge, :func:`tension`) at every step. Returns the samples (steps + 1,
    ...), times, Newton iterations per step, wall time per step (s: the steps only, the
    Functions built and warmed first), the step Jacobian's condition number at the start,
    and whether every step converged."""
    st = Stepper(mech, rho_inf, tol, scale_constraints)
    sample = sample or (lambda x: tension(mech, x, p))
    n = int(round(duration / dt))
    st.res(np.zeros(mech.n_v + mech.n_z), x0, 0.0, dt, p)  # build and warm
    conds = st.jacobian_cond(x0, 0.0, dt, p) if mech.n_v + mech.n_z <= 1200 else (np.nan,) * 2
    x, its, ys, ok = x0, [], [sample(x0)], True
    t0 = time.perf_counter()
    for k in range(n):
        x1, it, conv = st.step(x, k * dt, dt, p)
        its.append(it)
        if x1 is None or not conv:
            ok = False
            break
        x = x1
        ys.append(sample(x))
    wall = time.perf_counter() - t0
    return {"y": np.array(ys), "t": dt * np.arange(len(ys)), "iterations": np.array(its),
            "time_per_step": wall / max(len(its), 1), "cond": conds[0], "cond_eq": conds[1],
            "converged": ok,
            "x": x}


def run_ga1(mech, q0, v0, p, dt: float, duration: float, rho_inf: float,
            tol: float = 1e-8) -> dict:
    """The library's first-order generalized-alpha step (``galpha1_kernel``: the unrolled
    Newton of ``sc.simulate``, in the virtual machine; tolerance ``tol`` on its scaled
    residual, ``sc.simulate``'s 1e-8), which takes no constraints: the stiff rod only. The
    same outputs as :func:`run` (tension per edge at every step)."""
    kern = galpha1_kernel(mech, GeneralizedAlphaFirstOrder(rho_inf=rho_inf, tol=tol))
    F = functions(mech)
    r_f, _ = F.acc_residual(q0, v0, np.zeros(mech.n_v), np.zeros(0), 0.0, p)
    M = np.array(ca.DM(F.tangents(q0, v0, np.zeros(0), 0.0, p)[2]).full())
    a0 = np.linalg.solve(M, -np.asarray(r_f).ravel())
    x = np.concatenate([q0, v0, v0, a0])
    consts = (ca.DM([rho_inf, tol]), ca.DM(step_scales(mech)))
    nq, nv = mech.n_q, mech.n_v

    def sample(x):
        return tension(mech, np.concatenate([x[:nq + nv], a0, a0]), p)
    kern(x, 0.0, dt, p, *consts)  # build and warm
    n = int(round(duration / dt))
    its, ys, ok = [], [sample(x)], True
    t0 = time.perf_counter()
    for k in range(n):
        x1, _, _, it, failed = kern(x, k * dt, dt, p, *consts)
        its.append(float(it))
        if float(failed):
            ok = False
            break
        x = np.asarray(x1).ravel()
        ys.append(sample(x))
    wall = time.perf_counter() - t0
    return {"y": np.array(ys), "iterations": np.array(its), "converged": ok,
            "time_per_step": wall / max(len(its), 1)}


def tension(mech, x, p) -> np.ndarray:
    """Tension per edge, N: the stiff rod's EA e, the constrained rod's multiplier z."""
    F = functions(mech)
    nq, nv = mech.n_q, mech.n_v
    out = F.unpack(np.asarray(F.outputs(x[:nq], x[nq:nq + nv], x[nq + 3 * nv:], 0.0, p)).ravel())
    return np.atleast_1d(np.asarray(out["axial_force"], float).ravel())


def project(mech_c, q, v, p) -> np.ndarray:
    """v with its component along the constraint normals removed (B v = 0: the velocity
    the constrained rod admits), B of the constrained Mechanism at q."""
    F = functions(mech_c)
    B = np.array(ca.DM(F.tangents(q, v, np.zeros(mech_c.n_z), 0.0, p)[3]).full())
    return v - B.T @ np.linalg.solve(B @ B.T, B @ v)


def roughness(T: np.ndarray, peak: float) -> float:
    """Step-to-step oscillation of a tension history (steps, edges): the largest second
    difference |T_{n+1} - 2 T_n + T_{n-1}| over steps and edges, relative to ``peak``. A
    smooth history gives O(dt^2 T''); an axial mode that flips sign every step (a frozen
    high frequency at rho_inf) gives ~4 times its amplitude."""
    if T.shape[0] < 3:
        return float("nan")
    return float(np.max(np.abs(T[2:] - 2 * T[1:-1] + T[:-2]))) / peak


# ----------------------------------------------------------------------------- the pendulum

def pendulum_exact(t: np.ndarray, theta0: float, g: float, L: float):
    """The simple pendulum released at rest from theta0 (rad): angle (rad) and tension per
    unit mass times g (T / (m g)) at times t (s). sin(theta/2) = k sn(K - w t | k^2), k =
    sin(theta0/2), w = sqrt(g/L); T = m g (3 cos theta - 2 cos theta0)."""
    k = math.sin(theta0 / 2)
    K = float(ellipk(k * k))
    sn = ellipj(K - math.sqrt(g / L) * np.asarray(t, float), k * k)[0]
    th = 2 * np.arcsin(k * sn)
    return th, 3 * np.cos(th) - 2 * math.cos(theta0), 4 * K * math.sqrt(L / g)


def pendulum(dts, rhos, theta0_deg: float = 60.0, length: float = 2.0) -> list[dict]:
    """The pendulum (:func:`inext_statics.pendulum_scene`) released at rest from ``theta0_deg``
    over one period, each model at each step and rho_inf. The stiff rod starts twice: at its
    rest length (tension 0 against the exact m g cos theta0: the axial mode excited, as any
    start that ignores the stretch) and stretched to the exact tension (consistent). Rows:
    angle error (rad, max over the steps against the elliptic closed form), tension error and
    tension noise (max |T - T_exact(t)| and max |T - m g (3 cos theta - 2 cos theta0)| at
    the computed theta, after the first step, over m g; the noise also over the second half
    of the period only), Newton iterations per step, time
    per step, the step Jacobian's condition numbers, the axial frequency x dt."""
    s = pendulum_scene(length)
    rod, con, _ = pair(s)
    seg = rod_table(s)
    p0 = rod.static_p
    M = np.array(ca.DM(functions(rod).tangents(np.zeros(3), np.zeros(3), np.zeros(0), 0.0,
                                               p0)[2]).full())
    m = float(M[0, 0])
    g = float(seg["w"][0]) * length / 2 / m  # the lumped tip weight over the tip mass
    th0 = math.radians(theta0_deg)
    ea = float(seg["EA"][0])
    omega_axial = math.sqrt(ea / (m * length))
    period = pendulum_exact(np.zeros(1), th0, g, length)[2]
    u = np.array([math.sin(th0), 0.0, -math.cos(th0)])
    rows = []
    for rho in rhos:
        for dt in dts:
            for name, mech, stretch in (("stiff EA, rest length", rod, 0.0),
                                        ("stiff EA, stretched", rod, m * g * math.cos(th0) / ea),
                                        ("constrained", con, 0.0)):
                p = mech.static_p
                x0 = initial_state(mech, length * (1 + stretch) * u, np.zeros(3), p)

                def sample(x, mech=mech, p=p):
                    return np.concatenate([[math.atan2(x[0], -x[2])], tension(mech, x, p)])
                r = run(mech, x0, p, dt, period, rho, sample=sample)
                th_e, t_e, _ = pendulum_exact(r["t"], th0, g, length)
                th, T = r["y"][:, 0], r["y"][:, 1] / (m * g)
                noise = np.abs(T - 3 * np.cos(th) + 2 * math.cos(th0))
                rows.append({"case": "pendulum", "model": name, "rho_inf": rho, "dt": dt,
                             "steps": len(r["iterations"]), "converged": r["converged"],
                             "theta_err": float(np.max(np.abs(th - th_e))),
                             "T_err": float(np.max(np.abs(T - t_e)[1:])),
                             "T_noise": float(np.max(noise[1:])),
                             "T_noise_late": float(np.max(noise[len(noise) // 2:])),
                             "its_mean": float(r["iterations"].mean()),
                             "its_max": int(r["iterations"].max()),
                             "time_per_step": r["time_per_step"], "cond": r["cond"],
                             "cond_eq": r["cond_eq"],
                             "omega_axial_dt": omega_axial * dt if mech is rod else 0.0})
    return rows


def perturbed(n: int, duration: float, dts, rhos, speed: float = 0.01,
              ea_factors=(1.0,), ga1: bool = True) -> list[dict]:
    """The benchmark at ``n`` segments from its static state (each model's own), every node
    given the vertical velocity ``speed`` sin(pi s / L) m/s (projected so that the edge
    lengths do not change to first order: the same start for both models), marched over
    ``duration`` s. Rows per model, dt, rho_inf: Newton iterations per step (mean, max),
    time per step, the step Jacobian's condition numbers (and, for the constrained rod, with
    its constraint rows left unscaled), the tension history's roughness
    (:func:`roughness`), the largest tension difference from the constrained rod at the same
    dt and rho_inf (relative to the peak tension), the axial frequency sqrt(EA/m)/ds x dt.
    Newton tolerance: the library's :data:`STEP_TOL`, or for a stiff rod whose round-off
    eps EA/ds max|x| (over the force scale) comes within a tenth of it, 10 x that round-off
    (EA x 100 at 40 segments: 3.5e-9, which no step meets at 1e-10).
    ``ga1``: also each stiff rod through the library's first-order step (:func:`run_ga1`),
    which ``sc.simulate`` runs and which takes no constraints."""
    rows = []
    mechs = {}
    for fac in ea_factors:
        rod, con, ds = pair(benchmark(n, fac))
        mechs[f"stiff EA x{fac:g}"] = rod
    mechs["constrained"] = con
    seg = rod_table(benchmark(n))
    eqs = {}
    for k, mech in mechs.items():
        x = static_pair(mech if mech.n_z == 0 else rod, con)[1 if mech.n_z else 0]
        eqs[k] = (x[:mech.n_q], x[mech.n_q:])
    lay = con.layout.parts["line"]
    s, L = lay.s, lay.s[-1]
    v = np.zeros(con.n_v)
    for i in range(len(s)):
        if lay.node_v[i, 2] >= 0:
            v[lay.node_v[i, 2]] = speed * math.sin(math.pi * s[i] / L)
    v = project(con, eqs["constrained"][0], v, con.static_p)
    for rho in rhos:
        for dt in dts:
            hist = {}
            for name, mech in mechs.items():
                p, (q_s, z_s) = mech.static_p, eqs[name]
                x0 = initial_state(mech, q_s, v, p, z_s if mech.n_z else None)
                fac = ea_factors[list(mechs).index(name)] if mech.n_z == 0 else 0.0
                # the library's step tolerance 1e-10 (force rows over the force scale),
                # or 10 x the stiff rod's round-off eps EA/ds max|x| where that exceeds it
                roundoff = np.finfo(float).eps * fac * float(np.max(seg["EA"] / seg["ds"])) \
                    * float(np.max(np.abs(q_s))) / mech.scales.force
                tol = max(STEP_TOL, 10 * roundoff)
                r = run(mech, x0, p, dt, duration, rho, tol=tol)
                hist[name] = r["y"]
                w_ax = math.sqrt(fac * seg["EA"][0] / seg["mass"][0]) / seg["ds"][0]
                row = {"case": "benchmark perturbed", "segments": n, "model": name,
                       "rho_inf": rho, "dt": dt, "tol": tol, "steps": len(r["iterations"]),
                       "converged": r["converged"],
                       "its_mean": float(r["iterations"].mean()),
                       "its_max": int(r["iterations"].max()),
                       "time_per_step": r["time_per_step"], "cond": r["cond"],
                       "cond_eq": r["cond_eq"], "omega_axial_dt": w_ax * dt,
                       "roughness": roughness(r["y"], float(np.max(np.abs(r["y"]))))}
                if mech.n_z:
                    st = Stepper(mech, rho, scale_constraints=False)
                    row["cond_unscaled"] = st.jacobian_cond(x0, 0.0, dt, p)[0]
                rows.append(row)
            for name in (list(mechs)[:-1] if ga1 else []):  # sc.simulate's step, stiff rods
                mech = mechs[name]
                r = run_ga1(mech, eqs[name][0], v, mech.static_p, dt, duration, rho)
                hist[name + ", first-order GA"] = r["y"]
                rows.append({"case": "benchmark perturbed", "segments": n,
                             "model": name + ", first-order GA", "rho_inf": rho, "dt": dt,
                             "tol": 1e-8,
                             "steps": len(r["iterations"]), "converged": r["converged"],
                             "its_mean": float(r["iterations"].mean()),
                             "its_max": int(r["iterations"].max()),
                             "time_per_step": r["time_per_step"],
                             "roughness": roughness(r["y"], float(np.max(np.abs(r["y"]))))})
            ref = hist["constrained"]
            peak = float(np.max(np.abs(ref)))
            for row in rows[-len(hist):]:
                y = hist[row["model"]]
                k = min(len(y), len(ref))
                row["dT"] = float(np.max(np.abs(y[:k] - ref[:k]))) / peak
    return rows
