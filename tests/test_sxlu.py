"""The block LU written out in SX (symcable.linalg.sxlu): exact on the patterns the cable
systems have, an elimination order that depends on the pattern alone, and a clear refusal
where no fixed order exists."""
from __future__ import annotations

import copy

import casadi as ca
import numpy as np
import pytest

import symcable as sc
from symcable.mechanism.functions import functions
from symcable.models.planar.static import static_mechanism
from symcable.linalg.sxlu import BlockLU, block_lu_check, block_matching, block_plan
from symcable.api.planar_time import ga_residual_function

from conftest import OC3, seed001

# Relative solve errors below are bounded by (growth factor) x (condition) x eps; the
# matrices here have condition <= 1e6 and growth <= 1e4, so 1e-8 leaves a wide margin
# while a wrong elimination (a missed fill entry, a wrong order) gives O(1) errors.
REL = 1e-8


def _solve(lu: BlockLU, A: ca.DM, B: np.ndarray) -> np.ndarray:
    f = lu.factor(A.nonzeros())
    return np.array(lu.solve_function(B.shape[1])(f, B).full())


def _banded(n, lower, upper, rng, dense_rows=0):
    A = np.zeros((n, n))
    for k in range(-lower, upper + 1):
        A += np.diag(rng.standard_normal(n - abs(k)), k)
    A += np.diag(np.full(n, 4.0 * (lower + upper + 1)))  # dominant diagonal: no pivoting needed
    if dense_rows:
        A[-dense_rows:, :] = rng.standard_normal((dense_rows, n))
        A[-dense_rows:, -dense_rows:] += 10.0 * n * np.eye(dense_rows)
    return A


@pytest.mark.parametrize("block", [1, 2])
@pytest.mark.parametrize("dense_rows", [0, 2])
def test_banded_with_dense_rows_matches_numpy(block, dense_rows):
    rng = np.random.default_rng(3)
    A = _banded(40, 3, 5, rng, dense_rows)
    Ad = ca.DM(ca.sparsify(ca.DM(A)))
    lu = BlockLU(Ad.sparsity(), block)
    B = rng.standard_normal((40, 3))
    X = _solve(lu, Ad, B)
    ref = np.linalg.solve(A, B)
    assert np.max(np.abs(X - ref)) <= REL * np.max(np.abs(ref))


def test_static_jacobian_needs_and_gets_a_matched_block_order():
    d = copy.deepcopy(OC3)
    d["sections"][0]["segments"] = 12
    model = sc.build_model(sc.load_scene(d))
    J = functions(static_mechanism(model)).static_jacobian(
        next(iter(model.initial_guess())).w, model.p_target)[1]
    plan = block_plan(J.sparsity())
    # node balances do not involve node positions: the natural diagonal blocks are singular,
    # and the order pairs each balance with a segment, each compatibility with a node
    assert plan is not None and plan[0] == 2 and plan[1] is not None
    assert sorted(plan[1].tolist()) == list(range(J.size1() // 2))
    assert plan[1].tolist() != list(range(J.size1() // 2))
    check = block_lu_check(J, *plan)
    assert check["growth"] < 1e5 and check["max_pivot_condition"] < 1e5
    lu = BlockLU(J.sparsity(), *plan)
    b = np.random.default_rng(0).standard_normal((J.size1(), 1))
    x, ref = _solve(lu, J, b), np.linalg.solve(np.array(J.full()), b)
    assert np.max(np.abs(x - ref)) <= REL * np.max(np.abs(ref))


def test_order_depends_on_the_pattern_alone():
    a, b = copy.deepcopy(OC3), copy.deepcopy(OC3)
    b["end_b"]["position"] = [-10.0, -60.0]
    plans = []
    for d in (a, b):
        model = sc.build_model(sc.load_scene(d))
        J = functions(static_mechanism(model)).static_jacobian(
            next(iter(model.initial_guess())).w, model.p_target)[1]
        plans.append(block_plan(J.sparsity()))
    assert plans[0][0] == plans[1][0] and np.array_equal(plans[0][1], plans[1][1])


def test_generalized_alpha_matrix_keeps_its_natural_order():
    d = seed001()
    d["sections"][0]["segments"] = 10
    model = sc.build_dynamic_model(sc.load_scene(d))
    n = model.n_y
    J = ga_residual_function(model, 0.5)(np.zeros(n), np.zeros(n), np.zeros(n), 0.0, 0.5, model.p_value)[1]
    block, order = block_plan(J.sparsity())
    assert order is None  # alpha_m I on the diagonal: every pivot block regular
    check = block_lu_check(J, block)
    assert check["growth"] <= 10.0
    b = np.ones((n, 1))
    x, ref = _solve(BlockLU(J.sparsity(), block), J, b), np.linalg.solve(np.array(J.full()), b)
    assert np.max(np.abs(x - ref)) <= REL * np.max(np.abs(ref))


def test_structurally_singular_pattern_is_refused():
    sp = ca.Sparsity.triplet(3, 3, [0, 1, 2], [1, 0, 2])              # a permutation: regular
    sp_sing = ca.Sparsity.triplet(3, 3, [0, 1, 2], [0, 0, 2])      # column 1 empty
    assert block_plan(sp_sing) is None
    assert block_matching(sp_sing, 1) is None
    with pytest.raises(ValueError, match="structurally zero"):
        BlockLU(sp_sing, 1)
    with pytest.raises(ValueError, match="block = 2 must be 1 or 2 and divide"):
        BlockLU(ca.Sparsity.dense(3, 3), 2)
    block, order = block_plan(sp)
    assert block == 1 and order.tolist() == [1, 0, 2]
    lu = BlockLU(sp, 1, order)
    x = np.array(lu.solve_function()(lu.factor([2.0, 4.0, 8.0]), [1.0, 2.0, 3.0]).full())
    np.testing.assert_allclose(x.ravel(), [1.0, 0.25, 0.375], rtol=1e-15)  # A = [[0,4,0],[2,0,0],[0,0,8]]


def test_matching_finds_an_order_exactly_when_one_exists():
    # against brute force over all row permutations of random 6 x 6 patterns
    import itertools
    rng = np.random.default_rng(0)
    found = 0
    for _ in range(200):
        M = rng.random((6, 6)) < 0.3
        sp = ca.Sparsity.triplet(6, 6, *[[int(i) for i in v] for v in np.nonzero(M)])
        order = block_matching(sp, 1)
        exists = any(all(M[q[j], j] for j in range(6)) for q in itertools.permutations(range(6)))
        assert (order is not None) == exists
        if order is not None:
            assert sorted(order.tolist()) == list(range(6)) and all(M[order[j], j] for j in range(6))
            found += 1
    assert 10 <= found <= 190  # both outcomes exercised
