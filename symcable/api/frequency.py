"""The frequency domain: the linear response of a cable3d scene to its sea about the static
state (:func:`solve_frequency_domain`).

The moving nodes' displacements x about the calm sea's static state obey, per wave component
of angular frequency omega (x(t) = Re(X e^(-i omega t)), X per metre of the component's
amplitude),

    (K - i omega (C + B) - omega^2 M) X = F_waves + F_vessel,

K, C and M the exact stiffness, damping (material, seabed) and mass (structural and added)
of the scene's Mechanism at the static state (CasADi's derivatives; its drag left out), and

- B the drag linearised: on each element 0.5 rho d Cd L0 sqrt(1 + e) times E|u| twice,
  across (Cd_n) and along (Cd_t) it, u the water's velocity relative to the element's
  midpoint: stochastically for an irregular sea (u Gaussian of the standard deviation the
  response gives and the current's mean: 2 E|u| = 2 (sigma sqrt(2/pi) e^(-U^2 / 2 sigma^2) +
  U erf(U / sqrt(2) sigma))), or for a regular wave about its amplitude (|u| u as
  (8 / 3 pi) |u_hat| u), iterated until it changes by less than ``tol`` (as MoorPy's
  ``Line.dynamicSolve`` and RAFT do);
- F_waves the waves' drag B u_w and Morison inertia rho V (1 + Ca) a_w on each element, half
  on each node (the time domain's terms, :mod:`symcable.models.common.waves`, linear);
- F_vessel what the held ends' motion does to their neighbours: -K_fh X_h, the material
  damping and drag of the end element on the held end's velocity; X_h a vessel's RAOs at
  the end's point (:mod:`symcable.scene.vessel`), zero at a fixed point.

Each segment's axial force follows exactly (its derivatives with respect to the nodes,
their velocities and the held ends), and over the sea its variance sum_i |T_i|^2 a_i^2 / 2,
mean zero up-crossing period and the Rayleigh most probable maximum over ``duration``
(:mod:`symcable.analytic.extremes`).
"""
from __future__ import annotations

import math
import time
from collections import OrderedDict
from types import MappingProxyType

import casadi as ca
import numpy as np
from scipy.sparse import csc_matrix, coo_matrix
from scipy.special import erf

from ..analytic.extremes import rayleigh_mpm, zero_crossing_period
from ..errors import ConvergenceError, SymcableError
from ..models.cable3d.line import _axial_damping
from ..models.cable3d.mass import added_mass_coefficients
from ..models import formulation_of
from ..models.common.segments import segment_table
from ..results.frequency import FrequencyResponse, LineSpectrum
from ..scene import BodyEnd, Scene, load_scene
from ..scene.bodies import BodyKind, rotation_rpy
from ..scene.one_line import line_scene
from ..scene.waves import WaveComponents
from .cable3d_static import static_equilibrium

__all__ = ["solve_frequency_domain"]

#: the rows of a line block that hold its drag coefficients, in segments (line.SEGMENT_ROWS)
_CD_ROWS = (4, 6)


