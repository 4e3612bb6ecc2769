"""Generated C: same answers as the virtual machine, a build cache that survives damage and
concurrent builders, a warning and a fallback without a compiler, and exported sources that
compile with -Wall. Compiling takes 1-20 s per model structure, so the scenes here are
small (10-20 segments) except where a demo scene is the point."""
from __future__ import annotations

import copy
import subprocess
import sys
import warnings

import casadi as ca
import numpy as np
import pytest

import symcable as sc
from symcable.mechanism import codegen
from symcable.cli.main import main

from conftest import OC3, seed001


def small_seed(segments=10):
    d = seed001()
    d["sections"][0]["segments"] = segments
    return d


def _fake_exe(folder, name):
    path = folder / name
    path.write_text("#!/bin/sh\nexit 0\n")
    path.chmod(0o755)
    return str(path)


def test_compiler_lookup_follows_cc_then_path(monkeypatch, tmp_path):
    """symcable's choice of compiler, not the machine's: ``$CC`` (its first word, looked up on
    the PATH) wins; without it the first of cc, gcc, clang on the PATH; None when there is
    none, and then ``codegen=None`` quietly means the virtual machine. Fake executables on
    a PATH of our own, so the answer does not depend on what this machine has installed."""
    bin_dir = tmp_path / "bin"
    bin_dir.mkdir()
    monkeypatch.setenv("PATH", str(bin_dir))
    monkeypatch.delenv("CC", raising=False)
    monkeypatch.delenv("SYMCABLE_CODEGEN", raising=False)
    assert codegen.compiler() is None
    assert codegen.use_codegen(None) is False  # no compiler: the VM, no warning
    clang = _fake_exe(bin_dir, "clang")
    monkeypatch.setenv("PATH", str(bin_dir) + ":")  # a new PATH: looked up again
    assert codegen.compiler() == clang
    gcc = _fake_exe(bin_dir, "gcc")
    monkeypatch.setenv("PATH", str(bin_dir) + "::")
    assert codegen.compiler() == gcc  # gcc before clang
    mycc = _fake_exe(bin_dir, "mycc")
    monkeypatch.setenv("CC", "mycc -m64")
    assert codegen.compiler() == mycc  # $CC first, its first word
    monkeypatch.setenv("CC", "nosuchcc")
    assert codegen.compiler() is None  # a $CC that is not there is not replaced by gcc
    assert codegen.use_codegen(None) is False


def test_static_compiled_equals_vm():
    vm = sc.solve_static(copy.deepcopy(OC3), codegen=False)
    cg = sc.solve_static(copy.deepcopy(OC3), codegen=True)
    assert cg.stats["compiled"] and not vm.stats["compiled"]
    assert cg.stats["path"] == vm.stats["path"] == "newton"
    assert cg.stats["iterations"] == vm.stats["iterations"]
    # same operations in the same order up to the compiler's: agreement to round-off
    np.testing.assert_allclose(cg.positions, vm.positions, rtol=0, atol=1e-9)
    assert abs(cg.fairlead_tension - vm.fairlead_tension) <= 1e-9 * vm.fairlead_tension


def test_static_parameters_are_inputs_one_library_for_moved_ends():
    a, b = copy.deepcopy(OC3), copy.deepcopy(OC3)
    b["end_b"]["position"] = [-10.0, -60.0]
    b["name"] = "moved fairlead"
    sa = sc.solve_static(a, codegen=True)
    key_a = codegen.last_build["key"]
    sb = sc.solve_static(b, codegen=True)
    assert codegen.last_build["key"] == key_a and codegen.last_build["action"] == "memory"
    assert sb.fairlead_tension != pytest.approx(sa.fairlead_tension, rel=1e-3)
    vm = sc.solve_static(b, codegen=False)
    assert abs(sb.fairlead_tension - vm.fairlead_tension) <= 1e-9 * vm.fairlead_tension


@pytest.mark.parametrize("method", ["generalized-alpha", "rk4"])
def test_simulate_compiled_equals_vm(method):
    scene = small_seed(10)
    model = sc.build_dynamic_model(sc.load_scene(scene))
    vm = sc.simulate(None, 20.0, dt=0.05, method=method, model=model, codegen=False)
    cg = sc.simulate(None, 20.0, dt=0.05, method=method, model=model, codegen=True)
    assert cg.stats["compiled"] and not vm.stats["compiled"]
    rng = np.ptp(vm.fairlead_tension)
    assert np.max(np.abs(cg.fairlead_tension - vm.fairlead_tension)) <= 1e-9 * rng
    assert cg.stats["newton_iterations"] == vm.stats["newton_iterations"]


