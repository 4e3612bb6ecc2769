"""Seeded random planar scenes for the fuzz study, as the dicts ``symcable.solve_static`` takes.

Every scene is ``{"id", "class", "variant", "scene"}``; ``scene`` is the plain dict (JSON-able:
floats, ints, strings, lists). Scene ``i`` of a run is drawn from its own generator seeded with
``(seed, i)``, and the classes are assigned by a stratified schedule (largest remainder of
``CLASSES``' proportions times the number of scenes, then shuffled by ``seed``), so a run of
any size has the stated proportions and replaying one scene needs only its index.

Ranges (what a user may give): EA 1e5-1e10 N (log-uniform, then kept within the documented
scene checks: strain under the line's own weight |w| L / EA <= 5 %, EA <= 0.5e9 times the
line's load, ends no further apart than L (1 + max_strain)); lengths 5-2000 m; chain, wire,
rope, near-neutral (|w| down to 1e-4 of the displaced water's weight), buoyant and weightless
line types and cables in air; chord/length 0.2-0.999, taut and stretched, exactly vertical and
near-vertical (span 1e-7-3e-2 of the length); a flat seabed (penalty stiffness 1e4-1e7 Pa/m)
with the anchor on it, both ends on it, both ends above it (U-shaped lines touching down) and
fully slack lines with chain lying at zero tension; current up to 2 m/s; bending (EI from
1e-8 to 1 times |w| L^3, rods pinned or clamped, cantilevers); free ends with and without an
end force; 2-3 sections (chain-wire-chain moorings, lazy waves with a buoyant middle); 1 to
60 segments (1, 2 and 3 segments 3 %, 3 % and 2 % of the scenes per section, else
log-uniform in 4-60).
"""
from __future__ import annotations

import math

import numpy as np

from fuzz_draws import (EA_RANGE, MAX_STRAIN, RHO, Redraw, bending_stiffness, current_env,
                        draw_sections, drag_coefficients, end_force, env_seabed, finish_types,
                        flip_ends, free_end_line,
                        line_type, log_uniform, origin, pinned, polar, segments, single,
                        taut_ratio, weight_of, weight_strain)

#: class -> share of the scenes (sums to 1)
CLASSES = {
    "taut": 0.08, "slack": 0.10, "vertical": 0.05, "near_vertical": 0.04,
    "seabed_mooring": 0.12, "seabed_fully_slack": 0.06, "seabed_u": 0.04, "seabed_flat": 0.02,
    "weight_extremes": 0.06, "current": 0.08, "bending": 0.10, "cantilever": 0.03,
    "free_end": 0.10, "multi_section": 0.12,
}


# ----------------------------------------------------------------------------- classes
def gen_two_point(rng, cls: str) -> tuple[str, dict]:
    """taut, slack, vertical, near_vertical: one section, pinned-pinned, no seabed."""
    fam = str(rng.choice(["chain", "wire", "rope"]))
    L = log_uniform(rng, 5.0, 2000.0)
    types = {fam: line_type(rng, fam)}
    finish_types(rng, types, {fam: L})
    c = weight_strain(types, fam, L)
    a = origin(rng)
    if cls == "taut":
        r, theta = taut_ratio(rng, c), rng.uniform(-math.pi, math.pi)
        variant = "stretched" if r > 1.0 else "nearly taut"
    elif cls == "slack":
        r, theta = rng.uniform(0.2, 0.97), rng.uniform(-math.pi, math.pi)
        variant = "slack"
    else:
        up = rng.uniform() < 0.5
        r = rng.uniform(0.2, 0.999) if rng.uniform() < 0.75 else taut_ratio(rng, c)
        theta = math.pi / 2 if up else -math.pi / 2
        variant = ("taut " if r >= 0.999 else "folded ") + ("B above" if up else "B below")
    b = a + polar(r * L, theta)
    if cls == "vertical":
        b[0] = a[0]
    elif cls == "near_vertical":
        b[0] = a[0] + L * log_uniform(rng, 1e-7, 3e-2) * rng.choice([-1.0, 1.0])
    return variant, single(types, fam, L, segments(rng), pinned(a), pinned(b))


