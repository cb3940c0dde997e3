//! The contact forces of planar contacts at one instant: which closed contacts stay
//! closed, which stuck ones stay stuck, as a linear complementarity problem (Pfeiffer &
//! Glocker, *Multibody Dynamics with Unilateral Contacts*, 1996, §7; theory §8).
//!
//! Every contact here is closed (`g_N = 0`, `ġ_N = 0`); its tangential velocity is zero
//! (stuck) or has a sign (sliding). With the free accelerations `a₀` and the operator
//! `W` that maps a generalised force to its accelerations (`M⁻¹`, or its projection
//! onto a closed mechanism's loops), the accelerations are
//!
//! ```text
//! v̇ = a₀ + W (Σ_closed w_N λ_N + Σ_stuck w_T λ_T − Σ_sliding μ s w_T λ_N)
//! ```
//!
//! and the contacts' accelerations `g̈ = wᵀ v̇ − γ`. The laws:
//!
//! - normal: `g̈_N ≥ 0`, `λ_N ≥ 0`, `g̈_N λ_N = 0` (stays, or lifts off with no force);
//! - stuck: `|λ_T| ≤ μ λ_N`, and `g̈_T = 0` inside the cone, `g̈_T` opposing the force at
//!   its edge. With `λ_R = μ λ_N + λ_T ≥ 0`, `λ_L = μ λ_N − λ_T ≥ 0` and
//!   `g̈_T = g̈_T⁺ − g̈_T⁻` (both `≥ 0`), this is `g̈_T⁺ ⊥ λ_R`, `g̈_T⁻ ⊥ λ_L`.
//!
//! One LCP: `z = [λ_N; λ_R; g̈_T⁻]`, `w = [g̈_N; g̈_T⁺; λ_L] = A z + b`, solved by
//! complementary pivoting. Where sliding contacts' friction pulls them into the ground
//! strongly enough (Painlevé's paradox) their block of `A` — `g̈_N` against their own
//! `λ_N` — is not a P-matrix, and some states have no consistent mode or several:
//! [`ContactError::Painleve`] says so rather than pick one.

use nalgebra::{DMatrix, DVector};

use crate::numerics::lcp::{self, LcpError};

/// One closed contact, its rows and its law.
#[derive(Clone, Debug)]
pub(crate) struct Closed {
    /// `w_N`: the normal velocity is `w_Nᵀ v`.
    pub normal: DVector<f64>,
    /// `γ_N`: `g̈_N = w_Nᵀ v̇ − γ_N`.
    pub gamma_n: f64,
    /// `w_T` and `γ_T` along the plane's tangent.
    pub tangent: DVector<f64>,
    pub gamma_t: f64,
    /// Friction coefficient.
    pub mu: f64,
    /// `None`: stuck (tangential velocity zero); `Some(s)`: sliding with velocity sign `s`.
    pub sliding: Option<f64>,
}

/// What the contacts do next.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Outcome {
    /// `λ_N` per contact (`0` where it lifts off).
    pub normal: Vec<f64>,
    /// `λ_T` per contact (`−μ s λ_N` when sliding).
    pub tangent: Vec<f64>,
    /// `g̈_N` per contact: `> 0` where it lifts off.
    pub normal_acceleration: Vec<f64>,
    /// `g̈_T` per contact: for a stuck contact, nonzero where it breaks away (its sign
    /// the new sliding direction).
    pub tangent_acceleration: Vec<f64>,
    /// `v̇`.
    pub acceleration: DVector<f64>,
}

#[derive(Clone, Debug, PartialEq)]
pub(crate) enum ContactError {
    /// The problem's matrix is not a P-matrix: with these frictions and directions the
    /// contact problem has no solution or several for some forces (Painlevé).
    /// `solved`: whether a solution was found for these forces anyway.
    Painleve { solved: bool },
    /// No consistent forces for these (a dependent set of contacts).
    NoSolution,
}

