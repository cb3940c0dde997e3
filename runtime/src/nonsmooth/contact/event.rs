//! Event-driven integration of contacts (theory §8): each contact open, stuck or
//! sliding; the smooth motion of the current modes integrated by any method, kept on
//! their constraints by projection; switches located on the dense output and decided by
//! the contact problem ([`super::planar`] for planar contacts; for spatial ones the modes
//! as they are, else a short step of [`super::cone`]).
//!
//! In a mode the closed contacts' normal rows and the stuck ones' tangential rows are
//! equality constraints at acceleration level (`W v̇ = γ`), a sliding contact's force
//! `λ_N (w_N − μ s w_T)` (spatial: `s` the current slip direction in its two tangent
//! rows). The forces solve `C W D λ = γ − C a₀` (`C` the constraint rows, `D` the force
//! directions, `W = M⁻¹`; least norm where redundant contacts leave the split open,
//! redundant stuck frictions shared in proportion to `μ_s λ_N`). After every step the state is projected back onto the closed
//! contacts' gaps and the constrained velocities (in the mass metric); where the
//! constraints lock every coordinate, the velocity is set to exactly zero.
//!
//! The switching functions, positive while the mode holds: an open contact's gap; a
//! closed one's `λ_N`; a stuck one's `μ λ_N − |λ_T|`; a sliding one's slip along its
//! direction when the mode began. At a switch: an impact (a contact closing at speed) takes the velocity-level
//! problem (Newton's law with Coulomb's cone on the impulses); a rebound too small to
//! leave the position tolerance is taken as settled (the Zeno limit of its bounces);
//! then the modes are chosen by the acceleration-level problem.

use nalgebra::{DMatrix, DVector, SVector};

use super::cone::{self, CONE_SWEEPS, CONE_TOLERANCE, ConeContact, SLIP_ROUND_OFF};
use super::planar::{self, Closed, ContactError};
use crate::contacts::Contacts;
use crate::element::Mode;
use crate::input::Input;
use crate::method::{Begin, Eval, Method, Stepper};
use crate::nonsmooth::NonSmoothProblem;
use crate::numerics::factor;
use crate::numerics::rootfind::find_root;
use crate::system::Mechanism;
use crate::{ErrorKind, Keep, OdeSystem, Solution, SolveError, Switch, SwitchKind};

/// A constraint row of a mode: the row, its `γ`, its contact, and which of the contact's
/// rows it is (`0` normal, `1` and `2` tangents).
type Row = (DVector<f64>, f64, usize, u8);

/// A contact's mode.
#[derive(Clone, Copy, Debug, PartialEq)]
enum CMode {
    Open,
    Stick,
    /// Sliding with slip sign `s` (a planar contact).
    Slip(f64),
    /// Sliding (a spatial contact): its friction opposes the current slip velocity; `d`,
    /// the slip's direction in its two tangent rows when the mode began, is where its
    /// switching function `d · u_T` looks for the slip to stop.
    Slide([f64; 2]),
}

impl CMode {
    fn element_mode(self) -> Mode {
        match self {
            CMode::Open => Mode::Free,
            CMode::Stick => Mode::Stick,
            CMode::Slip(s) if s > 0.0 => Mode::SlipPos(0),
            CMode::Slip(_) => Mode::SlipNeg(0),
            CMode::Slide(_) => Mode::SlipPos(0),
        }
    }
    /// The same mode (a slide in the same sense: a new direction is not a switch).
    fn same(self, other: CMode) -> bool {
        match (self, other) {
            (CMode::Slide(a), CMode::Slide(b)) => a[0] * b[0] + a[1] * b[1] > 0.0,
            (a, b) => a == b,
        }
    }
    fn closed(self) -> bool {
        self != CMode::Open
    }
}

/// The scene in one assignment of modes, as an [`OdeSystem`].
struct InMode<'a, S, I: ?Sized, const N: usize, const K: usize, const T: usize> {
    scene: &'a S,
    input: &'a I,
    modes: [CMode; K],
    /// Kinetic friction coefficients (sliding contacts carry `μ λ_N`).
    mu: [f64; K],
    /// Static ones (a stuck contact holds while `|λ_T| ≤ μ_s λ_N`).
    mu_static: [f64; K],
    /// The first tangent row of each contact.
    tangent: [Option<usize>; K],
    /// The second tangent row of each spatial contact.
    second: [Option<usize>; K],
}

/// Accelerations and forces at a state: `v̇`, and per contact `(λ_N, λ_T)` (`λ_T` along
/// the first tangent row, `tangent2` along a spatial contact's second).
struct Dynamics<const N: usize, const K: usize> {
    a: SVector<f64, N>,
    normal: [f64; K],
    tangent: [f64; K],
    tangent2: [f64; K],
}

impl<const N: usize, const K: usize> Dynamics<N, K> {
    /// `|λ_T|` of contact `k`.
    fn friction(&self, k: usize) -> f64 {
        self.tangent[k].hypot(self.tangent2[k])
    }
}

