"""The scene of the live MoorDyn comparison on a 3D line (issue 12), for
``tests/test_moordyn_live3d.py`` and ``run.py`` beside this file.

One steel wire rope (d = 0.09 m, 40 kg/m, EA = 600 MN, 240 m in 8 m segments at 30) from
an anchor on the seabed at (0, 0, -60) m to a fairlead at (216, 60, -5) m: about 100 m of it
lies on a frictionless seabed. The fairlead moves harmonically in x, y and z at once
(period 12 s, amplitudes 1.5, 1.5, 1.0 m, phases 0, 90, -60 degrees; so the line leaves
the vertical plane of its ends), ramped in over the first period as symcable ramps it, in a
uniform current of 0.5 m/s at 30 degrees from that plane (towards the fairlead's side).

One MoorDyn v2 deck (:func:`deck_text`) is the source of both models:

* symcable reads it with ``symcable.scene.moordyn.parse_moordyn`` (the loader of
  ``load_scene``; it refuses ``Currents 1``, so it reads the deck without that line), then
  :func:`symcable_scene` adds the current and the fairlead motion and sets
  ``cd_tangential`` = pi CdAx: MoorDyn's axial drag is 0.5 rho_w CdAx (pi d l) |u_t| u_t
  (Line.cpp; docs/inputs.rst: "with respect to surface area, pi*d*l"), symcable's
  0.5 rho_w cd_tangential d l |u_t| u_t, and the loader copies CdAx unchanged (0.008 here,
  so the loader's reading would leave symcable's axial drag pi times too small).
* MoorDyn (2.7.2) runs the deck with ``1 Currents``, which reads ``current_profile.txt``
  from the deck's folder (MoorDyn's docs/waterkinematics.rst; source
  Waves/WaveGrid.cpp: three header lines, then rows ``z ux uy uz``, linear in z and held
  beyond the end rows). Its initial condition (``Init``, the stationary solver) does not
  include the current (measured: 61.14 kN at the fairlead with and without ``Currents``,
  61.69 kN settled in it), so the
  line settles in the current with the fairlead held (:func:`run_moordyn`), then the
  fairlead is driven from Python, one ``moordyn.Step`` per MoorDyn step with the exact
  position and velocity of the ramped motion at the step's start (MoorDyn moves a coupled
  point along x + v (t - t_k) within a call).

The compared quantity is the force of the line on the fairlead, tension plus the end node's
share of weight, buoyancy, drag and seabed force, without its inertia: symcable's
``fairlead_tension`` (``|end_force_b|``) and the force ``moordyn.Step`` returns for the
coupled point (the end node's net force, Point::doRHS; no inertia). MoorDyn's default
scheme, RK2 (explicit midpoint), returns the force of its last stage, the state half a step
before the call's end: its samples are dated ``t_k + dtM / 2``.

Everything else is equal by construction: weight and buoyancy (m - rho pi d^2 / 4) g per
unstretched metre; normal drag 0.5 rho d Cd per unstretched metre (symcable's has a factor
sqrt(1 + strain), within 1e-4 of 1 here); added mass rho pi d^2 / 4 Ca normal to the line, none
axial; material damping BA = zeta ds sqrt(EA m) with zeta = 0.8 (``BA/-zeta`` = -0.8, read
alike by both); the seabed k_bot d l (penetration) and c_bot d l (vertical speed) per node
(symcable smooths the contact's onset over 1 % of the
weight's penetration, 12 micrometres); no friction (``FrictionCoefficient 0``).
What differs is the discretisation of the same segments: MoorDyn lumps drag, added mass
and weight on the nodes with the node's own velocity and a node tangent (its neighbours'
chord); symcable computes drag on each element from the mean velocity of its two nodes and
its added mass with the element's tangent, half on each node.
"""
from __future__ import annotations

import copy
import math
import sys
import time
from pathlib import Path

import numpy as np

if str(Path(__file__).resolve().parents[1]) not in sys.path:
    sys.path.append(str(Path(__file__).resolve().parents[1]))
import moordyn_driver  # noqa: E402  (studies/moordyn_driver.py)

DEPTH = 60.0  # m, water depth: the seabed at z = -60 m
ANCHOR = (0.0, 0.0, -DEPTH)  # m, on the seabed
FAIRLEAD = (216.0, 60.0, -5.0)  # m
LENGTH = 240.0  # m, unstretched
SEGMENTS = 30
#: MoorDyn line type: Diam (m), Mass/m (kg/m), EA (N), BA/-zeta, Cd, Ca, CdAx, CaAx
LINE = {"Diam": 0.09, "Mass": 40.0, "EA": 6.0e8, "BA": -0.8, "Cd": 1.2, "Ca": 1.0,
        "CdAx": 0.008, "CaAx": 0.0}