def gen_seabed(rng, cls: str) -> tuple[str, dict]:
    """Anchor on the seabed (mooring, fully slack), U-shaped touching down, flat on the bed."""
    fam = str(rng.choice(["chain", "chain", "wire"]))
    types = {fam: line_type(rng, fam)}
    depth = log_uniform(rng, 20.0, 1000.0)
    if cls in ("seabed_mooring", "seabed_fully_slack"):
        h = depth * rng.uniform(0.05, 0.95)
        L = h * log_uniform(rng, 1.05, 4.0)
        finish_types(rng, types, {fam: L})
        if cls == "seabed_mooring":
            span = rng.uniform(0.3, 1.0) * math.sqrt(L * L - h * h)
            if rng.uniform() < 0.2:  # at or just past the taut limit
                span = math.sqrt(L * L - h * h) * rng.uniform(1.0, 1.0 + weight_strain(types, fam, L))
            variant = "anchor on the bed"
        else:
            span = rng.uniform(0.0, 0.95) * (L - h)
            variant = "fully slack, chain on the bed"
        a = np.array([rng.uniform(-1000.0, 1000.0), -depth])
        b = a + np.array([span * rng.choice([-1.0, 1.0]), h])
        scene = single(types, fam, L, segments(rng), pinned(a), pinned(b), **env_seabed(rng, depth))
        if rng.uniform() < 0.3:
            flip_ends(scene)
            variant += ", anchor is end B"
        return variant, scene
    if cls == "seabed_flat":
        L = log_uniform(rng, 10.0, 1000.0)
        finish_types(rng, types, {fam: L})
        r = rng.uniform(0.5, 1.0) if rng.uniform() < 0.6 else taut_ratio(rng, weight_strain(types, fam, L))
        a = np.array([rng.uniform(-1000.0, 1000.0), -depth])
        b = a + np.array([r * L * rng.choice([-1.0, 1.0]), 0.0])
        return ("flat, slack" if r < 1 else "flat, stretched"), single(
            types, fam, L, segments(rng), pinned(a), pinned(b), **env_seabed(rng, depth))
    # seabed_u: both ends above the bed, the free catenary dips below it
    from symcable.analytic import elastic_catenary
    L = log_uniform(rng, 20.0, 1500.0)
    finish_types(rng, types, {fam: L})
    w = weight_of(types[fam])
    span, height = rng.uniform(0.2, 0.9) * L, rng.uniform(-0.3, 0.3) * L
    span = min(span, 0.95 * math.sqrt(max(L * L - height * height, 0.0)))
    sol = elastic_catenary(span, height, L, types[fam]["EA"], w)
    z = sol.positions(np.linspace(0.0, L, 801))[:, 1]
    z_low = min(0.0, height)
    bed = z.min() + rng.uniform(0.1, 0.9) * (z_low - z.min())
    a = np.array([rng.uniform(-1000.0, 1000.0), rng.uniform(-100.0, 0.0)])
    b = a + np.array([span, height])
    return "U-shaped, touching down", single(types, fam, L, segments(rng), pinned(a), pinned(b),
                                              **env_seabed(rng, -(a[1] + bed)))


def gen_weight_extremes(rng) -> tuple[str, dict]:
    variant = str(rng.choice(["near-neutral slack", "buoyant slack", "weightless taut",
                              "in air slack", "in air taut"]))
    L = log_uniform(rng, 5.0, 1000.0)
    rho = 0.0 if variant.startswith("in air") else RHO
    fam = {"near-neutral slack": "neutral", "buoyant slack": "buoyant",
           "weightless taut": "weightless"}.get(variant, str(rng.choice(["chain", "wire"])))
    types = {fam: line_type(rng, fam)}
    extra = {"environment": {"water_density": 0.0}} if rho == 0.0 else {}
    if fam == "weightless":
        types[fam]["EA"] = log_uniform(rng, *EA_RANGE)
        r = 1.0 + log_uniform(rng, 1e-6, 0.5 * MAX_STRAIN)
    else:
        finish_types(rng, types, {fam: L}, rho=rho)
        c = weight_strain(types, fam, L, rho)
        r = taut_ratio(rng, c) if variant.endswith("taut") else rng.uniform(0.2, 0.97)
    a = origin(rng)
    b = a + polar(r * L, rng.uniform(-math.pi, math.pi))
    return variant, single(types, fam, L, segments(rng), pinned(a), pinned(b), **extra)


