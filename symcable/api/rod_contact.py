"""Self-contact of a rod shape, *reported, not modelled*: the least distance between the
centre lines of two segments that are not neighbours along the rod, against the cable's
diameter.

symcable's rod (``model = "rod"``, ``"hybrid"``) has no contact between its own segments: a
loop that closes passes through itself and the solvers do not notice. This module only tells
when a solution has done so (or come within ``diameter`` of it), so that a looped shape is
read for what it is: valid up to first contact. What contact would still need: detection between segment pairs (the closest points below, with a
spatial hash or bounding boxes beyond a few hundred segments), a force (a penalty energy
k/2 (d - g)^2 for g < d, or a unilateral constraint g >= d with a multiplier carried in z
and a complementarity solver), friction between the strands (the seabed's regularised or
bristle law, per contact pair), and its place in the energy: the penalty is a function of
the two segments' four nodes, so it enters the Mechanism's potential as any element does,
but its pairs change with the shape (a sparsity pattern that is not the line's band).

Layer: results (geometry on positions; no solver).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..errors import SymcableError

__all__ = ["SelfContact", "self_contact", "segment_distances", "writhe"]


@dataclass(frozen=True)
class SelfContact:
    """The closest pair of non-neighbouring segments of a rod shape
    (:func:`self_contact`'s answer).

    Attributes
    ----------
    min_distance : float
        m, least distance between their centre lines (inf: no pair).
    pair : (int, int)
        The two segments (0-based, i < j); (-1, -1) without a pair.
    points : ndarray (2, 3)
        m, the closest points on each (NaN without a pair).
    s : (float, float)
        m, their arc lengths along the polyline from its first node (NaN without a pair).
    diameter : float
        m, the cable's diameter the distance is compared with.
    skip : int
        Segments i, j with j - i <= skip were not compared.
    contact : bool
        min_distance < diameter: the shape passes into itself.
    gap : float
        m, min_distance - diameter (negative: interpenetration; inf without a pair).
    """

    min_distance: float
    pair: tuple
    points: np.ndarray
    s: tuple
    diameter: float
    skip: int
    contact: bool
    gap: float


def segment_distances(P0, P1, Q0, Q1):
    """Least distance between segments [P0, P1] and [Q0, Q1] (arrays (..., 3), m), pairwise
    over the leading axes: ``(d, u, v)``, d in m, u and v in [0, 1] the closest points'
    fractions along each (Ericson, Real-Time Collision Detection, 5.1.9)."""
    d1, d2, r = P1 - P0, Q1 - Q0, P0 - Q0
    a, e = np.sum(d1 * d1, -1), np.sum(d2 * d2, -1)
    b, c, f = np.sum(d1 * d2, -1), np.sum(d1 * r, -1), np.sum(d2 * r, -1)
    den = a * e - b * b
    tiny = 1e-300
    # u on the infinite lines (parallel segments: u = 0), then clamped and v from it
    u = np.where(den > 1e-12 * a * e, (b * f - c * e) / np.maximum(den, tiny), 0.0)
    u = np.clip(u, 0.0, 1.0)
    v = (b * u + f) / np.maximum(e, tiny)
    v_cl = np.clip(v, 0.0, 1.0)
    u = np.where(v != v_cl, np.clip((b * v_cl - c) / np.maximum(a, tiny), 0.0, 1.0), u)
    v = v_cl
    gap = (P0 + u[..., None] * d1) - (Q0 + v[..., None] * d2)
    return np.linalg.norm(gap, axis=-1), u, v


def writhe(positions, axis=None, extension: float = 1e3) -> float:
    """The writhe Wr (turns) of the polyline ``positions`` (n_nodes, 3; m), its ends
    extended by straight segments ``extension`` times its length along ``axis`` (a unit
    vector; default the chord from its first node to its last): the closure of a rod whose
    ends are clamped on one axis, so that its end rotation is 2 pi (Tw + Wr) (Calugareanu,
    White, Fuller). The double sum of the Gauss integral over segment pairs, each the signed
    solid angle of Klenin & Langowski (Biopolymers 54, 2000), n^2 / 2 pairs.

    Without contact a rod may pass through itself: Wr then jumps by 2 at once (the link
    changes by 2 when one strand crosses another), which the twist cannot follow. A jump
    of 2 between two states of a continuation says the shape crossed itself in between."""
    X = np.asarray(positions, dtype=float)
    if X.ndim != 2 or X.shape[1] != 3 or X.shape[0] < 2 or not np.all(np.isfinite(X)):
        raise SymcableError(f"positions: an (n_nodes >= 2, 3) array of finite node positions "
                            f"in m is needed, got shape {X.shape}")
    length = float(np.sum(np.linalg.norm(np.diff(X, axis=0), axis=1)))
    e = X[-1] - X[0] if axis is None else np.asarray(axis, float)
    if np.linalg.norm(e) == 0 or not np.all(np.isfinite(e)):
        raise SymcableError(f"axis = {axis!r}: a nonzero direction is needed (the chord is "
                            "zero: give the clamps' axis)")
    e = e / np.linalg.norm(e)
    X = np.vstack([X[0] - extension * length * e, X, X[-1] + extension * length * e])
    i, j = np.triu_indices(X.shape[0] - 1, k=2)
    p1, p2, p3, p4 = X[i], X[i + 1], X[j], X[j + 1]
    r13, r14, r23, r24 = p3 - p1, p4 - p1, p3 - p2, p4 - p2

    def unit(v):
        n = np.linalg.norm(v, axis=1, keepdims=True)
        return np.divide(v, n, out=np.zeros_like(v), where=n > 0)
    n1, n2 = unit(np.cross(r13, r14)), unit(np.cross(r14, r24))
    n3, n4 = unit(np.cross(r24, r23)), unit(np.cross(r23, r13))
    dots = [np.clip(np.sum(a * b, axis=1), -1.0, 1.0) for a, b in
            ((n1, n2), (n2, n3), (n3, n4), (n4, n1))]
    omega = sum(np.arcsin(d) for d in dots)
    sign = np.sign(np.sum(np.cross(p4 - p3, p2 - p1) * r13, axis=1))
    return float(2.0 * np.sum(omega * sign) / (4.0 * math.pi))


def self_contact(positions, diameter: float, *, skip: int | None = None) -> SelfContact:
    """The closest pair of segments of the polyline ``positions`` that are more than
    ``skip`` segments apart, and whether it is closer than ``diameter``.

    Parameters
    ----------
    positions : array (n_nodes, 3)
        m, the rod's nodes in order (a solution's ``positions``).
    diameter : float
        m, the cable's outer diameter (> 0): two centre lines closer than this touch.
    skip : int, optional
        Segment pairs with j - i <= skip are neighbours, not compared (>= 1). Default: the
        segments within half a turn of the tightest bend a rod of this diameter can make
        (radius diameter / 2: an arc of pi diameter / 2 between them), at least 1.

    Returns
    -------
    SelfContact
        ``contact`` True where the shape has passed into itself, which the rod does not
        prevent (self-contact is not modelled; module docstring).

    Raises
    ------
    SymcableError
        positions not (n >= 2, 3) and finite, diameter not > 0, skip not an int >= 1.
    """
    X = np.asarray(positions, dtype=float)
    if X.ndim != 2 or X.shape[1] != 3 or X.shape[0] < 2 or not np.all(np.isfinite(X)):
        raise SymcableError(f"positions: an (n_nodes >= 2, 3) array of finite node positions "
                            f"in m is needed, got shape {X.shape}")
    if not (isinstance(diameter, (int, float, np.floating)) and math.isfinite(diameter)
            and diameter > 0):
        raise SymcableError(f"diameter = {diameter!r} m: must be a number > 0")
    seg = np.diff(X, axis=0)
    ds = np.linalg.norm(seg, axis=1)
    if skip is None:
        skip = max(1, int(math.ceil(0.5 * math.pi * diameter / max(float(np.min(ds)), 1e-300))))
    elif not isinstance(skip, (int, np.integer)) or isinstance(skip, bool) or skip < 1:
        raise SymcableError(f"skip = {skip!r}: must be an integer >= 1 (1 compares every "
                            "pair but neighbours)")
    n = seg.shape[0]
    i, j = np.triu_indices(n, k=int(skip) + 1)
    s0 = np.concatenate([[0.0], np.cumsum(ds)])
    if i.size == 0:
        return SelfContact(math.inf, (-1, -1), np.full((2, 3), np.nan), (math.nan, math.nan),
                           float(diameter), int(skip), False, math.inf)
    d, u, v = segment_distances(X[i], X[i + 1], X[j], X[j + 1])
    k = int(np.argmin(d))
    a, b = int(i[k]), int(j[k])
    pts = np.array([X[a] + u[k] * seg[a], X[b] + v[k] * seg[b]])
    dmin = float(d[k])
    s_ab = (float(s0[a] + u[k] * ds[a]), float(s0[b] + v[k] * ds[b]))
    return SelfContact(dmin, (a, b), pts, s_ab,
                       float(diameter), int(skip), dmin < diameter, dmin - float(diameter))
