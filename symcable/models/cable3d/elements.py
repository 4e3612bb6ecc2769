"""The cable3d line's momentum rows as element kernels (:class:`~.element_form.ElementForm`):
each element's forces on its two nodes (:func:`~symcable.models.common.elements.element_kernel`: axial, material
damping, drag, weight and buoyancy) and its share of the mass (structural and added, lumped
or Sun, Zhu & LaRosa's consistent), so that a solver may evaluate the iteration matrix as a
loop over elements of the kernel's own 6 x 18 Jacobian. Contact, friction, bending and end
forces stay in the rest. Given only where the elements' inputs are the nodes' own: not
with a depth profile of current (the water speed of an element then depends on its depth).
"""
from __future__ import annotations

from dataclasses import dataclass

import casadi as ca
import numpy as np

from ...mechanism.element_form import ElementForm

__all__ = ["FormNumbers", "element_form", "form_constants"]

#: the per-element constants of the form's kernel, in the order of its input ``c``
CONSTANTS = ("L0", "EA", "BA", "EAs", "delta", "wall", "w", "d", "cdn", "cdt", "rho",
             "structural_half", "added_half", "ca_normal", "ca_tangential", "self", "other")


def _form_kernel(base: ca.Function, n_law: int) -> ca.Function:
    """``(u (18,), c, s (5,)) -> r (6,)``: r = the element's inertia on each node (its half
    mass block B = m I + m_a (Ca_n (I - t t^T) + Ca_t t t^T), weighted ``self`` on the
    node's own acceleration and ``other`` on its neighbour's: 1, 0 lumped; 2/3, 1/3
    consistent) less its forces; s = (current (3), load, slack width factor)."""
    u = ca.SX.sym("u", 18)
    c = ca.SX.sym("c", len(CONSTANTS) + n_law)
    s = ca.SX.sym("s", 5)
    xa, xb, va, vb, aa, ab = (u[3 * i:3 * i + 3] for i in range(6))
    k = dict(zip(CONSTANTS, (c[i] for i in range(len(CONSTANTS)))))
    law = [c[len(CONSTANTS):]] if n_law else []
    fa, fb, _, _ = base(xa, xb, va, vb, s[:3], k["L0"], k["EA"], k["BA"], k["EAs"],
                        s[4] * k["delta"], k["wall"], k["w"], k["d"], k["cdn"], k["cdt"],
                        k["rho"], s[3], *law)
    dx = xb - xa
    tt = ca.mtimes(dx, dx.T) / ca.dot(dx, dx)
    eye = ca.SX.eye(3)
    blk = k["structural_half"] * eye + k["added_half"] * (
        k["ca_normal"] * (eye - tt) + k["ca_tangential"] * tt)
    ra = ca.mtimes(blk, k["self"] * aa + k["other"] * ab) - fa
    rb = ca.mtimes(blk, k["other"] * aa + k["self"] * ab) - fb
    return ca.Function("cable3d_element_residual", [u, c, s], [ca.vertcat(ra, rb)],
                       ["u", "c", "s"], ["r"])


@dataclass(frozen=True)
class FormNumbers:
    """The numbers of a line's :class:`ElementForm` alone (``constants`` (n_c, N)), on a
    Mechanism built with ``symbols=False`` (:mod:`symcable.models.structure`)."""

    constants: np.ndarray


def form_constants(columns: dict, law, consistent: bool) -> np.ndarray:
    """The form's constants (n_c, N): ``columns`` (name -> (N,) or a scalar for every entry
    of CONSTANTS but ``self`` and ``other``), the mass weights, then the drag law's rows
    ``law`` (n_law, N) or None."""
    N = len(columns["L0"])
    weights = (2.0 / 3.0, 1.0 / 3.0) if consistent else (1.0, 0.0)
    cols = [np.broadcast_to(np.asarray(columns[n], float), (N,)) for n in CONSTANTS[:-2]]
    cols += [np.full(N, weights[0]), np.full(N, weights[1])]
    return np.vstack(cols + ([np.asarray(law, float)] if law is not None else []))


def element_form(base: ca.Function, columns: dict, law, shared, node_index: np.ndarray,
                 held, force_rest, consistent: bool) -> ElementForm:
    """The line's :class:`ElementForm`. ``base``: the single element kernel (not mapped);
    ``columns``: name -> array (N,) for every entry of CONSTANTS but ``self`` and ``other``;
    ``law``: the drag's loading functions (n_law, N) or None; ``shared``: (5, 1) of (t, p);
    ``held``: (9, N+1) positions, velocities and accelerations of the held ends (m, m/s,
    m/s^2); ``force_rest`` (n_v, 1); ``consistent``: Sun, Zhu & LaRosa's consistent mass, else
    lumped."""
    N = len(columns["L0"])
    C = form_constants(columns, law, consistent)
    n_law = 0 if law is None else int(np.asarray(law).shape[0])
    conn = np.column_stack([np.arange(N), np.arange(1, N + 1)])
    return ElementForm(_form_kernel(base, n_law), conn, C, shared, node_index, held, force_rest)
