"""The sea of a scene in numbers: :func:`wave_kinematics` (elevation, fluid velocity and
acceleration at given points and times) and :func:`wave_components`."""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import SymcableError
from ..analytic.waves import airy
from ..scene import Scene, load_scene
from ..scene.waves import WaveComponents, Waves

__all__ = ["SeaKinematics", "wave_components", "wave_kinematics"]


@dataclass(frozen=True)
class SeaKinematics:
    """Linear wave kinematics at points and times.

    Attributes
    ----------
    t : numpy.ndarray
        (nt,) times, s.
    points : numpy.ndarray
        (m, 3) positions, m.
    elevation : numpy.ndarray
        (nt, m) the surface elevation above each point's (x, y), m.
    velocity, acceleration : numpy.ndarray
        (nt, m, 3) the fluid's velocity (m/s) and local acceleration (m/s^2) at each point.
    """

    t: np.ndarray
    points: np.ndarray
    elevation: np.ndarray
    velocity: np.ndarray
    acceleration: np.ndarray


def _sea(scene) -> tuple[Waves, float | None, float]:
    if isinstance(scene, Waves):
        return scene, None, 9.80665
    sc = scene if isinstance(scene, Scene) else load_scene(scene)
    env = sc.environment
    if env.waves is None:
        raise SymcableError(f"scene {sc.name!r} has no waves: give [environment.waves]")
    return env.waves, env.depth, env.gravity


def wave_components(scene) -> WaveComponents:
    """The components of a scene's sea (amplitudes, m; angular frequencies, rad/s; wave
    numbers, rad/m; phases and directions, rad), as its lines feel them.

    Parameters
    ----------
    scene : Scene, str, path or dict
        A scene with ``[environment.waves]`` (anything :func:`load_scene` takes), or a
        :class:`~symcable.scene.waves.Waves` (deep water, standard gravity).
    """
    waves, depth, g = _sea(scene)
    return waves.components_in(depth, g)


def wave_kinematics(scene, points, t, *, ramp: bool = False) -> SeaKinematics:
    """The sea's elevation, fluid velocity and fluid acceleration at ``points`` and times
    ``t``: the sea the lines' equations feel (:mod:`symcable.models.common.waves`), in
    NumPy (:func:`~symcable.analytic.waves.airy`).

    Parameters
    ----------
    scene : Scene, str, path, dict or Waves
        A scene with ``[environment.waves]``, or a :class:`~symcable.scene.waves.Waves`
        (deep water, standard gravity).
    points : array_like
        (m, 3) or (3,) positions, m (z up, 0 at the mean water level).
    t : float or array_like
        Times, s.
    ramp : bool
        Apply the sea's ramp from t = 0 (as a time run does); default False: the full sea.

    Returns
    -------
    SeaKinematics
    """
    waves, depth, g = _sea(scene)
    X = np.atleast_2d(np.asarray(points, dtype=float))
    times = np.atleast_1d(np.asarray(t, dtype=float))
    if X.ndim != 2 or X.shape[1] != 3 or not np.all(np.isfinite(X)):
        raise SymcableError(f"wave_kinematics: points must be finite, shape (m, 3) in m; got "
                            f"shape {np.shape(points)}")
    if times.ndim != 1 or not np.all(np.isfinite(times)):
        raise SymcableError("wave_kinematics: t must be finite times in s")
    c = waves.components_in(depth, g)
    amp = c.amplitude
    if ramp:  # one evaluation per time when ramped (the ramp scales every component)
        T = waves.ramp_time
        r = np.where(times <= 0.0, 0.0, np.where(times < T, 0.5 * (1.0 - np.cos(np.pi * times / T)),
                                                  1.0))
    else:
        r = np.ones_like(times)
    eta = np.empty((times.size, X.shape[0]))
    u = np.empty((times.size, X.shape[0], 3))
    a = np.empty_like(u)
    chunk = max(1, int(2e6 // max(1, X.shape[0] * amp.size)))  # bounded memory
    for i in range(0, times.size, chunk):
        sl = slice(i, i + chunk)
        e_, u_, a_ = airy(amp, c.omega, c.k, c.phase, c.direction, X, times[sl], depth,
                          waves.stretching)
        if ramp:
            if waves.stretching == "wheeler":  # the ramp changes the surface the column maps to
                for j, tj in enumerate(times[sl]):
                    e_[j:j + 1], u_[j:j + 1], a_[j:j + 1] = airy(
                        r[i + j] * amp, c.omega, c.k, c.phase, c.direction, X, [tj], depth,
                        waves.stretching)
            else:
                rr = r[sl]
                e_, u_, a_ = e_ * rr[:, None], u_ * rr[:, None, None], a_ * rr[:, None, None]
        eta[sl], u[sl], a[sl] = e_, u_, a_
    return SeaKinematics(times, X, eta, u, a)
