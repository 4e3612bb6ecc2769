"""Design optimisation with exact gradients (issue 37, item 3, a first step): the lightest
three-line mooring of a float under a steady load, its fairlead tensions bounded, from
exact gradients and from central differences of whole solves, from several starts; the
optimum confirmed by its neighbours; bad problems refused in one line."""
from __future__ import annotations

import math

import numpy as np
import pytest

from symcable.api.optimize import optimize
from symcable.api.sensitivity import static_values
from symcable.errors import ConvergenceError, SymcableError

LIMIT = 1.7e5  # N, each fairlead's tension
VARIABLES = {f"lines[{i}].sections[0].length": (236.0, 300.0) for i in range(3)}
CONSTRAINTS = [("float.position[0]", "<=", 30.0)] + [
    (f"line{i}.fairlead_tension", "<=", LIMIT) for i in range(3)]


def float_scene() -> dict:
    """A buoyant float on three chains (anchors at 230 m radius in 100 m of water), pushed
    toward line0's anchor by a steady 150 kN."""
    d = {"name": "float", "model": "cable3d", "environment": {"depth": 100.0},
         "seabed": {"stiffness": 1e5},
         "line_types": {"chain": {"mass": 77.7, "diameter": 0.09, "EA": 3.84e8}},
         "points": {"float": {"kind": "free", "position": [0.0, 0.0, -20.0], "mass": 1e4,
                              "volume": 30.0, "force": [1.5e5, 0.0, 0.0]}}, "lines": []}
    for i, a in enumerate((0.0, 120.0, 240.0)):
        c, s = math.cos(math.radians(a)), math.sin(math.radians(a))
        d["points"][f"anchor{i}"] = {"kind": "fixed", "position": [230.0 * c, 230.0 * s, -100.0]}
        d["lines"].append({"name": f"line{i}", "end_a": f"anchor{i}", "end_b": "float",
                           "sections": [{"type": "chain", "length": 260.0, "segments": 10}]})
    return d


def test_lightest_mooring_exact_against_differences_and_starts():
    """The optimum: line0 (which the load slackens) at its shortest, lines 1 and 2 as short
    as their tension allows, the tension at its bound. Exact gradients and central
    differences reach it, the exact ones in fewer solves (measured 10 against
    64); two other starts reach it too; shortening line1 by a centimetre breaks its
    tension bound (so no lighter design is feasible nearby). Optima agree to 1e-4 m: SLSQP
    meets an active constraint to its tolerance (measured 1.6e-7 of the bound), which is
    1.3e-5 m of line length here."""
    exact = optimize(float_scene(), VARIABLES, "mass", CONSTRAINTS)
    diff = optimize(float_scene(), VARIABLES, "mass", CONSTRAINTS, gradients="differences")
    x = np.array(list(exact.variables.values()))
    assert np.allclose(x, list(diff.variables.values()), rtol=0, atol=1e-4)
    assert x[0] == pytest.approx(236.0, abs=1e-9)
    assert exact.constraints[f"line1.fairlead_tension <= {LIMIT:g}"] == pytest.approx(LIMIT,
                                                                                   rel=1e-6)
    assert exact.stats["solves"] * 3 < diff.stats["solves"]
    for start in (240.0, 290.0):
        other = optimize(float_scene(), VARIABLES, "mass", CONSTRAINTS,
                         start={k: start for k in VARIABLES})
        assert np.allclose(list(other.variables.values()), x, rtol=0, atol=1e-4)
    d = float_scene()
    for i, length in enumerate(x):
        d["lines"][i]["sections"][0]["length"] = float(length)
    d["lines"][1]["sections"][0]["length"] -= 0.01
    assert static_values(d, ["line1.fairlead_tension"])["line1.fairlead_tension"] > LIMIT


def test_infeasible_and_bad_problems():
    with pytest.raises(ConvergenceError, match="no feasible design"):
        optimize(float_scene(), VARIABLES, "mass", [("line1.fairlead_tension", "<=", 1e3)],
                 max_iter=10)
    with pytest.raises(SymcableError, match="must be finite with lower < upper"):
        optimize(float_scene(), {"lines[0].sections[0].length": (300.0, 236.0)})
    with pytest.raises(SymcableError, match="no 'line9' there|no 9 there"):
        optimize(float_scene(), {"lines[9].sections[0].length": (236.0, 300.0)})
    with pytest.raises(SymcableError, match="must be \\(output"):
        optimize(float_scene(), VARIABLES, "mass", [("line1.fairlead_tension", "<", 1e5)])
