//! Helpers shared by the integration tests.
#![allow(dead_code)]

use filippov::nalgebra::{DMatrix, DVector, SMatrix, SVector};

/// A small deterministic generator (SplitMix64), so tests need no RNG dependency and
/// every failure reproduces.
pub struct Rng(u64);

impl Rng {
    pub fn new(seed: u64) -> Self {
        Rng(seed)
    }

    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in `[lo, hi)`.
    pub fn uniform(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * ((self.next_u64() >> 11) as f64 / (1u64 << 53) as f64)
    }

    pub fn vector<const N: usize>(&mut self, scale: f64) -> SVector<f64, N> {
        SVector::from_fn(|_, _| self.uniform(-scale, scale))
    }
}

pub fn dvec<const N: usize>(v: &SVector<f64, N>) -> DVector<f64> {
    DVector::from_column_slice(v.as_slice())
}

pub fn dmat<const N: usize>(m: &SMatrix<f64, N, N>) -> DMatrix<f64> {
    DMatrix::from_column_slice(N, N, m.as_slice())
}

/// `‖a − b‖ ≤ tol · max(‖b‖, floor)`, with a message naming `what`.
#[track_caller]
pub fn assert_close(a: &[f64], b: &[f64], tol: f64, floor: f64, what: &str) {
    assert_eq!(a.len(), b.len(), "{what}: lengths differ");
    let diff: f64 = a
        .iter()
        .zip(b)
        .map(|(x, y)| (x - y) * (x - y))
        .sum::<f64>()
        .sqrt();
    let norm: f64 = b.iter().map(|y| y * y).sum::<f64>().sqrt();
    assert!(
        diff <= tol * norm.max(floor),
        "{what}: relative difference {:.3e} (‖b‖ = {norm:.3e})\n a = {a:?}\n b = {b:?}",
        diff / norm.max(floor)
    );
}
