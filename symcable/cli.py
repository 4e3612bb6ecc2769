"""The ``symcable`` command: check a scene, solve it, run the demo.

Every symcable error becomes one line on stderr and exit status 2; no traceback.
"""
from __future__ import annotations

import argparse
import json
import sys

from .errors import SymcableError


def _scene_summary(scene, model) -> str:
    lines = [f"scene      {scene.name}  ({scene.source})",
             f"model      {scene.model.value}: {model.n_w} unknowns, terms: {', '.join(model.terms)}",
             f"line       {scene.length:.3f} m in {scene.n_segments} segments"]
    for k, sec in enumerate(scene.sections):
        lt = sec.line_type
        lines.append(f"  section {k}: {sec.length:.3f} m of '{lt.name}' in {sec.segments} segments "
                     f"(EA {lt.EA:.4g} N, EI {lt.EI:.4g} N m^2, w {lt.weight:.4g} N/m)")
    for label, end in (("end_a", scene.end_a), ("end_b", scene.end_b)):
        extra = ""
        if end.position is not None:
            extra += f" at ({', '.join(f'{v:.3f}' for v in end.position)}) m"
        if end.angle_deg is not None:
            extra += f", angle {end.angle_deg:g} deg"
        if end.force is not None:
            extra += f", force ({', '.join(f'{v:.4g}' for v in end.force)}) N"
        if end.motion is not None:
            extra += f", harmonic motion of period {end.motion.period:g} s"
        lines.append(f"{label}      {end.condition.value}{extra}")
    return "\n".join(lines)


def _static(scene_path, args) -> int:
    from .solvers.static import solve_static
    from .scene_loader import load_scene

    scene = load_scene(scene_path)
    sol = solve_static(scene)
    if args.json:
        d = sol.to_dict()
        d.pop("unknowns", None)
        print(json.dumps(d, indent=1))
    else:
        print(sol.summary())
    if args.save:
        sol.save(args.save)
    if args.plot:
        from .plotting import close
        close(sol.plot(args.plot))
        if not args.json:
            print(f"plot              {args.plot}")
    return 0


def _check(args) -> int:
    from .models import build_model
    from .scene_loader import load_scene

    scene = load_scene(args.scene)
    print(_scene_summary(scene, build_model(scene)))
    print("ok")
    return 0


def _demo(args) -> int:
    from . import demo_scene_path
    print("symcable demo: the OC3-Hywind mooring line (planar, 50 segments, seabed contact)\n")
    args.json = False
    args.plot = args.plot or "symcable-demo.png"
    return _static(demo_scene_path(), args)


def build_parser() -> argparse.ArgumentParser:
    ap = argparse.ArgumentParser(prog="symcable", description=__doc__.splitlines()[0])
    sub = ap.add_subparsers(dest="command", required=True)
    p = sub.add_parser("check", help="validate a scene file and show what it builds")
    p.add_argument("scene")
    p = sub.add_parser("static", help="static configuration of a scene")
    p.add_argument("scene")
    p.add_argument("--json", action="store_true", help="print the solution as JSON (SI units)")
    p.add_argument("--plot", metavar="FILE", help="save the profile/tension/moment figure")
    p.add_argument("--save", metavar="FILE", help="save the solution (.npz or .json)")
    p = sub.add_parser("demo", help="solve the built-in OC3 scene and plot it")
    p.add_argument("--plot", metavar="FILE", help="figure path (default symcable-demo.png)")
    p.add_argument("--save", metavar="FILE", help="save the solution (.npz or .json)")
    return ap


def main(argv: list[str] | None = None) -> int:
    args = build_parser().parse_args(argv)
    try:
        if args.command == "check":
            return _check(args)
        if args.command == "static":
            return _static(args.scene, args)
        if args.command == "demo":
            return _demo(args)
    except SymcableError as exc:
        print(f"symcable: {type(exc).__name__}: {exc}", file=sys.stderr)
        return 2
    except OSError as exc:
        print(f"symcable: {exc}", file=sys.stderr)
        return 2
    return 1


if __name__ == "__main__":
    sys.exit(main())
