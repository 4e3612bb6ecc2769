"""The coupling interface (issue 36, item 6): a host program moving a spar steps symcable's
three chains through ``sc.Coupling`` and through the C library ``symcable codegen
--coupling`` writes, against ``sc.simulate`` of the same motion, against MoorDyn's own
coupling (``moordyn.Step``, run live) with the same host motion, and timed side by side.

The scene: OC3-Hywind's three chains (902.2 m each, 77.7066 kg/m, EA 384.243 MN) from
anchors at 853.87 m radius in 320 m of water to fairleads 5.2 m from a spar's axis at
-70 m, on a frictionless seabed (MoorDyn's default kBot 3e6 Pa/m, cBot 3e5 Pa s/m, written
out in the deck). One MoorDyn deck is the source of both models (symcable's loader reads it,
its three fairleads ``Coupled`` points; the axial drag on symcable's reference area, pi
CdAx, as studies/moordyn_live3d does). The host moves the spar harmonically about its
reference point at the still water line: surge 4 m, heave 1 m, pitch 3 degrees, period
12 s, ramped in over the first period as a scene's harmonic motion is.

1. symcable's ``Coupling`` (the spar as one coupled body; and its three fairleads as coupled
   points) at the host step T/100 against ``simulate`` of the spar as a vessel body with that
   harmonic motion at the same step: the spar's force and moment, as a fraction of their
   range.
2. The C library (``symcable codegen --coupling``, compiled with ``cc -O2``; ``-O0`` in the
   quick mode) with its example host: the same.
3. MoorDyn (2.7.2) coupled: the fairleads driven one MoorDyn step (dtM = 1 ms) per call with
   the exact position and velocity at each call's start (MoorDyn moves a coupled point along
   x + v (t - t_k) within a call); its samples dated half a step before the call's end
   (RK2's last stage). The spar's surge force over the last two periods from symcable at N
   segments a line against MoorDyn at 2N, beside MoorDyn's own change from N to 2N.
4. Time per host step (T/100 = 0.12 s of motion): Python's ``Coupling.step``, the C
   library's ``sc_step`` (its host's run over its steps) and MoorDyn's 120 calls; and
   MoorDyn at 5 and 20 ms steps, where stable, with its change from the 1 ms run.

``python run.py`` (N = 20 and 40, 4 periods) writes ``results.json``; ``--quick`` (N = 8
and 16, 2 periods) into ``out/``.
"""
from __future__ import annotations

import argparse
import json
import math
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

import symcable as sc
from symcable.scene.load import scene_to_toml

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent))
import moordyn_driver  # noqa: E402

DEPTH, RADIUS, LENGTH = 320.0, 853.87, 902.2
FAIR_R, FAIR_Z = 5.2, -70.0
#: MoorDyn line type: Diam (m), Mass/m (kg/m), EA (N), BA/-zeta, Cd, Ca, CdAx, CaAx
CHAIN = {"Diam": 0.09, "Mass": 77.7066, "EA": 3.84243e8, "BA": -0.8, "Cd": 1.6, "Ca": 1.0,
         "CdAx": 0.1 / math.pi, "CaAx": 0.0}
K_BOT, C_BOT = 3.0e6, 3.0e5
PERIOD = 12.0
#: the spar's motion: surge, sway, heave (m), roll, pitch, yaw (deg); phases (deg)
AMP6 = [4.0, 0.0, 1.0, 0.0, 3.0, 0.0]
PH6 = [0.0, 0.0, 60.0, 0.0, 30.0, 0.0]
ANGLES = [0.0, 120.0, 240.0]
#: MoorDyn steps (s) tried beside its 1 ms run (item 4)
MOORDYN_LONGER = (5e-3, 2e-2)


def fairlead_offsets() -> np.ndarray:
    """(3, 3) m: the fairleads in the spar's axes."""
    return np.array([[FAIR_R * math.cos(math.radians(a)), FAIR_R * math.sin(math.radians(a)),
                      FAIR_Z] for a in ANGLES])


