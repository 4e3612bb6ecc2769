"""symcable: marine cable mechanics written once in CasADi.

Public API (stable names)::

    import symcable as sc
    scene = sc.load_scene("scene.toml")      # or a dict
    st = sc.solve_static(scene)              # StaticSolution

See the README for the scene-file contract and the CLI.
"""
from __future__ import annotations

from .api.analyses import (build_dynamic_model, build_mechanism, end_stiffness, linearize,
                           modal_analysis, simulate, solve_periodic, sweep_periodic)
from .errors import ConvergenceError, LimitError, ModelNote, SceneError, SymcableError
from .limits import Limits, limits
from .models import build_model
from .results.static import (BodyState, ModalSolution, PointState, StaticSolution,
                             SystemStaticSolution)
from .results.periodic import PeriodicSolution, PeriodicSweep
from .results.trajectory import Trajectory
from .scene import Scene, load_scene
from .results.line3d import LineTrajectory
from .api.cable3d_static import cable3d_mechanism
from .api.planar_static import solve_static
from .mechanism.assembly import Prescribed, Shared, assemble
from .mechanism.mechanism import (Bound, Mechanism, Output, ParamBlocks, PartLayout, Layout, Scales,
                               Start)
from .models.toys import toys
from .results.generic import (Equilibrium, Linearization, MechanismModes, MechanismTrajectory,
                                SceneLinearization)
from .results.periodic_generic import MechanismPeriodic
from .results.sweep import CaseResult, SweepResult
from .api.offsets import offset_sweep, offsets_along
from .results.offsets import OffsetSweep
from .sweep import read_sweep, run_sweep
from .solvers.equilibrium import solve_equilibrium
from .api.branch import trace_branch
from .solvers.branch import Branch, BranchPoint
from .api.rod_contact import SelfContact, self_contact
from .solvers.integrate import integrate
from .solvers.linearize import linearize_mechanism, mechanism_modes, output_sensitivity
from .solvers.options import (RK4, Collocation, GeneralizedAlpha, GeneralizedAlphaFirstOrder,
                              HarmonicBalance, Shooting)
from .solvers.periodic_mech import solve_periodic_mech
from .api.waves import SeaKinematics, wave_components, wave_kinematics
from .api.frequency import solve_frequency_domain
from .results.frequency import FrequencyResponse, LineSpectrum
from .api.coupling import Coupling, CouplingState
from .api.sensitivity import sensitivity
from .api.optimize import DesignResult, optimize
from .results.sensitivity import Sensitivity
from .scene.waves import Waves, WaveComponents
from . import analytic

__version__ = "0.1.0"

__all__ = [
    "ConvergenceError",
    "LimitError",
    "ModelNote",
    "SceneError",
    "SymcableError",
    # resource limits on what an input may make symcable read, allocate or run
    "Limits",
    "limits",
    "Scene",
    "ModalSolution",
    "PeriodicSolution",
    "PeriodicSweep",
    "StaticSolution",
    "SystemStaticSolution",
    "PointState",
    "BodyState",
    "Trajectory",
    "LineTrajectory",
    "cable3d_mechanism",
    "offset_sweep",
    "offsets_along",
    "OffsetSweep",
    "analytic",
    "build_dynamic_model",
    "build_mechanism",
    "build_model",
    "load_scene",
    "modal_analysis",
    "simulate",
    "solve_periodic",
    "solve_static",
    "sweep_periodic",
    "demo_scene_path",
    "end_stiffness",
    "linearize",
    "SceneLinearization",
    # linear waves ([environment.waves])
    "Waves",
    "WaveComponents",
    "SeaKinematics",
    "wave_kinematics",
    "wave_components",
    # the frequency domain
    "solve_frequency_domain",
    "FrequencyResponse",
    "LineSpectrum",
    # a host program's coupling (MoorDyn's Init/Step pattern)
    "Coupling",
    "CouplingState",
    # exact design sensitivities of a static state
    "sensitivity",
    "Sensitivity",
    "optimize",
    "DesignResult",
    # sweeps: a table of cases on Dask (pip install "symcable[sweep]")
    "run_sweep",
    "read_sweep",
    "SweepResult",
    "CaseResult",
    # the Mechanism core: any formulation, assembled parts, generic solvers
    "Mechanism",
    "Bound",
    "Output",
    "ParamBlocks",
    "PartLayout",
    "Layout",
    "Scales",
    "Start",
    "Prescribed",
    "Shared",
    "assemble",
    "toys",
    "Equilibrium",
    "Linearization",
    "MechanismModes",
    "MechanismPeriodic",
    "MechanismTrajectory",
    "solve_equilibrium",
    "trace_branch",
    "Branch",
    "BranchPoint",
    "self_contact",
    "SelfContact",
    "integrate",
    "solve_periodic_mech",
    "mechanism_modes",
    "linearize_mechanism",
    "output_sensitivity",
    "GeneralizedAlpha",
    "GeneralizedAlphaFirstOrder",
    "RK4",
    "Collocation",
    "HarmonicBalance",
    "Shooting",
    "__version__",
]


def demo_scene_path(name: str = "oc3"):
    """Path of a built-in scene's TOML file, found by its name.

    The built-in scenes are ``"oc3"`` (the OC3-Hywind mooring line on its seabed),
    ``"seed001"`` (the planar line of Boral, Hickey & Basu: suspended, current, elliptic
    fairlead motion), or any other of :func:`symcable.data.names`: ``"sphere"``,
    ``"sphere127"`` (the payload sphere of Sun, Zhu & LaRosa at 0.807 and 1.27 Hz),
    ``"towed_body"`` (their towed body: 355 m bare + 125 m faired cable, 12 kn, a 270 degree
    turn), ``"seed000_rod"`` and ``"seed000_hybrid"`` (the 2 m cable of Goyal & Perkins as
    a Kirchhoff rod, and as a catenary with the rod on its last 0.5 m).

    Parameters
    ----------
    name : str
        The scene's name, one of :func:`symcable.data.names`. Default ``"oc3"``.

    Returns
    -------
    Traversable
        The file (a :class:`pathlib.Path` when the package is installed as files), for
        :func:`symcable.load_scene` or ``open``.

    Raises
    ------
    SymcableError
        ``name`` is not a built-in scene's name (the message lists them).
    """
    from .data import names, scene_path
    path = scene_path(name) if isinstance(name, str) else None
    if path is None:
        raise SymcableError(f"demo scene = {name!r}: must be one of {', '.join(names())}")
    return path
