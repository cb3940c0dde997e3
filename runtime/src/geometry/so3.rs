//! The rotation group SO(3): hat/vee, exponential and logarithm, the right Jacobian
//! (`dexp` for body velocities) and its inverse, and unit quaternions.
//!
//! Conventions. Rotations act actively on column vectors; a rotation vector `θ` (axis ·
//! angle) maps to `exp(θ̂)` (Rodrigues). Velocities are *right-trivialised* (body
//! angular velocity): `Ṙ = R ω̂`. If `R(t) = R₀ exp(θ(t))` then
//!
//! ```text
//! ω = J_r(θ) θ̇,    J_r(θ) = Σ_k (−θ̂)^k / (k+1)! = I − (1 − cos θ)/θ² θ̂ + (θ − sin θ)/θ³ θ̂²,
//! θ̇ = J_r(θ)⁻¹ ω,  J_r(θ)⁻¹ = Σ_k B_k (−θ̂)^k / k! = I + ½ θ̂ + (1/θ² − (1 + cos θ)/(2θ sin θ)) θ̂²
//! ```
//!
//! (`B_k` the Bernoulli numbers, `B₁ = −½`). `J_r` is `S(φ)` of theory §2 and `dexp_{−θ}`
//! in the notation of Iserles, Munthe-Kaas, Nørsett & Zanna, *Lie-group methods*, Acta
//! Numerica 9 (2000) 215–365, §2.3; the closed forms are in Chirikjian, *Stochastic
//! Models, Information Theory, and Lie Groups II* (2012), §10.2, and Solà, Deray &
//! Atchuthan, *A micro Lie theory*, arXiv:1812.01537, eqs. (143)–(144). Near `θ = 0`
//! every coefficient switches to its Taylor series (below `θ < 1e-3` three terms
//! give full double precision, the next term being `O(θ⁶) < 1e-18`).
//! `J_r⁻¹` is singular at `|θ| = 2π`; callers keep `|θ| < π`.

use nalgebra::{Matrix3, Vector3};

/// Below this angle the Taylor series replace the closed forms.
const SMALL: f64 = 1e-3;

/// `θ̂`, the skew matrix with `θ̂ x = θ × x`.
pub fn hat(theta: &Vector3<f64>) -> Matrix3<f64> {
    Matrix3::new(
        0.0, -theta.z, theta.y, //
        theta.z, 0.0, -theta.x, //
        -theta.y, theta.x, 0.0,
    )
}

/// The vector of a skew matrix (the skew part of any matrix: `(A − Aᵀ)/2`).
pub fn vee(a: &Matrix3<f64>) -> Vector3<f64> {
    Vector3::new(
        0.5 * (a[(2, 1)] - a[(1, 2)]),
        0.5 * (a[(0, 2)] - a[(2, 0)]),
        0.5 * (a[(1, 0)] - a[(0, 1)]),
    )
}

/// `1 − cos θ` as `2 sin²(θ/2)`, without the cancellation (which costs ~1e-10 relative
/// at θ = 1e-3, multiplied by `|θ̂|` in `exp` and `J_r`).
fn one_minus_cos(angle: f64) -> f64 {
    let s = (0.5 * angle).sin();
    2.0 * s * s
}

/// `(sin θ/θ, (1 − cos θ)/θ²)` with Taylor series near 0.
fn rodrigues_coefficients(angle: f64) -> (f64, f64) {
    let t2 = angle * angle;
    if angle < SMALL {
        (
            1.0 - t2 / 6.0 * (1.0 - t2 / 20.0),
            0.5 - t2 / 24.0 * (1.0 - t2 / 30.0),
        )
    } else {
        (angle.sin() / angle, one_minus_cos(angle) / t2)
    }
}

/// `exp(θ̂) = I + (sin θ/θ) θ̂ + ((1 − cos θ)/θ²) θ̂²` (Rodrigues).
pub fn exp(theta: &Vector3<f64>) -> Matrix3<f64> {
    let (a, b) = rodrigues_coefficients(theta.norm());
    let k = hat(theta);
    Matrix3::identity() + k * a + k * k * b
}

/// The rotation vector of `r` with angle in `[0, π]` (through the quaternion of `r`,
/// which stays well conditioned near `π` where `acos((tr R − 1)/2)` does not).
pub fn log(r: &Matrix3<f64>) -> Vector3<f64> {
    UnitQuat::from_matrix(r).log()
}

