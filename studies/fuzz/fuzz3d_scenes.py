"""Seeded random ``cable3d`` scenes for the fuzz study, as the dicts ``symcable.solve_static``
takes: one line with 3D ends (version 1) and points joining two or three lines (version 2).

Every scene is ``{"id", "class", "variant", "scene"}`` as in :mod:`fuzz_scenes` (scene ``i``
drawn from its own generator seeded ``(seed, 3, i)``, classes by a stratified schedule), ids
``c<seed>-<i>``; a draw that ``load_scene`` refuses is redrawn and counted. The draws of line types, EA, lengths and segment counts are the planar
study's (:mod:`fuzz_draws`); what is new is the geometry in 3D:

- version 1: ends anywhere (directions uniform on the sphere), taut to very slack (chord/L
  down to 0.05), exactly vertical and near-vertical (span 1e-7-3e-2 L at any azimuth),
  moorings with the anchor on the bed at any azimuth, lines lying mostly on the bed (fully
  slack piles, flat on the bed, U-shaped touching down), several sections and line types
  (chain-wire-chain, lazy waves), currents in the ends' vertical plane and oblique to it (the
  line then leaves its plane), free ends with 3D end forces;
- version 2: a buoy between an anchor chain and a riser rope, a clump weight between two
  lines (which may come to rest on the bed), three lines meeting at a point (a buoy held by
  three anchors, a clump hung from two points with a third line to an anchor, a bridle of two
  anchor lines and a fairlead line at a massless joint); the same with a current; fairleads
  fixed or vessel points, some with a motion (statics must ignore it: checked too);
- every seabed: penalty stiffness 1e4-1e7 Pa/m or the default, and friction in half of the
  scenes (isotropic, or axial and lateral apart): statics do not apply friction, and the
  classifier checks that the answer does not depend on it.
"""
from __future__ import annotations

import math

import numpy as np

from fuzz3d_draws import current3, horizontal, one_line, origin3, pinned3, seabed3, sphere
from fuzz3d_systems import gen_buoy, gen_clump, gen_system_current, gen_three_lines
from fuzz_draws import (EA_RANGE, Redraw, drag_coefficients, draw_sections, finish_types,
                        flip_ends, free_end_line, line_type, log_uniform, segments, taut_ratio, weight_of,
                        weight_strain)
from fuzz_scenes import _plain, stratified

#: class -> share of the scenes (sums to 1); the c3_ classes of one line, the s3_ ones systems
CLASSES3D = {
    "c3_taut": 0.08, "c3_slack": 0.10, "c3_vertical": 0.08, "c3_mooring": 0.12,
    "c3_on_bed": 0.10, "c3_multi_section": 0.10, "c3_current": 0.08, "c3_free_end": 0.06,
    "s3_buoy": 0.08, "s3_clump": 0.07, "s3_three_lines": 0.08, "s3_current": 0.05,
}


# ----------------------------------------------------------------------------- one line
def gen_two_point(rng, cls: str):
    """c3_taut, c3_slack, c3_vertical: one section between two pinned ends, no seabed."""
    fam = str(rng.choice(["chain", "wire", "rope"]))
    L = log_uniform(rng, 5.0, 2000.0)
    types = {fam: line_type(rng, fam)}
    finish_types(rng, types, {fam: L})
    c = weight_strain(types, fam, L)
    a = origin3(rng)
    if cls == "c3_taut":
        r, d = taut_ratio(rng, c), sphere(rng)
        variant = "stretched" if r > 1.0 else "nearly taut"
    elif cls == "c3_slack":
        r = rng.uniform(0.05, 0.2) if rng.uniform() < 0.25 else rng.uniform(0.2, 0.97)
        d = sphere(rng)
        variant = "very slack" if r < 0.2 else "slack"
    else:
        up = rng.uniform() < 0.5
        r = rng.uniform(0.2, 0.999) if rng.uniform() < 0.75 else taut_ratio(rng, c)
        d = np.array([0.0, 0.0, 1.0 if up else -1.0])
        variant = ("taut " if r >= 0.999 else "folded ") + ("B above" if up else "B below")
    b = a + r * L * d
    if cls == "c3_vertical" and rng.uniform() < 0.5:
        b = b + L * log_uniform(rng, 1e-7, 3e-2) * horizontal(rng.uniform(-math.pi, math.pi))
        variant = "near-vertical, " + variant
    n = segments(rng)
    return variant, one_line(types, [{"type": fam, "length": L, "segments": n}], pinned3(a), pinned3(b))


