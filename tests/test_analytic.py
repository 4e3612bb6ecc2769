"""Tests of the closed-form oracles in ``symcable.analytic``.

The oracles are checked three ways: their special functions against SciPy, their solutions
against the equations they solve (end positions, force balance, the constitutive law along
the line), and against independent implementations (MoorPy's catenary, SciPy's BVP solver
for the elastica). Every tolerance states its reason.
"""
from __future__ import annotations

import contextlib
import io
import math

import numpy as np
import pytest

from symcable import analytic as an
from symcable.errors import ConvergenceError

scipy_special = pytest.importorskip("scipy.special")
scipy_integrate = pytest.importorskip("scipy.integrate")


# --------------------------------------------------------------------------------------------
# Special functions
# --------------------------------------------------------------------------------------------

def test_legendre_f_e_match_scipy_on_grid():
    phi = np.linspace(-7.0, 7.0, 57)[:, None]
    m = np.linspace(0.0, 0.999, 41)[None, :]
    f_ref = scipy_special.ellipkinc(phi, m)
    e_ref = scipy_special.ellipeinc(phi, m)
    # 1e-12 relative: Carlson's duplication converges to machine precision (observed ~3e-15);
    # the margin covers round-off in the amplitude reduction phi -> phi - n pi.
    np.testing.assert_allclose(an.elliptic_f(phi, m), f_ref, rtol=1e-12, atol=1e-14)
    np.testing.assert_allclose(an.elliptic_e(phi, m), e_ref, rtol=1e-12, atol=1e-14)


def test_legendre_f_e_at_m_equal_one():
    # m = 1 is allowed for |phi| < pi/2: F = atanh(sin phi), E = sin phi.
    phi = np.linspace(-1.5, 1.5, 31)
    # 1e-12 relative: same algorithm, only the argument 1 - m sin^2 is formed differently.
    np.testing.assert_allclose(an.elliptic_f(phi, 1.0), np.arctanh(np.sin(phi)),
                               rtol=1e-12, atol=1e-15)
    np.testing.assert_allclose(an.elliptic_e(phi, 1.0), np.sin(phi), rtol=1e-12, atol=1e-15)


def test_carlson_rf_rd_match_scipy():
    rng = np.random.default_rng(0)
    x, y, z = 10.0 ** rng.uniform(-6, 3, (3, 500))
    x[:50] = 0.0  # one zero argument is allowed (complete integrals)
    # 1e-13 relative: both are duplication algorithms run to machine precision.
    np.testing.assert_allclose(an.carlson_rf(x, y, z), scipy_special.elliprf(x, y, z),
                               rtol=1e-13)
    np.testing.assert_allclose(an.carlson_rd(x, y, z), scipy_special.elliprd(x, y, z),
                               rtol=1e-13)
    assert isinstance(an.carlson_rf(1.0, 2.0, 3.0), float)


# --------------------------------------------------------------------------------------------
# Elastic catenary: the solution satisfies its own equations
# --------------------------------------------------------------------------------------------

OC3 = dict(span=848.67, height=250.0, length=902.2, EA=3.84243e8, weight=698.094)