def solve_frequency_domain(scene, *, duration: float = 10800.0, tol: float = 1e-3,
                           max_iter: int = 100, line_waves: bool = True) -> FrequencyResponse:
    """The linear response of a cable3d scene to its sea (module docstring).

    Parameters
    ----------
    scene : Scene, str, path or dict
        A cable3d scene with ``[environment.waves]``; its lines' ends fixed or on vessels
        moved by RAOs (free points and bodies are not in the frequency domain yet).
    duration : float
        s, the time the most probable maxima are over (default three hours).
    tol : float
        The drag linearisation's relative change at which it has settled.
    max_iter : int
        Most iterations of it.
    line_waves : bool
        The waves' drag and inertia on the lines (default True); False: the lines feel only
        their ends' motion (as MoorPy's ``Line.dynamicSolve``), their drag linearised on
        their own velocity.

    Returns
    -------
    FrequencyResponse
    """
    started = time.perf_counter()
    s = scene if isinstance(scene, Scene) else load_scene(scene)
    waves = _check(s, duration, tol, max_iter, line_waves)
    mech, eq = static_equilibrium(s)
    sea = waves.components_in(s.environment.depth, s.environment.gravity)
    unit = WaveComponents(np.ones(sea.n), sea.omega, sea.k, np.zeros(sea.n), sea.direction)
    lines = _lines(s, mech, eq, unit)
    if not line_waves:
        for ln in lines:
            ln["u"], ln["a"] = np.zeros_like(ln["u"]), np.zeros_like(ln["a"])
    p = np.array(eq.p, float)
    for ln in lines:  # the drag is linearised here, not by the Mechanism's derivatives
        sl = mech.params.slice(ln["block"])
        N = ln["N"]
        p[sl.start + _CD_ROWS[0] * N:sl.start + _CD_ROWS[1] * N] = 0.0
    J = _jacobians(mech, lines)(eq.q, np.zeros(mech.n_v), 0.0, p)
    Kq, Cv, M, Fp, Tq, Tv, Tp, T0 = J
    K, C, M = (-_csc(Kq), -_csc(Cv), _csc(M))
    Fp, Tq, Tv, Tp = (_csc(a) for a in (Fp, Tq, Tv, Tp))
    T0 = np.ravel(np.asarray(T0))
    regular = waves.kind == "regular" or sea.n == 1
    rho = s.environment.water_density
    U = np.asarray(s.environment.current, float)
    n_v = mech.n_v
    X = np.zeros((sea.n, n_v), complex)
    sig_n = [np.zeros(ln["N"]) for ln in lines]
    sig_t = [np.zeros(ln["N"]) for ln in lines]
    change, it = np.inf, 0
    Fh = np.asarray((Fp @ _held_matrix(lines, sea.n, mech.params.n)).T)  # (n, n_v)
    band = _Band(K, C, M, lines, n_v)
    for it in range(1, max_iter + 1):
        rel = [_relative(ln, X, sea) for ln in lines]  # (n, N, 3) per line
        new_n, new_t = [], []
        for ln, r in zip(lines, rel):
            rn = np.einsum("eij,cej->cei", ln["Pn"], r)
            rt = r - rn
            # variance sum a^2 / 2 (or a regular wave's amplitude a)
            w2 = sea.amplitude[:, None] ** 2 * (1.0 if regular else 0.5)
            new_n.append(np.sqrt(np.sum(w2 * np.sum(np.abs(rn) ** 2, -1), 0)))
            new_t.append(np.sqrt(np.sum(w2 * np.sum(np.abs(rt) ** 2, -1), 0)))
        scale = max(max(float(np.max(a)) for a in new_n + new_t), 1e-12)
        change = max(float(np.max(np.abs(a - b))) for a, b in
                     zip(new_n + new_t, sig_n + sig_t)) / scale
        sig_n, sig_t = new_n, new_t
        D = [_drag_matrices(ln, sn, st, U, rho, regular) for ln, sn, st in zip(lines, sig_n,
                                                                              sig_t)]
        F = Fh + _element_forcing(lines, D, sea.omega, rho, n_v)
        X = band.solve(_assemble(lines, D, n_v), sea.omega, F)
        if change < tol and it > 1:
            break
    else:
        raise ConvergenceError(f"frequency domain of '{s.name}': the drag linearisation "
                               f"changed by {change:.3g} (relative) after {max_iter} "
                               f"iterations, above tol = {tol:g}",
                               diagnostics={"change": change, "iterations": max_iter})
    return _result(s, lines, sea, X, Tq, Tv, Tp, T0, duration, regular, it, change,
                   time.perf_counter() - started, mech.params.n)


