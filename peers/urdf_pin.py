"""Pinocchio on the URDF robots the report exported (target/report/urdf/<robot>.json):
loads the same URDF file, computes M, C v + g (nonLinearEffects) and ABA at the exported
states and compares them with filippov's values; times ABA through the Python bindings.

Frames: for every frame the report exported (the bodies and the file's tool frames of
the generated forward kinematics), Pinocchio's framesForwardKinematics placement and
computeFrameJacobian(LOCAL_WORLD_ALIGNED) on the frame of the same name, the Jacobian
mapped to our velocity coordinates (J_ours = J_pin T).

Usage: urdf_pin.py <dir with the robots' JSON> <output .tsv> [pin_bench binary]

With the C++ benchmark (peers/pin_bench.cpp, built by peers/run.sh), each robot's model
as Pinocchio built it is also written next to the .tsv (urdf/<robot>.txt, read by
pin_bench) and ABA is timed in C++; its result must equal the bindings' at the state.
The report runs the same binary on those files beside its own timing of our forward
dynamics, so the two are measured in one run.

A free base (`base = free` in filippov) is Pinocchio's free-flyer joint. The two use
different velocity coordinates for it: filippov's are the world-frame rate of the base
position ṗ and the body angular velocity ω, Pinocchio's the body-frame linear velocity
v_b = Rᵀ ṗ and ω. With T = diag(Rᵀ, I, I) (ours → Pinocchio): M_ours = Tᵀ M_pin T,
τ_pin = diag(Rᵀ, I, I) τ_ours, and p̈ = R (v̇_b + ω × v_b). Configurations: filippov
[p, w x y z, joints], Pinocchio [p, x y z w, joints].
"""
import glob
import json
import os
import subprocess
import sys
import time

import numpy as np
import pinocchio as pin

import pin_model


