"""Exact design sensitivities of a static state (issue 37, item 2): ``sc.sensitivity`` against
central differences of whole static solves, and its refusals."""
from __future__ import annotations

import numpy as np
import pytest

import symcable as sc
from symcable.api.sensitivity import _expand, _set
from symcable.errors import SymcableError
from test_coupling import spar

OUTPUTS = ["line0.fairlead_tension", "line1.anchor_tension", "spar.force"]
PARAMETERS = ["line_types.chain.diameter", "lines[0].sections[0].length",
              "points.anchor1.position[0]", "bodies.spar.position[2]"]


def _scene() -> dict:
    """The spar's three chains (10 segments a line), the chain's submerged weight left to
    follow its diameter."""
    d = spar(10, body_motion=False)
    d["line_types"]["chain"].pop("weight")
    return d


def _outputs(d: dict) -> np.ndarray:
    st = sc.solve_static(d, tol=1e-6, estimate=False)  # N: far below what a difference resolves
    return np.concatenate([[st.lines["line0"].fairlead_tension,
                            st.lines["line1"].anchor_tension], st.bodies["spar"].force])


def test_equals_central_differences_of_whole_solves():
    """Each derivative equals the central difference of two static solves (tolerance 1e-6
    N) within 1e-6 of the output's largest derivative or three times the difference's own
    error (its change from a step h to 2h), whichever is larger. The chain's diameter moves
    the weight, drag and added mass the scene derives from it; the body's position moves
    every fairlead."""
    d = _scene()
    s = sc.sensitivity(d, OUTPUTS, PARAMETERS)
    assert s.outputs == ("line0.fairlead_tension", "line1.anchor_tension", "spar.force[0]",
                         "spar.force[1]", "spar.force[2]")
    assert np.allclose(s.values, _outputs(d), rtol=1e-9)
    for name, parts, value in _expand(d, PARAMETERS):
        h = 1e-4 * max(abs(value), 1.0)
        fd = {}
        for k in (1, 2):
            hi = _outputs(_set(d, parts, value + k * h))
            lo = _outputs(_set(d, parts, value - k * h))
            fd[k] = (hi - lo) / (2 * k * h)
        exact = s.jacobian[:, s.parameters.index(name)]
        scale = np.max(np.abs(fd[1]))
        allowed = np.maximum(1e-6 * scale, 3.0 * np.abs(fd[1] - fd[2]))
        assert np.all(np.abs(exact - fd[1]) <= allowed), (name, exact, fd[1], allowed)


def test_a_free_body_offset():
    """A free buoy on three chains: the derivatives of its static position and of a
    fairlead tension in a line's length, an anchor's position and the chain's diameter
    equal central differences of whole solves as above; a body's own numbers (its mass) are
    compiled into the equations and refused."""
    from test_bodies_scene import _scene as buoy

    d = buoy()
    pars = ["lines[0].sections[0].length", "points.a1.position[0]",
            "line_types.chain.diameter"]
    s = sc.sensitivity(d, ["buoy.position", "west.fairlead_tension"], pars)

    def outputs(dd):
        st = sc.solve_static(dd, tol=1e-6, estimate=False)
        return np.concatenate([st.bodies["buoy"].position, [st.lines["west"].fairlead_tension]])
    for name, parts, value in _expand(d, pars):
        h = 1e-4 * max(abs(value), 1.0)
        fd = {k: (outputs(_set(d, parts, value + k * h)) - outputs(_set(d, parts, value - k * h)))
              / (2 * k * h) for k in (1, 2)}
        exact = s.jacobian[:, s.parameters.index(name)]
        allowed = np.maximum(1e-6 * np.max(np.abs(fd[1])), 3.0 * np.abs(fd[1] - fd[2]))
        assert np.all(np.abs(exact - fd[1]) <= allowed), (name, exact, fd[1], allowed)
    with pytest.raises(SymcableError, match="compiled into the equations"):
        sc.sensitivity(d, "west.fairlead_tension", "bodies.buoy.mass")


def test_lookups_and_elasticities():
    s = sc.sensitivity(_scene(), "line0.fairlead_tension", "points.anchor0.position")
    assert s.parameters == tuple(f"points.anchor0.position[{i}]" for i in range(3))
    # moving line0's anchor outward along x stretches it: its fairlead tension rises
    assert s["line0.fairlead_tension", "points.anchor0.position[0]"] > 0
    assert s.relative().shape == (1, 3)
    assert "line0.fairlead_tension" in s.summary()


@pytest.mark.parametrize("parameter,match", [
    ("environment.depth", "compiled into the equations"),
    ("line_types.rope.diameter", "no 'rope' there"),
    ("lines[0].end_a", "must name a number"),
])
def test_refusals(parameter, match):
    with pytest.raises(SymcableError, match=match):
        sc.sensitivity(_scene(), "line0.fairlead_tension", parameter)


def test_unknown_output_lists_the_known():
    with pytest.raises(SymcableError, match="line0.fairlead_tension"):
        sc.sensitivity(_scene(), "line9.tension", "line_types.chain.EA")


def test_command_line(tmp_path):
    """``symcable sensitivity`` prints the same derivatives as JSON; a bad path is one line
    on stderr with exit status 2."""
    import json
    import subprocess
    import sys

    from symcable.scene.load import scene_to_toml
    path = tmp_path / "spar.toml"
    path.write_text(scene_to_toml(sc.load_scene(spar(6, body_motion=False))))
    args = [sys.executable, "-m", "symcable", "sensitivity", str(path), "--output",
            "line0.fairlead_tension", "--parameter", "points.anchor0.position[0]"]
    run = subprocess.run(args + ["--json"], capture_output=True, text=True, timeout=300)
    assert run.returncode == 0, run.stderr
    got = json.loads(run.stdout)
    want = sc.sensitivity(str(path), "line0.fairlead_tension", "points.anchor0.position[0]")
    assert got["jacobian"][0][0] == pytest.approx(want.jacobian[0, 0], rel=1e-12)
    bad = subprocess.run(args[:-1] + ["points.nowhere.position[0]"], capture_output=True,
                         text=True, timeout=300)
    assert bad.returncode == 2 and len(bad.stderr.strip().splitlines()) == 1