/// The contact forces of `contacts` (all closed) with free accelerations `a0` and
/// operator `w` (see the module documentation).
pub(crate) fn solve(
    w: &DMatrix<f64>,
    a0: &DVector<f64>,
    contacts: &[Closed],
) -> Result<Outcome, ContactError> {
    let k = contacts.len();
    let stuck: Vec<usize> = (0..k)
        .filter(|&i| contacts[i].sliding.is_none() && contacts[i].mu > 0.0)
        .collect();
    let h = stuck.len();
    // Each contact's force direction per unit λ_N: the normal, less the sliding friction.
    let normal_force: Vec<DVector<f64>> = contacts
        .iter()
        .map(|c| match c.sliding {
            Some(s) => &c.normal - &c.tangent * (c.mu * s),
            None => c.normal.clone(),
        })
        .collect();
    // Accelerations per unit force: W times each direction.
    let wn: Vec<DVector<f64>> = normal_force.iter().map(|f| w * f).collect();
    let wt: Vec<DVector<f64>> = stuck.iter().map(|&i| w * &contacts[i].tangent).collect();
    let size = k + 2 * h;
    let mut a = DMatrix::<f64>::zeros(size, size);
    let mut b = DVector::<f64>::zeros(size);
    // The effect of z on v̇: λ_N through wn less μ_i λ_N(i) through wt for stuck i (since
    // λ_T = λ_R − μ λ_N), λ_R through wt.
    let mut effect: Vec<DVector<f64>> = wn.clone();
    for (j, &i) in stuck.iter().enumerate() {
        effect[i] -= &wt[j] * contacts[i].mu;
    }
    for (r, c) in contacts.iter().enumerate() {
        // g̈_N row.
        for col in 0..k {
            a[(r, col)] = c.normal.dot(&effect[col]);
        }
        for (j, _) in stuck.iter().enumerate() {
            a[(r, k + j)] = c.normal.dot(&wt[j]);
        }
        b[r] = c.normal.dot(a0) - c.gamma_n;
    }
    for (j, &i) in stuck.iter().enumerate() {
        let c = &contacts[i];
        // g̈_T⁺ = g̈_T + g̈_T⁻.
        let row = k + j;
        for col in 0..k {
            a[(row, col)] = c.tangent.dot(&effect[col]);
        }
        for (jj, _) in stuck.iter().enumerate() {
            a[(row, k + jj)] = c.tangent.dot(&wt[jj]);
        }
        a[(row, k + h + j)] = 1.0;
        b[row] = c.tangent.dot(a0) - c.gamma_t;
        // λ_L = 2 μ λ_N − λ_R.
        let row = k + h + j;
        a[(row, i)] = 2.0 * c.mu;
        a[(row, k + j)] = -1.0;
    }
    // Painlevé: the sliding contacts' own block, `g̈_N` against their `λ_N` (friction
    // included), must be a P-matrix, or some forces give no consistent mode or several.
    let sliding: Vec<usize> = (0..k).filter(|&i| contacts[i].sliding.is_some()).collect();
    let block = DMatrix::from_fn(sliding.len(), sliding.len(), |r, c| {
        a[(sliding[r], sliding[c])]
    });
    let well_posed = sliding.is_empty() || lcp::is_p_matrix(&block);
    let sol = match lcp::solve(&a, &b) {
        Ok(s) => s,
        Err(LcpError::NoSolution) if !well_posed => {
            return Err(ContactError::Painleve { solved: false });
        }
        // Redundant contacts with friction make a problem that complementary pivoting
        // may end on a ray for although it has solutions: a few contacts' modes are
        // then enumerated.
        Err(_) => return enumerate(w, a0, contacts).ok_or(ContactError::NoSolution),
    };
    if !well_posed {
        return Err(ContactError::Painleve { solved: true });
    }
    let z = &sol.z;
    let mut normal = vec![0.0; k];
    let mut tangent = vec![0.0; k];
    let mut acc = a0.clone();
    for i in 0..k {
        normal[i] = z[i];
        acc += &wn[i] * z[i];
        if let Some(s) = contacts[i].sliding {
            tangent[i] = -contacts[i].mu * s * z[i];
        }
    }
    for (j, &i) in stuck.iter().enumerate() {
        tangent[i] = z[k + j] - contacts[i].mu * z[i];
        acc += &wt[j] * tangent[i];
    }
    let normal_acceleration = contacts
        .iter()
        .map(|c| c.normal.dot(&acc) - c.gamma_n)
        .collect();
    let tangent_acceleration = contacts
        .iter()
        .map(|c| c.tangent.dot(&acc) - c.gamma_t)
        .collect();
    Ok(Outcome {
        normal,
        tangent,
        normal_acceleration,
        tangent_acceleration,
        acceleration: acc,
    })
}

/// Most contacts whose modes [`enumerate`] tries (`4ᵏ` assignments).
const ENUMERATE_MAX: usize = 6;

