"""The StaticSolution of a rod scene carries the rod's shear and internal force (not cable3d's
axial-only tension): on a heavy, tip-loaded cantilever in air the internal force across every
section is the load beyond it, P + w (L - s), whatever the shape, so its magnitude at the nodes
is known exactly, and tension^2 + shear^2 of each edge is its square."""
import numpy as np

import symcable as sc
from test_rod_statics import cantilever

P, W, L = 5.0, 2.0, 2.0


def test_rod_static_solution_has_shear_and_internal_force():
    st = sc.solve_static(cantilever(tip=P, weight=W, segments=10))
    s = np.asarray(st.s)
    # nodes: the mean over the two edges' cuts at s -/+ ds/2 of P + w (L - s) is exact; the
    # tolerance is the static solve's force tolerance (RTOL of the force scale, ~1e-8 N here)
    assert np.allclose(st.tension[1:-1], P + W * (L - s[1:-1]), atol=1e-5)
    mid = 0.5 * (s[:-1] + s[1:])
    along = np.asarray(st.axial_force)
    # per edge: axial part^2 + shear^2 = |f|^2 = (P + w (L - s_mid))^2 (the axial force is
    # the stiff axial law's, equal to f . t to the solve tolerance)
    assert np.allclose(np.hypot(along, st.shear), P + W * (L - mid), atol=1e-5)
    # every load is vertical, so is f: the shear is |f| cos(elevation of the edge)
    assert np.allclose(st.shear, (P + W * (L - mid)) * np.cos(st.angle), atol=1e-5)
    assert st.shear[0] > 0.99 * (P + W * (L - mid[0]))  # the horizontal clamp: nearly all shear


def test_rod_statics_on_a_rubbing_seabed_warn_that_friction_is_not_applied():
    """As cable3d's: statics are frictionless unless seabed.static_friction = 'laid', and the
    solution says so (a user reading mu > 0 in the scene would expect it held)."""
    from test_rod_seabed import across
    st = sc.solve_static(across("coulomb", "none")("rod"))
    assert any("seabed friction is not applied" in w for w in st.warnings)
    st = sc.solve_static(across("coulomb", "laid")("rod"))
    assert not any("seabed friction is not applied" in w for w in st.warnings)
