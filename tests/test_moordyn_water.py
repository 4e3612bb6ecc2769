"""A MoorDyn deck's water kinematics (issue 36, item 1): ``Currents`` 1 and ``WaveKin`` 7 read
from the files beside the deck give MoorDyn's own kinematics (MoorDyn run live on the same
deck), ``WaveKin`` 3 reproduces its wave elevation series, and the others are refused in
one line."""
from __future__ import annotations

import os

import numpy as np
import pytest

import symcable as sc
from symcable.errors import SceneError

DECK = """--------------------- MoorDyn Input File ---------------------
a chain in waves and a current
---------------------- LINE TYPES ----------------------
TypeName Diam Mass/m EA BA/-zeta EI Cd Ca CdAx CaAx
(name) (m) (kg/m) (N) (N-s/-) (N-m^2) (-) (-) (-) (-)
chain 0.09 77.7 3.8e8 -0.8 0.0 1.6 1.0 0.03 0.0
---------------------- POINTS ----------------------
ID Attachment X Y Z Mass Volume CdA CA
(#) (-) (m) (m) (m) (kg) (m^3) (m^2) (-)
1 Fixed -300 0 -100 0 0 0 0
2 Coupled 0 0 -10 0 0 0 0
---------------------- LINES ----------------------
ID LineType AttachA AttachB UnstrLen NumSegs Outputs
(#) (name) (#) (#) (m) (-) (-)
1 chain 1 2 330 10 -
---------------------- OPTIONS ----------------------
0.001 dtM
100 WtrDpth
{wavekin} WaveKin
{currents} Currents
1 disableOutput
0 writeLog
--------------------- need this line ------------------
"""
#: omega (rad/s), complex amplitude (m), direction (rad): MoorDyn's wave_frequencies.txt
FREQUENCIES = "0.0 0.0 0.0\n0.5 1.0 0.5\n0.8 -0.3 0.7 0.5\n1.1 0.2 -0.4 -0.3\n"
PROFILE = ("--- a current profile\nheader\nz ux uy uz\n-100 0.2 0.0 0\n-50 0.5 0.1 0\n"
           "0 1.0 0.3 0\n")


def _deck(folder, wavekin=0, currents=0, files=()) -> str:
    path = folder / "deck.txt"
    path.write_text(DECK.format(wavekin=wavekin, currents=currents))
    for name, text in files:
        (folder / name).write_text(text)
    return str(path)


def test_frequencies_and_profile_are_moordyns(tmp_path):
    """WaveKin 7 and Currents 1: symcable's elevation, wave velocity plus profile current and
    acceleration at three points equal what MoorDyn (run live on the deck, stepped to 3.7 s)
    gives there (both sum the same components with Wheeler stretching)."""
    md = pytest.importorskip("moordyn")
    deck = _deck(tmp_path, 7, 1, [("wave_frequencies.txt", FREQUENCIES),
                                  ("current_profile.txt", PROFILE)])
    scene = sc.load_scene(deck)
    assert scene.environment.waves.kind == "components"
    assert scene.environment.current_profile[0] == (-100.0, 0.2, 0.0, 0.0)
    cwd = os.getcwd()
    os.chdir(tmp_path)
    try:
        system = md.Create(deck)
        md.SetVerbosity(system, md.LEVEL_ERR)
        md.Init(system, [0, 0, -10], [0, 0, 0])
        t = 0.0
        for _ in range(37):
            md.Step(system, [0, 0, -10], [0, 0, 0], t, 0.1)
            t += 0.1
        waves = md.GetWaves(system)
        pts = np.array([[0.0, 0.0, -10.0], [30.0, 5.0, -50.0], [-100.0, 20.0, -90.0]])
        kin = sc.wave_kinematics(scene, pts, t, ramp=False)
        prof = np.array(scene.environment.current_profile)
        for p, u, a, e in zip(pts, kin.velocity[0], kin.acceleration[0], kin.elevation[0]):
            mu, mud, zeta, _ = md.GetWavesKin(waves, *p)
            current = [np.interp(p[2], prof[:, 0], prof[:, i]) for i in (1, 2, 3)]
            # elevation, velocity and acceleration to 1e-8 of 1 m, 1 m/s and
            # 1 m/s^2 (measured 8e-11, 6.5e-10 and 3.1e-10: MoorDyn's iterative solve of the
            # dispersion relation against symcable's to the last digit)
            assert zeta == pytest.approx(e, abs=1e-8)
            assert np.allclose(mu, u + current, rtol=0, atol=1e-8)
            assert np.allclose(mud, a, rtol=0, atol=1e-8)
        md.Close(system)
    finally:
        os.chdir(cwd)


def test_elevation_series_is_reproduced(tmp_path):
    """WaveKin 3: the components' elevation at x = 0 is the series resampled at dtWave to
    round-off, for a series that its discrete Fourier components hold exactly (periodic over
    its 200 s record, nothing above MoorDyn's 0.5 Hz cut; a series that is not leaks across
    the cut, in MoorDyn's grid as here)."""
    t = np.arange(0.0, 200.0001, 0.25)  # at dtWave: its resampling changes nothing
    w = 2 * np.pi / 200.0 * np.array([13, 22, 41])  # 0.41, 0.69 and 1.29 rad/s
    eta = sum(a * np.cos(wi * t + p) for a, wi, p in zip([1.0, 0.5, 0.3], w, [0.3, 1.2, -2.0]))
    (tmp_path / "wave_elevation.txt").write_text(
        "\n".join(f"{float(a)!r} {float(b)!r}" for a, b in zip(t, eta)) + "\n")
    scene = sc.load_scene(_deck(tmp_path, 3))
    ts = np.arange(800) * 0.25  # MoorDyn's default dtWave, an even count
    ref = np.interp(ts, t, eta)
    kin = sc.wave_kinematics(scene, np.zeros((1, 3)), ts, ramp=False)
    assert np.allclose(kin.elevation[:, 0], ref, rtol=0, atol=1e-9)
    deck = sc.scene.load.moordyn_deck(tmp_path / "deck.txt")
    assert any("components up to 0.5 Hz" in n for n in deck.notes)


@pytest.mark.parametrize("wavekin,currents,match", [
    (1, 0, "WaveKin = 1: externally driven waves are a program's"),
    (2, 0, "WaveKin = 2: the FFT grid"),
    (5, 0, "WaveKin = 5: not a wave option"),
    (0, 2, "Currents = 2: symcable reads 1 and 3"),
    (7, 0, "wave_frequencies.txt beside the deck cannot be read"),
])
def test_other_options_refused_in_one_line(tmp_path, wavekin, currents, match):
    with pytest.raises(SceneError, match=match) as err:
        sc.load_scene(_deck(tmp_path, wavekin, currents))
    assert "\n" not in str(err.value)
