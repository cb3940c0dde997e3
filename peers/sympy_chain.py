"""One SymPy mechanics (Kane's method) derivation of a planar n-link rod pendulum chain,
CSE'd C code for M(q) and forcing(q, u), and a C harness timing M + forcing + Cholesky
solve. Usage: sympy_chain.py N BUILD_DIR OUT_JSON

Evened out with filippov's side (report, section "chains"): the parameters (m_i, l_i, g)
are substituted as literal numbers before the common-subexpression elimination, as the
generated chains of the report declare them as literals; and the harness is compiled
twice, with `gcc -O3` (the baseline x86-64 target, as rustc's default build of ours) and
with `-O3 -march=native` for reference."""
import json
import os
import subprocess
import sys
import time

import sympy as sm
import sympy.physics.mechanics as me


def derive(n):
    q = me.dynamicsymbols(f"q0:{n}")
    u = me.dynamicsymbols(f"u0:{n}")
    g = sm.symbols("g")
    m = sm.symbols(f"m0:{n}")
    l = sm.symbols(f"l0:{n}")
    N = me.ReferenceFrame("N")
    O = me.Point("O")
    O.set_vel(N, 0)
    frames, bodies, loads = [], [], []
    prev_frame, joint = N, O
    for i in range(n):
        A = me.ReferenceFrame(f"A{i}")
        A.orient_axis(prev_frame, prev_frame.z, q[i])  # relative angles, in the x-y plane
        A.set_ang_vel(prev_frame, u[i] * prev_frame.z)
        c = joint.locatenew(f"C{i}", l[i] / 2 * A.x)
        c.v2pt_theory(joint, N, A)
        I = me.inertia(A, 0, m[i] * l[i] ** 2 / 12, m[i] * l[i] ** 2 / 12)
        bodies.append(me.RigidBody(f"B{i}", c, A, m[i], (I, c)))
        loads.append((c, -m[i] * g * N.y))
        tip = joint.locatenew(f"P{i}", l[i] * A.x)
        tip.v2pt_theory(joint, N, A)
        prev_frame, joint = A, tip
    kd = [q[i].diff() - u[i] for i in range(n)]
    km = me.KanesMethod(N, q_ind=q, u_ind=u, kd_eqs=kd)
    km.kanes_equations(bodies, loads)
    return km, q, u, m, l, g


C_HARNESS = r"""
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <time.h>
#define N %(n)d
void eval_MF(const double *q, const double *u, double *M, double *F);
static double now(void) { struct timespec t; clock_gettime(CLOCK_MONOTONIC, &t); return t.tv_sec * 1e9 + t.tv_nsec; }
/* M a = F by Cholesky (M symmetric positive definite) */
static void solve(double *M, double *F, double *a) {
  for (int j = 0; j < N; ++j) {
    double d = M[j * N + j];
    for (int k = 0; k < j; ++k) d -= M[j * N + k] * M[j * N + k];
    d = sqrt(d); M[j * N + j] = d;
    for (int i = j + 1; i < N; ++i) {
      double s = M[i * N + j];
      for (int k = 0; k < j; ++k) s -= M[i * N + k] * M[j * N + k];
      M[i * N + j] = s / d;
    }
  }
  for (int i = 0; i < N; ++i) { double s = F[i]; for (int k = 0; k < i; ++k) s -= M[i * N + k] * a[k]; a[i] = s / M[i * N + i]; }
  for (int i = N - 1; i >= 0; --i) { double s = a[i]; for (int k = i + 1; k < N; ++k) s -= M[k * N + i] * a[k]; a[i] = s / M[i * N + i]; }
}
static int cmp(const void *a, const void *b) { double x = *(const double *)a, y = *(const double *)b; return (x > y) - (x < y); }
int main(void) {
  double q[N], u[N], M[N * N], F[N], a[N], sink = 0;
  for (int i = 0; i < N; ++i) { q[i] = 0.3 + 0.17 * i; u[i] = 0.5 - 0.23 * i; }
  eval_MF(q, u, M, F); solve(M, F, a);
  printf("ddq");
  for (int i = 0; i < N; ++i) printf(" %%.17g", a[i]);
  printf("\n");
  long reps = 1000;
  for (;;) {
    double t0 = now();
    for (long r = 0; r < reps; ++r) { q[0] += 1e-12; eval_MF(q, u, M, F); solve(M, F, a); sink += a[N - 1]; }
    if (now() - t0 > 2e7) break;
    reps *= 2;
  }
  double per[21];
  for (int k = 0; k < 21; ++k) {
    double t0 = now();
    for (long r = 0; r < reps; ++r) { q[0] += 1e-12; eval_MF(q, u, M, F); solve(M, F, a); sink += a[N - 1]; }
    per[k] = (now() - t0) / reps;
  }
  qsort(per, 21, sizeof(double), cmp);
  printf("solve_ns %%.3f %%.3f %%.3f\n", per[10], per[0], per[20]);
  fprintf(stderr, "(sink %%g)\n", sink);
  return 0;
}
"""


