"""Scenes with spherical or free joints (S10's free body, Solo12 and a humanoid on free
bases): kernels and runs equal Rust's bit for bit, configurations carry unit
quaternions, runs integrate on the Lie group and conserve what physics conserves."""

import pickle
import zlib

import numpy as np
import pytest

import filippov
from conftest import LIE, compare, fmt, numbers, same_bits

BATCH = 3


def quaternion_slots(cls):
    """The first slot (`.qw`) of every quaternion in `q`."""
    return [i for i, c in enumerate(cls.configuration) if c.endswith(".qw")]


def random_configuration(cls, rng, batch=None):
    """Random slots, each quaternion normalised."""
    shape = (len(cls.configuration),) if batch is None else (batch, len(cls.configuration))
    q = rng.uniform(-1.0, 1.0, shape)
    for s in quaternion_slots(cls):
        block = q[..., s : s + 4]
        block /= np.linalg.norm(block, axis=-1, keepdims=True)
    return q


def make(name, rng):
    """The scene, with random parameters for the free body (principal moments that
    make a body: each below the sum of the other two)."""
    cls = getattr(filippov, name)
    params = {}
    for p in cls.parameter_names:
        params[p] = float(rng.uniform(1.0, 1.5)) if p != "m" else float(rng.uniform(0.5, 2.0))
    return cls(**params), params


@pytest.mark.parametrize("name", LIE)
def test_kernels_equal_rust_bit_for_bit(name, rust):
    rng = np.random.default_rng(zlib.crc32(("lie" + name).encode()))
    scene, params = make(name, rng)
    cls = type(scene)
    n, nq = scene.dof, len(cls.configuration)
    assert nq == n + len(quaternion_slots(cls)), "a quaternion has one slot more than ω"
    p = fmt(list(params.values()))
    q = random_configuration(cls, rng, BATCH)
    v = rng.uniform(-2.0, 2.0, (BATCH, n))
    tau = rng.uniform(-5.0, 5.0, (BATCH, n))
    acc = rng.uniform(-3.0, 3.0, (BATCH, n))
    frames = [int(k) for k in rng.integers(0, len(cls.frames), BATCH)]
    requests = []
    for i in range(BATCH):
        requests += [
            f"kernel {name} mass_matrix {p} ; {fmt(q[i])}",
            f"kernel {name} forward_dynamics {p} ; {fmt(q[i])} {fmt(v[i])} {fmt(tau[i])}",
            f"kernel {name} jacobian {p} ; {fmt(q[i])} {fmt(v[i])} {fmt(tau[i])}",
            f"kernel {name} inverse_dynamics {p} ; {fmt(q[i])} {fmt(v[i])} {fmt(acc[i])}",
            f"kernel {name} frame_pose {p} ; {frames[i]} {fmt(q[i])}",
        ]
    answers = iter(rust.ask(requests))
    m = scene.mass_matrix(q)
    a = scene.forward_dynamics(q, v, tau)
    ja, jq, jv = scene.forward_dynamics_jacobian(q, v, tau)
    t = scene.inverse_dynamics(q, v, acc)
    assert m.shape == (BATCH, n, n) and a.shape == (BATCH, n) and jq.shape == (BATCH, n, n)
    for i in range(BATCH):
        assert same_bits(m[i].ravel(), numbers(next(answers)[0]))
        assert same_bits(a[i], numbers(next(answers)[0]))
        jac = numbers(next(answers)[0])
        assert same_bits(np.concatenate([ja[i], jq[i].ravel(), jv[i].ravel()]), jac)
        assert same_bits(t[i], numbers(next(answers)[0]))
        pose = scene.frame_pose(cls.frames[frames[i]], q[i])
        assert same_bits(pose.ravel(), numbers(next(answers)[0]))
        assert same_bits(scene.forward_dynamics(q[i], v[i], tau[i]), a[i])
    # Independent of Rust: inverse dynamics undoes forward dynamics.
    assert np.allclose(scene.inverse_dynamics(q, v, a), tau, rtol=1e-9, atol=1e-9)


@pytest.mark.parametrize("name", LIE)
def test_frame_jacobian_columns_of_slots_are_derivatives_of_the_pose(name):
    """For every coordinate that is also a slot of `q` (hinges, a free base's position),
    the Jacobian's first three rows are the derivative of the frame's origin along it
    (central differences)."""
    rng = np.random.default_rng(zlib.crc32(("liejac" + name).encode()))
    scene, _ = make(name, rng)
    cls = type(scene)
    q = random_configuration(cls, rng)
    frame = cls.frames[-1]
    jac = scene.frame_jacobian(frame, q)
    assert jac.shape == (6, scene.dof)
    h = 1e-6
    checked = 0
    for k, c in enumerate(cls.joints):
        if c not in cls.configuration:
            continue
        s = cls.configuration.index(c)
        dq = np.zeros_like(q)
        dq[s] = h
        d = (scene.frame_pose(frame, q + dq)[:3, 3] - scene.frame_pose(frame, q - dq)[:3, 3]) / (2 * h)
        assert np.allclose(d, jac[:3, k], atol=1e-8), c
        checked += 1
    assert checked >= 3


