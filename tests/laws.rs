//! The folds and plateaus of non-monotone slip laws against an independent computation.
//!
//! The event-driven integrator and time-stepping both take a non-monotone law's folds
//! and its maximal-dissipation plateaus from `law::Graph` (a sign scan of `φ'` and
//! bisection), so an error there would agree with itself in the randomized agreement
//! suite. Here they are checked against laws whose folds are known in closed form and
//! against roots computed another way (eigenvalues of a companion matrix).

use filippov::nalgebra::{DMatrix, Matrix3, Vector3};
use filippov::runtime::nonsmooth::law::Graph;
use filippov::runtime::nonsmooth::{Element, ElementKind, Law, Selection};
use filippov::runtime::numeric::{JointKind, Link, Model, Scene};

/// A law with four folds at known forces: `φ'(f) = (f − A1)(f − B1)(f − A2)(f − B2)` for
/// `f > 1`, `φ(1) = 0`, odd. Maxima at `A1`, `A2`, minima at `B1`, `B2`; the second dip is
/// the deeper one, so maximal dissipation skips the middle piece.
const A1: f64 = 1.5;
const B1: f64 = 2.0;
const A2: f64 = 2.5;
const B2: f64 = 3.2;

/// Coefficients of `φ'(f) = Σ c_k f^k` (k = 0..4), from the roots.
fn dphi_coefficients() -> [f64; 5] {
    let mut c = [1.0, 0.0, 0.0, 0.0, 0.0]; // the polynomial 1, times (f − r) for each root
    let mut degree = 0;
    for r in [A1, B1, A2, B2] {
        degree += 1;
        for k in (0..=degree).rev() {
            let lower = if k > 0 { c[k - 1] } else { 0.0 };
            c[k] = lower - r * c[k];
        }
    }
    c
}

/// `φ(f) = ∫₁^f φ'`, coefficients `p_k` of `f^k` (k = 0..5).
fn phi_coefficients() -> [f64; 6] {
    let c = dphi_coefficients();
    let mut p = [0.0; 6];
    for k in 0..5 {
        p[k + 1] = c[k] / (k + 1) as f64;
    }
    p[0] = -p.iter().sum::<f64>(); // φ(1) = 0
    p
}

fn horner(p: &[f64], x: f64) -> f64 {
    p.iter().rev().fold(0.0, |acc, &c| acc * x + c)
}

fn four_folds(f: f64) -> (f64, f64) {
    let (p, c) = (phi_coefficients(), dphi_coefficients());
    let x = f.abs();
    (f.signum() * horner(&p, x), horner(&c, x))
}

/// Theory S4's law: `v = (1 + 0.1 (f² − 4)(f² − 9)) (f − 1)` for `f > 1`, odd.
fn s4(f: f64) -> (f64, f64) {
    let (p, c) = (s4_coefficients(), s4_derivative());
    let x = f.abs();
    (f.signum() * horner(&p, x), horner(&c, x))
}

/// S4's `φ` expanded: `0.1 f⁵ − 0.1 f⁴ − 1.3 f³ + 1.3 f² + 4.6 f − 4.6`.
fn s4_coefficients() -> [f64; 6] {
    [-4.6, 4.6, 1.3, -1.3, -0.1, 0.1]
}

fn s4_derivative() -> [f64; 5] {
    let p = s4_coefficients();
    std::array::from_fn(|k| p[k + 1] * (k + 1) as f64)
}

/// The real roots of `Σ p_k x^k` in `(lo, hi)`, increasing: eigenvalues of the companion
/// matrix (no bracketing, no bisection), each polished by two Newton steps on the
/// polynomial itself.
fn real_roots(p: &[f64], lo: f64, hi: f64) -> Vec<f64> {
    let d = p.len() - 1;
    let lead = p[d];
    let companion = DMatrix::<f64>::from_fn(d, d, |i, j| {
        if i == 0 {
            -p[d - 1 - j] / lead
        } else if i == j + 1 {
            1.0
        } else {
            0.0
        }
    });
    let dp: Vec<f64> = (1..=d).map(|k| p[k] * k as f64).collect();
    let mut roots: Vec<f64> = companion
        .complex_eigenvalues()
        .iter()
        .filter(|z| z.im.abs() < 1e-6)
        .map(|z| {
            let mut x = z.re;
            for _ in 0..2 {
                let slope = horner(&dp, x);
                if slope != 0.0 {
                    x -= horner(p, x) / slope;
                }
            }
            x
        })
        .filter(|x| (lo..hi).contains(x))
        .collect();
    roots.sort_by(f64::total_cmp);
    roots
}

