"""Sweeps (issue 13, item 7; ``symcable.sweep``, ``symcable sweep``): a table of cases run as
independent solves on Dask, each result saved as it finishes.

- 50 static cases of a small cable3d line (25 fairlead offsets x 2 currents) on a local
  cluster of 2 workers, interrupted (a case limit, then result files deleted) and resumed:
  only the missing cases run, and the final table equals the same cases solved one by one
  in this process;
- the compiled functions are built once, in the client, for the first case: every worker
  case loads them from the build cache; a case of another structure runs in the virtual
  machine rather than compile on a worker;
- a case that fails (a SceneError from its overrides, a ConvergenceError in its analysis)
  is recorded with its message and no values, and the sweep goes on;
- the sweep file's errors: one SceneError naming the key, the value and what is allowed.
"""
from __future__ import annotations

import copy
import json
import os
import sys
from pathlib import Path

import numpy as np
import pytest
import tomli_w

import symcable as sc
from symcable.mechanism import codegen
from symcable.cli.main import main
from symcable.errors import SceneError, SymcableError

#: a 3-segment cable3d line on the seabed (OC3 geometry), no motion: a case (its Mechanism
#: and Functions built for its scene, then solved) takes about 0.1 s
LINE = {
    "name": "small cable3d line", "model": "cable3d",
    "environment": {"water_density": 1025.0, "depth": 320.0, "current": [0.0, 0.0, 0.0]},
    "seabed": {"stiffness": 1.0e5},
    "line_types": {"chain": {"EA": 3.84243e8, "mass": 77.7066, "diameter": 0.09,
                             "weight": 698.094, "cd_normal": 1.6, "cd_tangential": 0.1}},
    "sections": [{"type": "chain", "length": 902.2, "segments": 3}],
    "end_a": {"condition": "pinned", "position": [-853.87, 0.0, -320.0]},
    "end_b": {"condition": "pinned", "position": [-5.2, 0.0, -70.0]},
}
#: fairlead offsets along x, m: the line slack at every one (taut from dx = 18 m on, where its
#: force scale, a constant of its graph, grows with the reach: each taut case its own graph)
OFFSETS = [[-5.2 + dx, 0.0, -70.0] for dx in np.linspace(-20.0, 10.0, 25).tolist()]
CURRENTS = [[0.0, 0.0, 0.0], [0.0, 0.6, 0.0]]
STATIC_OUT = ["fairlead_tension", "anchor_tension", "fairlead_force_x", "fairlead_force_y",
              "fairlead_force_z", "grounded_length"]


def _write(folder, name, data):
    path = folder / name
    path.write_text(tomli_w.dumps(data))
    return path


@pytest.fixture(scope="module")
def compiled_env():
    """Generated C as a user gets it (conftest turns it off for the suite) into a fresh build
    cache, in this process and in the workers it starts (they inherit the environment)."""
    with pytest.MonkeyPatch.context() as mp:
        mp.delenv("SYMCABLE_CODEGEN", raising=False)
        import tempfile
        mp.setenv("SYMCABLE_CACHE_DIR", tempfile.mkdtemp(prefix="symcable-sweep-cache-"))
        yield


@pytest.fixture(scope="module")
def cluster(compiled_env):
    """One local Dask cluster of 2 single-threaded worker processes, for the tests that give
    a scheduler's address (a run without one starts its own)."""
    distributed = pytest.importorskip("distributed")
    import logging
    lc = distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                  dashboard_address="127.0.0.1:0", silence_logs=logging.ERROR)
    yield lc.scheduler_address
    lc.close()


@pytest.fixture(scope="module")
def static_sweep(tmp_path_factory):
    folder = tmp_path_factory.mktemp("sweep")
    _write(folder, "line.toml", LINE)
    path = _write(folder, "CASES.toml", {
        "name": "offsets", "scene": "line.toml", "analysis": "static", "outputs": STATIC_OUT,
        "grid": {"end_b.position": OFFSETS, "environment.current": CURRENTS},
        "cases": [{"name": "two segments", "sections[0].segments": 2},
                  {"name": "out of reach", "end_b.position": [1500.0, 0.0, -70.0]}]})
    return path