# (span, height, length, EA, weight, seabed)
CASES = [
    (848.67, 250.0, 902.2, 3.84243e8, 698.094, True),    # OC3-Hywind line, touches down
    (848.67, 250.0, 902.2, 3.84243e8, 698.094, False),   # same, no seabed: V_a < 0
    (87.466, 50.5, 100.0, 1.0e6, 10.0, False),           # taut, strain ~1 %
    (50.0, 10.0, 100.0, 1.0e8, 100.0, False),            # deep sag
    (300.0, -80.0, 400.0, 1.0e8, 100.0, False),          # end B below end A
    (1e-3, 100.0, 99.9, 1.0e7, 10.0, False),             # near-vertical, taut
    (1e-4, 50.0, 99.9, 1.0e7, 10.0, False),              # near-vertical, U-shaped
    (0.0, 50.0, 99.9, 1.0e7, 10.0, False),               # exactly vertical, U-shaped
    (0.0, 100.0, 99.9, 1.0e7, 10.0, True),               # exactly vertical, taut
    (60.0, 20.0, 100.0, 1.0e7, 10.0, True),              # fully slack, piled on the seabed
    (0.0, 20.0, 100.0, 1.0e7, 10.0, True),               # vertical with the rest on the seabed
    (100.0, 0.0, 99.0, 1.0e7, 10.0, True),               # flat on the seabed, stretched
    (95.0, 30.0, 100.0, 1.0e5, 10.0, True),              # short grounded part, 1 % strain
    (99.0, 5.0, 100.0, 1.0e9, 10.0, True),               # nearly straight, almost all grounded
    (70.71067811865476, 70.71067811865476, 100.0, 1e13, 10.0, False),  # inextensible, chord = L
    (400.0, 200.0, 500.0, 7.51e12, 200.0, False),
]
IDS = ["oc3-seabed", "oc3-free", "taut-1pct", "deep-sag", "b-below-a", "near-vertical-taut",
       "near-vertical-U", "vertical-U", "vertical-taut-seabed", "slack-piled",
       "vertical-piled", "flat-stretched", "short-grounded", "almost-all-grounded",
       "inextensible-chord-equals-L", "stiff-sagging"]


@pytest.mark.parametrize("span, height, length, EA, weight, seabed", CASES, ids=IDS)
def test_catenary_end_conditions_and_force_balance(span, height, length, EA, weight, seabed):
    sol = an.elastic_catenary(span, height, length, EA, weight, seabed=seabed)
    ends = sol.positions([0.0, length])
    # end A is the origin by construction: exact up to round-off
    np.testing.assert_allclose(ends[0], [0.0, 0.0], atol=1e-14 * length)
    # 1e-9 relative: the solver stops at a residual of 1e-12 L; 1e-9 leaves room for the
    # re-evaluation of the shape in dimensional form.
    np.testing.assert_allclose(ends[1], [span, height], rtol=0.0, atol=1e-9 * length)
    # vertical force balance of the suspended part: V_b - V_a = w (L - L_B). Exact in
    # exact arithmetic; 1e-12 of the largest force covers the rounding of V_a + w L_s.
    scale = max(abs(sol.V_a), abs(sol.V_b), weight * length)
    assert sol.V_b - sol.V_a == pytest.approx(weight * (length - sol.grounded_length),
                                              abs=1e-12 * scale)
    assert sol.H >= 0.0
    assert 0.0 <= sol.grounded_length <= length
    if seabed:
        assert sol.V_a >= 0.0
        if sol.grounded_length > 0.0:
            assert sol.V_a == 0.0
        z = sol.positions(np.linspace(0.0, length, 2001))[:, 1]
        assert z.min() >= -1e-12 * length  # never below the seabed (round-off allowed)
    assert sol.fairlead_tension == pytest.approx(math.hypot(sol.H, sol.V_b), rel=1e-15)
    assert sol.anchor_tension == pytest.approx(math.hypot(sol.H, sol.V_a), rel=1e-15)
    s = np.array([0.0, length])
    np.testing.assert_allclose(sol.tension(s), [sol.anchor_tension, sol.fairlead_tension],
                               rtol=1e-14)
    np.testing.assert_allclose(sol.strain(s), sol.tension(s) / EA, rtol=1e-15)


# lines with H > 0 (vertical lines have no tangent direction to difference; a slack pile
# on the seabed is not a stretched line)
SHAPE_IDS = [i for c, i in zip(CASES, IDS)
             if c[0] > 1e-2 and i not in ("slack-piled", "vertical-piled")]


@pytest.mark.parametrize("span, height, length, EA, weight, seabed",
                         [c for c, i in zip(CASES, IDS) if i in SHAPE_IDS], ids=SHAPE_IDS)
