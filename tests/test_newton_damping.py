"""The first-order generalized-alpha step's damped correction (galpha1.NEWTON_DAMPING): a
Newton iteration that cycles between two iterates, as a friction bristle's slip switching
on and off across its smoothing speed makes it, converges once the correction from an
iterate whose residual grew is halved. Scene: MoorDyn's WD0050 chain under the ZZP1_A2 heave
with the bristle law (studies/chains), rho_inf = 0.2 at dt = 0.1 s, in the virtual machine,
from t = -10 s through the step from -2.1 s that cycled (measured: 5 substepped steps over
the 30 s run without the damping, none with it)."""
from __future__ import annotations

import pytest

from conftest import load_study


def _run(study, tmp_path):
    from symcable.api.cable3d_static import cable3d_mechanism
    from symcable.solvers.equilibrium import solve_equilibrium
    from symcable.solvers.integrate import integrate
    from symcable.solvers.options import GeneralizedAlphaFirstOrder
    table = study.cases.extended_table("A2", tmp_path)
    mech = cable3d_mechanism(study.variant_scene("WD0050", table, "bristle"))
    eq = solve_equilibrium(mech, codegen=False)
    return integrate(mech, 8.0, 0.1, t0=study.cases.T0, start=eq, p=mech.params.values,
                     method=GeneralizedAlphaFirstOrder(rho_inf=0.2, tol=1e-8), codegen=False,
                     period=study.cases.PERIOD, progress=False)


def test_damped_correction_breaks_the_bristle_cycle(tmp_path, monkeypatch):
    study = load_study("chains", "friction.py")
    if not (study.cases.REF_DIR / "WD0050_Chain.txt").is_file():
        pytest.fail("the MoorDyn chain decks are missing from ../shared/reference")
    from symcable.solvers import galpha1
    from symcable.solvers.stepcache import STEP_CACHE
    damped = _run(study, tmp_path)
    assert damped.stats["substepped_steps"] == 0
    monkeypatch.setattr(galpha1, "NEWTON_DAMPING", 1.0)
    STEP_CACHE.clear()  # the steps built with the damping
    try:
        plain = _run(study, tmp_path)
    finally:
        STEP_CACHE.clear()  # no undamped step left for later tests
    assert plain.stats["substepped_steps"] >= 1
    assert plain.stats["first_substep_time"] == pytest.approx(-2.1)