def test_sweep_on_dask_interrupted_resumed_equals_one_by_one(static_sweep, cluster):
    sweep = sc.read_sweep(static_sweep)
    assert len(sweep.cases) == 52
    assert sweep.cases[0].name == "position=-25.2_0_-70,current=0_0_0"
    assert sweep.cases[50].name == "two segments"
    out = static_sweep.parent / "results"
    # interrupted: a local cluster of its own (the default), stopped after 20 cases
    first = sc.run_sweep(static_sweep, out=out, workers=2, limit=20)
    assert (first.stats["ran"], first.stats["not_run"], first.stats["workers"]) == (20, 32, 2)
    assert [c.status for c in first.cases[:20]] == ["converged"] * 20
    saved = sorted(out.glob("*-*.json"))
    assert len(saved) == 20
    for path in saved[:3]:  # and three results lost
        path.unlink()
    # resumed on a running cluster, by address: only the 35 missing cases run
    final = sc.run_sweep(static_sweep, out=out, scheduler=cluster)
    assert (final.stats["ran"], final.stats["skipped"], final.stats["not_run"]) == (35, 17, 0)
    assert sum(c.skipped for c in final.cases) == 17
    assert len(list(out.glob("*-*.json"))) == 52
    assert final.failed == {"out of reach": final["out of reach"].message}
    assert final["out of reach"].message.startswith("SceneError: end_b.position = [1500.0")
    assert final["out of reach"].values == {}
    # the same cases one by one, here: the same answers. Each case is its own Mechanism
    # (built per scene content) solved from its own start by the same code on the same
    # machine, so the numbers agree bit for bit; the tolerance allows a Newton solve that
    # ends one iteration apart (the static tolerance, 1e-9 of the force scale)
    for case in sweep.cases:
        if case.scene is None:
            continue
        codegen_ = False if case.name == "two segments" else None  # as the sweep ran it
        ref = sc.solve_static(case.scene, codegen=codegen_)
        got = final[case.name]
        assert got.status == "converged"
        assert got.values["fairlead_tension"] == pytest.approx(ref.fairlead_tension, rel=1e-9)
        assert got.values["anchor_tension"] == pytest.approx(ref.anchor_tension, rel=1e-9)
        np.testing.assert_allclose([got.values[f"fairlead_force_{a}"] for a in "xyz"],
                                   ref.fairlead_force, rtol=1e-9, atol=1e-9 * ref.fairlead_tension)
        assert got.values["grounded_length"] == pytest.approx(ref.grounded_length, abs=1e-6)
    # the current carries the fairlead force sideways, the offset raises the tension
    y = final.column("fairlead_force_y")
    assert np.count_nonzero(np.abs(y) > 1.0) == 25
    t = [final[c.name].values["fairlead_tension"] for c in sweep.cases[:50:2]]
    assert np.all(np.diff(t) > 0)
    # the table saved beside the case files, and read back
    table = sc.SweepResult.load(out / "results.csv")
    assert table.names == final.names and table.outputs == tuple(STATIC_OUT)
    np.testing.assert_array_equal(table.column("fairlead_tension"),
                                  final.column("fairlead_tension"))
    assert table["out of reach"].status == "failed" and table["out of reach"].values == {}
    assert sc.SweepResult.load(out / "results.json").to_dict() == final.to_dict()


def test_compiled_once_in_the_client(static_sweep, cluster):
    """After the test above: the first case compiled the static solve in the client, every
    grid case on a worker loaded it from the build cache; the two-segment case (another
    graph) ran in the virtual machine rather than compile on a worker."""
    if codegen.compiler() is None:
        pytest.skip("no C compiler: every case runs in the virtual machine")
    final = sc.SweepResult.load(static_sweep.parent / "results" / "results.json")
    first, *rest = [c for c in final.cases if c.name not in ("two segments", "out of reach")]
    assert first.builds["compiled"] >= 1 and first.worker.endswith(f":{os.getpid()}")
    assert all(c.builds["compiled"] == 0 and c.builds["vm"] == 0 and
               c.builds["cache"] + c.builds["memory"] >= 1 for c in rest)
    assert len({c.worker for c in rest}) >= 2  # both workers took cases
    two = final["two segments"]
    assert two.builds["compiled"] == 0 and two.builds["vm"] >= 1


