//! The compact kernels' fused multiply–add twins (`runtime::numerics::fused`).
//!
//! The loops of [`aba`] and [`crba`] write every sum of
//! products of their spatial algebra with [`Real::mul_add`], which rounds twice on
//! `f64`. Run on [`Fma`], an `f64` whose `mul_add` is the processor's fused
//! multiply–add, inside functions compiled for AVX2 and FMA, the same loops take one
//! instruction where they took two, and the joint angles' sines and cosines run four to
//! a register. The derive calls these twins from a compact scene's `f64` forward
//! dynamics and mass matrix where the processor has the features (x86-64 only), and
//! [`forward_dynamics_lanes`] and [`mass_matrix_lanes`] from its generic ones on
//! `f64x4`: the same loops on four states, in the lanes of [`F64x4`].

use std::ops::{Add, Div, Mul, Neg, Sub};

#[cfg(target_arch = "x86_64")]
use super::{Body, Node, Pair, aba, crba};
use crate::numerics::fused_lanes::F64x4;
#[cfg(target_arch = "x86_64")]
use crate::numerics::fused_lanes::align_frame;
use crate::numerics::trig;
use crate::real::Real;

/// An `f64` whose [`Real::mul_add`] is fused (one rounding). Use it only in code
/// compiled with the `fma` target feature, where `f64::mul_add` is one instruction
/// (elsewhere it is a library call).
#[derive(Clone, Copy, Debug, PartialEq, PartialOrd)]
#[repr(transparent)]
pub struct Fma(pub f64);

macro_rules! binary {
    ($tr:ident, $f:ident, $op:tt) => {
        impl $tr for Fma {
            type Output = Fma;
            #[inline(always)]
            fn $f(self, o: Fma) -> Fma {
                Fma(self.0 $op o.0)
            }
        }
    };
}

binary!(Add, add, +);
binary!(Sub, sub, -);
binary!(Mul, mul, *);
binary!(Div, div, /);

impl Neg for Fma {
    type Output = Fma;
    #[inline(always)]
    fn neg(self) -> Fma {
        Fma(-self.0)
    }
}

impl Real for Fma {
    #[inline(always)]
    fn cst(x: f64) -> Self {
        Fma(x)
    }
    #[inline(always)]
    fn sin(self) -> Self {
        Fma(trig::sin_cos_fused(self.0).0)
    }
    #[inline(always)]
    fn cos(self) -> Self {
        Fma(trig::sin_cos_fused(self.0).1)
    }
    #[inline(always)]
    fn sin_cos(self) -> (Self, Self) {
        let (s, c) = trig::sin_cos_fused(self.0);
        (Fma(s), Fma(c))
    }
    #[inline(always)]
    fn sin_cos_n<const K: usize>(x: [Self; K]) -> ([Self; K], [Self; K]) {
        // The angles read and the results written through `f64` views of the arrays,
        // without mapping them between `f64` and `Fma`.
        let mut out = ([Fma(0.0); K], [Fma(0.0); K]);
        trig::sin_cos_slice_fused(f64s(&x), f64s_mut(&mut out.0), f64s_mut(&mut out.1));
        out
    }
    #[inline(always)]
    fn sqrt(self) -> Self {
        Fma(self.0.sqrt())
    }
    #[inline(always)]
    fn exp(self) -> Self {
        Fma(self.0.exp())
    }
    #[inline(always)]
    fn ln(self) -> Self {
        Fma(self.0.ln())
    }
    #[inline(always)]
    fn mul_add(self, a: Self, b: Self) -> Self {
        Fma(self.0.mul_add(a.0, b.0))
    }
}

/// `Fma`s read as the `f64`s they wrap.
#[inline(always)]
fn f64s(x: &[Fma]) -> &[f64] {
    // SAFETY: `Fma` is a `repr(transparent)` `f64`, so a slice of them is a slice of
    // `f64` of the same length.
    unsafe { std::slice::from_raw_parts(x.as_ptr().cast(), x.len()) }
}

/// [`f64s`], to write.
#[inline(always)]
fn f64s_mut(x: &mut [Fma]) -> &mut [f64] {
    // SAFETY: as in `f64s`; the borrow is unique for as long as the result lives.
    unsafe { std::slice::from_raw_parts_mut(x.as_mut_ptr().cast(), x.len()) }
}

/// The table read as [`Fma`]s, without a copy.
#[cfg(target_arch = "x86_64")]
#[inline(always)]
fn as_fused<const B: usize>(bodies: &[Body<f64>; B]) -> &[Body<Fma>; B] {
    // SAFETY: `Fma` is `repr(transparent)` over `f64` and `Body` is `repr(C)`, so
    // `Body<Fma>` has `Body<f64>`'s layout, and arrays of them alike.
    unsafe { &*(bodies as *const [Body<f64>; B]).cast::<[Body<Fma>; B]>() }
}

