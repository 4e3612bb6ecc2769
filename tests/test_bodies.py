"""A rigid body of six degrees of freedom (issue 13, part 1: symcable/models/body/body.py) alone
and on lines: a free body in still water against the closed forms of hydrostatics (rest,
rising, roll), a pendulum of a compact body on a light wire against its period, and its
energy in a free run."""
from __future__ import annotations

import math

import casadi as ca
import numpy as np
import pytest

import symcable as sc
from symcable.mechanism.functions import functions
from symcable.models.body.body import body_part, start_q
from symcable.results.generic import Equilibrium
from symcable.scene.bodies import Body, BodyKind
from symcable.scene.model import Environment
from symcable.solvers.integrate import integrate
from symcable.solvers.linearize import mechanism_modes
from symcable.solvers.options import GeneralizedAlphaFirstOrder

RHO, G = 1025.0, 9.80665
WATER = Environment(water_density=RHO, gravity=G, current=(0.0, 0.0, 0.0))


def _body(**kw) -> Body:
    args = dict(name="fish", kind=BodyKind.FREE, position=(0.0, 0.0, -20.0), mass=RHO * 2.0,
                inertia=(300.0, 500.0, 400.0), volume=2.0, center_of_gravity=(0.3, 0.0, -0.6),
                center_of_buoyancy=(0.3, 0.0, -0.45), ca_volume=(0.4, 1.2, 2.0))
    args.update(kw)
    return Body(**args)


def _force_and_acceleration(mech, q):
    """(f, a) at rest at q: the generalized force (N, N m) and M^-1 f."""
    F = functions(mech)
    p, v0 = mech.params.values, np.zeros(mech.n_v)
    f = -np.ravel(np.asarray(F.acc_residual(q, v0, v0, np.zeros(0), 0.0, p)[0]))
    M = np.asarray(ca.DM(F.tangents(q, v0, np.zeros(0), 0.0, p)[2]))
    return f, np.linalg.solve(M, f)


def test_free_body_at_rest_only_where_weight_and_buoyancy_balance():
    """Neutral (m = rho V) with the centre of buoyancy straight above the centre of gravity:
    no force, no moment (to round-off of the weight); heavier: (rho V - m) g downward and its
    moment about the reference point (the centres 0.3 m from it along body x); the centre of
    buoyancy off the vertical through the centre of gravity: the couple rho g V (x_B - x_G)
    about body y, in any orientation about the vertical (yaw)."""
    mech = body_part(_body(), WATER)
    f, _ = _force_and_acceleration(mech, start_q(_body()))
    W = RHO * 2.0 * G
    assert np.max(np.abs(f)) < 1e-12 * W
    heavy = _body(mass=2500.0)
    f, _ = _force_and_acceleration(body_part(heavy, WATER), start_q(heavy))
    net = (RHO * 2.0 - 2500.0) * G
    np.testing.assert_allclose(f, [0, 0, net, 0, -0.3 * net, 0], atol=1e-12 * W)
    for yaw in (0.0, 90.0, 200.0):
        off = _body(center_of_buoyancy=(0.5, 0.0, -0.45), orientation_deg=(0.0, 0.0, yaw))
        f, _ = _force_and_acceleration(body_part(off, WATER), start_q(off))
        # the moment rows are in body axes: the couple is about body y whatever the yaw
        np.testing.assert_allclose(f, [0, 0, 0, 0, -W * 0.2, 0], atol=1e-12 * W)


def test_buoyant_body_rises_at_the_closed_form_acceleration():
    """rho V > m, centre of buoyancy above the centre of gravity, both off the reference
    point: at rest the reference point accelerates straight up at (rho V - m) g / (m + rho
    V_z), V_z the added-mass volume along the vertical, with no angular acceleration (to
    round-off); a run without drag follows z0 + a t^2 / 2 (generalized-alpha at rho_inf = 1,
    the trapezoidal rule, integrates a constant acceleration exactly: to its Newton
    tolerance)."""
    body = _body(mass=1500.0, center_of_gravity=(0.5, -0.2, 0.3),
                 center_of_buoyancy=(0.5, -0.2, 0.9), ca_volume=(0.3, 0.6, 1.1))
    mech = body_part(body, WATER)
    _, a = _force_and_acceleration(mech, start_q(body))
    expected = (RHO * 2.0 - 1500.0) * G / (1500.0 + RHO * 1.1)
    np.testing.assert_allclose(a, [0, 0, expected, 0, 0, 0], rtol=1e-14, atol=1e-14 * expected)
    tr = integrate(mech, 2.0, 0.1, method=GeneralizedAlphaFirstOrder(rho_inf=1.0),
                   q0=start_q(body), v0=np.zeros(6), p=mech.params.values, codegen=False)
    z = np.asarray(tr.outputs["position"]).reshape(-1, 3)[:, 2]
    np.testing.assert_allclose(z, -20.0 + 0.5 * expected * tr.time ** 2, atol=1e-8)


