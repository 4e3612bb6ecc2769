"""The first-order generalized-alpha step (symcable.solvers.galpha1): the unrolled Newton
loop (chord iterations on a block LU in a fill-reducing order) and CasADi's rootfinder give
the same step, the rootfinder's derivative is the implicit-function one, and the integrator
reports what the planar simulate reported (samples, failures) on any Mechanism.

Seed 001 at 10 segments (38 states) and a damped oscillator keep it to seconds."""
from __future__ import annotations

import math

import casadi as ca
import numpy as np
import pytest

import symcable as sc
from symcable.errors import ConvergenceError, SymcableError
from symcable.mechanism.mechanism import Mechanism, ParamBlocks, Scales, Start
from symcable.models.planar.mechanism import mechanism_of
from symcable.solvers.galpha1 import galpha1_kernel, galpha1_residual, galpha1_step, step_scales
from symcable.solvers.integrate import integrate, start_rates
from symcable.solvers.options import RK4, GeneralizedAlphaFirstOrder

from conftest import seed001


@pytest.fixture(scope="module")
def planar():
    d = seed001()
    d["sections"][0]["segments"] = 10
    model = sc.build_dynamic_model(sc.load_scene(d))
    return model, mechanism_of(model)


def _moving_state(mech, p):
    """A state some way into a run from rest (1 s at dt = 0.05)."""
    run = integrate(mech, 1.0, 0.05, method=GeneralizedAlphaFirstOrder(), p=p)
    q, v = run.q[-1], run.v[-1]
    return np.concatenate([q, v, *start_rates(mech, q, v, 1.0, p)])


def test_unrolled_and_rootfinder_agree(planar):
    """The same scheme solved two ways: the accepted iterates agree to the Newton tolerance
    (both converge to 1e-10 of a step's change of the state; measured 1e-13 of the scales),
    and the unrolled loop's err is its accepted measure (<= tol)."""
    _, mech = planar
    p = mech.params.values
    x = _moving_state(mech, p)
    out = {}
    for newton in ("unrolled", "rootfinder"):
        step = galpha1_step(mech, GeneralizedAlphaFirstOrder(rho_inf=0.5, newton=newton))
        x1, err, lte = (np.asarray(a, dtype=float).ravel() for a in step(x, 1.0, 0.05, p))
        assert err[0] <= 1e-10 and np.isfinite(lte[0])
        out[newton] = x1
    ny = mech.n_q + mech.n_v
    scale = step_scales(mech)[:ny]
    assert np.max(np.abs(out["unrolled"][:ny] - out["rootfinder"][:ny]) / scale) < 1e-9


def test_rootfinder_derivative_is_the_implicit_one(planar):
    """d y1 / d x of the rootfinder step against central differences of the step (each
    difference solved to 1e-10, so a relative step 1e-5 leaves an error ~1e-5 of the
    derivative's scale): within 1e-4."""
    _, mech = planar
    p = mech.params.values
    x0 = _moving_state(mech, p)
    step = galpha1_step(mech, GeneralizedAlphaFirstOrder(rho_inf=0.5, tol=1e-12,
                                                         newton="rootfinder"))
    ny = mech.n_q + mech.n_v
    x = ca.MX.sym("x", x0.size)
    J = np.asarray(ca.Function("J", [x], [ca.jacobian(step(x, 1.0, 0.05, p)[0][:ny], x)])(x0))
    scale = np.concatenate([step_scales(mech)[:ny]] * 2) * np.r_[np.ones(ny), np.full(ny, 20.0)]
    rng = np.random.default_rng(0)
    for k in rng.choice(x0.size, 6, replace=False):
        e = np.zeros(x0.size)
        e[k] = 1e-5 * scale[k]
        yp = np.asarray(step(x0 + e, 1.0, 0.05, p)[0]).ravel()[:ny]
        ym = np.asarray(step(x0 - e, 1.0, 0.05, p)[0]).ravel()[:ny]
        fd = (yp - ym) / (2 * e[k])
        ref = np.max(np.abs(J[:, k])) + 1e-300
        assert np.max(np.abs(J[:, k] - fd)) < 1e-4 * ref, k


def test_iteration_matrix_solve_is_exact(planar):
    """The unrolled step solves the Newton system by the block LU in a fill-reducing order:
    one Newton iteration from a perturbed guess on the linear part lands where a dense solve
    of the same system does (the kernel's first correction), to 1e-10 relative."""
    _, mech = planar
    p = mech.params.values
    x0 = _moving_state(mech, p)
    ny = mech.n_q + mech.n_v
    R = galpha1_residual(mech)
    w0 = x0[ny:]
    F, J = R(w0, x0, 1.0, 0.05, p, [0.5, 0.0])
    dw = -np.linalg.solve(np.array(ca.DM(J).full()), np.asarray(F).ravel())
    kern = galpha1_kernel(mech, GeneralizedAlphaFirstOrder(rho_inf=0.5, max_iter=1, tol=1e-300))
    x1, _, _, it, failed = kern(x0, 1.0, 0.05, p, [0.5, 1e-300], step_scales(mech))
    assert float(it) == 1 and float(failed) == 1
    w1 = np.asarray(x1).ravel()[ny:]
    np.testing.assert_allclose(w1 - w0, dw, rtol=0, atol=1e-10 * np.max(np.abs(dw)))