def gen_current(rng) -> tuple[str, dict]:
    """Suspended lines (one to three sections) in a current, pinned-pinned, no seabed."""
    n_sec = int(rng.choice([1, 1, 2, 3]))
    fams = [str(rng.choice(["chain", "wire", "rope"])) for _ in range(n_sec)]
    types, lengths, secs = draw_sections(rng, fams, 5.0, 600.0, drag=True)
    finish_types(rng, types, lengths)
    L = sum(lengths.values())
    r = rng.uniform(0.3, 0.99)
    a = origin(rng)
    b = a + polar(r * L, rng.uniform(-math.pi, math.pi))
    return f"{n_sec} section(s)", {"environment": current_env(rng), "line_types": types,
                                   "sections": secs, "end_a": pinned(a), "end_b": pinned(b)}


def gen_bending(rng) -> tuple[str, dict]:
    """Rods with EI > 0: pinned or clamped ends; taut, slack, vertical, weightless buckled."""
    variant = str(rng.choice(["taut", "slack", "slack", "vertical", "weightless buckled"]))
    L = log_uniform(rng, 5.0, 500.0)
    fam = "weightless" if variant == "weightless buckled" else "rod"
    types = {"rod": line_type(rng, fam)}
    if fam == "weightless":
        types["rod"]["EA"] = log_uniform(rng, *EA_RANGE)
    else:
        finish_types(rng, types, {"rod": L})
    w = abs(weight_of(types["rod"]))
    types["rod"]["EI"] = bending_stiffness(rng, w if w > 0 else 10.0, L)
    if variant == "taut":
        r, theta = taut_ratio(rng, weight_strain(types, "rod", L)), rng.uniform(-math.pi, math.pi)
    elif variant == "vertical":
        r, theta = rng.uniform(0.2, 0.99), float(rng.choice([-math.pi / 2, math.pi / 2]))
    else:
        r, theta = rng.uniform(0.3, 0.97), rng.uniform(-math.pi, math.pi)
    a = origin(rng)
    b = a + polar(r * L, theta)
    if variant == "vertical":
        b[0] = a[0]
    ends = [pinned(a), pinned(b)]
    cond = str(rng.choice(["pinned-pinned", "pinned-pinned", "clamped-pinned", "clamped-clamped"]))
    for k in range(cond.count("clamped")):
        ends[k]["condition"] = "clamped"
        ends[k]["angle_deg"] = math.degrees(theta) + rng.uniform(-30.0, 30.0)
    return f"{variant}, {cond}", single(types, "rod", L, segments(rng), *ends)


def gen_cantilever(rng) -> tuple[str, dict]:
    L = log_uniform(rng, 2.0, 200.0)
    types = {"rod": line_type(rng, "rod")}
    w_l = abs(weight_of(types["rod"])) * L
    force = end_force(rng, w_l) if rng.uniform() < 0.5 else None
    finish_types(rng, types, {"rod": L}, extra_load=math.hypot(*force) if force else 0.0)
    types["rod"]["EI"] = bending_stiffness(rng, abs(weight_of(types["rod"])), L)
    a = origin(rng)
    end_a = {"condition": "clamped", "position": [float(a[0]), float(a[1])],
             "angle_deg": rng.uniform(-180.0, 180.0)}
    end_b = {"condition": "free"}
    if force:
        end_b["force"] = force
    return ("tip force" if force else "own weight"), single(types, "rod", L, segments(rng), end_a, end_b)


def gen_free_end(rng) -> tuple[str, dict]:
    """Hanging lines with a free end: no force, an end force, in a current, onto a seabed,
    weightless with a force, and weightless with none (no load at all: any shape balances, so
    the right answer is a clean error)."""
    variant, L, fam, types, w_l = free_end_line(rng)
    force = None
    if variant in ("end force", "weightless, end force"):
        force = end_force(rng, max(w_l, 1e3))
    extra = {}
    a = origin(rng)
    if variant == "current":
        drag_coefficients(rng, types[fam])
        extra["environment"] = current_env(rng)
    if variant == "seabed":
        depth = L * rng.uniform(0.2, 0.95)
        a = np.array([rng.uniform(-1000.0, 1000.0), -depth * rng.uniform(0.0, 0.3)])
        extra.update(env_seabed(rng, depth))
        if rng.uniform() < 0.5:
            force = [float(rng.uniform(-1.0, 1.0) * w_l), 0.0]
    if fam == "weightless":   # with no end force the shape is undetermined: a clean error is right
        types[fam]["EA"] = log_uniform(rng, EA_RANGE[0], min(EA_RANGE[1], 0.5e9 * math.hypot(*force))
                                       if force else EA_RANGE[1])
    else:
        finish_types(rng, types, {fam: L}, extra_load=math.hypot(*force) if force else 0.0)
    free = {"condition": "free"}
    if force is not None:
        free["force"] = force
    scene = single(types, fam, L, segments(rng), pinned(a), free, **extra)
    if rng.uniform() < 0.3:
        flip_ends(scene)
        variant += ", end A free"
    return variant, scene


