//! Linear complementarity problems, solved exactly by complementary pivoting.
//!
//! Find `z` with
//!
//! ```text
//! w = M z + q,   w ≥ 0,   z ≥ 0,   wᵀ z = 0.
//! ```
//!
//! Lemke's algorithm (Cottle, Pang & Stone, *The Linear Complementarity Problem*, §4.4)
//! walks from the artificial solution `z₀ = max(−q)` (covering vector of ones) along
//! complementary bases until `z₀` leaves the basis. Ties in the ratio test are broken
//! lexicographically, which rules out cycling on degenerate problems. The pivots only
//! choose the active set: the solution is then recomputed from it (the active rows of
//! `M` solved directly, with partial pivoting), so that round-off in the tableau does not
//! reach the result, and checked to be a solution ([`LcpError::Inconsistent`] if not).
//!
//! When `M` is a P-matrix (every principal minor positive) the problem has exactly one
//! solution for every `q`, and Lemke's algorithm finds it. When `M` is copositive-plus,
//! ending on a ray ([`LcpError::NoSolution`]) proves there is none. For other matrices a
//! ray is a failure of the method, not a proof; [`is_p_matrix`] tells which case a
//! small problem is.

use nalgebra::{DMatrix, DVector};

/// Why [`solve`] returned no solution.
#[derive(Clone, Debug, PartialEq)]
pub enum LcpError {
    /// The pivots ended on an unbounded ray: no solution when `M` is copositive-plus
    /// (in particular positive semi-definite).
    NoSolution,
    /// More pivots than the problem has bases could need (never seen; a guard).
    PivotLimit,
    /// `M` or `q` has a NaN or infinite entry, or their sizes differ.
    InvalidInput,
    /// The active set the pivots ended on does not solve the problem (a negative `z` or
    /// `w` beyond round-off): the pivots went astray on a badly scaled problem.
    Inconsistent,
}

impl std::fmt::Display for LcpError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            LcpError::NoSolution => write!(f, "the complementarity problem has no solution"),
            LcpError::PivotLimit => write!(f, "complementary pivoting did not end"),
            LcpError::InvalidInput => write!(
                f,
                "the complementarity problem's data are not finite or do not fit"
            ),
            LcpError::Inconsistent => write!(
                f,
                "the complementarity problem's pivots ended on an active set that does not solve it"
            ),
        }
    }
}

/// A solution: `z` and `w = M z + q`, with the set of indices where `z` is the basic
/// variable (the active set).
#[derive(Clone, Debug, PartialEq)]
pub struct LcpSolution {
    pub z: DVector<f64>,
    pub w: DVector<f64>,
    /// `active[i]`: `z_i` is basic (may be positive), `w_i = 0`.
    pub active: Vec<bool>,
}

/// Relative size below which a tableau entry counts as zero in the pivot choice.
const PIVOT_TOL: f64 = 1e-12;

