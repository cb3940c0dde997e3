//! The compact kernels (`forward_dynamics = compact`: the articulated-body algorithm as
//! one loop over a table of the bodies in joint-aligned frames, `runtime::compact`)
//! against the unrolled ones the derive writes for the same scene: forward dynamics,
//! its Jacobian (dual numbers through the loop against the symbolic Jacobian), the
//! generic kernels on dual parameters and SIMD lanes, on a parametric oblique tree with
//! springs and dampers and on URDF robots. `tests/random_trees.rs` checks compact trees
//! against the numeric implementation too. The bit-for-bit comparisons are of the `f64`
//! kernels' portable path, and of the fused twins on lanes against the fused twins on
//! `f64`; the fused multiply–add twins (`runtime::compact::fused`) are compared with
//! the portable path to rounding.

// clippy's duplicated_attributes misreads repeated derive-helper attributes.
#![allow(clippy::duplicated_attributes)]

mod common;

use common::{Rng, assert_close};
use filippov::nalgebra::SVector;
use filippov::prelude::*;
use filippov::runtime::Dual;
use filippov::runtime::kernels::GenericDynamics;

/// The `f64` kernels' portable path for the rest of the run (the switch is global; the
/// fused twins' test calls them directly).
fn portable() {
    filippov::runtime::numerics::fused::set_enabled(false);
}

/// Declares the same scene twice: compact, and unrolled by the articulated-body
/// algorithm.
macro_rules! both {
    ($compact:ident, $unrolled:ident, $fields:tt, [$($mech:tt)*], $($attrs:tt)*) => {
        #[derive(Mechanism, Clone, Copy)]
        #[mechanism(forward_dynamics = compact, $($mech)*)]
        $($attrs)*
        struct $compact $fields

        #[derive(Mechanism, Clone, Copy)]
        #[mechanism(forward_dynamics = aba, $($mech)*)]
        $($attrs)*
        struct $unrolled $fields
    };
}

both!(ObliqueCompact, ObliqueUnrolled,
    { m1: f64, m2: f64, m3: f64, l: f64, k: f64, c: f64, g: f64 },
    [emit = [generic], gravity = [0.3, -0.2, -g]],
    #[body(base, mass = m1, com = [0.1, 0.0, 0.05], inertia = sphere(m1, 0.2))]
    #[joint(slide: prismatic([0.6, 0.0, 0.8]), parent = world, child = base, origin = [0.0, 0.0, 1.0], rpy = [0.1, 0.2, 0.3])]
    #[spring(slide, k = k)]
    #[damper(slide, c = c)]
    #[body(arm, mass = m2, com = [l / 2.0, 0.05, 0.0], inertia = rod(m2, l))]
    #[joint(shoulder: revolute([0.0, 0.6, 0.8]), parent = base, child = arm, origin = [0.1, 0.2, 0.0], rpy = [0.3, -0.2, 0.5])]
    #[body(hand, mass = m3, com = [0.05, 0.0, 0.02], inertia = sphere(m3, 0.05))]
    #[joint(wrist: revolute([1.0, 1.0, 0.0]), parent = arm, child = hand, origin = [l, 0.0, 0.1], rpy = [-0.2, 0.1, 0.0])]
    #[body(tool, mass = m3 / 2.0, com = [0.0, 0.02, 0.01], inertia = cuboid(m3 / 2.0, 0.02, 0.03, 0.04))]
    #[joint(weld: fixed, parent = hand, child = tool, origin = [0.0, 0.1, l], rpy = [0.4, 0.0, -0.3])]
    #[body(finger, mass = m3 / 3.0, com = [0.01, 0.0, 0.02], inertia = rod(m3 / 3.0, 0.05))]
    #[joint(knuckle: revolute(-y), parent = tool, child = finger, origin = [0.0, 0.0, 0.05])]
    #[damper(knuckle, c = 0.1)]
    #[body(side, mass = m2, com = [0.0, 0.1, 0.0], inertia = cylinder(m2, 0.03, l))]
    #[joint(elbow: revolute(x), parent = base, child = side, origin = [0.0, -0.1, 0.2], rpy = [0.0, 0.0, 0.7])]
    #[body(rail, mass = m3, com = [0.0, 0.0, 0.0], inertia = sphere(m3, 0.03))]
    #[joint(rail: prismatic(z), parent = side, child = rail, origin = [0.0, l, 0.0])]
);

