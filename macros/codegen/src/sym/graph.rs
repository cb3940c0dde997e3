//! The arena, the node kinds and the folding constructors.

use super::hash::FastMap;

/// Index of a node in a [`Graph`]. Children have smaller ids than their parents.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct Id(pub u32);

impl Id {
    pub fn index(self) -> usize {
        self.0 as usize
    }
}

/// Which argument of a generated function an input symbol stands for.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum InputKind {
    /// Joint coordinate `q[i]`.
    Q,
    /// Joint velocity `v[i]`.
    V,
    /// Joint acceleration `a[i]` (inverse dynamics).
    A,
    /// Applied generalised force `tau[i]`.
    Tau,
    /// Force `f[e]` of non-smooth element `e`.
    F,
}

/// An input symbol: `kind[index]`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct Input {
    pub kind: InputKind,
    pub index: u16,
}

/// Elementary functions of one argument.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Unary {
    Neg,
    Recip,
    Sin,
    Cos,
    Sqrt,
    Exp,
    Ln,
}

/// One node of the DAG. Constants are stored by their bit pattern so nodes hash.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Node {
    Const(u64),
    /// A field of the user's struct (a physical parameter), by field index.
    Param(u16),
    Input(Input),
    /// Sum of two nodes, children ordered (`a <= b`).
    Add(Id, Id),
    /// Product of two nodes, children ordered (`a <= b`).
    Mul(Id, Id),
    Unary(Unary, Id),
}

/// Bit masks of the coordinates (and velocities) a node depends on; they let
/// differentiation skip whole subgraphs that cannot depend on the variable. Input `i`
/// sets bit `i mod 64`: beyond 64 inputs a bit stands for several, which only skips
/// less.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Deps {
    pub q: u64,
    pub v: u64,
    /// Depends on an acceleration or force input (never differentiated).
    pub other: bool,
}

impl Deps {
    fn union(self, o: Deps) -> Deps {
        Deps {
            q: self.q | o.q,
            v: self.v | o.v,
            other: self.other || o.other,
        }
    }
}

/// The arena: nodes, their dependency masks, and the interning table.
#[derive(Default)]
pub struct Graph {
    nodes: Vec<Node>,
    deps: Vec<Deps>,
    memo: FastMap<Node, Id>,
    pub(crate) diff_memo: FastMap<(Id, Input), Id>,
}

impl Graph {
    pub fn new() -> Self {
        Self::default()
    }

    pub fn len(&self) -> usize {
        self.nodes.len()
    }

    pub fn is_empty(&self) -> bool {
        self.nodes.is_empty()
    }

    pub fn node(&self, id: Id) -> Node {
        self.nodes[id.index()]
    }

    pub fn deps(&self, id: Id) -> Deps {
        self.deps[id.index()]
    }

    /// The id of `node` if it exists in the graph.
    pub fn find(&self, node: Node) -> Option<Id> {
        self.memo.get(&node).copied()
    }

    fn intern(&mut self, node: Node) -> Id {
        if let Some(&id) = self.memo.get(&node) {
            return id;
        }
        let deps = match node {
            Node::Const(_) | Node::Param(_) => Deps::default(),
            Node::Input(Input { kind, index }) => match kind {
                InputKind::Q => Deps {
                    q: 1 << (index % 64),
                    ..Deps::default()
                },
                InputKind::V => Deps {
                    v: 1 << (index % 64),
                    ..Deps::default()
                },
                InputKind::A | InputKind::Tau | InputKind::F => Deps {
                    other: true,
                    ..Deps::default()
                },
            },
            Node::Add(a, b) | Node::Mul(a, b) => self.deps(a).union(self.deps(b)),
            Node::Unary(_, a) => self.deps(a),
        };
        let id = Id(u32::try_from(self.nodes.len()).expect("expression graph too large"));
        self.nodes.push(node);
        self.deps.push(deps);
        self.memo.insert(node, id);
        id
    }

    // ---- leaves ----------------------------------------------------------------------

    pub fn constant(&mut self, c: f64) -> Id {
        // -0.0 and 0.0 are one constant.
        let c = if c == 0.0 { 0.0 } else { c };
        self.intern(Node::Const(c.to_bits()))
    }

    pub fn zero(&mut self) -> Id {
        self.constant(0.0)
    }

    pub fn one(&mut self) -> Id {
        self.constant(1.0)
    }

    pub fn param(&mut self, field: u16) -> Id {
        self.intern(Node::Param(field))
    }

