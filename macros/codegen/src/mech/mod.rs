//! Mechanics on the symbolic DAG: every quantity the derive emits, as graph nodes.
//!
//! Where things are made:
//! - joint transforms and motion subspaces: [`kinematics`];
//! - mass matrix `M(q)`: [`crba`] (composite-rigid-body algorithm);
//! - inverse dynamics and bias forces: [`rnea`] (recursive Newton–Euler);
//! - gravity forces: [`gravity`] (composite first moments);
//! - Christoffel symbols and the Coriolis matrix: [`christoffel`] (derivatives of `M`
//!   along the local exponential coordinates of [`chart`]);
//! - forward dynamics: [`ltdl`] (sparse `LᵀDL` of `M`) applied to `τ + τ_p − bias`;
//! - its Jacobian: `∂v̇/∂x = −M⁻¹ ∂ID/∂x` at `a = v̇` ([`Kernels::build`]);
//! - world poses and Jacobians of bodies and `#[frame]`s: [`frames`].

pub mod chart;
pub mod christoffel;
pub mod crba;
pub mod frames;
pub mod gravity;
pub mod kinematics;
pub mod ltdl;
pub mod rnea;
pub mod spatial;

use std::collections::HashMap;

use crate::model::Model;
use crate::sym::{Graph, Id, Input, InputKind};
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
    pub jac_q: Vec<Vec<Id>>,
    pub jac_v: Vec<Vec<Id>>,
    /// `(kinetic, potential)`, built only when the energies are asked for.
    pub energy: Option<(Id, Id)>,
    /// `M⁻¹` (row-major), built only for scenes with non-smooth elements (their Delassus
    /// operator is its submatrix).
    pub inverse_mass: Option<Vec<Vec<Id>>>,
    /// For scenes with non-smooth elements: see [`ElementKernels`].
    pub elements: Option<ElementKernels>,
    /// Poses and Jacobians of every body and declared frame; built only when the
    /// scene asks for `kinematics` (or declares a frame).
    pub frames: Vec<frames::FrameKernel>,
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
        let coriolis_v = rnea::rnea(&mut g, model, &kin, &inertia, None, &v, &zeros);
        let bias: Vec<Id> = (0..n).map(|i| g.add(coriolis_v[i], gravity[i])).collect();
        let passive = passive_forces(&mut g, model, &q, &v);
        let rnea_a = rnea::rnea(&mut g, model, &kin, &inertia, None, &v, &a);
        let inverse: Vec<Id> = (0..n)
            .map(|i| {
                let t = g.add(rnea_a[i], gravity[i]);
                g.sub(t, passive[i])
            })
            .collect();

        // Forward dynamics: M v̇ = τ + τ_p − bias.
        let parent = model.coordinate_parents();
        let factor = ltdl::factor(&mut g, &mass, &parent);
        let rhs: Vec<Id> = (0..n)
            .map(|i| {
                let t = g.add(tau[i], passive[i]);
                g.sub(t, bias[i])
            })
            .collect();
        let forward = factor.solve(&mut g, &rhs);
        let inverse_mass = (!model.elements.is_empty()).then(|| {
            let cols: Vec<Vec<Id>> = (0..n)
                .map(|k| {
                    let e: Vec<Id> = (0..n)
                        .map(|i| g.constant(if i == k { 1.0 } else { 0.0 }))
                        .collect();
                    factor.solve(&mut g, &e)
                })
                .collect();
            (0..n)
                .map(|i| (0..n).map(|k| cols[k][i]).collect())
                .collect()
        });

        // ∂v̇/∂x = −M⁻¹ ∂ID(q, v, a)/∂x evaluated at a = v̇: differentiate inverse
        // dynamics with a held fixed (cheap: RNEA is linear-size), then substitute.
        let subst: HashMap<Id, Id> = a.iter().copied().zip(forward.iter().copied()).collect();
        let mut memo = HashMap::new();
        let mut jac = |g: &mut Graph, kind: InputKind| -> Vec<Vec<Id>> {
            let mut cols = Vec::with_capacity(n);
            for k in 0..n {
                let x = Input {
                    kind,
                    index: k as u16,
                };
                let d: Vec<Id> = (0..n)
                    .map(|i| {
                        let di = match kind {
                            InputKind::Q => chart.derivative(g, inverse[i], k),
                            _ => g.diff(inverse[i], x),
                        };
                        let s = g.substitute(di, &subst, &mut memo);
                        g.neg(s)
                    })
                    .collect();
                cols.push(factor.solve(g, &d));
            }
            // cols[k][i] = ∂v̇_i/∂x_k → rows
            (0..n)
                .map(|i| (0..n).map(|k| cols[k][i]).collect())
                .collect()
        };
        let jac_q = jac(&mut g, InputKind::Q);
        let jac_v = jac(&mut g, InputKind::V);

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

        // Last, so that the other kernels' code reads the same with or without frames.
        let frames = if model.emit.kinematics {
            frames::frames(&mut g, model, &kin)
        } else {
            Vec::new()
        };

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
            jac_q,
            jac_v,
            energy,
            inverse_mass,
            elements,
            frames,
        }
    }
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