def test_roll_period_of_a_submerged_body():
    """Neutral body, centre of buoyancy h = 0.15 m above the centre of gravity: the couple
    rho g V h sin(phi) restores roll. Free to translate, roll phi and sway y of the centre of
    gravity couple through the added mass A = rho V_y at the centre of buoyancy (kinetic
    energy m y'^2 / 2 + Ixx phi'^2 / 2 + A (y' - h phi')^2 / 2), so the period is
    2 pi sqrt(I_eff / (rho g V h)), I_eff = Ixx + A h^2 m / (m + A); pitch likewise with
    Iyy and A = rho V_x. The linearised modes give both to 1e-12 (round-off of the
    eigensolver); a free run from 2 degrees gives the roll period to 1e-3 (measured 4.1e-4 at
    dt = T/100: generalized-alpha's phase error (omega dt)^2 / 12 = 3.3e-4 and the amplitude's
    phi0^2 / 16 = 7.6e-5)."""
    body = _body()
    mech = body_part(body, WATER)
    m, h, q0 = RHO * 2.0, 0.15, start_q(body)
    eq = Equilibrium(mech.name, q0, np.zeros(0), mech.params.values, {}, "converged")
    modes = mechanism_modes(mech, eq)
    closed = [math.sqrt(m * G * h / (I + A * h * h * m / (m + A))) / (2 * math.pi)
              for I, A in ((500.0, RHO * 0.4), (300.0, RHO * 1.2))]  # pitch, then roll
    np.testing.assert_allclose(modes.frequencies, closed, rtol=1e-12)
    assert modes.stats["zero_modes"] == 4  # three translations and yaw
    T = 1.0 / closed[1]
    phi = math.radians(2.0)
    q1 = q0.copy()
    q1[3], q1[6] = math.sin(phi / 2), math.cos(phi / 2)  # (e1, e2, e3, e0): about body x
    tr = integrate(mech, 3 * T, T / 100, method=GeneralizedAlphaFirstOrder(rho_inf=1.0),
                   q0=q1, v0=np.zeros(6), p=mech.params.values, codegen=False)
    roll = np.asarray(tr.outputs["roll_pitch_yaw"]).reshape(-1, 3)[:, 0]
    t = tr.time
    i = np.flatnonzero((roll[:-1] > 0) & (roll[1:] <= 0))
    crossings = t[i] - roll[i] * (t[i + 1] - t[i]) / (roll[i + 1] - roll[i])
    assert len(crossings) == 3
    np.testing.assert_allclose(np.diff(crossings), T, rtol=1e-3)


def test_energy_of_a_tumbling_body():
    """A neutral body spun about all three axes with its centre of gravity off the
    reference point and isotropic added mass (the case whose energy the model conserves,
    models/body.py): the kinetic plus potential energy drifts at second order in dt
    (measured 0.104 and 0.026 J at 0.01 and 0.005 s over 5 s, of 2270 J kinetic)."""
    body = _body(orientation_deg=(10.0, 20.0, 30.0), ca_volume=(0.5, 0.5, 0.5),
                 center_of_gravity=(0.1, 0.2, -0.3), center_of_buoyancy=(0.0, 0.0, 0.2))
    mech = body_part(body, WATER)
    drift = []
    for dt in (0.01, 0.005):
        tr = integrate(mech, 5.0, dt, method=GeneralizedAlphaFirstOrder(rho_inf=1.0),
                       q0=start_q(body), v0=np.array([0.1, 0.0, 0.2, 1.0, -0.5, 0.3]),
                       p=mech.params.values, codegen=False)
        E = np.ravel(tr.outputs["kinetic_energy"]) + np.ravel(tr.outputs["potential_energy"])
        drift.append(float(np.max(np.abs(E - E[0]))))
    assert 3.0 < drift[0] / drift[1] < 5.0, drift
    assert drift[1] < 1e-4 * float(np.max(np.ravel(tr.outputs["kinetic_energy"])))  # 1.1e-5


