"""MoorDyn-C (``moordyn`` 2.7.2, the lumped-mass peer) on the seed-001 line and its fairlead motion.

The scene is ``symcable/data/seed001.toml``: one planar chain, anchor pinned, fairlead moved on
an ellipse ``dx = 2 r cos(wt)``, ``dz = r sin(wt)`` about its static place with symcable's
start-up ramp ``r = (1 - cos(pi t/T))/2`` over the first period, in a steady uniform current.
MoorDyn is 3-D: the plane is its (x, z), y = 0. Findings: ``test_notes_moordyn.md``.

Line properties (:func:`line_type`): MoorDyn's buoyancy and drag both use ``Diam``, so ``Diam``
is the volume-equivalent ``d_v = sqrt(4 (m g - w) / (pi rho g))`` and the coefficients keep
symcable's force per length: ``Cd = cd_n d/d_v``, ``CdAx = cd_t d/(pi d_v)`` (MoorDyn's tangential
drag is on the surface ``pi d l``), ``Ca = ca_n (d/d_v)^2``, ``CaAx = 0``; seed 001: d_v = 0.09 m.

MoorDyn behaviours that shape :func:`run` (read in MoorDyn's source, measured here):

* ``Init`` (its static initial condition) ignores the current: the line then settles in the
  current, fairlead held, before t = 0 (``settle``; counted in ``init_time``);
* ``Step`` moves a coupled point along ``x + v (t - t_k)`` from the values at the call's start,
  so a coarse coupling step excites axial waves (default: one call per MoorDyn step);
* the force ``Step`` returns is the end node's net force (tension, weight, drag; no inertia)
  at the last stage of the step: RK2's midpoint, ``dtM/2`` before the call's end (``lag``).
  ``fairlead_tension`` is ``|F - M a|`` (``M`` the end node's mass matrix, ``a`` the prescribed
  acceleration): the force the line exerts on the fairlead, symcable's quantity.
"""
from __future__ import annotations

import math
import sys
import time
from pathlib import Path

import numpy as np

if str(Path(__file__).resolve().parents[1]) not in sys.path:
    sys.path.append(str(Path(__file__).resolve().parents[1]))
import moordyn_driver  # noqa: E402  (studies/moordyn_driver.py)

SCENE = Path(__file__).resolve().parents[2] / "symcable" / "data" / "seed001.toml"
DEPTH = 600.0  # m: water depth, far below the line's lowest point (-339 m): no seabed contact
DT_LIMIT = {"RK2": 0.0222, "RK4": 0.036}  # s: measured stable dtM (RK2 with zeta = 1, RK4 zeta = 0)
DT_DEFAULT = 0.02  # s: T/500, below RK2's limit, a whole number of steps per T/100


def scene_parameters(scene=SCENE) -> dict:
    """Line, ends, motion and environment of a one-section planar scene TOML, SI units."""
    try:
        import tomllib
    except ImportError:  # Python < 3.11
        import tomli as tomllib
    with open(scene, "rb") as fh:
        s = tomllib.load(fh)
    if len(s["sections"]) != 1:
        raise ValueError(f"{scene}: one section only")
    sec = s["sections"][0]
    lt, env, mot = s["line_types"][sec["type"]], s["environment"], s["end_b"]["motion"]
    return dict(EA=lt["EA"], mass=lt["mass"], weight=lt["weight"], d=lt["diameter"],
                cdn=lt["cd_normal"], cdt=lt["cd_tangential"], can=lt["ca_normal"],
                cat=lt.get("ca_tangential", 0.0), length=sec["length"], segments=sec["segments"],
                anchor=tuple(s["end_a"]["position"]), fairlead=tuple(s["end_b"]["position"]),
                g=env["gravity"], rho=env["water_density"], current=tuple(env["current"]),
                period=mot["period"], amplitude=tuple(mot["amplitude"]),
                phase=tuple(math.radians(a) for a in mot["phase_deg"]))


def line_type(p: dict) -> dict:
    """MoorDyn line-type columns ``Diam`` (m), ``MassDen`` (kg/m), ``Cd, Ca, CdAx, CaAx`` (-)."""
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
        d, dd = A * math.cos(w * t + ph), -A * w * math.sin(w * t + ph)
        x[k] += r * d
        v[k] = r1 * d + r * dd
        a[k] = r2 * d + 2.0 * r1 * dd - r * w * w * d
    return x, v, a


def cfl_dt(p: dict | None = None, cfl: float = 0.5) -> float:
    """The dtM (s) MoorDyn 2.7 derives from its ``CFL`` option (default 0.5) when no dtM is given:
    ``cfl * 2 pi sqrt(m/k)``, the period of one segment's mass ``m = w L/N`` on ``k = EA N/L``."""
    p = p or scene_parameters()
    return cfl * 2.0 * math.pi * p["length"] / p["segments"] * math.sqrt(p["mass"] / p["EA"])


