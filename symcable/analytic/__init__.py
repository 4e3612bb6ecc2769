"""Closed-form and semi-analytic reference solutions (oracles for the tests and studies).

Everything here uses only NumPy and the standard library (rainflow counting excepted: the
``rainflow`` package's): the special functions (Carlson's symmetric elliptic integrals) and
the root finders (a damped 2x2 Newton, Brent's method) are written out, so that the oracles
do not share code with the solvers they check.

Contents
--------
* :func:`elastic_catenary` -- Irvine's elastic catenary between two points in a vertical
  plane, optionally touching down on a flat frictionless seabed at the level of end A.
* :func:`cantilever_tip_load` -- the inextensible elastica of a cantilever under a dead tip
  load (Bisshopp & Drucker 1945), in incomplete elliptic integrals.
* :func:`cantilever_tip_load_small`, :func:`heavy_cantilever_small` -- linear beam theory.
* :func:`taut_string_frequencies`, :func:`sagged_cable_frequencies` -- natural frequencies of
  a taut string and of a shallow sagged elastic cable (Irvine & Caughey 1974).
* :func:`twisted_loop` -- the localized loop of an infinite twisted rod under tension
  (Love's homoclinic solution): its shortening and end rotation.
* :func:`greenhill_moment` -- the critical twisting moment of a rod clamped at both ends
  under tension (Greenhill's problem).
* :func:`carlson_rf`, :func:`carlson_rd`, :func:`elliptic_f`, :func:`elliptic_e` -- the
  special functions these need.
* :func:`wave_number`, :func:`jonswap`, :func:`pierson_moskowitz`,
  :func:`spectrum_components`, :func:`airy` -- linear waves (:mod:`.waves`).
* :func:`rainflow_damage`, :func:`narrow_band_damage`, :func:`dirlik_damage`,
  :class:`TNCurve`, :data:`TN_CURVES` -- fatigue on DNV-OS-E301's and API RP 2SK's curves
  (:mod:`.fatigue`); :func:`rayleigh_mpm`, :func:`gumbel_mpm` -- most probable maxima
  (:mod:`.extremes`).

Conventions: SI units, planar (x, z) with z up, arc length ``s`` is the
unstretched length measured from end A (origin) to end B.
"""
from __future__ import annotations

from .catenary import VERTICAL_SPAN_RATIO, CatenarySolution, elastic_catenary
from .elastica import cantilever_tip_load, cantilever_tip_load_small, heavy_cantilever_small
from .frequencies import SaggedCableFrequencies, sagged_cable_frequencies, taut_string_frequencies
from .special import carlson_rd, carlson_rf, elliptic_e, elliptic_f
from .twisted_rod import TwistedLoop, greenhill_moment, twisted_loop
from .waves import airy, jonswap, pierson_moskowitz, spectrum_components, wave_number
from .fatigue import (TN_CURVES, TNCurve, dirlik_damage, equivalent_range, moments,
                      narrow_band_damage, nominal_area, rainflow_damage)
from .extremes import gumbel_mpm, rayleigh_mpm, zero_crossing_period

__all__ = [
    "airy", "jonswap", "pierson_moskowitz", "spectrum_components", "wave_number",
    "TN_CURVES", "TNCurve", "dirlik_damage", "equivalent_range", "moments",
    "narrow_band_damage", "nominal_area", "rainflow_damage", "rayleigh_mpm", "gumbel_mpm",
    "zero_crossing_period",
    "TwistedLoop",
    "twisted_loop",
    "greenhill_moment",
    "CatenarySolution",
    "VERTICAL_SPAN_RATIO",
    "elastic_catenary",
    "cantilever_tip_load",
    "cantilever_tip_load_small",
    "heavy_cantilever_small",
    "carlson_rf",
    "carlson_rd",
    "elliptic_f",
    "elliptic_e",
    "SaggedCableFrequencies",
    "sagged_cable_frequencies",
    "taut_string_frequencies",
]
