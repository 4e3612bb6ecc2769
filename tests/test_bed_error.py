"""The penalty seabed's effect on a static answer (symcable.api.bed_error, issue 33).

A line lying on the penalty bed sinks w / (k d) into it; a rigid-bed code (MoorPy) puts it
at z = -depth. The fuzz study found 3D answers 3-20 % off MoorPy on soft beds
(k = 1e4 Pa/m: a chain sinks 2 m), every one "converged" with no word. Now each answer whose
lines touch the bed carries ``stats["seabed_error"]``: per line the end tensions' distance
from a rigid bed's, extrapolated at first order in the sinking (cable3d, rod, hybrid: the
exact derivative with respect to the bed's stiffness scale; planar: a solve at 4 k), with a
warning above 1 % naming the stiffness that would bring it under.

The OC3 line (200 segments, its discretisation error 3-16 N) against MoorPy's catenary on a
rigid bed, at k = 1e5 (the default: sinks 0.078 m), 1e4 and 3e3 Pa/m (2.6 m): the true
distance is 342 N to 11.3 kN; the estimate read 0.91 to 1.22 of it, planar and cable3d
(measured). The tolerance asked is the issue's factor of 3, tightened to [0.7, 1.4]: an
estimate outside that would be a different method, not noise.
"""
from __future__ import annotations

import numpy as np
import pytest

import symcable as sc

from test_grounded_fine import _oc3


@pytest.fixture(scope="module")
def rigid():
    """MoorPy's catenary of the OC3 line on its rigid bed: (T_anchor, T_fairlead), N."""
    from moorpy.Catenary import catenary
    fAH, fAV, fBH, fBV, _ = catenary(848.67, 250.0, 902.2, 3.84243e8, 698.094, CB=0.0)
    return float(np.hypot(fAH, fAV)), float(np.hypot(fBH, fBV))


@pytest.mark.parametrize("model", ["planar", "cable3d"])
@pytest.mark.parametrize("stiffness", [1e5, 1e4, 3e3])
def test_seabed_estimate_tracks_the_distance_from_a_rigid_bed(rigid, model, stiffness):
    st = sc.solve_static(_oc3(200, model=model, stiffness=stiffness))
    rep = st.stats["seabed_error"]
    e = rep["lines"]["line"]
    true = max(abs(st.anchor_tension - rigid[0]), abs(st.fairlead_tension - rigid[1]))
    # what the discretisation leaves (at most 16 N here) is far below what is compared
    assert st.stats["discretisation_error"]["lines"]["line"]["error"] < 0.05 * true
    assert 0.7 < e["error"] / true < 1.4, (e, true)
    assert e["sinking"] == pytest.approx(698.094 / (stiffness * 0.09), rel=1e-3)
    assert e["relative"] == pytest.approx(e["error"] / st.fairlead_tension, rel=1e-6)
    warned = [w for w in st.warnings if "penalty seabed" in w]
    if e["relative"] > 0.01:  # k = 3e3: 1.2 %
        assert len(warned) == 1 and "seabed.stiffness = " in warned[0], st.warnings
        need = float(warned[0].split("seabed.stiffness = ")[1].split(" Pa/m")[0])
        assert need > stiffness
    else:
        assert not warned
    assert "seabed" in st.summary()


def test_the_two_methods_agree_on_a_3d_line():
    """The exact derivative (cable3d) and the Richardson step from an actual solve at 4 k (the
    same scene's cable3d answer at 4e4 Pa/m) give the same rigid-bed distance within 15 %
    (first order in the sinking, 0.78 m here: the derivative reads the slope at k, the step
    a secant; at 1e3 Pa/m, a 7.8 m sinking, they part by 23 %)."""
    soft = sc.solve_static(_oc3(100, model="cable3d", stiffness=1e4))
    stiff = sc.solve_static(_oc3(100, model="cable3d", stiffness=4e4), estimate=False)
    step = 4.0 / 3.0 * max(abs(soft.anchor_tension - stiff.anchor_tension),
                           abs(soft.fairlead_tension - stiff.fairlead_tension))
    slope = soft.stats["seabed_error"]["lines"]["line"]["error"]
    assert slope == pytest.approx(step, rel=0.15)


def test_no_seabed_estimate_where_no_line_touches_the_bed():
    """A taut line clear of the bed, and a scene without a seabed: no report, no warning,
    no cost."""
    d = _oc3(50, model="cable3d")
    d["environment"]["depth"] = 500.0  # the bed 180 m below the anchor
    st = sc.solve_static(d)
    # the contact ramp's smooth tail: a trace, 1.4e-8 of the tension (measured)
    assert float(np.max(st.contact_force)) < 1e-6 * st.fairlead_tension
    assert "seabed_error" not in st.stats
    d.pop("seabed")
    d["environment"].pop("depth")
    assert "seabed_error" not in sc.solve_static(d).stats
