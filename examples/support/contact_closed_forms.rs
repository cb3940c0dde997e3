//! Closed forms of two contact scenes (theory §8), shared by `tests/contacts.rs` and the
//! report: Housner's rocking block (impact times, speeds and amplitudes, the times by
//! quadrature of the energy equation — no differential equation integrated) and the
//! angle at which a rod tipping over on rough ground starts to slip.

/// Five-point Gauss–Legendre nodes and weights on `[−1, 1]`.
const GAUSS: [(f64, f64); 5] = [
    (-0.906_179_845_938_664, 0.236_926_885_056_189_1),
    (-0.538_469_310_105_683_1, 0.478_628_670_499_366_5),
    (0.0, 0.568_888_888_888_888_9),
    (0.538_469_310_105_683_1, 0.478_628_670_499_366_5),
    (0.906_179_845_938_664, 0.236_926_885_056_189_1),
];

/// `∫₀¹ f` by Gauss–Legendre on `panels` equal panels.
fn integrate(f: impl Fn(f64) -> f64, panels: usize) -> f64 {
    let h = 1.0 / panels as f64;
    (0..panels)
        .map(|p| {
            let mid = (p as f64 + 0.5) * h;
            GAUSS
                .iter()
                .map(|&(x, w)| 0.5 * h * w * f(mid + 0.5 * h * x))
                .sum::<f64>()
        })
        .sum()
}

/// Housner's block (half-width `a`, half-height `b`, gravity `g`) rocking on rigid
/// ground with no slip and no bounce: between impacts it turns about one bottom corner
/// like an inverted pendulum; at each impact (`θ = 0`) the other corner lands and
/// `θ̇⁺ = r θ̇⁻` with `r = 1 − (3/2) sin²α`, `α = atan(a/b)`.
pub struct Housner {
    /// `α`, the angle between the block's vertical axis and a corner's radius.
    pub alpha: f64,
    /// `r`, the impact's angular-velocity ratio.
    pub ratio: f64,
    /// `3 g / (2 R)` with `R = √(a² + b²)`: `θ̇² = k (cos(α − A) − cos(α − θ))` about
    /// a corner from rest at amplitude `A`.
    k: f64,
}

/// One impact: its time, the angular speed `|θ̇⁻|` before it, and the amplitude `|θ|`
/// of the swing after it, reached at `apex`.
#[derive(Clone, Copy, Debug)]
pub struct Impact {
    pub t: f64,
    pub speed: f64,
    pub amplitude: f64,
    pub apex: f64,
}

impl Housner {
    pub fn new(a: f64, b: f64, g: f64) -> Self {
        let alpha = (a / b).atan();
        Housner {
            alpha,
            ratio: 1.0 - 1.5 * alpha.sin().powi(2),
            k: 1.5 * g / a.hypot(b),
        }
    }

    /// The time to fall from rest at amplitude `amp` to `θ = 0`:
    /// `∫₀^A dθ / θ̇`, with `θ = A (1 − s²)` taking the square-root singularity at the
    /// turning point out of the integrand, and `cos x − cos y` written as a product of
    /// sines so the integrand keeps its digits near it.
    pub fn fall_time(&self, amp: f64) -> f64 {
        let alpha = self.alpha;
        integrate(
            |s| {
                let d = 2.0 * (alpha - amp + 0.5 * amp * s * s).sin() * (0.5 * amp * s * s).sin();
                2.0 * amp * s / (self.k * d).sqrt()
            },
            64,
        )
    }

    /// The first `n` impacts after release from rest at `theta0` (`0 < θ₀ < α`).
    pub fn impacts(&self, theta0: f64, n: usize) -> Vec<Impact> {
        let alpha = self.alpha;
        let mut out = Vec::with_capacity(n);
        let (mut t, mut amp) = (self.fall_time(theta0), theta0);
        for _ in 0..n {
            // cos(α − A) − cos α, as a product.
            let drop = 2.0 * (alpha - 0.5 * amp).sin() * (0.5 * amp).sin();
            let speed = (self.k * drop).sqrt();
            // After the impact: cos(α − A') − cos α = r² (cos(α − A) − cos α).
            let after = alpha - (alpha.cos() + self.ratio * self.ratio * drop).acos();
            let rise = self.fall_time(after);
            out.push(Impact {
                t,
                speed,
                amplitude: after,
                apex: t + rise,
            });
            t += 2.0 * rise;
            amp = after;
        }
        out
    }
}

/// The rod of half-length `l` pivoting on its foot from rest at `theta0` from the
/// vertical: with `θ` its angle, the ground's horizontal force (towards the lean) and
/// normal force are `F = (3 m g / 4) sin θ (3 cos θ − 2 cos θ₀)` and
/// `N = m g (1 − (3/4) sin²θ − (3/2)(cos θ₀ − cos θ) cos θ)`; the foot slips at the
/// first `θ > θ₀` where `|F| = μ N` (found by bisection) — backwards, against the lean,
/// where `F > 0` there, forwards where `F < 0`. Returns the angle and the sign of `F`;
/// `None` if it slips at once or the foot lifts (`N = 0`) first.
pub fn rod_slip_angle(mu: f64, theta0: f64) -> Option<(f64, f64)> {
    let c0 = theta0.cos();
    let forces = |th: f64| {
        let (s, c) = th.sin_cos();
        (
            0.75 * s * (3.0 * c - 2.0 * c0),
            1.0 - 0.75 * s * s - 1.5 * (c0 - c) * c,
        )
    };
    let excess = |th: f64| {
        let (f, n) = forces(th);
        f.abs() - mu * n
    };
    if excess(theta0) >= 0.0 {
        return None;
    }
    let (mut lo, mut hi) = (theta0, theta0);
    while excess(hi) < 0.0 {
        lo = hi;
        hi += 1e-3;
        if forces(hi).1 <= 0.0 {
            return None;
        }
    }
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if mid <= lo || mid >= hi {
            break;
        }
        if excess(mid) < 0.0 {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    let theta = 0.5 * (lo + hi);
    Some((theta, forces(theta).0.signum()))
}