def _check(s: Scene, duration, tol, max_iter, line_waves):
    """The scene's sea, after refusing what the frequency domain does not take."""
    form = formulation_of(s)
    if form.linearised or form.twists:
        raise SymcableError(f"scene {s.name!r}: the frequency domain runs 3D cables (model = "
                            f"'cable3d'), not {s.model.value!r}")
    waves = s.environment.waves
    if waves is None:
        raise SymcableError(f"scene {s.name!r} has no waves: the frequency domain needs a sea "
                            "([environment.waves])")
    if not isinstance(line_waves, bool):
        raise SymcableError(f"line_waves = {line_waves!r}: must be True or False")
    for name, value, ok in (("duration", duration, lambda v: v > 0),
                            ("tol", tol, lambda v: 0 < v < 1),
                            ("max_iter", max_iter, lambda v: int(v) == v and v >= 1)):
        if isinstance(value, bool) or not isinstance(value, (int, float)) or not \
                math.isfinite(value) or not ok(value):
            raise SymcableError(f"{name} = {value!r}: must be "
                                + {"duration": "> 0 s", "tol": "in (0, 1)",
                                   "max_iter": "an integer >= 1"}[name])
    if s.mass_matrix != "lumped":
        raise SymcableError("mass_matrix = 'consistent': the frequency domain takes the lumped "
                            "mass (its held ends' coupling is not written)")
    if s.seabed is not None and s.seabed.friction_law == "bristle":
        raise SymcableError("seabed.friction_law = 'bristle': its states are not in the "
                            "frequency domain; use 'coulomb'")
    if s.version == 2:
        free = [n for n, pt in s.points.items() if pt.is_free] + \
            [n for n, b in s.bodies.items() if b.is_free]
        if free:
            raise SymcableError(f"{free[0]!r} is free: free points and bodies are not in the "
                                "frequency domain yet (every line's ends held: fixed, or on "
                                "a vessel moved by RAOs)")
        moving = [n for n, pt in s.points.items() if pt.motion is not None] + \
            [n for n, b in s.bodies.items() if b.motion is not None and b.motion.kind != "rao"]
        if moving:
            raise SymcableError(f"{moving[0]!r} moves by a given motion: the frequency domain "
                                "takes vessels moved by the waves (motion kind = 'rao')")
    elif any(e.motion is not None for e in (s.end_a, s.end_b)):
        raise SymcableError("an end moves by a given motion: the frequency domain takes "
                            "vessels moved by the waves (a [bodies.NAME] with motion kind = "
                            "'rao')")
    if any(not e.is_fixed for e in _ends(s)):
        raise SymcableError("a free end: the frequency domain takes lines held at both ends")
    return waves


def _ends(s: Scene) -> list:
    if s.version == 1:
        return [s.end_a, s.end_b]
    return [line_scene(s, ln).end_a for ln in s.lines] + \
        [line_scene(s, ln).end_b for ln in s.lines]


def _lines(s: Scene, mech, eq, unit: WaveComponents) -> list:
    """Per line: its numbers, static shape, node indices, the waves' kinematics at its
    elements per unit amplitude and its held ends' motion per unit amplitude."""
    items = ([("line", "", s, (None, None))] if s.version == 1 else
             [(ln.name, f"{ln.name}.", line_scene(s, ln), (ln.end_a, ln.end_b))
              for ln in s.lines])
    out = []
    for name, prefix, ls, raw_ends in items:
        seg = segment_table(ls)
        N = len(seg["ds"])
        pos = np.asarray(eq.outputs[f"{prefix}positions"], float)
        strain = np.ravel(eq.outputs[f"{prefix}strain"])
        d = pos[1:] - pos[:-1]
        t = d / np.linalg.norm(d, axis=1)[:, None]
        Pn = np.eye(3)[None] - t[:, :, None] * t[:, None, :]
        can, cat = added_mass_coefficients(ls)
        mid = 0.5 * (pos[1:] + pos[:-1])
        u, a = _kinematics(unit, mid, s.environment.depth)
        held = {}
        for key, node, end in (("a", 0, raw_ends[0]), ("b", N, raw_ends[1])):
            layout = mech.layout.parts[name]
            if layout.node_v[node, 0] >= 0:
                continue
            held[node] = dict(slice=mech.params.slice(f"{prefix}end_{key}.position"),
                              X=_vessel_motion(s, end, unit))
        out.append(dict(name=name, prefix=prefix, N=N, seg=seg, t=t, Pn=Pn, pos=pos,
                        node_v=mech.layout.parts[name].node_v, can=can, cat=cat,
                        BA=_axial_damping(ls, seg), stretch=np.sqrt(1.0 + strain),
                        u=u, a=a, held=held, block=f"{prefix}line", s=np.asarray(seg["s"])))
    return out


