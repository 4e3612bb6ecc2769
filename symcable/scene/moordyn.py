"""MoorDyn v2 input decks read into the scene layout (issue 12, item 5, first step).

:func:`parse_moordyn` turns a deck's text into the plain dict that
:func:`~symcable.scene.load_scene` validates (``model = "cable3d"``), plus notes on what it
read differently or ignored; ``load_scene`` calls it for a file that is not TOML and looks like
a deck (:func:`is_moordyn_deck`), so every check of a TOML scene applies to a deck too, and
:func:`~symcable.scene.moordyn_deck` returns it (``symcable check`` prints its notes).
Sections are found as MoorDyn finds them: a line holding ``---`` and a section name
(case-insensitive); a table's header line is followed by its units line, then its rows.

Only a deck of exactly ONE line between two points, one of them Fixed (the anchor) and the
other Fixed or Vessel, is representable yet (several lines and points come with scene
version 2). Anything else is one :class:`~symcable.errors.SceneError` of the form
``<deck>:<line number>: '<that line>': <why>``.

===========================  ===============================================================
MoorDyn v2                   scene (SI units throughout, as in MoorDyn)
===========================  ===============================================================
LINE TYPES, by column name   ``[line_types.<TypeName>]`` (only the type the line uses)
  TypeName / Name            the type's name
  Diam                       ``diameter``, m
  Mass/m, MassDen            ``mass``, kg/m in air; ``weight`` left to its default
                             (mass - rho pi d^2/4) g, which is MoorDyn's too
  EA                         ``EA``, N (a table, a ``|`` or a Syrope law: refused)
  BA/-zeta                   ``damping``: BA >= 0 as given (N s); a negative -zeta as given
                             (:data:`ZETA_FACTOR` = 1: cable3d reads it as MoorDyn does,
                             BA = zeta ds sqrt(EA m))
  EI                         must be 0 (cable3d has no bending yet): else refused
  Cd, Ca / Cdn, Can          ``cd_normal``, ``ca_normal``
  CdAx, CaAx / Cdt, Cat      ``cd_tangential``, ``ca_tangential``
  Cl (dF, cF)                VIV lift: must be 0 (dF, cF then ignored)
POINTS (ID Type X Y Z M V    the line's AttachA point -> ``end_a``, AttachB -> ``end_b``,
[Fx Fy Fz] CdA Ca)           ``condition = "pinned"``, ``position = [X, Y, Z]``; Fixed,
                             Fix, Anchor or Vessel, Ves, Coupled, Cpld, Fairlead (a vessel
                             point is pinned where it is: its motion is not in the deck);
                             M, V, F must be 0; CdA, Ca of a held point are ignored
LINES (ID LineType AttachA   one ``[[sections]]``: ``type``, ``length`` = UnstrLen (m),
AttachB UnstrLen NumSegs)    ``segments`` = NumSegs; ``name`` = "<file stem> line <ID>"
OPTIONS (value, then key)
  WtrDpth                    ``environment.depth`` (seabed at z = -WtrDpth, as MoorDyn's);
                             missing or above a point: the deepest point's depth, as MoorDyn
  WtrDnsty / rho             ``environment.water_density``
  g / gravity                ``environment.gravity``
  kBot / kb                  ``seabed.stiffness`` (Pa/m); default MoorDyn's 3e6
  cBot / cb                  ``seabed.damping`` (Pa s/m); default MoorDyn's 3e5
  FrictionCoefficient        ``seabed.friction``
  FricDamp, StatDynFricScale ignored, with a note (MoorDyn's friction law, not symcable's)
  SeafloorFile               refused (a bathymetry file)
  WaveKin, Currents (not 0)  refused (waves and current files); ``current`` is zero
  anything else              ignored (dtM, CFL, TmaxIC, dtIC, threshIC, writeLog, fileIC,
                             dtOut, disableOutTime, ...: MoorDyn's solver settings)
OUTPUTS, title, comments     ignored
RODS, BODIES, ROD TYPES,     refused when they hold a row
FAILURE, SYROPE IC
===========================  ===============================================================
"""
from __future__ import annotations

