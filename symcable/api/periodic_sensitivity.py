"""Exact design sensitivities of a periodic steady state: a statistic over one period (its
range, largest, smallest or mean value) of a tension or another scalar output, against
numbers of the scene.

The periodic state is the harmonic balance's: Fourier coefficients w of the coordinates
that solve r(w; P) = 0 (:mod:`symcable.solvers.hbalance_mech`), P = (T, p), T the period
(s) and p the Mechanism's parameters. As for the static state
(:mod:`symcable.api.sensitivity`), by the implicit function theorem on the same equations

    dw/dtheta = -r_w^-1 r_P dP/dtheta,

r_w and r_P CasADi's exact derivatives, and dP/dtheta the slopes of the scene's arithmetic
(:func:`~symcable.api.design_slopes.parameter_slope`, here of the parameters a periodic
solve runs with). A scalar y(t) = y(q(t), v(t), z(t), t; p) along the period (a line's end
tension, the magnitude of its end force) then moves by

    dy(t)/dtheta = y_w dw/dtheta + y_P dP/dtheta

at each time, exact for the Fourier series, which is the harmonic balance's answer at
every t. Its largest value over the period is found on a grid of 16 samples per balanced
time sample and refined by a bounded scalar search on the series itself (to 1e-10 of the
period); where it is unique and smooth, its derivative is dy/dtheta there (the time of
the peak moves, but y'(t*) = 0 makes that move first-order silent: the envelope theorem).
The range is the largest less the smallest value; the mean is over the grid (exact for the
series' own harmonics, to round-off on the fine grid for a magnitude of them).
"""
from __future__ import annotations

import math
import time

import casadi as ca
import numpy as np
from scipy.optimize import minimize_scalar
from scipy.sparse.linalg import splu

from ..errors import SymcableError
from ..linalg.sparse import to_csc
from ..mechanism.functions import functions
from ..results.sensitivity import Sensitivity
from ..scene import load_scene
from ..solvers.hbalance_mech import _d1, default_samples, hb_system
from ..solvers.periodic_common import spectral_derivative, start_from_samples
from .cable3d import _period
from .cable3d_periodic import periodic_p, solve_periodic_3d_state
from .design_slopes import COMPILED_IN, breaking_loads, outputs_differ, parameter_slope
from .output_names import NO_MAGNITUDE, lines_of, requested_outputs
from .scene3d import dynamics_mechanism, scene_mechanism

__all__ = ["STATISTICS", "periodic_sensitivity", "split_statistic"]

#: statistics over one period of a scalar output: ``NAME.STATISTIC``
STATISTICS = ("range", "max", "min", "mean")
#: grid samples per balanced time sample on which the extremes are found (then refined)
GRID = 16
#: the periodic solve's harmonics by default (the method's own default)
HARMONICS = 10
#: the harmonic balance's tolerance (its residual's max-norm, scaled by the force scale)
#: and Newton steps from shooting's state
HB_TOL, HB_ITERATIONS = 1e-9, 30


def split_statistic(name: str) -> tuple[str, str] | None:
    """``(output, statistic)`` of a periodic output name ``"OUTPUT.STATISTIC"``, or None."""
    base, _, last = name.rpartition(".")
    return (base, last) if base and last in STATISTICS else None


def _series(mech, hbs, H: int, outs, sl) -> ca.Function:
    """``y(w, P, t) -> (n_out,)``: each requested scalar output at time t of the Fourier
    series with coefficients w (scaled, as the harmonic balance packs them), P = (T, p)."""
    nq, nz, nc = mech.n_q, mech.n_z, 2 * H + 1
    w = ca.MX.sym("w", hbs.square.n)
    P = ca.MX.sym("P", 1 + mech.params.n)
    t = ca.MX.sym("t")
    T, p = P[0], P[1:]
    om = 2 * math.pi / T
    tau = t / T
    b = ca.vertcat(1, *[f(2 * math.pi * h * tau) for h in range(1, H + 1)
                        for f in (ca.cos, ca.sin)])
    Qc = ca.diag(ca.DM(hbs.sc.q)) @ ca.reshape(w[:nq * nc], nq, nc)
    Zc = ca.diag(ca.DM(hbs.sc.z)) @ ca.reshape(w[nq * nc:], nz, nc) if nz else ca.MX(0, nc)
    D = ca.DM(_d1(H).T)
    q, v, z = Qc @ b, om * (Qc @ D) @ b, Zc @ b
    y = functions(mech).outputs(q, v, z, t, p)
    rows = []
    for _, source, how, entry in outs:
        block = y[sl[source]]
        if entry is not None:
            rows.append(block[entry])
        elif how == "up":
            rows.append(block[2])
        elif how == "horizontal":
            rows.append(ca.norm_2(block[:2]))
        elif how is None:  # a scalar output (requested_outputs' check in the caller)
            rows.append(block[0])
        else:  # "norm", "ratio" (its breaking load applied outside)
            rows.append(ca.norm_2(block))
    return ca.Function("periodic_series", [w, P, t], [ca.vertcat(*rows)])


