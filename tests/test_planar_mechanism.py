"""The planar linearised dynamics as a Mechanism (symcable.models.planar.mechanism) against
the DynamicModel it re-expresses, and the first-order generalized-alpha that runs it.

Seed 001 at 10 segments (38 states) keeps every run to a second or two."""
from __future__ import annotations

import math

import casadi as ca
import numpy as np
import pytest

import symcable as sc
from symcable.mechanism.functions import functions
from symcable.errors import SymcableError
from symcable.mechanism.mechanism import Mechanism, ParamBlocks, Scales, Start
from symcable.models.planar.mechanism import dynamics_mechanism, state_permutation
from symcable.results.periodic_generic import MechanismPeriodic
from symcable.solvers.integrate import integrate
from symcable.solvers.options import (RK4, Collocation, GeneralizedAlpha,
                                      GeneralizedAlphaFirstOrder)
from symcable.solvers.periodic_mech import solve_periodic_mech

from conftest import seed001

SEGMENTS = 10
PERIOD = 10.0


@pytest.fixture(scope="module")
def planar():
    d = seed001()
    d["sections"][0]["segments"] = SEGMENTS
    scene = sc.load_scene(d)
    model = sc.build_dynamic_model(scene)
    return scene, model, dynamics_mechanism(model)


def test_layout(planar):
    """q = (e_j, phi_j) per segment, v = (u_i, v_i) per free node, M diagonal and positive,
    no constraints, kinematics given; one part "line"."""
    _, model, mech = planar
    iq, iv = state_permutation(model)
    kinds = np.asarray(model.info["kinds"])
    assert list(kinds[iq]) == ["e", "phi"] * SEGMENTS
    assert list(kinds[iv]) == ["u", "v"] * (SEGMENTS - 1)
    assert (mech.n_q, mech.n_v, mech.n_z) == (2 * SEGMENTS, 2 * (SEGMENTS - 1), 0)
    M = np.asarray(ca.DM(mech.mass))
    assert mech.mass.sparsity().nnz() == mech.n_v and np.all(np.diag(M) > 0)
    assert mech.kinematics is not None and set(mech.layout.parts) == {"line"}
    assert mech.outputs["fairlead_tension"].unit == "N"
    assert mech.outputs["angle"].unit == "rad"


def test_dae_residual_equals_the_dynamic_models(planar):
    """At random states, rates and times (ramp on and off), the Mechanism's DAE residual
    (q' - kinematics, M v' - f) equals the DynamicModel's y' - f(y, t; p) permuted to (q, v):
    the kinematic rows are the same SX nodes (exactly equal); the momentum rows are the model's
    times the lumped mass (f is the numerator of the model's row n / m), so M^-1 (M v' - f)
    differs from v' - n / m only by the rounding of (m v') / m: 1e-15 of the row's size.
    The model's f is its record's ``rhs`` expression, made a Function here."""
    _, model, mech = planar
    F = functions(mech)
    f = ca.Function("model_rhs", [model.y, model.t, model.p], [model.rhs])
    iq, iv = state_permutation(model)
    M = np.diag(np.asarray(ca.DM(mech.mass)))
    rng = np.random.default_rng(0)
    for t, p in ((0.3, model.p_value), (4.0, model.p_value), (17.0, model.p_periodic)):
        y, yd = (model.y_scale * rng.standard_normal(model.n_y) for _ in range(2))
        ref = yd - np.asarray(f(y, t, p)).ravel()
        R = np.asarray(F.dae_residual(np.r_[yd[iq], yd[iv]], np.r_[y[iq], y[iv]], t, p)).ravel()
        nq = mech.n_q
        assert np.array_equal(R[:nq], ref[iq])
        scale = np.abs(yd[iv]) + np.abs(ref[iv])
        assert np.all(np.abs(R[nq:] / M - ref[iv]) <= 1e-14 * scale)


def test_first_order_generalized_alpha_matches_simulate(planar):
    """Three periods from rest at T/100, rho_inf = 0.5: the same scheme (Jansen et al. 2000,
    same coefficients, same start y'0 = f(y0, 0)) on the same equations (M-scaled momentum
    rows) at the same times; only the Newton iterations differ (CasADi's rootfinder on the
    scaled step residual vs simulate's chord/Newton loop, both to 1e-10 of a step's change
    of the state). Measured 1.4e-10 of the tension range; 1e-8 asked."""
    scene, model, mech = planar
    dur, dt = 3 * PERIOD, PERIOD / 100
    ref = sc.simulate(scene, dur, dt, method="generalized-alpha", rho_inf=0.5, model=model)
    run = integrate(mech, dur, dt, method=GeneralizedAlphaFirstOrder(rho_inf=0.5))
    assert run.status == "converged"
    np.testing.assert_allclose(run.time, ref.time, rtol=0, atol=1e-12)
    T, T_ref = run.outputs["fairlead_tension"], np.asarray(ref.fairlead_tension)
    assert np.max(np.abs(T - T_ref)) < 1e-8 * np.ptp(T_ref)


def test_rk4_matches_simulate(planar):
    """RK4 is the same formula on the same rates (v' = M^-1 f: the model's rate up to the
    rounding of (m n) / m): 1e-10 of the tension range (measured 1.8e-15) over one period
    at T/400 (below simulate's RK4 stability limit on this line)."""
    scene, model, mech = planar
    dt = PERIOD / 400
    ref = sc.simulate(scene, PERIOD, dt, method="rk4", model=model)
    run = integrate(mech, PERIOD, dt, method=RK4())
    T, T_ref = run.outputs["fairlead_tension"], np.asarray(ref.fairlead_tension)
    assert np.all(np.isfinite(T_ref))
    assert np.max(np.abs(T - T_ref)) < 1e-10 * np.ptp(T_ref)


