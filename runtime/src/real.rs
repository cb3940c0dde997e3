//! The scalars the generated kernels can run on (`#[mechanism(emit = [generic])]`):
//! [`Real`] for `f64` and `f32`, and forward-mode dual numbers [`Dual`] that carry `K`
//! directional derivatives beside the value.
//!
//! A kernel generic over its scalar is one straight-line function of `+`, `−`, `×`, `÷`,
//! `sin`, `cos`, `√`, `exp` and `ln` on the inputs and the scene's parameters; run on
//! `f64` it is the `f64` kernel (bit for bit), on `f32` half the width, on SIMD lanes
//! ([`f64x4`], [`f32x8`]) a batch of states per call, each lane bit for bit the scalar
//! kernel's result (sine and cosine of `f64` from [`numerics::trig`](crate::numerics::trig)
//! on all lanes at once, of `f32` and the exponential and logarithm lane by lane from the
//! standard library; the arithmetic and square root are IEEE in every lane), on duals it
//! differentiates itself: seed a coordinate's or a parameter's derivative with 1 and the
//! result's derivative part is the kernel's partial derivative along it, exact to
//! rounding (no step to choose, unlike finite differences).

use std::ops::{Add, Div, Mul, Neg, Sub};

/// Four `f64` lanes (AVX where the build targets it, two SSE2 halves otherwise) and
/// eight `f32` lanes, and their halves, two `f64` and four `f32` lanes (one SSE2
/// register each): one kernel call evaluates a batch of states laid out
/// structure-of-arrays, each coordinate a vector of lanes.
pub use wide::{f32x4, f32x8, f64x2, f64x4};

/// The `f64` lanes to batch states in: [`f64x4`] where the build targets AVX (for
/// example `RUSTFLAGS="-C target-cpu=native"` on an AVX2 machine), and on every x86-64
/// build (this one), [`f64x2`] elsewhere.
///
/// A default x86-64 build targets SSE2's 128-bit registers, where `f64x4` runs each
/// operation as two halves. But the forward dynamics and the mass matrix generic over
/// their scalar recognise `f64x4` and call their fused twins, compiled for AVX2 and FMA,
/// where the processor has them ([`numerics::fused_lanes`](crate::numerics::fused_lanes)):
/// four states in one register. On a processor without them, `f64x4` costs up to about
/// a tenth more per state than `f64x2` would (the Panda's portable forward dynamics in a
/// scratch crate: 226 ns per state against 204–228), and the twin of a large mass matrix
/// does not pay (the humanoid's; the report's section on scalars times every width).
#[cfg(any(target_feature = "avx", target_arch = "x86_64"))]
pub type F64Lanes = f64x4;
/// The `f64` lanes to batch states in: [`f64x4`] where the build targets AVX and on
/// x86-64, [`f64x2`] elsewhere (this build).
#[cfg(not(any(target_feature = "avx", target_arch = "x86_64")))]
pub type F64Lanes = f64x2;
/// The `f32` lanes that fill one SIMD register of the build's target: [`f32x8`] with
/// AVX (this build), [`f32x4`] otherwise (`f32` has no fused twins).
#[cfg(target_feature = "avx")]
pub type F32Lanes = f32x8;
/// The `f32` lanes that fill one SIMD register of the build's target: [`f32x8`] with
/// AVX, [`f32x4`] otherwise (this build; `f32` has no fused twins).
#[cfg(not(target_feature = "avx"))]
pub type F32Lanes = f32x4;

/// A scalar the generated kernels run on (`'static`: the generic kernels recognise
/// [`f64x4`] by its type, to call their fused twins, `numerics::fused_lanes`).
pub trait Real:
    'static
    + Copy
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + Neg<Output = Self>
{
    /// The constant `x` (a literal of the generated code or a parameter's value).
    fn cst(x: f64) -> Self;
    fn sin(self) -> Self;
    fn cos(self) -> Self;
    /// `(sin x, cos x)` together (one evaluation where the scalar has one).
    fn sin_cos(self) -> (Self, Self);
    /// `(sin x, cos x)` of each of `K` values, as two arrays: on `f64` one batch that
    /// runs in SIMD registers ([`numerics::trig`](crate::numerics::trig)), the same bit
    /// for bit as [`sin_cos`](Real::sin_cos) of each.
    #[inline(always)]
    fn sin_cos_n<const K: usize>(x: [Self; K]) -> ([Self; K], [Self; K]) {
        let sc = x.map(Self::sin_cos);
        (sc.map(|x| x.0), sc.map(|x| x.1))
    }
    fn sqrt(self) -> Self;
    fn exp(self) -> Self;
    fn ln(self) -> Self;
    /// `self · a + b`: two roundings on every scalar here, one on the fused scalar of
    /// the compact kernels' twins (`compact::fused`), which is what the spatial algebra
    /// writes its sums of products with.
    #[inline(always)]
    fn mul_add(self, a: Self, b: Self) -> Self {
        self * a + b
    }
}

