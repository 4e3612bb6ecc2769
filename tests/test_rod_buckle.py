"""Buckled shapes of the twisted rod reached by static continuation (issue 14 item 3):
:func:`symcable.trace_branch` in a clamp's twist across Greenhill's critical moment;
:func:`symcable.self_contact` on shapes; the loop oracle (:func:`symcable.analytic.twisted_loop`)
and :func:`symcable.api.rod_contact.writhe` checked on each other and the Kirchhoff equations.

The rod is test_rod_greenhill's (clamped at both ends along x, end rotation held, EA = 1e6
B / L^2), at 12 segments. With both ends held at distance L an inextensible rod has no shape
but the straight one: past the critical moment it buckles by stretching, so the tension T
grows with the buckle and the buckled states sit on Greenhill's curve with tension,
M = M_cr(T) (the state is neutrally stable for the tension it has made); T ~ (M - M_cr(0))
and the amplitude ~ sqrt(T) ~ sqrt(M - M_cr(0)): a supercritical pitchfork, stabilised by
the stretch (its amplitude scales as (B / EA)^(1/2)). The loop a twisted rod forms when its
ends are brought together (a longer, finer case: 20-70 s) is studies/hybrid/loop.py's.
"""
from __future__ import annotations

import math

import numpy as np
import pytest

from symcable import SymcableError, self_contact, trace_branch
from symcable.models.rod.rod import build_rod
from symcable.scene import load_scene

from test_rod_greenhill import B, GJ, GREENHILL, L, greenhill_with_tension, twisted_rod

N = 12
FRACS = (0.95, 1.0, 1.05, 1.1, 1.15, 1.2, 1.25, 1.3)  # of GREENHILL; 12 segments: 1.04


@pytest.fixture(scope="module")
def paths():
    mech = build_rod(load_scene(twisted_rod(N)))
    p = mech.params.with_values(motion=0.0)
    twists = np.array(FRACS) * GREENHILL * B / GJ  # rad: M = GJ Phi / L
    straight = trace_branch(mech, "end_b.twist", twists, p=p, leave_unstable=False)
    buckled = trace_branch(mech, "end_b.twist", twists, p=p)
    return mech, straight, buckled


def _amplitude(pt) -> float:
    return float(np.max(np.linalg.norm(pt.outputs["positions"][:, 1:], axis=1)))


def test_straight_branch_loses_stability_at_greenhill(paths):
    """Followed without leaving it, the straight branch stays straight (to 1e-12 m) and its
    lowest reduced stiffness changes sign once, between the points bracketing the rod's
    discrete critical moment; interpolated linearly there, M_cr L / B = 9.3496 at 12
    segments, 4.04 % above Greenhill's 8.98682 (9.0744, 0.97 % at 24; 9.0087, 0.24 % at 48:
    second order, as test_rod_greenhill's from the modes): asserted within 3-6 %."""
    _, straight, _ = paths
    lam = np.array([pt.min_stiffness for pt in straight.points])
    assert all(_amplitude(pt) < 1e-12 for pt in straight.points)
    assert [pt.stable for pt in straight.points] == [bool(x > 0) for x in lam]
    flips = np.flatnonzero(np.diff(np.sign(lam)))
    assert flips.size == 1, lam
    k = int(flips[0])
    M = np.array(FRACS) * GREENHILL
    m_cr = M[k] - lam[k] * (M[k + 1] - M[k]) / (lam[k + 1] - lam[k])
    assert 0.03 < m_cr / GREENHILL - 1.0 < 0.06, m_cr
    paths[1].stats["m_cr"] = m_cr


