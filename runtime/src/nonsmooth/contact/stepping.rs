//! Moreau–Jean time-stepping of contacts, planar and spatial, beside a scene's joint
//! friction elements and rigid stops (theory §8): no events, impulses per step.
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
//!    Planar contacts alone solve it as that complementarity problem; spatial contacts
//!    (the exact friction cone) or joint elements beside them solve it by Gauss–Seidel
//!    over contacts and elements ([`super::cone`]);
//! 3. `v⁺ = v_free + M⁻¹ (W_Nᵀ P_N + W_Tᵀ P_T)`, `q⁺ = q + h v⁺`, and a gap that sank
//!    below its plane lifted back onto it (the velocities kept).
//!
//! Where the contacts that hold (a normal impulse, the tangential one strictly inside
//! the cone, no rebound) lock every degree of freedom, `v⁺ = 0` is the solution of their
//! equations, and it is taken as exactly `0`: a box at rest on an incline below its
//! friction angle does not move by a single rounding.
//!
//! The solution's columns are the state, then each contact's normal force `λ_<contact>.n`
//! and tangential forces `λ_<contact>.<axis>`, then each joint element's force
//! `f_<element>`, as the step's impulses over `h`.

use nalgebra::{DMatrix, DVector, SVector};

use super::cone::{
    self, CONE_EDGE, CONE_SWEEPS, CONE_TOLERANCE, ConeContact, Friction, SLIP_ROUND_OFF,
};
use super::planar::{self, Closed, ContactError};
use crate::contacts::Contacts;
use crate::element::{Element, ElementKind, Law, Mode, Side, StopKind};
use crate::input::Input;
use crate::nonsmooth::NonSmoothProblem;
use crate::nonsmooth::bearing::{self, BEARING_ITERATIONS, BEARING_TOL, Bearings};
use crate::numerics::factor;
use crate::system::{Mechanism, state_names};
use crate::{ErrorKind, Keep, Solution, SolveError, Switch, SwitchKind};

/// Relative size of the smallest singular value of the holding contacts' rows below
/// which they are taken not to lock every degree of freedom.
const LOCK_RANK: f64 = 1e-10;

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

/// The joint elements acting over a step from `q` with free velocity `v_free`: every
/// friction element (its row `e_c` and its law over `h`), and the rigid stops that may
/// close in the step (their row, pointing into the admissible side).
fn acting_elements<const N: usize>(
    elements: &[Element],
    q: &SVector<f64, N>,
    v_free: &SVector<f64, N>,
    h: f64,
) -> Vec<(usize, DVector<f64>, Option<Friction>)> {
    let unit = |c: usize, s: f64| DVector::from_fn(N, |i, _| if i == c { s } else { 0.0 });
    elements
        .iter()
        .enumerate()
        .filter_map(|(i, el)| {
            let c = el.coordinate;
            match el.kind {
                ElementKind::DashPot { .. } => Some((i, unit(c, 1.0), friction_of(el, h))),
                ElementKind::Stop { side, position, .. } => {
                    // Upper (q ≤ position): gap position − q, row −e_c.
                    let s = match side {
                        Side::Upper => -1.0,
                        Side::Lower => 1.0,
                    };
                    let gap = s * (q[c] - position);
                    (gap + h * s * v_free[c] <= 0.0).then(|| (i, unit(c, s), None))
                }
            }
        })
        .collect()
}

/// A friction element's law over a step `h` (`None` for a stop).
fn friction_of(element: &Element, h: f64) -> Option<Friction> {
    let ElementKind::DashPot { law, f_crit } = element.kind else {
        return None;
    };
    let (slip, damping) = match law {
        Law::StaticKinetic { f_kinetic } => (f_kinetic, 0.0),
        Law::BinghamLinear { eta } => (f_crit, eta),
        _ => (f_crit, 0.0),
    };
    Some(Friction {
        stick: h * f_crit,
        slip: h * slip,
        damping: h * damping,
    })
}