fn oblique<S>(make: fn(f64, f64, f64, f64, f64, f64, f64) -> S) -> S {
    make(1.0, 0.5, 0.3, 0.4, 20.0, 0.7, 9.81)
}

fn compact() -> ObliqueCompact {
    oblique(|m1, m2, m3, l, k, c, g| ObliqueCompact {
        m1,
        m2,
        m3,
        l,
        k,
        c,
        g,
    })
}

fn unrolled() -> ObliqueUnrolled {
    oblique(|m1, m2, m3, l, k, c, g| ObliqueUnrolled {
        m1,
        m2,
        m3,
        l,
        k,
        c,
        g,
    })
}

#[derive(Mechanism)]
#[mechanism(
    urdf = "robots/panda.urdf",
    lock = [panda_finger_joint1, panda_finger_joint2],
    gravity = [0.0, 0.0, -9.81],
    forward_dynamics = compact,
    emit = [generic]
)]
struct PandaCompact;

#[derive(Mechanism)]
#[mechanism(
    urdf = "robots/panda.urdf",
    lock = [panda_finger_joint1, panda_finger_joint2],
    gravity = [0.0, 0.0, -9.81],
    forward_dynamics = aba
)]
struct PandaUnrolled;

#[derive(Mechanism)]
#[mechanism(urdf = "robots/ur5.urdf", gravity = [0.0, 0.0, -9.81], forward_dynamics = compact)]
struct Ur5Compact;

#[derive(Mechanism)]
#[mechanism(urdf = "robots/ur5.urdf", gravity = [0.0, 0.0, -9.81], forward_dynamics = aba)]
struct Ur5Unrolled;

/// Forward dynamics and its Jacobian of two declarations of one scene at random states.
fn agree<A: Mechanism<N>, B: Mechanism<N>, const N: usize>(a: &A, b: &B, seed: u64) {
    portable();
    let mut rng = Rng::new(seed);
    for _ in 0..50 {
        let q: SVector<f64, N> = rng.vector(2.5);
        let v: SVector<f64, N> = rng.vector(3.0);
        let tau: SVector<f64, N> = rng.vector(5.0);
        let fa = a.forward_dynamics(&q, &v, &tau);
        let fb = b.forward_dynamics(&q, &v, &tau);
        assert_close(
            fa.as_slice(),
            fb.as_slice(),
            1e-12,
            1e-12,
            "forward dynamics",
        );
        let ja = a.forward_dynamics_jacobian(&q, &v, &tau);
        let jb = b.forward_dynamics_jacobian(&q, &v, &tau);
        // The Jacobian kernel's v̇ is the forward dynamics kernel's, bit for bit.
        assert_eq!(ja.acceleration, fa, "the Jacobian's v̇");
        assert_close(ja.d_dq.as_slice(), jb.d_dq.as_slice(), 1e-11, 1e-9, "∂v̇/∂q");
        assert_close(ja.d_dv.as_slice(), jb.d_dv.as_slice(), 1e-11, 1e-9, "∂v̇/∂v");
    }
}

#[test]
fn oblique_tree_compact_equals_unrolled() {
    agree(&compact(), &unrolled(), 1);
}

#[test]
fn urdf_robots_compact_equal_unrolled() {
    agree(&PandaCompact, &PandaUnrolled, 2);
    agree(&Ur5Compact, &Ur5Unrolled, 3);
}

