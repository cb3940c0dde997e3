//! Consistent initial conditions for a closed mechanism: the coordinates a user gives
//! (the independent ones, such as a crank angle) are kept, and the others are solved
//! for so that every loop closes and every velocity constraint holds (theory §7).

use nalgebra::{DMatrix, DVector, SVector};

use super::LoopConstraints;
use super::manifold::{LoopError, position_tolerance};

/// Newton iterations of an assembly before it gives up.
const ASSEMBLY_ITERATIONS: usize = 50;

/// Completes `(q, v)`: the coordinates of the joints named in `given` keep their
/// values; the others start from `q` (a rough guess picks the assembly branch) and
/// are solved for by Gauss–Newton on `Φ(q) = 0` (each step the smallest that closes
/// the linearised loops, with the step halved while the residual grows), then their
/// velocities from `G v = 0` (the smallest again). Returns the completed state.
///
/// # Errors
/// [`LoopError::UnknownJoint`] for a name that is not one of the mechanism's joints,
/// [`LoopError::NoAssembly`] when the loops cannot be closed with the given coordinates
/// held (a crank angle the linkage cannot reach), naming the row that stays open.
///
/// For a four-bar whose crank angle and speed are given (`tests/loops.rs` runs it):
///
/// ```text
/// let (q0, v0) = assemble(&four_bar, &[0.5, 1.0, 1.5].into(), &[2.0, 0.0, 0.0].into(),
///                         &["crank_pivot"])?;
/// ```
pub fn assemble<S, const N: usize, const M: usize>(
    s: &S,
    q: &SVector<f64, N>,
    v: &SVector<f64, N>,
    given: &[&str],
) -> Result<(SVector<f64, N>, SVector<f64, N>), LoopError>
where
    S: LoopConstraints<N, M>,
{
    let mut fixed = [false; N];
    for name in given {
        let Some(i) = S::JOINTS.iter().position(|j| j == name) else {
            return Err(LoopError::UnknownJoint {
                name: name.to_string(),
                joints: S::JOINTS.to_vec(),
            });
        };
        fixed[i] = true;
    }
    let free: Vec<usize> = (0..N).filter(|&i| !fixed[i]).collect();
    let restrict =
        |g: &nalgebra::SMatrix<f64, M, N>| DMatrix::from_fn(M, free.len(), |r, c| g[(r, free[c])]);
    let least_norm = |a: DMatrix<f64>, b: DVector<f64>| -> DVector<f64> {
        let svd = a.svd(true, true);
        let eps = svd.singular_values.max() * 1e-12;
        svd.solve(&b, eps)
            .unwrap_or_else(|_| DVector::zeros(free.len()))
    };
    let mut q = *q;
    let tol = |q: &SVector<f64, N>| position_tolerance(q, &s.constraint_jacobian(q));
    let mut phi = s.constraint_residual(&q);
    for _ in 0..ASSEMBLY_ITERATIONS {
        if phi.amax() <= tol(&q) {
            break;
        }
        let step = least_norm(
            restrict(&s.constraint_jacobian(&q)),
            -DVector::from_column_slice(phi.as_slice()),
        );
        let mut scale = 1.0;
        loop {
            let mut trial = q;
            for (c, &i) in free.iter().enumerate() {
                trial[i] += scale * step[c];
            }
            let next = s.constraint_residual(&trial);
            if next.norm() < phi.norm() || scale < 1e-6 {
                q = trial;
                phi = next;
                break;
            }
            scale *= 0.5;
        }
    }
    if !(phi.amax() <= tol(&q)) {
        let worst = phi.iamax();
        return Err(LoopError::NoAssembly {
            row: S::CONSTRAINTS[worst],
            residual: phi[worst],
        });
    }
    let g = s.constraint_jacobian(&q);
    let mut v = *v;
    for &i in &free {
        v[i] = 0.0;
    }
    let rhs = -(g * v);
    let dv = least_norm(restrict(&g), DVector::from_column_slice(rhs.as_slice()));
    for (c, &i) in free.iter().enumerate() {
        v[i] = dv[c];
    }
    Ok((q, v))
}
