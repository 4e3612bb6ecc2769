"""The conformance matrix: every analysis on every built-in scene, through the Python API and
through the CLI, each cell classified.

Question: does every (scene, analysis, surface) cell either WORK or get REFUSED with one clear
line? Anything else is a FAIL: a Python traceback, an "internal error", a CLI exit status
other than 0 or 2, a NaN in a result, a plot not written (or blank), a save/load round trip
that is not exact, a refusal of more than one line.

Rows: the built-in scenes (symcable/data/*.toml), one single-line MoorDyn chain deck of
../shared/reference/moordyn-chains and one multi-line MoorDyn deck (decks/buoy.txt: the deck of
two lines and a free buoy of tests/test_cable3d_points.py, copied verbatim).
Columns: check, static, simulate, periodic, modes, linearize, end_stiffness, offsets, export
(API ``export_scene``, CLI ``codegen``). The CLI runs in this process (``main([...])``).

    python studies/conformance/matrix.py --quick   # short runs, the CI version (1-3 min)
    python studies/conformance/matrix.py           # every analysis with its default settings

A CLI cell with outputs runs ``--json --plot F.png --save F.json``, and in the full mode again
with ``--save F.npz`` (the quick mode leaves that second run out: it doubles the CLI's time,
and the API cells check both formats' round trip on the same result).

Writes matrix.md and results.json next to this file (``--out`` for the plots, saved results
and generated C, default ./out).
"""
# (no ``from __future__ import annotations``: the tests import this script by its path, without
# a sys.modules entry, and dataclasses would then look its string annotations up there)
import argparse
import contextlib
import dataclasses
import io
import json
import os
import signal
import sys
import threading
import time
import traceback
import warnings
from pathlib import Path
from typing import Callable

os.environ.setdefault("MPLBACKEND", "Agg")

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))  # a study is a script; its helper module sits beside it
from conformance_checks import (Failure, check_plot, check_result, close_figures,  # noqa: E402
                                first_difference, fresh, guarded, in_stats, nan_paths,
                                one_line, stray_notes, trace_ends)

SHARED = HERE.parents[2] / "shared"
CHAIN_DECK = SHARED / "reference" / "moordyn-chains" / "WD0050_Chain.txt"
MULTI_DECK = HERE / "decks" / "buoy.txt"
BUILTINS = ("oc3", "seed001", "seed000_rod", "seed000_hybrid", "sphere", "sphere127",
            "towed_body")
#: columns of the matrix and the surfaces each has (the CLI's verb, or None)
ANALYSES = {"check": (None, "check"), "static": ("API", "static"),
            "simulate": ("API", "simulate"), "periodic": ("API", "periodic"),
            "modes": ("API", "modes"), "linearize": ("API", "linearize"),
            "end_stiffness": ("API", None), "offsets": ("API", "offsets"),
            "export": ("API", "codegen")}
#: CLI exit statuses that are an answer (0) or a one-line refusal (2); anything else FAILs.
#: (``check`` documents 1 for a scene whose motion would be refused, the analyses 3 for an
#: "invalid" result: both are FAIL here, as the matrix's contract asks.)
EXIT_OK, EXIT_REFUSED = 0, 2
#: results of the CLI verbs that take --json, --plot and --save
OUTPUT_VERBS = ("static", "simulate", "periodic", "modes", "offsets")


@dataclasses.dataclass
class Cell:
    """One (scene, analysis, surface) cell: ``status`` "ok", "refused" or "FAIL"."""
    scene: str
    analysis: str
    surface: str
    status: str = "ok"
    message: str = ""
    time: float = 0.0
    call: str = ""
    notes: list = dataclasses.field(default_factory=list)
    traceback: str = ""


@dataclasses.dataclass(frozen=True)
class Row:
    """A scene: its row label, the CLI's scene argument, the API's ``load_scene`` path and
    that path as a reproducing call writes it."""
    name: str
    cli: str
    path: str
    path_text: str


class CellTimeout(BaseException):
    """A cell over its time limit (not an Exception: the CLI's main() must not catch it)."""


# ----------------------------------------------------------------------------- scenes