K_BOT, C_BOT = 3.0e6, 3.0e5  # Pa/m, Pa s/m: MoorDyn's defaults, written out
RHO, G = 1025.0, 9.80665  # kg/m^3, m/s^2
#: N/m, the submerged weight per metre, (m - rho pi d^2 / 4) g, as both codes make it
LINE_WEIGHT = (LINE["Mass"] - RHO * math.pi * LINE["Diam"] ** 2 / 4) * G
PERIOD = 12.0  # s
AMPLITUDE = (1.5, 1.5, 1.0)  # m, x y z
PHASE_DEG = (0.0, 90.0, -60.0)
CURRENT_SPEED = 0.5  # m/s
CURRENT_HEADING_DEG = 30.0  # from the vertical plane of the line's ends, about +z


def current_vector() -> tuple[float, float, float]:
    """The uniform current (ux, uy, 0), m/s: CURRENT_SPEED at CURRENT_HEADING_DEG from the
    horizontal direction anchor -> fairlead."""
    a = math.atan2(FAIRLEAD[1] - ANCHOR[1], FAIRLEAD[0] - ANCHOR[0]) + math.radians(CURRENT_HEADING_DEG)
    return (CURRENT_SPEED * math.cos(a), CURRENT_SPEED * math.sin(a), 0.0)


def deck_text(segments: int = SEGMENTS, dtM: float = 1e-3, currents: bool = True) -> str:
    """The MoorDyn v2 deck: point 1 Fixed (anchor), point 2 Coupled (fairlead), line 1 from
    1 to 2; OPTIONS dtM (s), g, WtrDnsty, WtrDpth, kBot, cBot, FrictionCoefficient 0 and,
    with ``currents``, ``1 Currents`` (read by MoorDyn from current_profile.txt)."""
    L = LINE
    a, b = ANCHOR, FAIRLEAD
    return "\n".join([
        "--------------------- MoorDyn Input File ---------------------",
        "3D wire rope with an out-of-plane fairlead motion in an oblique current (symcable issue 12)",
        "---------------------- LINE TYPES ----------------------",
        "TypeName Diam Mass/m EA BA/-zeta EI Cd Ca CdAx CaAx",
        "(name) (m) (kg/m) (N) (N-s/-) (N-m^2) (-) (-) (-) (-)",
        f"wire {L['Diam']!r} {L['Mass']!r} {L['EA']!r} {L['BA']!r} 0.0 {L['Cd']!r} {L['Ca']!r} "
        f"{L['CdAx']!r} {L['CaAx']!r}",
        "---------------------- POINTS ----------------------",
        "ID Attachment X Y Z Mass Volume CdA CA",
        "(#) (-) (m) (m) (m) (kg) (m^3) (m^2) (-)",
        f"1 Fixed {a[0]!r} {a[1]!r} {a[2]!r} 0 0 0 0",
        f"2 Coupled {b[0]!r} {b[1]!r} {b[2]!r} 0 0 0 0",
        "---------------------- LINES ----------------------",
        "ID LineType AttachA AttachB UnstrLen NumSegs Outputs",
        "(#) (name) (#) (#) (m) (-) (-)",
        f"1 wire 1 2 {LENGTH!r} {int(segments)} -",
        "---------------------- OPTIONS ----------------------",
        f"{dtM!r} dtM",
        f"{G!r} g",
        f"{RHO!r} WtrDnsty",
        f"{DEPTH!r} WtrDpth",
        f"{K_BOT!r} kBot",
        f"{C_BOT!r} cBot",
        "0.0 FrictionCoefficient",
        *(["1 Currents"] if currents else []),
        "1 disableOutput",
        "0 writeLog",
        "--------------------- need this line ------------------",
        ""])


def current_profile_text() -> str:
    """current_profile.txt: three header lines, then z ux uy uz at the seabed and the
    surface (MoorDyn holds the end rows beyond them: uniform)."""
    ux, uy, uz = current_vector()
    return ("uniform current written by studies/moordyn_live3d/case.py\n---\nz ux uy uz\n"
            + "".join(f"{z!r} {ux!r} {uy!r} {uz!r}\n" for z in (-DEPTH, 0.0)))


def symcable_scene(segments: int = SEGMENTS, motion: bool = True, current: bool = True) -> dict:
    """The deck read by symcable's MoorDyn loader, plus the current, the fairlead motion
    and the axial drag coefficient on symcable's reference area (module docstring)."""
    from symcable.scene import load_scene
    from symcable.scene.moordyn import parse_moordyn

    scene = copy.deepcopy(dict(parse_moordyn(deck_text(segments, currents=False), "live3d.txt").scene))
    (lt,) = scene["line_types"].values()
    assert lt["cd_tangential"] == math.pi * LINE["CdAx"]  # the loader's own reading
    scene["environment"]["current"] = list(current_vector()) if current else [0.0, 0.0, 0.0]
    if motion:
        scene["end_b"]["motion"] = {"kind": "harmonic", "period": PERIOD,
                                    "amplitude": list(AMPLITUDE), "phase_deg": list(PHASE_DEG)}
    return load_scene(scene).to_dict()


