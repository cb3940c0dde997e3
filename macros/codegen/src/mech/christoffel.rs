//! Christoffel symbols of the first kind and the Coriolis matrix (theory.md §2):
//!
//! ```text
//! c_ijk = ½ (∂M_ij/∂q_k + ∂M_ik/∂q_j − ∂M_jk/∂q_i),   C_ij = Σ_k c_ijk v_k
//! ```
//!
//! With this choice `Ṁ − 2C` is skew-symmetric. Derivatives come from the DAG
//! ([`Graph::diff`]), memoised, so the `n³` symbols share one derivative graph; `c_ijk =
//! c_ikj` is formed once.

use crate::sym::{Graph, Id, Input, InputKind};

pub fn christoffel_symbols(g: &mut Graph, m: &[Vec<Id>]) -> Vec<Vec<Vec<Id>>> {
    let n = m.len();
    let q = |k: usize| Input {
        kind: InputKind::Q,
        index: k as u16,
    };
    // dm[k][i][j] = ∂M_ij/∂q_k
    let mut dm = vec![vec![vec![g.zero(); n]; n]; n];
    for k in 0..n {
        for i in 0..n {
            for j in i..n {
                let d = g.diff(m[i][j], q(k));
                dm[k][i][j] = d;
                dm[k][j][i] = d;
            }
        }
    }
    let half = g.constant(0.5);
    let mut c = vec![vec![vec![g.zero(); n]; n]; n];
    for i in 0..n {
        for j in 0..n {
            for k in j..n {
                let s = g.add(dm[k][i][j], dm[j][i][k]);
                let s = g.sub(s, dm[i][j][k]);
                let s = g.mul(half, s);
                c[i][j][k] = s;
                c[i][k][j] = s;
            }
        }
    }
    c
}

pub fn coriolis(g: &mut Graph, c: &[Vec<Vec<Id>>], v: &[Id]) -> Vec<Vec<Id>> {
    c.iter()
        .map(|ci| ci.iter().map(|cij| g.dot(cij, v)).collect())
        .collect()
}
