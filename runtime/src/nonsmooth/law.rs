//! Constitutive graphs of the non-smooth elements, and the scalar problem every implicit
//! step reduces to: intersect a straight line with one element's graph.
//!
//! An element's constitutive relation is a *graph* in the `(f, v)` plane (theory.md §3):
//! the force `f` it carries against the velocity `v` of its coordinate.
//!
//! * Bingham dash-pots: `v = Φ(f)`, with `Φ = 0` in the dead zone `|f| ≤ f_crit` (stick)
//!   and the slip law `φ` outside it — a function of the force, monotone or not.
//! * Coulomb friction: `|f| ≤ f_crit` at `v = 0`, `f = f_crit sgn v` otherwise — neither a
//!   function of `v` nor of `f`, but a maximal monotone graph.
//! * Stops, in the gap coordinate `g = σ (q − position)` (`σ = +1` for [`Side::Lower`](crate::element::Side::Lower),
//!   `−1` for [`Side::Upper`](crate::element::Side::Upper)) with contact force `λ ≥ 0` pushing the coordinate back into
//!   its admissible side, i.e. element force `f = −σ λ` under the sign convention of
//!   [`crate::nonsmooth`].
//!
//! Implicit time-stepping (Moreau 1988; Jean 1999, *The non-smooth contact dynamics
//! method*, CMAME 177; Acary & Brogliato 2008, *Numerical Methods for Nonsmooth Dynamical
//! Systems*, ch. 10; the thesis's Fig. 18) writes the discrete momentum balance of one
//! element, all other forces frozen, as a straight [`Line`] `v = v_free − w f` with
//! `w > 0` (step × Delassus entry). [`Graph::on_line`] returns its intersection with the
//! element's graph. For a monotone graph the intersection exists and is unique for every
//! `w > 0`; for a non-monotone law the [`Selection`] rule picks one:
//!
//! * Approach 2 ([`Selection::MaximalDissipation`]): the intersection with the
//!   *maximal-dissipation graph* `ψ(f) = inf_{g ≥ f} φ(g)` (for `f > f_crit`, odd
//!   extension): at each velocity the largest force, with the jumps of `f` at the local
//!   minima filled by vertical segments at `v = v_min` (plateau mode, theory.md §3). `ψ`
//!   is monotone, so the intersection is unique; on a plateau the velocity is exactly
//!   `±v_min`.
//! * Approach 1 ([`Selection::NoVelocityJumps`]): stay on the current branch. The state
//!   is the previous force `f_prev`: starting at `f_prev`, the force moves in the
//!   direction that closes the gap between line and graph, to the *first* intersection.
//!   While the branch exists the force changes continuously; where it ends at a fold, the
//!   force jumps to the next branch (hysteresis).
//!
//! Non-monotone laws are assumed monotone beyond their folds: the folds (local extrema of
//! `φ`) are located once, by a sign scan of `φ'` on `f_crit < f ≤ FOLD_SCAN · (f_crit + 1)`
//! refined by bisection ([`Graph::folds`]).

use super::kind::bingham::side_phi;
use super::kind::graph::bisect;
pub use super::kind::graph::{
    Branch, Branches, Fold, LawError, Line, Part, PlateauLevel, Point, StepState,
};
use super::kind::{Context, Forces, Kind, NO_BRANCHES, with_kind};
use crate::element::{Element, ElementKind, Law, NonSmooth, Selection};

/// Non-monotone laws are scanned for folds on `f_crit < f ≤ FOLD_SCAN · (f_crit + 1)`.
pub const FOLD_SCAN: f64 = 16.0;
/// Grid cells of the fold scan.
const FOLD_CELLS: usize = 4096;

/// The weight `θ_q` of the new velocity in a time-step's position update
/// `q_{n+1} = q_n + h ((1 − θ_q) v_n + θ_q v_{n+1})`: `max(θ, 1 − θ)`, so that θ = 1 is
/// implicit Euler, θ = ½ the implicit midpoint rule and θ = 0 symplectic Euler.
pub fn position_weight(theta: f64) -> f64 {
    theta.max(1.0 - theta)
}