def scene_rows(names=None) -> tuple[list[Row], list[str]]:
    """The matrix's rows and notes on rows left out (a missing deck)."""
    import symcable as sc
    rows = [Row(n, n, str(sc.demo_scene_path(n)), f"sc.demo_scene_path({n!r})")
            for n in BUILTINS]
    skipped = []
    for label, path in (("moordyn_chain", CHAIN_DECK), ("moordyn_buoy", MULTI_DECK)):
        if path.is_file():
            rows.append(Row(label, str(path), str(path), repr(str(path))))
        else:
            skipped.append(f"{label}: {path} not found, row skipped")
    if names:
        rows = [r for r in rows if r.name in names]
    return rows, skipped


def motions(scene) -> list:
    """Every prescribed motion of a scene (its ends' and its points')."""
    ends = [getattr(scene, f"end_{e}", None) for e in "ab"]
    out = [e.motion for e in ends if e is not None and e.motion is not None]
    return out + [p.motion for p in (scene.points or {}).values()
                  if getattr(p, "motion", None) is not None]


def pinned_ends(scene) -> list[str]:
    ends = {e: getattr(scene, f"end_{e}", None) for e in "ab"}
    return [e for e, end in ends.items() if end is not None
            and str(getattr(end.condition, "value", end.condition)) == "pinned"]


# ----------------------------------------------------------------------------- settings

@dataclasses.dataclass(frozen=True)
class Settings:
    """Run lengths: ``quick`` short runs (the CI version), else each analysis's defaults."""
    quick: bool

    def simulate(self, scene) -> tuple[float, float | None]:
        """(duration, dt) s: quick two periods at T/40 (a tow 2 s at 0.05 s, no motion 1 s at
        0.1 s);
        else the CLI's default duration (10 periods, a table's span, a tow's turns + 60 s)."""
        kinds = {m.kind: m for m in motions(scene)}
        if self.quick:
            if "harmonic" in kinds:
                period = kinds["harmonic"].period
                return 2.0 * period, period / 40.0
            return (2.0, 0.05) if kinds else (1.0, 0.1)
        if "table" in kinds:
            return kinds["table"].period, None
        if "tow" in kinds:
            return kinds["tow"].period + 60.0, None
        return (10.0 * kinds["harmonic"].period if "harmonic" in kinds else 60.0), None

    @property
    def n_modes(self) -> int:
        return 3 if self.quick else 6

    @property
    def offsets(self) -> tuple[float, float, int]:
        return (-5.0, 5.0, 5) if self.quick else (-10.0, 10.0, 41)


def body_of(scene) -> str:
    """The scene's first body, or a name no scene has (the sweep must then refuse)."""
    return next(iter(scene.bodies or {}), "no_body")


# ----------------------------------------------------------------------------- API cells

def api_calls(scene, row: Row, settings: Settings, out: Path) -> dict:
    """analysis -> (call text, thunk) of the Python API on a loaded scene."""
    import symcable as sc
    from symcable.api.export import export_scene

    c3 = scene.model.value != "planar"
    duration, dt = settings.simulate(scene)
    per = {"stability": not settings.quick} if c3 else {}
    ends = pinned_ends(scene) or ["b"]
    body, (lo, hi, n) = body_of(scene), settings.offsets
    folder = out / f"{row.name}_export_api"
    s = "scene"
    return {
        "static": (f"sc.solve_static({s})", lambda: sc.solve_static(scene)),
        "simulate": (f"sc.simulate({s}, {duration!r}, dt={dt!r})",
                     lambda: sc.simulate(scene, duration, dt=dt)),
        "periodic": (f"sc.solve_periodic({s}{''.join(f', {k}={v}' for k, v in per.items())})",
                     lambda: sc.solve_periodic(scene, **per)),
        "modes": (f"sc.modal_analysis({s}, {settings.n_modes})",
                  lambda: sc.modal_analysis(scene, settings.n_modes)),
        "linearize": (f"sc.linearize({s})", lambda: sc.linearize(scene)),
        "end_stiffness": (" ; ".join(f"sc.end_stiffness({s}, {e!r})" for e in ends),
                          lambda: [sc.end_stiffness(scene, e) for e in ends][-1]),
        "offsets": (f"sc.offset_sweep({s}, {body!r}, sc.offsets_along('surge', {lo}, {hi}, "
                    f"{n}))", lambda: sc.offset_sweep(scene, body,
                                                      sc.offsets_along("surge", lo, hi, n))),
        "export": (f"export_scene({s}, {str(folder)!r})",
                   lambda: export_scene(scene, fresh(folder))),
    }