# ----------------------------------------------------------------------------- a pendulum

def _pendulum(n: int = 10) -> dict:
    """A 10 kg ball on a 10 m wire (0.01 kg/m, EA 1 MN) from a fixed point, in air, the
    wire attached at the ball's centre of gravity (the ball then turns freely: in statics
    the statics-only spring picks its orientation)."""
    return {"model": "cable3d", "environment": {"water_density": 0.0, "gravity": G},
            "line_types": {"wire": {"mass": 0.01, "diameter": 0.002, "EA": 1e6}},
            "points": {"top": {"kind": "fixed", "position": [0.0, 0.0, 0.0]}},
            "bodies": {"ball": {"mass": 10.0, "inertia": [0.04, 0.04, 0.04],
                                "position": [0.0, 0.0, -10.0]}},
            "lines": [{"name": "wire", "end_a": "top", "end_b": "ball",
                       "sections": [{"type": "wire", "length": 10.0, "segments": n}]}]}


def _pendulum_frequency() -> float:
    """sqrt(g / L_eff) / 2 pi, Hz: L_eff the wire's stretched length (tension m g plus the
    wire's own weight below each point, over EA) times (1 + r/3) / (1 + r/2), the
    compound pendulum of the wire's mass ratio r = mu L / m."""
    m, mu, L, EA = 10.0, 0.01, 10.0, 1e6
    stretched = L + (m * G * L + 0.5 * mu * G * L * L) / EA
    r = mu * L / m
    return math.sqrt(G / (stretched * (1 + r / 3) / (1 + r / 2))) / (2 * math.pi)


def test_pendulum_period():
    """The two swings of the pendulum (modal_analysis about the static state, the ball's
    free rotations left out as zero modes) at 2 pi sqrt(L_eff / g) within 1e-4: the wire's
    lumped mass against the compound pendulum's continuous one (measured -3.4e-5, -9.4e-6,
    -3.2e-6 at 5, 10, 20 segments). The static state hangs straight down, the ball at the
    wire's stretched length."""
    st = sc.solve_static(_pendulum(), codegen=False)
    ball = st.bodies["ball"]
    L = 10.0 + (10.0 * G * 10.0 + 0.5 * 0.01 * G * 100.0) / 1e6
    np.testing.assert_allclose(ball.position, [0.0, 0.0, -L], atol=1e-9)
    np.testing.assert_allclose(ball.force, [0.0, 0.0, 10.0 * G], rtol=0, atol=1e-9 * 10 * G)
    modes = sc.modal_analysis(_pendulum(), 3)
    f = _pendulum_frequency()
    np.testing.assert_allclose(modes.frequencies[:2], f, rtol=1e-4)
    assert modes.frequencies[2] > 20 * f  # the next is the wire's own
    np.testing.assert_allclose(np.abs(modes.shapes[0][-1]).max(), 1.0)  # the ball swings most


