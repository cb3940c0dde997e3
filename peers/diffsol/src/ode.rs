//! The right-hand sides handed to both libraries: the generated multibody kernels of the
//! smooth scenes, and the Coulomb oscillator with its friction regularised as
//! `f_crit·tanh(v/ε)` — the smooth ODE a user of a plain ODE solver would write.

use std::cell::{Cell, RefCell};

use filippov::Mechanism;
use filippov::nalgebra::SVector;
use filippov::runtime::ForwardJacobian;
use filippov_scenes::CoulombOscillator;

/// A first-order ODE `y' = f(t, y)` with the action of its Jacobian, in the slice form of
/// diffsol's closure API (`rhs(x, p, t, y)`, `jac_mul(x, p, t, v, y)`).
pub trait Ode {
    fn dim(&self) -> usize;
    fn rhs(&self, t: f64, x: &[f64], y: &mut [f64]);
    /// `y = ∂f/∂x (t, x) · w`.
    fn jac_mul(&self, t: f64, x: &[f64], w: &[f64], y: &mut [f64]);
    /// Right-hand-side calls and Jacobian evaluations since the last [`Ode::reset_counts`].
    fn counts(&self) -> (usize, usize);
    fn reset_counts(&self);
}

/// `y = [q; v]`, `y' = [v; FD(q, v, 0)]` from the generated kernel. The Jacobian-vector
/// product uses the generated symbolic Jacobian `forward_dynamics_jacobian`; diffsol
/// assembles its dense Jacobian from 2N products at the same `x`, so the last Jacobian is
/// cached by `x` and the kernel runs once per assembly (what a user handing the symbolic
/// Jacobian to this API would do).
pub struct Mechanical<'a, S, const N: usize> {
    sys: &'a S,
    cache: RefCell<Option<(Vec<f64>, ForwardJacobian<N>)>>,
    rhs_calls: Cell<usize>,
    jacobians: Cell<usize>,
}

impl<'a, S: Mechanism<N>, const N: usize> Mechanical<'a, S, N> {
    pub fn new(sys: &'a S) -> Self {
        Mechanical {
            sys,
            cache: RefCell::new(None),
            rhs_calls: Cell::new(0),
            jacobians: Cell::new(0),
        }
    }

    fn split(x: &[f64]) -> (SVector<f64, N>, SVector<f64, N>) {
        (
            SVector::from_column_slice(&x[..N]),
            SVector::from_column_slice(&x[N..2 * N]),
        )
    }
}

impl<S: Mechanism<N>, const N: usize> Ode for Mechanical<'_, S, N> {
    fn dim(&self) -> usize {
        2 * N
    }

    fn rhs(&self, _t: f64, x: &[f64], y: &mut [f64]) {
        self.rhs_calls.set(self.rhs_calls.get() + 1);
        let (q, v) = Self::split(x);
        let a = self.sys.forward_dynamics(&q, &v, &SVector::zeros());
        y[..N].copy_from_slice(&x[N..2 * N]);
        y[N..2 * N].copy_from_slice(a.as_slice());
    }

    fn jac_mul(&self, _t: f64, x: &[f64], w: &[f64], y: &mut [f64]) {
        let mut cache = self.cache.borrow_mut();
        let fresh = !matches!(&*cache, Some((key, _)) if key.as_slice() == x);
        if fresh {
            self.jacobians.set(self.jacobians.get() + 1);
            let (q, v) = Self::split(x);
            let d = self
                .sys
                .forward_dynamics_jacobian(&q, &v, &SVector::zeros());
            *cache = Some((x.to_vec(), d));
        }
        let d = &cache.as_ref().expect("filled above").1;
        let (wq, wv) = Self::split(w);
        let a = d.d_dq * wq + d.d_dv * wv;
        y[..N].copy_from_slice(&w[N..2 * N]);
        y[N..2 * N].copy_from_slice(a.as_slice());
    }

    fn counts(&self) -> (usize, usize) {
        (self.rhs_calls.get(), self.jacobians.get())
    }

    fn reset_counts(&self) {
        self.rhs_calls.set(0);
        self.jacobians.set(0);
        *self.cache.borrow_mut() = None;
    }
}

/// The Coulomb oscillator (scenes S5/S6) with regularised friction,
/// `m x'' = −k x + F(t) − f_crit·tanh(v/ε)`, `y = [x, v]`.
pub struct Regularised {
    pub scene: CoulombOscillator,
    pub eps: f64,
    pub forcing: fn(f64) -> f64,
    rhs_calls: Cell<usize>,
    jacobians: Cell<usize>,
}

impl Regularised {
    pub fn new(scene: CoulombOscillator, eps: f64, forcing: fn(f64) -> f64) -> Self {
        Regularised {
            scene,
            eps,
            forcing,
            rhs_calls: Cell::new(0),
            jacobians: Cell::new(0),
        }
    }
}

impl Ode for Regularised {
    fn dim(&self) -> usize {
        2
    }

    fn rhs(&self, t: f64, x: &[f64], y: &mut [f64]) {
        self.rhs_calls.set(self.rhs_calls.get() + 1);
        let CoulombOscillator { m, k, f_crit } = self.scene;
        y[0] = x[1];
        y[1] = (-k * x[0] + (self.forcing)(t) - f_crit * (x[1] / self.eps).tanh()) / m;
    }

    fn jac_mul(&self, _t: f64, x: &[f64], w: &[f64], y: &mut [f64]) {
        self.jacobians.set(self.jacobians.get() + 1);
        let CoulombOscillator { m, k, f_crit } = self.scene;
        let th = (x[1] / self.eps).tanh();
        let dv = -f_crit * (1.0 - th * th) / self.eps / m;
        y[0] = w[1];
        y[1] = -k / m * w[0] + dv * w[1];
    }

    /// Jacobian "evaluations" here count Jacobian-vector products (two per assembly).
    fn counts(&self) -> (usize, usize) {
        (self.rhs_calls.get(), self.jacobians.get())
    }

    fn reset_counts(&self) {
        self.rhs_calls.set(0);
        self.jacobians.set(0);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use filippov_scenes::DoublePendulum;

    /// The Jacobian-vector product agrees with central differences of the rhs.
    fn check_jac(ode: &dyn Ode, x: &[f64]) {
        let n = ode.dim();
        for j in 0..n {
            let mut w = vec![0.0; n];
            w[j] = 1.0;
            let mut jw = vec![0.0; n];
            ode.jac_mul(0.3, x, &w, &mut jw);
            let h = 1e-6;
            let (mut xp, mut xm) = (x.to_vec(), x.to_vec());
            xp[j] += h;
            xm[j] -= h;
            let (mut fp, mut fm) = (vec![0.0; n], vec![0.0; n]);
            ode.rhs(0.3, &xp, &mut fp);
            ode.rhs(0.3, &xm, &mut fm);
            for i in 0..n {
                let fd = (fp[i] - fm[i]) / (2.0 * h);
                assert!(
                    (fd - jw[i]).abs() < 1e-6 * (1.0 + fd.abs()),
                    "J[{i},{j}]: {} vs {fd}",
                    jw[i]
                );
            }
        }
    }

    #[test]
    fn jacobians_match_finite_differences() {
        let dp = DoublePendulum::default();
        check_jac(&Mechanical::new(&dp), &[1.2, -0.6, 0.3, -0.2]);
        let s = CoulombOscillator {
            m: 1.0,
            k: 1.0,
            f_crit: 0.5,
        };
        check_jac(
            &Regularised::new(s, 0.1, |t| 1.2 * (0.5 * t).sin()),
            &[0.25, 0.03],
        );
    }
}