def input_files(dtM: float | None, *, p: dict | None = None, zeta: float = 1.0,
                tscheme: str = "RK2", current: float | None = None, tmax_ic: float = 10.0) -> dict:
    """{"line.txt": the MoorDyn v2 input, "current_profile.txt": its current}. ``dtM`` (s; None: MoorDyn's ``CFL`` 0.5, :func:`cfl_dt`); ``p`` the
    :func:`scene_parameters` (default seed 001); ``zeta`` the internal axial damping as a
    fraction of a segment's critical damping (``BA/-zeta``; symcable has none, RK2 needs some:
    1 is MoorDyn's advice, RK4 runs with 0); ``tscheme`` (``RK2`` is MoorDyn's default);
    ``current`` (m/s along +x, default the scene's: ``Currents 1`` reads (z, ux, uy, uz) rows
    after three header lines of ``current_profile.txt`` beside the input); ``tmax_ic`` (s,
    ``TmaxIC`` of MoorDyn's stationary initial-condition solver)."""
    p = p or scene_parameters()
    lt, U = line_type(p), p["current"][0] if current is None else current
    (xa, za), (xb, zb) = p["anchor"], p["fairlead"]
    profile = f"current profile\nuniform\nz ux uy uz\n{-DEPTH!r} {U!r} 0 0\n0.0 {U!r} 0 0\n"
    step = "0.5 CFL" if dtM is None else f"{dtM!r} dtM"
    deck = f"""--------------------- MoorDyn Input File ---------------------
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
{step}
{tscheme} tScheme
{p['g']!r} g
{p['rho']!r} rho
{DEPTH!r} WtrDpth
1 Currents
{tmax_ic!r} TmaxIC
1 disableOutput
--------------------- need this line ------------------
"""
    return {"line.txt": deck, "current_profile.txt": profile}


def write_input(folder, dtM: float | None, **kw) -> Path:
    """Write :func:`input_files` into ``folder``; return the input's path (``line.txt``)."""
    for name, text in input_files(dtM, **kw).items():
        Path(folder, name).write_text(text)
    return Path(folder, "line.txt")


def run(duration: float = 300.0, dtM: float | None = None, dt_coupling: float | None = None, *,
        scene=SCENE, zeta: float = 1.0, tscheme: str = "RK2", current: float | None = None,
        settle: float = 200.0, settle_tol: float = 1e-6, velocity: str = "exact",
        params: dict | None = None) -> dict:
    """Run MoorDyn on the scene's line and fairlead motion from its static state in the current.

    Parameters
    ----------
    duration : float
        Simulated time, s (t = 0: the fairlead starts moving).
    dtM : float, optional
        MoorDyn time step, s (default ``DT_DEFAULT``), shortened so that a whole number of
        steps fills ``dt_coupling``.
    dt_coupling : float, optional
        Interval between ``moordyn.Step`` calls, s (default ``dtM``). MoorDyn extrapolates the
        fairlead linearly from each call's start; the velocity error excites axial waves
        (impedance ``sqrt(EA m)`` = 55 kN s/m): 0.1 s costs 1.8 % of the tension range.
    scene : path-like
        Scene TOML (one section, planar).
    zeta, tscheme, current
        As :func:`write_input`.
    settle : float
        Longest time, s, the line settles in the current with the fairlead held before t = 0.
    settle_tol : float
        Settling ends when the fairlead force changes by less than this fraction over 10 s.
    velocity : {"exact", "secant"}
        Fairlead velocity passed at each call: ``dx/dt`` at its start, or ``(x(t+dt) - x(t))/dt``.
    params : dict, optional
        The :func:`scene_parameters` to run instead of the scene's (an edited line).

    Returns
    -------
    dict
        ``time`` (s, call ends), ``fairlead_tension`` (N, ``|F - M a|``), ``segment_tension`` (N,
        MoorDyn's FairTen: the top segment's), ``fairlead_force`` (N, (n, 2): x, z),
        ``static_tension`` (N, settled), ``wall_time`` (s, the stepping loop only),
        ``init_time`` (s, Create + Init + settling), ``ic_time`` (s, Init), ``settle_time`` (s,
        simulated), ``dtM`` (s), ``n_calls``, ``substeps`` (per call), ``lag`` (s: the forces
        belong to ``time - lag``: ``dtM/2`` for RK2, 0 for RK4 whose last stage ends the step).

    Raises
    ------
    RuntimeError
        MoorDyn failed (e.g. above its stability limit); the message ends with its output.
    """
    p = params or scene_parameters(scene)
    dtM = DT_DEFAULT if dtM is None else dtM
    dt_coupling = dtM if dt_coupling is None else dt_coupling
    n_sub = max(1, math.ceil(dt_coupling / dtM - 1e-9))
    dtM = dt_coupling / n_sub * (1.0 + 1e-9)  # the last sub-step takes the exact remainder
    files = input_files(dtM, p=p, zeta=zeta, tscheme=tscheme, current=current)
    x0, v0, _ = fairlead_motion(0.0, p)
    with moordyn_driver.session(files, "line.txt", x0, v0) as s:
        out = _simulate(s, p, duration, dt_coupling, settle, settle_tol, velocity == "secant")
    return dict(out, dtM=dtM, substeps=n_sub, lag=0.5 * dtM if tscheme.upper() == "RK2" else 0.0)