def deck(segments: int, dtM: float = 1e-3) -> str:
    """The MoorDyn v2 deck: three Fixed anchors, three Coupled fairleads, three chains."""
    c = CHAIN
    pts, lines = [], []
    for i, a in enumerate(ANGLES):
        ca_, sa = math.cos(math.radians(a)), math.sin(math.radians(a))
        pts.append(f"{i + 1} Fixed {RADIUS * ca_!r} {RADIUS * sa!r} {-DEPTH!r} 0 0 0 0")
    for i, (x, y, z) in enumerate(fairlead_offsets().tolist()):
        pts.append(f"{i + 4} Coupled {x!r} {y!r} {z!r} 0 0 0 0")
        lines.append(f"{i + 1} chain {i + 1} {i + 4} {LENGTH!r} {int(segments)} -")
    return "\n".join([
        "--------------------- MoorDyn Input File ---------------------",
        "OC3-Hywind's chains on a spar moved by a host (symcable studies/coupling)",
        "---------------------- LINE TYPES ----------------------",
        "TypeName Diam Mass/m EA BA/-zeta EI Cd Ca CdAx CaAx",
        "(name) (m) (kg/m) (N) (N-s/-) (N-m^2) (-) (-) (-) (-)",
        f"chain {c['Diam']!r} {c['Mass']!r} {c['EA']!r} {c['BA']!r} 0.0 {c['Cd']!r} "
        f"{c['Ca']!r} {c['CdAx']!r} {c['CaAx']!r}",
        "---------------------- POINTS ----------------------",
        "ID Attachment X Y Z Mass Volume CdA CA",
        "(#) (-) (m) (m) (m) (kg) (m^3) (m^2) (-)", *pts,
        "---------------------- LINES ----------------------",
        "ID LineType AttachA AttachB UnstrLen NumSegs Outputs",
        "(#) (name) (#) (#) (m) (-) (-)", *lines,
        "---------------------- OPTIONS ----------------------",
        f"{dtM!r} dtM", "9.80665 g", "1025.0 WtrDnsty", f"{DEPTH!r} WtrDpth",
        f"{K_BOT!r} kBot", f"{C_BOT!r} cBot", "0.0 FrictionCoefficient",
        "1 disableOutput", "0 writeLog",
        "--------------------- need this line ------------------", ""])


def points_scene(segments: int) -> dict:
    """The deck as symcable reads it (its fairleads vessel points), the axial drag on
    symcable's reference area."""
    from symcable.scene.moordyn import parse_moordyn
    d = json.loads(json.dumps(dict(parse_moordyn(deck(segments), "spar.txt").scene)))
    (lt,) = d["line_types"].values()
    assert abs(lt["cd_tangential"] - math.pi * CHAIN["CdAx"]) < 1e-12
    return sc.load_scene(d).to_dict()


def body_scene(segments: int, motion: bool) -> dict:
    """The same lines on a spar body: a vessel with the harmonic motion (``motion``), else
    fixed (a host moves it)."""
    d = points_scene(segments)
    fairs = [ln["end_b"] for ln in d["lines"]]
    for ln, off in zip(d["lines"], fairlead_offsets().tolist()):
        ln["end_b"] = f"spar@[{off[0]!r}, {off[1]!r}, {off[2]!r}]"
    for name in fairs:
        del d["points"][name]
    body = {"kind": "fixed", "position": [0.0, 0.0, 0.0]}
    if motion:
        body = {"kind": "vessel", "position": [0.0, 0.0, 0.0],
                "motion": {"kind": "harmonic", "period": PERIOD, "amplitude": AMP6,
                           "phase_deg": PH6}}
    d["bodies"] = {"spar": body}
    return d


def spar_motion(t: float) -> tuple[np.ndarray, np.ndarray]:
    """The spar's pose (m, rad) and velocity (m/s; angular velocity, global axes, rad/s)."""
    a = np.array(AMP6, float)
    a[3:] = np.radians(a[3:])
    w, ph = 2 * math.pi / PERIOD, np.radians(PH6)
    if t <= 0.0:
        r, rd = 0.0, 0.0
    elif t < PERIOD:
        r = 0.5 * (1 - math.cos(math.pi * t / PERIOD))
        rd = 0.5 * math.pi / PERIOD * math.sin(math.pi * t / PERIOD)
    else:
        r, rd = 1.0, 0.0
    q = r * a * np.cos(w * t + ph)
    qd = rd * a * np.cos(w * t + ph) - r * a * w * np.sin(w * t + ph)
    cy, sy, cp, sp = math.cos(q[5]), math.sin(q[5]), math.cos(q[4]), math.sin(q[4])
    om = qd[3] * np.array([cy * cp, sy * cp, -sp]) + qd[4] * np.array([-sy, cy, 0.0]) \
        + qd[5] * np.array([0.0, 0.0, 1.0])
    return q, np.concatenate([qd[:3], om])


def fairleads(t: float) -> tuple[np.ndarray, np.ndarray]:
    """The three fairleads' positions (9,) and velocities (9,) with the spar at t."""
    from symcable.scene.bodies import rotation_rpy
    q, v = spar_motion(t)
    arm = fairlead_offsets() @ rotation_rpy(np.degrees(q[3:])).T
    return (q[:3] + arm).ravel(), (v[:3] + np.cross(v[3:], arm)).ravel()


def spar_load(x9, f9, t: float) -> np.ndarray:
    """The force and moment (about the spar's reference point) of the three fairlead forces."""
    q, _ = spar_motion(t)
    f, x = np.reshape(f9, (3, 3)), np.reshape(x9, (3, 3))
    return np.concatenate([f.sum(axis=0), np.cross(x - q[:3], f).sum(axis=0)])


