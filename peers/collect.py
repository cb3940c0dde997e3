"""Writes peers.md and peers.tsv from the JSON results of the benchmark scripts.
Usage: collect.py OUT_DIR HEADER_JSON"""
import json
import os
import sys

import numpy as np
import pinocchio as pin


def chain_check(n, ddq):
    """Pinocchio ABA on the same rod chain (parameters as in the C harness) vs the SymPy result."""
    model = pin.Model()
    model.gravity = pin.Motion(np.array([0.0, -9.81, 0.0]), np.zeros(3))
    parent, prev_l = 0, 0.0
    for i in range(n):
        m, l = 1.0 - 0.1 * i, 0.5 + 0.05 * i
        jid = model.addJoint(parent, pin.JointModelRZ(), pin.SE3(np.eye(3), np.array([prev_l, 0, 0])), f"j{i}")
        model.appendBodyToJoint(jid, pin.Inertia(m, np.array([l / 2, 0, 0]), np.diag([0, m * l * l / 12, m * l * l / 12])),
                                pin.SE3.Identity())
        parent, prev_l = jid, l
    q = np.array([0.3 + 0.17 * i for i in range(n)])
    u = np.array([0.5 - 0.23 * i for i in range(n)])
    a = pin.aba(model, model.createData(), q, u, np.zeros(n))
    return float(np.abs(a - np.array(ddq)).max())


def spread(r, key, lo, hi, fmt):
    """`median (min–max)` of r[key] when the range was recorded, else the median."""
    m = fmt.format(r[key])
    if lo in r and hi in r:
        return f"{m} ({fmt.format(r[lo])}–{fmt.format(r[hi])})"
    return m


def g(x, fmt="{:.3g}"):
    return "n/a" if x is None or (isinstance(x, float) and np.isnan(x)) else fmt.format(x)