impl<S, I, const N: usize, const K: usize, const T: usize> InMode<'_, S, I, N, K, T>
where
    S: Mechanism<N> + Contacts<N, K, T>,
    I: Input<N> + ?Sized,
{
    fn split(y: &[f64]) -> (SVector<f64, N>, SVector<f64, N>) {
        (
            SVector::from_column_slice(&y[..N]),
            SVector::from_column_slice(&y[N..2 * N]),
        )
    }

    fn inverse_mass(&self, q: &SVector<f64, N>) -> DMatrix<f64> {
        factor::inverse(factor::dynamic(&self.scene.mass_matrix(q)))
            .unwrap_or_else(|| DMatrix::from_element(N, N, f64::NAN))
    }

    /// The scale of the contact forces at a switch of the `candidates`: the largest of
    /// the forces `d` and, for each contact, the force whose acceleration (in the mass
    /// metric) is that of the free motion: `√(a_freeᵀ M a_free / (W_N,k M⁻¹ W_N,kᵀ))`
    /// (`m g` for a body resting on the ground). The forces alone are no scale where the
    /// one closed contact's force passes through zero, and neither is the free normal
    /// acceleration, zero there too.
    fn force_scale(
        &self,
        t: f64,
        q: &SVector<f64, N>,
        v: &SVector<f64, N>,
        candidates: &[usize],
        d: &Dynamics<N, K>,
    ) -> f64 {
        let w = self.inverse_mass(q);
        let w_n = self.scene.contact_normal_jacobian(q);
        let a_free = self
            .scene
            .forward_dynamics(q, v, &self.input.forces(t, q, v));
        let free = a_free.dot(&(self.scene.mass_matrix(q) * a_free));
        let alone = candidates.iter().map(|&k| {
            let r = DVector::from_iterator(N, w_n.row(k).iter().copied());
            (free / r.dot(&(&w * &r)).max(f64::MIN_POSITIVE)).sqrt()
        });
        (0..K)
            .map(|k| d.normal[k].abs().max(d.friction(k)))
            .chain(alone)
            .filter(|x| x.is_finite())
            .fold(0.0f64, f64::max)
    }

    /// The constraint rows of the current modes: `(row, γ)` and, per row, which contact
    /// and which of its rows (`0` normal, `1` and `2` its tangents).
    fn constraints(&self, q: &SVector<f64, N>, v: &SVector<f64, N>) -> Vec<Row> {
        let w_n = self.scene.contact_normal_jacobian(q);
        let w_t = self.scene.contact_tangent_jacobian(q);
        let g_n = self.scene.contact_normal_gamma(q, v);
        let g_t = self.scene.contact_tangent_gamma(q, v);
        let mut rows = Vec::new();
        for k in 0..K {
            if self.modes[k].closed() {
                rows.push((
                    DVector::from_iterator(N, w_n.row(k).iter().copied()),
                    g_n[k],
                    k,
                    0,
                ));
            }
            if self.modes[k] == CMode::Stick {
                for (j, r) in [self.tangent[k], self.second[k]].into_iter().enumerate() {
                    if let Some(r) = r {
                        rows.push((
                            DVector::from_iterator(N, w_t.row(r).iter().copied()),
                            g_t[r],
                            k,
                            j as u8 + 1,
                        ));
                    }
                }
            }
        }
        rows
    }

    fn dynamics(&self, t: f64, q: &SVector<f64, N>, v: &SVector<f64, N>) -> Dynamics<N, K> {
        let tau = self.input.forces(t, q, v);
        let a0 = self.scene.forward_dynamics(q, v, &tau);
        let rows = self.constraints(q, v);
        let mut out = Dynamics {
            a: a0,
            normal: [0.0; K],
            tangent: [0.0; K],
            tangent2: [0.0; K],
        };
        if rows.is_empty() {
            return out;
        }
        let w = self.inverse_mass(q);
        let w_t = self.scene.contact_tangent_jacobian(q);
        // Force directions: the rows themselves, a sliding contact's normal less its
        // friction.
        let slides: [[f64; 2]; K] = std::array::from_fn(|k| self.slide_direction(k, &w_t, v));
        let dirs: Vec<DVector<f64>> = rows
            .iter()
            .map(|(row, _, k, which)| match (self.modes[*k], which) {
                (CMode::Slip(s), 0) => {
                    let r = self.tangent[*k].expect("a sliding contact has a tangent");
                    let wt = DVector::from_iterator(N, w_t.row(r).iter().copied());
                    row - wt * (self.mu[*k] * s)
                }
                (CMode::Slide(_), 0) => {
                    let mut dir = row.clone();
                    let d = slides[*k];
                    for (r, dj) in [self.tangent[*k], self.second[*k]].into_iter().zip(d) {
                        if let Some(r) = r {
                            for (i, x) in dir.iter_mut().enumerate() {
                                *x -= self.mu[*k] * dj * w_t[(r, i)];
                            }
                        }
                    }
                    dir
                }
                _ => row.clone(),
            })
            .collect();
        let effect: Vec<DVector<f64>> = dirs.iter().map(|d| &w * d).collect();
        let m = rows.len();
        let a0d = DVector::from_iterator(N, a0.iter().copied());
        let lhs = DMatrix::from_fn(m, m, |i, j| rows[i].0.dot(&effect[j]));
        let rhs = DVector::from_fn(m, |i, _| rows[i].1 - rows[i].0.dot(&a0d));
        let lambda = factor::least_squares(lhs, &rhs, 1e-12)
            .unwrap_or_else(|| DVector::from_element(m, f64::NAN));
        let lambda = self.share_friction(&rows, lambda);
        let mut a = a0d;
        for (j, (_, _, k, which)) in rows.iter().enumerate() {
            a += &effect[j] * lambda[j];
            match which {
                1 => out.tangent[*k] = lambda[j],
                2 => out.tangent2[*k] = lambda[j],
                _ => {
                    out.normal[*k] = lambda[j];
                    match self.modes[*k] {
                        CMode::Slip(s) => out.tangent[*k] = -self.mu[*k] * s * lambda[j],
                        CMode::Slide(_) => {
                            let d = slides[*k];
                            out.tangent[*k] = -self.mu[*k] * d[0] * lambda[j];
                            out.tangent2[*k] = -self.mu[*k] * d[1] * lambda[j];
                        }
                        _ => {}
                    }
                }
            }
        }
        out.a = SVector::from_iterator(a.iter().copied());
        if self.locks(&rows) {
            // Locked: the accelerations are the constraints' own, `C v̇ = γ` (zero at
            // rest, exactly), not the round-off of the forces' solve.
            let c = DMatrix::from_fn(m, N, |i, j| rows[i].0[j]);
            let gamma = DVector::from_fn(m, |i, _| rows[i].1);
            if let Some(x) = factor::least_squares(c, &gamma, 0.0) {
                out.a = SVector::from_iterator(x.iter().copied());
            }
        }
        out
    }

    /// Redundant stuck frictions (contacts whose tangential rows are dependent: a box's
    /// two corners on the ground) leave the split of their forces open; the least-norm
    /// split would share them equally, and a contact with the smaller normal force
    /// would leave its cone (its switching function negative) while the group is still
    /// inside theirs together. The forces are moved within the split left open (the
    /// null space of the tangential rows) to the one proportional to each contact's
    /// `μ_s λ_N` — a weighted least norm — so that the contacts of a group reach their
    /// cones' edges together, exactly when the group does.
    fn share_friction(&self, rows: &[Row], mut lambda: DVector<f64>) -> DVector<f64> {
        let stuck: Vec<usize> = (0..rows.len()).filter(|&j| rows[j].3 > 0).collect();
        if stuck.len() < 2 {
            return lambda;
        }
        let m = stuck.len();
        let gram = DMatrix::from_fn(m, m, |a, b| rows[stuck[a]].0.dot(&rows[stuck[b]].0));
        let eig = factor::symmetric_eigen(gram);
        let top = eig.eigenvalues.amax();
        let null: Vec<usize> = (0..m)
            .filter(|&i| eig.eigenvalues[i] <= 1e-12 * top)
            .collect();
        if null.is_empty() {
            return lambda;
        }
        let z = DMatrix::from_fn(m, null.len(), |a, b| eig.eigenvectors[(a, null[b])]);
        // Weights μ_s λ_N of each stuck row's contact (its normal row's force).
        let normal = |k: usize| {
            (0..rows.len())
                .find(|&j| rows[j].2 == k && rows[j].3 == 0)
                .map_or(0.0, |j| lambda[j])
        };
        let weight: Vec<f64> = stuck
            .iter()
            .map(|&j| self.mu_static[rows[j].2] * normal(rows[j].2))
            .collect();
        let floor = 1e-12
            * weight
                .iter()
                .fold(f64::MIN_POSITIVE, |a, &b| a.max(b.abs()));
        let inv = DVector::from_iterator(m, weight.iter().map(|w| 1.0 / w.max(floor)));
        let lt = DVector::from_iterator(m, stuck.iter().map(|&j| lambda[j]));
        let zw = DMatrix::from_fn(m, null.len(), |a, b| z[(a, b)] * inv[a]);
        let lhs = z.transpose() * &zw;
        let rhs = -(zw.transpose() * &lt);
        if let Some(c) = factor::cholesky_solve(lhs, &rhs) {
            let shift = &z * c;
            for (a, &j) in stuck.iter().enumerate() {
                lambda[j] += shift[a];
            }
        }
        lambda
    }

    /// Contact `k`'s rows: its normal, then its tangents.
    fn rows_of(
        &self,
        k: usize,
        w_n: &nalgebra::SMatrix<f64, K, N>,
        w_t: &nalgebra::SMatrix<f64, T, N>,
    ) -> Vec<DVector<f64>> {
        let tangents = [self.tangent[k], self.second[k]].into_iter().flatten();
        cone::contact_rows(w_n, w_t, k, tangents)
    }

    /// The same scene in other modes.
    fn with_modes(&self, modes: [CMode; K]) -> Self {
        InMode {
            scene: self.scene,
            input: self.input,
            modes,
            mu: self.mu,
            mu_static: self.mu_static,
            tangent: self.tangent,
            second: self.second,
        }
    }

    /// The direction a sliding spatial contact's friction opposes: its slip velocity's,
    /// in its tangent rows; the mode's own direction where the slip is zero to
    /// round-off.
    fn slide_direction(
        &self,
        k: usize,
        w_t: &nalgebra::SMatrix<f64, T, N>,
        v: &SVector<f64, N>,
    ) -> [f64; 2] {
        let CMode::Slide(d) = self.modes[k] else {
            return [0.0; 2];
        };
        let u = [self.tangent[k], self.second[k]]
            .map(|r| r.map_or(0.0, |r| w_t.row(r).dot(&v.transpose())));
        let norm = u[0].hypot(u[1]);
        if norm > 1e-14 * v.amax() {
            [u[0] / norm, u[1] / norm]
        } else {
            d
        }
    }

    /// Whether the constraint rows span every coordinate (the state is locked).
    fn locks(&self, rows: &[Row]) -> bool {
        if rows.len() < N {
            return false;
        }
        let c = DMatrix::from_fn(rows.len(), N, |i, j| rows[i].0[j]);
        factor::full_column_rank(&c, 1e-10)
    }

    /// Onto the closed contacts' gaps (Newton steps, least change in the mass metric)
    /// and the constrained velocities; locked, the velocity is exactly zero.
    fn project_state(&self, q: &mut SVector<f64, N>, v: &mut SVector<f64, N>, tol: f64) {
        let closed: Vec<usize> = (0..K).filter(|&k| self.modes[k].closed()).collect();
        if closed.is_empty() {
            return;
        }
        for _ in 0..4 {
            let gaps = self.scene.contact_gaps(q);
            if closed.iter().all(|&k| gaps[k].abs() <= tol) {
                break;
            }
            let w = self.inverse_mass(q);
            let w_n = self.scene.contact_normal_jacobian(q);
            let g = DMatrix::from_fn(closed.len(), N, |i, j| w_n[(closed[i], j)]);
            let r = DVector::from_fn(closed.len(), |i, _| gaps[closed[i]]);
            let Some(dq) = factor::least_change(&g, &w, &r) else {
                break;
            };
            *q -= SVector::<f64, N>::from_iterator(dq.iter().copied());
        }
        let rows = self.constraints(q, v);
        if self.locks(&rows) {
            *v = SVector::zeros();
            return;
        }
        let w = self.inverse_mass(q);
        let c = DMatrix::from_fn(rows.len(), N, |i, j| rows[i].0[j]);
        let vd = DVector::from_iterator(N, v.iter().copied());
        let r = &c * &vd;
        if let Some(dv) = factor::least_change(&c, &w, &r) {
            *v -= SVector::<f64, N>::from_iterator(dv.iter().copied());
        }
    }

    /// The switching functions (positive while the modes hold), one per contact.
    fn switching(&self, t: f64, y: &[f64]) -> [f64; K] {
        let (q, v) = Self::split(y);
        let d = self.dynamics(t, &q, &v);
        let gaps = self.scene.contact_gaps(&q);
        let slips = self.scene.contact_tangent_jacobian(&q) * v;
        std::array::from_fn(|k| match self.modes[k] {
            CMode::Open => gaps[k],
            CMode::Stick => d.normal[k].min(self.mu_static[k] * d.normal[k] - d.friction(k)),
            CMode::Slip(s) => d.normal[k].min(s * self.tangent[k].map_or(0.0, |r| slips[r])),
            CMode::Slide(s) => {
                let u = [self.tangent[k], self.second[k]].map(|r| r.map_or(0.0, |r| slips[r]));
                d.normal[k].min(s[0] * u[0] + s[1] * u[1])
            }
        })
    }
}

