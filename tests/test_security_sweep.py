"""Sweeps under hostile or broken input (issue 31): every bad sweep file, saved case or
argument gives one line (a LimitError, SceneError or SymcableError naming the key, the value
and what is allowed) or, for a saved case, is taken as not saved and run again; never a
traceback, a hang or memory exhausted. The local Dask cluster listens on the loopback
interface only.

- the number of cases is checked against ``limits().sweep_cases`` before the grid is
  expanded or any case's scene loaded (a 2000 x 2000 grid is refused at once);
- the sweep file is read as a regular file under ``file_bytes`` (a FIFO, /dev/zero, a
  folder, a large file: one line) and nested no deeper than ``nesting``;
- a saved case file is used only when it is a JSON object of the right fields, types and
  values; every edited or corrupt one (a dozen kinds, a FIFO, /dev/zero) runs again;
- explicit ``workers`` are capped; case names stay in the results folder and on one line.
"""
from __future__ import annotations

import json
import os
import threading
import tracemalloc

import psutil
import pytest

import symcable as sc
from symcable.cli.main import main
from symcable.errors import LimitError, SceneError, SymcableError
from symcable.limits import limits
from symcable.results.sweep import SUMMARY_ROWS, CaseResult, SweepResult
from symcable.sweep import run as sweep_run
from symcable.sweep import spec

#: a 3-segment cable3d line on the seabed, no motion: its static solve takes milliseconds
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
OUTPUTS = ["fairlead_tension", "anchor_tension"]
#: the lines of SweepResult.summary before the cases (sweep, cases, workers, results)
HEAD = 4


def _sweep(**changes):
    d = {"scene": LINE, "analysis": "static", "outputs": OUTPUTS}
    d.update(changes)
    return d


def _one_line(exc, *parts):
    text = str(exc.value)
    assert "\n" not in text, text
    for part in parts:
        assert part in text, text
    return text


# ------------------------------------------------------------------------- case count

def test_case_count_checked_before_the_grid_is_expanded(monkeypatch):
    def never(*args, **kwargs):
        raise AssertionError("a case or scene was built before the case count was checked")

    grid = {"end_b.position": [[-5.2 + dx, 0.0, -70.0] for dx in range(4)],
            "environment.current": [[0.0, v, 0.0] for v in (0.0, 0.1, 0.2, 0.3)]}
    cases = [{"name": "a"}, {"name": "b"}]
    with monkeypatch.context() as mp:
        mp.setattr(spec, "load_scene", never)
        mp.setattr(spec, "_case", never)
        with limits(sweep_cases=17), pytest.raises(LimitError) as info:
            sc.read_sweep(_sweep(grid=grid, cases=cases))  # 4 x 4 + 2 = 18
    _one_line(info, "<dict>: ", "cases", "= 18: more than the limit of 17", "--max-cases",
              "sweep_cases=")
    with limits(sweep_cases=18):  # at the limit: read
        assert len(sc.read_sweep(_sweep(grid=grid, cases=cases)).cases) == 18


def test_a_huge_grid_is_refused_at_once(tmp_path, capsys):
    """2000 x 2000 values: one line, little memory (it used to build 4 million cases)."""
    (tmp_path / "line.toml").write_text(_toml(LINE))
    values = ", ".join(f"{x:.1f}" for x in range(2000))
    path = tmp_path / "BIG.toml"
    path.write_text('scene = "line.toml"\nanalysis = "static"\n[grid]\n'
                    f'"environment.depth" = [{values}]\n"seabed.stiffness" = [{values}]\n')
    tracemalloc.start()
    try:
        status = main(["sweep", str(path), "--workers", "0", "--limit", "1"])
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    err = capsys.readouterr().err.strip()
    assert status == 2
    assert err.startswith("symcable: LimitError: ") and "\n" not in err
    assert "= 4,000,000: more than the limit of 10,000" in err and "2000 x 2000" in err
    assert peak < 32e6  # measured 2 MB; the grid's expansion was gigabytes
    assert not (tmp_path / "BIG-results").exists()


def _toml(data) -> str:
    import tomli_w
    return tomli_w.dumps(data)


# ------------------------------------------------------------------------- the sweep file

