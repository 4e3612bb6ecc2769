"""The Mechanism's element form (symcable/mechanism/element_form.py) and the step built from it
(symcable/solvers/element_jacobian.py): the cable3d line's momentum rows as element kernels
plus a rest reproduce the Mechanism's own, the step's residual and iteration matrix from the
elements' loop equal the written-out ones, a run takes the same steps either way, and a
Mechanism whose force no longer matches its form is not stepped by it."""
from __future__ import annotations

import dataclasses
import warnings

import casadi as ca
import numpy as np
import pytest

from symcable.models.cable3d.line import build_cable3d
from symcable.mechanism.element_form import split_mismatch
from symcable.scene import load_scene
from symcable.solvers import galpha1 as ga
from symcable.solvers.equilibrium import solve_equilibrium
from symcable.solvers.integrate import integrate
from symcable.solvers.options import GeneralizedAlphaFirstOrder


def _scene(segments=12, **over):
    d = {"model": "cable3d", "environment": {"depth": 60.0, "current": [0.3, 0.1, 0.0]},
         "seabed": {"stiffness": 1e5, "damping": 1e3, "friction_axial": 0.5,
                    "friction_lateral": 0.8, "friction_velocity": 0.05},
         "line_types": {"c": {"mass": 80.0, "diameter": 0.1, "EA": 5e8, "cd_normal": 1.2,
                              "cd_tangential": 0.3, "ca_normal": 1.0, "ca_tangential": 0.2,
                              "damping": -0.5}},
         "sections": [{"type": "c", "length": 120.0, "segments": segments}],
         "end_a": {"condition": "pinned", "position": [0.0, 0.0, -60.0]},
         "end_b": {"condition": "pinned", "position": [95.0, 20.0, 0.0],
                   "motion": {"kind": "harmonic", "period": 9.0,
                              "amplitude": [1.0, 0.5, 1.5]}}}
    for k, v in over.items():
        d[k] = v
    return d


VARIANTS = {
    "lumped": {},
    "consistent": {"mass_matrix": "consistent"},
    "bending": {"line_types": {"c": {"mass": 80.0, "diameter": 0.1, "EA": 5e8, "EI": 2e4,
                                     "cd_normal": 1.2, "ca_normal": 1.0}}},
    "bristle": {"seabed": {"stiffness": 1e5, "friction_axial": 0.5, "friction_lateral": 0.8,
                           "friction_law": "bristle"}},
    "in air": {"environment": {"depth": 60.0, "water_density": 0.0}},
    # end B free under a force, drag by seed 003's loading functions (per-element constants)
    "free end, loading functions": {
        "line_types": {"c": {"mass": 80.0, "diameter": 0.1, "EA": 5e8, "ca_normal": 1.0,
                             "drag_law": "loading-functions",
                             "loading": {"cd": 1.2, "normal_cos": [0.5, 0.0, -0.5],
                                         "tangential_sin": [0.02]}}},
        "end_b": {"condition": "free", "force": [2e3, 0.0, 1e3]}},
    # end B towed (its motion a path in t, its acceleration into the consistent mass)
    "tow, consistent": {"mass_matrix": "consistent",
                        "end_b": {"condition": "pinned", "position": [95.0, 20.0, 0.0],
                                  "motion": {"kind": "tow", "speed": 1.5, "heading": 30.0}}},
}


@pytest.mark.parametrize("variant", list(VARIANTS))
def test_split_reproduces_the_residual(variant):
    """M v' - f of the Mechanism and of its element form at random states: equal to
    round-off (1e-12 of the force scale; the sums are the same terms in another order)."""
    mech = build_cable3d(load_scene(_scene(**VARIANTS[variant])))
    assert mech.elements is not None
    assert split_mismatch(mech, mech.elements, points=3, seed=4) < 1e-12


def test_no_form_with_a_current_profile():
    """A depth profile of current makes an element's water speed depend on its depth: no
    form (the step writes its matrix out)."""
    env = {"depth": 60.0, "current_profile": [[-60.0, 0.1, 0.0, 0.0], [0.0, 0.5, 0.0, 0.0]]}
    assert build_cable3d(load_scene(_scene(environment=env))).elements is None


