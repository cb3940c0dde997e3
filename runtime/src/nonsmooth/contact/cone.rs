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

/// Relative tolerance of the spatial contact problem's residual
/// ([`Stats::contact_residual`](crate::Stats::contact_residual)).
pub(crate) const CONE_TOLERANCE: f64 = 1e-12;

/// Most Gauss–Seidel sweeps over the contacts per step.
pub(crate) const CONE_SWEEPS: usize = 5000;

/// A spatial contact's friction impulse counts as strictly inside the cone below
/// `(1 − CONE_EDGE) μ P_N` (a sliding impulse is on the edge to round-off).
pub(crate) const CONE_EDGE: f64 = 1e-9;

/// A contact's slip after the step counts as zero below this fraction of the step's
/// largest velocity component (the contact problem's round-off).
pub(crate) const SLIP_ROUND_OFF: f64 = 1e-12;

/// Contact `k`'s rows for a local problem: its normal row of `w_n`, then its tangent
/// rows of `w_t` (`tangents`, in order).
pub(crate) fn contact_rows<const N: usize, const K: usize, const T: usize>(
    w_n: &nalgebra::SMatrix<f64, K, N>,
    w_t: &nalgebra::SMatrix<f64, T, N>,
    k: usize,
    tangents: impl Iterator<Item = usize>,
) -> Vec<DVector<f64>> {
    std::iter::once(DVector::from_iterator(N, w_n.row(k).iter().copied()))
        .chain(tangents.map(|r| DVector::from_iterator(N, w_t.row(r).iter().copied())))
        .collect()
}