def test_sweep_file_a_fifo_a_device_a_folder_or_too_large(tmp_path):
    (tmp_path / "line.toml").write_text(_toml(LINE))
    fifo = tmp_path / "FIFO.toml"
    os.mkfifo(fifo)
    outcome = []

    def read():
        try:
            sc.read_sweep(fifo)
        except BaseException as exc:  # recorded for the assertion below
            outcome.append(exc)

    reader = threading.Thread(target=read, daemon=True)  # a hang must not hang the suite
    reader.start()
    reader.join(20.0)
    assert not reader.is_alive(), "reading a FIFO as the sweep file hangs"
    assert isinstance(outcome[0], SymcableError), outcome
    assert "FIFO.toml" in str(outcome[0]) and "a FIFO" in str(outcome[0])

    zero = tmp_path / "ZERO.toml"
    zero.symlink_to("/dev/zero")  # read to its end, it exhausts memory
    with pytest.raises(SymcableError) as info:
        sc.read_sweep(zero)
    _one_line(info, "ZERO.toml", "a device", "regular files only")
    with pytest.raises(SymcableError) as info:
        sc.read_sweep(tmp_path)
    _one_line(info, "a folder")

    big = tmp_path / "BIG.toml"
    big.write_text(_toml({"scene": "line.toml", "analysis": "static",
                          "cases": [{"name": f"case {i}"} for i in range(100)]}))
    assert sc.read_sweep(big).cases[99].name == "case 99"
    with limits(file_bytes=1000), pytest.raises(LimitError) as info:
        sc.read_sweep(big)
    _one_line(info, "BIG.toml", f"= {big.stat().st_size:,}: more than the limit of 1,000",
              "--max-file-mb")


def test_nesting_refused_before_it_is_parsed_or_flattened(tmp_path):
    (tmp_path / "line.toml").write_text(_toml(LINE))
    head = 'scene = "line.toml"\nanalysis = "static"\n[[cases]]\nname = "deep"\n'
    arrays = tmp_path / "ARRAYS.toml"
    arrays.write_text(head + '"environment.current" = ' + "[" * 5000 + "]" * 5000 + "\n")
    with pytest.raises(LimitError) as info:
        sc.read_sweep(arrays)
    _one_line(info, "ARRAYS.toml", "nesting", "= 5,000: more than the limit of 32",
              "--max-nesting")
    # dotted keys: nested tables without a bracket (flattening them recursed)
    dotted = tmp_path / "DOTTED.toml"
    dotted.write_text(head + ".".join(["a"] * 5000) + " = 1\n")
    with pytest.raises(LimitError) as info:
        sc.read_sweep(dotted)
    _one_line(info, "DOTTED.toml", "nesting", "more than the limit of 32")
    # a dict in the sweep's layout
    deep: dict = {"x": 1.0}
    for _ in range(5000):
        deep = {"a": deep}
    with pytest.raises(LimitError) as info:
        sc.read_sweep(_sweep(cases=[{"name": "deep", **deep}]))
    _one_line(info, "<dict>", "nesting", "more than the limit of 32")
    # a grid of tables nested within the limit still flattens to its keys
    sweep = sc.read_sweep(_sweep(grid={"environment": {"current": [[0.0, 0.0, 0.0]]}}))
    assert list(sweep.cases[0].overrides) == ["environment.current"]


# ------------------------------------------------------------------------- saved cases

def _edit_values(rec, how):
    rec["values"] = how(rec["values"])
    return json.dumps(rec)


def _without(key):
    def edit(rec):
        del rec[key]
        return json.dumps(rec)
    return edit


def _raw_value(text):
    """The record with its fairlead tension written as ``text`` (JSON that json.dumps does
    not write)."""
    def edit(rec):
        rec["values"]["fairlead_tension"] = "@"
        return json.dumps(rec).replace('"@"', text)
    return edit


