"""The coupling library in C (``symcable codegen SCENE --coupling``): :class:`~symcable.api.
coupling.Coupling` as C a host program links, MoorDyn-like.

What is exported is the coupling's own Mechanism, step and numbers at the scene's poses of
the coupled things: the first-order generalized-alpha step (``ga_step``, the kernel
``simulate`` and :class:`~symcable.api.coupling.Coupling` run), the coupled ends' forces
(``end_forces``), the static residual and pseudo-transient step (``static_residual``,
``static_ptc_step``: a start with the things elsewhere, by
:func:`~symcable.solvers.equilibrium._ptc`'s continuation) and every output
(``dyn_outputs``); the data header holds the parameters, the static state
with its rates, the coupled ends (their thing, offset, start position and parameter
blocks), and the names. The runtime on them (``symcable_coupling.c``), the example host and
the README are :mod:`symcable.api.export_coupling_text`.
"""
from __future__ import annotations

from pathlib import Path

import casadi as ca
import numpy as np

from ..errors import SymcableError
from ..mechanism.codegen import export_sources
from ..mechanism.functions import functions
from ..solvers.equilibrium import PTC_DT0, PTC_DT_NEWTON, PTC_MAX_STEPS
from ..solvers.galpha1 import galpha1_kernel
from .coupling import MAX_SUBSTEPS, Coupling
from .export import _STEM, _c_array, _c_longs, _c_number, _c_string, _md_literal, _output_data, \
    _output_rows
from .export_coupling_text import HEADER, host_c, readme, runtime_c

__all__ = ["export_coupling"]


def _functions(c: Coupling) -> list:
    """``ga_step``, ``end_forces(y, t, p)``, ``static_solve``, ``dyn_outputs(y, t, p)``."""
    mech = c._mech
    kern = galpha1_kernel(mech, c._opts, lte=False, codegen=False)
    args = [ca.MX.sym(kern.name_in(i), kern.sparsity_in(i)) for i in range(kern.n_in())]
    step = ca.Function("ga_step", args, kern(*args), kern.name_in(), kern.name_out())
    nq, nx = mech.n_q, 2 * (mech.n_q + mech.n_v)
    x, t, p = ca.MX.sym("x", nx), ca.MX.sym("t"), ca.MX.sym("p", mech.params.n)
    q, v = x[:nq], x[nq:nq + mech.n_v]
    ends = c._end_out.fn(q, v, ca.MX(0, 1), t, p)
    out = functions(mech).outputs(q, v, ca.MX(0, 1), t, p)
    F = functions(mech)
    w, cd = ca.MX.sym("w", mech.n_q + mech.n_z), ca.MX.sym("c", mech.n_q + mech.n_z)
    r, dw = F.static_ptc_step(w, p, cd)
    return [step, ca.Function("end_forces", [x, t, p], [ends], ["x", "t", "p"], ["f"]),
            ca.Function("static_residual", [w, p], [F.static_residual(w, p)], ["w", "p"], ["r"]),
            ca.Function("static_ptc_step", [w, p, cd], [r, dw], ["w", "p", "c"], ["r", "dw"]),
            ca.Function("dyn_outputs", [x, t, p], [out], ["x", "t", "p"], ["outputs"])]


def _check_static(c: Coupling, residual: ca.Function, w: np.ndarray, p: np.ndarray) -> float:
    """The static tolerance, N, checked: the exported residual at the exported state is
    within it (or the export is refused)."""
    tol = float(c._eq.stats["tolerance"])
    res = float(np.max(np.abs(np.asarray(residual(w, p))))) if w.size else 0.0
    if not res <= tol:
        raise SymcableError(f"codegen --coupling: the static solve does not hold the scene's "
                            f"static state (residual {res:.3g} N, tolerance {tol:.3g} N)")
    return tol