def _extreme(f, k: int, grid: np.ndarray, T: float, sign: float) -> float:
    """The time of the largest (``sign`` 1) or smallest (-1) value of the scalar series
    ``f(t)`` near grid sample k, refined between its neighbours."""
    dt = T / grid.size
    res = minimize_scalar(lambda s: -sign * f(s), bounds=(grid[k] - dt, grid[k] + dt),
                          method="bounded", options={"xatol": 1e-10 * T})
    return float(res.x) if -sign * res.fun <= -sign * f(grid[k]) else float(grid[k])


def _checked(s0, outputs, harmonics) -> list:
    """``[(output, statistic)]`` of the requested names, after the scene's checks."""
    if s0.dim != 3:
        raise SymcableError(f"scene {s0.name!r}: periodic sensitivities are of 3D scenes "
                            f"(model = 'cable3d'), not model = {s0.model.value!r}")
    if s0.environment.waves is not None:
        raise SymcableError(f"scene {s0.name!r}: periodic sensitivities in waves are not "
                            "built yet (the sea's numbers are not in the static slopes); a "
                            "vessel's or fairlead's harmonic motion is taken")
    if not (isinstance(harmonics, int) and not isinstance(harmonics, bool) and harmonics >= 1):
        raise SymcableError(f"harmonics = {harmonics!r}: must be a whole number >= 1")
    wanted = []
    for name in outputs:
        split = split_statistic(name)
        if split is None:
            raise SymcableError(f"output {name!r}: a periodic output is OUTPUT.STATISTIC, "
                                f"STATISTIC one of {', '.join(STATISTICS)} "
                                "('line0.fairlead_tension.range')")
        wanted.append(split)
    return wanted


def _balanced(s0, mech, per, H: int):
    """``(hbs, w, P, residual)``: the harmonic balance of ``mech`` with H harmonics solved
    by Newton from the periodic state ``per`` (its Fourier coefficients, scaled)."""
    T = float(per.period)
    hbs = hb_system(mech, H, default_samples(H))
    P = np.concatenate([[T], np.asarray(per.p, float)])
    w = hbs.coefficients_of(start_from_samples(per.q, per.v, per.z, T), T)
    sol = hbs.square.solve(w, P, solver="newton", tol=HB_TOL, max_iter=HB_ITERATIONS)
    if not sol["residual"] <= HB_TOL:
        raise SymcableError(
            f"scene {s0.name!r}: the harmonic balance with {H} harmonics found no periodic "
            f"state from shooting's (residual {sol['residual']:.3g} after {HB_ITERATIONS} "
            f"Newton steps; {sol['return_status']}): more harmonics (harmonics=...) resolve a "
            "sharper response")
    return hbs, np.asarray(sol["w"], float).ravel(), P, float(sol["residual"])


def _in_motion(per, samples: int = 4):
    """``differs(m, mech, p)`` for :func:`~symcable.api.design_slopes.parameter_slope`:
    whether two Mechanisms' equations of motion (M a - f, g) or outputs differ at a few
    times of the periodic state ``per`` (a number compiled into the drag, the added mass,
    the seabed's damping or a motion, which the static checks at rest do not see)."""
    a = spectral_derivative(np.asarray(per.v, float), float(per.period))
    ks = np.linspace(0, len(per.time), samples, endpoint=False).astype(int)

    def differs(m, mech, p) -> bool:
        if m is mech or (m.functions_of or m) is (mech.functions_of or mech):
            return False
        Fm, F0 = functions(m), functions(mech)
        for k in ks:
            args = (per.q[k], per.v[k], a[k], per.z[k], per.time[k], p)
            for x, y in zip(Fm.acc_residual(*args), F0.acc_residual(*args)):
                if np.max(np.abs(np.asarray(x, float) - np.asarray(y, float)),
                          initial=0.0) > COMPILED_IN * float(mech.scales.force):
                    return True
            if outputs_differ(m, mech, np.concatenate([per.q[k], per.z[k]]), p,
                              v=per.v[k], t=per.time[k]):
                return True
        return False
    return differs


