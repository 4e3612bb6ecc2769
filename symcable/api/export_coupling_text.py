"""The C runtime of the coupling library (``symcable codegen --coupling``,
:mod:`symcable.api.export_coupling`): ``symcable_coupling.h`` / ``.c`` (the host's API, on
the generated functions and the data header), an example host ``host.c`` and the README.
Nothing of the scene reaches these texts but the stem (checked: a C identifier) and the
escaped literals of :mod:`symcable.api.export`."""
from __future__ import annotations

__all__ = ["HEADER", "host_c", "readme", "runtime_c"]

HEADER = r"""/* symcable's lines as a library a host program steps (MoorDyn's Init/Step pattern).
 * Units SI. Degrees of freedom, in order (sc_dof_name): a coupled point's x, y, z (m); a
 * coupled body's x, y, z (m) and roll, pitch, yaw (rad, R = Rz(yaw) Ry(pitch) Rx(roll)).
 * Velocities: m/s, and a body's angular velocity in global axes (rad/s; sc_angular_velocity
 * converts roll, pitch and yaw rates). Forces: what the lines exert on each point (N), on
 * each body the force (N) and its moment about the reference point (N m), global axes.
 * Functions return 0 on success, 1 for a bad argument, 2 when a solve failed; sc_error
 * says why. */
#ifndef SYMCABLE_COUPLING_H
#define SYMCABLE_COUPLING_H
#ifdef __cplusplus
extern "C" {
#endif

typedef struct sc_coupling sc_coupling;

int sc_n_dof(void);                 /* degrees of freedom of the coupled things */
const char *sc_dof_name(int i);     /* "NAME.x", ..., "NAME.yaw" */
int sc_state_size(void);            /* doubles in a saved state */
int sc_output_size(void);           /* doubles sc_outputs writes */
const char *sc_output_name(int k, long *offset, long *size);  /* NULL past the last */

sc_coupling *sc_create(void);       /* NULL when out of memory */
void sc_destroy(sc_coupling *c);
/* The lines' static state with the coupled things at x (n_dof), moving at xd, at time t (s);
 * the forces there into f (n_dof). */
int sc_initialize(sc_coupling *c, const double *x, const double *xd, double t, double *f);
/* From t (the coupling's time) to t + dt with the coupled things at x moving at xd at t + dt;
 * the forces there into f. A failed step leaves the state at t. */
int sc_step(sc_coupling *c, double t, double dt, const double *x, const double *xd, double *f);
double sc_time(const sc_coupling *c);
int sc_get_state(const sc_coupling *c, double *state);              /* sc_state_size() */
int sc_set_state(sc_coupling *c, const double *state, double *f);   /* forces there */
int sc_outputs(sc_coupling *c, double *out);                        /* sc_output_size() */
const char *sc_error(const sc_coupling *c);
void sc_angular_velocity(const double *rpy, const double *rpy_rates, double *omega);

#ifdef __cplusplus
}
#endif
#endif
"""

