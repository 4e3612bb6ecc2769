"""MoorDyn-C (``moordyn`` 2.7.2, the lumped-mass peer) on the line and fairlead motion of seed 001.

The scene is ``symcable/data/seed001.toml``: one planar chain, anchor pinned, fairlead moved
on an ellipse ``dx = r 2 cos(wt)``, ``dz = r sin(wt)`` about its static place, with the
start-up ramp ``r = (1 - cos(pi t / T)) / 2`` over the first period (symcable's), in a
steady uniform current. MoorDyn is 3-D: the plane is its (x, z), y = 0.

Mapping of the line properties (``line_type``). MoorDyn's buoyancy uses the volume of its
``Diam`` and its drag uses the same diameter, so ``Diam`` is the volume-equivalent diameter
``d_v = sqrt(4 (m g - w) / (pi rho g))`` (``MassDen = m``) and the coefficients are scaled
to keep symcable's force per length: ``Cd = cd_n d / d_v``; ``CdAx = cd_t d / (pi d_v)``
(MoorDyn's tangential drag is on the surface ``pi d l``); ``Ca = ca_n (d / d_v)^2``;
``CaAx = 0``. For seed 001 ``d_v = 0.0900004 m``: the scaling is 4e-6.

Two MoorDyn behaviours shape the runs (read in MoorDyn 2.7 source, checked here):

* its static initialisation (``Init``) ignores the current, so ``run`` first lets the line
  settle in the current with the fairlead held (``settle``; part of the init time);
* ``Step`` moves a coupled point along ``x + v (t - t_k)`` from the values given at the
  call's start ``t_k``, and its returned force is the end node's net force (tension, weight,
  drag: no inertia) at the last stage of the last sub-step (RK2: ``t_k+1 - dtM/2``).
  ``fairlead_tension`` is ``|F - M a|`` (``M`` the end node's mass matrix, ``a`` the
  prescribed acceleration): the force the line exerts on the fairlead, symcable's quantity.
"""
from __future__ import annotations

import contextlib
import math
import os
import tempfile
import time
from pathlib import Path

import numpy as np

SCENE = Path(__file__).resolve().parents[2] / "symcable" / "data" / "seed001.toml"
DEPTH = 600.0  # m: water depth, below the line's lowest point (-339 m): no seabed contact


def _moordyn():
    try:
        import moordyn
    except ImportError as exc:  # pragma: no cover - depends on the environment
        raise ImportError('MoorDyn is missing: pip install "symcable[bench]" '
                          "(or pip install moordyn==2.7.2)") from exc
    return moordyn


def scene_parameters(scene=SCENE) -> dict:
    """Line, ends, motion and environment of a one-section planar scene, SI units."""
    try:
        import tomllib
    except ImportError:  # Python < 3.11
        import tomli as tomllib
    with open(scene, "rb") as fh:
        s = tomllib.load(fh)
    if len(s["sections"]) != 1:
        raise ValueError("one section only")
    sec = s["sections"][0]
    lt, env, mot = s["line_types"][sec["type"]], s["environment"], s["end_b"]["motion"]
    return dict(EA=lt["EA"], mass=lt["mass"], weight=lt["weight"], d=lt["diameter"],
                cdn=lt["cd_normal"], cdt=lt["cd_tangential"], can=lt["ca_normal"],
                cat=lt.get("ca_tangential", 0.0), length=sec["length"], segments=sec["segments"],
                anchor=tuple(s["end_a"]["position"]), fairlead=tuple(s["end_b"]["position"]),
                g=env["gravity"], rho=env["water_density"], current=tuple(env["current"]),
                period=mot["period"], amplitude=tuple(mot["amplitude"]),
                phase=tuple(math.radians(p) for p in mot["phase_deg"]))


def line_type(p: dict) -> dict:
    """MoorDyn line-type columns (Diam m, MassDen kg/m, Cd, Ca, CdAx, CaAx) for scene ``p``."""
    dv = math.sqrt(4.0 * (p["mass"] * p["g"] - p["weight"]) / (math.pi * p["rho"] * p["g"]))
    return dict(Diam=dv, MassDen=p["mass"], Cd=p["cdn"] * p["d"] / dv, Ca=p["can"] * (p["d"] / dv) ** 2,
                CdAx=p["cdt"] * p["d"] / (math.pi * dv), CaAx=p["cat"] * (p["d"] / dv) ** 2)