def export_coupling(scene, folder, stem: str = "symcable_lines", coupled=None) -> list:
    """The coupling library for ``scene`` (module docstring) in ``folder``: ``<stem>.c``/``.h``
    (generated), ``<stem>_data.h``, ``symcable_coupling.h``/``.c``, ``host.c`` and
    ``README.md``; returns their paths. ``coupled``: as :class:`~symcable.api.coupling.
    Coupling`'s (default every vessel point and body). ``stem``: a letter, then letters,
    digits or underscores, not ``symcable_coupling``."""
    if not isinstance(stem, str) or not _STEM.fullmatch(stem) or stem == "symcable_coupling":
        raise SymcableError(f"stem = {stem!r}: must be a letter followed by letters, digits or "
                            "underscores ([A-Za-z][A-Za-z0-9_]*), not 'symcable_coupling'")
    c = Coupling(scene, coupled, codegen=False)
    c.initialize()
    mech, eq = c._mech, c._eq
    funcs = _functions(c)
    w = np.concatenate([np.asarray(eq.q, float), np.asarray(eq.z, float)[:mech.n_z]])
    p_static = np.asarray(eq.p, float)
    tol = _check_static(c, funcs[2], w, p_static)
    D = mech.scales.force / np.concatenate([mech.scales.q, np.ones(mech.n_z)])
    rows = _output_rows(mech)
    things = c.things
    dof0 = np.cumsum([0] + [th.dofs for th in things])[:-1]
    ends = c._ends
    index = {th.name: k for k, th in enumerate(things)}
    position = [mech.params.slice(c._block(e).replace(".coupled", ".position")).start
                for _, e in ends]
    data = [f"/* The numbers of {stem}.c for the coupling runtime (SI units). */\n",
            "#include <math.h>\n#ifndef casadi_real\n#define casadi_real double\n#endif\n",
            f"static const char SCENE_NAME[] = {_c_string(str(c.scene.name))};\n",
            f"#define N_X {c._x.size}\n#define N_Q {mech.n_q}\n#define N_P {mech.params.n}\n",
            f"#define N_W {max(w.size, 1)}\n#define N_DYN_OUT {max(funcs[4].nnz_out(0), 1)}\n",
            f"#define PTC_MAX_STEPS {PTC_MAX_STEPS}\n#define PTC_DT0 {_c_number(PTC_DT0)}\n",
            f"#define PTC_DT_NEWTON {_c_number(PTC_DT_NEWTON)}\n",
            f"#define N_DOF {c.n_dof}\n#define N_THINGS {len(things)}\n",
            f"#define N_ENDS {len(ends)}\n#define MAX_SUBSTEPS {MAX_SUBSTEPS}\n",
            f"#define STATE_TAG {int(c._key[:12], 16)}.0\n",
            f"#define STATIC_TOL {_c_number(tol)}\n",
            "static const char *const DOF_NAMES[] = {"
            + ", ".join(_c_string(n) for n in c.dof_names) + "};\n",
            _c_longs("THING_BODY", [th.kind == "body" for th in things]),
            _c_longs("THING_DOF0", dof0),
            _c_array("BASE_POSE", np.concatenate([np.asarray(th.pose, float) for th in things])),
            _c_longs("END_THING", [index[th.name] for th, _ in ends]),
            _c_array("END_OFFSET", [x for _, e in ends for x in e.offset]),
            _c_array("END_BASE", c._base.ravel()),
            _c_longs("END_BLOCK", [sl.start for sl in c._slices]),
            _c_longs("END_POSITION", position),
            _c_array("X0", c._x), _c_array("P_DYNAMIC", c._p), _c_array("P_STATIC", p_static),
            _c_array("W_STATIC", w), _c_array("PTC_D", np.where(np.arange(w.size) < mech.n_q,
                                                                 D, 0.0)),
            _c_array("SETTINGS", [c._opts.rho_inf, c._opts.tol]),
            _c_array("SCALES", c._consts[1]), _output_data("DYN", rows)]
    folder = Path(folder)
    src, hdr = export_sources(funcs, folder, stem)
    paths = [src, hdr, folder / f"{stem}_data.h", folder / "symcable_coupling.h",
             folder / "symcable_coupling.c", folder / "host.c", folder / "README.md"]
    paths[2].write_text("".join(data))
    paths[3].write_text(HEADER)
    paths[4].write_text(runtime_c(stem))
    paths[5].write_text(host_c(stem))
    facts = {"dofs": c.dof_names, "rho_inf": c._opts.rho_inf, "tol": c._opts.tol,
             "max_iter": c._opts.max_iter, "n_ends": len(ends), "n_x": c._x.size,
             "n_p": mech.params.n, "static_tol": tol}
    paths[6].write_text(readme(stem, _md_literal(str(c.scene.name)), facts, _md_literal))
    return paths
