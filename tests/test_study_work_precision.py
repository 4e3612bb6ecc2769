"""The work-precision study's --quick mode: it runs, writes its outputs, every method converges
over its (quick) grid, the periodic solvers agree with the reference, and shooting's error is
second order in its step. No wall-clock assertions (speed is measured in studies,
never asserted in a test)."""
from __future__ import annotations


import numpy as np

from conftest import load_study


def test_work_precision_quick(tmp_path):
    study = load_study("work_precision")
    res = study.main(["--quick", "--out", str(tmp_path)])

    for name in ("results.csv", "summary.md", "work_precision.png"):
        assert (tmp_path / name).is_file() and (tmp_path / name).stat().st_size > 0, name
    rows = res["rows"]
    assert {r["method"] for r in rows} == set(study.METHODS)
    assert all(r["status"] == "converged" for r in rows), [(r["config"], r["status"]) for r in rows]

    # each line of the plot (a method at fixed settings) gets more accurate as its resolution
    # grows: periods simulated (RK4), steps per period (generalized-alpha), harmonics,
    # collocation intervals
    for family in {r["family"] for r in rows}:
        errs = [r["error"] for r in sorted((r for r in rows if r["family"] == family),
                                           key=lambda r: r["resolution"])]
        assert np.all(np.diff(errs) < 0), (family, errs)

    # the finest quick collocation and harmonic balance are within 1 % of the tension range
    # of the (coarse) reference, and so is the reference's check (the largest H)
    for method in ("collocation-newton", "collocation-ipopt", "harmonic-balance"):
        best = min(r["error"] for r in rows if r["method"] == method)
        assert best < 1e-2, (method, best)
    assert res["reference_check"]["error"] < 1e-2

    # shooting is the fixed point of generalized-alpha's period map, so its error is that
    # integrator's, second order in dt: the first-harmonic amplitude's error (the cleanest of
    # the three; the coarse reference's own is ~1e-6 of the range) falls 3 to 5 times per
    # doubling of the steps per period (measured: 4.1 and 4.0 from T/25 to T/100)
    shots = sorted((r for r in rows if r["method"] == "shooting"), key=lambda r: r["resolution"])
    assert [r["resolution"] for r in shots] == list(study.QUICK.shoot_steps)
    for a, b in zip(shots, shots[1:]):
        assert b["resolution"] == 2 * a["resolution"]
        ratio = abs(a["err_a1"]) / abs(b["err_a1"])
        assert 3.0 <= ratio <= 5.0, (a["config"], b["config"], ratio)
    # the summary names the fastest periodic method to 0.1 % (which one is not asserted: it
    # is a wall-clock result)
    assert res["periodic_winner"]["method"] in study.PERIODIC


def test_work_precision_cable3d_quick(tmp_path):
    """The cable3d work-precision study's --quick mode (studies/work_precision/run3d.py: the
    3D line with seabed friction moved out of plane, 4 periods against RK4 at T/2048): it
    writes its outputs, every method converges, and the numbers hold what the study found:

    - generalized-alpha (both schemes) gets more accurate as dt falls, and the first-order
      scheme's error falls as dt^2 from T/200 to T/400 (measured order 2.07; 1.58 from T/100,
      before the asymptotic range: the full study finds 2.00 from T/400 on), within 0.4;
    - RK4 at 0.8 of its limit is within 1e-4 of the range (fourth order, measured 5e-7);
    - collocation (K = 20, d = 3) and harmonic balance (H = 5) are within 1 % of the range
      of the reference (measured 0.35 and 0.80 %);
    - shooting at T/100 (the period map of the ga1 rows' scheme, rho_inf 0) is within 0.5 %
      of the range of the ga1 row at T/100: the same discretisation, the difference what is
      left of the transient in the ga1 row's last of 4 periods (measured 1.30 against
      1.12 %)."""
    study = load_study("work_precision", "run3d.py")
    res = study.main(["--quick", "--out", str(tmp_path)])
    for name in ("results.csv", "summary.md", "work_precision_3d.png"):
        assert (tmp_path / name).is_file() and (tmp_path / name).stat().st_size > 0, name
    rows = res["rows"]
    assert {r["method"] for r in rows} == set(study.METHODS)
    assert all(r["status"] == "converged" for r in rows), [(r["config"], r["status"]) for r in rows]
    for scheme in ("ga1", "ga2"):
        errs = [r["error_disc"] for r in sorted((r for r in rows if r["method"] == scheme),
                                                key=lambda r: r["resolution"])]
        assert np.all(np.diff(errs) < 0), (scheme, errs)
    ga1 = dict(res["orders"]["ga1"]["pairs"])
    assert abs(ga1["dt=T/200 -> dt=T/400"] - 2.0) < 0.4, ga1
    assert next(r for r in rows if r["method"] == "rk4")["error_disc"] < 1e-4
    for method in ("collocation", "harmonic-balance"):
        assert next(r for r in rows if r["method"] == method)["error"] < 1e-2, method
    shot = next(r for r in rows if r["method"] == "shooting" and r["resolution"] == 100)
    twin = next(r for r in rows if r["method"] == "ga1" and r["resolution"] == 100)
    assert abs(shot["error"] - twin["error"]) < 5e-3, (shot["error"], twin["error"])