impl<S, I, const N: usize, const K: usize, const T: usize> OdeSystem for InMode<'_, S, I, N, K, T>
where
    S: Mechanism<N> + Contacts<N, K, T>,
    I: Input<N> + ?Sized,
{
    fn dim(&self) -> usize {
        2 * N
    }
    fn rhs(&self, t: f64, y: &[f64], dy: &mut [f64]) {
        let (q, v) = Self::split(y);
        let d = self.dynamics(t, &q, &v);
        dy[..N].copy_from_slice(v.as_slice());
        dy[N..].copy_from_slice(d.a.as_slice());
    }
    fn second_order(&self) -> Option<usize> {
        Some(N)
    }
    fn dense_positions(&self) -> bool {
        true
    }
}

/// Integrates `scene` with its contacts event-driven with `method` (see the module
/// documentation; spatial contacts where their slips stop along a fixed direction, theory
/// §8): the same columns as
/// [`contact_time_stepping`](super::stepping::contact_time_stepping), the forces at each
/// row, and a switch log.
///
/// # Errors
/// As [`contact_time_stepping`](super::stepping::contact_time_stepping), and
/// [`ErrorKind::IllPosedMode`] naming the contacts where no consistent set of modes
/// exists or several do (Painlevé's paradox), with the rows up to there kept.
pub fn contact_event_driven<S, I, const N: usize, const K: usize, const T: usize>(
    scene: &S,
    input: &I,
    problem: &NonSmoothProblem<N>,
    method: &Method,
) -> Result<Solution, SolveError>
where
    S: Mechanism<N> + Contacts<N, K, T>,
    I: Input<N> + ?Sized,
{
    let mut sol = Solution::new(
        super::stepping::column_names::<S, N, K, T>(),
        2 * N,
        problem.output.clone(),
    )
    .with_dense_positions(Some(N));
    if let Err(msg) = super::stepping::check::<S, N, K, T>(scene, problem) {
        return Err(SolveError::new(ErrorKind::InvalidInput(msg), sol));
    }
    let elements = scene.joint_elements();
    if !elements.is_empty() {
        let names: Vec<String> = elements.iter().map(|el| format!("`{}`", el.name)).collect();
        let msg = format!(
            "the scene has joint elements ({}) beside its contacts; the event-driven contact \
             integrator does not integrate them yet: integrate the scene with \
             `contact_time_stepping`, which takes both",
            names.join(", ")
        );
        return Err(SolveError::new(ErrorKind::InvalidInput(msg), sol));
    }
    let mut stepper = method.stepper(2 * N);
    let options = stepper.options();
    let tangent: [Option<usize>; K] =
        std::array::from_fn(|k| S::TANGENT_OF.iter().position(|&c| c == k));
    let second: [Option<usize>; K] =
        std::array::from_fn(|k| (0..T).filter(|&r| S::TANGENT_OF[r] == k).nth(1));
    let mut sys = InMode {
        scene,
        input,
        modes: [CMode::Open; K],
        mu: scene.contact_friction(),
        mu_static: scene.contact_static_friction(),
        tangent,
        second,
    };
    let e = scene.contact_restitution();
    let (mut t, tf) = (problem.t0, problem.tf);
    let mut y: Vec<f64> = problem
        .q0
        .iter()
        .chain(problem.v0.iter())
        .copied()
        .collect();
    let tol_q = |q: f64| options.atol + options.rtol * q.abs();
    let run = (|| -> Result<(), ErrorKind> {
        // Start: the contacts touching the ground choose their modes (an impact if
        // approaching).
        let mut armed = [true; K];
        let mut dy = vec![0.0; 2 * N];
        sys.rhs(t, &y, &mut dy);
        let mut first = y.clone();
        first.extend(std::iter::repeat_n(0.0, K + T));
        dy.resize(first.len(), 0.0);
        sol.push_start(t, &first, &dy);
        // Steps end no later than this: the apex of the latest rebound, where its gap
        // is back above its level and armed for the next landing.
        let mut until = switch(&mut sys, &e, t, &mut y, &mut sol, &options, &mut armed)?;
        let mut fresh = true;
        loop {
            let at = Begin {
                t,
                y: &y,
                span: tf - t,
                fresh,
            };
            stepper.begin(&mut Eval::new(&sys, &mut sol.stats), at)?;
            fresh = false;
            let mut switched = false;
            while stepper.t() < tf {
                let t0 = stepper.t();
                let g0 = sys.switching(t0, stepper.y());
                // A function that starts a step above its level is armed (one that a
                // switch left at its level waits until it has left it).
                for k in 0..K {
                    if !armed[k] && g0[k] > options.atol {
                        armed[k] = true;
                    }
                }
                let target = if until > t0 { until.min(tf) } else { tf };
                stepper.step(&mut Eval::new(&sys, &mut sol.stats), target)?;
                let t1 = stepper.t();
                // Back onto the modes' constraints.
                let mut y1 = stepper.y().to_vec();
                let (mut q, mut v) = InMode::<S, I, N, K, T>::split(&y1);
                let scale = q.amax().max(1.0);
                sys.project_state(&mut q, &mut v, tol_q(scale) * 1e-3);
                y1[..N].copy_from_slice(q.as_slice());
                y1[N..].copy_from_slice(v.as_slice());
                if y1 != stepper.y() {
                    stepper.nudge(&mut Eval::new(&sys, &mut sol.stats), &y1)?;
                }
                let g1 = sys.switching(t1, stepper.y());
                for k in 0..K {
                    // A function is armed again once it exceeds the absolute tolerance.
                    if !armed[k] && g1[k] > options.atol {
                        armed[k] = true;
                    }
                }
                stepper.prepare_dense();
                let dense = stepper.dense().clone();
                let mut buf = vec![0.0; 2 * N];
                // Each function at or below its level at the step's end: a crossing from
                // the step's start if armed there; else, a function that left its level
                // inside the step and came back (a small rebound over in one step) is
                // found by sampling the dense output, and its crossing is after the last
                // sample above the level.
                let mut brackets: Vec<(usize, f64, f64, f64)> = Vec::new();
                for k in (0..K).filter(|&k| g1[k] <= 0.0) {
                    if armed[k] && g0[k] > 0.0 {
                        brackets.push((k, t0, g0[k], 0.0));
                        continue;
                    }
                    // An open contact going into its plane beyond the position tolerance
                    // without having left it (a contact that opened at rest and is
                    // pressed back): a landing where it passes the tolerance.
                    if sys.modes[k] == CMode::Open {
                        let tol =
                            tol_q(stepper.y()[..N].iter().fold(1.0f64, |m, x| m.max(x.abs())));
                        if g1[k] < -tol && g0[k] > -tol {
                            brackets.push((k, t0, g0[k] + tol, tol));
                            continue;
                        }
                    }
                    let level = options.atol;
                    let above = (1..SAMPLES).rev().find_map(|j| {
                        let s = t0 + (t1 - t0) * j as f64 / SAMPLES as f64;
                        dense.eval(s, &mut buf);
                        let g = sys.switching(s, &buf)[k];
                        (g > level).then_some((s, g))
                    });
                    if let Some((s, g)) = above {
                        armed[k] = true;
                        brackets.push((k, s, g, 0.0));
                    }
                }
                if brackets.is_empty() {
                    push(
                        &sys,
                        &mut sol,
                        t1,
                        stepper.y(),
                        Some(&dense),
                        if t1 >= tf { Keep::Last } else { Keep::AsAsked },
                    );
                    continue;
                }
                // The earliest root among the crossing functions, on the dense output.
                let mut first = (t1, 0usize);
                for &(k, a, ga, shift) in &brackets {
                    let mut gk = |s: f64| {
                        dense.eval(s, &mut buf);
                        sys.switching(s, &buf)[k] + shift
                    };
                    let xtol = 4.0 * f64::EPSILON * t1.abs().max(1.0);
                    let br = find_root(&mut gk, a, t1, ga, g1[k] + shift, xtol);
                    if br.hi < first.0 {
                        first = (br.hi, k);
                    }
                }
                let te = first.0;
                let mut cut = dense.clone();
                cut.truncate(te);
                let mut ye = vec![0.0; 2 * N];
                cut.eval(te, &mut ye);
                // The located state back on its modes' constraints: the dense output
                // keeps them only to the method's accuracy, and an impact's outcome
                // depends on the velocities it meets.
                let (mut qe, mut ve) = InMode::<S, I, N, K, T>::split(&ye);
                let tol = tol_q(qe.amax().max(1.0)) * 1e-3;
                sys.project_state(&mut qe, &mut ve, tol);
                ye[..N].copy_from_slice(qe.as_slice());
                ye[N..].copy_from_slice(ve.as_slice());
                push(&sys, &mut sol, te, &ye, Some(&cut), Keep::Event);
                t = te;
                y = ye;
                // Switches count against the step budget: an accumulation the rules
                // above do not end is stopped, not followed for ever.
                sol.stats.events += 1;
                if sol.stats.steps + sol.stats.events > options.max_steps {
                    return Err(ErrorKind::MaxSteps { t });
                }
                until = switch(&mut sys, &e, t, &mut y, &mut sol, &options, &mut armed)?;
                switched = true;
                break;
            }
            if !switched {
                return Ok(());
            }
            if t >= tf {
                push(&sys, &mut sol, t, &y, None, Keep::Last);
                return Ok(());
            }
        }
    })();
    // Steps that shrink to nothing while spatial contacts slide: a slip whose direction
    // turns as it stops (a body spinning as it slides), where the friction's direction
    // has no limit; said as such, with the way through.
    let sliding: Vec<String> = (0..K)
        .filter(|&k| matches!(sys.modes[k], CMode::Slide(_)))
        .map(|k| format!("`{}`", S::CONTACTS[k]))
        .collect();
    let run = run.map_err(|kind| match kind {
        ErrorKind::MaxSteps { t } | ErrorKind::StepSizeUnderflow { t, .. }
            if !sliding.is_empty() =>
        {
            ErrorKind::IllPosedMode {
                t,
                detail: format!(
                    "the steps shrank to nothing while the spatial contacts {} slide: a slip \
                     whose direction turns as it stops (a body spinning as it slides) is beyond \
                     the event-driven integrator, which follows slips that stop along a fixed \
                     direction; integrate the scene with `contact_time_stepping`",
                    sliding.join(", ")
                ),
            }
        }
        kind => kind,
    });
    match run {
        Ok(()) => Ok(sol),
        Err(kind) => Err(SolveError::new(kind, sol)),
    }
}

