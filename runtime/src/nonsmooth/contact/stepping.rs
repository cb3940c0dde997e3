//! Moreau–Jean time-stepping of planar contacts (theory §8): no events, impulses per
//! step.
//!
//! A step of size `h` from `(q, v)`:
//!
//! 1. the free velocity `v_free = v + h a(q, v, τ)` (the smooth forces explicit);
//! 2. the contacts that may close in the step, `g_N(q) + h W_N v_free ≤ 0`, get impulses
//!    `P` from the velocity-level contact problem: Newton's law
//!    `W_N v⁺ + e W_N v ≥ 0 ⊥ P_N ≥ 0`, Coulomb's `|P_T| ≤ μ P_N` with `W_T v⁺ = 0`
//!    inside the cone and opposing `P_T` at its edge — the same complementarity problem
//!    as the event-driven selection ([`super::planar`]), with velocities for
//!    accelerations;
//! 3. `v⁺ = v_free + M⁻¹ (W_Nᵀ P_N + W_Tᵀ P_T)`, `q⁺ = q + h v⁺`.
//!
//! Where the contacts that hold (a normal impulse, the tangential one strictly inside
//! the cone, no rebound) lock every degree of freedom, `v⁺ = 0` is the solution of their
//! equations, and it is taken as exactly `0`: a box at rest on an incline below its
//! friction angle does not move by a single rounding.
//!
//! The solution's columns are the state, then each contact's normal force `λ_<contact>.n`
//! and tangential forces `λ_<contact>.<axis>`, as the step's impulses over `h`.

use nalgebra::{DMatrix, DVector, SVector};

use super::cone::{self, ConeContact};
use super::planar::{self, Closed, ContactError};
use crate::contacts::Contacts;
use crate::element::Mode;
use crate::input::Input;
use crate::nonsmooth::NonSmoothProblem;
use crate::system::{Mechanism, state_names};
use crate::{ErrorKind, Keep, Solution, SolveError, Switch, SwitchKind};

/// Relative size of the smallest singular value of the holding contacts' rows below
/// which they are taken not to lock every degree of freedom.
const LOCK_RANK: f64 = 1e-10;

/// Relative tolerance of the spatial contact problem's residual
/// ([`Stats::contact_residual`](crate::Stats::contact_residual)).
const CONE_TOLERANCE: f64 = 1e-12;

/// Most Gauss–Seidel sweeps over the contacts per step.
const CONE_SWEEPS: usize = 5000;

/// A spatial contact's friction impulse counts as strictly inside the cone below
/// `(1 − CONE_EDGE) μ P_N` (a sliding impulse is on the edge to round-off).
const CONE_EDGE: f64 = 1e-9;

/// A contact's slip after the step counts as zero below this fraction of the step's
/// largest velocity component (the contact problem's round-off).
const SLIP_ROUND_OFF: f64 = 1e-12;

/// The solution's column names for a scene with contacts: the state, then
/// `λ_<contact>.n` for each contact and `λ_<tangent row>` for each tangent row.
pub(crate) fn column_names<S, const N: usize, const K: usize, const T: usize>() -> Vec<String>
where
    S: Contacts<N, K, T>,
{
    let mut names = state_names(&S::JOINTS);
    names.extend(S::CONTACTS.iter().map(|c| format!("λ_{c}.n")));
    names.extend(S::TANGENTS.iter().map(|t| format!("λ_{t}")));
    names
}

/// What both contact integrators refuse: a time span or start that is not finite,
/// invalid parameters.
pub(crate) fn check<S, const N: usize, const K: usize, const T: usize>(
    scene: &S,
    problem: &NonSmoothProblem<N>,
) -> Result<(), String>
where
    S: Mechanism<N> + Contacts<N, K, T>,
{
    problem.check_span_and_start(&S::JOINTS)?;
    scene.validate().map_err(|e| e.to_string())
}

