"""Random scenes of several lines and points (scene version 2) for the fuzz study's cable3d
scenes (:mod:`fuzz3d_scenes`): a buoy (or sinker) between an anchor chain and a riser line, a
clump weight between two lines, three lines meeting at a free point, and any of them in a
current. Each line gets a line type of its own, its EA drawn against what loads it."""
from __future__ import annotations

import math

import numpy as np

from fuzz3d_draws import horizontal, seabed3
from fuzz_draws import (RHO, G, Redraw, drag_coefficients, draw_ea, line_type, log_uniform,
                        segments, weight_of)

def _line_type_for(rng, types: dict, name: str, fam, L: float, point_load: float,
                   applied: float = 0.0) -> None:
    """A line type of its own for one line (``fam`` a family, or a line type drawn
    already): EA with its weight plus what the points it carries load it with stretching it
    at most 5 %, and within the scene's stiffness check (EA <= 0.5e9 x the line's own weight
    and applied end forces)."""
    lt = line_type(rng, fam) if isinstance(fam, str) else fam
    w_l = abs(weight_of(lt)) * L
    ea = draw_ea(rng, w_l + point_load, w_l + applied)
    if ea is None:
        raise Redraw(f"no EA for {name}")
    lt["EA"] = ea
    types[name] = lt


def _line(name, a, b, secs) -> dict:
    return {"name": name, "end_a": a, "end_b": b, "sections": secs}


def _sec(name, L, rng) -> dict:
    return {"type": name, "length": float(L), "segments": segments(rng)}


def gen_buoy(rng):
    """An anchor chain up to a buoy (or a sinker), a rope or wire from it to a fixed or vessel
    point; the buoy sometimes pushed sideways by an applied force."""
    depth = log_uniform(rng, 50.0, 600.0)
    A = np.array([rng.uniform(-500.0, 500.0), rng.uniform(-500.0, 500.0), -depth])
    F = A + rng.uniform(0.3, 1.5) * depth * horizontal(rng.uniform(-math.pi, math.pi))
    F[2] = -rng.uniform(2.0, 0.3 * depth)
    f = rng.uniform(0.2, 0.8)
    B = A + f * (F - A)
    B[2] = A[2] + rng.uniform(0.2, 0.9) * (F[2] - A[2])
    L1 = float(np.linalg.norm(B - A)) * rng.uniform(1.0, 1.8)
    L2 = float(np.linalg.norm(F - B)) * rng.uniform(1.0, 1.5)
    upper = str(rng.choice(["rope", "wire"]))
    chain = line_type(rng, "chain")
    w1 = abs(weight_of(chain))
    sinker = rng.uniform() < 0.25
    lift = (w1 * L1) * log_uniform(rng, 0.3, 3.0)
    volume = rng.uniform(0.5, 20.0)
    mass = RHO * volume + (lift / G if sinker else -lift / G)
    if mass < 0:
        mass, volume = 0.0, lift / (RHO * G)
    push = None
    if rng.uniform() < 0.4:
        push = lift * rng.uniform(0.05, 0.5) * horizontal(rng.uniform(-math.pi, math.pi))
    types = {}
    _line_type_for(rng, types, "chain1", chain, L1, lift)
    _line_type_for(rng, types, f"{upper}2", upper, L2, lift,
                   float(np.linalg.norm(push)) if push is not None else 0.0)
    buoy = {"kind": "free", "position": list(B), "mass": float(mass), "volume": float(volume)}
    if push is not None:
        buoy["force"] = [float(v) for v in push]
    fair = {"kind": str(rng.choice(["fixed", "vessel"])), "position": list(F)}
    if fair["kind"] == "vessel" and rng.uniform() < 0.5:   # statics must ignore it
        fair["motion"] = {"period": rng.uniform(8.0, 20.0), "amplitude": [2.0, 1.0, 1.0]}
    scene = {**seabed3(rng, depth), "line_types": types,
             "points": {"anchor": {"kind": "fixed", "position": list(A)}, "buoy": buoy,
                        "fairlead": fair},
             "lines": [_line("lower", "anchor", "buoy", [_sec("chain1", L1, rng)]),
                       _line("upper", "buoy", "fairlead", [_sec(f"{upper}2", L2, rng)])]}
    what = "sinker" if sinker else "buoy"
    return f"{what}{', pushed sideways' if push is not None else ''}", scene


