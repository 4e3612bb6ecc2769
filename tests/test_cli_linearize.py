"""``symcable linearize``: the exact linearisation of a scene through the command line, the
same numbers as ``sc.linearize`` (one process, one function), printed, as JSON and saved."""
from __future__ import annotations

import json

import numpy as np

import symcable as sc
from symcable.cli.main import main
from test_cli_results import tmp_scene


def _small() -> str:
    d = sc.load_scene("seed001").to_dict()
    d["sections"][0]["segments"] = 8
    return tmp_scene(d)


def test_linearize_prints_the_end_stiffness(capsys):
    path = _small()
    assert main(["linearize", path]) == 0
    out = capsys.readouterr().out
    lin = sc.linearize(path)
    k = np.asarray(lin.end_stiffness["b"]) / 1e3
    assert f"stiffness end b    [{k[0, 0]:.5g} " in out
    assert "n_q = 16, n_v = 14" in out  # 8 strains and angles; 7 interior nodes x 2


def test_linearize_json_and_save_are_the_api_result(tmp_path, capsys):
    path = _small()
    assert main(["linearize", path, "--json", "--undamped", "--save",
                 str(tmp_path / "lin.npz")]) == 0
    d = json.loads(capsys.readouterr().out)
    lin = sc.linearize(path, undamped=True)
    np.testing.assert_array_equal(np.asarray(d["K"]), lin.K)
    back = type(lin).load(tmp_path / "lin.npz")
    np.testing.assert_array_equal(back.K, lin.K)
    np.testing.assert_array_equal(back.end_stiffness["a"], lin.end_stiffness["a"])
    assert back.undamped is True
