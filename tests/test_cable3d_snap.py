"""Slack and snap in time (issue 12: "a slack segment and a snap are handled and reported,
not a crash"): a light rope whose fairlead is jerked into MoorDyn's heave table (its velocity
jumps from 0 to 1.26 m/s at the first row) goes slack and snaps taut."""
from __future__ import annotations

import numpy as np

import symcable as sc
from test_motion_table import REF, _scene


def _rope(damping: float) -> dict:
    d = _scene({"kind": "table", "file": REF})
    d["line_types"]["rope"]["damping"] = damping
    return d


def test_an_undamped_snap_runs_through_with_substeps():
    """Without material damping the snap's axial waves ring on; at dt = 0.1 s 3 steps
    converged only as 2 substeps (measured; 17 with rho_inf = 0.5), where the run used to
    stop."""
    tr = sc.simulate(_rope(0.0), 30.0, dt=0.1, codegen=True)
    st = tr.stats
    assert tr.status == "converged" and tr.time[0] == -10.0  # starts at the table's first row
    assert st["substepped_steps"] > 0 and st["max_substeps"] >= 2
    assert st["snaps"] >= 1 and 0 < st["slack_fraction"] < 1
    assert any("substeps" in w for w in tr.warnings) and any("snapped" in w for w in tr.warnings)
    assert np.all(np.isfinite(tr.fairlead_tension))
    assert np.min(tr.axial_force) > -1e-3 * np.max(tr.axial_force)  # a rope: no compression


def test_the_snap_peak_converges_in_dt():
    """With MoorDyn's damping (BA/-zeta = -1) the peak fairlead tension of the snap at the
    start is 31.1 kN at dt = 0.05 s and 29.2 kN at 0.0025 s (measured): within 10 %, the
    size of a snap peak's time error at a step 20 times coarser."""
    peaks = {dt: sc.simulate(_rope(-1.0), 2.0, dt=dt, codegen=True).fairlead_tension.max()
             for dt in (0.05, 0.0025)}
    assert abs(peaks[0.05] / peaks[0.0025] - 1) < 0.10, peaks
    static = sc.solve_static(dict(_rope(-1.0), end_b={k: v for k, v in _rope(-1.0)["end_b"].items()
                                                       if k != "motion"}))
    assert peaks[0.0025] > 2 * static.fairlead_tension  # 2.6 times: a snap, not a gentle pull