/// One element's constitutive graph: the element, validated, and for non-monotone laws
/// its folds (located once).
#[derive(Clone, Debug, PartialEq)]
pub struct Graph {
    pub index: usize,
    pub element: Element,
    folds: Vec<Fold>,
}

impl Graph {
    /// Element `e` of `system`, validated: `f_crit ≥ 0`, `η > 0`, restitution in `[0, 1]`,
    /// support stiffness `> 0`, everything finite.
    pub fn new<S: NonSmooth<N>, const N: usize>(system: &S, e: usize) -> Result<Self, LawError> {
        let element = system.element(e);
        check(&element)?;
        if let ElementKind::DashPot {
            law: Law::BinghamMonotone | Law::BinghamNonMonotone { .. },
            f_crit,
        } = element.kind
        {
            check_law_finite(system, e, f_crit)?;
        }
        let mut graph = Graph {
            index: e,
            element,
            folds: Vec::new(),
        };
        if let ElementKind::DashPot {
            law: Law::BinghamNonMonotone { .. },
            f_crit,
        } = element.kind
        {
            graph.folds = find_folds(system, e, f_crit)?;
        }
        Ok(graph)
    }

    /// Local extrema of a non-monotone slip law on `f > f_crit`, by increasing force
    /// (empty for every other element). The negative side mirrors them (odd law).
    pub fn folds(&self) -> &[Fold] {
        &self.folds
    }

    /// What the element's kind needs to meet a line: the system, the index, the folds.
    fn context<'a, S>(&'a self, system: &'a S) -> Context<'a, S> {
        Context {
            system,
            index: self.index,
            branches: &NO_BRANCHES,
            folds: &self.folds,
        }
    }

    /// The slip branches of a non-monotone law under its selection rule (empty
    /// [`Branches`] for every other element).
    ///
    /// The increasing pieces of `φ` lie between the folds: `(f_crit, max₁)`,
    /// `(min₁, max₂)`, …, `(min_last, ∞)`. Approach 1 slips on all of them (the force
    /// jumps between pieces at a fold's velocity). Approach 2 keeps, besides the first,
    /// the pieces whose local minimum lies strictly below every later minimum (the
    /// pieces the envelope `ψ` touches), each up to the velocity of the next kept
    /// minimum, where a plateau joins it to the next kept piece.
    ///
    /// Errors with [`LawError::InvalidElement`] unless the folds alternate maximum,
    /// minimum, …, minimum (the law increases from `f_crit` and beyond its last fold).
    pub fn branches<S: NonSmooth<N>, const N: usize>(
        &self,
        system: &S,
    ) -> Result<Branches, LawError> {
        let ElementKind::DashPot {
            law: Law::BinghamNonMonotone { selection },
            f_crit,
        } = self.element.kind
        else {
            return Ok(Branches::default());
        };
        let alternating = self
            .folds
            .iter()
            .enumerate()
            .all(|(i, fold)| fold.minimum == (i % 2 == 1));
        if !alternating || self.folds.len() % 2 == 1 {
            return Err(LawError::InvalidElement(format!(
                "element `{}`: the non-monotone law must increase from f_crit and beyond its \
                 last fold (folds found: {:?})",
                self.element.name, self.folds
            )));
        }
        let phi = |x: f64| side_phi(system, self.index, 1.0, x);
        // The increasing pieces.
        let mut pieces = vec![Branch {
            f_lo: f_crit,
            f_hi: f64::INFINITY,
            v_lo: 0.0,
            v_hi: f64::INFINITY,
            f_top: f64::INFINITY,
            v_top: f64::INFINITY,
        }];
        for pair in self.folds.chunks(2) {
            let (max, min) = (pair[0], pair[1]);
            let last = pieces.last_mut().expect("one piece at least");
            (last.f_hi, last.f_top) = (max.force, max.force);
            (last.v_hi, last.v_top) = (max.velocity, max.velocity);
            pieces.push(Branch {
                f_lo: min.force,
                f_hi: f64::INFINITY,
                v_lo: min.velocity,
                v_hi: f64::INFINITY,
                f_top: f64::INFINITY,
                v_top: f64::INFINITY,
            });
        }
        if selection == Selection::NoVelocityJumps {
            return Ok(Branches {
                slip: pieces,
                plateaus: Vec::new(),
            });
        }
        // Approach 2: the pieces whose minimum is a strict suffix minimum.
        let mut kept: Vec<usize> = Vec::new();
        let mut below = f64::INFINITY;
        for k in (1..pieces.len()).rev() {
            if pieces[k].v_lo < below {
                kept.push(k);
                below = pieces[k].v_lo;
            }
        }
        kept.push(0);
        kept.reverse();
        let mut slip = Vec::with_capacity(kept.len());
        let mut plateaus = Vec::with_capacity(kept.len() - 1);
        for (i, &k) in kept.iter().enumerate() {
            let mut b = pieces[k];
            if let Some(&next) = kept.get(i + 1) {
                let level = pieces[next].v_lo;
                // φ rises from b.v_lo to the maximum b.v_hi > level on the piece.
                let f_cut = bisect(|x| phi(x) - level, b.f_lo, b.f_hi)?;
                b.f_hi = f_cut;
                b.v_hi = level;
                plateaus.push(PlateauLevel {
                    velocity: level,
                    f_lo: f_cut,
                    f_hi: pieces[next].f_lo,
                });
            }
            slip.push(b);
        }
        Ok(Branches { slip, plateaus })
    }

