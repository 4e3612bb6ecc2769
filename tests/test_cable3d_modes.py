"""Natural modes of the cable3d line from the generic modal analysis (issue 12, first step):
a weightless string stretched in air between two points on a diagonal of the x-y plane.
With lumped masses its modes are those of a chain of equal masses in closed form: in each
of the two transverse planes omega_j = 2 sqrt(T / (m ds l)) sin(j pi / 2N) (T the tension,
l the stretched segment length: the tangent stiffness T / l across the element), and
axially the same with EA / ds for T / l. The 3D mass matrix (lumped), the exact tangent
stiffness (EA/L0) t t^T + (T/l)(I - t t^T) and the generic eigen-solve must give them to
round-off, whatever the line's direction."""
from __future__ import annotations

import math

import numpy as np
import pytest

from symcable.api.cable3d_static import cable3d_mechanism
from symcable.scene import load_scene
from symcable.solvers.equilibrium import solve_equilibrium
from symcable.solvers.linearize import mechanism_modes


def test_stretched_string_modes_in_closed_form():
    N, L, m, EA, stretch = 20, 10.0, 1.0, 1e6, 0.01
    reach = L * (1 + stretch)
    d = {"model": "cable3d", "environment": {"water_density": 0.0},
         "line_types": {"s": {"mass": m, "diameter": 0.01, "EA": EA, "weight": 0.0}},
         "sections": [{"type": "s", "length": L, "segments": N}],
         "end_a": {"condition": "pinned", "position": [0.0, 0.0, 0.0]},
         "end_b": {"condition": "pinned",
                   "position": [reach * 0.6, reach * 0.48, reach * 0.64]}}
    mech = cable3d_mechanism(load_scene(d))
    eq = solve_equilibrium(mech)
    modes = mechanism_modes(mech, eq)
    f = np.sort(modes.frequencies)
    ds, T = L / N, EA * stretch
    j = np.arange(1, N)
    shape = 2 * np.sin(j * math.pi / (2 * N)) / (2 * math.pi)
    f_tr = shape * math.sqrt(T / (m * ds * ds * (1 + stretch)))
    f_ax = shape * math.sqrt(EA / (m * ds * ds))
    ref = np.sort(np.concatenate([f_tr, f_tr, f_ax]))
    assert f.size == ref.size == 3 * (N - 1)
    np.testing.assert_allclose(f, ref, rtol=1e-10)
    # and the continuum string, to the discretisation (second order: (pi / 2N)^2 / 6)
    f1 = math.sqrt(T / (m / (1 + stretch))) / (2 * reach)
    assert abs(f[0] - f1) / f1 < (math.pi / (2 * N)) ** 2 / 6 * 1.1


def test_material_damping_as_moordyn_zeta():
    """A line type's negative ``damping`` is minus the damping ratio zeta of the line's
    highest axial mode (adjacent nodes in opposition), as MoorDyn's BA/-zeta: BA = zeta ds
    sqrt(EA m). Kelvin-Voigt damping is stiffness-proportional, so the axial mode j of the
    lumped chain has zeta_j = zeta sin(j pi / 2N) (its frequency over that of the ideal
    opposition mode): the generic modal analysis with damping gives exactly that (1e-6)."""
    N, L, zeta = 12, 10.0, 0.3
    d = {"model": "cable3d", "environment": {"water_density": 0.0},
         "line_types": {"s": {"mass": 1.0, "diameter": 0.01, "EA": 1e6, "weight": 0.0,
                              "damping": -zeta}},
         "sections": [{"type": "s", "length": L, "segments": N}],
         "end_a": {"condition": "pinned", "position": [0.0, 0.0, 0.0]},
         "end_b": {"condition": "pinned", "position": [L * 1.01, 0.0, 0.0]}}
    mech = cable3d_mechanism(load_scene(d))
    modes = mechanism_modes(mech, solve_equilibrium(mech), damped=True)
    order = np.argsort(modes.frequencies)
    axial = np.asarray(modes.damping_ratios)[order][-(N - 1):]  # the stiff axial modes
    j = np.arange(1, N)
    np.testing.assert_allclose(axial, zeta * np.sin(j * math.pi / (2 * N)), rtol=1e-6)


