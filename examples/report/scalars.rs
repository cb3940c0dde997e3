//! The URDF robots' kernels on every scalar (`emit = [generic]`), beside Pinocchio's in
//! C++ in the same run: forward dynamics and the mass matrix one state per call (`f64`)
//! and in SIMD batches (two or four states per `f64x2` or `f64x4` call, four or eight per
//! `f32x4` or `f32x8`), the `f32`
//! kernel's error against `f64`, and the dual numbers' derivatives against central
//! differences and the complex step.

use std::hint::black_box as bb;

use filippov::prelude::*;
use filippov::runtime::real::{F64Lanes, Lanes, f32x4, f32x8, f64x2, f64x4, pack};
use filippov::runtime::{Dual, Real, UnitQuat};

use super::agreement_support::Rng;
use super::complex_step::{self, Complex};
use super::config::Config;
use super::markdown::{Page, sci};
use super::timing::{Timing, in_rounds, ns_timed, program_timing};
use super::urdf::{
    Humanoid, Oblique36, PandaUrdf, ROBOTS, Solo12, ThreeLinkArm, Ur5, pinocchio_aba,
};

#[derive(Default)]
pub struct Section {
    pub page: Page,
    pub summary: Vec<String>,
}

/// A headline's robot: Pinocchio's ABA, ours one state per call, ours per state in
/// [`F64Lanes`] (the lanes the runtime recommends).
type Head<'a> = (&'a str, Timing, Timing, Timing);

/// Interleaved rounds of our timings and Pinocchio's.
const ROUNDS: usize = 3;

/// What one robot measured.
struct Measured {
    dof: usize,
    /// Forward dynamics: `f64` per call, `f64x2`, `f64x4`, `f32x4` and `f32x8` per
    /// state; Pinocchio's ABA.
    fd: [Option<Timing>; 6],
    /// Mass matrix: `f64` per call, `f64x2` and `f64x4` per state; Pinocchio's CRBA.
    m: [Option<Timing>; 4],
    /// The `f32` accelerations' largest difference from `f64` at the same (rounded)
    /// states, over the largest acceleration.
    f32_error: f64,
    /// Directional derivatives of `v̇` along random `(q, v)` directions by duals, against
    /// central differences and against the complex step: the largest difference over the
    /// scale.
    against_differences: f64,
    against_complex_step: f64,
}

/// Random states of a robot (unit quaternions where `rotations` has them).
fn states<const N: usize, const NQ: usize>(
    rng: &mut Rng,
    count: usize,
    rotations: &[(usize, usize)],
) -> Vec<([f64; NQ], [f64; N], [f64; N])> {
    (0..count)
        .map(|_| {
            let mut q: [f64; NQ] = std::array::from_fn(|_| rng.uniform(-2.0, 2.0));
            for &(s, _) in rotations {
                let r = UnitQuat::try_new(q[s], q[s + 1], q[s + 2], q[s + 3])
                    .unwrap_or_default()
                    .coords();
                q[s..s + 4].copy_from_slice(r.as_slice());
            }
            let v = std::array::from_fn(|_| rng.uniform(-2.0, 2.0));
            let tau = std::array::from_fn(|_| rng.uniform(-5.0, 5.0));
            (q, v, tau)
        })
        .collect()
}

fn largest(x: &[f64]) -> f64 {
    x.iter().fold(0.0f64, |m, y| m.max(y.abs()))
}