#: a saved case file edited or corrupted: name -> its new content (text, bytes), or a
#: function of the path that puts something else there
EDITS = {
    "values as strings": lambda r: _edit_values(r, lambda v: {k: str(x) for k, x in v.items()}),
    "values nested": lambda r: _edit_values(r, lambda v: {k: {"N": x} for k, x in v.items()}),
    "values a list": lambda r: _edit_values(r, lambda v: list(v.values())),
    "value a bool": lambda r: _edit_values(r, lambda v: {**v, "fairlead_tension": True}),
    "value null": lambda r: _edit_values(r, lambda v: {**v, "fairlead_tension": None}),
    "an output missing": lambda r: _edit_values(r, lambda v: {"anchor_tension": 1.0}),
    "values missing": _without("values"),
    "status missing": _without("status"),
    "name missing": _without("name"),
    "hash missing": _without("hash"),
    "status unknown": lambda r: json.dumps({**r, "status": "done"}),
    "status a number": lambda r: json.dumps({**r, "status": 1}),
    "message a number": lambda r: json.dumps({**r, "message": 5}),
    "wall time a string": lambda r: json.dumps({**r, "wall_time": "1 s"}),
    "wall time negative": lambda r: json.dumps({**r, "wall_time": -1.0}),
    "builds a list": lambda r: json.dumps({**r, "builds": [1, 2]}),
    "builds as text": lambda r: json.dumps({**r, "builds": {"vm": "one"}}),
    "worker a table": lambda r: json.dumps({**r, "worker": {"host": "x"}}),
    "skipped a string": lambda r: json.dumps({**r, "skipped": "yes"}),
    "overrides a list": lambda r: json.dumps({**r, "overrides": []}),
    "a list, not an object": lambda r: json.dumps([r]),
    "a number": lambda r: "42",
    "huge number": _raw_value("1e999"),
    "huge integer": _raw_value("1" * 400),
    "too many digits": _raw_value("1" * 5000),
    "NaN": _raw_value("NaN"),
    "minus infinity": _raw_value("-Infinity"),
    "a million nested arrays": lambda r: "[" * 10**6 + "]" * 10**6,
    "nested arrays in a value": _raw_value("[" * 100 + "]" * 100),
    "not UTF-8": lambda r: b"\xff\xfe{}",
    "empty": lambda r: "",
    "truncated": lambda r: json.dumps(r)[:40],
    "larger than the file limit": lambda path: os.truncate(path, (16 << 20) + 1),
    "a FIFO": lambda path: (path.unlink(), os.mkfifo(path)),
    "a link to /dev/zero": lambda path: (path.unlink(), path.symlink_to("/dev/zero")),
}


def test_edited_or_corrupt_saved_cases_run_again(tmp_path):
    """Every case has the same content (no overrides), so one scene is built and each case
    is one static solve; each saved file but one ("intact") is then edited."""
    cases = [{"name": "intact"}] + [{"name": name} for name in EDITS]
    sweep = sc.read_sweep(_sweep(cases=cases))
    out = tmp_path / "results"
    first = sc.run_sweep(sweep, out=out, workers=0, progress=False)
    assert first.stats["ran"] == len(cases) and not first.failed
    files = {c.name: out / f"{c.stem}.json" for c in sweep.cases}
    assert all(p.is_file() for p in files.values())
    for name, edit in EDITS.items():
        path = files[name]
        if edit.__code__.co_varnames[:1] == ("path",):
            edit(path)
            continue
        new = edit(json.loads(path.read_text()))
        (path.write_bytes if isinstance(new, bytes) else path.write_text)(new)

    again = sc.run_sweep(sweep, out=out, workers=0, progress=False)
    assert (again.stats["ran"], again.stats["skipped"]) == (len(EDITS), 1)
    assert again["intact"].skipped
    for name in EDITS:
        got = again[name]
        assert not got.skipped and got.status == "converged", name
        assert got.values == pytest.approx(first[name].values, rel=1e-9), name
    lines = again.summary().splitlines()  # the first SUMMARY_ROWS cases, "... 16 more"
    assert len(lines) == HEAD + SUMMARY_ROWS + 1 and lines[-1].startswith("  ... 16 more")
    assert again.column("fairlead_tension").shape == (len(cases),)
    # rewritten: regular files again, every case found on the next run
    assert all(p.is_file() and not p.is_symlink() for p in files.values())
    third = sc.run_sweep(sweep, out=out, workers=0, progress=False)
    assert (third.stats["ran"], third.stats["skipped"]) == (0, len(cases))