/// Derivatives with respect to the parameters (masses, a length, the spring and damper,
/// gravity) by duals through the compact loop against those through the unrolled code.
#[test]
fn parameter_sensitivities_compact_equal_unrolled() {
    portable();
    let mut rng = Rng::new(4);
    let p = compact().parameters();
    assert_eq!(p, unrolled().parameters());
    let pd: [Dual<7>; 7] = std::array::from_fn(|k| Dual::variable(p[k], k));
    for _ in 0..20 {
        let q: [f64; 6] = rng.vector::<6>(2.0).into();
        let v: [f64; 6] = rng.vector::<6>(3.0).into();
        let tau: [f64; 6] = rng.vector::<6>(5.0).into();
        let c = |x: [f64; 6]| x.map(Dual::<7>::constant);
        let a = ObliqueCompact::forward_dynamics_generic(&pd, &c(q), &c(v), &c(tau));
        let b = ObliqueUnrolled::forward_dynamics_generic(&pd, &c(q), &c(v), &c(tau));
        let flat = |x: &[Dual<7>; 6]| -> Vec<f64> {
            x.iter()
                .flat_map(|d| std::iter::once(d.re).chain(d.eps))
                .collect()
        };
        assert_close(&flat(&a), &flat(&b), 1e-11, 1e-9, "v̇ and ∂v̇/∂p");
        // On f64, the generic compact kernel is the f64 one bit for bit.
        let f = compact().forward_dynamics_as::<f64>(&q, &v, &tau);
        let s = compact().forward_dynamics(&q.into(), &v.into(), &tau.into());
        assert_eq!(f.map(f64::to_bits), <[f64; 6]>::from(s).map(f64::to_bits));
    }
}

/// Four random Panda states: coordinates within ±2.5, velocities ±3, torques ±5.
#[allow(clippy::type_complexity)]
fn four_states(rng: &mut Rng) -> (Vec<[f64; 7]>, Vec<[f64; 7]>, Vec<[f64; 7]>) {
    let mut draw =
        |s: f64| -> Vec<[f64; 7]> { (0..4).map(|_| rng.vector::<7>(s).into()).collect() };
    let q = draw(2.5);
    let v = draw(3.0);
    (q, v, draw(5.0))
}

/// Four states in the lanes of one `f64x4` call: each lane is the scalar compact kernel
/// bit for bit.
#[test]
fn lanes_are_the_scalar_compact_kernel_bit_for_bit() {
    portable();
    use filippov::runtime::real::{f64x4, pack, unpack};
    let mut rng = Rng::new(5);
    for _ in 0..20 {
        let (q, v, tau) = four_states(&mut rng);
        let (qb, vb, tb): ([f64x4; 7], [f64x4; 7], [f64x4; 7]) = (pack(&q), pack(&v), pack(&tau));
        let out = unpack(&PandaCompact.forward_dynamics_as(&qb, &vb, &tb), 4);
        for s in 0..4 {
            let scalar = PandaCompact.forward_dynamics(&q[s].into(), &v[s].into(), &tau[s].into());
            assert_eq!(
                out[s].map(f64::to_bits),
                <[f64; 7]>::from(scalar).map(f64::to_bits),
                "lane {s}"
            );
        }
    }
}

/// The generic Jacobian (dual numbers of the scalar through the loop): on `f64` the
/// `f64` kernel bit for bit, on `f64x4` each lane the scalar kernel bit for bit.
#[test]
fn generic_jacobian_is_the_scalar_one_bit_for_bit() {
    portable();
    use filippov::runtime::real::{f64x4, pack, unpack};
    let mut rng = Rng::new(6);
    let bits = |m: &filippov::nalgebra::SMatrix<f64, 7, 7>| -> Vec<u64> {
        (0..49).map(|k| m[(k / 7, k % 7)].to_bits()).collect()
    };
    let rows =
        |m: &[[f64; 7]; 7]| -> Vec<u64> { m.iter().flatten().map(|x| x.to_bits()).collect() };
    for _ in 0..5 {
        let (q, v, tau) = four_states(&mut rng);
        let (qb, vb, tb): ([f64x4; 7], [f64x4; 7], [f64x4; 7]) = (pack(&q), pack(&v), pack(&tau));
        let batch = PandaCompact.forward_dynamics_jacobian_as(&qb, &vb, &tb);
        for s in 0..4 {
            let f =
                PandaCompact.forward_dynamics_jacobian(&q[s].into(), &v[s].into(), &tau[s].into());
            let g = PandaCompact.forward_dynamics_jacobian_as::<f64>(&q[s], &v[s], &tau[s]);
            assert_eq!(rows(&g.d_dq), bits(&f.d_dq));
            assert_eq!(rows(&g.d_dv), bits(&f.d_dv));
            let lane: [[f64; 7]; 7] = batch.d_dq.map(|r| unpack(&r, 4)[s]);
            assert_eq!(rows(&lane), bits(&f.d_dq), "lane {s}");
            let lane: [[f64; 7]; 7] = batch.d_dv.map(|r| unpack(&r, 4)[s]);
            assert_eq!(rows(&lane), bits(&f.d_dv), "lane {s}");
        }
    }
}

