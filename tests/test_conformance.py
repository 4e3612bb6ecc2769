"""The conformance matrix (studies/conformance/matrix.py, --quick): every analysis on every
built-in scene (and a single-line and a multi-line MoorDyn deck), through the Python API and
the CLI, either works or is refused with one clear line. A FAIL cell is a traceback, an
internal error, an exit status other than 0 or 2, a NaN in a result, a figure not written, or
a save/load round trip that is not exact; the assertion lists every one with its message and
the call that reproduces it."""
from __future__ import annotations

from conftest import load_study


def test_conformance_matrix_has_no_fail_cell(tmp_path):
    matrix = load_study("conformance", "matrix.py")
    res = matrix.run_matrix(quick=True, out=tmp_path, log=lambda line: None)
    assert res["cells"], "the matrix ran no cell"
    failed = matrix.failures(res)
    assert not failed, (f"{len(failed)} of {len(res['cells'])} cells FAIL:\n\n"
                        + matrix.fail_report(res))
