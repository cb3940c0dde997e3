"""Scenes with contacts (a box on a ramp, a three-legged table): runs of the contact
integrators equal the Rust runs bit for bit, and obey what the theory says of them —
the box slides to rest in its closed-form time and distance, does not creep below the
friction angle, and no run gains energy."""

import zlib

import numpy as np
import pytest

import filippov
from conftest import compare, fmt


def box(rng, phi=None):
    params = dict(
        m=float(rng.uniform(0.5, 2.0)),
        a=float(rng.uniform(0.15, 0.3)),
        b=float(rng.uniform(0.05, 0.15)),
        mu=float(rng.uniform(0.3, 0.8)),
        e=float(rng.uniform(0.0, 0.5)),
        phi=float(rng.uniform(0.0, 0.3)) if phi is None else phi,
        g=9.81,
    )
    return filippov.SlidingBox(**params), params


def resting(p):
    """The box on its ground (tilted by φ): angle φ, centre `b` along the normal."""
    return np.array([-p["b"] * np.sin(p["phi"]), p["b"] * np.cos(p["phi"]), p["phi"]])


def table(rng):
    mu, r = float(rng.uniform(0.2, 0.8)), float(rng.uniform(0.15, 0.4))
    params = dict(
        m=float(rng.uniform(0.5, 5.0)),
        a=float(rng.uniform(0.2, 0.5)),
        c=float(rng.uniform(0.01, 0.05)),
        r=r,
        # Legs short enough that the friction's moment does not tip it over.
        d=float(rng.uniform(0.05, 0.8)) * r / (2.0 * mu),
        mu=mu,
        e=float(rng.uniform(0.0, 0.5)),
        phi=0.0,
        g=9.81,
    )
    return filippov.Table(**params), params


@pytest.mark.parametrize("h", [0.0, 1e-3])
def test_box_runs_equal_rust_bit_for_bit(h, rust):
    rng = np.random.default_rng(zlib.crc32(f"box{h}".encode()))
    scene, p = box(rng)
    speed = float(rng.uniform(0.5, 2.0))
    q0 = resting(p)
    v0 = speed * np.array([np.cos(p["phi"]), np.sin(p["phi"]), 0.0])
    (answer,) = rust.ask([f"contact SlidingBox {fmt(list(p.values()))} ; 1.0 {h!r} {fmt(q0)} {fmt(v0)}"])
    assert not answer[0].startswith("error"), answer[0]
    if h > 0:
        sol = scene.solve_contacts(1.0, q0, v0, method="time_stepping", h=h)
    else:
        sol = scene.solve_contacts(1.0, q0, v0)
    compare(sol, answer)
    assert filippov.SlidingBox.contacts == ["rear", "front"]
    assert "λ_rear.n" in sol.names and "λ_front.x" in sol.names


def test_table_run_equals_rust_bit_for_bit_and_loses_energy(rust):
    rng = np.random.default_rng(11)
    scene, p = table(rng)
    q0 = np.array([0.0, 0.0, p["d"] + 0.02, float(rng.uniform(-1, 1)), 0.0, 0.0])
    v0 = np.array([float(rng.uniform(-1.5, 1.5)), float(rng.uniform(-1.5, 1.5)), 0.0, 2.0, 0.0, 0.0])
    (answer,) = rust.ask([f"contact Table {fmt(list(p.values()))} ; 1.0 0.001 {fmt(q0)} {fmt(v0)}"])
    assert not answer[0].startswith("error"), answer[0]
    sol = scene.solve_contacts(1.0, q0, v0, method="time_stepping", h=1e-3)
    compare(sol, answer)
    # Passivity, from the module's own mass matrix: no step gains energy.
    q, v = sol.y[:, :6], sol.y[:, 6:12]
    energy = 0.5 * np.einsum("ij,ijk,ik->i", v, scene.mass_matrix(q), v) + p["m"] * p["g"] * q[:, 2]
    assert np.all(np.diff(energy) <= 1e-9 * abs(energy[0]))
    assert energy[-1] < energy[0]


def test_box_slides_to_rest_in_closed_form():
    """Level ground, launched at v0: at rest at t = v0 / (μ g) after v0² / (2 μ g)."""
    b = filippov.SlidingBox(m=1.0, a=0.2, b=0.1, mu=0.5, e=0.0, phi=0.0, g=9.81)
    v0 = 2.0
    sol = b.solve_contacts(1.0, [0.0, 0.1, 0.0], [v0, 0.0, 0.0])
    vx = sol["v_x"]
    stop = sol.t[np.argmax(vx == 0.0)]
    assert abs(stop - v0 / (0.5 * 9.81)) < 1e-6
    assert abs(sol["q_x"][-1] - v0 * v0 / (2 * 0.5 * 9.81)) < 1e-6
    assert np.allclose(sol["q_y"], 0.1, atol=1e-12) and np.allclose(sol["q_angle"], 0.0, atol=1e-12)


@pytest.mark.parametrize("method", ["event_driven", "time_stepping"])
def test_box_on_a_ramp_does_not_creep(method):
    """Below the friction angle (tan φ < μ) a box at rest stays where it is."""
    b = filippov.SlidingBox(m=1.0, a=0.2, b=0.1, mu=0.5, e=0.0, phi=0.3, g=9.81)
    q0 = resting(b.parameters)
    extra = {"h": 0.01} if method == "time_stepping" else {}
    sol = b.solve_contacts(100.0, q0, method=method, **extra)
    assert np.allclose(sol.y[:, :3], q0, rtol=0, atol=1e-12)
    assert np.allclose(sol.y[:, 3:6], 0.0, rtol=0, atol=1e-12)


def test_contact_options_are_checked():
    b = filippov.SlidingBox(m=1.0, a=0.2, b=0.1, mu=0.5, e=0.0, phi=0.0, g=9.81)
    with pytest.raises(ValueError, match="Moreau–Jean.*theta"):
        b.solve_contacts(1.0, [0.0, 0.1, 0.0], method="time_stepping", h=1e-3, theta=0.5)
    with pytest.raises(ValueError, match="give it as h="):
        b.solve_contacts(1.0, [0.0, 0.1, 0.0], method="time_stepping")
    with pytest.raises(filippov.SolveError, match="h = -0.001 must be positive") as e:
        b.solve_contacts(1.0, [0.0, 0.1, 0.0], method="time_stepping", h=-1e-3)
    assert e.value.kind == "InvalidInput"
