//! Dense output of one step: the method's own continuous extension as a polynomial in
//! the step fraction, `y(t₀ + θh) = Σ_k c_k θᵏ` for `θ ∈ [0, 1]`, component by component.
//!
//! Every method writes its extension in this one form, so that drivers (event location,
//! output at requested times) and the [`Solution`](crate::Solution) need not know which
//! method made it:
//!
//! | method | extension | degree | local error |
//! |---|---|---|---|
//! | DOPRI5, first step after a (re)start | Dormand–Prince continuous extension (`set_dopri5`) | 4 | `O(h⁵)` |
//! | BDF of order k | the interpolating polynomial through its `k + 1` last points | k | `O(h^{k+1})` |
//! | RK4, SDIRK4, first step after a (re)start | cubic Hermite on the step's ends (`set_hermite`) | 3 | `O(h⁴)` |
//! | DOPRI5, RK4, SDIRK4 after their first step since a (re)start | quintic Hermite through the last three points (`set_hermite5`) | 5 | `O(h⁶)` |
//! | DOPRI5, RK4, SDIRK4: the positions `q` of a second-order system `[q; v]` whose [`OdeSystem::dense_positions`](crate::OdeSystem::dense_positions) is on (the event-driven integrator's), every step | quintic Hermite in `q, q̇, q̈` on the step's ends (`set_positions_quintic`) | 5 | `O(h⁶)`, a ninth of the two-step quintic's constant |
//!
//! The first two rows serve event location inside that first step; a stored
//! [`Solution`](crate::Solution) (`Output::Steps`) rewrites that step as the quintic
//! Hermite through its ends and the next point once the next step is taken without a
//! restart in between.
//!
//! The monomial form is well conditioned on `[0, 1]` for these degrees (≤ 5) and is
//! evaluated by Horner's rule without allocation.

/// The continuous extension of one accepted step from `t0` to `t0 + h`.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct DenseStep {
    t0: f64,
    h: f64,
    degree: usize,
    dim: usize,
    /// `c_k` of component `i` at `k · dim + i`, `k = 0 … degree`.
    coeffs: Vec<f64>,
    /// The third point of a two-step Hermite extension ([`set_hermite5`](Self::set_hermite5)).
    third_node: Option<f64>,
}

impl DenseStep {
    /// An empty extension for states of `dim` components.
    pub fn new(dim: usize) -> Self {
        DenseStep {
            dim,
            ..DenseStep::default()
        }
    }

    /// Start of the step.
    pub fn t0(&self) -> f64 {
        self.t0
    }

    /// End of the step.
    pub fn t1(&self) -> f64 {
        self.t0 + self.h
    }

    /// Length of the step.
    pub fn h(&self) -> f64 {
        self.h
    }

    /// Degree of the polynomial.
    pub fn degree(&self) -> usize {
        self.degree
    }

    /// Number of state components.
    pub fn dim(&self) -> usize {
        self.dim
    }

    /// All coefficients, `c_k` of component `i` at `k · dim + i`.
    pub fn coefficients(&self) -> &[f64] {
        &self.coeffs
    }

    /// Prepares a polynomial of `degree` over `[t0, t0 + h]` and returns its coefficients
    /// to be filled (layout as in [`coefficients`](Self::coefficients)).
    pub(crate) fn reset(&mut self, t0: f64, h: f64, degree: usize) -> &mut [f64] {
        self.t0 = t0;
        self.h = h;
        self.degree = degree;
        self.coeffs.clear();
        self.coeffs.resize((degree + 1) * self.dim, 0.0);
        self.third_node = None;
        &mut self.coeffs
    }

    /// The time of the third point of a two-step Hermite extension, `None` for every
    /// other kind.
    pub(crate) fn third_node(&self) -> Option<f64> {
        self.third_node
    }

    /// Cubic Hermite interpolation of `y0, f0` at `t0` and `y1, f1` at `t0 + h`.
    pub(crate) fn set_hermite(
        &mut self,
        t0: f64,
        h: f64,
        y0: &[f64],
        f0: &[f64],
        y1: &[f64],
        f1: &[f64],
    ) {
        let n = self.dim;
        let c = self.reset(t0, h, 3);
        for i in 0..n {
            let d = y1[i] - y0[i];
            let (a, b) = (h * f0[i], h * f1[i]);
            c[i] = y0[i];
            c[n + i] = a;
            c[2 * n + i] = 3.0 * d - 2.0 * a - b;
            c[3 * n + i] = -2.0 * d + a + b;
        }
    }

