"""Physics terms as small functions of CasADi (or NumPy) expressions.

Each returns a force, moment or load per unstretched length in SI units. Formulations
call only the ones their scene needs, and record their names in ``Model.terms``.
"""
from __future__ import annotations

import casadi as ca


def axial_force(EA, strain):
    """Axial (tangential) internal force T = EA * strain, N."""
    return EA * strain


def cable_axial_force(EA, strain, delta, EA_slack, F_wall, w_wall):
    """Axial force of a cable, which does not push, N: T = EA e in tension; in compression
    only a residual ``EA_slack`` e (``EA_slack`` in N per unit strain, a tiny fraction of
    EA: the resistance of a slack chain bunching up, which keeps a slack line's shape
    determined), and a wall that keeps every segment's length positive: a compression
    ``F_wall`` exp(-(1 + e) / w_wall) (N), negligible until the segment has bunched to a few
    ``w_wall`` of its length, then steep (finite everywhere, so a Newton iterate that
    crosses e = -1 meets a large restoring force rather than a pole); the corner at e = 0
    smoothed over a strain width ``delta`` (C-infinity, so Newton keeps its quadratic
    convergence):

        T = EA_slack e + (EA - EA_slack) (e + sqrt(e^2 + delta^2)) / 2
            - F_wall exp(-(1 + e) / w_wall)

    Exact to a relative (delta / 2 e)^2 + EA_slack / EA in tension; EA delta / 2 at e = 0."""
    return (EA_slack * strain + (EA - EA_slack) * smooth_ramp(strain, delta)
            - F_wall * ca.exp(-(1.0 + strain) / w_wall))


def bending_moment(EI, curvature):
    """Bending moment M = EI * kappa, N m (kappa in rad per unstretched metre)."""
    return EI * curvature


def shear_from_moments(M_start, M_end, ds, strain):
    """Shear force on a segment from moment balance, N.

    The segment (unstretched length ``ds``, stretch ``1 + strain``) carries end moments
    ``M_start`` and ``M_end``; balancing moments, dM/ds + (1 + strain) Q = 0, gives
    Q = -(M_end - M_start) / (ds (1 + strain)).
    """
    return -(M_end - M_start) / (ds * (1.0 + strain))


def submerged_weight(w):
    """Weight-and-buoyancy load per unstretched length, N/m, as (f_x, f_z)."""
    return 0.0, -w


def morison_drag(rho, diameter, cd_n, cd_t, u_t, u_n, strain):
    """Morison drag per unstretched length on a line element, N/m, as (f_t, f_n).

    ``u_t``, ``u_n`` are the tangential and normal components of the velocity of the water
    relative to the line (m/s). As in Boral, Hickey & Basu (cited in :mod:`symcable.models.planar.model`)
    the projected diameter times stretched length scales with sqrt(1 + strain) (constant
    volume): f = 0.5 rho d Cd |u| u sqrt(1+e).
    """
    stretch = ca.sqrt(1.0 + strain)
    f_t = 0.5 * rho * diameter * cd_t * ca.fabs(u_t) * u_t * stretch
    f_n = 0.5 * rho * diameter * cd_n * ca.fabs(u_n) * u_n * stretch
    return f_t, f_n


def smooth_ramp(x, delta):
    """max(x, 0) smoothed over a width ``delta`` (same units as x): C-infinity, exact far
    from zero, value delta/2 at x = 0."""
    return 0.5 * (x + ca.sqrt(x * x + delta * delta))


def seabed_contact(stiffness, diameter, seabed_z, z, delta):
    """Upward seabed contact force per unstretched length, N/m.

    Penalty contact: pressure ``stiffness * penetration`` (Pa) over the contact width
    ``diameter``; penetration = seabed_z - z, smoothed over ``delta`` m.
    """
    return stiffness * diameter * smooth_ramp(seabed_z - z, delta)


def contact_smoothing(weight, stiffness, diameter, fraction=0.01):
    """Smoothing width of the contact ramp, m: ``fraction`` of the penetration under the
    line's own weight (so the touchdown point moves by far less than a segment; 1 % for the
    planar line, :data:`~symcable.models.common.seabed.CONTACT_SMOOTHING` for the 3D lines), with
    a floor."""
    return max(fraction * abs(weight) / (stiffness * diameter), 1e-6)


def tangent(phi):
    """Unit tangent (cos phi, sin phi) and normal (-sin phi, cos phi) of angle phi."""
    c, s = ca.cos(phi), ca.sin(phi)
    return (c, s), (-s, c)


def fluid_term_names(sections, rho: float) -> list:
    """The fluid terms a line's equations of motion build, by name: ``"drag"`` (Morison, on
    the line's velocity relative to the water: in statics only a current's) where a section
    has a drag coefficient, ``"added mass"`` where one has an added-mass coefficient; none
    in air (``rho`` = 0, kg/m^3)."""
    if rho <= 0:
        return []
    types = [s.line_type for s in sections]
    return ((["drag"] if any(t.cd_normal > 0 or t.cd_tangential > 0 for t in types) else [])
            + (["added mass"] if any(t.ca_normal > 0 or (t.ca_tangential or 0) > 0
                                     for t in types) else []))