def classify_error(cell: Cell, exc: BaseException) -> None:
    """A SymcableError of one line is a refusal; anything else FAILs, with its traceback."""
    from symcable.errors import SymcableError
    text = str(exc).strip()
    if isinstance(exc, SymcableError) and text and "\n" not in text:
        cell.status, cell.message = "refused", f"{type(exc).__name__}: {text}"
        return
    why = "refusal of several lines: " if isinstance(exc, SymcableError) and text else ""
    cell.status, cell.message = "FAIL", f"{why}{type(exc).__name__}: {one_line(exc)}"
    cell.traceback = "".join(traceback.format_exception(type(exc), exc, exc.__traceback__))


def run_api_cell(cell: Cell, thunk: Callable, stem: Path, timeout: float | None):
    """Run one API cell; returns its result (None when refused or when it raised)."""
    started = time.perf_counter()
    result, err = None, io.StringIO()
    with warnings.catch_warnings(record=True) as caught, contextlib.redirect_stderr(err):
        warnings.simplefilter("always")
        try:
            with _time_limit(timeout):
                result = thunk()
                cell.time = time.perf_counter() - started
                cell.notes += check_result(result, stem)
        except Failure as exc:
            cell.status, cell.message, cause = "FAIL", str(exc), exc.__cause__
            if cause is not None:  # the exception a check caught (plot, save, load)
                cell.traceback = "".join(traceback.format_exception(type(cause), cause,
                                                                    cause.__traceback__))
        except Exception as exc:  # noqa: BLE001 - classified, never raised
            classify_error(cell, exc)
        except CellTimeout as exc:
            cell.status, cell.message = "FAIL", f"CellTimeout: {exc}"
        finally:
            close_figures(None)
    cell.time = cell.time or time.perf_counter() - started
    cell.notes += sorted({f"warning: {one_line(w.message)[:200]}" for w in caught})
    cell.notes += stray_notes(err.getvalue().splitlines())
    return result if cell.status != "refused" else None  # a check's FAIL still ran it


@contextlib.contextmanager
def _time_limit(seconds: float | None):
    """CellTimeout after ``seconds`` (main thread with SIGALRM only; else no limit)."""
    if not seconds or threading.current_thread() is not threading.main_thread() \
            or not hasattr(signal, "SIGALRM"):
        yield
        return

    def fire(signum, frame):
        raise CellTimeout(f"no answer after {seconds:g} s")
    old = signal.signal(signal.SIGALRM, fire)
    signal.setitimer(signal.ITIMER_REAL, seconds)
    try:
        yield
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, old)


# ----------------------------------------------------------------------------- CLI cells

def run_cli(argv: list[str]) -> tuple[int, str, str]:
    """``symcable ARGV`` in this process: (exit status, stdout, stderr)."""
    from symcable.cli.main import main
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        try:
            code = main(argv)
        except SystemExit as exc:  # argparse
            code = exc.code if isinstance(exc.code, int) else 2
        except BaseException as exc:  # noqa: BLE001 - main() must not raise
            if isinstance(exc, (KeyboardInterrupt, CellTimeout)):
                raise
            traceback.print_exc(file=err)
            code = -1
    close_figures(None)
    return code, out.getvalue(), err.getvalue()


def cli_argv(verb: str, row: Row, scene, settings: Settings, out: Path) -> list[str]:
    """The command line of one CLI cell (its outputs added by :func:`run_cli_cell`)."""
    argv = [verb, row.cli]
    if verb == "simulate" and scene is not None:
        duration, dt = settings.simulate(scene)
        argv += ["--duration", repr(duration)] + (["--dt", repr(dt)] if dt else [])
    elif verb == "periodic" and settings.quick:
        argv += ["--no-stability"]
    elif verb == "modes":
        argv += ["--n", str(settings.n_modes)]
    elif verb == "offsets":
        lo, hi, n = settings.offsets
        body = body_of(scene) if scene is not None else "no_body"
        argv += ["--body", body, "--range", repr(lo), repr(hi), "--n", str(n)]
    elif verb == "codegen":
        argv += ["--out", str(fresh(out / f"{row.name}_codegen_cli"))]
    return argv