def test_failed_case_recorded_and_the_sweep_goes_on(tmp_path, cluster):
    """A ConvergenceError on a worker (RK4 far beyond its stable step), a SceneError from a
    case's overrides: both recorded as failed with their one-line message, no value, and
    the other cases run."""
    scene = copy.deepcopy(LINE)
    scene["end_b"]["motion"] = {"kind": "harmonic", "period": 10.0,
                                "amplitude": [2.0, 0.0, 1.0], "phase_deg": [0.0, 0.0, -90.0]}
    _write(tmp_path, "line.toml", scene)
    path = _write(tmp_path, "CASES.toml", {
        "scene": "line.toml", "analysis": "simulate", "codegen": False,
        "simulate": {"duration": 4.0, "dt": 0.05, "method": "rk4"},
        "cases": [{"name": "ok"}, {"name": "blows up", "simulate": {"dt": 1.0}},
                  {"name": "below the seabed", "end_b.position": [-5.2, 0.0, -400.0]},
                  {"name": "ok too", "end_b.motion.period": 8.0}]})
    res = sc.run_sweep(path, scheduler=cluster)
    assert [c.status for c in res.cases] == ["converged", "failed", "failed", "converged"]
    assert res["blows up"].message.startswith("ConvergenceError: rk4: the state blew up")
    assert "below the seabed at z = -320.0 m" in res["below the seabed"].message
    assert all(c.values == {} for c in res.cases if not c.ok)
    assert np.isfinite(res.column("fairlead_tension_max")).all() and len(res.succeeded) == 2
    # the statistics are those of the run itself (the same run, here)
    tr = sc.simulate(tmp_path / "line.toml", 4.0, dt=0.05, method="rk4", codegen=False)
    ok = res["ok"].values
    assert ok["fairlead_tension_max"] == pytest.approx(tr.fairlead_tension.max(), rel=1e-12)
    assert ok["anchor_tension_mean"] == pytest.approx(tr.anchor_tension.mean(), rel=1e-12)
    assert ok["static_fairlead_tension"] == pytest.approx(
        sc.solve_static(tmp_path / "line.toml").fairlead_tension, rel=1e-9)
    # saved failed: a resume does not run them again, unless asked
    again = sc.run_sweep(path, workers=0)
    assert again.stats["skipped"] == 4 and again.stats["ran"] == 0
    retried = sc.run_sweep(path, workers=0, retry_failed=True)
    assert retried.stats["ran"] == 2 and retried.stats["failed"] == 2


def _sweep(**changes):
    d = {"scene": LINE, "analysis": "static", "grid": {"end_b.position": OFFSETS[:2]}}
    d.update(changes)
    return {k: v for k, v in d.items() if v is not None}


@pytest.mark.parametrize("changes, message", [
    (dict(analyse="static"), "<dict>: analyse = 'static': unknown key (allowed: name, scene, "),
    (dict(analysis="statics"), "analysis = 'statics': must be one of 'static', 'simulate', "),
    (dict(outputs=["fairlead_tension_max"]), "outputs = 'fairlead_tension_max': not an output "
     "of a cable3d 'static' analysis (allowed: fairlead_tension, anchor_tension, "),
    (dict(simulate={"duration": 10.0}), "[simulate] = {'duration': 10.0}: options of analysis "
     "'simulate', but analysis = 'static'"),
    (dict(analysis="simulate"), "simulate.duration: required key missing"),
    (dict(analysis="simulate", simulate={"duration": 10.0, "dt": -1}),
     "simulate.dt = -1: must be a number, s > 0"),
    (dict(analysis="simulate", simulate={"duration": 10.0, "tol": 2}),
     "simulate.tol = 2: must be a number in (0, 1), not with dt"),
    (dict(analysis="simulate", simulate={"duration": 10.0, "tol": 0.01, "dt": 0.1}),
     "simulate.tol = 0.01: give dt (a fixed step) or tol"),
    (dict(analysis="periodic", periodic={"method": "newton"}), "periodic.method = 'newton': "
     "must be 'shooting', 'collocation' or 'harmonic-balance'"),
    (dict(grid={"end_b.position": [-5.2, 0.0, -70.0]}), None),  # numbers: 3 (invalid) cases
    (dict(grid={"end_b.position": []}), "grid.'end_b.position' = []: must be a non-empty list"),
    (dict(grid=None), "no cases: give [[cases]]"),
    (dict(cases=[{"name": "a"}, {"name": "a"}]), "cases[1].name = 'a': already the name of "
     "cases[0]"),
    (dict(cases=[{"end_b.position": [0, 0, -70]}]), "cases[0].name = None: required"),
    (dict(cases=[{"name": "typo", "end_b.positon": [0, 0, -70]}]),
     "cases[0] ('typo'): end_b.positon: unknown key; did you mean 'position'?"),
    (dict(cases=[{"name": "idx", "sections[3].length": 10.0}]),
     "cases[0] ('idx'): 'sections[3].length': sections has 1 entries: index [3] must be < 1"),
    (dict(cases=[{"name": "deep", "name.first": 1}]), "'name.first': name is a value, not a "
     "table"),
    (dict(cases=[{"name": "bad key", "end_b..position": 1}]), "'' in 'end_b..position' is "
     "not a key"),
    (dict(scene="missing.toml"), "scene = 'missing.toml': no such file"),
    (dict(codegen="yes"), "codegen = 'yes': must be true or false"),
])
def test_sweep_file_errors(changes, message):
    if message is None:  # a grid of numbers where vectors belong: each case fails, recorded
        sweep = sc.read_sweep(_sweep(**changes))
        assert [c.scene for c in sweep.cases] == [None] * 3
        assert sweep.cases[0].error.startswith("SceneError: end_b.position = -5.2")
        return
    with pytest.raises(SceneError) as info:
        sc.read_sweep(_sweep(**changes))
    assert message in str(info.value)
    assert "\n" not in str(info.value)


