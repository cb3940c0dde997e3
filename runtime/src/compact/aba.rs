//! Forward dynamics of a compact tree by the articulated-body algorithm (Featherstone,
//! *Rigid Body Dynamics Algorithms*, §7.3), in three loops over the table: velocities
//! and bias terms outwards, articulated inertias inwards, accelerations outwards.
//! Gravity is the world's acceleration `−γ`.

use super::algebra::{Inertia, M3, Spatial, V3, add, cross, scale, sub, sym_mul};
use super::{Body, Joint, Node, placement};
use crate::real::Real;
use std::mem::MaybeUninit;

/// `v̇ = M(q)⁻¹ (τ − C(q, v) v − g(q))` of the tree `nodes`/`bodies` (parents before
/// children) under gravity `gravity` (world frame), `N` its coordinates.
///
/// The work arrays live on the stack: no allocation.
#[inline(never)]
pub fn forward_dynamics<T: Real, const B: usize, const N: usize>(
    nodes: &[Node; B],
    bodies: &[Body<T>; B],
    gravity: [T; 3],
    q: &[T; N],
    v: &[T; N],
    tau: &[T; N],
) -> [T; N] {
    forward_dynamics_in(nodes, bodies, gravity, q, v, tau)
}

/// [`forward_dynamics`]'s body, inlined into its callers: the fused twins (`super::fused`)
/// compile it with their target features. (The public function is never inlined: on
/// wide duals its unoptimised frame is over a megabyte, and the Jacobian that calls it
/// in a loop would otherwise carry it in its own.)
#[inline(always)]
pub(crate) fn forward_dynamics_in<T: Real, const B: usize, const N: usize>(
    nodes: &[Node; B],
    bodies: &[Body<T>; B],
    gravity: [T; 3],
    q: &[T; N],
    v: &[T; N],
    tau: &[T; N],
) -> [T; N] {
    let zero = T::cst(0.0);
    // Written for every body by the outward loop, in order, before any read (not
    // zeroed first).
    let mut rot = [const { MaybeUninit::<M3<T>>::uninit() }; B];
    let mut pos = [const { MaybeUninit::<V3<T>>::uninit() }; B];
    let mut vel = [const { MaybeUninit::<Spatial<T>>::uninit() }; B];
    let mut bias_acc = [const { MaybeUninit::<Spatial<T>>::uninit() }; B];
    let mut bias = [const { MaybeUninit::<Spatial<T>>::uninit() }; B];
    // Per body, the articulated inertias its children pass it (its own is added when
    // the inward loop reaches it).
    let mut art = [Inertia::rigid(zero, [zero; 3], [zero; 6]); B];
    // Per joint: U = I S, 1 / (Sᵀ I S), and τ − Sᵀ p.
    let mut u_col = [Spatial::zero(); B];
    let mut d_inv = [zero; B];
    let mut u_tau = [zero; B];
    let mut out = [zero; N];
    let trig = T::sin_cos_n(*q);

    // Outwards: placements, velocities, velocity-product accelerations and forces.
    for i in 0..B {
        let (node, body) = (&nodes[i], &bodies[i]);
        let (r, p) = placement(body, node.joint, q, &trig);
        let mut vi = match node.parent {
            Some(pa) => {
                assert!(pa < i, "a parent after its child in the table");
                // SAFETY: the loop wrote entry `pa < i` in an earlier turn.
                unsafe { vel[pa].assume_init() }.motion_to_child(&r, p)
            }
            None => Spatial::zero(),
        };
        let mut ci = Spatial::zero();
        // `x × (0, 0, s)`, its zeros not multiplied.
        let cross_z = |x: [T; 3], s: T| [x[1] * s, -(x[0] * s), zero];
        match node.joint {
            Joint::Revolute(k) => {
                vi.w[2] = vi.w[2] + v[k];
                ci.w = cross_z(vi.w, v[k]);
                ci.l = cross_z(vi.l, v[k]);
            }
            Joint::Prismatic(k) => {
                vi.l[2] = vi.l[2] + v[k];
                ci.l = cross_z(vi.w, v[k]);
            }
            Joint::Fixed => {}
        }
        // The rigid body's momentum `I v = (Ī ω + h × v, m v − h × ω)`, without the
        // zeros of its spatial inertia.
        let h = body.first_moment;
        let momentum = Spatial {
            w: add(sym_mul(&body.inertia, vi.w), cross(h, vi.l)),
            l: sub(scale(body.mass, vi.l), cross(h, vi.w)),
        };
        bias[i].write(vi.cross_force(momentum));
        vel[i].write(vi);
        bias_acc[i].write(ci);
        rot[i].write(r);
        pos[i].write(p);
    }
    // SAFETY: the loop above wrote every entry of these arrays, and `MaybeUninit<X>` has
    // `X`'s layout, arrays of them alike.
    let (rot, pos, bias_acc, bias) = unsafe {
        (
            &*rot.as_ptr().cast::<[M3<T>; B]>(),
            &*pos.as_ptr().cast::<[V3<T>; B]>(),
            &*bias_acc.as_ptr().cast::<[Spatial<T>; B]>(),
            &mut *bias.as_mut_ptr().cast::<[Spatial<T>; B]>(),
        )
    };

    // Inwards: articulated inertias and bias forces.
    for i in (0..B).rev() {
        let body = &bodies[i];
        let ia = art[i].plus_rigid(body.mass, body.first_moment, &body.inertia);
        let (ia_child, pa_child) = match nodes[i].joint {
            Joint::Revolute(k) | Joint::Prismatic(k) => {
                let revolute = matches!(nodes[i].joint, Joint::Revolute(_));
                // U = I S: the inertia's third or sixth column.
                let u = if revolute {
                    Spatial {
                        w: [ia.a[4], ia.a[5], ia.a[2]],
                        l: ia.b[2],
                    }
                } else {
                    Spatial {
                        w: [ia.b[0][2], ia.b[1][2], ia.b[2][2]],
                        l: [ia.c[4], ia.c[5], ia.c[2]],
                    }
                };
                let d = if revolute { u.w[2] } else { u.l[2] };
                let inv = T::cst(1.0) / d;
                let s_p = if revolute { bias[i].w[2] } else { bias[i].l[2] };
                let ut = tau[k] - s_p;
                u_col[i] = u;
                d_inv[i] = inv;
                u_tau[i] = ut;
                let ia2 = ia.minus_rank_one(u, inv);
                let gain = ut * inv;
                let c = ia2.apply(bias_acc[i]);
                let pa = Spatial {
                    w: add(
                        add(bias[i].w, c.w),
                        [u.w[0] * gain, u.w[1] * gain, u.w[2] * gain],
                    ),
                    l: add(
                        add(bias[i].l, c.l),
                        [u.l[0] * gain, u.l[1] * gain, u.l[2] * gain],
                    ),
                };
                (ia2, pa)
            }
            Joint::Fixed => (ia, bias[i]),
        };
        if let Some(pa) = nodes[i].parent {
            let moved = match nodes[i].joint {
                Joint::Revolute(_) => ia_child.to_parent_revolute(&rot[i], pos[i]),
                _ => ia_child.to_parent(&rot[i], pos[i]),
            };
            art[pa].add_to(&moved);
            bias[pa] = bias[pa].plus(pa_child.force_to_parent(&rot[i], pos[i]));
        }
    }

    // Outwards: accelerations, the world accelerating as −γ.
    let world = Spatial {
        w: [zero; 3],
        l: [-gravity[0], -gravity[1], -gravity[2]],
    };
    let mut acc = [Spatial::zero(); B];
    for i in 0..B {
        let parent = match nodes[i].parent {
            Some(pa) => acc[pa],
            None => world,
        };
        let mut ai = parent.motion_to_child(&rot[i], pos[i]).plus(bias_acc[i]);
        match nodes[i].joint {
            Joint::Revolute(k) => {
                let qdd = (u_tau[i] - u_col[i].dot(ai)) * d_inv[i];
                ai.w[2] = ai.w[2] + qdd;
                out[k] = qdd;
            }
            Joint::Prismatic(k) => {
                let qdd = (u_tau[i] - u_col[i].dot(ai)) * d_inv[i];
                ai.l[2] = ai.l[2] + qdd;
                out[k] = qdd;
            }
            Joint::Fixed => {}
        }
        acc[i] = ai;
    }
    out
}