def _simulate(s, p, duration, dt_c, settle, settle_tol, secant):
    md, motion = s.md, fairlead_motion
    x0, v0, _ = motion(0.0, p)
    line, point = md.GetLine(s.system, 1), md.GetPoint(s.system, 2)
    M = np.asarray(md.GetPointM(point))
    # Init ignored the current: settle in it, fairlead held
    ts, _ = moordyn_driver.settle(s, x0, v0, max_time=settle, tol=settle_tol, window=10)
    init_time = time.perf_counter() - s.started
    n = int(round(duration / dt_c))
    F0 = md.GetPointForce(point)

    def calls():
        x, v, _ = motion(0.0, p)
        for k in range(n):
            t = k * dt_c
            xn, vn, _ = motion(t + dt_c, p)
            if secant:
                v = [(b - a) / dt_c for a, b in zip(x, xn)]
            yield x, v, t, dt_c
            x, v = xn, vn

    run = moordyn_driver.drive(s, calls(), read=lambda: md.GetLineFairTen(line))
    F = np.vstack([np.asarray(F0, float)[None, :], run.force])
    Tseg = np.asarray(run.reads, float)
    tt = np.arange(n + 1) * dt_c
    Fl = (F - np.array([motion(t, p)[2] for t in tt]) @ M.T)[:, ::2]  # less the end node's inertia
    return dict(time=tt, fairlead_tension=np.hypot(Fl[:, 0], Fl[:, 1]), segment_tension=Tseg,
                fairlead_force=Fl, static_tension=float(np.hypot(*F[0, ::2])), wall_time=run.wall,
                init_time=init_time, ic_time=s.ic_time, settle_time=ts, n_calls=n)


def moordyn_time_step(dtM: float | None = None, **kw) -> tuple:
    """MoorDyn's own (dtM s, CFL) after ``Init`` for an input with ``dtM`` (None: CFL 0.5 only)."""
    p = kw.get("p") or scene_parameters()
    with moordyn_driver.session(input_files(dtM, **kw), "line.txt", *fairlead_motion(0.0, p)[:2]) as s:
        return s.dt(), s.cfl()


def last_period(res: dict, period: float = 10.0, samples: int = 100, key: str = "fairlead_tension",
                shift: bool = True):
    """(times s, values) of ``key`` over the record's last whole period at ``t0 + k T/samples``,
    k = 0..samples-1 (linear interpolation), the record moved back by its ``lag`` when ``shift``."""
    t0 = period * (math.floor(res["time"][-1] / period + 1e-9) - 1)
    t = t0 + period * np.arange(samples) / samples
    return t, np.interp(t, res["time"] - (res.get("lag", 0.0) if shift else 0.0), res[key])


def tension_error(res: dict, ref: dict, period: float = 10.0, shift: bool = True) -> float:
    """Max |T - T_ref| over the last period (every T/100) over the reference's range there."""
    a, b = last_period(res, period, shift=shift)[1], last_period(ref, period, shift=shift)[1]
    return float(np.max(np.abs(a - b)) / np.ptp(b))


def steady_state_distance(res: dict, period: float = 10.0, samples: int = 100) -> np.ndarray:
    """For each period n = 1..N: max |T(period n) - T(period N)| over period N's range."""
    n_per = int(math.floor(res["time"][-1] / period + 1e-9))
    t = period * np.arange(samples) / samples
    T = np.array([np.interp(t + k * period, res["time"], res["fairlead_tension"]) for k in range(n_per)])
    return np.max(np.abs(T - T[-1]), axis=1) / np.ptp(T[-1])


def stable_dt(lo: float, hi: float, tol: float = 2e-4, duration: float = 300.0, **kw) -> float:
    """Largest dtM (s) in [lo, hi] (bisection to ``tol``) whose run neither fails nor strays over
    5 % of the range from the run at ``lo`` (assumed stable; ``hi`` assumed not)."""
    base = run(duration, lo, **kw)
    while hi - lo > tol:
        mid = 0.5 * (lo + hi)
        try:
            ok = tension_error(run(duration, mid, **kw), base) < 0.05
        except RuntimeError:
            ok = False
        lo, hi = (mid, hi) if ok else (lo, mid)
    return lo


