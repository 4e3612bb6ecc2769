"""Large models build and solve (the cost against segments is measured in
studies/performance/scaling.py, never asserted here)."""
from __future__ import annotations

import pytest

import symcable as sc
from symcable.analytic import elastic_catenary
from symcable.mechanism.static_functions import SXLU_MAX_UNKNOWNS

from conftest import two_point


def test_2000_segment_catenary_matches_closed_form():
    """A 2000-segment line (7998 unknowns: the sparse-QR Newton step, not the written-out
    block LU) solves in the virtual machine by plain Newton, and its end tensions meet the
    closed-form elastic catenary within the discretisation error: second order, about 1e-4
    at 50 segments (test_planar_static), so (50/2000)^2 1e-4 ~ 1e-7 here; asserted at 1e-6."""
    a, b, L, EA, w = (0.0, 0.0), (70.0, -40.0), 100.0, 1e7, 100.0
    st = sc.solve_static(two_point(a, b, length=L, EA=EA, weight=w, segments=2000), codegen=False)
    assert st.status == "converged" and st.stats["path"] == "newton"
    assert st.stats["unknowns"] == 4 * 2000 - 2 > SXLU_MAX_UNKNOWNS
    assert not st.stats["compiled"]
    ref = elastic_catenary(b[0] - a[0], b[1] - a[1], L, EA, w)
    assert st.fairlead_tension == pytest.approx(ref.fairlead_tension, rel=1e-6)
    assert st.anchor_tension == pytest.approx(ref.anchor_tension, rel=1e-6)
