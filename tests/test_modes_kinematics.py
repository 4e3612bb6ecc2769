"""Natural modes of mechanisms with kinematics q' = G v + w(q, t): the symmetric problem
(K G, M) where H = dw/dq = 0 and K G is symmetric, the state matrix otherwise; both against
closed forms and against each other, and the low modes of a stiff line to round-off."""
from __future__ import annotations

import casadi as ca
import numpy as np
import pytest

import symcable as sc
from symcable.errors import SymcableError
from symcable.mechanism.mechanism import Layout, Mechanism, ParamBlocks, Scales, Start
from symcable.models.planar.mechanism import mechanism_of
from symcable.results.generic import Equilibrium
from symcable.solvers.linearize import mechanism_modes

from conftest import seed001

S = np.array([[300.0, -100.0, 0.0], [-100.0, 200.0, -50.0], [0.0, -50.0, 80.0]])  # N/m
G = np.array([[2.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 0.5, 3.0]])                 # q' = G v
MASS = np.diag([1.0, 2.0, 0.5])                                                    # kg


def _kinematic_toy(beta: float = 0.0) -> Mechanism:
    """Potential V = q^T S q / 2 in coordinates q with q' = G v - beta q: the generalized
    force on v is -G^T S q (virtual work), so K G = G^T S G, symmetric. With beta = 0 the
    frequencies are those of (G^T S G, M)."""
    q, v = ca.SX.sym("q", 3), ca.SX.sym("v", 3)
    z, t = ca.SX.sym("z", 0), ca.SX.sym("t")
    params = ParamBlocks(("beta",), (1,), np.array([beta]))
    p = ca.SX.sym("p", 1)
    force = -ca.mtimes(ca.DM(G.T @ S), q)
    return Mechanism(name="kinematic_toy", q=q, v=v, z=z, t=t, p=p, params=params,
                     mass=ca.SX(ca.DM(MASS)), force=force, constraint=ca.SX.zeros(0, 1),
                     scales=Scales(q=np.ones(3), v=np.ones(3), z=np.zeros(0), force=100.0),
                     starts=lambda: iter([Start(np.zeros(3), np.zeros(0), params.values, "rest")]),
                     layout=Layout(1), kinematics=ca.mtimes(ca.DM(G), v) - p[0] * q)


def _rest(mech: Mechanism, p=None) -> Equilibrium:
    p = mech.params.values if p is None else np.asarray(p, dtype=float)
    return Equilibrium(mech.name, np.zeros(mech.n_q), np.zeros(0), p, {}, "converged")


def test_symmetric_problem_with_kinematics_against_closed_form():
    """H = 0: the frequencies are sqrt(eig(G^T S G, M)) / 2 pi to 1e-12, and the shapes in q
    are G times those in the velocity coordinates (q = G u)."""
    mech = _kinematic_toy()
    modes = mechanism_modes(mech, _rest(mech))
    Li = np.diag(1 / np.sqrt(np.diag(MASS)))
    expected = np.sqrt(np.linalg.eigvalsh(Li @ G.T @ S @ G @ Li)) / (2 * np.pi)
    assert modes.stats["method"] == "symmetric (K G, M)"
    np.testing.assert_allclose(modes.frequencies, expected, rtol=1e-12)
    np.testing.assert_allclose(modes.shapes, modes.velocity_shapes @ G.T, atol=1e-14)
    np.testing.assert_allclose(np.max(np.abs(modes.shapes), axis=1), 1.0)
    assert np.all(modes.real_parts == 0.0)
    # each shape solves (G^T S G - omega^2 M) u = 0
    for f, u in zip(modes.frequencies, modes.velocity_shapes):
        r = (G.T @ S @ G - (2 * np.pi * f) ** 2 * MASS) @ u
        assert np.linalg.norm(r) < 1e-10 * np.linalg.norm(G.T @ S @ G @ u)


