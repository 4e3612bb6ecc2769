"""Re-anchoring in the time march (issue 14; notes/rod14.md sections 1 and 3): a rod's
reference frames are anchored (the parameter block ``frame``) and singular where an edge
has turned by half a turn from its anchor; the march calls the Mechanism's re-anchoring hook
(:func:`symcable.models.rod_reanchor.reanchor_hook`, :mod:`symcable.solvers.reanchor`)
between steps and runs through.

The case: a weakly weighted rod pinned at one end, free at the other, started straight and
horizontal, spinning at one turn a second in the vertical plane (w / m = 1 m/s^2, so it
loops over the top): every edge turns through 1.5 turns in 1.5 s.
"""
from __future__ import annotations

import math

import numpy as np
import pytest

from symcable.errors import ConvergenceError
from symcable.models.rod import build_rod
from symcable.models.rod_reanchor import frame_margin, reanchor_hook
from symcable.scene import load_scene
from symcable.solvers.integrate import integrate
from symcable.solvers.options import GeneralizedAlphaFirstOrder

L, N, OMEGA, DT = 1.0, 8, 2.0 * math.pi, 2e-3
METHOD = GeneralizedAlphaFirstOrder(rho_inf=1.0, tol=1e-10)


def _spinning(EI=1.0, axis=(0.0, 1.0, 0.0)):
    """(mechanism, q0, v0, p): the rod (bending stiffness ``EI``, N m^2, or [EI_1, EI_2])
    straight along +x, its anchors along +x (director +y), its nodes moving at
    Omega a x r (a the unit ``axis``: about +y, down and then round in the x-z plane)."""
    d = {"model": "rod", "environment": {"water_density": 0.0},
         "line_types": {"r": {"EA": 1e5, "EI": EI, "GJ": 0.8, "mass": 1.0,
                              "diameter": 0.02, "weight": 1.0}},
         "sections": [{"type": "r", "length": L, "segments": N}],
         "end_a": {"condition": "pinned", "position": [0.0, 0.0, 0.0]},
         "end_b": {"condition": "free"}}
    mech = build_rod(load_scene(d))
    p = mech.params.values.copy()
    p[mech.params.slice("frame")] = np.tile([1.0, 0, 0, 0, 1.0, 0], N)
    X = np.outer(np.linspace(0.0, L, N + 1), [1.0, 0.0, 0.0])
    V = np.cross(OMEGA * np.asarray(axis) / np.linalg.norm(axis), X)
    # q: node by node, each moving node's (x, y, z), then the twist of the edge after it
    # (edge 0's is held: no clamped end)
    q0 = np.concatenate([np.r_[X[i], [0.0] if i < N else []] for i in range(1, N + 1)])
    v0 = np.concatenate([np.r_[V[i], [0.0] if i < N else []] for i in range(1, N + 1)])
    return mech, q0, v0, p


@pytest.fixture(scope="module")
def spinning():
    return _spinning()


def _run(spinning, duration, **kw):
    mech, q0, v0, p = spinning
    return integrate(mech, duration, DT, method=METHOD, q0=q0, v0=v0, p=p, codegen=False,
                     **kw)


def test_without_reanchoring_the_half_turn_fails(spinning):
    """Without the hook the run stops at the half turn (t ~ 0.49 s, measured) with a
    ConvergenceError naming the step, its partial result up to there."""
    with pytest.raises(ConvergenceError) as err:
        _run(spinning, 1.5)
    part = err.value.partial
    assert 0.4 < part.time[-1] < 0.5


