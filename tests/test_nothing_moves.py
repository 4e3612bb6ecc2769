"""A 3D line of one segment between two held ends has no moving node: its dynamic analyses
refuse in one line (no internal error), its statics and linearisation still answer."""
from __future__ import annotations

import pytest

import symcable as sc

SCENE = {"name": "one segment", "model": "cable3d", "environment": {"depth": 100.0},
         "line_types": {"w": {"EA": 1e6, "mass": 1.0, "diameter": 0.01}},
         "sections": [{"type": "w", "length": 50.0, "segments": 1}],
         "end_a": {"condition": "pinned", "position": [0.0, 0.0, -60.0]},
         "end_b": {"condition": "pinned", "position": [40.0, 0.0, -30.0],
                   "motion": {"kind": "harmonic", "period": 10.0,
                              "amplitude": [1.0, 0.0, 0.0]}}}


@pytest.mark.parametrize("run", [lambda s: sc.simulate(s, 5.0), lambda s: sc.solve_periodic(s),
                                 lambda s: sc.modal_analysis(s, 2)],
                         ids=["simulate", "periodic", "modes"])
def test_dynamics_refuse_in_one_line(run):
    with pytest.raises(sc.SymcableError, match="nothing moves") as info:
        run(SCENE)
    assert "\n" not in str(info.value)


def test_statics_and_stiffness_still_answer():
    """The segment at rest: solved, its end stiffness a 3 x 3 matrix, its linearisation of
    no unknowns (nothing to integrate, and nothing refused)."""
    st = sc.solve_static(SCENE)
    assert st.status == "converged"
    K = sc.end_stiffness(SCENE, "b")
    assert K.shape == (3, 3)
    assert sc.linearize(SCENE).K.shape == (0, 0)
