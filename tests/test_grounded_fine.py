"""Grounded length of the OC3 line at fine meshes (issue 33).

On the penalty seabed a held anchor lying on the bed sits above the sunken line beside it:
the line sinks into the bed over the length lambda = sqrt(H / (k d)) = sqrt(737 kN /
(1e5 Pa/m x 0.09 m)) = 9.05 m, and the anchor props up that length's weight (its vertical
force, 6.29 kN = 9.0 m x 698 N/m), which the grounded length counts. It used to count it only
while the anchor node's contact force (its half segment takes its neighbour's penetration,
a fraction 1 - exp(-ds / lambda) of the full one) exceeded a tenth of its weight, i.e. for
segments longer than 0.95 m: from 1,000 segments (ds = 0.90 m) on the 9 m dropped out
(134.56 -> 125.55 m) and the touchdown was put 1.8 m from the anchor. The equilibrium was
right all along (same end forces, no lift-off, the node heights on the penalty bed's
exponential profile to 2.5e-5 m); a held end now rests on the grounded line where it lies on
the seabed (the contact models' own rule) and the line beside it sinks into the bed without
a break up to a node in contact, whatever the segment length.

Reference: MoorPy's catenary (rigid frictionless seabed, CB = 0), computed live: LBot =
134.786 m. Tolerance 1 m: on the built-in scene's soft seabed (1e5 Pa/m, 7.8 cm penetration
under the chain's weight) the grounded length converges to 134.562 m, 0.22 m short of the
rigid-bed value (on a 1e8 Pa/m bed it converges to 134.785 m, the last test); the
discretisation adds at most a fraction of a segment (the touchdown lies between nodes: at
most ds / 2 = 0.45 m at 1,000 segments; measured within 1e-3 m of 10,000 segments). The bug
was a 9 m drop, so 1 m separates them cleanly.
"""
from __future__ import annotations

import numpy as np
import pytest

import symcable as sc

ANCHOR = np.array([-853.87, -320.0])


@pytest.fixture(scope="module")
def moorpy_lbot() -> float:
    from moorpy.Catenary import catenary

    *_, info = catenary(848.67, 250.0, 902.2, 3.84243e8, 698.094, CB=0.0)
    return float(info["LBot"])  # 134.786 m


def _oc3(segments: int, *, model: str = "planar", stiffness: float | None = None) -> dict:
    d = sc.load_scene(sc.demo_scene_path("oc3")).to_dict()
    d["sections"][0]["segments"] = segments
    if stiffness is not None:
        d["seabed"]["stiffness"] = stiffness
    if model == "cable3d":
        d["model"] = "cable3d"
        for end in ("end_a", "end_b"):
            x, z = d[end]["position"]
            d[end]["position"] = [x, 0.0, z]
            d[end].pop("motion", None)
        d["environment"]["current"] = [0.0, 0.0, 0.0]
    return d


@pytest.mark.parametrize("model, segments", [("planar", 1000), ("planar", 2000),
                                             ("cable3d", 2000)])
def test_grounded_length_at_fine_meshes(moorpy_lbot, model, segments):
    st = sc.solve_static(_oc3(segments, model=model))
    assert st.status == "converged"
    assert st.grounded_length == pytest.approx(moorpy_lbot, abs=1.0)
    # the touchdown on the seabed, about the grounded length from the anchor (plus the
    # chain's 0.19 % stretch), not next to it
    td = st.touchdown[[0, -1]]
    assert td[1] == pytest.approx(-320.0, abs=0.1)
    assert td[0] - ANCHOR[0] == pytest.approx(moorpy_lbot, abs=1.0)
    # it is the length whose weight the seabed and the anchor carry: L - V_fairlead / w
    assert st.grounded_length == pytest.approx(902.2 + st.fairlead_force[-1] / 698.094,
                                               abs=1e-3)


def test_grounded_length_mesh_converged():
    """Across the old threshold (between 900 and 1,000 segments) the grounded length moves by
    far less than a segment: measured 1.2e-4 m (it jumped 9 m)."""
    g = [sc.solve_static(_oc3(n)).grounded_length for n in (900, 1000)]
    assert g[1] == pytest.approx(g[0], abs=0.01)


def test_stiff_seabed_converges_to_moorpy(moorpy_lbot):
    """On a near-rigid seabed (1e8 Pa/m: 0.08 mm penetration) the fine line's grounded length
    is MoorPy's (measured 134.7850 against 134.7855 m)."""
    st = sc.solve_static(_oc3(1000, stiffness=1e8))
    assert st.grounded_length == pytest.approx(moorpy_lbot, abs=0.01)
