//! The velocity-level contact problem of a time step with Coulomb's isotropic cone
//! (theory §8, "Spatial contacts"): the impulses of contacts that may slide in two
//! directions, on the exact cone `‖P_T‖ ≤ μ P_N`, not a pyramid.
//!
//! With the step's free velocity `v_free` and the operator `W` (`M⁻¹`), each contact
//! `i` has rows `H_i = [w_N, w_T1, w_T2]` (fewer where the mechanism cannot move along a
//! tangent), local velocity `u_i = H_iᵀ v` and impulse `P_i`, and
//! `v = v_free + W Σ H_i P_i`. The laws:
//!
//! - normal (Newton): `u_N + e u_N⁻ ≥ 0`, `P_N ≥ 0`, their product `0`;
//! - tangential (Coulomb): `‖P_T‖ ≤ μ P_N`; `u_T = 0` inside the cone, and at its edge
//!   `P_T = −μ P_N u_T/‖u_T‖`.
//!
//! The solver is non-smooth Gauss–Seidel: contact after contact, the others' impulses
//! held, the contact's own problem (three unknowns) is solved exactly — apart, stuck, or
//! sliding, the sliding direction the root of a function of one angle found to round-off
//! — until the sweep's residual is below the tolerance. The residual is De Saxcé's
//! natural map, in velocity units, relative to the free velocities: `0` exactly where
//! every law holds, so the solver says how far it converged
//! ([`Stats::contact_residual`](crate::Stats::contact_residual)).

use nalgebra::{DMatrix, DVector};

/// One contact that may close in the step, or a friction element on one coordinate.
#[derive(Clone, Debug)]
pub(crate) struct ConeContact {
    /// `w_N`, then the tangent rows (zero, one or two); a friction element's one row.
    pub rows: Vec<DVector<f64>>,
    /// `γ`: the normal law is `u_N ≥ γ` (`γ = −e u_N⁻`).
    pub gamma: f64,
    /// Friction coefficient.
    pub mu: f64,
    /// A friction element instead of a contact: its row's impulse is bounded, not
    /// unilateral.
    pub friction: Option<Friction>,
}

/// The law of a friction element over one step, on its row's impulse `P` and velocity
/// `u`: stuck (`u = 0`) while `|P| ≤ stick`; slipping, `P = −sgn(u) (slip + damping |u|)`
/// (Coulomb: `slip = stick = h f_crit`, no damping; static and kinetic friction:
/// `stick = h f_static`, `slip = h f_kinetic`; linear Bingham: `damping = h η`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Friction {
    pub stick: f64,
    pub slip: f64,
    pub damping: f64,
}

/// The impulses and velocity after the step.
#[derive(Clone, Debug)]
pub(crate) struct ConeOutcome {
    /// Per contact: `[P_N, P_T…]`.
    pub impulses: Vec<Vec<f64>>,
    /// Per contact: `[u_N, u_T…]` after the step.
    pub local: Vec<Vec<f64>>,
    /// `v` after the step.
    pub velocity: DVector<f64>,
    /// Gauss–Seidel sweeps taken.
    pub sweeps: usize,
    /// The natural-map residual reached (relative).
    pub residual: f64,
}

/// The local problem could not be solved: its normal row gains no velocity from its own
/// impulse in the sliding direction (friction drives it into the plane), so it has no
/// solution or several.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct NoLocalSolution {
    /// Index into the contacts.
    pub contact: usize,
}

/// Samples of the sliding angle before the root is refined.
const ANGLE_SAMPLES: usize = 96;

