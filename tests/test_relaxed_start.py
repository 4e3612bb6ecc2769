"""Slack cables that Newton on the equations could not reach from the closed-form starts
(scenes of the fuzz study, rounded), and the contact and grounded-length fixes found with
them:

- a slack pile of chain or wire on the seabed, reached from the minimum of the line's
  potential energy (:mod:`symcable.models.common.relax`), against the closed-form elastic
  catenary with seabed;
- a vertical line folded inside one of its two segments, whose nearly shut segment the slack
  law's wall holds open with a push within the bound (FOLD_PUSH of a segment's weight);
- a held end above the seabed carries its half segment itself, even when that segment
  reaches down to the bed;
- a light section between heavy ones on the bed does not count as more grounded line than
  lies in contact.
"""
from __future__ import annotations

import math

import numpy as np
import pytest

import symcable as sc
from symcable.analytic import elastic_catenary
from symcable.models.common.segments import FOLD_PUSH

G = 9.80665
RHO = 1025.0


def _w(mass, d):
    """Submerged weight per length, N/m, of a line of mass (kg/m) and diameter (m)."""
    return (mass - RHO * math.pi * d * d / 4.0) * G


PILE_CHAIN = {  # fuzz s11-0040: 35 m of chain, 15.5 m of it piled within 2 m of span
    "line_types": {"chain": {"mass": 264.7, "diameter": 0.1153, "EA": 1.3685e8}},
    "sections": [{"type": "chain", "length": 35.0, "segments": 15}],
    "end_a": {"condition": "pinned", "position": [0.0, -198.1]},
    "end_b": {"condition": "pinned", "position": [-2.045, -178.57]},
    "environment": {"depth": 198.1}, "seabed": {"stiffness": 27670.0}}

PILE_WIRE = {  # fuzz s11-0084: 1027 m of wire, 447 m on the bed within 203 m of span
    "line_types": {"wire": {"mass": 69.36, "diameter": 0.1178, "EA": 9.806e9}},
    "sections": [{"type": "wire", "length": 1026.8, "segments": 49}],
    "end_a": {"condition": "pinned", "position": [-299.34, -346.81]},
    "end_b": {"condition": "pinned", "position": [-96.16, -926.16]},
    "environment": {"depth": 926.16}, "seabed": {"stiffness": 7.339e6}}


@pytest.mark.parametrize("scene", [PILE_CHAIN, PILE_WIRE], ids=["chain", "wire"])
def test_slack_pile_matches_the_closed_form(scene):
    st = sc.solve_static(scene)
    assert st.status == "converged"
    lt = next(iter(scene["line_types"].values()))
    sec = scene["sections"][0]
    w, L, n = _w(lt["mass"], lt["diameter"]), sec["length"], sec["segments"]
    pa, pb = (np.array(scene[k]["position"]) for k in ("end_a", "end_b"))
    anchor, fair = (pa, pb) if pa[1] < pb[1] else (pb, pa)
    ref = elastic_catenary(abs(fair[0] - anchor[0]), fair[1] - anchor[1], L, lt["EA"], w,
                           seabed=True)
    assert ref.H == 0.0 and ref.grounded_length > 0.0  # the closed form is fully slack
    T_fair = st.fairlead_tension if fair is pb else st.anchor_tension
    T_anchor = st.anchor_tension if fair is pb else st.fairlead_tension
    # the touchdown falls between nodes: first order, about one segment's weight / length
    seg_w, ds = w * L / n, L / n
    assert abs(T_fair - ref.fairlead_tension) <= seg_w, (T_fair, ref.fairlead_tension)
    assert T_anchor <= seg_w  # the pile carries (almost) nothing to the anchor
    assert abs(st.grounded_length - ref.grounded_length) <= ds
    # no cable pushes beyond the bound, no segment crossed shut
    assert st.axial_force.min() >= -max(1e-4 * w * L, FOLD_PUSH * seg_w)
    assert st.strain.min() > -1.0


def test_fold_inside_one_of_two_segments():
    # fuzz s11-0619: 5.8 m of wire in 2 segments between ends 2.9 m apart on a vertical:
    # the lower segment folds shut, held open by the law's wall
    scene = {"line_types": {"wire": {"mass": 41.25, "diameter": 0.0908, "EA": 4.58e6}},
             "sections": [{"type": "wire", "length": 5.824, "segments": 2}],
             "end_a": {"condition": "pinned", "position": [0.0, -414.513]},
             "end_b": {"condition": "pinned", "position": [-4.27e-5, -411.624]}}
    st = sc.solve_static(scene)
    seg_w = _w(41.25, 0.0908) * 5.824 / 2
    assert st.status == "converged"
    assert st.axial_force.min() >= -FOLD_PUSH * seg_w
    assert st.strain.min() < -0.9 and st.strain.min() > -1.0  # bunched, not crossed
    assert any("slack in the water column" in m for m in st.warnings)
    # the ends carry the weight (end forces are what the line pulls on them: down), the
    # upper end B the most; the closed form's split (498 N / 1478 N) to within a segment's
    # weight, as the warning says
    assert abs(-st.anchor_force[1] - st.fairlead_force[1] - 2 * seg_w) <= 1e-6 * seg_w
    assert abs(st.anchor_tension - 498.1) <= seg_w and abs(st.fairlead_tension - 1478.5) <= seg_w


