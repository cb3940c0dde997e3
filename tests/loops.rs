//! Loop joints (`#[loop_joint]`): the generated constraint residual `Φ`, Jacobian
//! `G = ∂Φ/∂q` and acceleration term `γ = −Ġ v`, against the closed form of a planar
//! four-bar, against `Φ` composed here from the numeric model's link poses (a reference
//! that does not use the generator) for every loop joint kind on an oblique spatial tree,
//! and `G`, `γ` against central differences, at random states.

mod common;

use filippov::nalgebra::{DMatrix, DVector, Isometry3, Translation3, UnitQuaternion, Vector3};
use filippov::prelude::*;
use filippov::runtime::loops::LoopConstraints;
use filippov::runtime::numeric;

/// A four-bar linkage in the plane: crank `a` from the origin, coupler `b`, rocker `c`
/// from `(d, 0)`, the coupler's end pinned to the rocker's by a loop joint; gravity, a
/// spring on the crank and a damper on the rocker.
#[derive(Mechanism)]
#[mechanism(gravity = [0.0, -9.81, 0.0])]
#[spring(crank_pivot, k = 2.0, rest = 0.1)]
#[damper(rocker_pivot, c = 0.3)]
#[body(crank, mass = 1.0, com = [a / 2.0, 0.0, 0.0], inertia = rod(1.0, a))]
#[joint(crank_pivot: revolute(z), parent = world, child = crank)]
#[body(coupler, mass = 1.0, com = [b / 2.0, 0.0, 0.0], inertia = rod(1.0, b))]
#[joint(crank_pin: revolute(z), parent = crank, child = coupler, origin = [a, 0.0, 0.0])]
#[body(rocker, mass = 1.0, com = [c / 2.0, 0.0, 0.0], inertia = rod(1.0, c))]
#[joint(rocker_pivot: revolute(z), parent = world, child = rocker, origin = [d, 0.0, 0.0])]
#[loop_joint(rocker_pin: revolute(z), parent = coupler, child = rocker, origin = [b, 0.0, 0.0], child_origin = [c, 0.0, 0.0])]
struct FourBar {
    a: f64,
    b: f64,
    c: f64,
    d: f64,
}

/// An oblique spatial tree (nothing axis-aligned to fold) closed by one loop joint of
/// each kind, so that every row of every kind is present.
#[derive(Mechanism)]
#[body(b1, mass = 1.0, com = [0.1, 0.2, 0.0], inertia = sphere(1.0, 0.1))]
#[joint(j1: revolute([0.3, 0.5, 0.8]), parent = world, child = b1, origin = [0.1, -0.2, 0.3], rpy = [0.2, 0.1, -0.3])]
#[body(b2, mass = 1.0, com = [0.2, 0.0, 0.1], inertia = sphere(1.0, 0.1))]
#[joint(j2: revolute(x), parent = b1, child = b2, origin = [0.4, 0.1, -0.2], rpy = [0.1, 0.2, 0.3])]
#[body(b3, mass = 1.0, com = [0.0, 0.1, 0.1], inertia = sphere(1.0, 0.1))]
#[joint(j3: prismatic([0.0, 0.6, 0.8]), parent = world, child = b3, origin = [1.0, 0.2, 0.0], rpy = [0.0, 0.4, 0.0])]
#[body(b4, mass = 1.0, com = [0.1, 0.1, 0.1], inertia = sphere(1.0, 0.1))]
#[joint(j4: revolute([1.0, 1.0, 0.0]), parent = b3, child = b4, origin = [0.0, 0.3, 0.2], rpy = [-0.2, 0.3, 0.5])]
#[loop_joint(ball: spherical, parent = b2, child = b4, origin = [0.3, 0.1, 0.0], child_origin = [0.0, 0.2, 0.1])]
#[loop_joint(hinge: revolute([0.0, 0.6, 0.8]), parent = b1, child = b4, origin = [0.2, 0.0, 0.1], rpy = [0.1, 0.0, 0.2], child_origin = [0.1, 0.0, 0.3], child_rpy = [0.3, 0.2, 0.1])]
#[loop_joint(slide: prismatic(y), parent = world, child = b2, origin = [0.5, 0.5, 0.5], rpy = [0.4, 0.3, 0.2], child_origin = [0.1, 0.1, 0.1], child_rpy = [0.0, 0.1, 0.0])]
#[loop_joint(weld: fixed, parent = b3, child = b1, origin = [0.2, 0.2, 0.0], rpy = [0.0, 0.0, 0.5], child_origin = [0.0, 0.0, 0.2], child_rpy = [0.5, 0.0, 0.0])]
struct Spatial {}

fn offset(xyz: [f64; 3], rpy: [f64; 3]) -> Isometry3<f64> {
    Isometry3::from_parts(
        Translation3::new(xyz[0], xyz[1], xyz[2]),
        UnitQuaternion::from_euler_angles(rpy[0], rpy[1], rpy[2]),
    )
}