def test_pendulum_swings_at_its_period_and_keeps_its_energy():
    """The pendulum released from 1 degree (every node and the ball turned about the top):
    the x of the ball crosses zero every half period of the closed form within 5e-4
    (measured 1.1e-4 at dt = T/200: generalized-alpha's phase error (omega dt)^2 / 12 = 8e-5,
    the amplitude's theta0^2 / 16 = 2e-5, the wire's mass 1e-5); with rho_inf = 1 the
    energy changes by less than 1e-5 of the swing's (measured 1.5e-7: the ball's end node is
    a point of the ball, its mass and motion exact)."""
    from symcable.api.cable3d_static import static_equilibrium
    from symcable.scene import load_scene

    mech, eq = static_equilibrium(load_scene(_pendulum()), codegen=False)
    th = math.radians(1.0)
    c, s = math.cos(th), math.sin(th)
    q0 = np.array(eq.q)
    rows = [r for r in mech.layout.parts["wire"].node_q if r[0] >= 0]
    for r in rows + [mech.layout.parts["ball"].node_q[0]]:
        x, z = q0[r[0]], q0[r[2]]
        q0[r[0]], q0[r[2]] = c * x - s * z, s * x + c * z
    T = 1.0 / _pendulum_frequency()
    tr = integrate(mech, 1.6 * T, T / 200, method=GeneralizedAlphaFirstOrder(rho_inf=1.0),
                   q0=q0, v0=np.zeros(mech.n_v), p=mech.params.values, codegen=False)
    x = np.asarray(tr.outputs["ball.position"]).reshape(-1, 3)[:, 0]
    t = tr.time
    i = np.flatnonzero(np.sign(x[:-1]) != np.sign(x[1:]))
    crossings = t[i] - x[i] * (t[i + 1] - t[i]) / (x[i + 1] - x[i])
    assert len(crossings) == 3
    np.testing.assert_allclose(np.diff(crossings), T / 2, rtol=5e-4)
    E = np.ravel(tr.outputs["kinetic_energy"]) + np.ravel(tr.outputs["potential_energy"])
    swing = 10.0 * G * 10.0 * (1 - c)
    assert np.ptp(E) < 1e-5 * swing, np.ptp(E) / swing


@pytest.mark.parametrize("mass_matrix", ["lumped", "consistent"])
def test_energy_with_the_wire_off_the_centre_of_gravity(mass_matrix):
    """The wire attached at (0, 0.1, 0.3) m on the ball (inertia 1 kg m^2), the whole
    pendulum, ball orientation included, turned 5 degrees about the top and released: the
    ball swings and turns, the wire's end node is a point of it (its position x_O + R r,
    velocity v_O + R (w x r) and the acceleration (w x (w x r)) terms of the Attached joint,
    with the wire's lumped or consistent mass): the energy drifts at second order in dt
    (measured 9.7e-7 and 2.3e-7 J at 0.01 and 0.005 s, of 3.9 J kinetic, both mass
    matrices)."""
    from symcable.api.cable3d_static import static_equilibrium
    from symcable.scene import load_scene

    d = _pendulum()
    d["mass_matrix"] = mass_matrix
    d["bodies"]["ball"].update(position=[0.0, 0.0, -10.3], inertia=[1.0, 1.0, 1.0])
    d["lines"][0]["end_b"] = "ball@[0.0, 0.1, 0.3]"
    mech, eq = static_equilibrium(load_scene(d), codegen=False)
    th = math.radians(5.0)
    c, s = math.cos(th), math.sin(th)
    q0 = np.array(eq.q)
    rows = [r for r in mech.layout.parts["wire"].node_q if r[0] >= 0]
    for r in rows + [mech.layout.parts["ball"].node_q[0]]:  # x' = c x - s z: -th about y
        x, z = q0[r[0]], q0[r[2]]
        q0[r[0]], q0[r[2]] = c * x - s * z, s * x + c * z
    e, i0 = mech.layout.parts["ball"].node_q[1], mech.n_v  # (e1, e2, e3) and e0
    rv, r0 = np.array([0.0, -math.sin(th / 2), 0.0]), math.cos(th / 2)
    qv, qs = q0[e].copy(), q0[i0]
    q0[i0], q0[e] = r0 * qs - rv @ qv, r0 * qv + qs * rv + np.cross(rv, qv)
    drift = []
    for dt in (0.01, 0.005):
        tr = integrate(mech, 3.0, dt, method=GeneralizedAlphaFirstOrder(rho_inf=1.0), q0=q0,
                       v0=np.zeros(mech.n_v), p=mech.params.values, codegen=False)
        E = np.ravel(tr.outputs["kinetic_energy"]) + np.ravel(tr.outputs["potential_energy"])
        drift.append(float(np.ptp(E)))
    assert 3.0 < drift[0] / drift[1] < 5.0, drift
    assert drift[1] < 1e-6 * float(np.max(np.ravel(tr.outputs["kinetic_energy"]))), drift
    w = np.asarray(tr.outputs["ball.angular_velocity"]).reshape(-1, 3)
    assert np.max(np.abs(w)) > 0.05  # it turns