/// The duals' directional derivative of `v̇` along `(dq, dv)` against central
/// differences (step ε^⅓) and the complex step, at each state: the largest differences
/// over the scale (the larger of the derivative's and the accelerations' largest entry).
fn sensitivities<S, const N: usize, const NQ: usize, const P: usize>(
    s: &S,
    rng: &mut Rng,
    at: &[([f64; NQ], [f64; N], [f64; N])],
    fd64: &impl Fn(&[f64; NQ], &[f64; N], &[f64; N]) -> [f64; N],
) -> (f64, f64)
where
    S: GenericDynamics<N, NQ, P>,
{
    let (mut cd, mut cs) = (0.0f64, 0.0f64);
    for (q, v, tau) in at {
        let dq: [f64; NQ] = std::array::from_fn(|_| rng.uniform(-1.0, 1.0));
        let dv: [f64; N] = std::array::from_fn(|_| rng.uniform(-1.0, 1.0));
        let dual = s.forward_dynamics_as::<Dual<1>>(
            &std::array::from_fn(|i| Dual {
                re: q[i],
                eps: [dq[i]],
            }),
            &std::array::from_fn(|i| Dual {
                re: v[i],
                eps: [dv[i]],
            }),
            &tau.map(Dual::constant),
        );
        let h = complex_step::H;
        let step = s.forward_dynamics_as::<Complex>(
            &std::array::from_fn(|i| Complex::new(q[i], h * dq[i])),
            &std::array::from_fn(|i| Complex::new(v[i], h * dv[i])),
            &tau.map(Complex::cst),
        );
        let e = f64::EPSILON.cbrt();
        let shifted = |k: f64| {
            fd64(
                &std::array::from_fn(|i| q[i] + k * dq[i]),
                &std::array::from_fn(|i| v[i] + k * dv[i]),
                tau,
            )
        };
        let (up, down) = (shifted(e), shifted(-e));
        let d: Vec<f64> = dual.iter().map(|x| x.eps[0]).collect();
        let scale = largest(&d).max(largest(&dual.map(|x| x.re)));
        for i in 0..N {
            cd = cd.max((d[i] - (up[i] - down[i]) / (2.0 * e)).abs() / scale);
            cs = cs.max((d[i] - step[i].im / h).abs() / scale);
        }
    }
    (cd, cs)
}

/// One robot: timings in interleaved rounds with Pinocchio's programs, and accuracy.
fn measure<S, const N: usize, const NQ: usize, const P: usize>(
    config: &Config,
    robot: &str,
    s: &S,
    rotations: &[(usize, usize)],
    fd64: impl Fn(&[f64; NQ], &[f64; N], &[f64; N]) -> [f64; N],
    m64: impl Fn(&[f64; NQ]) -> SMatrix<f64, N, N>,
) -> Measured
where
    S: GenericDynamics<N, NQ, P>,
{
    let mut rng = Rng::new(2032);
    let at = states::<N, NQ>(&mut rng, 8, rotations);
    // The first `L::LANES` states in the lanes of `L`.
    fn batch<L: Lanes, const N: usize, const NQ: usize>(
        at: &[([f64; NQ], [f64; N], [f64; N])],
    ) -> ([L; NQ], [L; N], [L; N]) {
        let at = &at[..L::LANES];
        (
            pack(&at.iter().map(|x| x.0).collect::<Vec<_>>()),
            pack(&at.iter().map(|x| x.1).collect::<Vec<_>>()),
            pack(&at.iter().map(|x| x.2).collect::<Vec<_>>()),
        )
    }
    let (q2, v2, t2) = batch::<f64x2, N, NQ>(&at);
    let (q4, v4, t4) = batch::<f64x4, N, NQ>(&at);
    let (q4f, v4f, t4f) = batch::<f32x4, N, NQ>(&at);
    let (q8, v8, t8) = batch::<f32x8, N, NQ>(&at);
    let (q, v, tau) = at[0];
    let (reps, calls) = (config.repeats, config.kernel_calls);
    let pin = pinocchio_aba(&config.out_dir, robot);
    let program = |alg: &str, key: &str| {
        pin.as_ref()
            .and_then(|(bin, model)| program_timing(bin, &[model.as_os_str(), alg.as_ref()], key))
    };
    // Per state: a call's time over its lanes.
    let per_state = |lanes: usize, t: Timing| Some(t.scaled(1.0 / lanes as f64));
    let t = in_rounds(
        ROUNDS,
        &mut [
            &mut || Some(ns_timed(reps, calls, || fd64(bb(&q), bb(&v), bb(&tau)))),
            &mut || {
                let t = ns_timed(reps, calls, || {
                    s.forward_dynamics_as(bb(&q2), bb(&v2), bb(&t2))
                });
                per_state(2, t)
            },
            &mut || {
                let t = ns_timed(reps, calls, || {
                    s.forward_dynamics_as(bb(&q4), bb(&v4), bb(&t4))
                });
                per_state(4, t)
            },
            &mut || {
                let t = ns_timed(reps, calls, || {
                    s.forward_dynamics_as(bb(&q4f), bb(&v4f), bb(&t4f))
                });
                per_state(4, t)
            },
            &mut || {
                let t = ns_timed(reps, calls, || {
                    s.forward_dynamics_as(bb(&q8), bb(&v8), bb(&t8))
                });
                per_state(8, t)
            },
            &mut || program("aba", "aba_ns"),
            &mut || Some(ns_timed(reps, calls, || m64(bb(&q)))),
            &mut || per_state(2, ns_timed(reps, calls, || s.mass_matrix_as(bb(&q2)))),
            &mut || per_state(4, ns_timed(reps, calls, || s.mass_matrix_as(bb(&q4)))),
            &mut || program("crba", "crba_ns"),
        ],
    );
    // f32: the lanes of f32x8 (each the f32 kernel bit for bit) against f64 at the same
    // states rounded to f32, so that the difference is the kernel's arithmetic alone.
    let a8 = s.forward_dynamics_as(&q8, &v8, &t8);
    let mut f32_error = 0.0f64;
    for (l, _) in at.iter().enumerate() {
        let lane = |x: &[f32x8], k: usize| x[k].lane(l);
        let q: [f64; NQ] = std::array::from_fn(|k| lane(&q8, k));
        let v: [f64; N] = std::array::from_fn(|k| lane(&v8, k));
        let tau: [f64; N] = std::array::from_fn(|k| lane(&t8, k));
        let exact = fd64(&q, &v, &tau);
        let scale = largest(&exact);
        for k in 0..N {
            f32_error = f32_error.max((a8[k].lane(l) - exact[k]).abs() / scale);
        }
    }
    let (against_differences, against_complex_step) = sensitivities(s, &mut rng, &at, &fd64);
    Measured {
        dof: N,
        fd: [t[0], t[1], t[2], t[3], t[4], t[5]],
        m: [t[6], t[7], t[8], t[9]],
        f32_error,
        against_differences,
        against_complex_step,
    }
}

