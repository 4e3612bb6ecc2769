"""Exact save and load of results (symcable/results/io.py): every array with its dtype and
shape, NaN and infinities, tuples and nested dicts come back equal from .json and .npz; a
scene of several lines' time history saves to both."""
from __future__ import annotations

import math

import numpy as np
import pytest

import symcable as sc
from symcable.results.io import read_tree, write_tree


def _equal(a, b) -> bool:
    """Equal in value and type, NaN equal to NaN, arrays in dtype and shape too."""
    if isinstance(a, np.ndarray):
        return (isinstance(b, np.ndarray) and a.dtype == b.dtype and a.shape == b.shape
                and np.array_equal(a, b, equal_nan=a.dtype.kind in "fc"))
    if isinstance(a, float) and math.isnan(a):
        return isinstance(b, float) and math.isnan(b)
    if isinstance(a, dict):
        return isinstance(b, dict) and a.keys() == b.keys() and all(_equal(a[k], b[k]) for k in a)
    if isinstance(a, (list, tuple)):
        return type(a) is type(b) and len(a) == len(b) and all(map(_equal, a, b))
    return type(a) is type(b) and a == b


TREE = {"array": np.array([[1.0, np.nan], [np.inf, -0.0]]), "ints": np.arange(4),
        "empty": np.zeros((0, 3)), "complex": np.array([1 + 2j, complex(np.nan, 1)]),
        "flag": np.array(True), "stats": {"nan": math.nan, "inf": -math.inf, "tiny": 5e-324,
                                          "third": 1 / 3, "pair": (1, "a"), "none": None},
        "keys": {1: "int key", "__x": 2}, "nested": [np.ones(2), (np.zeros(1),)]}


@pytest.mark.parametrize("suffix", [".json", ".npz"])
def test_a_tree_round_trips_exactly(tmp_path, suffix):
    back = read_tree(write_tree(tmp_path / f"t{suffix}", TREE))
    assert _equal(TREE, back), back


def test_a_system_trajectory_saves_to_npz_and_json(tmp_path):
    """The sphere's time history (a scene of points and a body): both formats give back
    every output array exactly."""
    run = sc.simulate("sphere", 0.5, dt=0.05)
    for suffix in (".npz", ".json"):
        back = type(run).load(run.save(tmp_path / f"run{suffix}"))
        assert back.outputs.keys() == run.outputs.keys()
        assert all(np.array_equal(run.outputs[k], back.outputs[k]) for k in run.outputs)
        assert np.array_equal(back.time, run.time) and back.summary() == run.summary()


def test_an_unknown_suffix_is_refused(tmp_path):
    with pytest.raises(sc.SymcableError, match=r"suffix must be \.npz or \.json"):
        write_tree(tmp_path / "t.csv", TREE)