    /// Dash-pots: the velocity of a force, `v = Φ(f)` (`0` in the dead zone). `None` for
    /// friction (not a function of the force) and for stops.
    pub fn velocity_of_force<S: NonSmooth<N>, const N: usize>(
        &self,
        system: &S,
        f: f64,
    ) -> Option<f64> {
        with_kind!(self.element, |k| k
            .velocity_of_force(&self.context(system), f))
    }

    /// Dash-pots: the force of a slip velocity `v ≠ 0` (`None` for `v = 0`, where any
    /// force of the dead zone fits, and for stops). Friction: `±` its slip level.
    /// Monotone laws: the unique force, by safeguarded Newton on `Φ(f) = v`. Non-monotone
    /// laws: approach 2 the force of the maximal-dissipation graph; approach 1 the first
    /// force met from `previous` in the direction of `v − Φ(previous)`.
    pub fn force_of_velocity<S: NonSmooth<N>, const N: usize>(
        &self,
        system: &S,
        v: f64,
        previous: f64,
    ) -> Result<Option<f64>, LawError> {
        if !v.is_finite() || !previous.is_finite() {
            return Err(LawError::NonFinite);
        }
        if v == 0.0 {
            return Ok(None);
        }
        with_kind!(self.element, |k| k.force_of_velocity(
            &self.context(system),
            v,
            previous
        ))
    }

    /// The intersection of `line` with the graph (see the module documentation), given
    /// what the step knows at its start. Stuck dash-pots and rigid stops in contact
    /// return their velocity exactly (`0.0`, `−e·min(u_n, 0)` in the gap direction), set
    /// rather than computed.
    pub fn on_line<S: NonSmooth<N>, const N: usize>(
        &self,
        system: &S,
        line: Line,
        state: &StepState,
    ) -> Result<Point, LawError> {
        if !(line.v_free.is_finite() && line.w.is_finite() && line.w > 0.0) {
            return Err(LawError::NonFinite);
        }
        with_kind!(self.element, |k| k.on_line(
            &self.context(system),
            line,
            state
        ))
    }
}

/// Parameter checks with messages naming the element and what would be right.
fn check(el: &Element) -> Result<(), LawError> {
    with_kind!(el, |k| k.check())
        .map_err(|what| LawError::InvalidElement(format!("element `{}`: {what}", el.name)))
}