def test_reanchoring_runs_through_looping(spinning):
    """With the hook the rod loops 1.5 turns: re-anchored 4 times (at 0.32, 0.66, 1.0,
    1.33 s: each time an edge has turned by 120 degrees), its least margin 0.49; the motion stays in its plane and untwisted (to round-off), the energy is
    conserved at rho_inf = 1 (measured 9.1e-5 of the kinetic energy at dt = 2 ms: asserted
    5e-4), and up to the half turn it is the run without the hook (to 1e-9 m; measured
    identical: planar and isotropic, nothing here depends on the chart)."""
    mech, *_ = spinning
    tr = _run(spinning, 1.5, reanchor=reanchor_hook(mech))
    st = tr.stats
    assert tr.status == "converged" and st["reanchorings"] == 4
    assert st["min_frame_margin"] > 0.45 and len(st["p_final"]) == mech.params.n
    tip = tr.outputs["positions"][:, -1, :]
    turned = np.unwrap(np.arctan2(-tip[:, 2], tip[:, 0]))[-1]
    assert turned > 2.5 * math.pi
    assert np.max(np.abs(tip[:, 1])) < 1e-9 and np.max(np.abs(tr.outputs["twist_angles"])) < 1e-9
    K = tr.outputs["kinetic_energy"].ravel()
    E = K + tr.outputs["potential_energy"].ravel()
    assert np.max(np.abs(E - E[0])) < 5e-4 * np.max(K)
    ref = _run(spinning, 0.4)
    k = ref.time.size
    assert np.max(np.abs(tr.outputs["positions"][:k] - ref.outputs["positions"])) < 1e-9


def test_the_chart_changes_the_motion_only_through_the_omitted_spin():
    """What re-anchoring costs: the twist's kinetic energy leaves out the spin of the
    anchored reference frame about the tangent (second order in an edge's turn from its
    anchor, notes/rod14.md), so the motion depends on the chart, less as the anchors follow
    the edges more closely. Planar and isotropic (no twist couples), the runs re-anchored
    at thresholds 0.5 and 1.9 are the same to round-off (measured: identical). Tumbling in
    3D, anisotropic (EI_2 = 1.5 EI_1, spin axis tilted 17 deg out of the vertical plane, 0.8
    s), against a run re-anchored after every 0.35 deg of turn (threshold 1.99, 34 times:
    the time-parallel frame of DER, whose spin is zero, in the limit): positions differ by
    3.5e-5, 1.7e-5, 1.5e-6 m at thresholds 0.5, 1.0, 1.9 (d = 0.02 m; 10 times more at
    d = 0.2 m, whose rotary inertia is 100 times larger). Asserted: identical planar runs
    to 1e-12 m, and in 3D the error at 1.9 below 1e-5 m and below a fifth of that at 0.5."""
    mech, *_ = planar = _spinning()
    a = _run(planar, 0.8, reanchor=reanchor_hook(mech))
    b = _run(planar, 0.8, reanchor=reanchor_hook(mech, threshold=1.9))
    assert b.stats["reanchorings"] > 3 * a.stats["reanchorings"]
    assert np.max(np.abs(a.outputs["positions"] - b.outputs["positions"])) < 1e-12
    mech, *_ = tumbling = _spinning(EI=[1.0, 1.5], axis=[0.0, 1.0, 0.3])
    runs = {thr: _run(tumbling, 0.8, reanchor=reanchor_hook(mech, threshold=thr)).outputs[
        "positions"] for thr in (0.5, 1.9, 1.99)}
    err = {thr: float(np.max(np.abs(runs[thr] - runs[1.99]))) for thr in (0.5, 1.9)}
    assert err[1.9] < 1e-5 and err[1.9] < 0.2 * err[0.5], err


def test_frame_margin_needs_anchored_frames():
    """A Mechanism without a ``frame`` block has nothing to re-anchor: a SymcableError
    naming it (the cable3d march never asks)."""
    from symcable.cable3d_static import cable3d_mechanism
    from symcable.errors import SymcableError
    d = {"model": "cable3d", "line_types": {"c": {"EA": 1e6, "mass": 1.0, "diameter": 0.02}},
         "sections": [{"type": "c", "length": 10.0, "segments": 4}],
         "end_a": {"condition": "pinned", "position": [0.0, 0.0, -20.0]},
         "end_b": {"condition": "pinned", "position": [8.0, 0.0, -15.0]}}
    with pytest.raises(SymcableError, match="frame"):
        frame_margin(cable3d_mechanism(load_scene(d)))
