"""Frequency domain against time domain and MoorPy: OC3's three chains on a spar moved by its
RAOs in a JONSWAP sea.

The scene: OC3-Hywind's mooring (three 902.2 m chains, 320 m depth, fairleads 70 m below the
waterline at 5.2 m radius) on a vessel whose RAOs are representative of a spar (surge
falling from 4 m/m at 0.05 rad/s to nothing at 3 rad/s, heave and pitch small above their
resonances; not OC3's own, which are not public data here), frictionless seabed; the sea
JONSWAP Hs 6 m, Tp 10 s, gamma 3.3, from 0 deg (along line0).

Measured, side by side in one run, every figure through the public API at its defaults or a
documented option:

1. ``sc.solve_frequency_domain(scene)`` (waves on the lines and the vessel's motion);
2. ``sc.simulate(scene, duration, dt)``: the time domain over ``duration`` s of sea, its
   first 200 s (ramp and transient) dropped; the standard deviation of each fairlead's
   segment axial force;
3. fatigue: rainflow counting of the time run's fairlead segment against the frequency
   domain's Dirlik and narrow-band damage (DNV-OS-E301 studless chain, d 0.09 m);
4. MoorPy's ``Line.dynamicSolve`` on each line with the same fairlead RAOs (no waves on the
   line: MoorPy's model), against ``solve_frequency_domain(scene, line_waves=False)``.

``python fd_vs_td.py`` (one hour of sea) writes ``results.json`` and ``fd_vs_td.png``
(``--quick`` writes into ``out/``);
``--quick`` (ten minutes of sea, 30 components, 8 segments a line) is what the tests run.
"""
from __future__ import annotations

import argparse
import json
import math
import sys
import time
from pathlib import Path

import numpy as np

import symcable as sc
from symcable.analytic.fatigue import nominal_area, rainflow_damage

HERE = Path(__file__).resolve().parent
OMEGAS = [0.05, 0.2, 0.4, 0.6, 0.8, 1.0, 1.5, 3.0]
RAO_AMP = [[4.0, 0, 1.0, 0, 2.0, 0], [1.5, 0, 0.9, 0, 1.2, 0], [0.8, 0, 0.3, 0, 0.8, 0],
           [0.5, 0, 0.1, 0, 0.5, 0], [0.3, 0, 0.05, 0, 0.3, 0], [0.2, 0, 0.02, 0, 0.2, 0],
           [0.05, 0, 0.005, 0, 0.05, 0], [0.0, 0, 0.0, 0, 0.0, 0]]
RAO_PHASE = [[90.0, 0, 0.0, 0, 90.0, 0]] * len(OMEGAS)


def scene(segments: int, components: int) -> dict:
    """The spar's three chains (module docstring)."""
    d = {"name": "OC3 chains on a spar in a JONSWAP sea", "model": "cable3d",
         "environment": {"depth": 320.0, "waves": {
             "kind": "jonswap", "hs": 6.0, "tp": 10.0, "gamma": 3.3,
             "components": components, "seed": 1}},
         "seabed": {"stiffness": 1e5, "friction": 0.0},
         "line_types": {"chain": {"mass": 77.7066, "diameter": 0.09, "weight": 698.094,
                                  "EA": 3.84243e8, "cd_normal": 1.6, "cd_tangential": 0.1,
                                  "ca_normal": 1.0}},
         "points": {}, "lines": [],
         "bodies": {"spar": {"kind": "vessel", "position": [0.0, 0.0, 0.0], "motion": {
             "kind": "rao", "omegas": OMEGAS, "amplitude": RAO_AMP,
             "phase_deg": RAO_PHASE}}}}
    for i, a in enumerate((0.0, 120.0, 240.0)):
        c, s = math.cos(math.radians(a)), math.sin(math.radians(a))
        d["points"][f"anchor{i}"] = {"kind": "fixed",
                                     "position": [853.87 * c, 853.87 * s, -320.0]}
        d["lines"].append({"name": f"line{i}", "end_a": f"anchor{i}",
                           "end_b": f"spar@[{5.2 * c}, {5.2 * s}, -70.0]",
                           "sections": [{"type": "chain", "length": 902.2,
                                         "segments": segments}]})
    return d


