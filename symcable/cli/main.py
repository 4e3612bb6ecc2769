"""The ``symcable`` command: check a scene, solve it, run the demo.

Every error becomes one line on stderr and exit status 2 (the traceback only with
``--debug``); an interrupt (Ctrl-C) exits 130. Every subcommand takes the resource limits
of :mod:`symcable.limits` (``--max-segments``, ``--max-steps``, ...). A dynamic
result outside the range where the linearised dynamics hold (status "invalid") is printed,
with its reason on one line of stderr and exit status 3; ``check`` exits 1 when the scene's
motion would be refused.
"""
from __future__ import annotations

import argparse
import json
import sys
import traceback
import warnings
from pathlib import Path

from ..errors import SymcableError
from ..limits import OPTIONS, Limits, limits

def _scene_summary(scene, n_unknowns: int, terms) -> str:
    lines = [f"scene      {scene.name}  ({scene.source})",
             f"model      {scene.model.value}: {n_unknowns} unknowns, terms: {', '.join(terms)}",
             f"line       {scene.length:.3f} m in {scene.n_segments} segments"]
    if scene.environment.waves is not None:
        lines.insert(2, f"waves      {_waves_text(scene.environment.waves)}")
    if scene.version == 2:
        return "\n".join(lines[:-1] + _system_summary(scene))
    for k, sec in enumerate(scene.sections):
        lt = sec.line_type
        ei = f"EI {lt.EI:.4g} N m^2" if getattr(lt, "EI_2", None) is None else \
            f"EI {lt.EI:.4g}, {lt.EI_2:.4g} N m^2"
        rod = getattr(lt, "GJ", None) is not None and lt.GJ > 0
        kind = f", {sec.model}" if getattr(sec, "model", None) else ""
        lines.append(f"  section {k}: {sec.length:.3f} m of '{lt.name}' in {sec.segments} segments "
                     f"(EA {lt.EA:.4g} N, {ei}" + (f", GJ {lt.GJ:.4g} N m^2" if rod else "")
                     + f", w {lt.weight:.4g} N/m{kind})")
    if getattr(scene, "zones", "given") == "auto":
        lines.append("  zones      auto: rod sections chosen from the static tension "
                     "(sc.solve_static reports them in stats['zones'])")
    for label, end in (("end_a", scene.end_a), ("end_b", scene.end_b)):
        extra = ""
        if end.position is not None:
            extra += f" at ({', '.join(f'{v:.3f}' for v in end.position)}) m"
        if end.angle_deg is not None:
            extra += f", angle {end.angle_deg:g} deg"
        if getattr(end, "direction", None) is not None:
            extra += f", direction ({', '.join(f'{v:.4g}' for v in end.direction)})"
        if getattr(end, "twist_deg", None) is not None:
            extra += f", twist {end.twist_deg:g} deg"
        if getattr(end, "moment", None) is not None:
            extra += f", moment ({', '.join(f'{v:.4g}' for v in end.moment)}) N m"
        if end.force is not None:
            extra += f", force ({', '.join(f'{v:.4g}' for v in end.force)}) N"
        if end.motion is not None:
            m = end.motion
            extra += (f", motion from {m.file} ({len(m.samples)} rows over {m.period:g} s)"
                      if m.kind == "table" else
                      f", towed at {m.speed:g} m/s heading {m.heading_deg:g} deg"
                      + (f", {len(m.turns)} turn(s) over {m.period:g} s" if m.turns else "")
                      if m.kind == "tow" else f", harmonic motion of period {m.period:g} s")
        cond = "guided" if getattr(end, "guided", False) else end.condition.value
        lines.append(f"{label}      {cond}{extra}")
    return "\n".join(lines)


def _waves_text(w) -> str:
    """One line on a scene's sea (``[environment.waves]``)."""
    where = f", toward {w.direction_deg:g} deg, {w.stretching} stretching"
    if w.kind == "regular":
        return f"regular, height {w.height:g} m, period {w.period:g} s{where}"
    if w.kind == "components":
        return f"{w.count} given components{where}"
    gamma = f", gamma {w.gamma:g}" if w.kind == "jonswap" else ""
    return (f"{w.kind}, Hs {w.hs:g} m, Tp {w.tp:g} s{gamma}, {w.count} components (seed "
            f"{w.seed}){where}")


