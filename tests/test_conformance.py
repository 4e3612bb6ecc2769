"""The conformance matrix (studies/conformance/matrix.py, --quick): every analysis on every
built-in scene (and a single-line and a multi-line MoorDyn deck), through the Python API and
the CLI, either works or is refused with one clear line. A FAIL cell is a traceback, an
internal error, an exit status other than 0 or 2, a NaN in a result, a figure not written, or
a save/load round trip that is not exact; the assertion lists every one with its message and
the call that reproduces it.

One test class per row: the suite runs with ``--dist loadscope``, which sends each class to
one worker, so the rows (10-60 s each) spread over the workers instead of one worker running
the whole matrix."""
from __future__ import annotations

from conftest import load_study

matrix = load_study("conformance", "matrix.py")
ROWS = matrix.BUILTINS + ("moordyn_chain", "moordyn_buoy")


def test_every_row_has_a_scene():
    """The rows the classes below run are the matrix's rows (none skipped: both decks are
    present in a checkout with ../shared beside it)."""
    rows, skipped = matrix.scene_rows()
    assert not skipped, skipped
    assert tuple(r.name for r in rows) == ROWS


def _row_class(name: str) -> type:
    def test_row_has_no_fail_cell(self, tmp_path):
        res = matrix.run_matrix(quick=True, out=tmp_path, scenes=[name], log=lambda line: None)
        assert res["cells"], f"the matrix ran no cell for {name}"
        failed = matrix.failures(res)
        assert not failed, (f"{len(failed)} of {len(res['cells'])} cells FAIL:\n\n"
                            + matrix.fail_report(res))
    return type(f"TestConformance_{name}", (), {"test_row_has_no_fail_cell": test_row_has_no_fail_cell})


for _name in ROWS:
    globals()[f"TestConformance_{_name}"] = _row_class(_name)
