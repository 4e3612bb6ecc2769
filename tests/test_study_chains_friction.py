"""The chain study's friction section (studies/chains/friction.py) in --quick mode: WD0050
under the A1 heave over t = 0..5 s, the Coulomb law as the deck maps MoorDyn's friction and
the bristle law, first-order generalized-alpha at 0.1 s in the virtual machine. No
wall-clock assertions."""
from __future__ import annotations

import importlib.util
import json
from pathlib import Path

import pytest

HERE = Path(__file__).resolve().parents[1] / "studies" / "chains"


def _study():
    spec = importlib.util.spec_from_file_location("chains_friction", HERE / "friction.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


pytestmark = pytest.mark.skipif(
    not (_study().cases.REF_DIR / "WD0050_Chain.txt").is_file(),
    reason="reference decks not present")


def test_friction_quick(tmp_path):
    res = _study().main(["--quick", "--out", str(tmp_path)])
    for name in ("results.json", "results.csv", "summary.md", "friction_anchor.png"):
        assert (tmp_path / name).is_file() and (tmp_path / name).stat().st_size > 0, name
    assert json.loads((tmp_path / "results.json").read_text())["quick"] is True
    rows = {r["variant"]: r for r in res["rows"]}
    assert all(r["status"] == "ok" for r in rows.values())
    coulomb, bristle = rows["coulomb (deck)"], rows["bristle"]
    # the bristles are states of their own: 2 per node (42 nodes) beyond the 240 of positions
    # and velocities
    assert coulomb["states"] == 240 and bristle["states"] == 240 + 84
    # the fairlead barely depends on the law (measured 13.2 / 12.2 % max against OrcaFlex,
    # MoorDyn's own test accepts 15 % on the top segment: measured 8.4 / 7.2)
    assert bristle["seg_max"] < 15.0 and coulomb["seg_max"] < 15.0
    # the anchor: the bristle holds the grounded chain, the deck's viscous-like Coulomb law
    # lets it slide (measured max 40.9 against 65.1 %, rms 25.1 against 34.3 %)
    assert bristle["anch_max"] < coulomb["anch_max"]
    assert bristle["anch_rms"] < coulomb["anch_rms"]
    assert bristle["anch_vs_base"] > 10.0  # the laws differ there (measured 39 %)
    assert 1.0 < bristle["newton_per_step"] < 10.0
    # CableDyn beside them where the bench extra installed it (CI's test extra does not)
    study = _study()
    cd = rows.get(study.CABLEDYN)
    if study.peers.available()["CableDyn"]:
        assert cd is not None and cd["status"] == "ok" and cd["seg_max"] < 25.0, cd
        assert "wall_s" in cd
    else:
        assert cd is None
