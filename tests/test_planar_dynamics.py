"""The linearised planar dynamics, through its Mechanism: rest state, Jacobian, spectrum of a
taut string."""
from __future__ import annotations

import numpy as np
import pytest

import symcable as sc
from symcable.mechanism.functions import functions
from symcable.errors import SceneError
from symcable.models.planar.mechanism import mechanism_of, state_permutation

from conftest import OC3, planar_rates, seed001, taut_string


def test_static_state_is_exact_rest_state():
    """With the excitation off, the static solution gives zero rate to round-off (1e-12 of
    the state scales per second), with current, drag and bending all present (the rate of
    the model's Mechanism, q' = G v + w and v' = M^-1 f)."""
    d = seed001()
    d["line_types"]["chain"]["EI"] = 1e5
    m = sc.build_dynamic_model(sc.load_scene(d))
    assert {"drag", "added mass", "bending"} <= set(m.info["terms"])
    rate, _ = planar_rates(m)
    ydot = rate(m.y0, 3.7, m.with_params(amp_b=[0.0, 0.0]))
    assert np.max(np.abs(ydot) / m.y_scale) < 1e-12


def test_mechanism_jacobian_matches_finite_differences():
    """The exact Jacobian of the model's Mechanism, dF/d(q, v) = [[-H, -G], [K, C]] from its
    ``kinematics_jacobian`` (H, G) and ``tangents`` (K = -df/dq, C = -df/dv), against central
    differences of its DAE residual F = (q' - G v - w, M v' - f) at a random moving state:
    drag is smooth away from zero relative velocity (a current is on), so 1e-6 relative."""
    m = sc.build_dynamic_model(sc.load_scene(seed001()))
    mech = mechanism_of(m)
    F = functions(mech)
    iq, iv = state_permutation(m)
    rng = np.random.default_rng(1)
    y = m.y_scale * rng.standard_normal(m.n_y)
    x, s = np.r_[y[iq], y[iv]], np.r_[m.y_scale[iq], m.y_scale[iv]]
    nq, z, t, p = mech.n_q, np.zeros(0), 1.0, m.p_value
    H, G = (np.array(a.full()) for a in F.kinematics_jacobian(x[:nq], x[nq:], z, t, p))
    K, C = (np.array(a.full()) for a in F.tangents(x[:nq], x[nq:], z, t, p)[:2])
    J = np.block([[-H, -G], [K, C]])
    xd = np.zeros(x.size)  # the residual is affine in the rates (M is constant)

    def residual(x):
        return np.asarray(F.dae_residual(xd, x, t, p)).ravel()

    h = 1e-6 * s
    Jfd = np.zeros_like(J)
    for k in range(x.size):
        e = np.zeros(x.size)
        e[k] = h[k]
        Jfd[:, k] = (residual(x + e) - residual(x - e)) / (2 * h[k])
    scale = np.max(np.abs(J), axis=1, keepdims=True) + 1e-300
    assert np.max(np.abs(J - Jfd) / scale) < 1e-6


def test_taut_string_frequencies_from_the_spectrum():
    """Eigenvalues of the undamped linear model of a taut weightless string (the state
    matrix of its Mechanism, [[H, G], [-M^-1 K, -M^-1 C]]): the first three transverse
    frequencies within 0.5 % of n/(2L') sqrt(T/mu) (L', mu the stretched length and mass per
    stretched length). At 50 segments the discretisation error is (n pi/N)^2/24 <= 0.15 %."""
    T, L, mass, EA = 1e5, 100.0, 10.0, 1e9
    m = sc.build_dynamic_model(sc.load_scene(taut_string(T, L, mass, EA)))
    J = planar_rates(m)[1](m.y0, 0.0, m.p_value)
    w = np.sort(np.abs(np.linalg.eigvals(J).imag))
    f = w[w > 1e-9][::2] / (2 * np.pi)
    eps = T / EA
    exact = [n / (2 * L * (1 + eps)) * np.sqrt(T / (mass / (1 + eps))) for n in (1, 2, 3)]
    np.testing.assert_allclose(f[:3], exact, rtol=5e-3)


def test_dynamics_refuses_a_line_on_the_seabed():
    """Planar dynamics of a line touching the seabed is out of scope: a clear SceneError."""
    d = dict(OC3)
    d["end_b"] = {"condition": "pinned", "position": [-5.2, -70.0],
                  "motion": {"period": 10.0, "amplitude": [1.0, 0.0]}}
    with pytest.raises(SceneError, match="seabed"):
        sc.build_dynamic_model(sc.load_scene(d))


def _anchor_on_seabed(x_anchor):
    """The seed-001 line over a seabed at 320 m, its anchor on the seabed at x_anchor."""
    d = seed001()
    d["environment"]["depth"] = 320.0
    d["end_a"]["position"] = [x_anchor, -320.0]
    return sc.load_scene(d)


def test_taut_line_with_its_anchor_on_the_seabed_runs():
    """A taut line whose anchor sits on the seabed: the smoothed penalty contact leaves a
    grounded length of a few mm (0.0025 m here, node 1 is 2.3 cm up) although no node rests
    on the seabed, and the dynamics accept it (an exact ``> 0`` test refused it). The
    tolerance is 1 % of a segment, 0.18 m here: the seabed then carries under 1 % of one
    segment's weight. Moved 0.3 m closer, node 1 sinks 1.6 mm into the seabed and carries
    0.6 m of line: refused, with advice that keeps the seabed (never "remove the depth",
    which would hang the line through it)."""
    from symcable.models.planar.dynamics import grounded_tolerance

    scene = _anchor_on_seabed(-887.8)
    st = sc.solve_static(scene)
    assert 0.0 < st.grounded_length < grounded_tolerance(scene) == pytest.approx(0.01 * 902.2 / 50)
    model = sc.build_dynamic_model(scene, st)
    tr = sc.simulate(None, 10.0, dt=0.1, model=model)
    assert tr.status == "converged" and np.ptp(tr.fairlead_tension) > 1e4
    scene = _anchor_on_seabed(-887.5)
    st = sc.solve_static(scene)
    assert st.grounded_length > grounded_tolerance(scene)
    with pytest.raises(SceneError, match="rests 0.598 m on the seabed") as info:
        sc.build_dynamic_model(scene, st)
    msg = str(info.value)
    assert "move end_a.position further from end_b" in msg and "statics only" in msg
    assert "remove the depth" not in msg and "\n" not in msg