def test_catenary_shape_obeys_constitutive_law(span, height, length, EA, weight, seabed):
    """|dr/ds| = 1 + T/EA and the tangent direction is atan2(V, H) along the whole line."""
    sol = an.elastic_catenary(span, height, length, EA, weight, seabed=seabed)
    assert sol.H > 0.0
    ds = 1e-5 * length
    s = np.linspace(2 * ds, length - 2 * ds, 401)
    # central differences are O(ds^2) only where the curvature is smooth: skip the touchdown
    s = s[np.abs(s - sol.grounded_length) > 4 * ds]
    dr = (sol.positions(s + ds) - sol.positions(s - ds)) / (2 * ds)
    # 1e-6: central-difference truncation (ds kappa)^2 with ds = 1e-5 L is far below it;
    # round-off of the positions (1e-16 L / ds = 1e-11) too.
    np.testing.assert_allclose(np.hypot(dr[:, 0], dr[:, 1]), 1.0 + sol.strain(s), rtol=1e-6)
    np.testing.assert_allclose(np.arctan2(dr[:, 1], dr[:, 0]), sol.angle(s), atol=1e-6)


def test_catenary_horizontal_tension_increases_with_span():
    # A positive-definite flexibility: pulling B away raises H, through touchdown and lift-off.
    spans = np.linspace(700.0, 880.0, 61)
    for seabed in (False, True):
        H = [an.elastic_catenary(x, 250.0, 902.2, 3.84243e8, 698.094, seabed=seabed).H
             for x in spans]
        assert np.all(np.diff(H) > 0.0)
    lb = [an.elastic_catenary(x, 250.0, 902.2, 3.84243e8, 698.094, seabed=True)
          .grounded_length for x in spans]
    assert lb[0] > 0.0 and lb[-1] == 0.0  # the sweep crosses lift-off at end A
    assert np.all(np.diff(lb) <= 0.0)


def test_catenary_touchdown_is_continuous():
    # At lift-off the grounded and the free solution coincide (V_a = 0, L_B = 0).
    geo = dict(height=250.0, length=902.2, EA=3.84243e8, weight=698.094)
    lo, hi = 850.0, 880.0
    for _ in range(60):  # bisect on the span where the free solution has V_a = 0
        mid = 0.5 * (lo + hi)
        if an.elastic_catenary(mid, seabed=False, **geo).V_a < 0.0:
            lo = mid
        else:
            hi = mid
    for x in (lo, hi):
        free = an.elastic_catenary(x, seabed=False, **geo)
        ground = an.elastic_catenary(x, seabed=True, **geo)
        # 1e-9: the two solutions differ by O(span bracket / L) ~ 1e-14 plus solver tolerance
        assert ground.H == pytest.approx(free.H, rel=1e-9)
        assert ground.V_b == pytest.approx(free.V_b, rel=1e-9)
        assert ground.grounded_length == pytest.approx(0.0, abs=1e-9 * geo["length"])


def test_catenary_vertical_closed_forms():
    L, EA, w = 99.9, 1.0e7, 10.0
    # U-shaped vertical line: lowest point at s0 = (L + wL^2/(2EA) - z)/(2 + wL/EA)
    z = 50.0
    sol = an.elastic_catenary(0.0, z, L, EA, w)
    s0 = (L + w * L * L / (2 * EA) - z) / (2 + w * L / EA)
    assert sol.H == 0.0
    # 1e-13 relative: closed form, one rounding-level difference in the algebra
    assert sol.V_a == pytest.approx(-w * s0, rel=1e-13)
    low = sol.positions([s0])[0]
    assert low[1] == pytest.approx(-(s0 + w * s0 ** 2 / (2 * EA)), rel=1e-13)
    assert sol.angle([0.0])[0] == pytest.approx(-math.pi / 2)
    assert sol.angle([L])[0] == pytest.approx(math.pi / 2)
    # taut vertical line: V_a = EA (z - L - wL^2/(2EA))/L
    z = 100.0
    sol = an.elastic_catenary(0.0, z, L, EA, w)
    assert sol.V_a == pytest.approx(EA * (z - L - w * L * L / (2 * EA)) / L, rel=1e-12)