/// Inner samples of a step's dense output searched for a switching function that left
/// its level and came back within the step.
const SAMPLES: usize = 8;

/// The row of `(t, y)` in the current modes: the state, then the contacts' normal and
/// tangential forces; and its derivative (the forces' stored as zero).
fn row_of<S, I, const N: usize, const K: usize, const T: usize>(
    sys: &InMode<'_, S, I, N, K, T>,
    t: f64,
    y: &[f64],
) -> (Vec<f64>, Vec<f64>)
where
    S: Mechanism<N> + Contacts<N, K, T>,
    I: Input<N> + ?Sized,
{
    let (q, v) = InMode::<S, I, N, K, T>::split(y);
    let d = sys.dynamics(t, &q, &v);
    let mut row = y.to_vec();
    row.extend_from_slice(&d.normal);
    let mut tangential = [0.0; T];
    for k in 0..K {
        if let Some(r) = sys.tangent[k] {
            tangential[r] = d.tangent[k];
        }
        if let Some(r) = sys.second[k] {
            tangential[r] = d.tangent2[k];
        }
    }
    row.extend_from_slice(&tangential);
    let mut dy: Vec<f64> = v.iter().chain(d.a.iter()).copied().collect();
    dy.resize(row.len(), 0.0);
    (row, dy)
}