/// Solves the contact problem (module documentation), starting from `warm` impulses
/// (one per contact, or empty), until the relative residual is at most `tolerance` or
/// after `max_sweeps` sweeps.
pub(crate) fn solve(
    w: &DMatrix<f64>,
    v_free: &DVector<f64>,
    contacts: &[ConeContact],
    warm: &[Vec<f64>],
    tolerance: f64,
    max_sweeps: usize,
) -> Result<ConeOutcome, NoLocalSolution> {
    let k = contacts.len();
    // W H_i and the local Delassus blocks H_iᵀ W H_i.
    let wh: Vec<Vec<DVector<f64>>> = contacts
        .iter()
        .map(|c| c.rows.iter().map(|r| w * r).collect())
        .collect();
    let blocks: Vec<DMatrix<f64>> = contacts
        .iter()
        .zip(&wh)
        .map(|(c, whi)| {
            let d = c.rows.len();
            DMatrix::from_fn(d, d, |a, b| c.rows[a].dot(&whi[b]))
        })
        .collect();
    let mut impulses: Vec<Vec<f64>> = contacts
        .iter()
        .enumerate()
        .map(|(i, c)| match warm.get(i) {
            Some(p) if p.len() == c.rows.len() && p.iter().all(|x| x.is_finite()) => p.clone(),
            _ => vec![0.0; c.rows.len()],
        })
        .collect();
    let mut v = v_free.clone();
    for i in 0..k {
        for (col, p) in wh[i].iter().zip(&impulses[i]) {
            v.axpy(*p, col, 1.0);
        }
    }
    let scale = contacts
        .iter()
        .flat_map(|c| c.rows.iter().map(|r| r.dot(v_free).abs()))
        .chain(contacts.iter().map(|c| c.gamma.abs()))
        .fold(f64::MIN_POSITIVE, f64::max);
    let local = |v: &DVector<f64>, i: usize| -> Vec<f64> {
        let c = &contacts[i];
        let mut u: Vec<f64> = c.rows.iter().map(|r| r.dot(v)).collect();
        if c.friction.is_none() {
            u[0] -= c.gamma;
        }
        u
    };
    // The local problem's solution from its free velocity `c`.
    let local_law = |i: usize, c: &[f64]| -> Option<Vec<f64>> {
        match contacts[i].friction {
            Some(f) => Some(vec![friction_solve(blocks[i][(0, 0)], c[0], f)]),
            None => local_solve(&blocks[i], c, contacts[i].mu),
        }
    };
    let mut sweeps = 0;
    let mut residual = f64::INFINITY;
    while sweeps < max_sweeps {
        sweeps += 1;
        for i in 0..k {
            // The local free velocity: the others' impulses held, this one's removed.
            let mut c = local(&v, i);
            let a = &blocks[i];
            for (r, cr) in c.iter_mut().enumerate() {
                *cr -= (0..a.ncols())
                    .map(|s| a[(r, s)] * impulses[i][s])
                    .sum::<f64>();
            }
            let p = local_law(i, &c).ok_or(NoLocalSolution { contact: i })?;
            for (s, col) in wh[i].iter().enumerate() {
                let dp = p[s] - impulses[i][s];
                if dp != 0.0 {
                    v.axpy(dp, col, 1.0);
                }
            }
            impulses[i] = p;
        }
        residual = (0..k)
            .map(|i| match contacts[i].friction {
                // A friction element: how far its law would move its impulse, in
                // velocity units.
                Some(f) => {
                    let a = blocks[i][(0, 0)];
                    let c = local(&v, i)[0] - a * impulses[i][0];
                    (friction_solve(a, c, f) - impulses[i][0]).abs() * a
                }
                None => natural_map(&impulses[i], &local(&v, i), contacts[i].mu, &blocks[i]),
            })
            .fold(0.0, f64::max)
            / scale;
        if residual <= tolerance {
            break;
        }
    }
    let local_velocities = (0..k).map(|i| local(&v, i)).collect();
    Ok(ConeOutcome {
        impulses,
        local: local_velocities,
        velocity: v,
        sweeps,
        residual,
    })
}

/// A friction element's impulse for its free velocity `c` and Delassus entry `a`
/// (`u = a P + c`): stuck if `−c/a` is within the stick bound, else slipping the way `c`
/// goes, `u = (c − a s slip) / (1 + a damping)`.
fn friction_solve(a: f64, c: f64, f: Friction) -> f64 {
    let stuck = -c / a;
    if stuck.abs() <= f.stick {
        return stuck;
    }
    let s = c.signum();
    let u = (c - a * s * f.slip) / (1.0 + a * f.damping);
    -s * (f.slip + f.damping * u.abs())
}