def classify_cli(code: int, out: str, err: str, cell: Cell) -> None:
    """Classify a CLI run's exit status and stderr onto ``cell`` (FAIL or refused)."""
    lines = [ln for ln in err.splitlines() if ln.strip()]
    said = [ln for ln in lines if ln.startswith("symcable: ")
            and not ln.startswith("symcable: warning:")]
    cell.notes += stray_notes([ln for ln in lines if not ln.startswith("symcable: ")])
    cell.notes += [ln[len("symcable: "):][:200] for ln in lines
                   if ln.startswith("symcable: warning:")]
    if "Traceback (most recent call last)" in err:
        cell.status, cell.message = "FAIL", f"traceback on stderr: {lines[-1][:300]}"
        cell.traceback = err
    elif code not in (EXIT_OK, EXIT_REFUSED):
        last = (said[-1][len("symcable: "):] if said else
                next((ln for ln in reversed(out.splitlines()) if ln.strip()), ""))
        cell.status, cell.message = "FAIL", f"exit status {code}" + (f": {last}" if last else "")
    elif code == EXIT_REFUSED:
        if not said:
            cell.status, cell.message = "FAIL", "exit status 2 without a 'symcable: ' line"
        elif "internal error" in said[-1]:
            cell.status, cell.message = "FAIL", said[-1][len("symcable: "):]
        else:
            cell.status, cell.message = "refused", said[-1][len("symcable: "):]


def _check_cli_outputs(stdout: str, files: dict, result_type) -> list[str]:
    """Run 1's outputs: stdout strict JSON, the plot written, the .json save read back
    equal to what was printed. Raises Failure; returns notes."""
    def no_constant(name):
        raise ValueError(f"{name} in the JSON output")
    try:
        printed = json.loads(stdout, parse_constant=no_constant)
    except ValueError as exc:
        raise Failure(f"--json output is not strict JSON: {one_line(exc)[:200]}") from None
    check_plot(files["png"])
    if result_type is None:
        return ["the API gave no result: --save not read back"]
    back = guarded(f"{result_type.__name__}.load(--save .json)",
                 lambda: result_type.load(files["json"]))
    nans = [p for p in nan_paths(back) if not in_stats(p)]
    if nans:
        raise Failure(f"NaN in the saved result: {', '.join(nans[:4])}")
    d = json.loads(json.dumps(back.to_dict()))
    for key in ("states", "unknowns"):  # the CLI leaves these out of --json
        d.pop(key, None)
        printed.pop(key, None)
    diff = first_difference(printed, d, "json")
    if diff:
        raise Failure(f"--save .json read back differs from --json output: {diff}")
    return []


def run_cli_cell(cell: Cell, argv: list[str], stem: Path, result_type,
                 timeout: float | None, npz: bool = True) -> None:
    """One CLI cell. A verb with outputs runs ``--json --plot .png --save .json`` (checked
    and read back), then, when ``npz``, again with ``--save .npz`` (the summary; read back)."""
    outputs = argv[0] in OUTPUT_VERBS
    files = {k: fresh(stem.with_suffix(f".{k}")) for k in ("png", "json", "npz")}
    runs = [argv + ["--json", "--plot", str(files["png"]), "--save", str(files["json"])],
            argv + ["--save", str(files["npz"])]][:2 if npz else 1] if outputs else [argv]
    cell.call = "symcable " + " ".join(runs[0])
    started = time.perf_counter()
    try:
        with _time_limit(timeout):
            for k, run in enumerate(runs):
                code, stdout, stderr = run_cli(run)
                classify_cli(code, stdout, stderr, cell)
                if cell.status != "ok":
                    cell.call = "symcable " + " ".join(run)
                    if k > 0 and cell.status == "refused":  # the analysis ran in run 1
                        cell.status = "FAIL"
                        cell.message = f"--save .npz refused after the run: {cell.message}"
                    break
                if outputs and k == 0:
                    cell.notes += _check_cli_outputs(stdout, files, result_type)
                elif outputs and result_type is not None:
                    cell.notes += _compare_runs(files, result_type)
                elif argv[0] == "codegen":
                    _check_codegen(stdout)
    except Failure as exc:
        cell.status, cell.message = "FAIL", str(exc)
    except CellTimeout as exc:
        cell.status, cell.message = "FAIL", f"CellTimeout: {exc}"
    cell.time = time.perf_counter() - started
    if cell.status == "FAIL" and not cell.traceback and "internal error" in cell.message:
        cell.traceback = run_cli(run + ["--debug"])[2]  # the traceback, for the report


