"""The BODIES table of a MoorDyn v2 deck (:mod:`.moordyn`) read into ``[bodies.body<ID>]``:
a mix-in of the deck parser, whose ``fail``, ``number``, ``table`` and ``lines`` it uses.

==========================  ================================================================
MoorDyn v2 BODIES column    scene (``[bodies.body<ID>]``, :mod:`.bodies`)
==========================  ================================================================
ID                          the body's name ``body<ID>``
Attachment                  Free -> ``kind = "free"``; Fixed, Fix, Anchor -> ``"fixed"``;
                            Coupled, Vessel, Ves, Cpld -> ``"fixed"``, held where the deck
                            puts it (its motion is not in the deck), with a note;
                            CoupledPinned, Pinned, Turbine: refused (the rotation free under
                            a prescribed translation is not representable)
X0 Y0 Z0, r0 p0 y0          ``position`` (m), ``orientation`` ([roll, pitch, yaw], deg: the
                            same R = Rz Ry Rx as MoorDyn's and MoorPy's)
Mass                        ``mass`` (kg)
CG                          ``center_of_gravity``: one value z -> [0, 0, z]; or x|y|z
I                           ``inertia``: one value -> [I, I, I]; or Ix|Iy|Iz (about the centre
                            of gravity, body axes, as MoorDyn's)
Volume                      ``volume`` (m^3), its buoyancy at the reference point (MoorDyn's):
                            ``center_of_buoyancy = [0, 0, 0]``
CdA                         ``cd_area``, translational: one value -> [c, c, c]; two (t|r) ->
                            [t, t, t]; three -> them; six -> the first three. The rotational
                            drag (MoorDyn's other values) is not modelled: a note when it is
                            not zero (it acts in motion only, never in statics)
Ca                          ``ca_volume`` = Ca V along each axis: one value or Ca_x|Ca_y|Ca_z
==========================  ================================================================

A point whose Attachment is ``Body<ID>`` is a point fixed on that body at X, Y, Z in body
axes: a line end there is ``"body<ID>@[X, Y, Z]"``; its M and V must be 0 (MoorDyn adds them
to the body; give them to the body instead). A free body's mass, inertia must be > 0.
"""
from __future__ import annotations

import re
from typing import Any

__all__ = ["body_name"]

_FIXED = ("FIXED", "FIX", "ANCHOR")
_COUPLED = ("COUPLED", "VESSEL", "VES", "CPLD")
_FREE = ("FREE",)
_COLUMNS = ("ID", "Attachment", "X0", "Y0", "Z0", "r0", "p0", "y0", "Mass", "CG", "I",
            "Volume", "CdA", "Ca")


def body_name(ident: int) -> str:
    """The scene name of MoorDyn body ``ident``."""
    return f"body{ident}"


class _Bodies:
    """BODIES of the deck (the module docstring's table)."""

    def values(self, n: int, token: str, what: str, counts: tuple[int, ...]) -> list[float]:
        """The ``|``-separated numbers of ``token``, as many as one of ``counts``."""
        parts = [self.number(n, t, what) for t in token.split("|")]
        if len(parts) not in counts:
            raise self.fail(n, f"{what} = {token!r}: {' or '.join(map(str, counts))} values "
                               "separated by | (no spaces)")
        return parts

    def body_rows(self, sec: dict) -> dict[int, tuple[int, dict[str, Any]]]:
        """ID -> (deck line, the body's scene table)."""
        if "bodies" not in sec:
            return {}
        _, rows = self.table(sec, "bodies")
        out: dict[int, tuple[int, dict[str, Any]]] = {}
        for n in rows:
            e = self.lines[n - 1].split()
            if len(e) < len(_COLUMNS):
                raise self.fail(n, f"a body needs {' '.join(_COLUMNS)} ({len(_COLUMNS)} values)")
            try:
                ident = int(e[0])
            except ValueError:
                raise self.fail(n, f"body ID {e[0]!r}: must be an integer") from None
            if ident in out:
                raise self.fail(n, f"body {ident} defined twice (first at line {out[ident][0]})")
            kind = re.match(r"[A-Za-z]*", e[1]).group(0).upper()
            if kind not in _FIXED + _COUPLED + _FREE:
                raise self.fail(n, f"body attachment {e[1]!r} is not representable (Free, "
                                   "Fixed, Coupled or Vessel; a CoupledPinned or Turbine body "
                                   "turns freely under a prescribed translation)")
            pose = [self.number(n, t, c) for t, c in zip(e[2:8], _COLUMNS[2:8])]
            mass, volume = self.number(n, e[8], "Mass"), self.number(n, e[11], "Volume")
            cg = self.values(n, e[9], "CG", (1, 3))
            inertia = self.values(n, e[10], "I", (1, 3))
            cda = self.values(n, e[12], "CdA", (1, 2, 3, 6))
            ca = self.values(n, e[13], "Ca", (1, 3))
            cg = [0.0, 0.0, cg[0]] if len(cg) == 1 else cg
            inertia = inertia * 3 if len(inertia) == 1 else inertia
            trans = {1: cda * 3, 2: cda[:1] * 3, 3: cda, 6: cda[:3]}[len(cda)]
            rot = {1: cda, 2: cda[1:], 3: cda, 6: cda[3:]}[len(cda)]
            ca = ca * 3 if len(ca) == 1 else ca
            if min(mass, volume, *inertia, *trans, *ca) < 0:
                raise self.fail(n, "a body's Mass, I, Volume, CdA and Ca must be >= 0")
            body: dict[str, Any] = {"position": pose[:3], "orientation": pose[3:]}
            if kind in _FREE:
                if mass <= 0 or min(inertia) <= 0:
                    raise self.fail(n, f"free body {ident}: Mass and I must be > 0 (MoorDyn "
                                       "adds the mass of rods and points on it; symcable has "
                                       "neither: give the body its whole mass)")
                body.update(kind="free", mass=mass, inertia=inertia, volume=volume,
                            center_of_gravity=cg, center_of_buoyancy=[0.0, 0.0, 0.0],
                            cd_area=trans, ca_volume=[c * volume for c in ca])
                if any(rot):
                    self.notes.append(f"line {n}: body {ident}'s rotational drag (CdA "
                                      f"{e[12]}) is not modelled (symcable's body drag is "
                                      "translational; no effect on statics)")
            else:
                body["kind"] = "fixed"
                if kind in _COUPLED:
                    self.notes.append(f"line {n}: {e[1]} body {ident} is held at its position "
                                      "(its motion is not in the deck: simulate --motion "
                                      "FILE, or kind = 'vessel' with a motion)")
            out[ident] = (n, body)
        return out
