//! Complex numbers as a kernel's scalar, for the complex-step derivative: a second,
//! independent way to differentiate a generic kernel (`emit = [generic]`) beside the
//! dual numbers. For a real-analytic `f`, `f'(x) = Im f(x + i h) / h + O(h²)` with no
//! subtraction, so `h` can be tiny (`1e-100`) and the result is exact to rounding, like
//! the duals' — but computed through complex arithmetic and the complex sine, cosine,
//! square root, exponential and logarithm instead of the chain rule.

use filippov::runtime::Real;
use std::ops::{Add, Div, Mul, Neg, Sub};

/// `re + i im`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Complex {
    pub re: f64,
    pub im: f64,
}

impl Complex {
    pub fn new(re: f64, im: f64) -> Complex {
        Complex { re, im }
    }
}

impl Add for Complex {
    type Output = Complex;
    fn add(self, o: Complex) -> Complex {
        Complex::new(self.re + o.re, self.im + o.im)
    }
}

impl Sub for Complex {
    type Output = Complex;
    fn sub(self, o: Complex) -> Complex {
        Complex::new(self.re - o.re, self.im - o.im)
    }
}

impl Mul for Complex {
    type Output = Complex;
    fn mul(self, o: Complex) -> Complex {
        Complex::new(
            self.re * o.re - self.im * o.im,
            self.re * o.im + self.im * o.re,
        )
    }
}

impl Div for Complex {
    type Output = Complex;
    fn div(self, o: Complex) -> Complex {
        let d = o.re * o.re + o.im * o.im;
        Complex::new(
            (self.re * o.re + self.im * o.im) / d,
            (self.im * o.re - self.re * o.im) / d,
        )
    }
}

impl Neg for Complex {
    type Output = Complex;
    fn neg(self) -> Complex {
        Complex::new(-self.re, -self.im)
    }
}

impl Real for Complex {
    fn cst(x: f64) -> Self {
        Complex::new(x, 0.0)
    }
    fn sin(self) -> Self {
        Complex::new(
            self.re.sin() * self.im.cosh(),
            self.re.cos() * self.im.sinh(),
        )
    }
    fn cos(self) -> Self {
        Complex::new(
            self.re.cos() * self.im.cosh(),
            -self.re.sin() * self.im.sinh(),
        )
    }
    fn sin_cos(self) -> (Self, Self) {
        (self.sin(), self.cos())
    }
    /// The principal root; the imaginary part as `im / (2 re)`, which keeps its digits
    /// when `im` is tiny (the textbook `√((|z| − re)/2)` would cancel them).
    fn sqrt(self) -> Self {
        let r = self.re.hypot(self.im);
        if self.re >= 0.0 {
            let s = ((r + self.re) / 2.0).sqrt();
            Complex::new(s, if s == 0.0 { 0.0 } else { self.im / (2.0 * s) })
        } else {
            let t = ((r - self.re) / 2.0).sqrt().copysign(self.im);
            Complex::new(self.im / (2.0 * t), t)
        }
    }
    fn exp(self) -> Self {
        let e = self.re.exp();
        Complex::new(e * self.im.cos(), e * self.im.sin())
    }
    fn ln(self) -> Self {
        Complex::new(self.re.hypot(self.im).ln(), self.im.atan2(self.re))
    }
}

/// The complex step: small enough that `h²` vanishes beside any value's rounding, large
/// enough that `h` times a kernel's derivatives stays a normal number.
pub const H: f64 = 1e-100;
