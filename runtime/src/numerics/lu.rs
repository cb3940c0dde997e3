//! LU factorisation with partial pivoting of the small dense Newton matrices `I − sJ`
//! (Golub & Van Loan, *Matrix Computations*, Algorithm 3.4.1, in LAPACK `getf2`'s
//! column-oriented form), in one column-major buffer allocated once: factorising and
//! solving allocate nothing. Every inner loop is an update of a contiguous column whose
//! entries are independent of each other, so a triangular solve is bounded by one
//! multiply–add per row rather than by a chain of dot products and divisions (the
//! diagonal's reciprocals are kept). For mechanical systems (a few to a few hundred
//! states) this is the cost of an implicit step beside the right-hand side.

use nalgebra::DMatrix;

/// `P A = L U` of an `n × n` matrix, column-major: `U` on and above the diagonal, the
/// multipliers of the unit lower-triangular `L` below it, and the row interchanges in
/// order.
#[derive(Clone, Debug)]
pub(crate) struct DenseLu {
    n: usize,
    /// Column-major `L \ U`: entry `(i, j)` at `a[j n + i]`.
    a: Vec<f64>,
    /// `1 / U_kk`.
    inverse_diagonal: Vec<f64>,
    /// At elimination step `k`, row `k` was interchanged with row `swap[k] ≥ k`.
    swap: Vec<usize>,
    /// A pivot was exactly zero: [`solve`](Self::solve) refuses.
    singular: bool,
}

impl DenseLu {
    pub fn new(n: usize) -> Self {
        DenseLu {
            n,
            a: vec![0.0; n * n],
            inverse_diagonal: vec![0.0; n],
            swap: (0..n).collect(),
            singular: true,
        }
    }

    /// Factorises `I − s J` (`J` square, of this size).
    pub fn factor_shifted(&mut self, jac: &DMatrix<f64>, s: f64) {
        let n = self.n;
        debug_assert_eq!(jac.shape(), (n, n));
        // nalgebra stores column-major too.
        for (x, j) in self.a.iter_mut().zip(jac.as_slice()) {
            *x = -s * j;
        }
        for i in 0..n {
            self.a[i * n + i] += 1.0;
        }
        self.factor_in_place();
    }

    /// Factorises the Schur complement `I − s A_v − s² A_q` of `I − s J` for
    /// `J = [[0, I], [A_q, A_v]]` (`2n × 2n`, this LU `n × n`): the Newton matrix of a
    /// second-order system `y = [q; v]`, `q̇ = v` (see `NewtonMatrix`).
    pub fn factor_second_order(&mut self, jac: &DMatrix<f64>, s: f64) {
        let n = self.n;
        debug_assert_eq!(jac.shape(), (2 * n, 2 * n));
        let s2 = s * s;
        for j in 0..n {
            for i in 0..n {
                self.a[j * n + i] = -s * jac[(n + i, n + j)] - s2 * jac[(n + i, j)];
            }
            self.a[j * n + j] += 1.0;
        }
        self.factor_in_place();
    }

    fn factor_in_place(&mut self) {
        let n = self.n;
        let a = &mut self.a;
        self.singular = false;
        for k in 0..n {
            // The largest entry of column k on or below the diagonal becomes the pivot.
            let column = &a[k * n..(k + 1) * n];
            let mut p = k;
            for i in k + 1..n {
                if column[i].abs() > column[p].abs() {
                    p = i;
                }
            }
            self.swap[k] = p;
            if p != k {
                for j in 0..n {
                    a.swap(j * n + k, j * n + p);
                }
            }
            let pivot = a[k * n + k];
            if pivot == 0.0 {
                self.singular = true;
                continue;
            }
            let inverse = 1.0 / pivot;
            self.inverse_diagonal[k] = inverse;
            for l in &mut a[k * n + k + 1..(k + 1) * n] {
                *l *= inverse;
            }
            // Columns right of k: A_ij −= l_i U_kj below row k.
            let (left, right) = a.split_at_mut((k + 1) * n);
            let multipliers = &left[k * n + k + 1..(k + 1) * n];
            for column in right.chunks_exact_mut(n) {
                let u = column[k];
                if u != 0.0 {
                    for (x, l) in column[k + 1..].iter_mut().zip(multipliers) {
                        *x -= l * u;
                    }
                }
            }
        }
    }

