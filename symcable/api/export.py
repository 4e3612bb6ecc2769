"""Standalone C for a whole scene (``symcable codegen SCENE``): the scene's static solve and
time step as C sources with their data, an example ``main.c`` and a README, for every
formulation alike.

What is exported is what the library itself solves and runs for the scene
(:mod:`symcable.api.export_plan`): the static Mechanism's residual, sparse Jacobian, fused
Newton solve and outputs (:meth:`~symcable.mechanism.functions.MechanismFunctions.static_solver`),
and, when the scene moves, the first-order generalized-alpha step that ``simulate`` runs
(:func:`~symcable.solvers.galpha1.galpha1_kernel`, its Newton loop unrolled: CasADi writes C
for it, which it cannot for a rootfinder) with the dynamic outputs. Writing the C itself is
:func:`symcable.mechanism.codegen.export_sources`; the example and the README are
:mod:`symcable.api.export_text`.

The scene's name reaches the files only as an escaped literal (:func:`_c_string` in C,
:func:`_md_literal` in the README). The outputs' names, which hold line, point and body names,
must be letters, digits, ``_``, ``-`` and ``.`` (as :func:`symcable.load_scene` allows them;
anything else is refused before a file is written), and go through the same literals in the
data header and README (CasADi writes them into the generated C as the outputs' names).
"""
from __future__ import annotations

import json
import math
import re
from pathlib import Path

import casadi as ca
import numpy as np

from ..errors import SymcableError
from ..mechanism.codegen import export_sources
from ..mechanism.functions import functions
from ..scene import load_scene
from ..solvers.galpha1 import galpha1_kernel, step_scales
from .export_plan import DynamicPlan, StaticPlan, dynamic_plan, static_plan
from .export_text import main_c, readme

__all__ = ["N_STEPS", "export_scene"]

#: time steps the example ``main.c`` takes by default (its first argument overrides it)
N_STEPS = 100
_STEM = re.compile(r"[A-Za-z][A-Za-z0-9_]*")
#: what an output name may hold to be written into C (as a string literal) and Markdown:
#: the library's names and the scene's line, point and body names (letters, digits, ``_``
#: and ``-``), joined by dots
_OUTPUT_NAME = re.compile(r"[A-Za-z0-9_.\-]{1,200}")


def _c_string(text: str) -> str:
    """``text`` as a C string literal of its UTF-8 bytes: printable ASCII other than ``"``,
    ``\\`` and ``?`` (trigraphs) as itself, every other byte as a three-digit octal escape
    (an octal escape ends after three digits, so no following character extends it)."""
    out = []
    for b in text.encode("utf-8", "surrogatepass"):
        out.append(chr(b) if 0x20 <= b < 0x7F and chr(b) not in '"\\?' else f"\\{b:03o}")
    return '"' + "".join(out) + '"'


def _md_literal(text: str) -> str:
    """``text`` for Markdown: a JSON string (non-ASCII and control characters escaped, and
    the backtick, ``<``, ``>``, ``&`` and ``|`` (a table's cell) as ``\\u00XX``) in a code
    span."""
    lit = json.dumps(text, ensure_ascii=True)
    for ch in "`<>&|":
        lit = lit.replace(ch, f"\\u{ord(ch):04x}")
    return f"`{lit}`"


def _c_number(v) -> str:
    """A double as C source: its shortest round-trip decimal; infinities and NaN by
    ``<math.h>``'s macros."""
    v = float(v)
    if math.isnan(v):
        return "NAN"
    if math.isinf(v):
        return "HUGE_VAL" if v > 0 else "-HUGE_VAL"
    return repr(v)


def _c_array(name: str, values) -> str:
    vals = ", ".join(_c_number(v) for v in np.ravel(values)) or "0.0"
    return f"static const casadi_real {name}[] = {{{vals}}};\n"


def _c_longs(name: str, values) -> str:
    vals = ", ".join(str(int(v)) for v in values) or "0"
    return f"static const long {name}[] = {{{vals}}};\n"


def _output_rows(mech) -> list:
    """(name, offset, rows, cols, unit) of each output of ``mech`` as its packed outputs
    hold them (:meth:`~symcable.mechanism.functions.MechanismFunctions.output_slices`).
    Raises SymcableError for a name that is not the library's (a Scene built around the
    checks of :func:`symcable.load_scene`)."""
    rows = []
    for name, sl in functions(mech).output_slices().items():
        if not _OUTPUT_NAME.fullmatch(name):
            raise SymcableError(f"output {name!r} of mechanism {mech.name!r}: an output name "
                                "must be letters, digits, '_', '-' and '.' to be exported "
                                "(line, point and body names as load_scene allows them)")
        r, c = mech.outputs[name].expr.shape
        rows.append((name, sl.start, r, c, str(mech.outputs[name].unit)))
    return rows


