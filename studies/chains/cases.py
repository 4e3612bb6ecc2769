"""The chain cases of studies/chains: the reference data, the scenes symcable runs, its runs
and their errors (imported by run.py; see its docstring for the question).

Scene of a case (:func:`chain_scene`): ``symcable.scene.load_scene(deck)`` (the MoorDyn v2
deck: 41/76/170 segments, seabed kBot 1e5 Pa/m, cBot 1e4 Pa s/m, friction 0.5, BA/-zeta = -1)
with ``motion = {"kind": "table", "file": ...}`` added to the vessel end (end B) through
``to_dict()``. The loader (symcable/scene/moordyn.py) reads two keys as MoorDyn means them:

* ``cd_tangential = pi CdAx``: MoorDyn's tangential drag is 0.5 rho d pi CdAx |u| u per metre
  (Line.cpp: ``Dq = vq_mag * Cdt * pi * ...``), symcable's 0.5 rho d cd_tangential |u| u;
* ``seabed.friction_velocity = w ds / FricDamp``: MoorDyn's friction is
  min(mu FricDamp |v|, mu N) against the node's bed velocity (FricDamp default 200 N s/m,
  Line.cpp), symcable's mu N v / sqrt(|v|^2 + v_eps^2): the same slope mu N / v_eps at rest
  for a node carrying its own submerged weight N = w ds. For these decks v_eps = 166, 166,
  166 m/s: the friction is a light viscous drag on the bed (0.5 x 200 N s/m per node), far
  from its Coulomb cap at any speed of these runs. With symcable's default v_eps = 0.01 m/s
  it would be a stiff one: see the README.

The table: the motion files run from -10 s to 20 s, the reference's last sample; held after
its last row, the fairlead would stop dead at t = 20 s and the last sample would see it. The
study writes the table extended by one period (the heave is 10 s periodic: rows t + 10 for
10 < t <= 20) into the out dir and drives symcable with it.
"""
from __future__ import annotations

import time
from pathlib import Path

import numpy as np

from symcable.api.cable3d import NEWTON_TOL, RHO_INF
from symcable.api.cable3d_static import cable3d_mechanism
from symcable.scene import load_scene
from symcable.solvers.equilibrium import solve_equilibrium
from symcable.solvers.integrate import integrate
from symcable.solvers.options import GeneralizedAlpha, GeneralizedAlphaFirstOrder

#: ../shared/reference beside the repository
REF_DIR = Path(__file__).resolve().parents[3] / "shared" / "reference" / "moordyn-chains"
DECKS = ("WD0050", "WD0200", "WD0600")
MOTIONS = ("A1", "A2")
T0 = -10.0  # s: the tables' first row; every code starts at rest there
PERIOD = 10.0  # s: the heave's period


def deck_path(deck: str) -> Path:
    return REF_DIR / f"{deck}_Chain.txt"


def motion_rows(motion: str) -> np.ndarray:
    """(n, 7) rows t x y z rx ry rz of ``ZZP1_<motion>.txt``."""
    return np.loadtxt(REF_DIR / f"ZZP1_{motion}.txt")


def reference(deck: str, motion: str) -> np.ndarray:
    """OrcaFlex's series (MoorDyn's validation data): rows t, anchor distance (m), fairlead
    heave (m), fairlead tension (kN), anchor tension (kN), fairlead angle (deg)."""
    return np.loadtxt(REF_DIR / f"{deck}_Chain_ZZP1_{motion}.txt")


def extended_table(motion: str, out_dir: Path) -> Path:
    """The motion table continued by one period past its last row, written to ``out_dir``."""
    rows = motion_rows(motion)
    t_last = rows[-1, 0]
    tail = rows[rows[:, 0] > t_last - PERIOD + 1e-9].copy()
    tail[:, 0] += PERIOD
    path = Path(out_dir) / f"ZZP1_{motion}_extended.txt"
    np.savetxt(path, np.vstack([rows, tail]), fmt="%.10g")
    return path


def chain_scene(deck: str, table: Path):
    """The case's Scene (module docstring)."""
    d = load_scene(deck_path(deck)).to_dict()
    d["end_b"]["motion"] = {"kind": "table", "file": str(table)}
    return load_scene(d)


