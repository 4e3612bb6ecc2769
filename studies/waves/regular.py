"""The periodic steady state in a regular wave against a long time run and the frequency
domain: OC3's chains on the spar of ``fd_vs_td.py`` moved by its RAOs in a regular wave
(H 6 m, T 10 s), every method through the public API at its defaults.

For each of ``solve_periodic``'s methods (shooting, collocation, harmonic balance): its
wall time and the largest difference of each fairlead segment's axial force over the period
from ``simulate``'s run of 40 periods (its default step for its tolerance), the
last period compared at the same phase, as a fraction of that force's range; and the
frequency domain's first-harmonic amplitude against the periodic one's.

``python regular.py`` writes ``regular.json``; ``--quick`` (8 segments, 12 periods) into
``out/``.
"""
from __future__ import annotations

import math
import sys
import time

import numpy as np

import symcable as sc
from fd_vs_td import scene, study_main

H, T = 6.0, 10.0


def run(quick: bool) -> dict:
    segments, periods = (8, 12) if quick else (20, 40)
    d = scene(segments, 1)
    d["environment"]["waves"] = {"kind": "regular", "height": H, "period": T}
    out = {"segments": segments, "periods": periods, "methods": {}}
    t0 = time.perf_counter()
    td = sc.simulate(d, duration=periods * T, progress=False)
    out["td_time"] = time.perf_counter() - t0
    out["td_warnings"] = list(td.warnings)
    t0 = time.perf_counter()
    fd = sc.solve_frequency_domain(d)
    out["fd_time"] = time.perf_counter() - t0
    w = 2 * math.pi / T
    last = td.time >= td.time[-1] - T - 1e-9
    for method in ("shooting", "collocation", "harmonic-balance"):
        t0 = time.perf_counter()
        try:
            per = sc.solve_periodic(d, method=method)
        except Exception as exc:  # a method's failure is a result of the study
            out["methods"][method] = {"error": f"{type(exc).__name__}: {exc}"[:300]}
            continue
        row = {"time": time.perf_counter() - t0, "lines": {}}
        tp = np.asarray(per.time)
        for name in per.lines:
            f_per = np.asarray(per.lines[name].axial_force)[:, -1]
            f_td = np.interp((tp % T) + td.time[last][0] - (td.time[last][0] % T),
                             td.time, td.lines[name].axial_force[:, -1])
            rng = float(np.ptp(td.lines[name].axial_force[last, -1]))
            dt = tp[1] - tp[0]
            h1 = abs(2 * np.sum((f_per - f_per.mean()) * np.exp(1j * w * tp)) * dt / T)
            row["lines"][name] = {"max_diff_over_range": float(np.max(np.abs(f_per - f_td))) / rng,
                                  "range": rng, "first_harmonic": float(h1),
                                  "fd_amplitude": float(abs(fd.lines[name].rao[0, -1]) * H / 2),
                                  }
            row["lines"][name]["fd_over_periodic"] = row["lines"][name]["fd_amplitude"] / h1
        out["methods"][method] = row
    return out


def main(argv=None) -> int:
    return study_main(__doc__, run, "regular", argv)


if __name__ == "__main__":
    sys.exit(main())