/// The first contact that can slide in two directions (two tangent rows), if any.
pub(crate) fn spatial_contact<S, const N: usize, const K: usize, const T: usize>() -> Option<usize>
where
    S: Contacts<N, K, T>,
{
    (0..K).find(|&k| S::TANGENT_OF.iter().filter(|&&c| c == k).count() > 1)
}

/// Whether `rows` (constraints `rowᵀ v = 0`) leave no velocity but `0`.
fn locks<const N: usize>(rows: &[DVector<f64>]) -> bool {
    if rows.len() < N {
        return false;
    }
    let m = DMatrix::from_fn(rows.len(), N, |i, j| rows[i][j]);
    let sv = m.singular_values();
    sv.min() > LOCK_RANK * sv.max()
}

/// Integrates `scene` with its contacts by Moreau–Jean time-stepping with step `h`
/// (see the module documentation), the input `τ(t, q, v)` on its coordinates.
///
/// # Errors
/// [`ErrorKind::InvalidInput`] for a non-positive step, a non-finite start or invalid
/// parameters; [`ErrorKind::IllPosedMode`] where the contact problem has no solution
/// (naming the contacts); [`ErrorKind::NonFinite`]. The rows computed up to the failure
/// are kept.
pub fn contact_time_stepping<S, I, const N: usize, const K: usize, const T: usize>(
    scene: &S,
    input: &I,
    problem: &NonSmoothProblem<N>,
    h: f64,
) -> Result<Solution, SolveError>
where
    S: Mechanism<N> + Contacts<N, K, T>,
    I: Input<N> + ?Sized,
{
    let sol = Solution::new(column_names::<S, N, K, T>(), 2 * N, problem.output.clone());
    if !(h > 0.0 && h.is_finite()) {
        let msg = format!("the step h = {h} must be positive and finite");
        return Err(SolveError::new(ErrorKind::InvalidInput(msg), sol));
    }
    if let Err(msg) = check::<S, N, K, T>(scene, problem) {
        return Err(SolveError::new(ErrorKind::InvalidInput(msg), sol));
    }
    let mut sol = sol;
    let (mu, e) = (scene.contact_friction(), scene.contact_restitution());
    let (mut t, mut q, mut v) = (problem.t0, problem.q0, problem.v0);
    let mut modes = [Mode::Free; K];
    let spatial = spatial_contact::<S, N, K, T>().is_some();
    let tangent_rows = |k: usize| (0..T).filter(move |&r| S::TANGENT_OF[r] == k);
    // The last step's impulses of each contact, to start the next step's solver from.
    let mut warm: Vec<Vec<f64>> = vec![Vec::new(); K];
    let zero_forces = vec![0.0; K + T];
    let row = |q: &SVector<f64, N>, v: &SVector<f64, N>, f: &[f64]| -> Vec<f64> {
        q.iter().chain(v.iter()).chain(f.iter()).copied().collect()
    };
    let derivative = |v: &SVector<f64, N>, dv: &SVector<f64, N>| -> Vec<f64> {
        let mut d: Vec<f64> = v.iter().chain(dv.iter()).copied().collect();
        d.resize(2 * N + K + T, 0.0);
        d
    };
    let a0 = scene.forward_dynamics(&q, &v, &input.forces(t, &q, &v));
    sol.push_start(t, &row(&q, &v, &zero_forces), &derivative(&v, &a0));
    let steps = ((problem.tf - problem.t0) / h - 1e-9).ceil().max(0.0) as usize;
    for n in 0..steps {
        let t_next = if n + 1 == steps {
            problem.tf
        } else {
            problem.t0 + (n + 1) as f64 * h
        };
        let hn = t_next - t;
        let tau = input.forces(t, &q, &v);
        let a = scene.forward_dynamics(&q, &v, &tau);
        let v_free = v + a * hn;
        let gaps = scene.contact_gaps(&q);
        let w_n = scene.contact_normal_jacobian(&q);
        let w_t = scene.contact_tangent_jacobian(&q);
        let vn = w_n * v;
        let vn_free = w_n * v_free;
        let active: Vec<usize> = (0..K)
            .filter(|&k| gaps[k] + hn * vn_free[k] <= 0.0)
            .collect();
        let mut v_next = v_free;
        let mut forces = vec![0.0; K + T];
        let mut new_modes = [Mode::Free; K];
        if !active.is_empty() {
            let Some(chol) = scene.mass_matrix(&q).cholesky() else {
                return Err(SolveError::new(
                    ErrorKind::IllPosedMode {
                        t,
                        detail: "the mass matrix is not positive definite".into(),
                    },
                    sol,
                ));
            };
            let inverse = chol.inverse();
            let w = DMatrix::from_fn(N, N, |i, j| inverse[(i, j)]);
            // One tangent row per contact in the plane (the first of its rows).
            let tangent_row = |k: usize| S::TANGENT_OF.iter().position(|&c| c == k);
            let closed: Vec<Closed> = active
                .iter()
                .map(|&k| Closed {
                    normal: DVector::from_iterator(N, w_n.row(k).iter().copied()),
                    gamma_n: -e[k] * vn[k].min(0.0),
                    tangent: match tangent_row(k) {
                        Some(r) => DVector::from_iterator(N, w_t.row(r).iter().copied()),
                        None => DVector::zeros(N),
                    },
                    gamma_t: 0.0,
                    mu: if tangent_row(k).is_some() { mu[k] } else { 0.0 },
                    sliding: None,
                })
                .collect();
            let v_free_d = DVector::from_iterator(N, v_free.iter().copied());
            if spatial {
                let rows_of = |k: usize| -> Vec<DVector<f64>> {
                    std::iter::once(DVector::from_iterator(N, w_n.row(k).iter().copied()))
                        .chain(
                            tangent_rows(k)
                                .map(|r| DVector::from_iterator(N, w_t.row(r).iter().copied())),
                        )
                        .collect()
                };
                let cones: Vec<ConeContact> = active
                    .iter()
                    .map(|&k| ConeContact {
                        rows: rows_of(k),
                        gamma: -e[k] * vn[k].min(0.0),
                        mu: mu[k],
                    })
                    .collect();
                let start: Vec<Vec<f64>> = active.iter().map(|&k| warm[k].clone()).collect();
                let out =
                    match cone::solve(&w, &v_free_d, &cones, &start, CONE_TOLERANCE, CONE_SWEEPS) {
                        Ok(out) => out,
                        Err(cone::NoLocalSolution { contact }) => {
                            let detail = format!(
                                "the contact problem of `{}` has no solution: its friction drives \
                             it into the plane in every sliding direction",
                                S::CONTACTS[active[contact]]
                            );
                            return Err(SolveError::new(
                                ErrorKind::IllPosedMode { t, detail },
                                sol,
                            ));
                        }
                    };
                sol.stats.contact_sweeps += out.sweeps;
                sol.stats.contact_residual = sol.stats.contact_residual.max(out.residual);
                v_next = SVector::from_iterator(out.velocity.iter().copied());
                let slip_tol = SLIP_ROUND_OFF * v_free.amax().max(v.amax());
                let mut holding: Vec<DVector<f64>> = Vec::new();
                for (i, &k) in active.iter().enumerate() {
                    let p = &out.impulses[i];
                    forces[k] = p[0] / hn;
                    for (j, r) in tangent_rows(k).enumerate() {
                        forces[K + r] = p[1 + j] / hn;
                    }
                    let friction = p[1..].iter().map(|x| x * x).sum::<f64>().sqrt();
                    let slip = out.local[i][1..].iter().map(|x| x * x).sum::<f64>().sqrt();
                    // Strictly inside the cone is stuck (a sliding impulse is on its edge
                    // to round-off).
                    let inside = friction < mu[k] * p[0] * (1.0 - CONE_EDGE);
                    let stuck = slip <= slip_tol || (p[0] > 0.0 && inside);
                    new_modes[k] = if p[0] <= 0.0 {
                        Mode::Free
                    } else if stuck {
                        Mode::Stick
                    } else {
                        Mode::SlipPos(0)
                    };
                    if p[0] > 0.0 && cones[i].gamma == 0.0 {
                        holding.push(cones[i].rows[0].clone());
                        if stuck && inside {
                            holding.extend(cones[i].rows[1..].iter().cloned());
                        }
                    }
                    warm[k] = p.clone();
                }
                if locks::<N>(&holding) {
                    v_next = SVector::zeros();
                }
            } else {
                let out = planar::solve(&w, &v_free_d, &closed).map_err(|err| {
                    let names: Vec<String> = active
                        .iter()
                        .map(|&k| format!("`{}`", S::CONTACTS[k]))
                        .collect();
                    let detail = match err {
                        ContactError::Painleve { .. } => format!(
                            "the contact problem of {} has no unique solution (Painlevé)",
                            names.join(", ")
                        ),
                        ContactError::NoSolution => format!(
                            "the contact problem of {} has no solution",
                            names.join(", ")
                        ),
                    };
                    ErrorKind::IllPosedMode { t, detail }
                });
                let out = match out {
                    Ok(o) => o,
                    Err(kind) => return Err(SolveError::new(kind, sol)),
                };
                v_next = SVector::from_iterator(out.acceleration.iter().copied());
                // The holding contacts: a normal impulse, no rebound, stuck (no slip beyond
                // round-off of the step's velocities) inside the cone.
                let slip_tol = SLIP_ROUND_OFF * v_free.amax().max(v.amax());
                let mut holding: Vec<DVector<f64>> = Vec::new();
                for (i, &k) in active.iter().enumerate() {
                    let (pn, pt) = (out.normal[i], out.tangent[i]);
                    forces[k] = pn / hn;
                    if let Some(r) = tangent_row(k) {
                        forces[K + r] = pt / hn;
                    }
                    let slip = out.tangent_acceleration[i];
                    let stuck = slip.abs() <= slip_tol;
                    new_modes[k] = if pn <= 0.0 {
                        Mode::Free
                    } else if stuck {
                        Mode::Stick
                    } else if slip > 0.0 {
                        Mode::SlipPos(0)
                    } else {
                        Mode::SlipNeg(0)
                    };
                    if pn > 0.0 && closed[i].gamma_n == 0.0 {
                        holding.push(closed[i].normal.clone());
                        if stuck && pt.abs() < mu[k] * pn && tangent_row(k).is_some() {
                            holding.push(closed[i].tangent.clone());
                        }
                    }
                }
                if locks::<N>(&holding) {
                    v_next = SVector::zeros();
                }
            }
        }
        for k in 0..K {
            if !active.contains(&k) {
                warm[k].clear();
            }
        }
        let q_next = q + v_next * hn;
        let y = row(&q_next, &v_next, &forces);
        if let Some(component) = y.iter().position(|x| !x.is_finite()) {
            return Err(SolveError::new(
                ErrorKind::NonFinite {
                    t: t_next,
                    component,
                },
                sol,
            ));
        }
        for k in 0..K {
            if new_modes[k] != modes[k] {
                let before = row(&q, &v, &[]);
                let after = row(&q_next, &v_next, &[]);
                let impact = modes[k] == Mode::Free && vn[k] < 0.0 && forces[k] > 0.0;
                let mut s = Switch::of_run(
                    t_next,
                    if impact {
                        SwitchKind::Impact
                    } else {
                        SwitchKind::Mode
                    },
                    before,
                    after,
                );
                s.element = Some(S::CONTACTS[k].to_string());
                s.index = Some(k);
                s.from = Some(modes[k]);
                s.to = Some(new_modes[k]);
                s.jump = forces[k] * hn;
                sol.switches.push(s);
            }
        }
        modes = new_modes;
        let dv = (v_next - v) / hn;
        let keep = if n + 1 == steps {
            Keep::Last
        } else {
            Keep::AsAsked
        };
        sol.push_step(t_next, &y, &derivative(&v_next, &dv), None, keep);
        sol.stats.steps += 1;
        (t, q, v) = (t_next, q_next, v_next);
    }
    Ok(sol)
}
