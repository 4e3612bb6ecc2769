"""Issue 12's "planar equals 3D" in time: the small-amplitude dynamics of the seed-001 line
(suspended OC3 geometry, elliptic fairlead motion, current 0.5 m/s) by the linearised planar
model (``model = "planar"``, seed 001's dynamics) and by the fully nonlinear 3D cable
(``model = "cable3d"``), in the x-z plane and in a vertical plane turned about z.

At a tenth of the seed's motion (0.2 m by 0.1 m) the current dominates the relative flow,
so the quadratic drag is linear in the motion to first order and the two models should
agree to their small differences of formulation. Measured: the fairlead tension over the
last of six periods agrees to 0.26 % of its dynamic range (30 kN) at dt = 0.05 s, 0.24 % at
0.0125 s, 0.21 % at a fiftieth of the motion: not time error and not nonlinearity but the
models' own details (drag smoothing, added-mass lumping). 1 % of the range, the issue's bar
for periodic solutions against long runs, is the tolerance."""
from __future__ import annotations

import copy
import math

import numpy as np
import pytest

import symcable as sc

from conftest import seed001

SCALE, DT, DURATION, PERIOD = 0.1, 0.05, 60.0, 10.0


def _planar() -> dict:
    d = seed001()
    d["end_b"]["motion"]["amplitude"] = [2.0 * SCALE, 1.0 * SCALE]
    return d


def _cable3d(angle: float) -> dict:
    """The planar scene as a cable3d dict in the vertical plane turned by ``angle`` about z."""
    d = copy.deepcopy(_planar())
    d["model"] = "cable3d"
    c, s = math.cos(angle), math.sin(angle)
    for end in ("end_a", "end_b"):
        x, z = d[end]["position"]
        d[end]["position"] = [x * c, x * s, z]
    m = d["end_b"]["motion"]
    (ax, az), (px, pz) = m["amplitude"], m["phase_deg"]
    m["amplitude"], m["phase_deg"] = [ax * c, ax * s, az], [px, px, pz]
    ux, uz = d["environment"]["current"]
    d["environment"]["current"] = [ux * c, ux * s, uz]
    return d


@pytest.fixture(scope="module")
def planar_run():
    return sc.simulate(_planar(), DURATION, dt=DT)


@pytest.mark.parametrize("angle", [0.0, 0.7])
def test_small_motion_dynamics_equal_the_planar_model(planar_run, angle):
    tr = sc.simulate(_cable3d(angle), DURATION, dt=DT)
    assert planar_run.status == tr.status == "converged"
    tp, Tp = np.asarray(planar_run.time), np.asarray(planar_run.fairlead_tension)
    last = tp >= DURATION - PERIOD
    T3 = np.interp(tp[last], np.asarray(tr.time), np.asarray(tr.fairlead_tension))
    rng = np.ptp(Tp[last])
    assert rng > 1e4  # a real dynamic response (measured 30 kN)
    assert np.max(np.abs(T3 - Tp[last])) <= 0.01 * rng
    # and the 3D line stays in its plane
    pos = np.asarray(tr.positions)
    off = pos[..., 0] * -math.sin(angle) + pos[..., 1] * math.cos(angle)
    assert np.max(np.abs(off)) < 1e-6
