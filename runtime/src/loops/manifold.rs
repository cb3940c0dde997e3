//! Keeping a closed mechanism on its constraint manifold (theory §7): the projection
//! after each accepted step, and the rank test that reports a singular configuration.
//!
//! Both work with the Schur complement `A = G M⁻¹ Gᵀ` at the current configuration,
//! factored here as `A = L D Lᵀ` with the pivots checked: a pivot `d_j` that is a tiny
//! fraction of `A`'s largest diagonal entry ([`SINGULAR_PIVOT`]) means that constraint
//! row `j` has vanished or become a combination of the rows before it — the loops lost
//! a constraint's worth of stiffness, as a four-bar at a change point does — and the
//! constraint forces would grow without bound.

use nalgebra::{SMatrix, SVector};

use super::LoopConstraints;
pub use super::error::LoopError;

/// A constraint row is taken as lost — vanished, or dependent on the rows before it —
/// when its pivot in `G M⁻¹ Gᵀ` is below this fraction of the largest diagonal entry.
pub const SINGULAR_PIVOT: f64 = 1e-10;

/// `A = L D Lᵀ` (`L` unit lower triangular, stored below the diagonal, `D` on it), and
/// the smallest pivot against `A`'s largest diagonal entry (a row of `G` that vanishes,
/// as at a four-bar's change point, has a pivot that vanishes against it, not against
/// its own diagonal) with its row; the factorisation stops at the first pivot that is
/// not positive (that row and the rest are left unfactored).
fn factor<const M: usize>(a: &SMatrix<f64, M, M>) -> (SMatrix<f64, M, M>, (f64, usize)) {
    let mut ld = SMatrix::<f64, M, M>::zeros();
    let worst = factor_in(a.as_slice(), M, ld.as_mut_slice());
    (ld, worst)
}

/// [`factor`] on `m × m` column-major slices (`ld` zero on entry): not generic, so
/// compiled once, optimised, here, whatever crate names the scene.
fn factor_in(a: &[f64], m: usize, ld: &mut [f64]) -> (f64, usize) {
    let at = |i: usize, j: usize| i + j * m;
    let scale = (0..m).map(|j| a[at(j, j)]).fold(0.0, f64::max);
    let mut worst = (f64::INFINITY, 0);
    for j in 0..m {
        let mut d = a[at(j, j)];
        for k in 0..j {
            d -= ld[at(j, k)] * ld[at(j, k)] * ld[at(k, k)];
        }
        let pivot = d / scale;
        if !(pivot >= worst.0) {
            worst = (pivot, j);
        }
        if !(d > 0.0) {
            return (pivot.min(0.0), j);
        }
        ld[at(j, j)] = d;
        for i in j + 1..m {
            let mut s = a[at(i, j)];
            for k in 0..j {
                s -= ld[at(i, k)] * ld[at(j, k)] * ld[at(k, k)];
            }
            ld[at(i, j)] = s / d;
        }
    }
    worst
}

/// The smallest relative pivot of `A = G M⁻¹ Gᵀ` and its row (`(0, 0)` where `M` is not
/// positive definite), on the caller's column-major buffers: `l` holds `M` (`n × n`)
/// and is overwritten by its Cholesky factor `L`, `y` holds `Gᵀ` (`n × m`) and is
/// overwritten by `L⁻¹ Gᵀ`, so that `A = yᵀ y` (its lower triangle) goes to `a`, and its factor to `ld`
/// (both `m × m`, zero on entry). The rank test is sampled seven times a step: on
/// buffers the caller keeps on its stack it allocates nothing, and not being generic it
/// is compiled here, optimised, whatever crate names the scene.
fn conditioning_in(
    n: usize,
    m: usize,
    l: &mut [f64],
    y: &mut [f64],
    a: &mut [f64],
    ld: &mut [f64],
) -> (f64, usize) {
    for j in 0..n {
        let mut d = l[j + j * n];
        for k in 0..j {
            d -= l[j + k * n] * l[j + k * n];
        }
        if !(d > 0.0) {
            return (0.0, 0);
        }
        let d = d.sqrt();
        l[j + j * n] = d;
        for i in j + 1..n {
            let mut s = l[i + j * n];
            for k in 0..j {
                s -= l[i + k * n] * l[j + k * n];
            }
            l[i + j * n] = s / d;
        }
    }
    for c in 0..m {
        let col = &mut y[c * n..(c + 1) * n];
        for i in 0..n {
            let mut s = col[i];
            for k in 0..i {
                s -= l[i + k * n] * col[k];
            }
            col[i] = s / l[i + i * n];
        }
    }
    // `factor_in` reads the lower triangle only.
    for c in 0..m {
        for r in c..m {
            a[r + c * m] = (0..n).map(|i| y[i + r * n] * y[i + c * n]).sum();
        }
    }
    factor_in(a, m, ld)
}

