"""CasADi's sparse QR returns NaN when a column holds entries near 1e-160 (their squares are
subnormal numbers in its Householder norm). Every QR solve in symcable flushes such entries
first (symcable.linalg.sparse.qr_solve). Both tests fail without the flush: the first with a
NaN solution, the second with RK4 'blowing up' at its 9th step, far inside its stable step."""
from __future__ import annotations

import casadi as ca
import numpy as np
import pytest
from conftest import load_study

import symcable as sc
from symcable.linalg.sparse import qr_solve, sparse_solve


@pytest.mark.parametrize("tiny", [1e-161, 1e-160, 1e-157, 1e-154])
@pytest.mark.parametrize("kind", ["MX", "DM"])
def test_qr_solve_of_a_matrix_with_tiny_entries(tiny, kind):
    A = ca.DM([[2.0, tiny, 0.0], [tiny, 3.0, tiny], [0.0, tiny, 4.0]])
    b = ca.DM([1.0, 1.0, 1.0])
    if kind == "MX":
        Am, bm = ca.MX.sym("A", A.sparsity()), ca.MX.sym("b", 3)
        x = ca.Function("f", [Am, bm], [sparse_solve(Am, bm)])(A, b)
    else:
        x = qr_solve(A, b)
    # the tiny couplings change the solution by ~1e-160: it is diag(A)^-1 b to the last digit
    np.testing.assert_array_equal(np.array(x).ravel(), [0.5, 1.0 / 3.0, 0.25])


def test_rk4_runs_the_lifted_module_at_40_segments():
    """A 20 t module hanging 100 m under a crane on a 40-segment wire: its mass matrix (the
    body's and the wire's added mass) has entries of 1e-167 to 1e-150 across the nearly
    vertical wire. RK4 at its own stable step: every sample finite, tensions near static."""
    case = load_study(".", "systems_case.py")
    scene = sc.load_scene(case.module_scene(segments=40))
    run = sc.simulate(scene, 0.01, method="rk4")
    assert run.status == "converged"
    tension = np.asarray(run.lines["lift"].tension, float)  # (n_t, n) N
    assert np.all(np.isfinite(tension))
    # 0.01 s of crane motion (mm) moves the top tension by far less than 1 % of its
    # static 153 kN; a blow-up is orders of magnitude off
    assert np.ptp(tension[:, -1]) < 0.01 * np.max(tension[:, -1])