def main():
    out_dir, header_json = sys.argv[1:3]
    tmp = os.path.join(out_dir, "results")
    hdr = json.load(open(header_json))
    md, tsv = [], []
    tsv.append(f"# peers/run.sh {hdr['date']}; {hdr['machine']}; {hdr['versions']}")
    tsv.append("# peer\tscene\tquantity\tvalue\tunit")
    md.append(f"*Run {hdr['date']} on {hdr['machine']}; {hdr['versions']}.*\n")

    # Pinocchio
    pj = os.path.join(tmp, "pinocchio.json")
    if os.path.exists(pj):
        p = json.load(open(pj))
        cpp = p["cpp"]
        md.append("### Pinocchio (rigid-body algorithms)\n")
        md.append("Models built from the exported JSON (`target/report/models/*.json`), one Pinocchio joint per moving "
                  "link (RX/RY/RZ, RevoluteUnaligned, PX/PY/PZ), fixed links merged into their parent body. "
                  + ("Timed in C++ (`peers/pin_bench.cpp`, compiled against the headers the `pin` wheel ships with "
                     f"`{hdr.get('cxxflags', '')}`; templates instantiated in the benchmark itself, not through the shipped "
                     "`libpinocchio_default.so`): median (min–max) over 21 batches of ns per call at a fixed state, after warm-up; the Python column is a median. "
                     if cpp else
                     "C++ build failed or was skipped, so these are Python-binding timings minus the measured call "
                     f"overhead of a trivial bound function ({p['py_overhead_ns']:.0f} ns). ")
                  + "Pinocchio's ABA gets the joint torques only; our planar_arm3 and branched_tree forward dynamics also "
                  "evaluate springs/dampers (a few flops).\n")
        dp = p["scenes"]["double_pendulum"]["closed_form_maxdiff"]
        md.append(f"Import check against the closed-form double pendulum (m1 = 1, l1 = 1, m2 = 0.5, l2 = 0.7 rods, 20 random "
                  f"states): max abs difference M {dp['M']:.1e}, rnea {dp['rnea']:.1e}, aba {dp['aba']:.1e}. "
                  + ("C++ results vs Python bindings at the timing state: max abs difference "
                     + ", ".join(f"{s} {r['cpp_vs_py_maxdiff']:.1e}" for s, r in p["scenes"].items()) + "." if cpp else "")
                  + "\n")
        md.append("| scene | dof | joints | crba ns | rnea ns | aba ns | Coriolis matrix ns | aba ns via Python (raw) |")
        md.append("|---|---|---|---|---|---|---|---|")
        peer = "pinocchio" if cpp else "pinocchio-python"
        for s, r in p["scenes"].items():
            t = r["cpp"] if cpp else {k: v - p["py_overhead_ns"] for k, v in r["py"].items()}
            rng = r.get("cpp_range", {}) if cpp else {}

            def ns(k):
                return f"{t[k]:.0f}" + (f" ({rng[k][0]:.0f}–{rng[k][1]:.0f})" if k in rng else "")
            md.append(f"| {s} | {r['nq']} | {' '.join(r['joints'])} | {ns('crba_ns')} | {ns('rnea_ns')} | "
                      f"{ns('aba_ns')} | {ns('coriolis_ns')} | {r['py']['aba_ns']:.0f} |")
            for k in ("crba_ns", "rnea_ns", "aba_ns", "coriolis_ns"):
                tsv.append(f"{peer}\t{s}\t{k}\t{t[k]:.3f}\tns")
            tsv.append(f"pinocchio-python\t{s}\taba_call_ns\t{r['py']['aba_ns']:.3f}\tns")
        tsv.append(f"pinocchio-python\t-\tcall_overhead_ns\t{p['py_overhead_ns']:.3f}\tns")
        tsv.append(f"pinocchio\tdouble_pendulum\tclosed_form_maxdiff\t{max(dp.values()):.3e}\t-")
        md.append("")
    else:
        md.append("### Pinocchio\n\nFailed: no results (see the run.sh log).\n")

    # SciPy
    sj = os.path.join(tmp, "scipy.json")
    if os.path.exists(sj):
        s = json.load(open(sj))
        md.append("### SciPy `solve_ivp` on the Coulomb scenes S5 and S6\n")
        md.append("Event-driven stick/slip switching (a velocity-zero event ends a slip phase; in the stick phase the "
                  "events are the required holding force reaching ±f_crit), restarting `solve_ivp` at every switch. "
                  "S6 errors against the closed-form turning points (−1)ⁿ(1 − 0.2n) at nπ, n = 1…5, and x(30) = 0; "
                  "S5 error of x(30) against a piecewise closed form (linear modes, switch times by root bracketing, "
                  f"{s['s5_reference']['switches']} switches, x(30) = {s['s5_reference']['x_end']:.10f}). atol = rtol/100; "
                  "time is the median (min–max) of 5 runs after a warm-up.\n")
        md.append("| scene | method | rtol | s | nfev | turning points | turning-point x error | turning-point t error | x(30) error |")
        md.append("|---|---|---|---|---|---|---|---|---|")
        for r in s["event"]:
            md.append(f"| {r['scene']} | {r['method']} | {r['rtol']:.0e} | {spread(r, 's', 's_min', 's_max', '{:.4f}')} | {r['nfev']} | {r['turns']} | "
                      f"{g(r.get('err_turn_x'))} | {g(r.get('err_turn_t'))} | {g(r['err_end'])} |")
            tag = f"event_{r['method'].split(',')[0]}{'_nomaxstep' if ',' in r['method'] else ''}_rtol{r['rtol']:.0e}"
            tsv.append(f"scipy\t{r['scene']}\t{tag}_s\t{r['s']:.6f}\ts")
            tsv.append(f"scipy\t{r['scene']}\t{tag}_err_end\t{r['err_end']:.3e}\t-")
            if r.get("err_turn_x") is not None:
                tsv.append(f"scipy\t{r['scene']}\t{tag}_err_turn_x\t{r['err_turn_x']:.3e}\t-")
        naive = [r for r in s["event"] if "," in r["method"]]
        if naive:
            md.append(f"\nThe naive variant (no `max_step` in the stick phase, whose right-hand side is zero) lets the "
                      f"step grow until the release event is stepped over: x(30) error {naive[0]['err_end']:.3g}.\n")
        md.append("Regularised friction f_crit·tanh(v/ε), rtol = 1e-8, atol = 1e-10, one `solve_ivp` call over t ∈ [0, 30] "
                  "(median (min–max) of 3 runs):\n")
        md.append("| scene | ε | method | s | nfev | x error at nπ (S6) | x(30) error |")
        md.append("|---|---|---|---|---|---|---|")
        for r in s["tanh"]:
            md.append(f"| {r['scene']} | {r['eps']:.0e} | {r['method']} | {spread(r, 's', 's_min', 's_max', '{:.4f}')} | {r['nfev']} | "
                      f"{g(r.get('err_turn_x'))} | {g(r['err_end'])} |")
            tag = f"tanh_{r['method']}_eps{r['eps']:.0e}"
            tsv.append(f"scipy\t{r['scene']}\t{tag}_s\t{r['s']:.6f}\ts")
            tsv.append(f"scipy\t{r['scene']}\t{tag}_err_end\t{r['err_end']:.3e}\t-")
        md.append("")
    else:
        md.append("### SciPy\n\nFailed: no results (see the run.sh log).\n")

    # SymPy
    rows = []
    for n in range(2, 8):
        f = os.path.join(tmp, f"chain{n}.json")
        if os.path.exists(f):
            rows.append(json.load(open(f)))
    md.append("### SymPy mechanics (Kane's method) on planar n-link rod chains\n")
    md.append("Derivation (`KanesMethod.kanes_equations`, no simplification), the parameters substituted as literal numbers "
              "(m_i = 1 − 0.1 i, l_i = 0.5 + 0.05 i, g = 9.81, as the report's chains declare them), `sympy.cse` over M and "
              "forcing, `sympy.ccode` into one C function, compiled with a Cholesky solve twice: `gcc -O3` (the baseline "
              "x86-64 target, as rustc's default build of ours) and `gcc -O3 -march=native`; ns per call of M + forcing + solve, "
              "median (min–max) of 21 batches, in this script's run (the report times the same binaries again beside ours). "
              "ops = `count_ops` over the CSE output. The accelerations are checked against Pinocchio's ABA on the same chain.\n")
    md.append("| n | derivation s | codegen s | gcc s | ops after CSE | M + forcing + solve ns, -O3 | -O3 -march=native | max abs ddq diff vs Pinocchio |")
    md.append("|---|---|---|---|---|---|---|---|")
    for r in rows:
        diff = chain_check(r["n"], r["ddq"])

        def ns(key):
            return f"{r[key + '_ns']:.0f} ({r[key + '_ns_min']:.0f}–{r[key + '_ns_max']:.0f})" if key + "_ns" in r else "n/a"
        md.append(f"| {r['n']} | {r['derive_s']:.2f} | {r['codegen_s']:.2f} | {r['compile_s']:.2f} | {r['ops']} | "
                  f"{ns('solve')} | {ns('solve_native')} | {diff:.1e} |")
        sc = f"chain{r['n']}"
        tsv += [f"sympy\t{sc}\tderive_s\t{r['derive_s']:.4f}\ts", f"sympy\t{sc}\tcodegen_s\t{r['codegen_s']:.4f}\ts",
                f"sympy\t{sc}\tops\t{r['ops']}\tops", f"sympy\t{sc}\tsolve_ns\t{r['solve_ns']:.3f}\tns",
                f"sympy\t{sc}\tsolve_ns_min\t{r.get('solve_ns_min', float('nan')):.3f}\tns",
                f"sympy\t{sc}\tsolve_ns_max\t{r.get('solve_ns_max', float('nan')):.3f}\tns",
                f"sympy\t{sc}\tsolve_native_ns\t{r.get('solve_native_ns', float('nan')):.3f}\tns",
                f"sympy\t{sc}\tddq_maxdiff_vs_pinocchio\t{diff:.3e}\t-"]
    note = open(os.path.join(tmp, "sympy_note.txt")).read().strip() if os.path.exists(os.path.join(tmp, "sympy_note.txt")) else ""
    if note:
        md.append(f"\n{note}")
    md.append("")
    open(os.path.join(out_dir, "peers.md"), "w").write("\n".join(md) + "\n")
    open(os.path.join(out_dir, "peers.tsv"), "w").write("\n".join(tsv) + "\n")


if __name__ == "__main__":
    main()