@pytest.mark.parametrize("variant", ["lumped", "consistent", "bristle",
                                     "free end, loading functions", "tow, consistent"])
def test_step_residual_and_matrix_equal_the_written_out_ones(variant):
    """The step's residual and iteration matrix from the elements' loop against the SX
    ones at random steps (states moved off the start by 1 % of their scales, random rates):
    to 1e-12 of their largest entry (round-off), every entry of the SX pattern covered."""
    mech = build_cable3d(load_scene(_scene(**VARIANTS[variant])))
    ny = mech.n_q + mech.n_v
    x, t, h, p, st, _ = ga._symbols(mech, ca.SX)
    w = ca.SX.sym("w", ny)
    args = [w, x, t, h, p, st]
    R, (sp, jac, _) = ga._element_loops(mech, args, ny, False)
    r = ga._step_residual(ga._sx_residual(mech), w, x, t, h, p, st[0], ny)
    J = ga._jacobian(r, w)
    sx = ca.Function("sx", args, [r, J])
    rng = np.random.default_rng(7)
    q0 = next(iter(mech.starts())).q
    for _ in range(3):
        y = np.concatenate([q0 + 0.01 * mech.scales.q * rng.standard_normal(mech.n_q),
                            0.1 * mech.scales.v * rng.standard_normal(mech.n_v)])
        a = (0.1 * rng.standard_normal(ny), np.concatenate([y, 0.1 * rng.standard_normal(ny)]),
             float(rng.uniform(0, 20)), 0.1, mech.params.values, [0.3, 1e-8])
        r_sx, J_sx = (np.asarray(ca.DM(v).full()) for v in sx(*a))
        r_el = np.asarray(R(*a)).ravel()
        J_el = np.asarray(ca.DM(sp, jac(*a)).full())
        assert np.max(np.abs(r_el - r_sx.ravel())) <= 1e-12 * np.max(np.abs(r_sx))
        assert np.max(np.abs(J_el - J_sx)) <= 1e-12 * np.max(np.abs(J_sx))
    missing = np.setdiff1d(np.flatnonzero(np.asarray(ca.DM(J.sparsity(), 1).full()).ravel()),
                           np.flatnonzero(np.asarray(ca.DM(sp, 1).full()).ravel()))
    assert missing.size == 0


def test_a_run_takes_the_same_steps_either_way(monkeypatch):
    """First-order generalized-alpha on a 40-segment line (234 states, above
    ELEMENT_MIN_STATES) stepped with the elements' matrix and with the written-out one: the
    same Newton iterations, and states that agree to Newton's tolerance (1e-8 of the
    scales; 1e-6 m on positions whose scale is 12 m)."""
    scene = load_scene(_scene(segments=40))
    out = {}
    for by_elements in (True, False):
        monkeypatch.setattr(ga, "ELEMENT_MATRIX", by_elements)
        mech = build_cable3d(scene)
        assert mech.n_q + mech.n_v >= ga.ELEMENT_MIN_STATES
        eq = solve_equilibrium(mech)
        tr = integrate(mech, 9.0, 0.25, start=eq, p=mech.params.values, codegen=False,
                       method=GeneralizedAlphaFirstOrder(tol=1e-8), progress=False)
        assert tr.status == "converged"
        out[by_elements] = tr
    a, b = out[True], out[False]
    assert a.stats["newton_iterations"] == b.stats["newton_iterations"]
    assert np.max(np.abs(a.q - b.q)) < 1e-6


def test_a_stale_form_is_not_used():
    """A Mechanism rebuilt with another force that kept its form: the step sees the split
    no longer reproduces the residual, says so, and writes its matrix out."""
    mech = build_cable3d(load_scene(_scene()))
    stale = dataclasses.replace(mech, force=2.0 * mech.force)
    ny = mech.n_q + mech.n_v
    x, t, h, p, st, _ = ga._symbols(mech, ca.SX)
    args = [ca.SX.sym("w", ny), x, t, h, p, st]
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        assert ga._element_parts(stale, args, ny) is None
    assert any("element form" in str(c.message) for c in caught)
    assert ga._element_parts(mech, args, ny) is not None


