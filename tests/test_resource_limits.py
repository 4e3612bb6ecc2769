"""The resource limits (symcable.limits) one by one, through the public API: each refuses
the input over it with one LimitError naming the value, the limit and the option, each is
raised by ``sc.limits(...)`` for a block only, and what they guard stays within them (a
scene of points and lines assembles a sparse mass matrix, not a dense n_v x n_v one)."""
from __future__ import annotations

import copy
import os
import threading

import pytest

import symcable as sc
from symcable.limits import _open_brackets, check_nesting, current, read_bounded
from symcable.mechanism.mechanism import casadi_name

from conftest import OC3, seed001

#: the sphere's scene: a free point hung from a moving vessel point by one line
SYSTEM = {
    "name": "system", "model": "cable3d", "environment": {"water_density": 1025.0},
    "line_types": {"wire": {"EA": 1.0e5, "mass": 0.02, "diameter": 0.002, "damping": 100.0}},
    "points": {"weight": {"kind": "free", "position": [0.0, 0.0, -12.0], "mass": 10.0,
                          "volume": 0.004, "diameter": 0.2, "cd": 0.5, "ca": 0.2},
               "top": {"kind": "fixed", "position": [0.0, 0.0, -1.0]}},
    "lines": [{"name": "cable", "end_a": "weight", "end_b": "top",
               "sections": [{"type": "wire", "length": 10.0, "segments": 4}]}],
}


def _one_line(info, *parts):
    text = str(info.value)
    assert "\n" not in text, text
    for part in parts:
        assert part in text, text
    return text


def test_limits_are_checked_and_scoped():
    """Limits() validates its fields; sc.limits changes them in its block only, in its own
    thread only; an unknown name is refused."""
    base = current()
    assert base == sc.Limits()
    with pytest.raises(sc.LimitError, match="segments = 0: must be an integer >= 1"):
        sc.Limits(segments=0)
    with pytest.raises(sc.LimitError, match="unknown limit 'segmnets'"):
        with sc.limits(segmnets=10):
            pass
    seen = {}
    with sc.limits(segments=7) as inner:
        assert inner.segments == current().segments == 7
        t = threading.Thread(target=lambda: seen.update(other=current().segments))
        t.start()
        t.join()
        with sc.limits(steps=3):
            assert (current().segments, current().steps) == (7, 3)
    assert seen["other"] == base.segments and current() == base


def test_segments_refused_before_building():
    """A scene of more segments than the limit is refused by load_scene, named by its
    section, or as the total of all lines; the same scene loads with the limit raised."""
    d = copy.deepcopy(OC3)
    d["sections"][0]["segments"] = 10**7
    with pytest.raises(sc.LimitError) as info:
        sc.load_scene(d)
    _one_line(info, "sections[0].segments = 10,000,000: more than the limit of 20,000",
              "sc.limits(segments=...)", "--max-segments")
    two = copy.deepcopy(SYSTEM)
    two["lines"].append(copy.deepcopy(two["lines"][0]) | {"name": "other"})
    for line in two["lines"]:
        line["sections"][0]["segments"] = 6
    with sc.limits(segments=11), pytest.raises(sc.LimitError) as info:
        sc.load_scene(two)
    _one_line(info, "the scene's segments, all lines together = 12: more than the limit of 11")
    with sc.limits(segments=12):
        assert sc.load_scene(two).lines[1].n_segments == 6


def test_rod_segments_have_their_own_limit():
    """Rod sections count against rod_segments (a rod segment costs about 0.7 MB): the
    built-in rod of 400 loads, and is refused under a rod limit of 399 while the same
    number of cable segments passes."""
    rod = sc.load_scene(str(sc.demo_scene_path("seed000_rod")))
    assert sum(s.segments for s in rod.sections) == 400
    with sc.limits(rod_segments=399), pytest.raises(sc.LimitError) as info:
        sc.load_scene(str(sc.demo_scene_path("seed000_rod")))
    _one_line(info, "(rod segments) = 400: more than the limit of 399", "--max-rod-segments")
    d = copy.deepcopy(OC3)
    d["sections"][0]["segments"] = 400
    with sc.limits(rod_segments=399):
        assert sc.load_scene(d).n_segments == 400


