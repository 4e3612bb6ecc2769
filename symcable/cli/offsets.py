"""``symcable offsets SCENE --body NAME --dof surge --range -20 20 --n 41``: the offset
sweep of :func:`symcable.api.offsets.offset_sweep` from the command line (summary, JSON, the
force-offset figure, the saved result)."""
from __future__ import annotations

import json

from ..results.offsets import DOF_NAMES

__all__ = ["add_parser", "main"]


def add_parser(sub) -> None:
    """The ``offsets`` subcommand on the ``symcable`` parser's subparsers ``sub``."""
    p = sub.add_parser("offsets", help="restoring force on a moored body over a sweep of "
                                       "offsets (one batched static solve)")
    p.add_argument("scene")
    p.add_argument("--body", required=True, help="the body's name ([bodies.NAME])")
    p.add_argument("--dof", default="surge", choices=DOF_NAMES,
                   help="the offset swept (m for surge/sway/heave, deg for roll/pitch/yaw)")
    p.add_argument("--range", nargs=2, type=float, default=(-10.0, 10.0),
                   metavar=("FROM", "TO"), help="the offsets' range (default -10 10)")
    p.add_argument("--n", type=int, default=41, help="number of offsets (default 41)")
    p.add_argument("--about", default="equilibrium", choices=("equilibrium", "scene"),
                   help="offsets from the body's static equilibrium or from where the scene "
                        "puts it")
    p.add_argument("--json", action="store_true", help="print the sweep as JSON (SI units)")
    p.add_argument("--plot", metavar="FILE", help="save the force-offset figure")
    p.add_argument("--save", metavar="FILE", help="save the sweep (.npz or .json)")


def main(args) -> int:
    """Run the sweep of ``args``; exit status 0, or 3 when some offset failed."""
    from ..api.offsets import offset_sweep, offsets_along

    res = offset_sweep(args.scene, args.body, offsets_along(args.dof, *args.range, args.n),
                       about=args.about)
    print(json.dumps(res.to_dict(), indent=1) if args.json else res.summary())
    if args.save:
        res.save(args.save)
    if args.plot:
        from ..plotting.profiles import close
        close(res.plot(args.plot, dof=args.dof))
        if not args.json:
            print(f"plot              {args.plot}")
    return 0 if res.converged.all() else 3
