"""The study's reference for lines with bending (EI > 0): the planar extensible elastica as a
boundary-value problem, solved by scipy's ``solve_bvp`` (collocation with mesh refinement).
One section; weight, drag of a steady current, pinned, clamped and free ends; no seabed.

State along the unstretched arc length s: y = (x, z, phi, M, Nx, Nz), with N the internal
force (the part beyond s on the part before), M the moment, t = (cos phi, sin phi),
n = (-sin phi, cos phi), axial force T = N.t, shear Q = N.n, strain T / EA:

    x' = (1 + T/EA) cos phi,  z' = (1 + T/EA) sin phi,  phi' = M / EI,
    M' = -(1 + T/EA) Q,       N' = -f   (f: weight (0, -w) and drag, per unstretched length).

Boundary conditions, three at each end: a pinned end fixes x, z and M = 0; a clamped end x, z
and phi; a free end N (= the applied force at B, minus it at A) and M = 0.

Starts: the cable reference's profile and forces (a tension-dominated line); for a
cantilever the straight unloaded line, then load continuation (0.1, 0.3, 0.6, 1 of the load,
each from the last); for a weightless rod whose ends are closer than its length the first
Euler mode with the amplitude its length needs. A buckled or looped rod has a mirror twin
(about its chord) when the scene is mirror-symmetric; the comparison takes the nearer.
"""
from __future__ import annotations

import math

import numpy as np
from scipy.integrate import solve_bvp

from fuzz_catenary import N_PROFILE, NoReference

TOL = 1e-6
MAX_NODES = 20_000
CONTINUATION = (0.1, 0.3, 0.6, 1.0)
LAMBDA_MIN = 1e-3          # bending length over L below which the BVP is not attempted


class Rod:
    def __init__(self, sec: dict, rho: float, current, ends: dict):
        self.sec, self.rho = sec, rho
        self.U = np.asarray(current, float) if rho > 0 else np.zeros(2)
        self.L, self.EA, self.EI = sec["length"], sec["EA"], sec["EI"]
        self.ends = ends
        self.load_factor = 1.0

    def fun(self, _s, y):
        x, z, phi, M, Nx, Nz = y
        c, s = np.cos(phi), np.sin(phi)
        T = Nx * c + Nz * s
        Q = -Nx * s + Nz * c
        st = 1.0 + T / self.EA
        fx = np.zeros_like(phi)
        fz = np.full_like(phi, -self.sec["w"])
        if np.any(self.U != 0.0):
            ut = self.U[0] * c + self.U[1] * s
            un = -self.U[0] * s + self.U[1] * c
            k = 0.5 * self.rho * self.sec["d"] * np.sqrt(np.maximum(st, 0.0))
            ft, fn = k * self.sec["cdt"] * np.abs(ut) * ut, k * self.sec["cdn"] * np.abs(un) * un
            fx, fz = fx + ft * c - fn * s, fz + ft * s + fn * c
        lf = self.load_factor
        return np.vstack([st * c, st * s, M / self.EI, -st * Q, -lf * fx, -lf * fz])

    def bc(self, ya, yb):
        out = []
        for y, name, sign in ((ya, "A", -1.0), (yb, "B", 1.0)):
            e = self.ends[name]
            if e["cond"] == "free":
                F = sign * self.load_factor * np.asarray(e["force"], float)
                out += [y[4] - F[0], y[5] - F[1], y[3]]
            else:
                out += [y[0] - e["pos"][0], y[1] - e["pos"][1]]
                out.append(y[2] - math.radians(e["angle_deg"]) if e["cond"] == "clamped" else y[3])
        return np.array(out)


def _guess_from_cable(rod: Rod, cable: dict):
    prof, s = np.asarray(cable["profile"]), np.asarray(cable["s"])
    keep = np.concatenate([[True], np.diff(s) > 1e-12 * rod.L])
    prof, s = prof[keep], s[keep]
    d = np.gradient(prof, s, axis=0)
    phi = np.unwrap(np.arctan2(d[:, 1], d[:, 0]))
    M = rod.EI * np.gradient(phi, s)
    H, Va = cable["F_A"]
    Nz = Va + rod.sec["w"] * s
    y = np.vstack([prof[:, 0], prof[:, 1], phi, M, np.full_like(s, H), Nz])
    return s, y


def _guess_straight(rod: Rod, n: int = 401):
    """The unloaded straight cantilever from its clamped end (forces of the rigid line)."""
    s = np.linspace(0.0, rod.L, n)
    fixed = "A" if rod.ends["A"]["cond"] != "free" else "B"
    e = rod.ends[fixed]
    phi0 = math.radians(e["angle_deg"])
    t = np.array([math.cos(phi0), math.sin(phi0)])
    pos = np.asarray(e["pos"]) + np.outer(s - (0.0 if fixed == "A" else rod.L), t)
    y = np.zeros((6, n))
    y[0], y[1], y[2] = pos[:, 0], pos[:, 1], phi0
    return s, y