/// `G` against central differences of `Φ`, and `γ = −Ġ v` against central differences
/// of `G v` along `v`, relative to the entries' scale.
fn check_derivatives<S, const N: usize, const M: usize>(
    s: &S,
    q: &SVector<f64, N>,
    v: &SVector<f64, N>,
) where
    S: LoopConstraints<N, M>,
{
    let h = 1e-6;
    let g = s.constraint_jacobian(q);
    for k in 0..N {
        let mut e = SVector::<f64, N>::zeros();
        e[k] = h;
        let fd = (s.constraint_residual(&(q + e)) - s.constraint_residual(&(q - e))) / (2.0 * h);
        let err = (fd - g.column(k)).amax();
        assert!(err < 1e-8 * (1.0 + g.amax()), "G column {k}: {err:e}");
    }
    let gdot_v = (s.constraint_jacobian(&(q + v * h)) * v
        - s.constraint_jacobian(&(q - v * h)) * v)
        / (2.0 * h);
    let gamma = s.constraint_gamma(q, v);
    let err = (gamma + gdot_v).amax();
    assert!(err < 1e-7 * (1.0 + gamma.amax()), "γ: {err:e}");
}

#[test]
fn four_bar_has_two_rows_that_match_its_closed_form() {
    let fb = FourBar {
        a: 0.3,
        b: 1.1,
        c: 0.8,
        d: 1.0,
    };
    assert_eq!(FourBar::CONSTRAINTS, ["rocker_pin.x", "rocker_pin.y"]);
    let mut rng = common::Rng::new(30);
    for _ in 0..50 {
        let q: SVector<f64, 3> = rng.vector(3.0);
        let v: SVector<f64, 3> = rng.vector(2.0);
        let (t1, t12) = (q[0], q[0] + q[1]);
        let pin = [
            fb.a * t1.cos() + fb.b * t12.cos(),
            fb.a * t1.sin() + fb.b * t12.sin(),
        ];
        let rocker = [fb.d + fb.c * q[2].cos(), fb.c * q[2].sin()];
        let phi = fb.constraint_residual(&q);
        for k in 0..2 {
            assert!(
                (phi[k] - (rocker[k] - pin[k])).abs() < 1e-14,
                "{phi} at {q}"
            );
        }
        check_derivatives(&fb, &q, &v);
    }
}

#[test]
fn every_loop_joint_kind_matches_the_numeric_model() {
    let s = Spatial {};
    assert_eq!(
        Spatial::CONSTRAINTS.len(),
        3 + 5 + 5 + 6,
        "{:?}",
        Spatial::CONSTRAINTS
    );
    let model = s.model();
    let mut rng = common::Rng::new(31);
    for _ in 0..30 {
        let q: SVector<f64, 4> = rng.vector(2.0);
        let v: SVector<f64, 4> = rng.vector(2.0);
        let poses: Vec<Isometry3<f64>> = numeric::link_poses(&model, &common::dvec(&q))
            .into_iter()
            .map(Into::into)
            .collect();
        let world = Isometry3::identity();
        let frames = |parent: &Isometry3<f64>,
                      a: ([f64; 3], [f64; 3]),
                      child: &Isometry3<f64>,
                      b: ([f64; 3], [f64; 3])| {
            (parent * offset(a.0, a.1), child * offset(b.0, b.1))
        };
        let axis = |p: &Isometry3<f64>, v: [f64; 3]| p.rotation * Vector3::from(v).normalize();
        let d =
            |a: &Isometry3<f64>, b: &Isometry3<f64>| b.translation.vector - a.translation.vector;
        let mut expected: Vec<f64> = Vec::new();
        // ball: the distance.
        let (a, b) = frames(
            &poses[1],
            ([0.3, 0.1, 0.0], [0.0; 3]),
            &poses[3],
            ([0.0, 0.2, 0.1], [0.0; 3]),
        );
        expected.extend(d(&a, &b).iter());
        // hinge: the distance, and the axis normal to the two normals of the axis.
        let (a, b) = frames(
            &poses[0],
            ([0.2, 0.0, 0.1], [0.1, 0.0, 0.2]),
            &poses[3],
            ([0.1, 0.0, 0.3], [0.3, 0.2, 0.1]),
        );
        expected.extend(d(&a, &b).iter());
        let n = Vector3::new(0.0, 0.6, 0.8);
        let u1 = n.cross(&Vector3::x()).normalize();
        let u2 = n.cross(&u1);
        for u in [u1, u2] {
            expected.push((a.rotation * u).dot(&axis(&b, [0.0, 0.6, 0.8])));
        }
        // slide: no motion across y (along the parent-side z and x), no rotation.
        let (a, b) = frames(
            &world,
            ([0.5, 0.5, 0.5], [0.4, 0.3, 0.2]),
            &poses[1],
            ([0.1, 0.1, 0.1], [0.0, 0.1, 0.0]),
        );
        let weld_rows = |a: &Isometry3<f64>, b: &Isometry3<f64>| {
            [
                axis(a, [1.0, 0.0, 0.0]).dot(&axis(b, [0.0, 1.0, 0.0])),
                axis(a, [0.0, 1.0, 0.0]).dot(&axis(b, [0.0, 0.0, 1.0])),
                axis(a, [0.0, 0.0, 1.0]).dot(&axis(b, [1.0, 0.0, 0.0])),
            ]
        };
        expected.push(d(&a, &b).dot(&axis(&a, [0.0, 0.0, 1.0])));
        expected.push(d(&a, &b).dot(&axis(&a, [1.0, 0.0, 0.0])));
        expected.extend(weld_rows(&a, &b));
        // weld: the distance and no rotation.
        let (a, b) = frames(
            &poses[2],
            ([0.2, 0.2, 0.0], [0.0, 0.0, 0.5]),
            &poses[0],
            ([0.0, 0.0, 0.2], [0.5, 0.0, 0.0]),
        );
        expected.extend(d(&a, &b).iter());
        expected.extend(weld_rows(&a, &b));
        let phi = s.constraint_residual(&q);
        for (k, (&got, want)) in phi.iter().zip(&expected).enumerate() {
            assert!(
                (got - want).abs() < 1e-13,
                "row {k} ({}): {got} against {want}",
                Spatial::CONSTRAINTS[k]
            );
        }
        check_derivatives(&s, &q, &v);
    }
}

