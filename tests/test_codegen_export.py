"""``symcable codegen`` for every formulation: each built-in scene (planar, cable3d with
points and bodies, rod, hybrid; the rod and hybrid coarser), a MoorDyn chain deck with its
heave table, and seed 000's rod heaved, is exported, its example compiled with the system
compiler and run, and what it prints is checked against the library's own results: the
static outputs against the equilibrium the library solves (and the fairlead tension against
``solve_static``), the exported residual and Jacobian at the solution, and for a moving scene
the outputs after a number of time steps against ``simulate`` run with the same step from the
same start. The example's fallback (a start plain Newton does not converge from) is checked
on one scene.

Compiling is what costs (gcc's time grows faster than the C's length: 1-5 MB of
straight-line C per scene here): the scenes are exported one after the other while up to
two compilers run beside (the CI machine has 2 cores), at -O0 (half of -O1's time on these
files, a quarter of -O2's; see OPT)."""
from __future__ import annotations

import re
import shutil
import subprocess
import time
import warnings
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import numpy as np
import pytest

import symcable as sc
from symcable.api.export import export_scene
from symcable.api.scene3d import scene_equilibrium
from symcable.mechanism.functions import functions
from symcable.scene import load_scene

#: MoorDyn's chain decks and heave tables, in the shared folder beside the repository
REF = Path(__file__).resolve().parents[2] / "shared" / "reference" / "moordyn-chains"
#: time steps the example takes (its first argument), and simulate with it
STEPS = 20
#: the compiler's flags: -O0 because the compiler's time, not the run's, is what this test
#: spends (gcc's CPU time on these 8 exports, 1-5 MB of C each, the heaved rod at 8
#: segments: 43 s at -O0, 89 s at -O1, 184 s at -O2, 59 s of it the towed body's). The
#: numbers do not depend on the level: without -ffast-math and without FMA contraction
#: (x86-64's default target has no FMA) every level evaluates the same operations in the
#: same order (the sphere's example printed the same digits at -O0 and -O2). -Wall: the
#: generated C and the example compile without a warning.
OPT = ["-O0", "-Wall"]
#: static outputs, relative to each output's largest entry. Both sides run the same fused
#: plain Newton from the same start to the same tolerance (1e-9 of the force scale), so on
#: the same arithmetic they agree to the last digit (measured: 0 on every scene, x86-64
#: gcc). On a target that contracts FMAs the round-off differs, and a residual that lands
#: near the tolerance (WD0050: 0.026 N against 0.030 N after 4 steps) can take one Newton
#: step more on one side: the states then differ by about what the tolerance allows, a force
#: of 1e-9 of the force scale, i.e. a tension within 1e-8 of itself; 1e-7 leaves room.
STATIC_RTOL = 1e-7
#: dynamic outputs after STEPS steps, relative to each output's largest entry: the same step
#: function on both sides (measured: 0 on every scene, x86-64 gcc); with other round-off a
#: step's Newton loop may stop one iteration apart, which moves y1 by at most the Newton
#: tolerance (1e-8 of the state's scales on the Mechanism path, 1e-10 on the linearised one)
#: per step, 2e-7 of the scales over 20 steps: 1e-6.
DYNAMIC_RTOL = 1e-6


def _resized(name: str, segments: list) -> sc.Scene:
    """A built-in scene with its sections' segments set: seed 000's 5 mm segments (400) give
    50 MB of C for the rod, which gcc -O0 could not compile in 9 GB of memory (the hybrid's,
    18 MB: 23 s and 3.4 GB); the same lines coarser exercise the same export."""
    d = load_scene(name).to_dict()
    for section, n in zip(d["sections"], segments):
        section["segments"] = n
    return load_scene(d)


def _heaved_rod() -> sc.Scene:
    """seed 000's rod (4 segments) with its pinned end heaving: the rod's own time step (the
    frames' reference spin in its kinetic energy); its static state is turned far from the
    anchors (below the margin 0.5), so the march re-anchors at the start."""
    d = _resized("seed000_rod", [4]).to_dict()
    d["name"] = "seed 000 rod, heaved"
    d["end_a"]["motion"] = {"kind": "harmonic", "period": 2.0, "amplitude": [0.0, 0.0, 0.01]}
    return load_scene(d)


def _chain() -> sc.Scene:
    """MoorDyn's WD0050 chain deck (41 segments on a seabed with friction) with its A1 heave
    table on the vessel end (from -10 s)."""
    d = load_scene(REF / "WD0050_Chain.txt").to_dict()
    d["end_b"]["motion"] = {"kind": "table", "file": str(REF / "ZZP1_A1.txt")}
    return load_scene(d)