/// Appends the row of `(t, y)` after a step (see [`row_of`]).
fn push<S, I, const N: usize, const K: usize, const T: usize>(
    sys: &InMode<'_, S, I, N, K, T>,
    sol: &mut Solution,
    t: f64,
    y: &[f64],
    dense: Option<&crate::method::DenseStep>,
    keep: Keep,
) where
    S: Mechanism<N> + Contacts<N, K, T>,
    I: Input<N> + ?Sized,
{
    let (row, dy) = row_of(sys, t, y);
    sol.push_step(t, &row, &dy, dense, keep);
}

/// The row after a switch at `t`: the state and the forces of the new modes.
fn jump_row<S, I, const N: usize, const K: usize, const T: usize>(
    sys: &InMode<'_, S, I, N, K, T>,
    sol: &mut Solution,
    t: f64,
    y: &[f64],
) where
    S: Mechanism<N> + Contacts<N, K, T>,
    I: Input<N> + ?Sized,
{
    let (row, dy) = row_of(sys, t, y);
    sol.push_jump(t, &row, &dy);
}

/// At a switch at `(t, y)`: impacts first (velocity level), then the modes of the
/// contacts that touch (acceleration level); logs what changed and disarms the
/// functions that start at their switching level. Returns the time of the earliest
/// rebound's apex (`t` when there is none), which the next steps must not pass over.
#[allow(clippy::too_many_arguments)]
fn switch<S, I, const N: usize, const K: usize, const T: usize>(
    sys: &mut InMode<'_, S, I, N, K, T>,
    e: &[f64; K],
    t: f64,
    y: &mut Vec<f64>,
    sol: &mut Solution,
    options: &crate::Options,
    armed: &mut [bool; K],
) -> Result<f64, ErrorKind>
where
    S: Mechanism<N> + Contacts<N, K, T>,
    I: Input<N> + ?Sized,
{
    let (q, mut v) = InMode::<S, I, N, K, T>::split(y);
    let scene = sys.scene;
    let spatial = sys.second.iter().any(Option::is_some);
    let tol_x = |x: f64| options.atol + options.rtol * x.abs();
    let gaps = scene.contact_gaps(&q);
    let w_n = scene.contact_normal_jacobian(&q);
    let w_t = scene.contact_tangent_jacobian(&q);
    let scale_q = q.amax().max(1.0);
    let touching: Vec<usize> = (0..K).filter(|&k| gaps[k] <= tol_x(scale_q)).collect();
    let row = |m: &nalgebra::SMatrix<f64, K, N>, k: usize| {
        DVector::from_iterator(N, m.row(k).iter().copied())
    };
    let trow = |r: Option<usize>| match r {
        Some(r) => DVector::from_iterator(N, w_t.row(r).iter().copied()),
        None => DVector::zeros(N),
    };
    let old = sys.modes;
    let vn = w_n * v;
    let vn_before = vn;
    let v_scale = v.amax().max(1.0);
    let approaching: Vec<usize> = touching
        .iter()
        .copied()
        .filter(|&k| vn[k] < -tol_x(v_scale))
        .collect();
    let w = sys.inverse_mass(&q);
    let mut settled = [false; K];
    let mut impulses = [0.0; K];
    // The acceleration pressing each contact into its plane without contact forces.
    let tau = sys.input.forces(t, &q, &v);
    let a_free = scene.forward_dynamics(&q, &v, &tau);
    let pressing = -(w_n * a_free - scene.contact_normal_gamma(&q, &v));
    if !approaching.is_empty() {
        let before: Vec<f64> = y.clone();
        if spatial {
            // Spatial: Moreau's impact law on the exact cone (a settled rebound's normal
            // velocity held at zero), the impulses of the touching contacts at once.
            for &k in &touching {
                let rebound = e[k] * (-vn[k]).max(0.0);
                let settle =
                    pressing[k] > 0.0 && rebound * rebound <= 2.0 * pressing[k] * tol_x(scale_q);
                settled[k] = settle && vn[k] < 0.0;
            }
            let locals: Vec<ConeContact> = touching
                .iter()
                .map(|&k| ConeContact {
                    rows: sys.rows_of(k, &w_n, &w_t),
                    gamma: if settled[k] {
                        0.0
                    } else {
                        -e[k] * vn[k].min(0.0)
                    },
                    mu: sys.mu[k],
                    friction: None,
                })
                .collect();
            let vd = DVector::from_iterator(N, v.iter().copied());
            let out = cone::solve(&w, &vd, &locals, &[], CONE_TOLERANCE, CONE_SWEEPS)
                .map_err(|err| cone_ill_posed(t, touching[err.contact], &S::CONTACTS))?;
            v = SVector::from_iterator(out.velocity.iter().copied());
            for (i, &k) in touching.iter().enumerate() {
                impulses[k] = out.impulses[i][0];
            }
        } else {
            // Newton's law with Coulomb's cone on the impulses of the touching contacts.
            let closed: Vec<Closed> = touching
                .iter()
                .map(|&k| {
                    // A rebound that could not rise above the position tolerance under the
                    // pressing acceleration is taken as settled.
                    let rebound = e[k] * (-vn[k]).max(0.0);
                    let settle = pressing[k] > 0.0
                        && rebound * rebound <= 2.0 * pressing[k] * tol_x(scale_q);
                    settled[k] = settle && vn[k] < 0.0;
                    Closed {
                        normal: row(&w_n, k),
                        gamma_n: if settle { 0.0 } else { -e[k] * vn[k].min(0.0) },
                        tangent: trow(sys.tangent[k]),
                        gamma_t: 0.0,
                        mu: if sys.tangent[k].is_some() {
                            sys.mu[k]
                        } else {
                            0.0
                        },
                        sliding: None,
                    }
                })
                .collect();
            let vd = DVector::from_iterator(N, v.iter().copied());
            // A plastic impact that can hold every touching contact does (the contact
            // problem of redundant contacts has other solutions too); else the problem
            // decides which rebound, stick or slide.
            let plastic = closed.iter().all(|c| c.gamma_n == 0.0);
            // Holding every contact needs its impulses in the static cones.
            let static_cones: Vec<Closed> = closed
                .iter()
                .zip(&touching)
                .map(|(c, &k)| Closed {
                    mu: if c.mu > 0.0 { sys.mu_static[k] } else { 0.0 },
                    ..c.clone()
                })
                .collect();
            match held(&w, &vd, &static_cones).filter(|_| plastic) {
                Some(v_held) => {
                    let dv = &v_held - &vd;
                    for (i, &k) in touching.iter().enumerate() {
                        // The normal impulse along the contact's row: its effect on the
                        // normal velocity over the row's effective inverse mass.
                        let wn = &closed[i].normal;
                        impulses[k] = wn.dot(&dv) / wn.dot(&(&w * wn)).max(f64::MIN_POSITIVE);
                    }
                    v = SVector::from_iterator(v_held.iter().copied());
                }
                None => {
                    let out = planar::solve(&w, &vd, &closed)
                        .map_err(|err| ill_posed(t, &touching, err, &S::CONTACTS))?;
                    v = SVector::from_iterator(out.acceleration.iter().copied());
                    for (i, &k) in touching.iter().enumerate() {
                        impulses[k] = out.normal[i];
                    }
                }
            }
        }
        y[N..].copy_from_slice(v.as_slice());
        for &k in &approaching {
            let mut s = Switch::of_run(
                t,
                if settled[k] {
                    SwitchKind::Settled
                } else {
                    SwitchKind::Impact
                },
                before.clone(),
                y.clone(),
            );
            s.element = Some(S::CONTACTS[k].to_string());
            s.index = Some(k);
            s.from = Some(old[k].element_mode());
            s.to = Some(if settled[k] {
                Mode::Contact
            } else {
                Mode::Free
            });
            s.jump = impulses[k];
            // The Zeno limit of the rebounds taken as settled: at speed w = e |v⁻| under
            // the pressing acceleration a, the bounces last 2 w / (a (1 − e)) more.
            if settled[k] && e[k] < 1.0 && pressing[k] > 0.0 {
                let w = e[k] * (-vn_before[k]).max(0.0);
                s.accumulation = Some(t + 2.0 * w / (pressing[k] * (1.0 - e[k])));
            }
            sol.switches.push(s);
        }
    }
    // A contact leaving its plane so slowly that it would not rise above the position
    // tolerance before falling back (the last of a rocking block's or a ball's
    // accumulating bounces) is held on it: the touching contacts' normal velocities
    // set to zero by the smallest impulse (in the mass metric), the Zeno limit of the
    // bounces, logged as settled.
    let vn = w_n * v;
    let creeping: Vec<usize> = touching
        .iter()
        .copied()
        .filter(|&k| {
            vn[k] > tol_x(v_scale)
                && pressing[k] > 0.0
                && vn[k] * vn[k] <= 2.0 * pressing[k] * tol_x(scale_q)
        })
        .collect();
    if !creeping.is_empty() {
        // The Zeno limit of the bounces or rocking: every contact that touches and does
        // not move away faster than that is held, its normal velocity and (with
        // friction) its slip set to zero by the smallest change in the mass metric.
        // The impulses this takes need not all press (the rocking's alternate
        // impacts do, one corner at a time); the energy removed is that of a motion
        // below the position tolerance.
        let hold: Vec<usize> = touching
            .iter()
            .copied()
            .filter(|&k| vn[k] <= tol_x(v_scale) || creeping.contains(&k))
            .collect();
        let mut held_rows: Vec<DVector<f64>> = Vec::new();
        for &k in &hold {
            held_rows.push(row(&w_n, k));
            if sys.tangent[k].is_some() && sys.mu[k] > 0.0 {
                held_rows.push(trow(sys.tangent[k]));
                if sys.second[k].is_some() {
                    held_rows.push(trow(sys.second[k]));
                }
            }
        }
        let c = DMatrix::from_fn(held_rows.len(), N, |i, j| held_rows[i][j]);
        let vd = DVector::from_iterator(N, v.iter().copied());
        let dv = factor::least_change(&c, &w, &(&c * &vd)).unwrap_or_else(|| DVector::zeros(N));
        let v_new = &vd - dv;
        let before = y.clone();
        v = SVector::from_iterator(v_new.iter().copied());
        y[N..].copy_from_slice(v.as_slice());
        for &k in &creeping {
            let mut s = Switch::of_run(t, SwitchKind::Settled, before.clone(), y.clone());
            s.element = Some(S::CONTACTS[k].to_string());
            s.index = Some(k);
            s.from = Some(old[k].element_mode());
            s.to = Some(Mode::Contact);
            sol.switches.push(s);
            settled[k] = true;
        }
    }
    // The modes at acceleration level, among the contacts touching with no normal speed.
    let vn = w_n * v;
    let slips = w_t * v;
    let candidates: Vec<usize> = touching
        .iter()
        .copied()
        .filter(|&k| vn[k].abs() <= tol_x(v_scale))
        .collect();
    let mut modes = [CMode::Open; K];
    if !candidates.is_empty() && spatial {
        modes = select_spatial(sys, t, &q, &v, &candidates, tol_x(v_scale))?;
    } else if !candidates.is_empty() {
        let tau = sys.input.forces(t, &q, &v);
        let a0 = scene.forward_dynamics(&q, &v, &tau);
        let g_n = scene.contact_normal_gamma(&q, &v);
        let g_t = scene.contact_tangent_gamma(&q, &v);
        let mut closed: Vec<Closed> = candidates
            .iter()
            .map(|&k| {
                let slip = sys.tangent[k].map_or(0.0, |r| slips[r]);
                Closed {
                    normal: row(&w_n, k),
                    gamma_n: g_n[k],
                    tangent: trow(sys.tangent[k]),
                    gamma_t: sys.tangent[k].map_or(0.0, |r| g_t[r]),
                    // A stuck contact's cone is the static one, a sliding one's force
                    // the kinetic.
                    mu: match (sys.tangent[k], slip.abs() > tol_x(v_scale)) {
                        (None, _) => 0.0,
                        (Some(_), true) => sys.mu[k],
                        (Some(_), false) => sys.mu_static[k],
                    },
                    sliding: (slip.abs() > tol_x(v_scale)).then(|| slip.signum()),
                }
            })
            .collect();
        // The candidates closed as they are (stuck where not slipping) first: if their
        // forces are admissible they are the modes. A redundant set of contacts (a
        // block flat on two corners) has other solutions of the contact problem too
        // (one corner carrying all, breaking away), which complementary pivoting could
        // pick; the one that keeps the contacts as they are is the one that continues
        // the motion.
        let mut trial = sys.with_modes([CMode::Open; K]);
        for (i, &k) in candidates.iter().enumerate() {
            trial.modes[k] = match closed[i].sliding {
                Some(s) => CMode::Slip(s),
                None if closed[i].mu > 0.0 => CMode::Stick,
                None => CMode::Slip(1.0),
            };
        }
        let mut d = trial.dynamics(t, &q, &v);
        let f_scale = trial.force_scale(t, &q, &v, &candidates, &d);
        let f_tol = 1e-10 * f_scale.max(f64::MIN_POSITIVE);
        // On the edge of a mode (a stuck contact's friction at `μ λ_N`, a closed one's
        // normal force at 0) both modes give the same forces at this instant; the one
        // that continues is decided by where the force goes next.
        if leave_edges(&mut trial, &candidates, &d, t, &q, &v, EDGE * f_scale) {
            d = trial.dynamics(t, &q, &v);
            for (i, &k) in candidates.iter().enumerate() {
                if let CMode::Slip(s) = trial.modes[k] {
                    closed[i].sliding = Some(s);
                }
            }
        }
        let admissible = candidates.iter().all(|&k| {
            d.normal[k] >= -f_tol
                && (trial.modes[k] != CMode::Stick
                    || d.friction(k) <= sys.mu_static[k] * d.normal[k] + f_tol)
        }) && d.a.iter().all(|x| x.is_finite());
        let a0d = DVector::from_iterator(N, a0.iter().copied());
        let out = if admissible {
            None
        } else {
            Some(
                planar::solve(&w, &a0d, &closed)
                    .map_err(|err| ill_posed(t, &candidates, err, &S::CONTACTS))?,
            )
        };
        let a_scale = a0.amax().max(1.0);
        for (i, &k) in candidates.iter().enumerate() {
            let Some(out) = &out else {
                modes[k] = trial.modes[k];
                continue;
            };
            modes[k] = if out.normal[i] <= 0.0 && out.normal_acceleration[i] > 1e-12 * a_scale {
                CMode::Open
            } else if let Some(s) = closed[i].sliding {
                CMode::Slip(s)
            } else if sys.tangent[k].is_none() || sys.mu[k] == 0.0 {
                // Frictionless: slides freely, whichever way.
                CMode::Slip(if out.tangent_acceleration[i] >= 0.0 {
                    1.0
                } else {
                    -1.0
                })
            } else if out.tangent_acceleration[i].abs() <= 1e-12 * a_scale {
                CMode::Stick
            } else {
                CMode::Slip(out.tangent_acceleration[i].signum())
            };
        }
    }
    // (A frictionless contact "slides" either way: it has no friction to reverse.)
    sys.modes = modes;
    for k in 0..K {
        if !modes[k].same(old[k]) && !approaching.contains(&k) && !creeping.contains(&k) {
            let mut s = Switch::of_run(t, SwitchKind::Mode, y.clone(), y.clone());
            s.element = Some(S::CONTACTS[k].to_string());
            s.index = Some(k);
            s.from = Some(old[k].element_mode());
            s.to = Some(modes[k].element_mode());
            sol.switches.push(s);
        }
        // A function that starts at its level waits until it has left it.
        if !modes[k].same(old[k]) || approaching.contains(&k) {
            armed[k] = false;
        }
    }
    // Onto the new modes' constraints, and the row after the switch with their forces.
    let (mut q, mut v) = InMode::<S, I, N, K, T>::split(y);
    sys.project_state(&mut q, &mut v, tol_x(scale_q) * 1e-3);
    y[..N].copy_from_slice(q.as_slice());
    y[N..].copy_from_slice(v.as_slice());
    jump_row(sys, sol, t, y);
    // Contacts leaving their plane (a rebound, a corner lifting as the other lands):
    // steps end by half way to the apex of each, where its gap is up and its landing
    // function armed, so that a landing within one step is not stepped over.
    let w_n = scene.contact_normal_jacobian(&q);
    let vn = w_n * v;
    let gaps = scene.contact_gaps(&q);
    let d = sys.dynamics(t, &q, &v);
    let g_n = scene.contact_normal_gamma(&q, &v);
    let acc = w_n * d.a - g_n;
    let hold = (0..K)
        .filter(|&k| {
            sys.modes[k] == CMode::Open && gaps[k] <= tol_x(scale_q) && vn[k] > 0.0 && acc[k] < 0.0
        })
        .map(|k| t + 0.5 * vn[k] / -acc[k])
        .fold(f64::INFINITY, f64::min);
    Ok(if hold.is_finite() { hold } else { t })
}

