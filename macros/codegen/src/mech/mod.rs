//! Mechanics on the symbolic DAG: every quantity the derive emits, as graph nodes.
//!
//! Where things are made:
//! - joint transforms and motion subspaces: [`kinematics`];
//! - mass matrix `M(q)`: [`crba`] (composite-rigid-body algorithm);
//! - inverse dynamics and bias forces: [`rnea`] (recursive Newton–Euler);
//! - the loads that set bearing friction's limits: [`bearing`] (the forces RNEA
//!   transmits across the joints);
//! - gravity forces: [`gravity`] (composite first moments);
//! - springs between two points: [`point_springs`] (their potential, differentiated);
//! - Christoffel symbols and the Coriolis matrix: [`christoffel`] (derivatives of `M`
//!   along the local exponential coordinates of [`chart`]);
//! - forward dynamics `M⁻¹ (τ + τ_p − bias)`, its Jacobian `∂v̇/∂x = −M⁻¹ ∂ID/∂x` at
//!   `a = v̇` and `M⁻¹` ([`Kernels::build`]), each solving with `M` either by [`ltdl`]
//!   (sparse `LᵀDL` of the CRBA mass matrix) or by [`aba`] (the articulated-body
//!   algorithm, unrolled per link), whichever emits fewer operations for the scene
//!   (`#[mechanism(forward_dynamics = auto | crba | aba)]`, see `Solver`);
//! - world poses and Jacobians of bodies and `#[frame]`s: [`frames`];
//! - the constraints of loop joints, `Φ`, `G = ∂Φ/∂q` and `γ = −Ġ v`: [`loops`];
//! - contacts' gaps, normal and tangential Jacobians and `γ`: [`contacts`].

pub mod aba;
pub mod bearing;
pub mod chart;
pub mod christoffel;
pub mod compact;
pub mod contacts;
pub mod crba;
pub mod frames;
pub mod gravity;
pub mod kinematics;
pub mod loops;
pub mod ltdl;
pub mod point_springs;
pub mod rnea;
pub mod spatial;

use crate::model::{Algorithm, Model};
use crate::sym::{FastMap, Graph, Id, Input, InputKind};
use spatial::{Inertia, dot3};

