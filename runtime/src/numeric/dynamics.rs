//! Joint-space dynamics built from RNEA and CRBA (theory.md §1–2):
//! `M(q) v̇ + C(q, v) v + g(q) = τ + τ_p(q, v)`, `τ_p = −k (q − q_rest) − c v`, and the
//! spatial momentum. `q` is in the configuration layout, `v`, `a`, `τ` in the velocity
//! layout ([`Model`]'s coordinates).

use nalgebra::{DVector, Vector3};

use super::Model;
use super::crba::{composite_inertias, crba, crba_in};
use super::kinematics::WorldTree;
use super::rnea::{rnea, rnea_in};

/// The configuration slot of a spring's coordinate.
///
/// # Panics
/// If the spring is on a component of a spherical joint (no position to stretch).
fn spring_slot(model: &Model, coordinate: usize) -> usize {
    model.euclid_slot(coordinate).unwrap_or_else(|| {
        panic!("spring on coordinate {coordinate}, which is not a Euclidean coordinate")
    })
}

/// Generalised gravity force `g(q) = RNEA(q, 0, 0)`.
pub fn gravity(model: &Model, q: &DVector<f64>) -> DVector<f64> {
    let zero = DVector::zeros(model.dof());
    rnea(model, q, &zero, &zero)
}

/// `C(q, v) v + g(q) = RNEA(q, v, 0)`.
pub fn bias(model: &Model, q: &DVector<f64>, v: &DVector<f64>) -> DVector<f64> {
    rnea(model, q, v, &DVector::zeros(model.dof()))
}

/// Passive forces `τ_p = −Σ k (q_i − rest) − Σ c v_i` of the model's springs and dampers
/// (`q_i` the configuration slot of the spring's coordinate, [`Model::euclid_slot`]).
///
/// # Panics
/// If a spring is on a component of a spherical joint.
pub fn passive_forces(model: &Model, q: &DVector<f64>, v: &DVector<f64>) -> DVector<f64> {
    let mut tau = DVector::zeros(model.dof());
    for s in &model.springs {
        tau[s.coordinate] -= s.stiffness * (q[spring_slot(model, s.coordinate)] - s.rest);
    }
    for d in &model.dampers {
        tau[d.coordinate] -= d.damping * v[d.coordinate];
    }
    if !model.point_springs.is_empty() {
        let poses = super::link_poses(model, q);
        for s in &model.point_springs {
            let (pa, pb) = (world_point(&poses, &s.a), world_point(&poses, &s.b));
            let d = pb - pa;
            let length = d.norm();
            // The force on b; a takes its opposite.
            let f = d * (-s.stiffness * (length - s.rest) / length);
            apply_point_force(model, &poses, s.b.0, &pb, &f, &mut tau);
            apply_point_force(model, &poses, s.a.0, &pa, &(-f), &mut tau);
        }
    }
    tau
}

/// A point given on a link (`None`: the world), in world coordinates.
fn world_point(poses: &[super::Pose], p: &(Option<usize>, Vector3<f64>)) -> Vector3<f64> {
    match p.0 {
        Some(l) => poses[l].transform_point(&p.1),
        None => p.1,
    }
}

/// Adds the generalised force of the world force `f` applied at the world point `p` of
/// `link` (nothing for the world): for every joint on the path to the root, each of its
/// motion directions (a unit rotation about, or translation along, a world axis
/// through its link's origin) does `(w × (p − o))·f` or `w·f` of work per unit speed.
fn apply_point_force(
    model: &Model,
    poses: &[super::Pose],
    link: Option<usize>,
    p: &Vector3<f64>,
    f: &Vector3<f64>,
    tau: &mut DVector<f64>,
) {
    use super::JointKind;
    let mut at = link;
    while let Some(l) = at {
        let link = &model.links[l];
        if let Some(c) = link.coordinate {
            let pose = &poses[l];
            let arm = p - pose.translation;
            match link.joint {
                JointKind::Revolute { axis } => {
                    let w = pose.rotation * axis;
                    tau[c] += w.cross(&arm).dot(f);
                }
                JointKind::Prismatic { axis } => tau[c] += (pose.rotation * axis).dot(f),
                JointKind::Spherical => {
                    for k in 0..3 {
                        let w = pose.rotation.column(k).into_owned();
                        tau[c + k] += w.cross(&arm).dot(f);
                    }
                }
                JointKind::Translation => {
                    for k in 0..3 {
                        tau[c + k] += pose.rotation.column(k).dot(f);
                    }
                }
                JointKind::Fixed => {}
            }
        }
        at = link.parent;
    }
}