def moorpy_std(d: dict, fd_dry) -> dict:
    """MoorPy's ``dynamicSolve`` fairlead-segment standard deviation per line, N, with the
    fairleads' RAOs of symcable's vessel (translations, rotation linearised) and the sea's
    spectrum at its components."""
    import moorpy as mp
    from symcable.api.frequency import _vessel_motion
    from symcable.scene.waves import WaveComponents
    s = sc.load_scene(d)
    w = s.environment.waves
    sea = w.components_in(320.0, 9.80665)
    order = np.argsort(sea.omega)
    om = sea.omega[order]
    S = w.spectrum(om)
    unit = WaveComponents(np.ones(sea.n), sea.omega, sea.k, np.zeros(sea.n), sea.direction)
    lt = d["line_types"]["chain"]
    out = {}
    for ln in s.lines:
        ms = mp.System(depth=320.0, rho=1025.0, g=9.80665)
        ms.lineTypes["chain"] = {"name": "chain", "d_vol": lt["diameter"], "m": lt["mass"],
                                 "w": lt["weight"], "EA": lt["EA"], "MBL": 1e9,
                                 "Cd": lt["cd_normal"], "CdAx": lt["cd_tangential"],
                                 "Ca": lt["ca_normal"], "CaAx": 0.0, "material": "chain",
                                 "input_d": lt["diameter"], "input_type": {}}
        a_pos = np.array(s.points[ln.end_a].position, float)
        b_pos = s.bodies["spar"].world(ln.end_b.offset)
        ms.addPoint(1, a_pos)
        ms.addPoint(1, b_pos)
        ms.addLine(902.2, "chain", nSegs=ln.n_segments, pointA=1, pointB=2)
        ms.initialize()
        ms.solveEquilibrium()
        line = ms.lineList[0]
        # MoorPy's convention is x = Re(X e^(+i omega t)), symcable's e^(-i omega t): the same
        # motion is the conjugate
        rao_b = np.conj(_vessel_motion(s, ln.end_b, unit)[order])
        kbot = 1e5 * lt["diameter"] * 902.2 / ln.n_segments
        _, _, T_std, *_ = line.dynamicSolve(om, S, np.zeros_like(rao_b), rao_b, 320.0,
                                            kbot=kbot, cbot=0.0)
        out[ln.name] = float(T_std[-1])
    return out


def run(quick: bool) -> dict:
    segments, components, duration = (8, 30, 600.0) if quick else (20, 100, 3800.0)
    d = scene(segments, components)
    (HERE / "out").mkdir(exist_ok=True)
    res = {"segments": segments, "components": components, "duration": duration}
    t0 = time.perf_counter()
    fd = sc.solve_frequency_domain(d)
    res["fd_time"] = time.perf_counter() - t0
    t0 = time.perf_counter()
    dry = sc.solve_frequency_domain(d, line_waves=False)
    res["fd_dry_time"] = time.perf_counter() - t0
    t0 = time.perf_counter()
    td = sc.simulate(d, duration=duration, dt=0.1, progress=False)
    res["td_time"] = time.perf_counter() - t0
    keep = td.time >= 200.0
    res["td_warnings"] = list(td.warnings)
    try:
        mp_std = moorpy_std(d, dry)
    except Exception as exc:  # MoorPy's own failure is reported, not hidden
        mp_std = {"error": f"{type(exc).__name__}: {exc}"}
    res["lines"] = {}
    kept = float(td.time[keep][-1] - td.time[keep][0])
    for name in fd.lines:
        td_std = float(np.std(td.lines[name].axial_force[keep, -1]))
        rf = rainflow_damage(td.lines[name].axial_force[keep, -1], "dnv-studless-chain",
                             area=nominal_area(0.09, "chain"))["damage"]
        spec = fd.damage(name, diameter=0.09, duration=kept)
        own = _own_dirlik(td.lines[name].axial_force[keep, -1], td.time[1] - td.time[0], kept)
        row = {"fd_std": float(fd.lines[name].std[-1]), "td_std": td_std,
               "fd_over_td": float(fd.lines[name].std[-1]) / td_std,
               "fd_dry_std": float(dry.lines[name].std[-1]),
               "moorpy_std": mp_std.get(name), "mean": float(fd.lines[name].mean[-1]),
               "damage_rainflow_td": rf, "damage_dirlik_fd": spec["dirlik"],
               "damage_narrow_band_fd": spec["narrow_band"],
               "dirlik_over_rainflow": spec["dirlik"] / rf,
               "dirlik_of_td_spectrum_over_rainflow": own / rf}
        if row["moorpy_std"]:
            row["fd_dry_over_moorpy"] = row["fd_dry_std"] / row["moorpy_std"]
        res["lines"][name] = row
    if "error" in mp_std:
        res["moorpy_error"] = mp_std["error"]
    res["time_ratio"] = res["td_time"] / res["fd_time"]
    _plot(fd, td, keep, (HERE / "out" / "fd_vs_td_quick.png") if quick else HERE / "fd_vs_td.png")
    return res