/// Newton iterations of a position projection before it is declared stuck.
const PROJECTION_ITERATIONS: usize = 8;

/// `G`, `Y = M⁻¹ Gᵀ` and the factor of `A = G Y` at one configuration.
pub(crate) struct Schur<const N: usize, const M: usize> {
    pub g: SMatrix<f64, M, N>,
    y: SMatrix<f64, N, M>,
    /// `L` (unit lower triangular, below the diagonal) and `D` (on it).
    ld: SMatrix<f64, M, M>,
}

impl<const N: usize, const M: usize> Schur<N, M> {
    /// At `q`, with the coordinates marked in `held` (if any) held fixed: their
    /// columns of `G` taken out and their rows and columns of `M` replaced by the
    /// identity, so that every correction leaves them where they are.
    pub fn at<S: LoopConstraints<N, M>>(
        s: &S,
        q: &SVector<f64, N>,
        held: &[bool],
    ) -> Result<Self, LoopError> {
        let mut g = s.constraint_jacobian(q);
        let mut mass = s.mass_matrix(q);
        for (c, _) in held.iter().enumerate().filter(|(_, h)| **h) {
            g.column_mut(c).fill(0.0);
            mass.row_mut(c).fill(0.0);
            mass.column_mut(c).fill(0.0);
            mass[(c, c)] = 1.0;
        }
        let chol = mass.cholesky().ok_or(LoopError::Singular {
            row: S::CONSTRAINTS.first().copied().unwrap_or(""),
            pivot: f64::NAN,
        })?;
        let y = chol.solve(&g.transpose());
        let (ld, (pivot, row)) = factor(&(g * y));
        if !(pivot > SINGULAR_PIVOT) {
            return Err(LoopError::Singular {
                row: S::CONSTRAINTS[row],
                pivot,
            });
        }
        Ok(Schur { g, y, ld })
    }

    /// The smallest relative pivot of `A = G M⁻¹ Gᵀ` at `q` and its row: how far the
    /// constraints are from losing rank (`1` for orthogonal rows, `0` where a row
    /// depends on the rows before it).
    pub fn conditioning<S: LoopConstraints<N, M>>(s: &S, q: &SVector<f64, N>) -> (f64, usize) {
        let mut l = s.mass_matrix(q);
        let mut y = s.constraint_jacobian(q).transpose();
        let (mut a, mut ld) = (SMatrix::<f64, M, M>::zeros(), SMatrix::<f64, M, M>::zeros());
        conditioning_in(
            N,
            M,
            l.as_mut_slice(),
            y.as_mut_slice(),
            a.as_mut_slice(),
            ld.as_mut_slice(),
        )
    }

    /// `Y A⁻¹ r`: the smallest change, in the mass metric, that moves `G x` by `r`.
    pub fn correction(&self, r: &SVector<f64, M>) -> SVector<f64, N> {
        let mut x = *r;
        for i in 0..M {
            for k in 0..i {
                x[i] -= self.ld[(i, k)] * x[k];
            }
        }
        for i in 0..M {
            x[i] /= self.ld[(i, i)];
        }
        for i in (0..M).rev() {
            for k in i + 1..M {
                x[i] -= self.ld[(k, i)] * x[k];
            }
        }
        self.y * x
    }
}

/// How close to the manifold a projection puts the state: `|Φ|∞` within
/// `ROUND_OFF · (1 + |G|∞)` plus what the coordinates' own rounding leaves
/// (`4 ε |q|∞ |G|∞`: a crank that has turned ten thousand times carries its angle to
/// 1.5e-11 only), `|G v|∞` within `ROUND_OFF · (1 + |G|∞ |v|∞)`.
pub const ROUND_OFF: f64 = 1e-14;

/// The position tolerance of [`ROUND_OFF`] at `q` with constraint Jacobian `g`.
pub(super) fn position_tolerance<const N: usize, const M: usize>(
    q: &SVector<f64, N>,
    g: &SMatrix<f64, M, N>,
) -> f64 {
    let g_scale = g.amax();
    ROUND_OFF * (1.0 + g_scale) + 4.0 * f64::EPSILON * q.amax() * g_scale
}