def _guess_euler(rod: Rod, n: int = 401):
    """First Euler mode between two held ends closer than the length (inextensible)."""
    pa, pb = np.asarray(rod.ends["A"]["pos"]), np.asarray(rod.ends["B"]["pos"])
    d = float(np.hypot(*(pb - pa)))
    s = np.linspace(0.0, rod.L, n)
    u = (pb - pa) / max(d, 1e-300)
    nrm = np.array([-u[1], u[0]])
    a = 2.0 * d / math.pi * math.sqrt(max(rod.L / max(d, 1e-300) - 1.0, 0.0))
    pos = pa + np.outer(s / rod.L * d, u) + np.outer(a * np.sin(math.pi * s / rod.L), nrm)
    g = np.gradient(pos, s, axis=0)
    phi = np.unwrap(np.arctan2(g[:, 1], g[:, 0]))
    P = math.pi ** 2 * rod.EI / rod.L ** 2
    y = np.vstack([pos[:, 0], pos[:, 1], phi, rod.EI * np.gradient(phi, s),
                   np.full(n, -P * u[0]), np.full(n, -P * u[1])])
    return s, y


def _solve(rod: Rod, s, y):
    sol = solve_bvp(rod.fun, rod.bc, s, y, tol=TOL, max_nodes=MAX_NODES, bc_tol=TOL * rod.L)
    if sol.status != 0:
        raise NoReference(f"solve_bvp did not converge: {sol.message}")
    return sol


def elastica(info, cable: dict | None) -> dict:
    """Reference of a single-section line with bending (``info``: fuzz_refs.Info; ``cable``:
    the same line without bending, as a start, or None)."""
    if len(info.secs) != 1:
        raise NoReference("bending reference covers one section")
    rod = Rod(info.secs[0], info.rho, info.current, info.ends)
    t_scale = max(info.force_scale, cable["T_A"], cable["T_B"]) if cable and "T_A" in cable \
        else info.force_scale
    lam = math.sqrt(rod.EI / max(t_scale, 1e-300)) / rod.L
    if lam < LAMBDA_MIN:
        raise NoReference(f"bending length sqrt(EI/T) = {lam:.2g} L: boundary layer too thin "
                          f"for the BVP (below {LAMBDA_MIN:g} L)")
    sol = None
    if cable is not None and "T_A" in cable and (not info.free or lam < 0.1):
        try:
            sol = _solve(rod, *_guess_from_cable(rod, cable))
        except NoReference:
            if not info.free:
                raise
    if sol is None and info.free:
        s, y = _guess_straight(rod)
        for lf in CONTINUATION:
            rod.load_factor = lf
            sol = _solve(rod, s, y)
            s, y = sol.x, sol.y
    elif sol is None:
        sol = _solve(rod, *_guess_euler(rod))
    grid = np.linspace(0.0, rod.L, N_PROFILE)
    y = sol.sol(grid)
    if info.depth is not None and y[1].min() < -info.depth - 1e-9 * info.L:
        raise NoReference("the rod touches the seabed")
    NA, NB = y[4:, 0], y[4:, -1]
    return {"F_A": [float(NA[0]), float(NA[1])], "F_B": [-float(NB[0]), -float(NB[1])],
            "T_A": float(np.hypot(*NA)), "T_B": float(np.hypot(*NB)), "grounded": 0.0,
            "pile": False, "regime": "elastica", "profile": y[:2].T, "s": grid,
            "mirror": _mirror_axis(info), "min_axial_N": float(np.min(
                y[4] * np.cos(y[2]) + y[5] * np.sin(y[2])))}


def _mirror_axis(info):
    """(point, direction) of the chord when the scene is symmetric under reflection about it
    (no weight or a vertical chord, no current, pinned ends, no end force), else None."""
    if info.free or info.drag or any(e["cond"] == "clamped" for e in info.ends.values()):
        return None
    pa, pb = np.asarray(info.ends["A"]["pos"]), np.asarray(info.ends["B"]["pos"])
    u = pb - pa
    if info.W > 0 and abs(u[0]) > 1e-12 * info.L:
        return None
    return [pa.tolist(), (u / max(np.hypot(*u), 1e-300)).tolist()]


def reflect(points, axis):
    """Points reflected about the line through axis[0] along axis[1]."""
    p0, u = np.asarray(axis[0]), np.asarray(axis[1])
    d = np.asarray(points) - p0
    along = (d @ u)[:, None] * u
    return p0 + 2.0 * along - d