    pub fn input(&mut self, kind: InputKind, index: usize) -> Id {
        let index = u16::try_from(index).expect("input index fits u16");
        self.intern(Node::Input(Input { kind, index }))
    }

    /// The value of a constant node.
    pub fn as_const(&self, id: Id) -> Option<f64> {
        match self.node(id) {
            Node::Const(bits) => Some(f64::from_bits(bits)),
            _ => None,
        }
    }

    pub fn is_zero(&self, id: Id) -> bool {
        self.as_const(id) == Some(0.0)
    }

    pub fn is_one(&self, id: Id) -> bool {
        self.as_const(id) == Some(1.0)
    }

    /// `x` if `id` is `-x`.
    fn negated(&self, id: Id) -> Option<Id> {
        match self.node(id) {
            Node::Unary(Unary::Neg, x) => Some(x),
            _ => None,
        }
    }

    // ---- arithmetic --------------------------------------------------------------------

    pub fn add(&mut self, a: Id, b: Id) -> Id {
        if let (Some(x), Some(y)) = (self.as_const(a), self.as_const(b)) {
            return self.constant(x + y);
        }
        if self.is_zero(a) {
            return b;
        }
        if self.is_zero(b) {
            return a;
        }
        // x + (-x) = 0
        if self.negated(a) == Some(b) || self.negated(b) == Some(a) {
            return self.zero();
        }
        // (-x) + (-y) = -(x + y): keeps negations at the top, where they cancel.
        if let (Some(x), Some(y)) = (self.negated(a), self.negated(b)) {
            let s = self.add(x, y);
            return self.neg(s);
        }
        if let Some(k) = self.pythagorean(a, b) {
            return k;
        }
        // x + x = 2 x
        if a == b {
            let two = self.constant(2.0);
            return self.mul(two, a);
        }
        let (a, b) = if a <= b { (a, b) } else { (b, a) };
        self.intern(Node::Add(a, b))
    }

    pub fn sub(&mut self, a: Id, b: Id) -> Id {
        let nb = self.neg(b);
        self.add(a, nb)
    }

    pub fn mul(&mut self, a: Id, b: Id) -> Id {
        if let (Some(x), Some(y)) = (self.as_const(a), self.as_const(b)) {
            return self.constant(x * y);
        }
        if self.is_zero(a) || self.is_zero(b) {
            return self.zero();
        }
        if self.is_one(a) {
            return b;
        }
        if self.is_one(b) {
            return a;
        }
        if self.as_const(a) == Some(-1.0) {
            return self.neg(b);
        }
        if self.as_const(b) == Some(-1.0) {
            return self.neg(a);
        }
        // Pull negations out of products: (-x) y = -(x y).
        if let Some(x) = self.negated(a) {
            let p = self.mul(x, b);
            return self.neg(p);
        }
        if let Some(y) = self.negated(b) {
            let p = self.mul(a, y);
            return self.neg(p);
        }
        // Negative constants become a negation of a positive one, for the same reason.
        if let Some(c) = self.as_const(a).filter(|c| *c < 0.0) {
            let k = self.constant(-c);
            let p = self.mul(k, b);
            return self.neg(p);
        }
        if let Some(c) = self.as_const(b).filter(|c| *c < 0.0) {
            let k = self.constant(-c);
            let p = self.mul(a, k);
            return self.neg(p);
        }
        // k₁ (k₂ x) = (k₁ k₂) x: constant factors merge.
        for (k, other) in [(a, b), (b, a)] {
            if let (Some(k1), Node::Mul(x, y)) = (self.as_const(k), self.node(other)) {
                if let Some(k2) = self.as_const(x) {
                    let kk = self.constant(k1 * k2);
                    return self.mul(kk, y);
                }
                if let Some(k2) = self.as_const(y) {
                    let kk = self.constant(k1 * k2);
                    return self.mul(kk, x);
                }
            }
        }
        // x · (1/x) = 1
        if self.node(b) == Node::Unary(Unary::Recip, a)
            || self.node(a) == Node::Unary(Unary::Recip, b)
        {
            return self.one();
        }
        let (a, b) = if a <= b { (a, b) } else { (b, a) };
        self.intern(Node::Mul(a, b))
    }

    pub fn div(&mut self, a: Id, b: Id) -> Id {
        if a == b && !self.is_zero(a) {
            return self.one();
        }
        let r = self.recip(b);
        self.mul(a, r)
    }

