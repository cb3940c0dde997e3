//! Event-driven integration against closed forms (theory.md §5) on hand-built lumped
//! systems: masses on linear springs, `M = diag(m)`, `τ_p = −K q`.

use std::f64::consts::PI;

use nalgebra::{SMatrix, SVector, Vector3};

use super::*;
use crate::nonsmooth::{Law, Side};
use crate::numeric::{JointKind, Link, Model};
use crate::system::Mechanism;
use crate::{ForwardJacobian, Output};

/// Point masses `m` on prismatic coordinates with a stiffness matrix `K`
/// (`τ_p = −K q`) and `E` non-smooth elements.
struct Lumped<const N: usize, const E: usize> {
    m: [f64; N],
    k: SMatrix<f64, N, N>,
    elements: [Element; E],
    /// Monotone user law `v = φ(f)` with its derivative (for `BinghamMonotone`).
    law: Option<fn(f64) -> (f64, f64)>,
}

impl<const N: usize, const E: usize> Mechanism<N> for Lumped<N, E> {
    const JOINTS: [&'static str; N] = ["x"; N];

    fn mass_matrix(&self, _q: &SVector<f64, N>) -> SMatrix<f64, N, N> {
        SMatrix::from_diagonal(&SVector::from(self.m))
    }
    fn forward_dynamics(
        &self,
        q: &SVector<f64, N>,
        _v: &SVector<f64, N>,
        tau: &SVector<f64, N>,
    ) -> SVector<f64, N> {
        (tau - self.k * q).component_div(&SVector::from(self.m))
    }
    fn forward_dynamics_jacobian(
        &self,
        q: &SVector<f64, N>,
        v: &SVector<f64, N>,
        tau: &SVector<f64, N>,
    ) -> ForwardJacobian<N> {
        let minv = SMatrix::from_diagonal(&SVector::from(self.m.map(|m| 1.0 / m)));
        ForwardJacobian {
            acceleration: self.forward_dynamics(q, v, tau),
            d_dq: -minv * self.k,
            d_dv: SMatrix::zeros(),
        }
    }
    fn model(&self) -> Model {
        // Independent prismatic joints along x from the world (the springs between
        // masses are not expressible as joint springs; the tests do not use the model).
        let links = (0..N)
            .map(|i| Link {
                name: format!("mass{i}"),
                parent: None,
                joint: JointKind::Prismatic { axis: Vector3::x() },
                coordinate: Some(i),
                origin_xyz: Vector3::zeros(),
                origin_rpy: Vector3::zeros(),
                mass: self.m[i],
                com: Vector3::zeros(),
                inertia: nalgebra::Matrix3::zeros(),
            })
            .collect();
        Model {
            gravity: Vector3::zeros(),
            links,
            springs: Vec::new(),
            dampers: Vec::new(),
            point_springs: Vec::new(),
        }
    }
}

impl<const N: usize, const E: usize> crate::kernels::Energy<N> for Lumped<N, E> {
    fn kinetic_energy(&self, _q: &SVector<f64, N>, v: &SVector<f64, N>) -> f64 {
        (0..N).map(|i| 0.5 * self.m[i] * v[i] * v[i]).sum()
    }
    fn potential_energy(&self, q: &SVector<f64, N>) -> f64 {
        0.5 * q.dot(&(self.k * q))
    }
}

impl<const N: usize, const E: usize> NonSmooth<N> for Lumped<N, E> {
    const ELEMENTS: usize = E;
    fn element(&self, e: usize) -> Element {
        self.elements[e]
    }
    fn law(&self, _e: usize, f: f64) -> (f64, f64) {
        self.law.map_or((0.0, 0.0), |law| law(f))
    }
    fn inverse_mass_matrix(&self, _q: &SVector<f64, N>) -> SMatrix<f64, N, N> {
        SMatrix::from_diagonal(&SVector::from(self.m.map(|m| 1.0 / m)))
    }
}

fn dashpot(law: Law, f_crit: f64) -> Element {
    Element {
        name: "d",
        coordinate: 0,
        kind: ElementKind::DashPot { law, f_crit },
    }
}

fn oscillator(m: f64, k: f64, element: Element) -> Lumped<1, 1> {
    Lumped {
        m: [m],
        k: SMatrix::from_element(k),
        elements: [element],
        law: None,
    }
}

fn no_input<const N: usize>(
    _t: f64,
    _q: &SVector<f64, N>,
    _v: &SVector<f64, N>,
) -> SVector<f64, N> {
    SVector::zeros()
}

fn tight() -> Options {
    Options::tolerances(1e-12, 1e-14)
}

fn problem1(tf: f64, x0: f64, v0: f64) -> NonSmoothProblem<1> {
    NonSmoothProblem::new(0.0, tf, SVector::from([x0]), SVector::from([v0]))
}

/// `(t, state before, state after)` of every event: the rows that share a time.
fn events(traj: &Solution) -> Vec<(f64, Vec<f64>, Vec<f64>)> {
    let t = traj.times();
    (1..t.len())
        .filter(|&i| t[i] == t[i - 1])
        .map(|i| (t[i], traj.state(i - 1).to_vec(), traj.state(i).to_vec()))
        .collect()
}

#[test]
fn s6_coulomb_free_decay_turning_points_and_exact_stop() {
    let sys = oscillator(1.0, 1.0, dashpot(Law::Coulomb, 0.1));
    let traj = event_driven(
        &sys,
        &no_input,
        &problem1(30.0, 1.0, 0.0),
        &Method::Dopri5(tight()),
    )
    .unwrap();
    let ev = events(&traj);
    // Initial slip is chosen at t0 (not an event); then velocity zeros at nπ.
    assert_eq!(ev.len(), 5, "{ev:?}");
    let expected = [-0.8, 0.6, -0.4, 0.2, 0.0];
    let mut worst: f64 = 0.0;
    for (n, (t, _, after)) in ev.iter().enumerate() {
        let dt = (t - (n + 1) as f64 * PI).abs();
        let dx = (after[0] - expected[n]).abs();
        worst = worst.max(dt).max(dx);
        assert!(
            dt <= 1e-9 && dx <= 1e-9,
            "turning point {n}: t {t}, x {}",
            after[0]
        );
        assert_eq!(after[1], 0.0);
    }
    eprintln!(
        "S6 worst turning-point error {worst:e}, stats {}",
        traj.stats
    );
    // Stuck for good after 5π: v exactly 0.0, x frozen, force within bounds.
    let t_stop = ev[4].0;
    let x_stop = ev[4].2[0];
    for i in 0..traj.len() {
        if traj.times()[i] >= t_stop && i > 0 && traj.times()[i - 1] == t_stop
            || traj.times()[i] > t_stop
        {
            let s = traj.state(i);
            assert_eq!(s[1], 0.0);
            assert_eq!(s[0], x_stop);
            assert!(s[2].abs() <= 0.1);
        }
    }
    assert_eq!(traj.last().unwrap().0, 30.0);
    assert_eq!(traj.stats.events, 5);
}

#[test]
fn s1_bingham_linear_free_decay_matches_piecewise_closed_form() {
    let (eta, fc) = (0.2, 0.1);
    let sys = oscillator(1.0, 1.0, dashpot(Law::BinghamLinear { eta }, fc));
    let traj = event_driven(
        &sys,
        &no_input,
        &problem1(30.0, 1.0, 0.0),
        &Method::Dopri5(tight()),
    )
    .unwrap();
    // Closed form: from rest at x_n, sliding in direction s = −sgn(x_n) about the
    // offset −s f_c/k, the next velocity zero is π/ω_d later at
    // x_{n+1} = −s f_c − (x_n + s f_c) e^{−ζ π/ω_d}.
    let zeta = eta / 2.0;
    let wd = (1.0 - zeta * zeta).sqrt();
    let r = (-zeta * PI / wd).exp();
    let mut zeros = Vec::new();
    let mut x: f64 = 1.0;
    let mut t = 0.0;
    while x.abs() > fc {
        let s = -x.signum();
        x = -s * fc - (x + s * fc) * r;
        t += PI / wd;
        zeros.push((t, x));
    }
    let ev = events(&traj);
    assert_eq!(ev.len(), zeros.len(), "{ev:?} vs {zeros:?}");
    let mut worst: f64 = 0.0;
    for ((t, _, after), (te, xe)) in ev.iter().zip(&zeros) {
        worst = worst.max((t - te).abs()).max((after[0] - xe).abs());
        assert!(
            (t - te).abs() <= 1e-9 && (after[0] - xe).abs() <= 1e-9,
            "{t} {} vs {te} {xe}",
            after[0]
        );
    }
    eprintln!("S1 {} velocity zeros, worst error {worst:e}", zeros.len());
    let last = traj.last().unwrap().1;
    assert_eq!(last[1], 0.0);
    assert_eq!(last[0], ev.last().unwrap().2[0]);
}

#[test]
fn s5_coulomb_forced_stick_slip_first_break_away_and_sign_consistency() {
    let fc = 0.5;
    let sys = oscillator(1.0, 1.0, dashpot(Law::Coulomb, fc));
    let force =
        |t: f64, _q: &SVector<f64, 1>, _v: &SVector<f64, 1>| SVector::from([1.2 * (0.5 * t).sin()]);
    let problem = problem1(30.0, 0.25, 0.0).with_forces(vec![Some(-fc / 2.0)]);
    let traj = event_driven(&sys, &force, &problem, &Method::Dopri5(tight())).unwrap();
    assert_eq!(traj.state(0)[2], -0.25);
    // Independent: first root of |F(t) − k x0| = f_crit by bisection.
    let g = |t: f64| (1.2 * (0.5 * t).sin() - 0.25).abs() - fc;
    let (mut a, mut b) = (0.0, 3.0);
    for _ in 0..200 {
        let m = 0.5 * (a + b);
        if g(m) < 0.0 { a = m } else { b = m }
    }
    let ev = events(&traj);
    assert!(ev.len() >= 4, "{} events", ev.len());
    let (t1, before, after) = &ev[0];
    eprintln!(
        "S5 first break-away {t1} vs {a} ({:e}); {} events",
        (t1 - a).abs(),
        ev.len()
    );
    assert!((t1 - a).abs() <= 1e-9);
    assert_eq!(before[1], 0.0);
    assert!(
        (after[2] - fc).abs() < 1e-15,
        "slips forward with f = +f_crit: {after:?}"
    );
    // Everywhere: stuck rows have |f| ≤ f_crit and v = 0 exactly; moving rows have
    // f = f_crit sgn v (except the pre-switch rows, a round-off past a velocity zero).
    for i in 0..traj.len() {
        let s = traj.state(i);
        if s[1] == 0.0 {
            assert!(s[2].abs() <= fc * (1.0 + 1e-12), "row {i}: {s:?}");
        } else if i + 1 == traj.len() || traj.times()[i + 1] != traj.times()[i] {
            assert_eq!(s[2], fc * s[1].signum(), "row {i}: {s:?}");
        }
    }
    assert!(traj.stats.mode_changes >= ev.len());
}

#[test]
fn bingham_mass_under_constant_force() {
    let (eta, fc) = (0.2, 0.1);
    let sys = oscillator(1.0, 0.0, dashpot(Law::BinghamLinear { eta }, fc));
    let push = |_t: f64, _q: &SVector<f64, 1>, _v: &SVector<f64, 1>| SVector::from([0.5]);
    let traj = event_driven(
        &sys,
        &push,
        &problem1(20.0, 0.0, 0.0),
        &Method::Dopri5(tight()),
    )
    .unwrap();
    let mut worst: f64 = 0.0;
    for (i, &t) in traj.times().iter().enumerate() {
        let exact = (0.5 - fc) / eta * (1.0 - (-eta * t).exp());
        worst = worst.max((traj.state(i)[1] - exact).abs());
    }
    eprintln!("Bingham F = 0.5: worst velocity error {worst:e}");
    assert!(worst <= 1e-9);
    // F ≤ f_crit: at rest exactly, held by f = F.
    let hold = |_t: f64, _q: &SVector<f64, 1>, _v: &SVector<f64, 1>| SVector::from([0.1]);
    let traj = event_driven(
        &sys,
        &hold,
        &problem1(20.0, 0.0, 0.0),
        &Method::Dopri5(tight()),
    )
    .unwrap();
    for i in 0..traj.len() {
        assert_eq!(traj.state(i), &[0.0, 0.0, 0.1][..]);
    }
    assert_eq!(traj.stats.events, 0);
}

/// Theory §5, bilinear oscillator period.
fn bilinear_period(k: f64, ks: f64, l: f64, v0: f64) -> f64 {
    let e = 0.5 * v0 * v0;
    let (w1, w2) = (k.sqrt(), (k + ks).sqrt());
    let a1 = (2.0 * e / k).sqrt();
    let xe = ks * l / (k + ks);
    let vl = w1 * (a1 * a1 - l * l).sqrt();
    let a2 = ((l - xe).powi(2) + (vl / w2).powi(2)).sqrt();
    2.0 * (PI - (l / a1).acos()) / w1 + 2.0 * ((l - xe) / a2).acos() / w2
}

#[test]
fn s7_spring_backed_stop_period() {
    let stop = Element {
        name: "support",
        coordinate: 0,
        kind: ElementKind::Stop {
            side: Side::Upper,
            position: 0.5,
            kind: StopKind::SpringBacked { stiffness: 1.0 },
        },
    };
    let sys = oscillator(1.0, 1.0, stop);
    let period = bilinear_period(1.0, 1.0, 0.5, 1.0);
    assert!((period - 5.8620872).abs() < 1e-7);
    let traj = event_driven(
        &sys,
        &no_input,
        &problem1(20.0, 0.0, 1.0),
        &Method::Dopri5(tight()),
    )
    .unwrap();
    let ev = events(&traj);
    // Entries into compression (mode change Free → Compressed: force still 0, v > 0).
    let entries: Vec<f64> = ev
        .iter()
        .filter(|(_, b, _)| b[1] > 0.0)
        .map(|e| e.0)
        .collect();
    assert!(entries.len() >= 3, "{ev:?}");
    let mut worst: f64 = 0.0;
    for w in entries.windows(2) {
        worst = worst.max((w[1] - w[0] - period).abs());
    }
    eprintln!("S7 period {period}, worst error {worst:e}");
    assert!(worst <= 1e-8);
    // Compressed rows carry λ = k_s (x − L) ≥ 0, free rows 0.
    for i in 0..traj.len() {
        let s = traj.state(i);
        assert!((s[2] - (s[0] - 0.5).max(0.0)).abs() < 1e-10, "{s:?}");
    }
}

#[test]
fn error_in_a_single_mode_follows_the_smooth_method_order() {
    // S1's first half-cycle (t < π/ω_d): one slip mode, a damped oscillation about 0.1.
    let (eta, fc) = (0.2, 0.1);
    let sys = oscillator(1.0, 1.0, dashpot(Law::BinghamLinear { eta }, fc));
    let zeta = eta / 2.0;
    let wd = (1.0 - zeta * zeta).sqrt();
    let t_end = 3.0;
    let exact = fc
        + (1.0 - fc)
            * (-zeta * t_end).exp()
            * ((wd * t_end).cos() + zeta / wd * (wd * t_end).sin());
    let methods: [(fn(Options) -> Method, f64); 2] = [(Method::Dopri5, 4.0), (Method::Sdirk4, 3.0)];
    for (method, min_order) in methods {
        let name = method(Options::default()).name();
        let mut runs = Vec::new();
        for tol in [1e-5, 1e-7, 1e-9] {
            let traj = event_driven(
                &sys,
                &no_input,
                &problem1(t_end, 1.0, 0.0),
                &method(Options::tolerances(tol, tol * 1e-2)),
            )
            .unwrap();
            let err = (traj.last().unwrap().1[0] - exact).abs();
            runs.push((tol, traj.stats.steps as f64, err));
        }
        let (_, n0, e0) = runs[0];
        let (_, n2, e2) = runs[2];
        let order = (e0 / e2).ln() / (n2 / n0).ln();
        eprintln!("{name}: (tol, steps, error) {runs:?}, observed order {order:.2}");
        assert!(e2 < e0 * 1e-2, "error must follow the tolerance: {runs:?}");
        assert!(order >= min_order, "{name} order {order}");
    }
}

#[test]
fn two_masses_stick_at_once_by_mode_selection() {
    // Two unit masses on wall springs k = 1, coupled by k_c = 0.5, each with Coulomb
    // friction f_crit = 0.8, both launched at v = 1: the coupling spring stays
    // unstretched, each mass follows ẍ + x = −0.8 until v = 0 at t* = atan(1.25), where
    // x* = −0.8 + 0.8 cos t* + sin t*, |x*| < 0.8: both stick together, each held by
    // f = −x*.
    let kc = 0.5;
    let k = SMatrix::<f64, 2, 2>::new(1.0 + kc, -kc, -kc, 1.0 + kc);
    let fc = 0.8;
    let el = |name, coordinate| Element {
        name,
        coordinate,
        kind: ElementKind::DashPot {
            law: Law::Coulomb,
            f_crit: fc,
        },
    };
    let sys = Lumped {
        m: [1.0, 1.0],
        k,
        elements: [el("a", 0), el("b", 1)],
        law: None,
    };
    let problem = NonSmoothProblem::new(
        0.0,
        5.0,
        SVector::from([0.0, 0.0]),
        SVector::from([1.0, 1.0]),
    );
    let traj = event_driven(&sys, &no_input, &problem, &Method::Dopri5(tight())).unwrap();
    let ev = events(&traj);
    assert_eq!(ev.len(), 1, "{ev:?}");
    assert_eq!(traj.stats.mode_changes, 2);
    let ts = 1.25f64.atan();
    let xs = -fc + fc * ts.cos() + ts.sin();
    let (t, _, after) = &ev[0];
    eprintln!(
        "two masses: stick at {t} (exact {ts}), x {} (exact {xs}), forces {:?}",
        after[0],
        &after[4..]
    );
    assert!((t - ts).abs() < 1e-9 && (after[0] - xs).abs() < 1e-9);
    for i in traj.len() - 3..traj.len() {
        let s = traj.state(i);
        assert_eq!(&s[2..4], &[0.0, 0.0]);
        assert!(s[4].abs() <= fc && s[5].abs() <= fc);
        assert!((s[4] + xs).abs() < 1e-9 && (s[5] + xs).abs() < 1e-9);
    }
}

fn floor(restitution: f64) -> Element {
    Element {
        name: "floor",
        coordinate: 0,
        kind: ElementKind::Stop {
            side: Side::Lower,
            position: 0.0,
            kind: StopKind::Rigid { restitution },
        },
    }
}

/// Unit mass under a constant force −1 toward a lower rigid stop at 0: impacts at
/// t1 = √2, then flight times shrinking by e: accumulation at √2 (1 + 2e/(1 − e)). The
/// rebounds settle by themselves, without a hand-over, and the switch log gives the
/// accumulation time in closed form from the last visible rebound.
#[test]
fn bouncing_on_a_rigid_stop_settles_at_its_computed_accumulation_time() {
    let down = |_t: f64, _q: &SVector<f64, 1>, _v: &SVector<f64, 1>| SVector::from([-1.0]);
    for e in [0.5, 0.9, 0.99] {
        let t_acc = 2f64.sqrt() * (1.0 + 2.0 * e / (1.0 - e));
        let sys = oscillator(1.0, 0.0, floor(e));
        let tf = 1.5 * t_acc;
        let traj = event_driven(
            &sys,
            &down,
            &problem1(tf, 1.0, 0.0),
            &Method::Dopri5(tight()),
        )
        .unwrap();
        eprintln!("e = {e}: {}", traj.stats);
        assert_eq!(traj.stats.zeno_handovers, 0, "e = {e}");
        assert_eq!(traj.stats.mode_changes, 1, "free → contact once");
        let settled: Vec<&Switch> = traj
            .switches
            .iter()
            .filter(|s| s.kind == SwitchKind::Settled)
            .collect();
        assert_eq!(settled.len(), 1, "e = {e}");
        let located = settled[0].accumulation.expect("e < 1 accumulates");
        eprintln!(
            "e = {e}: settled at {}, accumulation located at {located} (closed form {t_acc}, error {:.1e})",
            settled[0].t,
            (located - t_acc).abs()
        );
        assert!(
            settled[0].t < t_acc && (located - t_acc).abs() < 1e-9 * t_acc,
            "e = {e}"
        );
        let ev = events(&traj);
        assert!((ev[0].0 - 2f64.sqrt()).abs() < 1e-9);
        let (t, last) = traj.last().unwrap();
        assert_eq!(t, tf);
        assert_eq!(
            last,
            &[0.0, 0.0, -1.0][..],
            "rests on the stop, pushed up by λ = 1"
        );
    }
}

/// The same ball with Coulomb friction on its coordinate: every rebound also switches
/// the friction's direction and every apex sticks it for an instant, so the events are
/// not rebounds alone; the rebounds still settle once they would stay within the
/// position tolerance, with no hand-over, and the ball ends at rest on the stop.
#[test]
fn rebounds_that_switch_friction_too_settle_without_a_hand_over() {
    let sys = Lumped {
        m: [1.0],
        k: SMatrix::zeros(),
        elements: [floor(0.5), dashpot(Law::Coulomb, 0.2)],
        law: None,
    };
    let down = |_t: f64, _q: &SVector<f64, 1>, _v: &SVector<f64, 1>| SVector::from([-1.0]);
    let traj = event_driven(
        &sys,
        &down,
        &problem1(8.0, 1.0, 0.0),
        &Method::Dopri5(tight()),
    )
    .unwrap();
    eprintln!("rebounds with friction: {}", traj.stats);
    assert_eq!(traj.stats.zeno_handovers, 0);
    assert!(
        traj.switches
            .iter()
            .any(|s| s.kind == SwitchKind::Settled && s.accumulation.is_some())
    );
    assert!(
        traj.stats.mode_changes > 10,
        "the friction switches at every rebound"
    );
    let (t, last) = traj.last().unwrap();
    assert_eq!(t, 8.0);
    assert_eq!(&last[..2], &[0.0, 0.0][..], "rests on the stop");
}

#[test]
fn bad_input_gives_typed_errors() {
    let run = |sys: &Lumped<1, 1>, problem: &NonSmoothProblem<1>| {
        event_driven(sys, &no_input, problem, &Method::Dopri5(Options::default()))
            .unwrap_err()
            .kind
    };
    let p = problem1(1.0, 1.0, 0.0);
    assert!(
        matches!(run(&oscillator(1.0, 1.0, dashpot(Law::Coulomb, -0.1)), &p), ErrorKind::InvalidInput(m) if m.contains("f_crit"))
    );
    let rigid = |e: f64| Element {
        name: "stop",
        coordinate: 0,
        kind: ElementKind::Stop {
            side: Side::Upper,
            position: 0.5,
            kind: StopKind::Rigid { restitution: e },
        },
    };
    assert!(
        matches!(run(&oscillator(1.0, 1.0, rigid(1.5)), &p), ErrorKind::InvalidInput(m) if m.contains("restitution"))
    );
    // x0 = 1 is past an upper stop at 0.5.
    assert!(
        matches!(run(&oscillator(1.0, 1.0, rigid(0.0)), &p), ErrorKind::InconsistentInitialData(m) if m.contains("inside the rigid stop"))
    );
    // A given stuck force beyond f_crit.
    let p = problem1(1.0, 0.0, 0.0).with_forces(vec![Some(0.3)]);
    assert!(matches!(
        run(&oscillator(1.0, 1.0, dashpot(Law::Coulomb, 0.1)), &p),
        ErrorKind::InconsistentInitialData(_)
    ));
    // forces0 of the wrong length.
    let p = problem1(1.0, 0.0, 0.0).with_forces(vec![None, None]);
    assert!(matches!(
        run(&oscillator(1.0, 1.0, dashpot(Law::Coulomb, 0.1)), &p),
        ErrorKind::InvalidInput(_)
    ));
    // A non-monotone law that decreases beyond its last fold.
    let nm = dashpot(
        Law::BinghamNonMonotone {
            selection: crate::nonsmooth::Selection::MaximalDissipation,
        },
        1.0,
    );
    let mut sys = oscillator(1.0, 1.0, nm);
    sys.law = Some(|f| {
        let x = f.abs() - 1.0;
        (f.signum() * x * (2.0 - x), 1.0 - x)
    });
    assert!(
        matches!(run(&sys, &problem1(1.0, 0.0, 0.0)), ErrorKind::InvalidInput(m) if m.contains("last fold"))
    );
}

#[test]
fn monotone_user_law_is_inverted_exactly_and_rigid_contact_is_released() {
    // Cubic Bingham (4.7b) with γ = 1: v = f² (f − f_c sgn f).
    let cubic: fn(f64) -> (f64, f64) = |f| {
        let fc = 1.0;
        (
            f * f * (f - fc * f.signum()),
            3.0 * f * f - 2.0 * fc * f.abs(),
        )
    };
    let mut sys = oscillator(1.0, 0.0, dashpot(Law::BinghamMonotone, 1.0));
    sys.law = Some(cubic);
    let push = |_t: f64, _q: &SVector<f64, 1>, _v: &SVector<f64, 1>| SVector::from([3.0]);
    let traj = event_driven(
        &sys,
        &push,
        &problem1(500.0, 0.0, 0.0),
        &Method::Dopri5(tight()),
    )
    .unwrap();
    // Terminal velocity: f = 3 ⇒ v = 9 · 2 = 18 (approached with time constant
    // dφ/df(3) = 21); the stored force inverts the law.
    let last = traj.last().unwrap().1;
    assert!((last[1] - 18.0).abs() < 1e-6, "{last:?}");
    for i in 1..traj.len() {
        let s = traj.state(i);
        assert!(
            (cubic(s[2]).0 - s[1]).abs() <= 1e-12 * s[1].abs().max(1.0),
            "{s:?}"
        );
    }
    // A mass resting on a lower rigid stop, pulled up by a growing force: contact is
    // released when λ = 1 − t crosses zero.
    let stop = Element {
        name: "floor",
        coordinate: 0,
        kind: ElementKind::Stop {
            side: Side::Lower,
            position: 0.0,
            kind: StopKind::Rigid { restitution: 0.0 },
        },
    };
    let sys = oscillator(1.0, 0.0, stop);
    let pull = |t: f64, _q: &SVector<f64, 1>, _v: &SVector<f64, 1>| SVector::from([t - 1.0]);
    let traj = event_driven(
        &sys,
        &pull,
        &problem1(3.0, 0.0, 0.0),
        &Method::Sdirk4(tight()),
    )
    .unwrap();
    let ev = events(&traj);
    assert_eq!(ev.len(), 1);
    assert!((ev[0].0 - 1.0).abs() < 1e-10);
    // After release: x = (t − 1)³/6.
    let x_end = traj.last().unwrap().1[0];
    assert!((x_end - 8.0 / 6.0).abs() < 1e-6, "{x_end}");
}

/// The non-monotone law 4.9b (f_crit = 1): v = (1 + 0.1 (f² − 4)(f² − 9)) (f − sgn f).
fn law_4_9b(f: f64) -> (f64, f64) {
    let a = 1.0 + 0.1 * (f * f - 4.0) * (f * f - 9.0);
    let da = 0.1 * (2.0 * f * (f * f - 9.0) + 2.0 * f * (f * f - 4.0));
    (a * (f - f.signum()), da * (f - f.signum()) + a)
}

/// S4 (theory.md §4): m = k = 1, f_crit = 1, F = 3 sin(0.5 t), x0 = v0 = 0, t ∈ [0, 40].
fn s4_system(selection: crate::nonsmooth::Selection) -> Lumped<1, 1> {
    let mut sys = oscillator(
        1.0,
        1.0,
        dashpot(Law::BinghamNonMonotone { selection }, 1.0),
    );
    sys.law = Some(law_4_9b);
    sys
}

fn s4_input(t: f64, _q: &SVector<f64, 1>, _v: &SVector<f64, 1>) -> SVector<f64, 1> {
    SVector::from([3.0 * (0.5 * t).sin()])
}

fn s4_event_driven(selection: crate::nonsmooth::Selection) -> Solution {
    event_driven(
        &s4_system(selection),
        &s4_input,
        &problem1(40.0, 0.0, 0.0),
        &Method::Dopri5(Options::tolerances(1e-10, 1e-12)),
    )
    .unwrap()
}

/// Largest difference of x between a time-stepping run and the event-driven one at the
/// time-stepping's grid points.
fn s4_distance(ed: &Solution, ts: &Solution) -> f64 {
    (0..ts.len())
        .map(|i| {
            let t = ts.times()[i];
            (ts.state(i)[0] - ed.at(t).unwrap()[0]).abs()
        })
        .fold(0.0, f64::max)
}

/// S4 with both selection rules: event-driven at tight tolerance against time-stepping
/// (θ = 1/2) at h = 2e-3 and 1e-3. The time-stepping error is at least O(h), so the
/// largest distance of x over the grid must fall at least by half with h (both converge
/// to one solution; measured 3.3×: between switches θ = ½ is the midpoint rule); the
/// two rules end on opposite sides (theory.md §3); no chattering and no Zeno hand-over.
#[test]
fn s4_non_monotone_event_driven_agrees_with_time_stepping() {
    use crate::nonsmooth::Selection;
    let mut ends = Vec::new();
    for sel in [Selection::NoVelocityJumps, Selection::MaximalDissipation] {
        let ed = s4_event_driven(sel);
        let x_end = ed.last().unwrap().1[0];
        let dist: Vec<f64> = [2e-3, 1e-3]
            .iter()
            .map(|&h| {
                let ts = crate::nonsmooth::time_stepping(
                    &s4_system(sel),
                    &s4_input,
                    &problem1(40.0, 0.0, 0.0),
                    h,
                    0.5,
                )
                .unwrap();
                eprintln!(
                    "S4 {sel:?}: time-stepping h = {h}: x(40) = {}",
                    ts.last().unwrap().1[0]
                );
                s4_distance(&ed, &ts)
            })
            .collect();
        eprintln!(
            "S4 {sel:?}: event-driven x(40) = {x_end}, {} events, max |Δx| vs time-stepping \
             {dist:?} (ratio {}), stats {:?}",
            ed.stats.events,
            dist[0] / dist[1],
            ed.stats
        );
        let ratio = dist[0] / dist[1];
        assert!((1.6..8.0).contains(&ratio), "{dist:?}");
        assert!(dist[1] < 2e-3, "{dist:?}");
        assert_eq!(ed.stats.zeno_detected, 0);
        assert_eq!(ed.stats.zeno_handovers, 0);
        assert!(
            ed.stats.events > 10 && ed.stats.events < 60,
            "{:?}",
            ed.stats
        );
        // Off the plateaus every slipping row lies on the law.
        let sys = s4_system(sel);
        let branches = crate::nonsmooth::law::Graph::new(&sys, 0)
            .unwrap()
            .branches(&sys)
            .unwrap();
        let plateau = branches.plateaus.first().map_or(f64::NAN, |p| p.velocity);
        for i in 0..ed.len() {
            let s = ed.state(i);
            if s[1] != 0.0 && s[1].abs() != plateau {
                assert!((law_4_9b(s[2]).0 - s[1]).abs() < 1e-9, "{s:?}");
            }
        }
        ends.push(x_end);
    }
    assert!(ends[0] * ends[1] < 0.0, "x(40) differ in sign: {ends:?}");
}

/// S4, approach 1: the force jumps at the folds (v = v_max: inner → outer branch,
/// v = v_min: outer → inner) with the velocity continuous, bit for bit.
#[test]
fn s4_approach_1_hysteresis_at_the_folds() {
    use crate::nonsmooth::Selection;
    let ed = s4_event_driven(Selection::NoVelocityJumps);
    let sys = s4_system(Selection::NoVelocityJumps);
    let graph = crate::nonsmooth::law::Graph::new(&sys, 0).unwrap();
    let (max, min) = (graph.folds()[0], graph.folds()[1]);
    let (mut up, mut down) = (0usize, 0usize);
    for (t, a, b) in events(&ed) {
        assert_eq!(a[..2], b[..2], "state continuous at t = {t}");
        if a[1].abs() == max.velocity {
            up += 1;
            assert!((a[2].abs() - max.force).abs() < 1e-9 && b[2].abs() > min.force);
            assert!((law_4_9b(b[2]).0 - b[1]).abs() < 1e-12);
        }
        if a[1].abs() == min.velocity {
            down += 1;
            assert!((a[2].abs() - min.force).abs() < 1e-9 && b[2].abs() < max.force);
            assert!((law_4_9b(b[2]).0 - b[1]).abs() < 1e-12);
        }
    }
    eprintln!("S4 approach 1: {up} jumps up, {down} down");
    assert!(up >= 4 && down >= 4 && up.abs_diff(down) <= 1);
}

/// S4, approach 2: the plateau rows move at |v| = v_min exactly with the force between
/// the two branch forces there; the plateau is entered and left without chattering.
#[test]
fn s4_approach_2_plateau_is_exact() {
    use crate::nonsmooth::Selection;
    let ed = s4_event_driven(Selection::MaximalDissipation);
    let sys = s4_system(Selection::MaximalDissipation);
    let p = crate::nonsmooth::law::Graph::new(&sys, 0)
        .unwrap()
        .branches(&sys)
        .unwrap()
        .plateaus[0];
    assert!((p.velocity - 0.571_87).abs() < 1e-5 && (p.f_hi - 2.499_09).abs() < 1e-5);
    let mut rows = 0;
    for i in 0..ed.len() {
        let s = ed.state(i);
        if s[1].abs() == p.velocity {
            rows += 1;
            let f = s[2].abs();
            assert!(f >= p.f_lo - 1e-9 && f <= p.f_hi + 1e-9, "{s:?}");
            assert_eq!(s[2].signum(), s[1].signum());
        }
    }
    // Plateau rows between the events, and the plateau positions move at v_min.
    let on_plateau = (1..ed.len())
        .filter(|&i| {
            let (a, b) = (ed.state(i - 1), ed.state(i));
            a[1] == b[1] && b[1].abs() == p.velocity && ed.times()[i] > ed.times()[i - 1]
        })
        .map(|i| {
            let (a, b) = (ed.state(i - 1), ed.state(i));
            let dt = ed.times()[i] - ed.times()[i - 1];
            ((b[0] - a[0]) - b[1] * dt).abs()
        })
        .collect::<Vec<_>>();
    eprintln!(
        "S4 approach 2: {rows} rows at |v| = v_min exactly, {} plateau steps, {} events",
        on_plateau.len(),
        ed.stats.events
    );
    assert!(on_plateau.len() > 10);
    assert!(on_plateau.iter().all(|e| *e < 1e-12));
}

/// Consistent initialisation of a moving non-monotone element: at v0 = 0.8 three forces
/// fit; approach 1 starts on the inner branch (as time-stepping seeds it), approach 2 on
/// the outer one; both then run unforced to rest without errors or hand-overs.
#[test]
fn non_monotone_moving_start_picks_the_rule_s_branch() {
    use crate::nonsmooth::Selection;
    for (sel, inner) in [
        (Selection::NoVelocityJumps, true),
        (Selection::MaximalDissipation, false),
    ] {
        let traj = event_driven(
            &s4_system(sel),
            &no_input,
            &problem1(20.0, 0.0, 0.8),
            // At rtol 1e-12: approach 1 used to underflow the step size as v → 0 here,
            // against the kink of a slip force clamped below the branch (now continued
            // by the law's tangent, `mode::below_branch`).
            &Method::Dopri5(Options::tolerances(1e-12, 1e-14)),
        )
        .unwrap();
        let f0 = traj.state(0)[2];
        assert!((law_4_9b(f0).0 - 0.8).abs() < 1e-12, "{f0}");
        assert_eq!(f0 < 1.69, inner, "{sel:?}: {f0}");
        assert_eq!(traj.stats.zeno_handovers, 0);
        assert_eq!(traj.last().unwrap().1[1], 0.0, "{sel:?} ends at rest");
    }
}

/// The slip force past a branch end: smooth across approach 2's cut at the plateau speed
/// (the law's own piece continues: value, slope and curvature match on both sides), and
/// the ends classified — folds where `φ' = 0`, neither the rest speed nor the cut.
#[test]
fn slip_force_continues_smoothly_past_a_cut_end_and_folds_are_told_apart() {
    use crate::nonsmooth::Selection;
    use crate::nonsmooth::kind::{Context, bingham::Bingham};
    use crate::nonsmooth::mode::fold_end;
    for selection in [Selection::NoVelocityJumps, Selection::MaximalDissipation] {
        let sys = s4_system(selection);
        let law = Law::BinghamNonMonotone { selection };
        let branches = crate::nonsmooth::law::Graph::new(&sys, 0)
            .unwrap()
            .branches(&sys)
            .unwrap();
        let b0 = branches.slip[0];
        let b1 = branches.slip[1];
        // Both rules: the rest end of the first branch is no fold, the bottom of the
        // second is the law's local minimum.
        assert!(!fold_end(&branches, 0, 1e-3));
        assert!(fold_end(&branches, 1, b1.v_lo + 1e-3));
        assert!((law_4_9b(b1.f_lo).0 - b1.v_lo).abs() < 1e-12 && law_4_9b(b1.f_lo).1.abs() < 1e-6);
        let cut = selection == Selection::MaximalDissipation;
        // The first branch's top: the fold (approach 1) or the cut at v_min (approach 2).
        assert_eq!(fold_end(&branches, 0, b0.v_hi - 1e-3), !cut);
        assert_eq!(b0.v_hi < b0.v_top, cut);
        let bingham = Bingham { law, f_crit: 1.0 };
        let cx = Context {
            system: &sys,
            index: 0,
            branches: &branches,
            folds: &[],
        };
        let f = |w: f64| bingham.slip_force(&cx, 0, w, 1.0);
        if cut {
            // Finite differences of the force on either side of v_hi: one smooth function.
            let h = 1e-4;
            let (e, f_hi) = (b0.v_hi, b0.f_hi);
            assert!((f(e) - f_hi).abs() < 1e-12);
            let below = [f(e - 2.0 * h), f(e - h), f(e)];
            let above = [f(e), f(e + h), f(e + 2.0 * h)];
            let slope = |p: [f64; 3]| (p[2] - p[0]) / (2.0 * h);
            let curvature = |p: [f64; 3]| (p[2] - 2.0 * p[1] + p[0]) / (h * h);
            let exact_slope = 1.0 / law_4_9b(f_hi).1;
            assert!((slope(below) - exact_slope).abs() < 1e-3 * exact_slope);
            assert!((slope(above) - exact_slope).abs() < 1e-3 * exact_slope);
            assert!(
                (curvature(below) - curvature(above)).abs() < 1e-2 * curvature(above).abs(),
                "{} {}",
                curvature(below),
                curvature(above)
            );
            // Past the piece's own fold the force is clamped there.
            assert_eq!(f(b0.v_top + 0.1), b0.f_top);
        } else {
            assert_eq!(f(b0.v_hi + 0.1), b0.f_hi);
        }
    }
}

/// The switch log's rules (the doc of [`SwitchKind::Settled`]): one entry per element
/// per instant, carrying the states around it; an impact at t0 is logged with the state
/// before it, and the first row is that state.
#[test]
fn switch_log_has_one_entry_per_element_and_instant_with_its_states() {
    let down = |_t: f64, _q: &SVector<f64, 1>, _v: &SVector<f64, 1>| SVector::from([-1.0]);
    // Starting on the floor and moving into it at 2 m/s: an impact at t0 (v⁺ = −e v⁻),
    // then rebounds under the constant force −1 until they settle.
    for e in [0.0, 0.5] {
        let sys = oscillator(1.0, 0.0, floor(e));
        let traj = event_driven(
            &sys,
            &down,
            &problem1(10.0, 0.0, -2.0),
            &Method::Dopri5(tight()),
        )
        .unwrap();
        let first = &traj.switches[0];
        assert_eq!(first.t, 0.0, "e = {e}: the t0 impact is logged");
        assert_eq!(first.index, Some(0));
        assert_eq!(first.element.as_deref(), Some("floor"));
        assert_eq!(first.before, vec![0.0, -2.0], "e = {e}: the state before");
        assert!(
            (first.after[1] - 2.0 * e).abs() < 1e-12,
            "e = {e}: v⁺ = −e v⁻"
        );
        assert!(
            (first.jump - (-2.0 - 2.0 * e)).abs() < 1e-12,
            "e = {e}: impulse P with v⁺ = v⁻ − P/m: {}",
            first.jump
        );
        // The plastic hit leaves the stop in contact (pressed on by the force): Settled;
        // the elastic one rebounds: Impact.
        let expected = if e == 0.0 {
            SwitchKind::Settled
        } else {
            SwitchKind::Impact
        };
        assert_eq!(first.kind, expected, "e = {e}");
        assert_eq!(traj.times()[0], 0.0);
        assert_eq!(
            traj.state(0)[..2],
            [0.0, -2.0],
            "row 0 is the pre-impact state"
        );
        assert_eq!(traj.times()[1], 0.0);
        assert!(
            (traj.state(1)[1] - 2.0 * e).abs() < 1e-12,
            "row 1 is after it"
        );
        // No element has two entries at one instant.
        for (i, a) in traj.switches.iter().enumerate() {
            for b in &traj.switches[i + 1..] {
                assert!(
                    !(a.t == b.t && a.index == b.index && a.index.is_some()),
                    "e = {e}: two entries for {:?} at t = {}: {:?} and {:?}",
                    a.element,
                    a.t,
                    a.kind,
                    b.kind
                );
            }
        }
        for s in &traj.switches {
            assert_eq!((s.before.len(), s.after.len()), (2, 2));
            if s.kind == SwitchKind::Mode {
                assert_eq!(s.before, s.after, "a mode switch keeps the state");
            }
        }
        if e == 0.0 {
            assert_eq!(
                traj.switches.len(),
                1,
                "settled at once: {:?}",
                traj.switches
            );
        }
    }
}

/// `Output::Times(ts)` keeps exactly `ts` on a run with events, and each value is the
/// run's dense output there.
#[test]
fn output_times_are_exactly_the_times_asked_for() {
    let sys = oscillator(1.0, 1.0, dashpot(Law::Coulomb, 0.1));
    let steps = event_driven(
        &sys,
        &no_input,
        &problem1(10.0, 1.0, 0.0),
        &Method::Dopri5(tight()),
    )
    .unwrap();
    assert!(steps.stats.events >= 3, "the run has events");
    let ts: Vec<f64> = (0..=37).map(|i| 10.0 * i as f64 / 37.0).collect();
    let asked = problem1(10.0, 1.0, 0.0).with_output(Output::Times(ts.clone()));
    let grid = event_driven(&sys, &no_input, &asked, &Method::Dopri5(tight())).unwrap();
    assert_eq!(grid.times(), &ts[..]);
    assert_eq!(grid.switches.len(), steps.switches.len());
    for (i, &t) in ts.iter().enumerate() {
        let y = steps.at(t).unwrap();
        assert!(
            (grid.state(i)[0] - y[0]).abs() < 1e-10,
            "t = {t}: {} against {}",
            grid.state(i)[0],
            y[0]
        );
    }
}
