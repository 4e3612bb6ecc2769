"""Where the rod's generated step costs go (studies/rod_notes/rodc14.md): SX instruction counts of the
dynamics residual, of the step's residual and iteration matrix, of the written-out LU, the
serialised size and generated C size of the step kernel, for rod (with / without the
reference frames' spin, isotropic / anisotropic), hybrid and cable3d of the same line.

    PYTHONPATH=$PWD python studies/rod_notes/rodc14_measure.py 8 20 40 [--compile] [--step]
"""
from __future__ import annotations

import math
import os
import sys
import tempfile
import time

import casadi as ca

from symcable.scene import load_scene
from symcable.api.scene3d import scene_mechanism
from symcable.models.rod.spin import with_reference_spin
from symcable.solvers import galpha1 as g1
from symcable.solvers.options import GeneralizedAlphaFirstOrder
from symcable.linalg.sparse import jacobian as _jacobian


def line(model, N, iso=False):
    L_, EI = 2.0, 10.0
    lt = {"EA": 1e4 * EI / L_**2, "EI": EI if iso or model == "cable3d" else [EI, 2 * EI],
          "mass": 1.0, "diameter": 0.02, "weight": 2.0 * EI / L_**3}
    if model != "cable3d":
        lt["GJ"] = 7.0
    d = {"model": model, "environment": {"water_density": 0.0},
         "line_types": {"beam": lt},
         "sections": [{"type": "beam", "length": L_, "segments": N}],
         "end_a": {"condition": "clamped", "position": [0.0, 0.0, 0.0],
                   "direction": [math.cos(0.7), math.sin(0.7), 0.0], "twist_deg": 30.0},
         "end_b": {"condition": "free"}}
    if model == "cable3d":
        del d["end_a"]["twist_deg"]
    if model == "hybrid":
        lt2 = dict(lt)
        lt2.pop("GJ")
        lt2["EI"] = EI
        d["line_types"]["cab"] = lt2
        d["sections"] = [{"type": "beam", "length": L_ / 2, "segments": N // 2, "model": "rod"},
                         {"type": "cab", "length": L_ / 2, "segments": N - N // 2}]
    return d


def measure(mech, compile_=False):
    out = {}
    t0 = time.perf_counter()
    dae = g1._sx_residual(mech)
    out["dae_instr"] = dae.n_instructions()
    ny = mech.n_q + mech.n_v
    x, t, h, p, st, _ = g1._symbols(mech, ca.SX)
    w = ca.SX.sym("w", ny)
    r = g1._step_residual(dae, w, x, t, h, p, st[0], ny)
    args = [w, x, t, h, p, st]
    R = ca.Function("R", args, [r], {"cse": True})
    J = _jacobian(r, w)
    Jf = ca.Function("J", args, [J.nz[:]], {"cse": True})
    out["ny"] = ny
    out["R_instr"] = R.n_instructions()
    out["J_instr"] = Jf.n_instructions()
    out["J_nnz"] = J.nnz()
    factor, solve, n_f, kind = g1._linear_solver(J, args, {}, True, mech.n_q)
    out["factor_instr"] = factor.n_instructions()
    out["solve_instr"] = solve.n_instructions()
    out["n_f"] = n_f
    out["parts_s"] = time.perf_counter() - t0
    t0 = time.perf_counter()
    opts = GeneralizedAlphaFirstOrder()
    kern = g1._unrolled(mech, opts.max_iter, False, True)
    out["kernel_s"] = time.perf_counter() - t0
    out["ser_MB"] = len(kern.serialize()) / 1e6
    with tempfile.TemporaryDirectory() as tmp:
        cg = ca.CodeGenerator("k.c")
        cg.add(kern)
        cg.generate(tmp + os.sep)
        out["C_MB"] = os.path.getsize(os.path.join(tmp, "k.c")) / 1e6
    return out, kern


if __name__ == "__main__":
    Ns = [int(a) for a in sys.argv[1:] if a.isdigit()]
    for N in Ns:
        for label, model, iso, spin in [("cable3d", "cable3d", True, False),
                                        ("rod iso", "rod", True, False),
                                        ("rod iso+spin", "rod", True, True),
                                        ("rod aniso", "rod", False, False),
                                        ("rod aniso+spin", "rod", False, True),
                                        ("hybrid+spin", "hybrid", False, True)]:
            sc = load_scene(line(model, N, iso))
            t0 = time.perf_counter()
            mech = scene_mechanism(sc)
            tb = time.perf_counter() - t0
            t0 = time.perf_counter()
            if spin:
                mech = with_reference_spin(mech)
            ts = time.perf_counter() - t0
            o, _ = measure(mech)
            print(N, label, f"build {tb:.2f}s spin {ts:.2f}s", o, flush=True)
