"""The studies' --quick modes: they run, write their outputs, and their numbers meet the issues'
criteria. No wall-clock assertions (speed is measured in studies, never asserted in a test)."""
from __future__ import annotations


import numpy as np
import pytest

from conftest import load_study


@pytest.fixture(scope="module")
def static_accuracy(tmp_path_factory):
    out = tmp_path_factory.mktemp("static_accuracy")
    res = load_study("static_accuracy").main(["--quick", "--out", str(out)])
    return out, res


def test_static_accuracy_writes_outputs(static_accuracy):
    out, res = static_accuracy
    for name in ("results.csv", "summary.md", "convergence.png"):
        assert (out / name).is_file() and (out / name).stat().st_size > 0, name
    assert len(res["rows"]) == 3 * 3  # three lines x (10, 20, 40) segments
    assert all(r["path"] == "newton" for r in res["rows"])


def test_static_accuracy_converges(static_accuracy):
    """The fairlead-tension error of every line falls with segments. The observed order of the
    suspended lines is within 0.5 of 2: the scheme is second order, and 0.5 is half-way to the
    first and third orders, so it catches a lost order while pre-asymptotic h^4 terms (which
    move the measured order by ~0.02 at 10-40 segments here) cannot trip it. The seabed line
    is left out of the order check: contact acts on nodes, so its error carries a term from
    where the touchdown falls between nodes (its 10 -> 20 order is ~1.4)."""
    _, res = static_accuracy
    for line in ("taut", "slack", "seabed"):
        errs = [abs(r["fairlead_rel_err"]) for r in res["rows"] if r["line"] == line]
        assert np.all(np.diff(errs) < 0), (line, errs)
    for line in ("taut", "slack"):
        assert np.all(np.abs(np.array(res["orders"][line]) - 2.0) < 0.5), res["orders"][line]


def test_static_accuracy_oc3_headline(static_accuracy):
    """The OC3 line as symcable/data/oc3.toml gives it (1e5 Pa/m seabed, 50 segments) against MoorPy: the
    issue's criteria, fairlead tension within 0.5 % and grounded length within 3 %."""
    _, res = static_accuracy
    h = res["oc3"]
    assert abs(h["fairlead_rel_diff"]) < 5e-3
    assert abs(h["grounded_rel_diff"]) < 3e-2


def test_performance_quick_writes_its_table(tmp_path):
    """The performance study's --quick mode runs symcable (C and VM), MoorPy and MoorDyn side by
    side and writes its table. Timing ratios are reported, never asserted (noisy shared
    machine); what is asserted is what could be wrong regardless of load:

    - MoorDyn's static-to-dynamic run reaches its own steady state, and both time runs are
      accurate to 1 % of the tension range against their own references;
    - the study's equal-accuracy step obeys generalized-alpha's second order: the errors at
      T/steps_equal and T/100 are in the ratio (100/steps_equal)^2 within a factor 2 (the
      quick mode's reference, T/400, carries 1/16 of the T/100 error, and higher-order terms
      move the ratio by some 20 % at these steps: measured 0.82 of the prediction), and the
      search stopped where the study says (no worse than MoorDyn RK4, or at its cap);
    - the Newton iterations per generalized-alpha step lie in [1, NEWTON_MAX_ITER];
    - the shooting error the study reports matches an independent recomputation in the
      virtual machine (the study ran generated C) to 1e-5 of the tension range: both periodic
      solves converge far below that (collocation to 1e-10 scaled residual, shooting to 1e-8),
      and C and VM agree to round-off; the error itself is generalized-alpha's at T/100,
      1.3e-3 of the range."""
    import symcable as sc
    from symcable.api.planar_time import NEWTON_MAX_ITER

    study = load_study("performance")
    res = study.main(["--quick", "--out", str(tmp_path)])
    assert (tmp_path / "summary.md").read_text().count("|") > 20
    tr, pe = res["time_run"], res["periodic"]
    assert tr["symcable_error"] < 0.01 and tr["moordyn_error"] < 0.01
    assert 1 <= pe["moordyn_periods_to_1pct"] <= 6
    n_eq = tr["steps_equal"]
    assert 1 <= n_eq <= study.N_EQUAL_MAX
    assert tr["symcable_error_equal"] <= tr["moordyn_RK4_error"] or n_eq == study.N_EQUAL_MAX
    predicted = (100.0 / n_eq) ** 2
    assert 0.5 < (tr["symcable_error_equal"] / tr["symcable_error"]) / predicted < 2.0, (n_eq, tr)
    assert 1.0 <= tr["symcable_newton_iterations_per_step"] <= NEWTON_MAX_ITER
    # shooting's answer is generalized-alpha's at T/100: 1.3e-3 of the range from collocation
    assert pe["shooting_error"] < 3e-3
    scene = sc.load_scene(sc.demo_scene_path("seed001"))
    model = sc.build_dynamic_model(scene)
    col = sc.solve_periodic(scene, "collocation", model=model, codegen=False)
    shot = sc.solve_periodic(scene, "shooting", model=model, codegen=False)
    ft = col.fairlead_tension
    again = float(np.max(np.abs(shot.fairlead_tension - ft)) / np.ptp(ft))
    assert abs(again - pe["shooting_error"]) < 1e-5, (again, pe["shooting_error"])