def _kinematics(c: WaveComponents, X, depth):
    """Per unit amplitude: the fluid velocity and acceleration (n, m, 3) complex at points
    ``X`` (m, 3) (linear theory, kinematics at z <= 0 held above)."""
    th = c.k[:, None] * (X[None, :, 0] * np.cos(c.direction)[:, None]
                         + X[None, :, 1] * np.sin(c.direction)[:, None])
    E = np.exp(1j * th)
    z = np.minimum(X[None, :, 2], 0.0)
    k = c.k[:, None]
    if depth is None:
        Ch = Sh = np.exp(k * z)
    else:
        e1, e2 = np.exp(k * z), np.exp(-k * (z + 2.0 * depth))
        den = 1.0 - np.exp(-2.0 * k * depth)
        Ch, Sh = (e1 + e2) / den, (e1 - e2) / den
    w = c.omega[:, None]
    u = np.stack([w * Ch * np.cos(c.direction)[:, None] * E,
                  w * Ch * np.sin(c.direction)[:, None] * E, -1j * w * Sh * E], axis=-1)
    return u, -1j * c.omega[:, None, None] * u


def _vessel_motion(s: Scene, end, unit: WaveComponents) -> np.ndarray:
    """(n, 3) complex: a held end's displacement per unit wave amplitude (zero unless on a
    vessel moved by RAOs; its rotation linearised about the mean pose)."""
    X = np.zeros((unit.n, 3), complex)
    if not isinstance(end, BodyEnd):
        return X
    body = s.bodies[end.body]
    if body.kind is not BodyKind.VESSEL:
        return X
    amp, ph = body.motion.response(unit, body.position)
    z = amp * np.exp(1j * ph)  # (n, 6): m, deg
    off = np.asarray(end.offset, float)
    h = 1e-6
    for j in range(3):
        da = np.zeros(3)
        da[j] = h
        o = np.asarray(body.orientation_deg, float)
        dR = (rotation_rpy(o + da) - rotation_rpy(o - da)) @ off / (2.0 * h)  # m per deg
        X += z[:, 3 + j, None] * dR[None, :]
    return X + z[:, :3]


#: the derivatives' Functions of the most recent structures: {id: (expressions' owner, Function)}
_FUNCTIONS: "OrderedDict[int, tuple]" = OrderedDict()
_KEPT = 8


def _jacobians(mech, lines):
    """The Function (q, v, t, p) -> df/dq, df/dv, M, df/dp, dT/dq, dT/dv, dT/dp, T, T every
    line's segment axial forces; built once per structure (a scene rebound to a template's
    expressions shares its Function)."""
    owner = mech.functions_of or mech
    hit = _FUNCTIONS.get(id(owner))
    if hit is not None and hit[0] is owner:
        _FUNCTIONS.move_to_end(id(owner))
        return hit[1]
    T = ca.vertcat(*[mech.outputs[f"{ln['prefix']}axial_force"].expr for ln in lines])
    f = mech.force
    fn = ca.Function("frequency_domain", [mech.q, mech.v, mech.t, mech.p],
                     [ca.jacobian(f, mech.q), ca.jacobian(f, mech.v), mech.mass,
                      ca.jacobian(f, mech.p), ca.jacobian(T, mech.q), ca.jacobian(T, mech.v),
                      ca.jacobian(T, mech.p), T])
    _FUNCTIONS[id(owner)] = (owner, fn)
    if len(_FUNCTIONS) > _KEPT:
        _FUNCTIONS.popitem(last=False)
    return fn


def _csc(dm) -> csc_matrix:
    dm = ca.DM(dm)
    return csc_matrix((np.array(dm.nonzeros()), np.array(dm.row()), np.array(dm.colind())),
                      shape=dm.shape)


def _relative(ln: dict, X: np.ndarray, sea) -> np.ndarray:
    """(n, N, 3) complex: the water's velocity relative to each element's midpoint."""
    V = _node_velocities(ln, X, sea)
    return ln["u"] - 0.5 * (V[:, 1:] + V[:, :-1])