/// Local extrema of `φ` on `f_crit < f ≤ FOLD_SCAN (f_crit + 1)`: sign changes of `φ'`
/// on a uniform grid, refined by bisection on `φ'`.
/// A user slip law must be finite, with a finite slope, on its whole domain
/// `|f| ≥ f_crit`: it is sampled at `±f_crit` and on the fold-scan grid beyond (both
/// signs). A law like `(f − f_c)/f` with `f_c = 0` (`0/0` at `f = 0`) would otherwise
/// give NaN forces that no comparison catches.
fn check_law_finite<S: NonSmooth<N>, const N: usize>(
    system: &S,
    e: usize,
    f_crit: f64,
) -> Result<(), LawError> {
    let top = FOLD_SCAN * (f_crit + 1.0);
    for k in 0..=FOLD_CELLS {
        let x = f_crit + (top - f_crit) * k as f64 / FOLD_CELLS as f64;
        for f in [x, -x] {
            let (phi, dphi) = system.law(e, f);
            if !(phi.is_finite() && dphi.is_finite()) {
                return Err(LawError::InvalidElement(format!(
                    "element `{}`: its slip law is not finite at f = {f} (φ = {phi}, φ' = {dphi}); a law v = φ(f) must be finite, with a finite slope, for every |f| ≥ f_crit = {f_crit}",
                    system.element(e).name
                )));
            }
        }
    }
    Ok(())
}

fn find_folds<S: NonSmooth<N>, const N: usize>(
    system: &S,
    e: usize,
    f_crit: f64,
) -> Result<Vec<Fold>, LawError> {
    let top = FOLD_SCAN * (f_crit + 1.0);
    let dphi = |x: f64| system.law(e, x).1;
    let grid = |k: usize| f_crit + (top - f_crit) * k as f64 / FOLD_CELLS as f64;
    let mut folds = Vec::new();
    // The last grid point with a nonzero slope, and that slope.
    let (mut x0, mut d0) = (grid(1), dphi(grid(1)));
    for k in 2..=FOLD_CELLS {
        let x1 = grid(k);
        let d1 = dphi(x1);
        if !(d0.is_finite() && d1.is_finite()) {
            return Err(LawError::NonFinite);
        }
        if d1 == 0.0 {
            continue;
        }
        if d0 != 0.0 && (d0 > 0.0) != (d1 > 0.0) {
            let x = bisect(dphi, x0, x1)?;
            folds.push(Fold {
                force: x,
                velocity: system.law(e, x).0,
                minimum: d0 < 0.0,
            });
        }
        (x0, d0) = (x1, d1);
    }
    Ok(folds)
}

/// Hand-built test mechanisms: a chain of prismatic x-links (coordinates relative to the
/// parent, so `M_ij = Σ_{l ≥ max(i,j)} m_l`), linear springs to the rest position 0,
/// elements given as data, one user slip law for all Bingham user elements.
#[cfg(test)]
pub(crate) mod test_systems {
    use nalgebra::{Matrix3, SMatrix, SVector, Vector3};

    use crate::nonsmooth::{Element, NonSmooth};
    use crate::numeric::{JointKind, Link, Model, Spring};
    use crate::system::{ForwardJacobian, Mechanism};

    pub struct Chain<const N: usize, const E: usize> {
        pub masses: [f64; N],
        pub springs: [f64; N],
        pub elements: [Element; E],
        pub law: fn(f64) -> (f64, f64),
    }

    /// Cubic Bingham law 4.7b (γ = 1, f_crit = 1): v = f² (f − sgn f).
    pub fn cubic(f: f64) -> (f64, f64) {
        (f * f * (f - f.signum()), 3.0 * f * f - 2.0 * f.abs())
    }

    /// Non-monotone law 4.9b (f_crit = 1): v = (1 + 0.1 (f² − 4)(f² − 9)) (f − sgn f).
    pub fn non_monotone(f: f64) -> (f64, f64) {
        let a = 1.0 + 0.1 * (f * f - 4.0) * (f * f - 9.0);
        let da = 0.1 * (2.0 * f * (f * f - 9.0) + 2.0 * f * (f * f - 4.0));
        (a * (f - f.signum()), da * (f - f.signum()) + a)
    }

