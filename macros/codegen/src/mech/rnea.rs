//! Inverse dynamics by the recursive Newton–Euler algorithm (Featherstone 2008, §5.3,
//! Table 5.1), on the DAG: `RNEA(q, v, a) = M a + C v + g`. With `v = a = 0` it is the
//! generalised gravity force, with `a = 0` the bias force; the folding constructors drop
//! every term a zero input kills.

use super::kinematics::{Kinematics, lower3, project};
use super::spatial::{Force, Motion, V3, add3, cross, mat_vec, scale3, v3_zero};
use crate::model::Model;
use crate::sym::{Graph, Id};

/// The force link `i` needs for its motion, `I a + v ×* I v`, in its own coordinates.
///
/// Taken through the centre of mass `c` where the link's inertia is its own (the model's
/// mass, centre of mass and `I_c`): there the spatial inertia is block-diagonal,
/// `diag(I_c, m 1)`, so with the motion moved to `c` (`v_c = v + ω × c`,
/// `a_c = a + α × c`) the force is `(I_c α + ω × I_c ω, m (a_c + ω × v_c))`, and moved
/// back to the origin its moment gains `c × f`. That takes fewer operations than the
/// inertia about the origin, where the first moment `h = m c` couples the blocks
/// (the report's operation counts measure both).
fn body_force(g: &mut Graph, model: &Model, i: usize, v: Motion, a: Motion) -> Force {
    let link = &model.links[i];
    let m = link.mass.lower(g);
    let c: V3 = lower3(g, &link.com);
    let mut ic = [[m; 3]; 3];
    for (r, row) in ic.iter_mut().enumerate() {
        for (k, x) in row.iter_mut().enumerate() {
            *x = link.inertia[r][k].lower(g);
        }
    }
    let (w, alpha) = (v.w, a.w);
    let wc = cross(g, w, c);
    let vc = add3(g, v.v, wc);
    let alc = cross(g, alpha, c);
    let ac = add3(g, a.v, alc);
    let icw = mat_vec(g, &ic, w);
    let ica = mat_vec(g, &ic, alpha);
    let gyro = cross(g, w, icw);
    let nc = add3(g, ica, gyro);
    let wv = cross(g, w, vc);
    let acc = add3(g, ac, wv);
    let f = scale3(g, m, acc);
    let cf = cross(g, c, f);
    Force {
        n: add3(g, nc, cf),
        f,
    }
}

/// `τ = M(q) a + C(q, v) v + g(q)` for symbolic `v`, `a` (one node per coordinate);
/// gravity enters as a base acceleration `−gravity`.
pub fn rnea(
    g: &mut Graph,
    model: &Model,
    kin: &Kinematics,
    gravity: Option<[Id; 3]>,
    v: &[Id],
    a: &[Id],
) -> Vec<Id> {
    rnea_forces(g, model, kin, gravity, v, a).0
}

/// [`rnea`]'s `τ`, and the spatial force each link's joint transmits to it from its
/// parent (in link coordinates): what its subtree needs for the motion `(v, a)`.
pub fn rnea_forces(
    g: &mut Graph,
    model: &Model,
    kin: &Kinematics,
    gravity: Option<[Id; 3]>,
    v: &[Id],
    a: &[Id],
) -> (Vec<Id>, Vec<Force>) {
    let nl = model.links.len();
    let base_acc = match gravity {
        Some(gv) => Motion {
            w: v3_zero(g),
            v: gv.map(|c| g.neg(c)),
        },
        None => Motion::zero(g),
    };
    let base_vel = Motion::zero(g);
    let mut vel = Vec::with_capacity(nl);
    let mut acc = Vec::with_capacity(nl);
    let mut force: Vec<Force> = Vec::with_capacity(nl);
    for (i, link) in model.links.iter().enumerate() {
        let (vp, ap) = match link.parent {
            Some(p) => (vel[p], acc[p]),
            None => (base_vel, base_acc),
        };
        let x = &kin.xform[i];
        let mut vi = x.apply_motion(g, vp);
        let mut ai = x.apply_motion(g, ap);
        if let Some(c) = link.coordinate {
            // v_J = Σ S_k v_k and a_J likewise (S constant in link coordinates).
            let cols = &kin.subspace[i];
            let mut vj = cols[0].scale(g, v[c]);
            for (k, s) in cols.iter().enumerate().skip(1) {
                let t = s.scale(g, v[c + k]);
                vj = vj.add(g, t);
            }
            vi = vi.add(g, vj);
            let mut aj = cols[0].scale(g, a[c]);
            for (k, s) in cols.iter().enumerate().skip(1) {
                let t = s.scale(g, a[c + k]);
                aj = aj.add(g, t);
            }
            ai = ai.add(g, aj);
            let cor = vi.cross_motion(g, vj);
            ai = ai.add(g, cor);
        }
        force.push(body_force(g, model, i, vi, ai));
        vel.push(vi);
        acc.push(ai);
    }
    let z = g.zero();
    let mut tau = vec![z; model.dof()];
    for i in (0..nl).rev() {
        if let Some(c) = model.links[i].coordinate {
            for (k, s) in kin.subspace[i].iter().enumerate() {
                tau[c + k] = project(g, s, force[i]);
            }
        }
        if let Some(p) = model.links[i].parent {
            let up = kin.xform[i].apply_force_t(g, force[i]);
            force[p] = force[p].add(g, up);
        }
    }
    // Link i's force is final once its own turn has come (children come after parents).
    (tau, force)
}