/// A fixed-base robot's `f64` forward dynamics and mass matrix on arrays.
#[allow(clippy::type_complexity)]
fn tree_kernels<S: Mechanism<N>, const N: usize>(
    s: &S,
) -> (
    impl Fn(&[f64; N], &[f64; N], &[f64; N]) -> [f64; N] + '_,
    impl Fn(&[f64; N]) -> SMatrix<f64, N, N> + '_,
) {
    (
        move |q, v, t| {
            s.forward_dynamics(&(*q).into(), &(*v).into(), &(*t).into())
                .into()
        },
        move |q| s.mass_matrix(&(*q).into()),
    )
}

/// A free-base robot's `f64` forward dynamics and mass matrix on arrays.
#[allow(clippy::type_complexity)]
fn free_kernels<S: LieMechanism<N, NQ>, const N: usize, const NQ: usize>(
    s: &S,
) -> (
    impl Fn(&[f64; NQ], &[f64; N], &[f64; N]) -> [f64; N] + '_,
    impl Fn(&[f64; NQ]) -> SMatrix<f64, N, N> + '_,
) {
    (
        move |q, v, t| {
            LieMechanism::forward_dynamics(s, &(*q).into(), &(*v).into(), &(*t).into()).into()
        },
        move |q| LieMechanism::mass_matrix(s, &(*q).into()),
    )
}