/// Projects `(q, v)` onto the constraint manifold `Φ(q) = 0`, `G(q) v = 0` (theory §7):
/// Newton steps `Δq = −M⁻¹Gᵀ A⁻¹ Φ` (each the smallest in the mass metric) until `|Φ|`
/// is at round-off, then `v ← v − M⁻¹Gᵀ A⁻¹ G v`, the velocity's component off the
/// constraints removed (in the mass metric: the kinetic energy only falls). The
/// coordinates marked in `held` (a stuck joint, a stop in contact; empty for none) stay
/// where they are, and so do their velocities. Returns whether anything moved.
///
/// # Errors
/// [`LoopError::Singular`] where `G` has lost rank, [`LoopError::NoAssembly`] where the
/// iterations do not close the loops.
pub fn project<S, const N: usize, const M: usize>(
    s: &S,
    q: &mut SVector<f64, N>,
    v: &mut SVector<f64, N>,
    held: &[bool],
) -> Result<bool, LoopError>
where
    S: LoopConstraints<N, M>,
{
    let mut moved = false;
    let mut phi = s.constraint_residual(q);
    let mut schur = Schur::at(s, q, held)?;
    let tol_q = position_tolerance(q, &schur.g);
    for _ in 0..PROJECTION_ITERATIONS {
        if !(phi.amax() > tol_q) {
            break;
        }
        *q -= schur.correction(&phi);
        moved = true;
        phi = s.constraint_residual(q);
        schur = Schur::at(s, q, held)?;
    }
    if !(phi.amax() <= tol_q) {
        let worst = phi.iamax();
        return Err(LoopError::NoAssembly {
            row: S::CONSTRAINTS[worst],
            residual: phi[worst],
        });
    }
    let gv = schur.g * *v;
    if gv.amax() > ROUND_OFF * (1.0 + schur.g.amax() * v.amax()) {
        *v -= schur.correction(&gv);
        moved = true;
    }
    Ok(moved)
}

/// The smallest relative pivot of `G M⁻¹ Gᵀ` at `q` (see [`SINGULAR_PIVOT`]): `1` for
/// constraints whose rows are orthogonal in the mass metric, falling to `0` where they
/// lose rank. The integrators follow it over each step to catch a singular
/// configuration the steps would step over.
pub fn conditioning<S, const N: usize, const M: usize>(s: &S, q: &SVector<f64, N>) -> f64
where
    S: LoopConstraints<N, M>,
{
    Schur::conditioning(s, q).0
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::DMatrix;

    /// A small deterministic generator (splitmix64), uniform in `[-1, 1)`.
    fn uniform(state: &mut u64) -> f64 {
        *state = state.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = *state;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        2.0 * ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64 - 1.0
    }

    /// The buffers' rank test against the same pivots of `G M⁻¹ Gᵀ` formed by nalgebra's
    /// Cholesky solve, on random positive definite `M` and random `G` (one with a row
    /// repeated, whose pivot vanishes), and `(0, 0)` for a mass matrix that is not
    /// positive definite.
    #[test]
    fn conditioning_on_buffers_is_the_pivots_of_the_schur_complement() {
        let mut state = 7;
        for trial in 0..200 {
            let n = 1 + trial % 7;
            let m = 1 + (trial / 7) % n;
            let b = DMatrix::from_fn(n, n, |_, _| uniform(&mut state));
            let mass = b.transpose() * &b + DMatrix::identity(n, n) * 0.1;
            let mut g = DMatrix::from_fn(m, n, |_, _| uniform(&mut state));
            if m > 1 && trial % 5 == 0 {
                let first = g.row(0).into_owned();
                g.set_row(m - 1, &first);
            }
            let a = &g * mass.clone().cholesky().unwrap().solve(&g.transpose());
            let mut ld = vec![0.0; m * m];
            let expected = factor_in(a.as_slice(), m, &mut ld);
            let (mut l, mut y) = (mass.clone(), g.transpose());
            let (mut a2, mut ld2) = (vec![0.0; m * m], vec![0.0; m * m]);
            let got = conditioning_in(n, m, l.as_mut_slice(), y.as_mut_slice(), &mut a2, &mut ld2);
            assert_eq!(got.1, expected.1, "trial {trial}: row");
            assert!(
                (got.0 - expected.0).abs() <= 1e-12,
                "trial {trial}: {got:?} {expected:?}"
            );
            if m > 1 && trial % 5 == 0 {
                assert!(got.0 < 1e-12, "trial {trial}: a repeated row keeps {got:?}");
            }
        }
        let mut l = vec![1.0, 0.0, 0.0, -1.0];
        let mut y = vec![1.0, 1.0];
        let got = conditioning_in(2, 1, &mut l, &mut y, &mut [0.0], &mut [0.0]);
        assert_eq!(got, (0.0, 0));
    }
}