/// A spatial chain of seven oblique revolute joints from the world, its tip held to the
/// world by a revolute loop joint (five rows; two degrees of freedom), under gravity.
#[derive(Mechanism)]
#[mechanism(gravity = [0.0, 0.0, -9.81])]
#[body(l1, mass = 1.0, com = [0.1, 0.0, 0.05], inertia = cuboid(1.0, 0.2, 0.05, 0.05))]
#[joint(r1: revolute(z), parent = world, child = l1, origin = [0.0, 0.0, 0.1])]
#[body(l2, mass = 0.8, com = [0.15, 0.02, 0.0], inertia = cuboid(0.8, 0.3, 0.05, 0.05))]
#[joint(r2: revolute([0.0, 0.6, 0.8]), parent = l1, child = l2, origin = [0.2, 0.0, 0.1], rpy = [0.1, 0.2, 0.0])]
#[body(l3, mass = 0.7, com = [0.1, 0.0, 0.03], inertia = cuboid(0.7, 0.2, 0.05, 0.05))]
#[joint(r3: revolute(x), parent = l2, child = l3, origin = [0.3, 0.0, 0.0], rpy = [0.0, 0.3, 0.1])]
#[body(l4, mass = 0.6, com = [0.1, 0.01, 0.0], inertia = cuboid(0.6, 0.2, 0.05, 0.05))]
#[joint(r4: revolute([1.0, 1.0, 0.0]), parent = l3, child = l4, origin = [0.2, 0.05, 0.0], rpy = [0.2, 0.0, 0.3])]
#[body(l5, mass = 0.5, com = [0.1, 0.0, 0.0], inertia = cuboid(0.5, 0.2, 0.05, 0.05))]
#[joint(r5: revolute(y), parent = l4, child = l5, origin = [0.2, 0.0, 0.05], rpy = [0.0, 0.1, 0.4])]
#[body(l6, mass = 0.4, com = [0.05, 0.02, 0.0], inertia = cuboid(0.4, 0.1, 0.05, 0.05))]
#[joint(r6: revolute([0.3, 0.0, 0.95]), parent = l5, child = l6, origin = [0.2, 0.0, 0.0], rpy = [0.3, 0.0, 0.0])]
#[body(l7, mass = 0.3, com = [0.05, 0.0, 0.01], inertia = cuboid(0.3, 0.1, 0.05, 0.05))]
#[joint(r7: revolute(z), parent = l6, child = l7, origin = [0.1, 0.0, 0.0], rpy = [0.0, 0.2, 0.0])]
#[loop_joint(anchor: revolute([0.0, 0.6, 0.8]), parent = world, child = l7, origin = [0.5, 0.3, 0.2], rpy = [0.1, 0.0, 0.2], child_origin = [0.1, 0.0, 0.0])]
struct SpatialLoop {}

/// The constrained dynamics against the augmented system `[M −Gᵀ; G 0] [a; λ] = [τ + τ_p −
/// C v − g; γ]` solved here densely, with `M` and `C v + g` from the numeric model (not
/// the generator); `forward_dynamics` is the constrained one; its Jacobian against
/// central differences.
fn check_dynamics<S, const N: usize, const M: usize>(
    s: &S,
    q: &SVector<f64, N>,
    v: &SVector<f64, N>,
    tau: &SVector<f64, N>,
) where
    S: LoopConstraints<N, M>,
{
    let model = s.model();
    let (qd, vd) = (common::dvec(q), common::dvec(v));
    let mass = numeric::crba(&model, &qd);
    let rhs0 = common::dvec(tau) + numeric::passive_forces(&model, &qd, &vd)
        - numeric::bias(&model, &qd, &vd);
    let g = s.constraint_jacobian(q);
    let mut k = DMatrix::<f64>::zeros(N + M, N + M);
    k.view_mut((0, 0), (N, N)).copy_from(&mass);
    for r in 0..M {
        for c in 0..N {
            k[(N + r, c)] = g[(r, c)];
            k[(c, N + r)] = -g[(r, c)];
        }
    }
    let mut rhs = DVector::<f64>::zeros(N + M);
    rhs.rows_mut(0, N).copy_from(&rhs0);
    rhs.rows_mut(N, M)
        .copy_from(&common::dvec(&s.constraint_gamma(q, v)));
    let x = k.lu().solve(&rhs).expect("the augmented system is regular");
    let (a, lambda) = s.constrained_forward_dynamics(q, v, tau);
    let scale = 1.0 + x.amax();
    for i in 0..N {
        assert!(
            (a[i] - x[i]).abs() < 1e-9 * scale,
            "a[{i}] = {} against {}",
            a[i],
            x[i]
        );
    }
    for r in 0..M {
        assert!(
            (lambda[r] - x[N + r]).abs() < 1e-9 * scale,
            "λ[{r}] = {} against {}",
            lambda[r],
            x[N + r]
        );
    }
    // The same solve as the forward dynamics kernel's portable path, bit for bit (its
    // fused multiply–add twin rounds differently).
    filippov::runtime::numerics::fused::set_enabled(false);
    assert_eq!(s.forward_dynamics(q, v, tau), a);
    // The constraint holds at the acceleration level.
    let residual = (g * a - s.constraint_gamma(q, v)).amax();
    assert!(residual < 1e-9 * scale, "G a − γ = {residual:e}");
    let jac = s.forward_dynamics_jacobian(q, v, tau);
    let h = 1e-6;
    for k in 0..N {
        let mut e = SVector::<f64, N>::zeros();
        e[k] = h;
        let dq = (s.forward_dynamics(&(q + e), v, tau) - s.forward_dynamics(&(q - e), v, tau))
            / (2.0 * h);
        let dv = (s.forward_dynamics(q, &(v + e), tau) - s.forward_dynamics(q, &(v - e), tau))
            / (2.0 * h);
        let eq = (dq - jac.d_dq.column(k)).amax();
        let ev = (dv - jac.d_dv.column(k)).amax();
        let js = 1.0 + jac.d_dq.amax().max(jac.d_dv.amax());
        assert!(
            eq < 1e-6 * js && ev < 1e-6 * js,
            "Jacobian column {k}: {eq:e}, {ev:e}"
        );
    }
    assert!((jac.acceleration - a).amax() < 1e-12 * scale);
}