/// How close (relative to the largest contact force) a force must be to the edge of its
/// mode for [`leave_edges`] to look at where it goes.
const EDGE: f64 = 1e-8;

/// The contacts of `trial` whose forces `d` sit on the edge of their mode — a stuck one
/// with `|λ_T| = μ λ_N`, a closed one with `λ_N = 0` — where both modes give the same
/// forces at `t`: each is moved to the mode the motion continues in, by the forces a
/// moment either side of `t` along the trial modes' motion. Friction growing past the
/// cone: it slides, against its friction. The normal force falling through zero: it
/// opens. Returns whether a mode changed.
fn leave_edges<S, I, const N: usize, const K: usize, const T: usize>(
    trial: &mut InMode<'_, S, I, N, K, T>,
    candidates: &[usize],
    d: &Dynamics<N, K>,
    t: f64,
    q: &SVector<f64, N>,
    v: &SVector<f64, N>,
    edge: f64,
) -> bool
where
    S: Mechanism<N> + Contacts<N, K, T>,
    I: Input<N> + ?Sized,
{
    let on_edge = |k: usize| match trial.modes[k] {
        CMode::Stick => {
            d.normal[k].abs() <= edge
                || (trial.mu_static[k] * d.normal[k] - d.friction(k)).abs() <= edge
        }
        CMode::Slip(_) | CMode::Slide(_) => d.normal[k].abs() <= edge,
        CMode::Open => false,
    };
    let edges: Vec<usize> = candidates.iter().copied().filter(|&k| on_edge(k)).collect();
    if edges.is_empty() {
        return false;
    }
    // A moment: a millionth of the motion's own time scale (the time to move, or to
    // accelerate across, the configuration's size).
    let scale = q.amax().max(1.0);
    let time = (scale / v.amax().max(f64::MIN_POSITIVE))
        .min((scale / d.a.amax().max(f64::MIN_POSITIVE)).sqrt());
    let delta = 1e-6 * if time.is_finite() { time } else { 1.0 };
    let at = |s: f64| {
        let (qs, vs) = (q + v * s + d.a * (0.5 * s * s), v + d.a * s);
        trial.dynamics(t + s, &qs, &vs)
    };
    let (before, after) = (at(-delta), at(delta));
    let mut changed = false;
    for k in edges {
        let falling = after.normal[k] < before.normal[k] && d.normal[k].abs() <= edge;
        let margin = |x: &Dynamics<N, K>| trial.mu_static[k] * x.normal[k] - x.friction(k);
        if falling {
            trial.modes[k] = CMode::Open;
            changed = true;
        } else if trial.modes[k] == CMode::Stick && margin(&after) < margin(&before) {
            trial.modes[k] = if trial.second[k].is_some() {
                let f = d.friction(k);
                CMode::Slide([-d.tangent[k] / f, -d.tangent2[k] / f])
            } else {
                CMode::Slip(-d.tangent[k].signum())
            };
            changed = true;
        }
    }
    changed
}

