"""The example ``main.c`` and the README that ``symcable codegen`` writes beside the generated
C (:mod:`symcable.api.export`). Nothing of the scene reaches them but through the escaped
literals of :mod:`symcable.api.export` (the README's ``literal`` argument); every other text
here is symcable's own.
"""
from __future__ import annotations

import casadi as ca

__all__ = ["main_c", "readme"]

_MAIN_C = r"""/* Example: call symcable's generated functions from C.
 * Build:  cc -O2 -Wall main.c {stem}.c -lm -o example && ./example [steps]
 * Every function has CasADi's calling convention: arrays of input and output pointers,
 * integer and real work arrays sized by <name>_work, and a memory slot from
 * <name>_checkout (see {stem}.h and README.md). Results are printed one number a line,
 * "<what>.<output>[<i>] = <value>", i the entry in column-major order. */
#include <math.h>
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

/* Print the packed outputs `y` (n of them, named, each `size` entries from `offset`). */
static void print_outputs(const char *what, const casadi_real *y, int n,
                          const char *const *names, const long *offset, const long *size) {{
  for (int k = 0; k < n; ++k)
    for (long i = 0; i < size[k]; ++i)
      printf("%s.%s[%ld] = %.17g\n", what, names[k], i, y[offset[k] + i]);
}}

/* The static solve (plain Newton, at most 12 steps) from w0: 0, or 1 when a call failed. */
static int solve_static(const casadi_real *w0, casadi_real *w, casadi_real *iterations,
                        casadi_real *residual, casadi_real *outputs) {{
  casadi_real tol = STATIC_TOL;
  const casadi_real *arg[] = {{w0, P_STATIC, &tol}};
  casadi_real *res[] = {{w, iterations, residual, outputs}};
  CALL(static_solve, arg, res);
  return 0;
}}
{dynamic_function}
int main(int argc, char **argv) {{
  /* statics: from W_START, the start the library's own solve began from; where plain
   * Newton does not converge from it, a Newton refinement of W_STATIC (the library's
   * static solution) */
  static casadi_real w[N_W], iterations, residual, outputs[N_OUT];
  const char *from = "W_START";
  if (solve_static(W_START, w, &iterations, &residual, outputs) || !(residual <= STATIC_TOL)) {{
    from = "W_STATIC";
    if (solve_static(W_STATIC, w, &iterations, &residual, outputs)) return 1;
  }}
  printf("scene: %s\n", SCENE_NAME);
  printf("static: %g Newton iterations from %s, residual %.3g N (tolerance %.3g N)\n",
         iterations, from, residual, STATIC_TOL);
  printf("static_converged = %d\n", residual <= STATIC_TOL);
  print_outputs("static", outputs, N_STATIC_OUTPUTS, STATIC_OUTPUT_NAMES,
                STATIC_OUTPUT_OFFSET, STATIC_OUTPUT_SIZE);
  if (!(residual <= STATIC_TOL)) {{
    fprintf(stderr, "static solve: residual %g N above the tolerance\n", residual);
    return 1;
  }}
  {{
    /* the residual and its Jacobian at the solution, by their own functions */
    static casadi_real r[N_W], J[N_JAC_NZ];
    casadi_real r_max = 0, j_sum = 0;
    const casadi_real *a[] = {{w, P_STATIC}};
    casadi_real *res_r[] = {{r}}, *res_j[] = {{r, J}};
    CALL(static_residual, a, res_r);
    CALL(static_jacobian, a, res_j);
    for (int i = 0; i < N_W; ++i) if (fabs(r[i]) > r_max) r_max = fabs(r[i]);
    for (int i = 0; i < N_JAC_NZ; ++i) j_sum += fabs(J[i]);
    printf("static_residual_max = %.17g\n", r_max);
    printf("static_jacobian_abs_sum = %.17g\n", j_sum);
  }}
{dynamic_call}  (void)argc; (void)argv;
  return 0;
}}
"""