_RUNTIME = r"""/* The coupling runtime (see symcable_coupling.h and README.md). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "{stem}.h"
#include "{stem}_data.h"
#include "symcable_coupling.h"

/* a saved state: its tag (this export's), t, x, the ends' path, the pose, the ends' base */
#define SC_STATE (2 + N_X + 6 * N_ENDS + N_DOF + 3 * N_ENDS)

struct sc_coupling {{
  double t, x[N_X], p[N_P], now[6 * N_ENDS], pose[N_DOF], base[3 * N_ENDS];
  casadi_real xt[N_X], x1[N_X];  /* a step's iterates */
  casadi_real ps[N_P], ws[N_W], w1[N_W], r[N_W], dw[N_W], cd[N_W];  /* the static solve's */
  int ready;
  char message[512];
  const casadi_real **arg;
  casadi_real **res;
  casadi_int *iw;
  casadi_real *w;
}};

typedef int (*sc_fn)(const casadi_real **, casadi_real **, casadi_int *, casadi_real *, int);
typedef int (*sc_work_fn)(casadi_int *, casadi_int *, casadi_int *, casadi_int *);

static int sc_eval(sc_coupling *c, sc_fn f, int (*checkout)(void), void (*release)(int),
                   casadi_int n_in, casadi_int n_out, const casadi_real **in,
                   casadi_real **out) {{
  for (casadi_int i = 0; i < n_in; ++i) c->arg[i] = in[i];
  for (casadi_int i = 0; i < n_out; ++i) c->res[i] = out[i];
  int mem = checkout();
  int flag = f(c->arg, c->res, c->iw, c->w, mem);
  release(mem);
  return flag;
}}
#define SC_CALL(c, f, in, out) \
  sc_eval(c, f, f##_checkout, f##_release, f##_n_in(), f##_n_out(), in, out)

static int sc_fail(sc_coupling *c, int code, const char *what) {{
  snprintf(c->message, sizeof c->message, "%s", what);
  return code;
}}

int sc_n_dof(void) {{ return N_DOF; }}
const char *sc_dof_name(int i) {{ return i >= 0 && i < N_DOF ? DOF_NAMES[i] : NULL; }}
int sc_state_size(void) {{ return SC_STATE; }}
int sc_output_size(void) {{ return N_DYN_OUT; }}
const char *sc_output_name(int k, long *offset, long *size) {{
  if (k < 0 || k >= N_DYN_OUTPUTS) return NULL;
  if (offset) *offset = DYN_OUTPUT_OFFSET[k];
  if (size) *size = DYN_OUTPUT_SIZE[k];
  return DYN_OUTPUT_NAMES[k];
}}
double sc_time(const sc_coupling *c) {{ return c->t; }}
const char *sc_error(const sc_coupling *c) {{ return c->message; }}

sc_coupling *sc_create(void) {{
  sc_coupling *c = calloc(1, sizeof *c);
  if (!c) return NULL;
  casadi_int a = 0, r = 0, i = 0, w = 0, sa, sr, si, sw;
  sc_work_fn works[] = {{ga_step_work, end_forces_work, static_residual_work,
                        static_ptc_step_work, dyn_outputs_work}};
  for (int k = 0; k < 5; ++k) {{
    works[k](&sa, &sr, &si, &sw);
    a = sa > a ? sa : a; r = sr > r ? sr : r; i = si > i ? si : i; w = sw > w ? sw : w;
  }}
  c->arg = malloc(sizeof *c->arg * (a > 0 ? a : 1));
  c->res = malloc(sizeof *c->res * (r > 0 ? r : 1));
  c->iw = malloc(sizeof *c->iw * (i > 0 ? i : 1));
  c->w = malloc(sizeof *c->w * (w > 0 ? w : 1));
  if (!c->arg || !c->res || !c->iw || !c->w) {{ sc_destroy(c); return NULL; }}
  ga_step_incref(); end_forces_incref(); static_residual_incref(); static_ptc_step_incref();
  dyn_outputs_incref();
  snprintf(c->message, sizeof c->message, "not initialized: call sc_initialize first");
  return c;
}}

void sc_destroy(sc_coupling *c) {{
  if (!c) return;
  if (c->w) {{
    ga_step_decref(); end_forces_decref(); static_residual_decref(); static_ptc_step_decref();
    dyn_outputs_decref();
  }}
  free(c->arg); free(c->res); free(c->iw); free(c->w); free(c);
}}

static void sc_rotation(const double *rpy, double *R) {{
  double cr = cos(rpy[0]), sr = sin(rpy[0]), cp = cos(rpy[1]), sp = sin(rpy[1]);
  double cy = cos(rpy[2]), sy = sin(rpy[2]);
  R[0] = cy * cp; R[1] = cy * sp * sr - sy * cr; R[2] = cy * sp * cr + sy * sr;
  R[3] = sy * cp; R[4] = sy * sp * sr + cy * cr; R[5] = sy * sp * cr - cy * sr;
  R[6] = -sp;     R[7] = cp * sr;                R[8] = cp * cr;
}}

void sc_angular_velocity(const double *rpy, const double *rates, double *omega) {{
  double cp = cos(rpy[1]), sp = sin(rpy[1]), cy = cos(rpy[2]), sy = sin(rpy[2]);
  omega[0] = rates[0] * cy * cp - rates[1] * sy;
  omega[1] = rates[0] * sy * cp + rates[1] * cy;
  omega[2] = -rates[0] * sp + rates[2];
}}

/* end e's position and velocity with the things at x moving at xd */
static void sc_end(int e, const double *x, const double *xd, double *pos, double *vel) {{
  int k = END_THING[e], o = THING_DOF0[k];
  if (!THING_BODY[k]) {{
    for (int i = 0; i < 3; ++i) {{ pos[i] = x[o + i]; vel[i] = xd ? xd[o + i] : 0.0; }}
    return;
  }}
  double R[9], arm[3];
  sc_rotation(x + o + 3, R);
  for (int i = 0; i < 3; ++i)
    arm[i] = R[3 * i] * END_OFFSET[3 * e] + R[3 * i + 1] * END_OFFSET[3 * e + 1]
             + R[3 * i + 2] * END_OFFSET[3 * e + 2];
  for (int i = 0; i < 3; ++i) pos[i] = x[o + i] + arm[i];
  if (!xd) {{ vel[0] = vel[1] = vel[2] = 0.0; return; }}
  const double *v = xd + o, *om = xd + o + 3;
  vel[0] = v[0] + om[1] * arm[2] - om[2] * arm[1];
  vel[1] = v[1] + om[2] * arm[0] - om[0] * arm[2];
  vel[2] = v[2] + om[0] * arm[1] - om[1] * arm[0];
}}

/* a finite array of n numbers; names (n of them) or NULL name its entries in the message */
static int sc_check(sc_coupling *c, const double *a, int n, const char *what,
                    const char *const *names) {{
  if (!a) {{
    snprintf(c->message, sizeof c->message, "%s: NULL, must be %d numbers", what, n);
    return 1;
  }}
  for (int i = 0; i < n; ++i)
    if (!isfinite(a[i])) {{
      snprintf(c->message, sizeof c->message, "%s[%d] = %g: must be finite%s%s%s", what, i,
               a[i], names ? " (" : "", names ? names[i] : "", names ? ")" : "");
      return 1;
    }}
  return 0;
}}

/* the ends' displacement and velocity with the things at x, xd (rows of 6) */
static void sc_ends(sc_coupling *c, const double *x, const double *xd, double *rows) {{
  for (int e = 0; e < N_ENDS; ++e) {{
    sc_end(e, x, xd, rows + 6 * e, rows + 6 * e + 3);
    for (int i = 0; i < 3; ++i) rows[6 * e + i] -= c->base[3 * e + i];
  }}
}}

static void sc_path(sc_coupling *c, const double *a, const double *b, double t0, double t1) {{
  for (int e = 0; e < N_ENDS; ++e) {{
    double *blk = c->p + END_BLOCK[e];
    memcpy(blk, a + 6 * e, 6 * sizeof(double));
    memcpy(blk + 6, b + 6 * e, 6 * sizeof(double));
    blk[12] = t0; blk[13] = t1;
  }}
}}

static int sc_forces(sc_coupling *c, double *f) {{
  double fe[3 * N_ENDS + 1];
  const casadi_real *in[] = {{c->x, &c->t, c->p}};
  casadi_real *out[] = {{fe}};
  if (SC_CALL(c, end_forces, in, out)) return sc_fail(c, 2, "end_forces failed");
  for (int i = 0; i < N_DOF; ++i) f[i] = 0.0;
  for (int e = 0; e < N_ENDS; ++e) {{
    int k = END_THING[e], o = THING_DOF0[k];
    const double *fk = fe + 3 * e;
    for (int i = 0; i < 3; ++i) f[o + i] += fk[i];
    if (THING_BODY[k]) {{
      double pos[3], vel[3], r[3];
      sc_end(e, c->pose, NULL, pos, vel);
      for (int i = 0; i < 3; ++i) r[i] = pos[i] - c->pose[o + i];
      f[o + 3] += r[1] * fk[2] - r[2] * fk[1];
      f[o + 4] += r[2] * fk[0] - r[0] * fk[2];
      f[o + 5] += r[0] * fk[1] - r[1] * fk[0];
    }}
  }}
  return 0;
}}

/* the largest |entry| */
static double sc_norm(const casadi_real *r, int n) {{
  double m = 0.0;
  for (int i = 0; i < n; ++i) m = fabs(r[i]) > m || isnan(r[i]) ? fabs(r[i]) : m;
  return m;
}}

/* The static state with the ends at pos (3 N_ENDS), by pseudo-transient continuation from
 * the exported state (symcable's own fallback: steps (D / dtau - J) dw = r, D the force
 * scale over each unknown's scale, dtau doubling after each accepted step, cut by 4 where
 * the residual jumps a hundredfold); into c->x, at rest. */
static int sc_static(sc_coupling *c, const double *pos, double moved) {{
  casadi_real *ps = c->ps, *w = c->ws, *w1 = c->w1, *r = c->r, *dw = c->dw, *cd = c->cd;
  double dtau = PTC_DT0, nr;
  memcpy(ps, P_STATIC, sizeof c->ps);
  for (int e = 0; e < N_ENDS; ++e)
    for (int i = 0; i < 3; ++i) ps[END_POSITION[e] + i] = pos[3 * e + i];
  memcpy(w, W_STATIC, sizeof c->ws);
  const casadi_real *in[] = {{w, ps}};
  casadi_real *out[] = {{r}};
  if (SC_CALL(c, static_residual, in, out)) return sc_fail(c, 2, "static_residual failed");
  nr = sc_norm(r, N_W);
  for (int it = 0; it < PTC_MAX_STEPS && !(nr <= STATIC_TOL); ++it) {{
    for (int i = 0; i < N_W; ++i) cd[i] = PTC_D[i] / dtau;
    const casadi_real *in2[] = {{w, ps, cd}};
    casadi_real *out2[] = {{r, dw}};
    if (SC_CALL(c, static_ptc_step, in2, out2)) return sc_fail(c, 2, "static_ptc_step failed");
    for (int i = 0; i < N_W; ++i) w1[i] = w[i] + dw[i];
    const casadi_real *in3[] = {{w1, ps}};
    casadi_real *out3[] = {{r}};
    if (SC_CALL(c, static_residual, in3, out3)) return sc_fail(c, 2, "static_residual failed");
    double nr1 = sc_norm(r, N_W);
    if (!isfinite(nr1) || nr1 > 100.0 * nr) {{
      dtau /= 4.0;
      if (dtau < 1e-12) break;
      continue;
    }}
    memcpy(w, w1, sizeof c->ws);
    nr = nr1;
    dtau = fmin(2.0 * dtau, PTC_DT_NEWTON);
  }}
  if (!(nr <= STATIC_TOL)) {{
    snprintf(c->message, sizeof c->message, "the static solve with the coupled things at x "
             "did not converge (residual %g N, tolerance %g N, from the exported state, the "
             "ends moved up to %.3g m): export the scene with the things nearer x", nr,
             STATIC_TOL, moved);
    return 2;
  }}
  memset(c->x, 0, sizeof c->x);
  memcpy(c->x, w, N_Q * sizeof(double));
  return 0;
}}

int sc_initialize(sc_coupling *c, const double *x, const double *xd, double t, double *f) {{
  static const double zero[N_DOF > 0 ? N_DOF : 1];
  if (!c) return 1;
  c->ready = 0;  /* until this start succeeds: a failed one leaves nothing to step */
  if (sc_check(c, x, N_DOF, "x", DOF_NAMES) || (xd && sc_check(c, xd, N_DOF, "xd", DOF_NAMES)))
    return 1;
  if (!isfinite(t)) return sc_fail(c, 1, "t: must be finite");
  double pos[3 * N_ENDS + 1], vel[3], dev = 0.0;
  for (int e = 0; e < N_ENDS; ++e) {{
    sc_end(e, x, NULL, pos + 3 * e, vel);
    for (int i = 0; i < 3; ++i) {{
      double d = fabs(pos[3 * e + i] - END_BASE[3 * e + i]);
      dev = d > dev ? d : dev;
    }}
  }}
  memcpy(c->p, P_DYNAMIC, sizeof c->p);
  if (dev <= 1e-12 * (1.0 + fabs(END_BASE[0]))) {{
    memcpy(c->x, X0, sizeof c->x);  /* the exported static state, with its rates */
  }} else {{  /* the static state with the ends where x puts them, from the exported one */
    for (int e = 0; e < N_ENDS; ++e)
      for (int i = 0; i < 3; ++i) c->p[END_POSITION[e] + i] = pos[3 * e + i];
    int rc = sc_static(c, pos, dev);
    if (rc) return rc;
  }}
  for (int e = 0; e < N_ENDS; ++e) memcpy(c->base + 3 * e, pos + 3 * e, 3 * sizeof(double));
  sc_ends(c, x, xd ? xd : zero, c->now);
  sc_path(c, c->now, c->now, t, t);
  memcpy(c->pose, x, N_DOF * sizeof(double));
  c->t = t;
  c->ready = 1;
  c->message[0] = '\0';
  return sc_forces(c, f);
}}

int sc_step(sc_coupling *c, double t, double dt, const double *x, const double *xd, double *f) {{
  if (!c) return 1;
  if (!c->ready) return sc_fail(c, 1, "sc_step before sc_initialize");
  if (sc_check(c, x, N_DOF, "x", DOF_NAMES) || sc_check(c, xd, N_DOF, "xd", DOF_NAMES))
    return 1;
  if (!(dt > 0.0) || !isfinite(dt)) {{
    snprintf(c->message, sizeof c->message, "dt = %g s: must be > 0 and finite", dt);
    return 1;
  }}
  if (!(fabs(t - c->t) <= 1e-9 * fmax(1.0, fmax(fabs(t), dt)))) {{
    snprintf(c->message, sizeof c->message, "t = %.17g s: the coupling is at t = %.17g s; "
             "step from there (sc_set_state to step from another time)", t, c->t);
    return 1;
  }}
  double next[6 * N_ENDS + 1];
  casadi_real *xt = c->xt, *x1 = c->x1;
  sc_ends(c, x, xd, next);
  sc_path(c, c->now, next, t, t + dt);
  casadi_real err = 0, lte, its, failed = 1;
  for (int n = 1; n <= MAX_SUBSTEPS && failed; n *= 2) {{
    casadi_real h = dt / n;
    memcpy(xt, c->x, sizeof c->xt);
    failed = 0;
    for (int k = 0; k < n && !failed; ++k) {{
      casadi_real tk = k ? t + k * h : t;
      const casadi_real *in[] = {{xt, &tk, &h, c->p, SETTINGS, SCALES}};
      casadi_real *out[] = {{x1, &err, &lte, &its, &failed}};
      if (SC_CALL(c, ga_step, in, out)) return sc_fail(c, 2, "ga_step failed");
      for (int i = 0; i < N_X && !failed; ++i) if (!isfinite(x1[i])) failed = 1;
      if (!failed) memcpy(xt, x1, sizeof c->xt);
    }}
  }}
  if (failed) {{
    sc_path(c, c->now, c->now, t, t);
    snprintf(c->message, sizeof c->message, "Newton did not converge in the step from t = %g "
             "to %g s, not even as %d substeps (scaled residual %g, tolerance %g): a smaller "
             "dt, or check x", t, t + dt, MAX_SUBSTEPS, err, SETTINGS[1]);
    return 2;
  }}
  memcpy(c->x, xt, sizeof c->x);
  memcpy(c->now, next, sizeof c->now);
  memcpy(c->pose, x, N_DOF * sizeof(double));
  c->t = t + dt;
  return sc_forces(c, f);
}}

int sc_get_state(const sc_coupling *c, double *s) {{
  if (!c || !c->ready || !s) return 1;
  s[0] = STATE_TAG;
  s[1] = c->t;
  memcpy(s + 2, c->x, N_X * sizeof(double));
  memcpy(s + 2 + N_X, c->now, 6 * N_ENDS * sizeof(double));
  memcpy(s + 2 + N_X + 6 * N_ENDS, c->pose, N_DOF * sizeof(double));
  memcpy(s + 2 + N_X + 6 * N_ENDS + N_DOF, c->base, 3 * N_ENDS * sizeof(double));
  return 0;
}}

int sc_set_state(sc_coupling *c, const double *s, double *f) {{
  if (!c || !s) return 1;
  if (sc_check(c, s, SC_STATE, "state", NULL)) return 1;
  if (s[0] != STATE_TAG)
    return sc_fail(c, 1, "state: not one of this library's (another export or scene)");
  c->t = s[1];
  memcpy(c->x, s + 2, N_X * sizeof(double));
  memcpy(c->now, s + 2 + N_X, 6 * N_ENDS * sizeof(double));
  memcpy(c->pose, s + 2 + N_X + 6 * N_ENDS, N_DOF * sizeof(double));
  memcpy(c->base, s + 2 + N_X + 6 * N_ENDS + N_DOF, 3 * N_ENDS * sizeof(double));
  memcpy(c->p, P_DYNAMIC, sizeof c->p);
  for (int e = 0; e < N_ENDS; ++e)
    memcpy(c->p + END_POSITION[e], c->base + 3 * e, 3 * sizeof(double));
  sc_path(c, c->now, c->now, c->t, c->t);
  c->ready = 1;
  return sc_forces(c, f);
}}

int sc_outputs(sc_coupling *c, double *out) {{
  if (!c || !c->ready || !out) return 1;
  const casadi_real *in[] = {{c->x, &c->t, c->p}};
  casadi_real *res[] = {{out}};
  return SC_CALL(c, dyn_outputs, in, res) ? sc_fail(c, 2, "dyn_outputs failed") : 0;
}}
"""