    /// Quintic Hermite interpolation over two steps: the polynomial of degree 5 through
    /// `y, f` at the previous point `tm`, at `t0` and at `t0 + h`, kept on
    /// `[t0, t0 + h]` (`tm` may also lie after the step: the solution then rewrites a
    /// finished step's extension from the next point, see `Solution::push_step`). Its interpolation error is
    /// `y⁽⁶⁾(ξ)/6! · (t − tm)²(t − t0)²(t − t0 − h)² = O(h⁶)`, one order above the
    /// local error of every one-step method here, so reading a solution between its steps
    /// costs no accuracy. It needs a smooth solution over `[tm, t0 + h]`: the steppers use
    /// it only when no restart (a discontinuity) lies between `tm` and `t0`.
    ///
    /// Components before `first` are left zero, for the caller to write (the positions of
    /// a second-order state, [`set_positions_quintic`](Self::set_positions_quintic)).
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn set_hermite5(
        &mut self,
        first: usize,
        tm: f64,
        ym: &[f64],
        fm: &[f64],
        t0: f64,
        h: f64,
        y0: &[f64],
        f0: &[f64],
        y1: &[f64],
        f1: &[f64],
    ) {
        let n = self.dim;
        // Nodes in θ = (t − t0)/h, each twice: value and derivative (dy/dθ = h f).
        let rho = (t0 - tm) / h;
        let z = [0.0, 0.0, 1.0, 1.0, -rho, -rho];
        // 1/(z_j − z_{j−k}) for every column k ≥ 1 of the divided-difference table, the
        // same for all components (0 marks a repeated node, where the derivative enters).
        let mut inv = [[0.0; 6]; 6];
        for k in 1..6 {
            for j in k..6 {
                let dz = z[j] - z[j - k];
                inv[k][j] = if dz == 0.0 { 0.0 } else { 1.0 / dz };
            }
        }
        let c = self.reset(t0, h, 5);
        for i in first..n {
            // Confluent divided differences, column by column in place: after column k,
            // d[j] = p[z_{j−k} … z_j] for j ≥ k.
            let (v, dv) = ([y0[i], y1[i], ym[i]], [h * f0[i], h * f1[i], h * fm[i]]);
            let mut d = [v[0], v[0], v[1], v[1], v[2], v[2]];
            for k in 1..6 {
                for j in (k..6).rev() {
                    d[j] = if inv[k][j] == 0.0 {
                        dv[j / 2]
                    } else {
                        (d[j] - d[j - 1]) * inv[k][j]
                    };
                }
            }
            // Newton form to powers of θ: a ← a (θ − z_k) + d_k, from k = 4 down.
            let mut a = [0.0; 6];
            a[0] = d[5];
            for k in (0..5).rev() {
                for m in (1..6).rev() {
                    a[m] = a[m - 1] - z[k] * a[m];
                }
                a[0] = d[k] - z[k] * a[0];
            }
            for (k, ak) in a.iter().enumerate() {
                c[k * n + i] = *ak;
            }
        }
        self.third_node = Some(tm);
    }

    /// Rewrites components `0..n` (the positions `q` of a state `[q; v]` with `q̇ = v`) as
    /// the quintic Hermite in value, first and second derivative on the step's two ends:
    /// `q`, `q̇ = v = y[n + i]` and `q̈ = f[n + i]`. Its interpolation error
    /// `q⁽⁶⁾(ξ)/6! · (t − t0)³(t − t0 − h)³` is at most `h⁶/46080 · |q⁽⁶⁾|`, a ninth of the
    /// two-step quintic's on the same step (`(t − tm)²(t − t0)²(t − t0 − h)²` with
    /// `tm = t0 − h`), and it needs no earlier point: the first step after a restart
    /// reads positions as accurately as the others. Raises the degree to 5 (the other
    /// components keep their polynomial, padded with zero coefficients).
    pub(crate) fn set_positions_quintic(
        &mut self,
        n: usize,
        y0: &[f64],
        f0: &[f64],
        y1: &[f64],
        f1: &[f64],
    ) {
        let dim = self.dim;
        debug_assert!(n > 0 && 2 * n <= dim, "positions {n} of a state of {dim}");
        if self.degree < 5 {
            self.coeffs.resize(6 * dim, 0.0);
            self.degree = 5;
        }
        let (h, c) = (self.h, &mut self.coeffs);
        for i in 0..n {
            // θ-derivatives: d/dθ = h d/dt.
            let (p0, d0, s0) = (y0[i], h * y0[n + i], h * h * f0[n + i]);
            let (p1, d1, s1) = (y1[i], h * y1[n + i], h * h * f1[n + i]);
            let big_delta = p1 - p0 - d0 - 0.5 * s0;
            let big_d = d1 - d0 - s0;
            let big_s = s1 - s0;
            c[i] = p0;
            c[dim + i] = d0;
            c[2 * dim + i] = 0.5 * s0;
            c[3 * dim + i] = 10.0 * big_delta - 4.0 * big_d + 0.5 * big_s;
            c[4 * dim + i] = -15.0 * big_delta + 7.0 * big_d - big_s;
            c[5 * dim + i] = 6.0 * big_delta - 3.0 * big_d + 0.5 * big_s;
        }
    }

