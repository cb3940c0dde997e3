//! Four `f64` lanes for the fused twins of the kernels generic over their scalar.
//!
//! [`wide::f64x4`](crate::real::f64x4) chooses its instructions when it is compiled: in
//! a default build, two SSE2 halves and a multiply–add rounded twice, even inside a
//! function compiled for AVX2 and FMA. [`F64x4`] is four `f64` in one 32-byte block
//! whose operations are written lane by lane in plain Rust, so the compiler vectorises
//! them for the function they are inlined into: one AVX register per value, and
//! [`Real::mul_add`] one fused instruction, in the derive's twins (compiled with
//! `#[target_feature(enable = "avx2,fma")]`, [`fused`](super::fused)). Anywhere else they
//! are correct and slow (`f64::mul_add` is then a library call): the type is not meant
//! for user code.
//!
//! The kernels generic over their scalar call their twin on `F64x4` when they are
//! called on [`f64x4`] and [`fused::enabled`](super::fused::enabled)
//! holds: [`to_fused`] reads the inputs in place, [`from_fused`] copies the result. Each lane of the
//! twin rounds as the `f64` kernel's fused twin does (the same products fused, the same
//! sines and cosines), so a batch's lanes and the scalar kernel agree bit for bit in
//! both modes.

use std::any::TypeId;
use std::ops::{Add, Div, Mul, Neg, Sub};

use super::trig;
use crate::real::{Lanes, Real, f64x4};

/// Four `f64` lanes whose arithmetic the compiler vectorises where it is inlined (see
/// the module's documentation).
#[derive(Clone, Copy, Debug, PartialEq)]
#[repr(C, align(32))]
pub struct F64x4(pub [f64; 4]);

macro_rules! lanewise {
    ($tr:ident, $f:ident, $op:tt) => {
        impl $tr for F64x4 {
            type Output = Self;
            #[inline(always)]
            fn $f(self, o: Self) -> Self {
                let (a, b) = (self.0, o.0);
                F64x4([a[0] $op b[0], a[1] $op b[1], a[2] $op b[2], a[3] $op b[3]])
            }
        }
    };
}

lanewise!(Add, add, +);
lanewise!(Sub, sub, -);
lanewise!(Mul, mul, *);
lanewise!(Div, div, /);

impl Neg for F64x4 {
    type Output = Self;
    #[inline(always)]
    fn neg(self) -> Self {
        let a = self.0;
        F64x4([-a[0], -a[1], -a[2], -a[3]])
    }
}

impl Real for F64x4 {
    #[inline(always)]
    fn cst(x: f64) -> Self {
        F64x4([x; 4])
    }
    #[inline(always)]
    fn sin(self) -> Self {
        self.sin_cos().0
    }
    #[inline(always)]
    fn cos(self) -> Self {
        self.sin_cos().1
    }
    #[inline(always)]
    fn sin_cos(self) -> (Self, Self) {
        let ([s], [c]) = Self::sin_cos_n([self]);
        (s, c)
    }
    // All `4 K` lanes in one loop, which the compiler vectorises four to a register
    // (four lanes of one angle alone it left scalar, at a third of the Panda's time). No
    // `map`: an array's `map` is a function call the compiler may leave out of line,
    // and there, outside the twin's target features, each fused multiply–add is a
    // library call.
    #[inline(always)]
    fn sin_cos_n<const K: usize>(x: [Self; K]) -> ([Self; K], [Self; K]) {
        let mut xs = [[0.0; 4]; K];
        for k in 0..K {
            xs[k] = x[k].0;
        }
        let mut s = [[0.0; 4]; K];
        let mut c = [[0.0; 4]; K];
        trig::sin_cos_slice_fused(
            xs.as_flattened(),
            s.as_flattened_mut(),
            c.as_flattened_mut(),
        );
        let mut out = ([F64x4([0.0; 4]); K], [F64x4([0.0; 4]); K]);
        for k in 0..K {
            (out.0[k], out.1[k]) = (F64x4(s[k]), F64x4(c[k]));
        }
        out
    }
    #[inline(always)]
    fn sqrt(self) -> Self {
        let a = self.0;
        F64x4([a[0].sqrt(), a[1].sqrt(), a[2].sqrt(), a[3].sqrt()])
    }
    #[inline(always)]
    fn exp(self) -> Self {
        let a = self.0;
        F64x4([a[0].exp(), a[1].exp(), a[2].exp(), a[3].exp()])
    }
    #[inline(always)]
    fn ln(self) -> Self {
        let a = self.0;
        F64x4([a[0].ln(), a[1].ln(), a[2].ln(), a[3].ln()])
    }
    /// One rounding per lane (`f64::mul_add`).
    #[inline(always)]
    fn mul_add(self, a: Self, b: Self) -> Self {
        let (x, y, z) = (self.0, a.0, b.0);
        F64x4([
            f64::mul_add(x[0], y[0], z[0]),
            f64::mul_add(x[1], y[1], z[1]),
            f64::mul_add(x[2], y[2], z[2]),
            f64::mul_add(x[3], y[3], z[3]),
        ])
    }
}