/// A primitive float: its own operations (`cst` rounds to the nearest value of the type),
/// its sines and cosines from `$trig`, a function giving `(sin x, cos x)`, and from
/// `$batch` for an array of them when given.
macro_rules! primitive {
    ($t:ty, $trig:path $(, $batch:path)?) => {
        impl Real for $t {
            $(
                #[inline(always)]
                fn sin_cos_n<const K: usize>(x: [Self; K]) -> ([Self; K], [Self; K]) {
                    $batch(x)
                }
            )?
            #[inline(always)]
            fn cst(x: f64) -> Self {
                x as $t
            }
            #[inline(always)]
            fn sin(self) -> Self {
                $trig(self).0
            }
            #[inline(always)]
            fn cos(self) -> Self {
                $trig(self).1
            }
            #[inline(always)]
            fn sin_cos(self) -> (Self, Self) {
                $trig(self)
            }
            #[inline(always)]
            fn sqrt(self) -> Self {
                <$t>::sqrt(self)
            }
            #[inline(always)]
            fn exp(self) -> Self {
                <$t>::exp(self)
            }
            #[inline(always)]
            fn ln(self) -> Self {
                <$t>::ln(self)
            }
        }
    };
}

// `f64` takes its sines and cosines from `numerics::trig`, whose batches vectorise, so
// that a kernel is the same bit for bit whether it takes its angles one at a time (the
// generic kernels, the compact loops) or in a batch (the `f64` kernels).
primitive!(
    f64,
    crate::numerics::trig::sin_cos,
    crate::numerics::trig::sin_cos_n
);
primitive!(f32, f32::sin_cos);

/// SIMD lanes: each lane as the scalar would compute it, the sines and cosines of all
/// lanes from `$trig`, a function from an array of lanes to the arrays of their sines and
/// cosines.
macro_rules! lanes {
    ($t:ty, $s:ty, $trig:expr) => {
        impl Real for $t {
            #[inline(always)]
            fn cst(x: f64) -> Self {
                <$t>::splat(x as $s)
            }
            #[inline(always)]
            fn sin(self) -> Self {
                <$t>::new($trig(self.to_array()).0)
            }
            #[inline(always)]
            fn cos(self) -> Self {
                <$t>::new($trig(self.to_array()).1)
            }
            #[inline(always)]
            fn sin_cos(self) -> (Self, Self) {
                let (s, c) = $trig(self.to_array());
                (<$t>::new(s), <$t>::new(c))
            }
            #[inline(always)]
            fn sqrt(self) -> Self {
                <$t>::sqrt(self)
            }
            #[inline(always)]
            fn exp(self) -> Self {
                <$t>::new(self.to_array().map(<$s>::exp))
            }
            #[inline(always)]
            fn ln(self) -> Self {
                <$t>::new(self.to_array().map(<$s>::ln))
            }
        }
    };
}

/// Each `f32` lane's sine and cosine from the standard library.
#[inline(always)]
fn f32_lanes<const L: usize>(x: [f32; L]) -> ([f32; L], [f32; L]) {
    let sc = x.map(f32::sin_cos);
    (sc.map(|x| x.0), sc.map(|x| x.1))
}

lanes!(f64x4, f64, crate::numerics::trig::sin_cos_n);
lanes!(f32x8, f32, f32_lanes);
lanes!(f64x2, f64, crate::numerics::trig::sin_cos_n);
lanes!(f32x4, f32, f32_lanes);

/// SIMD lanes as a batch of states: `L::LANES` states per kernel call, each coordinate
/// one vector of lanes (structure of arrays). [`pack`] and [`unpack`] convert from and
/// to one array per state.
pub trait Lanes: Real {
    /// The number of lanes (states per call).
    const LANES: usize;
    /// The vector whose lane `i` is `f(i)` (rounded to the lane's type).
    fn from_fn(f: impl FnMut(usize) -> f64) -> Self;
    /// Lane `i` (as `f64`).
    fn lane(self, i: usize) -> f64;
}