def test_catenary_fully_slack_on_seabed():
    L, EA, w, z = 100.0, 1.0e7, 10.0, 20.0
    sol = an.elastic_catenary(60.0, z, L, EA, w, seabed=True)
    # hanging length: z = L_h + w L_h^2/(2 EA) (root written without cancellation)
    l_h = 2.0 * z / (1.0 + math.sqrt(1.0 + 2.0 * z * w / EA))
    assert sol.H == 0.0 and sol.V_a == 0.0
    assert sol.V_b == pytest.approx(w * l_h, rel=1e-12)  # closed form, rounding only
    assert sol.grounded_length == pytest.approx(L - l_h, rel=1e-12)
    p = sol.positions(np.linspace(0.0, L, 101))
    assert np.all(p[:, 0] <= 60.0) and np.all(p[:, 1] >= 0.0)


def test_catenary_flat_on_seabed():
    sol = an.elastic_catenary(100.0, 0.0, 99.0, 1.0e7, 10.0, seabed=True)
    assert sol.H == pytest.approx(1.0e7 * (100.0 / 99.0 - 1.0), rel=1e-12)
    assert sol.grounded_length == 99.0 and sol.V_b == 0.0
    slack = an.elastic_catenary(90.0, 0.0, 99.0, 1.0e7, 10.0, seabed=True)
    assert slack.H == 0.0 and slack.fairlead_tension == 0.0


def test_catenary_rejects_bad_input():
    with pytest.raises(ValueError, match="span"):
        an.elastic_catenary(-1.0, 10.0, 100.0, 1e6, 10.0)
    with pytest.raises(ValueError, match="length"):
        an.elastic_catenary(1.0, 10.0, 0.0, 1e6, 10.0)
    with pytest.raises(ValueError, match="EA"):
        an.elastic_catenary(1.0, 10.0, 100.0, -1e6, 10.0)
    with pytest.raises(ValueError, match="weight"):
        an.elastic_catenary(1.0, 10.0, 100.0, 1e6, 0.0)
    with pytest.raises(ValueError, match="height"):
        an.elastic_catenary(50.0, -10.0, 100.0, 1e6, 10.0, seabed=True)
    sol = an.elastic_catenary(50.0, 10.0, 100.0, 1e6, 10.0)
    with pytest.raises(ValueError, match=r"\[0, L"):
        sol.positions([0.0, 101.0])


def test_catenary_convergence_error_carries_diagnostics():
    with pytest.raises(ConvergenceError) as info:
        an.elastic_catenary(50.0, 10.0, 100.0, 1e8, 100.0, max_iter=1)
    assert info.value.diagnostics  # residual histories of the attempts
    with pytest.raises(ConvergenceError):
        an.elastic_catenary(**OC3, seabed=True, max_iter=1)


# --------------------------------------------------------------------------------------------
# Elastic catenary against MoorPy
# --------------------------------------------------------------------------------------------

def _moorpy(span, height, length, EA, weight, seabed):
    """MoorPy's catenary: CB = 0 is a frictionless seabed at the level of end A, a negative CB
    a seabed that far below A (here 1e6 m: never reached). Returns (H, V_a, V_b, L_B, info)
    in our convention: MoorPy's fAV is V_a (internal force along s, positive up) and
    fBV = -V_b (force on end B)."""
    moorpy_catenary = pytest.importorskip("moorpy.Catenary").catenary
    with contextlib.redirect_stdout(io.StringIO()):
        fAH, fAV, fBH, fBV, info = moorpy_catenary(
            span, height, length, EA, weight, CB=0.0 if seabed else -1.0e6, Tol=1e-10,
            MaxIter=200)
    return fAH, fAV, -fBV, info["LBot"], info


MOORPY_CASES = {
    # name: (span, height, length, EA, weight, seabed)
    "oc3-seabed": (848.67, 250.0, 902.2, 3.84243e8, 698.094, True),
    "taut-1pct-strain": (87.466, 50.5, 100.0, 1.0e6, 10.0, False),
    "deep-sag": (50.0, 10.0, 100.0, 1.0e8, 100.0, False),
    "b-below-a": (300.0, -80.0, 400.0, 1.0e8, 100.0, False),
    "short-grounded-1pct": (95.0, 30.0, 100.0, 1.0e5, 10.0, True),
    "lifted-off-with-seabed": (880.0, 250.0, 902.2, 3.84243e8, 698.094, True),
    "fully-slack-seabed": (60.0, 20.0, 100.0, 1.0e7, 10.0, True),
    "flat-stretched-seabed": (100.0, 0.0, 99.0, 1.0e7, 10.0, True),
}