/// The modes of a spatial scene's touching contacts at acceleration level: first as
/// they are (stuck where not slipping, sliding against their slip), moved off the edges
/// of their modes (see [`leave_edges`]), kept when their forces are admissible. Else the
/// modes of a short Moreau step (`10⁻⁶` of the motion's time scale) on the exact cone:
/// the acceleration-level problem's, to that step's first order, with the contacts'
/// `γ` terms taken in (`u = H v⁺ − h γ` through a least-norm shift of the free
/// velocity). The modes must then be admissible, or the switch fails, naming the
/// contacts.
fn select_spatial<S, I, const N: usize, const K: usize, const T: usize>(
    sys: &InMode<'_, S, I, N, K, T>,
    t: f64,
    q: &SVector<f64, N>,
    v: &SVector<f64, N>,
    candidates: &[usize],
    slip_tol: f64,
) -> Result<[CMode; K], ErrorKind>
where
    S: Mechanism<N> + Contacts<N, K, T>,
    I: Input<N> + ?Sized,
{
    let scene = sys.scene;
    let (w_n, w_t) = (
        scene.contact_normal_jacobian(q),
        scene.contact_tangent_jacobian(q),
    );
    let slips = w_t * v;
    let slip_of = |k: usize| [sys.tangent[k], sys.second[k]].map(|r| r.map_or(0.0, |r| slips[r]));
    let frictional = |k: usize| sys.tangent[k].is_some() && sys.mu_static[k] > 0.0;
    let mut trial = sys.with_modes([CMode::Open; K]);
    for &k in candidates {
        let u = slip_of(k);
        let norm = u[0].hypot(u[1]);
        trial.modes[k] = if norm > slip_tol {
            CMode::Slide([u[0] / norm, u[1] / norm])
        } else if frictional(k) {
            CMode::Stick
        } else {
            CMode::Slide([1.0, 0.0])
        };
    }
    let g_n = scene.contact_normal_gamma(q, v);
    let admissible = |trial: &InMode<'_, S, I, N, K, T>, d: &Dynamics<N, K>| {
        let f_tol = 1e-10
            * trial
                .force_scale(t, q, v, candidates, d)
                .max(f64::MIN_POSITIVE);
        let acc = w_n * d.a - g_n;
        let a_tol = 1e-10 * d.a.amax().max(1.0);
        d.a.iter().all(|x| x.is_finite())
            && candidates.iter().all(|&k| match trial.modes[k] {
                CMode::Open => acc[k] >= -a_tol,
                CMode::Stick => {
                    d.normal[k] >= -f_tol
                        && d.friction(k) <= trial.mu_static[k] * d.normal[k] + f_tol
                }
                _ => d.normal[k] >= -f_tol,
            })
    };
    let mut d = trial.dynamics(t, q, v);
    let f_scale = trial.force_scale(t, q, v, candidates, &d);
    if leave_edges(&mut trial, candidates, &d, t, q, v, EDGE * f_scale) {
        d = trial.dynamics(t, q, v);
    }
    if admissible(&trial, &d) {
        return Ok(trial.modes);
    }
    // A short Moreau step on the exact cone decides.
    let tau = sys.input.forces(t, q, v);
    let a0 = scene.forward_dynamics(q, v, &tau);
    let scale = q.amax().max(1.0);
    let time = (scale / v.amax().max(f64::MIN_POSITIVE))
        .min((scale / a0.amax().max(f64::MIN_POSITIVE)).sqrt());
    let h = 1e-6 * if time.is_finite() { time } else { 1.0 };
    let g_t = scene.contact_tangent_gamma(q, v);
    let mut rows: Vec<DVector<f64>> = Vec::new();
    let mut shift: Vec<f64> = Vec::new();
    for &k in candidates {
        rows.push(DVector::from_iterator(N, w_n.row(k).iter().copied()));
        shift.push(h * g_n[k]);
        for r in [sys.tangent[k], sys.second[k]].into_iter().flatten() {
            rows.push(DVector::from_iterator(N, w_t.row(r).iter().copied()));
            shift.push(h * g_t[r]);
        }
    }
    let hm = DMatrix::from_fn(rows.len(), N, |i, j| rows[i][j]);
    let gram = &hm * hm.transpose();
    let x = factor::least_squares(gram, &DVector::from_vec(shift), 1e-12)
        .unwrap_or_else(|| DVector::zeros(rows.len()));
    let v_shift = hm.transpose() * x;
    let v_free = DVector::from_iterator(N, (v + a0 * h).iter().copied()) - &v_shift;
    let locals: Vec<ConeContact> = candidates
        .iter()
        .map(|&k| {
            let u = slip_of(k);
            ConeContact {
                rows: sys.rows_of(k, &w_n, &w_t),
                gamma: 0.0,
                mu: if u[0].hypot(u[1]) > slip_tol {
                    sys.mu[k]
                } else {
                    sys.mu_static[k]
                },
                friction: None,
            }
        })
        .collect();
    let out = cone::solve(
        &sys.inverse_mass(q),
        &v_free,
        &locals,
        &[],
        CONE_TOLERANCE,
        CONE_SWEEPS,
    )
    .map_err(|err| cone_ill_posed(t, candidates[err.contact], &S::CONTACTS))?;
    let round_off = SLIP_ROUND_OFF * v_free.amax().max(v.amax());
    for (i, &k) in candidates.iter().enumerate() {
        let (p, u) = (&out.impulses[i], &out.local[i]);
        let slip = u[1..].iter().map(|x| x * x).sum::<f64>().sqrt();
        trial.modes[k] = if p[0] <= 0.0 {
            CMode::Open
        } else if frictional(k) && cone::is_stuck(p, u, locals[i].mu, round_off) {
            CMode::Stick
        } else if slip > 0.0 {
            let mut dir = [0.0; 2];
            for (j, x) in u[1..].iter().enumerate() {
                dir[j] = x / slip;
            }
            CMode::Slide(dir)
        } else {
            CMode::Slide([1.0, 0.0])
        };
    }
    let d = trial.dynamics(t, q, v);
    if admissible(&trial, &d) {
        return Ok(trial.modes);
    }
    let names: Vec<String> = candidates
        .iter()
        .map(|&k| format!("`{}`", S::CONTACTS[k]))
        .collect();
    Err(ErrorKind::IllPosedMode {
        t,
        detail: format!(
            "no consistent modes were found for the spatial contacts {} (open, stuck or \
             sliding); integrate the scene with `contact_time_stepping`",
            names.join(", ")
        ),
    })
}