    impl<const N: usize, const E: usize> Chain<N, E> {
        fn m(&self) -> SMatrix<f64, N, N> {
            SMatrix::from_fn(|i, j| self.masses[i.max(j)..].iter().sum())
        }
        fn k(&self) -> SMatrix<f64, N, N> {
            SMatrix::from_diagonal(&SVector::from(self.springs))
        }
    }

    impl<const N: usize, const E: usize> Mechanism<N> for Chain<N, E> {
        const JOINTS: [&'static str; N] = [""; N];
        fn mass_matrix(&self, _q: &SVector<f64, N>) -> SMatrix<f64, N, N> {
            self.m()
        }
        fn forward_dynamics(
            &self,
            q: &SVector<f64, N>,
            _v: &SVector<f64, N>,
            tau: &SVector<f64, N>,
        ) -> SVector<f64, N> {
            self.inverse_mass_matrix(q) * (tau - self.k() * q)
        }
        fn forward_dynamics_jacobian(
            &self,
            q: &SVector<f64, N>,
            v: &SVector<f64, N>,
            tau: &SVector<f64, N>,
        ) -> ForwardJacobian<N> {
            ForwardJacobian {
                acceleration: self.forward_dynamics(q, v, tau),
                d_dq: -self.inverse_mass_matrix(q) * self.k(),
                d_dv: SMatrix::zeros(),
            }
        }
        fn model(&self) -> Model {
            Model {
                gravity: Vector3::zeros(),
                links: (0..N)
                    .map(|i| Link {
                        name: format!("body{i}"),
                        parent: i.checked_sub(1),
                        joint: JointKind::Prismatic { axis: Vector3::x() },
                        coordinate: Some(i),
                        origin_xyz: Vector3::zeros(),
                        origin_rpy: Vector3::zeros(),
                        mass: self.masses[i],
                        com: Vector3::zeros(),
                        inertia: Matrix3::zeros(),
                    })
                    .collect(),
                springs: (0..N)
                    .map(|i| Spring {
                        coordinate: i,
                        stiffness: self.springs[i],
                        rest: 0.0,
                    })
                    .collect(),
                dampers: vec![],
                point_springs: vec![],
            }
        }
    }

    impl<const N: usize, const E: usize> crate::kernels::Energy<N> for Chain<N, E> {
        fn kinetic_energy(&self, _q: &SVector<f64, N>, v: &SVector<f64, N>) -> f64 {
            0.5 * v.dot(&(self.m() * v))
        }
        fn potential_energy(&self, q: &SVector<f64, N>) -> f64 {
            (0..N).map(|i| 0.5 * self.springs[i] * q[i] * q[i]).sum()
        }
    }

    impl<const N: usize, const E: usize> NonSmooth<N> for Chain<N, E> {
        const ELEMENTS: usize = E;
        fn element(&self, e: usize) -> Element {
            self.elements[e]
        }
        fn law(&self, _e: usize, f: f64) -> (f64, f64) {
            (self.law)(f)
        }
        fn inverse_mass_matrix(&self, _q: &SVector<f64, N>) -> SMatrix<f64, N, N> {
            self.m().try_inverse().expect("masses are positive")
        }
    }

    /// One mass `m` on a spring `k` with the given elements.
    pub fn oscillator<const E: usize>(
        m: f64,
        k: f64,
        elements: [Element; E],
        law: fn(f64) -> (f64, f64),
    ) -> Chain<1, E> {
        Chain {
            masses: [m],
            springs: [k],
            elements,
            law,
        }
    }

    pub fn dashpot(
        name: &'static str,
        coordinate: usize,
        law: crate::nonsmooth::Law,
        f_crit: f64,
    ) -> Element {
        Element {
            name,
            coordinate,
            kind: crate::nonsmooth::ElementKind::DashPot { law, f_crit },
        }
    }

