"""A clump resting on the seabed, a chain lying on the bed up to it on both sides (issue 33):
the lines' force on the clump is their tension there, the end segments' axial pull, at every
segment count.

Before, the line's contact at the end node it shares with the clump was switched on by a
smooth step of the clump's penetration about zero, as wide as the line's contact smoothing
(a tenth of the chain's penetration under its own weight, sink = w / (k d)); the clump's own
contact is far stiffer, so at rest it pressed in only about 1.1 of that width, the step was
0.87, and the clump's contact carried the other 13 % of each end half segment's weight. That
was reported as the line pulling the clump down: here 767, 396, 202 N by the upper line and
1534, 792, 403 N by the lower at 10, 20, 40 segments each (0.13 of the 15, 7.5, 3.75 m and
30, 15, 7.5 m segments' half weight, halving with each doubling; the clump's "force" 2300,
1188, 604 N) for an end segment's axial force of 164, 146, 127 N; MoorPy's catenary end
tension is 72 N (horizontal), which the lumped chain approaches slowly (108, 94 N at 80, 160
segments: the nearly vertical chain's touchdown bend, 0.1 m in radius, lies within a
segment), so the test compares with the line's own end segment.

Now the factor is 1 to 4e-9 while the clump lies on the bed (its switch is at sink above the
bed, seabed.joined_on, as a held end's), and each line's end force is its end segment's
axial force: within 0.01 % in magnitude (measured at most 1e-6 relative), and horizontal but
for the end segment's slope into the penalty bed: the clump's node sits dz <= sink = 5.35 mm
above the sunk chain beside it, so the pull has T dz / ds downward, and the half segment's
contact, half the neighbour's, is short by half of the neighbour's share of that:
|F_z| = 1.5 T dz / ds <= 2 T sink / ds (measured 0.078, 0.14, 0.24 N on the upper line, half
that on the lower; 0 on a rigid bed). The clump rises by 3e-5 m (its own contact no longer
carries 13 % of two half segments' weight) and moves 5e-9 m sideways."""
from __future__ import annotations

import math

import numpy as np
import pytest

import symcable as sc

RHO, G = 1025.0, 9.80665
MASS, D, EA, K = 100.0, 0.15, 7.5e8, 1e6
W = (MASS - RHO * math.pi * D * D / 4) * G  # submerged weight, N/m
SINK = W / (K * D)  # the chain's penetration under its own weight, m


def _scene(n: int) -> dict:
    """A 300 m chain from an anchor on the bed to a 5 t clump, a 150 m chain from the clump up
    to a fixed point 90 m above the bed and 60.6 m beyond the clump, no seabed friction: the
    upper chain lies 60 m on the bed and hangs nearly vertical, so the tension along the bed
    is small (MoorPy: 72 N; the lumped chain 164 to 127 N at 10 to 40 segments)."""
    return {"model": "cable3d", "environment": {"depth": 100.0}, "seabed": {"stiffness": K},
            "line_types": {"chain": {"mass": MASS, "diameter": D, "EA": EA}},
            "points": {"anchor": {"kind": "fixed", "position": [-300.0, 0.0, -100.0]},
                       "clump": {"kind": "free", "position": [0.0, 0.0, -100.0],
                                 "mass": 5000.0, "volume": 0.6},
                       "fairlead": {"kind": "fixed", "position": [60.6, 0.0, -10.0]}},
            "lines": [{"name": "lower", "end_a": "anchor", "end_b": "clump",
                       "sections": [{"type": "chain", "length": 300.0, "segments": n}]},
                      {"name": "upper", "end_a": "clump", "end_b": "fairlead",
                       "sections": [{"type": "chain", "length": 150.0, "segments": n}]}]}


@pytest.mark.parametrize("n", [10, 20, 40])
def test_line_force_on_a_clump_on_the_bed_is_the_end_tension(n):
    st = sc.solve_static(_scene(n))
    assert st.status == "converged"
    clump = st.points["clump"]
    assert -100.0 - SINK <= clump.position[2] <= -100.0  # resting on the bed
    ends = {"lower": (st.lines["lower"].fairlead_force, st.lines["lower"].axial_force[-1]),
            "upper": (st.lines["upper"].anchor_force, st.lines["upper"].axial_force[0])}
    ds = {"lower": 300.0 / n, "upper": 150.0 / n}
    for name, (force, T) in ends.items():
        assert 10.0 < T < 1000.0  # small: the chain lies on the bed at the clump
        # the end force is the end segment's pull (before, |F| was 9.4 to 1.9 times T)
        assert np.linalg.norm(force) == pytest.approx(T, rel=1e-4)
        # horizontal but for the end segment's slope from the sunk chain up to the clump's
        # node (module docstring; before: hundreds of N down, a share of the half segment's
        # weight)
        assert abs(force[2]) <= 2 * T * SINK / ds[name]
    # the lines' force on the clump: their pulls, which balance on a frictionless bed; the
    # seabed carries the clump's own weight, its contact none of the chain's
    T = max(T for _, T in ends.values())
    assert np.linalg.norm(clump.force) <= 4 * T * SINK / ds["upper"]  # before: 2300, 1188, 604 N
    np.testing.assert_allclose(clump.force, ends["lower"][0] + ends["upper"][0], atol=1e-9)
    assert np.max(np.abs(clump.net_force)) < 10 * st.stats["tolerance"]


def test_joined_on_factor():
    """The joined end's on-off factor: 1 (to 4e-9) on the bed and in it, 0.5 at the line's
    sink above it, 0 (to 4e-9) two sinks above it; increasing."""
    import casadi as ca

    from symcable.models.common.seabed import joined_on
    width = 0.1 * SINK
    pen = ca.SX.sym("pen")
    f = ca.Function("on", [pen], [joined_on(pen, SINK, width)])
    assert float(f(0.0)) == pytest.approx(1.0, abs=1e-8)
    assert float(f(0.5 * SINK)) == pytest.approx(1.0, abs=1e-8)
    assert float(f(-SINK)) == pytest.approx(0.5, abs=1e-12)
    assert float(f(-2.0 * SINK)) == pytest.approx(0.0, abs=1e-8)
    values = [float(f(x)) for x in np.linspace(-3 * SINK, SINK, 41)]
    assert np.all(np.diff(values) >= 0.0)
