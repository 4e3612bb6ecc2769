"""The ROD TYPES and RODS tables of a MoorDyn v2 deck (:mod:`.moordyn`): a mix-in of the
deck parser, whose ``fail``, ``number``, ``table``, ``notes`` and ``lines`` it uses.

A MoorDyn rod is a rigid cylinder; lines attach to its ends (``R<ID>A``, ``R<ID>B``). Where
the rod is held, its ends are points the lines end at, and that is what symcable reads:

==========================  ================================================================
MoorDyn v2 rod Attachment   scene
==========================  ================================================================
Fixed, Fix, Anchor          its two ends are fixed points ``R<ID>A``, ``R<ID>B`` at
                            (Xa, Ya, Za), (Xb, Yb, Zb)
Coupled, Vessel, Ves, Cpld  its ends are vessel points (held where the deck puts them; their
                            motion is not in the deck), with a note
Body<N>                     its ends are points on body N at (Xa, Ya, Za), (Xb, Yb, Zb) in
                            body axes (``"body<N>@[X, Y, Z]"``)
Free, Pinned, Body<N>Pinned,  refused: the rod then moves as a rigid body of its own (6 or
CoupledPinned, Point        3 degrees of freedom), which symcable models as a body: give a
                            ``[bodies.NAME]`` in a TOML scene with the lines at its ends
==========================  ================================================================

A held rod's own mass, buoyancy and hydrodynamics (its ROD TYPES row) act on whatever holds
it, not on the lines: they are not read, with a note. A rod end no line attaches to is left
out.
"""
from __future__ import annotations

import re

__all__ = ["rod_end_name"]

_FIXED = ("FIXED", "FIX", "ANCHOR")
_VESSEL = ("COUPLED", "VESSEL", "VES", "CPLD")
_MOVING = ("FREE", "PINNED", "COUPLEDPINNED", "CPLDPIN", "POINT", "TURBINE")


def rod_end_name(ident: int, end: str) -> str:
    """The point name of rod ``ident``'s end ``"A"`` or ``"B"``: ``R<ID>A``, ``R<ID>B``
    (the token lines attach with)."""
    return f"R{ident}{end}"


class _Rods:
    """ROD TYPES and RODS of the deck (see the module's table)."""

    def rod_rows(self, sec: dict) -> dict[str, tuple]:
        """Rod end name (``R<ID>A``) -> (deck line, "fixed" | "vessel" | "body", the
        Attachment token, [X, Y, Z], {"body": N} for a body's): the ends of every held rod,
        in the form of the POINTS rows (:meth:`point_rows`)."""
        if "rods" not in sec or not sec["rods"][1][2:]:
            return {}
        _, rows = self.table(sec, "rods")
        types = self.rod_types(sec)
        out: dict[str, tuple] = {}
        seen: dict[int, int] = {}
        for n in rows:
            entries = self.lines[n - 1].split()
            if len(entries) < 10:
                raise self.fail(n, "a rod needs ID RodType Attachment Xa Ya Za Xb Yb Zb NumSegs")
            try:
                ident = int(entries[0])
            except ValueError:
                raise self.fail(n, f"rod ID {entries[0]!r}: must be an integer") from None
            if ident in seen:
                raise self.fail(n, f"rod {ident} defined twice (first at line {seen[ident]})")
            seen[ident] = n
            if entries[1] not in types:
                raise self.fail(n, f"unknown rod type {entries[1]!r} (defined: "
                                   f"{', '.join(map(repr, types)) or 'none'})")
            kind, extra = self._rod_attachment(n, entries[2])
            a = [self.number(n, t, c) for t, c in zip(entries[3:6], ("Xa", "Ya", "Za"))]
            b = [self.number(n, t, c) for t, c in zip(entries[6:9], ("Xb", "Yb", "Zb"))]
            for end, xyz in (("A", a), ("B", b)):
                out[rod_end_name(ident, end)] = (n, kind, entries[2], xyz, dict(extra))
            self.notes.append(f"line {n}: rod {ident} ({entries[2]}) holds its lines' ends at "
                              f"its ends R{ident}A, R{ident}B; its own weight, buoyancy and "
                              "hydrodynamics act on what holds it and are not read")
        return out

    def rod_types(self, sec: dict) -> dict[str, int]:
        """Rod type name -> its deck line (a held rod's properties are not read)."""
        if "rod_types" not in sec:
            return {}
        _, rows = self.table(sec, "rod_types")
        out: dict[str, int] = {}
        for n in rows:
            name = self.lines[n - 1].split()[0]
            if name in out:
                raise self.fail(n, f"rod type {name!r} defined twice (first at line "
                                   f"{out[name]})")
            out[name] = n
        return out

    def _rod_attachment(self, n: int, token: str) -> tuple[str, dict]:
        """("fixed" | "vessel" | "body", extra) of a rod's Attachment, or the refusal."""
        up = token.upper()
        m = re.fullmatch(r"BODY(\d+)(PINNED)?", up)
        if up in _FIXED:
            return "fixed", {}
        if up in _VESSEL:
            return "vessel", {}
        if m and not m.group(2):
            return "body", {"body": int(m.group(1))}
        if up in _MOVING or m:
            return self._refuse_rod(n, token)
        raise self.fail(n, f"unknown rod attachment {token!r} (MoorDyn's: Fixed, Coupled, "
                           "Vessel, Body<N>, Free, Pinned, Body<N>Pinned, CoupledPinned)")

    def _refuse_rod(self, n: int, token: str):
        raise self.fail(n, f"a {token} rod moves as a rigid body of its own, which symcable "
                           "models as a body, not a rod: give it as [bodies.NAME] in a TOML "
                           "scene with the lines at its ends, or hold it (Fixed, Coupled, "
                           "Body<N>)")
