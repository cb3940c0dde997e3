//! Substitution of nodes by nodes, rebuilt through the folding constructors.

use super::graph::{Graph, Id, Node};
use super::hash::FastMap;

impl Graph {
    /// `id` with every occurrence of a key of `map` replaced by its value. `memo` may be
    /// shared across calls with the same map.
    pub fn substitute(&mut self, id: Id, map: &FastMap<Id, Id>, memo: &mut FastMap<Id, Id>) -> Id {
        if let Some(&r) = map.get(&id) {
            return r;
        }
        if let Some(&r) = memo.get(&id) {
            return r;
        }
        let r = match self.node(id) {
            Node::Const(_) | Node::Param(_) | Node::Input(_) => id,
            Node::Add(a, b) => {
                let (a, b) = (self.substitute(a, map, memo), self.substitute(b, map, memo));
                self.add(a, b)
            }
            Node::Mul(a, b) => {
                let (a, b) = (self.substitute(a, map, memo), self.substitute(b, map, memo));
                self.mul(a, b)
            }
            Node::Unary(op, a) => {
                let a = self.substitute(a, map, memo);
                self.unary(op, a)
            }
        };
        memo.insert(id, r);
        r
    }
}
