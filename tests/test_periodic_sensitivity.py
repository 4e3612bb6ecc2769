"""Exact sensitivities of periodic statistics (:mod:`symcable.api.periodic_sensitivity`):
against central differences of whole periodic solves, and the refusals."""
from __future__ import annotations

import copy

import numpy as np
import pytest

import symcable as sc
from symcable.api.sensitivity import _expand, _set
from symcable.errors import SymcableError

MOTION = {"kind": "harmonic", "period": 8.0, "amplitude": [2.0, 0.0, 1.0],
          "phase_deg": [0.0, 0.0, -90.0]}
LINE = {"model": "cable3d", "environment": {"depth": 300.0, "current": [0.4, 0.1, 0.0]},
        "line_types": {"chain": {"EA": 3.84243e8, "mass": 77.7066, "diameter": 0.09,
                                 "cd_normal": 1.6, "cd_tangential": 0.1, "ca_normal": 1.0,
                                 "breaking_load": 8.0e6}},
        "sections": [{"type": "chain", "length": 290.0, "segments": 10}],
        "end_a": {"condition": "pinned", "position": [-220.0, 0.0, -180.0]},
        "end_b": {"condition": "pinned", "position": [0.0, 0.0, -10.0], "motion": MOTION}}
OUTS = ["fairlead_tension.range", "fairlead_tension.max", "anchor_tension.mean",
        "anchor_uplift.min", "fairlead_utilisation.max"]
PARS = ["sections[0].length", "line_types.chain.diameter", "end_a.position[0]"]
H = 6


@pytest.fixture(scope="module")
def exact():
    return sc.sensitivity(LINE, OUTS, PARS, harmonics=H)


def test_statistics_are_the_periodic_solution_s(exact):
    """The values are the harmonic balance's (6 harmonics) statistics of the periodic
    state: within 2 % of the range of shooting's (at T/100, its own discretisation) and
    the utilisation the tension over the breaking load to round-off."""
    per = sc.solve_periodic(LINE)
    t = per.fairlead_tension
    v = dict(zip(exact.outputs, exact.values))
    assert v["fairlead_tension.range"] == pytest.approx(t.max() - t.min(),
                                                        rel=0.02)
    assert abs(v["fairlead_tension.max"] - t.max()) < 0.02 * (t.max() - t.min())
    assert v["fairlead_utilisation.max"] == pytest.approx(v["fairlead_tension.max"] / 8.0e6,
                                                          rel=1e-12)
    assert exact.stats["period"] == 8.0 and exact.stats["harmonics"] == H
    assert "periodic steady state" in exact.summary()


def test_derivatives_equal_central_differences_of_periodic_solves(exact):
    """Each derivative equals central differences of whole periodic solves (the same
    harmonic balance from shooting's state) at relative steps 1e-4 and 2e-4, within 1e-6 of
    its row's largest derivative or 3 times the two differences' own disagreement
    (measured: 1e-9 to 4e-8 relative on the length and the anchor, 1e-8 on the
    diameter)."""
    def values(d):
        return sc.sensitivity(d, OUTS, PARS[1], harmonics=H).values
    for name, parts, value in _expand(copy.deepcopy(LINE), PARS):
        fd = {}
        for rel in (1e-4, 2e-4):
            h = rel * max(abs(value), 1.0)
            fd[rel] = (values(_set(LINE, parts, value + h))
                       - values(_set(LINE, parts, value - h))) / (2.0 * h)
        got = exact.jacobian[:, exact.parameters.index(name)]
        allowed = np.maximum(1e-6 * np.max(np.abs(got)), 3.0 * np.abs(fd[1e-4] - fd[2e-4]))
        assert np.all(np.abs(got - fd[1e-4]) <= allowed), (name, got, fd)


def test_periodic_refusals():
    """Mixed static and periodic outputs, the grounded length over a period, a vector
    output without its entry, a motion's amplitude or period (compiled in), a free point's
    drag area (compiled into the drag, which a check at rest does not see), a scene in
    waves and harmonics below one: one line each."""
    with pytest.raises(SymcableError, match="two calls"):
        sc.sensitivity(LINE, ["fairlead_tension.range", "fairlead_tension"], PARS[0])
    with pytest.raises(SymcableError, match="harmonics"):
        sc.sensitivity(LINE, ["fairlead_tension.range"], PARS[0], harmonics=0)
    waves = copy.deepcopy(LINE)
    waves["environment"]["waves"] = {"kind": "regular", "height": 2.0, "period": 8.0}
    with pytest.raises(SymcableError, match="in waves"):
        sc.sensitivity(waves, ["fairlead_tension.range"], PARS[0])
    with pytest.raises(SymcableError, match="compiled into"):
        sc.sensitivity(LINE, ["fairlead_tension.range"], ["end_b.motion.amplitude[0]"],
                       harmonics=H)
    with pytest.raises(SymcableError, match="has 33 entries"):
        sc.sensitivity(LINE, ["positions.mean"], PARS[0], harmonics=H)
    phased = copy.deepcopy(LINE)  # (in phase, the motion at t = 0 does not see its period)
    phased["end_b"]["motion"]["phase_deg"] = [0.0, 0.0, 0.0]
    with pytest.raises(SymcableError, match="compiled into"):
        sc.sensitivity(phased, ["fairlead_tension.range"], ["end_b.motion.period"],
                       harmonics=H)
    on_bed = copy.deepcopy(LINE)
    on_bed["environment"]["depth"] = 180.0
    on_bed["seabed"] = {"stiffness": 1e5}
    with pytest.raises(SymcableError, match="grounded length is a static balance"):
        sc.sensitivity(on_bed, ["grounded_length.max"], PARS[0], harmonics=H)


def test_a_number_compiled_into_the_motion_s_terms_is_refused():
    """A free clump's drag area and added mass are compiled into its part's equations and
    act only in motion (no current): the check on the equations of motion at samples of the
    periodic state refuses them, where one at rest would take them as parameters of slope
    zero."""
    d = {"model": "cable3d", "environment": {"depth": 150.0},
         "line_types": {"chain": {"EA": 3.8e8, "mass": 77.7, "diameter": 0.09}},
         "points": {"anchor": {"kind": "fixed", "position": [-200.0, 0.0, -150.0]},
                    "clump": {"kind": "free", "position": [-100.0, 0.0, -110.0],
                              "mass": 3000.0, "volume": 0.5, "cd_area": [8.0, 8.0, 8.0],
                              "ca": 1.0},
                    "fair": {"kind": "vessel", "position": [0.0, 0.0, -10.0],
                             "motion": dict(MOTION)}},
         "lines": [{"name": "lower", "end_a": "anchor", "end_b": "clump",
                    "sections": [{"type": "chain", "length": 120.0, "segments": 4}]},
                   {"name": "upper", "end_a": "clump", "end_b": "fair",
                    "sections": [{"type": "chain", "length": 150.0, "segments": 4}]}]}
    with pytest.raises(SymcableError, match="compiled into"):
        sc.sensitivity(d, ["upper.fairlead_tension.range"], ["points.clump.cd_area[0]"],
                       harmonics=4)