    /// The Dormand–Prince continuous extension (Hairer, Nørsett & Wanner, *Solving ODEs
    /// I*, §II.6, and the `CONTD5` routine of `dopri5.f`):
    /// `y0 + θ (r₂ + (1 − θ)(r₃ + θ (r₄ + (1 − θ) r₅)))` with `r₂ = y1 − y0`,
    /// `r₃ = h f0 − r₂`, `r₄ = r₂ − h f1 − r₃` and `r₅ = h Σ d_i k_i`
    /// ([`DOPRI5_DENSE`](super::tableau::DOPRI5_DENSE)), expanded into powers of θ.
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn set_dopri5(
        &mut self,
        t0: f64,
        h: f64,
        y0: &[f64],
        y1: &[f64],
        f0: &[f64],
        f1: &[f64],
        r5: &[f64],
    ) {
        let n = self.dim;
        let c = self.reset(t0, h, 4);
        for i in 0..n {
            let r2 = y1[i] - y0[i];
            let r3 = h * f0[i] - r2;
            let r4 = r2 - h * f1[i] - r3;
            let r5 = r5[i];
            c[i] = y0[i];
            c[n + i] = r2 + r3;
            c[2 * n + i] = -r3 + r4 + r5;
            c[3 * n + i] = -r4 - 2.0 * r5;
            c[4 * n + i] = r5;
        }
    }

    /// The state at `t` (normally inside `[t0, t1]`; outside it the polynomial is
    /// extrapolated) into `out[..dim]`.
    pub fn eval(&self, t: f64, out: &mut [f64]) {
        let theta = if self.h == 0.0 {
            0.0
        } else {
            (t - self.t0) / self.h
        };
        eval_poly(&self.coeffs, self.dim, self.degree, theta, out);
    }

    /// The time derivative at `t` into `out[..dim]`.
    pub fn eval_derivative(&self, t: f64, out: &mut [f64]) {
        let n = self.dim;
        if self.h == 0.0 || self.degree == 0 {
            out[..n].fill(0.0);
            return;
        }
        let theta = (t - self.t0) / self.h;
        for (i, o) in out.iter_mut().enumerate().take(n) {
            let mut acc = 0.0;
            for k in (1..=self.degree).rev() {
                acc = acc * theta + k as f64 * self.coeffs[k * n + i];
            }
            *o = acc / self.h;
        }
    }

    /// Restricts the polynomial to `[t0, t_end]` (`t_end` inside the step): the same
    /// curve, re-parametrised so that `θ = 1` is `t_end` (`c_k ← c_k rᵏ`,
    /// `r = (t_end − t0)/h`).
    pub fn truncate(&mut self, t_end: f64) {
        if self.h == 0.0 {
            return;
        }
        let r = (t_end - self.t0) / self.h;
        let n = self.dim;
        let mut rk = 1.0;
        for k in 1..=self.degree {
            rk *= r;
            for c in &mut self.coeffs[k * n..(k + 1) * n] {
                *c *= rk;
            }
        }
        self.h = t_end - self.t0;
    }
}

