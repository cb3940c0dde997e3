//! The double pendulum of theory S8 against its closed-form M, C and g.

use filippov::prelude::*;

#[derive(Mechanism)]
#[mechanism(gravity = [0.0, -9.81, 0.0])]
#[body(upper, mass = m1, com = [l1 / 2.0, 0.0, 0.0], inertia = rod(m1, l1))]
#[joint(shoulder: revolute(z), parent = world, child = upper)]
#[body(lower, mass = m2, com = [l2 / 2.0, 0.0, 0.0], inertia = rod(m2, l2))]
#[joint(elbow: revolute(z), parent = upper, child = lower, origin = [l1, 0.0, 0.0])]
struct DoublePendulum {
    m1: f64,
    l1: f64,
    m2: f64,
    l2: f64,
}

const P: DoublePendulum = DoublePendulum { m1: 1.0, l1: 1.0, m2: 0.5, l2: 0.7 };

/// Textbook closed form for two uniform rods hinged at their ends, angles measured from
/// the x axis (gravity along −y): `M`, `C` (Christoffel form) and `g`.
fn closed_form(q: [f64; 2], v: [f64; 2]) -> ([[f64; 2]; 2], [[f64; 2]; 2], [f64; 2]) {
    let DoublePendulum { m1, l1, m2, l2 } = P;
    let (lc1, lc2) = (l1 / 2.0, l2 / 2.0);
    let (i1, i2) = (m1 * l1 * l1 / 12.0, m2 * l2 * l2 / 12.0);
    let c2 = q[1].cos();
    let s2 = q[1].sin();
    let m11 = m1 * lc1 * lc1 + i1 + m2 * (l1 * l1 + lc2 * lc2 + 2.0 * l1 * lc2 * c2) + i2;
    let m12 = m2 * (lc2 * lc2 + l1 * lc2 * c2) + i2;
    let m22 = m2 * lc2 * lc2 + i2;
    let h = -m2 * l1 * lc2 * s2;
    let c = [[h * v[1], h * (v[0] + v[1])], [-h * v[0], 0.0]];
    let gr = 9.81;
    let g1 = (m1 * lc1 + m2 * l1) * gr * q[0].cos() + m2 * lc2 * gr * (q[0] + q[1]).cos();
    let g2 = m2 * lc2 * gr * (q[0] + q[1]).cos();
    ([[m11, m12], [m12, m22]], c, [g1, g2])
}

fn states() -> Vec<([f64; 2], [f64; 2])> {
    // A fixed, spread-out set of states (deterministic, no RNG dependency).
    (0..20)
        .map(|k| {
            let t = k as f64;
            ([(1.3 * t).sin() * 3.0, (0.7 * t + 1.0).cos() * 2.5], [(2.1 * t).cos() * 4.0, (0.4 * t).sin() * 3.0])
        })
        .collect()
}

#[test]
fn mass_coriolis_gravity_match_closed_form() {
    for (q, v) in states() {
        let (m, c, g) = closed_form(q, v);
        let (qs, vs) = (SVector::from(q), SVector::from(v));
        let mg = P.mass_matrix(&qs);
        let cg = P.coriolis_matrix(&qs, &vs);
        let gg = P.gravity(&qs);
        for i in 0..2 {
            for j in 0..2 {
                assert!((mg[(i, j)] - m[i][j]).abs() < 1e-13, "M[{i}{j}] {} vs {}", mg[(i, j)], m[i][j]);
                assert!((cg[(i, j)] - c[i][j]).abs() < 1e-13, "C[{i}{j}] {} vs {}", cg[(i, j)], c[i][j]);
            }
            assert!((gg[i] - g[i]).abs() < 1e-12, "g[{i}] {} vs {}", gg[i], g[i]);
        }
    }
}