def _body_motion_text(m) -> str:
    """A vessel's motion in a few words."""
    if m.kind == "table":
        return f", moved by {m.file} ({len(m.samples)} rows over {m.period:g} s)"
    if m.kind == "rao":
        return (f", moved by its RAOs at {len(m.omegas)} frequencies "
                f"({min(m.omegas):g}-{max(m.omegas):g} rad/s)")
    return f", harmonic motion of period {m.period:g} s"


def _end_text(end) -> str:
    if isinstance(end, str):
        return f"point '{end}'"
    if hasattr(end, "body"):
        return f"body point '{end.text}'"
    return end.condition.value + (f" at ({', '.join(f'{v:.3f}' for v in end.position)}) m"
                                  if end.position is not None else "")


def _system_summary(scene) -> list:
    """Lines of a version-2 scene: its points, then its lines with their sections."""
    out = []
    for name, pt in scene.points.items():
        extra = f", mass {pt.mass:g} kg" if pt.mass else ""
        extra += f", volume {pt.volume:g} m^3" if pt.volume else ""
        extra += ", moving" if pt.motion is not None else ""
        out.append(f"point      {name}: {pt.kind.value} at "
                   f"({', '.join(f'{v:.3f}' for v in pt.position)}) m{extra}")
    for name, b in scene.bodies.items():
        extra = f", mass {b.mass:g} kg, volume {b.volume:g} m^3" if b.is_free else ""
        extra += _body_motion_text(b.motion) if b.motion is not None else ""
        out.append(f"body       {name}: {b.kind.value} at "
                   f"({', '.join(f'{v:.3f}' for v in b.position)}) m, roll/pitch/yaw "
                   f"({', '.join(f'{v:g}' for v in b.orientation_deg)}) deg{extra}")
    for ln in scene.lines:
        out.append(f"line       {ln.name}: {ln.length:.3f} m in {ln.n_segments} segments, from "
                   f"{_end_text(ln.end_a)} to {_end_text(ln.end_b)}")
        for k, sec in enumerate(ln.sections):
            lt = sec.line_type
            out.append(f"  section {k}: {sec.length:.3f} m of '{lt.name}' in {sec.segments} "
                       f"segments (EA {lt.EA:.4g} N, w {lt.weight:.4g} N/m)")
    return out


def _static(scene_path, args) -> int:
    from ..api.planar_static import solve_static
    from ..scene import load_scene

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
        from ..plotting.profiles import close
        close(sol.plot(args.plot, scene=scene))
        if not args.json:
            print(f"plot              {args.plot}")
    return 0


def _check(args) -> int:
    from ..api.analyses import dynamics_scene
    from ..api.planar_static import solve_static
    from ..models import build_model, formulation_of
    from ..scene import load_scene, moordyn_deck

    scene = load_scene(args.scene)
    if not formulation_of(scene).linearised:
        from ..api.scene3d import scene_mechanism
        mech = scene_mechanism(scene)
        print(_scene_summary(scene, mech.n_q, mech.terms))
        deck = moordyn_deck(args.scene) if isinstance(args.scene, str) else None
        for note in deck.notes if deck is not None else ():
            print(f"deck note  {note}")
        print("ok")
        return 0
    model = build_model(scene)
    print(_scene_summary(scene, model.n_w, model.terms))
    if not any(e.motion is not None for e in (scene.end_a, scene.end_b)):
        print("ok")
        return 0
    # a moving scene: its dynamics are linearised about the static state, so whether they
    # can run, and how, is only known from that state
    static = solve_static(scene, codegen=False, estimate=False)
    try:
        run = dynamics_scene(scene)
    except SymcableError as exc:
        print(f"dynamics   refused: {exc}")
        print("not ok: the scene's motion cannot run (simulate and periodic would refuse it; "
              "static runs)")
        return 1
    if run is not scene:
        print(f"dynamics   ok: the static line rests {static.grounded_length:.4g} m on the "
              f"seabed, which the linearised dynamics do not model; simulate, periodic and "
              f"modes run it as model = {run.model.value!r} in its plane")
    else:
        from ..results.io import force_text
        print(f"dynamics   ok: linearised about the static state (fairlead tension "
              f"{force_text(static.fairlead_tension)}, grounded length "
              f"{static.grounded_length:.3g} m)")
    print("ok")
    return 0


def _emit(result, args, plot) -> None:
    """Print JSON or the summary, save and plot as asked."""
    if args.json:
        d = result.to_dict()
        d.pop("states", None)
        d.pop("unknowns", None)
        print(json.dumps(d, indent=1))
    else:
        print(result.summary())
    if getattr(args, "save", None):
        result.save(args.save)
    if args.plot:
        from ..plotting.profiles import close
        close(plot(args.plot))
        if not args.json:
            print(f"plot              {args.plot}")


