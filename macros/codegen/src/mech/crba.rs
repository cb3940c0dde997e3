//! The mass matrix by the composite-rigid-body algorithm (Featherstone 2008, §6.2,
//! Table 6.2), on the DAG: composite inertias accumulate from the leaves, and each
//! column's force is carried up the ancestors only, so entries of M between different
//! branches are never formed (they are structural zeros).

use super::kinematics::{Kinematics, project};
use super::spatial::{Inertia, V3};
use crate::model::Model;
use crate::sym::{Graph, Id};

/// The inertia of every link about its own origin, in its own coordinates.
pub fn link_inertias(g: &mut Graph, model: &Model) -> Vec<Inertia> {
    model
        .links
        .iter()
        .map(|l| {
            let m = l.mass.lower(g);
            let c: V3 = [l.com[0].lower(g), l.com[1].lower(g), l.com[2].lower(g)];
            let mut ic = [[m; 3]; 3];
            for i in 0..3 {
                for j in 0..3 {
                    ic[i][j] = l.inertia[i][j].lower(g);
                }
            }
            Inertia::from_com(g, m, c, &ic)
        })
        .collect()
}

/// Composite inertias: link `i` together with all its descendants, in `i`'s coordinates.
pub fn composite_inertias(
    g: &mut Graph,
    model: &Model,
    kin: &Kinematics,
    inertia: &[Inertia],
) -> Vec<Inertia> {
    let mut ic = inertia.to_vec();
    for i in (0..model.links.len()).rev() {
        if let Some(p) = model.links[i].parent {
            let moved = ic[i].to_parent(g, &kin.xform[i]);
            ic[p] = ic[p].add(g, &moved);
        }
    }
    ic
}

/// `M(q)`, dense `n × n` (zeros as constant nodes), symmetric by construction.
pub fn mass_matrix(
    g: &mut Graph,
    model: &Model,
    kin: &Kinematics,
    composite: &[Inertia],
) -> Vec<Vec<Id>> {
    let n = model.dof();
    let z = g.zero();
    let mut m = vec![vec![z; n]; n];
    for (i, link) in model.links.iter().enumerate() {
        let Some(ci) = link.coordinate else {
            continue;
        };
        for (a, s) in kin.subspace[i].iter().enumerate() {
            let mut f = composite[i].apply(g, *s);
            // The joint's own block (one entry for one-dof joints).
            for (b, sb) in kin.subspace[i].iter().enumerate().take(a + 1) {
                let mab = project(g, sb, f);
                m[ci + a][ci + b] = mab;
                m[ci + b][ci + a] = mab;
            }
            let mut j = i;
            while let Some(p) = model.links[j].parent {
                f = kin.xform[j].apply_force_t(g, f);
                j = p;
                if let Some(cj) = model.links[j].coordinate {
                    for (b, sj) in kin.subspace[j].iter().enumerate() {
                        let mij = project(g, sj, f);
                        m[ci + a][cj + b] = mij;
                        m[cj + b][ci + a] = mij;
                    }
                }
            }
        }
    }
    m
}