def _output_data(prefix: str, rows: list) -> str:
    """The data header's table of packed outputs: count, names (C literals), offsets,
    sizes, rows."""
    names = ", ".join(_c_string(n) for n, *_ in rows) or '""'
    return (f"#define N_{prefix}_OUTPUTS {len(rows)}\n"
            f"static const char *const {prefix}_OUTPUT_NAMES[] = {{{names}}};\n"
            + _c_longs(f"{prefix}_OUTPUT_OFFSET", [o for _, o, *_ in rows])
            + _c_longs(f"{prefix}_OUTPUT_SIZE", [r * c for _, _, r, c, _ in rows])
            + _c_longs(f"{prefix}_OUTPUT_ROWS", [r for _, _, r, _, _ in rows]))


def _static_functions(plan: StaticPlan) -> list:
    """``static_residual``, ``static_jacobian``, ``static_solve``, ``static_outputs`` of the
    static Mechanism (the virtual machine's Functions: CasADi writes their C). Where the
    solve's Newton step evaluates J by a Function of its own (the sparse QR of a large
    system, :mod:`symcable.mechanism.static_functions`), ``static_jacobian`` calls that one
    and the solve's residual, so that the C holds J once: on a rod of 400 segments J is some
    45 MB of C."""
    st = functions(plan.mech).static_solver(codegen=False)
    inner = {f.name(): f for f in st.solve.find_functions()}
    jac = inner.get("static_jacobian_only")
    jacobian = st.jacobian
    if (jac is not None and inner.get("static_residual") is not None
            and jac.sparsity_out(0) == st.jacobian.sparsity_out(1)):
        x, p = ca.MX.sym("x", jac.sparsity_in(0)), ca.MX.sym("p", jac.sparsity_in(1))
        jacobian = ca.Function("static_jacobian", [x, p],
                               [inner["static_residual"](x, p), jac(x, p)], ["x", "p"],
                               ["r", "J"])
    return [st.residual, jacobian, st.solve, st.outputs]


def _static_data(plan: StaticPlan, n_out: int, n_jac: int, rows: list) -> list:
    # (at least 1: the arrays main.c sizes by them; one segment between held ends has no
    # unknowns)
    return [f"#define N_W {max(plan.start.size, 1)}\n#define N_OUT {max(n_out, 1)}\n",
            f"#define N_JAC_NZ {max(n_jac, 1)}\n",
            f"#define STATIC_TOL {_c_number(plan.tol)}\n",
            f"static const char STATIC_PATH[] = {_c_string(plan.path)};\n",
            _c_array("W_START", plan.start), _c_array("W_STATIC", plan.solution),
            _c_array("P_STATIC", plan.p), _output_data("STATIC", rows)]


def _dynamic_functions(plan: DynamicPlan) -> list:
    """``ga_step`` (the generalized-alpha kernel ``simulate`` runs, its Newton loop unrolled),
    ``dyn_outputs(y, t, p)`` and, for a Mechanism that re-anchors, ``frame_margin(y, t, p)``."""
    mech = plan.mech
    kern = galpha1_kernel(mech, plan.opts, codegen=False)
    args = [ca.MX.sym(kern.name_in(i), kern.sparsity_in(i)) for i in range(kern.n_in())]
    step = ca.Function("ga_step", args, kern(*args), kern.name_in(), kern.name_out())
    nq, ny = mech.n_q, mech.n_q + mech.n_v
    y, t, p = ca.MX.sym("y", ny), ca.MX.sym("t"), ca.MX.sym("p", mech.params.n)
    out = functions(mech).outputs(y[:nq], y[nq:], ca.MX(0, 1), t, p)
    funcs = [step, ca.Function("dyn_outputs", [y, t, p], [out], ["y", "t", "p"], ["outputs"])]
    if plan.reanchor is not None:
        margin = ca.Function("margin", [mech.q, mech.t, mech.p], [plan.reanchor.margin])
        funcs.append(ca.Function("frame_margin", [y, t, p], [margin(y[:nq], t, p)],
                                 ["y", "t", "p"], ["margin"]))
    return funcs