#: exit status of a dynamic result whose status is "invalid" (outside the range where the
#: linearised dynamics hold): it was computed and is printed, but it is not an answer
EXIT_INVALID = 3


def _exit_status(result) -> int:
    """0, or EXIT_INVALID with the reason on one line of stderr for an invalid result."""
    if result.status != "invalid":
        return 0
    why = next((w for w in result.warnings if w.startswith("invalid")), "invalid result")
    print(f"symcable: {why}", file=sys.stderr)
    return EXIT_INVALID


def _simulate(args) -> int:
    from ..scene import load_scene
    from ..api.analyses import simulate
    from ..api.analyses import check_steps
    from ..plotting.profiles import plot_trajectory
    from ..results.line3d import LineTrajectory, SystemTrajectory

    scene = load_scene(args.scene)
    if args.motion is not None:
        from ..scene.moving import with_motion
        scene = with_motion(scene, args.motion, args.moving)
    elif args.moving is not None:
        raise SymcableError(f"--moving {args.moving}: names what --motion FILE moves; give "
                            "--motion")
    motions = [e.motion for e in (scene.end_a, scene.end_b) if e is not None and e.motion] \
        + [pt.motion for pt in (scene.points or {}).values() if getattr(pt, "motion", None)] \
        + [b.motion for b in (scene.bodies or {}).values() if b.motion is not None]
    period = next((m.period for m in motions if m.kind == "harmonic"), None)
    # a table runs over its rows, a tow over its turns (and a minute more), a harmonic
    # motion ten periods
    table = next((m for m in motions if m.kind == "table"), None)
    tow = next((m for m in motions if m.kind == "tow"), None)
    duration = args.duration if args.duration is not None else (table.period if table else tow.period + 60.0 if tow
                                 else 10.0 * period if period else 60.0)
    # the options as given, in one line each (the API would name its parameters instead)
    check_steps(duration, args.dt, min((m.period for m in motions if m.kind == "harmonic"),
                                       default=None), names=("--duration", "--dt"))
    if args.tol is not None:  # (named as the option, before any solve)
        from ..api.time_tolerance import check_tol
        if args.dt is not None:
            raise SymcableError(f"--tol {args.tol:g} with --dt {args.dt:g}: give one (--dt a "
                                "fixed step, --tol the step chosen for it)")
        try:
            check_tol(args.tol)
        except SymcableError:
            raise SymcableError(f"--tol {args.tol!r}: must be a number in (0, 1), the error "
                                "asked of the end tensions relative to their range (e.g. 0.01)"
                                ) from None
    traj = simulate(scene, duration, dt=args.dt, method=args.method, tol=args.tol)
    if tow is not None:  # a tow: tracks in plan, towed depth, towpoint tension / T0
        from ..plotting.tows import plot_tow
        _emit(traj, args, lambda path: plot_tow(traj, scene, path))
        return _exit_status(traj)
    _emit(traj, args, lambda path: (_plot_3d(traj, scene, path)
                                    if isinstance(traj, (LineTrajectory, SystemTrajectory))
                                    else plot_trajectory(traj, path)))
    return _exit_status(traj)


def _plot_3d(res, scene, path):
    """A cable3d time or periodic result's plot: a one-line scene's own; a scene of several
    lines and points (a SystemTrajectory): every line's end tensions over T0, the static
    solution's (its plain kN if the static solve fails)."""
    if not hasattr(res, "line_names"):
        return res.plot(path)
    from ..api.analyses import solve_static
    try:
        st = solve_static(scene, estimate=False)
        t0 = {n: (st.lines[n].anchor_tension, st.lines[n].fairlead_tension)
              for n in res.line_names}
    except SymcableError:
        t0 = None
    return res.plot(path, t0=t0)


