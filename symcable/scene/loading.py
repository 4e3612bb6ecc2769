"""Drag loading functions of a line type (``drag_law = "loading-functions"``, cable3d): the
law of seed 003 (towed cables: Eames, Choo and Casarella, Pode) as a short Fourier series in
the angle of attack, ``[line_types.NAME.loading]`` (read by :mod:`.drag`).

The law
-------
With u the water's velocity relative to the line, t the line's unit tangent, u_t = u . t
and u_n = |u - u_t t|, the angle of attack psi is the ACUTE angle between the flow and the
line's axis, 0 <= psi <= 90 deg (cos psi = |u_t| / |u|, sin psi = u_n / |u|): the
classical loading functions are tabulated or fitted over that range, and a line whose
tangent is reversed feels the same drag. Per unstretched metre (the cable3d Morison law's
stretch factor sqrt(1 + e) included),

    D_n = 0.5 rho d cd |u|^2 f_n(psi)   along (u - u_t t) / u_n  (the flow's normal part),
    D_t = 0.5 rho d cd |u|^2 f_t(psi)   along sign(u_t) t         (with the flow, along t),

    f_n(psi) = a_0 + sum_k a_k cos(k psi) + sum_k b_k sin(k psi),   k = 1..8,
    f_t(psi) = c_0 + sum_k c_k cos(k psi) + sum_k d_k sin(k psi),

d the line type's ``diameter`` (m), rho the water density. The keys (all dimensionless):

- ``cd``: the reference drag coefficient (the seed's D_0, Pode's C_R; required, >= 0). It
  is not called R: in Pode's towed-cable theory R is the normal drag per metre,
  0.5 rho d C_R U^2 (N/m);
- ``normal_cos = [a_0, a_1, ...]``, ``normal_sin = [b_1, b_2, ...]``: f_n's cosine (from
  k = 0) and sine (from k = 1) coefficients; ``tangential_cos = [c_0, ...]``,
  ``tangential_sin = [d_1, ...]``: f_t's. At least one list per direction; at most
  :data:`MAX_HARMONIC` harmonics.

A drag law must not drive the line: f_n and f_t must be >= 0 over 0..90 deg (checked at
every half degree). Morison's law (``cd_normal``, ``cd_tangential``) is the special case
cd = 1, f_n = Cd_n sin^2 psi = Cd_n (1 - cos 2 psi) / 2, f_t = Cd_t cos^2 psi =
Cd_t (1 + cos 2 psi) / 2 (:meth:`LoadingFunctions.morison`), and Pode's law f_n = sin^2
psi, f_t = f (constant): ``normal_cos = [0.5, 0, -0.5]``, ``tangential_cos = [f]``.
"""
from __future__ import annotations

from typing import Any

from dataclasses import dataclass


import numpy as np

__all__ = ["DRAG_LAWS", "LOADING_KEYS", "MAX_HARMONIC", "LoadingFunctions"]

#: the drag laws a line type may name (``drag_law``)
DRAG_LAWS = ("morison", "loading-functions")
#: keys of ``[line_types.NAME.loading]``
LOADING_KEYS = ("cd", "normal_cos", "normal_sin", "tangential_cos", "tangential_sin")
#: the highest harmonic k a law may have: a short series (the published fits stop at 2 to 4)
MAX_HARMONIC = 8


@dataclass(frozen=True)
class LoadingFunctions:
    """A line type's drag loading functions (module docstring; all dimensionless).

    Attributes
    ----------
    cd : float
        Reference drag coefficient (>= 0).
    normal_cos, normal_sin : tuple of float
        f_n's cosine coefficients a_0, a_1, ... and sine coefficients b_1, b_2, ...
    tangential_cos, tangential_sin : tuple of float
        f_t's, likewise.
    """

    cd: float
    normal_cos: tuple[float, ...] = ()
    normal_sin: tuple[float, ...] = ()
    tangential_cos: tuple[float, ...] = ()
    tangential_sin: tuple[float, ...] = ()

    @classmethod
    def morison(cls, cd_normal: float, cd_tangential: float) -> "LoadingFunctions":
        """Morison's law as loading functions: f_n = Cd_n sin^2 psi, f_t = Cd_t cos^2 psi."""
        return cls(1.0, (0.5 * cd_normal, 0.0, -0.5 * cd_normal), (),
                   (0.5 * cd_tangential, 0.0, 0.5 * cd_tangential), ())

    def f_normal(self, psi) -> np.ndarray:
        """f_n at angles ``psi`` (rad), without ``cd``."""
        return _series(self.normal_cos, self.normal_sin, psi)

    def f_tangential(self, psi) -> np.ndarray:
        """f_t at angles ``psi`` (rad), without ``cd``."""
        return _series(self.tangential_cos, self.tangential_sin, psi)

    def to_dict(self) -> dict:
        """The ``[line_types.NAME.loading]`` table (lists given only when not empty)."""
        out: dict[str, Any] = {"cd": self.cd}
        for key in LOADING_KEYS[1:]:
            if getattr(self, key):
                out[key] = list(getattr(self, key))
        return out


def _series(cos, sin, psi) -> np.ndarray:
    psi = np.asarray(psi, float)
    out = np.zeros_like(psi)
    for k, a in enumerate(cos):
        out = out + a * np.cos(k * psi)
    for k, b in enumerate(sin, start=1):
        out = out + b * np.sin(k * psi)
    return out