def _slopes(base, mech, per, names, values, raw_at, step) -> tuple:
    """``(dP (1 + n_p + aux, n_par), steps)``: the period's slope (zero: a number that
    moves the motion's period is refused, the period being compiled into the motion) and
    the periodic solve's parameters' slopes through the scene's arithmetic, then the
    breaking loads' (aux)."""
    x0 = np.concatenate([per.q[0], per.z[0]])
    differs = _in_motion(per)
    slopes, steps = [], []
    for name, value, at in zip(names, values, raw_at):
        dp, h = parameter_slope(at, base, mech, x0, name, float(value), step, None,
                                p_of=periodic_p, differs=differs)
        if _period(load_scene(at(float(value) + h), base=base)) != float(per.period):
            raise SymcableError(f"parameter {name!r}: it moves the motion's period, which is "
                                "compiled into the equations, so it has no exact derivative "
                                "yet")
        slopes.append(np.concatenate([[0.0], dp]))
        steps.append(h)
    return np.column_stack(slopes), steps


def _coefficient_slopes(s0, hbs, w, P, dPp) -> np.ndarray:
    """dw/dtheta (n_w, n_par) = -r_w^-1 r_P dP/dtheta at the balance's solution w."""
    cache = hbs.__dict__.setdefault("_sensitivity", {})
    if "jac" not in cache:
        W, PP, dPs = ca.MX.sym("w", hbs.square.n), ca.MX.sym("P", P.size), \
            ca.MX.sym("dP", P.size)
        r = hbs.square.residual(W, PP)
        cache["jac"] = ca.Function("hb_jacobian", [W, PP], [ca.jacobian(r, W)])
        cache["slope"] = ca.Function("hb_slope", [W, PP, dPs], [ca.jtimes(r, PP, dPs)])
    try:
        lu = splu(to_csc(cache["jac"](w, P)))
    except RuntimeError:
        raise SymcableError(f"scene {s0.name!r}: the harmonic balance's Jacobian is singular "
                            "at its solution (a neutral mode): no unique derivative") from None
    Rp = np.column_stack([np.asarray(cache["slope"](w, P, dPp[:, j]), float).ravel()
                          for j in range(dPp.shape[1])])
    return -lu.solve(Rp)


def _series_functions(mech, hbs, H: int, outs) -> tuple:
    """``(f, df)``: the requested scalars along the period, f(w, P, t), and their
    directional derivative df(w, P, t, dw, dP); built once per balance and outputs."""
    cache = hbs.__dict__.setdefault("_sensitivity", {})
    key = ("series", tuple(o[1:] for o in outs))
    if key not in cache:
        f = _series(mech, hbs, H, outs, functions(mech).output_slices())
        W, PP, t = (ca.MX.sym(n, f.size1_in(i)) for i, n in enumerate(("w", "P", "t")))
        Wd, Pd = ca.MX.sym("dw", f.size1_in(0)), ca.MX.sym("dP", f.size1_in(1))
        cache[key] = (f, ca.Function("periodic_series_slope", [W, PP, t, Wd, Pd],
                                     [ca.jtimes(f(W, PP, t), ca.vertcat(W, PP),
                                                ca.vertcat(Wd, Pd))]))
    return cache[key]


def _statistic(i: int, stat: str, f, df, w, P, dw, dPp, grid, Y) -> tuple:
    """``(value, row (n_par,))`` of statistic ``stat`` of scalar i over the period."""
    T = float(P[0])
    times = {}
    for s, label in ((1.0, "max"), (-1.0, "min")):
        if stat in (label, "range"):
            times[label] = _extreme(lambda t: float(f(w, P, t)[i]), int(np.argmax(s * Y[i])),
                                    grid, T, s)
    d_at = {lab: np.array([float(df(w, P, t, dw[:, j], dPp[:, j])[i])
                           for j in range(dw.shape[1])]) for lab, t in times.items()}
    at = {lab: float(f(w, P, t)[i]) for lab, t in times.items()}
    if stat == "range":
        return at["max"] - at["min"], d_at["max"] - d_at["min"]
    if stat == "mean":
        dmap = df.map(grid.size)
        return float(np.mean(Y[i])), np.array([
            np.mean(np.asarray(dmap(w, P, grid.reshape(1, -1), dw[:, j], dPp[:, j]),
                               float)[i]) for j in range(dw.shape[1])])
    return at[stat], d_at[stat]