/// The right Jacobian `J_r(θ)` (`dexp` for body velocities): `ω = J_r(θ) θ̇` when
/// `R = R₀ exp(θ)`. See the module documentation.
pub fn dexp(theta: &Vector3<f64>) -> Matrix3<f64> {
    let angle = theta.norm();
    let t2 = angle * angle;
    let (a, b) = if angle < SMALL {
        (
            0.5 - t2 / 24.0 * (1.0 - t2 / 30.0),
            1.0 / 6.0 - t2 / 120.0 * (1.0 - t2 / 42.0),
        )
    } else {
        (
            one_minus_cos(angle) / t2,
            (angle - angle.sin()) / (t2 * angle),
        )
    };
    let k = hat(theta);
    Matrix3::identity() - k * a + k * k * b
}

/// `J_r(θ)⁻¹ = I + ½ θ̂ + c(θ) θ̂²` with `c = 1/θ² − (1 + cos θ)/(2θ sin θ)
/// = 1/12 + θ²/720 + θ⁴/30240 + …`; finite for `|θ| < 2π`.
pub fn dexp_inv(theta: &Vector3<f64>) -> Matrix3<f64> {
    let angle = theta.norm();
    let t2 = angle * angle;
    let c = if angle < SMALL {
        1.0 / 12.0 + t2 / 720.0 + t2 * t2 / 30240.0
    } else {
        1.0 / t2 - (1.0 + angle.cos()) / (2.0 * angle * angle.sin())
    };
    let k = hat(theta);
    Matrix3::identity() + k * 0.5 + k * k * c
}

/// `J_r(θ)⁻¹ ω` without forming the matrix (the RKMK stage map).
pub fn dexp_inv_apply(theta: &Vector3<f64>, omega: &Vector3<f64>) -> Vector3<f64> {
    let angle = theta.norm();
    let t2 = angle * angle;
    let c = if angle < SMALL {
        1.0 / 12.0 + t2 / 720.0 + t2 * t2 / 30240.0
    } else {
        1.0 / t2 - (1.0 + angle.cos()) / (2.0 * angle * angle.sin())
    };
    let tw = theta.cross(omega);
    omega + tw * 0.5 + theta.cross(&tw) * c
}

/// A unit quaternion `w + x i + y j + z k` (Hamilton convention: `q₁ q₂` rotates by
/// `R(q₁) R(q₂)`), the storage of SO(3) configurations.
///
/// Constructors normalise; products of unit quaternions are unit up to round-off and
/// are *not* re-normalised (see [`normalised`](Self::normalised) and the policy of
/// [`Rkmk5`](crate::liegroup::Rkmk5)). `q` and `−q` are the same rotation.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct UnitQuat {
    w: f64,
    x: f64,
    y: f64,
    z: f64,
}

impl Default for UnitQuat {
    fn default() -> Self {
        Self::IDENTITY
    }
}

impl UnitQuat {
    pub const IDENTITY: UnitQuat = UnitQuat {
        w: 1.0,
        x: 0.0,
        y: 0.0,
        z: 0.0,
    };

    /// The normalised quaternion, or `None` when the components are not finite or the
    /// norm is zero.
    pub fn try_new(w: f64, x: f64, y: f64, z: f64) -> Option<Self> {
        let n = (w * w + x * x + y * y + z * z).sqrt();
        (n.is_finite() && n > 0.0).then(|| UnitQuat {
            w: w / n,
            x: x / n,
            y: y / n,
            z: z / n,
        })
    }

    /// Stored components known to be unit (up to round-off).
    pub(crate) fn from_coords_unchecked(w: f64, x: f64, y: f64, z: f64) -> Self {
        UnitQuat { w, x, y, z }
    }

    /// Components `[w, x, y, z]`.
    pub fn coords(&self) -> [f64; 4] {
        [self.w, self.x, self.y, self.z]
    }

    /// The Euclidean norm (1 up to the round-off of the products since the last
    /// normalisation).
    pub fn norm(&self) -> f64 {
        (self.w * self.w + self.x * self.x + self.y * self.y + self.z * self.z).sqrt()
    }

    /// Divides by the norm.
    pub fn normalised(self) -> Self {
        let n = self.norm();
        UnitQuat {
            w: self.w / n,
            x: self.x / n,
            y: self.y / n,
            z: self.z / n,
        }
    }

    /// The inverse rotation (the conjugate).
    pub fn inverse(&self) -> Self {
        UnitQuat {
            w: self.w,
            x: -self.x,
            y: -self.y,
            z: -self.z,
        }
    }