pub fn scalars(config: &Config) -> Section {
    let mut page = Page::empty();
    let mut summary = Vec::new();
    let mut table = Vec::new();
    let mut heads = Vec::new();
    for robot in &ROBOTS {
        macro_rules! tree {
            ($s:ident, $n:literal) => {{
                let (fd, m) = tree_kernels::<_, $n>(&$s);
                measure::<_, $n, $n, 0>(config, robot.name, &$s, &[], fd, m)
            }};
        }
        macro_rules! free {
            ($s:ident, $n:literal, $nq:literal) => {{
                let (fd, m) = free_kernels::<_, $n, $nq>(&$s);
                let rotations = <$s as LieMechanism<$n, $nq>>::ROTATIONS;
                measure::<_, $n, $nq, 0>(config, robot.name, &$s, rotations, fd, m)
            }};
        }
        let m = match robot.name {
            "panda" => tree!(PandaUrdf, 7),
            "ur5" => tree!(Ur5, 6),
            "three_link_arm" => tree!(ThreeLinkArm, 3),
            "oblique36" => tree!(Oblique36, 36),
            "solo12" => free!(Solo12, 18, 19),
            _ => free!(Humanoid, 35, 36),
        };
        let show = |t: &Option<Timing>| t.map_or("—".into(), |t| t.show(0));
        let ratio = |peer: &Option<Timing>, ours: &Option<Timing>| match (peer, ours) {
            (Some(p), Some(o)) => p.ratio_to(o, 1),
            _ => "—".into(),
        };
        // The lanes the runtime recommends: f64x4 on x86-64, f64x2 elsewhere without AVX.
        let own = if F64Lanes::LANES == 2 { 1 } else { 2 };
        let (aba, crba) = (&m.fd[5], &m.m[3]);
        table.push(vec![
            format!(
                "{}{}",
                robot.name,
                if robot.free_base { " (free base)" } else { "" }
            ),
            m.dof.to_string(),
            show(&m.fd[0]),
            show(&m.fd[1]),
            show(&m.fd[2]),
            show(&m.fd[3]),
            show(&m.fd[4]),
            show(aba),
            format!("{} / {}", ratio(aba, &m.fd[0]), ratio(aba, &m.fd[own])),
            show(&m.m[0]),
            show(&m.m[1]),
            show(&m.m[2]),
            show(crba),
            format!("{} / {}", ratio(crba, &m.m[0]), ratio(crba, &m.m[own])),
            sci(m.f32_error),
            format!(
                "{} / {}",
                sci(m.against_differences),
                sci(m.against_complex_step)
            ),
        ]);
        summary.push(format!(
            "`{}` kernels on other scalars: FD {} ns per state in {} batches ({} in f64x4, {} in f32x4) against {} ns one at a time; f32 within {} of f64; dual derivatives within {} of central differences and {} of the complex step{}",
            robot.name,
            show(&m.fd[own]),
            lanes_name(),
            show(&m.fd[2]),
            show(&m.fd[3]),
            show(&m.fd[0]),
            sci(m.f32_error),
            sci(m.against_differences),
            sci(m.against_complex_step),
            match (aba, &m.fd[own]) {
                (Some(p), Some(o)) => format!("; Pinocchio's ABA / our {} per state {}", lanes_name(), p.ratio_to(o, 1)),
                _ => String::new(),
            }
        ));
        if let (Some(p), Some(one), Some(batch)) = (*aba, m.fd[0], m.fd[own]) {
            heads.push((robot.name, p, one, batch));
        }
    }
    if !heads.is_empty() {
        let list = |f: &dyn Fn(&Head) -> String| heads.iter().map(f).collect::<Vec<_>>().join("; ");
        super::markdown::headline(
            &format!(
                "Forward dynamics per state in SIMD batches ({}, {} states per call, `F64Lanes`) against Pinocchio's ABA in C++",
                lanes_name(),
                F64Lanes::LANES
            ),
            format!(
                "{} ns per state",
                list(&|h| format!("{} {}", h.0, h.3.show(0)))
            ),
            format!("{} ns", list(&|h| format!("{} {}", h.0, h.1.show(0)))),
            list(&|h| format!("{} {}", h.0, h.1.ratio_to(&h.3, 1))),
            "ns per state, median of 3 interleaved rounds (min–max over their batches), both in this run, both built for the same x86-64 target; ratio Pinocchio / ours",
        );
    }
    page.h2("Kernels on every scalar and in batches");
    page.para(&format!(
        "The URDF robots' kernels generic over their scalar (`emit = [generic]`): forward dynamics (FD) and the \
         mass matrix (M) one `f64` state per call, and in SIMD batches of two and four states (`f64x2`, \
         `f64x4`) and, for FD, four and eight (`f32x4`, `f32x8`), as ns per state; Pinocchio's C++ `aba` and \
         `crba` on the model it built from the same file, timed beside ours in three interleaved rounds, with \
         the ratios Pinocchio / ours (one state per call / per state in `{}`, the lanes the runtime \
         recommends, `runtime::real::F64Lanes`). On `f64x4` the forward dynamics and mass matrix call \
         their fused twins where the processor has AVX2 and FMA (`runtime::numerics::fused_lanes`): four \
         states in one AVX2 register, in a default build. Other lanes wider than the build's register \
         (`f32x8` without AVX; `f64x4` without the twins) run each operation as two halves. f32: the largest difference of the `f32` \
         accelerations from `f64` at the same eight states (rounded to `f32` first), over the largest \
         acceleration. Sensitivities: the derivative of v̇ along a random direction of (q, v) by dual numbers \
         (`Dual<1>`), against central differences (step ε^⅓) and against the complex step (h = 1e-100), the \
         largest difference over the larger of the derivative's and the accelerations' largest entry, over eight \
         states.",
        lanes_name()
    ));
    let ratio_head = |k: &str| format!("{k} / ours (f64 / {})", lanes_name());
    page.table(
        &[
            "robot",
            "dof",
            "FD f64 ns",
            "FD f64x2 ns/state",
            "FD f64x4 ns/state",
            "FD f32x4 ns/state",
            "FD f32x8 ns/state",
            "Pinocchio ABA ns",
            &ratio_head("ABA"),
            "M f64 ns",
            "M f64x2 ns/state",
            "M f64x4 ns/state",
            "Pinocchio CRBA ns",
            &ratio_head("CRBA"),
            "f32 error",
            "duals vs differences / complex step",
        ],
        &table,
    );
    Section { page, summary }
}