def test_no_dask_names_the_extra(monkeypatch):
    monkeypatch.setitem(sys.modules, "distributed", None)  # import distributed fails
    with pytest.raises(SymcableError, match=r'pip install "symcable\[sweep\]"'):
        sc.run_sweep(_sweep(), workers=2)
    # without Dask, one by one in this process
    res = sc.run_sweep(_sweep(), workers=0)
    assert [c.status for c in res.cases] == ["converged"] * 2


def test_cli_sweep_and_a_changed_scene_runs_again(tmp_path, capsys):
    _write(tmp_path, "line.toml", LINE)
    path = _write(tmp_path, "CASES.toml", {
        "scene": "line.toml", "analysis": "static", "outputs": ["fairlead_tension"],
        "cases": [{"name": "near", "end_b.position": [-10.0, 0.0, -70.0]},
                  {"name": "far", "end_b.position": [10.0, 0.0, -70.0]}]})
    assert main(["sweep", str(path), "--workers", "0", "--limit", "1"]) == 1  # one not run
    out = capsys.readouterr().out
    assert "1 run, 0 already done, 0 failed, 1 not run" in out and "far: not run" in out
    assert main(["sweep", str(path), "--workers", "0", "--json"]) == 0
    d = json.loads(capsys.readouterr().out)
    assert [c["skipped"] for c in d["cases"]] == [True, False]
    assert d["cases"][1]["values"]["fairlead_tension"] > d["cases"][0]["values"]["fairlead_tension"]
    # the scene file changed: every case's hash changes, both run again
    heavier = copy.deepcopy(LINE)
    heavier["line_types"]["chain"]["weight"] = 800.0
    _write(tmp_path, "line.toml", heavier)
    assert main(["sweep", str(path), "--workers", "0", "--json"]) == 0
    d2 = json.loads(capsys.readouterr().out)
    assert d2["stats"]["ran"] == 2 and d2["cases"][0]["hash"] != d["cases"][0]["hash"]
    assert len(list((tmp_path / "CASES-results").glob("near-*.json"))) == 2
    # a bad sweep file: one line, status 2
    bad = _write(tmp_path, "BAD.toml", {"scene": "line.toml", "analysis": "dynamic"})
    assert main(["sweep", str(bad), "--workers", "0"]) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith("symcable: SceneError: ") and "analysis = 'dynamic'" in err
    assert "\n" not in err


DECKS = Path("/work/shared/reference/moordyn-chains")


@pytest.mark.skipif(not DECKS.is_dir(), reason="reference decks not present")
def test_a_moordyn_deck_as_the_scene(tmp_path):
    """The scene of a sweep may be a MoorDyn deck: its keys are those of the scene it reads
    as (``environment.current``)."""
    path = _write(tmp_path, "CASES.toml", {
        "scene": str(DECKS / "WD0050_Chain.txt"), "analysis": "static",
        "grid": {"environment.current": [[0.0, 0.0, 0.0], [0.5, 0.0, 0.0]]}})
    res = sc.run_sweep(path, workers=0)
    deck = sc.load_scene(DECKS / "WD0050_Chain.txt").to_dict()
    deck["environment"]["current"] = [0.5, 0.0, 0.0]
    assert res["current=0.5_0_0"].values["fairlead_tension"] == pytest.approx(
        sc.solve_static(deck).fairlead_tension, rel=1e-9)
    assert res.column("anchor_tension")[1] != res.column("anchor_tension")[0]


def test_a_builtin_scene_by_name():
    """``scene = "oc3"``: a built-in scene's name, as everywhere a scene is taken."""
    sw = sc.read_sweep({"scene": "oc3", "analysis": "static", "outputs": ["fairlead_tension"],
                        "cases": [{"name": "a", "end_b.position": [-5.2, -70.0]}]})
    assert sw.scene_source == sc.load_scene("oc3").source and len(sw.cases) == 1
    assert sw.model == "planar"