def _periodic(args) -> int:
    from ..scene import load_scene
    from ..api.analyses import runs_on_mechanism, solve_periodic
    from ..plotting.profiles import plot_periodic
    from ..results.line3d import LineTrajectory, SystemTrajectory

    scene = load_scene(args.scene)
    # on the Mechanism: the Floquet multipliers too (the linearised path does not take them)
    per = solve_periodic(scene, method=args.method, **(
        {"stability": not args.no_stability} if runs_on_mechanism(scene) else {}))
    _emit(per, args, lambda path: (_plot_3d(per, scene, path)
                                   if isinstance(per, (LineTrajectory, SystemTrajectory))
                                   else plot_periodic(per, path)))
    if "floquet_max" in per.stats and not args.json:
        print(f"stable: {'yes' if per.stats['stable'] else 'no'}, largest Floquet multiplier "
              f"|mu| = {per.stats['floquet_max']:.6g} (margin {per.stats['floquet_margin']:g}, "
              f"monodromy of {per.stats['floquet_steps']} steps)")
    return _exit_status(per)


def _modes(args) -> int:
    from ..scene import load_scene
    from ..api.analyses import modal_analysis
    from ..plotting.profiles import plot_modes

    scene = load_scene(args.scene)
    modal = modal_analysis(scene, args.n, **({"max_dense": args.max_dense}
                                             if args.max_dense is not None else {}))
    if modal.positions.shape[-1] == 3:
        from ..plotting.line3d import plot_modes_3d
        depth = scene.environment.depth
        _emit(modal, args, lambda path: plot_modes_3d(
            modal, path, seabed=None if depth is None else -float(depth)))
        return 0
    _emit(modal, args, lambda path: plot_modes(modal, modal.positions, path))
    return 0


def _linearize(args) -> int:
    from ..api.analyses import linearize

    lin = linearize(args.scene, undamped=args.undamped)
    print(json.dumps(lin.to_dict(), indent=1) if args.json else lin.summary())
    if args.save:
        lin.save(args.save)
    if args.plot:
        from ..plotting.profiles import close
        close(lin.plot(args.plot))
        if not args.json:
            print(f"plot              {args.plot}")
    return 0


def _demo(args) -> int:
    from .. import demo_scene_path
    from ..api.analyses import solve_periodic
    from ..plotting.profiles import plot_periodic, close
    from ..scene import load_scene

    print("symcable demo 1/2: statics of the OC3-Hywind mooring line (planar, 50 segments, "
          "seabed contact)\n")
    args.json = False
    plot = args.plot or "symcable-demo.png"
    args.plot = plot
    _static(demo_scene_path(), args)
    print("\nsymcable demo 2/2: periodic steady state of the seed001 line (suspended, current "
          "0.5 m/s, elliptic fairlead motion, T = 10 s)\n")
    scene = load_scene(demo_scene_path("seed001"))
    per = solve_periodic(scene, "collocation")  # as docs/demo-periodic.png and its caption
    print(per.summary())
    stem = Path(plot)
    periodic_plot = stem.with_name(stem.stem + "-periodic" + stem.suffix)
    close(plot_periodic(per, periodic_plot))
    print(f"plot              {periodic_plot}")
    return 0


def _codegen(args) -> int:
    from ..api.export import export_scene
    from ..scene import load_scene

    scene = load_scene(args.scene)
    if args.coupling:
        from ..api.export_coupling import export_coupling
        paths = export_coupling(scene, args.out, stem=args.stem or "symcable_lines",
                                coupled=args.coupled)
    else:
        if args.coupled:
            raise SymcableError("--coupled: only with --coupling")
        paths = export_scene(scene, args.out, stem=args.stem or "symcable_scene")
    for path in paths:
        print(path)
    return 0


def _cache(args) -> int:
    from ..mechanism.codegen import cache_info, clear_cache

    if args.action == "clear":
        n = clear_cache()
        print(f"removed {n} entries from {cache_info()['folder']}")
    else:
        info = cache_info()
        print(f"build cache {info['folder']}: {info['entries']} entries, {info['bytes'] / 1e6:.1f} MB")
    return 0


def _output_options(p: argparse.ArgumentParser, what: str) -> None:
    """The options every analysis shares: JSON on stdout, a figure, a saved result."""
    p.add_argument("--json", action="store_true", help=f"print the {what} as JSON (SI units)")
    p.add_argument("--plot", metavar="FILE", help="save its figure (PNG, PDF or SVG)")
    p.add_argument("--save", metavar="FILE", help=f"save the {what} (.npz or .json)")