    pub fn stop(
        name: &'static str,
        coordinate: usize,
        side: crate::nonsmooth::Side,
        position: f64,
        kind: crate::nonsmooth::StopKind,
    ) -> Element {
        Element {
            name,
            coordinate,
            kind: crate::nonsmooth::ElementKind::Stop {
                side,
                position,
                kind,
            },
        }
    }
}

#[cfg(test)]
mod tests {
    use super::test_systems::*;
    use super::*;

    fn graph(law: Law, f_crit: f64, lawfn: fn(f64) -> (f64, f64)) -> (Chain<1, 1>, Graph) {
        let sys = oscillator(1.0, 1.0, [dashpot("d", 0, law, f_crit)], lawfn);
        let g = Graph::new(&sys, 0).unwrap();
        (sys, g)
    }

    fn state(force: f64) -> StepState {
        StepState {
            q: 0.0,
            v: 0.0,
            h: 0.01,
            theta_q: 1.0,
            force,
            v_smooth: 0.0,
        }
    }

    #[test]
    fn monotone_graphs_meet_a_line_once_and_stick_exactly() {
        let (sys, g) = graph(Law::Coulomb, 0.5, cubic);
        let p = g
            .on_line(
                &sys,
                Line {
                    v_free: 0.004,
                    w: 0.01,
                },
                &state(0.0),
            )
            .unwrap();
        assert_eq!((p.v, p.part), (0.0, Part::Stick));
        assert!((p.f - 0.4).abs() < 1e-15);
        let p = g
            .on_line(
                &sys,
                Line {
                    v_free: -0.1,
                    w: 0.01,
                },
                &state(0.0),
            )
            .unwrap();
        assert_eq!((p.f, p.part), (-0.5, Part::Slip));
        assert!((p.v - (-0.095)).abs() < 1e-15);
        // Linear Bingham: v = (f − f_c)/η and v = v_free − w f.
        let (sys, g) = graph(Law::BinghamLinear { eta: 0.2 }, 0.1, cubic);
        let p = g
            .on_line(
                &sys,
                Line {
                    v_free: 1.0,
                    w: 0.05,
                },
                &state(0.0),
            )
            .unwrap();
        assert!(
            (p.v - (p.f - 0.1) / 0.2).abs() < 1e-14 && (p.v - (1.0 - 0.05 * p.f)).abs() < 1e-14
        );
        // Cubic user law, both signs; force of velocity inverts velocity of force.
        let (sys, g) = graph(Law::BinghamMonotone, 1.0, cubic);
        for vf in [0.3, -0.3, 2.0, -50.0] {
            let p = g
                .on_line(
                    &sys,
                    Line {
                        v_free: vf,
                        w: 0.01,
                    },
                    &state(0.0),
                )
                .unwrap();
            assert_eq!(p.part, Part::Slip);
            assert!((cubic(p.f).0 - p.v).abs() < 1e-13 * (1.0 + p.v.abs()));
            assert!((vf - 0.01 * p.f - p.v).abs() < 1e-13 * (1.0 + p.v.abs()));
            let f = g.force_of_velocity(&sys, p.v, 0.0).unwrap().unwrap();
            assert!((f - p.f).abs() < 1e-12 * p.f.abs());
        }
        assert_eq!(g.force_of_velocity(&sys, 0.0, 0.3).unwrap(), None);
        assert_eq!(g.velocity_of_force(&sys, 0.7), Some(0.0));
    }