def errors(t, F, t_ref, F_ref, rng: float) -> dict:
    """Max, rms and mean of F (interpolated to t_ref) - F_ref, % of ``rng``."""
    e = np.interp(t_ref, t, F) - F_ref
    return {"max": 100 * float(np.max(np.abs(e))) / rng,
            "rms": 100 * float(np.sqrt(np.mean(e * e))) / rng,
            "mean": 100 * float(np.mean(e)) / rng}


#: Newton iterations per step of the first-order scheme: simulate's default (20). It was 30
#: (the start from rest into the table's full speed took 22 at dt = 0.2 s on WD0050); a
#: step that does not converge is now retried as substeps, and 20, 12 and 30 give the same
#: runs (the same steps substepped, the same tensions) while a step that fails costs
#: max_iter iterations: WD0200 A2 at 0.2 s 0.102 s with 20 against 0.117 s with 30
MAX_ITER_GA1 = GeneralizedAlphaFirstOrder().max_iter

#: the second GA1 row's rho_inf. simulate's default (0) damps the axial ringing from the
#: table's kinks at once and is robust at any step, but its dissipation also shifts the slow
#: response. Measured here (README): at 0.05 s rho_inf = 0.2 is the more accurate on five of
#: six (its max time error on WD0600 A2 0.2 % of the range against 0.7), at 0.1 s the less
#: accurate on five, and at 0.2 s it rings (10-72 %): a row beside the default, not a default
RHO_INF_LIGHT = 0.2

#: the symcable schemes of the study: name -> (method, what the name means)
SCHEMES = {
    "GA2": (lambda: GeneralizedAlpha(rho_inf=0.0),
            "second-order generalized-alpha (integrate's default scheme; its equations hold at "
            "the step's end), rho_inf = 0; always the CasADi virtual machine (its step is a "
            "CasADi rootfinder, which symcable does not generate C for)"),
    "GA1": (lambda: GeneralizedAlphaFirstOrder(rho_inf=RHO_INF, tol=NEWTON_TOL,
                                               max_iter=MAX_ITER_GA1),
            "first-order generalized-alpha (simulate's scheme and defaults: rho_inf = 0, "
            "Newton tolerance 1e-8, 20 iterations; its equations hold at t + alpha_f h); "
            "generated C when "
            "the study's codegen is on"),
    "GA1-rho0.2": (lambda: GeneralizedAlphaFirstOrder(rho_inf=RHO_INF_LIGHT, tol=NEWTON_TOL,
                                                      max_iter=MAX_ITER_GA1),
                   "the same first-order scheme with rho_inf = 0.2 (less numerical damping of "
                   "the low modes; its stiff axial modes decay by -0.2 per step instead of at "
                   "once); generated C when the study's codegen is on"),
}


class SymcableRun:
    """One symcable run of a scene at one step: ``once()`` does the static solve
    (:func:`solve_equilibrium`) and the run from T0 to ``t_end`` and returns
    (trajectory, static s, run s); the first call warms the caches (generated C, mapped step
    batches), later ones are timed by the caller."""

    def __init__(self, scene, dt: float, t_end: float, scheme: str, codegen=True):
        self.mech = cable3d_mechanism(scene)
        self.dt, self.t_end, self.codegen = dt, t_end, codegen
        self.method = SCHEMES[scheme][0]()

    def once(self):
        t0 = time.perf_counter()
        eq = solve_equilibrium(self.mech, codegen=self.codegen)
        t1 = time.perf_counter()
        tr = integrate(self.mech, self.t_end - T0, self.dt, t0=T0, start=eq,
                       p=self.mech.params.values, method=self.method, codegen=self.codegen,
                       period=PERIOD, progress=False)
        return tr, t1 - t0, time.perf_counter() - t1


def tensions(tr) -> dict:
    """kN series of a trajectory: ``fairlead`` / ``anchor`` (the force of the line on its
    end, ``end_force_b`` / ``end_force_a``: the end segment's tension plus the half segment's
    weight and drag lumped on the end node) and ``fairlead_segment`` / ``anchor_segment`` (the
    end segments' axial force, tension plus material damping: MoorDyn's FairTen)."""
    o = tr.outputs
    seg = np.asarray(o["axial_force"]).reshape(tr.time.size, -1)
    return {"time": tr.time, "fairlead": 1e-3 * np.linalg.norm(o["end_force_b"], axis=-1),
            "anchor": 1e-3 * np.linalg.norm(o["end_force_a"], axis=-1),
            "fairlead_segment": 1e-3 * seg[:, -1], "anchor_segment": 1e-3 * seg[:, 0]}