def _own_dirlik(x, dt: float, duration: float) -> float:
    """Dirlik's damage from the time run's own spectrum (its periodogram's moments): the
    spectral method's error alone, without the frequency domain's."""
    from symcable.analytic.fatigue import dirlik_damage
    y = x - x.mean()
    P = np.abs(np.fft.rfft(y)) ** 2 / y.size ** 2 * 2.0  # variance per bin
    w = 2 * np.pi * np.fft.rfftfreq(y.size, dt)
    m = {k: float(np.sum(w ** k * P)) for k in (0, 1, 2, 4)}
    return dirlik_damage(m[0], m[1], m[2], m[4], duration, "dnv-studless-chain",
                         area=nominal_area(0.09, "chain"))


def _plot(fd, td, keep, path):
    """End B's axial force spectrum of line0: the time run's (Welch) and the frequency
    domain's."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from scipy.signal import welch
    fig, ax = plt.subplots(figsize=(7.5, 4.2))
    for name, ls in (("line0", "-"), ("line1", "--")):
        x = td.lines[name].axial_force[keep, -1]
        dt = td.time[1] - td.time[0]
        f, P = welch(x - x.mean(), fs=1.0 / dt, nperseg=min(4096, x.size))
        ax.plot(2 * np.pi * f, P / (2 * np.pi) / 1e6, ls, color="C0", label=f"{name}, time domain")
        ln = fd.lines[name]
        om = fd.omega
        order = np.argsort(om)
        dw = np.gradient(om[order])
        Sfd = (np.abs(ln.rao[order, -1]) * fd.amplitude[order]) ** 2 / (2 * dw)
        ax.plot(om[order], Sfd / 1e6, ls, color="C1", label=f"{name}, frequency domain")
    ax.set_xlim(0.2, 2.0)
    ax.set_xlabel("angular frequency (rad/s)")
    ax.set_ylabel("fairlead axial force spectrum (kN² s/rad)")
    ax.set_title("OC3 chains on a spar, JONSWAP Hs 6 m Tp 10 s")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=130)
    plt.close(fig)


def study_main(doc: str, runner, name: str, argv=None) -> int:
    """The study scripts' command line: ``--quick`` runs ``runner(True)`` into
    ``out/NAME_quick.json``, else ``runner(False)`` into ``NAME.json``; prints the result."""
    ap = argparse.ArgumentParser(description=doc.splitlines()[0])
    ap.add_argument("--quick", action="store_true")
    args = ap.parse_args(argv)
    res = runner(args.quick)
    (HERE / "out").mkdir(exist_ok=True)
    out = (HERE / "out" / f"{name}_quick.json") if args.quick else HERE / f"{name}.json"
    out.write_text(json.dumps(res, indent=1))
    print(json.dumps(res, indent=1))
    return 0


def main(argv=None) -> int:
    return study_main(__doc__, run, "results", argv)


if __name__ == "__main__":
    sys.exit(main())
