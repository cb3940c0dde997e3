//! The local exponential chart a Lie-group step works in: `y = y₀ · exp(Θ)` with
//! `Θ = (θ_1, …, θ_m, δx, δv)`, the vector field in those coordinates, and the
//! magnitudes the error weights use.

use nalgebra::Vector3;

use super::LieState;
use crate::geometry::so3::{self, UnitQuat};

/// `y₀ · exp(Θ)` into `out` (same shapes as `base`).
pub(super) fn retract(base: &LieState, theta: &[f64], out: &mut LieState) {
    let m = base.rotations.len();
    for (k, (q, q0)) in out.rotations.iter_mut().zip(&base.rotations).enumerate() {
        *q = *q0 * UnitQuat::exp(&Vector3::from_column_slice(&theta[3 * k..3 * k + 3]));
    }
    let rest = &theta[3 * m..];
    let n = base.euclid.len();
    for (x, (x0, d)) in out.euclid.iter_mut().zip(base.euclid.iter().zip(rest)) {
        *x = x0 + d;
    }
    for (v, (v0, d)) in out
        .velocity
        .iter_mut()
        .zip(base.velocity.iter().zip(&rest[n..]))
    {
        *v = v0 + d;
    }
}

/// `Θ̇ = (J_r(θ_k)⁻¹ ω_k, u, f)` at `Θ` with `y = y₀ · exp(Θ)` and `f = f(t, y)`.
pub(super) fn chart_field(theta: &[f64], y: &LieState, f: &[f64], out: &mut [f64]) {
    let m = y.rotations.len();
    for k in 0..m {
        let th = Vector3::from_column_slice(&theta[3 * k..3 * k + 3]);
        let w = so3::dexp_inv_apply(&th, &y.omega(k));
        out[3 * k..3 * k + 3].copy_from_slice(w.as_slice());
    }
    let n = y.euclid.len();
    out[3 * m..3 * m + n].copy_from_slice(y.euclid_velocity());
    out[3 * m + n..].copy_from_slice(f);
}

/// Reference magnitudes for the error weights: 1 per rotation component, `|x|`, `|v|`.
pub(super) fn magnitudes(y: &LieState, out: &mut [f64]) {
    let m3 = 3 * y.rotations.len();
    out[..m3].fill(1.0);
    let n = y.euclid.len();
    out[m3..m3 + n].copy_from_slice(&y.euclid);
    out[m3 + n..].copy_from_slice(&y.velocity);
}