def test_buckled_branch_is_greenhill_with_its_tension(paths):
    """Leaving the straight branch along its unstable mode: every point past the critical
    moment is buckled (the first one marked ``left``) and stable (its lowest stiffness is
    the zero of the buckle's turn about the axis, within the 1e-9 scale tolerance), none
    before. Each buckled state's (T, M) lies on the closed-form M_cr(T) times the rod's
    discretisation factor at T = 0 (M_cr,12 / 8.98682): measured 0.09 % high at T = 0.5 N
    growing to 1.25 % at T = 15 N (the discrete slope dM_cr/dT: 0.35 %, 0.09 % at T = 15 N
    with 24, 48 segments, second order); asserted 1.5 % (M = M_cr(0), no tension effect,
    would be 19 % off at T = 15 N). The rotation held: the twisting moment is GJ Phi / L
    within 4e-5 (the writhe takes the rest). The amplitude against M - M_cr,12: log-log
    slope 0.5 at the bifurcation (supercritical pitchfork), measured 0.494 over these points
    (0.476, 0.471 at 24, 48 segments, whose points lie further past it: M_cr(T) bends);
    asserted within 0.05."""
    _, straight, buckled = paths
    if "m_cr" not in straight.stats:
        test_straight_branch_loses_stability_at_greenhill(paths)
    m_cr = straight.stats["m_cr"]
    M = np.array(FRACS) * GREENHILL
    past = M > m_cr
    amp = np.array([_amplitude(pt) for pt in buckled.points])
    assert np.all(amp[~past] < 1e-12) and np.all(amp[past] > 1e-4), amp
    assert [pt.left for pt in buckled.points] == [bool(x) for x in
                                                  np.r_[False, past[1:] & ~past[:-1]]]
    assert all(pt.stable for pt in buckled.points)
    factor = m_cr / GREENHILL
    rows = []
    for pt, m in zip(np.array(buckled.points)[past], M[past]):
        T = -float(pt.outputs["end_force_b"][0])
        Mt = float(np.mean(pt.outputs["twisting_moment"]))
        assert Mt == pytest.approx(m, rel=1e-3)
        rows.append((T, Mt, factor * greenhill_with_tension(T)))
    rows = np.array(rows)
    assert np.all(rows[:, 0] > 0)
    assert np.max(np.abs(rows[:, 1] / rows[:, 2] - 1.0)) < 0.015, rows
    slope = np.polyfit(np.log(M[past] - m_cr), np.log(amp[past]), 1)[0]
    assert abs(slope - 0.5) < 0.05, slope


def test_self_contact():
    """Two crossing segments 0.3 m apart: distance 0.3 to 1e-12 m, the closest points where
    they cross; a straight line has no pair closer than its segments' separation; a closed
    planar loop (a circle's polyline returning past its start) touches itself; bad input
    refused naming the argument."""
    X = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0.3], [0.5, -1, 0.3], [0.5, -2, 0.3]], float)
    c = self_contact(X, 0.35, skip=1)
    assert c.min_distance == pytest.approx(0.3, abs=1e-12) and c.pair == (0, 2)
    assert c.contact and c.gap == pytest.approx(-0.05, abs=1e-12)
    assert np.allclose(c.points, [[0.75, 0, 0], [0.75, 0, 0.3]], atol=1e-12)
    line = np.c_[np.linspace(0, 1, 11), np.zeros((11, 2))]
    c = self_contact(line, 0.01)
    assert c.skip == 1 and c.min_distance == pytest.approx(0.1) and not c.contact
    a = np.linspace(0, 2.2 * math.pi, 45)
    ring = np.c_[np.cos(a), np.sin(a), 0.002 * a]
    c = self_contact(ring, 0.02)
    assert c.contact and c.min_distance < 0.02 and c.pair[1] - c.pair[0] > 35
    for args, word in [((np.zeros((3, 2)), 0.1), "positions"), ((line, -1.0), "diameter"),
                       ((line, 0.1, ), "skip")]:
        with pytest.raises(SymcableError, match=word):
            self_contact(*args, **({"skip": 0} if word == "skip" else {}))


def test_trace_branch_refuses_bad_input(paths):
    mech = paths[0]
    with pytest.raises(SymcableError, match="block = 'twist'.*allowed: load"):
        trace_branch(mech, "twist", [0.0, 1.0])
    with pytest.raises(SymcableError, match=r"shape \(K, 3\)"):
        trace_branch(mech, "end_b.position", [1.0, 0.9])
    with pytest.raises(SymcableError, match="component = 3"):
        trace_branch(mech, "end_b.position", [1.0, 0.9], component=3)
    with pytest.raises(SymcableError, match="at least two finite"):
        trace_branch(mech, "end_b.twist", [0.0, np.nan])