#[test]
fn constrained_dynamics_solve_the_augmented_system() {
    let fb = FourBar {
        a: 0.3,
        b: 1.1,
        c: 0.8,
        d: 1.0,
    };
    let chain = SpatialLoop {};
    let mut rng = common::Rng::new(32);
    for _ in 0..30 {
        let q: SVector<f64, 3> = rng.vector(3.0);
        let v: SVector<f64, 3> = rng.vector(2.0);
        let tau: SVector<f64, 3> = rng.vector(5.0);
        check_dynamics(&fb, &q, &v, &tau);
        let q: SVector<f64, 7> = rng.vector(3.0);
        let v: SVector<f64, 7> = rng.vector(2.0);
        let tau: SVector<f64, 7> = rng.vector(5.0);
        check_dynamics(&chain, &q, &v, &tau);
    }
}

/// Integrated with every method from a state projected onto the loop (a rough guess of
/// the closed configuration and a random velocity): at every row the loop is closed and
/// its velocity constraint holds to round-off, and the energy is conserved to the
/// integration's accuracy.
#[test]
fn closed_four_bar_stays_on_its_constraints_and_conserves_energy() {
    use filippov::runtime::{MechanicalSystem, Method, Options, Problem, solve};
    let fb = filippov::scenes::FourBar::default();
    let system = MechanicalSystem::unforced(&fb);
    // Off the loop on purpose: the start is projected.
    let y0 = [0.5, 1.0, 2.0, 6.0, -1.0, 0.5];
    let energy = |y: &[f64]| {
        let q = SVector::<f64, 3>::from_column_slice(&y[..3]);
        let v = SVector::<f64, 3>::from_column_slice(&y[3..6]);
        fb.kinetic_energy(&q, &v) + fb.potential_energy(&q)
    };
    for (name, method) in [
        ("DOPRI5", Method::Dopri5(Options::tolerances(1e-10, 1e-12))),
        ("SDIRK4", Method::Sdirk4(Options::tolerances(1e-10, 1e-12))),
        ("BDF", Method::Bdf(Options::tolerances(1e-10, 1e-12))),
    ] {
        let sol = solve(&system, &Problem::new(0.0, 5.0, y0), &method)
            .unwrap_or_else(|e| panic!("{name}: {e}"));
        let e0 = energy(sol.state(0));
        let mut worst = [0.0f64; 3];
        for (_, y) in sol.rows() {
            let q = SVector::<f64, 3>::from_column_slice(&y[..3]);
            let v = SVector::<f64, 3>::from_column_slice(&y[3..6]);
            worst[0] = worst[0].max(fb.constraint_residual(&q).amax());
            worst[1] = worst[1].max((fb.constraint_jacobian(&q) * v).amax());
            worst[2] = worst[2].max((energy(y) - e0).abs() / e0.abs());
        }
        eprintln!(
            "{name}: {} rows, |Φ| ≤ {:.1e}, |G v| ≤ {:.1e}, energy drift ≤ {:.1e}; {}",
            sol.len(),
            worst[0],
            worst[1],
            worst[2],
            sol.stats
        );
        assert!(worst[0] <= 1e-12 && worst[1] <= 1e-12, "{name}: {worst:?}");
        assert!(worst[2] <= 1e-8, "{name}: energy drift {:e}", worst[2]);
    }
}