#: name -> (scene builder, whether the scene moves); the largest C first (its compiler starts
#: first)
SCENES = {
    "towed_body": (lambda: load_scene("towed_body"), True),  # a body, a steady tow start
    "WD0050_chain": (_chain, True),
    "seed001": (lambda: load_scene("seed001"), True),  # planar, linearised dynamics
    "sphere": (lambda: load_scene("sphere"), True),  # lines and points
    "oc3": (lambda: load_scene("oc3"), True),  # planar; its dynamics run as the 3D cable
    "rod_heaved": (_heaved_rod, True),  # the rod's dynamics, re-anchored at the start
    "seed000_rod": (lambda: _resized("seed000_rod", [8]), False),
    "seed000_hybrid": (lambda: _resized("seed000_hybrid", [12, 4]), False),
}


def _compile(cc: str, folder: Path) -> tuple:
    """``scene.c`` to ``scene.o``, then the example: (return code, stderr, seconds)."""
    t0 = time.perf_counter()
    err = ""
    for cmd in (["-c", "scene.c", "-o", "scene.o"], ["main.c", "scene.o", "-lm", "-o", "example"]):
        proc = subprocess.run([cc, *OPT, *cmd], cwd=folder, capture_output=True, text=True,
                              timeout=600, check=False)
        err += proc.stderr
        if proc.returncode:
            break
    return proc.returncode, err, time.perf_counter() - t0


@pytest.fixture(scope="module")
def builds(tmp_path_factory):
    """name -> (scene, folder, (compiler's return code, its stderr, seconds)): every scene
    exported (stem ``scene``), the compilers running two at a time beside the exports."""
    cc = shutil.which("cc")
    if cc is None:
        pytest.fail("no C compiler: test_codegen_export compiles the exported C with `cc` "
                    "(install gcc or clang, or put a cc on the PATH)")
    if not REF.is_dir():
        pytest.fail(f"{REF}: MoorDyn's chain decks are not there (the shared reference "
                    "folder beside the repository)")
    root = tmp_path_factory.mktemp("codegen_export")
    jobs = {}
    with ThreadPoolExecutor(max_workers=2) as pool:
        for name, (make, _) in SCENES.items():
            scene = make()
            export_scene(scene, root / name, stem="scene")
            jobs[name] = (scene, root / name, pool.submit(_compile, cc, root / name))
        return {name: (scene, folder, job.result()) for name, (scene, folder, job) in jobs.items()}


def _printed(text: str) -> dict:
    """{(what, output): values (column-major)} of the lines ``what.output[i] = value``."""
    found: dict = {}
    for m in re.finditer(r"^(static|dyn)\.(\S+)\[(\d+)\] = (\S+)$", text, re.MULTILINE):
        found.setdefault((m[1], m[2]), {})[int(m[3])] = float(m[4])
    return {k: np.array([v[i] for i in range(len(v))]) for k, v in found.items()}


def _close(got, want, rtol: float, what: str) -> None:
    """``got`` equals ``want`` within ``rtol`` of want's largest entry."""
    got, want = np.ravel(got), np.ravel(want)
    assert got.shape == want.shape, what
    atol = rtol * float(np.max(np.abs(want), initial=0.0)) + 1e-300
    np.testing.assert_allclose(got, want, rtol=0, atol=atol, err_msg=what)


def _value(stdout: str, name: str) -> float:
    return float(re.search(rf"^{name} = (\S+)$", stdout, re.MULTILINE)[1])


def _define(header: str, name: str) -> float:
    return float(re.search(rf"^#define {name} (\S+)$", header, re.MULTILINE)[1])


def _check_static(scene, stdout: str, got: dict, start: str = "W_START") -> None:
    """The static outputs against the library's equilibrium, every one by name; the end
    tensions against solve_static's; the solve from ``start`` (where the library's plain
    Newton converged from W_START, the C's does too)."""
    mech, eq = scene_equilibrium(scene, codegen=False)
    if eq.stats["path"] == "newton" or start != "W_START":
        assert re.search(rf"^static: \S+ Newton iterations from {start}", stdout,
                         re.MULTILINE), stdout[:300]
    assert "static_converged = 1" in stdout
    assert {n for w, n in got if w == "static"} == set(eq.outputs)
    for name, value in eq.outputs.items():
        _close(got[("static", name)], np.ravel(np.asarray(value, float), order="F"),
               STATIC_RTOL, f"static output {name}")
    # the exported residual and Jacobian at the C's solution: the residual within the
    # tolerance, the Jacobian's entries those of the library's Jacobian at its solution
    assert _value(stdout, "static_residual_max") <= eq.stats["tolerance"]
    _, J = functions(mech).static_jacobian(np.concatenate([eq.q, eq.z]), eq.p)
    _close(_value(stdout, "static_jacobian_abs_sum"), np.sum(np.abs(J.nonzeros())),
           STATIC_RTOL, "sum of |J|")
    st = sc.solve_static(scene, codegen=False)
    for line, sol in st.lines.items():  # a one-line scene's outputs carry no line prefix
        key = ("static", f"{line}.end_force_b")
        key = key if key in got else ("static", "end_force_b")
        _close(np.linalg.norm(got[key]), sol.fairlead_tension, STATIC_RTOL,
               f"fairlead tension of line {line!r}")