def fairlead_motion(t: float) -> tuple[np.ndarray, np.ndarray]:
    """Fairlead position (m) and velocity (m/s) at ``t`` s, as symcable moves a pinned end:
    FAIRLEAD + r(t) A_i cos(2 pi t / T + phase_i), r = (1 - cos(pi t / T)) / 2 over the
    first period (0 before t = 0, 1 after t = T)."""
    w = 2.0 * math.pi / PERIOD
    if t <= 0.0:
        r, dr = 0.0, 0.0
    elif t < PERIOD:
        r = 0.5 * (1.0 - math.cos(math.pi * t / PERIOD))
        dr = 0.5 * math.pi / PERIOD * math.sin(math.pi * t / PERIOD)
    else:
        r, dr = 1.0, 0.0
    ph = np.radians(PHASE_DEG)
    A = np.asarray(AMPLITUDE)
    c, s = A * np.cos(w * t + ph), -A * w * np.sin(w * t + ph)
    return np.asarray(FAIRLEAD) + r * c, dr * c + r * s


def run_moordyn(segments: int = SEGMENTS, dtM: float = 1e-3, duration: float = 3 * PERIOD,
                settle_max: float = 200.0, settle_tol: float = 1e-7) -> dict:
    """MoorDyn on the deck: Init (its IC solve, without the current), settling in the
    current with the fairlead held (1 s calls until the fairlead force changes by less than
    ``settle_tol`` of itself over 5 s, at most ``settle_max`` s), then the ramped motion
    for ``duration`` s, one call per step ``dtM`` (s). Driven by ``studies/moordyn_driver.py``.

    Returns ``time`` (s, each sample's own time: RK2's last stage is half a step before
    the call's end), ``tension`` (N, ``|force on the fairlead|``), ``ic_tension`` (N, after
    Init), ``static_tension`` (N, settled), ``settled_after`` (s simulated),
    ``wall_time`` (s: Create + Init + settling + run), ``run_time`` (s, the motion's calls).
    """
    n = int(round(duration / dtM))
    files = {"live3d.txt": deck_text(segments, dtM), "current_profile.txt": current_profile_text()}

    def calls():  # the exact position and velocity of the ramped motion at each step's start
        for k in range(n):
            x, v = fairlead_motion(k * dtM)
            yield x.tolist(), v.tolist(), k * dtM, dtM

    held, rest = list(FAIRLEAD), [0.0, 0.0, 0.0]
    with moordyn_driver.session(files, "live3d.txt", held, rest, prefix="symcable_md_") as s:
        point = s.md.GetPoint(s.system, 2)
        ic = float(np.linalg.norm(s.md.GetPointForce(point)))
        settled_after, static = moordyn_driver.settle(
            s, held, rest, max_time=settle_max, tol=settle_tol, window=5, t_start=-settle_max, first=ic)
        F0 = s.md.GetPointForce(point)
        run = moordyn_driver.drive(s, calls())
        wall = time.perf_counter() - s.started
    F = np.vstack([np.asarray(F0, float)[None, :], run.force])
    tk = np.arange(n + 1) * dtM
    tk[1:] -= 0.5 * dtM
    return {"time": tk, "tension": np.linalg.norm(F, axis=1), "force": F, "ic_tension": ic,
            "static_tension": static, "settled_after": settled_after, "dtM": dtM,
            "wall_time": wall, "run_time": run.wall}


def run_symcable(segments: int = SEGMENTS, dt: float = 0.025, duration: float = 3 * PERIOD,
                 rho_inf: float = 0.0, codegen: bool | None = None) -> dict:
    """symcable's static solve and run (generalized-alpha, ``rho_inf``, step ``dt`` s).
    Returns ``time``, ``tension`` (N), ``static_tension`` (N), ``wall_time`` (s: static
    solve and run, as ``stats["wall_time"]``), ``static_time`` (s), ``error_estimate`` and
    the :class:`~symcable.results.line3d.LineTrajectory` as ``trajectory``."""
    import symcable as sc

    tr = sc.simulate(symcable_scene(segments), duration, dt=dt, rho_inf=rho_inf, codegen=codegen)
    return {"time": tr.time, "tension": tr.fairlead_tension,
            "static_tension": float(tr.fairlead_tension[0]), "wall_time": tr.stats["wall_time"],
            "static_time": tr.stats["static_time"], "error_estimate": tr.stats["error_estimate"],
            "trajectory": tr}


def difference(ref_time, ref, time_, series, t_from: float = PERIOD) -> dict:
    """``series`` against ``ref`` (each sampled at its own times, s) on ``time_`` >= t_from
    (``ref`` interpolated linearly): ``max`` and ``rms`` of the difference as a fraction
    of ``ref``'s range there, ``range`` (N) and ``mean`` (N, series - ref)."""
    t, s = np.asarray(time_, float), np.asarray(series, float)
    sel = t >= t_from - 1e-9
    r = np.interp(t[sel], np.asarray(ref_time, float), np.asarray(ref, float))
    d = s[sel] - r
    rng = float(np.ptp(r))
    return {"max": float(np.max(np.abs(d))) / rng, "rms": float(np.sqrt(np.mean(d * d))) / rng,
            "range": rng, "mean": float(np.mean(d))}
