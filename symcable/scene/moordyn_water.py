"""A MoorDyn deck's water kinematics options (``WaveKin``, ``Currents``, ``dtWave``) read
into the scene's environment, from the files MoorDyn reads beside the deck:

=================  =========================================================================
Currents 1 or 3    ``current_profile.txt`` (three header lines, then rows ``z ux [uy [uz]]``,
                   m and m/s) -> ``environment.current_profile`` (one row: a uniform
                   ``environment.current``); MoorDyn holds the end rows beyond them, as
                   symcable's profile does
WaveKin 7          ``wave_frequencies.txt`` (rows ``omega re im [beta]``: rad/s, the complex
                   amplitude in m, the direction in rad), summed as MoorDyn sums them,
                   elevation |A| sin(omega t - k x + arg A) -> ``[environment.waves]`` of
                   ``kind = "components"`` (phase 90 deg - arg A in symcable's cosine
                   convention; the 0 rad/s row, a constant level, left out), with Wheeler
                   stretching, as MoorDyn stretches these kinematics to the surface
WaveKin 3          ``wave_elevation.txt`` (rows ``t eta``: s, m), resampled at ``dtWave``
                   (default 0.25 s, MoorDyn's) from t = 0 to its last time, an even count,
                   and split into its discrete Fourier components up to 0.5 Hz (MoorDyn's
                   own cut), travelling toward +x: ``kind = "components"``
other values       refused in one line: 1 (externally driven: a program's, not a file's),
                   2 (the FFT grid: MoorDyn interpolates the spectrum onto an even grid; give
                   7 for the same file summed exactly), 4-6 and dynamic currents (2, 4+)
=================  =========================================================================

MoorDyn's waves start at full height at t = 0; symcable's ramp in over the ramp time of
:class:`~symcable.scene.waves.Waves` (a note says so). Above the instantaneous surface
MoorDyn's summed components give no fluid velocity; symcable's Wheeler stretching gives the
surface's (its lines, points and bodies are taken as submerged wherever they are). MoorDyn's ``water_grid.txt`` (the
grid it interpolates on) is not read: symcable evaluates the kinematics at the nodes.
"""
from __future__ import annotations

import math
import os
from typing import Callable

import numpy as np

from ..errors import LimitError, SceneError
from ..limits import read_bounded

__all__ = ["WATER_KEYS", "water_kinematics"]

#: the deck options this module reads
WATER_KEYS = ("wavekin", "currents", "dtwave")
#: MoorDyn's default dtWave, s
DT_WAVE = 0.25
#: MoorDyn's cut of a wave elevation series' spectrum (WaveGrid.cpp), rad/s: 0.5 Hz
ELEVATION_CUT = math.pi


def water_kinematics(values: dict, source: str, fail: Callable[[int, str], SceneError],
                     notes: list) -> dict:
    """The environment's ``current_profile`` / ``current`` and ``waves`` for the options
    ``values`` ({key of WATER_KEYS: (deck line, value)}) of the deck at ``source`` (its
    folder holds the files); ``fail(line, why)`` makes the one-line error; notes appended."""
    out: dict = {}
    folder = os.path.dirname(os.path.abspath(source)) if source not in ("", "<deck>") else None
    cur = values.get("currents")
    if cur is not None and cur[1] != 0:
        if cur[1] not in (1, 3):
            raise fail(cur[0], f"Currents = {cur[1]:g}: symcable reads 1 and 3 (a steady "
                               "profile, current_profile.txt); dynamic currents are not read")
        rows = _rows(folder, "current_profile.txt", cur[0], fail, skip=3, columns=2)
        uvw = np.zeros((rows.shape[0], 3))
        uvw[:, :min(3, rows.shape[1] - 1)] = rows[:, 1:4]
        if rows.shape[0] == 1:
            out["current"] = uvw[0].tolist()
        else:
            if len(set(rows[:, 0])) != rows.shape[0]:
                raise fail(cur[0], "current_profile.txt: two rows at the same z")
            out["current_profile"] = [[float(z), *map(float, u)] for z, u in zip(rows[:, 0], uvw)]
    kin = values.get("wavekin")
    if kin is None or kin[1] == 0:
        return out
    if kin[1] == 7:
        out["waves"] = _frequencies(_rows(folder, "wave_frequencies.txt", kin[0], fail,
                                          skip=0, columns=3), kin[0], fail, notes)
    elif kin[1] == 3:
        dt = values.get("dtwave", (kin[0], DT_WAVE))[1]
        if not dt > 0:
            raise fail(values["dtwave"][0], f"dtWave = {dt:g} s: must be > 0")
        rows = _rows(folder, "wave_elevation.txt", kin[0], fail, skip=0, columns=2)
        out["waves"] = _elevation(rows, dt, kin[0], fail, notes)
    else:
        why = {1: "externally driven waves are a program's (the coupling's host sets them), "
                  "not a file's",
               2: "the FFT grid interpolates the spectrum onto an even grid; WaveKin 7 reads "
                  "the same wave_frequencies.txt and sums it exactly"}.get(
            int(kin[1]) if float(kin[1]).is_integer() else -1, "not a wave option symcable reads")
        raise fail(kin[0], f"WaveKin = {kin[1]:g}: {why} (symcable reads 0, 3 and 7; or give "
                           "[environment.waves] in a scene)")
    notes.append(f"line {kin[0]}: WaveKin = {kin[1]:g}: symcable ramps the waves in over "
                 "their ramp time from t = 0 (MoorDyn starts them at full height)")
    return out