impl Lanes for F64x4 {
    const LANES: usize = 4;
    #[inline(always)]
    fn from_fn(f: impl FnMut(usize) -> f64) -> Self {
        F64x4(std::array::from_fn(f))
    }
    #[inline(always)]
    fn lane(self, i: usize) -> f64 {
        self.0[i]
    }
}

/// Makes the function it is inlined into align its stack frame to 32 bytes, by keeping
/// one [`F64x4`] in memory there. The twins call it first: without a frame pointer the
/// compiler does not realign the frame for its own spills, and spills 32 bytes wide at
/// addresses aligned to 16 split across cache lines every other time (the Panda's twin
/// on four lanes, in a scratch release crate: 83.6 ns per state without this call, 71.0
/// with it, one measurement of each, median of 21 batches).
#[inline(always)]
pub fn align_frame() {
    let mut a = F64x4([0.0; 4]);
    std::hint::black_box(&mut a);
}

// `F64x4` has `f64x4`'s layout: 32 bytes aligned to 32 holding the four lanes in order
// (`wide` declares its lanes plain old data and converts them to and from `[f64; 4]` by
// reinterpreting the bytes). The conversions below rely on it and check it here.
const _: () =
    assert!(size_of::<F64x4>() == size_of::<f64x4>() && align_of::<F64x4>() == align_of::<f64x4>());

/// `x` as [`F64x4`] lanes, in place, when its scalar `T` is [`f64x4`]; `None` for any
/// other scalar.
#[inline(always)]
pub fn to_fused<T: Real, const K: usize>(x: &[T; K]) -> Option<&[F64x4; K]> {
    if TypeId::of::<T>() != TypeId::of::<f64x4>() {
        return None;
    }
    // SAFETY: `T` is `f64x4`, whose layout `F64x4` has (checked above), so `[T; K]` and
    // `[F64x4; K]` have the same layout too, and every bit pattern is a valid `F64x4`.
    Some(unsafe { &*(x as *const [T; K]).cast::<[F64x4; K]>() })
}

/// A value made of [`F64x4`] lanes (a lane vector, or arrays of them), with its
/// counterpart in [`f64x4`].
///
/// # Safety
/// `Wide` must have `Self`'s layout, lane for lane.
pub unsafe trait FusedValue: Copy {
    /// The same shape in `f64x4`.
    type Wide: 'static;
}

// SAFETY: the layouts are the same (checked above).
unsafe impl FusedValue for F64x4 {
    type Wide = f64x4;
}

// SAFETY: arrays of values of the same layout have the same layout.
unsafe impl<X: FusedValue, const K: usize> FusedValue for [X; K] {
    type Wide = [X::Wide; K];
}

/// The twin's result `x` as the generic kernel's return type `R`, which is `x`'s shape
/// in `f64x4`: the same bytes, one copy (a result returned in an `Option` took two, a
/// third of the humanoid's mass matrix on lanes).
///
/// # Panics
/// If `R` is not `x`'s shape in `f64x4`. The generated kernels call it only after
/// [`to_fused`] has found their scalar to be `f64x4`, so their `R` always is.
#[inline(always)]
pub fn from_fused<R: 'static, X: FusedValue>(x: X) -> R {
    assert!(
        TypeId::of::<R>() == TypeId::of::<X::Wide>(),
        "from_fused: the result type is not the twin's shape in f64x4"
    );
    // SAFETY: `R` is `X::Wide`, whose layout is `X`'s (`FusedValue`), and `X` is `Copy`
    // (nothing to drop twice).
    unsafe { std::mem::transmute_copy::<X, R>(&x) }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn converts_only_f64x4_and_back() {
        let x = [f64x4::new([1.0, 2.0, 3.0, 4.0]); 2];
        let f = *to_fused(&x).expect("f64x4 converts");
        assert_eq!(f[1].0, [1.0, 2.0, 3.0, 4.0]);
        assert!(to_fused(&[1.0f64; 2]).is_none());
        let back: [f64x4; 2] = from_fused(f);
        assert_eq!(back.map(|l| l.to_array()), x.map(|l| l.to_array()));
        let wrong = std::panic::catch_unwind(|| from_fused::<[f64; 8], _>(f));
        assert!(wrong.is_err(), "a result of another shape is refused");
    }

    #[test]
    fn lanes_round_as_the_fused_scalar() {
        let a = F64x4([0.1, -2.5, 3.0e10, 7.0]);
        let b = F64x4([3.3, 1.0 / 3.0, -1e-7, 0.5]);
        let c = F64x4([1.0, 2.0, -3.0, 1e300]);
        let r = a.mul_add(b, c);
        for i in 0..4 {
            assert_eq!(r.0[i].to_bits(), a.0[i].mul_add(b.0[i], c.0[i]).to_bits());
            let (s, k) = a.sin_cos();
            assert_eq!(s.0[i].to_bits(), trig::sin_cos_fused(a.0[i]).0.to_bits());
            assert_eq!(k.0[i].to_bits(), trig::sin_cos_fused(a.0[i]).1.to_bits());
        }
    }
}
