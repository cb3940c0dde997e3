"""The module's kernels equal the Rust kernels bit for bit, on random scenes and
states, one at a time and in batches."""

import zlib

import numpy as np
import pytest

import filippov
from conftest import KINEMATICS, SCENES, fmt, numbers, random_scene, same_bits

BATCH = 5


@pytest.mark.parametrize("name", SCENES)
def test_kernels_equal_rust_bit_for_bit(name, rust):
    rng = np.random.default_rng(zlib.crc32(name.encode()))
    scene, params = random_scene(name, rng)
    n = scene.dof
    p = fmt(list(params.values()))
    q = rng.uniform(-1.0, 1.0, (BATCH, n))
    v = rng.uniform(-2.0, 2.0, (BATCH, n))
    tau = rng.uniform(-5.0, 5.0, (BATCH, n))
    acc = rng.uniform(-3.0, 3.0, (BATCH, n))
    requests = []
    for i in range(BATCH):
        requests += [
            f"kernel {name} mass_matrix {p} ; {fmt(q[i])}",
            f"kernel {name} forward_dynamics {p} ; {fmt(q[i])} {fmt(v[i])} {fmt(tau[i])}",
            f"kernel {name} jacobian {p} ; {fmt(q[i])} {fmt(v[i])} {fmt(tau[i])}",
            f"kernel {name} inverse_dynamics {p} ; {fmt(q[i])} {fmt(v[i])} {fmt(acc[i])}",
        ]
    answers = iter(rust.ask(requests))
    m = scene.mass_matrix(q)
    a = scene.forward_dynamics(q, v, tau)
    ja, jq, jv = scene.forward_dynamics_jacobian(q, v, tau)
    t = scene.inverse_dynamics(q, v, acc)
    assert m.shape == (BATCH, n, n) and jq.shape == (BATCH, n, n)
    for i in range(BATCH):
        assert same_bits(m[i].ravel(), numbers(next(answers)[0]))
        assert same_bits(a[i], numbers(next(answers)[0]))
        jac = numbers(next(answers)[0])
        assert same_bits(np.concatenate([ja[i], jq[i].ravel(), jv[i].ravel()]), jac)
        assert same_bits(t[i], numbers(next(answers)[0]))
        # One state at a time gives the batch's row.
        assert same_bits(scene.mass_matrix(q[i]), m[i])
        assert same_bits(scene.forward_dynamics(q[i], v[i], tau[i]), a[i])
        assert same_bits(scene.inverse_dynamics(q[i], v[i], acc[i]), t[i])
    # Without τ the forces are zero.
    assert same_bits(scene.forward_dynamics(q, v), scene.forward_dynamics(q, v, np.zeros_like(q)))


@pytest.mark.parametrize("name", KINEMATICS)
def test_frame_poses_equal_rust_bit_for_bit(name, rust):
    rng = np.random.default_rng(zlib.crc32((name + "frames").encode()))
    scene, params = random_scene(name, rng)
    cls = type(scene)
    q = rng.uniform(-1.0, 1.0, (len(cls.frames), scene.dof))
    requests = [
        f"kernel {name} frame_pose {fmt(list(params.values()))} ; {k} {fmt(q[k])}"
        for k in range(len(cls.frames))
    ]
    for k, (answer,) in enumerate(rust.ask(requests)):
        pose = scene.frame_pose(cls.frames[k], q[k])
        assert pose.shape == (4, 4)
        assert same_bits(pose.ravel(), numbers(answer))
        assert same_bits(scene.frame_pose(cls.frames[k], q[k : k + 1])[0], pose)
        jac = scene.frame_jacobian(cls.frames[k], q[k])
        assert jac.shape == (6, scene.dof)


def test_frame_jacobian_is_the_derivative_of_the_pose():
    """An independent check of the frames the module returns: the first three rows of
    the Jacobian are the derivative of the frame's origin (central differences)."""
    rng = np.random.default_rng(7)
    arm = filippov.Panda(g=9.81)
    q = rng.uniform(-1.0, 1.0, 7)
    frame = filippov.Panda.frames[-1]
    jac = arm.frame_jacobian(frame, q)
    h = 1e-6
    for j in range(7):
        dq = np.zeros(7)
        dq[j] = h
        d = (arm.frame_pose(frame, q + dq)[:3, 3] - arm.frame_pose(frame, q - dq)[:3, 3]) / (2 * h)
        assert np.allclose(d, jac[:3, j], atol=1e-8)


def test_inputs_of_any_array_like_and_dtype():
    arm = filippov.DoublePendulum(m1=1.0, l1=1.0, m2=0.5, l2=0.7, g=9.81)
    a = arm.mass_matrix(np.array([0.3, -0.2]))
    assert same_bits(arm.mass_matrix([0.3, -0.2]), a)
    assert same_bits(arm.mass_matrix((0.3, -0.2)), a)
    # A strided view is read as its values.
    qs = np.array([[0.3, 9.0], [-0.2, 9.0]])
    assert same_bits(arm.mass_matrix(qs[:, 0]), a)
    assert same_bits(arm.mass_matrix(np.array([0, 1], dtype=np.int32)), arm.mass_matrix([0.0, 1.0]))


def test_fused_kernels_switch_agrees_to_rounding():
    """`fused_kernels(False)` puts the forward dynamics and mass matrix on their portable
    path for the process and `fused_kernels()` reports it; the two paths agree to
    rounding (bit for bit where the processor has no AVX2 and FMA). The switch is put
    back as it was."""
    rng = np.random.default_rng(11)
    arm = filippov.Panda(g=9.81)
    q = rng.uniform(-2.0, 2.0, (20, 7))
    v = rng.uniform(-3.0, 3.0, (20, 7))
    tau = rng.uniform(-5.0, 5.0, (20, 7))
    was = filippov.fused_kernels()
    try:
        filippov.fused_kernels(True)
        on = filippov.fused_kernels()
        a1, m1 = arm.forward_dynamics(q, v, tau), arm.mass_matrix(q)
        assert filippov.fused_kernels(False) is False
        assert filippov.fused_kernels() is False
        a0, m0 = arm.forward_dynamics(q, v, tau), arm.mass_matrix(q)
    finally:
        filippov.fused_kernels(was)
    assert filippov.fused_kernels() == was
    if not on:
        assert same_bits(a1, a0) and same_bits(m1, m0)
    for i in range(len(q)):
        eig = np.linalg.eigvalsh(m0[i])
        kappa = eig.max() / eig.min()
        scale = max(1.0, np.abs(a0[i]).max())
        eps = np.finfo(float).eps
        assert np.abs(a1[i] - a0[i]).max() <= 4 * eps * kappa * scale
        assert np.abs(m1[i] - m0[i]).max() <= 8 * eps * np.abs(m0[i]).max()