/// The loop joints' constraint forces are columns of the solution, `λ_<row>`: the force
/// the joint applies to its child body at the joint, in world axes. Checked by the
/// rocker's own equation of motion, which no kernel writes: turning about its fixed
/// pivot, `I_O α = −m g (c/2) cos θ + c (cos θ λ_y − sin θ λ_x)`, at every row, with
/// `α` the row's derivative.
#[test]
fn constraint_forces_are_columns_of_the_solution() {
    use filippov::runtime::{MechanicalSystem, Method, Options, Problem, solve};
    let fb = filippov::scenes::FourBar::default();
    let y0 = [0.5, 1.0, 2.0, 6.0, -1.0, 0.5];
    let sol = solve(
        &MechanicalSystem::unforced(&fb),
        &Problem::new(0.0, 2.0, y0),
        &Method::Dopri5(Options::tolerances(1e-10, 1e-12)),
    )
    .unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(sol.dim(), 8);
    let (lx, ly) = (
        sol.column_index("λ_rocker_pin.x").expect("a λ column"),
        sol.column_index("λ_rocker_pin.y").expect("a λ column"),
    );
    let inertia = fb.mc * fb.c * fb.c / 3.0;
    let mut worst = 0.0f64;
    let mut largest = 0.0f64;
    for i in 0..sol.len() {
        let (y, dy) = (sol.state(i), sol.derivative(i));
        let theta = y[2];
        let (fx, fy) = (y[lx], y[ly]);
        let moment =
            -fb.mc * fb.g * fb.c / 2.0 * theta.cos() + fb.c * (theta.cos() * fy - theta.sin() * fx);
        worst = worst.max((inertia * dy[5] - moment).abs());
        largest = largest.max(fx.abs().max(fy.abs()));
    }
    eprintln!("rocker's moment balance within {worst:.1e} N·m, |λ| up to {largest:.2} N");
    assert!(largest > 1.0, "the pin carries a force");
    assert!(worst < 1e-10 * largest * fb.c, "{worst:e}");
    // Between rows the columns are read back linearly.
    let (t0, t1) = (sol.times()[3], sol.times()[4]);
    let mid = sol.at(0.5 * (t0 + t1)).expect("inside");
    assert_eq!(mid[lx], 0.5 * (sol.state(3)[lx] + sol.state(4)[lx]));
}

/// A parallelogram four-bar turning uniformly reaches the configuration where all its
/// links are collinear (a change point: the constraint rows lose rank, and the linkage
/// may go on as a parallelogram or fold into an antiparallelogram) at
/// `t* = (π − 1)/ω`. Every method stops there with the typed error naming the row,
/// within 1e-6 of `t*`, keeping the solution up to it (or to the end of the step before,
/// when the point lies just past it, with the crank where uniform rotation puts it) —
/// although no accepted step lands on the point.
#[test]
fn change_point_is_reported_where_it_is_reached() {
    use filippov::runtime::loops::LoopError;
    use filippov::runtime::{ErrorKind, MechanicalSystem, Method, Options, Problem, solve};
    use filippov::scenes::FourBar;
    let fb = FourBar {
        a: 0.5,
        b: 1.0,
        c: 0.5,
        d: 1.0,
        g: 0.0,
        ..FourBar::default()
    };
    let omega = 2.0;
    let t_star = (std::f64::consts::PI - 1.0) / omega;
    let y0 = [1.0, -1.0, 1.0, omega, -omega, omega];
    for (name, method) in [
        ("DOPRI5", Method::Dopri5(Options::tolerances(1e-8, 1e-10))),
        ("SDIRK4", Method::Sdirk4(Options::tolerances(1e-8, 1e-10))),
        ("BDF", Method::Bdf(Options::tolerances(1e-8, 1e-10))),
    ] {
        let err = solve(
            &MechanicalSystem::unforced(&fb),
            &Problem::new(0.0, 3.0, y0),
            &method,
        )
        .expect_err(name);
        let ErrorKind::Loops {
            t,
            error: LoopError::Singular { row, pivot },
        } = err.kind
        else {
            panic!("{name}: {}", err.kind)
        };
        eprintln!("{name}: singular at t = {t} (t* = {t_star}), row {row}, pivot {pivot:e}");
        assert!((t - t_star).abs() < 1e-6, "{name}: t = {t}");
        assert!(row.starts_with("rocker_pin."));
        let (t_last, y) = err.solution.last().unwrap();
        assert!(
            t_last <= t && t - t_last < 1e-5,
            "{name}: last row at {t_last}"
        );
        // The parallelogram turns uniformly (its mass matrix is constant): the crank at
        // the last row is where uniform rotation puts it, 1 + ω t_last (π at t*).
        assert!(
            (y[0] - (1.0 + omega * t_last)).abs() < 1e-6,
            "{name}: crank at {} at t = {t_last}",
            y[0]
        );
    }
}