def _node_velocities(ln: dict, X: np.ndarray, sea) -> np.ndarray:
    """(n, N+1, 3) complex: every node's velocity, held ends' included."""
    idx = ln["node_v"]
    n = X.shape[0]
    disp = np.zeros((n, ln["N"] + 1, 3), complex)
    free = idx[:, 0] >= 0
    disp[:, free] = X[:, idx[free]]
    for node, h in ln["held"].items():
        disp[:, node] = h["X"]
    return -1j * sea.omega[:, None, None] * disp


def _drag_matrices(ln, sig_n, sig_t, U, rho, regular) -> np.ndarray:
    """(N, 3, 3) each element's linearised drag B_n P_n + B_t t t^T, N s/m."""
    seg = ln["seg"]
    base = 0.5 * rho * seg["d"] * seg["ds"] * ln["stretch"]
    Un = np.linalg.norm(np.einsum("eij,j->ei", ln["Pn"], U), axis=1)
    Ut = np.abs(ln["t"] @ U)

    def twice_mean_speed(sig, mean):
        if regular:
            return (8.0 / (3.0 * math.pi)) * np.sqrt(sig ** 2 + mean ** 2)
        s = np.maximum(sig, 1e-12)
        return 2.0 * (s * math.sqrt(2.0 / math.pi) * np.exp(-mean ** 2 / (2.0 * s * s))
                      + mean * erf(mean / (math.sqrt(2.0) * s)))
    Bn = base * seg["cdn"] * twice_mean_speed(sig_n, Un)
    Bt = base * seg["cdt"] * twice_mean_speed(sig_t, Ut)
    tt = ln["t"][:, :, None] * ln["t"][:, None, :]
    return Bn[:, None, None] * ln["Pn"] + Bt[:, None, None] * tt


def _assemble(lines, D, n_v) -> csc_matrix:
    """The linearised drag's damping over the moving nodes: a quarter of each element's on
    each pair of its nodes."""
    rows, cols, vals = [], [], []
    for ln, De in zip(lines, D):
        idx = ln["node_v"]
        for a_off in (0, 1):
            for b_off in (0, 1):
                ia, ib = idx[a_off:ln["N"] + a_off], idx[b_off:ln["N"] + b_off]
                ok = (ia[:, 0] >= 0) & (ib[:, 0] >= 0)
                r = np.repeat(ia[ok][:, :, None], 3, axis=2)
                c = np.repeat(ib[ok][:, None, :], 3, axis=1)
                rows.append(r.ravel())
                cols.append(c.ravel())
                vals.append(0.25 * De[ok].ravel())
    return coo_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))),
                      shape=(n_v, n_v)).tocsc()


def _held_matrix(lines, n, n_p) -> np.ndarray:
    """(n_p, n) complex: the held ends' displacements of each component in their position
    parameters' places."""
    out = np.zeros((n_p, n), complex)
    for ln in lines:
        for h in ln["held"].values():
            out[h["slice"]] = h["X"].T
    return out


class _Band:
    """K - i omega C - omega^2 M solved as a banded matrix (the lines' nodes are numbered
    along them, and with every end held the lines do not couple): the band's storage of K,
    C and M once, of the drag's damping per iteration."""

    def __init__(self, K, C, M, lines, n_v):
        pattern = (abs(K) + abs(C) + abs(M) + abs(_assemble(
            lines, [np.ones((ln["N"], 3, 3)) for ln in lines], n_v))).tocoo()
        self.n = n_v
        self.bw = int(np.max(np.abs(pattern.row - pattern.col))) if pattern.nnz else 0
        self.K, self.C, self.M = (self._band(X) for X in (K, C, M))

    def _band(self, X) -> np.ndarray:
        X = X.tocoo()
        ab = np.zeros((2 * self.bw + 1, self.n))
        np.add.at(ab, (self.bw + X.row - X.col, X.col), X.data)
        return ab

    def solve(self, Cd, omega, F) -> np.ndarray:
        """(n, n_v) complex: the response to each component's force ``F`` (n, n_v)."""
        from scipy.linalg import solve_banded
        Cb = self.C + self._band(Cd)
        X = np.empty_like(F)
        for i, w in enumerate(omega):
            X[i] = solve_banded((self.bw, self.bw), self.K - 1j * w * Cb - w * w * self.M,
                                F[i], check_finite=False)
        return X