import json
import math
import os
import re
from dataclasses import dataclass
from types import MappingProxyType
from typing import Any, Mapping

from ..errors import SceneError

__all__ = ["ZETA_FACTOR", "MoorDynDeck", "is_moordyn_deck", "parse_moordyn"]

#: cable3d's negative ``damping`` per MoorDyn negative BA/-zeta: both set
#: BA = zeta ds sqrt(EA m), zeta the damping ratio of the line's highest axial mode
ZETA_FACTOR = 1.0

#: section kind -> names MoorDyn accepts in the header (MoorDyn2.cpp, findStartOfSection),
#: the v2 name first
_SECTIONS = {
    "line_types": ("LINE TYPES", "LINE DICTIONARY"),
    "rod_types": ("ROD TYPES", "ROD DICTIONARY"),
    "bodies": ("BODIES", "BODY LIST", "BODY PROPERTIES"),
    "rods": ("RODS", "ROD LIST", "ROD PROPERTIES"),
    "points": ("POINTS", "POINT LIST", "POINT PROPERTIES", "CONNECTION PROPERTIES",
               "NODE PROPERTIES"),
    "lines": ("LINES", "LINE LIST", "LINE PROPERTIES"),
    "failure": ("FAILURE",),
    "syrope": ("SYROPE IC",),
    "options": ("OPTIONS",),
    "outputs": ("OUTPUT",),
}
_REFUSED = {"rod_types": "rod types (symcable has no rods yet)",
            "bodies": "bodies (symcable has no bodies yet)",
            "rods": "rods (symcable has no rods yet)",
            "failure": "line failures (not modelled)",
            "syrope": "Syrope initial conditions (no Syrope law)"}

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

#: OPTIONS keys (lower case) -> (table, key) in the scene
_OPTIONS = {"wtrdpth": ("environment", "depth"), "wtrdnsty": ("environment", "water_density"),
            "rho": ("environment", "water_density"), "g": ("environment", "gravity"),
            "gravity": ("environment", "gravity"), "kbot": ("seabed", "stiffness"),
            "kb": ("seabed", "stiffness"), "cbot": ("seabed", "damping"),
            "cb": ("seabed", "damping"), "frictioncoefficient": ("seabed", "friction")}
#: MoorDyn's defaults of the seabed options (MoorDyn2.cpp), which a deck leaving them out means
_SEABED_DEFAULTS = {"stiffness": 3.0e6, "damping": 3.0e5}
_FRICTION_NOTES = {"fricdamp": "MoorDyn's friction rises as mu FricDamp |v| (N s/m per node) "
                               "to mu N; symcable's is -mu N v / sqrt(|v|^2 + v_eps^2) with "
                               "seabed.friction_velocity",
                   "statdynfricscale": "symcable has one friction coefficient, static = dynamic"}

_SCALE = "scenes of several lines and points come with scene version 2"


@dataclass(frozen=True)
class MoorDynDeck:
    """A deck read into the scene layout.

    Attributes
    ----------
    scene : Mapping
        The scene as a plain dict in the file's layout (``model = "cable3d"``), for
        :func:`~symcable.scene.load_scene`.
    notes : tuple of str
        One line each: what was ignored or read with a default (``"line 17: ..."``).
    origin : Mapping[str, int]
        Scene key path (``"line_types.chain"``, ``"sections[0]"``, ``"end_a"``,
        ``"environment.depth"``, ...) -> the deck's line number (1-based) it came from.
    lines : tuple of str
        The deck's lines, to quote them in messages.
    source : str
        The deck's path, or ``"<deck>"``.
    """

    scene: Mapping[str, Any]
    notes: tuple[str, ...]
    origin: Mapping[str, int]
    lines: tuple[str, ...]
    source: str

    def locate(self, message: str) -> str:
        """``message`` (a SceneError about the scene's keys) prefixed with the deck line the
        key it names came from, when there is one."""
        best = max((k for k in self.origin if message.startswith(k)
                    and message[len(k):len(k) + 1] in ("", " ", ".", "[", ":", "=")),
                   key=len, default=None)
        if best is None:
            return f"{self.source}: {message}"
        n = self.origin[best]
        return f"{self.source}:{n}: {self.lines[n - 1].strip()!r}: {message}"