def test_consistent_mass_string_modes_in_closed_form():
    """mass_matrix = "consistent" (seed 003: m ds / 6 [[2, 1], [1, 2]] per element): the
    linear-element string's modes in closed form, omega_j^2 = 6 k (1 - cos th) / (m ds
    (2 + cos th)), th = j pi / N, k = T / l transversally and EA / ds axially (to 1e-10:
    the assembly is exact); the fundamental is as far above the continuum (+(pi/N)^2/24) as
    the lumped one is below it (measured -0.103 % and +0.103 % at N = 20)."""
    N, L, m, EA, stretch = 20, 10.0, 1.0, 1e6, 0.01
    reach = L * (1 + stretch)
    d = {"model": "cable3d", "environment": {"water_density": 0.0}, "mass_matrix": "consistent",
         "line_types": {"s": {"mass": m, "diameter": 0.01, "EA": EA, "weight": 0.0}},
         "sections": [{"type": "s", "length": L, "segments": N}],
         "end_a": {"condition": "pinned", "position": [0.0, 0.0, 0.0]},
         "end_b": {"condition": "pinned", "position": [reach * 0.6, reach * 0.48, reach * 0.64]}}
    mech = cable3d_mechanism(load_scene(d))
    f = np.sort(mechanism_modes(mech, solve_equilibrium(mech)).frequencies)
    ds, T = L / N, EA * stretch
    th = np.arange(1, N) * math.pi / N
    shape = np.sqrt(6 * (1 - np.cos(th)) / (2 + np.cos(th))) / (2 * math.pi)
    f_tr = shape * math.sqrt(T / (m * ds * ds * (1 + stretch)))
    f_ax = shape * math.sqrt(EA / (m * ds * ds))
    np.testing.assert_allclose(f, np.sort(np.concatenate([f_tr, f_tr, f_ax])), rtol=1e-10)
    f1 = math.sqrt(T / (m / (1 + stretch))) / (2 * reach)
    assert 0 < (f[0] - f1) / f1 < (math.pi / N) ** 2 / 24 * 1.1


def test_hanging_chain_against_bessel():
    """A chain hanging in air from a pin, its lower end free, hung off the vertical axis
    (Bernoulli/Euler): omega_k = (j_0,k / 2) sqrt(g / L), j_0,k the zeros of J_0
    (Abramowitz & Stegun table 9.5), each twice (the two horizontal directions swing alike;
    the axial modes are far above at EA = 1e9 N). The vanishing tension at the free end
    slows the lumped-mass convergence: at 100 segments the planar model's modes 1-3 are
    within 0.5 % (tests/test_modal.py); the 3D line's the same (measured -0.003, -0.04,
    -0.15 %), through sc.modal_analysis, whose shapes swing horizontally only."""
    import symcable as sc
    L, g = 10.0, 9.80665
    top = [3.0, -2.0, 5.0]
    d = {"model": "cable3d", "environment": {"water_density": 0.0, "gravity": g},
         "line_types": {"c": {"EA": 1e9, "mass": 2.0, "diameter": 0.01, "weight": 2.0 * g}},
         "sections": [{"type": "c", "length": L, "segments": 100}],
         "end_a": {"condition": "pinned", "position": top},
         "end_b": {"condition": "free", "force": [0.0, 0.0, 0.0]}}
    res = sc.modal_analysis(d, n_modes=6)
    j0 = np.array([2.404825557695773, 5.520078110286311, 8.653727912911013])
    ref = np.repeat(j0 / 2 * np.sqrt(g / L) / (2 * math.pi), 2)
    np.testing.assert_allclose(res.frequencies, ref, rtol=5e-3)
    shapes = np.asarray(res.shapes)  # (mode, node, 3)
    assert np.max(np.abs(shapes[..., 2])) < 1e-6 * np.max(np.abs(shapes))


def test_sparse_eigensolver_equals_the_dense_one():
    """Above max_dense a symmetric problem's lowest modes come from sparse shift-invert
    Lanczos: on a chain sagging in air between two pins (100 segments, 297 free velocities,
    in-plane and out-of-plane modes apart) forced onto it (max_dense = 100), its 6
    frequencies equal the dense solver's to 1e-7 relative and its shapes to 1e-6 of their
    peak (measured 1.1e-8 to 5e-8 and 4e-8: the two solvers' round-off on a stiff line, EA =
    1e9 N, whose axial modes are 1e4 times higher, so eigenvalues 1e8 apart and the lowest
    known to about 1e8 eps; it moves with the order of the stiffness's operations, e.g. the
    line's numbers as parameters); asked for half the modes or more it refuses in one
    line."""
    import symcable as sc
    g = 9.80665
    d = {"model": "cable3d", "environment": {"water_density": 0.0, "gravity": g},
         "line_types": {"c": {"EA": 1e9, "mass": 2.0, "diameter": 0.01, "weight": 2.0 * g}},
         "sections": [{"type": "c", "length": 10.0, "segments": 100}],
         "end_a": {"condition": "pinned", "position": [0.0, 0.0, 0.0]},
         "end_b": {"condition": "pinned", "position": [8.0, 0.0, -2.0]}}
    dense = sc.modal_analysis(d, n_modes=6)
    sparse = sc.modal_analysis(d, n_modes=6, max_dense=100)
    assert "sparse" in sparse.stats["method"] and "sparse" not in dense.stats["method"]
    np.testing.assert_allclose(sparse.frequencies, dense.frequencies, rtol=1e-7)
    f = np.asarray(dense.frequencies)
    assert np.all(np.diff(f) > 1e-3 * f[1:])  # simple frequencies: shapes comparable
    for a, b in zip(np.asarray(sparse.shapes), np.asarray(dense.shapes)):
        s = np.sign(np.vdot(a, b))
        assert np.max(np.abs(a - s * b)) < 1e-6 * np.max(np.abs(b))
    with pytest.raises(sc.SymcableError, match="max_dense = 100"):
        sc.modal_analysis(d, n_modes=200, max_dense=100)