/// Horner evaluation of `Σ_k c_k θᵏ` for every component of a coefficient block laid
/// out as in [`DenseStep::coefficients`].
pub(crate) fn eval_poly(coeffs: &[f64], dim: usize, degree: usize, theta: f64, out: &mut [f64]) {
    for (i, o) in out.iter_mut().enumerate().take(dim) {
        let mut acc = coeffs[degree * dim + i];
        for k in (0..degree).rev() {
            acc = acc * theta + coeffs[k * dim + i];
        }
        *o = acc;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::numerics::tableau::dopri5_dense;

    #[test]
    fn hermite_reproduces_cubics_and_their_derivatives() {
        let y = |t: f64| t * t * t - 2.0 * t + 1.0;
        let dy = |t: f64| 3.0 * t * t - 2.0;
        let mut d = DenseStep::new(1);
        d.set_hermite(0.5, 1.5, &[y(0.5)], &[dy(0.5)], &[y(2.0)], &[dy(2.0)]);
        let mut out = [0.0];
        for t in [0.5, 0.7, 1.3, 2.0] {
            d.eval(t, &mut out);
            assert!((out[0] - y(t)).abs() < 1e-13, "{t}");
            d.eval_derivative(t, &mut out);
            assert!((out[0] - dy(t)).abs() < 1e-12, "{t}");
        }
    }

    /// Positions `q = sin t` of the state `[q; v]` (`v = cos t`, `q̈ = −sin t`): the
    /// quintic in `q, q̇, q̈` reproduces quintics exactly, keeps the other components'
    /// polynomial, converges at order 6 and stays within its error bound
    /// `h⁶/46080 · max |q⁽⁶⁾|` (here `max |sin| ≤ 1`).
    #[test]
    fn positions_quintic_is_exact_for_quintics_and_of_order_six() {
        // A quintic q with its v = q̇ and a = q̈: reproduced to round-off.
        let q = |t: f64| 0.3 * t.powi(5) - t.powi(4) + 2.0 * t.powi(3) - t + 0.5;
        let v = |t: f64| 1.5 * t.powi(4) - 4.0 * t.powi(3) + 6.0 * t * t - 1.0;
        let a = |t: f64| 6.0 * t.powi(3) - 12.0 * t * t + 12.0 * t;
        let (t0, h) = (0.4, 1.3);
        let (t1, mut d) = (t0 + h, DenseStep::new(2));
        d.set_hermite(
            t0,
            h,
            &[q(t0), v(t0)],
            &[v(t0), a(t0)],
            &[q(t1), v(t1)],
            &[v(t1), a(t1)],
        );
        let before = d.clone();
        d.set_positions_quintic(
            1,
            &[q(t0), v(t0)],
            &[v(t0), a(t0)],
            &[q(t1), v(t1)],
            &[v(t1), a(t1)],
        );
        assert_eq!(d.degree(), 5);
        let (mut out, mut old) = ([0.0; 2], [0.0; 2]);
        for k in 0..=20 {
            let t = t0 + h * k as f64 / 20.0;
            d.eval(t, &mut out);
            before.eval(t, &mut old);
            assert!((out[0] - q(t)).abs() < 1e-13, "q at {t}");
            assert_eq!(out[1], old[1], "v keeps its cubic at {t}");
            d.eval_derivative(t, &mut out);
            assert!((out[0] - v(t)).abs() < 1e-12, "q̇ at {t}");
        }
        // sin: order 6 and the bound.
        let worst = |h: f64| {
            let t0 = 0.7;
            let t1 = t0 + h;
            let (y0, f0) = ([t0.sin(), t0.cos()], [t0.cos(), -t0.sin()]);
            let (y1, f1) = ([t1.sin(), t1.cos()], [t1.cos(), -t1.sin()]);
            let mut d = DenseStep::new(2);
            d.set_hermite(t0, h, &y0, &f0, &y1, &f1);
            d.set_positions_quintic(1, &y0, &f0, &y1, &f1);
            let mut out = [0.0; 2];
            (0..=50)
                .map(|k| {
                    let t = t0 + h * k as f64 / 50.0;
                    d.eval(t, &mut out);
                    (out[0] - t.sin()).abs()
                })
                .fold(0.0, f64::max)
        };
        for h in [0.4, 0.2, 0.1] {
            let (e, e2) = (worst(h), worst(h / 2.0));
            assert!(e <= h.powi(6) / 46080.0, "h {h}: {e:e} above the bound");
            let order = (e / e2).log2();
            assert!((5.8..6.2).contains(&order), "h {h}: observed order {order}");
        }
    }

    /// The two-step Hermite extension of the scalar `y` (derivative `dy`) through
    /// `tm`, `t0` and `t0 + h`.
    fn hermite5_of(
        y: &dyn Fn(f64) -> f64,
        dy: &dyn Fn(f64) -> f64,
        tm: f64,
        t0: f64,
        h: f64,
    ) -> DenseStep {
        let mut d = DenseStep::new(1);
        let t1 = t0 + h;
        d.set_hermite5(
            0,
            tm,
            &[y(tm)],
            &[dy(tm)],
            t0,
            h,
            &[y(t0)],
            &[dy(t0)],
            &[y(t1)],
            &[dy(t1)],
        );
        d
    }

    #[test]
    fn two_step_hermite_reproduces_quintics_for_any_step_ratio() {
        let y = |t: f64| 0.3 * t.powi(5) - t.powi(4) + 2.0 * t.powi(3) - t + 0.5;
        let dy = |t: f64| 1.5 * t.powi(4) - 4.0 * t.powi(3) + 6.0 * t * t - 1.0;
        // Previous step 0.1×, 1× and 5× the current one.
        for hm in [0.07, 0.7, 3.5] {
            let (t0, h) = (0.4, 0.7);
            let d = hermite5_of(&y, &dy, t0 - hm, t0, h);
            assert_eq!(d.degree(), 5);
            let mut out = [0.0];
            for theta in [0.0, 0.2, 0.5, 0.9, 1.0] {
                let t = t0 + theta * h;
                d.eval(t, &mut out);
                assert!((out[0] - y(t)).abs() < 1e-12, "hm = {hm}, θ = {theta}");
                d.eval_derivative(t, &mut out);
                assert!((out[0] - dy(t)).abs() < 1e-11, "hm = {hm}, θ = {theta}");
            }
        }
    }

    /// The interpolation error is `O(h⁶)`: halving both steps divides it by 64.
    #[test]
    fn two_step_hermite_has_interpolation_order_six() {
        let error = |h: f64| {
            let t0 = 1.0;
            let d = hermite5_of(
                &|t: f64| t.exp().sin(),
                &|t: f64| t.exp() * t.exp().cos(),
                t0 - 0.8 * h,
                t0,
                h,
            );
            let mut out = [0.0];
            (1..20)
                .map(|k| {
                    let t = t0 + h * k as f64 / 20.0;
                    d.eval(t, &mut out);
                    (out[0] - t.exp().sin()).abs()
                })
                .fold(0.0, f64::max)
        };
        let e: Vec<f64> = [0.1, 0.05, 0.025].iter().map(|&h| error(h)).collect();
        for w in e.windows(2) {
            let order = (w[0] / w[1]).log2();
            assert!((order - 6.0).abs() < 0.3, "interpolation order {order:.2}");
        }
    }

    #[test]
    fn dopri5_expansion_equals_hairers_nested_form() {
        let (y0, y1, f0, f1, r5) = (0.3, -1.1, 2.0, -0.7, 0.25);
        let h = 0.37;
        let mut d = DenseStep::new(1);
        d.set_dopri5(1.0, h, &[y0], &[y1], &[f0], &[f1], &[r5]);
        let mut out = [0.0];
        for theta in [0.0, 0.1, 0.5, 0.77, 1.0] {
            d.eval(1.0 + theta * h, &mut out);
            let reference = dopri5_dense(theta, h, y0, y1, f0, f1, r5);
            assert!((out[0] - reference).abs() < 1e-15, "θ = {theta}");
        }
    }

    #[test]
    fn truncation_keeps_the_curve() {
        let mut d = DenseStep::new(2);
        d.set_hermite(
            0.0,
            2.0,
            &[1.0, 0.0],
            &[0.5, -1.0],
            &[0.0, 3.0],
            &[2.0, 1.0],
        );
        let before: Vec<[f64; 2]> = [0.0, 0.3, 0.9, 1.2]
            .iter()
            .map(|&t| {
                let mut o = [0.0; 2];
                d.eval(t, &mut o);
                o
            })
            .collect();
        d.truncate(1.2);
        assert_eq!(d.t1(), 1.2);
        for (t, b) in [0.0, 0.3, 0.9, 1.2].iter().zip(&before) {
            let mut o = [0.0; 2];
            d.eval(*t, &mut o);
            assert!((o[0] - b[0]).abs() < 1e-14 && (o[1] - b[1]).abs() < 1e-14);
        }
    }
}