def is_moordyn_deck(text: str) -> bool:
    """True when ``text`` has a line naming MoorDyn and a ``---`` line naming one of its
    sections (LINE TYPES, POINTS, LINES, OPTIONS, ...)."""
    lines = text.splitlines()
    return any("MOORDYN" in ln.upper() for ln in lines) and \
        any(_kind(ln) is not None for ln in lines)


def parse_moordyn(text: str, source: str = "<deck>") -> MoorDynDeck:
    """Read a MoorDyn v2 deck (the module's table) into the scene layout; ``source`` is
    the deck's path (its stem names the scene) or a label, for messages.

    Raises
    ------
    SceneError
        ``<source>:<line>: '<deck line>': <why>`` for anything not representable yet or
        malformed; ``<source>: no <SECTION> section`` when a needed section is missing.
    """
    return _Parser(text, source).run()


def _kind(line: str) -> str | None:
    """The section a ``---`` header line opens, or None (not a header, or unknown)."""
    if "---" not in line:
        return None
    up = line.upper()
    return next((k for k, names in _SECTIONS.items() if any(n in up for n in names)), None)


class _Parser:
    def __init__(self, text: str, source: str):
        self.lines = tuple(text.splitlines())
        self.source = source
        self.notes: list[str] = []
        self.origin: dict[str, int] = {}

    def fail(self, n: int, why: str) -> SceneError:
        """The one-line error naming deck line ``n`` (1-based)."""
        return SceneError(f"{self.source}:{n}: {self.lines[n - 1].strip()!r}: {why}"
                          .replace("\n", " "))

    def sections(self) -> dict[str, tuple[int, list[int]]]:
        """kind -> (header line number, numbers of its non-blank lines up to the next ``---``)."""
        out: dict[str, tuple[int, list[int]]] = {}
        current: list[int] | None = None
        for n, line in enumerate(self.lines, start=1):
            if "---" in line:
                kind = _kind(line)
                current = None
                if kind is not None:
                    if kind in out:
                        raise self.fail(n, f"a second {_SECTIONS[kind][0]} section (the "
                                           f"first is at line {out[kind][0]})")
                    current = []
                    out[kind] = (n, current)
            elif current is not None and line.strip():
                current.append(n)
        return out

    def table(self, sec: dict, kind: str) -> tuple[int, list[int]]:
        """(header line number, row line numbers) of a table section: its first line is the
        column names and its second the units, as MoorDyn reads it."""
        if kind not in sec:
            raise SceneError(f"{self.source}: no {_SECTIONS[kind][0]} section ('---- "
                             f"{_SECTIONS[kind][0]} ----', then column names, units, rows)")
        head, rows = sec[kind]
        if len(rows) < 2:
            raise self.fail(head, "a table needs a line of column names and a line of units "
                                  "before its rows")
        return rows[0], rows[2:]

    def number(self, n: int, token: str, what: str) -> float:
        x = _float(token)
        if not math.isfinite(x):
            raise self.fail(n, f"{what} = {token!r}: must be a finite number")
        return x

    def run(self) -> MoorDynDeck:
        sec = self.sections()
        for kind, what in _REFUSED.items():
            if kind in sec:
                rows = sec[kind][1][2:]  # column names and units first
                if rows:
                    raise self.fail(rows[0], f"{what} are not representable yet")
        options = self.options(sec)
        types = self.line_types(sec)
        line_n, line = self.line(sec, types)
        ends = self.points(sec, line_n, line)
        env: dict[str, Any] = dict(options.get("environment", {}))
        deepest = -min(e["position"][2] for e in ends.values())
        depth = env.get("depth")
        if depth is None or depth < deepest:
            if deepest <= 0:
                raise SceneError(f"{self.source}: no WtrDpth option and no point below z = 0: "
                                 "give the water depth ('<depth> WtrDpth' under OPTIONS)")
            given = "missing" if depth is None else f"= {depth:g} m, above a point"
            self.notes.append(f"WtrDpth {given}: depth {deepest:g} m, the deepest point's "
                              "(as MoorDyn sets it)")
            env["depth"] = deepest
        env["current"] = [0.0, 0.0, 0.0]
        seabed = {**_SEABED_DEFAULTS, **options.get("seabed", {})}
        for key, value in _SEABED_DEFAULTS.items():
            if key not in options.get("seabed", {}):
                self.notes.append(f"seabed.{key} not in the deck: MoorDyn's default {value:g}")
        stem = os.path.splitext(os.path.basename(self.source))[0]
        type_name = line["type"]
        scene = {"name": f"{stem} line {line['id']}", "model": "cable3d", "environment": env,
                 "seabed": seabed, "line_types": {type_name: types[type_name][1]},
                 "sections": [{"type": type_name, "length": line["length"],
                               "segments": line["segments"]}],
                 **ends}
        self.origin.update({_dotted("line_types", type_name): types[type_name][0],
                            "sections[0]": line_n})
        for name in types:
            if name != type_name:
                self.notes.append(f"line {types[name][0]}: line type {name!r} unused, not read")
        return MoorDynDeck(scene=scene, notes=tuple(self.notes),
                           origin=MappingProxyType(dict(self.origin)), lines=self.lines,
                           source=self.source)

    # ------------------------------------------------------------------- sections

    def options(self, sec: dict) -> dict[str, dict[str, float]]:
        out: dict[str, dict[str, float]] = {}
        for n in sec.get("options", (0, []))[1]:
            entries = self.lines[n - 1].split()
            if len(entries) < 2:
                continue
            value, key = entries[0], entries[1].lower()
            if key == "seafloorfile":
                raise self.fail(n, "a bathymetry file is not representable yet (flat seabed "
                                   "at z = -WtrDpth only)")
            if key in ("wavekin", "currents"):
                if self.number(n, value, entries[1]) != 0:
                    raise self.fail(n, f"{entries[1]} = {value}: waves and current files are "
                                       "not representable yet (0 only)")
                continue
            if key in _FRICTION_NOTES:
                self.notes.append(f"line {n}: {entries[1]} = {value} ignored: "
                                  f"{_FRICTION_NOTES[key]}")
            elif key in _OPTIONS:
                table, name = _OPTIONS[key]
                out.setdefault(table, {})[name] = self.number(n, value, entries[1])
                self.origin[f"{table}.{name}"] = n
            else:
                self.notes.append(f"line {n}: {entries[1]} = {value} ignored (a MoorDyn "
                                  "solver or output setting, or unknown)")
        return out

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
            for key, why in (("EI", "cable3d has no bending yet"), ("Cl", "no VIV lift")):
                if values.pop(key, 0.0) != 0.0:
                    raise self.fail(n, f"{key} = {row[key]} in line type {name!r} is not "
                                       f"representable yet ({why}): {key} must be 0")
            values.pop("dF", None)
            values.pop("cF", None)
            if values["damping"] < 0:
                values["damping"] *= ZETA_FACTOR
            out[name] = (n, values)
        if not out:
            raise self.fail(head, "LINE TYPES has no rows")
        return out

    def line(self, sec: dict, types: dict) -> tuple[int, dict[str, Any]]:
        head, rows = self.table(sec, "lines")
        if not rows:
            raise self.fail(head, "LINES has no rows (a line needs one)")
        if len(rows) > 1:
            raise self.fail(rows[1], f"a second line is not representable yet ({_SCALE})")
        n = rows[0]
        entries = self.lines[n - 1].split()
        if len(entries) < 6:
            raise self.fail(n, "a line needs ID LineType AttachA AttachB UnstrLen NumSegs")
        ident, type_name = entries[0], entries[1]
        if type_name not in types:
            raise self.fail(n, f"unknown line type {type_name!r} (defined: "
                               f"{', '.join(map(repr, types))})")
        attach = []
        for tok in entries[2:4]:
            m = re.fullmatch(r"([A-Za-z]*)(\d+)([A-Za-z]*)", tok)
            if m and m.group(1).upper() in ("R", "ROD"):
                raise self.fail(n, f"attachment {tok!r} to a rod is not representable yet "
                                   "(symcable has no rods yet)")
            if not m or m.group(1).upper() not in ("", "C", "CON", "P", "POINT") or m.group(3):
                raise self.fail(n, f"attachment {tok!r}: must be a point's ID (1, P1, ...)")
            attach.append(int(m.group(2)))
        try:
            segments = int(entries[5])
        except ValueError:
            raise self.fail(n, f"NumSegs = {entries[5]!r}: must be an integer") from None
        return n, {"id": ident, "type": type_name, "attach": attach,
                   "length": self.number(n, entries[4], "UnstrLen"), "segments": segments}

    def points(self, sec: dict, line_n: int, line: dict) -> dict[str, dict[str, Any]]:
        _, rows = self.table(sec, "points")
        found: dict[int, tuple[int, str, list[float]]] = {}  # ID -> (line, vessel type, xyz)
        for n in rows:
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
            kind = re.match(r"[A-Za-z]*", entries[1]).group(0).upper()
            for kinds, why in ((_FREE, f"(free, solved for) is not representable yet ({_SCALE})"),
                               (("BODY", "TURBINE"), "on a body is not representable yet "
                                                     "(symcable has no bodies yet)")):
                if kind in kinds:
                    raise self.fail(n, f"a {entries[1]} point {why}")
            if kind not in _FIXED + _VESSEL:
                raise self.fail(n, f"unknown point type {entries[1]!r} (MoorDyn's: Fixed, "
                                   "Vessel, Coupled, Free, Connect, Body<n>)")
            xyz = [self.number(n, t, c) for t, c in zip(entries[2:5], "XYZ")]
            extra = dict(zip(("M", "V", "Fx", "Fy", "Fz"),
                             entries[5:10] if len(entries) >= 12 else entries[5:7]))
            for key, tok in extra.items():
                if self.number(n, tok, key) != 0.0:
                    raise self.fail(n, f"{key} = {tok}: a point with mass, volume or force "
                                       f"is not representable yet ({_SCALE})")
            found[ident] = (n, entries[1] if kind in _VESSEL else "", xyz)
        for ident, (n, _, _) in found.items():
            if ident not in line["attach"]:
                raise self.fail(n, f"point {ident} is not on the line: points beyond the "
                                   f"line's two ends are not representable yet ({_SCALE})")
        ends: dict[str, dict[str, Any]] = {}
        for end, ident in zip(("end_a", "end_b"), line["attach"]):
            if ident not in found:
                raise self.fail(line_n, f"the line attaches to point {ident}, which POINTS "
                                        "does not define")
            n, vessel, xyz = found[ident]
            ends[end] = {"condition": "pinned", "position": xyz}
            self.origin[end] = n
            if vessel:
                self.notes.append(f"line {n}: {vessel} point {ident} is {end}, pinned at its "
                                  f"position (its motion is not in the deck: add {end}.motion)")
        if all(found[i][1] for i in line["attach"]):
            raise self.fail(found[line["attach"][1]][0], "both ends are vessel points: one "
                            "must be Fixed (the anchor) in a one-line scene")
        return ends


def _float(token: str) -> float:
    """The number a deck's token spells, or NaN."""
    try:
        return float(token)
    except ValueError:
        return math.nan


def _dotted(path: str, key: str) -> str:
    """``path.key``, quoting the key as the scene's messages do when it is not bare."""
    if re.fullmatch(r"[A-Za-z0-9_-]+", key):
        return f"{path}.{key}"
    return f"{path}.{json.dumps(key, ensure_ascii=False)}"