def test_case_records_checked_field_by_field():
    good = {"name": "a", "hash": "0123456789ab", "overrides": {"end_b.position": [1, 0, 2]},
            "status": "converged", "values": {"fairlead_tension": 1e5, "anchor_tension": 7},
            "message": "", "wall_time": 0.1, "worker": "host:1", "builds": {"vm": 1},
            "analysis": "static"}
    rec = CaseResult.from_dict(good)
    assert rec.values == {"fairlead_tension": 1e5, "anchor_tension": 7.0}
    assert type(rec.values["anchor_tension"]) is float
    bad = [({**good, "values": {"fairlead_tension": "1e5"}}, "values.fairlead_tension = '1e5'"),
           ({**good, "values": {"fairlead_tension": float("inf")}}, "finite"),
           ({**good, "values": {"fairlead_tension": 10**400}}, "finite"),
           ({**good, "status": "done"}, "status = 'done': must be one of 'converged'"),
           ({**good, "status": "failed"}, "must be empty for status 'failed'"),
           ({k: v for k, v in good.items() if k != "hash"}, "hash: required field missing"),
           ([good], "must be a table (JSON object)"),
           ({**good, "wall_time": float("nan")}, "wall_time = nan: must be a number >= 0"),
           ({**good, "builds": {"vm": -1}}, "builds.vm = -1: must be an integer >= 0")]
    for record, message in bad:
        with pytest.raises(SymcableError) as info:
            CaseResult.from_dict(record)
        _one_line(info, message)
    # a results table with a bad case: one line, naming it
    table = {"name": "s", "analysis": "static", "outputs": OUTPUTS, "cases": [bad[0][0]]}
    with pytest.raises(SymcableError) as info:
        SweepResult.from_dict(table)
    _one_line(info, "cases[0]", "values.fairlead_tension")


# ------------------------------------------------------------------------- Dask, workers

def test_local_cluster_listens_on_localhost_only():
    """The scheduler, its dashboard, the nanny and the worker of a sweep's local cluster:
    every socket they listen on is on 127.0.0.1."""
    me = psutil.Process()

    def listening(proc):
        return {c.laddr for c in proc.net_connections(kind="inet")
                if c.status == psutil.CONN_LISTEN}

    before = listening(me)
    with sweep_run._dask(1, None, 1) as (_, client, n, label):
        assert (n, label) == (1, "local")
        assert client.scheduler.address.startswith("tcp://127.0.0.1:")
        assert client.cluster.dashboard_link.startswith("http://127.0.0.1:")
        pids = client.run(os.getpid)  # worker address -> its process id
        assert len(pids) == 1 and all(a.startswith("tcp://127.0.0.1:") for a in pids)
        here = listening(me) - before
        there = set().union(*(listening(psutil.Process(p)) for p in pids.values()))
    dashboard = int(client.cluster.dashboard_link.split(":")[2].split("/")[0])
    assert dashboard in {a.port for a in here}
    assert len(here) >= 3 and there  # scheduler, dashboard, nanny; the worker
    assert {a.ip for a in here | there} == {"127.0.0.1"}


def test_explicit_workers_capped(tmp_path, monkeypatch, capsys):
    def no_cluster():
        raise AssertionError("a local cluster was started")

    monkeypatch.setattr(sweep_run, "_distributed", no_cluster)
    cases = [{"name": "a"}, {"name": "b"}]
    top = 4 * (os.cpu_count() or 1)
    with pytest.raises(SymcableError) as info:
        sc.run_sweep(_sweep(cases=cases), workers=10**6)
    _one_line(info, "workers = 1,000,000: more than", f"at most {top} local worker processes")
    assert sweep_run.max_workers() == top
    (tmp_path / "line.toml").write_text(_toml(LINE))
    path = tmp_path / "CASES.toml"
    path.write_text(_toml({"scene": "line.toml", "analysis": "static", "cases": cases}))
    assert main(["sweep", str(path), "--workers", str(top + 1)]) == 2
    err = capsys.readouterr().err.strip()
    assert f"workers = {top + 1:,}: more than" in err and "\n" not in err
    assert not (tmp_path / "CASES-results").exists()


