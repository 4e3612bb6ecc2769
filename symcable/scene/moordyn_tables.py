"""The LINE TYPES, LINES and POINTS tables of a MoorDyn v2 deck (:mod:`.moordyn`), read
into rows: a mix-in of the deck parser, whose ``fail``, ``number``, ``table`` and ``lines``
it uses."""
from __future__ import annotations

import math
import re
from typing import Any

__all__ = ["ZETA_FACTOR"]

#: cable3d's negative ``damping`` per MoorDyn negative BA/-zeta: both set
#: BA = zeta ds sqrt(EA m), zeta the damping ratio of the line's highest axial mode
ZETA_FACTOR = 1.0

#: LINE TYPES column names (lower case) -> scene key
_COLUMNS = {
    "typename": "name", "name": "name", "type": "name", "linetype": "name",
    "diam": "diameter", "diameter": "diameter", "d": "diameter",
    "mass/m": "mass", "massden": "mass", "massdeninair": "mass", "mass": "mass", "m": "mass",
    "ea": "EA", "ba/-zeta": "damping", "ba": "damping", "ba/zeta": "damping",
    "-zeta": "damping", "ei": "EI",
    "cd": "cd_normal", "cdn": "cd_normal", "ca": "ca_normal", "can": "ca_normal",
    "cdax": "cd_tangential", "cdt": "cd_tangential", "caax": "ca_tangential",
    "cat": "ca_tangential", "cl": "Cl", "df": "dF", "cf": "cF",
}
_REQUIRED_COLUMNS = ("name", "diameter", "mass", "EA", "damping", "cd_normal", "ca_normal",
                     "cd_tangential", "ca_tangential")

_FIXED = ("ANCHOR", "FIXED", "FIX")
_VESSEL = ("VESSEL", "VES", "COUPLED", "CPLD", "FAIRLEAD")
_FREE = ("POINT", "CONNECT", "CON", "FREE")