/// De Saxcé's natural map `P − proj_K(P − ρ ũ)` with `ũ = u + (μ‖u_T‖, 0, 0)`, over `ρ`
/// (velocity units), `ρ` the inverse of the block's largest diagonal entry: its norm is
/// `0` exactly where the contact's laws hold.
fn natural_map(p: &[f64], u: &[f64], mu: f64, block: &DMatrix<f64>) -> f64 {
    let rho = 1.0 / block.diagonal().amax().max(f64::MIN_POSITIVE);
    let slip = u[1..].iter().map(|x| x * x).sum::<f64>().sqrt();
    let mut y: Vec<f64> = p.iter().zip(u).map(|(pi, ui)| pi - rho * ui).collect();
    y[0] -= rho * mu * slip;
    let projected = project_on_cone(&y, mu);
    p.iter()
        .zip(&projected)
        .map(|(a, b)| (a - b) * (a - b))
        .sum::<f64>()
        .sqrt()
        / rho
}

/// The Euclidean projection of `(y_N, y_T)` on the cone `‖P_T‖ ≤ μ P_N`.
fn project_on_cone(y: &[f64], mu: f64) -> Vec<f64> {
    let (n, t) = (y[0], y[1..].iter().map(|x| x * x).sum::<f64>().sqrt());
    if t <= mu * n {
        return y.to_vec();
    }
    if mu * t <= -n {
        return vec![0.0; y.len()];
    }
    let pn = (n + mu * t) / (1.0 + mu * mu);
    let mut out = vec![pn; 1];
    out.extend(y[1..].iter().map(|x| x / t * mu * pn));
    out
}

