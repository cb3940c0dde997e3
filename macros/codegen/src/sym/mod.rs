//! The symbolic engine: a hash-consed expression DAG.
//!
//! Expressions live in one flat arena ([`Graph`]) indexed by a small [`Id`]; children
//! always have smaller ids than their parents, so the arena order *is* a topological
//! order. Every constructor folds constants and applies the few identities that matter
//! for mechanics (exact zeros and ones, double negation, `sin² + cos² = 1`, odd/even
//! trigonometric symmetry), then interns the node: a subexpression exists once, so common
//! subexpression elimination is free and the emitter only has to decide which shared
//! nodes get a `let`.
//!
//! Passes over the DAG: `diff.rs` ([`Graph::diff`], memoised differentiation), `subst.rs`
//! ([`Graph::substitute`]),
//! `count.rs` ([`Graph::count_ops`], operation counts).

mod count;
mod diff;
mod graph;
mod hash;
mod subst;

pub use count::OpCount;
pub use graph::{Graph, Id, Input, InputKind, Node, Unary};
pub use hash::FastMap;
