"""Seabed friction of the cable3d line in time (issue 12, item 2, first step): a line lying
straight on a frictional seabed, both ends dragged together slowly (harmonic, 5 m over a
200 s period, ramped in over the first period), carries on its ends the friction of its
grounded weight: at the instant of greatest speed (no acceleration) the end forces sum to
mu sum_i N_i v / sqrt(v^2 + v_eps^2) against the motion (N_i the nodes' contact forces, the
regularised Coulomb law at the line's speed v), with mu the axial coefficient when dragged
along the line and the lateral one across it. No drag or added mass (Cd = Ca = 0), so
friction is the only force along the bed. The line is pre-stretched by 5e-4 so that its
trailing half never goes slack, and laid at exactly its length in the last test, where it
does."""
from __future__ import annotations

import math

import numpy as np
import pytest

from symcable.api.cable3d_static import cable3d_mechanism
from symcable.scene import load_scene
from symcable.solvers.equilibrium import solve_equilibrium
from symcable.solvers.integrate import integrate

L, T, A, EPS = 40.0, 200.0, 5.0, 0.01


def _drag(direction, mu_a, mu_l, stretch=5e-4):
    amp = [A * direction[0], A * direction[1], 0.0]
    motion = {"kind": "harmonic", "period": T, "amplitude": amp, "phase_deg": [0.0, 0.0, 0.0]}
    d = {"model": "cable3d", "environment": {"depth": 50.0},
         "seabed": {"stiffness": 1e6, "friction_axial": mu_a, "friction_lateral": mu_l,
                    "friction_velocity": EPS},
         "line_types": {"c": {"mass": 100.0, "diameter": 0.1, "EA": 1e8, "cd_normal": 0.0,
                              "cd_tangential": 0.0, "ca_normal": 0.0}},
         "sections": [{"type": "c", "length": L, "segments": 20}],
         "end_a": {"condition": "pinned", "position": [0.0, 0.0, -50.0], "motion": motion},
         "end_b": {"condition": "pinned", "position": [L * (1 + stretch), 0.0, -50.0],
                   "motion": motion}}
    mech = cable3d_mechanism(load_scene(d))
    eq = solve_equilibrium(mech)
    tr = integrate(mech, 1.75 * T, 1.0, start=eq, p=mech.params.values)
    assert tr.status == "converged"
    n = len(tr.time)
    total = (np.asarray(tr.outputs["end_force_a"]).reshape(n, -1)
             + np.asarray(tr.outputs["end_force_b"]).reshape(n, -1))[-1]
    N = float(np.sum(np.asarray(tr.outputs["contact_force"]).reshape(n, -1)[-1]))
    v = A * 2 * math.pi / T  # at t = 1.75 T the ends move at +A omega, not accelerating
    return total, N * v / math.sqrt(v * v + EPS * EPS)


@pytest.mark.parametrize("mu_a, mu_l", [(0.5, 1.0), (1.0, 0.5)])
def test_axial_friction(mu_a, mu_l):
    """Dragged along its length: the axial coefficient, whatever the lateral one (5e-3:
    the residual axial waves of the 1 s steps)."""
    total, friction = _drag((1.0, 0.0), mu_a, mu_l)
    assert total[0] == pytest.approx(-mu_a * friction, rel=5e-3)
    assert abs(total[1]) < 1e-6 * friction


def test_lateral_friction_isotropic():
    """Dragged across its length with one coefficient for both directions: the line bows
    (its tension against the friction, 3.6 m at mid-length) and slides at the ends' speed.
    1 %: measured 0.6 % more than the friction, the bow's own motion (its depth follows the
    ends' speed through the regularised law)."""
    total, friction = _drag((0.0, 1.0), 0.8, 0.8)
    assert total[1] == pytest.approx(-0.8 * friction, rel=1e-2)


def test_lateral_coefficient_across_the_line():
    """Dragged across with mu_lateral = 1 and mu_axial = 0.5: between the two, nearer the
    lateral one (the bowed line's ends slide partly along themselves)."""
    total, friction = _drag((0.0, 1.0), 0.5, 1.0)
    assert 0.85 * friction < -total[1] < 1.0 * friction


def test_dragged_at_its_length_trailing_half_slack():
    """The same drag along the line laid at exactly its length: the trailing half carries
    no tension and its nodes are held by friction alone, which at the velocity reversals
    takes generalized-alpha's line-searched Newton 21-30 iterations (it failed at the old
    cap of 20). The friction is still carried to the ends (the leading end pulls it all)."""
    total, friction = _drag((1.0, 0.0), 0.5, 1.0, stretch=0.0)
    assert total[0] == pytest.approx(-0.5 * friction, rel=5e-3)