_HOST = r"""/* Example host: moves every coupled degree of freedom harmonically about its exported
 * pose, ramped in over the first period as a scene's harmonic motion is, and prints the
 * forces at every step, one line "t f_1 ... f_n". Halfway it saves the state; at the end it
 * restores it, steps to the end again and prints how far the forces differ (0: the same).
 * Build: cc -O2 host.c symcable_coupling.c {stem}.c -lm -o host
 * Run:   ./host PERIOD DT STEPS  A_1 PHASE_1 ... A_n PHASE_n   (A m or rad, PHASE rad) */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include "symcable_coupling.h"
#include "{stem}_data.h"
#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

static double period;

/* the motion at t: pose x, and velocity xd (bodies: angular velocity, global axes) */
static void motion(double t, const double *amp, const double *phase, double *x, double *xd) {{
  double w = 2.0 * M_PI / period, r = 1.0, rd = 0.0, rates[N_DOF];
  if (t <= 0.0) {{ r = 0.0; }}
  else if (t < period) {{
    r = 0.5 * (1.0 - cos(M_PI * t / period));
    rd = 0.5 * M_PI / period * sin(M_PI * t / period);
  }}
  for (int i = 0; i < N_DOF; ++i) {{
    x[i] = BASE_POSE[i] + r * amp[i] * cos(w * t + phase[i]);
    rates[i] = rd * amp[i] * cos(w * t + phase[i]) - r * amp[i] * w * sin(w * t + phase[i]);
    xd[i] = rates[i];
  }}
  for (int k = 0; k < N_THINGS; ++k)
    if (THING_BODY[k]) sc_angular_velocity(x + THING_DOF0[k] + 3, rates + THING_DOF0[k] + 3,
                                           xd + THING_DOF0[k] + 3);
}}

static void print_forces(double t, const double *f) {{
  printf("%.17g", t);
  for (int i = 0; i < N_DOF; ++i) printf(" %.17g", f[i]);
  printf("\n");
}}

int main(int argc, char **argv) {{
  double amp[N_DOF], phase[N_DOF], x[N_DOF], xd[N_DOF], f[N_DOF], g[N_DOF];
  if (argc != 4 + 2 * N_DOF) {{
    fprintf(stderr, "usage: %s PERIOD DT STEPS then an amplitude and a phase for each of",
            argv[0]);
    for (int i = 0; i < N_DOF; ++i) fprintf(stderr, " %s", sc_dof_name(i));
    fprintf(stderr, "\n");
    return 1;
  }}
  period = atof(argv[1]);
  double dt = atof(argv[2]);
  long steps = atol(argv[3]);
  if (steps < 1 || !(period > 0.0) || !(dt > 0.0)) {{
    fprintf(stderr, "PERIOD and DT must be > 0 and STEPS at least 1\n");
    return 1;
  }}
  for (int i = 0; i < N_DOF; ++i) {{ amp[i] = atof(argv[4 + 2 * i]); phase[i] = atof(argv[5 + 2 * i]); }}
  sc_coupling *c = sc_create();
  double *saved = malloc(sizeof(double) * sc_state_size());
  if (!c || !saved) return 1;
  motion(0.0, amp, phase, x, xd);
  if (sc_initialize(c, x, xd, 0.0, f)) {{ fprintf(stderr, "%s\n", sc_error(c)); return 1; }}
  print_forces(0.0, f);
  long half = steps / 2;
  for (long k = 0; k < steps; ++k) {{
    if (k == half) sc_get_state(c, saved);
    motion((k + 1) * dt, amp, phase, x, xd);
    if (sc_step(c, k * dt, dt, x, xd, f)) {{ fprintf(stderr, "%s\n", sc_error(c)); return 2; }}
    print_forces((k + 1) * dt, f);
  }}
  if (sc_set_state(c, saved, g)) {{ fprintf(stderr, "%s\n", sc_error(c)); return 2; }}
  for (long k = half; k < steps; ++k) {{
    motion((k + 1) * dt, amp, phase, x, xd);
    if (sc_step(c, k * dt, dt, x, xd, g)) {{ fprintf(stderr, "%s\n", sc_error(c)); return 2; }}
  }}
  double diff = 0.0;
  for (int i = 0; i < N_DOF; ++i) diff = fmax(diff, fabs(f[i] - g[i]));
  printf("restore_check = %.17g\n", diff);
  free(saved);
  sc_destroy(c);
  return 0;
}}
"""