def gen_clump(rng):
    """Anchor - chain - clump weight - line (one or two sections) - fairlead; the clump may
    come to rest on the bed."""
    depth = log_uniform(rng, 30.0, 600.0)
    A = np.array([rng.uniform(-500.0, 500.0), rng.uniform(-500.0, 500.0), -depth])
    F = A + rng.uniform(0.5, 2.0) * depth * horizontal(rng.uniform(-math.pi, math.pi))
    F[2] = -rng.uniform(2.0, 0.3 * depth)
    C = A + rng.uniform(0.2, 0.7) * (F - A)
    C[2] = A[2] + rng.uniform(0.0, 0.5) * (F[2] - A[2])
    L1 = float(np.linalg.norm(C - A)) * rng.uniform(1.0, 1.6)
    L2 = float(np.linalg.norm(F - C)) * rng.uniform(1.0, 1.4)
    chain = line_type(rng, "chain")
    weight = abs(weight_of(chain)) * (L1 + L2) * log_uniform(rng, 0.05, 2.0)
    volume = rng.uniform(0.0, 1.0)
    mass = weight / G + RHO * volume
    types = {}
    _line_type_for(rng, types, "chain1", chain, L1, weight)
    two = rng.uniform() < 0.4
    if two:
        fam = str(rng.choice(["wire", "rope"]))
        _line_type_for(rng, types, f"{fam}2", fam, 0.6 * L2, weight)
        _line_type_for(rng, types, "chain3", "chain", 0.4 * L2, weight)
        secs = [_sec(f"{fam}2", 0.6 * L2, rng), _sec("chain3", 0.4 * L2, rng)]
    else:
        _line_type_for(rng, types, "chain2", "chain", L2, weight)
        secs = [_sec("chain2", L2, rng)]
    scene = {**seabed3(rng, depth), "line_types": types,
             "points": {"anchor": {"kind": "fixed", "position": list(A)},
                        "clump": {"kind": "free", "position": list(C), "mass": float(mass),
                                  "volume": float(volume)},
                        "fairlead": {"kind": "fixed", "position": list(F)}},
             "lines": [_line("lower", "anchor", "clump", [_sec("chain1", L1, rng)]),
                       _line("upper", "clump", "fairlead", secs)]}
    return f"clump, upper line {'2 sections' if two else 'chain'}", scene


def gen_three_lines(rng):
    """Three lines at one free point: a buoy held down by three anchors; a clump hung from
    two fixed points with a third line down to an anchor; a bridle of two anchor lines and a
    fairlead line at a massless joint."""
    variant = str(rng.choice(["buoy on three anchors", "clump on two points and an anchor",
                              "bridle at a massless joint"]))
    depth = log_uniform(rng, 50.0, 500.0)
    P = np.array([rng.uniform(-300.0, 300.0), rng.uniform(-300.0, 300.0),
                  -depth * rng.uniform(0.3, 0.8)])
    phi0 = rng.uniform(-math.pi, math.pi)
    ends, fams, kinds = [], [], []
    for k in range(3):
        phi = phi0 + 2.0 * math.pi * k / 3.0 + rng.uniform(-0.4, 0.4)
        R = depth * rng.uniform(0.5, 2.0)
        E = P + R * horizontal(phi)
        on_bed = variant == "buoy on three anchors" or (k == 2 and variant.startswith("clump")) \
            or (k < 2 and variant.startswith("bridle"))
        E[2] = -depth if on_bed else -rng.uniform(2.0, 0.2 * depth)
        ends.append(E)
        fams.append("chain" if on_bed else str(rng.choice(["wire", "rope"])))
        kinds.append("fixed")
    lengths = [float(np.linalg.norm(E - P)) * rng.uniform(1.0, 1.6) for E in ends]
    drawn = [line_type(rng, fam) for fam in fams]
    w = max(abs(weight_of(lt)) for lt in drawn)
    if variant.startswith("buoy"):
        volume = w * sum(lengths) * log_uniform(rng, 0.5, 3.0) / (RHO * G)
        point = {"kind": "free", "position": list(P), "mass": 0.2 * RHO * volume, "volume": volume}
        load = (RHO * 0.8 * volume) * G
    elif variant.startswith("clump"):
        load = w * sum(lengths) * log_uniform(rng, 0.1, 2.0)
        point = {"kind": "free", "position": list(P), "mass": load / G}
    else:
        load = 0.0
        point = {"kind": "free", "position": list(P), "mass": 0.0}
    types, lines = {}, []
    for k, (E, L, fam) in enumerate(zip(ends, lengths, fams)):
        name = f"{fam}{k}"
        _line_type_for(rng, types, name, drawn[k], L, load)
        lines.append(_line(f"line{k}", f"end{k}", "P", [_sec(name, L, rng)]))
    points = {f"end{k}": {"kind": kinds[k], "position": list(E)} for k, E in enumerate(ends)}
    points["P"] = point
    return variant, {**seabed3(rng, depth), "line_types": types, "points": points, "lines": lines}


def gen_system_current(rng):
    """One of the systems above in a uniform current of any direction (0.1-1.5 m/s); the
    lines get drag coefficients, a buoy a sphere's diameter and Cd."""
    kind = str(rng.choice(["buoy", "clump", "three lines"]))
    variant, scene = {"buoy": gen_buoy, "clump": gen_clump, "three lines": gen_three_lines}[kind](rng)
    u = rng.uniform(0.1, 1.5) * horizontal(rng.uniform(-math.pi, math.pi))
    scene["environment"]["current"] = [float(u[0]), float(u[1]), 0.0]
    for lt in scene["line_types"].values():
        drag_coefficients(rng, lt)
    for pt in scene["points"].values():
        if pt["kind"] == "free" and pt.get("volume", 0.0) > 0:
            pt["diameter"] = float((6.0 * pt["volume"] / math.pi) ** (1.0 / 3.0))
            pt["cd"] = rng.uniform(0.3, 1.0)
    return variant + ", in a current", scene