/// The error of a spatial contact problem without a solution.
fn cone_ill_posed(t: f64, k: usize, names: &[&str]) -> ErrorKind {
    ErrorKind::IllPosedMode {
        t,
        detail: format!(
            "the contact problem of `{}` has no solution: its friction drives it into the \
             plane in every sliding direction",
            names[k]
        ),
    }
}

/// The velocities after a plastic impact that holds every contact of `closed` (normal
/// and, with friction, tangential velocity zero), if its impulses are admissible
/// (pressing, inside the cone): the least-norm impulses where the contacts are
/// redundant. `None` when some contact would have to pull or slip.
fn held(w: &DMatrix<f64>, v: &DVector<f64>, closed: &[Closed]) -> Option<DVector<f64>> {
    let mut rows: Vec<&DVector<f64>> = Vec::new();
    for c in closed {
        rows.push(&c.normal);
        if c.mu > 0.0 {
            rows.push(&c.tangent);
        }
    }
    let n = v.len();
    let c = DMatrix::from_fn(rows.len(), n, |i, j| rows[i][j]);
    let a = &c * w * c.transpose();
    let p = a
        .clone()
        .svd(true, true)
        .solve(&(-(&c * v)), 1e-12 * a.amax().max(f64::MIN_POSITIVE))
        .ok()?;
    let scale = p.amax().max(f64::MIN_POSITIVE);
    let mut r = 0;
    for cl in closed {
        let pn = p[r];
        r += 1;
        if pn < -1e-10 * scale {
            return None;
        }
        if cl.mu > 0.0 {
            let pt = p[r];
            r += 1;
            if pt.abs() > cl.mu * pn + 1e-10 * scale {
                return None;
            }
        }
    }
    let v_new = v + w * c.transpose() * p;
    v_new.iter().all(|x| x.is_finite()).then_some(v_new)
}

fn ill_posed(t: f64, which: &[usize], err: ContactError, names: &[&str]) -> ErrorKind {
    let names: Vec<String> = which.iter().map(|&k| format!("`{}`", names[k])).collect();
    let detail = match err {
        ContactError::Painleve { .. } => format!(
            "the contact problem of {} has no unique solution: the friction of a sliding contact pulls it \
             into its plane harder than the normal force can push (Painlevé's paradox); time-stepping \
             (`contact_time_stepping`) resolves it with an impulse",
            names.join(", ")
        ),
        ContactError::NoSolution => format!(
            "the contact problem of {} has no solution",
            names.join(", ")
        ),
    };
    ErrorKind::IllPosedMode { t, detail }
}