def test_arnold_bruels_refuses_kinematics(planar):
    """The second-order generalized-alpha needs q' = v: a one-line error naming the
    first-order scheme."""
    *_, mech = planar
    with pytest.raises(SymcableError, match="GeneralizedAlphaFirstOrder") as exc:
        integrate(mech, 1.0, 0.1, method=GeneralizedAlpha(rho_inf=0.5))
    assert "\n" not in str(exc.value)


def _toy(constrained=False):
    """A damped oscillator x'' = -w^2 x - 2 c w x' as a Mechanism (optionally with a
    trivial constraint z = 0)."""
    q, v, t, p = ca.SX.sym("q"), ca.SX.sym("v"), ca.SX.sym("t"), ca.SX.sym("p", 1)
    z = ca.SX.sym("z", 1 if constrained else 0)
    w, c = 2 * math.pi, 0.05
    force = -w ** 2 * q - 2 * c * w * v
    g = z if constrained else ca.SX.zeros(0, 1)
    return Mechanism(name="toy", q=q, v=v, z=z, t=t, p=p, params=ParamBlocks(("k",), (1,),
                     np.zeros(1)), mass=ca.SX(1.0), force=force, constraint=g,
                     scales=Scales(q=np.ones(1), v=np.full(1, w), z=np.ones(z.numel()),
                                   force=w ** 2),
                     starts=lambda: [Start(np.ones(1), np.zeros(z.numel()), np.zeros(1), "x")],
                     kinematics=1.0 * v)


def test_first_order_refuses_constraints():
    with pytest.raises(SymcableError, match="n_z = 0"):
        integrate(_toy(constrained=True), 1.0, 0.1, method=GeneralizedAlphaFirstOrder())


def test_error_estimate_tracks_the_local_error():
    """On the damped oscillator (one free period, 50 steps): at every step past the start-up
    (the carried y' settles on the principal root within a few steps, its spurious root
    being -0.2 per step at rho_inf = 0.5), the estimate is within a factor 2 of the true local
    error, the step from the run's own (y_n, y'_n) minus the exact solution through y_n
    (measured 0.96 to 1.05).
    The estimate's constant is the principal root's C = 1/9 (see galpha1_step)."""
    mech = _toy()
    opts = GeneralizedAlphaFirstOrder(rho_inf=0.5)
    from symcable.solvers.integrate import galpha1_step
    step = galpha1_step(mech, opts)
    w, c = 2 * math.pi, 0.05
    A = np.array([[0.0, 1.0], [-w ** 2, -2 * c * w]])
    lam, V = np.linalg.eig(A)

    def exact(y, h):
        return np.real(V @ np.diag(np.exp(lam * h)) @ np.linalg.solve(V, y))

    h = 1.0 / 50
    x = np.array([1.0, 0.0, 0.0, -w ** 2])
    sc_y = np.array([1.0, w])
    ratios = []
    for n in range(60):
        x1, err, lte = (np.asarray(a).ravel() for a in step(x, n * h, h, np.zeros(1)))
        true = np.max(np.abs(x1[:2] - exact(x[:2], h)) / sc_y)
        if n >= 10:
            ratios.append(float(lte[0]) / true)
        assert err[0] < 1e-9
        x = x1
    ratios = np.array(ratios)
    assert np.all((ratios > 0.5) & (ratios < 2.0)), (ratios.min(), ratios.max())


def test_collocation_agrees_with_solve_periodic(planar):
    """Collocation of the Mechanism (Radau IIA, 40 intervals of degree 3, the planar
    default) against ``solve_periodic(scene, "collocation")`` on the DynamicModel: the same
    equations discretised the same way (IPOPT to 1e-10 both), so 1e-3 of the tension range
    is loose: measured 4.6e-7 (each solved to its own tolerance from its own start). The
    start: periodic_mech's own start runs the second-order generalized-alpha, which refuses
    kinematics, so the start is 4 periods of the first-order scheme from rest (ramp on),
    its last period at T/100."""
    scene, model, mech = planar
    p = mech.params.with_values(ramp=0.0)
    steps = 100
    run = integrate(mech, 4 * PERIOD, PERIOD / steps, method=GeneralizedAlphaFirstOrder(0.5))
    last = slice(-steps - 1, -1)
    start = MechanismPeriodic(mech.name, PERIOD, run.time[last] - 3 * PERIOD, run.q[last],
                              run.v[last], run.z[last], p, {}, "time run", "converged", {}, ())
    sol = solve_periodic_mech(mech, PERIOD, Collocation(intervals=40, degree=3), p=p,
                              start=start)
    ref = sc.solve_periodic(scene, "collocation", model=model)
    T_ref = np.asarray(ref.fairlead_tension)
    t_ref = np.asarray(ref.time)
    T = np.interp(t_ref, np.r_[sol.time, PERIOD], np.r_[sol.outputs["fairlead_tension"],
                                                        sol.outputs["fairlead_tension"][:1]])
    # both at the same instants: the Mechanism's samples by trigonometric interpolation
    q, v, z = sol.at(t_ref)
    F = functions(mech)
    Tm = F.unpack(np.asarray(F.outputs.map(t_ref.size)(q.T, v.T, z.T, t_ref[None, :], p)))
    err = np.max(np.abs(Tm["fairlead_tension"] - T_ref)) / np.ptp(T_ref)
    assert err < 1e-3, err
    assert np.max(np.abs(T - T_ref)) / np.ptp(T_ref) < 1e-2  # linear interpolation only
