//! The simplified-Newton matrix `I − s J` shared by the implicit methods (SDIRK4 with
//! `s = hγ`, BDF with `s = h/γ_k`), and Jacobians by forward differences where the system
//! has none.
//!
//! Policy (Hairer & Wanner, *Solving ODEs II*, §IV.8): `J` is evaluated at an accepted
//! point and kept while Newton converges fast; it is marked stale after every accepted
//! step and refreshed only when an iteration fails with a stale one (or converged
//! slowly). The LU of `I − s J` is kept while `s` and `J` are unchanged.

use nalgebra::DMatrix;

use super::eval::Eval;
use super::lu::DenseLu;
use super::tableau::SDIRK4;
use crate::{ErrorKind, OdeSystem, Options};

/// The stage Newton iteration of the stiffly accurate DIRK methods (`Sdirk4` and, on the
/// group, `LieSdirk`): iterations per stage before the step counts as failed.
pub(crate) const DIRK_MAX_NEWTON_ITERATIONS: usize = 10;
/// After an accepted DIRK step, the Jacobian is kept if Newton converged at least this
/// fast.
pub(crate) const DIRK_THETA_REUSE_JACOBIAN: f64 = 0.1;

/// A DIRK stage's Newton iteration stops when its estimated remaining error is below
/// this fraction of the tolerance (in the error test's weighted norm).
///
/// `κ ∈ [0.01, 0.1]` (Hairer & Wanner II, §IV.8, here 0.05) suits a collocation method
/// such as RADAU5, whose stages are solved together so that their Newton error enters
/// `y₁` once. In a DIRK the stage derivatives are recovered as
/// `k_j = (Z_j − base_j)/(hγ)`, so a stage error `δ_j` reaches `y₁ = Z_s` (and the error
/// estimate) multiplied by up to `|a_sj|/γ`, in all up to `A = Σ_j |a_sj|/γ ≈ 68`
/// ([`dirk_amplification`]), and with the same sign step after step: the global error
/// grows with the number of steps times `A δ`. Measured on S10 (the free body, three
/// flip periods, against a different method): with `κ / (10 A)` `LieSdirk`'s error
/// stopped following the tolerance below rtol 1e-8 (8.6e-7 at 1e-8, 1.3e-9 at 1e-12),
/// while at a fixed step with a tight Newton tolerance it converges at order 4 to the
/// reference's accuracy; with `κ / (1000 A)` it follows the tolerance (1.5e-7 at 1e-8,
/// 3.5e-11 at 1e-12) for 10–25 % more evaluations, and a tenth of that changes nothing.
pub(crate) fn dirk_stage_tolerance() -> f64 {
    0.05 / (1000.0 * dirk_amplification())
}

/// `Σ_j |a_sj| / γ` of SDIRK4: the largest factor by which Newton errors in the stages
/// can reach the result `y₁ = Z_s` through the stage derivatives
/// `k_j = (Z_j − base_j)/(hγ)`.
pub(crate) fn dirk_amplification() -> f64 {
    let s = SDIRK4.stages();
    (0..s).map(|j| SDIRK4.a(s - 1, j).abs()).sum::<f64>() / SDIRK4.a(0, 0)
}

/// Why a DIRK stage's Newton iteration stopped short.
pub(crate) enum StageFailure {
    /// Diverged, converged too slowly, or met a singular matrix or a non-finite stage.
    Diverged,
    /// The right-hand side failed at a stage point (kept for reporting).
    Evaluation(ErrorKind),
    /// On the group: a stage's rotation vector left the ball `|θ| < π`.
    TooFar,
}

/// What one stage's iteration is measured against: the step's `hγ`, the stage's
/// explicit part `base`, the stopping tolerance `tol` (a fraction of the error test's,
/// [`dirk_stage_tolerance`], floored at round-off), the `stagnant` correction size below
/// which nothing improves, and the weights (`scale`, `options`) of the error norm.
pub(crate) struct DirkStage<'a> {
    pub hg: f64,
    pub base: &'a [f64],
    pub tol: f64,
    pub stagnant: f64,
    pub scale: &'a [f64],
    pub options: &'a Options,
}