/// Solves the LCP `(M, q)` (see the module documentation).
///
/// # Errors
/// [`LcpError`]: no solution found (a ray), the pivot guard, or invalid data.
pub fn solve(m: &DMatrix<f64>, q: &DVector<f64>) -> Result<LcpSolution, LcpError> {
    let n = q.len();
    if m.nrows() != n || m.ncols() != n || m.iter().chain(q.iter()).any(|x| !x.is_finite()) {
        return Err(LcpError::InvalidInput);
    }
    if q.iter().all(|&x| x >= 0.0) {
        return Ok(LcpSolution {
            z: DVector::zeros(n),
            w: q.clone(),
            active: vec![false; n],
        });
    }
    // Tableau columns: w (0..n), z (n..2n), z0 (2n), rhs (2n + 1); rows: the n equations
    // w − M z − e z0 = q.
    let cols = 2 * n + 2;
    let (z0, rhs) = (2 * n, 2 * n + 1);
    let mut t = DMatrix::<f64>::zeros(n, cols);
    for i in 0..n {
        t[(i, i)] = 1.0;
        for j in 0..n {
            t[(i, n + j)] = -m[(i, j)];
        }
        t[(i, z0)] = -1.0;
        t[(i, rhs)] = q[i];
    }
    // Lexicographic order: the rows of the basis inverse, which are the w columns here.
    let mut basis: Vec<usize> = (0..n).collect();
    let scale = m.amax().max(q.amax()).max(1.0);
    let pivot = |t: &mut DMatrix<f64>, r: usize, c: usize| {
        let p = t[(r, c)];
        for j in 0..cols {
            t[(r, j)] /= p;
        }
        for i in 0..n {
            if i != r {
                let f = t[(i, c)];
                if f != 0.0 {
                    for j in 0..cols {
                        t[(i, j)] -= f * t[(r, j)];
                    }
                }
            }
        }
    };
    // First pivot: z0 enters at the most negative q.
    let r0 = (0..n)
        .min_by(|&a, &b| t[(a, rhs)].total_cmp(&t[(b, rhs)]))
        .unwrap_or(0);
    pivot(&mut t, r0, z0);
    let mut leaving = basis[r0];
    basis[r0] = z0;
    // The complement of the variable that just left enters.
    let limit = 50 * (n + 1) * (n + 1);
    for _ in 0..limit {
        let entering = if leaving < n {
            leaving + n
        } else {
            leaving - n
        };
        // Ratio test over rows with a positive entry, lexicographic on (rhs, w-columns).
        let mut best: Option<usize> = None;
        for i in 0..n {
            let a = t[(i, entering)];
            if a > PIVOT_TOL * scale {
                best = Some(match best {
                    None => i,
                    Some(b) => {
                        let ab = t[(b, entering)];
                        let key = |row: usize, piv: f64, k: usize| {
                            let col = if k == 0 { rhs } else { k - 1 };
                            t[(row, col)] / piv
                        };
                        let mut choice = b;
                        for k in 0..=n {
                            let (x, y) = (key(i, a, k), key(b, ab, k));
                            // Equal up to the round-off of the column's entries over
                            // the pivots: a tie is a tie in the column's own scale (a
                            // right-hand side of 1e-7 against pivots of 1e3 has ratios
                            // of 1e-10 that an absolute tolerance would call equal).
                            let col = if k == 0 { rhs } else { k - 1 };
                            let round_off = t.column(col).amax() / a.min(ab);
                            let tol = PIVOT_TOL * (x.abs().max(y.abs()) + round_off);
                            if x < y - tol {
                                choice = i;
                                break;
                            }
                            if x > y + tol {
                                break;
                            }
                        }
                        // Prefer z0 leaving on a tie: it ends the walk.
                        if basis[i] == z0
                            && (key(i, a, 0) - key(b, ab, 0)).abs() <= PIVOT_TOL * scale
                        {
                            choice = i;
                        }
                        choice
                    }
                });
            }
        }
        let Some(r) = best else {
            return Err(LcpError::NoSolution);
        };
        pivot(&mut t, r, entering);
        leaving = basis[r];
        basis[r] = entering;
        if leaving == z0 {
            let mut active = vec![false; n];
            for &b in &basis {
                if (n..2 * n).contains(&b) {
                    active[b - n] = true;
                }
            }
            return finish(m, q, active);
        }
    }
    Err(LcpError::PivotLimit)
}

/// The solution of the active set `active`, from the active rows of `M` directly:
/// `M_AA z_A = −q_A`, `z` zero elsewhere, `w = M z + q` (zero on `A` up to round-off,
/// set to exactly zero there).
fn finish(m: &DMatrix<f64>, q: &DVector<f64>, active: Vec<bool>) -> Result<LcpSolution, LcpError> {
    let n = q.len();
    let idx: Vec<usize> = (0..n).filter(|&i| active[i]).collect();
    let k = idx.len();
    let mut z = DVector::zeros(n);
    if k > 0 {
        let maa = DMatrix::from_fn(k, k, |i, j| m[(idx[i], idx[j])]);
        let qa = DVector::from_fn(k, |i, _| -q[idx[i]]);
        let za = maa.lu().solve(&qa).ok_or(LcpError::NoSolution)?;
        let z_tol = 1e-9 * za.amax();
        for (a, &i) in idx.iter().enumerate() {
            // A basic variable at a degenerate vertex may come out as −round-off; more
            // than that, and the active set is wrong.
            if za[a] < -z_tol {
                return Err(LcpError::Inconsistent);
            }
            z[i] = za[a].max(0.0);
        }
    }
    let mut w = m * &z + q;
    for &i in &idx {
        w[i] = 0.0;
    }
    // Each inactive row's `w` non-negative up to the round-off of its terms.
    for i in (0..n).filter(|&i| !active[i]) {
        let terms = (0..n).fold(q[i].abs(), |s, j| s.max((m[(i, j)] * z[j]).abs()));
        if w[i] < -1e-9 * terms {
            return Err(LcpError::Inconsistent);
        }
    }
    Ok(LcpSolution { z, w, active })
}