def _dynamic_data(plan: DynamicPlan, n_out: int, rows: list) -> list:
    opts = plan.opts
    data = [f"#define N_X {plan.x0.size}\n#define N_DYN_OUT {max(n_out, 1)}\n",
            f"#define T0 {_c_number(plan.t0)}\n#define DT {_c_number(plan.dt)}\n",
            f"#define N_STEPS {N_STEPS}\n",
            _c_array("X0", plan.x0), _c_array("P_DYNAMIC", plan.p),
            _c_array("SETTINGS", [opts.rho_inf, opts.tol]),
            _c_array("SCALES", step_scales(plan.mech)), _output_data("DYN", rows)]
    if plan.reanchor is not None:
        data.append(f"#define FRAME_THRESHOLD {_c_number(plan.reanchor.threshold)}\n")
    return data


def _dynamics(scene) -> tuple[DynamicPlan | None, list, str]:
    """``(plan, functions, "")`` (:func:`~symcable.api.export_plan.dynamic_plan`,
    :func:`_dynamic_functions`), or ``(None, [], why not)`` when the scene does not move or
    the library cannot build, start or step its dynamics (its message as a Markdown
    literal)."""
    try:
        plan, why_not = dynamic_plan(scene)
        return plan, ([] if plan is None else _dynamic_functions(plan)), why_not
    except SymcableError as exc:
        return None, [], ("the library did not build, start or step the scene's dynamics; "
                          f"it said {_md_literal(str(exc))}")


def _dynamic_facts(plan: DynamicPlan, rows: list) -> dict:
    """What the README says of the dynamics."""
    mech, opts = plan.mech, plan.opts
    return {"mechanism": mech.name, "path": plan.path, "stand_in": plan.stand_in,
            "model": plan.model, "n_y": plan.y0.size, "n_p": mech.params.n,
            "max_iter": opts.max_iter, "rho_inf": opts.rho_inf, "tol": opts.tol,
            "t0": plan.t0, "dt": plan.dt, "n_steps": N_STEPS, "outputs": rows,
            "start": plan.start,
            "margin": plan.reanchor is not None, "reanchored": plan.reanchored,
            "threshold": getattr(plan.reanchor, "threshold", 0.0)}


def export_scene(scene, folder, stem: str = "symcable_scene") -> list:
    """Standalone C for ``scene`` (``symcable codegen``): ``<stem>.c``/``.h`` with the static
    residual, Jacobian, solve and outputs, and (when the scene moves and the library runs its
    dynamics) the generalized-alpha step and dynamic outputs (and a rod's frame margin);
    ``<stem>_data.h`` with the scene's parameter values, starts, static solution, step and
    scales and the outputs' names and places; ``main.c`` calling them and printing every
    result; ``README.md``. Returns the paths.

    ``stem`` names the files: a letter, then letters, digits or underscores. The scene's
    name reaches the files only as an escaped string literal (``SCENE_NAME`` in
    ``<stem>_data.h``, which ``main.c`` prints; a JSON string in the README).
    """
    if not isinstance(stem, str) or not _STEM.fullmatch(stem):
        raise SymcableError(f"stem = {stem!r}: must be a letter followed by letters, digits or "
                            "underscores ([A-Za-z][A-Za-z0-9_]*)")
    scene = load_scene(scene)
    folder = Path(folder)
    splan = static_plan(scene)
    funcs = _static_functions(splan)
    s_rows = _output_rows(splan.mech)
    data = [f"/* Parameter values for {stem}.c (SI units); SCENE_NAME is the scene's name. */\n",
            "#include <math.h>\n#ifndef casadi_real\n#define casadi_real double\n#endif\n",
            f"static const char SCENE_NAME[] = {_c_string(str(scene.name))};\n"]
    data += _static_data(splan, funcs[2].nnz_out(3), funcs[1].nnz_out(1), s_rows)
    dplan, dyn_funcs, why_not = _dynamics(scene)
    d_rows = None
    if dplan is not None:
        d_rows = _output_rows(dplan.mech)
        funcs += dyn_funcs
        data += _dynamic_data(dplan, dyn_funcs[1].nnz_out(0), d_rows)
    src, hdr = export_sources(funcs, folder, stem)
    paths = [src, hdr, folder / f"{stem}_data.h", folder / "main.c", folder / "README.md"]
    paths[2].write_text("".join(data))
    paths[3].write_text(main_c(stem, dplan is not None,
                               dplan is not None and dplan.reanchor is not None))
    facts = {"mechanism": splan.mech.name, "n_w": splan.start.size, "n_p": splan.mech.params.n,
             "start": splan.start_source, "tol": splan.tol, "path": splan.path,
             "outputs": s_rows, "c_bytes": src.stat().st_size}
    dfacts = None if dplan is None else _dynamic_facts(dplan, d_rows)
    paths[4].write_text(readme(stem, _md_literal(str(scene.name)), funcs, facts, dfacts,
                               why_not, _md_literal))
    return paths
