"""``symcable sensitivity``: exact derivatives of a static state's outputs with respect to
numbers of the scene (:func:`symcable.sensitivity`)."""
from __future__ import annotations

import json

__all__ = ["add_parser", "main"]


def add_parser(sub) -> None:
    """The ``sensitivity`` subcommand on the ``symcable`` parser's subparsers ``sub``."""
    p = sub.add_parser("sensitivity", help="exact derivatives of static outputs with respect "
                                           "to numbers of the scene (design sensitivities)")
    p.add_argument("scene")
    p.add_argument("--output", action="append", required=True, metavar="NAME",
                   help="a static output (line0.fairlead_tension, spar.force, NAME[i]); "
                        "repeat for several")
    p.add_argument("--parameter", action="append", required=True, metavar="PATH",
                   help="a number of the scene by its path (line_types.chain.diameter, "
                        "lines[0].sections[0].length, points.a.position[0]); repeat")
    p.add_argument("--json", action="store_true", help="print the derivatives as JSON (SI "
                                                       "units)")


def main(args) -> int:
    """Print the sensitivities of ``args``."""
    from ..api.sensitivity import sensitivity

    s = sensitivity(args.scene, args.output, args.parameter)
    print(json.dumps(s.to_dict(), indent=1) if args.json else s.summary())
    return 0