/// The name of [`F64Lanes`] in this build.
pub(super) fn lanes_name() -> &'static str {
    if F64Lanes::LANES == 2 {
        "f64x2"
    } else {
        "f64x4"
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Four states in `f64x4` lanes, lane by lane, against the `f64` kernels bit for bit
    /// (forward dynamics and mass matrix). With the fused twins on (this binary leaves
    /// them on; they are on where the processor has AVX2 and FMA) that compares the
    /// lanes' twins with the `f64` twins, including the chunked twins of the free-base
    /// robots' kernels, which are too long to be emitted whole; without them, the
    /// portable kernels.
    fn lanes_match<S, const N: usize, const NQ: usize, const P: usize>(
        name: &str,
        s: &S,
        rotations: &[(usize, usize)],
        fd64: impl Fn(&[f64; NQ], &[f64; N], &[f64; N]) -> [f64; N],
        m64: impl Fn(&[f64; NQ]) -> SMatrix<f64, N, N>,
    ) where
        S: GenericDynamics<N, NQ, P>,
    {
        let mut rng = Rng::new(2033);
        for _ in 0..5 {
            let at = states::<N, NQ>(&mut rng, 4, rotations);
            let q: [f64x4; NQ] = pack(&at.iter().map(|x| x.0).collect::<Vec<_>>());
            let v: [f64x4; N] = pack(&at.iter().map(|x| x.1).collect::<Vec<_>>());
            let t: [f64x4; N] = pack(&at.iter().map(|x| x.2).collect::<Vec<_>>());
            let a = s.forward_dynamics_as(&q, &v, &t);
            let m = s.mass_matrix_as(&q);
            for (l, (q, v, t)) in at.iter().enumerate() {
                let (sa, sm) = (fd64(q, v, t), m64(q));
                for i in 0..N {
                    assert_eq!(
                        a[i].lane(l).to_bits(),
                        sa[i].to_bits(),
                        "{name}: v̇[{i}], lane {l}"
                    );
                    for j in 0..N {
                        assert_eq!(
                            m[i][j].lane(l).to_bits(),
                            sm[(i, j)].to_bits(),
                            "{name}: M[{i}][{j}], lane {l}"
                        );
                    }
                }
            }
        }
    }

    #[test]
    fn f64x4_lanes_are_the_f64_kernels_bit_for_bit() {
        macro_rules! tree {
            ($s:ident, $n:literal) => {{
                let (fd, m) = tree_kernels::<_, $n>(&$s);
                lanes_match::<_, $n, $n, 0>(stringify!($s), &$s, &[], fd, m)
            }};
        }
        macro_rules! free {
            ($s:ident, $n:literal, $nq:literal) => {{
                let (fd, m) = free_kernels::<_, $n, $nq>(&$s);
                let rotations = <$s as LieMechanism<$n, $nq>>::ROTATIONS;
                lanes_match::<_, $n, $nq, 0>(stringify!($s), &$s, rotations, fd, m)
            }};
        }
        tree!(PandaUrdf, 7);
        tree!(Ur5, 6);
        tree!(ThreeLinkArm, 3);
        tree!(Oblique36, 36);
        free!(Solo12, 18, 19);
        free!(Humanoid, 35, 36);
    }
}