    /// `exp(θ)`: `(cos(θ/2), sin(θ/2) θ/θ)`, with a series for `sin(θ/2)/θ` near 0.
    pub fn exp(theta: &Vector3<f64>) -> Self {
        let angle = theta.norm();
        let half = 0.5 * angle;
        let s = if angle < SMALL {
            let t2 = angle * angle;
            0.5 - t2 / 48.0 * (1.0 - t2 / 80.0)
        } else {
            half.sin() / angle
        };
        UnitQuat {
            w: half.cos(),
            x: s * theta.x,
            y: s * theta.y,
            z: s * theta.z,
        }
    }

    /// The rotation vector with angle in `[0, π]` (the sign of `q` is chosen with `w ≥ 0`).
    pub fn log(&self) -> Vector3<f64> {
        let sign = if self.w < 0.0 { -1.0 } else { 1.0 };
        let (w, v) = (sign * self.w, Vector3::new(self.x, self.y, self.z) * sign);
        let s = v.norm();
        // θ = 2 atan2(s, w); the factor θ/s has the series 2/w (1 − s²/(3w²)) for small s.
        let f = if s < SMALL * w {
            let r2 = (s / w) * (s / w);
            2.0 / w * (1.0 - r2 / 3.0 * (1.0 - 0.6 * r2))
        } else {
            2.0 * s.atan2(w) / s
        };
        v * f
    }

    /// `R(q)`.
    pub fn to_matrix(&self) -> Matrix3<f64> {
        let UnitQuat { w, x, y, z } = *self;
        Matrix3::new(
            1.0 - 2.0 * (y * y + z * z),
            2.0 * (x * y - w * z),
            2.0 * (x * z + w * y),
            2.0 * (x * y + w * z),
            1.0 - 2.0 * (x * x + z * z),
            2.0 * (y * z - w * x),
            2.0 * (x * z - w * y),
            2.0 * (y * z + w * x),
            1.0 - 2.0 * (x * x + y * y),
        )
    }

    /// The quaternion of a rotation matrix, by Shepperd's method (the largest of
    /// `w², x², y², z²` is computed first, so no division by a small number; S. W.
    /// Shepperd, J. Guidance Control 1 (1978) 223–224). Returned with `w ≥ 0`.
    pub fn from_matrix(r: &Matrix3<f64>) -> Self {
        let tr = r.trace();
        let d = [tr, r[(0, 0)], r[(1, 1)], r[(2, 2)]];
        let (w, x, y, z);
        if d[0] >= d[1] && d[0] >= d[2] && d[0] >= d[3] {
            let s = 2.0 * (1.0 + tr).sqrt(); // 4w
            w = 0.25 * s;
            x = (r[(2, 1)] - r[(1, 2)]) / s;
            y = (r[(0, 2)] - r[(2, 0)]) / s;
            z = (r[(1, 0)] - r[(0, 1)]) / s;
        } else if d[1] >= d[2] && d[1] >= d[3] {
            let s = 2.0 * (1.0 + r[(0, 0)] - r[(1, 1)] - r[(2, 2)]).sqrt(); // 4x
            w = (r[(2, 1)] - r[(1, 2)]) / s;
            x = 0.25 * s;
            y = (r[(0, 1)] + r[(1, 0)]) / s;
            z = (r[(0, 2)] + r[(2, 0)]) / s;
        } else if d[2] >= d[3] {
            let s = 2.0 * (1.0 - r[(0, 0)] + r[(1, 1)] - r[(2, 2)]).sqrt(); // 4y
            w = (r[(0, 2)] - r[(2, 0)]) / s;
            x = (r[(0, 1)] + r[(1, 0)]) / s;
            y = 0.25 * s;
            z = (r[(1, 2)] + r[(2, 1)]) / s;
        } else {
            let s = 2.0 * (1.0 - r[(0, 0)] - r[(1, 1)] + r[(2, 2)]).sqrt(); // 4z
            w = (r[(1, 0)] - r[(0, 1)]) / s;
            x = (r[(0, 2)] + r[(2, 0)]) / s;
            y = (r[(1, 2)] + r[(2, 1)]) / s;
            z = 0.25 * s;
        }
        let sign = if w < 0.0 { -1.0 } else { 1.0 };
        UnitQuat {
            w: sign * w,
            x: sign * x,
            y: sign * y,
            z: sign * z,
        }
        .normalised()
    }

    /// `R(q) v`.
    pub fn rotate(&self, v: &Vector3<f64>) -> Vector3<f64> {
        // v + 2 u × (u × v + w v), u = (x, y, z).
        let u = Vector3::new(self.x, self.y, self.z);
        let t = u.cross(v) + v * self.w;
        v + u.cross(&t) * 2.0
    }
}

impl std::ops::Mul for UnitQuat {
    type Output = UnitQuat;

