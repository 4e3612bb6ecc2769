"""Drag loading functions of a line type (``drag_law = "loading-functions"``, cable3d): the
law of Sun, Zhu & LaRosa (towed cables: Eames, Choo and Casarella, Pode) as a short Fourier
series in the angle of attack, ``[line_types.NAME.loading]`` (read by :mod:`.drag`).

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

- ``cd``: the reference drag coefficient (the paper's D_0, Pode's C_R; required, >= 0). It
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

Presets: Sun, Zhu & LaRosa's laws (``loading = "seed003-bare"`` or ``"seed003-faired"``)
--------------------------------------------------------------------------------------
A line type may name a preset instead of the table (``loading = "seed003-bare"``), or a
table with the preset and its own reference coefficient (``loading = {preset =
"seed003-bare", cd = 1.5}``); the presets are :data:`PRESETS` (their coefficients are what
``to_dict`` writes back). The paper of Sun, Zhu & LaRosa ("Dynamic modeling of cable towed
body using nodal position finite element method", Ocean Engineering 38 (2011)) gives the
bare cable's laws as its Eq. 28 and the faired cable's as Eq. 29, with D_0 = 1.70 (bare,
d = 0.0411 m) and 0.15 (faired, d = 0.0800 m) in its Table 3; our copy of the paper lost
Eq. 28's signs and all of Eq. 29. Reconstructed here (alpha the angle of attack, our psi):

- ``"seed003-bare"`` (Eq. 28): C_Dn = D_0 sin^2 psi, as printed; C_Dt = D_0 (0.019 +
  0.0239 cos psi - 0.02 sin psi - 0.001 cos 2 psi). Eq. 28 keeps the four magnitudes
  0.019, 0.0239 cos, 0.02 sin, 0.001 cos 2 without their signs; of the eight readings (the
  constant positive), those with -0.0239 cos psi are negative at axial flow (0.019 - 0.0239
  +- 0.001 < 0), those with +0.02 sin psi leave a tangential force of 0.038 to 0.040 D_0 at
  normal flow (where symmetry makes it zero) and peak near 45 deg, and +0.001 cos 2 psi with
  -0.02 sin psi is negative at 90 deg (-0.002). The one reading left is chosen: it is
  non-negative over 0..90 deg, largest at axial flow (0.0419 D_0 = 0.0712, skin friction
  along the armoured cable) and exactly zero at normal flow (0.019 - 0.02 + 0.001 = 0),
  falling monotonically between: the shape of the classical bare-cable tangential fits
  (Choo & Casarella 1973's survey, "A survey of analytical methods for dynamic simulation
  of cable-body systems", J. Hydronautics 7: f_t near 0.02 at axial flow, small at normal
  flow, for C_R near 1.5).
- ``"seed003-faired"`` (Eq. 29, lost: our reconstruction, not the paper's): C_Dn = D_0
  sin^2 psi and C_Dt = D_0 0.08 cos^2 psi, the crossflow (independence) principle, which
  Packwood (1990, "Performance of segmented swept and unswept cable fairings at low
  Reynolds numbers", Ocean Engineering 17, 393-407) found to predict swept fairings' drag
  better than the commonly used loading functions: the normal force the fairing's section
  drag D_0 on the flow's normal part, the tangential force skin friction over the fairing's
  wetted perimeter, about 2.1 chords (Packwood's section), on the axial part. With the
  chord taken as the reference 0.08 m and the ITTC-1957 friction line at 12 knots
  (Re = U c / nu = 6.17 x 0.08 / 1.19e-6 = 4.2e5, C_f = 0.075 / (log10 Re - 2)^2 =
  0.0057), the tangential coefficient at axial flow is 2.1 C_f = 0.0120 per metre of
  reference dimension, 0.080 D_0.
"""
from __future__ import annotations

from typing import Any

from dataclasses import dataclass


import numpy as np

__all__ = ["DRAG_LAWS", "LOADING_KEYS", "MAX_HARMONIC", "PRESETS", "LoadingFunctions"]

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


#: named laws (``loading = "NAME"``; module docstring: what they are and where from)
PRESETS = {
    "seed003-bare": LoadingFunctions(1.70, (0.5, 0.0, -0.5), (),
                                     (0.019, 0.0239, -0.001), (-0.02,)),
    "seed003-faired": LoadingFunctions(0.15, (0.5, 0.0, -0.5), (), (0.04, 0.0, 0.04), ()),
}