def _rows(folder: str | None, name: str, n: int, fail, *, skip: int,
          columns: int) -> np.ndarray:
    """The numeric rows of the file ``name`` beside the deck (after ``skip`` header lines),
    at least ``columns`` finite numbers each, read within the ``table_bytes`` limit."""
    if folder is None:
        raise fail(n, f"{name}: the deck was given as text, with no folder to read it from "
                      "(load the deck from its file)")
    path = os.path.join(folder, name)
    try:
        text = read_bounded(path, "table_bytes", name).decode("utf-8", "replace")
    except LimitError:
        raise
    except OSError as exc:
        raise fail(n, f"{name} beside the deck cannot be read ({exc.strerror or exc})") from None
    parsed = []
    for k, line in enumerate(text.splitlines()[skip:], start=skip + 1):
        if not line.strip():
            continue
        try:
            parsed.append([float(v) for v in line.split()])
        except ValueError:
            raise fail(n, f"{name}: line {k} is not numbers: {line.strip()[:60]!r}") from None
    width = max((len(r) for r in parsed), default=0)
    if any(len(r) < columns for r in parsed):
        width = 0  # refused below
    rows = np.array([r + [0.0] * (width - len(r)) for r in parsed]) if parsed and width \
        else np.zeros((0, 0))
    if rows.shape[0] < 1 or rows.shape[1] < columns or not np.all(np.isfinite(rows)):
        raise fail(n, f"{name}: needs rows of at least {columns} finite numbers (got "
                      f"{rows.shape[0]} rows of {rows.shape[1] if rows.ndim == 2 else 0})")
    return rows


def _frequencies(rows: np.ndarray, n: int, fail, notes: list) -> dict:
    """``wave_frequencies.txt`` as components (module docstring)."""
    w, A = rows[:, 0], rows[:, 1] + 1j * rows[:, 2]
    beta = rows[:, 3] if rows.shape[1] > 3 else np.zeros(w.size)
    if np.any(w < 0) or np.any(np.abs(beta) > 2 * math.pi):
        raise fail(n, "wave_frequencies.txt: frequencies must be >= 0 rad/s and directions "
                      "within +-2 pi rad")
    if np.any((w == 0) & (np.abs(A) > 0)):
        notes.append(f"line {n}: wave_frequencies.txt: the 0 rad/s component (a constant "
                     "level) left out")
    keep = (w > 0) & (np.abs(A) > 0)
    if not np.any(keep):
        raise fail(n, "wave_frequencies.txt: no component above 0 rad/s with an amplitude")
    return {"kind": "components", "stretching": "wheeler", "amplitudes": np.abs(A[keep]).tolist(),
            "omegas": w[keep].tolist(),
            "phases_deg": (90.0 - np.degrees(np.angle(A[keep]))).tolist(),
            "directions_deg": np.degrees(beta[keep]).tolist()}


def _elevation(rows: np.ndarray, dt: float, n: int, fail, notes: list) -> dict:
    """``wave_elevation.txt`` as its discrete Fourier components (module docstring)."""
    t, eta = rows[:, 0], rows[:, 1]
    if rows.shape[0] < 2 or not np.all(np.diff(t) > 0) or t[-1] <= 0:
        raise fail(n, "wave_elevation.txt: needs times increasing from 0 (s) with elevations")
    count = int(math.floor(t[-1] / dt)) + 1
    count -= count % 2
    if count < 4:
        raise fail(n, f"wave_elevation.txt: {t[-1]:g} s of record is under 4 samples of "
                      f"dtWave = {dt:g} s")
    X = np.fft.rfft(np.interp(np.arange(count) * dt, t, eta))
    w = np.arange(X.size) * 2.0 * math.pi / (count * dt)
    amp = 2.0 * np.abs(X) / count
    amp[-1] *= 0.5  # the Nyquist bin
    keep = (w > 0) & (w <= ELEVATION_CUT) & (amp > 0)
    notes.append(f"line {n}: wave_elevation.txt: {count} samples at {dt:g} s, "
                 f"{int(np.sum(keep))} components up to 0.5 Hz, travelling toward +x")
    return {"kind": "components", "amplitudes": amp[keep].tolist(), "omegas": w[keep].tolist(),
            "phases_deg": (-np.degrees(np.angle(X[keep]))).tolist()}
