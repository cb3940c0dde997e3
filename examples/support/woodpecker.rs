//! The woodpecker toy (Glocker's benchmark, theory §8): a sleeve with a little play on a
//! vertical pole, a bird on a torsion spring on the sleeve, three contacts with
//! friction (the beak on the pole, the sleeve's upper and lower edges on the pole).
//!
//! The published model linearises the kinematics about the upright pose: the mass matrix
//! is constant and the gaps are linear in the coordinates `q = (y, φ_M, φ_S)` (the
//! sleeve's height and angle, the bird's angle). That is no tree of rigid bodies, so it
//! is written here by hand against the runtime's traits ([`Mechanism`] and
//! [`Contacts`]) — what the derive writes for a tree — with the published parameters
//! and the published state on the toy's periodic motion. Siconos ships the same model
//! as an example, with a reference run by its Moreau–Jean integrator
//! (`examples/support/woodpecker_siconos.csv`).

#![allow(dead_code)]

use filippov::nalgebra::{SMatrix, SVector, Vector3};
use filippov::runtime::contacts::Contacts;
use filippov::runtime::numeric::Model;
use filippov::runtime::{ForwardJacobian, Mechanism, Solution};

/// Glocker's woodpecker: lengths in m, masses in kg, inertias in kg m², the spring in
/// N m/rad.
#[derive(Clone, Copy, Debug)]
pub struct Woodpecker {
    /// The pole's radius.
    pub r0: f64,
    /// The sleeve's inner radius.
    pub r_m: f64,
    /// Half the sleeve's height.
    pub h_m: f64,
    /// From the sleeve's centre to the spring's hinge.
    pub l_m: f64,
    /// From the hinge to the bird's centre of mass.
    pub l_g: f64,
    /// The beak's height above the bird's centre of mass.
    pub h_s: f64,
    /// The beak's horizontal distance from the bird's centre of mass.
    pub l_s: f64,
    /// Sleeve mass and inertia.
    pub m_m: f64,
    pub j_m: f64,
    /// Bird mass and inertia.
    pub m_s: f64,
    pub j_s: f64,
    /// The torsion spring.
    pub c_phi: f64,
    pub g: f64,
    /// Newton's restitution at the beak and at the sleeve's edges.
    pub e_beak: f64,
    pub e_sleeve: f64,
    /// Coulomb's coefficient at all three contacts.
    pub mu: f64,
}

/// The published parameters (Glocker 1995).
pub const GLOCKER: Woodpecker = Woodpecker {
    r0: 0.0025,
    r_m: 0.0031,
    h_m: 0.0058,
    l_m: 0.010,
    l_g: 0.015,
    h_s: 0.020,
    l_s: 0.0201,
    m_m: 0.0003,
    j_m: 5.0e-9,
    m_s: 0.0045,
    j_s: 7.0e-7,
    c_phi: 0.0056,
    g: 9.81,
    e_beak: 0.5,
    e_sleeve: 0.0,
    mu: 0.3,
};

/// The published state on the periodic motion: `(q, v)` with `q = (y, φ_M, φ_S)`.
pub const PUBLISHED_START: ([f64; 3], [f64; 3]) =
    ([0.0, -0.1036, -0.2788], [-0.3411, 0.0, -7.4583]);

/// Siconos's reference run (`woodpecker_siconos.csv`): rows `(t, [y, φ_M, φ_S],
/// [ẏ, φ̇_M, φ̇_S])`, one per millisecond from the published state.
pub fn siconos_reference() -> Vec<(f64, [f64; 3], [f64; 3])> {
    include_str!("woodpecker_siconos.csv")
        .lines()
        .filter(|l| !l.starts_with('#') && !l.starts_with('t'))
        .map(|l| {
            let x: Vec<f64> = l
                .split(',')
                .map(|x| x.parse().expect("a number in the reference"))
                .collect();
            (x[0], [x[1], x[3], x[5]], [x[2], x[4], x[6]])
        })
        .collect()
}

/// The largest difference of each coordinate `(y, φ_M, φ_S)` between `run` and `other`
/// (Siconos's reference where `None`) over the reference's sample times; NaN where a run
/// does not reach one.
pub fn largest_difference(run: &Solution, other: Option<&Solution>) -> [f64; 3] {
    let mut out = [0.0f64; 3];
    for (t, q, _) in siconos_reference() {
        let (Some(x), Some(y)) = (run.at(t), other.map_or(Some(q.to_vec()), |o| o.at(t))) else {
            return [f64::NAN; 3];
        };
        for i in 0..3 {
            out[i] = out[i].max((x[i] - y[i]).abs());
        }
    }
    out
}

/// The beak's impacts in a run sampled at `rows` (as [`siconos_reference`]'s): where
/// the bird's angular velocity falls by more than `drop` rad/s from one sample to the
/// next (the beak's impact reverses it), as the pair of sample times around each.
pub fn beak_impacts(rows: &[(f64, [f64; 3], [f64; 3])], drop: f64) -> Vec<(f64, f64)> {
    rows.windows(2)
        .filter(|w| w[0].2[2] - w[1].2[2] > drop)
        .map(|w| (w[0].0, w[1].0))
        .collect()
}

