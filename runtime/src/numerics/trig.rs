//! Sine and cosine of several angles at once, in plain arithmetic that the compiler
//! turns into SIMD: the generated kernels take every joint's `(sin q, cos q)` in one
//! call ([`sin_cos_n`]) instead of one library call per joint.
//!
//! The standard library's `sin_cos` is a call into the C library per angle, which the
//! compiler cannot vectorise: on the Panda's forward dynamics its six calls were 14 % of
//! the kernel's time in a default build and 22 % built for AVX2 and FMA (`perf record`).
//! Here the angle is reduced by `π/2` and the two polynomials of the reduced angle are
//! evaluated lane by lane with no branch and no call, so a batch of angles runs in SIMD
//! registers (two per SSE2 register, four with AVX).
//!
//! **Method.** `k = round(x · 2/π)` (by adding and subtracting `1.5 · 2⁵²`, which rounds
//! to nearest without a library call), `r = x − k π/2` in three steps with `π/2` split
//! into three parts, the first two of 33 significant bits (so that `k` times each is
//! exact for `|k| < 2²⁰`),
//! then `sin r` and `cos r` on `|r| ≤ π/4` by the minimax polynomials of degree 13 and
//! 14 of Sun's fdlibm (`k_sin.c`, `k_cos.c`, public coefficients, error below one unit
//! in the last place on that interval), and the quadrant `k mod 4` (the low bits of
//! the rounding sum) swaps and negates them. Angles of magnitude `LIMIT` and beyond, and
//! non-finite ones, go to the standard library, so every input gets an answer the
//! reduction can vouch for. The tests hold every result within one unit in the last
//! place of the standard library's for angles up to 1,000 rad, and within two up to
//! `LIMIT` (the reduced angle's own rounding, which fdlibm carries as a second word,
//! shows there).
//!
//! [`sin_cos_n_fused`] is the same with fused multiply–adds, for code compiled with
//! `#[target_feature(enable = "fma")]`; elsewhere `f64::mul_add` is a library call.

// The coefficients as published: their decimal forms round to the intended values.
#![allow(clippy::excessive_precision)]

/// Beyond this magnitude an angle goes to the standard library (`k` stays below 2¹⁷,
/// far inside the exact range of the three-part reduction).
pub const LIMIT: f64 = 1.0e5;

const TWO_OVER_PI: f64 = std::f64::consts::FRAC_2_PI;
/// `1.5 · 2⁵²`: adding it rounds a value below 2⁵¹ in magnitude to an integer.
const ROUND: f64 = 6_755_399_441_055_744.0;
// π/2 = P1 + P2 + P3 (to about 1e-37), P1 and P2 of 33 significant bits.
const P1: f64 = 1.570_796_326_734_125_614_17;
const P2: f64 = 6.077_100_506_303_965_976_60e-11;
const P3: f64 = 2.022_266_248_795_950_631_54e-21;
// sin r ≈ r + r³ (S1 + z S2 + … + z⁵ S6), z = r².
const S1: f64 = -1.666_666_666_666_663_243_48e-01;
const S2: f64 = 8.333_333_333_322_489_461_24e-03;
const S3: f64 = -1.984_126_982_985_794_931_34e-04;
const S4: f64 = 2.755_731_370_707_006_767_89e-06;
const S5: f64 = -2.505_076_025_340_686_341_95e-08;
const S6: f64 = 1.589_690_995_211_550_102_21e-10;
// cos r ≈ 1 − z/2 + z² (C1 + z C2 + … + z⁵ C6).
const C1: f64 = 4.166_666_666_666_660_190_37e-02;
const C2: f64 = -1.388_888_888_887_410_957_49e-03;
const C3: f64 = 2.480_158_728_947_672_941_78e-05;
const C4: f64 = -2.755_731_435_139_066_330_35e-07;
const C5: f64 = 2.087_572_321_298_174_827_90e-09;
const C6: f64 = -1.135_964_755_778_819_482_65e-11;

/// `a · b + c`, fused (one rounding) when `FUSED`.
#[inline(always)]
fn madd<const FUSED: bool>(a: f64, b: f64, c: f64) -> f64 {
    if FUSED { a.mul_add(b, c) } else { a * b + c }
}