_DYNAMIC_FUNCTION = r"""
/* N steps of the generalized-alpha step from X0 at T0, then the outputs at the end:
 * 0, 1 when a call or a step failed, 2 when a re-anchoring would be needed. */
static int run_dynamics(int n_steps) {{
  static casadi_real x[N_X], x1[N_X], out[N_DYN_OUT];
  casadi_real t, dt = DT, err, lte, its, failed, its_max = 0;
  for (int i = 0; i < N_X; ++i) x[i] = X0[i];
  for (int n = 0; n < n_steps; ++n) {{
    t = T0 + n * dt;
    const casadi_real *a[] = {{x, &t, &dt, P_DYNAMIC, SETTINGS, SCALES}};
    casadi_real *r[] = {{x1, &err, &lte, &its, &failed}};
    CALL(ga_step, a, r);
    if (failed) {{
      fprintf(stderr, "step %d (t = %g s): Newton failed (measure %g)\n", n, t, err);
      return 1;
    }}
    if (its > its_max) its_max = its;
    for (int i = 0; i < N_X; ++i) x[i] = x1[i];{margin}
  }}
  t = T0 + n_steps * dt;
  printf("dynamics: %d steps done, t = %g s\n", n_steps, t);
  printf("dyn_newton_iterations_max = %g\n", its_max);
  for (int i = 0; i < N_X / 2; ++i) printf("dyn_y[%d] = %.17g\n", i, x[i]);
  const casadi_real *a[] = {{x, &t, P_DYNAMIC}};
  casadi_real *r[] = {{out}};
  CALL(dyn_outputs, a, r);
  print_outputs("dyn", out, N_DYN_OUTPUTS, DYN_OUTPUT_NAMES, DYN_OUTPUT_OFFSET,
                DYN_OUTPUT_SIZE);
  return 0;
}}
"""

_MARGIN = r"""
    {{
      casadi_real t1 = t + dt, margin;
      const casadi_real *am[] = {{x, &t1, P_DYNAMIC}};
      casadi_real *rm[] = {{&margin}};
      CALL(frame_margin, am, rm);
      if (margin < FRAME_THRESHOLD) {{
        printf("dynamics: stopped after %d steps, t = %g s: frame margin %g below %g "
               "(symcable would re-anchor the frames here; see README.md)\n",
               n + 1, t1, margin, FRAME_THRESHOLD);
        return 2;
      }}
    }}"""

_DYNAMIC_CALL = r"""  {{
    /* dynamics: N_STEPS steps of DT from X0 at T0 (or as many as the first argument) */
    long n_steps = N_STEPS;
    if (argc > 1) {{
      char *end;
      n_steps = strtol(argv[1], &end, 10);
      if (*end != '\0' || n_steps < 0 || n_steps > 100000000L) {{
        fprintf(stderr, "steps: %s: must be a whole number from 0 to 1e8\n", argv[1]);
        return 1;
      }}
    }}
    int rc = run_dynamics((int)n_steps);
    if (rc) return rc;
  }}
"""


def main_c(stem: str, dynamics: bool, margin: bool) -> str:
    """The example ``main.c``: the static solve and its outputs, then (``dynamics``) the
    time steps and the outputs at their end, each step checked against the frames' margin
    (``margin``: a Mechanism that re-anchors)."""
    dyn_fn = _DYNAMIC_FUNCTION.format(margin=_MARGIN.format() if margin else "") \
        if dynamics else ""
    return _MAIN_C.format(stem=stem, dynamic_function=dyn_fn,
                          dynamic_call=_DYNAMIC_CALL.format() if dynamics else "")


def _signature(f: ca.Function) -> str:
    ins = ", ".join(f"{f.name_in(i)}[{f.nnz_in(i)}]" for i in range(f.n_in()))
    outs = ", ".join(f"{f.name_out(i)}[{f.nnz_out(i)}]" for i in range(f.n_out()))
    return f"- `{f.name()}({ins}) -> ({outs})`"


def _output_table(title: str, rows: list, literal) -> list:
    """A Markdown table of packed outputs: (name, offset, rows, cols, unit) each; names and
    units through ``literal`` (the README's escaped literal)."""
    lines = ["", title, "", "| output | offset | shape | unit |", "|---|---|---|---|"]
    lines += [f"| {literal(n)} | {o} | {r} x {c} | {literal(u)} |" for n, o, r, c, u in rows]
    return lines


def readme(stem: str, name_literal: str, funcs: list, static: dict, dynamic: dict | None,
           why_not: str, literal) -> str:
    """README.md: how to build the example, the functions, the data and what each does.
    ``static``/``dynamic``: the facts to state (see :func:`symcable.api.export.export_scene`);
    ``literal``: the escaping of any text that may come from the scene."""
    lines = ["# Generated C for a symcable scene", "",
             f"Scene name (a JSON string; `SCENE_NAME` in `{stem}_data.h`): {name_literal}", "",
             (f"Written by symcable (CasADi {ca.__version__}). Build and run the example "
              "(its optional argument: the number of time steps):"), "",
             "```sh", f"cc -O2 -Wall main.c {stem}.c -lm -o example && ./example", "```", "",
             (f"`{stem}.c` is {static['c_bytes'] / 1e6:.1f} MB of straight-line C: the "
              "compiler's time grows faster than its length (-O1 or -O0 compile a large one "
              "in a fraction of -O2's time, and it runs about as fast)."), "",
             "Functions (CasADi's calling convention: see the header; sizes in SI units):", ""]
    lines += [_signature(f) for f in funcs]
    lines += ["", "## Statics", ""] + _static_lines(static, literal)
    lines += _output_table("Static outputs (`static_outputs`, packed in this order by "
                           "`static_solve`):", static["outputs"], literal)
    lines += ["", "## Dynamics", ""]
    if dynamic is None:
        lines.append(f"No time-step function: {why_not}.")
    else:
        lines += _dynamic_lines(dynamic, literal)
        lines += _output_table("Dynamic outputs (`dyn_outputs`, packed in this order):",
                               dynamic["outputs"], literal)
    return "\n".join(lines) + "\n"