def main():
    n, build, out_json = int(sys.argv[1]), sys.argv[2], sys.argv[3]
    t0 = time.perf_counter()
    km, q, u, m, l, g = derive(n)
    M = km.mass_matrix
    F = km.forcing
    derive_s = time.perf_counter() - t0

    t0 = time.perf_counter()
    qs, us = sm.symbols(f"q_0:{n}"), sm.symbols(f"u_0:{n}")
    sub = dict(zip(q, qs)) | dict(zip(u, us))
    # Literal parameters, the values of the report's 7-link chain (m_i = 1 - 0.1 i,
    # l_i = 0.5 + 0.05 i, g = 9.81), as filippov's chains declare them.
    values = {m[i]: sm.Float(1.0 - 0.1 * i) for i in range(n)}
    values |= {l[i]: sm.Float(0.5 + 0.05 * i) for i in range(n)}
    values[g] = sm.Float(9.81)
    exprs = [e.xreplace(sub).xreplace(values) for e in list(M) + list(F)]
    repl, red = sm.cse(exprs)
    ops = int(sum(sm.count_ops(e) for _, e in repl) + sum(sm.count_ops(e) for e in red))
    names = {s: sm.Symbol(f"q[{i}]") for i, s in enumerate(qs)}
    names |= {s: sm.Symbol(f"u[{i}]") for i, s in enumerate(us)}
    lines = ["#include <math.h>",
             "void eval_MF(const double *q, const double *u, double *M, double *F) {"]
    for s, e in repl:
        lines.append(f"  const double {s} = {sm.ccode(e.xreplace(names))};")
    for i, e in enumerate(red):
        target = f"M[{i}]" if i < n * n else f"F[{i - n * n}]"
        lines.append(f"  {target} = {sm.ccode(e.xreplace(names))};")
    lines.append("}")
    src = os.path.join(build, f"chain{n}_mf.c")
    with open(src, "w") as f:
        f.write("\n".join(lines) + "\n")
    harness = os.path.join(build, f"chain{n}_main.c")
    with open(harness, "w") as f:
        f.write(C_HARNESS % {"n": n})
    codegen_s = time.perf_counter() - t0

    out = {"n": n, "derive_s": derive_s, "codegen_s": codegen_s, "ops": ops, "cse_terms": len(repl),
           "parameters": "literal"}
    # Baseline target first (the flags of ours in the report), then native for reference.
    for key, flags in (("", ["-O3"]), ("_native", ["-O3", "-march=native"])):
        exe = os.path.join(build, f"chain{n}{key}")
        t0 = time.perf_counter()
        subprocess.run(["gcc", *flags, "-o", exe, harness, src, "-lm"], check=True)
        out[f"compile{key}_s"] = time.perf_counter() - t0
        res = subprocess.run([exe], capture_output=True, text=True, check=True)
        vals = {}
        for line in res.stdout.splitlines():
            k, *x = line.split()
            vals[k] = [float(t) for t in x]
        out[f"solve{key}_ns"], out[f"solve{key}_ns_min"], out[f"solve{key}_ns_max"] = vals["solve_ns"]
        out[f"flags{key}"] = " ".join(flags)
        out["ddq"] = vals["ddq"]
    with open(out_json, "w") as f:
        json.dump(out, f)
    print(json.dumps(out), flush=True)


if __name__ == "__main__":
    main()