def build_parser() -> argparse.ArgumentParser:
    ap = argparse.ArgumentParser(prog="symcable", description=__doc__.splitlines()[0])
    sub = ap.add_subparsers(dest="command", required=True)
    p = sub.add_parser("check", help="validate a scene file and show what it builds")
    p.add_argument("scene")
    p = sub.add_parser("static", help="static configuration of a scene")
    p.add_argument("scene")
    _output_options(p, "solution")
    p = sub.add_parser("simulate", help="time response to the scene's end motion")
    p.add_argument("scene")
    _output_options(p, "trajectory")
    p.add_argument("--duration", type=float, help="s (default 10 excitation periods; a table's "
                   "span; a tow's turns plus 60 s)")
    p.add_argument("--dt", type=float, help="a fixed time step, s (default: generalized-alpha "
                   "chosen for --tol, RK4 its stability limit)")
    p.add_argument("--tol", type=float, help="generalized-alpha: the end tensions' error asked, "
                   "a fraction of their range (default 0.01; not with --dt)")
    p.add_argument("--method", default="generalized-alpha", choices=["generalized-alpha", "rk4"])
    p.add_argument("--motion", metavar="FILE", help="a motion table, rows t x y z [roll pitch "
                   "yaw] (s, m, deg, from the scene's pose), for end B of a one-line scene, "
                   "the scene's one fixed or vessel body, or else its vessel points moved as "
                   "one vessel about their centroid at z = 0")
    p.add_argument("--moving", metavar="NAME", help="with --motion: the body, point or end "
                   "(end_a, end_b) it moves")
    p = sub.add_parser("periodic", help="periodic steady state over one excitation period")
    p.add_argument("scene")
    _output_options(p, "solution")
    p.add_argument("--method", default="shooting", choices=["collocation", "harmonic-balance", "shooting"])
    p.add_argument("--no-stability", action="store_true", help="cable3d: skip the Floquet "
                   "multipliers (the monodromy costs about as much as the solve)")
    p = sub.add_parser("modes", help="natural frequencies and mode shapes")
    p.add_argument("scene")
    _output_options(p, "modes")
    p.add_argument("--n", type=int, default=6, help="number of modes (default 6)")
    p.add_argument("--max-dense", type=int, default=None, metavar="N", help="largest dense "
                   "eigenproblem (default 3000; a larger symmetric one is solved sparse for a "
                   "few modes)")
    p = sub.add_parser("linearize", help="exact stiffness, damping and mass about the static "
                       "state; each held end's stiffness and each free body's")
    p.add_argument("scene")
    p.add_argument("--json", action="store_true", help="print the linearisation as JSON (SI "
                   "units)")
    p.add_argument("--save", metavar="FILE", help="save the linearisation (.npz or .json)")
    p.add_argument("--plot", metavar="FILE", help="save a map of K, C and M (PNG, PDF or SVG)")
    p.add_argument("--undamped", action="store_true", help="current, excitation and the "
                   "closure stabilisation off (as modes has them)")
    p = sub.add_parser("codegen", help="write standalone C sources for a scene: its static "
                       "solve and (when it moves) its time step, with README and main.c")
    p.add_argument("scene")
    p.add_argument("--out", required=True, metavar="DIR", help="folder to write into (created)")
    p.add_argument("--stem", default=None, help="name of the C files (a letter, then letters, "
                   "digits or underscores; default symcable_scene, with --coupling "
                   "symcable_lines)")
    p.add_argument("--coupling", action="store_true", help="write instead the coupling "
                   "library a host program steps (symcable_coupling.h: sc_initialize, "
                   "sc_step, ...), with an example host.c")
    p.add_argument("--coupled", action="append", metavar="NAME", help="with --coupling: a "
                   "point or body the host moves (repeat for several; default every vessel "
                   "point and body)")
    p = sub.add_parser("cache", help="the build cache of generated C (SYMCABLE_CACHE_DIR)")
    p.add_argument("action", choices=["info", "clear"])
    p = sub.add_parser("demo", help="the built-in scenes: OC3 statics, the seed001 periodic response")
    p.add_argument("--plot", metavar="FILE", help="figure path (default symcable-demo.png)")
    p.add_argument("--save", metavar="FILE", help="save the static solution (.npz or .json)")
    from ..sweep.command import add_parser as add_sweep
    add_sweep(sub)
    from .offsets import add_parser as add_offsets
    add_offsets(sub)
    from .design import add_parser as add_sensitivity
    add_sensitivity(sub)
    for p in sub.choices.values():
        _common_options(p)
    return ap