    /// The Hamilton product (not re-normalised).
    fn mul(self, o: UnitQuat) -> UnitQuat {
        UnitQuat {
            w: self.w * o.w - self.x * o.x - self.y * o.y - self.z * o.z,
            x: self.w * o.x + self.x * o.w + self.y * o.z - self.z * o.y,
            y: self.w * o.y - self.x * o.z + self.y * o.w + self.z * o.x,
            z: self.w * o.z + self.x * o.y - self.y * o.x + self.z * o.w,
        }
    }
}

/// To nalgebra's unit quaternion (the same rotation; nalgebra stores `(x, y, z, w)`).
impl From<UnitQuat> for nalgebra::UnitQuaternion<f64> {
    fn from(q: UnitQuat) -> Self {
        let [w, x, y, z] = q.coords();
        nalgebra::UnitQuaternion::new_unchecked(nalgebra::Quaternion::new(w, x, y, z))
    }
}

/// From nalgebra's unit quaternion (the same rotation).
impl From<nalgebra::UnitQuaternion<f64>> for UnitQuat {
    fn from(q: nalgebra::UnitQuaternion<f64>) -> Self {
        UnitQuat::from_coords_unchecked(q.w, q.i, q.j, q.k)
    }
}

#[cfg(test)]
mod tests {
    #[test]
    fn conversions_to_and_from_nalgebra_keep_the_rotation() {
        let q = UnitQuat::try_new(0.3, -0.5, 0.2, 0.7).unwrap();
        let n: nalgebra::UnitQuaternion<f64> = q.into();
        let v = nalgebra::Vector3::new(0.4, -1.0, 2.0);
        let ours = q.to_matrix() * v;
        assert!((n * v - ours).norm() < 1e-14);
        let back: UnitQuat = n.into();
        let [w, x, y, z] = back.coords();
        let [w0, x0, y0, z0] = q.coords();
        assert!((w - w0).abs() + (x - x0).abs() + (y - y0).abs() + (z - z0).abs() < 1e-15);
    }

    use super::*;

