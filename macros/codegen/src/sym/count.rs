//! Operation counts of the code emitted for a set of outputs.

use super::graph::{Graph, Id, Node, Unary};

/// Floating-point operations in the straight-line code that computes a set of outputs,
/// each distinct subexpression counted once (as the emitted code evaluates it once).
/// A subtraction counts as an addition; a negation feeding an addition or
/// multiplication is absorbed by the emitter and counted under `neg` only when it stands
/// alone.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct OpCount {
    pub add: usize,
    pub mul: usize,
    pub div: usize,
    pub neg: usize,
    /// sin/cos pairs of the same argument, computed together with `sin_cos`.
    pub trig: usize,
    pub sqrt: usize,
    /// exp, ln.
    pub other: usize,
}

impl OpCount {
    pub fn total(&self) -> usize {
        self.add + self.mul + self.div + self.neg + self.trig + self.sqrt + self.other
    }
}

impl std::ops::Add for OpCount {
    type Output = OpCount;
    fn add(self, o: OpCount) -> OpCount {
        OpCount {
            add: self.add + o.add,
            mul: self.mul + o.mul,
            div: self.div + o.div,
            neg: self.neg + o.neg,
            trig: self.trig + o.trig,
            sqrt: self.sqrt + o.sqrt,
            other: self.other + o.other,
        }
    }
}

impl std::ops::Sub for OpCount {
    type Output = OpCount;
    /// Saturating: a part's count is what it adds to a larger set's.
    fn sub(self, o: OpCount) -> OpCount {
        OpCount {
            add: self.add.saturating_sub(o.add),
            mul: self.mul.saturating_sub(o.mul),
            div: self.div.saturating_sub(o.div),
            neg: self.neg.saturating_sub(o.neg),
            trig: self.trig.saturating_sub(o.trig),
            sqrt: self.sqrt.saturating_sub(o.sqrt),
            other: self.other.saturating_sub(o.other),
        }
    }
}

impl std::fmt::Display for OpCount {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "{} add, {} mul, {} div, {} neg, {} sin/cos, {} sqrt",
            self.add, self.mul, self.div, self.neg, self.trig, self.sqrt
        )?;
        if self.other > 0 {
            write!(f, ", {} exp/ln", self.other)?;
        }
        Ok(())
    }
}

impl Graph {
    /// The nodes reachable from `roots`, as a mask over the arena.
    pub fn reachable(&self, roots: &[Id]) -> Vec<bool> {
        let mut seen = vec![false; self.len()];
        let mut stack: Vec<Id> = roots.to_vec();
        while let Some(id) = stack.pop() {
            if std::mem::replace(&mut seen[id.index()], true) {
                continue;
            }
            match self.node(id) {
                Node::Add(a, b) | Node::Mul(a, b) => stack.extend([a, b]),
                Node::Unary(_, a) => stack.push(a),
                _ => {}
            }
        }
        seen
    }

    /// Operation counts of the code that evaluates `roots`.
    pub fn count_ops(&self, roots: &[Id]) -> OpCount {
        self.count_mask(&self.reachable(roots))
    }

    /// Where the operations of the code that evaluates `outputs` go: `parts` in the
    /// order the code computes them, each given by the nodes it produces. A part's count
    /// is what it adds to the parts before it, within what `outputs` need, so a
    /// subexpression two parts share counts in the earlier one and the counts sum to
    /// `count_ops(outputs)` when the last part's nodes include the outputs.
    pub fn count_parts(&self, outputs: &[Id], parts: &[&[Id]]) -> Vec<OpCount> {
        let needed = self.reachable(outputs);
        let mut before = vec![false; self.len()];
        let mut counts = Vec::with_capacity(parts.len());
        let mut so_far = OpCount::default();
        for part in parts {
            let reach = self.reachable(part);
            for (b, (r, n)) in before.iter_mut().zip(reach.iter().zip(&needed)) {
                *b |= *r && *n;
            }
            let total = self.count_mask(&before);
            counts.push(total - so_far);
            so_far = total;
        }
        counts
    }

    /// Operation counts of the nodes set in `seen`.
    fn count_mask(&self, seen: &[bool]) -> OpCount {
        let mut c = OpCount::default();
        let mut trig_args = std::collections::HashSet::new();
        // Negations whose only role is to turn an addition into a subtraction are free.
        let mut absorbed = vec![false; self.len()];
        for (i, _) in seen.iter().enumerate().filter(|(_, s)| **s) {
            if let Node::Add(a, b) = self.node(Id(i as u32)) {
                for x in [a, b] {
                    if matches!(self.node(x), Node::Unary(Unary::Neg, _)) {
                        absorbed[x.index()] = true;
                    }
                }
            }
        }
        for (i, _) in seen.iter().enumerate().filter(|(_, s)| **s) {
            match self.node(Id(i as u32)) {
                Node::Add(..) => c.add += 1,
                Node::Mul(..) => c.mul += 1,
                Node::Unary(op, a) => match op {
                    Unary::Neg if !absorbed[i] => c.neg += 1,
                    Unary::Neg => {}
                    Unary::Recip => c.div += 1,
                    Unary::Sin | Unary::Cos => {
                        if trig_args.insert(a) {
                            c.trig += 1
                        }
                    }
                    Unary::Sqrt => c.sqrt += 1,
                    Unary::Exp | Unary::Ln => c.other += 1,
                },
                _ => {}
            }
        }
        c
    }
}
