//! The scalars the generated kernels can run on (`#[mechanism(emit = [generic])]`):
//! [`Real`] for `f64` and `f32`, and forward-mode dual numbers [`Dual`] that carry `K`
//! directional derivatives beside the value.
//!
//! A kernel generic over its scalar is one straight-line function of `+`, `−`, `×`, `÷`,
//! `sin`, `cos`, `√`, `exp` and `ln` on the inputs and the scene's parameters; run on
//! `f64` it is the `f64` kernel (bit for bit), on `f32` half the width, on SIMD lanes
//! ([`f64x4`], [`f32x8`]) a batch of states per call, each lane bit for bit the scalar
//! kernel's result (sine, cosine, exponential and logarithm are taken lane by lane from
//! the standard library; the arithmetic and square root are IEEE in every lane), on duals it
//! differentiates itself: seed a coordinate's or a parameter's derivative with 1 and the
//! result's derivative part is the kernel's partial derivative along it, exact to
//! rounding (no step to choose, unlike finite differences).

use std::ops::{Add, Div, Mul, Neg, Sub};

/// Four `f64` lanes (AVX where the build targets it, two SSE2 halves otherwise) and
/// eight `f32` lanes: one kernel call evaluates a batch of states laid out
/// structure-of-arrays, each coordinate a vector of lanes.
pub use wide::{f32x8, f64x4};

/// A scalar the generated kernels run on.
pub trait Real:
    Copy
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
    fn sqrt(self) -> Self;
    fn exp(self) -> Self;
    fn ln(self) -> Self;
}

/// A primitive float: its own operations (`cst` rounds to the nearest value of the type).
macro_rules! primitive {
    ($t:ty) => {
        impl Real for $t {
            #[inline(always)]
            fn cst(x: f64) -> Self {
                x as $t
            }
            #[inline(always)]
            fn sin(self) -> Self {
                <$t>::sin(self)
            }
            #[inline(always)]
            fn cos(self) -> Self {
                <$t>::cos(self)
            }
            #[inline(always)]
            fn sin_cos(self) -> (Self, Self) {
                <$t>::sin_cos(self)
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

primitive!(f64);
primitive!(f32);

/// SIMD lanes: each lane as the scalar would compute it.
macro_rules! lanes {
    ($t:ty, $s:ty) => {
        impl Real for $t {
            #[inline(always)]
            fn cst(x: f64) -> Self {
                <$t>::splat(x as $s)
            }
            #[inline(always)]
            fn sin(self) -> Self {
                <$t>::new(self.to_array().map(<$s>::sin))
            }
            #[inline(always)]
            fn cos(self) -> Self {
                <$t>::new(self.to_array().map(<$s>::cos))
            }
            #[inline(always)]
            fn sin_cos(self) -> (Self, Self) {
                let sc = self.to_array().map(<$s>::sin_cos);
                (<$t>::new(sc.map(|x| x.0)), <$t>::new(sc.map(|x| x.1)))
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

lanes!(f64x4, f64);
lanes!(f32x8, f32);

/// A forward-mode dual number: a value and its derivatives along `K` directions,
/// `x + Σ ε_k ∂_k x` with `ε_j ε_k = 0`.
///
/// ```
/// use filippov_runtime::real::{Dual, Real};
/// // d/dx of x sin x at x = 2, with x seeded along direction 0.
/// let x = Dual::<1>::variable(2.0, 0);
/// let y = x * x.sin();
/// assert!((y.eps[0] - (2.0f64.sin() + 2.0 * 2.0f64.cos())).abs() < 1e-15);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Dual<const K: usize> {
    /// The value.
    pub re: f64,
    /// Its derivatives along the `K` directions.
    pub eps: [f64; K],
}

impl<const K: usize> Dual<K> {
    /// A constant: no derivatives.
    pub fn constant(re: f64) -> Self {
        Dual { re, eps: [0.0; K] }
    }

    /// The variable along direction `k`: value `re`, derivative 1 along `k`, 0 along the
    /// others.
    ///
    /// # Panics
    /// If `k ≥ K`.
    pub fn variable(re: f64, k: usize) -> Self {
        let mut eps = [0.0; K];
        eps[k] = 1.0;
        Dual { re, eps }
    }

    /// The chain rule for a function with value `f` and derivative `df` at `self.re`.
    #[inline(always)]
    fn chain(self, f: f64, df: f64) -> Self {
        Dual {
            re: f,
            eps: self.eps.map(|e| df * e),
        }
    }
}

impl<const K: usize> Add for Dual<K> {
    type Output = Self;
    #[inline(always)]
    fn add(self, o: Self) -> Self {
        Dual {
            re: self.re + o.re,
            eps: std::array::from_fn(|k| self.eps[k] + o.eps[k]),
        }
    }
}

impl<const K: usize> Sub for Dual<K> {
    type Output = Self;
    #[inline(always)]
    fn sub(self, o: Self) -> Self {
        Dual {
            re: self.re - o.re,
            eps: std::array::from_fn(|k| self.eps[k] - o.eps[k]),
        }
    }
}

impl<const K: usize> Mul for Dual<K> {
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

impl<const K: usize> Div for Dual<K> {
    type Output = Self;
    #[inline(always)]
    fn div(self, o: Self) -> Self {
        let inv = 1.0 / o.re;
        let re = self.re * inv;
        Dual {
            re,
            eps: std::array::from_fn(|k| (self.eps[k] - re * o.eps[k]) * inv),
        }
    }
}

impl<const K: usize> Neg for Dual<K> {
    type Output = Self;
    #[inline(always)]
    fn neg(self) -> Self {
        Dual {
            re: -self.re,
            eps: self.eps.map(|e| -e),
        }
    }
}

impl<const K: usize> Real for Dual<K> {
    #[inline(always)]
    fn cst(x: f64) -> Self {
        Dual::constant(x)
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
        self.chain(r, 0.5 / r)
    }
    #[inline(always)]
    fn exp(self) -> Self {
        let e = self.re.exp();
        self.chain(e, e)
    }
    #[inline(always)]
    fn ln(self) -> Self {
        self.chain(self.re.ln(), 1.0 / self.re)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Each rule against a central difference of the value, at points spread over each
    /// function's domain.
    #[test]
    fn dual_rules_match_central_differences() {
        let fs: [(&str, fn(Dual<1>) -> Dual<1>); 9] = [
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
