//! Sparse `M = Lᵀ D L` factorisation and solve (Featherstone 2008, §6.5, Tables 6.3 and
//! 6.4). With coordinates numbered so that `λ(i) < i`, `L` has the sparsity of the
//! tree: only entries between a coordinate and its ancestors exist, so there is no
//! fill-in and branches cost nothing. `D⁻¹` is formed once (one division per coordinate).

use crate::sym::{Graph, Id};

/// The factor: `l[k][i]` for `i` an ancestor of `k`, and `1 / D_kk`.
pub struct Ltdl {
    pub l: Vec<Vec<Id>>,
    pub d_inv: Vec<Id>,
    parent: Vec<Option<usize>>,
}

fn ancestors(parent: &[Option<usize>], k: usize) -> impl Iterator<Item = usize> + '_ {
    std::iter::successors(parent[k], move |&i| parent[i])
}

pub fn factor(g: &mut Graph, m: &[Vec<Id>], parent: &[Option<usize>]) -> Ltdl {
    let n = m.len();
    let mut h: Vec<Vec<Id>> = m.to_vec();
    let mut d_inv = vec![g.zero(); n];
    for k in (0..n).rev() {
        let inv = g.recip(h[k][k]);
        d_inv[k] = inv;
        let anc: Vec<usize> = ancestors(parent, k).collect();
        for (pos, &i) in anc.iter().enumerate() {
            let a = g.mul(h[k][i], inv);
            for &j in &anc[pos..] {
                let t = g.mul(a, h[k][j]);
                h[i][j] = g.sub(h[i][j], t);
                h[j][i] = h[i][j];
            }
            h[k][i] = a;
        }
    }
    Ltdl {
        l: h,
        d_inv,
        parent: parent.to_vec(),
    }
}

impl Ltdl {
    /// Every node of the factor: `L` (with `M`'s entries that the tree leaves as they
    /// are) and `D⁻¹`.
    pub fn nodes(&self) -> Vec<Id> {
        self.l
            .iter()
            .flatten()
            .chain(&self.d_inv)
            .copied()
            .collect()
    }

    /// `M⁻¹ b`.
    pub fn solve(&self, g: &mut Graph, b: &[Id]) -> Vec<Id> {
        let n = b.len();
        let mut x = b.to_vec();
        // x ← L⁻ᵀ x
        for i in (0..n).rev() {
            for j in ancestors(&self.parent, i) {
                let t = g.mul(self.l[i][j], x[i]);
                x[j] = g.sub(x[j], t);
            }
        }
        // x ← D⁻¹ x
        for i in 0..n {
            x[i] = g.mul(x[i], self.d_inv[i]);
        }
        // x ← L⁻¹ x
        for i in 0..n {
            for j in ancestors(&self.parent, i) {
                let t = g.mul(self.l[i][j], x[j]);
                x[i] = g.sub(x[i], t);
            }
        }
        x
    }
}