/// All outputs of a scene, as nodes of one shared graph.
pub struct Kernels {
    pub graph: Graph,
    pub dof: usize,
    pub mass: Vec<Vec<Id>>,
    /// `christoffel[i][j][k] = c_ijk`; built only when the scene asks for the
    /// Christoffel symbols or the Coriolis matrix (empty otherwise).
    pub christoffel: Vec<Vec<Vec<Id>>>,
    /// Built only when asked for (empty otherwise).
    pub coriolis: Vec<Vec<Id>>,
    pub gravity: Vec<Id>,
    pub bias: Vec<Id>,
    pub passive: Vec<Id>,
    pub inverse: Vec<Id>,
    pub forward: Vec<Id>,
    /// `v̇` as the Jacobian's kernel computes it (it returns both): the same nodes as
    /// `forward` unless the two kernels were built with different algorithms.
    pub jacobian_forward: Vec<Id>,
    /// The algorithm each of forward dynamics and its Jacobian was built with.
    pub algorithms: [Algorithm; 2],
    pub jac_q: Vec<Vec<Id>>,
    pub jac_v: Vec<Vec<Id>>,
    /// `(kinetic, potential)`, built only when the energies are asked for.
    pub energy: Option<(Id, Id)>,
    /// `M⁻¹` (row-major), built only for scenes with non-smooth elements (their Delassus
    /// operator is its submatrix).
    pub inverse_mass: Option<Vec<Vec<Id>>>,
    /// For scenes with non-smooth elements: see [`ElementKernels`].
    pub elements: Option<ElementKernels>,
    /// The load-dependent limits `c |F_⊥(q, v, a)|` of the bearing frictions, in element
    /// order; empty where the scene has none.
    pub bearings: Vec<Id>,
    /// Poses and Jacobians of every body and declared frame; built only when the
    /// scene asks for `kinematics` (or declares a frame).
    pub frames: Vec<frames::FrameKernel>,
    /// The constraints of the loop joints and their forces; only for scenes that
    /// declare some (their `forward` is then the constrained system's).
    pub loops: Option<LoopOutputs>,
    /// Gaps, normal and tangential Jacobians and `γ` of the contacts; only for scenes
    /// that declare some.
    pub contacts: Option<contacts::ContactKernels>,
    /// For scenes whose forward dynamics and its Jacobian run as compact loops
    /// ([`Algorithm::Compact`]): the table and the forces. `forward` and the Jacobian's
    /// nodes are then empty.
    pub compact: Option<CompactKernels>,
    /// Where the forward dynamics' operations go: its parts in the order they are
    /// computed, each the nodes it produces ([`Graph::count_parts`](crate::sym::Graph)
    /// counts each part's share once, the earliest part first). Empty for compact and
    /// loop-constrained forward dynamics.
    pub forward_parts: Vec<(&'static str, Vec<Id>)>,
}

/// What the compact kernels read: the table of the tree and the generalised forces.
pub struct CompactKernels {
    pub tree: compact::Tree,
    /// `τ + τ_p`, `None` when the scene has no springs or dampers (then `τ`).
    pub forces: Option<Vec<Id>>,
}

/// Under `forward_dynamics = auto`, a tree the compact kernels take gets them when its
/// unrolled forward dynamics would take more operations than this in all, and more than
/// [`COMPACT_PER_JOINT`] per joint (geometry that does not fold). Measured in the
/// report's scaling section (docs/measurements.md, "Compact kernels"): on random oblique
/// trees the compact forward dynamics was faster from 7 joints on, but its Jacobian
/// (duals) 8× slower at 15 joints (12,373 operations unrolled) and 1.7× slower at 30
/// (26,890), where it built in 9 s against 113 s; planar chains, which fold to about 110
/// operations per joint, stayed faster unrolled up to 50 joints.
pub const COMPACT_ABOVE: usize = 20_000;
/// See [`COMPACT_ABOVE`].
pub const COMPACT_PER_JOINT: usize = 300;

/// What a scene with loop joints emits besides its constrained forward dynamics.
pub struct LoopOutputs {
    pub constraints: loops::LoopKernels,
    /// The constraint forces `λ` beside `forward` (same nodes' algorithm).
    pub lambda: Vec<Id>,
}

/// What the derive emits for non-smooth elements besides their parameters.
pub struct ElementKernels {
    /// `W = J M⁻¹ Jᵀ` (row-major, `K × K`).
    pub delassus: Vec<Vec<Id>>,
    /// DAE residual of the momentum balance `M a + C v + g − τ − τ_p + Σ f_e e_c`.
    pub momentum_residual: Vec<Id>,
    /// Two per element: dash-pot `[v_c, f_crit² − f_e²]` (slip→stick, stick→slip); stop
    /// `[gap, f_e]` (contact, release), the gap positive on the admissible side.
    pub switching: Vec<Id>,
}

impl Kernels {
    pub fn build(model: &Model) -> Kernels {
        let mut g = Graph::new();
        let n = model.dof();
        // The configuration slot of each coordinate (its `q` on one-dof joints).
        let q: Vec<Id> = (0..n)
            .map(|i| g.input(InputKind::Q, model.slot_of(i)))
            .collect();
        let chart = chart::Chart::new(model);
        let v: Vec<Id> = (0..n).map(|i| g.input(InputKind::V, i)).collect();
        let a: Vec<Id> = (0..n).map(|i| g.input(InputKind::A, i)).collect();
        let tau: Vec<Id> = (0..n).map(|i| g.input(InputKind::Tau, i)).collect();
        let zeros = vec![g.zero(); n];
        let gravity_vec = model.gravity.as_ref().map(|gv| {
            [
                gv[0].lower(&mut g),
                gv[1].lower(&mut g),
                gv[2].lower(&mut g),
            ]
        });

        let kin = kinematics::kinematics(&mut g, model);
        let inertia = crba::link_inertias(&mut g, model);
        let composite = crba::composite_inertias(&mut g, model, &kin, &inertia);
        let mass = crba::mass_matrix(&mut g, model, &kin, &composite);
        // The Christoffel symbols are O(n³) expressions no integrator calls: most of
        // the code of a long chain when emitted. Built only on request.
        let emit = model.emit;
        let (christoffel, coriolis) = if emit.christoffel || emit.coriolis {
            let christoffel = christoffel::christoffel_symbols(&mut g, &chart, &mass);
            let mut coriolis = christoffel::coriolis(&mut g, &christoffel, &v);
            christoffel::lie_bracket_term(&mut g, &chart, &mass, &v, &mut coriolis);
            (christoffel, coriolis)
        } else {
            (Vec::new(), Vec::new())
        };

        // RNEA without gravity plus gravity from composite first moments (see
        // [`gravity`] for why gravity is not a base acceleration here).
        let gravity = gravity::gravity_forces(&mut g, model, &kin, &composite, gravity_vec);
        let coriolis_v = rnea::rnea(&mut g, model, &kin, None, &v, &zeros);
        let bias: Vec<Id> = (0..n).map(|i| g.add(coriolis_v[i], gravity[i])).collect();
        let mut passive = passive_forces(&mut g, model, &q, &v);
        // Springs between two points: their forces −∂U/∂q.
        let point_potential = point_springs::potential(&mut g, model, &kin);
        if let Some(u) = point_potential {
            for (k, p) in passive.iter_mut().enumerate() {
                let du = chart.derivative(&mut g, u, k);
                *p = g.sub(*p, du);
            }
        }
        let rnea_a = rnea::rnea(&mut g, model, &kin, None, &v, &a);
        let inverse: Vec<Id> = (0..n)
            .map(|i| {
                let t = g.add(rnea_a[i], gravity[i]);
                g.sub(t, passive[i])
            })
            .collect();

        // Forward dynamics M v̇ = τ + τ_p − bias, its Jacobian and M⁻¹: each solves
        // with M, by either algorithm (see [`Solver`]).
        let solver = Solver::new(&mut g, model, &kin, &inertia, &mass);
        let rhs: Vec<Id> = (0..n)
            .map(|i| {
                let t = g.add(tau[i], passive[i]);
                g.sub(t, bias[i])
            })
            .collect();
        // For the articulated-body algorithm, gravity is the base's acceleration `−γ`
        // (no composite inertias needed) and the right-hand side keeps only `C v`.
        let base = gravity_vec.map(|gv| spatial::Motion {
            w: spatial::v3_zero(&mut g),
            v: gv.map(|c| g.neg(c)),
        });
        let rhs_aba: Vec<Id> = (0..n)
            .map(|i| {
                let t = g.add(tau[i], passive[i]);
                g.sub(t, coriolis_v[i])
            })
            .collect();
        let solve_forward = |g: &mut Graph, s: Which<'_, '_>| match s {
            Which::Crba(_) => s.solve(g, &rhs, None),
            Which::Aba(_) => s.solve(g, &rhs_aba, base),
        };
        // With loop joints, forward dynamics is that of the constrained system (theory
        // §5): the free accelerations corrected by the constraint forces `λ`.
        let loop_k =
            (!model.loops.is_empty()).then(|| loops::loop_constraints(&mut g, model, &kin));
        let compact_ok = model.compact_unsupported().is_none();
        let (forward, forward_algorithm, loop_lambda) = match &loop_k {
            None if model.algorithm == Algorithm::Compact => {
                (Vec::new(), Algorithm::Compact, Vec::new())
            }
            None => {
                let (f, used) = solver.choose(&mut g, solve_forward);
                let ops = g.count_ops(&f).total();
                if model.algorithm == Algorithm::Auto
                    && compact_ok
                    && ops > COMPACT_ABOVE
                    && ops > COMPACT_PER_JOINT * n.max(1)
                {
                    (Vec::new(), Algorithm::Compact, Vec::new())
                } else {
                    (f, used, Vec::new())
                }
            }
            Some(lk) => {
                let (out, used) = solver.choose(&mut g, |g, s| {
                    let free = solve_forward(g, s);
                    let c = loops::Constrained::build(g, lk, free, &mut |g, b| s.solve(g, b, None));
                    c.acceleration.into_iter().chain(c.lambda).collect()
                });
                (out[..n].to_vec(), used, out[n..].to_vec())
            }
        };
        // With loop joints, the constrained system's: `P = M⁻¹ − Y A⁻¹ Yᵀ`, the
        // response to a unit force that the loops let through (column k: the augmented
        // solve with `r₁ = e_k`, `r₂ = 0`), so that the elements' Delassus operator and
        // impulses respect the loops (`G P = 0`).
        let inverse_mass = (!model.elements.is_empty()).then(|| {
            let mut constrained: [Option<loops::Constrained>; 2] = [None, None];
            let (cols, _) = solver.choose_columns(&mut g, n, |g, s, k| {
                let e: Vec<Id> = (0..n)
                    .map(|i| g.constant(if i == k { 1.0 } else { 0.0 }))
                    .collect();
                let Some(lk) = &loop_k else {
                    return s.solve(g, &e, None);
                };
                let slot = usize::from(matches!(s, Which::Aba(_)));
                if constrained[slot].is_none() {
                    let free = solve_forward(g, s);
                    constrained[slot] =
                        Some(loops::Constrained::build(g, lk, free, &mut |g, b| {
                            s.solve(g, b, None)
                        }));
                }
                let c = constrained[slot].as_ref().expect("built above");
                let zeros = vec![g.zero(); lk.rows()];
                c.column(g, lk, &e, &zeros, &mut |g, b| s.solve(g, b, None))
            });
            transpose_cols(&cols)
        });

        let forward_parts = if loop_k.is_none() {
            let kinematics: Vec<Id> = kin
                .xform
                .iter()
                .flat_map(|x| {
                    x.e.iter()
                        .flatten()
                        .chain(&x.r)
                        .copied()
                        .collect::<Vec<_>>()
                })
                .collect();
            let factor = solver.factor_nodes(forward_algorithm);
            match forward_algorithm {
                Algorithm::Crba => vec![
                    ("kinematics", kinematics),
                    (
                        "mass matrix (CRBA)",
                        mass.iter().flatten().copied().collect(),
                    ),
                    ("bias forces (RNEA, gravity, springs)", rhs.clone()),
                    ("factorisation (LᵀDL)", factor),
                    ("solves", forward.clone()),
                ],
                Algorithm::Aba => vec![
                    ("kinematics", kinematics),
                    ("articulated inertias", factor),
                    ("velocity terms (RNEA, springs)", rhs_aba.clone()),
                    ("solves (two passes)", forward.clone()),
                ],
                _ => Vec::new(),
            }
        } else {
            Vec::new()
        };

        let compact = (forward_algorithm == Algorithm::Compact).then(|| {
            let tree = compact::tree(&mut g, model, &inertia);
            let forces = passive
                .iter()
                .any(|&p| !g.is_zero(p))
                .then(|| (0..n).map(|i| g.add(tau[i], passive[i])).collect());
            CompactKernels { tree, forces }
        });
        // The compact kernels' Jacobian runs dual numbers through their loops (on any
        // scalar): no symbolic one.
        let symbolic_jacobian = compact.is_none();

        // ∂v̇/∂x = −M⁻¹ ∂ID(q, v, a)/∂x evaluated at a = v̇: differentiate inverse
        // dynamics with a held fixed (cheap: RNEA is linear-size), then substitute v̇
        // as the same algorithm computes it (the Jacobian's code computes v̇ too).
        let mut d_x: Vec<Vec<Id>> = Vec::with_capacity(2 * n);
        let kinds: &[InputKind] = if symbolic_jacobian {
            &[InputKind::Q, InputKind::V]
        } else {
            &[]
        };
        for &kind in kinds {
            for k in 0..n {
                let x = Input {
                    kind,
                    index: k as u16,
                };
                let col = (0..n)
                    .map(|i| match kind {
                        InputKind::Q => chart.derivative(&mut g, inverse[i], k),
                        _ => g.diff(inverse[i], x),
                    })
                    .collect();
                d_x.push(col);
            }
        }
        // One kernel returns v̇ (column 0) and both halves of its Jacobian, so one
        // algorithm for all. The substitution's memo is kept per algorithm.
        let mut substitutions: [Option<(FastMap<Id, Id>, FastMap<Id, Id>)>; 2] = [None, None];
        let mut constrained: [Option<loops::Constrained>; 2] = [None, None];
        let columns = if symbolic_jacobian { 2 * n + 1 } else { 0 };
        let (mut cols, jacobian_algorithm) = solver.choose_columns(&mut g, columns, |g, s, k| {
            if let Some(lk) = &loop_k {
                // The constrained system's: v̇ = a, and the columns of the augmented
                // system's derivative (see `loops::Constrained::column`).
                let slot = usize::from(matches!(s, Which::Aba(_)));
                if constrained[slot].is_none() {
                    let free = solve_forward(g, s);
                    let c = loops::Constrained::build(g, lk, free, &mut |g, b| s.solve(g, b, None));
                    substitutions[slot] = Some((
                        a.iter().copied().zip(c.acceleration.clone()).collect(),
                        FastMap::default(),
                    ));
                    constrained[slot] = Some(c);
                }
                let (Some(c), Some((subst, memo))) = (&constrained[slot], &mut substitutions[slot])
                else {
                    unreachable!("built above")
                };
                if k == 0 {
                    return c.acceleration.clone();
                }
                let x = if k <= n {
                    Input {
                        kind: InputKind::Q,
                        index: (k - 1) as u16,
                    }
                } else {
                    Input {
                        kind: InputKind::V,
                        index: (k - 1 - n) as u16,
                    }
                };
                let m = lk.rows();
                let on_q = x.kind == InputKind::Q;
                let r1: Vec<Id> = (0..n)
                    .map(|i| {
                        let mut t = g.substitute(d_x[k - 1][i], subst, memo);
                        if on_q {
                            for r in 0..m {
                                let dg = g.diff(lk.jacobian[r * n + i], x);
                                let f = g.mul(dg, c.lambda[r]);
                                t = g.sub(t, f);
                            }
                        }
                        g.neg(t)
                    })
                    .collect();
                let r2: Vec<Id> = (0..m)
                    .map(|r| {
                        let mut t = g.zero();
                        if on_q {
                            for i in 0..n {
                                let dg = g.diff(lk.jacobian[r * n + i], x);
                                let f = g.mul(dg, c.acceleration[i]);
                                t = g.add(t, f);
                            }
                        }
                        let dgamma = g.diff(lk.gamma[r], x);
                        let t = g.sub(t, dgamma);
                        g.neg(t)
                    })
                    .collect();
                return c.column(g, lk, &r1, &r2, &mut |g, b| s.solve(g, b, None));
            }
            if k == 0 {
                return solve_forward(g, s);
            }
            let slot = usize::from(matches!(s, Which::Aba(_)));
            let (subst, memo) = substitutions[slot].get_or_insert_with(|| {
                let fwd = solve_forward(g, s);
                (a.iter().copied().zip(fwd).collect(), FastMap::default())
            });
            let rhs: Vec<Id> = d_x[k - 1]
                .iter()
                .map(|&d| {
                    let t = g.substitute(d, subst, memo);
                    g.neg(t)
                })
                .collect();
            s.solve(g, &rhs, None)
        });
        let (jacobian_forward, jacobian_algorithm) = if symbolic_jacobian {
            (cols.remove(0), jacobian_algorithm)
        } else {
            (Vec::new(), Algorithm::Compact)
        };
        // cols[k][i] = ∂v̇_i/∂x_k → rows
        let (jac_q, jac_v) = if symbolic_jacobian {
            (transpose_cols(&cols[..n]), transpose_cols(&cols[n..]))
        } else {
            (Vec::new(), Vec::new())
        };

        // Energies: T = ½ vᵀ M v; U = −gravity · (first moment of everything) + springs.
        let energy = emit.energy.then(|| {
            let mut kinetic = g.zero();
            for i in 0..n {
                let mv = g.dot(&mass[i], &v);
                let t = g.mul(v[i], mv);
                kinetic = g.add(kinetic, t);
            }
            let half = g.constant(0.5);
            kinetic = g.mul(half, kinetic);
            let mut potential = g.zero();
            if let Some(gv) = gravity_vec {
                for (i, link) in model.links.iter().enumerate() {
                    if link.parent.is_none() {
                        let world: Inertia = composite[i].to_parent(&mut g, &kin.xform[i]);
                        let w = dot3(&mut g, gv, world.h);
                        potential = g.sub(potential, w);
                    }
                }
            }
            for p in &model.potentials {
                let u = p.u.lower_var(&mut g, q[p.coordinate]);
                potential = g.add(potential, u);
            }
            for s in &model.springs {
                let k = s.k.lower(&mut g);
                let rest = s.rest.lower(&mut g);
                let d = g.sub(q[s.coordinate], rest);
                let dd = g.mul(d, d);
                let e = g.mul(k, dd);
                let e = g.mul(half, e);
                potential = g.add(potential, e);
            }
            if let Some(u) = point_potential {
                potential = g.add(potential, u);
            }
            (kinetic, potential)
        });

        let elements = inverse_mass.as_ref().map(|inv: &Vec<Vec<Id>>| {
            use crate::model::ElementKind;
            let f: Vec<Id> = (0..model.elements.len())
                .map(|e| g.input(InputKind::F, e))
                .collect();
            let delassus = model
                .elements
                .iter()
                .map(|a| {
                    model
                        .elements
                        .iter()
                        .map(|b| inv[a.coordinate][b.coordinate])
                        .collect()
                })
                .collect();
            let mut momentum_residual: Vec<Id> =
                (0..n).map(|i| g.sub(inverse[i], tau[i])).collect();
            let mut switching = Vec::new();
            for (e, el) in model.elements.iter().enumerate() {
                let c = el.coordinate;
                momentum_residual[c] = g.add(momentum_residual[c], f[e]);
                match &el.kind {
                    ElementKind::DashPot { f_crit, .. } => {
                        let fc = f_crit.lower(&mut g);
                        let fc2 = g.mul(fc, fc);
                        let f2 = g.mul(f[e], f[e]);
                        switching.push(v[c]);
                        switching.push(g.sub(fc2, f2));
                    }
                    ElementKind::Stop {
                        upper, position, ..
                    } => {
                        let l = position.lower(&mut g);
                        let gap = if *upper {
                            g.sub(l, q[c])
                        } else {
                            g.sub(q[c], l)
                        };
                        switching.push(gap);
                        switching.push(f[e]);
                    }
                }
            }
            ElementKernels {
                delassus,
                momentum_residual,
                switching,
            }
        });

        let bearings = bearing::bearing_limits(&mut g, model, &kin, gravity_vec, &v, &a);

        // Last, so that the other kernels' code reads the same with or without frames.
        let frames = if model.emit.kinematics {
            frames::frames(&mut g, model, &kin)
        } else {
            Vec::new()
        };
        let loops = loop_k.map(|lk| LoopOutputs {
            constraints: lk,
            lambda: loop_lambda,
        });
        let contacts =
            (!model.contacts.is_empty()).then(|| contacts::contacts(&mut g, model, &kin));

        Kernels {
            graph: g,
            dof: n,
            mass,
            christoffel,
            coriolis,
            gravity,
            bias,
            passive,
            inverse,
            forward,
            jacobian_forward,
            algorithms: [forward_algorithm, jacobian_algorithm],
            jac_q,
            jac_v,
            energy,
            inverse_mass,
            elements,
            bearings,
            frames,
            loops,
            contacts,
            compact,
            forward_parts,
        }
    }
}

/// One algorithm's solve with `M`, handed to the code that builds a kernel.
#[derive(Clone, Copy)]
pub enum Which<'a, 'm> {
    Crba(&'a ltdl::Ltdl),
    Aba(&'a aba::Articulated<'m>),
}

impl Which<'_, '_> {
    /// `M⁻¹ b` (for the articulated-body algorithm, with the base accelerating as
    /// `base`; the factor ignores it, and is only ever asked for with `None`).
    fn solve(self, g: &mut Graph, b: &[Id], base: Option<spatial::Motion>) -> Vec<Id> {
        match self {
            Which::Crba(f) => f.solve(g, b),
            Which::Aba(a) => a.solve(g, b, base),
        }
    }
}

/// The solves with `M` a scene's kernels use: the `LᵀDL` factor of the CRBA mass
/// matrix, the articulated-body algorithm, or (for [`Algorithm::Auto`]) both, each
/// kernel then built with both and emitted with whichever takes fewer operations.
enum Solver<'m> {
    Crba(ltdl::Ltdl),
    Aba(aba::Articulated<'m>),
    Both(ltdl::Ltdl, aba::Articulated<'m>),
}

impl<'m> Solver<'m> {
    fn new(
        g: &mut Graph,
        model: &'m Model,
        kin: &'m kinematics::Kinematics,
        inertia: &[Inertia],
        mass: &[Vec<Id>],
    ) -> Self {
        let parents = model.coordinate_parents();
        match model.algorithm {
            Algorithm::Crba => Solver::Crba(ltdl::factor(g, mass, &parents)),
            Algorithm::Aba => Solver::Aba(aba::Articulated::new(g, model, kin, inertia)),
            Algorithm::Auto | Algorithm::Compact => Solver::Both(
                ltdl::factor(g, mass, &parents),
                aba::Articulated::new(g, model, kin, inertia),
            ),
        }
    }

    /// The nodes of `algorithm`'s factorisation: `L` and `D⁻¹` of `LᵀDL`, or the
    /// articulated-body algorithm's `U D⁻¹` and `D⁻¹` (empty for any other algorithm).
    fn factor_nodes(&self, algorithm: Algorithm) -> Vec<Id> {
        let (l, a) = match self {
            Solver::Crba(l) => (Some(l), None),
            Solver::Aba(a) => (None, Some(a)),
            Solver::Both(l, a) => (Some(l), Some(a)),
        };
        match algorithm {
            Algorithm::Crba => l.map(ltdl::Ltdl::nodes).unwrap_or_default(),
            Algorithm::Aba => a.map(aba::Articulated::nodes).unwrap_or_default(),
            _ => Vec::new(),
        }
    }

    /// One output vector built by `build` with the chosen algorithm.
    fn choose(
        &self,
        g: &mut Graph,
        mut build: impl FnMut(&mut Graph, Which<'_, 'm>) -> Vec<Id>,
    ) -> (Vec<Id>, Algorithm) {
        let (mut cols, used) = self.choose_columns(g, 1, |g, w, _| build(g, w));
        (cols.pop().unwrap_or_default(), used)
    }

    /// The `count` columns of one kernel, all with one algorithm: the one whose code for
    /// all of them together has fewer operations. With both algorithms at hand, a few
    /// columns are built with each (the first two, then at a quarter, half and three
    /// quarters of the way, and the last) and the rest extrapolated from what each
    /// sampled column adds to the others: building every
    /// column twice would double the expansion of a large scene.
    fn choose_columns(
        &self,
        g: &mut Graph,
        count: usize,
        mut col: impl FnMut(&mut Graph, Which<'_, 'm>, usize) -> Vec<Id>,
    ) -> (Vec<Vec<Id>>, Algorithm) {
        let (l, a) = match self {
            Solver::Crba(l) => return (build_all(g, Which::Crba(l), count, col), Algorithm::Crba),
            Solver::Aba(a) => return (build_all(g, Which::Aba(a), count, col), Algorithm::Aba),
            Solver::Both(l, a) => (l, a),
        };
        // Columns spread over the kernel: a tree's columns cost more near the root.
        let last = count.saturating_sub(1);
        let mut sample: Vec<usize> = vec![0, 1, count / 4, count / 2, 3 * count / 4, last];
        sample.retain(|&k| k < count);
        sample.sort_unstable();
        sample.dedup();
        let estimate = |g: &mut Graph,
                        w: Which<'_, 'm>,
                        col: &mut dyn FnMut(&mut Graph, Which<'_, 'm>, usize) -> Vec<Id>|
         -> f64 {
            let cols: Vec<Vec<Id>> = sample.iter().map(|&k| col(g, w, k)).collect();
            let ops = |g: &Graph, skip: Option<usize>| -> usize {
                let roots: Vec<Id> = cols
                    .iter()
                    .enumerate()
                    .filter(|(j, _)| Some(*j) != skip)
                    .flat_map(|(_, c)| c.iter().copied())
                    .collect();
                g.count_ops(&roots).total()
            };
            let total = ops(g, None);
            if sample.len() == count {
                return total as f64;
            }
            // What each sampled column after the first adds to the others.
            let added: Vec<usize> = (1..sample.len()).map(|j| total - ops(g, Some(j))).collect();
            let per_column = added.iter().sum::<usize>() as f64 / added.len() as f64;
            total as f64 + per_column * (count - sample.len()) as f64
        };
        let crba = estimate(g, Which::Crba(l), &mut col);
        let aba = estimate(g, Which::Aba(a), &mut col);
        if aba < crba {
            (build_all(g, Which::Aba(a), count, col), Algorithm::Aba)
        } else {
            (build_all(g, Which::Crba(l), count, col), Algorithm::Crba)
        }
    }
}

fn build_all<'m>(
    g: &mut Graph,
    w: Which<'_, 'm>,
    count: usize,
    mut col: impl FnMut(&mut Graph, Which<'_, 'm>, usize) -> Vec<Id>,
) -> Vec<Vec<Id>> {
    (0..count).map(|k| col(g, w, k)).collect()
}

/// `cols[k][i]` → rows `[i][k]`.
fn transpose_cols(cols: &[Vec<Id>]) -> Vec<Vec<Id>> {
    let n = cols.first().map_or(0, Vec::len);
    (0..n)
        .map(|i| cols.iter().map(|c| c[i]).collect())
        .collect()
}

/// `τ_p = −k (q − rest) − c v`, summed over the springs and dampers of each coordinate.
fn passive_forces(g: &mut Graph, model: &Model, q: &[Id], v: &[Id]) -> Vec<Id> {
    let mut out = vec![g.zero(); q.len()];
    for s in &model.springs {
        let k = s.k.lower(g);
        let rest = s.rest.lower(g);
        let d = g.sub(q[s.coordinate], rest);
        let f = g.mul(k, d);
        out[s.coordinate] = g.sub(out[s.coordinate], f);
    }
    for p in &model.potentials {
        let u = p.u.lower_var(g, q[p.coordinate]);
        let du = g.diff(
            u,
            Input {
                kind: InputKind::Q,
                index: model.slot_of(p.coordinate) as u16,
            },
        );
        out[p.coordinate] = g.sub(out[p.coordinate], du);
    }
    for d in &model.dampers {
        let c = d.c.lower(g);
        let f = g.mul(c, v[d.coordinate]);
        out[d.coordinate] = g.sub(out[d.coordinate], f);
    }
    out
}