def test_held_end_above_the_seabed_carries_its_half_segment():
    # fuzz s11-0558 in small: segments (40 m) longer than the ends' height over the bed (30
    # m), so each end segment reaches down to the bed; the end node is not on the bed and
    # its half segment's weight is its own to carry (it rested on the bed before)
    w_m, d = 130.0, 0.08
    scene = {"line_types": {"chain": {"mass": w_m, "diameter": d, "EA": 3.5e8}},
             "sections": [{"type": "chain", "length": 400.0, "segments": 10}],
             "end_a": {"condition": "pinned", "position": [0.0, -50.0]},
             "end_b": {"condition": "pinned", "position": [330.0, -50.0]},
             "environment": {"depth": 80.0}, "seabed": {"stiffness": 3e5}}
    st = sc.solve_static(scene)
    half = 0.5 * _w(w_m, d) * 40.0
    # what the line pulls down on each end: at least its half segment (1e-6: round-off of
    # the contact's smoothing, which carries k d delta^2 / 4h per metre at a height h)
    for f in (st.anchor_force, st.fairlead_force):
        assert -f[1] >= half * (1 - 1e-6), (f, half)


def test_grounded_length_of_a_light_section_between_heavy_ones():
    # fuzz s11-1130: chain - wire - chain, the anchor chain and the wire on the bed; the
    # wire (70 N/m) between chains (850 and 2300 N/m) carries some of their weight where the
    # line curves over the penalty bed: the contact over its own weight counted 17 m of line
    # that is not there
    scene = {"line_types": {"c0": {"mass": 102.95, "diameter": 0.0719, "EA": 3.51e8},
                            "w1": {"mass": 8.536, "diameter": 0.0413, "EA": 1.173e9},
                            "c2": {"mass": 272.37, "diameter": 0.117, "EA": 6.705e6}},
             "sections": [{"type": "c0", "length": 14.216, "segments": 24},
                          {"type": "w1", "length": 12.258, "segments": 31},
                          {"type": "c2", "length": 48.118, "segments": 18}],
             "end_a": {"condition": "pinned", "position": [0.0, -41.892]},
             "end_b": {"condition": "pinned", "position": [63.03, -20.078]},
             "environment": {"depth": 41.892}, "seabed": {"stiffness": 2.4655e5}}
    st = sc.solve_static(scene)
    c = st.contact_force
    in_contact = np.flatnonzero(c > 0.01 * c.max())
    s_last = st.s[in_contact.max()]
    ds_max = 48.118 / 18
    assert abs(st.grounded_length - s_last) <= ds_max, (st.grounded_length, s_last)


def test_line_in_a_strong_current():
    # fuzz s11-0533: chain and wire in a 1.86 m/s current, which carries the line 128 m
    # downstream of ends 41 m apart; from the closed-form starts and by continuation in the
    # current Newton stalled; the energy start with the drag frozen at the last shape gets
    # it. The study's ODE shooting (DOP853, rtol 1e-11; no discretisation) gives T_A 4648.7
    # N, T_B 4298.1 N; 25 segments leave a second-order error (the study's tolerance
    # 4 / N_eff^2 of the tension scale: 1 % here)
    scene = {"environment": {"current": [1.8592, 0.0]},
             "line_types": {"c0": {"mass": 15.598, "diameter": 0.027997, "cd_normal": 1.59334,
                                   "cd_tangential": 0.051565, "EA": 2.87065e6},
                            "w1": {"mass": 6.1523, "diameter": 0.035078, "cd_normal": 1.11145,
                                   "cd_tangential": 0.29670, "EA": 2.05683e9}},
             "sections": [{"type": "c0", "length": 31.7045, "segments": 5},
                          {"type": "w1", "length": 96.2124, "segments": 20}],
             "end_a": {"condition": "pinned", "position": [13.7388, -38.3294]},
             "end_b": {"condition": "pinned", "position": [0.0, 0.0]}}
    st = sc.solve_static(scene)
    assert st.status == "converged"
    assert abs(st.anchor_tension - 4648.7) <= 0.01 * 4648.7
    assert abs(st.fairlead_tension - 4298.1) <= 0.01 * 4648.7