def _static_lines(s: dict, literal) -> list:
    how = (" from that start: the same plain Newton, so the C solve converges from it to the "
           "same state." if s["path"] == "newton" else
           ", not by plain Newton from that start: the C solve from `W_START` may not "
           "converge, and then `main.c` refines `W_STATIC` (zero or one Newton step).")
    return [(f"- The scene's static Mechanism ({literal(s['mechanism'])}): {s['n_w']} unknowns "
             f"x = (q, z), {s['n_p']} parameters p (`P_STATIC`, the values the library "
             "solved with); residual rows in N."),
            ("- `static_solve(x0, p, tol)`: plain Newton, at most 12 steps (skipped once "
             "max |r| <= tol), each on the exact Jacobian; returns x, the steps taken, "
             "max |r| (N) and every output of `static_outputs` packed (table below)."),
            ("- `static_jacobian`: J is sparse (column-compressed; its pattern is given by "
             "`static_jacobian_sparsity_out(1)`)."),
            (f"- `main.c` starts `static_solve` from `W_START`, the start the library's own "
             f"solve began from ({literal(s['start'])}), to `STATIC_TOL` = {s['tol']:.6g} N, "
             "the library's tolerance for this Mechanism (1e-9 of its force scale); where "
             "that does not converge it refines `W_STATIC`, the library's static solution "
             f"in the data header. The library found its equilibrium by "
             f"{literal(s['path'])}{how}")]


def _dynamic_lines(d: dict, literal) -> list:
    stand_in = (f", as a stand-in scene of model = {literal(d['model'])}" if d["stand_in"]
                else "")
    lines = [(f"- The Mechanism `simulate` steps for this scene ({literal(d['mechanism'])}, "
              f"the {d['path']} path{stand_in}): y = (q, v), {d['n_y']} states, {d['n_p']} "
              "parameters (`P_DYNAMIC`)."),
             ("- `ga_step(x, t, h, p, settings, scales)`: one step of first-order "
              "generalized-alpha (Jansen, Whiting & Hulbert 2000) from t (s) of size h (s), "
              f"Newton on the exact iteration matrix unrolled (at most {d['max_iter']} "
              "iterations): x = (y, y'), the state and its rates; settings = [rho_inf, "
              f"Newton tolerance] (`SETTINGS` = [{d['rho_inf']:g}, {d['tol']:g}], `simulate`'s "
              "defaults here); scales = the state's scales and the residual rows' "
              "(`SCALES`); returns the next x, the Newton measure, NaN, the linear solves and "
              "a failure flag (1: Newton did not converge; `simulate` would then retake the "
              "step as substeps, which `main.c` does not)."),
             (f"- `X0` = (y0, y0'): where `simulate` starts, at `T0` = {d['t0']:g} s "
              f"({literal(d['start'])}), with its rates (q' from the kinematics, v' = M^-1 f). "
              f"`DT` = {d['dt']:.6g} s, the step `symcable simulate` takes by default for "
              f"this scene; `main.c` takes `N_STEPS` = {d['n_steps']} steps (or as many as "
              "its first argument says), each at t = T0 + n DT."),
             ("- `dyn_outputs(y, t, p)`: every output of a state (SI units), packed (table "
              "below).")]
    if d["margin"]:
        lines.append("- `frame_margin(y, t, p)`: min over the rod's edges of 1 + t0 . t (2 on "
                     "the anchors, 0 at a half turn). `simulate` re-anchors the frames (p's "
                     "block `frame` := the output `reference_frame`, the twist rates moved to "
                     "the new chart) once it falls below "
                     f"`FRAME_THRESHOLD` = {d['threshold']:g}; `main.c` does not: it stops "
                     "there and says so (a run beyond needs the re-anchoring)."
                     + (" `X0` and `P_DYNAMIC` are in the chart `simulate` takes its first "
                        "step in: it re-anchored the frames at the start, where the margin "
                        "was below the threshold." if d["reanchored"] else ""))
    return lines