type V3 = SVector<f64, 3>;
type M3 = SMatrix<f64, 3, 3>;

impl Woodpecker {
    fn mass(&self) -> M3 {
        let (ms, lm, lg) = (self.m_s, self.l_m, self.l_g);
        M3::new(
            ms + self.m_m,
            ms * lm,
            ms * lg,
            ms * lm,
            self.j_m + ms * lm * lm,
            ms * lm * lg,
            ms * lg,
            ms * lm * lg,
            self.j_s + ms * lg * lg,
        )
    }

    /// Gravity and the spring: `h(q)`, so that `M v̇ = h(q) + τ + W λ`.
    fn forces(&self, q: &V3) -> V3 {
        let spring = self.c_phi * (q[1] - q[2]);
        V3::new(
            -(self.m_s + self.m_m) * self.g,
            -spring - self.m_s * self.l_m * self.g,
            spring - self.m_s * self.l_g * self.g,
        )
    }

    /// `W_N`: rows beak, sleeve's first edge, sleeve's second edge.
    fn normal_rows(&self) -> M3 {
        M3::new(
            0.0, 0.0, -self.h_s, //
            0.0, self.h_m, 0.0, //
            0.0, -self.h_m, 0.0,
        )
    }

    /// `W_T`: the contact points' vertical velocities, as published.
    fn tangent_rows(&self) -> M3 {
        M3::new(
            1.0,
            self.l_m,
            self.l_g - self.l_s,
            1.0,
            self.r_m,
            0.0,
            1.0,
            self.r_m,
            0.0,
        )
    }
}

impl Woodpecker {
    /// The energy: kinetic, gravity's and the spring's (`h(q) = −∂U/∂q`).
    pub fn energy(&self, q: &V3, v: &V3) -> f64 {
        let spring = 0.5 * self.c_phi * (q[1] - q[2]).powi(2);
        let gravity = self.g
            * ((self.m_s + self.m_m) * q[0]
                + self.m_s * self.l_m * q[1]
                + self.m_s * self.l_g * q[2]);
        0.5 * v.dot(&(self.mass() * v)) + spring + gravity
    }
}

impl Mechanism<3> for Woodpecker {
    const JOINTS: [&'static str; 3] = ["y", "phi_m", "phi_s"];

    fn mass_matrix(&self, _q: &V3) -> M3 {
        self.mass()
    }

    fn forward_dynamics(&self, q: &V3, _v: &V3, tau: &V3) -> V3 {
        self.mass()
            .cholesky()
            .expect("the published mass matrix is positive definite")
            .solve(&(self.forces(q) + tau))
    }

    fn forward_dynamics_jacobian(&self, q: &V3, v: &V3, tau: &V3) -> ForwardJacobian<3> {
        let inverse = self.mass().try_inverse().expect("positive definite");
        let spring = M3::new(
            0.0,
            0.0,
            0.0, //
            0.0,
            -self.c_phi,
            self.c_phi, //
            0.0,
            self.c_phi,
            -self.c_phi,
        );
        ForwardJacobian {
            acceleration: self.forward_dynamics(q, v, tau),
            d_dq: inverse * spring,
            d_dv: M3::zeros(),
        }
    }

    /// Not a tree: the numeric implementation's cross-checks do not apply, and the
    /// contact integrators do not use it. An empty model with the published gravity.
    fn model(&self) -> Model {
        Model {
            gravity: Vector3::new(0.0, -self.g, 0.0),
            links: Vec::new(),
            springs: Vec::new(),
            dampers: Vec::new(),
            point_springs: Vec::new(),
        }
    }
}

impl Contacts<3, 3, 3> for Woodpecker {
    const CONTACTS: [&'static str; 3] = ["beak", "sleeve_1", "sleeve_2"];
    const TANGENTS: [&'static str; 3] = ["beak.y", "sleeve_1.y", "sleeve_2.y"];
    const TANGENT_OF: [usize; 3] = [0, 1, 2];

    fn contact_friction(&self) -> [f64; 3] {
        [self.mu; 3]
    }
    fn contact_restitution(&self) -> [f64; 3] {
        [self.e_beak, self.e_sleeve, self.e_sleeve]
    }
    fn contact_gaps(&self, q: &V3) -> V3 {
        let play = self.r_m - self.r0;
        V3::new(self.l_m + self.l_g - self.l_s - self.r0, play, play) + self.normal_rows() * q
    }
    fn contact_normal_jacobian(&self, _q: &V3) -> M3 {
        self.normal_rows()
    }
    fn contact_normal_gamma(&self, _q: &V3, _v: &V3) -> V3 {
        V3::zeros()
    }
    fn contact_tangent_jacobian(&self, _q: &V3) -> M3 {
        self.tangent_rows()
    }
    fn contact_tangent_gamma(&self, _q: &V3, _v: &V3) -> V3 {
        V3::zeros()
    }
}
