//! Non-smooth ensembles in lockstep: many time-stepping runs of one scene (each with
//! its own parameters, elements and initial state) whose kernels are evaluated together
//! in the lanes of a SIMD batch ([`Lanes`]: `f64x4` holds four runs, `f64x2` two;
//! [`F64Lanes`](crate::real::F64Lanes) is the width to use: four on x86-64, where the
//! kernels' fused twins run four lanes in one AVX2 register).
//!
//! Each run is exactly a [`time_stepping`](super::time_stepping) run: its own grid, its
//! own element solve (Gauss–Seidel on its Delassus operator), its own switch log and
//! passivity check. What the lanes share is the arithmetic of the scene: every step of
//! every lane needs the forward dynamics with its Jacobian and `M⁻¹` at the step's
//! prediction point, and these are one call of the scene's generic kernels
//! ([`GenericDynamics`], `emit = [generic]`) for all lanes. The runs step independently
//! — a lane whose run ends (or fails) takes the next run of the ensemble at once — so no
//! lane waits for another and no run's result depends on the others'. The element
//! solves, which differ from lane to lane in their modes and sweeps, stay scalar.
//!
//! On `f64` (one lane) the same driver is the plain scalar ensemble, which is what the
//! lanes are measured against.

use nalgebra::{SMatrix, SVector};

use super::NonSmoothProblem;
use super::timestepping::{StepKernels, StepPoint, TimeSteps};
use crate::element::NonSmooth;
use crate::kernels::GenericDynamics;
use crate::real::Lanes;
use crate::{ErrorKind, ForwardJacobian, Solution, SolveError};

/// One run of a non-smooth ensemble: its scene (parameters and elements, as the struct's
/// fields set them) and its problem (time span, initial state, output).
#[derive(Clone, Debug)]
pub struct NonSmoothRun<S, const N: usize> {
    pub system: S,
    pub problem: NonSmoothProblem<N>,
}