/// `assemble` keeps the given coordinates and closes the loops with the others, from a
/// rough guess: the crank angle and speed given, the four-bar's residual and velocity
/// constraint at round-off; a rocker angle the linkage cannot reach, and a joint name
/// it does not have, are typed errors naming the row and the joints.
#[test]
fn assembly_completes_a_partial_state_or_says_why_not() {
    use filippov::runtime::loops::{LoopError, assemble};
    use filippov::scenes::FourBar;
    let fb = FourBar::default();
    let mut rng = common::Rng::new(33);
    for _ in 0..20 {
        let crank = rng.uniform(-3.0, 3.0);
        let speed = rng.uniform(-5.0, 5.0);
        // The open branch of the crank-rocker: the coupler roughly level, the rocker up.
        let guess = SVector::from([crank, 1.0 - crank, 1.5]);
        let (q, v) = assemble(
            &fb,
            &guess,
            &SVector::from([speed, 0.0, 0.0]),
            &["crank_pivot"],
        )
        .unwrap_or_else(|e| panic!("crank at {crank}: {e}"));
        assert_eq!((q[0], v[0]), (crank, speed));
        assert!(fb.constraint_residual(&q).amax() < 1e-13, "{q}");
        assert!((fb.constraint_jacobian(&q) * v).amax() < 1e-12 * (1.0 + v.amax()));
    }
    // The rocker pointing back at the crank's pivot: its end 0.2 from it, nearer than
    // the coupler can fold (b − a = 0.8).
    let far = assemble(
        &fb,
        &SVector::from([0.0, 0.0, std::f64::consts::PI]),
        &SVector::zeros(),
        &["rocker_pivot"],
    );
    assert!(
        matches!(far, Err(LoopError::NoAssembly { row, .. }) if row.starts_with("rocker_pin.")),
        "{far:?}"
    );
    let unknown = assemble(&fb, &SVector::zeros(), &SVector::zeros(), &["crank"]);
    let Err(e @ LoopError::UnknownJoint { .. }) = unknown else {
        panic!("{unknown:?}")
    };
    assert!(e.to_string().contains("`crank_pivot`"), "{e}");
}

/// Andrews' squeezing mechanism, built with the derive in the test set's coordinates:
/// its published consistent start is on the loops (|Φ| at round-off), and integrated to
/// t = 0.03 every position is within 1e-8 (absolute) of the published reference.
#[test]
fn andrews_squeezer_meets_the_published_reference() {
    use filippov::runtime::{MechanicalSystem, Method, Options, Problem, solve};
    use filippov::scenes::AndrewsSqueezer;
    use filippov::scenes::references::ANDREWS_Q_AT_0_03;
    let sq = AndrewsSqueezer::default();
    let q0 = AndrewsSqueezer::initial_positions();
    let phi0 = sq.constraint_residual(&q0).amax();
    assert!(
        phi0 < 1e-15,
        "the published start is off the loops by {phi0:e}"
    );
    let torque = sq.torque();
    let system = MechanicalSystem::new(
        &sq,
        move |_t, _q: &SVector<f64, 7>, _v: &SVector<f64, 7>| torque,
    );
    let mut y0 = vec![0.0; 14];
    y0[..7].copy_from_slice(q0.as_slice());
    for (name, method) in [
        ("DOPRI5", Method::Dopri5(Options::tolerances(1e-12, 1e-14))),
        ("BDF", Method::Bdf(Options::tolerances(1e-12, 1e-14))),
    ] {
        let sol = solve(&system, &Problem::new(0.0, 0.03, y0.clone()), &method)
            .unwrap_or_else(|e| panic!("{name}: {e}"));
        let (t, y) = sol.last().unwrap();
        assert_eq!(t, 0.03);
        let err = AndrewsSqueezer::TEST_SET_ORDER
            .iter()
            .zip(ANDREWS_Q_AT_0_03)
            .map(|(&i, r)| (y[i] - r).abs())
            .fold(0.0, f64::max);
        eprintln!(
            "{name}: max |q(0.03) − reference| = {err:.2e}; {}",
            sol.stats
        );
        assert!(err < 1e-8, "{name}: {err:e}");
    }
}