def fairlead_motion(t: float, p: dict):
    """Prescribed fairlead position (m), velocity (m/s), acceleration (m/s^2) at ``t`` (s), 3-D."""
    T, w = p["period"], 2.0 * math.pi / p["period"]
    tau = min(t / T, 1.0)
    r = 0.5 * (1.0 - math.cos(math.pi * tau))
    r1 = 0.5 * math.pi / T * math.sin(math.pi * tau) if t < T else 0.0
    r2 = 0.5 * (math.pi / T) ** 2 * math.cos(math.pi * tau) if t < T else 0.0
    x, v, a = [p["fairlead"][0], 0.0, p["fairlead"][1]], [0.0] * 3, [0.0] * 3
    for c, k in ((0, 0), (1, 2)):
        A, ph = p["amplitude"][c], p["phase"][c]
        d, dd, ddd = A * math.cos(w * t + ph), -A * w * math.sin(w * t + ph), -w * w * A * math.cos(w * t + ph)
        x[k] += r * d
        v[k] = r1 * d + r * dd
        a[k] = r2 * d + 2.0 * r1 * dd + r * ddd
    return x, v, a


def cfl_dt(p: dict | None = None, cfl: float = 0.5) -> float:
    """The dtM (s) MoorDyn 2.7 takes from its ``CFL`` option alone (default 0.5).

    MoorDyn's line CFL is ``dt / P`` with ``P = 2 pi sqrt(m / k)`` the period of one segment
    of mass ``m = w L/N`` on its spring ``k = EA N/L``: ``dt = cfl 2 pi (L/N) sqrt(w/EA)``.
    """
    p = p or scene_parameters()
    return cfl * 2.0 * math.pi * p["length"] / p["segments"] * math.sqrt(p["mass"] / p["EA"])


def write_input(folder, dtM: float, *, p: dict | None = None, zeta: float = 1.0, tscheme: str = "RK2",
                current: float | None = None, tmax_ic: float = 10.0) -> Path:
    """Write ``line.txt`` (MoorDyn v2 input) and ``current_profile.txt`` into ``folder``.

    Parameters
    ----------
    folder : path-like
        Existing folder; MoorDyn reads the current profile from the input file's folder.
    dtM : float
        MoorDyn time step, s.
    p : dict, optional
        :func:`scene_parameters` (default: seed 001).
    zeta : float
        Internal axial damping as a fraction of each segment's critical damping (MoorDyn's
        ``BA/-zeta = -zeta``); symcable has none, RK2 needs some (module notes).
    tscheme : str
        MoorDyn time scheme (``RK2`` is its default).
    current : float, optional
        Uniform current along +x, m/s (default: the scene's). ``Currents 1`` reads it from
        ``current_profile.txt`` (z, ux, uy, uz rows after three header lines).
    tmax_ic : float
        ``TmaxIC``, s, of MoorDyn's stationary initial-condition solver.
    """
    p = p or scene_parameters()
    lt, U = line_type(p), p["current"][0] if current is None else current
    (xa, za), (xb, zb) = p["anchor"], p["fairlead"]
    folder = Path(folder)
    (folder / "current_profile.txt").write_text(
        "steady current profile\nfor moordyn_line.py\nz (m) ux uy uz (m/s)\n"
        f"{-DEPTH:.1f} {U!r} 0 0\n0.0 {U!r} 0 0\n")
    path = folder / "line.txt"
    path.write_text(f"""--------------------- MoorDyn Input File ---------------------
seed 001 line, written by studies/performance/moordyn_line.py
---------------------- LINE TYPES ----------------------
TypeName Diam MassDen EA BA/-zeta EI Cd Ca CdAx CaAx
(name) (m) (kg/m) (N) (N-s/-) (N-m^2) (-) (-) (-) (-)
chain {lt['Diam']!r} {lt['MassDen']!r} {p['EA']!r} {-zeta!r} 0.0 {lt['Cd']!r} {lt['Ca']!r} {lt['CdAx']!r} {lt['CaAx']!r}
---------------------- POINTS ----------------------
ID Attachment X Y Z Mass Volume CdA CA
(#) (-) (m) (m) (m) (kg) (m^3) (m^2) (-)
1 Fixed {xa!r} 0.0 {za!r} 0 0 0 0
2 Coupled {xb!r} 0.0 {zb!r} 0 0 0 0
---------------------- LINES ----------------------
ID LineType AttachA AttachB UnstrLen NumSegs Outputs
(#) (name) (#) (#) (m) (-) (-)
1 chain 1 2 {p['length']!r} {p['segments']} -
---------------------- OPTIONS ----------------------
{dtM!r} dtM
{tscheme} tScheme
{p['g']!r} g
{p['rho']!r} rho
{DEPTH} WtrDpth
1 Currents
{tmax_ic!r} TmaxIC
1 disableOutput
--------------------- need this line ------------------
""")
    return path