@pytest.mark.parametrize("name, t_end", [("FreeBody", 2.0), ("Solo12", 0.3), ("Humanoid", 0.1)])
def test_run_equals_rust_bit_for_bit(name, t_end, rust):
    rng = np.random.default_rng(zlib.crc32(("lierun" + name).encode()))
    scene, params = make(name, rng)
    cls = type(scene)
    q0 = random_configuration(cls, rng)
    v0 = rng.uniform(-1.0, 1.0, scene.dof)
    (answer,) = rust.ask([f"run {name} {fmt(list(params.values()))} ; {t_end!r} {fmt(q0)} {fmt(v0)}"])
    assert not answer[0].startswith("error"), answer[0]
    sol = scene.solve(t_end, q0, v0)
    compare(sol, answer)
    assert sol.names == [f"q_{c}" for c in cls.configuration] + [f"v_{c}" for c in cls.joints]
    # The dense output stays on the group: unit quaternions between the steps.
    mid = 0.5 * (sol.t[:-1] + sol.t[1:])
    y = sol.at(mid)
    for s in quaternion_slots(cls):
        assert np.allclose(np.linalg.norm(y[:, s : s + 4], axis=1), 1.0, atol=1e-13)
    assert np.allclose(sol.at(sol.t), sol.y, rtol=0, atol=1e-13)


def test_s10_conserves_energy_and_the_methods_agree():
    """S10 (theory: a free body spun near its intermediate axis turns over, the
    Dzhanibekov effect): kinetic energy ½ vᵀ M v is conserved, and the explicit and the
    stiff Lie-group methods reach the same state."""
    assert filippov.CANONICAL["S10"] == "FreeBody"
    body = filippov.FreeBody(m=1.0, i1=1.0, i2=2.0, i3=3.0)
    q0 = np.zeros(len(body.configuration))
    q0[quaternion_slots(type(body))[0]] = 1.0
    v0 = np.zeros(body.dof)
    v0[3:] = [0.01, 1.0, 0.0]
    v0[:3] = [0.2, -0.1, 0.3]
    sol = body.solve(20.0, q0, v0, rtol=1e-10, atol=1e-12)
    energy = [0.5 * v @ body.mass_matrix(q) @ v for q, v in zip(sol.y[:, :7], sol.y[:, 7:])]
    assert np.ptp(energy) < 1e-8 * energy[0]
    # ω_y turns over: the body flips within 20 s.
    assert sol["v_" + body.joints[4]].min() < -0.9
    stiff = body.solve(20.0, q0, v0, method="lie_sdirk", rtol=1e-9, atol=1e-11, times=[20.0])
    assert np.allclose(stiff.y[-1], sol.y[-1], atol=1e-5)
    fixed = body.solve(20.0, q0, v0, h=1e-2)
    assert np.allclose(fixed.y[-1], sol.y[-1], atol=1e-5)
    assert len(fixed) == 2001


def test_quaternions_and_options_are_checked():
    body = filippov.FreeBody(m=1.0, i1=1.0, i2=2.0, i3=3.0)
    q = np.zeros(7)
    with pytest.raises(ValueError, match=r"quaternion of joint `\w+` \(slots 3–6.*norm 0"):
        body.mass_matrix(q)
    q[3] = 2.0
    with pytest.raises(ValueError, match="norm 2"):
        body.solve(1.0, q)
    q[3] = 1.0
    with pytest.raises(ValueError, match="7 configuration slots"):
        body.forward_dynamics(np.ones(6), np.zeros(6))
    with pytest.raises(ValueError, match="no method `dopri5`.*rkmk5.*lie_sdirk"):
        body.solve(1.0, q, method="dopri5")
    with pytest.raises(TypeError, match="unexpected option `smooth`"):
        body.solve(1.0, q, smooth="rk4")
    with pytest.raises(filippov.SolveError) as e:
        body.solve(1.0, q, rtol=-1.0)
    assert e.value.kind == "InvalidInput"
    assert not hasattr(body, "solve_nonsmooth") and body.elements == []


def test_lie_scenes_pickle_and_tabulate():
    body = filippov.FreeBody(m=1.5, i1=1.0, i2=2.0, i3=2.5)
    again = pickle.loads(pickle.dumps(body))
    assert again.parameters == body.parameters
    q0 = np.array([0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0])
    sol = body.solve(1.0, q0, [0.0, 0.0, 0.0, 0.1, 1.0, 0.2], every=5)
    df = sol.to_pandas()
    assert list(df.columns) == ["t"] + sol.names
    assert "q_" + body.configuration[3] in df