def relative(a, b) -> float:
    """max |a - b| over b's range per column (columns of round-off range skipped)."""
    a, b = np.asarray(a, float), np.asarray(b, float)
    rng = np.ptp(b, axis=0)
    keep = rng > 1e-6 * np.max(rng)
    return float(np.max(np.max(np.abs(a - b), axis=0)[keep] / rng[keep]))


def python_runs(n: int, dt: float, steps: int) -> dict:
    """simulate, the body coupling and the points coupling, side by side."""
    t0 = time.perf_counter()
    tr = sc.simulate(body_scene(n, True), duration=steps * dt, dt=dt, progress=False)
    t_sim = time.perf_counter() - t0
    ref = np.hstack([np.reshape(tr.outputs["spar.force"], (-1, 3)),
                     np.reshape(tr.outputs["spar.moment"], (-1, 3))])
    body = sc.Coupling(body_scene(n, False), coupled="spar")
    pts = sc.Coupling(points_scene(n))
    got_b, got_p = [body.initialize(np.zeros(6))], []
    x9, _ = fairleads(0.0)
    got_p.append(spar_load(x9, pts.initialize(x9), 0.0))
    walls = []
    for k in range(steps):
        q, v = spar_motion((k + 1) * dt)
        t1 = time.perf_counter()
        got_b.append(body.step(k * dt, dt, q, v))
        walls.append(time.perf_counter() - t1)
        x9, v9 = fairleads((k + 1) * dt)
        got_p.append(spar_load(x9, pts.step(k * dt, dt, x9, v9), (k + 1) * dt))
    return {"time": tr.time, "simulate": ref, "body": np.array(got_b), "points": np.array(got_p),
            "simulate_wall_s": t_sim, "coupling_step_s": float(np.median(walls)),
            "coupling_stats": body.stats, "simulate_substepped": tr.stats["substepped_steps"]}


def coupling_only(n: int, dt: float, steps: int) -> np.ndarray:
    """The body coupling's spar force and moment at n segments a line."""
    body = sc.Coupling(body_scene(n, False), coupled="spar")
    got = [body.initialize(np.zeros(6))]
    for k in range(steps):
        got.append(body.step(k * dt, dt, *spar_motion((k + 1) * dt)))
    return np.array(got)


