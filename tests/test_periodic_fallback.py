"""The periodic solvers' fallback by continuation in the motion amplitude
(symcable.solvers.periodic_fallback): its path logic on a stand-in solve, and where it
applies. The solve is a stand-in (a function of the amplitude factor that fails when the
step from its start is too long), so each assertion is about the path, not about a model:
a real mechanism's continuation runs in studies/stability/periodic3d.py."""
from __future__ import annotations

from dataclasses import dataclass, field
from types import SimpleNamespace

import numpy as np
import pytest

from symcable.errors import ConvergenceError
from symcable.mechanism.mechanism import ParamBlocks
from symcable.solvers import periodic_fallback as pf

#: a stand-in mechanism: a stiffness block, the motion's scale and its ramp flag
PARAMS = ParamBlocks(("line1.ea", "line1.motion", "line1.ramp"), (1, 3, 1),
                     np.array([5.0, 1.0, 1.0, 1.0, 0.0]))
MECH = SimpleNamespace(params=PARAMS)
NOT_CONVERGED = ConvergenceError("no convergence", diagnostics={"residual": 1.0,
                                                                 "tolerance": 1e-9})


@dataclass
class Sol:
    """What a solve returns (the fields solve_by_continuation reads and replaces)."""
    s: float
    stats: dict = field(default_factory=dict)
    warnings: tuple = ()


def reach(limit: float):
    """A solve that converges when the amplitude factor is at most ``limit`` beyond its
    start's (0 for the method's own start), and records the factors it was asked for."""
    asked = []

    def solve(p, prev, sp):
        s = float(p[1])
        assert np.all(p[1:4] == s) and p[0] == 5.0 and p[4] == 0.0  # only the motion scaled
        asked.append(s)
        if s - (0.0 if prev is None else prev.s) > limit + 1e-12:
            raise NOT_CONVERGED
        return Sol(s)
    return solve, asked


def test_reaches_full_amplitude_in_growing_steps():
    solve, asked = reach(0.3)
    sol = pf.solve_by_continuation(solve, MECH, PARAMS.values, NOT_CONVERGED)
    assert sol.s == 1.0
    # 0.25 from the start, then 0.5 fails (step 0.5 > 0.3), 0.5 halved ... always ending at 1
    assert sol.stats["continuation"][-1] == 1.0
    assert list(sol.stats["continuation"]) == sorted(sol.stats["continuation"])
    assert sol.stats["continuation_solves"] == len(asked)
    steps = np.diff([0.0, *sol.stats["continuation"]])
    assert np.all(steps <= 0.3 + 1e-12)
    assert "continuation in the motion amplitude" in sol.warnings[-1]


def test_gives_up_below_the_smallest_step_and_names_both_failures():
    solve, asked = reach(0.01)  # below MIN_STEP: no step can succeed
    with pytest.raises(ConvergenceError) as exc:
        pf.solve_by_continuation(solve, MECH, PARAMS.values, NOT_CONVERGED)
    msg = str(exc.value)
    assert "no convergence" in msg and "amplitude factor 0" in msg
    assert len(asked) <= pf.MAX_SOLVES and min(asked) >= pf.MIN_STEP


def test_a_solve_refused_by_its_check_at_full_amplitude_ends_the_path():
    refused = ConvergenceError("defect too large", diagnostics={"residual": 1e-12,
                                                                  "tolerance": 1e-9})

    def solve(p, prev, sp):
        if p[1] == 1.0:
            raise refused
        return Sol(float(p[1]))
    with pytest.raises(ConvergenceError, match="defect too large"):
        pf.solve_by_continuation(solve, MECH, PARAMS.values, NOT_CONVERGED)


def test_where_it_applies():
    held = PARAMS.values  # ramp 0: the motion at full amplitude from t = 0
    ramped = PARAMS.with_values(**{"line1.ramp": [1.0]})
    converged = ConvergenceError("refused by the check",
                                 diagnostics={"residual": 0.0, "tolerance": 1e-9})
    assert pf.continuation_applies(MECH, ramped, None, NOT_CONVERGED)
    assert not pf.continuation_applies(MECH, held, None, NOT_CONVERGED)  # jerk at t = 0
    assert pf.continuation_applies(MECH, held, ramped, NOT_CONVERGED)  # ramped start given
    assert not pf.continuation_applies(MECH, ramped, None, converged)  # the same again
    no_motion = SimpleNamespace(params=ParamBlocks(("ea",), (1,), np.array([1.0])))
    assert not pf.continuation_applies(no_motion, np.array([1.0]), None, NOT_CONVERGED)
