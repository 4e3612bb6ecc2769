"""The body and the tow that the work-precision and stability studies add to their line rows
(studies are scripts, not a package: each puts this folder on ``sys.path`` to import this).

**The lifted module** (a body, periodic): a 20 t, 5 m³ subsea module (inertia 3-5e4 kg m²,
its centre of buoyancy 0.4 m above its centre of gravity, drag areas 6-9 m², added-mass
volumes 3-8 m³) hangs 100 m below a crane tip on a 50 mm steel wire (9 kg/m, EA 2e8 N, Cd 1.2
/ 0.01, Ca 1; 10 segments), lifted at a point 0.2 m ahead of and 1.2 m above its centre of
gravity, in a 0.5 m/s current. The crane tip moves with the vessel: amplitude [1, 0.5, 1.5] m,
phases [0, 30, -90] deg, period T = 8 s. The wire stays taut (top tension 126-182 kN about a
static 153 kN). The module's swing and rotation are lightly damped (by its drag alone): a run
from rest beats about its periodic state with 0.4 % of the tension range for 30 periods and
more, so its periodic state comes from the periodic solvers, not from a time run.

**The tow**: the built-in ``towed_body`` scene (seed 003's 355 m bare + 125 m faired cable
and 9500 kg body at 12 knots through a 270 deg turn of radius 300 m) with the seed's own 9 + 3
elements, a 10 s straight start and 30 s after the turn (269 s in all); not periodic.
"""
from __future__ import annotations

import copy
import math

import numpy as np

import symcable as sc
from symcable.scene import load_scene

PERIOD = 8.0  # s, the module's crane-tip motion
TOW_AFTER, TOW_TAIL = 10.0, 30.0  # s of straight tow before the turn and after it

MODULE = {
    "model": "cable3d",
    "environment": {"gravity": 9.80665, "water_density": 1025.0, "current": [0.5, 0.0, 0.0]},
    "line_types": {"wire": {"EA": 2.0e8, "mass": 9.0, "diameter": 0.05, "cd_normal": 1.2,
                            "cd_tangential": 0.01, "ca_normal": 1.0}},
    "points": {"crane": {"kind": "vessel", "position": [0.0, 0.0, 0.0],
                         "motion": {"kind": "harmonic", "period": PERIOD,
                                    "amplitude": [1.0, 0.5, 1.5],
                                    "phase_deg": [0.0, 30.0, -90.0]}}},
    "bodies": {"module": {"position": [0.0, 0.0, -103.0], "mass": 20000.0, "volume": 5.0,
                          "inertia": [3.0e4, 4.0e4, 5.0e4], "center_of_buoyancy": [0.0, 0.0, 0.4],
                          "cd_area": [6.0, 8.0, 9.0], "ca_volume": [3.0, 4.0, 8.0]}},
    "lines": [{"name": "lift", "end_a": "module@[0.2, 0.0, 1.2]", "end_b": "crane",
               "sections": [{"type": "wire", "length": 100.0, "segments": 10}]}],
}


def module_scene(*, segments: int = 10, ea_factor: float = 1.0, mass: float | None = None,
                 amplitude_factor: float = 1.0, name: str | None = None) -> dict:
    """The lifted module as a scene dict; ``mass`` (kg) replaces the module's 20 t (its
    volume stays: 5 m³ displace 5125 kg)."""
    d = copy.deepcopy(MODULE)
    d["lines"][0]["sections"][0]["segments"] = int(segments)
    d["line_types"]["wire"]["EA"] *= ea_factor
    if mass is not None:
        d["bodies"]["module"]["mass"] = float(mass)
    mo = d["points"]["crane"]["motion"]
    mo["amplitude"] = [a * amplitude_factor for a in mo["amplitude"]]
    d["name"] = name or "lifted module"
    return d


def tow_scene(*, segments: tuple = (9, 3), radius: float | None = None,
              speed: float | None = None, name: str | None = None) -> dict:
    """The built-in tow with ``segments`` (bare, faired), TOW_AFTER s of straight tow; a
    turn ``radius`` (m) and tow ``speed`` (m/s) to change them."""
    d = load_scene(sc.demo_scene_path("towed_body")).to_dict()
    for sec, n in zip(d["lines"][0]["sections"], segments):
        sec["segments"] = int(n)
    mo = d["points"]["ship"]["motion"]
    mo["turns"][0]["after"] = TOW_AFTER
    if radius is not None:
        mo["turns"][0]["radius"] = float(radius)
    if speed is not None:
        mo["speed"] = float(speed)
    d["name"] = name or "towed body"
    return d


def tow_duration(d: dict) -> float:
    """The straight start, the turn and TOW_TAIL s after it, s."""
    mo = d["points"]["ship"]["motion"]
    turn = mo["turns"][0]
    return turn["after"] + turn["radius"] * math.radians(turn["angle"]) / mo["speed"] + TOW_TAIL


def segments(d: dict) -> int:
    """The scene's segments over all its lines."""
    return sum(s["segments"] for ln in d["lines"] for s in ln["sections"])


def moordyn_cfl_step(d: dict, cfl: float = 0.1) -> float:
    """MoorDyn's step at CFL number ``cfl`` over every section of every line, s."""
    out = []
    for ln in d["lines"]:
        for s in ln["sections"]:
            lt = d["line_types"][s["type"]]
            out.append(cfl * (s["length"] / s["segments"]) / math.sqrt(lt["EA"] / lt["mass"]))
    return min(out)


def tow_series(tr) -> dict:
    """The towpoint tension (N) and the body's depth (m) against time (s) of a tow run."""
    return {"time": np.asarray(tr.time, float),
            "tension": np.linalg.norm(np.asarray(tr.points["ship"]["force"], float), axis=1),
            "depth": -np.asarray(tr.bodies["fish"]["position"], float)[:, 2]}


def tow_error(run: dict, ref: dict) -> dict:
    """A tow run's series against the reference's: the largest difference of the towpoint
    tension over the run (this run interpolated onto the reference's samples) over the
    reference's tension range, its extremes' differences over that range, and the body's
    depth at the end (m)."""
    t, T = ref["time"], ref["tension"]
    rng = float(np.ptp(T))
    f = np.interp(t, run["time"], run["tension"])
    return {"error": float(np.max(np.abs(f - T))) / rng,
            "err_t_max": (float(run["tension"].max()) - float(T.max())) / rng,
            "err_t_min": (float(run["tension"].min()) - float(T.min())) / rng,
            "depth_end_m": float(run["depth"][-1] - ref["depth"][-1]), "range_N": rng}