def _check_dynamics(scene, header: str, stdout: str, got: dict) -> None:
    """The outputs after STEPS steps against simulate's with the same step from the same
    start: every output of a scene of lines and points, else the positions and the fairlead
    tension of the line."""
    dt, t0 = _define(header, "DT"), _define(header, "T0")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the stand-in's note, the error estimate's
        tr = sc.simulate(scene, STEPS * dt, dt=dt, codegen=False)
    assert not tr.stats.get("substepped_steps"), "the Python run substepped: not comparable"
    assert tr.time[0] == pytest.approx(t0, abs=1e-12)
    m = re.search(r"^dynamics: (\d+) steps done, t = (\S+) s$", stdout, re.MULTILINE)
    assert m and int(m[1]) == STEPS, stdout[-500:]
    assert float(m[2]) == pytest.approx(tr.time[-1], rel=1e-5, abs=1e-9)
    outputs = getattr(tr, "outputs", None)
    if isinstance(outputs, dict) and outputs:  # a scene of lines, points and bodies
        for name, series in outputs.items():
            _close(got[("dyn", name)], np.ravel(np.asarray(series)[-1], order="F"),
                   DYNAMIC_RTOL, f"output {name} at t = {tr.time[-1]:g} s")
        return
    _close(got[("dyn", "positions")], np.ravel(np.asarray(tr.positions)[-1], order="F"),
           DYNAMIC_RTOL, "positions")
    tension = got.get(("dyn", "fairlead_tension"))
    if tension is None:
        tension = np.linalg.norm(got[("dyn", "end_force_b")])
    _close(tension, tr.fairlead_tension[-1], DYNAMIC_RTOL, "fairlead tension")


@pytest.mark.parametrize("name", list(SCENES))
def test_exported_c_agrees_with_python(builds, name):
    scene, folder, (rc, err, _) = builds[name]
    assert rc == 0, err[-2000:]
    assert "warning" not in err, err[-2000:]
    run = subprocess.run([str(folder / "example"), str(STEPS)], cwd=folder, capture_output=True,
                         text=True, timeout=300, check=False)
    assert run.returncode == 0, run.stderr[-2000:]
    assert run.stdout.startswith(f"scene: {scene.name}\nstatic: ")
    got = _printed(run.stdout)
    _check_static(scene, run.stdout, got)
    header = (folder / "scene_data.h").read_text()
    readme = (folder / "README.md").read_text()
    moves = SCENES[name][1]
    assert ("#define N_X " in header) is moves
    if not moves:
        assert "No time-step function: the scene prescribes no motion" in readme
        assert "dynamics:" not in run.stdout
        return
    _check_dynamics(scene, header, run.stdout, got)


def test_static_solve_falls_back_to_the_library_solution(builds, tmp_path):
    """Where plain Newton from ``W_START`` does not converge (here a start of zeros: every
    segment of zero length), ``main.c`` refines ``W_STATIC``, the library's solution in the
    data header, and says so: converged in at most one step, the library's outputs."""
    scene, folder, (rc, err, _) = builds["seed000_hybrid"]
    assert rc == 0, err[-2000:]
    for name in ("main.c", "scene.h"):
        shutil.copy(folder / name, tmp_path / name)
    header = (folder / "scene_data.h").read_text()
    n_w = int(_define(header, "N_W"))
    zeros = "static const casadi_real W_START[] = {" + ", ".join(["0.0"] * n_w) + "};"
    header, n = re.subn(r"^static const casadi_real W_START\[\] = \{[^}]*\};$", zeros, header,
                        flags=re.MULTILINE)
    assert n == 1
    (tmp_path / "scene_data.h").write_text(header)
    build = subprocess.run([shutil.which("cc"), *OPT, "main.c", str(folder / "scene.o"), "-lm",
                            "-o", "example"], cwd=tmp_path, capture_output=True, text=True,
                           timeout=120, check=False)
    assert build.returncode == 0, build.stderr[-2000:]
    run = subprocess.run([str(tmp_path / "example")], cwd=tmp_path, capture_output=True,
                         text=True, timeout=60, check=False)
    assert run.returncode == 0, run.stderr[-2000:]
    m = re.search(r"^static: (\S+) Newton iterations from W_STATIC", run.stdout, re.MULTILINE)
    assert m and float(m[1]) <= 1, run.stdout[:300]  # Newton from a converged state
    _check_static(scene, run.stdout, _printed(run.stdout), start="W_STATIC")