def periodic_sensitivity(raw: dict, base, outputs, names, values, raw_at, step,
                         harmonics: int = HARMONICS) -> Sensitivity:
    """:func:`symcable.sensitivity` of periodic statistics (``"LINE.fairlead_tension.range"``;
    module docstring): the scene's periodic state by shooting, its harmonic balance with
    ``harmonics`` harmonics solved from it; each parameter j given by its name, value and
    ``raw_at[j](v)`` (the scene's dict with it at v)."""
    started = time.perf_counter()
    s0 = load_scene(raw, base=base)
    wanted = _checked(s0, outputs, harmonics)
    mech = dynamics_mechanism(s0, scene_mechanism(s0))
    if mech.kinematics is not None:
        raise SymcableError(f"scene {s0.name!r}: periodic sensitivities need a Mechanism "
                            "without first-order states (a free body's quaternion, a "
                            "seabed.friction_law = 'bristle' add them): not built yet")
    outs = requested_outputs(mech, [o for o, _ in wanted])
    for (name, source, how, entry), (_, stat) in zip(outs, wanted):
        if how == "ground":
            raise SymcableError(f"output {name}.{stat!r}: the grounded length is a static "
                                "balance; over a period, ask for the anchor's uplift")
        if how is None and entry is None and int(mech.outputs[source].expr.numel()) != 1:
            raise SymcableError(f"output {name}.{stat!r}: {name!r} has "
                                f"{int(mech.outputs[source].expr.numel())} entries: a "
                                f"statistic is of one, {name}[i]")
    _, per = solve_periodic_3d_state(s0, "shooting", None, False, None, {})
    hbs, w, P, residual = _balanced(s0, mech, per, harmonics)
    dP, steps = _slopes(base, mech, per, names, values, raw_at, step)
    dPp, daux = dP[:P.size], dP[P.size:]
    dw = _coefficient_slopes(s0, hbs, w, P, dPp)
    f, df = _series_functions(mech, hbs, harmonics, outs)
    T = float(P[0])
    grid = T * np.arange(GRID * hbs.M) / (GRID * hbs.M)
    Y = np.asarray(f.map(grid.size)(w, P, grid.reshape(1, -1)), float)  # (n_out, m)
    mbl, lines = breaking_loads(s0), lines_of(s0)
    names_out, units, vals, rows = [], [], [], []
    for i, ((name, source, how, _), (_, stat)) in enumerate(zip(outs, wanted)):
        value, row = _statistic(i, stat, f, df, w, P, dw, dPp, grid, Y)
        if how in ("norm", "ratio", "horizontal") and stat in ("min", "range") and \
                not np.min(Y[i]) > NO_MAGNITUDE * float(mech.scales.force):
            raise SymcableError(f"output {name}.{stat!r}: the magnitude falls to "
                                f"{np.min(Y[i]):.3g} N over the period: at zero it has no "
                                "derivative (a direction's entry, NAME[i], has)")
        if how == "ratio":  # over the end section's breaking load, its slope included
            line = source.rpartition(".")[0]
            k = 2 * ([n[0] for n in lines].index(line) if line else 0) + source.endswith("_b")
            if not math.isfinite(mbl[k]):
                raise SymcableError(f"output {name!r}: the line's end section has no breaking "
                                    "load (give its line type breaking_load, or a family)")
            value, row = value / mbl[k], row / mbl[k] - value / mbl[k] ** 2 * daux[k]
        names_out.append(f"{name}.{stat}")
        units.append("" if how == "ratio" else str(mech.outputs[source].unit))
        vals.append(value)
        rows.append(row)
    return Sensitivity(s0.name, tuple(names_out), tuple(units), tuple(names), np.array(vals),
                       np.array(values, float), np.array(rows),
                       {"parameter_steps": steps, "slopes": dP, "period": T,
                        "harmonics": harmonics, "residual": residual,
                        "wall_time": time.perf_counter() - started})