/// The mass matrix by the compact composite-rigid-body loop against the unrolled CRBA,
/// and its lanes against the scalar loop bit for bit.
#[test]
fn compact_mass_matrix_equals_unrolled() {
    portable();
    use filippov::runtime::real::{f64x4, pack, unpack};
    let mut rng = Rng::new(7);
    for _ in 0..50 {
        let q: SVector<f64, 6> = rng.vector(2.5);
        let a = compact().mass_matrix(&q);
        let b = unrolled().mass_matrix(&q);
        assert_close(a.as_slice(), b.as_slice(), 1e-13, 1e-12, "oblique M");
        let q: SVector<f64, 7> = rng.vector(2.5);
        let a = PandaCompact.mass_matrix(&q);
        let b = PandaUnrolled.mass_matrix(&q);
        assert_close(a.as_slice(), b.as_slice(), 1e-13, 1e-12, "Panda M");
        let q: SVector<f64, 6> = rng.vector(2.5);
        let a = Ur5Compact.mass_matrix(&q);
        let b = Ur5Unrolled.mass_matrix(&q);
        assert_close(a.as_slice(), b.as_slice(), 1e-13, 1e-12, "UR5 M");
    }
    for _ in 0..5 {
        let qs: Vec<[f64; 7]> = (0..4).map(|_| rng.vector::<7>(2.5).into()).collect();
        let qb: [f64x4; 7] = pack(&qs);
        let m = PandaCompact.mass_matrix_as(&qb);
        for (s, q) in qs.iter().enumerate() {
            let scalar = PandaCompact.mass_matrix(&(*q).into());
            let lane: [[f64; 7]; 7] = m.map(|r| unpack(&r, 4)[s]);
            for i in 0..7 {
                for j in 0..7 {
                    assert_eq!(lane[i][j].to_bits(), scalar[(i, j)].to_bits(), "lane {s}");
                }
            }
        }
    }
}