/// [`aba::forward_dynamics`] on four states at once, in [`F64x4`] lanes with fused
/// multiply–adds: each lane is [`forward_dynamics`] of that lane's state, bit for bit.
/// The generic kernel of a compact scene whose table is constant calls it for `f64x4`
/// where the processor has AVX2 and FMA.
///
/// # Safety
/// Only on a processor with AVX2 and FMA ([`crate::numerics::fused::available`]).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
pub unsafe fn forward_dynamics_lanes<const B: usize, const N: usize>(
    nodes: &[Node; B],
    bodies: &[Body<F64x4>; B],
    gravity: [f64; 3],
    q: &[F64x4; N],
    v: &[F64x4; N],
    tau: &[F64x4; N],
) -> [F64x4; N] {
    align_frame();
    aba::forward_dynamics_in(nodes, bodies, gravity.map(F64x4::cst), q, v, tau)
}

/// [`crba::mass_matrix`] on four states at once, in [`F64x4`] lanes with fused
/// multiply–adds: each lane is [`mass_matrix`] of that lane's state, bit for bit. The
/// generic kernel of a compact scene whose table is constant calls it for `f64x4` where
/// the processor has AVX2 and FMA.
///
/// # Safety
/// Only on a processor with AVX2 and FMA ([`crate::numerics::fused::available`]).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
pub unsafe fn mass_matrix_lanes<const B: usize, const N: usize>(
    nodes: &[Node; B],
    pairs: &[Pair],
    bodies: &[Body<F64x4>; B],
    q: &[F64x4; N],
) -> [[F64x4; N]; N] {
    align_frame();
    crba::mass_matrix_in(nodes, pairs, bodies, q, |x| x)
}

/// The table with each constant in all four lanes, for [`forward_dynamics_lanes`] and
/// [`mass_matrix_lanes`]: the derive evaluates it in a `const`, so that no call spreads
/// the table again. ([`Body::map`] does the same at run time; it takes a closure, which
/// a `const fn` cannot call.)
pub const fn lanes_table<const B: usize>(bodies: &[Body<f64>; B]) -> [Body<F64x4>; B] {
    const fn splat(x: f64) -> F64x4 {
        F64x4([x; 4])
    }
    let zero = splat(0.0);
    let mut out = [Body {
        rotation: [[zero; 3]; 3],
        translation: [zero; 3],
        mass: zero,
        first_moment: [zero; 3],
        inertia: [zero; 6],
    }; B];
    let mut i = 0;
    while i < B {
        let (b, o) = (&bodies[i], &mut out[i]);
        let mut k = 0;
        while k < 3 {
            let mut c = 0;
            while c < 3 {
                o.rotation[k][c] = splat(b.rotation[k][c]);
                c += 1;
            }
            o.translation[k] = splat(b.translation[k]);
            o.first_moment[k] = splat(b.first_moment[k]);
            k += 1;
        }
        o.mass = splat(b.mass);
        let mut k = 0;
        while k < 6 {
            o.inertia[k] = splat(b.inertia[k]);
            k += 1;
        }
        i += 1;
    }
    out
}

/// An array of `f64` read as [`Fma`]s, without a copy.
#[cfg(target_arch = "x86_64")]
#[inline(always)]
fn as_fused_array<const N: usize>(x: &[f64; N]) -> &[Fma; N] {
    // SAFETY: `Fma` is `repr(transparent)` over `f64`, so arrays of them have the same
    // layout.
    unsafe { &*(x as *const [f64; N]).cast::<[Fma; N]>() }
}

/// [`aba::forward_dynamics`] on [`Fma`].
///
/// # Safety
/// Only on a processor with AVX2 and FMA ([`crate::numerics::fused::available`]).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
pub unsafe fn forward_dynamics<const B: usize, const N: usize>(
    nodes: &[Node; B],
    bodies: &[Body<f64>; B],
    gravity: [f64; 3],
    q: &[f64; N],
    v: &[f64; N],
    tau: &[f64; N],
) -> [f64; N] {
    aba::forward_dynamics_in(
        nodes,
        as_fused(bodies),
        gravity.map(Fma),
        as_fused_array(q),
        as_fused_array(v),
        as_fused_array(tau),
    )
    .map(|x| x.0)
}

/// [`crba::mass_matrix`] on [`Fma`].
///
/// # Safety
/// Only on a processor with AVX2 and FMA ([`crate::numerics::fused::available`]).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
pub unsafe fn mass_matrix<const B: usize, const N: usize>(
    nodes: &[Node; B],
    pairs: &[Pair],
    bodies: &[Body<f64>; B],
    q: &[f64; N],
) -> [[f64; N]; N] {
    crba::mass_matrix_in(nodes, pairs, as_fused(bodies), as_fused_array(q), |x| x.0)
}