/// The simplified Newton iteration of one stage of a stiffly accurate DIRK, written once
/// for `Sdirk4` (increments `z = Y − y` of a vector state) and `LieSdirk` (chart
/// coordinates `z = Θ`): solves `z = base + hγ F(z)` with `(I − hγJ) δ = −(z − base −
/// hγ F(z))` (`solve` applies the factorised matrix in place), `field(z, fz)` writing
/// `F(z)`. Stops when the estimated remaining error `η ‖δ‖`, `η = θ/(1 − θ)` from the
/// contraction rate `θ` of successive corrections (Hairer & Wanner II, §IV.8), is below
/// `tol`, or a correction is `stagnant`; fails on `θ ≥ 0.99`, a NaN rate, a failed
/// solve or [`DIRK_MAX_NEWTON_ITERATIONS`]. `eta` carries `η` from stage to stage (its
/// start `max(η, ε)^0.8`), `theta_max` the slowest rate seen.
#[allow(clippy::too_many_arguments)]
pub(crate) fn dirk_stage_newton(
    stage: &DirkStage<'_>,
    z: &mut [f64],
    fz: &mut [f64],
    delta: &mut [f64],
    eta: &mut f64,
    theta_max: &mut f64,
    solve: impl Fn(&mut [f64]) -> bool,
    mut field: impl FnMut(&[f64], &mut [f64]) -> Result<(), StageFailure>,
) -> Result<(), StageFailure> {
    let mut rate = eta.max(f64::EPSILON).powf(0.8);
    let mut norm_prev = f64::NAN;
    for iteration in 0..DIRK_MAX_NEWTON_ITERATIONS {
        field(z, fz)?;
        for k in 0..z.len() {
            delta[k] = -(z[k] - stage.base[k] - stage.hg * fz[k]);
        }
        if !solve(delta) {
            return Err(StageFailure::Diverged);
        }
        let norm = super::error_norm(delta, stage.scale, stage.scale, stage.options);
        if iteration > 0 && norm > stage.stagnant {
            let theta = norm / norm_prev;
            *theta_max = theta_max.max(theta);
            if theta.is_nan() || theta >= 0.99 {
                return Err(StageFailure::Diverged);
            }
            rate = theta / (1.0 - theta);
        }
        for (zk, dk) in z.iter_mut().zip(delta.iter()) {
            *zk += dk;
        }
        norm_prev = norm;
        if rate * norm <= stage.tol || norm <= stage.stagnant {
            *eta = rate;
            return Ok(());
        }
    }
    Err(StageFailure::Diverged)
}

/// `J`, what it was built from, and the factorised `I − s J`.
///
/// For a second-order system (`y = [q; v]` with `q̇ = v`, [`OdeSystem::second_order`]),
/// `J = [[0, I], [A_q, A_v]]` and `(I − sJ) [x; z] = [r; w]` reduces to
/// `(I − s A_v − s² A_q) z = w + s A_q r`, `x = r + s z`: an LU of half the size (an
/// eighth of the work) and a solve of half the work. The same Newton iteration, to
/// round-off.
#[derive(Debug)]
pub(crate) struct NewtonMatrix {
    pub jac: DMatrix<f64>,
    /// `J` was evaluated at the current accepted point.
    pub jac_current: bool,
    /// `J` must be (re)evaluated before the next attempt.
    pub jac_needed: bool,
    /// `Some(n)`: `lu` holds the `n × n` Schur complement (see above).
    second_order: Option<usize>,
    lu: DenseLu,
    /// `lu` holds `I − s J` for the current `J` and `s = scale`.
    factored: bool,
    /// The `s` of the factorised matrix.
    scale: f64,
}

impl NewtonMatrix {
    pub fn new(n: usize) -> Self {
        NewtonMatrix {
            jac: DMatrix::zeros(n, n),
            jac_current: false,
            jac_needed: true,
            second_order: None,
            lu: DenseLu::new(n),
            factored: false,
            scale: f64::NAN,
        }
    }

