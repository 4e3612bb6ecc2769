"""Shared scene builders for the tests (plain dicts in the scene-file layout), and the planar
dynamics' explicit rate through its Mechanism (:func:`planar_rates`)."""
from __future__ import annotations

import copy
import os
import tempfile

import pytest

# The suite runs the CasADi virtual machine by default: compiling every test scene (2-10 s
# each) would dominate CI. test_codegen.py asks for generated C explicitly, into a build
# cache of its own for this session.
os.environ.setdefault("SYMCABLE_CODEGEN", "0")
os.environ.setdefault("SYMCABLE_CACHE_DIR", tempfile.mkdtemp(prefix="symcable-test-cache-"))
# what is compiled, at -O0: the tests check what the C computes, not how fast it runs, and
# gcc builds a large straight-line kernel several times faster at -O0 (the performance
# study's --quick: 65 s at the default levels, 25 s at -O0)
os.environ.setdefault("SYMCABLE_CC_OPT", "-O0")

OC3 = {
    "name": "OC3 line",
    "model": "planar",
    "environment": {"water_density": 1025.0, "depth": 320.0},
    "seabed": {"stiffness": 1.0e5},
    "line_types": {"chain": {"EA": 3.84243e8, "mass": 77.7066, "diameter": 0.09,
                             "weight": 698.094, "cd_normal": 1.6, "cd_tangential": 0.1}},
    "sections": [{"type": "chain", "length": 902.2, "segments": 50}],
    "end_a": {"condition": "pinned", "position": [-853.87, -320.0]},
    "end_b": {"condition": "pinned", "position": [-5.2, -70.0]},
}


def two_point(a, b, *, length=100.0, segments=40, EA=1e7, weight=100.0, EI=0.0,
              depth=None, stiffness=None, **extra):
    """A single-section line pinned at a and b; weight given directly (N/m)."""
    d = {
        "name": "two-point line",
        "environment": {"water_density": 1025.0},
        "line_types": {"rope": {"EA": EA, "EI": EI, "mass": 20.0, "diameter": 0.05, "weight": weight}},
        "sections": [{"type": "rope", "length": length, "segments": segments}],
        "end_a": {"condition": "pinned", "position": list(a)},
        "end_b": {"condition": "pinned", "position": list(b)},
    }
    if depth is not None:
        d["environment"]["depth"] = depth
        d["seabed"] = {"stiffness": stiffness or 1e5}
    for k, v in extra.items():
        d[k] = v
    return d


@pytest.fixture
def oc3():
    return copy.deepcopy(OC3)


def seed001(**env):
    """The seed-001 line: OC3 geometry, EA 3.84243e7 N, Cd 1.6 both ways, Ca 1, suspended
    (no seabed), elliptic fairlead motion X = 2 cos wt, Z = 1 sin wt, T = 10 s."""
    d = copy.deepcopy(OC3)
    d["name"] = "seed-001 line"
    d["environment"] = {"water_density": 1025.0, "current": [0.5, 0.0], **env}
    d.pop("seabed")
    d["line_types"]["chain"].update(EA=3.84243e7, cd_normal=1.6, cd_tangential=1.6, ca_normal=1.0)
    d["end_b"]["motion"] = {"period": 10.0, "amplitude": [2.0, 1.0], "phase_deg": [0.0, -90.0]}
    return d


def taut_string(T=1e5, L=100.0, mass=10.0, EA=1e9, segments=50):
    """A weightless string in air pinned at both ends and pulled to tension T (N)."""
    eps = T / EA
    return {
        "name": "taut string",
        "environment": {"water_density": 0.0},
        "line_types": {"wire": {"EA": EA, "mass": mass, "diameter": 0.01, "weight": 0.0}},
        "sections": [{"type": "wire", "length": L, "segments": segments}],
        "end_a": {"condition": "pinned", "position": [0.0, 0.0]},
        "end_b": {"condition": "pinned", "position": [L * (1 + eps), 0.0]},
    }


def planar_rates(model):
    """``(rate, jacobian)`` of the planar DynamicModel ``model`` in its own state order y,
    composed from the derived Functions of its Mechanism
    (``symcable.mechanism.functions.functions(mechanism_of(model))``, permuted by ``state_permutation``):

    * ``rate(y, t, p) -> y'`` (n_y,): q' = ``qdot`` (the kinematics G v + w) and v' = M^-1 f
      with f = -``acc_residual``(q, v, a = 0).r_f;
    * ``jacobian(y, t, p) -> dy'/dy`` (n_y, n_y), dense: the state matrix
      [[H, G], [-M^-1 K, -M^-1 C]] of ``kinematics_jacobian`` (H, G) and ``tangents``
      (K, C; the planar mass matrix M is constant)."""
    import casadi as ca
    import numpy as np

    from symcable.mechanism.functions import functions
    from symcable.models.planar.mechanism import mechanism_of, state_permutation

    mech = mechanism_of(model)
    F = functions(mech)
    iq, iv = state_permutation(model)
    back = np.argsort(np.concatenate([iq, iv]))
    Minv = np.linalg.inv(np.atleast_2d(np.asarray(ca.evalf(mech.mass), dtype=float)))
    z = np.zeros(0)

    def rate(y, t, p):
        y = np.asarray(y, dtype=float).ravel()
        q, v = y[iq], y[iv]
        qd = np.asarray(F.qdot(q, v, z, t, p)).ravel()
        f = -np.asarray(F.acc_residual(q, v, np.zeros(v.size), z, t, p)[0]).ravel()
        return np.concatenate([qd, Minv @ f])[back]

    def jacobian(y, t, p):
        y = np.asarray(y, dtype=float).ravel()
        q, v = y[iq], y[iv]
        H, G = (np.array(a.full()) for a in F.kinematics_jacobian(q, v, z, t, p))
        K, C = (np.array(a.full()) for a in F.tangents(q, v, z, t, p)[:2])
        A = np.block([[H, G], [-Minv @ K, -Minv @ C]])
        return A[np.ix_(back, back)]

    return rate, jacobian


def load_study(name: str, script: str = "run.py"):
    """Import studies/<name>/<script> by file path (studies/ is not a package)."""
    import importlib.util
    from pathlib import Path

    path = Path(__file__).resolve().parents[1] / "studies" / name / script
    stem = "" if script == "run.py" else "_" + Path(script).stem
    spec = importlib.util.spec_from_file_location(f"study_{name}{stem}", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module