# ------------------------------------------------------------------------- names

@pytest.mark.parametrize("name", ["two\nlines", "nul\0", "tab\there", "line\u2028sep",
                                  "x" * 201, ""])
def test_case_names_one_printable_line(name):
    with pytest.raises(SceneError) as info:
        sc.read_sweep(_sweep(cases=[{"name": "ok"}, {"name": name}]))
    _one_line(info, "cases[1].name = ", "1 to 200 printable characters")
    with pytest.raises(SceneError) as info:
        sc.read_sweep(_sweep(name=name, cases=[{"name": "ok"}]))
    _one_line(info, "name = ", "1 to 200 printable characters")


def test_names_from_values_stay_in_the_folder_and_on_one_line(tmp_path):
    """Grid values that make odd names (a newline, NUL, '/', '..', 10,000 characters) and
    listed names with '/' and '..': every file lands in the results folder, every case is
    one line of the summary."""
    values = ["a\nb", "../../escape", "y" * 10_000, "nul\0z", "ok/../../x", "/etc/passwd"]
    cases = [{"name": "../../../up"}, {"name": "/abs/path"}, {"name": "." * 200}]
    sweep = sc.read_sweep(_sweep(grid={"name": values}, cases=cases))
    names = [c.name for c in sweep.cases]
    assert names == ["grid1", "name=../../escape", "grid3", "grid4", "name=ok/../../x",
                     "name=/etc/passwd", "../../../up", "/abs/path", "." * 200]
    out = tmp_path / "deep" / "results"
    res = sc.run_sweep(sweep, out=out, workers=0, progress=False)
    assert sorted(p.name for p in tmp_path.rglob("*") if p.is_file()) == sorted(
        [f"{c.stem}.json" for c in sweep.cases] + ["results.csv", "results.json"])
    assert all(p.parent == out for p in tmp_path.rglob("*") if p.is_file())
    assert all(len(c.stem) <= 93 and "/" not in c.stem for c in sweep.cases)
    lines = res.summary().splitlines()
    assert len(lines) == HEAD + len(names)
    # the scene refuses the names that are not one printable line: those cases failed
    assert sorted(res.failed) == ["grid1", "grid3", "grid4"]
    assert SweepResult.load(out / "results.csv").names == res.names
    # a table from elsewhere with control characters: still one line per case
    odd = SweepResult("s", "static", ("fairlead_tension",), (), (
        CaseResult("two\nlines", "0" * 12, {}, "failed", message="a\nb\rc"),
        CaseResult("ok", "1" * 12, {}, "converged", {"fairlead_tension": 1.0})), {})
    text = odd.summary()
    assert len(text.splitlines()) == 3 + 2 and "two\\nlines: failed: a\\nb\\rc" in text


def test_limits_reach_the_workers():
    """The limits in force where a sweep is run hold on its Dask workers too: under a step
    limit of 5, a 10-step simulate case fails with the limit's message both in the client
    (the first case) and on the worker (the second), which has default limits of its own."""
    moving = {"name": "moving line", "environment": {"water_density": 1025.0},
              "line_types": {"rope": {"EA": 1e7, "mass": 20.0, "diameter": 0.05}},
              "sections": [{"type": "rope", "length": 100.0, "segments": 4}],
              "end_a": {"condition": "pinned", "position": [-80.0, -60.0]},
              "end_b": {"condition": "pinned", "position": [0.0, 0.0],
                        "motion": {"kind": "harmonic", "period": 10.0,
                                   "amplitude": [1.0, 0.5]}}}
    sweep = {"scene": moving, "analysis": "simulate", "simulate": {"duration": 1.0, "dt": 0.1},
             "cases": [{"name": "a"}, {"name": "b", "end_b.position": [1.0, 0.0]}]}
    with limits(steps=5):
        res = sc.run_sweep(sweep, workers=1)
    assert res.stats["workers"] == 1
    assert [c.status for c in res.cases] == ["failed", "failed"]
    assert all("= 10: more than the limit of 5" in c.message for c in res.cases), \
        [c.message for c in res.cases]
