//! The Jacobian of a compact tree's forward dynamics with respect to `(q, v)`, by
//! forward-mode dual numbers through [`aba::forward_dynamics`](super::aba): eight
//! directions per pass, so `⌈2N / 8⌉` passes. Exact to rounding, like the unrolled
//! kernels' symbolic Jacobian; no table of derivatives is emitted.

use super::{Body, Node, aba};
use crate::real::{Dual, Real};

/// Directions per pass.
pub const CHUNK: usize = 8;

/// `(v̇, ∂v̇/∂q, ∂v̇/∂v)` on any scalar, the matrices as arrays of rows; `forces(q, v)`
/// the generalised forces `τ + τ_p` (their derivatives enter too).
#[allow(clippy::type_complexity)]
pub fn forward_dynamics_jacobian<T: Real, const B: usize, const N: usize>(
    nodes: &[Node; B],
    bodies: &[Body<T>; B],
    gravity: [T; 3],
    q: &[T; N],
    v: &[T; N],
    forces: impl Fn(&[Dual<CHUNK, T>; N], &[Dual<CHUNK, T>; N]) -> [Dual<CHUNK, T>; N],
) -> ([T; N], [[T; N]; N], [[T; N]; N]) {
    let lifted: [Body<Dual<CHUNK, T>>; B] = std::array::from_fn(|i| bodies[i].map(Dual::constant));
    let g = gravity.map(Dual::constant);
    let zero = T::cst(0.0);
    let mut acc = [zero; N];
    let mut d_dq = [[zero; N]; N];
    let mut d_dv = [[zero; N]; N];
    let mut start = 0;
    while start < 2 * N {
        // Direction `start + k` seeds q_j (j < N) or v_(j − N).
        let seed = |x: T, j: usize| {
            let mut d = Dual::constant(x);
            if (start..start + CHUNK).contains(&j) {
                d.eps[j - start] = T::cst(1.0);
            }
            d
        };
        let qd: [Dual<CHUNK, T>; N] = std::array::from_fn(|j| seed(q[j], j));
        let vd: [Dual<CHUNK, T>; N] = std::array::from_fn(|j| seed(v[j], N + j));
        let t = forces(&qd, &vd);
        let out = aba::forward_dynamics(nodes, &lifted, g, &qd, &vd, &t);
        for (i, o) in out.iter().enumerate() {
            acc[i] = o.re;
            for k in 0..CHUNK {
                let j = start + k;
                if j < N {
                    d_dq[i][j] = o.eps[k];
                } else if j < 2 * N {
                    d_dv[i][j - N] = o.eps[k];
                }
            }
        }
        start += CHUNK;
    }
    (acc, d_dq, d_dv)
}