fn graph(law: fn(f64) -> (f64, f64), selection: Selection) -> (Scene<1, 1>, Graph) {
    let model = Model {
        gravity: Vector3::zeros(),
        links: vec![Link {
            name: "block".into(),
            parent: None,
            joint: JointKind::Prismatic { axis: Vector3::x() },
            coordinate: Some(0),
            origin_xyz: Vector3::zeros(),
            origin_rpy: Vector3::zeros(),
            mass: 1.0,
            com: Vector3::zeros(),
            inertia: Matrix3::identity(),
        }],
        springs: vec![],
        dampers: vec![],
        point_springs: vec![],
    };
    let element = Element {
        name: "damper",
        coordinate: 0,
        kind: ElementKind::DashPot {
            law: Law::BinghamNonMonotone { selection },
            f_crit: 1.0,
        },
    };
    let mut scene = Scene::<1, 1>::new(model, [element]).expect("one coordinate");
    scene.laws[0] = Some(law);
    let g = Graph::new(&scene, 0).expect("a valid law");
    (scene, g)
}

fn close(a: f64, b: f64) -> bool {
    (a - b).abs() <= 1e-12 * a.abs().max(1.0)
}

#[test]
fn folds_are_the_closed_form_and_companion_roots() {
    // Closed form: the four roots the law was built from.
    let (_, g) = graph(four_folds, Selection::NoVelocityJumps);
    let forces: Vec<f64> = g.folds().iter().map(|f| f.force).collect();
    assert_eq!(forces.len(), 4, "{:?}", g.folds());
    for (found, exact) in forces.iter().zip([A1, B1, A2, B2]) {
        assert!(close(*found, exact), "fold at {found}, exact {exact}");
    }
    for (fold, minimum) in g.folds().iter().zip([false, true, false, true]) {
        assert_eq!(fold.minimum, minimum, "{fold:?}");
        assert!(close(fold.velocity, four_folds(fold.force).0), "{fold:?}");
    }
    // S4: the roots of φ' above f_crit, from the companion matrix.
    let (_, g) = graph(s4, Selection::NoVelocityJumps);
    let exact = real_roots(&s4_derivative(), 1.0, 16.0 * 2.0);
    let found: Vec<f64> = g.folds().iter().map(|f| f.force).collect();
    assert_eq!(found.len(), exact.len(), "{found:?} against {exact:?}");
    for (a, b) in found.iter().zip(&exact) {
        assert!(close(*a, *b), "fold at {a}, companion root {b}");
    }
}

#[test]
fn maximal_dissipation_plateaus_are_where_the_largest_force_jumps() {
    // Maximal dissipation takes, at each speed, the largest force with φ(f) = v. It
    // jumps where a deeper minimum's speed is reached: for the four-fold law at
    // v = φ(B2) (the deeper dip), from the smallest root of φ(f) = φ(B2) to B2 itself;
    // the middle piece (minimum φ(B1) > φ(B2)) is never selected.
    let p = phi_coefficients();
    let (v1, v2) = (horner(&p, B1), horner(&p, B2));
    assert!(
        0.0 < v2 && v2 < v1,
        "the law's set-up: φ(B2) = {v2}, φ(B1) = {v1}"
    );
    let (scene, g) = graph(four_folds, Selection::MaximalDissipation);
    let b = g.branches(&scene).expect("branches");
    assert_eq!(b.plateaus.len(), 1, "{b:?}");
    let mut shifted = p;
    shifted[0] -= v2;
    let roots = real_roots(&shifted, 1.0, 16.0);
    let plateau = b.plateaus[0];
    assert!(close(plateau.velocity, v2), "{plateau:?}, φ(B2) = {v2}");
    assert!(
        close(plateau.f_lo, roots[0]),
        "{plateau:?}, roots {roots:?}"
    );
    assert!(close(plateau.f_hi, B2), "{plateau:?}");
    assert_eq!(b.slip.len(), 2, "{b:?}");

    // S4: one dip; the plateau joins the first piece to the outer one at the minimum.
    let (scene, g) = graph(s4, Selection::MaximalDissipation);
    let b = g.branches(&scene).expect("branches");
    let folds = real_roots(&s4_derivative(), 1.0, 32.0);
    assert_eq!(folds.len(), 2, "{folds:?}");
    let v_min = horner(&s4_coefficients(), folds[1]);
    let mut shifted = s4_coefficients();
    shifted[0] -= v_min;
    let roots = real_roots(&shifted, 1.0, 32.0);
    assert_eq!(b.plateaus.len(), 1, "{b:?}");
    let plateau = b.plateaus[0];
    assert!(
        close(plateau.velocity, v_min),
        "{plateau:?}, φ(min) = {v_min}"
    );
    assert!(
        close(plateau.f_lo, roots[0]),
        "{plateau:?}, roots {roots:?}"
    );
    assert!(
        close(plateau.f_hi, folds[1]),
        "{plateau:?}, fold {}",
        folds[1]
    );
}