/// The local problem `u = A P + c` of one contact, solved exactly: apart (`P = 0`),
/// stuck (`u = 0` with `P` in the cone), or sliding. `None` where no sliding direction
/// gives a positive normal impulse.
fn local_solve(a: &DMatrix<f64>, c: &[f64], mu: f64) -> Option<Vec<f64>> {
    let d = c.len();
    if c[0] >= 0.0 {
        return Some(vec![0.0; d]);
    }
    if mu == 0.0 || d == 1 {
        let mut p = vec![0.0; d];
        p[0] = -c[0] / a[(0, 0)];
        return (p[0] > 0.0).then_some(p);
    }
    // Stuck: A P = −c.
    let rhs = DVector::from_iterator(d, c.iter().map(|x| -x));
    if let Some(p) = a.clone().lu().solve(&rhs) {
        let pt = p.rows(1, d - 1).norm();
        if p[0] > 0.0 && pt <= mu * p[0] {
            return Some(p.iter().copied().collect());
        }
    }
    // Sliding along unit `s` (in the tangent rows): P = P_N (1, −μ s),
    // P_N = −c_N / (A_NN − μ A_NT s), and u_T = P_N (A_TN − μ A_TT s) + c_T ∥ s.
    let at = |s: &[f64]| -> Option<(f64, Vec<f64>)> {
        let den = a[(0, 0)] - mu * (1..d).map(|j| a[(0, j)] * s[j - 1]).sum::<f64>();
        if den <= 0.0 {
            return None;
        }
        let pn = -c[0] / den;
        let ut = (1..d)
            .map(|r| {
                pn * (a[(r, 0)] - mu * (1..d).map(|j| a[(r, j)] * s[j - 1]).sum::<f64>()) + c[r]
            })
            .collect();
        Some((pn, ut))
    };
    let impulse = |pn: f64, s: &[f64]| -> Vec<f64> {
        std::iter::once(pn)
            .chain(s.iter().map(|x| -mu * pn * x))
            .collect()
    };
    if d == 2 {
        for s in [1.0, -1.0] {
            if let Some((pn, ut)) = at(&[s]) {
                if ut[0] * s >= 0.0 {
                    return Some(impulse(pn, &[s]));
                }
            }
        }
        return None;
    }
    // Two tangent rows: the sliding angle θ, s = (cos θ, sin θ), is a root of
    // f(θ) = s × u_T(θ) with s · u_T ≥ 0 — bracketed by sampling, refined by bisection.
    let dir = |theta: f64| [theta.cos(), theta.sin()];
    let f = |theta: f64| -> Option<(f64, f64, f64)> {
        let s = dir(theta);
        at(&s).map(|(pn, ut)| (s[0] * ut[1] - s[1] * ut[0], s[0] * ut[0] + s[1] * ut[1], pn))
    };
    let step = std::f64::consts::TAU / ANGLE_SAMPLES as f64;
    let mut best: Option<(f64, f64)> = None; // (θ, P_N)
    let mut prev = (0.0, f(0.0));
    for j in 1..=ANGLE_SAMPLES {
        let theta = j as f64 * step;
        let cur = f(theta);
        if let (Some((f0, _, _)), Some((f1, _, _))) = (prev.1, cur) {
            if f0 == 0.0 || f0.signum() != f1.signum() {
                let (mut lo, mut hi, mut flo) = (prev.0, theta, f0);
                if f0 != 0.0 {
                    for _ in 0..80 {
                        let mid = 0.5 * (lo + hi);
                        if mid <= lo || mid >= hi {
                            break;
                        }
                        match f(mid) {
                            Some((fm, _, _)) if fm.signum() == flo.signum() && fm != 0.0 => {
                                (lo, flo) = (mid, fm);
                            }
                            Some(_) => hi = mid,
                            None => break,
                        }
                    }
                }
                let root = if f0 == 0.0 { prev.0 } else { 0.5 * (lo + hi) };
                if let Some((_, along, pn)) = f(root) {
                    if along >= 0.0 && best.is_none_or(|(_, b)| pn < b) {
                        best = Some((root, pn));
                    }
                }
            }
        }
        prev = (theta, cur);
    }
    best.map(|(theta, pn)| impulse(pn, &dir(theta)))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A point mass `m` on a plane with normal `z`: `W = I/m`, rows the axes.
    fn point(m: f64, mu: f64) -> (DMatrix<f64>, ConeContact) {
        let rows = (0..3)
            .map(|i| DVector::from_fn(3, |j, _| if i == j { 1.0 } else { 0.0 }))
            .collect::<Vec<_>>();
        let rows = vec![rows[2].clone(), rows[0].clone(), rows[1].clone()];
        (
            DMatrix::identity(3, 3) / m,
            ConeContact {
                rows,
                gamma: 0.0,
                mu,
                friction: None,
            },
        )
    }

    #[test]
    fn a_sliding_point_loses_speed_along_its_velocity_in_every_direction() {
        // The isotropic cone: the friction impulse opposes the velocity whatever its
        // direction (a pyramid would not).
        let (m, mu, g, h) = (2.0, 0.4, 9.81, 1e-3);
        let (w, c) = point(m, mu);
        for k in 0..16 {
            let theta = k as f64 * 0.41;
            let speed = 1.5;
            let v_free =
                DVector::from_row_slice(&[speed * theta.cos(), speed * theta.sin(), -g * h]);
            let out = solve(&w, &v_free, std::slice::from_ref(&c), &[], 1e-14, 50).unwrap();
            let v = &out.velocity;
            assert!(v[2].abs() < 1e-15, "{v}");
            let lost = speed - (v[0] * v[0] + v[1] * v[1]).sqrt();
            assert!((lost - mu * g * h).abs() < 1e-14, "{lost}");
            assert!((v[0] * theta.sin() - v[1] * theta.cos()).abs() < 1e-14);
            assert!(out.residual < 1e-14);
        }
    }

    #[test]
    fn a_slow_point_sticks_and_a_lifted_one_gets_no_impulse() {
        let (m, mu, g, h) = (1.0, 0.5, 9.81, 1e-2);
        let (w, c) = point(m, mu);
        let slow = DVector::from_row_slice(&[0.3 * mu * g * h, 0.2 * mu * g * h, -g * h]);
        let out = solve(&w, &slow, std::slice::from_ref(&c), &[], 1e-14, 50).unwrap();
        assert!(out.velocity.amax() < 1e-16, "{}", out.velocity);
        let up = DVector::from_row_slice(&[1.0, 0.0, 0.5]);
        let out = solve(&w, &up, std::slice::from_ref(&c), &[], 1e-14, 50).unwrap();
        assert_eq!(out.impulses[0], vec![0.0; 3]);
    }

    #[test]
    fn projection_on_the_cone() {
        let mu = 0.5;
        assert_eq!(project_on_cone(&[1.0, 0.2, 0.1], mu), vec![1.0, 0.2, 0.1]);
        assert_eq!(project_on_cone(&[-1.0, 0.1, 0.0], mu), vec![0.0; 3]);
        let p = project_on_cone(&[1.0, 3.0, 4.0], mu);
        let t = (p[1] * p[1] + p[2] * p[2]).sqrt();
        assert!((t - mu * p[0]).abs() < 1e-15);
        // The difference is normal to the cone at p.
        let d = [1.0 - p[0], 3.0 - p[1], 4.0 - p[2]];
        assert!((d[0] * p[0] + d[1] * p[1] + d[2] * p[2]).abs() < 1e-14);
    }
}
