"""A planar line resting on the seabed: its dynamics run as the 3D cable in its plane.

The linearised planar dynamics (seed 001's model) have no seabed contact. A planar scene whose
static line rests on the seabed runs ``simulate``, ``solve_periodic``, ``modal_analysis`` and
``linearize`` through the same line as a ``model = "cable3d"`` scene in the x-z plane
(``symcable.models.planar.in_plane.as_cable3d``), with a ``ModelNote`` saying so.
"""
from __future__ import annotations

import warnings

import numpy as np
import pytest

import symcable as sc
from symcable.models.planar.in_plane import as_cable3d


def _oc3(segments: int = 20) -> dict:
    """The built-in OC3 scene (planar, 135 m on the seabed) with fewer segments."""
    d = sc.load_scene("oc3").to_dict()
    d["sections"][0]["segments"] = segments
    return d


def test_the_stand_in_is_the_same_line_in_its_plane():
    """The stand-in's static state is the planar solve's: the two formulations discretise
    the same elastic catenary on the same segments (the planar one by segment angles and
    strains, the 3D one by node positions), so they agree to the discretisation: measured
    2.3e-5 relative in the fairlead tension and 1.4 mm in positions on OC3's 50 segments;
    bounds 1e-4 and 1 cm. Every y is exactly 0."""
    scene = sc.load_scene("oc3")
    planar, lifted = sc.solve_static(scene), sc.solve_static(as_cable3d(scene))
    assert lifted.fairlead_tension == pytest.approx(planar.fairlead_tension, rel=1e-4)
    assert lifted.grounded_length == pytest.approx(planar.grounded_length, abs=0.1)
    X = np.asarray(lifted.positions)
    assert np.all(X[:, 1] == 0.0)
    assert np.max(np.abs(X[:, [0, 2]] - np.asarray(planar.positions))) < 0.01


@pytest.mark.parametrize("analysis", ["simulate", "periodic", "modes", "linearize"])
def test_a_grounded_planar_line_runs_its_stand_in_with_a_note(analysis):
    """Each dynamic analysis of the grounded planar line gives the stand-in's own answer,
    exactly (the same path on the same scene), and says so in one ModelNote."""
    planar, lifted = _oc3(), as_cable3d(sc.load_scene(_oc3()))
    run = {"simulate": lambda s: sc.simulate(s, 4.0, dt=0.2),
           "periodic": lambda s: sc.solve_periodic(s, steps=40),
           "modes": lambda s: sc.modal_analysis(s, 3),
           "linearize": lambda s: sc.linearize(s)}[analysis]
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        got = run(planar)
    notes = [w for w in caught if issubclass(w.category, sc.ModelNote)]
    assert len(notes) == 1 and "in its plane" in str(notes[0].message)
    with warnings.catch_warnings():
        warnings.simplefilter("error", sc.ModelNote)
        want = run(lifted)
    key = {"simulate": "fairlead_tension", "periodic": "fairlead_tension",
           "modes": "frequencies", "linearize": "K"}[analysis]
    np.testing.assert_array_equal(np.asarray(getattr(got, key)), np.asarray(getattr(want, key)))


def test_a_suspended_planar_line_stays_linearised():
    """seed 001's line hangs clear of the seabed: its dynamics stay the linearised planar
    model (its Trajectory, not the 3D cable's LineTrajectory; no note)."""
    d = sc.load_scene("seed001").to_dict()
    d["sections"][0]["segments"] = 10
    with warnings.catch_warnings():
        warnings.simplefilter("error", sc.ModelNote)
        traj = sc.simulate(d, 2.0, dt=0.1)
    assert isinstance(traj, sc.Trajectory) and not isinstance(traj, sc.LineTrajectory)


def test_a_clamped_planar_end_has_no_stand_in():
    """The 3D cable takes a clamped end's tangent as a direction, not an angle: the
    conversion refuses it in one line naming the key and the fix."""
    d = _oc3()
    d["end_a"] = {"condition": "clamped", "position": d["end_a"]["position"], "angle_deg": 0.0}
    d["line_types"]["chain"]["EI"] = 1e3
    with pytest.raises(sc.SceneError, match=r"end_a\.angle_deg = 0\.0 deg.*direction"):
        as_cable3d(sc.load_scene(d))


@pytest.mark.parametrize("name", ["seed001", "seed000_rod", "sphere", "towed_body"])
def test_build_mechanism_for_every_formulation(name):
    """sc.build_mechanism gives any scene's static Mechanism (planar, rod, a scene of points
    and bodies), built once per content; the generic solver finds the same state as
    sc.solve_static (its fairlead tension to the solve's tolerance, 1e-6 relative)."""
    mech = sc.build_mechanism(name)
    assert sc.build_mechanism(name) is mech
    eq = sc.solve_equilibrium(mech)
    assert eq.status == "converged" and eq.q.shape == (mech.n_q,)