def gen_multi_section(rng) -> tuple[str, dict]:
    """Chain-wire-chain moorings (anchor on the bed or suspended) and lazy waves."""
    variant = str(rng.choice(["mooring on the bed", "mooring on the bed", "suspended", "lazy wave"]))
    if variant == "lazy wave":
        fams = ["chain", "buoyant", "wire"]
    else:
        fams = ["chain", "wire", "chain"] if rng.uniform() < 0.7 else ["chain", "wire"]
    types, lengths, secs = draw_sections(rng, fams, 10.0, 600.0)
    finish_types(rng, types, lengths)
    L = sum(lengths.values())
    extra = {}
    if variant == "suspended":
        a = origin(rng)
        b = a + polar(rng.uniform(0.3, 0.99) * L, rng.uniform(-math.pi, math.pi))
    else:
        depth = L * rng.uniform(0.2, 0.8)
        h = depth * rng.uniform(0.3, 0.95)
        a = np.array([rng.uniform(-1000.0, 1000.0), -depth])
        b = a + np.array([rng.uniform(0.1, 0.98) * math.sqrt(L * L - h * h), h])
        extra = env_seabed(rng, depth)
    scene = {"line_types": types, "sections": secs, "end_a": pinned(a), "end_b": pinned(b)}
    scene.update(extra)
    if rng.uniform() < 0.3:
        flip_ends(scene)
        variant += ", reversed"
    return f"{variant}, {len(fams)} sections", scene


def generate_one(rng, cls: str) -> tuple[str, dict]:
    if cls in ("taut", "slack", "vertical", "near_vertical"):
        return gen_two_point(rng, cls)
    if cls.startswith("seabed"):
        return gen_seabed(rng, cls)
    return {"weight_extremes": gen_weight_extremes, "current": gen_current,
            "bending": gen_bending, "cantilever": gen_cantilever, "free_end": gen_free_end,
            "multi_section": gen_multi_section}[cls](rng)


# ----------------------------------------------------------------------------- the set
def stratified(classes: dict, n: int, rng) -> list[str]:
    """Classes of n scenes in the proportions ``classes`` (class -> share, summing to 1) by
    largest remainder, shuffled by ``rng``."""
    quota = {c: p * n for c, p in classes.items()}
    counts = {c: int(q) for c, q in quota.items()}
    rest = sorted(classes, key=lambda c: quota[c] - counts[c], reverse=True)
    for c in rest[: n - sum(counts.values())]:
        counts[c] += 1
    order = [c for c in classes for _ in range(counts[c])]
    rng.shuffle(order)
    return order


def schedule(n: int, seed: int) -> list[str]:
    """Classes of n scenes in CLASSES' proportions (largest remainder), shuffled by seed."""
    return stratified(CLASSES, n, np.random.default_rng(seed))


def _plain(x):
    """Plain Python numbers (JSON-able) all the way down."""
    if isinstance(x, dict):
        return {k: _plain(v) for k, v in x.items()}
    if isinstance(x, (list, tuple, np.ndarray)):
        return [_plain(v) for v in x]
    if isinstance(x, np.integer):
        return int(x)
    if isinstance(x, np.floating):
        return float(x)
    return x


def make_scene(i: int, cls: str, seed: int) -> dict:
    """Scene ``i`` of class ``cls`` (redrawn until the draws make a valid scene)."""
    rng = np.random.default_rng([seed, i])
    for _ in range(100):
        try:
            variant, scene = generate_one(rng, cls)
        except Redraw:
            continue
        scene = {"name": f"fuzz {i:04d} {cls}", "model": "planar", **scene}
        return {"id": f"s{seed}-{i:04d}", "class": cls, "variant": variant, "scene": _plain(scene)}
    raise RuntimeError(f"scene {i} ({cls}): no valid draw in 100 tries")


def generate(n: int, seed: int = 11) -> list[dict]:
    """n scenes in the stated proportions."""
    return [make_scene(i, cls, seed) for i, cls in enumerate(schedule(n, seed))]