def runtime_c(stem: str) -> str:
    """``symcable_coupling.c`` on the generated ``<stem>.c`` and its data header."""
    return _RUNTIME.format(stem=stem)


def host_c(stem: str) -> str:
    """The example host ``host.c``."""
    return _HOST.format(stem=stem)


def readme(stem: str, name_literal: str, facts: dict, literal) -> str:
    """The folder's README: what the library is, how to build and call it, its numbers."""
    dofs = "\n".join(f"| {i} | {literal(n)} |" for i, n in enumerate(facts["dofs"]))
    return f"""# symcable coupling library for the scene {name_literal}

Written by `symcable codegen --coupling`. A host program (a floating-body solver) moves the
coupled points and bodies; this library steps the mooring lines between them with the
first-order generalized-alpha step that `symcable.simulate` takes (rho_inf
{facts['rho_inf']:g}, Newton tolerance {facts['tol']:.3g} on the scaled step residual, at
most {facts['max_iter']} iterations) and returns the forces the lines exert on the coupled
things. It is `symcable.Coupling` in C: the same step, and from the exported static state at
rest the same answers to round-off. A start elsewhere (`sc_initialize` at another pose, or
moving) begins from rates of zero where the Python coupling computes them, which moves the
first steps' forces by about 1e-6 of themselves.

## Files

| file | what |
|---|---|
| `{stem}.c`, `{stem}.h` | CasADi's generated C: `ga_step`, `end_forces`, `static_residual`, `static_ptc_step`, `dyn_outputs` |
| `{stem}_data.h` | the scene's numbers: parameters, the static state, the coupled ends |
| `symcable_coupling.h`, `symcable_coupling.c` | the host's API (below) |
| `host.c` | an example host: a harmonic motion of every degree of freedom |

Build: `cc -O2 host.c symcable_coupling.c {stem}.c -lm -o host`, then
`./host PERIOD DT STEPS A_1 PHASE_1 ... A_n PHASE_n`.

## The API (`symcable_coupling.h`)

- `sc_create()`, `sc_destroy(c)`.
- `sc_initialize(c, x, xd, t, f)`: the lines' static state with the coupled things at `x`
  (exactly the exported state when `x` is the exported pose `BASE_POSE`; otherwise the
  static solve from it by pseudo-transient continuation, symcable's own fallback), at rest at
  time `t`; the forces at `x` into `f`.
- `sc_step(c, t, dt, x, xd, f)`: from `t` to `t + dt`, the things at `x` moving at `xd`
  at `t + dt`; the coupled line ends follow the cubic through the host's positions and
  velocities at `t` and `t + dt`. A step whose Newton iterations fail is retried as 2, 4, ...
  16 substeps; then it returns 2 and the state stays at `t`.
- `sc_get_state(c, s)`, `sc_set_state(c, s, f)`: save and restore (`sc_state_size()`
  doubles), e.g. for a host's predictor-corrector.
- `sc_outputs(c, out)`: every named output of the lines (`sc_output_name`), at the
  current time.
- Return codes: 0 done, 1 a bad argument, 2 a solve failed; `sc_error(c)` says which.

## Degrees of freedom

A point: x, y, z (m). A body: x, y, z (m), roll, pitch, yaw (rad; R = Rz(yaw) Ry(pitch)
Rx(roll)), its velocity the reference point's (m/s) and its angular velocity in global axes
(rad/s; `sc_angular_velocity` converts Euler rates). Forces: N on points; N and N m about
the reference point (global axes) on bodies.

| index | degree of freedom |
|---|---|
{dofs}

## Numbers

{facts['n_ends']} coupled line end(s), {facts['n_x']} entries of the step's carried state,
{facts['n_p']} parameters; static tolerance {facts['static_tol']:.3g} N.
"""
