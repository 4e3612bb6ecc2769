"""A line type's keys in the scene file: the key sets, the catalogue families a line type may
name instead of its numbers, and writing a line type back to the file's layout.

A family (``family = "studless_chain"``, ``nominal_diameter = 0.09``) gives a line type's
mass, axial stiffness, breaking load, hydrodynamic diameter and coefficients from the
nominal diameter d (m) by the usual catalogue formulas; a key the table gives itself wins.

============== ================ ============= ============= =============================
family         diameter (vol.)  mass, kg/m    EA, N         breaking load, N
============== ================ ============= ============= =============================
studless_chain 1.80 d           19.9e3 d^2    0.854e11 d^2  c d_mm^2 (44 - 0.08 d_mm) kN
studlink_chain 1.89 d           21.9e3 d^2    1.01e11 d^2   the same
wire           1.18 d           5293 d^2      97.1e9 d^2    1022e6 d^2
polyester      0.7915 d*        679 d^2       14 x MBL      308e6 d^2
============== ================ ============= ============= =============================

Sources: chain mass, EA, volume-equivalent diameter and drag and added-mass coefficients:
Orcina, OrcaFlex help, "Chain" (the line type wizard); the chain's drag coefficients there
(normal 2.4 / 2.6 on d, axial 1.15 / 1.4 on d) are divided by the diameter ratio, so that
they act on the volume-equivalent diameter symcable's drag uses. Chain breaking load:
DNV-OS-E302 (offshore mooring chain), c = 0.0223 (R3), 0.0249 (R3S), 0.0274 (R4), 0.0304
(R4S), 0.0320 (R5), d_mm the nominal diameter in mm. Wire (spiral strand) and polyester:
NREL's MoorPy line-property defaults (``MoorProps_default.yaml``: mass, breaking load,
stiffness, volume-equivalent diameter, coefficients; polyester's EA is its quasi-static
stiffness, 14 times the breaking load; * its volume at 1380 kg/m^3).
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, Mapping

#: keys of a line type (``[line_types.NAME]``) in the file, in the order they are written
LINE_KEYS = ("EA", "EI", "mass", "diameter", "weight", "cd_normal", "cd_tangential", "ca_normal",
             "max_strain", "ca_tangential", "damping")
#: the keys only cable3d reads (written only when set)
LINE_KEYS_3D = ("ca_tangential", "damping")
#: the keys only the rod reads (written only when set): torsion; EI may be [EI_1, EI_2]
LINE_KEYS_ROD = ("GJ", "tension_twist")
#: the drag law's keys (cable3d; written only for a law other than Morison's)
LINE_KEYS_DRAG = ("drag_law", "loading")
#: a catalogue family's keys, and the breaking load any line type may give
FAMILY_KEYS = ("family", "nominal_diameter", "grade", "breaking_load")

#: DNV-OS-E302's chain grades: c of the breaking load c d^2 (44 - 0.08 d) kN, d in mm
CHAIN_GRADES = {"R3": 0.0223, "R3S": 0.0249, "R4": 0.0274, "R4S": 0.0304, "R5": 0.0320}
#: the grade a chain family takes when the table gives none
DEFAULT_GRADE = "R4"
#: the largest nominal diameter each family takes, m: the catalogues' range with margin
#: (DNV-OS-E302's breaking load peaks at 367 mm and falls beyond)
MAX_NOMINAL = {"studless_chain": 0.25, "studlink_chain": 0.25, "wire": 0.2, "polyester": 0.4}


def _chain(vol, mass, ea, cdn, cdt):
    def values(d: float, grade: str) -> dict:
        mm = 1e3 * d
        return {"diameter": vol * d, "mass": mass * d * d, "EA": ea * d * d,
                "breaking_load": 1e3 * CHAIN_GRADES[grade] * mm * mm * (44.0 - 0.08 * mm),
                "cd_normal": cdn / vol, "cd_tangential": cdt / vol, "ca_normal": 1.0,
                "ca_tangential": 0.5}
    return values


def _wire(d: float, grade: str | None) -> dict:
    return {"diameter": 1.18 * d, "mass": 5293.0 * d * d, "EA": 97.1e9 * d * d,
            "breaking_load": 1022e6 * d * d, "cd_normal": 1.021}


def _polyester(d: float, grade: str | None) -> dict:
    mbl = 308e6 * d * d
    return {"diameter": math.sqrt(4.0 * 679.0 / (1380.0 * math.pi)) * d, "mass": 679.0 * d * d, "EA": 14.0 * mbl,
            "breaking_load": mbl, "cd_normal": 2.021, "ca_normal": 1.1,
            "ca_tangential": 0.15}


#: family name -> values(nominal diameter m, grade) -> {line-type key: value}
FAMILIES = {"studless_chain": _chain(1.80, 19.9e3, 0.854e11, 2.4, 1.15),
            "studlink_chain": _chain(1.89, 21.9e3, 1.01e11, 2.6, 1.4),
            "wire": _wire, "polyester": _polyester}


@dataclass(frozen=True)
class Family:
    """A line type's catalogue family, as its table named it.

    Attributes
    ----------
    name : str
        One of :data:`FAMILIES`.
    nominal_diameter : float
        m (a chain's bar diameter, a rope's nominal diameter).
    grade : str or None
        A chain's grade (:data:`CHAIN_GRADES`); None for ropes.
    given : tuple of str
        The keys the table gave itself over the family's values (``weight`` included).
    """

    name: str
    nominal_diameter: float
    grade: str | None
    given: tuple = ()


def family_table(path: str, t: Mapping, dim: int, number, err) -> tuple[dict, Family | None]:
    """The table ``t`` of the line type at ``path`` with its family's values filled in
    (keys it gives itself win), and its :class:`Family` (None without ``family``).
    ``number(key, value, unit, **bounds)`` and ``err(key, value, unit, allowed)`` are the
    reader's checks."""
    out = {k: v for k, v in t.items() if k not in ("family", "nominal_diameter", "grade")}
    if "family" not in t:
        for key in ("nominal_diameter", "grade"):
            if key in t:
                raise err(f"{path}.{key}", t[key], "", "is read with family = "
                          f"{' | '.join(map(repr, FAMILIES))} only")
        return out, None
    name = t["family"]
    if not isinstance(name, str) or name not in FAMILIES:
        raise err(f"{path}.family", name, "", f"must be one of {', '.join(map(repr, FAMILIES))}")
    if "nominal_diameter" not in t:
        raise err(f"{path}.family", name, "", "needs nominal_diameter (m): the diameter the "
                  "family's formulas take")
    d = number(f"{path}.nominal_diameter", t["nominal_diameter"], "m", gt=0)
    if d > MAX_NOMINAL[name]:
        raise err(f"{path}.nominal_diameter", d, "m", f"must be <= {MAX_NOMINAL[name]:g} m "
                  f"for {name!r} (the catalogue formulas' range)")
    grade = None
    if name.endswith("_chain"):
        grade = t.get("grade", DEFAULT_GRADE)
        if not isinstance(grade, str) or grade not in CHAIN_GRADES:
            raise err(f"{path}.grade", grade, "", f"must be one of "
                      f"{', '.join(map(repr, CHAIN_GRADES))} (DNV-OS-E302)")
    elif "grade" in t:
        raise err(f"{path}.grade", t["grade"], "", "is a chain's (family = 'studless_chain' "
                  "or 'studlink_chain')")
    values = FAMILIES[name](d, grade)
    if dim != 3:
        values.pop("ca_tangential", None)  # the planar line has no tangential added mass
    given = tuple(k for k in LINE_KEYS + ("breaking_load",)
                  if k in t and (k in values or k == "weight"))
    return {**values, **out}, Family(name, d, grade, given)


def line_type_dict(lt) -> dict:
    """A :class:`~symcable.scene.model.LineType` as its file table: a family's keys and the
    keys given over it, else every key that applies."""
    fam = lt.family
    out: dict[str, Any] = {k: getattr(lt, k) for k in LINE_KEYS
                           if k not in LINE_KEYS_3D or getattr(lt, k) != 0.0}
    if fam is not None:
        derived = (set(FAMILIES[fam.name](fam.nominal_diameter, fam.grade)) | {"weight"}) \
            - set(fam.given)
        out = {"family": fam.name, "nominal_diameter": fam.nominal_diameter,
               **({"grade": fam.grade} if fam.grade is not None else {}),
               **{k: v for k, v in out.items() if k not in derived}}
    if lt.breaking_load is not None and (fam is None or "breaking_load" in fam.given):
        out["breaking_load"] = lt.breaking_load
    if lt.EI_2 is not None:
        out["EI"] = [lt.EI, lt.EI_2]
    for key in ("GJ", "tension_twist"):
        if getattr(lt, key) != 0.0:
            out[key] = getattr(lt, key)
    if lt.drag_law != "morison":
        out["drag_law"] = lt.drag_law
        out["loading"] = lt.loading.to_dict()
    return out