@pytest.mark.parametrize("name", list(MOORPY_CASES))
def test_catenary_matches_moorpy(name):
    span, height, length, EA, weight, seabed = MOORPY_CASES[name]
    sol = an.elastic_catenary(span, height, length, EA, weight, seabed=seabed)
    H, V_a, V_b, l_bot, info = _moorpy(span, height, length, EA, weight, seabed)
    t_ref = math.hypot(H, V_b)
    # 1e-6 relative: both solve the same equations, MoorPy to an end-position error of
    # 1e-10 m, we to 1e-12 L; 1e-6 is a generous bound for both (observed ~1e-10).
    assert sol.fairlead_tension == pytest.approx(t_ref, rel=1e-6)
    assert sol.H == pytest.approx(H, rel=1e-6, abs=1e-9 * t_ref)
    assert sol.V_b == pytest.approx(V_b, rel=1e-6, abs=1e-9 * t_ref)
    assert sol.V_a == pytest.approx(V_a, rel=1e-6, abs=1e-9 * t_ref)
    assert sol.grounded_length == pytest.approx(l_bot, rel=1e-6, abs=1e-9 * length)


def test_catenary_oc3_reference_values():
    # OC3-Hywind mooring line at its undisplaced position: fairlead tension about 0.91 MN,
    # part of the line on the seabed; MoorPy gives the digits.
    sol = an.elastic_catenary(**OC3, seabed=True)
    H, V_a, V_b, l_bot, info = _moorpy(*OC3.values(), True)
    assert info["ProfileType"] == 2  # touches down, anchor tension H
    assert sol.fairlead_tension == pytest.approx(math.hypot(H, V_b), rel=1e-6)
    assert sol.grounded_length == pytest.approx(l_bot, rel=1e-6)
    assert 0.85e6 < sol.fairlead_tension < 0.95e6
    assert sol.anchor_tension == pytest.approx(sol.H)


@pytest.mark.parametrize("span", [1e-3, 0.0])
def test_catenary_near_vertical_taut_matches_moorpy(span):
    # MoorPy treats span/height < 1e-4 as exactly vertical (H = 0); we solve the catenary for
    # any span >= 1e-9 L, so H is tiny but non-zero there.
    L, EA, w, z = 99.9, 1.0e7, 10.0, 100.0
    sol = an.elastic_catenary(span, z, L, EA, w)
    H, V_a, V_b, _, info = _moorpy(span, z, L, EA, w, False)
    assert info["ProfileType"] == 6
    # 1e-6 relative: H^2/(2 V) and the span's effect on V are ~1e-8 relative here
    assert sol.V_a == pytest.approx(V_a, rel=1e-6)
    assert sol.V_b == pytest.approx(V_b, rel=1e-6)
    assert sol.fairlead_tension == pytest.approx(math.hypot(H, V_b), rel=1e-6)
    # a straight line leaning by span/height carries H ~ T span/height
    assert sol.H <= 2.0 * sol.fairlead_tension * span / z


def test_catenary_vertical_slack_matches_moorpy_magnitudes():
    # U-shaped vertical line. MoorPy's profile 6 returns VA = +w L_A (its other profiles
    # use V_a < 0 for a line leaving A downwards, as we do), so compare magnitudes.
    L, EA, w, z = 99.9, 1.0e7, 10.0, 50.0
    sol = an.elastic_catenary(0.0, z, L, EA, w)
    H, V_a, V_b, _, info = _moorpy(0.0, z, L, EA, w, False)
    assert info["ProfileType"] == 6
    assert sol.V_a < 0.0
    # 1e-12: both evaluate the same closed form
    assert abs(sol.V_a) == pytest.approx(abs(V_a), rel=1e-12)
    assert sol.V_b == pytest.approx(V_b, rel=1e-12)