def test_the_compiled_step_equals_the_virtual_machine():
    """The element-loop step in generated C (loops, maps, index gathers) against the same
    step in CasADi's virtual machine, three steps of 0.25 s on the 40-segment line: the
    same iterations and states to 1e-10 of their scales (round-off through Newton's
    iterations; the same graph evaluated in another order)."""
    from symcable.mechanism.codegen import use_codegen
    from symcable.solvers.galpha1 import galpha1_kernel
    if not use_codegen(True):
        pytest.fail("no C compiler on this machine: CI installs one")
    mech = build_cable3d(load_scene(_scene(segments=40)))
    opts = GeneralizedAlphaFirstOrder(tol=1e-8)
    assert ga.solver_choice(mech, True) == (False, True)
    vm = galpha1_kernel(mech, opts, codegen=False)
    c = galpha1_kernel(mech, opts, codegen=True)
    assert c.is_a("External") and not vm.is_a("External")
    _same_steps(mech, opts, vm, c)


def _same_steps(mech, opts, vm, other):
    """Three steps of 0.25 s from the static state by the step Functions ``vm`` and
    ``other``: no failure, the same iterations, states equal to 1e-10 of their scales."""
    from symcable.solvers.galpha1 import step_scales
    eq = solve_equilibrium(mech)
    ny = mech.n_q + mech.n_v
    x = np.concatenate([eq.q, np.zeros(mech.n_v), np.zeros(ny)])
    consts = ([opts.rho_inf, opts.tol], step_scales(mech))
    scale = np.concatenate([mech.scales.q, mech.scales.v])
    for k in range(3):
        outs = [f(x, 0.25 * k, 0.25, mech.params.values, *consts) for f in (vm, other)]
        (x_vm, _, _, it_vm, fail_vm), (x_o, _, _, it_o, fail_o) = (
            [np.asarray(ca.DM(o)).ravel() for o in out] for out in outs)
        assert fail_vm[0] == fail_o[0] == 0 and it_vm[0] == it_o[0]
        assert np.max(np.abs(x_vm[:ny] - x_o[:ny]) / scale) < 1e-10
        x = x_vm


@pytest.mark.parametrize("variant", ["lumped", "bending", "bristle",
                                     "free end, loading functions"])
def test_a_step_too_large_to_compile_calls_its_kernels_in_c(monkeypatch, variant):
    """A step whose graph is too large to compile whole (here: DEFAULT_MAX_SIZE lowered
    below the 40-segment line's) runs its loops in the virtual machine, calling the element
    and banded LU kernels' generated C: the same iterations and states as the virtual
    machine's step to 1e-10 of their scales (the same arithmetic in another order), for
    each kind of element kernel (drag laws, bending, a bristle's states)."""
    from symcable.mechanism import codegen
    from symcable.solvers.galpha1 import galpha1_kernel
    monkeypatch.delenv("SYMCABLE_CODEGEN", raising=False)
    if not codegen.use_codegen(True):
        pytest.fail("no C compiler on this machine: CI installs one")
    monkeypatch.setattr(codegen, "DEFAULT_MAX_SIZE", 1000)
    mech = build_cable3d(load_scene(_scene(segments=40, **VARIANTS[variant])))
    opts = GeneralizedAlphaFirstOrder(tol=1e-8)
    vm = galpha1_kernel(mech, opts, codegen=False)
    mixed = galpha1_kernel(mech, opts, codegen=None)
    assert not mixed.is_a("External") and mixed is not vm
    called = {f.name(): f for f in mixed.find_functions()}
    assert sum(f.is_a("External") for f in called.values()) >= 4  # 2 element, 3 band kernels
    _same_steps(mech, opts, vm, mixed)
    if variant == "lumped":  # what a run says of its step
        eq = solve_equilibrium(mech)
        tr = integrate(mech, 0.5, 0.25, start=eq, p=mech.params.values, codegen=None,
                       method=opts, progress=False)
        assert tr.stats["compiled_kernels"] and not tr.stats["compiled"]