    /// Deterministic pseudo-random vectors (no dev-dependency needed).
    fn vectors(scale: f64) -> Vec<Vector3<f64>> {
        let mut s: u64 = 0x2545_f491_4f6c_dd1d;
        let mut next = || {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            (s >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
        };
        (0..50)
            .map(|_| Vector3::new(next(), next(), next()) * scale)
            .collect()
    }

    /// Rotation vectors at every scale where a branch changes, up to just below π.
    fn samples() -> Vec<Vector3<f64>> {
        let mut out = Vec::new();
        for scale in [1e-9, 1e-4, 9e-4, 1.1e-3, 0.1, 1.0, 1.8] {
            out.extend(vectors(scale));
        }
        out.push(Vector3::zeros());
        out.push(Vector3::new(0.0, 0.0, 3.1));
        out
    }

    fn close(a: &Matrix3<f64>, b: &Matrix3<f64>, tol: f64) -> bool {
        (a - b).abs().max() <= tol
    }

    #[test]
    fn hat_vee_and_exp_is_a_rotation() {
        for th in samples() {
            assert_eq!(vee(&hat(&th)), th);
            let r = exp(&th);
            assert!(close(&(r.transpose() * r), &Matrix3::identity(), 1e-15));
            assert!((r.determinant() - 1.0).abs() < 1e-14);
            // The axis is fixed.
            assert!((r * th - th).norm() <= 1e-15 * th.norm().max(1.0));
        }
    }

    #[test]
    fn log_inverts_exp_and_exp_inverts_log() {
        for th in samples() {
            let back = log(&exp(&th));
            assert!((back - th).norm() < 1e-13 * th.norm().max(1.0), "{th:?}");
            let r = exp(&th);
            assert!(close(&exp(&log(&r)), &r, 1e-14));
        }
        // At π the angle is recovered (the axis up to sign).
        let pi = Vector3::new(0.0, std::f64::consts::PI, 0.0);
        assert!((log(&exp(&pi)).norm() - std::f64::consts::PI).abs() < 1e-12);
    }

    #[test]
    fn dexp_times_dexp_inv_is_identity() {
        for th in samples() {
            let p = dexp(&th) * dexp_inv(&th);
            assert!(close(&p, &Matrix3::identity(), 1e-13), "{th:?}");
            let w = Vector3::new(0.3, -1.2, 0.7);
            assert!((dexp_inv_apply(&th, &w) - dexp_inv(&th) * w).norm() < 1e-14);
        }
    }

    /// Series and closed forms agree across the switch at `SMALL`.
    #[test]
    fn branches_are_continuous() {
        let dir = Vector3::new(0.48, -0.6, 0.64);
        // Points 2e-17 apart on either side of the switch: the difference is the error
        // of one of the branches there (the closed forms of the θ̂² coefficients lose
        // ~1e-9 relative to cancellation, but θ̂² is ~1e-6 in size).
        let below = dir * (SMALL * (1.0 - 1e-14));
        let above = dir * (SMALL * (1.0 + 1e-14));
        assert!(below.norm() < SMALL && above.norm() > SMALL);
        assert!(close(&exp(&below), &exp(&above), 1e-15));
        assert!(close(&dexp(&below), &dexp(&above), 1e-15));
        assert!(close(&dexp_inv(&below), &dexp_inv(&above), 1e-15));
        let (qa, qb) = (UnitQuat::exp(&below), UnitQuat::exp(&above));
        let d: f64 = qa
            .coords()
            .iter()
            .zip(qb.coords())
            .map(|(a, b)| (a - b).abs())
            .sum();
        assert!(d < 1e-15);
    }

    /// `d/ds exp(θ + s δ)|₀ = exp(θ) (J_r(θ) δ)^`, checked by central differences.
    #[test]
    fn dexp_is_the_derivative_of_exp() {
        let delta = Vector3::new(0.2, -0.5, 0.9);
        for th in samples() {
            let eps = 1e-6;
            let fd = (exp(&(th + delta * eps)) - exp(&(th - delta * eps))) / (2.0 * eps);
            let exact = exp(&th) * hat(&(dexp(&th) * delta));
            assert!(
                close(&fd, &exact, 1e-9),
                "{th:?}: {}",
                (fd - exact).abs().max()
            );
        }
    }

    #[test]
    fn quaternion_matrix_round_trip_and_homomorphism() {
        let s = samples();
        for (a, b) in s.iter().zip(s.iter().rev()) {
            let (qa, qb) = (UnitQuat::exp(a), UnitQuat::exp(b));
            assert!(close(&qa.to_matrix(), &exp(a), 1e-15));
            // Matrix → quaternion → matrix, and the quaternion up to sign.
            let q = UnitQuat::from_matrix(&exp(a));
            assert!(close(&q.to_matrix(), &exp(a), 1e-15));
            let sign = if q.coords()[0] * qa.coords()[0] < 0.0 {
                -1.0
            } else {
                1.0
            };
            for (x, y) in q.coords().iter().zip(qa.coords()) {
                assert!((x - sign * y).abs() < 1e-15);
            }
            assert!(close(&(qa * qb).to_matrix(), &(exp(a) * exp(b)), 1e-14));
            assert!(close(
                &(qa * qa.inverse()).to_matrix(),
                &Matrix3::identity(),
                1e-15
            ));
            let v = Vector3::new(1.0, 2.0, -3.0);
            assert!((qa.rotate(&v) - exp(a) * v).norm() < 1e-14);
            assert!((qa.log() - log(&exp(a))).norm() < 1e-14);
        }
        // Shepperd's branches: rotations by π about each axis and near them.
        for axis in [Vector3::x(), Vector3::y(), Vector3::z()] {
            let r = exp(&(axis * (std::f64::consts::PI - 1e-5)));
            assert!(close(&UnitQuat::from_matrix(&r).to_matrix(), &r, 1e-14));
        }
        assert_eq!(UnitQuat::try_new(0.0, 0.0, 0.0, 0.0), None);
        assert_eq!(UnitQuat::try_new(f64::NAN, 1.0, 0.0, 0.0), None);
        assert!((UnitQuat::try_new(2.0, 0.0, 0.0, 0.0).unwrap().norm() - 1.0).abs() < 1e-16);
    }

    /// The drift of `‖q‖` under repeated group updates `q ← q exp(θ)` without
    /// normalisation: a random walk of round-off, about `ε √n`.
    #[test]
    fn product_drift_without_normalisation_is_round_off() {
        let steps = vectors(0.05);
        let mut q = UnitQuat::IDENTITY;
        let n = 100_000;
        let mut worst: f64 = 0.0;
        for i in 0..n {
            q = q * UnitQuat::exp(&steps[i % steps.len()]);
            worst = worst.max((q.norm() - 1.0).abs());
        }
        eprintln!("|‖q‖ − 1| after {n} unnormalised updates: {worst:.1e}");
        assert!(worst < 1e-12, "{worst:e}");
        assert!((q.normalised().norm() - 1.0).abs() < 2.0 * f64::EPSILON);
    }
}