/// `τ = M a + C v + g − τ_p`: the input forces that produce acceleration `a`.
pub fn inverse_dynamics(
    model: &Model,
    q: &DVector<f64>,
    v: &DVector<f64>,
    a: &DVector<f64>,
) -> DVector<f64> {
    rnea(model, q, v, a) - passive_forces(model, q, v)
}

/// `v̇ = M⁻¹ (τ + τ_p − C v − g)`, solved with a Cholesky factorisation of `M`.
///
/// A mass matrix that is not positive definite (a massless chain, a modelling error)
/// yields an all-NaN acceleration rather than a panic, so integrators report it as a
/// non-finite derivative.
pub fn forward_dynamics(
    model: &Model,
    q: &DVector<f64>,
    v: &DVector<f64>,
    tau: &DVector<f64>,
) -> DVector<f64> {
    AtConfiguration::new(model, q).forward_dynamics(v, tau)
}

/// What forward dynamics needs of one configuration `q` — the links' world motion
/// subspaces and inertias, and the Cholesky factor of `M(q)` — computed once for any
/// number of velocities and torques (the same numbers as [`forward_dynamics`]).
pub(crate) struct AtConfiguration<'a> {
    model: &'a Model,
    q: &'a DVector<f64>,
    tree: WorldTree,
    chol: Option<nalgebra::Cholesky<f64, nalgebra::Dyn>>,
}

impl<'a> AtConfiguration<'a> {
    pub(crate) fn new(model: &'a Model, q: &'a DVector<f64>) -> Self {
        let tree = WorldTree::new(model, q);
        let composite = composite_inertias(model, &tree);
        let chol = crba_in(model, &tree, &composite).cholesky();
        AtConfiguration {
            model,
            q,
            tree,
            chol,
        }
    }

    /// `v̇ = M⁻¹ (τ + τ_p − C v − g)` at this configuration (NaN where `M` is not
    /// positive definite).
    pub(crate) fn forward_dynamics(&self, v: &DVector<f64>, tau: &DVector<f64>) -> DVector<f64> {
        let zero = DVector::zeros(self.model.dof());
        let rhs =
            tau + passive_forces(self.model, self.q, v) - rnea_in(self.model, &self.tree, v, &zero);
        match &self.chol {
            Some(chol) => chol.solve(&rhs),
            None => DVector::from_element(rhs.len(), f64::NAN),
        }
    }
}

/// Kinetic energy `½ vᵀ M(q) v`.
pub fn kinetic_energy(model: &Model, q: &DVector<f64>, v: &DVector<f64>) -> f64 {
    0.5 * v.dot(&(crba(model, q) * v))
}

/// Potential energy of gravity, `−Σ m gravity · p_com`, plus the springs
/// `Σ ½ k (q_i − rest)²` and the point springs `Σ ½ k (ℓ − rest)²`.
pub fn potential_energy(model: &Model, q: &DVector<f64>) -> f64 {
    let poses = super::link_poses(model, q);
    let gravity: f64 = model
        .links
        .iter()
        .zip(&poses)
        .map(|(link, pose)| -link.mass * model.gravity.dot(&pose.transform_point(&link.com)))
        .sum();
    let springs: f64 = model
        .springs
        .iter()
        .map(|s| 0.5 * s.stiffness * (q[spring_slot(model, s.coordinate)] - s.rest).powi(2))
        .sum();
    let point_springs: f64 = model
        .point_springs
        .iter()
        .map(|s| {
            let length = (world_point(&poses, &s.b) - world_point(&poses, &s.a)).norm();
            0.5 * s.stiffness * (length - s.rest).powi(2)
        })
        .sum();
    gravity + springs + point_springs
}