/// Whether a contact's impulses `p = [P_N, P_T…]` and velocities `u = [u_N, u_T…]` after
/// a solve leave it stuck: its slip zero to `slip_tol`, or its friction strictly inside
/// the cone `μ` (a sliding impulse is on the edge to round-off).
pub(crate) fn is_stuck(p: &[f64], u: &[f64], mu: f64, slip_tol: f64) -> bool {
    let friction = p[1..].iter().map(|x| x * x).sum::<f64>().sqrt();
    let slip = u[1..].iter().map(|x| x * x).sum::<f64>().sqrt();
    slip <= slip_tol || (p[0] > 0.0 && friction < mu * p[0] * (1.0 - CONE_EDGE))
}

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
    // The largest residual over the contacts, relative: a contact's natural map, a
    // friction element's distance from its law (how far the law would move its impulse),
    // both in velocity units.
    let residual_of = |impulses: &[Vec<f64>], v: &DVector<f64>| -> f64 {
        (0..k)
            .map(|i| match contacts[i].friction {
                Some(f) => {
                    let a = blocks[i][(0, 0)];
                    let c = local(v, i)[0] - a * impulses[i][0];
                    (friction_solve(a, c, f) - impulses[i][0]).abs() * a
                }
                None => natural_map(&impulses[i], &local(v, i), contacts[i].mu, &blocks[i]),
            })
            .fold(0.0, f64::max)
            / scale
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
        residual = residual_of(&impulses, &v);
        if residual <= tolerance {
            break;
        }
    }
    // Gauss–Seidel converges slowly, or cycles, where coupled frictions come to rest
    // together (a table's legs, their friction turning it and so pressing its legs):
    // every contact held (closed and stuck) is then tried as a whole, and taken where
    // its impulses are admissible and leave a smaller residual.
    if residual > tolerance {
        let refined = active_set(v_free, contacts, &wh, &impulses)
            .into_iter()
            .flatten();
        for (held, v_held) in all_held(v_free, contacts, &wh).into_iter().chain(refined) {
            let r = residual_of(&held, &v_held);
            if r < residual {
                (impulses, v, residual) = (held, v_held, r);
            }
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

/// Every contact closed and stuck, every friction element stuck: the least-norm
/// impulses that hold all their rows (`u = 0`, a contact's normal at `γ`), if each is
/// admissible (pressing, inside its cone or bound) and the rows are consistent.
fn all_held(
    v_free: &DVector<f64>,
    contacts: &[ConeContact],
    wh: &[Vec<DVector<f64>>],
) -> Option<(Vec<Vec<f64>>, DVector<f64>)> {
    let rows: Vec<(&DVector<f64>, &DVector<f64>, f64)> = contacts
        .iter()
        .zip(wh)
        .flat_map(|(c, whi)| {
            c.rows.iter().zip(whi).enumerate().map(move |(j, (r, x))| {
                let target = if j == 0 && c.friction.is_none() {
                    c.gamma
                } else {
                    0.0
                };
                (r, x, target)
            })
        })
        .collect();
    let m = rows.len();
    let a = DMatrix::from_fn(m, m, |i, j| rows[i].0.dot(rows[j].1));
    let b = DVector::from_fn(m, |i, _| rows[i].2 - rows[i].0.dot(v_free));
    let p = a
        .clone()
        .svd(true, true)
        .solve(&b, 1e-12 * a.amax().max(f64::MIN_POSITIVE))
        .ok()?;
    let mut v = v_free.clone();
    for (i, row) in rows.iter().enumerate() {
        v.axpy(p[i], row.1, 1.0);
    }
    // Consistent: every row held to round-off.
    let scale = b.amax().max(f64::MIN_POSITIVE);
    if rows
        .iter()
        .any(|(r, _, target)| (r.dot(&v) - target).abs() > 1e-12 * scale)
    {
        return None;
    }
    let mut out = Vec::with_capacity(contacts.len());
    let mut at = 0;
    for c in contacts {
        let d = c.rows.len();
        let pc: Vec<f64> = p.rows(at, d).iter().copied().collect();
        at += d;
        let fits = match c.friction {
            Some(f) => pc[0].abs() <= f.stick,
            None => {
                let t = pc[1..].iter().map(|x| x * x).sum::<f64>().sqrt();
                pc[0] >= 0.0 && t <= c.mu * pc[0]
            }
        };
        if !fits {
            return None;
        }
        out.push(pc);
    }
    Some((out, v))
}

/// How a contact takes part in [`active_set`]'s linear problem.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Part {
    Open,
    Held,
    /// Sliding, its friction impulse along `−μ P_N s` (`s` a unit vector in the
    /// tangent rows, at most two).
    Sliding([f64; 2]),
}

/// Active-set refinement of a Gauss–Seidel iterate: each contact open, held or sliding
/// (its direction) as the iterate has it; the linear problem of those equalities solved
/// (least norm where redundant), the parts corrected by the laws the solution breaks (a
/// pulling contact opens, a held one outside its cone slides against its friction, a
/// sliding one follows its slip, an open one that sinks is held), up to a few times.
/// The solution where every law holds, if one is reached. Friction elements are held or
/// slide like contacts' tangents.
fn active_set(
    v_free: &DVector<f64>,
    contacts: &[ConeContact],
    wh: &[Vec<DVector<f64>>],
    start: &[Vec<f64>],
) -> Option<Vec<(Vec<Vec<f64>>, DVector<f64>)>> {
    let edge = 1e-9;
    let mut parts: Vec<Part> = contacts
        .iter()
        .zip(start)
        .map(|(c, p)| match c.friction {
            Some(f) if p[0].abs() >= f.stick * (1.0 - edge) && p[0] != 0.0 => {
                Part::Sliding([-p[0].signum(), 0.0])
            }
            Some(_) => Part::Held,
            None if p[0] <= 0.0 => Part::Open,
            None => {
                let t = p[1..].iter().map(|x| x * x).sum::<f64>().sqrt();
                if t >= c.mu * p[0] * (1.0 - edge) && t > 0.0 {
                    let mut s = [0.0; 2];
                    for (j, x) in p[1..].iter().enumerate() {
                        s[j] = -x / t;
                    }
                    Part::Sliding(s)
                } else {
                    Part::Held
                }
            }
        })
        .collect();
    for _ in 0..ACTIVE_SET_ROUNDS {
        let (p, v) = solve_parts(v_free, contacts, wh, &parts)?;
        // The laws the solution breaks correct the parts.
        let mut changed = false;
        let scale = v_free.amax().max(v.amax()).max(f64::MIN_POSITIVE);
        for (i, c) in contacts.iter().enumerate() {
            let u: Vec<f64> = c.rows.iter().map(|r| r.dot(&v)).collect();
            let next = match (c.friction, parts[i]) {
                (Some(f), Part::Held) if p[i][0].abs() > f.stick => {
                    Part::Sliding([-p[i][0].signum(), 0.0])
                }
                (Some(_), Part::Sliding(s)) if u[0] * -s[0] > 1e-12 * scale => Part::Held,
                (None, Part::Open) if u[0] < c.gamma - 1e-12 * scale => Part::Held,
                (None, Part::Held | Part::Sliding(_)) if p[i][0] < 0.0 => Part::Open,
                (None, Part::Held) => {
                    let t = p[i][1..].iter().map(|x| x * x).sum::<f64>().sqrt();
                    if t > c.mu * p[i][0] {
                        let mut s = [0.0; 2];
                        for (j, x) in p[i][1..].iter().enumerate() {
                            s[j] = -x / t;
                        }
                        Part::Sliding(s)
                    } else {
                        Part::Held
                    }
                }
                // A sliding contact's direction is its own problem's, the others'
                // parts held: its reduced local problem solved exactly.
                (None, Part::Sliding(_)) => match reduced(v_free, contacts, wh, &parts, &p, i) {
                    Some(q) if q[0] <= 0.0 => Part::Open,
                    Some(q) => {
                        let t = q[1..].iter().map(|x| x * x).sum::<f64>().sqrt();
                        if t < c.mu * q[0] * (1.0 - edge) || t == 0.0 {
                            Part::Held
                        } else {
                            let mut dir = [0.0; 2];
                            for (j, x) in q[1..].iter().enumerate() {
                                dir[j] = -x / t;
                            }
                            Part::Sliding(dir)
                        }
                    }
                    None => parts[i],
                },
                (_, part) => part,
            };
            // Only a change of part counts: the sliding directions are Newton's below.
            changed |= std::mem::discriminant(&next) != std::mem::discriminant(&parts[i]);
            parts[i] = next;
        }
        if !changed {
            // Also the directions polished by Newton's method, where that converges: the
            // caller keeps whichever leaves the smaller residual.
            let polished = newton_directions(v_free, contacts, wh, &mut parts);
            return Some(std::iter::once((p, v)).chain(polished).collect());
        }
    }
    None
}

/// The linear problem of `parts` (see [`active_set`]) solved: the impulses per contact
/// and the velocity.
fn solve_parts(
    v_free: &DVector<f64>,
    contacts: &[ConeContact],
    wh: &[Vec<DVector<f64>>],
    parts: &[Part],
) -> Option<(Vec<Vec<f64>>, DVector<f64>)> {
    // Unknowns and their force directions (in W-applied form), equations and targets.
    let mut dirs: Vec<DVector<f64>> = Vec::new();
    let mut eqs: Vec<(&DVector<f64>, f64)> = Vec::new();
    let mut owner: Vec<(usize, usize)> = Vec::new();
    for (i, (c, part)) in contacts.iter().zip(parts).enumerate() {
        let d = c.rows.len();
        match (c.friction, *part) {
            (_, Part::Open) => {}
            (Some(_), Part::Held) | (None, Part::Held) => {
                for j in 0..d {
                    let target = if j == 0 && c.friction.is_none() {
                        c.gamma
                    } else {
                        0.0
                    };
                    dirs.push(wh[i][j].clone());
                    eqs.push((&c.rows[j], target));
                    owner.push((i, j));
                }
            }
            (Some(f), Part::Sliding(s)) => {
                // A fixed impulse −s · slip bound (no unknown): applied below.
                let _ = f;
                let _ = s;
            }
            (None, Part::Sliding(s)) => {
                let mut dir = wh[i][0].clone();
                for j in 1..d {
                    dir.axpy(-c.mu * s[j - 1], &wh[i][j], 1.0);
                }
                dirs.push(dir);
                eqs.push((&c.rows[0], c.gamma));
                owner.push((i, 0));
            }
        }
    }
    // The sliding friction elements' impulses are known.
    let mut v0 = v_free.clone();
    for (i, (c, part)) in contacts.iter().zip(parts).enumerate() {
        if let (Some(f), Part::Sliding(s)) = (c.friction, *part) {
            v0.axpy(-s[0] * f.slip, &wh[i][0], 1.0);
        }
    }
    let m = eqs.len();
    let a = DMatrix::from_fn(m, m, |r, k| eqs[r].0.dot(&dirs[k]));
    let b = DVector::from_fn(m, |r, _| eqs[r].1 - eqs[r].0.dot(&v0));
    let x = if m == 0 {
        DVector::zeros(0)
    } else {
        a.clone()
            .svd(true, true)
            .solve(&b, 1e-12 * a.amax().max(f64::MIN_POSITIVE))
            .ok()?
    };
    let mut v = v0;
    for (k, dir) in dirs.iter().enumerate() {
        v.axpy(x[k], dir, 1.0);
    }
    // The impulses, per contact.
    let mut p: Vec<Vec<f64>> = contacts.iter().map(|c| vec![0.0; c.rows.len()]).collect();
    for (k, &(i, j)) in owner.iter().enumerate() {
        p[i][j] = x[k];
    }
    for (i, (c, part)) in contacts.iter().zip(parts).enumerate() {
        match (c.friction, *part) {
            (Some(f), Part::Sliding(s)) => p[i][0] = -s[0] * f.slip,
            (None, Part::Sliding(s)) => {
                let pn = p[i][0];
                for j in 1..c.rows.len() {
                    p[i][j] = -c.mu * pn * s[j - 1];
                }
            }
            _ => {}
        }
    }
    Some((p, v))
}

/// Newton's method on the sliding angles of `parts`' contacts with two tangent rows:
/// each angle's residual `s × u_T` (the slip parallel to the assumed direction), the
/// Jacobian by differences. The solution with every slip along its direction, if
/// reached.
fn newton_directions(
    v_free: &DVector<f64>,
    contacts: &[ConeContact],
    wh: &[Vec<DVector<f64>>],
    parts: &mut [Part],
) -> Option<(Vec<Vec<f64>>, DVector<f64>)> {
    let sliding: Vec<usize> = (0..contacts.len())
        .filter(|&i| contacts[i].friction.is_none() && contacts[i].rows.len() == 3)
        .filter(|&i| matches!(parts[i], Part::Sliding(_)))
        .collect();
    let angle = |part: &Part| match part {
        Part::Sliding(s) => s[1].atan2(s[0]),
        _ => 0.0,
    };
    let mut theta: Vec<f64> = sliding.iter().map(|&i| angle(&parts[i])).collect();
    let residual =
        |theta: &[f64], parts: &mut [Part]| -> Option<(Vec<f64>, Vec<Vec<f64>>, DVector<f64>)> {
            for (k, &i) in sliding.iter().enumerate() {
                parts[i] = Part::Sliding([theta[k].cos(), theta[k].sin()]);
            }
            let (p, v) = solve_parts(v_free, contacts, wh, parts)?;
            let f = sliding
                .iter()
                .zip(theta)
                .map(|(&i, th)| {
                    let u1 = contacts[i].rows[1].dot(&v);
                    let u2 = contacts[i].rows[2].dot(&v);
                    th.cos() * u2 - th.sin() * u1
                })
                .collect();
            Some((f, p, v))
        };
    let scale = v_free.amax().max(f64::MIN_POSITIVE);
    for _ in 0..NEWTON_ITERATIONS {
        let (f, p, v) = residual(&theta, parts)?;
        if f.iter().all(|x| x.abs() <= 1e-15 * scale) {
            return Some((p, v));
        }
        let n = theta.len();
        let delta = 1e-7;
        let mut jac = DMatrix::zeros(n, n);
        for c in 0..n {
            let mut shifted = theta.clone();
            shifted[c] += delta;
            let (fc, _, _) = residual(&shifted, parts)?;
            for r in 0..n {
                jac[(r, c)] = (fc[r] - f[r]) / delta;
            }
        }
        let step = jac
            .lu()
            .solve(&DVector::from_iterator(n, f.iter().map(|x| -x)))?;
        for c in 0..n {
            theta[c] += step[c];
        }
        if step.amax() <= 1e-14 {
            let (_, p, v) = residual(&theta, parts)?;
            return Some((p, v));
        }
    }
    None
}

/// Newton iterations on the sliding angles.
const NEWTON_ITERATIONS: usize = 30;

/// Contact `i`'s local problem with the other contacts in their `parts` — held ones'
/// rows kept at their targets (least-norm impulses where redundant), sliding and
/// friction elements' impulses as in `p` — solved exactly by [`local_solve`].
fn reduced(
    v_free: &DVector<f64>,
    contacts: &[ConeContact],
    wh: &[Vec<DVector<f64>>],
    parts: &[Part],
    p: &[Vec<f64>],
    i: usize,
) -> Option<Vec<f64>> {
    // The fixed impulses of the others that are not held.
    let mut v0 = v_free.clone();
    // Rows kept at their targets, with the force direction of their unknown impulse: a
    // held contact's every row; a sliding contact's normal, its friction along its
    // direction (so that sliding contacts' normal forces answer each other).
    let mut held_rows: Vec<(&DVector<f64>, DVector<f64>, f64)> = Vec::new();
    for (k, c) in contacts.iter().enumerate() {
        if k == i {
            continue;
        }
        match (c.friction, parts[k]) {
            (_, Part::Held) => {
                for j in 0..c.rows.len() {
                    let target = if j == 0 && c.friction.is_none() {
                        c.gamma
                    } else {
                        0.0
                    };
                    held_rows.push((&c.rows[j], wh[k][j].clone(), target));
                }
            }
            (None, Part::Sliding(s)) => {
                let mut dir = wh[k][0].clone();
                for j in 1..c.rows.len() {
                    dir.axpy(-c.mu * s[j - 1], &wh[k][j], 1.0);
                }
                held_rows.push((&c.rows[0], dir, c.gamma));
            }
            _ => {
                for (j, x) in p[k].iter().enumerate() {
                    v0.axpy(*x, &wh[k][j], 1.0);
                }
            }
        }
    }
    let c = &contacts[i];
    let d = c.rows.len();
    let m = held_rows.len();
    // u_i = E_iᵀ v, v = v0 + D_i P + D_H x, K x = b − E_Hᵀ (v0 + D_i P).
    let (a_eff, c_eff) = if m == 0 {
        let a = DMatrix::from_fn(d, d, |r, s| c.rows[r].dot(&wh[i][s]));
        let cv: Vec<f64> = (0..d).map(|r| c.rows[r].dot(&v0)).collect();
        (a, cv)
    } else {
        let k = DMatrix::from_fn(m, m, |r, s| held_rows[r].0.dot(&held_rows[s].1));
        let pinv = k
            .clone()
            .pseudo_inverse(1e-12 * k.amax().max(f64::MIN_POSITIVE))
            .ok()?;
        let b = DVector::from_fn(m, |r, _| held_rows[r].2 - held_rows[r].0.dot(&v0));
        let x0 = &pinv * b;
        let mut v_base = v0.clone();
        for (r, h) in held_rows.iter().enumerate() {
            v_base.axpy(x0[r], &h.1, 1.0);
        }
        // Per unit impulse along each of i's rows: its direct effect less the held
        // contacts' response.
        let effect: Vec<DVector<f64>> = (0..d)
            .map(|s| {
                let e = DVector::from_fn(m, |r, _| held_rows[r].0.dot(&wh[i][s]));
                let x = &pinv * e;
                let mut out = wh[i][s].clone();
                for (r, h) in held_rows.iter().enumerate() {
                    out.axpy(-x[r], &h.1, 1.0);
                }
                out
            })
            .collect();
        let a = DMatrix::from_fn(d, d, |r, s| c.rows[r].dot(&effect[s]));
        let cv: Vec<f64> = (0..d).map(|r| c.rows[r].dot(&v_base)).collect();
        (a, cv)
    };
    let mut cl = c_eff;
    if c.friction.is_none() {
        cl[0] -= c.gamma;
    }
    local_solve(&a_eff, &cl, c.mu)
}

/// Rounds of [`active_set`].
const ACTIVE_SET_ROUNDS: usize = 30;

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
    // Where it is not, the slip is roughly against the stuck impulse's friction.
    let mut guess = None;
    if let Some(p) = a.clone().lu().solve(&rhs) {
        let pt = p.rows(1, d - 1).norm();
        if p[0] > 0.0 && pt <= mu * p[0] {
            return Some(p.iter().copied().collect());
        }
        if d == 3 && pt > 0.0 {
            guess = Some((-p[2]).atan2(-p[1]));
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
            if let Some((pn, ut)) = at(&[s])
                && ut[0] * s >= 0.0
            {
                return Some(impulse(pn, &[s]));
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
    // First the secant method from the guess (a few evaluations where it converges on
    // an admissible root), then the sampling that finds every root.
    if let Some(theta0) = guess {
        let (mut x0, mut x1) = (theta0, theta0 + 1e-3);
        let (mut f0, mut f1) = (f(x0).map(|r| r.0), f(x1).map(|r| r.0));
        for _ in 0..SECANT_ITERATIONS {
            let (Some(y0), Some(y1)) = (f0, f1) else {
                break;
            };
            if y1 == y0 {
                break;
            }
            let x2 = x1 - y1 * (x1 - x0) / (y1 - y0);
            if !x2.is_finite() {
                break;
            }
            if (x2 - x1).abs() <= 4.0 * f64::EPSILON * (1.0 + x2.abs()) {
                if let Some((_, along, pn)) = f(x2)
                    && along >= 0.0
                {
                    return Some(impulse(pn, &dir(x2)));
                }
                break;
            }
            (x0, f0, x1) = (x1, f1, x2);
            f1 = f(x1).map(|r| r.0);
        }
    }
    let step = std::f64::consts::TAU / ANGLE_SAMPLES as f64;
    let mut best: Option<(f64, f64)> = None; // (θ, P_N)
    let mut prev = (0.0, f(0.0));
    for j in 1..=ANGLE_SAMPLES {
        let theta = j as f64 * step;
        let cur = f(theta);
        if let (Some((f0, _, _)), Some((f1, _, _))) = (prev.1, cur)
            && (f0 == 0.0 || f0.signum() != f1.signum())
        {
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
            if let Some((_, along, pn)) = f(root)
                && along >= 0.0
                && best.is_none_or(|(_, b)| pn < b)
            {
                best = Some((root, pn));
            }
        }
        prev = (theta, cur);
    }
    match best {
        Some((theta, pn)) => Some(impulse(pn, &dir(theta))),
        // No sliding direction found (friction coupling the normal so strongly that
        // P_N's denominator changes sign around the circle): De Saxcé's projected
        // iteration, whose distance from a solution the sweep's residual reports.
        None => project_iterate(a, c, mu),
    }
}

/// Secant iterations on the sliding angle before sampling.
const SECANT_ITERATIONS: usize = 30;

/// Iterations of the projected fixed point [`project_iterate`].
const PROJECTION_ITERATIONS: usize = 500;

/// `P ← proj_K(P − ρ (A P + c + μ |u_T| e_N))` from `P = 0`, `ρ` the inverse of the
/// block's largest diagonal entry: the local problem's fallback. `None` if it leaves the
/// finite numbers.
fn project_iterate(a: &DMatrix<f64>, c: &[f64], mu: f64) -> Option<Vec<f64>> {
    let d = c.len();
    let rho = 1.0 / a.diagonal().amax().max(f64::MIN_POSITIVE);
    let mut p = vec![0.0; d];
    for _ in 0..PROJECTION_ITERATIONS {
        let u: Vec<f64> = (0..d)
            .map(|r| c[r] + (0..d).map(|s| a[(r, s)] * p[s]).sum::<f64>())
            .collect();
        let slip = u[1..].iter().map(|x| x * x).sum::<f64>().sqrt();
        let mut y: Vec<f64> = p.iter().zip(&u).map(|(pi, ui)| pi - rho * ui).collect();
        y[0] -= rho * mu * slip;
        p = project_on_cone(&y, mu);
    }
    p.iter().all(|x| x.is_finite()).then_some(p)
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