def quat_matrix(w, x, y, z):
    return np.array([
        [1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
        [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
        [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)],
    ])


def rel(a, b):
    a, b = np.asarray(a, float).ravel(), np.asarray(b, float).ravel()
    return float(np.max(np.abs(a - b)) / max(1.0, float(np.max(np.abs(b)))))


def load(d):
    if d["free_base"]:
        model = pin.buildModelFromUrdf(d["urdf"], pin.JointModelFreeFlyer())
    else:
        model = pin.buildModelFromUrdf(d["urdf"])
    if d["lock"]:
        ids = [model.getJointId(n) for n in d["lock"]]
        model = pin.buildReducedModel(model, ids, pin.neutral(model))
    model.gravity.linear = np.array([0.0, 0.0, -9.81])
    return model


def cpp_aba(binary, model, path, q, v, tau):
    """ABA ns from pin_bench on the model written to `path`; checks its result first."""
    os.makedirs(os.path.dirname(path), exist_ok=True)
    pin_model.write_model(model, path, q, v, tau)
    res = subprocess.run([binary, path], capture_output=True, text=True, check=True)
    vals = {k: [float(t) for t in x] for k, *x in (l.split() for l in res.stdout.splitlines())}
    ref = pin.aba(model, model.createData(), q, v, tau)
    diff = rel(vals["aba"], ref)
    if diff > 1e-12:
        raise SystemExit(f"{path}: the C++ model's ABA differs from the bindings' by {diff:.2e}")
    return vals["aba_ns"][0]


def robot(d, binary=None, flat_dir=None):
    model = load(d)
    data = model.createData()
    free = d["free_base"]
    # Pinocchio numbers joints depth-first with children in its own order; ours follow
    # the file. P maps our velocity vector to Pinocchio's: v_pin = P v.
    nv = model.nv
    perm = list(range(6)) if free else []
    for name in d["joints"]:
        perm.append(model.joints[model.getJointId(name)].idx_v)
    P = np.zeros((nv, nv))
    for i, j in enumerate(perm):
        P[j, i] = 1.0
    err_m = err_b = err_fd = err_pose = err_jac = 0.0
    frame_ids = [model.getFrameId(f) for f in d.get("frames", [])]
    missing = [f for f, i in zip(d.get("frames", []), frame_ids) if i >= model.nframes]
    if missing:
        print(f"{d['name']}: frames not in Pinocchio's model: {missing}")
    for s in d["states"]:
        q, v, tau = (np.array(s[k]) for k in ("q", "v", "tau"))
        n = len(v)
        if free:
            p, (w, x, y, z), joints = q[:3], q[3:7], q[7:]
            R = quat_matrix(w, x, y, z)
            q_pin = np.concatenate([p, [x, y, z, w], (P[6:, 6:] @ joints)])
            T = np.eye(n)
            T[:3, :3] = R.T
        else:
            R = None
            T = np.eye(n)
            q_pin = P @ q
        T = P @ T
        v_pin = T @ v
        tau_pin = np.linalg.solve(T.T, tau)
        M_pin = pin.crba(model, data, q_pin)
        M_pin = np.triu(M_pin) + np.triu(M_pin, 1).T
        M = T.T @ M_pin @ T

        def ours_accel(a_pin):
            a = P.T @ np.array(a_pin)
            if free:
                vb, om = v_pin[:3], v_pin[3:6]
                a[:3] = R @ (a_pin[:3] + np.cross(om, vb))
            return a

        fd = ours_accel(pin.aba(model, data, q_pin, v_pin, tau_pin))
        bias = -M @ ours_accel(pin.aba(model, data, q_pin, v_pin, np.zeros(n)))
        err_m = max(err_m, rel(np.array(s["m"]).reshape(n, n), M))
        err_b = max(err_b, rel(s["bias"], bias))
        err_fd = max(err_fd, rel(s["fd"], fd))
        if frame_ids:
            pin.framesForwardKinematics(model, data, q_pin)
            pin.computeJointJacobians(model, data, q_pin)
            for fid, ours in zip(frame_ids, s["fk"]):
                if fid >= model.nframes:
                    continue
                ours = np.array(ours)
                o = data.oMf[fid]
                err_pose = max(err_pose, float(np.max(np.abs(ours[:9] - o.rotation.ravel()))),
                               float(np.max(np.abs(ours[9:12] - o.translation))))
                J = pin.getFrameJacobian(model, data, fid, pin.LOCAL_WORLD_ALIGNED) @ T
                err_jac = max(err_jac, rel(ours[12:].reshape(6, n), J))
    # ABA through the bindings, median of 5 batches.
    s = d["states"][0]
    q, v, tau = (np.array(s[k]) for k in ("q", "v", "tau"))
    if free:
        q = np.concatenate([q[:3], q[4:7], q[3:4], q[7:]])
    calls, times = 20000, []
    for _ in range(5):
        t0 = time.perf_counter()
        for _ in range(calls):
            pin.aba(model, data, q, v, tau)
        times.append((time.perf_counter() - t0) / calls * 1e9)
    cpp = (cpp_aba(binary, model, os.path.join(flat_dir, d["name"] + ".txt"), q, v, tau)
           if binary else float("nan"))
    return err_m, err_b, err_fd, sorted(times)[2], model.nv, err_pose, err_jac, cpp


def main():
    src, out = sys.argv[1], sys.argv[2]
    binary = sys.argv[3] if len(sys.argv) > 3 and sys.argv[3] else None
    flat_dir = os.path.join(os.path.dirname(out), "urdf")
    rows = ["robot\tM\tbias\tfd\taba_ns_python\tnv\tframe_pose\tframe_jacobian\taba_ns_cpp"]
    for path in sorted(glob.glob(os.path.join(src, "*.json"))):
        d = json.load(open(path))
        m, b, fd, ns, nv, fp, fj, cpp = robot(d, binary, flat_dir)
        print(f"{d['name']}: nv {nv}, max rel difference M {m:.2e}, C v + g {b:.2e}, FD {fd:.2e}; "
              f"{len(d.get('frames', []))} frames: pose {fp:.2e}, Jacobian {fj:.2e}; "
              f"ABA {ns:.0f} ns (Python), {cpp:.0f} ns (C++)")
        rows.append(f"{d['name']}\t{m:e}\t{b:e}\t{fd:e}\t{ns:.1f}\t{nv}\t{fp:e}\t{fj:e}\t{cpp:.1f}")
    os.makedirs(os.path.dirname(out), exist_ok=True)
    open(out, "w").write("\n".join(rows) + "\n")


if __name__ == "__main__":
    main()