/// The bundled slider-crank (Coulomb friction on the slider, a rigid elastic stop at the
/// end of its stroke, the crank driven by a reversing torque), event-driven and
/// time-stepping: at rtol 1e-10 the energy balance (kinetic
/// + gravity + the torque's work − the friction's dissipation; the stop is elastic)
/// closes to 1e-8 of the energy scale with the loop closed at every row, the slider
/// breaks away from sticking, slips both ways and bounces on its stop, and
/// time-stepping converges to the event-driven solution at first order.
#[test]
fn slider_crank_with_friction_and_a_stop() {
    use filippov::Energy;
    use filippov::runtime::loops::assemble;
    use filippov::runtime::{
        Method, NonSmoothMethod, NonSmoothProblem, Options, SwitchKind, solve_nonsmooth,
    };
    use filippov::scenes::SliderCrank;
    let press = SliderCrank::default();
    let (q0, v0) = assemble(
        &press,
        &SVector::from([2.0, -2.0, 0.3]),
        &SVector::zeros(),
        &["crank"],
    )
    .unwrap();
    // A torque that reverses, so that the slider sticks where it passes zero.
    let torque = |t: f64| 2.0 * (4.0 * t).sin();
    let input = move |t: f64, _q: &SVector<f64, 3>, _v: &SVector<f64, 3>| {
        SliderCrank::input_forces(&SVector::from([torque(t)]))
    };
    let p = NonSmoothProblem::new(0.0, 2.0, q0, v0);
    let ed = solve_nonsmooth(
        &press,
        &input,
        &p,
        &NonSmoothMethod::EventDriven(Method::Dopri5(Options::tolerances(1e-10, 1e-12))),
    )
    .unwrap_or_else(|e| panic!("event-driven: {e}"));
    let energy = |y: &[f64]| {
        let q = SVector::<f64, 3>::from_column_slice(&y[..3]);
        let v = SVector::<f64, 3>::from_column_slice(&y[3..6]);
        press.kinetic_energy(&q, &v) + press.potential_energy(&q)
    };
    let f = ed.column_index("f_friction_stroke").unwrap();
    // ∫ τ v_crank dt and ∫ f v_stroke dt.
    let work = common::integral(&ed, &|t, y| torque(t) * y[3]);
    let dissipated = common::integral(&ed, &|_, y| y[f] * y[5]);
    let (_, y1) = ed.last().unwrap();
    let e0 = energy(ed.state(0));
    let scale = e0.abs().max(work.abs()).max(1.0);
    let balance = energy(y1) + dissipated - work - e0;
    let impacts = ed
        .switches
        .iter()
        .filter(|s| s.kind == SwitchKind::Impact)
        .count();
    let stick = Some(filippov::runtime::Mode::Stick);
    let sticks = ed
        .switches
        .iter()
        .filter(|s| s.to == stick || s.from == stick)
        .count();
    let mut worst_phi = 0.0f64;
    for (_, y) in ed.rows() {
        worst_phi = worst_phi.max(
            press
                .constraint_residual(&SVector::from_column_slice(&y[..3]))
                .amax(),
        );
    }
    eprintln!(
        "event-driven: {impacts} impacts, {sticks} stick switches, balance {:.2e} of {scale:.2}, |Φ| ≤ {worst_phi:.1e}; {}",
        balance / scale,
        ed.stats
    );
    assert!(
        impacts >= 1 && sticks >= 1,
        "{:?}",
        ed.switches
            .iter()
            .map(|s| (s.t, s.kind, s.to))
            .collect::<Vec<_>>()
    );
    assert!(worst_phi < 1e-10, "|Φ| = {worst_phi:e}");
    assert!(balance.abs() < 1e-8 * scale, "balance {balance:e}");
    // The wrist pin's force is a column after the elements' forces; the slider's own
    // equation along its stroke, m_s a = λ_x − f_friction − f_stop, holds at every row
    // (sliding, stuck, against the stop).
    let lx = ed.column_index("λ_wrist_pin.x").expect("a λ column");
    let stop = ed.column_index("f_stop_stroke").expect("the stop's force");
    assert!(lx > stop && lx > f, "{:?}", ed.names());
    let mut worst_slider = 0.0f64;
    for i in 0..ed.len() {
        let (y, dy) = (ed.state(i), ed.derivative(i));
        let residual = press.ms * dy[5] - (y[lx] - y[f] - y[stop]);
        worst_slider = worst_slider.max(residual.abs() / (1.0 + y[lx].abs()));
    }
    eprintln!("slider's equation along its stroke within {worst_slider:.1e} of the pin force");
    assert!(worst_slider < 1e-8, "{worst_slider:e}");
    // Time-stepping converges to it: positions, uniformly over the first half second
    // (later, the bounces on the stop amplify every difference).
    let dist = |h: f64| {
        let ts = solve_nonsmooth(
            &press,
            &input,
            &p,
            &NonSmoothMethod::TimeStepping { h, theta: 1.0 },
        )
        .unwrap_or_else(|e| panic!("time-stepping h = {h}: {e}"));
        assert_eq!(ts.names(), ed.names(), "the same columns");
        (0..=50)
            .map(|k| {
                let t = 0.01 * k as f64;
                let (a, b) = (ed.at(t).unwrap(), ts.at(t).unwrap());
                (0..3).map(|i| (a[i] - b[i]).abs()).fold(0.0, f64::max)
            })
            .fold(0.0, f64::max)
    };
    let (d3, d4) = (dist(1e-3), dist(1e-4));
    eprintln!(
        "time-stepping's largest position difference over [0, 0.5]: h = 1e-3 {d3:.2e}, 1e-4 {d4:.2e}"
    );
    assert!(d4 < 0.2 * d3, "{d3:e} → {d4:e}");
}

