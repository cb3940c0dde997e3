//! Differentiation on the DAG.
//!
//! `∂node/∂x` is memoised per `(node, x)` in the graph, so derivatives share structure
//! with each other and with the original expressions: the derivative DAG of a whole
//! output set costs at most a constant times its size per variable, never the expression
//! swell of differentiating flattened formulas. Subgraphs whose dependency mask does not
//! contain `x` are zero without a visit.

use super::graph::{Graph, Id, Input, InputKind, Node, Unary};

impl Graph {
    /// `∂id/∂x` for a coordinate or velocity input `x`.
    pub fn diff(&mut self, id: Id, x: Input) -> Id {
        let deps = self.deps(id);
        let bit = 1u64 << (x.index % 64);
        let depends = match x.kind {
            InputKind::Q => deps.q & bit != 0,
            InputKind::V => deps.v & bit != 0,
            InputKind::A | InputKind::Tau | InputKind::F => {
                panic!("differentiation only in q and v")
            }
        };
        if !depends {
            return self.zero();
        }
        if let Some(&d) = self.diff_memo.get(&(id, x)) {
            return d;
        }
        let d = match self.node(id) {
            Node::Const(_) | Node::Param(_) => self.zero(),
            Node::Input(i) => {
                if i == x {
                    self.one()
                } else {
                    self.zero()
                }
            }
            Node::Add(a, b) => {
                let da = self.diff(a, x);
                let db = self.diff(b, x);
                self.add(da, db)
            }
            Node::Mul(a, b) => {
                let da = self.diff(a, x);
                let db = self.diff(b, x);
                let l = self.mul(da, b);
                let r = self.mul(a, db);
                self.add(l, r)
            }
            Node::Unary(op, a) => {
                let da = self.diff(a, x);
                let outer = match op {
                    Unary::Neg => self.constant(-1.0),
                    // d(1/a) = -(1/a)² da
                    Unary::Recip => {
                        let sq = self.mul(id, id);
                        self.neg(sq)
                    }
                    Unary::Sin => self.cos(a),
                    Unary::Cos => {
                        let s = self.sin(a);
                        self.neg(s)
                    }
                    // d√a = da / (2√a)
                    Unary::Sqrt => {
                        let two = self.constant(2.0);
                        let t = self.mul(two, id);
                        self.recip(t)
                    }
                    Unary::Exp => id,
                    Unary::Ln => self.recip(a),
                };
                self.mul(outer, da)
            }
        };
        self.diff_memo.insert((id, x), d);
        d
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn q(i: u16) -> Input {
        Input {
            kind: InputKind::Q,
            index: i,
        }
    }

    #[test]
    fn product_and_chain_rules() {
        let mut g = Graph::new();
        let x = g.input(InputKind::Q, 0);
        let y = g.input(InputKind::Q, 1);
        let s = g.sin(x);
        let e = g.mul(s, y); // y sin x
        let dx = g.diff(e, q(0));
        let c = g.cos(x);
        let expect = g.mul(c, y);
        assert_eq!(dx, expect);
        let dy = g.diff(e, q(1));
        assert_eq!(dy, s);
        let d2 = g.diff(e, q(2));
        assert!(g.is_zero(d2));
    }

    #[test]
    fn second_derivative_of_sin_is_minus_sin() {
        let mut g = Graph::new();
        let x = g.input(InputKind::Q, 0);
        let s = g.sin(x);
        let d1 = g.diff(s, q(0));
        let d2 = g.diff(d1, q(0));
        let expect = g.neg(s);
        assert_eq!(d2, expect);
    }
}