/// One angle, no branch: what each lane of a batch computes.
#[inline(always)]
fn lane<const FUSED: bool>(x: f64) -> (f64, f64) {
    let t = madd::<FUSED>(x, TWO_OVER_PI, ROUND);
    let quadrant = t.to_bits();
    let k = t - ROUND;
    let r = madd::<FUSED>(-k, P3, madd::<FUSED>(-k, P2, madd::<FUSED>(-k, P1, x)));
    let z = r * r;
    let ps = madd::<FUSED>(
        z,
        madd::<FUSED>(z, madd::<FUSED>(z, madd::<FUSED>(z, S6, S5), S4), S3),
        S2,
    );
    let sin = madd::<FUSED>(r * z, madd::<FUSED>(z, ps, S1), r);
    let pc = madd::<FUSED>(
        z,
        madd::<FUSED>(z, madd::<FUSED>(z, madd::<FUSED>(z, C6, C5), C4), C3),
        C2,
    );
    let hz = 0.5 * z;
    let w = 1.0 - hz;
    // 1 − z/2 rounded, then what the rounding lost, then the rest of the series.
    let cos = w + madd::<FUSED>(z * z, madd::<FUSED>(z, pc, C1), (1.0 - w) - hz);
    // Quadrant k mod 4: 1 and 3 swap sine and cosine, 2 and 3 negate the sine, 1 and 2
    // the cosine.
    let swap = quadrant & 1 == 1;
    let (s, c) = if swap { (cos, sin) } else { (sin, cos) };
    let s = f64::from_bits(s.to_bits() ^ ((quadrant & 2) << 62));
    let c = f64::from_bits(c.to_bits() ^ ((quadrant.wrapping_add(1) & 2) << 62));
    (s, c)
}

/// Each `x[i]`'s sine and cosine into `s[i]` and `c[i]`: one loop of [`lane`], which the
/// compiler vectorises, then the standard library's answer for the angles outside its
/// range. Every batch, of an array or of a slice, runs this.
///
/// # Panics
/// If `s` or `c` is shorter than `x`.
#[inline(always)]
fn fill<const FUSED: bool>(x: &[f64], s: &mut [f64], c: &mut [f64]) {
    let (s, c) = (&mut s[..x.len()], &mut c[..x.len()]);
    for i in 0..x.len() {
        (s[i], c[i]) = lane::<FUSED>(x[i]);
    }
    // `!(|v| < LIMIT)`: also true for NaN, in one comparison.
    #[allow(clippy::neg_cmp_op_on_partial_ord)]
    let outside = |v: f64| !(v.abs() < LIMIT);
    if x.iter().any(|&v| outside(v)) {
        for i in 0..x.len() {
            if outside(x[i]) {
                (s[i], c[i]) = x[i].sin_cos();
            }
        }
    }
}

#[inline(always)]
fn batch<const K: usize, const FUSED: bool>(x: [f64; K]) -> ([f64; K], [f64; K]) {
    let mut s = [0.0; K];
    let mut c = [0.0; K];
    fill::<FUSED>(&x, &mut s, &mut c);
    (s, c)
}

/// `(sin x, cos x)` of each of `K` angles, as two arrays.
#[inline(always)]
pub fn sin_cos_n<const K: usize>(x: [f64; K]) -> ([f64; K], [f64; K]) {
    batch::<K, false>(x)
}

/// [`sin_cos_n`] with fused multiply–adds. Call it only from code compiled with the
/// `fma` target feature: without it each `mul_add` is a library call.
#[inline(always)]
pub fn sin_cos_n_fused<const K: usize>(x: [f64; K]) -> ([f64; K], [f64; K]) {
    batch::<K, true>(x)
}

/// [`sin_cos_n_fused`] on a slice: `s[i], c[i] = sin x[i], cos x[i]`, for `x` as long
/// as `s` and `c` (a loop the compiler vectorises whatever the length: the fused lanes'
/// batches, `numerics::fused_lanes`). As there, only for code compiled with `fma`.
///
/// # Panics
/// If `s` or `c` is shorter than `x`.
#[inline(always)]
pub fn sin_cos_slice_fused(x: &[f64], s: &mut [f64], c: &mut [f64]) {
    fill::<true>(x, s, c);
}

/// `(sin x, cos x)` of one angle, by the same arithmetic as [`sin_cos_n`]'s lanes (so
/// that a kernel taking its angles one at a time and one taking them in a batch agree
/// bit for bit).
#[inline(always)]
pub fn sin_cos(x: f64) -> (f64, f64) {
    let ([s], [c]) = sin_cos_n([x]);
    (s, c)
}