    #[test]
    fn non_monotone_law_folds_and_both_selections() {
        let (sys, g) = graph(
            Law::BinghamNonMonotone {
                selection: Selection::MaximalDissipation,
            },
            1.0,
            non_monotone,
        );
        // theory.md §3: maximum 1.17493 at 1.69072, minimum 0.57187 at 2.49909.
        let folds = g.folds();
        assert_eq!(folds.len(), 2);
        assert!(
            !folds[0].minimum
                && (folds[0].force - 1.69072).abs() < 1e-5
                && (folds[0].velocity - 1.17493).abs() < 1e-5
        );
        assert!(
            folds[1].minimum
                && (folds[1].force - 2.49909).abs() < 1e-5
                && (folds[1].velocity - 0.57187).abs() < 1e-5
        );
        let v_min = folds[1].velocity;
        // Approach 2: v = 0.8 has three forces; the outer one is taken.
        let f = g.force_of_velocity(&sys, -0.8, 0.0).unwrap().unwrap();
        assert!(f < -2.5 && (non_monotone(f).0 + 0.8).abs() < 1e-12);
        // A line passing just below the local minimum lands on the plateau, exactly.
        let w = 1e-3;
        let p = g
            .on_line(
                &sys,
                Line {
                    v_free: v_min + 2.0 * w,
                    w,
                },
                &state(0.0),
            )
            .unwrap();
        assert_eq!((p.part, p.v), (Part::Plateau, v_min));
        assert!((p.f - 2.0).abs() < 1e-9);
        // Approach 1: from the inner branch the force stays inner while it exists...
        let (sys, g1) = graph(
            Law::BinghamNonMonotone {
                selection: Selection::NoVelocityJumps,
            },
            1.0,
            non_monotone,
        );
        let p = g1
            .on_line(
                &sys,
                Line {
                    v_free: 0.8 + 1.3e-3,
                    w: 1e-3,
                },
                &state(1.25),
            )
            .unwrap();
        assert!(p.f > 1.0 && p.f < 1.69 && (non_monotone(p.f).0 - p.v).abs() < 1e-12);
        // ... from the outer branch the same line gives the outer force ...
        let q = g1
            .on_line(
                &sys,
                Line {
                    v_free: 0.8 + 1.3e-3,
                    w: 1e-3,
                },
                &state(2.8),
            )
            .unwrap();
        assert!(q.f > 2.5 && (non_monotone(q.f).0 - q.v).abs() < 1e-12);
        // ... and past the fold (v > 1.17493) the inner branch jumps to the outer one.
        let r = g1
            .on_line(
                &sys,
                Line {
                    v_free: 1.2,
                    w: 1e-3,
                },
                &state(1.6),
            )
            .unwrap();
        assert!(r.f > 2.5 && (non_monotone(r.f).0 - r.v).abs() < 1e-12);
        // Stick is the dead-zone branch.
        let s = g1
            .on_line(
                &sys,
                Line {
                    v_free: 5e-4,
                    w: 1e-3,
                },
                &state(0.0),
            )
            .unwrap();
        assert_eq!((s.part, s.v), (Part::Stick, 0.0));
    }