/// The fused multiply–add twins of the compact forward dynamics and mass matrix
/// (`runtime::compact::fused`, what the `f64` kernels call where the processor has AVX2
/// and FMA), called directly, against the portable loop on `f64`: the mass matrices
/// within eight units in the last place of their largest entry, the accelerations
/// within `4 ε κ max(1, |v̇|)`, `κ` the condition number of `M`.
#[test]
#[cfg(target_arch = "x86_64")]
fn fused_twins_agree_with_the_portable_loops() {
    use filippov::runtime::compact::fused;
    if !filippov::runtime::numerics::fused::available() {
        eprintln!("this processor has no AVX2 and FMA: no fused twins to compare");
        return;
    }
    let mut rng = Rng::new(8);
    let mut worst = (0.0f64, 0.0f64);
    let (bodies, gravity) = &PandaCompact::__FILIPPOV_TABLE;
    let nodes = &PandaCompact::__FILIPPOV_NODES;
    for _ in 0..200 {
        let q: [f64; 7] = rng.vector::<7>(2.5).into();
        let v: [f64; 7] = rng.vector::<7>(3.0).into();
        let tau: [f64; 7] = rng.vector::<7>(5.0).into();
        // SAFETY: `available` says the processor has AVX2 and FMA.
        let pairs = &PandaCompact::__FILIPPOV_PAIRS;
        let (a, m) = unsafe {
            (
                fused::forward_dynamics(nodes, bodies, *gravity, &q, &v, &tau),
                fused::mass_matrix(nodes, pairs, bodies, &q),
            )
        };
        let a0 = PandaCompact.forward_dynamics_as::<f64>(&q, &v, &tau);
        let m0 = PandaCompact.mass_matrix_as::<f64>(&q);
        let m0 = filippov::nalgebra::DMatrix::from_fn(7, 7, |i, j| m0[i][j]);
        let eig = m0.clone().symmetric_eigenvalues();
        let kappa = eig.amax() / eig.amin();
        let scale = a0.iter().fold(1.0f64, |x, y| x.max(y.abs()));
        let da = (0..7).fold(0.0f64, |x, i| x.max((a[i] - a0[i]).abs()));
        let dm = (0..49).fold(0.0f64, |x, k| {
            x.max((m[k / 7][k % 7] - m0[(k / 7, k % 7)]).abs())
        });
        worst.0 = worst.0.max(da / (f64::EPSILON * kappa * scale));
        worst.1 = worst.1.max(dm / (f64::EPSILON * m0.amax()));
    }
    eprintln!(
        "fused against portable: accelerations {:.2} ε κ, mass matrices {:.2} ε",
        worst.0, worst.1
    );
    assert!(worst.0 <= 4.0, "accelerations differ by {} ε κ", worst.0);
    assert!(worst.1 <= 8.0, "mass matrices differ by {} ε", worst.1);
}

/// The compact kernels' lanes twins (`runtime::compact::fused::forward_dynamics_lanes` and
/// `mass_matrix_lanes`, what the generic kernels call on `f64x4` where the processor has
/// AVX2 and FMA), called directly on four random states: each lane is the fused `f64`
/// twin bit for bit.
#[test]
#[cfg(target_arch = "x86_64")]
fn fused_lanes_are_the_fused_scalar_twin_bit_for_bit() {
    use filippov::runtime::compact::fused;
    use filippov::runtime::numerics::fused_lanes::F64x4;
    if !filippov::runtime::numerics::fused::available() {
        eprintln!("this processor has no AVX2 and FMA: no fused twins to compare");
        return;
    }
    let (bodies, gravity) = &PandaCompact::__FILIPPOV_TABLE;
    let nodes = &PandaCompact::__FILIPPOV_NODES;
    let lanes = |x: &[[f64; 7]]| -> [F64x4; 7] {
        std::array::from_fn(|k| F64x4(std::array::from_fn(|l| x[l][k])))
    };
    let mut rng = Rng::new(11);
    for _ in 0..50 {
        let (q, v, tau) = four_states(&mut rng);
        // SAFETY: `available` says the processor has AVX2 and FMA.
        let out = unsafe {
            fused::forward_dynamics_lanes(
                nodes,
                &PandaCompact::__FILIPPOV_TABLE_LANES,
                *gravity,
                &lanes(&q),
                &lanes(&v),
                &lanes(&tau),
            )
        };
        let pairs = &PandaCompact::__FILIPPOV_PAIRS;
        let m4 = unsafe {
            fused::mass_matrix_lanes(
                nodes,
                pairs,
                &PandaCompact::__FILIPPOV_TABLE_LANES,
                &lanes(&q),
            )
        };
        for l in 0..4 {
            let one =
                unsafe { fused::forward_dynamics(nodes, bodies, *gravity, &q[l], &v[l], &tau[l]) };
            let lane: [f64; 7] = std::array::from_fn(|k| out[k].0[l]);
            assert_eq!(lane.map(f64::to_bits), one.map(f64::to_bits), "lane {l}");
            let m1 = unsafe { fused::mass_matrix(nodes, pairs, bodies, &q[l]) };
            let lane: [[f64; 7]; 7] =
                std::array::from_fn(|i| std::array::from_fn(|j| m4[i][j].0[l]));
            assert_eq!(
                lane.map(|r| r.map(f64::to_bits)),
                m1.map(|r| r.map(f64::to_bits)),
                "M, lane {l}"
            );
        }
    }
}