    pub fn neg(&mut self, a: Id) -> Id {
        if let Some(c) = self.as_const(a) {
            return self.constant(-c);
        }
        if let Some(x) = self.negated(a) {
            return x;
        }
        self.intern(Node::Unary(Unary::Neg, a))
    }

    pub fn recip(&mut self, a: Id) -> Id {
        if let Some(c) = self.as_const(a) {
            return self.constant(1.0 / c);
        }
        match self.node(a) {
            Node::Unary(Unary::Recip, x) => return x,
            Node::Unary(Unary::Neg, x) => {
                let r = self.recip(x);
                return self.neg(r);
            }
            _ => {}
        }
        self.intern(Node::Unary(Unary::Recip, a))
    }

    pub fn sin(&mut self, a: Id) -> Id {
        if let Some(c) = self.as_const(a) {
            return self.constant(snap(c.sin()));
        }
        if let Some(x) = self.negated(a) {
            let s = self.sin(x);
            return self.neg(s);
        }
        self.intern(Node::Unary(Unary::Sin, a))
    }

    pub fn cos(&mut self, a: Id) -> Id {
        if let Some(c) = self.as_const(a) {
            return self.constant(snap(c.cos()));
        }
        if let Some(x) = self.negated(a) {
            return self.cos(x);
        }
        self.intern(Node::Unary(Unary::Cos, a))
    }

    pub fn unary(&mut self, op: Unary, a: Id) -> Id {
        match op {
            Unary::Neg => self.neg(a),
            Unary::Recip => self.recip(a),
            Unary::Sin => self.sin(a),
            Unary::Cos => self.cos(a),
            Unary::Sqrt | Unary::Exp | Unary::Ln => {
                if let Some(c) = self.as_const(a) {
                    let v = match op {
                        Unary::Sqrt => c.sqrt(),
                        Unary::Exp => c.exp(),
                        _ => c.ln(),
                    };
                    if v.is_finite() {
                        return self.constant(v);
                    }
                }
                self.intern(Node::Unary(op, a))
            }
        }
    }

    /// `k sin²x + k cos²x = k` for the two summands of an addition, `k` optional.
    fn pythagorean(&mut self, a: Id, b: Id) -> Option<Id> {
        let (ka, sa) = self.scaled_trig_square(a)?;
        let (kb, sb) = self.scaled_trig_square(b)?;
        if ka != kb {
            return None;
        }
        match (self.node(sa), self.node(sb)) {
            (Node::Unary(Unary::Sin, x), Node::Unary(Unary::Cos, y))
            | (Node::Unary(Unary::Cos, x), Node::Unary(Unary::Sin, y))
                if x == y =>
            {
                Some(ka.unwrap_or_else(|| self.one()))
            }
            _ => None,
        }
    }

    /// `(k, t)` when `id` is `k · t · t` (or `t · t`, `k = None`) with `t` a sin or cos.
    fn scaled_trig_square(&self, id: Id) -> Option<(Option<Id>, Id)> {
        let is_trig =
            |g: &Self, t: Id| matches!(g.node(t), Node::Unary(Unary::Sin | Unary::Cos, _));
        match self.node(id) {
            Node::Mul(x, y) if x == y && is_trig(self, x) => Some((None, x)),
            Node::Mul(x, y) => {
                for (k, sq) in [(x, y), (y, x)] {
                    if let Node::Mul(t, u) = self.node(sq)
                        && t == u
                        && is_trig(self, t)
                    {
                        return Some((Some(k), t));
                    }
                }
                None
            }
            _ => None,
        }
    }

    /// Sum of many nodes (zero for none).
    pub fn sum(&mut self, terms: impl IntoIterator<Item = Id>) -> Id {
        let mut acc = self.zero();
        for t in terms {
            acc = self.add(acc, t);
        }
        acc
    }

    /// `Σ a_i b_i`.
    pub fn dot(&mut self, a: &[Id], b: &[Id]) -> Id {
        let mut acc = self.zero();
        for (&x, &y) in a.iter().zip(b) {
            let p = self.mul(x, y);
            acc = self.add(acc, p);
        }
        acc
    }
}

/// Rounds values within 1e-15 of 0 or ±1 to them: `cos(π/2)` of a literal roll angle is
/// an exact zero for the folding, not 6e-17.
fn snap(x: f64) -> f64 {
    for t in [0.0, 1.0, -1.0] {
        if (x - t).abs() < 1e-15 {
            return t;
        }
    }
    x
}
