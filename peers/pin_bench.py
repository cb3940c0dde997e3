"""Pinocchio on filippov's scene models: import check (closed-form double pendulum, C++ vs
Python bindings), C++ timings (pin_bench.cpp) and Python-binding timings.
Usage: pin_bench.py MODELS_DIR BUILD_DIR OUT_JSON [PIN_BENCH_BINARY or '']"""
import json
import os
import subprocess
import sys
import time

import numpy as np
import pinocchio as pin

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import pin_model  # noqa: E402

SCENES = ["double_pendulum", "planar_arm3", "branched_tree", "panda"]


def state(n):
    q = np.array([0.3 + 0.17 * i for i in range(n)])
    v = np.array([0.5 - 0.23 * i for i in range(n)])
    tau = np.array([0.7 - 0.11 * i for i in range(n)])
    return q, v, tau


def closed_form_check(model):
    """Max abs difference of Pinocchio's M, rnea and aba against the closed-form double pendulum."""
    m1, l1, m2, l2, g = 1.0, 1.0, 0.5, 0.7, 9.81
    lc1, lc2 = l1 / 2, l2 / 2
    I1, I2 = m1 * l1**2 / 12, m2 * l2**2 / 12
    data = model.createData()
    worst = {"M": 0.0, "rnea": 0.0, "aba": 0.0}
    rng = np.random.default_rng(1)
    for _ in range(20):
        q, v, a = rng.uniform(-3, 3, 2), rng.uniform(-2, 2, 2), rng.uniform(-2, 2, 2)
        c2 = np.cos(q[1])
        M = np.array([
            [m1 * lc1**2 + I1 + m2 * (l1**2 + lc2**2 + 2 * l1 * lc2 * c2) + I2, m2 * (lc2**2 + l1 * lc2 * c2) + I2],
            [m2 * (lc2**2 + l1 * lc2 * c2) + I2, m2 * lc2**2 + I2],
        ])
        h = m2 * l1 * lc2 * np.sin(q[1])
        cor = np.array([-h * (2 * v[0] * v[1] + v[1] ** 2), h * v[0] ** 2])
        grav = np.array([
            (m1 * lc1 + m2 * l1) * g * np.cos(q[0]) + m2 * lc2 * g * np.cos(q[0] + q[1]),
            m2 * lc2 * g * np.cos(q[0] + q[1]),
        ])
        Mp = pin.crba(model, data, q)
        Mp = np.triu(Mp) + np.triu(Mp, 1).T
        worst["M"] = max(worst["M"], np.abs(Mp - M).max())
        worst["rnea"] = max(worst["rnea"], np.abs(pin.rnea(model, data, q, v, a) - (M @ a + cor + grav)).max())
        tau = rng.uniform(-2, 2, 2)
        ddq = np.linalg.solve(M, tau - cor - grav)
        worst["aba"] = max(worst["aba"], np.abs(pin.aba(model, data, q, v, tau) - ddq).max())
    return worst


def py_time(f, reps=21, inner=2000):
    for _ in range(inner):
        f()
    per = []
    for _ in range(reps):
        t0 = time.perf_counter_ns()
        for _ in range(inner):
            f()
        per.append((time.perf_counter_ns() - t0) / inner)
    return float(np.median(per))


def main():
    models_dir, build_dir, out_json = sys.argv[1:4]
    binary = sys.argv[4] if len(sys.argv) > 4 else ""
    out = {"scenes": {}, "cpp": bool(binary)}
    # call overhead of a trivial bound function (same argument passing as the algorithms)
    m0 = pin.Model()
    out["py_overhead_ns"] = py_time(lambda: m0.existJointName("x"))
    for scene in SCENES:
        model, spec, info = pin_model.load(os.path.join(models_dir, scene + ".json"))
        data = model.createData()
        n = model.nv
        q, v, tau = state(n)
        a = np.full(n, 0.3)
        r = {"nq": model.nq, "joints": [s[0] for s in spec], "springs": len(info["springs"]),
             "dampers": len(info["dampers"]), "links": info["links"]}
        if scene == "double_pendulum":
            r["closed_form_maxdiff"] = closed_form_check(model)
        # Python-binding timings (per call, raw)
        r["py"] = {
            "crba_ns": py_time(lambda: pin.crba(model, data, q)),
            "rnea_ns": py_time(lambda: pin.rnea(model, data, q, v, a)),
            "aba_ns": py_time(lambda: pin.aba(model, data, q, v, tau)),
            "coriolis_ns": py_time(lambda: pin.computeCoriolisMatrix(model, data, q, v)),
        }
        if binary:
            flat = os.path.join(build_dir, scene + ".txt")
            pin_model.write_flat(model, spec, flat, q, v, tau)
            res = subprocess.run([binary, flat], capture_output=True, text=True, check=True)
            vals = {}
            for line in res.stdout.splitlines():
                k, *x = line.split()
                vals[k] = [float(t) for t in x]
            M = pin.crba(model, data, q)
            M = np.triu(M) + np.triu(M, 1).T
            r["cpp_vs_py_maxdiff"] = max(
                np.abs(np.array(vals["M"]).reshape(n, n) - M).max(),
                np.abs(np.array(vals["rnea"]) - pin.rnea(model, data, q, v, a)).max(),
                np.abs(np.array(vals["aba"]) - pin.aba(model, data, q, v, tau)).max(),
            )
            r["cpp"] = {k: vals[k][0] for k in ("crba_ns", "rnea_ns", "aba_ns", "coriolis_ns")}
            # fastest and slowest batch of each timing
            r["cpp_range"] = {k: vals[k + "_range"] for k in r["cpp"] if k + "_range" in vals}
        out["scenes"][scene] = r
        print(scene, json.dumps(r), flush=True)
    with open(out_json, "w") as f:
        json.dump(out, f, indent=1)


if __name__ == "__main__":
    main()