def _compare_runs(files: dict, result_type) -> list[str]:
    """Run 2's ``--save .npz`` read back (a Failure if it cannot be), against run 1's
    ``--save .json``: a difference is a note (two runs of the analysis, not one result)."""
    back = guarded(f"{result_type.__name__}.load(--save .npz)",
                 lambda: result_type.load(files["npz"]))
    nans = [p for p in nan_paths(back) if not in_stats(p)]
    if nans:
        raise Failure(f"NaN in the saved result: {', '.join(nans[:4])}")
    first = result_type.load(files["json"])
    diff = first_difference(_plain(first), _plain(back), "npz")
    return [f"--save .npz of run 2 differs from --save .json of run 1: {diff}"] if diff else []


def _plain(result) -> dict:
    """A result as plain JSON values (the form both save formats agree on), without its
    ``stats`` at any level (wall times differ between runs)."""
    def drop(v):
        if isinstance(v, dict):
            return {k: drop(x) for k, x in v.items() if k != "stats"}
        return [drop(x) for x in v] if isinstance(v, list) else v
    return drop(json.loads(json.dumps(result.to_dict())))


def _check_codegen(stdout: str) -> None:
    paths = [Path(p) for p in stdout.splitlines() if p.strip()]
    if not paths or any(not p.is_file() or p.stat().st_size == 0 for p in paths):
        raise Failure(f"codegen listed missing or empty files: {stdout[:200]!r}")


# ----------------------------------------------------------------------------- the matrix

def run_row(row: Row, settings: Settings, out: Path, timeout: float | None,
            log: Callable[[str], None]) -> list[Cell]:
    """Every cell of one scene: the API cells first (their result types read the CLI's saved
    files back), then the CLI's."""
    import symcable as sc
    cells, types = [], {}
    scene, load_error, calls = None, None, {}
    try:
        scene = sc.load_scene(row.path)
        calls = api_calls(scene, row, settings, out)
    except Exception as exc:  # noqa: BLE001 - every API cell reports it
        load_error = exc
    for analysis, (api, _) in ANALYSES.items():
        if api is None:
            continue
        cell = Cell(row.name, analysis, "API")
        if not calls:  # the scene did not load
            cell.call = f"sc.load_scene({row.path_text})"
            classify_error(cell, load_error)
        else:
            cell.call, thunk = calls[analysis]
            cell.call = f"scene = sc.load_scene({row.path_text}); {cell.call}"
            result = run_api_cell(cell, thunk, out / f"{row.name}_{analysis}", timeout)
            types[analysis] = type(result) if result is not None and \
                hasattr(result, "load") else None
        cells.append(_logged(cell, log))
    for analysis, (_, verb) in ANALYSES.items():
        if verb is None:
            continue
        cell = Cell(row.name, analysis, "CLI")
        argv = cli_argv(verb, row, scene, settings, out)
        run_cli_cell(cell, argv, out / f"{row.name}_{analysis}_cli", types.get(analysis),
                     timeout, npz=not settings.quick)
        cells.append(_logged(cell, log))
    return cells


def _logged(cell: Cell, log: Callable[[str], None]) -> Cell:
    log(f"{cell.scene:15s} {cell.analysis:14s} {cell.surface}  {cell.status:8s} "
        f"{cell.time:7.2f} s  {cell.message[:90]}")
    return cell


def run_matrix(quick: bool = True, out: Path | None = None, scenes=None,
               timeout: float | None = 600.0, log: Callable[[str], None] = print) -> dict:
    """Run the matrix: {"cells": [Cell], "rows", "skipped": [str], "quick", "out", "time"
    (s, wall), "cpu" (s)}. ``quick`` sets SYMCABLE_CODEGEN=0 while it runs."""
    out = Path(out) if out is not None else HERE / "out"
    out.mkdir(parents=True, exist_ok=True)
    settings = Settings(quick)
    saved = os.environ.get("SYMCABLE_CODEGEN")
    if quick:  # compiling generated C (2-10 s a structure) would dominate the short runs
        os.environ["SYMCABLE_CODEGEN"] = "0"
    started, cpu = time.perf_counter(), time.process_time()
    try:
        rows, skipped = scene_rows(scenes)
        cells = [c for row in rows for c in run_row(row, settings, out, timeout, log)]
    finally:
        if saved is None:
            os.environ.pop("SYMCABLE_CODEGEN", None)
        else:
            os.environ["SYMCABLE_CODEGEN"] = saved
    return {"cells": cells, "skipped": skipped, "quick": quick, "out": str(out),
            "time": time.perf_counter() - started, "cpu": time.process_time() - cpu,
            "rows": [r.name for r in rows]}