def test_periodic_and_modes_compiled_equal_vm():
    scene = sc.load_scene(small_seed(10))
    model = sc.build_dynamic_model(scene)
    vm = sc.solve_periodic(scene, "collocation", model=model, intervals=8, codegen=False)
    cg = sc.solve_periodic(scene, "collocation", model=model, intervals=8, codegen=True)
    assert cg.stats["compiled"] and not vm.stats["compiled"]
    rng = np.ptp(vm.fairlead_tension)
    # both converge to 1e-10 scaled states per second; tension agrees far below 1e-6 of range
    assert np.max(np.abs(cg.fairlead_tension - vm.fairlead_tension)) <= 1e-6 * rng
    hb_vm = sc.solve_periodic(scene, "harmonic-balance", model=model, harmonics=3, codegen=False)
    hb_cg = sc.solve_periodic(scene, "harmonic-balance", model=model, harmonics=3, codegen=True)
    assert np.max(np.abs(hb_cg.fairlead_tension - hb_vm.fairlead_tension)) <= 1e-6 * rng
    m_vm = sc.modal_analysis(None, 4, model=model, codegen=False)
    m_cg = sc.modal_analysis(None, 4, model=model, codegen=True)
    np.testing.assert_allclose(m_cg.frequencies, m_vm.frequencies, rtol=1e-10)


def _tiny(name="tiny_fn"):
    x = ca.SX.sym("x", 3)
    return ca.Function(name, [x], [ca.sin(x) * x[0]], ["x"], ["y"])


def test_cache_memory_disk_and_damaged_entry(monkeypatch, tmp_path):
    monkeypatch.setenv("SYMCABLE_CACHE_DIR", str(tmp_path))
    f = _tiny()
    x = np.array([0.3, -1.0, 2.0])
    want = np.array(f(x).full()).ravel()
    lib = codegen.compile_functions([f])
    assert codegen.last_build["action"] == "compiled"
    assert codegen.compile_functions([f]) is lib and codegen.last_build["action"] == "memory"
    codegen._loaded.clear()
    lib = codegen.compile_functions([f])
    assert codegen.last_build["action"] == "cache"
    np.testing.assert_allclose(np.array(lib["tiny_fn"](x).full()).ravel(), want, rtol=1e-15)
    # a truncated library (a new file: the loaded one stays mapped in this process, as it
    # would after a crash of another process mid-copy): detected by its digest, rebuilt
    so = next(tmp_path.glob("*.so"))
    head = so.read_bytes()[:100]
    so.unlink()
    so.write_bytes(head)
    codegen._loaded.clear()
    lib = codegen.compile_functions([f])
    assert codegen.last_build["action"] == "compiled"
    np.testing.assert_allclose(np.array(lib["tiny_fn"](x).full()).ravel(), want, rtol=1e-15)
    # an unreadable record: rebuilt as well
    next(tmp_path.glob("*.json")).write_text("{not json")
    codegen._loaded.clear()
    codegen.compile_functions([f])
    assert codegen.last_build["action"] == "compiled"
    assert main(["cache", "clear"]) == 0
    assert not list(tmp_path.glob("*.so")) and not list(tmp_path.glob("*.json"))


def test_cache_concurrent_builders(tmp_path):
    code = ("import casadi as ca, numpy as np; from symcable.mechanism import codegen\n"
            "x = ca.SX.sym('x', 3)\n"
            "f = ca.Function('race_fn', [x], [ca.cos(x) * x[1]], ['x'], ['y'])\n"
            "y = codegen.compile_functions([f])['race_fn']([1.0, 2.0, 3.0])\n"
            "assert np.allclose(np.array(y.full()).ravel(), np.cos([1, 2, 3]) * 2.0)\n"
            "print(codegen.last_build['action'])\n")
    env = {**__import__("os").environ, "SYMCABLE_CACHE_DIR": str(tmp_path)}
    procs = [subprocess.Popen([sys.executable, "-c", code], env=env, stdout=subprocess.PIPE,
                              stderr=subprocess.PIPE, text=True) for _ in range(3)]
    outs = [p.communicate(timeout=120) for p in procs]
    assert all(p.returncode == 0 for p in procs), [o[1][-500:] for o in outs]
    assert len(list(tmp_path.glob("*.json"))) == 1
    assert codegen._valid_entry(tmp_path, next(tmp_path.glob("*.json")).stem) is not None


def test_no_compiler_warns_once_and_falls_back(monkeypatch):
    monkeypatch.setenv("CC", "/nonexistent/cc")
    monkeypatch.setattr(codegen, "_warned", set())
    with pytest.warns(codegen.CodegenWarning, match="no C compiler"):
        sol = sc.solve_static(copy.deepcopy(OC3), codegen=True)
    assert sol.status == "converged" and not sol.stats["compiled"]
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        sc.solve_static(copy.deepcopy(OC3), codegen=True)  # no second warning
        assert not sc.solve_static(copy.deepcopy(OC3)).stats["compiled"]  # default: silent VM
    with pytest.raises(sc.SymcableError, match="codegen = 'yes'"):
        sc.solve_static(copy.deepcopy(OC3), codegen="yes")


