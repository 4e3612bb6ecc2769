"""The stiffness a line presents at its fairlead, exact from CasADi (implicit function theorem
on the static residual), against MoorPy's analytic catenary stiffness and central
differences of solve_static."""
from __future__ import annotations

import numpy as np
import pytest

import symcable as sc
from symcable.errors import SymcableError
from symcable.api.analyses import end_stiffness
from symcable.scene import load_scene


def _oc3(segments=None, bed=None):
    d = load_scene(sc.demo_scene_path()).to_dict()
    if segments:
        d["sections"] = [dict(d["sections"][0], segments=segments)]
    if bed:
        d["seabed"] = dict(d.get("seabed", {}), stiffness=bed)
    return d


def test_oc3_end_stiffness_against_moorpy():
    """OC3 at 200 segments on a stiff bed (1e7 Pa/m): every entry of the 2x2 fairlead
    stiffness within 1 % of MoorPy's closed form (measured 0.14-0.2 %). At the scene's own
    50 segments and 1e5 Pa/m it is 2.4 % off: the touchdown moves across a coarse node
    spacing into a soft bed (200 segments, 1e5 Pa/m: 0.6 %), which is the discretisation's
    error, not the derivative's (that agrees with differences to 1e-5, next test)."""
    from moorpy.Catenary import catenary

    K = end_stiffness(_oc3(200, 1e7))
    *_, info = catenary(848.67, 250.0, 902.2, 3.84243e8, 698.094, CB=0.0)
    ref = np.asarray(info["stiffnessB"])
    np.testing.assert_allclose(K, ref, rtol=1e-2)
    assert K[0, 1] == pytest.approx(K[1, 0], rel=1e-9)  # conservative: symmetric


def test_end_stiffness_equals_differences_of_solve_static():
    """At the scene's own discretisation, K = -dF/dx equals central differences of the
    fairlead force from solve_static, step 1 mm (difference error O(h^2 F''') ~ 1e-7 relative,
    solve tolerance ~1e-12 of the tension over 2 mm ~ 1e-6 relative; tolerance 1e-4)."""
    d = _oc3()
    K = end_stiffness(d)
    h = 1e-3
    fd = np.zeros((2, 2))
    xb = np.array(d["end_b"]["position"], dtype=float)
    for j in range(2):
        F = []
        for sgn in (1, -1):
            dd = dict(d, end_b=dict(d["end_b"], position=list(xb + sgn * h * np.eye(2)[j])))
            F.append(sc.solve_static(dd).fairlead_force)
        fd[:, j] = -(F[0] - F[1]) / (2 * h)
    np.testing.assert_allclose(K, fd, rtol=1e-4)


def test_end_stiffness_errors():
    """Only a pinned end has a position to differentiate against; a bad end name is refused."""
    d = _oc3()
    with pytest.raises(SymcableError, match="end = 'c'"):
        end_stiffness(d, "c")
    d["end_b"] = {"condition": "free", "force": [-7e5, -5e5]}
    with pytest.raises(SymcableError, match="pinned"):
        end_stiffness(d, "b")


def test_linearize_scene_gives_modal_frequencies_and_end_stiffness():
    """sc.linearize: the undamped state matrix's eigenvalues are +-i omega at exactly the
    frequencies modal_analysis reports (1e-8 relative: the same linearisation reached by two
    routes, CasADi's tangents of the Mechanism here, the DynamicModel's Jacobian there; the
    eigensolvers differ), plus zero eigenvalues for the closure invariants; the end
    stiffness at the fairlead is end_stiffness's; with current the drag gives C > 0."""
    from conftest import seed001

    scene = sc.load_scene(seed001())
    lin = sc.linearize(scene, undamped=True)
    assert lin.K.shape == (lin.M.shape[0], lin.G.shape[0]) and set(lin.end_stiffness) == {"a", "b"}
    ev = np.linalg.eigvals(lin.state_matrix())
    omega = np.sort(np.abs(ev.imag[ev.imag > 1e-9]))
    modes = sc.modal_analysis(scene, 6)
    np.testing.assert_allclose(omega[:6] / (2 * np.pi), modes.frequencies, rtol=1e-8)
    assert np.max(np.abs(ev.real)) < 1e-8 * np.max(np.abs(ev))  # undamped: on the axis
    np.testing.assert_allclose(lin.end_stiffness["b"], end_stiffness(scene, "b"), rtol=1e-12)
    damped = sc.linearize(scene)
    assert np.all(np.diag(damped.C) > 0) and np.allclose(lin.C, 0.0)
