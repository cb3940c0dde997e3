//! Christoffel symbols of the first kind and the Coriolis matrix (theory.md §2):
//!
//! ```text
//! c_ijk = ½ (∂M_ij/∂q_k + ∂M_ik/∂q_j − ∂M_jk/∂q_i),   C_ij = Σ_k c_ijk v_k
//! ```
//!
//! With this choice `Ṁ − 2C` is skew-symmetric. Derivatives come from the DAG
//! ([`Graph::diff`]), memoised, so the `n³` symbols share one derivative graph; `c_ijk =
//! c_ikj` is formed once.
//!
//! With Lie-group joints the derivatives are along local exponential coordinates
//! ([`Chart`]), and the Coriolis matrix gains the structure-constant term of
//! [`lie_bracket_term`].

use super::chart::Chart;
use crate::sym::{Graph, Id};

pub fn christoffel_symbols(g: &mut Graph, chart: &Chart, m: &[Vec<Id>]) -> Vec<Vec<Vec<Id>>> {
    let n = m.len();
    // dm[k][i][j] = ∂M_ij/∂φ_k
    let mut dm = vec![vec![vec![g.zero(); n]; n]; n];
    for k in 0..n {
        for i in 0..n {
            for j in i..n {
                let d = chart.derivative(g, m[i][j], k);
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

/// `X_ij = (M v)·[e_i, e_j]`, added to the Christoffel form of `C` on Lie groups. Theory
/// §2 writes this part as `−ad_vᵀ M`; both give the same `C v` (`X v = −ad_vᵀ M v`),
/// but `X` is skew-symmetric, so `Ṁ − 2C` stays skew. Brackets vanish except within one
/// rotation, `[e_a, e_b] = ε_abc e_c`: there `X = −p̂` with `p` that block of `M v`.
pub fn lie_bracket_term(
    g: &mut Graph,
    chart: &Chart,
    m: &[Vec<Id>],
    v: &[Id],
    coriolis: &mut [Vec<Id>],
) {
    for r in chart.rotations() {
        let p: Vec<Id> = (0..3).map(|c| g.dot(&m[r + c], v)).collect();
        for (a, b, c) in [(0, 1, 2), (1, 2, 0), (2, 0, 1)] {
            // X_ab = p_c, X_ba = −p_c for (a, b, c) cyclic.
            coriolis[r + a][r + b] = g.add(coriolis[r + a][r + b], p[c]);
            coriolis[r + b][r + a] = g.sub(coriolis[r + b][r + a], p[c]);
        }
    }
}
