"""symcable: marine cable mechanics written once in CasADi.

Public API (stable names)::

    import symcable as sc
    scene = sc.load_scene("scene.toml")      # or a dict
    st = sc.solve_static(scene)              # StaticSolution

See the README for the scene-file contract and the CLI.
"""
from __future__ import annotations

from .errors import ConvergenceError, SceneError, SymcableError
from .models import build_dynamic_model, build_model
from .results import StaticSolution
from .scene import Scene
from .scene_loader import load_scene
from .solvers.modal import ModalSolution, modal_analysis
from .solvers.static import solve_static
from . import analytic

__version__ = "0.1.0"

__all__ = [
    "ConvergenceError",
    "SceneError",
    "SymcableError",
    "Scene",
    "ModalSolution",
    "StaticSolution",
    "analytic",
    "build_dynamic_model",
    "build_model",
    "load_scene",
    "modal_analysis",
    "solve_static",
    "demo_scene_path",
    "__version__",
]


def demo_scene_path():
    """Path of the built-in demo scene (the OC3-Hywind mooring line, planar)."""
    from importlib.resources import files
    return files("symcable") / "data" / "oc3.toml"