    #[test]
    fn stops_on_a_line() {
        use crate::nonsmooth::{Side, StopKind};
        let rigid = oscillator(
            1.0,
            0.0,
            [stop(
                "floor",
                0,
                Side::Lower,
                0.0,
                StopKind::Rigid { restitution: 0.5 },
            )],
            cubic,
        );
        let g = Graph::new(&rigid, 0).unwrap();
        // Arriving at −2 with the gap closed: bounces at +1, force pushes up (f < 0).
        let st = StepState {
            q: -0.001,
            v: -2.0,
            h: 0.01,
            theta_q: 1.0,
            force: 0.0,
            v_smooth: -2.0,
        };
        let p = g
            .on_line(
                &rigid,
                Line {
                    v_free: -2.01,
                    w: 0.01,
                },
                &st,
            )
            .unwrap();
        assert_eq!((p.v, p.part), (1.0, Part::Contact));
        assert!(p.f < 0.0);
        // Far from the stop: open.
        let st = StepState { q: 1.0, ..st };
        assert_eq!(
            g.on_line(
                &rigid,
                Line {
                    v_free: -2.01,
                    w: 0.01
                },
                &st
            )
            .unwrap()
            .part,
            Part::Open
        );
        // Spring-backed, upper: λ = k (q + h v − L)₊ with v = v_free − w λ.
        let spring = oscillator(
            1.0,
            0.0,
            [stop(
                "wall",
                0,
                Side::Upper,
                0.5,
                StopKind::SpringBacked { stiffness: 1e6 },
            )],
            cubic,
        );
        let g = Graph::new(&spring, 0).unwrap();
        // Arriving at the support at v = 1, for the step's position weight θ_q.
        let arrive = |theta_q: f64| {
            let st = StepState {
                q: 0.5,
                v: 1.0,
                h: 0.01,
                theta_q,
                force: 0.0,
                v_smooth: 1.0,
            };
            let line = Line {
                v_free: 1.0,
                w: 0.01,
            };
            g.on_line(&spring, line, &st).unwrap()
        };
        let p = arrive(1.0);
        assert!(
            (p.f - 1e6 * (0.5 + 0.01 * p.v - 0.5)).abs() < 1e-6
                && (p.v - (1.0 - 0.01 * p.f)).abs() < 1e-12
        );
        // θ_q = ½: the discrete gradient; pressed in over the whole step (q_n = 0.5 at
        // the support, q_{n+1} = q_n + h (v_n + v)/2 beyond it) it is the force at the
        // midpoint, k ((q_n + q_{n+1})/2 − L).
        let p = arrive(0.5);
        let q_next = 0.5 + 0.01 * 0.5 * (1.0 + p.v);
        assert!(
            q_next > 0.5
                && (p.f - 1e6 * (0.5 * (0.5 + q_next) - 0.5)).abs() < 1e-6
                && (p.v - (1.0 - 0.01 * p.f)).abs() < 1e-12
        );
        // Invalid parameters name the element.
        let bad = oscillator(
            1.0,
            0.0,
            [stop(
                "floor",
                0,
                Side::Lower,
                0.0,
                StopKind::Rigid { restitution: 1.5 },
            )],
            cubic,
        );
        match Graph::new(&bad, 0) {
            Err(LawError::InvalidElement(msg)) => {
                assert!(msg.contains("floor") && msg.contains("[0, 1]"))
            }
            other => panic!("{other:?}"),
        }
    }

    /// The discrete gradient's force balances the support's energy over the step,
    /// `λ (g_b − g_a) = −(V(g_b) − V(g_a))`, is ≥ 0, and is the only root: the residual
    /// changes sign there (random gaps on both sides of the support, stiffnesses 1…1e12).
    #[test]
    fn support_discrete_gradient_balances_energy() {
        use crate::nonsmooth::kind::stop::support_discrete_gradient;
        let mut seed = 0x2545_f491_4f6c_dd1du64;
        let mut uniform = move || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            (seed >> 11) as f64 / (1u64 << 53) as f64
        };
        for _ in 0..10_000 {
            let k = 10f64.powf(12.0 * uniform());
            let g_a = 2e-3 * (uniform() - 0.5);
            let g_free = 2e-3 * (uniform() - 0.5);
            let c = 10f64.powf(-8.0 + 6.0 * uniform());
            let lambda = support_discrete_gradient(k, g_a, g_free, c);
            let g_b = g_free + c * lambda;
            let v = |g: f64| 0.5 * k * (-g).max(0.0).powi(2);
            let scale = v(g_a).max(v(g_b)).max(v(g_free)) + 1e-300;
            assert!(lambda >= 0.0 && lambda.is_finite(), "λ = {lambda}");
            assert!(
                (lambda * (g_b - g_a) + v(g_b) - v(g_a)).abs() <= 1e-9 * scale,
                "k {k:e}, g_a {g_a:e}, g_free {g_free:e}, c {c:e}: λ {lambda:e}"
            );
            // The right side falls as λ grows: r(λ) = λ − DG(λ) < 0 below the root and
            // > 0 above it.
            let dg = |l: f64| {
                let g = g_free + c * l;
                if (g - g_a).abs() < 1e-300 {
                    k * (-g).max(0.0)
                } else {
                    -(v(g) - v(g_a)) / (g - g_a)
                }
            };
            let up = lambda * (1.0 + 1e-6) + 1e-300;
            assert!(up - dg(up) > 0.0, "above the root");
            if lambda > 0.0 {
                let down = lambda * (1.0 - 1e-6);
                assert!(down - dg(down) < 0.0, "below the root");
            }
        }
    }
}