@contextlib.contextmanager
def _quiet(log):
    """Send the C library's stdout/stderr (banner, progress) to ``log`` (a path)."""
    with open(log, "ab") as sink:
        saved = [os.dup(1), os.dup(2)]
        try:
            os.dup2(sink.fileno(), 1)
            os.dup2(sink.fileno(), 2)
            yield
        finally:
            os.dup2(saved[0], 1)
            os.dup2(saved[1], 2)
            os.close(saved[0])
            os.close(saved[1])


def run(duration: float = 300.0, dtM: float | None = None, dt_coupling: float = 0.1, *,
        scene=SCENE, zeta: float = 1.0, tscheme: str = "RK2", current: float | None = None,
        settle: float = 200.0, settle_tol: float = 1e-6, velocity: str = "exact") -> dict:
    """Run MoorDyn on the scene's line and fairlead motion.

    Parameters
    ----------
    duration : float
        Simulated time, s (t = 0 is the start of the fairlead motion).
    dtM : float, optional
        Largest MoorDyn time step, s (default ``DT_STABLE``, the measured limit for RK2 at
        ``zeta = 1``). It is shrunk so that a whole number of steps fills ``dt_coupling``.
    dt_coupling : float
        Interval between ``moordyn.Step`` calls, s: the fairlead position and velocity are set
        at each call's start and extrapolated linearly by MoorDyn over the interval.
    scene : path-like
        Scene TOML (one section, planar).
    zeta, tscheme, current
        As :func:`write_input`.
    settle : float
        Longest time, s, the line settles in the current with the fairlead held before t = 0.
    settle_tol : float
        Settling stops when the fairlead force changes by less than this fraction over 10 s.
    velocity : {"exact", "secant"}
        Fairlead velocity passed at each call: the exact ``dx/dt`` at the call's start, or the
        secant ``(x(t + dt) - x(t)) / dt`` (MoorDyn's extrapolation then lands on ``x(t+dt)``).

    Returns
    -------
    dict
        ``time`` (s), ``fairlead_tension`` (N, ``|F - M a|``), ``segment_tension`` (N, MoorDyn's
        FairTen: the top segment), ``fairlead_force`` (N, (n, 2): x, z), ``static_tension`` (N,
        after settling), ``wall_time`` (s, the stepping loop only), ``init_time`` (s, Create +
        Init + settling), ``ic_time`` (s, Init alone), ``settle_time`` (s, simulated), ``dtM``
        (s), ``n_calls``, ``substeps`` (MoorDyn steps per call).

    Raises
    ------
    RuntimeError
        MoorDyn failed (e.g. a time step above the stability limit); the message ends with
        MoorDyn's own output.
    """
    md = _moordyn()
    p = scene_parameters(scene)
    n_sub = max(1, math.ceil(dt_coupling / (DT_STABLE if dtM is None else dtM) - 1e-9))
    dtM = dt_coupling / n_sub * (1.0 + 1e-9)  # the last sub-step takes the exact remainder
    with tempfile.TemporaryDirectory(prefix="moordyn_") as tmp:
        path, log = write_input(tmp, dtM, p=p, zeta=zeta, tscheme=tscheme, current=current), Path(tmp, "log")
        try:
            with _quiet(log):
                out = _simulate(md, path, p, duration, dt_coupling, settle, settle_tol, velocity == "secant")
        except RuntimeError as exc:
            raise RuntimeError(f"{exc}; MoorDyn printed:\n{log.read_text()[-1500:]}") from exc
    return dict(out, dtM=dtM, substeps=n_sub)