def gen_seabed(rng, cls: str):
    """c3_mooring (anchor on the bed, fairlead at any azimuth) and c3_on_bed (fully slack,
    flat on the bed, U-shaped touching down)."""
    fam = str(rng.choice(["chain", "chain", "wire"]))
    types = {fam: line_type(rng, fam)}
    depth = log_uniform(rng, 20.0, 1000.0)
    phi = rng.uniform(-math.pi, math.pi)
    anchor = np.array([rng.uniform(-1000.0, 1000.0), rng.uniform(-1000.0, 1000.0), -depth])
    variant = str(rng.choice(["fully slack", "flat", "U-shaped"])) if cls == "c3_on_bed" \
        else "anchor on the bed"
    if variant in ("anchor on the bed", "fully slack"):
        h = depth * rng.uniform(0.05, 0.95)
        L = h * log_uniform(rng, 1.05, 4.0)
        finish_types(rng, types, {fam: L})
        if variant == "fully slack":
            span = rng.uniform(0.0, 0.95) * (L - h)
        else:
            span = rng.uniform(0.3, 1.0) * math.sqrt(L * L - h * h)
            if rng.uniform() < 0.2:
                span = math.sqrt(L * L - h * h) * rng.uniform(1.0, 1.0 + weight_strain(types, fam, L))
        a, b = anchor, anchor + span * horizontal(phi) + np.array([0.0, 0.0, h])
    elif variant == "flat":
        L = log_uniform(rng, 10.0, 1000.0)
        finish_types(rng, types, {fam: L})
        r = rng.uniform(0.5, 1.0) if rng.uniform() < 0.6 else taut_ratio(rng, weight_strain(types, fam, L))
        a, b = anchor, anchor + r * L * horizontal(phi)
        variant = "flat, " + ("slack" if r < 1 else "stretched")
    else:   # both ends above the bed, the free catenary dipping below it
        from symcable.analytic import elastic_catenary
        L = log_uniform(rng, 20.0, 1500.0)
        finish_types(rng, types, {fam: L})
        span, height = rng.uniform(0.2, 0.9) * L, rng.uniform(-0.3, 0.3) * L
        span = min(span, 0.95 * math.sqrt(max(L * L - height * height, 0.0)))
        sol = elastic_catenary(span, height, L, types[fam]["EA"], weight_of(types[fam]))
        z = sol.positions(np.linspace(0.0, L, 801))[:, 1]
        bed = z.min() + rng.uniform(0.1, 0.9) * (min(0.0, height) - z.min())
        a = np.array([anchor[0], anchor[1], rng.uniform(-100.0, 0.0)])
        b = a + span * horizontal(phi) + np.array([0.0, 0.0, height])
        depth = -(a[2] + bed)
    scene = one_line(types, [{"type": fam, "length": L, "segments": segments(rng)}],
                     pinned3(a), pinned3(b), **seabed3(rng, depth))
    if rng.uniform() < 0.3:
        flip_ends(scene)
        variant += ", reversed"
    return variant, scene


def gen_multi_section(rng):
    """Chain-wire-chain or chain-wire moorings on the bed, suspended, lazy waves; 3D."""
    variant = str(rng.choice(["mooring on the bed", "mooring on the bed", "suspended", "lazy wave"]))
    fams = ["chain", "buoyant", "wire"] if variant == "lazy wave" else (
        ["chain", "wire", "chain"] if rng.uniform() < 0.7 else ["chain", "wire"])
    types, lengths, secs = draw_sections(rng, fams, 10.0, 600.0)
    finish_types(rng, types, lengths)
    L = sum(lengths.values())
    extra = {}
    if variant == "suspended":
        a = origin3(rng)
        b = a + rng.uniform(0.3, 0.99) * L * sphere(rng)
    else:
        depth = L * rng.uniform(0.2, 0.8)
        h = depth * rng.uniform(0.3, 0.95)
        a = np.array([rng.uniform(-1000.0, 1000.0), rng.uniform(-1000.0, 1000.0), -depth])
        b = a + rng.uniform(0.1, 0.98) * math.sqrt(L * L - h * h) * horizontal(
            rng.uniform(-math.pi, math.pi)) + np.array([0.0, 0.0, h])
        extra = seabed3(rng, depth)
    scene = one_line(types, secs, pinned3(a), pinned3(b), **extra)
    if rng.uniform() < 0.3:
        flip_ends(scene)
        variant += ", reversed"
    return f"{variant}, {len(fams)} sections", scene


