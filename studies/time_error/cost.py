"""What the run error estimate costs per step: the batched generalized-alpha steps of the
seed-001 line in generated C, with and without the estimate, side by side in one process.

The estimate is computed in NumPy on the states the batched calls return
(:class:`symcable.solvers.march.RunningEstimate`), nothing is added to the step. "without" is
the batched call alone (``_Stepper.run``), "with" the same call plus ``RunningEstimate.update``
on its steps. Batches of S steps between samples and m samples per call, as ``simulate`` makes
them: S = 1 (every step saved, m = 256) and S = 8 (m = 32). Interleaved rounds (the order
alternates), process time, medians (and the ratio of the fastest rounds); and, within the rounds
with the estimate, the time of ``update`` over the time of the batched calls (median), which the
neighbours' load affects alike.

Run ``python studies/time_error/cost.py [--rounds N]``. For the whole ``simulate`` against the
code before this change, in two processes, use studies/performance/compare_baseline_time.py
``--baseline <checkout>``.
"""
from __future__ import annotations

import argparse
import statistics
import time

import numpy as np

import symcable as sc
from symcable.mechanism.functions import functions
from symcable.models.planar.mechanism import mechanism_of, state_permutation
from symcable.solvers.integrate import _initial_state
from symcable.solvers.march import RunningEstimate, get_stepper
from symcable.solvers.options import GeneralizedAlphaFirstOrder

T = 10.0


def main(argv=None) -> dict:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--rounds", type=int, default=31)
    args = ap.parse_args(argv)
    scene = sc.load_scene(sc.demo_scene_path("seed001"))
    model = sc.build_dynamic_model(scene)
    mech = mechanism_of(model)
    iq, iv = state_permutation(model)
    y0, p = np.asarray(model.y0), np.asarray(model.p_value, dtype=float)
    opts = GeneralizedAlphaFirstOrder(rho_inf=0.5, tol=1e-10, max_iter=10)
    x0, _ = _initial_state(mech, functions(mech), opts, y0[iq], y0[iv], None, 0.0, p)
    st = get_stepper(mech, opts, True, lte=False)
    h, tau, calls = T / 100, T / (2 * np.pi), 4
    rows = []
    for S, m in ((1, 256), (8, 32)):
        st.batch(S, m)

        def run(with_estimate: bool, split: list):
            x = x0.copy()
            track = RunningEstimate(st.est, x0, tau)
            for b in range(calls):
                t0 = time.process_time()
                X, *_, Xs, Ls = st.run(S, m, x, b * S * m * h, h, p)
                x = X[-1].copy()
                t1 = time.process_time()
                if with_estimate:
                    track.update(h, Xs, Ls)
                split[0] += t1 - t0
                split[1] += time.process_time() - t1
            return x

        assert np.array_equal(run(False, [0, 0]), run(True, [0, 0]))
        times, share = {False: [], True: []}, []
        for r in range(args.rounds):
            for w in ((False, True) if r % 2 else (True, False)):
                split = [0.0, 0.0]
                t0 = time.process_time()
                run(w, split)
                times[w].append(1e6 * (time.process_time() - t0) / (calls * S * m))
                if w:
                    share.append(split[1] / split[0])
        n = calls * S * m
        row = {"S": S, "m": m, "compiled": st.compiled,
               "without_us": statistics.median(times[False]),
               "with_us": statistics.median(times[True]),
               "ratio": statistics.median(times[True]) / statistics.median(times[False]),
               "ratio_min": min(times[True]) / min(times[False]),
               "estimate_share": statistics.median(share)}
        rows.append(row)
        print(f"S = {S}, m = {m} (compiled {st.compiled}, {n} steps a round): without "
              f"{row['without_us']:.1f} us/step, with {row['with_us']:.1f} us/step (medians of "
              f"{args.rounds}), ratio {row['ratio']:.3f} (fastest rounds {row['ratio_min']:.3f}); "
              f"within the rounds with it, the estimate takes {100 * row['estimate_share']:.1f} % "
              "of the time of the batched steps (median)", flush=True)
    return {"rows": rows}


if __name__ == "__main__":
    main()