/// A solution by trying the contacts' modes (stuck, sliding either way, open), those
/// that keep more contacts stuck first: each assignment's equalities solved (least norm
/// where redundant) and checked against every law. `None` if none fits.
fn enumerate(w: &DMatrix<f64>, a0: &DVector<f64>, contacts: &[Closed]) -> Option<Outcome> {
    let k = contacts.len();
    if k > ENUMERATE_MAX {
        return None;
    }
    // Per contact: 0 stuck, 1 slides +, 2 slides −, 3 open (a sliding one keeps its way).
    let mut assignments: Vec<Vec<u8>> = (0..4usize.pow(k as u32))
        .map(|mut code| {
            (0..k)
                .map(|_| {
                    let m = (code % 4) as u8;
                    code /= 4;
                    m
                })
                .collect()
        })
        .filter(|m: &Vec<u8>| {
            m.iter()
                .zip(contacts)
                .all(|(&mode, c)| match (mode, c.sliding) {
                    (0, Some(_)) => false,
                    (1, Some(s)) => s > 0.0,
                    (2, Some(s)) => s < 0.0,
                    (0..=2, None) => c.mu > 0.0,
                    _ => true,
                })
        })
        .collect();
    assignments.sort_by_key(|m| m.iter().map(|&x| x as usize).sum::<usize>());
    for m in assignments {
        // Unknowns: λ_N of every closed contact, λ_T of the stuck ones.
        let mut dirs: Vec<DVector<f64>> = Vec::new();
        let mut rows: Vec<(DVector<f64>, f64)> = Vec::new();
        let mut which: Vec<(usize, bool)> = Vec::new();
        for (i, c) in contacts.iter().enumerate() {
            match m[i] {
                3 => {}
                0 => {
                    dirs.push(c.normal.clone());
                    rows.push((c.normal.clone(), c.gamma_n));
                    which.push((i, false));
                    dirs.push(c.tangent.clone());
                    rows.push((c.tangent.clone(), c.gamma_t));
                    which.push((i, true));
                }
                mode => {
                    let s = if mode == 1 { 1.0 } else { -1.0 };
                    dirs.push(&c.normal - &c.tangent * (c.mu * s));
                    rows.push((c.normal.clone(), c.gamma_n));
                    which.push((i, false));
                }
            }
        }
        let r = rows.len();
        let effect: Vec<DVector<f64>> = dirs.iter().map(|d| w * d).collect();
        let lambda = if r == 0 {
            DVector::zeros(0)
        } else {
            let lhs = DMatrix::from_fn(r, r, |i, j| rows[i].0.dot(&effect[j]));
            let rhs = DVector::from_fn(r, |i, _| rows[i].1 - rows[i].0.dot(a0));
            match lhs
                .clone()
                .svd(true, true)
                .solve(&rhs, 1e-12 * lhs.amax().max(f64::MIN_POSITIVE))
            {
                Ok(x) => x,
                Err(_) => continue,
            }
        };
        let mut acc = a0.clone();
        for j in 0..r {
            acc += &effect[j] * lambda[j];
        }
        // Tolerances in each quantity's own units: the contacts' accelerations against
        // the largest of the free one and the forces' effects on them, the forces
        // against the largest force (the operator's entries mix units: angles and
        // lengths, masses and inertias).
        let a_scale = contacts
            .iter()
            .flat_map(|c| [&c.normal, &c.tangent])
            .map(|row| {
                (0..r).fold(row.dot(a0).abs(), |m, j| {
                    m.max((row.dot(&effect[j]) * lambda[j]).abs())
                })
            })
            .fold(f64::MIN_POSITIVE, f64::max);
        let tol = 1e-9 * a_scale;
        let f_tol = 1e-9 * lambda.amax();
        // The equalities hold (redundant rows consistent).
        if rows.iter().any(|(row, g)| (row.dot(&acc) - g).abs() > tol) {
            continue;
        }
        let mut normal = vec![0.0; k];
        let mut tangent = vec![0.0; k];
        for (j, &(i, tangential)) in which.iter().enumerate() {
            if tangential {
                tangent[i] = lambda[j];
            } else {
                normal[i] = lambda[j];
                if m[i] == 1 || m[i] == 2 {
                    let s = if m[i] == 1 { 1.0 } else { -1.0 };
                    tangent[i] = -contacts[i].mu * s * lambda[j];
                }
            }
        }
        let normal_acceleration: Vec<f64> = contacts
            .iter()
            .map(|c| c.normal.dot(&acc) - c.gamma_n)
            .collect();
        let tangent_acceleration: Vec<f64> = contacts
            .iter()
            .map(|c| c.tangent.dot(&acc) - c.gamma_t)
            .collect();
        let fits = (0..k).all(|i| match m[i] {
            3 => normal_acceleration[i] >= -tol,
            0 => normal[i] >= -f_tol && tangent[i].abs() <= contacts[i].mu * normal[i] + f_tol,
            1 => normal[i] >= -f_tol && tangent_acceleration[i] >= -tol,
            _ => normal[i] >= -f_tol && tangent_acceleration[i] <= tol,
        });
        if fits && acc.iter().all(|x| x.is_finite()) {
            return Some(Outcome {
                normal,
                tangent,
                normal_acceleration,
                tangent_acceleration,
                acceleration: acc,
            });
        }
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    const G: f64 = 9.81;

    /// A point of a planar body with coordinates (x, y, θ) at body offset `r` (rotated by
    /// θ), against a line with unit normal `n` and tangent `t`: its rows `[n; r × n]`.
    fn rows(theta: f64, r: [f64; 2], n: [f64; 2], t: [f64; 2]) -> (DVector<f64>, DVector<f64>) {
        let (s, c) = theta.sin_cos();
        let rw = [c * r[0] - s * r[1], s * r[0] + c * r[1]];
        let cross = |d: [f64; 2]| rw[0] * d[1] - rw[1] * d[0];
        (
            DVector::from_row_slice(&[n[0], n[1], cross(n)]),
            DVector::from_row_slice(&[t[0], t[1], cross(t)]),
        )
    }

    /// A box of half-sizes (a, b) resting with its bottom on a line at angle φ, both
    /// corners closed; `sliding` gives both corners' tangential velocity sign.
    fn boxed(
        phi: f64,
        mu: f64,
        sliding: Option<f64>,
    ) -> (DMatrix<f64>, DVector<f64>, Vec<Closed>, [f64; 3]) {
        let (m, a, b) = (2.0, 0.3, 0.2);
        let inertia = m * ((2.0 * a) * (2.0 * a) + (2.0 * b) * (2.0 * b)) / 12.0;
        let w =
            DMatrix::from_diagonal(&DVector::from_row_slice(&[1.0 / m, 1.0 / m, 1.0 / inertia]));
        let a0 = DVector::from_row_slice(&[0.0, -G, 0.0]);
        let (n, t) = ([-phi.sin(), phi.cos()], [phi.cos(), phi.sin()]);
        let contacts = [[-a, -b], [a, -b]]
            .map(|r| {
                let (wn, wt) = rows(phi, r, n, t);
                Closed {
                    normal: wn,
                    gamma_n: 0.0,
                    tangent: wt,
                    gamma_t: 0.0,
                    mu,
                    sliding,
                }
            })
            .to_vec();
        (w, a0, contacts, [m, a, b])
    }

    #[test]
    fn box_on_an_incline_below_its_friction_angle_stays() {
        for phi in [0.0, 0.1, 0.3, 0.45] {
            let mu = 0.5; // friction angle atan(0.5) = 0.4636
            let (w, a0, contacts, [m, a, b]) = boxed(phi, mu, None);
            let out = solve(&w, &a0, &contacts).expect("well posed");
            assert!(
                out.acceleration.amax() < 1e-12,
                "{phi}: {}",
                out.acceleration
            );
            let (n_sum, t_sum) = (
                out.normal[0] + out.normal[1],
                out.tangent[0] + out.tangent[1],
            );
            assert!((n_sum - m * G * phi.cos()).abs() < 1e-12, "{phi}");
            assert!((t_sum - m * G * phi.sin()).abs() < 1e-12, "{phi}");
            // No rotation: a (λ_front − λ_rear) + b Σλ_T = 0 (front = up the slope).
            let split = out.normal[1] - out.normal[0];
            assert!(
                (split + b / a * m * G * phi.sin()).abs() < 1e-12,
                "{phi}: {split}"
            );
            for i in 0..2 {
                assert!(out.tangent[i].abs() <= mu * out.normal[i] + 1e-12);
            }
        }
    }

    #[test]
    fn box_on_an_incline_above_its_friction_angle_breaks_away() {
        let (phi, mu) = (0.6, 0.5);
        let (w, a0, contacts, [m, _, _]) = boxed(phi, mu, None);
        let out = solve(&w, &a0, &contacts).expect("well posed");
        // Down the slope at g (sin φ − μ cos φ), friction at the cone's edge up the slope.
        let expected = -G * (phi.sin() - mu * phi.cos());
        for i in 0..2 {
            assert!(
                (out.tangent_acceleration[i] - expected).abs() < 1e-12,
                "{:?}",
                out.tangent_acceleration
            );
            assert!((out.tangent[i] - mu * out.normal[i]).abs() < 1e-12);
            assert!(out.normal_acceleration[i].abs() < 1e-12);
        }
        assert!((out.normal[0] + out.normal[1] - m * G * phi.cos()).abs() < 1e-12);
    }

    #[test]
    fn sliding_box_loads_its_leading_corner() {
        // Level ground, sliding towards +x: decelerates at μ g without turning, the leading
        // corner carrying μ b m g / a more than the trailing one.
        let mu = 0.4;
        let (w, a0, contacts, [m, a, b]) = boxed(0.0, mu, Some(1.0));
        let out = solve(&w, &a0, &contacts).expect("well posed");
        assert!(
            (out.acceleration[0] + mu * G).abs() < 1e-12,
            "{}",
            out.acceleration
        );
        assert!(out.acceleration[1].abs() < 1e-12 && out.acceleration[2].abs() < 1e-12);
        assert!((out.normal[1] - out.normal[0] - mu * b * m * G / a).abs() < 1e-12);
        assert!((out.normal[0] + out.normal[1] - m * G).abs() < 1e-12);
    }

    #[test]
    fn pulled_up_box_lifts_off() {
        let (w, _, contacts, _) = boxed(0.0, 0.5, None);
        let a0 = DVector::from_row_slice(&[0.0, 1.0, 0.0]);
        let out = solve(&w, &a0, &contacts).expect("well posed");
        assert_eq!(out.normal, vec![0.0, 0.0]);
        assert!(
            out.normal_acceleration
                .iter()
                .all(|&x| (x - 1.0).abs() < 1e-12)
        );
    }

    /// Painlevé's rod: a uniform rod of half-length l at angle θ, its lower end sliding
    /// (velocity sign s = −1, towards the rod's foot). `g̈_N` per unit `λ_N` is
    /// `(1 + 3 cos²θ − 3 μ sin θ cos θ) / m`: negative above
    /// `μ_P = (1 + 3 cos²θ) / (3 sin θ cos θ)`, where the problem has no solution or two.
    #[test]
    fn painleve_is_named_above_its_threshold_and_not_below() {
        let (m, l) = (1.0, 0.5);
        let w = DMatrix::from_diagonal(&DVector::from_row_slice(&[
            1.0 / m,
            1.0 / m,
            3.0 / (m * l * l),
        ]));
        let a0 = DVector::from_row_slice(&[0.0, -G, 0.0]);
        for theta in [0.3f64, 0.5, 0.8, 1.1] {
            let (s, c) = theta.sin_cos();
            let threshold = (1.0 + 3.0 * c * c) / (3.0 * s * c);
            let contact = |mu: f64| Closed {
                normal: DVector::from_row_slice(&[0.0, 1.0, -l * c]),
                gamma_n: 0.0,
                tangent: DVector::from_row_slice(&[1.0, 0.0, l * s]),
                gamma_t: 0.0,
                mu,
                sliding: Some(-1.0),
            };
            let below = solve(&w, &a0, &[contact(threshold * 0.99)]);
            assert!(below.is_ok(), "θ = {theta}: {below:?}");
            let above = solve(&w, &a0, &[contact(threshold * 1.01)]);
            assert!(
                matches!(above, Err(ContactError::Painleve { .. })),
                "θ = {theta}: {above:?}"
            );
        }
    }

    /// A stuck contact's laws at random, badly scaled states: coordinates of mixed
    /// units (masses from 1e-3 to 1e3 along them, rows of lengths from 1e-3 to 1), free
    /// accelerations from 1e-4 to 1e2, half of them with a normal part from 1e-10 to
    /// 1e-3 of the tangential (a contact about to lift off, or barely pressed). Each outcome must keep the laws in its own units (forces against
    /// the largest force, accelerations against the free one): the complementarity
    /// problem's pivots and the fallback's checks once took a slide for a stick there
    /// (the woodpecker's sleeve held with 3.5× its friction cone).
    #[test]
    fn a_stuck_contact_keeps_its_laws_at_any_scale() {
        let mut seed = 11u64;
        let mut uniform = |lo: f64, hi: f64| {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            lo + (hi - lo) * ((seed >> 11) as f64 / (1u64 << 53) as f64)
        };
        let mut checked = 0;
        for trial in 0..600 {
            let a = DMatrix::from_fn(3, 3, |_, _| uniform(-1.0, 1.0));
            let d =
                DMatrix::from_diagonal(&DVector::from_fn(3, |_, _| 10f64.powf(uniform(-1.5, 1.5))));
            let mass = &d * (&a * a.transpose() + DMatrix::identity(3, 3) * 0.2) * &d;
            let w = mass.try_inverse().expect("positive definite");
            let row = |len: f64, u: &mut dyn FnMut(f64, f64) -> f64| {
                DVector::from_fn(3, |_, _| u(-1.0, 1.0)) * len
            };
            let normal = row(10f64.powf(uniform(-3.0, 0.0)), &mut uniform);
            let tangent = row(10f64.powf(uniform(-3.0, 0.0)), &mut uniform);
            let mu = uniform(0.1, 1.0);
            // Each sliding direction's own effective mass positive (no Painlevé): a
            // solution exists.
            if [1.0, -1.0]
                .iter()
                .any(|s| normal.dot(&(&w * (&normal - &tangent * (mu * s)))) <= 0.0)
            {
                continue;
            }
            // Half the states about to lift off or press: the free normal acceleration
            // a small fraction of the tangential one.
            let mut a0 =
                DVector::from_fn(3, |_, _| uniform(-1.0, 1.0)) * 10f64.powf(uniform(-4.0, 2.0));
            if trial % 2 == 0 {
                let target = tangent.dot(&a0).abs()
                    * 10f64.powf(uniform(-10.0, -3.0))
                    * uniform(-1.0, 1.0).signum();
                a0 -= &normal * ((normal.dot(&a0) - target) / normal.dot(&normal));
            }
            let c = Closed {
                normal: normal.clone(),
                gamma_n: 0.0,
                tangent: tangent.clone(),
                gamma_t: 0.0,
                mu,
                sliding: None,
            };
            let out = solve(&w, &a0, &[c]).unwrap_or_else(|e| panic!("trial {trial}: {e:?}"));
            let (ln, lt) = (out.normal[0], out.tangent[0]);
            let (gn, gt) = (out.normal_acceleration[0], out.tangent_acceleration[0]);
            // The force scale: the largest force, or the force that alone would stop
            // the free normal or tangential acceleration.
            let alone = |r: &DVector<f64>| r.dot(&a0).abs() / r.dot(&(&w * r));
            let f_tol = 1e-9
                * ln.abs()
                    .max(lt.abs())
                    .max(alone(&normal))
                    .max(alone(&tangent));
            let a_tol = 1e-9 * normal.dot(&a0).abs().max(tangent.dot(&a0).abs());
            assert!(ln >= -f_tol, "trial {trial}: λ_N = {ln:e}");
            assert!(
                lt.abs() <= mu * ln + f_tol,
                "trial {trial}: |λ_T| = {:e} beyond μ λ_N = {:e}",
                lt.abs(),
                mu * ln
            );
            assert!(gn >= -a_tol, "trial {trial}: g̈_N = {gn:e}");
            // Complementary: a pressing contact does not accelerate off its plane.
            assert!(
                ln <= f_tol || gn.abs() <= a_tol,
                "trial {trial}: λ_N = {ln:e} with g̈_N = {gn:e}"
            );
            if ln <= f_tol {
                // Open: no friction.
                assert!(lt.abs() <= f_tol, "trial {trial}: open with λ_T = {lt:e}");
            } else if lt.abs() < mu * ln * (1.0 - 1e-6) {
                assert!(gt.abs() <= a_tol, "trial {trial}: stuck but g̈_T = {gt:e}");
            } else {
                // On the cone's edge the friction opposes the slip it starts.
                assert!(
                    gt.abs() <= a_tol || gt * lt < 0.0,
                    "trial {trial}: friction {lt:e} along its slip {gt:e}"
                );
            }
            checked += 1;
        }
        assert!(checked > 300, "{checked} trials checked");
    }
}
