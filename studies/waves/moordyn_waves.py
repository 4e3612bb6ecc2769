"""symcable against MoorDyn run live in the same regular wave: a 400 m chain between a fixed
anchor and a still fairlead (no seabed contact), H 6 m, T 10 s; both with MoorDyn's axial damping of 0.8 of
critical on the highest mode (BA/-zeta = -0.8: without it MoorDyn's line rings at its axial
modes, 9 kN at 4 Hz, against a 1 kN wave response).

MoorDyn (the ``moordyn`` package, 2.7.2) reads no wave of its own here: with ``WaveKin = 1``
("externally driven") it is given, before each call of 0.01 s, the water's velocity and
acceleration at its own nodes, computed by ``sc.wave_kinematics`` (the sea symcable's
lines feel, ramped in the same way): the same wave on both. symcable runs ``sc.simulate``
at its defaults. The fairlead tension over the last two periods of 60 s is compared as a
fraction of its range, against MoorDyn's own change from N to 2N segments.

``python moordyn_waves.py`` (N = 20 and 40) writes ``moordyn_waves.json``; ``--quick``
(N = 10 and 20, 40 s) into ``out/``.
"""
from __future__ import annotations

import math
import sys
import time
from pathlib import Path

import numpy as np

import symcable as sc
from fd_vs_td import study_main

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
import moordyn_driver  # noqa: E402

H, T = 6.0, 10.0
ANCHOR, FAIRLEAD = (-300.0, 0.0, -150.0), (0.0, 0.0, -10.0)
CHAIN = dict(d=0.1, m=80.0, EA=6e8, cdn=1.2, cdt=0.4, can=1.0, cat=0.0, zeta=0.8)
DEPTH = 200.0


def scene(segments: int) -> dict:
    c = CHAIN
    return {"name": "chain in a regular wave", "model": "cable3d",
            "environment": {"depth": DEPTH, "waves": {"kind": "regular", "height": H,
                                                      "period": T}},
            "line_types": {"chain": {"mass": c["m"], "diameter": c["d"], "EA": c["EA"],
                                     "cd_normal": c["cdn"], "cd_tangential": c["cdt"],
                                     "ca_normal": c["can"], "ca_tangential": c["cat"],
                                     "damping": -c["zeta"]}},
            "sections": [{"type": "chain", "length": 400.0, "segments": segments}],
            "end_a": {"condition": "pinned", "position": list(ANCHOR)},
            "end_b": {"condition": "pinned", "position": list(FAIRLEAD)}}


def deck(segments: int) -> str:
    """The chain as a MoorDyn deck (its axial drag CdAx per surface area pi d l: symcable's
    cd_tangential over pi)."""
    c = CHAIN
    return f"""MoorDyn v2: a chain in externally driven waves
---------------------- LINE TYPES -----------------------------------
TypeName  Diam   Mass/m  EA      BA/-zeta  EI  Cd   Ca   CdAx  CaAx
(name)    (m)    (kg/m)  (N)     (N-s)     (-) (-)  (-)  (-)   (-)
chain     {c['d']}   {c['m']}    {c['EA']}   {-c['zeta']}      0   {c['cdn']}  {c['can']}  {c['cdt'] / math.pi:.6g}   {c['cat']}
---------------------- POINTS ---------------------------------------
ID  Type    X      Y    Z      M    V    CdA  Ca
(#) (-)     (m)    (m)  (m)    (kg) (m^3) (m^2) (-)
1   Fixed   {ANCHOR[0]}  {ANCHOR[1]}  {ANCHOR[2]}  0    0    0    0
2   Vessel  {FAIRLEAD[0]}  {FAIRLEAD[1]}  {FAIRLEAD[2]}  0    0    0    0
---------------------- LINES ----------------------------------------
ID  LineType  AttachA  AttachB  UnstrLen  NumSegs  Outputs
(#) (name)    (#)      (#)      (m)       (-)      (-)
1   chain     1        2        400.0     {segments}       -
---------------------- OPTIONS --------------------------------------
{DEPTH}   WtrDpth
1025    WtrDnsty
1       WaveKin
5e-5    dtM
---------------------------------------------------------------------
"""


def moordyn_run(segments: int, duration: float, waves_scene: dict, dt: float = 0.01):
    """MoorDyn's fairlead tension (N) at each call's end over ``duration`` s."""
    x0 = list(FAIRLEAD)
    with moordyn_driver.session({"chain.txt": deck(segments)}, "chain.txt", x0,
                                [0.0] * 3) as s:
        md = s.md
        md.ExternalWaveKinInit(s.system)
        xyz = np.asarray(md.ExternalWaveKinGetCoordinates(s.system), float).reshape(-1, 3)
        zero = np.zeros_like(xyz).tolist()
        md.ExternalWaveKinSet(s.system, zero, zero, 0.0)
        # MoorDyn's own initial condition is not at rest: settle it in still water first
        held, _ = moordyn_driver.settle(s, x0, [0.0] * 3, max_time=300.0, tol=1e-7,
                                        window=10)
        times, tension = [], []
        t = 0.0
        t0 = time.perf_counter()
        while t < duration - 1e-9:
            xyz = np.asarray(md.ExternalWaveKinGetCoordinates(s.system), float).reshape(-1, 3)
            kin = sc.wave_kinematics(waves_scene, xyz, t + dt, ramp=True)
            md.ExternalWaveKinSet(s.system, kin.velocity[0].tolist(),
                                  kin.acceleration[0].tolist(), held + t + dt)
            f = md.Step(s.system, x0, [0.0] * 3, held + t, dt)
            t += dt
            times.append(t)
            tension.append(float(np.linalg.norm(f)))
        wall = time.perf_counter() - t0
    return np.asarray(times), np.asarray(tension), wall


def run(quick: bool) -> dict:
    n1, n2, duration = (10, 20, 40.0) if quick else (20, 40, 60.0)
    out = {"segments": [n1, n2], "duration": duration}
    runs = {}
    for n in (n1, n2):
        t, f, wall = moordyn_run(n, duration, scene(n))
        runs[n] = (t, f)
        out[f"moordyn_{n}_wall"] = wall
    t0 = time.perf_counter()
    r = sc.simulate(scene(n1), duration=duration, progress=False)
    out["symcable_wall"] = time.perf_counter() - t0
    out["symcable_warnings"] = list(r.warnings)
    keep = runs[n2][0] >= duration - 2 * T
    t = runs[n2][0][keep]
    ref = runs[n2][1][keep]
    rng = float(np.ptp(ref))
    mine = np.interp(t, r.time, r.fairlead_tension)
    md_n1 = runs[n1][1][keep]
    out.update(range_N=rng, symcable_vs_moordyn_2N=float(np.max(np.abs(mine - ref))) / rng,
               moordyn_N_vs_2N=float(np.max(np.abs(md_n1 - ref))) / rng,
               symcable_vs_moordyn_N=float(np.max(np.abs(mine - md_n1))) / rng)
    return out


def main(argv=None) -> int:
    return study_main(__doc__, run, "moordyn_waves", argv)


if __name__ == "__main__":
    sys.exit(main())