def test_cli_codegen_sources_compile_with_wall_and_run(tmp_path, capsys):
    scene = tmp_path / "scene.toml"
    scene.write_text(sc.demo_scene_path("seed001").read_text()
                     .replace("segments = 50", "segments = 12"))
    out = tmp_path / "c"
    assert main(["codegen", str(scene), "--out", str(out)]) == 0
    names = {p.name for p in out.iterdir()}
    assert {"symcable_scene.c", "symcable_scene.h", "symcable_scene_data.h", "main.c",
            "README.md"} <= names
    cc = codegen.compiler()
    proc = subprocess.run([cc, "-c", "-Wall", "symcable_scene.c", "main.c"], cwd=out,
                          capture_output=True, text=True)
    assert proc.returncode == 0 and "warning" not in proc.stderr, proc.stderr
    proc = subprocess.run([cc, "-O1", "main.c", "symcable_scene.c", "-lm", "-o", "example"],
                          cwd=out, capture_output=True, text=True)
    assert proc.returncode == 0, proc.stderr
    run = subprocess.run([str(out / "example")], capture_output=True, text=True)
    assert run.returncode == 0, run.stderr
    st = sc.solve_static(scene, codegen=False)
    assert f"static: {st.stats['iterations']} Newton iterations" in run.stdout
    assert "dynamics: 100 steps done, t = 10 s" in run.stdout


def test_graph_estimate_tracks_the_serialised_size_without_serialising():
    # the estimate decides the default codegen of large steps; off by more than a fifth it
    # would move the DEFAULT_MAX_SIZE crossover by more than a fifth of its segments
    from symcable.api.cable3d_static import cable3d_mechanism
    from symcable.mechanism.functions import functions
    from conftest import two_point
    d = two_point([0.0, 0.0, -50.0], [80.0, 0.0, 0.0], segments=20, depth=50.0,
                  model="cable3d")
    mech = cable3d_mechanism(sc.load_scene(d))
    F = functions(mech)
    for group in (F.static_solver(False).group(), [F.outputs]):
        exact = codegen.graph_size(group)
        assert 0.8 <= codegen.graph_estimate(group) / exact <= 1.2
        # far below the limit: serialised as before; far above it: the estimate
        assert codegen.graph_size(group, limit=10 * exact) == exact
        assert codegen.graph_size(group, limit=exact / 10) == codegen.graph_estimate(group)


def test_codegen_true_refuses_a_graph_too_large_to_compile(monkeypatch, tmp_path):
    # a 2000-segment step asked for in C took the compiler past 20 GB: above
    # MAX_COMPILE_SIZE the virtual machine runs it, with one warning, and nothing compiles
    monkeypatch.setenv("SYMCABLE_CACHE_DIR", str(tmp_path))
    monkeypatch.setattr(codegen, "MAX_COMPILE_SIZE", 1000)
    before = dict(codegen.build_counts)
    with pytest.warns(codegen.CodegenWarning, match="MAX_COMPILE_SIZE"):
        sol = sc.solve_static(small_seed(12), codegen=True)
    assert sol.status == "converged" and not sol.stats["compiled"]
    assert codegen.build_counts["compiled"] == before["compiled"]
    assert not list(tmp_path.glob("*.so"))


def test_default_compiles_in_the_background(monkeypatch, tmp_path):
    """The default ``codegen=None`` gives its first answer in the virtual machine while a
    separate process compiles the structure's C into the build cache: the solve after the
    build, in this process and in a new one, runs the library, with the same answer to
    round-off (1e-9 of the tension: the same arithmetic, compiled)."""
    from symcable.mechanism import background_build
    monkeypatch.delenv("SYMCABLE_CODEGEN", raising=False)
    monkeypatch.delenv("SYMCABLE_CODEGEN_WAIT", raising=False)
    monkeypatch.setenv("SYMCABLE_CACHE_DIR", str(tmp_path))
    d = small_seed(8)
    before = dict(codegen.build_counts)
    first = sc.solve_static(d, estimate=False)
    assert not first.stats["compiled"]
    assert codegen.build_counts["background"] == before["background"] + 1
    assert codegen.build_counts["compiled"] == before["compiled"]  # nothing waited for
    assert background_build.wait(600)
    later = sc.solve_static(d, estimate=False)
    assert later.stats["compiled"]
    assert abs(later.fairlead_tension - first.fairlead_tension) <= 1e-9 * first.fairlead_tension
    probe = ("import json, sys, symcable as sc\n"
             "from symcable.mechanism import codegen\n"
             f"st = sc.solve_static({d!r}, estimate=False)\n"
             "print(json.dumps([st.stats['compiled'], codegen.build_counts]))\n")
    out = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True,
                         check=True).stdout
    compiled, counts = __import__("json").loads(out.strip().splitlines()[-1])
    assert compiled and counts["cache"] >= 1 and counts["compiled"] == counts["background"] == 0
    # asked for (codegen=True), or SYMCABLE_CODEGEN_WAIT=1: the compiler is waited for
    monkeypatch.setenv("SYMCABLE_CODEGEN_WAIT", "1")
    assert background_build.waits(None) and background_build.waits(True)
    monkeypatch.delenv("SYMCABLE_CODEGEN_WAIT")
    assert not background_build.waits(None)
    with background_build.waiting():
        assert background_build.waits(None)
