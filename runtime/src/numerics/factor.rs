//! The dense factorisations the drivers use (SVD, Cholesky, LU, symmetric
//! eigendecomposition), behind functions that are not generic.
//!
//! A driver generic over its scene (`contact_time_stepping::<S, …>`, `TimeSteps<S, N>`)
//! is compiled in the crate that names the scene, and every nalgebra factorisation it
//! calls directly is compiled there with it, at that crate's optimisation: in a debug
//! build or a test crate, an unoptimised SVD, about a hundred times slower than this
//! crate's. Called through these functions, each factorisation is compiled once, here.
//! They compute exactly what the nalgebra call they wrap computes, and take the matrix
//! they factorise by value (the drivers' are temporaries), so that none is copied.

use nalgebra::{DMatrix, DVector, SMatrix, SymmetricEigen};

/// `m` as a dynamically sized matrix (the drivers' factorisations take those).
pub(crate) fn dynamic<const R: usize, const C: usize>(m: &SMatrix<f64, R, C>) -> DMatrix<f64> {
    DMatrix::from_column_slice(R, C, m.as_slice())
}

/// `A⁺ b` by SVD, singular values at or below `rel · max|Aᵢⱼ|` taken as zero: the
/// least-norm least-squares solution. `None` where the SVD fails.
pub(crate) fn least_squares(a: DMatrix<f64>, b: &DVector<f64>, rel: f64) -> Option<DVector<f64>> {
    let eps = rel * a.amax().max(f64::MIN_POSITIVE);
    a.svd(true, true).solve(b, eps).ok()
}

/// The least change `W Cᵀ (C W Cᵀ)⁺ r` in the metric `W` that changes the rows' values
/// `C x` by `r` (singular values of `C W Cᵀ` below `1e-12` of its largest entry taken
/// as zero). `None` where the SVD fails.
pub(crate) fn least_change(
    c: &DMatrix<f64>,
    w: &DMatrix<f64>,
    r: &DVector<f64>,
) -> Option<DVector<f64>> {
    let x = least_squares(c * w * c.transpose(), r, 1e-12)?;
    Some(w * c.transpose() * x)
}

/// Whether the rows of `m` span every column: its smallest singular value above `rel`
/// times its largest (`false` for fewer rows than columns).
pub(crate) fn full_column_rank(m: &DMatrix<f64>, rel: f64) -> bool {
    if m.nrows() < m.ncols() {
        return false;
    }
    let sv = m.singular_values();
    sv.min() > rel * sv.max()
}

/// `M⁻¹` by Cholesky; `None` where `M` is not positive definite.
pub(crate) fn spd_inverse(m: DMatrix<f64>) -> Option<DMatrix<f64>> {
    m.cholesky().map(|c| c.inverse())
}

/// `M⁻¹` by Cholesky, or by LU where `M` is not positive definite; `None` where it is
/// singular.
pub(crate) fn inverse(m: DMatrix<f64>) -> Option<DMatrix<f64>> {
    spd_inverse(m.clone()).or_else(|| m.try_inverse())
}

/// `A⁻¹ b` by Cholesky; `None` where `A` is not positive definite.
pub(crate) fn cholesky_solve(a: DMatrix<f64>, b: &DVector<f64>) -> Option<DVector<f64>> {
    a.cholesky().map(|c| c.solve(b))
}

/// `A⁻¹ b` by LU with partial pivoting; `None` where `A` is singular.
pub(crate) fn lu_solve(a: DMatrix<f64>, b: &DVector<f64>) -> Option<DVector<f64>> {
    a.lu().solve(b)
}

/// The eigenvalues and eigenvectors of the symmetric `m`.
pub(crate) fn symmetric_eigen(m: DMatrix<f64>) -> SymmetricEigen<f64, nalgebra::Dyn> {
    m.symmetric_eigen()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_wrapper_solves_its_problem() {
        let m = DMatrix::from_row_slice(3, 3, &[4.0, 1.0, 0.5, 1.0, 3.0, 0.2, 0.5, 0.2, 2.0]);
        let b = DVector::from_vec(vec![1.0, -2.0, 0.5]);
        let eye = DMatrix::identity(3, 3);
        assert!((&m * spd_inverse(m.clone()).unwrap() - &eye).amax() < 1e-14);
        assert!((&m * cholesky_solve(m.clone(), &b).unwrap() - &b).amax() < 1e-14);
        assert!((&m * lu_solve(m.clone(), &b).unwrap() - &b).amax() < 1e-14);
        assert!((&m * least_squares(m.clone(), &b, 1e-12).unwrap() - &b).amax() < 1e-14);
        let indefinite = DMatrix::from_row_slice(2, 2, &[0.0, 1.0, 1.0, 0.0]);
        assert!(spd_inverse(indefinite.clone()).is_none());
        assert!((inverse(indefinite.clone()).unwrap() - &indefinite).amax() == 0.0);
        assert!(inverse(DMatrix::zeros(2, 2)).is_none());
        let eig = symmetric_eigen(m.clone());
        for i in 0..3 {
            let x = eig.eigenvectors.column(i);
            assert!((&m * x - x * eig.eigenvalues[i]).amax() < 1e-13);
        }
        // Two rows cannot span three columns; three independent ones do; a repeated row
        // does not.
        assert!(!full_column_rank(&m.rows(0, 2).into_owned(), 1e-10));
        assert!(full_column_rank(&m, 1e-10));
        let mut repeated = m.clone();
        repeated.set_row(2, &m.row(0));
        assert!(!full_column_rank(&repeated, 1e-10));
        // The least change moves `C x` by `r`, along `W Cᵀ`.
        let c = DMatrix::from_row_slice(1, 3, &[1.0, 2.0, -1.0]);
        let r = DVector::from_vec(vec![0.3]);
        let dx = least_change(&c, &m, &r).unwrap();
        assert!(((&c * &dx)[0] - 0.3).abs() < 1e-15);
        let along = &m * c.transpose();
        assert!((dx.normalize() - along.normalize()).amax() < 1e-14);
    }
}