/// Integrates every run by time-stepping (fixed step `h`, θ-method; see
/// [`time_stepping`](super::time_stepping), whose arguments and errors these are),
/// `L::LANES` runs at a time, and returns each run's result in the order of `runs`.
///
/// The applied forces `input(t, q, v)` are the same function for every run. A run's
/// result is the one `time_stepping` gives it alone, up to the rounding of the lanes'
/// kernels (the generic forward dynamics, its Jacobian and `M⁻¹` from the generic mass
/// matrix, instead of the scalar generated ones): a run that fails returns its typed
/// error with its trajectory so far, and the other runs go on.
///
/// Scenes with closed loops are refused per run ([`ErrorKind::InvalidInput`]): their
/// generic kernels are those of the open tree.
///
/// ```rust,ignore
/// use filippov::runtime::lockstep::{NonSmoothRun, time_stepping_lockstep};
/// use filippov::runtime::real::F64Lanes;
/// let runs: Vec<NonSmoothRun<Arm, 3>> = /* a scene and a problem per run */;
/// let zero = |_t: f64, _q: &V3, _v: &V3| V3::zeros();
/// let solutions = time_stepping_lockstep::<_, F64Lanes, _, 3, 3>(&runs, &zero, 1e-3, 1.0);
/// ```
pub fn time_stepping_lockstep<S, L, F, const N: usize, const P: usize>(
    runs: &[NonSmoothRun<S, N>],
    input: &F,
    h: f64,
    theta: f64,
) -> Vec<Result<Solution, SolveError>>
where
    S: NonSmooth<N> + GenericDynamics<N, N, P>,
    L: Lanes,
    F: Fn(f64, &SVector<f64, N>, &SVector<f64, N>) -> SVector<f64, N>,
{
    let mut results: Vec<Option<Result<Solution, SolveError>>> =
        runs.iter().map(|_| None).collect();
    let mut lanes: Vec<Option<(usize, TimeSteps<'_, N>)>> = (0..L::LANES).map(|_| None).collect();
    let mut next = 0;
    // Each lane's point and parameters (an idle lane's: the first busy lane's, not read).
    let mut points: Vec<Option<StepPoint<N>>> = vec![None; L::LANES];
    let mut filled: Vec<StepPoint<N>> = Vec::with_capacity(L::LANES);
    let mut parameters: Vec<[f64; P]> = vec![[0.0; P]; L::LANES];
    let mut kernels: Vec<StepKernels<N>> = Vec::with_capacity(L::LANES);
    loop {
        // Every free lane takes the next run that needs a step.
        for (slot, p) in lanes.iter_mut().zip(parameters.iter_mut()) {
            while slot.is_none() && next < runs.len() {
                let (r, run) = (next, &runs[next]);
                next += 1;
                if !S::LOOP_CONSTRAINTS.is_empty() {
                    let names = crate::element::column_names::<S, N>(&run.system);
                    results[r] = Some(Err(SolveError::new(
                        ErrorKind::InvalidInput(
                            "the lockstep ensemble integrates open trees only; this scene \
                             has closed loops (use `time_stepping` per run)"
                                .into(),
                        ),
                        Solution::new(names, 2 * N, run.problem.output.clone()),
                    )));
                    continue;
                }
                match TimeSteps::new(&run.system, input, &run.problem, h, theta) {
                    Ok(steps) if steps.t < run.problem.tf => {
                        *p = run.system.parameters();
                        *slot = Some((r, steps));
                    }
                    Ok(steps) => results[r] = Some(Ok(steps.traj)),
                    Err(error) => results[r] = Some(Err(error)),
                }
            }
        }
        let Some(first) = lanes.iter().position(Option::is_some) else {
            break;
        };
        for (point, lane) in points.iter_mut().zip(&lanes) {
            *point = lane
                .as_ref()
                .map(|(r, steps)| steps.point(input, runs[*r].problem.tf));
        }
        filled.clear();
        for i in 0..L::LANES {
            if lanes[i].is_none() {
                parameters[i] = parameters[first];
            }
            filled.push(
                points[i]
                    .or(points[first])
                    .expect("a busy lane has a point"),
            );
        }
        lane_kernels::<S, L, N, P>(&parameters, &filled, &mut kernels);
        for (i, lane) in lanes.iter_mut().enumerate() {
            let Some((r, steps)) = lane.as_mut() else {
                continue;
            };
            let r = *r;
            let done = match steps.finish(&runs[r].system, &filled[i], &kernels[i]) {
                Ok(()) if steps.t < runs[r].problem.tf => None,
                Ok(()) => Some(Ok(())),
                Err(kind) => Some(Err(kind)),
            };
            if let Some(end) = done {
                let (_, steps) = lane.take().expect("a busy lane");
                results[r] = Some(match end {
                    Ok(()) => Ok(steps.traj),
                    Err(kind) => Err(SolveError::new(kind, steps.traj)),
                });
            }
        }
    }
    results
        .into_iter()
        .map(|r| r.expect("every run ends with a result"))
        .collect()
}

/// The kernels of one step of every lane: the forward dynamics and its Jacobian at each
/// lane's point, and `M⁻¹` there (the generic mass matrix, inverted in the lanes).
fn lane_kernels<S, L, const N: usize, const P: usize>(
    parameters: &[[f64; P]],
    points: &[StepPoint<N>],
    out: &mut Vec<StepKernels<N>>,
) where
    S: GenericDynamics<N, N, P>,
    L: Lanes,
{
    let p: [L; P] = std::array::from_fn(|k| L::from_fn(|i| parameters[i][k]));
    let gather = |x: &dyn Fn(&StepPoint<N>) -> &SVector<f64, N>| -> [L; N] {
        std::array::from_fn(|k| L::from_fn(|i| x(&points[i])[k]))
    };
    let (q, v, tau) = (
        gather(&|p| &p.q_theta),
        gather(&|p| &p.v),
        gather(&|p| &p.tau),
    );
    let jac = S::forward_dynamics_jacobian_generic(&p, &q, &v, &tau);
    let minv = spd_inverse(&S::mass_matrix_generic(&p, &q));
    out.clear();
    for i in 0..L::LANES {
        let matrix = |m: &[[L; N]; N]| SMatrix::<f64, N, N>::from_fn(|r, c| m[r][c].lane(i));
        out.push(StepKernels {
            jacobian: ForwardJacobian {
                acceleration: SVector::from_fn(|r, _| jac.acceleration[r].lane(i)),
                d_dq: matrix(&jac.d_dq),
                d_dv: matrix(&jac.d_dv),
            },
            inverse_mass: matrix(&minv),
        });
    }
}

/// The inverse of a symmetric positive definite matrix by its `L D Lᵀ` factorisation, in
/// every lane at once (no pivoting: a mass matrix needs none). A lane whose matrix is
/// singular gets non-finite entries, which the step reports as non-finite.
#[allow(clippy::needless_range_loop)] // the factorisation's indices are the algebra's
fn spd_inverse<T: crate::Real, const N: usize>(m: &[[T; N]; N]) -> [[T; N]; N] {
    let zero = T::cst(0.0);
    let mut l = [[zero; N]; N];
    let mut d = [zero; N];
    for j in 0..N {
        let mut djj = m[j][j];
        for k in 0..j {
            djj = djj - l[j][k] * l[j][k] * d[k];
        }
        d[j] = djj;
        let inv = T::cst(1.0) / djj;
        for i in j + 1..N {
            let mut lij = m[i][j];
            for k in 0..j {
                lij = lij - l[i][k] * l[j][k] * d[k];
            }
            l[i][j] = lij * inv;
        }
    }
    // Column c of the inverse: L y = e_c, D z = y, Lᵀ x = z.
    let mut out = [[zero; N]; N];
    for c in 0..N {
        let mut y = [zero; N];
        for i in 0..N {
            let mut s = if i == c { T::cst(1.0) } else { zero };
            for k in 0..i {
                s = s - l[i][k] * y[k];
            }
            y[i] = s;
        }
        for i in 0..N {
            y[i] = y[i] / d[i];
        }
        for i in (0..N).rev() {
            let mut s = y[i];
            for k in i + 1..N {
                s = s - l[k][i] * out[k][c];
            }
            out[i][c] = s;
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn spd_inverse_inverts_random_spd_matrices() {
        let mut seed = 7u64;
        let mut next = || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            (seed >> 11) as f64 / (1u64 << 53) as f64 - 0.5
        };
        for _ in 0..50 {
            let a = SMatrix::<f64, 5, 5>::from_fn(|_, _| next());
            let m = a * a.transpose() + SMatrix::<f64, 5, 5>::identity() * 0.1;
            let rows: [[f64; 5]; 5] = std::array::from_fn(|r| std::array::from_fn(|c| m[(r, c)]));
            let inv = spd_inverse(&rows);
            let inv = SMatrix::<f64, 5, 5>::from_fn(|r, c| inv[r][c]);
            let err = (m * inv - SMatrix::<f64, 5, 5>::identity()).amax();
            assert!(err < 1e-10, "‖M M⁻¹ − I‖ = {err}");
        }
    }
}