def test_mass_matrix_quick(tmp_path):
    """The mass-matrix study's --quick mode runs both matrices and writes its table and figure
    (its coarse grid, N = 4 and 8 at T/200, is not yet in the asymptotic range: 44 % and 184 %
    measured, so no order is asserted here; the full run's is in its README)."""
    rows = load_study("mass_matrix").main(["--quick", "--out", str(tmp_path)])
    assert (tmp_path / "mass_matrix.png").stat().st_size > 10_000
    assert sorted((r["mass_matrix"], r["segments"]) for r in rows) == [
        ("consistent", 4), ("consistent", 8), ("lumped", 4), ("lumped", 8)]
    assert all(np.isfinite(r["error_pct_range"]) and r["error_pct_range"] > 0 for r in rows)
    assert "T/200" in (tmp_path / "summary.md").read_text()


def test_mass_matrix_chains_quick(tmp_path):
    """The chain-deck comparison of the two mass matrices (--quick: WD0050 A1 at 0.1 s, the
    virtual machine) writes its table, each matrix's max error within 2 points of the full
    run's 8.4 / 8.0 % (measured in C: the virtual machine runs the same steps, so the two
    agree to round-off; 2 points is the full run's spread between the matrices plus a
    margin, and a broken mass matrix moves the error by tens of points)."""
    rows = load_study("mass_matrix", "chains.py").main(["--quick", "--out", str(tmp_path)])
    assert sorted(r["mass_matrix"] for r in rows) == ["consistent", "lumped"]
    errs = {r["mass_matrix"]: r["max_pct"] for r in rows}
    assert abs(errs["lumped"] - 8.4) < 2.0 and abs(errs["consistent"] - 8.0) < 2.0, errs
    assert "WD0050 A1" in (tmp_path / "chains.md").read_text()


def test_offsets_quick(tmp_path):
    """The offset study's --quick mode (OC3 lines, 10 segments, the virtual machine): every
    offset solved in the batch (no fallback), its forces within 2 % of MoorPy's catenaries
    (the 10-segment chain's discretisation: measured 0.60 % in surge and 1.0 % in pitch;
    0.13 % and 0.32 % at 20 segments in the full run), and its tables and figure written."""
    pytest.importorskip("moorpy")
    res = load_study("offsets").main(["--quick", "--out", str(tmp_path)])
    acc = [r for r in res["rows"] if r["measure"] == "accuracy"]
    assert {r["dof"] for r in acc} == {"surge", "pitch"}
    assert all(r["fallbacks"] == 0 and r["converged"] == r["offsets"] for r in acc)
    assert max(r["max_rel_error"] for r in acc) < 2e-2
    assert any(r["measure"] == "speed" and r["moorpy_ms_per_offset"] > 0 for r in res["rows"])
    assert (tmp_path / "offsets.png").stat().st_size > 10_000
    assert "MoorPy" in (tmp_path / "summary.md").read_text()


def test_hybrid_quick(tmp_path):
    """Seed 000's benchmark study (studies/hybrid, --quick: 20 and 40 segments): it writes its
    outputs; the pure rod's relaxation from straight ends at the static solution (5e-4 m: the
    Newton tolerance and the 1 s steps' residual motion, measured 1.3e-4 m); the hybrid,
    where it exists, is the rod's within the issue's 1 % (tension) and 5 % (shear, moment in
    the rod zone)."""
    res = load_study("hybrid").main(["--quick", "--out", str(tmp_path)])
    for name in ("results.csv", "summary.md", "profiles.png", "speed.png"):
        assert (tmp_path / name).stat().st_size > 0, name
    assert res["relax"]["rod"]["pos_err"] < 5e-4
    for n, r in res["statics"]["hybrid"].items():
        if r is not None:
            d = r["diff"]
            assert d["tension_err"] < 0.01 and d["shear_err"] < 0.05 and d["moment_err"] < 0.05