def _main():  # the measurements of test_notes_moordyn.md (about a minute of CPU)
    p, kN, med = scene_parameters(), 1e-3, lambda rs: float(np.median([r["wall_time"] for r in rs]))
    print("line type:", {k: round(v, 7) for k, v in line_type(p).items()})
    print(f"CFL: formula dt {cfl_dt(p):.6f} s; MoorDyn's (dt, CFL) from CFL 0.5: {moordyn_time_step(None)}; "
          f"from dtM {DT_LIMIT['RK2']}: {moordyn_time_step(DT_LIMIT['RK2'])}")
    for U in (0.5, 0.0, -0.5):
        r = run(0.0, current=U)
        print(f"current {U:+.1f} m/s: static tension {r['static_tension'] * kN:.3f} kN, force (x, z) "
              f"{np.round(r['fairlead_force'][0] * kN, 3)} kN; Init {r['ic_time']:.3f} s, settled "
              f"{r['settle_time']:.0f} s, Create + Init + settle {r['init_time']:.3f} s")
    lim = stable_dt(0.02, 0.03)
    rs = [run(300.0, lim) for _ in range(3)]
    w, over = med(rs), 1.0 - med([run(300.0, DT_DEFAULT, 1.0) for _ in range(3)]) / med(
        [run(300.0, DT_DEFAULT) for _ in range(3)])
    print(f"RK2, zeta 1: stable up to dtM {lim:.4f} s (CFL {lim / cfl_dt(p, 1.0):.3f}); 30 periods: wall "
          f"{w:.3f} s (median of 3), init {rs[0]['init_time']:.3f} s; call overhead at dtM {DT_DEFAULT}: {over:.1%}")
    ref = run(300.0, 0.1 / 320)
    print(f"  reference dtM {ref['dtM']:.4g} s, wall {ref['wall_time']:.1f} s; error: at the forces' own time "
          f"(as returned), wall, periods to 1 % of steady state")
    for dt in [lim, 0.02, 0.01, 0.005, 0.0025, 0.00125, 0.000625]:
        r = rs[0] if dt == lim else run(300.0, dt)
        print(f"  dtM {dt:.6f}: {tension_error(r, ref):.2e} ({tension_error(r, ref, shift=False):.2e}), "
              f"{r['wall_time']:.3f} s, {int(np.argmax(steady_state_distance(r) < 0.01)) + 1}")
    d = steady_state_distance(rs[0])
    n1 = int(np.argmax(d < 0.01)) + 1
    print(f"  distance from steady state by period: {np.round(d[:6], 5)}, max after: {d[6:-1].max():.1e}; "
          f"within 1 % after {n1} periods = {n1 * w / 30:.4f} s wall")
    lim4 = stable_dt(0.03, 0.04, zeta=0.0, tscheme="RK4")
    rk4 = dict(zeta=0.0, tscheme="RK4")
    r4, ref4 = [run(300.0, lim4, **rk4) for _ in range(3)], run(300.0, 0.1 / 160, **rk4)
    print(f"RK4, zeta 0: stable up to dtM {lim4:.4f} s; wall {med(r4):.3f} s (median of 3); error "
          f"{tension_error(r4[0], ref4):.2e} vs dtM {ref4['dtM']:.4g}; zeta 1 vs 0: {tension_error(ref, ref4):.2e}")
    try:
        import symcable
        t0 = time.perf_counter()
        tr = symcable.simulate(str(SCENE), duration=300.0, dt=0.1, save_every=1, progress=False)
        ws, st = time.perf_counter() - t0, symcable.solve_static(str(SCENE))
    except Exception as exc:  # noqa: BLE001 - report and go on
        return print(f"symcable comparison skipped: {exc!r}")
    Ts = last_period(dict(time=np.asarray(tr.time), fairlead_tension=np.asarray(tr.fairlead_tension)))[1]
    print(f"symcable: static {st.fairlead_tension * kN:.3f} kN; generalized-alpha dt 0.1 s, 300 s: wall "
          f"{ws:.2f} s; last period mean {Ts.mean() * kN:.2f}, range {np.ptp(Ts) * kN:.2f} kN")
    for name, r in (("RK2 zeta 1 ref", ref), (f"RK2 zeta 1 dtM {lim:.4f}", rs[0]), ("RK4 zeta 0 ref", ref4)):
        for key in ("fairlead_tension", "segment_tension"):
            T = last_period(r, key=key)[1]
            print(f"  MoorDyn {name} {key}: mean {T.mean() * kN:.2f}, range {np.ptp(T) * kN:.2f}, max |diff| "
                  f"{np.max(np.abs(T - Ts)) * kN:.2f} kN = {np.max(np.abs(T - Ts)) / np.ptp(Ts):.2%} of range")


if __name__ == "__main__":
    _main()