def _element_forcing(lines, D, omega, rho, n_v) -> np.ndarray:
    """(n, n_v) complex: the waves' drag and inertia on the elements and the end elements'
    drag and material damping on the held ends' velocity, on the moving nodes, per
    component."""
    F = np.zeros((omega.size, n_v), complex)
    for ln, De in zip(lines, D):
        seg, idx, N = ln["seg"], ln["node_v"], ln["N"]
        vol = rho * math.pi / 4.0 * seg["d"] ** 2 * seg["ds"]
        tt = ln["t"][:, :, None] * ln["t"][:, None, :]
        inertia = vol[:, None, None] * ((1.0 + ln["can"])[:, None, None] * ln["Pn"]
                                        + (1.0 + ln["cat"])[:, None, None] * tt)
        f = 0.5 * (np.einsum("eij,cej->cei", De, ln["u"])
                   + np.einsum("eij,cej->cei", inertia, ln["a"]))  # (n, N, 3) on each node
        for node, h in ln["held"].items():
            e = 0 if node == 0 else N - 1  # the end element, its other node
            other = 1 if node == 0 else N - 1
            Vh = -1j * omega[:, None] * h["X"]  # (n, 3)
            k = ln["BA"][e] / seg["ds"][e]
            push = Vh @ (-0.25 * De[e] + k * tt[e]).T
            if idx[other, 0] >= 0:
                F[:, idx[other]] += push
        for off in (0, 1):
            nodes = idx[off:N + off]
            ok = nodes[:, 0] >= 0
            F[:, nodes[ok].ravel()] += f[:, ok].reshape(omega.size, -1)
    return F


def _result(s, lines, sea, X, Tq, Tv, Tp, T0, duration, regular, iterations, change,
            wall, n_p) -> FrequencyResponse:
    """The axial forces' response and statistics."""
    n = sea.n
    H = _held_matrix(lines, n, n_p)
    T = np.zeros((n, T0.size), complex)
    for i in range(n):
        w = sea.omega[i]
        T[i] = Tq @ X[i] + Tv @ (-1j * w * X[i]) + Tp @ H[:, i]
    # the held ends' velocity in the end segments' material damping
    start = 0
    for ln in lines:
        seg = ln["seg"]
        for node, h in ln["held"].items():
            e = 0 if node == 0 else ln["N"] - 1
            sign = -1.0 if node == 0 else 1.0
            T[:, start + e] += sign * ln["BA"][e] / seg["ds"][e] * (
                (-1j * sea.omega[:, None] * h["X"]) @ ln["t"][e])
        start += ln["N"]
    weight = (sea.amplitude ** 2) * (1.0 if regular else 0.5)
    out, start = {}, 0
    for ln in lines:
        sl = slice(start, start + ln["N"])
        start += ln["N"]
        m0 = (np.abs(T[:, sl]) ** 2 * weight[:, None]).sum(0)
        m2 = (np.abs(T[:, sl]) ** 2 * (weight * sea.omega ** 2)[:, None]).sum(0)
        std = np.sqrt(m0)
        if regular:  # one harmonic: its amplitude, at the component's period
            tz, top = np.full(ln["N"], 2 * math.pi / sea.omega[0]), std
            std = std / math.sqrt(2.0)
        else:
            tz, top = zero_crossing_period(m0, m2), rayleigh_mpm(m0, m2, duration)
        out[ln["name"]] = LineSpectrum(ln["s"], T0[sl], T[:, sl], std, tz, T0[sl] + top)
    return FrequencyResponse(
        s.name, np.asarray(sea.omega), np.asarray(sea.amplitude), MappingProxyType(out),
        float(duration), "converged",
        {"iterations": iterations, "change": change, "components": n, "wall_time": wall,
         "linearisation": "harmonic" if regular else "stochastic"})