def test_twisted_loop_solves_kirchhoff():
    """The oracle of studies/hybrid/loop.py (symcable.analytic.twisted_loop), checked
    against the rod equations it claims to solve: the curve built from its theta(s) and
    psi' = M / (B (2 - u)) satisfies the Kirchhoff moment balance m' + t x n = 0, m = B t x t'
    + M t, n = T e_z, to 1e-5 of its scale B k^3 (measured 2.6e-6 at m = 0.69, falling 16x
    at h / 4: the central differences' O(h^2) at h = 1e-3 / k; a wrong sign of psi' or of
    the tension leaves residuals of 0.3-0.5 B k^3), and the
    quadratures of 1 - cos theta and psi' (1 - cos theta) over +-25 / k give its shortening
    and end rotation to 1e-8 (trapezoid on a decaying integrand), at m = 0.69 and 1.66;
    m = 0 is the planar elastica loop (4 sqrt(B / T), 2 pi)."""
    from symcable.analytic import twisted_loop
    Bs, T = 1.3, 40.0
    for M in (5.0, 12.0):  # m = 0.69, 1.66 (at m = 0 psi jumps by pi at the middle)
        lp = twisted_loop(Bs, T, M)
        s = np.linspace(-25.0, 25.0, 50001) / lp.k
        h = s[1] - s[0]
        u = lp.one_minus_cos(s)
        th = 2.0 * np.arcsin(np.sqrt(0.5 * u))  # 1 - cos = 2 sin^2(theta / 2): no round-off
        dpsi = M / (Bs * (2.0 - u))
        psi = np.concatenate([[0.0], np.cumsum(0.5 * (dpsi[1:] + dpsi[:-1]) * h)])
        t = np.c_[np.sin(th) * np.cos(psi), np.sin(th) * np.sin(psi), np.cos(th)]
        dt = np.gradient(t, h, axis=0)
        mom = Bs * np.cross(t, dt) + M * t
        res = np.gradient(mom, h, axis=0) + np.cross(t, [0.0, 0.0, T])
        assert np.max(np.abs(res[2:-2])) < 1e-5 * Bs * lp.k**3, (M, np.max(np.abs(res[2:-2])))
        assert np.trapezoid(u, s) == pytest.approx(lp.shortening, rel=1e-8)
        assert np.trapezoid(dpsi * u, s) == pytest.approx(lp.rotation, rel=1e-8)
    planar = twisted_loop(Bs, T, 0.0)
    assert planar.shortening == pytest.approx(4.0 * math.sqrt(Bs / T))
    assert planar.rotation == pytest.approx(2.0 * math.pi)
    with pytest.raises(ValueError, match="Greenhill"):
        twisted_loop(Bs, T, 2.0 * math.sqrt(Bs * T))


def test_writhe_of_the_loop():
    """symcable.api.rod_contact.writhe on the homoclinic loop's centre line (its tangent
    integrated at 400 segments over +-20 / k, the ends extended along the axis): 2 pi Wr is
    the loop's end rotation 4 arccos(m / 2) (Calugareanu-White-Fuller with the twist M / C
    uniform), measured 0.21 % / 1.08 % low at m = 0.69 / 1.66 (second order in the
    segments: 0.013 % / 0.067 % at 1600); asserted 2 %. A planar curve has none, and the
    mirror image the opposite."""
    from symcable.analytic import twisted_loop
    from symcable.api.rod_contact import writhe
    Bs, T = 1.3, 40.0
    for M in (5.0, 12.0):
        lp = twisted_loop(Bs, T, M)
        s = np.linspace(-20.0, 20.0, 401) / lp.k
        h = s[1] - s[0]
        u = lp.one_minus_cos(s)
        th = 2.0 * np.arcsin(np.sqrt(0.5 * u))
        dpsi = M / (Bs * (2.0 - u))
        psi = np.concatenate([[0.0], np.cumsum(0.5 * (dpsi[1:] + dpsi[:-1]) * h)])
        t = np.c_[np.sin(th) * np.cos(psi), np.sin(th) * np.sin(psi), np.cos(th)]
        X = np.vstack([np.zeros(3), np.cumsum(0.5 * (t[1:] + t[:-1]) * h, axis=0)])
        w = writhe(X, axis=[0.0, 0.0, 1.0])
        assert 2.0 * math.pi * w == pytest.approx(lp.rotation, rel=0.02), (M, w)
    assert writhe(X * [1.0, 1.0, -1.0], axis=[0.0, 0.0, -1.0]) == pytest.approx(-w)
    a = np.linspace(0.0, 1.8 * math.pi, 50)
    assert abs(writhe(np.c_[np.cos(a), np.sin(a), 0 * a])) < 1e-12