macro_rules! batch {
    ($t:ty, $s:ty, $l:literal) => {
        impl Lanes for $t {
            const LANES: usize = $l;
            #[inline(always)]
            fn from_fn(mut f: impl FnMut(usize) -> f64) -> Self {
                <$t>::new(std::array::from_fn(|i| f(i) as $s))
            }
            #[inline(always)]
            fn lane(self, i: usize) -> f64 {
                self.to_array()[i] as f64
            }
        }
    };
}

batch!(f64x4, f64, 4);
batch!(f32x8, f32, 8);
batch!(f64x2, f64, 2);
batch!(f32x4, f32, 4);

/// One lane: the scalar itself, so that code written for batches runs on single states.
impl Lanes for f64 {
    const LANES: usize = 1;
    #[inline(always)]
    fn from_fn(mut f: impl FnMut(usize) -> f64) -> Self {
        f(0)
    }
    #[inline(always)]
    fn lane(self, _: usize) -> f64 {
        self
    }
}

/// Packs up to `L::LANES` states (one array each) into one array of lanes: lane `i` of
/// entry `k` is `states[i][k]`. Fewer states than lanes fill the remaining lanes with
/// the last state (so that every lane computes something finite); an empty slice gives
/// zeros.
///
/// ```
/// use filippov_runtime::real::{Lanes, f64x4, pack, unpack};
/// let states = [[1.0, 2.0], [3.0, 4.0], [5.0, 6.0]];
/// let x: [f64x4; 2] = pack(&states);
/// assert_eq!(x[1].lane(2), 6.0);
/// assert_eq!(unpack(&x, 3), states.to_vec());
/// ```
pub fn pack<L: Lanes, const M: usize>(states: &[[f64; M]]) -> [L; M] {
    let last = states.len().saturating_sub(1);
    std::array::from_fn(|k| L::from_fn(|i| states.get(i.min(last)).map_or(0.0, |s| s[k])))
}

/// The first `count` states (at most `L::LANES`) of a batch, one array each: the
/// inverse of [`pack`].
pub fn unpack<L: Lanes, const M: usize>(x: &[L; M], count: usize) -> Vec<[f64; M]> {
    (0..count.min(L::LANES))
        .map(|i| x.map(|l| l.lane(i)))
        .collect()
}

/// A forward-mode dual number: a value and its derivatives along `K` directions,
/// `x + Σ ε_k ∂_k x` with `ε_j ε_k = 0`, all of scalar `T` (`f64` unless named:
/// `Dual<8, f64x4>` carries the derivatives of four states at once).
///
/// ```
/// use filippov_runtime::real::{Dual, Real};
/// // d/dx of x sin x at x = 2, with x seeded along direction 0.
/// let x = Dual::<1>::variable(2.0, 0);
/// let y = x * x.sin();
/// assert!((y.eps[0] - (2.0f64.sin() + 2.0 * 2.0f64.cos())).abs() < 1e-15);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Dual<const K: usize, T = f64> {
    /// The value.
    pub re: T,
    /// Its derivatives along the `K` directions.
    pub eps: [T; K],
}

impl<const K: usize, T: Real> Dual<K, T> {
    /// A constant: no derivatives.
    #[inline(always)]
    pub fn constant(re: T) -> Self {
        Dual {
            re,
            eps: [T::cst(0.0); K],
        }
    }

    /// The variable along direction `k`: value `re`, derivative 1 along `k`, 0 along the
    /// others.
    ///
    /// # Panics
    /// If `k ≥ K`.
    pub fn variable(re: T, k: usize) -> Self {
        let mut eps = [T::cst(0.0); K];
        eps[k] = T::cst(1.0);
        Dual { re, eps }
    }

    /// The chain rule for a function with value `f` and derivative `df` at `self.re`.
    #[inline(always)]
    fn chain(self, f: T, df: T) -> Self {
        Dual {
            re: f,
            eps: self.eps.map(|e| df * e),
        }
    }
}

impl<const K: usize, T: Real> Add for Dual<K, T> {
    type Output = Self;
    #[inline(always)]
    fn add(self, o: Self) -> Self {
        Dual {
            re: self.re + o.re,
            eps: std::array::from_fn(|k| self.eps[k] + o.eps[k]),
        }
    }
}

