"""The rod's cost (studies/rod_notes/rodc14.md): the reference frames' spin in closed form equals its
Lagrange terms by CasADi, the compiler's optimisation level follows the graph's size, and
a small rod run in generated C equals the virtual machine's."""
from __future__ import annotations

import math

import casadi as ca
import numpy as np
import pytest

import symcable as sc
from symcable.mechanism import codegen
from symcable.errors import SymcableError
from symcable.models.rod.spin import with_reference_spin, with_reference_spin_ad
from symcable.scene import load_scene
from symcable.api.scene3d import scene_mechanism


def _rod(model: str = "rod", segments: int = 6, iso: bool = False, motion=None) -> dict:
    """A clamped-free rod in air (two principal stiffnesses unless ``iso``); ``model =
    "hybrid"``: its first half a rod section, the rest cable3d."""
    L, EI = 2.0, 10.0
    lt = {"EA": 1e4 * EI / L**2, "EI": EI if iso else [EI, 2 * EI], "GJ": 7.0, "mass": 1.0,
          "diameter": 0.02, "weight": 2.0 * EI / L**3}
    d = {"model": model, "environment": {"water_density": 0.0}, "line_types": {"beam": lt},
         "sections": [{"type": "beam", "length": L, "segments": segments}],
         "end_a": {"condition": "clamped", "position": [0.0, 0.0, 0.0],
                   "direction": [math.cos(0.7), math.sin(0.7), 0.0], "twist_deg": 30.0},
         "end_b": {"condition": "free"}}
    if model == "hybrid":
        d["line_types"]["cab"] = {k: v for k, v in lt.items() if k != "GJ"} | {"EI": EI}
        d["sections"] = [{"type": "beam", "length": L / 2, "segments": segments // 2,
                          "model": "rod"},
                         {"type": "cab", "length": L / 2, "segments": segments - segments // 2}]
    if motion is not None:
        d["end_a"]["motion"] = motion
    return d


@pytest.mark.parametrize("case", ["aniso", "iso", "hybrid", "harmonic", "table"])
def test_closed_form_spin_equals_casadi_lagrange_terms(case, tmp_path):
    """Mass, force and kinetic energy of :func:`with_reference_spin` (closed form) against
    :func:`with_reference_spin_ad` (CasADi's Lagrange terms, the first version) at random
    states and times, a moving clamp included (a table's row at 0.05 s: where its velocity
    output is smoothed, both take the held end's rate as its position's derivative): equal
    to round-off."""
    motion = None
    if case == "harmonic":
        motion = {"kind": "harmonic", "period": 0.5, "amplitude": [0.02, 0.03, 0.01]}
    elif case == "table":
        path = tmp_path / "m.txt"
        path.write_text("0 0 0 0\n0.05 0 0.02 0.01\n0.1 0 0.05 0\n")
        motion = {"kind": "table", "file": str(path)}
    d = _rod("hybrid" if case == "hybrid" else "rod", 6, case == "iso", motion)
    mech = scene_mechanism(load_scene(d))
    a, b = with_reference_spin(mech), with_reference_spin_ad(mech)
    f = ca.Function("f", [mech.q, mech.v, mech.t, mech.p],
                    [a.mass, a.force, b.mass, b.force, a.outputs["kinetic_energy"].expr])
    rng = np.random.default_rng(3)
    q0 = np.asarray(next(mech.starts()).q, float)
    for t in (0.02, 0.05, 0.3):
        q = q0 + 0.05 * rng.normal(size=mech.n_q)
        v = rng.normal(size=mech.n_v)
        Ma, Fa, Mb, Fb, Ka = (np.array(x) for x in f(q, v, t, mech.params.values))
        assert np.max(np.abs(Ma - Mb)) <= 1e-14 * np.max(np.abs(Mb))
        assert np.max(np.abs(Fa - Fb)) <= 1e-13 * np.max(np.abs(Fb))
        assert Ka.item() >= 0.0
    # the closed form's Jacobian is far smaller (studies/rod_notes/rodc14.md: 124 k -> 37 k at 8 edges)
    y = ca.vertcat(mech.q, mech.v)
    size = [ca.Function("J", [y, mech.t, mech.p], [ca.jacobian(m.force, y)]).n_instructions()
            for m in (a, b)]
    assert size[0] < size[1]


def test_optimisation_level_follows_graph_size(monkeypatch):
    """Graphs that the default compiles keep -O2 (FLAGS, the same cache keys as before);
    larger ones get -O1, then -O0; $SYMCABLE_CC_OPT (the suite's -O0) overrides all."""
    monkeypatch.setenv("SYMCABLE_CC_OPT", "-O1")
    assert codegen.flags_for(1000)[0] == "-O1"
    monkeypatch.setenv("SYMCABLE_CC_OPT", "-O9")
    with pytest.raises(SymcableError, match="SYMCABLE_CC_OPT = '-O9'"):
        codegen.flags_for(1000)
    monkeypatch.delenv("SYMCABLE_CC_OPT")
    assert codegen.flags_for(1000) == codegen.FLAGS
    assert codegen.flags_for(codegen.DEFAULT_MAX_SIZE) == codegen.FLAGS
    assert codegen.flags_for(codegen.DEFAULT_MAX_SIZE + 1)[0] == "-O1"
    assert codegen.flags_for(10**9)[0] == "-O0"
    assert set(codegen.flags_for(10**9)[1:]) == set(codegen.FLAGS[1:])


def test_vertex_kernel_as_call_gives_the_same_step(monkeypatch):
    """With ``rod_frames.CALL_MIN_VERTICES`` reached the vertex kernel is a call node per
    vertex (never inlined): the DAE residual and its Jacobian are the straight-line
    Mechanism's to round-off, in a fraction of the instructions."""
    from symcable.models.rod import frames as rod_frames
    from symcable.models.rod.hybrid import build_hybrid  # uncached (scene_mechanism caches)
    from symcable.solvers.galpha1 import _sx_residual
    scene = load_scene(_rod("rod", 5, False))
    straight = with_reference_spin(build_hybrid(scene))
    monkeypatch.setattr(rod_frames, "CALL_MIN_VERTICES", 3)
    called = with_reference_spin(build_hybrid(scene))
    rng = np.random.default_rng(5)
    y0 = np.concatenate([np.asarray(next(straight.starts()).q, float), np.zeros(straight.n_v)])
    yd, y = rng.normal(size=y0.size), y0 + 0.02 * rng.normal(size=y0.size)
    sizes, values = [], []
    for m in (straight, called):
        F = _sx_residual(m)
        Y = ca.SX.sym("y", y0.size)
        J = ca.Function("J", [Y], [ca.jacobian(F(yd, Y, 0.1, m.params.values), Y)])
        sizes.append(J.n_instructions())
        values.append((np.array(F(yd, y, 0.1, m.params.values)), np.array(J(y))))
    assert sizes[1] < sizes[0] / 2
    for a, b in zip(*values):
        assert np.max(np.abs(a - b)) <= 1e-12 * np.max(np.abs(a))


@pytest.mark.skipif(codegen.compiler() is None, reason="no C compiler")
def test_compiled_rod_run_equals_virtual_machine():
    """``sc.simulate`` of a 3-segment isotropic rod (its reference frames' spin on), its
    clamp heaving, in generated C and in the virtual machine: the same positions and twists
    to round-off."""
    d = _rod("rod", 3, True, {"kind": "harmonic", "period": 0.05, "amplitude": [0.0, 0.0, 0.02]})
    runs = [sc.simulate(d, 0.05, dt=0.005, rho_inf=0.5, codegen=cg) for cg in (False, True)]
    assert runs[1].stats.get("compiled", True)
    np.testing.assert_allclose(runs[1].positions, runs[0].positions, rtol=0, atol=1e-10)
    tw = [r.stats["outputs"]["twist_angles"] for r in runs]
    np.testing.assert_allclose(tw[1], tw[0], rtol=0, atol=1e-10)
    assert np.max(np.abs(runs[0].positions[-1] - runs[0].positions[0])) > 1e-4  # it moved