def test_reanchoring_keeps_every_vertex_twist():
    """Re-anchoring in trace_branch's relaxations (``_Charts.renew``): a 6-segment rod whose
    edges 1-3 turn to 170 deg from their anchors (along x) on alternate sides, so that two
    vertices carry reference twists of +-5.93 rad (beyond pi). The new chart takes the
    anchors' angle afresh by atan2 and gives them -+0.35 rad: without more, each vertex's
    twist would jump by a turn (what made a coarse loop's snap lose a turn of link). The
    edge twist between them is shifted by 2 pi instead: every vertex twist the same to
    1e-12 rad. With one such vertex alone no shift restores it (the clamps hold the total):
    the chart is kept."""
    import casadi as ca
    from symcable.models.rod.reanchor import reanchor_hook
    from symcable.solvers.branch import _Charts

    mech = build_rod(load_scene(twisted_rod(6)))
    p = mech.params.with_values(motion=0.0)
    pos = mech.outputs["positions"].expr
    tw = ca.Function("tw", [mech.q, mech.p], [mech.outputs["twist"].expr])
    q0 = np.zeros(mech.n_q)
    J = np.asarray(ca.Function("J", [mech.q, mech.p], [ca.jacobian(pos, mech.q)])(q0, p))
    x0 = np.asarray(ca.Function("x", [mech.q, mech.p], [pos])(q0, p)).ravel(order="F")

    def state(*dirs):  # nodes 0.2 m apart along the directions (polar, azimuth deg about x)
        X = [np.zeros(3), np.array([0.2, 0.0, 0.0])]
        for a, f in dirs:
            a, f = math.radians(a), math.radians(f)
            X.append(X[-1] + 0.2 * np.array([math.cos(a), math.sin(a) * math.cos(f),
                                             math.sin(a) * math.sin(f)]))
        X.append(np.array([L, 0.0, 0.0]))  # the clamp at end B (positions in p)
        return np.linalg.lstsq(J, np.array(X).ravel(order="F") - x0, rcond=None)[0]

    charts = _Charts(mech, reanchor_hook(mech)).stepwise()
    q = state((170, 90), (170, -80), (170, 90), (0, 0))
    before = np.asarray(tw(q, p)).ravel()
    assert np.allclose(before[2:4], [5.9314, -5.9314], atol=1e-4), before
    p_new, renewed, q_new = charts.renew(q, p)
    assert renewed and not np.array_equal(p_new, p)
    assert np.allclose(np.asarray(tw(q, p_new)).ravel()[2:4], [-0.3517, 0.3517], atol=1e-4)
    assert np.max(np.abs(np.asarray(tw(q_new, p_new)).ravel() - before)) < 1e-12
    assert np.sort(np.abs(q_new - q))[-2] == 0.0  # one coordinate moved,
    assert np.max(np.abs(q_new - q)) == pytest.approx(2.0 * math.pi)  # by one turn
    q = state((170, 90), (170, -80), (60, 0), (0, 0))
    p_same, renewed, q_same = charts.renew(q, p)
    assert not renewed and p_same is p and q_same is q