def test_catenary_random_cases_match_moorpy():
    """A seeded sweep of suspended lines (no seabed) against MoorPy."""
    rng = np.random.default_rng(7)
    compared = 0
    for _ in range(60):
        length = 10.0 ** rng.uniform(1, 3)
        angle = rng.uniform(-1.4, 1.4)
        d = length * rng.uniform(0.3, 1.01)
        span, height = d * math.cos(angle), d * math.sin(angle)
        w = 10.0 ** rng.uniform(0, 3)
        EA = w * length * 10.0 ** rng.uniform(1, 6)
        sol = an.elastic_catenary(span, height, length, EA, w)
        H, V_a, V_b, _, info = _moorpy(span, height, length, EA, w, False)
        if info["ProfileType"] != 1:
            continue  # MoorPy approximated (e.g. its last-resort straight spring)
        compared += 1
        t_ref = math.hypot(H, V_b)
        # 1e-6 relative: as in test_catenary_matches_moorpy (observed 1.4e-12)
        assert sol.fairlead_tension == pytest.approx(t_ref, rel=1e-6)
        assert sol.V_a == pytest.approx(V_a, rel=1e-6, abs=1e-9 * t_ref)
    assert compared >= 50  # the sweep must not be vacuous


# --------------------------------------------------------------------------------------------
# Elastica: cantilever with a dead tip load
# --------------------------------------------------------------------------------------------

def _elastica_bvp(length, EI, load):
    """Tip of the loaded cantilever from scipy's solve_bvp.

    With theta the tangent angle and M = EI theta' the bending moment, the part (s, L] is
    held by the tip force (0, -P), whose moment about r(s) is -P (x_L - x(s)); so
    EI theta' = -P (x_L - x) and, differentiating, EI theta'' = P cos(theta), with
    theta(0) = 0 (clamp) and theta'(L) = 0 (no moment at the tip).
    """
    p = load / EI

    def rhs(s, y):
        theta, kappa, x, z = y
        return np.vstack([kappa, p * np.cos(theta), np.cos(theta), np.sin(theta)])

    def bc(ya, yb):
        return np.array([ya[0], ya[2], ya[3], yb[1]])

    s = np.linspace(0.0, length, 201)
    # linear-theory start: theta = -p (L s - s^2/2)
    theta = -p * (length * s - s ** 2 / 2)
    theta = np.maximum(theta, -1.4)
    y0 = np.vstack([theta, -p * (length - s), s, -p * (length * s ** 2 / 2 - s ** 3 / 6)])
    res = scipy_integrate.solve_bvp(rhs, bc, s, y0, tol=1e-10, max_nodes=200000)
    assert res.success, res.message
    return res.y[2, -1], res.y[3, -1], res.y[0, -1]


@pytest.mark.parametrize("load", [0.2, 1.0, 3.0, 10.0])
def test_elastica_tip_load_matches_bvp(load):
    length, EI = 2.0, 4.0  # P L^2 / EI = load
    ref = an.cantilever_tip_load(length, EI, load)
    x, z, angle = _elastica_bvp(length, EI, load)
    # 1e-6: solve_bvp's collocation tolerance is 1e-10 on the residual; its error in the tip
    # position is well below 1e-6 L, the closed form is accurate to ~1e-14.
    assert ref["x_tip"] == pytest.approx(x, abs=1e-6 * length)
    assert ref["z_tip"] == pytest.approx(z, abs=1e-6 * length)
    assert ref["angle_tip"] == pytest.approx(angle, abs=1e-6)


def test_elastica_classic_table_value():
    # Bisshopp & Drucker (1945) tabulate, for P L^2/EI = 1, a tip deflection of 0.3017 L and a
    # horizontal tip displacement of 0.0564 L (4 digits); the BVP test checks further digits.
    ref = an.cantilever_tip_load(1.0, 1.0, 1.0)
    assert ref["z_tip"] == pytest.approx(-0.3017, abs=1e-4)  # the table's last digit
    assert 1.0 - ref["x_tip"] == pytest.approx(0.0564, abs=1e-4)