    /// Evaluates `J` at `(t, y)` if it is needed (see [`jacobian`] for `f` and `fresh`).
    pub fn update_jacobian<S: OdeSystem + ?Sized>(
        &mut self,
        ev: &mut Eval<'_, S>,
        t: f64,
        y: &[f64],
        f: &mut [f64],
        fresh: bool,
    ) -> Result<(), ErrorKind> {
        if self.jac_needed {
            jacobian(ev, t, y, f, fresh, &mut self.jac)?;
            let reduced = ev
                .system
                .second_order()
                .filter(|&n| n > 0 && 2 * n == y.len());
            if reduced != self.second_order {
                self.second_order = reduced;
                self.lu = DenseLu::new(reduced.unwrap_or(y.len()));
            }
            self.jacobian_updated();
        }
        Ok(())
    }

    /// `jac` was just evaluated at the current accepted point (by the caller, for
    /// methods with their own Jacobian, e.g. in a Lie-group chart).
    pub fn jacobian_updated(&mut self) {
        self.jac_current = true;
        self.jac_needed = false;
        self.factored = false;
    }

    /// Factorises `I − s J` unless it is already factorised for this `s` and `J`
    /// (counted in `lu`).
    pub fn factor(&mut self, s: f64, lu_count: &mut usize) {
        if !self.factored || self.scale != s {
            match self.second_order {
                Some(_) => self.lu.factor_second_order(&self.jac, s),
                None => self.lu.factor_shifted(&self.jac, s),
            }
            self.factored = true;
            self.scale = s;
            *lu_count += 1;
        }
    }

    /// Like [`factor`](Self::factor), but keeps a factorisation of the current `J` whose
    /// `s` is within the relative distance `keep` of the wanted one (the simplified
    /// Newton iteration converges with it, a little slower; CVODE and diffsol do the
    /// same for BDF). Returns whether the factorised `s` is exactly `s`.
    pub fn factor_near(&mut self, s: f64, keep: f64, lu_count: &mut usize) -> bool {
        if self.factored && (s / self.scale - 1.0).abs() <= keep {
            return self.scale == s;
        }
        self.factor(s, lu_count);
        true
    }

    /// Solves `(I − s J) x = b` in place with the factorised matrix (after
    /// [`factor`](Self::factor)); `false` if it is singular.
    pub fn solve(&self, b: &mut [f64]) -> bool {
        debug_assert!(self.factored, "factorised before use");
        let Some(n) = self.second_order else {
            return self.lu.solve(b);
        };
        let s = self.scale;
        let (r, w) = b.split_at_mut(n);
        // w + s A_q r, then z, then x = r + s z.
        for (j, &rj) in r.iter().enumerate() {
            if rj != 0.0 {
                let column = &self.jac.as_slice()[j * 2 * n + n..(j + 1) * 2 * n];
                for (wi, a) in w.iter_mut().zip(column) {
                    *wi += s * a * rj;
                }
            }
        }
        if !self.lu.solve(w) {
            return false;
        }
        for (ri, zi) in r.iter_mut().zip(w.iter()) {
            *ri += s * zi;
        }
        true
    }

    /// After a failure with a stale `J`: refresh it before the next attempt.
    pub fn refresh_if_stale(&mut self) {
        if !self.jac_current {
            self.jac_needed = true;
        }
    }

    /// At a discontinuity (new equations from here on): `J` may still serve the
    /// simplified Newton iteration, but is refreshed at the first failure.
    pub fn mark_stale(&mut self) {
        self.jac_current = false;
    }
}