/// The Delta-style parallel robot (three spherical loop joints): nine rows; assembled
/// from a given platform position; its constrained forward dynamics against the
/// augmented system built without the generator — the numeric model's mass matrix and
/// bias forces, the loops' residual composed from its link poses, `G` and `γ` by finite
/// differences of that residual — at random velocities and hip torques; and a short
/// lossless run stays on the loops with its energy conserved.
#[test]
fn delta_robot_against_a_reference_without_the_generator() {
    use filippov::Energy;
    use filippov::nalgebra::{DMatrix, DVector};
    use filippov::runtime::loops::assemble;
    use filippov::runtime::{MechanicalSystem, Method, Options, Problem, solve};
    use filippov::scenes::Delta;
    let delta = Delta::default();
    assert_eq!(Delta::CONSTRAINTS.len(), 9, "{:?}", Delta::CONSTRAINTS);
    let model = delta.model();
    let link = |name: &str| model.links.iter().position(|l| l.name == name).unwrap();
    let (platform, forearms) = (
        link("platform"),
        [link("forearm_1"), link("forearm_2"), link("forearm_3")],
    );
    let angles = [
        0.0,
        2.0 * std::f64::consts::PI / 3.0,
        4.0 * std::f64::consts::PI / 3.0,
    ];
    // Φ from the numeric model's link poses: each forearm's end minus its ball on the
    // platform, world axes.
    let phi = |q: &DVector<f64>| -> DVector<f64> {
        let poses = numeric::link_poses(&model, q);
        let mut out = DVector::zeros(9);
        for (i, (&f, a)) in forearms.iter().zip(angles).enumerate() {
            let ball = poses[platform].transform_point(&Vector3::new(
                delta.rp * a.cos(),
                delta.rp * a.sin(),
                0.0,
            ));
            let end = poses[f].transform_point(&Vector3::new(delta.lf, 0.0, 0.0));
            out.rows_mut(3 * i, 3).copy_from(&(end - ball));
        }
        out
    };
    // The platform 5 cm off centre; the legs from a rough guess.
    let guess = SVector::<f64, 12>::from_fn(|i, _| match i {
        0 => 0.03,
        1 => -0.02,
        2 => -0.05,
        _ => 0.0,
    });
    let mut guess = guess;
    for leg in 0..3 {
        guess[3 + 3 * leg] = 0.6; // hip: the arm down
        guess[4 + 3 * leg] = 0.9; // elbow bend
    }
    let (q, _) = assemble(
        &delta,
        &guess,
        &SVector::zeros(),
        &["platform_x", "platform_y", "platform_z"],
    )
    .unwrap_or_else(|e| panic!("{e}"));
    let qd = common::dvec(&q);
    assert!(
        phi(&qd).amax() < 1e-13,
        "assembled: the numeric loops are open by {:e}",
        phi(&qd).amax()
    );
    let mut rng = common::Rng::new(34);
    for _ in 0..10 {
        // A velocity on the loops: any velocity projected by the generated kernels would
        // not be independent, so the reference takes the free part of a random one.
        let v_any: SVector<f64, 12> = rng.vector(1.0);
        let tau = Delta::input_forces(&rng.vector::<3>(2.0));
        let h = 1e-6;
        let g_num = DMatrix::from_fn(9, 12, |r, c| {
            let mut e = DVector::zeros(12);
            e[c] = h;
            (phi(&(&qd + &e))[r] - phi(&(&qd - &e))[r]) / (2.0 * h)
        });
        // v = v_any minus its component off the loops (least squares in the plain metric).
        let svd = g_num.clone().svd(true, true);
        let vd0 = common::dvec(&v_any);
        let correction = svd.solve(&(&g_num * &vd0), 1e-12).unwrap();
        let vd = &vd0 - correction;
        let v = SVector::<f64, 12>::from_column_slice(vd.as_slice());
        // γ = −vᵀ ∂²Φ v by second differences along v.
        let e = 1e-4;
        let gamma = -(phi(&(&qd + &vd * e)) - phi(&qd) * 2.0 + phi(&(&qd - &vd * e))) / (e * e);
        let mass = numeric::crba(&model, &qd);
        let rhs0 = common::dvec(&tau) + numeric::passive_forces(&model, &qd, &vd)
            - numeric::bias(&model, &qd, &vd);
        let mut k = DMatrix::<f64>::zeros(21, 21);
        k.view_mut((0, 0), (12, 12)).copy_from(&mass);
        k.view_mut((12, 0), (9, 12)).copy_from(&g_num);
        k.view_mut((0, 12), (12, 9))
            .copy_from(&(-g_num.transpose()));
        let mut rhs = DVector::<f64>::zeros(21);
        rhs.rows_mut(0, 12).copy_from(&rhs0);
        rhs.rows_mut(12, 9).copy_from(&gamma);
        let x = k.lu().solve(&rhs).expect("the augmented system is regular");
        let a = delta.forward_dynamics(&q, &v, &tau);
        let scale = 1.0 + x.rows(0, 12).amax();
        let err = (0..12).map(|i| (a[i] - x[i]).abs()).fold(0.0, f64::max);
        assert!(
            err < 1e-5 * scale,
            "a against the reference: {err:e} of {scale:e}"
        );
    }
    // A short lossless run under gravity from rest: on the loops, energy conserved.
    let energy = |y: &[f64]| {
        let q = SVector::<f64, 12>::from_column_slice(&y[..12]);
        let v = SVector::<f64, 12>::from_column_slice(&y[12..24]);
        delta.kinetic_energy(&q, &v) + delta.potential_energy(&q)
    };
    let mut y0 = q.as_slice().to_vec();
    y0.extend_from_slice(&[0.0; 12]);
    let sol = solve(
        &MechanicalSystem::unforced(&delta),
        &Problem::new(0.0, 0.2, y0),
        &Method::Dopri5(Options::tolerances(1e-10, 1e-12)),
    )
    .unwrap_or_else(|e| panic!("{e}"));
    let e0 = energy(sol.state(0));
    let mut worst = [0.0f64; 2];
    for (_, y) in sol.rows() {
        worst[0] = worst[0].max(
            delta
                .constraint_residual(&SVector::from_column_slice(&y[..12]))
                .amax(),
        );
        worst[1] = worst[1].max((energy(y) - e0).abs());
    }
    let moved = (sol.last().unwrap().1[2] - q[2]).abs();
    eprintln!(
        "Delta, 0.2 s from rest: platform dropped {moved:.3e}, |Φ| ≤ {:.1e}, energy within {:.1e} J; {}",
        worst[0], worst[1], sol.stats
    );
    assert!(moved > 1e-3, "the platform falls");
    assert!(
        worst[0] < 1e-12 && worst[1] < 1e-8 * (1.0 + e0.abs()),
        "{worst:?}"
    );
}
