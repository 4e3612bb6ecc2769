"""Standalone C for a whole scene (``symcable codegen SCENE``): the scene's static solve and
time step as C sources with their data, an example ``main.c`` and a README.

It builds the scene's models, derives and solves them, so it sits at the top of the
package beside :mod:`symcable.api.analyses`; writing the C itself is :func:`symcable.mechanism.codegen.export_sources`.
"""
from __future__ import annotations

import json
import re
from pathlib import Path

import casadi as ca
import numpy as np

from .analyses import build_dynamic_model
from ..mechanism.codegen import export_sources
from ..errors import SymcableError
from ..mechanism.functions import functions
from ..models import build_model
from ..models.planar.static import static_mechanism
from .planar_static import solve_static
from ..mechanism.functions import functions as mechanism_functions
from ..models.planar.mechanism import mechanism_of, state_permutation
from .planar_time import NEWTON_MAX_ITER, NEWTON_TOL
from ..solvers.galpha1 import galpha1_kernel, step_scales
from ..solvers.integrate import start_rates
from ..solvers.options import GeneralizedAlphaFirstOrder

__all__ = ["export_scene"]


_MAIN_C = r"""/* Example: call symcable's generated functions from C.
 * Build:  cc -O2 -Wall main.c {stem}.c -lm -o example && ./example
 * Every function has CasADi's calling convention: arrays of input and output pointers,
 * integer and real work arrays sized by <name>_work, and a memory slot from
 * <name>_checkout (see {stem}.h and README.md). */
#include <stdio.h>
#include <stdlib.h>
#include "{stem}.h"
#include "{stem}_data.h"

/* Evaluate `f` (one of the generated functions) with inputs `arg`, outputs `res`. */
#define CALL(f, arg, res) do {{ \
    casadi_int n_arg, n_res, n_iw, n_w; \
    f##_work(&n_arg, &n_res, &n_iw, &n_w); \
    const casadi_real **a_ = malloc(sizeof(*a_) * (n_arg > 0 ? n_arg : 1)); \
    casadi_real **r_ = malloc(sizeof(*r_) * (n_res > 0 ? n_res : 1)); \
    casadi_int *iw_ = malloc(sizeof(*iw_) * (n_iw > 0 ? n_iw : 1)); \
    casadi_real *w_ = malloc(sizeof(*w_) * (n_w > 0 ? n_w : 1)); \
    for (casadi_int i_ = 0; i_ < f##_n_in(); ++i_) a_[i_] = (arg)[i_]; \
    for (casadi_int i_ = 0; i_ < f##_n_out(); ++i_) r_[i_] = (res)[i_]; \
    f##_incref(); \
    int mem_ = f##_checkout(); \
    int flag_ = f(a_, r_, iw_, w_, mem_); \
    f##_release(mem_); \
    f##_decref(); \
    free(a_); free(r_); free(iw_); free(w_); \
    if (flag_) {{ fprintf(stderr, #f " failed\n"); return 1; }} \
}} while (0)

int main(void) {{
  /* static configuration: plain Newton from the catenary start */
  static casadi_real w[N_W], iterations, residual, outputs[N_OUT];
  casadi_real tol = STATIC_TOL;
  const casadi_real *arg[] = {{W_START, P_STATIC, &tol}};
  casadi_real *res[] = {{w, &iterations, &residual, outputs}};
  CALL(static_solve, arg, res);
  printf("scene: %s\n", SCENE_NAME);
  printf("static: %g Newton iterations, residual %.3g N (tolerance %.3g N)\n",
         iterations, residual, tol);
{dynamic}  return 0;
}}
"""