def test_steps_refused_before_the_run():
    """duration / dt over the step limit is refused before anything is built or run; a run
    within it goes."""
    scene = sc.load_scene(seed001())
    with sc.limits(steps=99), pytest.raises(sc.LimitError) as info:
        sc.simulate(scene, 10.0, dt=0.1)
    _one_line(info, "the run's time steps (duration 10 s / dt 0.1 s) = 100: more than the "
              "limit of 99", "--max-steps")
    with pytest.raises(sc.LimitError, match="= 10,000,000,000,000"):
        sc.simulate(scene, 1e12, dt=0.1)
    with sc.limits(steps=100):
        tr = sc.simulate(scene, 1.0, dt=0.1)
    assert tr.status == "converged" and tr.time.size == 11


def test_read_bounded_reads_regular_files_only(tmp_path):
    """A FIFO is refused without blocking, a device or folder as not a regular file, a file
    over its limit by its size; a regular file within it is read whole."""
    fifo = tmp_path / "fifo"
    os.mkfifo(fifo)
    out = {}

    def read():
        try:
            read_bounded(fifo, "file_bytes", "scene file")
        except OSError as exc:
            out["error"] = exc.strerror

    t = threading.Thread(target=read, daemon=True)
    t.start()
    t.join(20.0)
    assert not t.is_alive() and "a FIFO (named pipe), not a regular file" in out["error"]
    for path, kind in (("/dev/zero", "a device"), (tmp_path, "a folder")):
        with pytest.raises(OSError, match=kind):
            read_bounded(path, "file_bytes", "scene file")
    big = tmp_path / "big.txt"
    big.write_bytes(b"1 2 3 4\n" * 1000)
    with sc.limits(table_bytes=7999), pytest.raises(sc.LimitError) as info:
        read_bounded(big, "table_bytes", "motion table")
    _one_line(info, "its size, bytes = 8,000: more than the limit of 7,999", "--max-table-mb")
    with sc.limits(table_bytes=8000):
        assert read_bounded(big, "table_bytes", "motion table") == big.read_bytes()


def test_nesting_is_counted_without_recursion():
    """TOML text: brackets inside strings and comments do not count, table headers do; data:
    its depth, a container shared many times walked once, one that holds itself refused."""
    assert _open_brackets('a = [1, "[[[", \'{{\'] # [[[[\n[[b]]\nc = {d = {e = [1]}}') == 3
    assert _open_brackets('s = """ [[[ \\""" ]"""\nx = [[0]]') == 2
    leaf = [1.0]
    shared = {"k": [leaf] * 5}
    wide = {f"x{i}": shared for i in range(10_000)}  # 10^4 references to one subtree
    check_nesting(wide, "scene")  # depth 4
    with sc.limits(nesting=3), pytest.raises(sc.LimitError, match="= 4: more than the limit of 3"):
        check_nesting(wide, "scene")
    deep = leaf
    for _ in range(10_000):
        deep = [deep]
    with pytest.raises(sc.LimitError, match="more than the limit of 32"):
        check_nesting({"a": deep}, "scene")
    loop: dict = {"a": {}}
    loop["a"]["b"] = loop
    with pytest.raises(sc.LimitError, match="holds itself"):
        sc.load_scene(loop)


def test_casadi_names_are_valid_and_distinct():
    """Every part name the scene allows maps to a valid CasADi Function name; names CasADi
    takes are kept; two names never map to one."""
    import casadi as ca

    names = ["cable", "line1", "my-cable", "my_cable", "a__b", "_x", "x_", "1", "null",
             "jac", "hess", "-", "_", "9" * 64, "a-_-b"]
    mapped = [casadi_name(n) for n in names]
    assert mapped[:2] == ["cable", "line1"]
    assert len(set(mapped)) == len(names)
    x = ca.SX.sym("x")
    for m in mapped:
        ca.Function(f"part_{m}_out", [x], [x])  # raises on an invalid name


def test_points_and_lines_assemble_a_sparse_mass_matrix():
    """The assembled mass matrix of a scene of points and lines has O(n) nonzeros (it was
    dense: 60,000 x 60,000 at 20,000 segments, std::bad_alloc)."""
    d = copy.deepcopy(SYSTEM)
    d["lines"][0]["sections"][0]["segments"] = 200
    mech = sc.cable3d_mechanism(sc.load_scene(d))
    n_v = mech.n_v
    assert n_v == 3 * 200  # 199 interior nodes and the free point
    assert mech.mass.nnz() <= 10 * n_v, (mech.mass.nnz(), n_v)