/// Whether every principal minor of `m` is positive (`2ⁿ − 1` determinants: for the small
/// matrices of contact problems). A P-matrix gives every `q` exactly one solution; a
/// matrix that is not one has some `q` with none or several.
pub fn is_p_matrix(m: &DMatrix<f64>) -> bool {
    let n = m.nrows();
    if n != m.ncols() || n > 20 {
        return false;
    }
    let scale = m.amax().max(f64::MIN_POSITIVE);
    (1u32..(1u32 << n)).all(|mask| {
        let idx: Vec<usize> = (0..n).filter(|&i| mask & (1 << i) != 0).collect();
        let k = idx.len();
        let sub = DMatrix::from_fn(k, k, |i, j| m[(idx[i], idx[j])]);
        sub.determinant() > 1e-12 * scale.powi(k as i32)
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    struct Rng(u64);
    impl Rng {
        fn uniform(&mut self, lo: f64, hi: f64) -> f64 {
            self.0 = self
                .0
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            lo + (hi - lo) * ((self.0 >> 11) as f64 / (1u64 << 53) as f64)
        }
    }

    /// Every solution by enumerating the `2ⁿ` active sets: an independent reference.
    fn enumerate(m: &DMatrix<f64>, q: &DVector<f64>) -> Vec<DVector<f64>> {
        let n = q.len();
        let mut out = Vec::new();
        for mask in 0u32..(1 << n) {
            let active: Vec<bool> = (0..n).map(|i| mask & (1 << i) != 0).collect();
            if let Ok(s) = finish(m, q, active.clone()) {
                let z_ok = (0..n).all(|i| !active[i] || s.z[i] >= 0.0);
                let raw = m * &s.z + q;
                let w_ok = (0..n).all(|i| active[i] || raw[i] >= -1e-12);
                let zs = (0..n).all(|i| !active[i] || raw[i].abs() <= 1e-9 * (1.0 + q.amax()));
                if z_ok && w_ok && zs {
                    out.push(s.z);
                }
            }
        }
        out
    }

    fn check(m: &DMatrix<f64>, q: &DVector<f64>, s: &LcpSolution) -> f64 {
        let w = m * &s.z + q;
        let mut worst = 0.0f64;
        for i in 0..q.len() {
            worst = worst
                .max((-s.z[i]).max(0.0))
                .max((-w[i]).max(0.0))
                .max((s.z[i] * w[i]).abs());
        }
        worst
    }

    #[test]
    fn random_p_matrices_have_the_unique_solution() {
        let mut rng = Rng(3);
        for trial in 0..400 {
            let n = 1 + trial % 8;
            // Positive definite (a P-matrix) plus a skew part (still a P-matrix): the
            // Delassus matrices of contacts with friction are of this kind.
            let a = DMatrix::from_fn(n, n, |_, _| rng.uniform(-1.0, 1.0));
            let s = DMatrix::from_fn(n, n, |_, _| rng.uniform(-0.5, 0.5));
            let m = &a * a.transpose() + DMatrix::identity(n, n) * 0.1 + (&s - s.transpose());
            let q = DVector::from_fn(n, |_, _| rng.uniform(-2.0, 2.0));
            assert!(is_p_matrix(&m));
            let sol = solve(&m, &q).unwrap_or_else(|e| panic!("trial {trial}: {e}"));
            assert!(
                check(&m, &q, &sol) < 1e-12,
                "trial {trial}: {}",
                check(&m, &q, &sol)
            );
            let all = enumerate(&m, &q);
            assert_eq!(all.len(), 1, "trial {trial}: a P-matrix has one solution");
            assert!((&all[0] - &sol.z).amax() < 1e-10, "trial {trial}");
        }
    }

    #[test]
    fn degenerate_problems_do_not_cycle() {
        // q with zeros and repeated entries, M with repeated rows: ties in every ratio test.
        let m = DMatrix::from_row_slice(3, 3, &[1.0, 2.0, 0.0, 0.0, 1.0, 2.0, 2.0, 0.0, 1.0]);
        for q in [
            [-1.0, -1.0, -1.0],
            [0.0, -1.0, 0.0],
            [-1.0, 0.0, -1.0],
            [0.0, 0.0, -1.0],
        ] {
            let q = DVector::from_row_slice(&q);
            let sol = solve(&m, &q).expect("a P-matrix");
            assert!(check(&m, &q, &sol) < 1e-12, "{q:?}");
        }
    }

    #[test]
    fn infeasible_problems_end_on_a_ray() {
        // w = −z − 1 cannot be non-negative.
        let m = DMatrix::from_row_slice(1, 1, &[-1.0]);
        let q = DVector::from_row_slice(&[-1.0]);
        assert_eq!(solve(&m, &q), Err(LcpError::NoSolution));
        // Positive semi-definite, no solution: w₁ = z₂ − 1, w₂ = −z₁ − 1 (z₁ ≥ 0 gives w₂ < 0).
        let m = DMatrix::from_row_slice(2, 2, &[0.0, 1.0, -1.0, 0.0]);
        let q = DVector::from_row_slice(&[-1.0, -1.0]);
        assert_eq!(solve(&m, &q), Err(LcpError::NoSolution));
        assert!(enumerate(&m, &q).is_empty());
        assert!(!is_p_matrix(&m));
        let nan = DVector::from_row_slice(&[f64::NAN, 1.0]);
        assert_eq!(solve(&m, &nan), Err(LcpError::InvalidInput));
    }

    #[test]
    fn a_non_p_matrix_can_have_several_solutions() {
        // M = [[−1]] with q = 1: z = 0 (w = 1) and z = 1 (w = 0) both solve it.
        let m = DMatrix::from_row_slice(1, 1, &[-1.0]);
        let q = DVector::from_row_slice(&[1.0]);
        assert_eq!(enumerate(&m, &q).len(), 2);
        assert!(!is_p_matrix(&m));
        let sol = solve(&m, &q).expect("z = 0");
        assert!(check(&m, &q, &sol) < 1e-12);
    }
}