_MAIN_DYN = r"""  /* 100 generalized-alpha steps of dt = period / 100 from rest */
  {{
    static casadi_real x[N_X], x1[N_X];
    casadi_real t, dt = DT, err, lte, its, failed;
    for (int i = 0; i < N_X; ++i) x[i] = X0[i];
    for (int n = 0; n < 100; ++n) {{
      t = n * dt;
      const casadi_real *a[] = {{x, &t, &dt, P_DYNAMIC, SETTINGS, SCALES}};
      casadi_real *r[] = {{x1, &err, &lte, &its, &failed}};
      CALL(ga_step, a, r);
      if (failed) {{ fprintf(stderr, "step %d: Newton failed\n", n); return 1; }}
      for (int i = 0; i < N_X; ++i) x[i] = x1[i];
    }}
    printf("dynamics: 100 steps done, t = %g s\n", 100 * dt);
  }}
"""


def _dynamic_functions(dyn) -> tuple[list, list]:
    """The exported ``ga_step`` and ``dyn_outputs`` of a DynamicModel's dynamics Mechanism,
    and their data (start, parameters, settings, scales)."""
    mech = mechanism_of(dyn)
    opts = GeneralizedAlphaFirstOrder(rho_inf=0.5, tol=NEWTON_TOL, max_iter=NEWTON_MAX_ITER)
    kern = galpha1_kernel(mech, opts, codegen=False)
    args = [ca.MX.sym(kern.name_in(i), kern.sparsity_in(i)) for i in range(kern.n_in())]
    step = ca.Function("ga_step", args, kern(*args), kern.name_in(), kern.name_out())
    nq, ny = mech.n_q, mech.n_q + mech.n_v
    y, t, p = ca.MX.sym("y", ny), ca.MX.sym("t"), ca.MX.sym("p", mech.params.n)
    out = mechanism_functions(mech).outputs(y[:nq], y[nq:], ca.MX(0, 1), t, p)
    outputs = ca.Function("dyn_outputs", [y, t, p], [out], ["y", "t", "p"], ["outputs"])
    iq, iv = state_permutation(dyn)
    y0 = np.asarray(dyn.y0, dtype=float)
    qd, vd = start_rates(mech, y0[iq], y0[iv], 0.0, dyn.p_value)
    data = [f"#define N_X {2 * ny}\n#define DT {dyn.period / 100.0!r}\n",
            _c_array("X0", np.concatenate([y0[iq], y0[iv], qd, vd])),
            _c_array("P_DYNAMIC", dyn.p_value), _c_array("SETTINGS", [opts.rho_inf, opts.tol]),
            _c_array("SCALES", step_scales(mech))]
    return [step, outputs], data


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
    the backtick, ``<``, ``>`` and ``&`` as ``\\u00XX``) in a code span."""
    lit = json.dumps(text, ensure_ascii=True)
    for ch in "`<>&":
        lit = lit.replace(ch, f"\\u{ord(ch):04x}")
    return f"`{lit}`"


_STEM = re.compile(r"[A-Za-z][A-Za-z0-9_]*")


def _c_array(name: str, values) -> str:
    vals = ", ".join(repr(float(v)) for v in values) or "0.0"
    return f"static const casadi_real {name}[] = {{{vals}}};\n"


def export_scene(scene, folder, stem: str = "symcable_scene") -> list:
    """Standalone C for ``scene`` (``symcable codegen``): ``<stem>.c``/``.h`` with the static
    residual, Jacobian and solve, and (when the scene moves and hangs free of the seabed) the
    generalized-α step and dynamic outputs; ``<stem>_data.h`` with the scene's parameter
    values, start and scales; ``main.c`` calling them; ``README.md``. Returns the paths.

    ``stem`` names the files and the C functions' prefix: a letter, then letters, digits or
    underscores. The scene's name reaches the files only as an escaped string literal
    (``SCENE_NAME`` in ``<stem>_data.h``, which ``main.c`` prints; a JSON string in the
    README).
    """
    if not isinstance(stem, str) or not _STEM.fullmatch(stem):
        raise SymcableError(f"stem = {stem!r}: must be a letter followed by letters, digits or "
                            "underscores ([A-Za-z][A-Za-z0-9_]*)")
    folder = Path(folder)
    model = build_model(scene)
    sol = solve_static(scene, model=model, codegen=False)
    mech = static_mechanism(model)
    start = np.asarray(next(iter(mech.starts())).q, dtype=float)
    st = functions(mech).static_solver(codegen=False)
    funcs = [st.residual, st.jacobian, st.solve, st.outputs]
    dyn, why_not = None, ""
    if any(e.motion is not None for e in (scene.end_a, scene.end_b)):
        try:
            dyn = build_dynamic_model(scene, static=sol)
        except SymcableError as exc:
            why_not = f"the dynamic model was not built; symcable said {_md_literal(str(exc))}"
    else:
        why_not = "the scene prescribes no end motion"
    data = [f"/* Parameter values for {stem}.c (SI units); SCENE_NAME is the scene's name. */\n",
            "#ifndef casadi_real\n#define casadi_real double\n#endif\n",
            f"static const char SCENE_NAME[] = {_c_string(str(scene.name))};\n",
            f"#define N_W {model.n_w}\n#define N_OUT {st.solve.nnz_out(3)}\n",
            f"#define STATIC_TOL {sol.stats['tolerance']!r}\n",
            _c_array("W_START", start), _c_array("P_STATIC", model.p_target)]
    if dyn is not None:
        dyn_funcs, dyn_data = _dynamic_functions(dyn)
        funcs += dyn_funcs
        data += dyn_data
    src, hdr = export_sources(funcs, folder, stem)
    paths = [src, hdr]
    p = folder / f"{stem}_data.h"
    p.write_text("".join(data))
    paths.append(p)
    p = folder / "main.c"
    p.write_text(_MAIN_C.format(stem=stem, dynamic=_MAIN_DYN.format() if dyn is not None else ""))
    paths.append(p)
    lines = ["# Generated C for a symcable scene", "",
             f"Scene name (a JSON string; `SCENE_NAME` in `{stem}_data.h`): "
             f"{_md_literal(str(scene.name))}", "",
             f"Written by symcable (CasADi {ca.__version__}). Build and run the example:", "",
             "```sh", f"cc -O2 -Wall main.c {stem}.c -lm -o example && ./example", "```", "",
             "Functions (CasADi's calling convention: see the header; sizes in SI units):", ""]
    for f in funcs:
        ins = ", ".join(f"{f.name_in(i)}[{f.nnz_in(i)}]" for i in range(f.n_in()))
        outs = ", ".join(f"{f.name_out(i)}[{f.nnz_out(i)}]" for i in range(f.n_out()))
        lines.append(f"- `{f.name()}({ins}) -> ({outs})`")
    lines += ["", "- `static_*`: x (the start x0, `W_START`) holds node positions (m), segment angles "
              "(rad) and strains; p the scene parameters (`P_STATIC`); residual rows in N. "
              "`static_solve` runs up to 12 Newton steps and packs every output of "
              "`static_outputs`, each in column-major order, one after the other.",
              "- `static_jacobian`: J is sparse (column-compressed; its pattern is given by "
              "`static_jacobian_sparsity_out(1)`)."]
    if dyn is not None:
        lines += ["- `ga_step`: one first-order generalized-alpha step from t of size dt: x = (y, "
                  "y'), y = (q, v) the dynamics' state (segment dynamic strain and angle, then "
                  "node velocities, m/s); settings = [rho_inf, Newton tolerance]; scales = the "
                  "state's scales and the residual rows' (`SCALES`); returns the next x, the "
                  "Newton measure, NaN, the Newton iterations and a failure flag.",
                  "- `dyn_outputs(y, t, p)`: every output of a state (tensions and forces in N, "
                  "strains, angles in rad, positions in m), stacked."]
    else:
        lines += ["", f"No time-step function: {why_not}."]
    p = folder / "README.md"
    p.write_text("\n".join(lines) + "\n")
    paths.append(p)
    return paths
