"""The 3D line the cable3d work-precision and stability studies share (studies are scripts,
not a package: each puts this folder on ``sys.path`` to import this module and study_io).

The line is the one of tests/test_cable3d_api.py: 110 m of rope (60 kg/m, 0.08 m, EA 5e7 N,
Cd 1.2 / 0.1, Ca 1, MoorDyn-style damping ratio 0.5 on its highest axial mode) from an anchor
on the bed at 60 m depth to a fairlead at (80, 30, -10) m, 10 segments (ds = 11 m); about a
third of it (35 m) lies on the bed at rest. Added here:

* Coulomb friction 0.5 on the bed (isotropic, regularised at 0.01 m/s, symcable's default);
* a normal damping of the bed of 1e4 Pa s/m: MoorDyn's default ratio cBot / kBot = 0.1 s
  (3e5 / 3e6) at symcable's 1e5 Pa/m. Without it the grounded nodes bounce on the soft bed
  (four modes at 1.6-2.0 Hz with damping ratios below 1 %, from ``modal_analysis``): a run
  from rest then keeps period-to-period changes of 1e-4 to 1e-3 of the tension range for 24
  periods and more (measured with RK4 at T/6400), and no time run has a periodic state to
  compare; with it a node bouncing on the bed has a damping ratio of about 0.55;
* the fairlead moved out of the line's vertical plane: amplitude [1, 2, HEAVE] m, phases
  [0, 30, -90] deg, period T = 8 s. The line's plane runs along (80, 30), so the 2 m in y
  swing the suspended part and the touchdown sideways, and the grounded nodes slide
  (the touchdown node) or are held by friction (the others).

HEAVE = 0.5 m ("smooth"): the touchdown rolls along the bed. HEAVE = 1.5 m ("landing", the
API test's heave): the fifth node is lifted 2.9 m off the bed and lands again at about
1 m/s once a period, an impact.
"""
from __future__ import annotations

import copy
import math

import numpy as np

from study_io import trig_interp  # studies/study_io.py: this folder is on sys.path

PERIOD = 8.0              # s
DEPTH = 60.0              # m
HEAVES = {"smooth": 0.5, "landing": 1.5}  # m, the fairlead's vertical amplitude
SEABED_DAMPING = 1.0e4    # Pa s/m (see the module docstring)
FRICTION = 0.5
CFL = 0.1                 # MoorDyn's CFL number (the chain decks' value)

BASE = {
    "model": "cable3d",
    "environment": {"depth": DEPTH},
    "line_types": {"rope": {"mass": 60.0, "diameter": 0.08, "EA": 5e7, "cd_normal": 1.2,
                            "cd_tangential": 0.1, "ca_normal": 1.0, "damping": -0.5}},
    "seabed": {"stiffness": 1e5, "damping": SEABED_DAMPING, "friction": FRICTION},
    "sections": [{"type": "rope", "length": 110.0, "segments": 10}],
    "end_a": {"condition": "pinned", "position": [0.0, 0.0, -DEPTH]},
    "end_b": {"condition": "pinned", "position": [80.0, 30.0, -10.0],
              "motion": {"kind": "harmonic", "period": PERIOD, "amplitude": [1.0, 2.0, 0.5],
                         "phase_deg": [0.0, 30.0, -90.0]}},
}


def scene_dict(case: str = "smooth", *, segments: int | None = None, name: str | None = None) -> dict:
    """The study line as a scene dict: ``case`` "smooth" or "landing" (the fairlead heave,
    :data:`HEAVES`), ``segments`` to refine it (default 10)."""
    d = copy.deepcopy(BASE)
    d["end_b"]["motion"]["amplitude"][2] = HEAVES[case]
    if segments is not None:
        d["sections"][0]["segments"] = int(segments)
    d["name"] = name or f"cable3d study line ({case})"
    return d


def moordyn_cfl_step(d: dict, cfl: float = CFL) -> float:
    """MoorDyn's time step for CFL number ``cfl``, s: cfl ds / c over the scene's sections,
    smallest, with ds the segment length and c = sqrt(EA / m) the axial wave speed (m the
    structural mass per metre, as MoorDyn's line mass)."""
    dts = []
    for s in d["sections"]:
        lt = d["line_types"][s["type"]]
        c = math.sqrt(lt["EA"] / lt["mass"])
        dts.append(cfl * (s["length"] / s["segments"]) / c)
    return min(dts)


def period_metrics(f) -> dict:
    """Max and min (of the trigonometric interpolant on 4096 points) and first-harmonic
    amplitude, N, of one period of fairlead tension sampled uniformly from t = 0 (mod T)."""
    x = np.asarray(f, float)
    fine = trig_interp(x, 4096) if x.size < 4096 else x
    return {"t_max_N": float(fine.max()), "t_min_N": float(fine.min()),
            "a1_N": float(2.0 * abs(np.fft.rfft(x)[1]) / x.size)}


def rel_error(m: dict, ref: dict) -> dict:
    """Signed errors of T_max, T_min, A_1 over the reference's range, and their largest
    magnitude (``error``)."""
    rng = ref["t_max_N"] - ref["t_min_N"]
    e = {f"err_{k}": (m[f"{k}_N"] - ref[f"{k}_N"]) / rng for k in ("t_max", "t_min", "a1")}
    e["error"] = max(abs(v) for v in e.values())
    return e


def per_period(time, f, period: float, t0: float = 0.0) -> list:
    """:func:`period_metrics` of every whole period of a uniformly sampled series (samples at
    t0 + k h, a whole number of them per period)."""
    t = np.asarray(time, float) - t0
    h = t[1] - t[0]
    n = int(round(period / h))
    f = np.asarray(f, float)
    return [period_metrics(f[k * n:(k + 1) * n]) for k in range(len(f) // n)]


def observed_orders(res: list, key: str = "error") -> list:
    """log2 of successive error ratios of runs whose resolution doubles: [(label, order)]."""
    out = []
    for a, b in zip(res, res[1:]):
        if a[key] > 0 and b[key] > 0:
            out.append((f"{a['config']} -> {b['config']}",
                        math.log(a[key] / b[key]) / math.log(b["resolution"] / a["resolution"])))
    return out
