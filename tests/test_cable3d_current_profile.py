"""A current varying with depth (issue 12, item 3): environment.current_profile, rows
[z, U_x, U_y, U_z] linear between them and held beyond, applied at each element's mid-depth."""
from __future__ import annotations

import math

import numpy as np
import pytest

import symcable as sc
from symcable.errors import SceneError
from symcable.scene import load_scene

RHO, D, CDN, CDT = 1025.0, 0.08, 1.2, 0.3
PROFILE = [[-80.0, 0.0, 0.2, 0.0], [-30.0, 0.3, 0.6, 0.0], [0.0, 0.5, 1.0, 0.0]]


def _scene(profile=PROFILE, current=(0.0, 0.0, 0.0)) -> dict:
    env = {"water_density": RHO, "current": list(current)}
    if profile is not None:
        env["current_profile"] = profile
    return {"model": "cable3d", "environment": env,
            "line_types": {"rope": {"mass": 30.0, "diameter": D, "EA": 1e8, "cd_normal": CDN,
                                    "cd_tangential": CDT}},
            "sections": [{"type": "rope", "length": 120.0, "segments": 30}],
            "end_a": {"condition": "pinned", "position": [0.0, 0.0, -100.0]},
            "end_b": {"condition": "pinned", "position": [60.0, 0.0, -5.0]}}


def _drag(pos, strain, ds):
    """Morison drag (N) on each element from its positions, by NumPy, with the profile at
    its mid-depth (np.interp: linear, held beyond), split along and across the element."""
    z = np.array(PROFILE)
    mid = 0.5 * (pos[1:] + pos[:-1])
    u = np.stack([np.interp(mid[:, 2], z[:, 0], z[:, k]) for k in (1, 2, 3)], axis=1)
    t = np.diff(pos, axis=0)
    t /= np.linalg.norm(t, axis=1)[:, None]
    ut = np.sum(u * t, axis=1)[:, None] * t
    un = u - ut
    per_m = 0.5 * RHO * D * (CDN * np.linalg.norm(un, axis=1)[:, None] * un
                             + CDT * np.linalg.norm(ut, axis=1)[:, None] * ut)
    return per_m * (ds * np.sqrt(1.0 + strain))[:, None]


def test_static_force_balance_with_a_sheared_current():
    """The supports carry the line's weight and the drag of the current at each element's
    depth: the sum of the end forces equals weight plus drag computed from the solution by
    NumPy, to 1e-6 of the load (the solve's tolerance is 1e-9 of the force scale; |u| is
    smoothed below 1e-4 m/s, 4 orders below these speeds)."""
    s = load_scene(_scene())
    st = sc.solve_static(s)
    lt = s.line_types["rope"]
    ds = 120.0 / 30
    drag = _drag(st.positions, st.strain, ds).sum(axis=0)
    weight = np.array([0.0, 0.0, -lt.weight * 120.0])
    total = st.fairlead_force + st.anchor_force
    load = np.linalg.norm(weight) + np.linalg.norm(drag)
    np.testing.assert_allclose(total, weight + drag, atol=1e-6 * load)
    assert drag[1] > 0.03 * np.linalg.norm(weight)  # 4.8 %: 5e4 times the tolerance
    # a uniform current at the surface value is another answer (the profile is applied)
    uni = sc.solve_static(_scene(profile=None, current=(0.5, 1.0, 0.0)))
    assert abs(uni.fairlead_force[1] - st.fairlead_force[1]) > 0.1 * abs(st.fairlead_force[1])


def test_a_uniform_profile_is_a_uniform_current():
    a = sc.solve_static(_scene(profile=[[-200.0, 0.3, 0.4, 0.0], [0.0, 0.3, 0.4, 0.0]]))
    b = sc.solve_static(_scene(profile=None, current=(0.3, 0.4, 0.0)))
    np.testing.assert_allclose(a.positions, b.positions, atol=1e-9)


@pytest.mark.parametrize("profile, fragment", [
    ([[0.0, 1.0, 0.0, 0.0]], "at least two rows"),
    ([[0.0, 1.0, 0.0], [-5.0, 1.0, 0.0]], "current_profile[0]"),
    ([[0.0, 1.0, 0.0, 0.0], [0.0, 2.0, 0.0, 0.0]], "same z"),
    ("fast", "at least two rows"),
])
def test_bad_profiles_are_one_line_errors(profile, fragment):
    with pytest.raises(SceneError, match=None) as err:
        load_scene(_scene(profile=profile))
    msg = str(err.value)
    assert fragment in msg and "environment.current_profile" in msg and "\n" not in msg


def test_profile_round_trips_and_is_refused_in_planar():
    s = load_scene(_scene())
    assert load_scene(s.to_dict()) == s
    d = {"environment": {"current_profile": PROFILE},
         "line_types": {"r": {"mass": 1.0, "diameter": 0.1, "EA": 1e6}},
         "sections": [{"type": "r", "length": 10.0, "segments": 4}],
         "end_a": {"condition": "pinned", "position": [0.0, 0.0]},
         "end_b": {"condition": "pinned", "position": [8.0, 0.0]}}
    with pytest.raises(SceneError, match="cable3d option"):
        load_scene(d)
    assert math.isclose(s.environment.current_profile[0][0], -80.0)