def failures(res: dict) -> list[Cell]:
    return [c for c in res["cells"] if c.status == "FAIL"]


# ----------------------------------------------------------------------------- reports

def markdown(res: dict) -> str:
    """The matrix (rows scenes, columns analyses, each cell "API / CLI"), its footnotes and
    the time of every cell."""
    cells = {(c.scene, c.analysis, c.surface): c for c in res["cells"]}
    notes: dict[str, int] = {}

    def mark(c: Cell | None) -> str:
        if c is None:
            return "–"
        if c.status == "ok":
            return "ok"
        text = c.message.replace(res.get("out", "\0"), "out")  # no machine's own paths
        n = notes.setdefault(f"**{c.status}** {text}", len(notes) + 1)
        return f"{'FAIL' if c.status == 'FAIL' else 'refused'} [{n}]"

    def row_of(scene, fmt) -> str:
        return f"| {scene} | " + " | ".join(
            " / ".join(fmt(cells.get((scene, a, s))) for s in ("API", "CLI")
                       if (s == "API" and api) or (s == "CLI" and cli))
            for a, (api, cli) in ANALYSES.items()) + " |"
    head = ("| scene | " + " | ".join(
        f"{a} ({' / '.join(s for s in (api, cli and 'CLI') if s)})"
        for a, (api, cli) in ANALYSES.items()) + " |\n|" + "---|" * (len(ANALYSES) + 1))
    table = "\n".join([head] + [row_of(s, mark) for s in res["rows"]])
    counts = {s: sum(c.status == s for c in res["cells"]) for s in ("ok", "refused", "FAIL")}
    times = "\n".join([head] + [row_of(s, lambda c: "–" if c is None else f"{c.time:.2f}")
                                for s in res["rows"]])
    foot = "\n".join(f"{n}. {text}" for text, n in notes.items())
    skipped = "".join(f"\nSkipped: {s}" for s in res["skipped"])
    return (f"Mode: {'--quick' if res['quick'] else 'full'}; {len(res['cells'])} cells: "
            f"{counts['ok']} ok, {counts['refused']} refused, {counts['FAIL']} FAIL; "
            f"{res['time']:.0f} s in all ({res['cpu']:.0f} s of CPU).{skipped}\n\n{table}\n\n"
            f"{foot}\n\nWall time per cell, s (API: the analysis; CLI: its run"
            f"{'' if res['quick'] else 's'} with outputs):\n\n{times}\n")


def write_reports(res: dict, folder: Path = HERE) -> None:
    """matrix.md, results.json, and the table in README.md (between its two markers)."""
    text = markdown(res)
    (folder / "matrix.md").write_text("# Conformance matrix\n\n" + text)
    data = {"quick": res["quick"], "time": res["time"], "cpu": res["cpu"],
            "skipped": res["skipped"], "cells": [dataclasses.asdict(c) for c in res["cells"]]}
    (folder / "results.json").write_text(json.dumps(data, indent=1) + "\n")
    readme, start, end = folder / "README.md", "<!-- matrix -->", "<!-- /matrix -->"
    if readme.is_file() and start in (old := readme.read_text()) and end in old:
        head, rest = old.split(start, 1)
        readme.write_text(f"{head}{start}\n{text}\n{end}{rest.split(end, 1)[1]}")


def fail_report(res: dict) -> str:
    """The FAIL cells, their messages, calls and traceback ends (the test's message)."""
    return "\n\n".join(f"{c.scene} / {c.analysis} / {c.surface}: {c.message}\n  call: {c.call}"
                       + (f"\n  {trace_ends(c.traceback)}" if c.traceback else "")
                       for c in failures(res))


def main(argv: list[str] | None = None) -> dict:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="short runs (the CI version)")
    ap.add_argument("--out", type=Path, default=HERE / "out",
                    help="folder for plots, saved results and generated C")
    ap.add_argument("--scenes", nargs="*", help="only these rows")
    ap.add_argument("--timeout", type=float, default=600.0, help="s per cell")
    args = ap.parse_args(argv)
    res = run_matrix(args.quick, args.out, args.scenes, args.timeout)
    write_reports(res)
    print(markdown(res))
    return res


if __name__ == "__main__":
    main()