def c_run(n: int, dt: float, steps: int, quick: bool) -> dict:
    """The C library: exported by the command line, compiled, its host run."""
    cc = shutil.which("cc")
    if cc is None:
        return {"error": "no C compiler"}
    with tempfile.TemporaryDirectory(prefix="symcable_coupling_") as tmp:
        folder = Path(tmp)
        (folder / "spar.toml").write_text(scene_to_toml(sc.load_scene(body_scene(n, False))))
        t0 = time.perf_counter()
        subprocess.run([sys.executable, "-m", "symcable", "codegen", "spar.toml", "--out", ".",
                        "--coupling", "--coupled", "spar"], cwd=folder, check=True,
                       capture_output=True)
        t_export = time.perf_counter() - t0
        opt = "-O0" if quick else "-O2"
        t0 = time.perf_counter()
        subprocess.run([cc, opt, "host.c", "symcable_coupling.c", "symcable_lines.c", "-lm",
                        "-o", "host"], cwd=folder, check=True, capture_output=True)
        t_cc = time.perf_counter() - t0
        a = np.array(AMP6, float)
        a[3:] = np.radians(a[3:])
        args = ["./host", repr(PERIOD), repr(dt)]
        ph = np.radians(PH6)
        amps = ["%.17g" % v for x, p in zip(a, ph) for v in (x, p)]
        walls = {}
        for count in (1, steps):  # the host's start with one step, then with the steps
            t0 = time.perf_counter()
            out = subprocess.run(args + [str(count)] + amps, cwd=folder, check=True,
                                 capture_output=True, text=True).stdout
            walls[count] = time.perf_counter() - t0
    lines = out.strip().splitlines()
    rows = np.array([[float(v) for v in ln.split()] for ln in lines[:-1]])
    # (the host repeats the second half after restoring its saved state: n + n - n // 2
    # steps for n; 2 for 1)
    per_step = (walls[steps] - walls[1]) / (steps + steps - steps // 2 - 2)
    return {"forces": rows[:, 1:], "restore_check": lines[-1], "export_s": t_export,
            "compile_s": t_cc, "compile_flags": opt, "step_s": per_step}


def moordyn_run(n: int, duration: float, dtM: float = 1e-3) -> dict:
    """MoorDyn coupled: the spar's force and moment, its samples' times, the run's wall time."""
    steps = int(round(duration / dtM))
    x0, v0 = fairleads(0.0)

    def calls():
        for k in range(steps):
            x, v = fairleads(k * dtM)
            yield x.tolist(), v.tolist(), k * dtM, dtM

    with moordyn_driver.session({"spar.txt": deck(n, dtM)}, "spar.txt", x0.tolist(),
                                v0.tolist(), prefix="symcable_cpl_") as s:
        held, _ = moordyn_driver.settle(s, x0.tolist(), [0.0] * 9, max_time=200.0, tol=1e-7,
                                        window=5, t_start=-200.0)
        run = moordyn_driver.drive(s, calls())
    tk = (np.arange(steps) + 0.5) * dtM  # RK2's last stage
    loads = np.array([spar_load(fairleads(t)[0], f, t) for t, f in zip(tk, run.force)])
    return {"time": tk, "load": loads, "run_s": run.wall, "settled_s": held}


def run(quick: bool) -> dict:
    n1, n2, periods = (8, 16, 2) if quick else (20, 40, 4)
    dt = PERIOD / 100
    steps = periods * 100
    out = {"segments": [n1, n2], "periods": periods, "dt": dt}
    py = python_runs(n1, dt, steps)
    out["coupling_body_vs_simulate"] = relative(py["body"], py["simulate"])
    out["coupling_points_vs_simulate"] = relative(py["points"], py["simulate"])
    out["python_step_s"] = py["coupling_step_s"]
    out["simulate_s"] = py["simulate_wall_s"]
    out["newton_iterations_per_step"] = py["coupling_stats"]["newton_iterations"] / steps
    # host steps whose Newton iterations needed substeps (in simulate and in the coupling
    # alike): within them the coupled ends follow the cubic through the host's states, not
    # the exact motion
    out["substepped_host_steps"] = py["coupling_stats"]["substepped_steps"]
    out["simulate_substepped_steps"] = py["simulate_substepped"]
    c = c_run(n1, dt, steps, quick)
    if "forces" in c:
        out["c_vs_simulate"] = relative(c["forces"], py["simulate"])
        out.update({f"c_{k}": v for k, v in c.items() if k != "forces"})
    md = {n: moordyn_run(n, steps * dt) for n in (n1, n2)}
    t = py["time"]
    last = t >= t[-1] - 2 * PERIOD - 1e-9
    ref = np.interp(t[last], md[n2]["time"], md[n2]["load"][:, 0])
    rng = float(np.ptp(ref))
    md1 = np.interp(t[last], md[n1]["time"], md[n1]["load"][:, 0])
    out.update(surge_force_range_N=rng,
               symcable_N_vs_moordyn_2N=float(np.max(np.abs(py["body"][last, 0] - ref))) / rng,
               moordyn_N_vs_2N=float(np.max(np.abs(md1 - ref))) / rng,
               symcable_N_vs_moordyn_N=float(np.max(np.abs(py["body"][last, 0] - md1))) / rng)
    mine2 = coupling_only(n2, dt, steps)[last, 0]
    out.update(symcable_2N_vs_moordyn_2N=float(np.max(np.abs(mine2 - ref))) / rng,
               symcable_N_vs_2N=float(np.max(np.abs(py["body"][last, 0] - mine2))) / rng)
    out["moordyn_step_s"] = {str(n): md[n]["run_s"] / steps for n in (n1, n2)}
    # MoorDyn at a longer step of its own: where it is stable, its time per host step and
    # its change from the 1 ms run
    out["moordyn_N_longer_steps"] = {}
    for dtM in MOORDYN_LONGER:
        try:
            m = moordyn_run(n1, steps * dt, dtM)
            f = np.interp(t[last], m["time"], m["load"][:, 0])
            ok = bool(np.all(np.isfinite(f)))
            row = {"step_s": m["run_s"] / steps,
                   "vs_1ms": float(np.max(np.abs(f - md1))) / rng if ok else None}
        except RuntimeError as exc:  # MoorDyn's own failure (unstable)
            row = {"error": str(exc).splitlines()[0]}
        out["moordyn_N_longer_steps"][repr(dtM)] = row
    out["python_vs_moordyn_N_step"] = out["python_step_s"] / out["moordyn_step_s"][str(n1)]
    if "c_step_s" in out:
        out["c_vs_moordyn_N_step"] = out["c_step_s"] / out["moordyn_step_s"][str(n1)]
    return out


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true")
    args = ap.parse_args(argv)
    res = run(args.quick)
    (HERE / "out").mkdir(exist_ok=True)
    path = HERE / "out" / "results_quick.json" if args.quick else HERE / "results.json"
    path.write_text(json.dumps(res, indent=1))
    print(json.dumps(res, indent=1))
    return 0


if __name__ == "__main__":
    sys.exit(main())