def _oscillator():
    """x'' = -w^2 (x + x^3 / 2), w = 2 pi, from x = 1 at rest."""
    q, v, t, p = ca.SX.sym("q"), ca.SX.sym("v"), ca.SX.sym("t"), ca.SX.sym("p", 1)
    w = 2 * math.pi
    return Mechanism(name="osc", q=q, v=v, z=ca.SX.sym("z", 0), t=t, p=p,
                     params=ParamBlocks(("k",), (1,), np.ones(1)), mass=ca.SX(1.0),
                     force=-p[0] * w ** 2 * (q + 0.5 * q ** 3), constraint=ca.SX.zeros(0, 1),
                     scales=Scales(q=np.ones(1), v=np.full(1, w), z=np.zeros(0), force=w ** 2),
                     starts=lambda: [Start(np.ones(1), np.zeros(0), np.ones(1), "x")],
                     outputs={"x": sc.Output(q, "m")})


def test_integrate_saves_reports_and_refuses():
    """save_times and save_every pick steps; a dt that does not divide the duration is
    shortened (dt_requested kept); RK4 above its stability limit at the start (2 sqrt 2 /
    omega, omega^2 = w^2 (1 + 1.5 q0^2) the stiffness there, which only grows as the
    amplitude grows) blows up with the time and the worst entry; an impossible Newton
    tolerance names the step."""
    mech = _oscillator()
    run = integrate(mech, 1.0, 0.1, method=GeneralizedAlphaFirstOrder(), save_times=[0.31, 0.5])
    np.testing.assert_allclose(run.time, [0.3, 0.5], atol=1e-12)
    run = integrate(mech, 1.0, 0.3, method=GeneralizedAlphaFirstOrder(), save_every=2)
    assert run.stats["dt"] == pytest.approx(0.25) and run.stats["dt_requested"] == 0.3
    np.testing.assert_allclose(run.time, [0.0, 0.5, 1.0], atol=1e-12)
    assert run.stats["newton_iterations"] >= 4 and run.stats["compiled"] is False
    lim = 2 * math.sqrt(2) / (2 * math.pi * math.sqrt(2.5))
    with pytest.raises(ConvergenceError, match=r"blew up.*worst entry [qv]\[0\].*stable here only") as exc:
        integrate(mech, 50.0, 1.2 * lim, method=RK4())
    assert exc.value.diagnostics["reason"] == "blowup" and exc.value.partial.status == "failed"
    assert exc.value.partial.stats["dt_stable"] == pytest.approx(lim, rel=1e-6)
    with pytest.raises(ConvergenceError, match="Newton did not converge in 3 iterations") as exc:
        integrate(mech, 1.0, 0.1, method=GeneralizedAlphaFirstOrder(tol=1e-300, max_iter=3))
    assert exc.value.diagnostics["time"] == pytest.approx(0.1)
    with pytest.raises(SymcableError, match="save_every and save_times"):
        integrate(mech, 1.0, 0.1, save_every=2, save_times=[0.5])
    with pytest.raises(SymcableError, match="newton = 'secant'"):
        GeneralizedAlphaFirstOrder(newton="secant")


def test_rootfinder_run_reports_no_iteration_counts():
    """newton = "rootfinder" gives no iteration counts (NaN from CasADi's rootfinder): the run
    says None, where it crashed converting NaN to an integer (found by studies/chains)."""
    from symcable.models.toys.toys import duffing
    from symcable.solvers.options import GeneralizedAlphaFirstOrder, NewtonScheme

    mech = duffing()
    tr = sc.integrate(mech, 2.0, 0.05, method=GeneralizedAlphaFirstOrder(
        newton=NewtonScheme.ROOTFINDER), codegen=False)
    assert tr.status == "converged" and tr.stats["newton_iterations"] is None
    unrolled = sc.integrate(mech, 2.0, 0.05, method=GeneralizedAlphaFirstOrder(), codegen=False)
    np.testing.assert_allclose(tr.q, unrolled.q, atol=1e-8)  # the same steps, solved alike


@pytest.mark.parametrize("rho", [0.0, 0.5, 1.0])
def test_taylor_start_lands_on_the_taylor_step(rho):
    """Newton's Taylor start (galpha1._taylor_rate) is the rate whose update y1 = y0 + h y'0
    + gamma h (y'1 - y'0) puts q1 at q0 + h v0 + h^2 a0 / 2 and v1 at v0 + h a0 (q' = v),
    whatever the carried q'0 (the scheme carries q' at its alpha points, not v): to
    round-off, at every rho_inf (gamma 1, 2/3, 1/2)."""
    from symcable.models.toys.toys import spring_chain
    from symcable.solvers.galpha1 import _taylor_rate, coefficients

    mech = spring_chain(4)
    nq, nv = mech.n_q, mech.n_v
    rng = np.random.default_rng(3)
    q0, v0, qd0, a0 = (rng.normal(size=n) for n in (nq, nv, nq, nv))
    h, gamma = 0.3, coefficients(rho)[2]
    x, t, hs = ca.MX.sym("x", 2 * (nq + nv)), ca.MX.sym("t"), ca.MX.sym("h")
    p = ca.MX.sym("p", mech.params.n)
    z = ca.Function("z", [x, t, hs, p], [_taylor_rate(mech, x, t, hs, p, gamma)])
    xv = np.concatenate([q0, v0, qd0, a0])
    w = np.ravel(z(xv, 0.0, h, mech.params.values))
    y1 = xv[:nq + nv] + h * xv[nq + nv:] + gamma * h * (w - xv[nq + nv:])
    np.testing.assert_allclose(y1[:nq], q0 + h * v0 + 0.5 * h * h * a0, atol=1e-13)
    np.testing.assert_allclose(y1[nq:], v0 + h * a0, atol=1e-13)