/// Total spatial momentum in world coordinates, `(linear, angular)`: the linear momentum
/// `Σ m_i ċ_i` (`c_i` the world centre of mass of link `i`) and the angular momentum
/// about the world origin `Σ (c_i × m_i ċ_i + R_i I_i ω_i)` (`ω_i` the world angular
/// velocity, `I_i` the inertia about the centre of mass in link axes). It is
/// `Σ_i I_i^O v_i` in the Plücker coordinates of `spatial.rs` (moment first).
///
/// Its rate is the total external wrench: with no gravity and no joint to the world
/// that can push (a free base: translation + spherical), it is constant.
pub fn spatial_momentum(
    model: &Model,
    q: &DVector<f64>,
    v: &DVector<f64>,
) -> (Vector3<f64>, Vector3<f64>) {
    let tree = WorldTree::new(model, q);
    let h = tree
        .velocities(model, v)
        .iter()
        .zip(&tree.inertia)
        .fold(nalgebra::Vector6::zeros(), |acc, (vi, ii)| acc + ii * vi);
    (
        h.fixed_rows::<3>(3).into_owned(),
        h.fixed_rows::<3>(0).into_owned(),
    )
}

#[cfg(test)]
mod tests {
    use super::super::test_models::*;
    use super::super::{Damper, Spring};
    use super::*;

    #[test]
    fn double_pendulum_gravity_matches_closed_form_and_potential_gradient() {
        let (m1, l1, m2, l2) = (1.0, 1.0, 0.5, 0.7);
        let model = double_pendulum(m1, l1, m2, l2);
        let q = DVector::from_vec(vec![0.3, -1.2]);
        let (_, expected) = double_pendulum_closed_form(m1, l1, m2, l2, q[0], q[1]);
        assert!((gravity(&model, &q) - &expected).norm() < 1e-13);
        let h = 1e-6;
        for k in 0..2 {
            let mut qp = q.clone();
            let mut qm = q.clone();
            qp[k] += h;
            qm[k] -= h;
            let du = (potential_energy(&model, &qp) - potential_energy(&model, &qm)) / (2.0 * h);
            assert!((du - expected[k]).abs() < 1e-8);
        }
    }

    #[test]
    fn forward_and_inverse_dynamics_are_inverse() {
        let mut model = spatial_chain();
        model.springs.push(Spring {
            coordinate: 1,
            stiffness: 3.0,
            rest: 0.2,
        });
        model.dampers.push(Damper {
            coordinate: 2,
            damping: 0.7,
        });
        let n = model.dof();
        let q = DVector::from_fn(n, |i, _| 0.1 * i as f64 - 0.4);
        let v = DVector::from_fn(n, |i, _| 0.9 - 0.3 * i as f64);
        let tau = DVector::from_fn(n, |i, _| (i as f64).sin());
        let a = forward_dynamics(&model, &q, &v, &tau);
        assert!((inverse_dynamics(&model, &q, &v, &a) - tau).norm() < 1e-11);
    }

    /// Energy balance (theory.md §6): with the springs inside the potential energy,
    /// `dE/dt = vᵀ (τ + τ_damper)`. Checked by a central difference along the motion
    /// `q(t) ≈ q + t v + t²/2 a`, `v(t) ≈ v + t a` with `a` from forward dynamics.
    #[test]
    fn energy_rate_equals_input_and_damper_power() {
        let mut model = spatial_chain();
        model.springs.push(Spring {
            coordinate: 0,
            stiffness: 5.0,
            rest: -0.3,
        });
        model.dampers.push(Damper {
            coordinate: 1,
            damping: 0.4,
        });
        let n = model.dof();
        let q = DVector::from_fn(n, |i, _| 0.25 * i as f64 + 0.1);
        let v = DVector::from_fn(n, |i, _| 0.6 - 0.5 * i as f64);
        let tau = DVector::from_fn(n, |i, _| 0.3 * i as f64 - 0.2);
        let a = forward_dynamics(&model, &q, &v, &tau);
        let energy = |t: f64| {
            let qt = &q + &v * t + &a * (0.5 * t * t);
            let vt = &v + &a * t;
            kinetic_energy(&model, &qt, &vt) + potential_energy(&model, &qt)
        };
        let h = 1e-5;
        let rate = (energy(h) - energy(-h)) / (2.0 * h);
        let damper: DVector<f64> = passive_forces(&model, &q, &v)
            + DVector::from_fn(n, |i, _| if i == 0 { 5.0 * (q[0] + 0.3) } else { 0.0 });
        let power = v.dot(&(tau + damper));
        assert!((rate - power).abs() < 1e-7, "{rate} vs {power}");
    }
}
