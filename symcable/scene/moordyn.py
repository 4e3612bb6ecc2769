"""MoorDyn v2 input decks read into the scene layout.

:func:`parse_moordyn` turns a deck's text into the plain dict that
:func:`~symcable.scene.load_scene` validates (``model = "cable3d"``), plus notes on what it
read differently or ignored; ``load_scene`` calls it for a file that is not TOML and looks like
a deck (:func:`is_moordyn_deck`), so every check of a TOML scene applies to a deck too, and
:func:`~symcable.scene.moordyn_deck` returns it (``symcable check`` prints its notes).
Sections are found as MoorDyn finds them: a line holding ``---`` and a section name
(case-insensitive); a table's header line is followed by its units line, then its rows.

A deck of one line between two held points (one of them Fixed) reads into a version-1 scene
(``sections``, ``end_a``, ``end_b``); any other deck (several lines, Free points) into a
version-2 scene: ``[points.<ID>]`` named by the point IDs, ``[[lines]]`` named
``line<ID>`` (a line and a point cannot share a name). Anything not representable is one
:class:`~symcable.errors.SceneError` of the form ``<deck>:<line number>: '<that line>': <why>``.

===========================  ===============================================================
MoorDyn v2                   scene (SI units throughout, as in MoorDyn)
===========================  ===============================================================
LINE TYPES, by column name   ``[line_types.<TypeName>]`` (only the types the lines use)
  TypeName / Name            the type's name
  Diam                       ``diameter``, m
  Mass/m, MassDen            ``mass``, kg/m in air; ``weight`` left to its default
                             (mass - rho pi d^2/4) g, which is MoorDyn's too
  EA                         ``EA``, N (a table, a ``|`` or a Syrope law: refused)
  BA/-zeta                   ``damping``: BA >= 0 as given (N s); a negative -zeta as given
                             (:data:`ZETA_FACTOR` = 1: cable3d reads it as MoorDyn does,
                             BA = zeta ds sqrt(EA m))
  EI                         ``EI``, N m^2 (> 0: cable3d's bending, moment-free ends)
  Cd, Ca / Cdn, Can          ``cd_normal``, ``ca_normal``
  CdAx, CaAx / Cdt, Cat      ``cd_tangential`` = pi CdAx (MoorDyn's axial drag is per surface
                             area pi d l, symcable's per d l), ``ca_tangential`` = CaAx
  Cl (dF, cF)                VIV lift: must be 0 (dF, cF then ignored)
POINTS (ID Type X Y Z M V    one line: its AttachA point -> ``end_a``, AttachB -> ``end_b``,
[Fx Fy Fz] CdA Ca)           ``condition = "pinned"``, ``position = [X, Y, Z]``. Otherwise
                             ``[points.<ID>]``: Fixed, Fix, Anchor -> ``kind = "fixed"``;
                             Vessel, Ves, Coupled, Cpld, Fairlead -> ``"vessel"`` (held where
                             it is: its motion is not in the deck); Free, Point, Connect, Con
                             -> ``"free"`` with ``mass`` = M, ``volume`` = V, ``cd_area`` =
                             [CdA] * 3, ``ca`` = Ca, ``force`` = [Fx, Fy, Fz] (when not 0).
                             A held point's M, V, F must be 0 (its CdA, Ca are ignored);
                             every point must be some line's end
LINES (ID LineType AttachA   one ``[[sections]]`` (or ``[[lines.sections]]``): ``type``,
AttachB UnstrLen NumSegs)    ``length`` = UnstrLen (m), ``segments`` = NumSegs; the scene's
                             ``name``: "<file stem> line <ID>" (one line) or "<file stem>"
OPTIONS (value, then key)
  WtrDpth                    ``environment.depth`` (seabed at z = -WtrDpth, as MoorDyn's);
                             missing or above a point: the deepest point's depth, as MoorDyn
  WtrDnsty / rho             ``environment.water_density``
  g / gravity                ``environment.gravity``
  kBot / kb                  ``seabed.stiffness`` (Pa/m); default MoorDyn's 3e6
  cBot / cb                  ``seabed.damping`` (Pa s/m); default MoorDyn's 3e5
  FrictionCoefficient        ``seabed.friction``
  FricDamp                   ``seabed.friction_velocity`` = w ds / FricDamp (default 200 N s/m):
                             MoorDyn's friction rises as mu FricDamp |v| per node up to mu N,
                             symcable's as mu N |v| / v_eps; equal slopes at N = w ds
  StatDynFricScale           ignored, with a note (one coefficient, static = dynamic)
  SeafloorFile               refused (a bathymetry file)
  WaveKin, Currents, dtWave  the files beside the deck (:mod:`.moordyn_water`): Currents 1, 3
                             -> ``environment.current_profile``; WaveKin 7
                             (wave_frequencies.txt), 3 (wave_elevation.txt) ->
                             ``[environment.waves]`` components; the others refused.
                             Without them ``current`` is zero
  anything else              ignored (dtM, CFL, TmaxIC, dtIC, threshIC, writeLog, fileIC,
                             dtOut, disableOutTime, ...: MoorDyn's solver settings)
OUTPUTS, title, comments     ignored
BODIES                       ``[bodies.body<ID>]`` (:mod:`.moordyn_bodies`); a point with
                             Attachment Body<ID> is a point on it (lines end at
                             ``"body<ID>@[X, Y, Z]"``, body axes)
RODS, ROD TYPES              a held rod (Fixed, Coupled, Body<N>): its ends are points the
                             lines attach to (``R<ID>A``, ``R<ID>B``); a moving rod (Free,
                             Pinned) is refused (:mod:`.moordyn_rods`)
FAILURE, SYROPE IC           refused when they hold a row
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
from .bodies import rotation_rpy
from .moordyn_bodies import _Bodies, body_name
from .moordyn_rods import _Rods
from .moordyn_tables import ZETA_FACTOR, _Tables, _float
from .moordyn_water import WATER_KEYS, water_kinematics

__all__ = ["ZETA_FACTOR", "MoorDynDeck", "is_moordyn_deck", "parse_moordyn"]


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
_REFUSED = {"failure": "line failures (not modelled)",
            "syrope": "Syrope initial conditions (no Syrope law)"}


#: OPTIONS keys (lower case) -> (table, key) in the scene
_OPTIONS = {"wtrdpth": ("environment", "depth"), "wtrdnsty": ("environment", "water_density"),
            "rho": ("environment", "water_density"), "g": ("environment", "gravity"),
            "gravity": ("environment", "gravity"), "kbot": ("seabed", "stiffness"),
            "kb": ("seabed", "stiffness"), "cbot": ("seabed", "damping"),
            "cb": ("seabed", "damping"), "frictioncoefficient": ("seabed", "friction")}
#: MoorDyn's defaults of the seabed options (MoorDyn2.cpp), which a deck leaving them out means
_SEABED_DEFAULTS = {"stiffness": 3.0e6, "damping": 3.0e5}
_FRICTION_NOTES = {"statdynfricscale": "symcable has one friction coefficient, static = dynamic"}
#: MoorDyn's default FricDamp, N s/m (MoorDyn2.cpp)
FRIC_DAMP = 200.0



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


class _Parser(_Tables, _Bodies, _Rods):
    def __init__(self, text: str, source: str):
        self.lines = tuple(text.splitlines())
        self.source = source
        self.notes: list[str] = []
        self.origin: dict[str, int] = {}
        self.water: dict[str, tuple[int, float]] = {}

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
        rows = self.line_rows(sec, types)
        found = self.point_rows(sec, rows, self.rod_rows(sec))
        bodies = self.body_rows(sec)
        if len(rows) == 1 and not bodies and not any(f[1] in ("free", "body")
                                                     for f in found.values()):
            body, held = self.one_line(types, rows[0], found)
        else:
            body, held = self.system(types, rows, found, bodies)
        env: dict[str, Any] = dict(options.get("environment", {}))
        deepest = -min(xyz[2] for xyz in held)
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
        env.update(water_kinematics(self.water, self.source, self.fail, self.notes))
        for key, option in (("current_profile", "currents"), ("waves", "wavekin")):
            if key in env:
                self.origin[f"environment.{key}"] = self.water[option][0]
        seabed = {**_SEABED_DEFAULTS, **options.get("seabed", {})}
        for key, value in _SEABED_DEFAULTS.items():
            if key not in options.get("seabed", {}):
                self.notes.append(f"seabed.{key} not in the deck: MoorDyn's default {value:g}")
        if seabed.get("friction", 0.0) > 0:
            seabed["friction_velocity"] = self.friction_velocity(
                types, rows, options.get("friction", {}).get("fricdamp", FRIC_DAMP),
                env.get("water_density", 1025.0), env.get("gravity", 9.80665))
        stem = os.path.splitext(os.path.basename(self.source))[0]
        used = list(dict.fromkeys(line["type"] for _, line in rows))
        name = f"{stem} line {rows[0][1]['id']}" if len(rows) == 1 else stem
        scene = {"name": name, "model": "cable3d", "environment": env, "seabed": seabed,
                 "line_types": {t: types[t][1] for t in used}, **body}
        for t in used:
            self.origin[_dotted("line_types", t)] = types[t][0]
        for t in types:
            if t not in used:
                self.notes.append(f"line {types[t][0]}: line type {t!r} unused, not read")
        return MoorDynDeck(scene=scene, notes=tuple(self.notes),
                           origin=MappingProxyType(dict(self.origin)), lines=self.lines,
                           source=self.source)

    def friction_velocity(self, types: dict, rows: list, fricdamp: float, rho: float,
                          g: float) -> float:
        """symcable's friction_velocity for MoorDyn's friction: MoorDyn's rises as
        mu FricDamp |v| (per node) until it reaches mu N, symcable's as mu N |v| / v_eps near
        rest, so v_eps = N / FricDamp with N a grounded node's contact force, its weight
        w ds (the smallest over the deck's lines; MoorDyn's transition is per node)."""
        if not fricdamp > 0:
            raise SceneError(f"{self.source}: FricDamp = {fricdamp!r}: must be > 0 N s/m")
        vs = []
        for _, line in rows:
            lt = types[line["type"]][1]
            w = (lt["mass"] - rho * math.pi * lt["diameter"] ** 2 / 4.0) * g
            vs.append(abs(w) * line["length"] / line["segments"] / fricdamp)
        v = max(min(vs), 1e-6)
        self.notes.append(f"friction: MoorDyn's law (mu FricDamp |v| up to mu N, FricDamp = "
                          f"{fricdamp:g} N s/m) as seabed.friction_velocity = w ds / FricDamp = "
                          f"{v:.4g} m/s")
        return v

    def one_line(self, types: dict, row: tuple[int, dict], found: dict) -> tuple[dict, list]:
        """A deck of one line between two held points: a version-1 scene (its sections,
        end_a, end_b) and the held positions."""
        line_n, line = row
        ends: dict[str, dict[str, Any]] = {}
        for end, ident in zip(("end_a", "end_b"), line["attach"]):
            n, kind, token, xyz, _ = found[ident]
            ends[end] = {"condition": "pinned", "position": xyz}
            self.origin[end] = n
            if kind == "vessel":
                self.notes.append(f"line {n}: {token} point {ident} is {end}, pinned at its "
                                  f"position (its motion is not in the deck: add {end}.motion, or "
                                  "simulate --motion FILE)")
        if all(found[i][1] == "vessel" for i in line["attach"]):
            raise self.fail(found[line["attach"][1]][0], "both ends are vessel points: one "
                            "must be Fixed (the anchor) in a one-line scene")
        self.origin["sections[0]"] = line_n
        return ({"sections": [{"type": line["type"], "length": line["length"],
                               "segments": line["segments"]}], **ends},
                [e["position"] for e in ends.values()])

    def system(self, types: dict, rows: list, found: dict, bodies: dict) -> tuple[dict, list]:
        """A deck of several lines, with free points or with bodies: a version-2 scene
        (points named by their IDs, lines ``line<ID>``, bodies ``body<ID>``,
        :mod:`.moordyn_bodies`) and the held positions (a body's points included)."""
        points: dict[str, dict[str, Any]] = {}
        ends: dict[int, str] = {}
        on_body: set[int] = set()
        held = []
        for ident, (n, kind, token, xyz, extra) in found.items():
            if kind == "body":
                if extra["body"] not in bodies:
                    raise self.fail(n, f"point {ident} ({token}) is a point on a body that "
                                       "BODIES does not define")
                b = bodies[extra["body"]][1]
                ends[ident] = f"{body_name(extra['body'])}@[{', '.join(repr(float(c)) for c in xyz)}]"
                on_body.add(extra["body"])
                held.append(list(b["position"] + rotation_rpy(b["orientation"]) @ xyz))
                continue
            pt: dict[str, Any] = {"kind": kind, "position": xyz}
            if kind == "free":
                pt.update(mass=extra["M"], volume=extra["V"], cd_area=[extra["CdA"]] * 3,
                          ca=extra["Ca"])
                force = [extra.get(k, 0.0) for k in ("Fx", "Fy", "Fz")]
                if any(force):
                    pt["force"] = force
            elif kind == "vessel":
                self.notes.append(f"line {n}: {token} point {ident} is held at its position "
                                  f"(its motion is not in the deck: add points.{ident}.motion, or "
                                  "simulate --motion FILE)")
            points[str(ident)] = pt
            self.origin[f"points.{ident}"] = n
        for ident, (n, body) in bodies.items():
            if ident not in on_body:
                raise self.fail(n, f"body {ident}: no line is attached to it (a point with "
                                   f"Attachment Body{ident} at a line's end)")
            self.origin[f"bodies.{body_name(ident)}"] = n
        lines = []
        for i, (n, line) in enumerate(rows):
            a, b = (ends.get(k, str(k)) for k in line["attach"])
            lines.append({"name": f"line{line['id']}", "end_a": a, "end_b": b,
                          "sections": [{"type": line["type"], "length": line["length"],
                                        "segments": line["segments"]}]})
            self.origin[f"lines[{i}]"] = n
        out: dict[str, Any] = {"points": points, "lines": lines}
        if bodies:
            out["bodies"] = {body_name(i): b for i, (_, b) in bodies.items()}
        return out, held + [f[3] for f in found.values() if f[1] not in ("free", "body")]

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
            if key in WATER_KEYS:
                self.water[key] = (n, self.number(n, value, entries[1]))
                continue
            if key == "fricdamp":
                out.setdefault("friction", {})["fricdamp"] = self.number(n, value, entries[1])
                self.origin["seabed.friction_velocity"] = n
            elif key in _FRICTION_NOTES:
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

def _dotted(path: str, key: str) -> str:
    """``path.key``, quoting the key as the scene's messages do when it is not bare."""
    if re.fullmatch(r"[A-Za-z0-9_-]+", key):
        return f"{path}.{key}"
    return f"{path}.{json.dumps(key, ensure_ascii=False)}"