/// A rigid stop's coefficient of restitution (`0` for anything else).
fn stop_restitution(element: &Element) -> f64 {
    match element.kind {
        ElementKind::Stop {
            kind: StopKind::Rigid { restitution },
            ..
        } => restitution,
        _ => 0.0,
    }
}

/// The joint elements contact time-stepping takes: Coulomb, static–kinetic and linear
/// Bingham friction, rigid stops. Others are refused by name.
fn check_elements<const N: usize>(elements: &[Element], joints: &[&str]) -> Result<(), String> {
    for el in elements {
        let supported = match el.kind {
            ElementKind::DashPot { law, .. } => matches!(
                law,
                Law::Coulomb | Law::StaticKinetic { .. } | Law::BinghamLinear { .. }
            ),
            ElementKind::Stop { kind, .. } => matches!(kind, StopKind::Rigid { .. }),
        };
        if !supported {
            return Err(format!(
                "element `{}` on {} is not integrated beside contacts yet: contact \
                 time-stepping takes Coulomb, static–kinetic and linear Bingham friction and \
                 rigid stops",
                el.name,
                crate::element::joint_name(joints, el.coordinate)
            ));
        }
        if el.coordinate >= N {
            return Err(format!(
                "element `{}` acts on coordinate {} but the mechanism has {N}",
                el.name, el.coordinate
            ));
        }
    }
    Ok(())
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

/// A gap below this fraction of the coordinates' size is lifted back onto its plane.
const SUNK: f64 = 1e-12;

/// Lifts the contacts that sank below their planes (beyond [`SUNK`]) back onto them:
/// Newton steps on their gaps, each the least change of `q` in the mass metric.
fn lift_sunk<S, const N: usize, const K: usize, const T: usize>(scene: &S, q: &mut SVector<f64, N>)
where
    S: Mechanism<N> + Contacts<N, K, T>,
{
    let tol = SUNK * q.amax().max(1.0);
    for _ in 0..3 {
        let gaps = scene.contact_gaps(q);
        let sunk: Vec<usize> = (0..K).filter(|&k| gaps[k] < -tol).collect();
        if sunk.is_empty() {
            return;
        }
        let Some(w) = factor::spd_inverse(factor::dynamic(&scene.mass_matrix(q))) else {
            return;
        };
        let w_n = scene.contact_normal_jacobian(q);
        let g = DMatrix::from_fn(sunk.len(), N, |i, j| w_n[(sunk[i], j)]);
        let r = DVector::from_fn(sunk.len(), |i, _| -gaps[sunk[i]]);
        let Some(dq) = factor::least_change(&g, &w, &r) else {
            return;
        };
        *q += SVector::<f64, N>::from_iterator(dq.iter().copied());
    }
}

/// Whether `rows` (constraints `rowᵀ v = 0`) leave no velocity but `0`.
fn locks<const N: usize>(rows: &[DVector<f64>]) -> bool {
    if rows.len() < N {
        return false;
    }
    let m = DMatrix::from_fn(rows.len(), N, |i, j| rows[i][j]);
    factor::full_column_rank(&m, LOCK_RANK)
}

/// Integrates `scene` with its contacts (and its joint friction elements and rigid
/// stops) by Moreau–Jean time-stepping with step `h` (see the module documentation),
/// the input `τ(t, q, v)` on its coordinates. How far each step's spatial contact
/// problem was solved is in the solution's
/// [`Stats::contact_residual`](crate::Stats::contact_residual).
///
/// # Errors
/// [`ErrorKind::InvalidInput`] for a non-positive step, a non-finite start, invalid
/// parameters or a joint element it does not integrate (named); [`ErrorKind::IllPosedMode`]
/// where the contact problem has no solution (naming the contacts);
/// [`ErrorKind::NonFinite`]. The rows computed up to the failure are kept.
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
    // The scene's joint elements, their forces `f_<element>` after the contacts'.
    let mut elements = scene.joint_elements();
    // Bearing friction's limits, from the loads of each step's motion (`bearing`).
    let mut bearings = Bearings::new(S::JOINT_BEARINGS, &elements);
    let n_elements = elements.len();
    let mut names = column_names::<S, N, K, T>();
    names.extend(elements.iter().map(|el| format!("f_{}", el.name)));
    let sol = Solution::new(names, 2 * N, problem.output.clone());
    if !(h > 0.0 && h.is_finite()) {
        let msg = format!("the step h = {h} must be positive and finite");
        return Err(SolveError::new(ErrorKind::InvalidInput(msg), sol));
    }
    if let Err(msg) = check::<S, N, K, T>(scene, problem)
        .and_then(|()| check_elements::<N>(&elements, &S::JOINTS))
    {
        return Err(SolveError::new(ErrorKind::InvalidInput(msg), sol));
    }
    let mut sol = sol;
    let (mu_kinetic, mu_static, e) = (
        scene.contact_friction(),
        scene.contact_static_friction(),
        scene.contact_restitution(),
    );
    let (mut t, mut q, mut v) = (problem.t0, problem.q0, problem.v0);
    // A contact touching without slipping at the start is stuck (it holds within its
    // static cone from the first step).
    let mut modes = {
        let (gaps, slips) = (
            scene.contact_gaps(&q),
            scene.contact_tangent_jacobian(&q) * v,
        );
        std::array::from_fn(|k| {
            let still = (0..T).all(|r| S::TANGENT_OF[r] != k || slips[r] == 0.0);
            if gaps[k] <= 0.0 && still {
                Mode::Stick
            } else {
                Mode::Free
            }
        })
    };
    // Each joint element's last impulse and mode.
    let mut warm_elements: Vec<Vec<f64>> = vec![Vec::new(); elements.len()];
    let mut element_modes: Vec<Mode> = vec![Mode::Free; elements.len()];
    // Spatial contacts or joint elements: the Gauss–Seidel problem of `cone`; planar
    // contacts alone: the complementarity problem of `planar`.
    let general = spatial_contact::<S, N, K, T>().is_some() || !elements.is_empty();
    let tangent_rows = |k: usize| (0..T).filter(move |&r| S::TANGENT_OF[r] == k);
    // The last step's impulses of each contact, to start the next step's solver from.
    let mut warm: Vec<Vec<f64>> = vec![Vec::new(); K];
    let zero_forces = vec![0.0; K + T + elements.len()];
    let row = |q: &SVector<f64, N>, v: &SVector<f64, N>, f: &[f64]| -> Vec<f64> {
        q.iter().chain(v.iter()).chain(f.iter()).copied().collect()
    };
    let derivative = |v: &SVector<f64, N>, dv: &SVector<f64, N>| -> Vec<f64> {
        let mut d: Vec<f64> = v.iter().chain(dv.iter()).copied().collect();
        d.resize(2 * N + K + T + n_elements, 0.0);
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
        // A contact stuck over the last step holds within its static cone this step; any
        // other, the kinetic one.
        let mu: [f64; K] = std::array::from_fn(|k| {
            if modes[k] == Mode::Stick {
                mu_static[k]
            } else {
                mu_kinetic[k]
            }
        });
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
        let acting = acting_elements(&elements, &q, &v_free, hn);
        let v_d = DVector::from_iterator(N, v.iter().copied());
        let mut v_next = v_free;
        let mut forces = vec![0.0; K + T + elements.len()];
        let mut new_modes = [Mode::Free; K];
        let element_modes_before = element_modes.clone();
        for (i, m) in element_modes.iter_mut().enumerate() {
            if !acting.iter().any(|&(el, _, _)| el == i) {
                *m = Mode::Free;
            }
        }
        if !active.is_empty() || !acting.is_empty() {
            let Some(w) = factor::spd_inverse(factor::dynamic(&scene.mass_matrix(&q))) else {
                return Err(SolveError::new(
                    ErrorKind::IllPosedMode {
                        t,
                        detail: "the mass matrix is not positive definite".into(),
                    },
                    sol,
                ));
            };
            let v_free_d = DVector::from_iterator(N, v_free.iter().copied());
            if general {
                let rows_of = |k: usize| cone::contact_rows(&w_n, &w_t, k, tangent_rows(k));
                // The local problems: the contacts that may close, then the elements that
                // act in the step.
                let mut locals: Vec<ConeContact> = active
                    .iter()
                    .map(|&k| ConeContact {
                        rows: rows_of(k),
                        gamma: -e[k] * vn[k].min(0.0),
                        mu: mu[k],
                        friction: None,
                    })
                    .collect();
                locals.extend(acting.iter().map(|&(i, ref row, law)| match law {
                    Some(friction) => ConeContact {
                        rows: vec![row.clone()],
                        gamma: 0.0,
                        mu: 0.0,
                        friction: Some(friction),
                    },
                    None => ConeContact {
                        rows: vec![row.clone()],
                        gamma: -stop_restitution(&elements[i]) * row.dot(&v_d).min(0.0),
                        mu: 0.0,
                        friction: None,
                    },
                }));
                let mut start: Vec<Vec<f64>> = active
                    .iter()
                    .map(|&k| warm[k].clone())
                    .chain(acting.iter().map(|&(i, _, _)| warm_elements[i].clone()))
                    .collect();
                // With bearing friction, solved again with the limits of the loads of the
                // motion found, until they settle.
                let mut solves = 0;
                let out = loop {
                    let out = match cone::solve(
                        &w,
                        &v_free_d,
                        &locals,
                        &start,
                        CONE_TOLERANCE,
                        CONE_SWEEPS,
                    ) {
                        Ok(out) => out,
                        Err(cone::NoLocalSolution { contact }) => {
                            let detail = format!(
                                "the contact problem of `{}` has no solution: its friction \
                                 drives it into the plane in every sliding direction",
                                S::CONTACTS[active[contact]]
                            );
                            return Err(SolveError::new(
                                ErrorKind::IllPosedMode { t, detail },
                                sol,
                            ));
                        }
                    };
                    if bearings.is_empty() {
                        break out;
                    }
                    sol.stats.contact_sweeps += out.sweeps;
                    let v_try = SVector::<f64, N>::from_iterator(out.velocity.iter().copied());
                    // The smooth part is explicit: the loads at (q, v) with the step's
                    // mean acceleration.
                    let (v_at, a_step) = bearing::motion(&v, &v_try, hn, 0.0);
                    let change = match bearings
                        .update(|out| scene.joint_bearing_limits(&q, &v_at, &a_step, out))
                    {
                        Ok(change) => change,
                        Err(e) => {
                            let component = 2 * N + K + T + e;
                            let kind = ErrorKind::NonFinite { t, component };
                            return Err(SolveError::new(kind, sol));
                        }
                    };
                    for (e, limit) in bearings.limits() {
                        bearing::set_limit(&mut elements[e], limit);
                        if let Some(j) = acting.iter().position(|&(el, _, _)| el == e) {
                            locals[active.len() + j].friction = friction_of(&elements[e], hn);
                        }
                    }
                    if change <= BEARING_TOL {
                        break out;
                    }
                    solves += 1;
                    if solves == BEARING_ITERATIONS {
                        let loaded: Vec<&str> = bearings
                            .elements
                            .iter()
                            .map(|&e| elements[e].name)
                            .collect();
                        let detail = bearing::unsettled(&loaded, BEARING_ITERATIONS);
                        let kind = ErrorKind::StepNotSolved { t, detail };
                        return Err(SolveError::new(kind, sol));
                    }
                    start = out.impulses;
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
                    let inside = friction < mu[k] * p[0] * (1.0 - CONE_EDGE);
                    let stuck = cone::is_stuck(p, &out.local[i], mu[k], slip_tol);
                    new_modes[k] = if p[0] <= 0.0 {
                        Mode::Free
                    } else if stuck {
                        Mode::Stick
                    } else if tangent_rows(k).count() == 1 && out.local[i][1] < 0.0 {
                        Mode::SlipNeg(0)
                    } else {
                        Mode::SlipPos(0)
                    };
                    if p[0] > 0.0 && locals[i].gamma == 0.0 {
                        holding.push(locals[i].rows[0].clone());
                        if stuck && inside {
                            holding.extend(locals[i].rows[1..].iter().cloned());
                        }
                    }
                    // The next step starts from these impulses; a sliding contact's from
                    // its normal one only, so that where redundant frictions (two stuck
                    // contacts, a contact and a joint's friction) come to rest together
                    // they do not keep the opposite pair of forces that stopped them.
                    warm[k] = p.clone();
                    if !stuck {
                        warm[k][1..].iter_mut().for_each(|x| *x = 0.0);
                    }
                }
                for (j, &(el, ref row, _)) in acting.iter().enumerate() {
                    let i = active.len() + j;
                    let law = locals[i].friction;
                    let (p, u) = (out.impulses[i][0], out.local[i][0]);
                    // Sliding, the next step starts its friction from zero (as a
                    // contact's above).
                    warm_elements[el] = vec![if law.is_some() && u != 0.0 { 0.0 } else { p }];
                    match law {
                        Some(friction) => {
                            // The element's force resists: the momentum gets −f h.
                            forces[K + T + el] = -p / hn;
                            let stuck =
                                u.abs() <= slip_tol || p.abs() < friction.stick * (1.0 - CONE_EDGE);
                            element_modes[el] = if stuck {
                                Mode::Stick
                            } else if u > 0.0 {
                                Mode::SlipPos(0)
                            } else {
                                Mode::SlipNeg(0)
                            };
                            if stuck {
                                holding.push(row.clone());
                            }
                        }
                        None => {
                            // A stop pushes its coordinate back: `f = side · λ`.
                            forces[K + T + el] = -row.sum() * p / hn;
                            element_modes[el] = if p > 0.0 { Mode::Contact } else { Mode::Free };
                            if p > 0.0 && locals[i].gamma == 0.0 {
                                holding.push(row.clone());
                            }
                        }
                    }
                }
                if locks::<N>(&holding) {
                    v_next = SVector::zeros();
                }
            } else {
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
        let mut q_next = q + v_next * hn;
        // Closed contacts drift into their planes at second order per step where the
        // motion turns (the velocity law holds their rows, not their gaps): a gap below
        // its plane beyond round-off is lifted back by the least change of the
        // coordinates in the mass metric, the velocities kept (a position projection).
        lift_sunk(scene, &mut q_next);
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
        // The switches of the step: contacts, then joint elements (index K + e), each
        // an impact where it closed against an approach.
        let mut log =
            |name: &str, index: usize, (from, to): (Mode, Mode), impact: bool, impulse: f64| {
                let kind = if impact {
                    SwitchKind::Impact
                } else {
                    SwitchKind::Mode
                };
                let mut s =
                    Switch::of_run(t_next, kind, row(&q, &v, &[]), row(&q_next, &v_next, &[]));
                s.element = Some(name.to_string());
                s.index = Some(index);
                s.from = Some(from);
                s.to = Some(to);
                s.jump = impulse;
                sol.switches.push(s);
            };
        for k in (0..K).filter(|&k| new_modes[k] != modes[k]) {
            let impact = modes[k] == Mode::Free && vn[k] < 0.0 && forces[k] > 0.0;
            log(
                S::CONTACTS[k],
                k,
                (modes[k], new_modes[k]),
                impact,
                forces[k] * hn,
            );
        }
        for (i, el) in elements.iter().enumerate() {
            let (from, to) = (element_modes_before[i], element_modes[i]);
            if from != to {
                let impact = from == Mode::Free && to == Mode::Contact;
                log(el.name, K + i, (from, to), impact, forces[K + T + i] * hn);
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