impl<const K: usize, T: Real> Sub for Dual<K, T> {
    type Output = Self;
    #[inline(always)]
    fn sub(self, o: Self) -> Self {
        Dual {
            re: self.re - o.re,
            eps: std::array::from_fn(|k| self.eps[k] - o.eps[k]),
        }
    }
}

impl<const K: usize, T: Real> Mul for Dual<K, T> {
    type Output = Self;
    // The product rule: the derivative of a product is a sum.
    #[allow(clippy::suspicious_arithmetic_impl)]
    #[inline(always)]
    fn mul(self, o: Self) -> Self {
        Dual {
            re: self.re * o.re,
            eps: std::array::from_fn(|k| self.eps[k] * o.re + self.re * o.eps[k]),
        }
    }
}

impl<const K: usize, T: Real> Div for Dual<K, T> {
    type Output = Self;
    #[inline(always)]
    fn div(self, o: Self) -> Self {
        let inv = T::cst(1.0) / o.re;
        let re = self.re * inv;
        Dual {
            re,
            eps: std::array::from_fn(|k| (self.eps[k] - re * o.eps[k]) * inv),
        }
    }
}

impl<const K: usize, T: Real> Neg for Dual<K, T> {
    type Output = Self;
    #[inline(always)]
    fn neg(self) -> Self {
        Dual {
            re: -self.re,
            eps: self.eps.map(|e| -e),
        }
    }
}

/// On any scalar: `Dual<K, f64>` for derivatives of `f64` kernels, `Dual<K, f64x4>` for
/// derivatives of four states at once, nested duals for second derivatives.
impl<const K: usize, T: Real> Real for Dual<K, T> {
    #[inline(always)]
    fn cst(x: f64) -> Self {
        Dual::constant(T::cst(x))
    }
    #[inline(always)]
    fn sin(self) -> Self {
        let (s, c) = self.re.sin_cos();
        self.chain(s, c)
    }
    #[inline(always)]
    fn cos(self) -> Self {
        let (s, c) = self.re.sin_cos();
        self.chain(c, -s)
    }
    #[inline(always)]
    fn sin_cos(self) -> (Self, Self) {
        let (s, c) = self.re.sin_cos();
        (self.chain(s, c), self.chain(c, -s))
    }
    #[inline(always)]
    fn sqrt(self) -> Self {
        let r = self.re.sqrt();
        self.chain(r, T::cst(0.5) / r)
    }
    #[inline(always)]
    fn exp(self) -> Self {
        let e = self.re.exp();
        self.chain(e, e)
    }
    #[inline(always)]
    fn ln(self) -> Self {
        self.chain(self.re.ln(), T::cst(1.0) / self.re)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Each rule against a central difference of the value, at points spread over each
    /// function's domain.
    #[test]
    fn dual_rules_match_central_differences() {
        type Rule = (&'static str, fn(Dual<1>) -> Dual<1>);
        let fs: [Rule; 9] = [
            ("sin", |x| x.sin()),
            ("cos", |x| x.cos()),
            ("sin_cos.0 + sin_cos.1", |x| {
                let (s, c) = x.sin_cos();
                s * Dual::cst(3.0) + c
            }),
            ("sqrt", |x| x.sqrt()),
            ("exp", |x| x.exp()),
            ("ln", |x| x.ln()),
            ("x / (1 + x²)", |x| x / (Dual::cst(1.0) + x * x)),
            ("−x − 2", |x| -x - Dual::cst(2.0)),
            ("x³", |x| x * x * x),
        ];
        for (name, f) in fs {
            for x in [0.3, 0.9, 1.7, 2.6, 4.1] {
                let d = f(Dual::variable(x, 0)).eps[0];
                let h = 1e-6;
                let fd = (f(Dual::constant(x + h)).re - f(Dual::constant(x - h)).re) / (2.0 * h);
                assert!(
                    (d - fd).abs() <= 1e-8 * (1.0 + d.abs()),
                    "{name} at {x}: {d} against {fd}"
                );
            }
        }
    }

    #[test]
    fn directions_are_independent() {
        let (x, y) = (Dual::<2>::variable(1.5, 0), Dual::<2>::variable(-0.5, 1));
        let z = x * y + x.exp();
        assert_eq!(z.eps, [-0.5 + 1.5f64.exp(), 1.5]);
    }
}