def test_hybrid_laid_quick(tmp_path):
    """The laid-cable study's --quick mode (studies/hybrid/laid.py: the seed's cable laid on
    the bed, 3 m at ds = 0.1 m, its lifted guided end in a 0.5 m rod zone): it writes its
    tables; the hybrid has fewer unknowns than the rod (3 per catenary node against 4) and
    rod fraction 0.5 / 3; its tension is the rod's within the issue's 1 % of the peak
    everywhere (measured 0.56 %; 0.65 % at the full run's 5 cm) and its nodes within 3 cm
    (measured 1.9 cm: the EI = 0 catenary takes the lift-off ~1 m from the end, outside the
    rod zone, as the benchmark's sags 3.8 cm deeper); both stay at rest over their 1 s steps
    (1e-6 m: they start at their own static solutions). Speed is measured in the study, not
    asserted here."""
    res = load_study("hybrid", "laid.py").main(["--quick", "--out", str(tmp_path)])
    for name in ("results_laid.csv", "summary_laid.md"):
        assert (tmp_path / name).stat().st_size > 0, name
    rows = {r["model"]: r for r in res["rows"]}
    rod, hyb = rows["rod"], rows["hybrid"]
    assert hyb["n_q"] < rod["n_q"] and hyb["f"] == pytest.approx(0.5 / 3.0)
    assert hyb["tension_err"] < 0.01 and hyb["pos_err"] < 0.03
    assert rod["drift"] < 1e-6 and hyb["drift"] < 1e-6

def test_work_precision_rod_quick(tmp_path):
    """The rod and hybrid work-precision rows' --quick mode (studies/work_precision/
    run_rod.py: the damped rod cantilever heaving at its clamp, T = 1 s, and the taut
    cable3d-rod-cable3d hose heaving at end B, T = 2 s; GA1 through ``sc.simulate`` at T/25,
    T/50, T/100 against T/400, 2 periods, the VM): every run converges, the node-position
    error falls as dt falls, and from T/50 to T/100 faster than first order (measured orders
    1.56 on the rod, 1.46 on the hybrid: not yet asymptotic at these steps, the full run's
    finer steps approach 2; 1.3 catches a scheme that lost its second order)."""
    res = load_study("work_precision", "run_rod.py").main(["--quick", "--out", str(tmp_path)])
    for name in ("results.csv", "summary.md", "work_precision_rod.png"):
        assert (tmp_path / name).is_file() and (tmp_path / name).stat().st_size > 0, name
    assert [c["case"] for c in res["cases"]] == ["rod cantilever", "hybrid hose"]
    for c in res["cases"]:
        rows = [r for r in c["rows"] if r["method"] == "ga1"]
        assert all(r["status"] == "converged" for r in rows), c["case"]
        errs = [r["error"] for r in rows]
        assert np.all(np.diff(errs) < 0), (c["case"], errs)
        assert dict(c["orders"])["T/50->T/100"] > 1.3, (c["case"], c["orders"])


def test_stability_rod_quick(tmp_path):
    """The rod stability rows' --quick mode (studies/stability/run_rod.py): the twisted rod
    clamped at both ends at 0.95 of Greenhill's moment (10 segments) is stable and its
    lowest frequency near zero: below half the unloaded clamped-clamped beam's 22.373 /
    (2 pi) sqrt(B / (m L^4)) = 3.561 Hz (measured 1.687 Hz; the straight rod buckles at
    M_cr = 9.519 B/L at 10 segments, and f^2 falls roughly as 1 - (M / M_cr)^2: 1.6 Hz);
    the seed's benchmark relaxing from straight at the seed's 1 s is reported, a failure as
    its ConvergenceError's one-line message (not raised), and the tables are written."""
    res = load_study("stability", "run_rod.py").main(["--quick", "--out", str(tmp_path)])
    for name in ("results.csv", "summary.md"):
        assert (tmp_path / name).is_file() and (tmp_path / name).stat().st_size > 0, name
    green = next(c for c in res["cells"] if c["group"] == "Greenhill")
    assert 0.0 < green["lowest_frequency_hz"] < 0.5 * 3.561, green
    seed = next(c for c in res["cells"] if c["group"] == "seed dt")
    assert seed["dt_s" if seed["ok"] else "exc_type"] == (1.0 if seed["ok"] else "ConvergenceError")
    assert seed["ok"] or "dt = 1 s" in seed["message"], seed


def test_first_answer_quick_writes_its_table(tmp_path):
    """The first-answer study's --quick mode solves the three-line OC3 mooring in fresh
    processes and again with changed numbers beside MoorPy, random systems and simulate's
    first three calls, and writes its table. Times are reported, never asserted; asserted is
    that symcable's fairlead tensions are MoorPy's to 2e-3 (100 segments against MoorPy's
    exact elastic catenary with a rigid bed: measured 5e-4) in the fresh process and on
    every changed design (the reused template with new numbers)."""
    study = load_study("performance", "first_answer.py")
    res = study.main(["--quick", "--out", str(tmp_path)])
    assert (tmp_path / "summary.md").read_text().count("|") > 20
    assert res["cold_tension_diff"] < 2e-3
    assert res["resolve_tension_diff_max"] < 2e-3
    assert res["resolve_cases"] == 3 and res["random_n"] == 2
    assert all(res[f"simulate_{k}_s"] > 0 for k in ("first", "second", "third"))
    assert res["run_line_first_s"] > 0 and res["run_line_changed_s"] > 0
    # with an empty build cache the default answered in the virtual machine while its C
    # compiled in the background; waiting for the compiler answered in C
    assert not res["empty_background_compiled"] and res["empty_waiting_compiled"]