def _common_options(p: argparse.ArgumentParser) -> None:
    """``--debug`` and the resource limits (:mod:`symcable.limits`), on every subcommand."""
    p.add_argument("--debug", action="store_true", help="on an error, print its traceback too")
    g = p.add_argument_group("resource limits (a guard against inputs that exhaust the "
                             "machine; defaults in parentheses)")
    base = Limits()
    for name, (option, factor, what) in OPTIONS.items():
        unit = "MB" if factor != 1 else "N"
        g.add_argument(option, type=_positive(float if factor != 1 else int), metavar=unit,
                       dest=f"limit_{name}", help=f"{what} ({getattr(base, name) // factor:,}"
                       + (" MB)" if factor != 1 else ")"))


def _positive(kind):
    def parse(text: str):
        try:
            value = kind(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"{text!r}: must be a number > 0") from None
        if not value > 0 or value == float("inf"):
            raise argparse.ArgumentTypeError(f"{text!r}: must be a finite number > 0")
        return value
    return parse


def _limits(args) -> dict:
    """The limits the options change: {name: value in the limit's unit}."""
    out = {}
    for name, (_, factor, _) in OPTIONS.items():
        value = getattr(args, f"limit_{name}", None)
        if value is not None:
            out[name] = max(1, int(value * factor))
    return out


def _show_warning(message, category, filename, lineno, file=None, line=None) -> None:
    """A Python warning as one line on stderr (no source file and line)."""
    print(f"symcable: warning: {_one_line(message)}", file=sys.stderr)


def _one_line(exc: BaseException) -> str:
    return " ".join(str(exc).split()) or repr(exc)


def main(argv: list[str] | None = None) -> int:
    args = build_parser().parse_args(argv)
    from .. import progress
    try:
        with limits(**_limits(args)), warnings.catch_warnings():
            warnings.showwarning = _show_warning
            progress.show_notices(True)  # the one line while compiling generated C, on stderr
            return _run(args)
    except KeyboardInterrupt:
        print("symcable: interrupted", file=sys.stderr)
        return 130
    except Exception as exc:  # one line; the traceback with --debug
        if getattr(args, "debug", False):
            traceback.print_exc()
        if isinstance(exc, SymcableError):
            print(f"symcable: {type(exc).__name__}: {_one_line(exc)}", file=sys.stderr)
        elif isinstance(exc, OSError):
            print(f"symcable: {_one_line(exc)}", file=sys.stderr)
        else:
            what = {MemoryError: "out of memory", RecursionError: "input nested too deeply"}
            what = "out of memory" if "bad_alloc" in str(exc) else \
                what.get(type(exc), type(exc).__name__)  # CasADi's C++ std::bad_alloc
            print(f"symcable: internal error ({what}: "
                  f"{_one_line(exc)}); run again with --debug for the traceback and report it",
                  file=sys.stderr)
        return 2
    finally:
        progress.show_notices(None)


#: figure formats ``--plot`` writes (by the file's suffix)
PLOT_FORMATS = (".png", ".pdf", ".svg", ".svgz", ".eps", ".ps", ".jpg", ".jpeg", ".tif",
                ".tiff", ".webp")
#: result formats ``--save`` writes
SAVE_FORMATS = (".npz", ".json")


def _check_outputs(args) -> None:
    """``--plot`` and ``--save`` name a file of a known format in an existing folder (checked
    before the analysis runs)."""
    for option, formats in (("plot", PLOT_FORMATS), ("save", SAVE_FORMATS)):
        path = getattr(args, option, None)
        if path is None:
            continue
        p = Path(path)
        if p.suffix.lower() not in formats:
            raise SymcableError(f"--{option} {path!r}: the file name must end in one of "
                                f"{', '.join(formats)}")
        if not p.parent.is_dir():
            raise SymcableError(f"--{option} {path!r}: the folder {str(p.parent)!r} does not "
                                "exist")


def _run(args) -> int:
    """The subcommand ``args`` names."""
    _check_outputs(args)
    if getattr(args, "scene", None) is not None:  # a built-in scene by name: "sphere"
        from ..data import resolve
        args.scene = resolve(args.scene)
    commands = {"check": _check, "static": lambda a: _static(a.scene, a), "demo": _demo,
                "simulate": _simulate, "periodic": _periodic, "modes": _modes,
                "linearize": _linearize,
                "codegen": _codegen, "cache": _cache}
    if args.command in commands:
        return commands[args.command](args)
    if args.command == "sweep":
        from ..sweep.command import main as sweep
        return sweep(args)
    if args.command == "sensitivity":
        from .design import main as sensitivity
        return sensitivity(args)
    from .offsets import main as offsets
    return offsets(args)


if __name__ == "__main__":
    sys.exit(main())