def test_state_matrix_when_the_kinematics_depend_on_q():
    """H = -beta I != 0: the state matrix [[H, G], [-M^-1 K, 0]] is solved; its eigenvalues
    with a positive imaginary part are those numpy finds for the same matrix written here,
    with their real parts, and the result says that the model is not conservative."""
    beta = 0.3
    mech = _kinematic_toy(beta)
    modes = mechanism_modes(mech, _rest(mech))
    A = np.block([[-beta * np.eye(3), G], [-np.linalg.solve(MASS, G.T @ S), np.zeros((3, 3))]])
    ev = np.linalg.eigvals(A)
    ev = ev[ev.imag > 0]
    ev = ev[np.argsort(ev.imag)]
    assert modes.stats["method"] == "state matrix"
    np.testing.assert_allclose(modes.frequencies, ev.imag / (2 * np.pi), rtol=1e-12)
    np.testing.assert_allclose(modes.real_parts, ev.real, rtol=1e-10)
    assert any("not conservative" in w for w in modes.warnings)


def test_planar_line_both_routes_agree():
    """The seed-001 line's dynamics Mechanism: with its closure stabilisation on (H != 0,
    the state matrix) and off (the symmetric problem) the oscillating modes are the same
    (1e-12: the stabilisation only damps the closure invariant), and so are the shapes."""
    model = sc.build_dynamic_model(sc.load_scene(seed001()))
    mech = mechanism_of(model)
    p_off = np.array(model.p_undamped)
    p_on = np.array(p_off)
    p_on[model.p_slices["beta"]] = model.p_periodic[model.p_slices["beta"]]
    assert np.all(p_on[model.p_slices["beta"]] > 0)
    off = mechanism_modes(mech, _rest(mech, p_off), 6)
    on = mechanism_modes(mech, _rest(mech, p_on), 6)
    assert (off.stats["method"], on.stats["method"]) == ("symmetric (K G, M)", "state matrix")
    np.testing.assert_allclose(on.frequencies, off.frequencies, rtol=1e-12)
    np.testing.assert_allclose(np.abs(np.sum(on.velocity_shapes * off.velocity_shapes, axis=1))
                               / np.linalg.norm(on.velocity_shapes, axis=1)
                               / np.linalg.norm(off.velocity_shapes, axis=1), 1.0, atol=1e-10)
    # the two closure invariants are zero eigenvalues of the state matrix
    assert off.stats["zero_eigenvalues"] == mech.n_q - mech.n_v == 2


def test_stiff_line_low_modes_to_round_off():
    """A hanging chain with EA = 1e9 N over 0.1 m segments: omega_max / omega_min ~ 4e5, so a
    symmetric eigensolver on K G alone would give the lowest frequency to only ~2e-7
    (eps (omega_max / omega_min)^2); modal_analysis gives the undamped state matrix's
    frequencies (sc.linearize, another route) to 1e-11."""
    L, g = 10.0, 9.80665
    d = {"name": "hanging chain", "environment": {"water_density": 0.0, "gravity": g},
         "line_types": {"c": {"EA": 1e9, "mass": 2.0, "diameter": 0.01, "weight": 2.0 * g}},
         "sections": [{"type": "c", "length": L, "segments": 100}],
         "end_a": {"condition": "pinned", "position": [0.0, 0.0]},
         "end_b": {"condition": "free", "force": [0.0, 0.0]}}
    modes = sc.modal_analysis(d, 5)
    ev = np.linalg.eigvals(sc.linearize(d, undamped=True).state_matrix())
    omega = np.sort(ev.imag[ev.imag > 1e-9])[:5]
    np.testing.assert_allclose(modes.frequencies, omega / (2 * np.pi), rtol=1e-11)


def test_refusals_and_fewer_modes():
    """An eigenproblem above max_dense (here the symmetric one, of the toy's 3 free
    velocities) names the limit; asking for more modes than exist returns them all with a
    warning; an unstable equilibrium (negative stiffness) is refused."""
    mech = _kinematic_toy()
    with pytest.raises(SymcableError, match="max_dense = 2"):
        mechanism_modes(mech, _rest(mech), max_dense=2)
    with pytest.raises(SymcableError, match="n_modes"):
        mechanism_modes(mech, _rest(mech), 0)
    modes = mechanism_modes(mech, _rest(mech), 10)
    assert modes.frequencies.size == 3 and "only 3" in modes.warnings[0]
    chain = sc.toys.spring_chain(3, stiffness=100.0, rest_length=2.0, span=6.0)  # compressed
    eq = sc.solve_equilibrium(chain, require_stable=False)
    with pytest.raises(SymcableError, match="unstable"):
        mechanism_modes(chain, eq)