    /// Solves `A x = b` in place (`b` becomes `x`); `false`, with `b` unchanged, if a pivot
    /// was zero.
    pub fn solve(&self, b: &mut [f64]) -> bool {
        if self.singular {
            return false;
        }
        let n = self.n;
        debug_assert_eq!(b.len(), n);
        for (k, &p) in self.swap.iter().enumerate() {
            if p != k {
                b.swap(k, p);
            }
        }
        // L y = P b, column by column.
        for k in 0..n {
            let x = b[k];
            if x != 0.0 {
                let column = &self.a[k * n + k + 1..(k + 1) * n];
                for (bi, l) in b[k + 1..].iter_mut().zip(column) {
                    *bi -= l * x;
                }
            }
        }
        // U x = y, from the last column.
        for k in (0..n).rev() {
            b[k] *= self.inverse_diagonal[k];
            let x = b[k];
            if x != 0.0 {
                let column = &self.a[k * n..k * n + k];
                for (bi, u) in b[..k].iter_mut().zip(column) {
                    *bi -= u * x;
                }
            }
        }
        true
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// xorshift64*, uniform in [-1, 1).
    fn rng(seed: u64) -> impl FnMut() -> f64 {
        let mut s = seed.max(1);
        move || {
            s ^= s >> 12;
            s ^= s << 25;
            s ^= s >> 27;
            let x = s.wrapping_mul(0x2545_f491_4f6c_dd1d);
            (x >> 11) as f64 / (1u64 << 52) as f64 - 1.0
        }
    }

    /// Random systems of sizes 1–40, shifts small and large (so that pivoting matters):
    /// the residual of the solution is at the level of round-off, and it agrees with
    /// nalgebra's LU.
    #[test]
    fn solves_random_systems_to_round_off() {
        let mut r = rng(7);
        for n in [1, 2, 3, 5, 8, 14, 21, 40] {
            for s in [1e-3, 1.0, 1e3] {
                let jac = DMatrix::from_fn(n, n, |_, _| r());
                let b: Vec<f64> = (0..n).map(|_| r()).collect();
                let mut lu = DenseLu::new(n);
                lu.factor_shifted(&jac, s);
                let mut x = b.clone();
                assert!(lu.solve(&mut x));
                let m = DMatrix::identity(n, n) - &jac * s;
                let residual = &m * nalgebra::DVector::from_column_slice(&x)
                    - nalgebra::DVector::from_column_slice(&b);
                let scale = m.norm() * nalgebra::DVector::from_column_slice(&x).norm();
                assert!(
                    residual.norm() <= 1e-13 * scale.max(1.0),
                    "n {n}, s {s}: residual {:e}",
                    residual.norm()
                );
                let reference = m
                    .lu()
                    .solve(&nalgebra::DVector::from_column_slice(&b))
                    .expect("regular");
                let diff = (reference - nalgebra::DVector::from_column_slice(&x)).norm();
                assert!(diff <= 1e-10 * (1.0 + scale), "n {n}, s {s}: {diff:e}");
            }
        }
    }

    /// A zero on the diagonal needs an interchange; an exactly singular matrix is refused
    /// and leaves the right-hand side as it was.
    #[test]
    fn pivots_and_refuses_singular_matrices() {
        // I − J = [[0, 1], [1, 0]]: no solve without interchanging the rows.
        let jac = DMatrix::from_row_slice(2, 2, &[1.0, -1.0, -1.0, 1.0]);
        let mut lu = DenseLu::new(2);
        lu.factor_shifted(&jac, 1.0);
        let mut b = [2.0, 3.0];
        assert!(lu.solve(&mut b));
        assert_eq!(b, [3.0, 2.0]);
        // I − J = 0.
        let mut lu = DenseLu::new(3);
        lu.factor_shifted(&DMatrix::identity(3, 3), 1.0);
        let mut b = [1.0, 2.0, 3.0];
        assert!(!lu.solve(&mut b));
        assert_eq!(b, [1.0, 2.0, 3.0]);
    }
}