class _Tables:
    """LINE TYPES, LINES and POINTS of the deck (see :mod:`.moordyn`'s table)."""

    def line_types(self, sec: dict) -> dict[str, tuple[int, dict[str, float]]]:
        head, rows = self.table(sec, "line_types")
        names = self.lines[head - 1].split()
        keys = []
        for col in names:
            key = _COLUMNS.get(col.lower())
            if key is None or key in keys:
                why = "repeated" if key else "unknown"
                raise self.fail(head, f"LINE TYPES column {col!r} {why} (known: TypeName, "
                                      "Diam, Mass/m, EA, BA/-zeta, EI, Cd, Ca, CdAx, CaAx, Cl, dF, "
                                      "cF; or Cdn, Can, Cdt, Cat)")
            keys.append(key)
        missing = [k for k in _REQUIRED_COLUMNS if k not in keys]
        if missing:
            raise self.fail(head, f"LINE TYPES columns lack {', '.join(missing)}")
        out: dict[str, tuple[int, dict[str, float]]] = {}
        for n in rows:
            entries = self.lines[n - 1].split()
            if len(entries) != len(keys):
                raise self.fail(n, f"{len(entries)} values for the {len(keys)} LINE TYPES "
                                   f"columns {' '.join(names)}")
            row = dict(zip(keys, entries))
            name = row.pop("name")
            if name in out:
                raise self.fail(n, f"line type {name!r} defined twice (first at line "
                                   f"{out[name][0]})")
            for key, col in (("EA", "EA"), ("damping", "BA"), ("EI", "EI")):
                if math.isnan(_float(row.get(key, "0"))):
                    raise self.fail(n, f"{col} = {row[key]!r}: a nonlinear or viscoelastic {col}"
                                       " (a table, a file or a '|' list) is not representable yet")
            values = {k: self.number(n, v, k) for k, v in row.items()}
            if values.pop("Cl", 0.0) != 0.0:
                raise self.fail(n, f"Cl = {row['Cl']} in line type {name!r} is not "
                                   "representable yet (no VIV lift): Cl must be 0")
            values.pop("dF", None)
            values.pop("cF", None)
            if values["damping"] < 0:
                values["damping"] *= ZETA_FACTOR
            # MoorDyn's axial drag coefficient is per surface area pi d l (its docs and
            # Line.cpp), symcable's cd_tangential per d l as the normal one
            values["cd_tangential"] *= math.pi
            out[name] = (n, values)
        if not out:
            raise self.fail(head, "LINE TYPES has no rows")
        return out

    def line_rows(self, sec: dict, types: dict) -> list[tuple[int, dict[str, Any]]]:
        head, rows = self.table(sec, "lines")
        if not rows:
            raise self.fail(head, "LINES has no rows (a line needs one)")
        out, ids = [], {}
        for n in rows:
            entries = self.lines[n - 1].split()
            if len(entries) < 6:
                raise self.fail(n, "a line needs ID LineType AttachA AttachB UnstrLen NumSegs")
            ident, type_name = entries[0], entries[1]
            if not re.fullmatch(r"[A-Za-z0-9_-]+", ident):
                raise self.fail(n, f"line ID {ident!r}: must be a number or a plain name")
            if ident in ids:
                raise self.fail(n, f"line {ident} defined twice (first at line {ids[ident]})")
            ids[ident] = n
            if type_name not in types:
                raise self.fail(n, f"unknown line type {type_name!r} (defined: "
                                   f"{', '.join(map(repr, types))})")
            attach = []
            for tok in entries[2:4]:
                m = re.fullmatch(r"([A-Za-z]*)(\d+)([A-Za-z]*)", tok)
                if m and m.group(1).upper() in ("R", "ROD"):
                    if m.group(3).upper() not in ("A", "B"):
                        raise self.fail(n, f"attachment {tok!r}: a rod's end is R<ID>A or "
                                           "R<ID>B")
                    attach.append(f"R{int(m.group(2))}{m.group(3).upper()}")
                    continue
                if not m or m.group(1).upper() not in ("", "C", "CON", "P", "POINT") \
                        or m.group(3):
                    raise self.fail(n, f"attachment {tok!r}: must be a point's ID (1, P1, ...)")
                attach.append(int(m.group(2)))
            try:
                segments = int(entries[5])
            except ValueError:
                raise self.fail(n, f"NumSegs = {entries[5]!r}: must be an integer") from None
            out.append((n, {"id": ident, "type": type_name, "attach": attach,
                            "length": self.number(n, entries[4], "UnstrLen"),
                            "segments": segments}))
        return out

    def point_rows(self, sec: dict, rows: list, rods: dict | None = None) -> dict:
        """ID -> (deck line, "fixed" | "vessel" | "free" | "body", type token, [X, Y, Z],
        {M, V, Fx, Fy, Fz, CdA, Ca}), every point on some line, every line's points defined;
        with the ends of held rods (``rods``, :meth:`rod_rows`) that lines attach to, by
        their names ``R<ID>A``, ``R<ID>B``."""
        rods = rods or {}
        _, point_lines = self.table(sec, "points") if "points" in sec or not rods else (0, [])
        found: dict[int, tuple] = {}
        for n in point_lines:
            entries = self.lines[n - 1].split()
            if len(entries) < 9:
                raise self.fail(n, "a point needs ID Type X Y Z M V CdA Ca (9 values, or 12 "
                                   "with Fx Fy Fz after V)")
            try:
                ident = int(entries[0])
            except ValueError:
                raise self.fail(n, f"point ID {entries[0]!r}: must be an integer") from None
            if ident in found:
                raise self.fail(n, f"point {ident} defined twice (first at line "
                                   f"{found[ident][0]})")
            match = re.fullmatch(r"([A-Za-z]*)(\d*)", entries[1])
            kind = (match.group(1) if match else entries[1]).upper()
            if kind == "TURBINE":
                raise self.fail(n, f"a {entries[1]} point is not representable yet")
            if kind == "BODY" and not match.group(2):
                raise self.fail(n, f"attachment {entries[1]!r}: a point on a body is Body<ID>")
            if kind not in _FIXED + _VESSEL + _FREE + ("BODY",):
                raise self.fail(n, f"unknown point type {entries[1]!r} (MoorDyn's: Fixed, "
                                   "Vessel, Coupled, Free, Connect, Body<n>)")
            xyz = [self.number(n, t, c) for t, c in zip(entries[2:5], "XYZ")]
            names = ("M", "V", "Fx", "Fy", "Fz", "CdA", "Ca") if len(entries) >= 12 \
                else ("M", "V", "CdA", "Ca")
            extra = {k: self.number(n, t, k) for k, t in zip(names, entries[5:])}
            what = "free" if kind in _FREE else "vessel" if kind in _VESSEL else \
                "body" if kind == "BODY" else "fixed"
            if what == "body":
                extra["body"] = int(match.group(2))
            if what != "free":
                for key in ("M", "V", "Fx", "Fy", "Fz"):
                    if extra.get(key, 0.0) != 0.0:
                        raise self.fail(n, f"{key} = {entries[5 + names.index(key)]}: a "
                                           f"{entries[1]} point with mass, volume or force is "
                                           "not representable (its position is given; only a "
                                           "Free point takes M, V, F)")
            elif extra["CdA"] < 0 or extra["M"] < 0 or extra["V"] < 0:
                raise self.fail(n, "a Free point's M, V and CdA must be >= 0")
            found[ident] = (n, what, entries[1], xyz, extra)
        attached = {i for _, line in rows for i in line["attach"]}
        for ident, entry in rods.items():  # a held rod's ends: those lines attach to
            if ident in attached:
                found[ident] = entry
        for line_n, line in rows:
            for ident in line["attach"]:
                if ident not in found:
                    what = "rod end" if isinstance(ident, str) else "point"
                    table = "RODS (a held rod)" if isinstance(ident, str) else "POINTS"
                    raise self.fail(line_n, f"the line attaches to {what} {ident}, which "
                                            f"{table} does not define")
        for ident, (n, *_rest) in found.items():
            if ident not in attached:
                raise self.fail(n, f"point {ident} is not on the line{'s' if len(rows) > 1 else ''}"
                                   ": every point must be a line's end (AttachA or AttachB)")
        return found


def _float(token: str) -> float:
    """The number a deck's token spells, or NaN."""
    try:
        return float(token)
    except ValueError:
        return math.nan