def gen_current(rng):
    """Suspended lines (1-3 sections) in a uniform current, in the ends' vertical plane or
    oblique to it."""
    n_sec = int(rng.choice([1, 1, 2, 3]))
    types, lengths, secs = {}, {}, []
    for k in range(n_sec):
        fam = str(rng.choice(["chain", "wire", "rope"]))
        name = f"{fam}{k}"
        types[name] = line_type(rng, fam)
        drag_coefficients(rng, types[name])
        lengths[name] = log_uniform(rng, 5.0, 600.0)
        secs.append({"type": name, "length": lengths[name], "segments": segments(rng)})
    finish_types(rng, types, lengths)
    L = sum(lengths.values())
    a = origin3(rng)
    b = a + rng.uniform(0.3, 0.99) * L * sphere(rng)
    in_plane = rng.uniform() < 0.5
    h = (b - a)[:2]
    u = np.array([h[0], h[1], 0.0]) / max(np.hypot(*h), 1e-300)
    cur = current3(rng, u if in_plane else None)
    variant = f"{n_sec} section(s), current {'in the plane' if in_plane else 'oblique'}"
    return variant, one_line(types, secs, pinned3(a), pinned3(b), environment={"current": cur})


def gen_free_end(rng):
    """A free end: hanging, with a 3D end force, in an oblique current, onto the bed,
    weightless with a force and with none (undetermined: refused as input)."""
    variant, L, fam, types, w_l = free_end_line(rng)
    force = None
    if variant in ("end force", "weightless, end force"):
        force = max(w_l, 1e3) * log_uniform(rng, 0.1, 10.0) * sphere(rng)
    extra = {}
    a = origin3(rng)
    if variant == "current":
        drag_coefficients(rng, types[fam])
        extra["environment"] = {"current": current3(rng, None)}
    if variant == "seabed":
        depth = L * rng.uniform(0.2, 0.95)
        a[2] = -depth * rng.uniform(0.0, 0.3)
        extra.update(seabed3(rng, depth))
        if rng.uniform() < 0.5:
            force = rng.uniform(0.1, 1.0) * w_l * horizontal(rng.uniform(-math.pi, math.pi))
    if fam == "weightless":
        hi = min(EA_RANGE[1], 0.5e9 * float(np.linalg.norm(force))) if force is not None else EA_RANGE[1]
        types[fam]["EA"] = log_uniform(rng, EA_RANGE[0], hi)
    else:
        finish_types(rng, types, {fam: L},
                     extra_load=float(np.linalg.norm(force)) if force is not None else 0.0)
    free = {"condition": "free"}
    if force is not None:
        free["force"] = [float(v) for v in force]
    scene = one_line(types, [{"type": fam, "length": L, "segments": segments(rng)}],
                     pinned3(a), free, **extra)
    if rng.uniform() < 0.3:
        flip_ends(scene)
        variant += ", end A free"
    return variant, scene


def generate_one(rng, cls: str):
    if cls in ("c3_taut", "c3_slack", "c3_vertical"):
        return gen_two_point(rng, cls)
    if cls in ("c3_mooring", "c3_on_bed"):
        return gen_seabed(rng, cls)
    return {"c3_multi_section": gen_multi_section, "c3_current": gen_current,
            "c3_free_end": gen_free_end, "s3_buoy": gen_buoy, "s3_clump": gen_clump,
            "s3_three_lines": gen_three_lines, "s3_current": gen_system_current}[cls](rng)


# ----------------------------------------------------------------------------- the set
def schedule(n: int, seed: int) -> list[str]:
    """Classes of n scenes in CLASSES3D's proportions (largest remainder), shuffled by seed."""
    return stratified(CLASSES3D, n, np.random.default_rng([seed, 3]))


def make_scene(i: int, cls: str, seed: int) -> dict:
    """Scene ``i`` of class ``cls`` (redrawn until the draws make a valid scene)."""
    import symcable as sc
    from symcable.errors import SceneError
    rng = np.random.default_rng([seed, 3, i])
    refused = []
    for _ in range(100):
        try:
            variant, scene = generate_one(rng, cls)
        except Redraw:
            continue
        scene = _plain({"name": f"fuzz3d {i:04d} {cls}", "model": "cable3d", **scene})
        if not variant.endswith("no end force"):
            try:   # the draws keep to the documented checks but for rare corners (a system's
                sc.load_scene(scene)    # reach, a stiffness): those are redrawn, and counted
            except SceneError as exc:
                refused.append(str(exc)[:200])
                continue
        return {"id": f"c{seed}-{i:04d}", "class": cls, "variant": variant, "scene": scene,
                "model": "cable3d", "refused_draws": refused}
    raise RuntimeError(f"scene {i} ({cls}): no valid draw in 100 tries")


def generate(n: int, seed: int = 11) -> list[dict]:
    """n cable3d scenes in the stated proportions."""
    return [make_scene(i, cls, seed) for i, cls in enumerate(schedule(n, seed))]