/// [`sin_cos`] with fused multiply–adds (the lanes of [`sin_cos_n_fused`]); as there,
/// only for code compiled with the `fma` target feature.
#[inline(always)]
pub fn sin_cos_fused(x: f64) -> (f64, f64) {
    let ([s], [c]) = sin_cos_n_fused([x]);
    (s, c)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Units in the last place between `a` and the reference `b` (at least the spacing
    /// at `b`, so that results near zero are measured on the reference's scale).
    fn ulps(a: f64, b: f64) -> f64 {
        let spacing = f64::from_bits(b.abs().max(f64::MIN_POSITIVE).to_bits() + 1) - b.abs();
        (a - b).abs() / spacing
    }

    fn worst(xs: &[f64]) -> f64 {
        let mut w: f64 = 0.0;
        for chunk in xs.chunks(7) {
            let mut a = [0.0; 7];
            a[..chunk.len()].copy_from_slice(chunk);
            let (s, c) = sin_cos_n(a);
            let (sf, cf) = sin_cos_n_fused(a);
            for (i, &x) in chunk.iter().enumerate() {
                let (es, ec) = x.sin_cos();
                for (got, want) in [(s[i], es), (c[i], ec), (sf[i], es), (cf[i], ec)] {
                    w = w.max(ulps(got, want));
                }
                assert_eq!(
                    sin_cos(x),
                    (s[i], c[i]),
                    "one angle and the batch differ at {x}"
                );
            }
        }
        w
    }

    /// A deterministic spread of angles: uniform in `[-lim, lim]`.
    fn uniform(n: usize, lim: f64, seed: u64) -> Vec<f64> {
        let mut s = seed;
        (0..n)
            .map(|_| {
                s = s
                    .wrapping_mul(6_364_136_223_846_793_005)
                    .wrapping_add(1_442_695_040_888_963_407);
                lim * (2.0 * (s >> 11) as f64 / (1u64 << 53) as f64 - 1.0)
            })
            .collect()
    }

    #[test]
    fn within_an_ulp_of_the_standard_library_and_two_far_out() {
        let mut xs = uniform(200_000, 7.0, 1);
        xs.extend(uniform(100_000, 1e3, 2));
        // Near the multiples of π/2, where the reduction cancels most of the angle.
        for k in -600..=600 {
            let m = k as f64 * std::f64::consts::FRAC_PI_2;
            let mut y = m;
            for _ in 0..8 {
                xs.push(y);
                y = f64::from_bits(y.to_bits() + 1);
            }
        }
        xs.extend([
            0.0,
            -0.0,
            1e-300,
            -1e-300,
            5e-324,
            1e-8,
            std::f64::consts::FRAC_PI_4,
        ]);
        let near = worst(&xs);
        assert!(near <= 1.0, "worst error within 1000 rad: {near} ulp");
        // Out to the limit the reduced angle's own rounding shows.
        let far = worst(&uniform(100_000, 0.999 * LIMIT, 3));
        assert!(far <= 2.0, "worst error within {LIMIT} rad: {far} ulp");
    }

    #[test]
    fn large_and_non_finite_angles_are_the_standard_library_s() {
        let xs = [
            LIMIT,
            -LIMIT,
            1e6,
            -3e15,
            1e300,
            f64::INFINITY,
            f64::NEG_INFINITY,
        ];
        let (s, c) = sin_cos_n(xs);
        for (i, x) in xs.iter().enumerate() {
            assert_eq!((s[i].to_bits(), c[i].to_bits()), {
                let (a, b) = x.sin_cos();
                (a.to_bits(), b.to_bits())
            });
        }
        let (s, c) = sin_cos_n([f64::NAN, 1.0]);
        assert!(s[0].is_nan() && c[0].is_nan());
        assert_eq!((s[1], c[1]), 1.0f64.sin_cos());
    }

    #[test]
    fn signs_and_quadrants() {
        for k in -8..8 {
            let x = k as f64 * std::f64::consts::FRAC_PI_2 + 0.3;
            let (s, c) = sin_cos(x);
            let (es, ec) = x.sin_cos();
            assert_eq!(s.signum(), es.signum(), "sin at {x}");
            assert_eq!(c.signum(), ec.signum(), "cos at {x}");
        }
    }
}
