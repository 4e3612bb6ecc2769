"""One result type for the periodic analysis: ``sc.solve_periodic`` gives a
``sc.PeriodicSolution`` on every formulation (the planar line's dataclass; a 3D line's or a
scene's samples over the period as PeriodicLine / PeriodicSystem), each with the period, the
fairlead tension and its harmonics, summary, plot, save and load."""
from __future__ import annotations

import numpy as np
import pytest

import symcable as sc
from symcable.results.periodic_line import harmonics


def _planar() -> dict:
    d = sc.load_scene("seed001").to_dict()
    d["sections"][0]["segments"] = 10
    return d


@pytest.mark.parametrize("scene", [_planar(), "sphere"], ids=["planar", "system"])
def test_every_periodic_result_is_a_periodic_solution(scene, tmp_path):
    per = sc.solve_periodic(scene, steps=40)
    assert isinstance(per, sc.PeriodicSolution)
    assert per.period == pytest.approx(per.time[1] * len(per.time), rel=1e-12)
    amp = per.fairlead_tension_harmonics_amplitude
    assert amp[0] == pytest.approx(np.mean(per.fairlead_tension), rel=1e-12)
    assert per.fairlead_tension_amplitude == amp[1] > 0
    assert "period" in per.summary()
    back = type(per).load(per.save(tmp_path / "p.npz"))
    assert type(back) is type(per) and back.summary() == per.summary()
    assert per.plot(tmp_path / "p.png") is not None


def test_harmonics_are_the_fourier_series_of_the_samples():
    """From uniform samples over a period starting at t = 0, the harmonics are the scaled
    discrete Fourier coefficients (numpy's rfft, to round-off), and the truncated series
    reproduces a band-limited signal exactly."""
    T, n = 7.0, 64
    t = np.arange(n) * T / n
    w = 2 * np.pi / T
    x = 3.0 + 2.0 * np.cos(w * t + 0.4) + 0.5 * np.cos(3 * w * t - 1.1)
    amp, ph = harmonics(t, x, T)
    c = np.fft.rfft(x) / n
    np.testing.assert_allclose(amp[1:], 2 * np.abs(c[1:11]), atol=1e-12)
    np.testing.assert_allclose([amp[0], amp[1], ph[1], amp[3], ph[3]],
                               [3.0, 2.0, 0.4, 0.5, -1.1], atol=1e-12)
    shifted = harmonics(t + 1.0, 3.0 + 2.0 * np.cos(w * (t + 1.0) + 0.4), T)
    np.testing.assert_allclose(shifted[1][1], 0.4, atol=1e-12)  # phases on absolute time


def test_every_static_and_time_result_is_one_type():
    """sc.solve_static gives a sc.StaticSolution and sc.simulate a sc.Trajectory on every
    formulation: the planar line's, a 3D line's, a scene of several lines and points."""
    deck = sc.load_scene("seed001").to_dict()
    deck["sections"][0]["segments"] = 8
    for scene in (deck, "sphere", "seed000_hybrid"):
        assert isinstance(sc.solve_static(scene), sc.StaticSolution), scene
    for scene in (deck, "sphere"):
        tr = sc.simulate(scene, 1.0, dt=0.1)
        assert isinstance(tr, sc.Trajectory) and tr.fairlead_tension.shape == tr.time.shape