def test_elastica_small_loads_approach_linear_theory():
    length, EI = 3.0, 2.0
    errs = []
    for lam2 in (1e-1, 1e-2, 1e-3, 1e-4, 1e-6):
        load = lam2 * EI / length ** 2
        ref = an.cantilever_tip_load(length, EI, load)
        lin = an.cantilever_tip_load_small(length, EI, load)
        assert lin == pytest.approx(load * length ** 3 / (3 * EI), rel=1e-15)
        ratio = -ref["z_tip"] / lin
        errs.append(abs(ratio - 1.0))
        # the first nonlinear correction is ~0.11 (P L^2/EI)^2 (observed); bound it by 0.2
        # of that plus 1e-12 for the round-off of the closed form
        assert abs(ratio - 1.0) <= 0.2 * lam2 ** 2 + 1e-12
        # tip angle: linear theory P L^2/(2 EI), same order of correction
        assert -ref["angle_tip"] == pytest.approx(lam2 / 2, rel=0.2 * lam2 + 1e-12)
    assert errs == sorted(errs, reverse=True)


def test_elastica_extremes():
    assert an.cantilever_tip_load(1.0, 1.0, 0.0) == {"x_tip": 1.0, "z_tip": 0.0,
                                                     "angle_tip": 0.0}
    big = an.cantilever_tip_load(1.0, 1.0, 1.0e4)
    # a very heavy tip load pulls the beam nearly vertical: angle -> -pi/2,
    # x_tip = sqrt(2 EI/P) sqrt(sin alpha) -> sqrt(2/P)
    assert big["angle_tip"] == pytest.approx(-math.pi / 2, abs=1e-12)
    assert big["x_tip"] == pytest.approx(math.sqrt(2.0e-4), rel=1e-12)
    assert -1.0 < big["z_tip"] < -0.99
    with pytest.raises(ValueError):
        an.cantilever_tip_load(1.0, 1.0, -1.0)


def test_heavy_cantilever_small_matches_integrated_linear_beam():
    length, EI, w = 2.5, 7.0, 3.0
    # linear beam: EI theta'(s) = M(s) = -w (L - s)^2 / 2, theta(0) = 0; deflection = -int theta
    theta = lambda s: -w * (length ** 3 - (length - s) ** 3) / (6 * EI)  # noqa: E731
    delta, _ = scipy_integrate.quad(lambda s: -theta(s), 0.0, length, epsabs=1e-14)
    # 1e-12: quad integrates a cubic exactly up to round-off
    assert an.heavy_cantilever_small(length, EI, w) == pytest.approx(delta, rel=1e-12)
    assert an.heavy_cantilever_small(length, EI, w) == pytest.approx(w * length ** 4 / (8 * EI))


def test_greenhill_moment_limits_and_scaling():
    """Greenhill's clamped rod: as T -> 0, M_cr L / B -> 8.98682 (the tensionless value,
    2.861 pi; at T L^2 / B = 0.01 the tension adds 1.6e-4 of it, so 3e-4); at high tension
    M_cr -> 2 sqrt(B T) from above (the infinite rod's criterion, approached as the rod
    grows long against sqrt(B / T): within 5 % at T L^2 / B = 1e4); M_cr scales as B / L at
    fixed T L^2 / B. Bad input is refused."""
    assert an.greenhill_moment(1.0, 1.0, 0.01) == pytest.approx(8.98682, rel=3e-4)
    m = an.greenhill_moment(1.0, 1.0, 1e4)
    assert 2.0 * math.sqrt(1e4) < m < 1.05 * 2.0 * math.sqrt(1e4)
    assert an.greenhill_moment(3.0, 2.0, 10.0 * 3.0 / 4.0) == \
        pytest.approx(an.greenhill_moment(1.0, 1.0, 10.0) * 3.0 / 2.0, rel=1e-9)
    with pytest.raises(ValueError, match="B, L, T > 0"):
        an.greenhill_moment(1.0, 1.0, 0.0)
