//! The applied generalised forces `τ(t, q, v)` of a non-smooth run: a function of time
//! and state, and, for a controller driving an
//! [`Integrator`](crate::nonsmooth::Integrator), a value held between its samples.

use nalgebra::SVector;

/// Applied generalised forces `τ(t, q, v)` on the `N` coordinates. Every closure
/// `Fn(f64, &SVector<f64, N>, &SVector<f64, N>) -> SVector<f64, N>` is one.
pub trait Input<const N: usize> {
    fn forces(&self, t: f64, q: &SVector<f64, N>, v: &SVector<f64, N>) -> SVector<f64, N>;
}

impl<F, const N: usize> Input<N> for F
where
    F: Fn(f64, &SVector<f64, N>, &SVector<f64, N>) -> SVector<f64, N>,
{
    fn forces(&self, t: f64, q: &SVector<f64, N>, v: &SVector<f64, N>) -> SVector<f64, N> {
        self(t, q, v)
    }
}

/// No applied forces: `τ = 0` on any number of coordinates. A closure written inline
/// without its argument types (`&|_, _, _| SVector::zeros()`) is not taken as an input
/// for every borrow of the state (Rust infers one lifetime for it); `&Unforced` is.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Unforced;

impl<const N: usize> Input<N> for Unforced {
    fn forces(&self, _: f64, _: &SVector<f64, N>, _: &SVector<f64, N>) -> SVector<f64, N> {
        SVector::zeros()
    }
}

/// A function plus a value held constant between the times it is set (a zero-order
/// hold): `τ = function(t, q, v) + held`.
#[derive(Clone, Debug)]
pub(crate) struct Held<F, const N: usize> {
    pub function: F,
    pub held: SVector<f64, N>,
}

impl<F: Input<N>, const N: usize> Input<N> for Held<F, N> {
    fn forces(&self, t: f64, q: &SVector<f64, N>, v: &SVector<f64, N>) -> SVector<f64, N> {
        self.function.forces(t, q, v) + self.held
    }
}

/// An input read no later than `until`: `forces(min(t, until), q, v)`.
pub(crate) struct Capped<'a, I: ?Sized> {
    pub input: &'a I,
    pub until: f64,
}

impl<I: Input<N> + ?Sized, const N: usize> Input<N> for Capped<'_, I> {
    fn forces(&self, t: f64, q: &SVector<f64, N>, v: &SVector<f64, N>) -> SVector<f64, N> {
        self.input.forces(t.min(self.until), q, v)
    }
}