def _simulate(md, path, p, duration, dt_c, settle, settle_tol, secant):
    t0 = time.perf_counter()
    system = md.Create(str(path))
    if system is None:
        raise RuntimeError("moordyn.Create failed")
    try:
        md.SetVerbosity(system, md.LEVEL_ERR)
        x0, v0, _ = fairlead_motion(0.0, p)
        t1 = time.perf_counter()
        if md.Init(system, x0, v0) != md.ERRCODE_SUCCESS:
            raise RuntimeError("moordyn.Init failed")
        ic_time = time.perf_counter() - t1
        line, point = md.GetLine(system, 1), md.GetPoint(system, 2)
        M = np.asarray(md.GetPointM(point))
        hist, ts = [], 0.0  # the initial condition ignores the current: settle in it
        while ts < settle:
            f = md.Step(system, x0, v0, ts, 1.0)
            ts += 1.0
            hist.append(math.hypot(f[0], f[2]))
            if len(hist) > 10 and abs(hist[-1] - hist[-11]) < settle_tol * hist[-1]:
                break
        init_time = time.perf_counter() - t0
        n = int(round(duration / dt_c))
        F, Tseg = np.empty((n + 1, 3)), np.empty(n + 1)
        F[0], Tseg[0] = md.GetPointForce(point), md.GetLineFairTen(line)
        step, fair_ten, motion = md.Step, md.GetLineFairTen, fairlead_motion
        t1 = time.perf_counter()
        x, v, _ = motion(0.0, p)
        for k in range(n):
            t = k * dt_c
            xn, vn, _ = motion(t + dt_c, p)
            if secant:
                v = [(b - a) / dt_c for a, b in zip(x, xn)]
            F[k + 1] = step(system, x, v, t, dt_c)
            Tseg[k + 1] = fair_ten(line)
            x, v = xn, vn
        wall = time.perf_counter() - t1
    finally:
        md.Close(system)
    tt = np.arange(n + 1) * dt_c
    acc = np.array([fairlead_motion(t, p)[2] for t in tt])
    Fl = (F - acc @ M.T)[:, ::2]  # the force on the fairlead: the end node's net force less its inertia
    return dict(time=tt, fairlead_tension=np.hypot(Fl[:, 0], Fl[:, 1]), segment_tension=Tseg,
                fairlead_force=Fl, static_tension=float(np.hypot(*F[0, ::2])), wall_time=wall,
                init_time=init_time, ic_time=ic_time, settle_time=ts, n_calls=n)


def last_period(res: dict, period: float = 10.0, samples: int = 100, key: str = "fairlead_tension"):
    """``key`` over the record's last period at ``samples`` equal steps (linear interpolation)."""
    t_end = res["time"][-1]
    t = t_end - period + period * np.arange(1, samples + 1) / samples
    return t, np.interp(t, res["time"], res[key])


def tension_error(res: dict, ref: dict, period: float = 10.0) -> float:
    """Max |T - T_ref| over the last period, sampled every T/100, over the reference's range."""
    a, b = last_period(res, period)[1], last_period(ref, period)[1]
    return float(np.max(np.abs(a - b)) / np.ptp(b))


def steady_state_distance(res: dict, period: float = 10.0, samples: int = 100) -> np.ndarray:
    """For each period n = 1..N, max |T(period n) - T(last period)| over the last period's range."""
    n_per = int(round(res["time"][-1] / period))
    t = period * np.arange(1, samples + 1) / samples
    T = np.array([np.interp(t + k * period, res["time"], res["fairlead_tension"]) for k in range(n_per)])
    return np.max(np.abs(T - T[-1]), axis=1) / np.ptp(T[-1])


DT_STABLE = 0.02  # s: placeholder, set from the measurement below
