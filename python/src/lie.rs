//! Scenes with spherical or free joints ([`LieMechanism`]): the kind [`Lie`] of
//! [`Scene`]. A configuration holds unit quaternions `(w, x, y, z)`, checked on the way
//! in; a run integrates on the Lie group (`rkmk5`, `lie_sdirk`), its rows in the
//! mechanism's layout (`q_<slot>`, `v_<coordinate>`) and its dense output on the group.

use std::marker::PhantomData;

use filippov_runtime::liegroup::mechanism_rows;
use filippov_runtime::system::{ForwardJacobian, ParameterError, Parameters};
use filippov_runtime::{LieMechanical, LieMechanism, LieProblem, LieState};
use nalgebra::{SMatrix, SVector};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::errors::solve_error;
use crate::options::{self, LieMethod};
use crate::scene::{Scene, vec};
use crate::solution::{OnGroup, PySolution};

/// How far a quaternion's norm may be from one (single-precision data passes).
const UNIT: f64 = 1e-6;

/// A scene with spherical or free joints ([`LieMechanism`]).
pub struct Lie<S>(PhantomData<S>);

/// A state of the trajectory as a row `(q, v)` in the mechanism's layout.
fn row<S: LieMechanism<N, NQ>, const N: usize, const NQ: usize>(y: &LieState, out: &mut [f64]) {
    let (q, v) = S::state_to_qv(y);
    out[..NQ].copy_from_slice(q.as_slice());
    out[NQ..].copy_from_slice(v.as_slice());
}

impl<S, const N: usize, const NQ: usize> Scene<N, NQ> for Lie<S>
where
    S: LieMechanism<N, NQ> + Parameters + Sync,
{
    type Inner = S;

    fn coordinates() -> Vec<&'static str> {
        S::COORDINATES.to_vec()
    }

    fn configuration() -> Vec<String> {
        S::configuration_names().to_vec()
    }

    fn elements() -> Vec<&'static str> {
        Vec::new()
    }

    fn check_configuration(q: &[f64]) -> Result<(), String> {
        for &(s, _) in S::ROTATIONS {
            let norm = q[s..s + 4].iter().map(|x| x * x).sum::<f64>().sqrt();
            if norm.is_nan() || (norm - 1.0).abs() > UNIT {
                // The names only for the message: this runs for every state of a batch.
                let names = S::configuration_names();
                let joint = names[s].strip_suffix(".qw").unwrap_or(&names[s]);
                return Err(format!(
                    "the quaternion of joint `{joint}` (slots {s}–{}, w x y z) has norm \
                     {norm}; give unit quaternions (divide by the norm)",
                    s + 3
                ));
            }
        }
        Ok(())
    }

    fn validate(scene: &S) -> Result<(), ParameterError> {
        scene.validate()
    }

    fn mass_matrix(scene: &S, q: &SVector<f64, NQ>) -> SMatrix<f64, N, N> {
        scene.mass_matrix(q)
    }

    fn forward_dynamics(
        scene: &S,
        q: &SVector<f64, NQ>,
        v: &SVector<f64, N>,
        tau: &SVector<f64, N>,
    ) -> SVector<f64, N> {
        scene.forward_dynamics(q, v, tau)
    }

    fn forward_dynamics_jacobian(
        scene: &S,
        q: &SVector<f64, NQ>,
        v: &SVector<f64, N>,
        tau: &SVector<f64, N>,
    ) -> ForwardJacobian<N> {
        scene.forward_dynamics_jacobian(q, v, tau)
    }

    fn run(
        py: Python<'_>,
        scene: &S,
        t_end: f64,
        q: SVector<f64, NQ>,
        v: SVector<f64, N>,
        opts: Option<&Bound<'_, PyDict>>,
    ) -> PyResult<PySolution> {
        let (method, common) = options::lie(N, opts)?;
        let problem =
            LieProblem::new(common.t0, t_end, S::qv_to_state(&q, &v)).with_output(common.output);
        let tau: SVector<f64, N> = common.tau.as_deref().map_or(SVector::zeros(), vec);
        let run = py.detach(|| {
            let sys = LieMechanical::new(
                scene,
                move |_t: f64, _q: &SVector<f64, NQ>, _v: &SVector<f64, N>| tau,
            );
            match &method {
                LieMethod::Rkmk5(m) => m.solve(&sys, &problem),
                LieMethod::Sdirk(m) => m.solve(&sys, &problem),
            }
        });
        match run {
            Ok(trajectory) => {
                let inner = mechanism_rows::<S, N, NQ>(trajectory.flat())
                    .expect("a run of this scene has its columns");
                Ok(PySolution {
                    inner,
                    group: Some(OnGroup {
                        trajectory,
                        row: row::<S, N, NQ>,
                    }),
                })
            }
            Err(e) => {
                let message = e.to_string();
                let rows = mechanism_rows::<S, N, NQ>(&e.solution).unwrap_or(*e.solution);
                Err(solve_error(py, &e.kind, message, rows))
            }
        }
    }
}
