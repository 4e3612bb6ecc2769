"""The names of a 3D scene's outputs that sensitivities take: the static state's own
outputs (an entry as ``NAME[i]``) and the design outputs derived from the lines' end
forces (tensions, utilisations, grounded length, uplift, a horizontal force), for
:mod:`symcable.api.sensitivity` and :mod:`symcable.api.periodic_sensitivity`."""
from __future__ import annotations

import re

from ..errors import SymcableError

__all__ = ["BED_REACH", "DERIVED", "NO_MAGNITUDE", "lines_of", "requested_outputs"]

#: an anchor within this share of the depth above the seabed rests on it
#: (``LINE.grounded_length``)
BED_REACH = 0.01
#: a derived magnitude below this share of the scene's force scale is taken as zero, where
#: it has no derivative
NO_MAGNITUDE = 1e-6
#: derived outputs: name suffix -> (the end force they read, how: its magnitude, its
#: magnitude over the end's breaking load, its vertical entry)
DERIVED = {"fairlead_tension": ("end_force_b", "norm"), "anchor_tension": ("end_force_a", "norm"),
           "fairlead_utilisation": ("end_force_b", "ratio"),
           "anchor_utilisation": ("end_force_a", "ratio"),
           "anchor_uplift": ("end_force_a", "up"), "grounded_length": ("end_force_b", "ground"),
           "horizontal_force": ("force", "horizontal")}


def requested_outputs(mech, names) -> list:
    """[(name, output it reads, derived or None, entry or None)] of each requested output
    (``"NAME[i]"``: that entry of a vector output alone)."""
    if isinstance(names, str):
        names = [names]
    out = []
    for name in names:
        name = str(name)
        m = re.fullmatch(r"(.+)\[(\d+)\]", name)
        whole, entry = (m.group(1), int(m.group(2))) if m and m.group(1) in mech.outputs \
            else (name, None)
        head, _, tail = whole.rpartition(".")
        source, how = DERIVED.get(tail if head or "." not in whole else "", (None, None))
        force = None if source is None else f"{head}.{source}" if head else source
        if whole in mech.outputs:
            size = int(mech.outputs[whole].expr.numel())
            if entry is not None and entry >= size:
                raise SymcableError(f"output {name!r}: {whole!r} has {size} entries")
            out.append((name, whole, None, entry))
        elif entry is None and force is not None and force in mech.outputs:
            out.append((name, force, how, None))
        else:
            known = sorted(set(mech.outputs) | {
                (f"{n.rpartition('.')[0]}." if "." in n else "") + k
                for n in mech.outputs for k, (v, _) in DERIVED.items()
                if n == v or n.endswith("." + v)})
            raise SymcableError(f"output {name!r}: unknown; the static state's outputs: "
                                f"{', '.join(known)} (an entry of a vector one as NAME[i])")
    if not out:
        raise SymcableError("outputs: give at least one")
    return out


def lines_of(scene) -> list:
    """[(line name, number of sections, whether end A is held on the seabed)]; a one-line
    scene's line is named ""."""
    depth = scene.environment.depth

    def on_bed(position) -> bool:
        return depth is not None and position is not None \
            and float(position[-1]) <= -depth + BED_REACH * depth
    if not scene.lines:
        e = scene.end_a
        return [("", len(scene.sections), e.condition.value != "free" and on_bed(e.position))]
    out = []
    for ln in scene.lines:
        pt = scene.points.get(ln.end_a) if isinstance(ln.end_a, str) else None
        out.append((ln.name, len(ln.sections), pt is not None and not pt.is_free
                    and pt.motion is None and on_bed(pt.position)))
    return out
