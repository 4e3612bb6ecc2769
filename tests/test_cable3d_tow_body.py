"""A heavy, dragging body towed on a cable (issue 13, item 2): symcable's steady tow (the
static problem in the frame moving with the towpoint, the start of ``simulate``) against
the steady-tow ODEs integrated from the body up the cable (derived in
:mod:`symcable.models.tow_steady`, our derivation: s the unstretched arc length from the
body, phi the cable's angle above the horizontal, T' = w sin phi + F_t cos^2 phi sqrt(1+e),
T phi' = w cos phi - R sin^2 phi sqrt(1+e), the body's weight and drag setting T(0) and
phi(0); scipy DOP853 at rtol 1e-12)."""
from __future__ import annotations

import math

import numpy as np
import pytest

from symcable.cable3d_api import simulate_3d
from symcable.models.tow_steady import steady_tow, tow_sections
from symcable.scene import load_scene

U, L, D, CDN, CDT, W, EA, RHO, G = 2.0, 200.0, 0.03, 1.5, 0.03, 20.0, 1e8, 1025.0, 9.80665
MB, VB, CDA = 2000.0, 0.5, 1.0  # the body: kg, m^3, drag coefficient x area (m^2)


def _towed_point(segments: int, law: dict | None = None) -> dict:
    """A 200 m cable (20 N/m, 30 mm, Cdn 1.5, Cdt 0.03, EA 1e8 N) towed at 2 m/s from a
    vessel point, a free point of 2000 kg and 0.5 m^3 (14.7 kN submerged) with isotropic
    drag area 1 m^2 (2.05 kN at 2 m/s) at its end: the body's drag does not depend on its
    attitude, so the ODE's end condition is exact."""
    lt = {"EA": EA, "mass": 3.0, "diameter": D, "weight": W,
          "cd_normal": CDN, "cd_tangential": CDT}
    if law is not None:
        lt.update(drag_law="loading-functions", loading=law)
    return {"model": "cable3d", "line_types": {"c": lt},
            "points": {"ship": {"kind": "vessel", "position": [0.0, 0.0, 0.0],
                                "motion": {"kind": "tow", "speed": U, "heading": 0.0}},
                       "fish": {"kind": "free", "mass": MB, "volume": VB,
                                "position": [-100.0, 0.0, -150.0], "cd_area": [CDA] * 3}},
            "lines": [{"name": "tow", "end_a": "ship", "end_b": "fish",
                       "sections": [{"type": "c", "length": L, "segments": segments}]}]}


def _steady(scene) -> tuple[float, float, float]:
    """(top tension N, layback m, depth m) of the scene's steady tow (simulate's start)."""
    tr = simulate_3d(scene, 0.1, 0.05, codegen=False)
    assert tr.stats["start"] == "steady tow"
    ship, fish = tr.points["ship"]["position"][0], tr.points["fish"]["position"][0]
    return (float(np.linalg.norm(tr.points["ship"]["force"][0])), float(ship[0] - fish[0]),
            float(ship[2] - fish[2]))


def _oracle(scene):
    return steady_tow(tow_sections(scene.lines[0]), U, (MB - RHO * VB) * G,
                      0.5 * RHO * CDA * U * U, RHO)


def test_steady_tow_with_a_heavy_body_matches_the_ode():
    """Top tension, layback and depth within 1 % of the ODE's (the issue's "done when")
    from 5 segments; the error falls as N^-2 (the lumped drag and weight of chords: measured
    relative errors at N = 5, 10, 20: tension 4.2e-4, 1.0e-4, 2.6e-5; layback 8.9e-4,
    2.3e-4, 5.8e-5; depth 7.3e-4, 1.8e-4, 4.5e-5; the observed order 2.0 each), here an
    order between 1.8 and 2.2 over each halving and every error under 1e-3 at N = 10. The
    cable leaves the body at 82 deg to the horizontal and meets the tow at 43 deg (ODE)."""
    scene = load_scene(_towed_point(5))
    ref = _oracle(scene)
    assert ref.phi[0] == pytest.approx(82.0, abs=0.1) and ref.angle == pytest.approx(43.2, abs=0.1)
    errs = []
    for n in (5, 10, 20):
        T, x, z = _steady(load_scene(_towed_point(n)))
        errs.append([abs(T / ref.tension - 1), abs(x / ref.layback - 1), abs(z / ref.depth - 1)])
    errs = np.array(errs)
    assert np.all(errs < 1e-2)
    assert np.all(errs[1] < 1e-3)
    order = np.log2(errs[:-1] / errs[1:])
    assert np.all((order > 1.8) & (order < 2.2)), order