/// `∂f/∂y(t, y)` into `jac`: from the system, or by forward differences with increments
/// `√(ε max(10⁻⁵, |y_j|))` (Hairer & Wanner II, §IV.8) around `f`. With `fresh`, `f` is
/// first overwritten by `f(t, y)` (only when differences are needed): for methods whose
/// stored derivative is not `f(t, y)` itself (BDF's is the formula's), differencing
/// against it would mix the Newton error into `J`.
pub(crate) fn jacobian<S: OdeSystem + ?Sized>(
    ev: &mut Eval<'_, S>,
    t: f64,
    y: &[f64],
    f: &mut [f64],
    fresh: bool,
    jac: &mut DMatrix<f64>,
) -> Result<(), ErrorKind> {
    ev.stats.jacobian_evaluations += 1;
    if !ev.system.jacobian(t, y, jac) {
        ev.stats.finite_difference_jacobians += 1;
        if fresh {
            ev.rhs(t, y, f)?;
        }
        let mut yp = y.to_vec();
        let mut fp = vec![0.0; y.len()];
        for j in 0..y.len() {
            let delta = (f64::EPSILON * y[j].abs().max(1e-5)).sqrt();
            yp[j] = y[j] + delta;
            ev.rhs(t, &yp, &mut fp)?;
            for i in 0..y.len() {
                jac[(i, j)] = (fp[i] - f[i]) / delta;
            }
            yp[j] = y[j];
        }
    }
    match jac.iter().position(|x| !x.is_finite()) {
        Some(p) => Err(ErrorKind::NonFinite {
            t,
            component: p % y.len(),
        }),
        None => Ok(()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Stats;

    /// `y = [q; v]`, `q̇ = v`, `v̇ = A_q q + A_v v` with random `A_q, A_v`: declared
    /// second-order or not.
    struct Linear {
        n: usize,
        a: DMatrix<f64>,
        second_order: bool,
    }

    impl OdeSystem for Linear {
        fn dim(&self) -> usize {
            2 * self.n
        }
        fn rhs(&self, _t: f64, y: &[f64], dy: &mut [f64]) {
            let n = self.n;
            dy[..n].copy_from_slice(&y[n..]);
            for i in 0..n {
                dy[n + i] = (0..2 * n).map(|j| self.a[(i, j)] * y[j]).sum();
            }
        }
        fn jacobian(&self, _t: f64, _y: &[f64], jac: &mut DMatrix<f64>) -> bool {
            let n = self.n;
            jac.fill(0.0);
            jac.view_mut((0, n), (n, n)).fill_with_identity();
            jac.view_mut((n, 0), (n, 2 * n)).copy_from(&self.a);
            true
        }
        fn second_order(&self) -> Option<usize> {
            self.second_order.then_some(self.n)
        }
    }

    /// The reduced solve of a second-order system equals the full LU solve of
    /// `I − sJ` to round-off, for random `J`, `s` and right-hand sides.
    #[test]
    fn second_order_reduction_solves_the_full_system() {
        let mut seed = 0x9e37_79b9_7f4a_7c15u64;
        let mut r = move || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            (seed >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
        };
        for n in [1, 2, 3, 7, 12] {
            for s in [1e-4, 0.03, 1.0, 50.0] {
                let a = DMatrix::from_fn(n, 2 * n, |_, _| 10.0 * r());
                let y: Vec<f64> = (0..2 * n).map(|_| r()).collect();
                let b: Vec<f64> = (0..2 * n).map(|_| r()).collect();
                let mut solved = Vec::new();
                for second_order in [false, true] {
                    let sys = Linear {
                        n,
                        a: a.clone(),
                        second_order,
                    };
                    let mut stats = Stats::default();
                    let mut ev = Eval::new(&sys, &mut stats);
                    let mut m = NewtonMatrix::new(2 * n);
                    let mut f = vec![0.0; 2 * n];
                    m.update_jacobian(&mut ev, 0.0, &y, &mut f, false).unwrap();
                    assert_eq!(m.second_order.is_some(), second_order);
                    m.factor(s, &mut stats.lu_factorisations);
                    let mut x = b.clone();
                    assert!(m.solve(&mut x));
                    solved.push(x);
                }
                // Residual of the reduced solution in the full system.
                let jac = {
                    let mut j = DMatrix::zeros(2 * n, 2 * n);
                    j.view_mut((0, n), (n, n)).fill_with_identity();
                    j.view_mut((n, 0), (n, 2 * n)).copy_from(&a);
                    j
                };
                let m = DMatrix::identity(2 * n, 2 * n) - &jac * s;
                let x = nalgebra::DVector::from_column_slice(&solved[1]);
                let residual = (&m * &x - nalgebra::DVector::from_column_slice(&b)).norm();
                let scale = m.norm() * x.norm();
                assert!(
                    residual <= 1e-13 * scale,
                    "n {n}, s {s}: residual {residual:e}"
                );
                let diff = solved[0]
                    .iter()
                    .zip(&solved[1])
                    .map(|(p, q)| (p - q).abs())
                    .fold(0.0, f64::max);
                let size = solved[0].iter().fold(0.0f64, |m, x| m.max(x.abs()));
                assert!(diff <= 1e-10 * size.max(1.0), "n {n}, s {s}: {diff:e}");
            }
        }
    }
}
