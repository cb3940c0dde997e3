//! The serialised form of a [`Solution`] (feature `serde`): schema
//! `filippov.solution/1`, stable and versioned.
//!
//! ```text
//! {
//!   "schema": "filippov.solution/1",
//!   "t": ["0e0", "1.25e-2", …],                      the rows' times
//!   "columns": [{"name": "q_x", "values": [...]}, …], one per column, a value per row
//!   "switches": [{"t", "kind", "element", "index", "from", "to", "jump",
//!                 "accumulation", "before", "after"}, …],
//!   "events": [{"event", "t", "state"}, …],
//!   "stats": {"steps": …, "rejected_steps": …, …},
//!   "output": "Steps" | {"Every": k} | {"Times": [...]},
//!   "dense": {...}                                    what `at` reads between rows
//! }
//! ```
//!
//! Every floating-point number is written as a string holding its shortest decimal form
//! that reads back to the same `f64` (`"0.1"` is written `"1e-1"`; `"inf"`, `"-inf"`,
//! `"NaN"` for the non-finite), so that any JSON reader restores every bit — serde_json
//! without its `float_roundtrip` feature parses JSON numbers to within an ulp only (it
//! changed 295,524 of 1,000,000 random doubles in a test), and Python's `float(s)` reads
//! the strings exactly. Numbers are accepted as well on reading, as a JSON writer other
//! than this one may give them. `dense` holds each row's derivative and the method's
//! dense-output polynomials (their layout belongs to this crate and may change with the
//! schema's version); a reader that wants the table only can ignore it. A different
//! `schema` is refused with an error that names both versions.

use serde::de::{self, Deserializer};
use serde::ser::Serializer;
use serde::{Deserialize, Serialize};

use super::{Output, Recorder, Segment, Solution, Switch, SwitchKind};
use crate::Stats;
use crate::element::Mode;
use crate::events::EventHit;

/// The schema this version writes and reads.
pub const SCHEMA: &str = "filippov.solution/1";

/// An `f64` written as its shortest round-trip decimal string.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Exact(f64);

impl Serialize for Exact {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        if self.0.is_nan() {
            s.serialize_str("NaN")
        } else {
            s.serialize_str(&format!("{:e}", self.0))
        }
    }
}

impl<'de> Deserialize<'de> for Exact {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct V;
        impl de::Visitor<'_> for V {
            type Value = Exact;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str("a number, or a string holding one")
            }
            fn visit_str<E: de::Error>(self, s: &str) -> Result<Exact, E> {
                s.parse::<f64>()
                    .map(Exact)
                    .map_err(|_| E::custom(format!("`{s}` is not a number")))
            }
            fn visit_f64<E: de::Error>(self, x: f64) -> Result<Exact, E> {
                Ok(Exact(x))
            }
            fn visit_i64<E: de::Error>(self, x: i64) -> Result<Exact, E> {
                Ok(Exact(x as f64))
            }
            fn visit_u64<E: de::Error>(self, x: u64) -> Result<Exact, E> {
                Ok(Exact(x as f64))
            }
        }
        d.deserialize_any(V)
    }
}

fn exact(x: &[f64]) -> Vec<Exact> {
    x.iter().copied().map(Exact).collect()
}

fn plain(x: &[Exact]) -> Vec<f64> {
    x.iter().map(|e| e.0).collect()
}

#[derive(Serialize, Deserialize)]
struct Column {
    name: String,
    values: Vec<Exact>,
}

#[derive(Serialize, Deserialize)]
struct SwitchV1 {
    t: Exact,
    kind: SwitchKind,
    element: Option<String>,
    index: Option<usize>,
    from: Option<Mode>,
    to: Option<Mode>,
    jump: Exact,
    accumulation: Option<Exact>,
    before: Vec<Exact>,
    after: Vec<Exact>,
}

#[derive(Serialize, Deserialize)]
struct EventV1 {
    event: usize,
    t: Exact,
    state: Vec<Exact>,
}

#[derive(Serialize, Deserialize)]
enum OutputV1 {
    Steps,
    Every(usize),
    Times(Vec<Exact>),
}

/// One row's interval of dense output: the polynomial's degree (`0`: cubic Hermite on
/// the rows), whether it is a one-step method's own extension, its coefficients.
#[derive(Serialize, Deserialize)]
struct SegmentV1 {
    degree: usize,
    one_step: bool,
    coefficients: Vec<Exact>,
}

/// The row filter's state between steps (a solution still being written).
#[derive(Serialize, Deserialize)]
struct FilterV1 {
    skipped: usize,
    next: usize,
    t: Exact,
    row: Vec<Exact>,
    drow: Vec<Exact>,
    started: bool,
}

#[derive(Serialize, Deserialize)]
struct DenseV1 {
    /// The leading columns the dense output covers (later ones: linear between rows).
    columns: usize,
    /// The leading columns read back as positions (the quintic in `q, q̇, q̈`).
    positions: Option<usize>,
    /// Each row's derivative.
    derivatives: Vec<Vec<Exact>>,
    /// `segments[i]`: from row `i − 1` to row `i` (`segments[0]` unused).
    segments: Vec<SegmentV1>,
    filter: FilterV1,
}

#[derive(Serialize, Deserialize)]
struct SolutionV1 {
    schema: String,
    t: Vec<Exact>,
    columns: Vec<Column>,
    switches: Vec<SwitchV1>,
    events: Vec<EventV1>,
    stats: Stats,
    output: OutputV1,
    dense: DenseV1,
}

impl Serialize for Solution {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        let n = self.t.len();
        let dim = self.dim;
        let columns = (0..dim)
            .map(|j| Column {
                name: self.names[j].clone(),
                values: (0..n).map(|i| Exact(self.y[i * dim + j])).collect(),
            })
            .collect();
        // A segment's coefficients: (degree + 1) blocks of the dense columns.
        let len = |g: &Segment| (g.degree + 1) * self.dense_dim;
        let segments = self
            .seg
            .iter()
            .map(|g| SegmentV1 {
                degree: g.degree,
                one_step: g.one_step,
                coefficients: if g.degree > 0 {
                    exact(&self.coeffs[g.offset..g.offset + len(g)])
                } else {
                    Vec::new()
                },
            })
            .collect();
        let r = &self.recorder;
        SolutionV1 {
            schema: SCHEMA.to_string(),
            t: exact(&self.t),
            columns,
            switches: self
                .switches
                .iter()
                .map(|w| SwitchV1 {
                    t: Exact(w.t),
                    kind: w.kind,
                    element: w.element.clone(),
                    index: w.index,
                    from: w.from,
                    to: w.to,
                    jump: Exact(w.jump),
                    accumulation: w.accumulation.map(Exact),
                    before: exact(&w.before),
                    after: exact(&w.after),
                })
                .collect(),
            events: self
                .events
                .iter()
                .map(|e| EventV1 {
                    event: e.event,
                    t: Exact(e.t),
                    state: exact(&e.state),
                })
                .collect(),
            stats: self.stats,
            output: match &self.output {
                Output::Steps => OutputV1::Steps,
                Output::Every(k) => OutputV1::Every(*k),
                Output::Times(ts) => OutputV1::Times(exact(ts)),
            },
            dense: DenseV1 {
                columns: self.dense_dim,
                positions: self.dense_positions,
                derivatives: self.dy.chunks(dim.max(1)).map(exact).collect(),
                segments,
                filter: FilterV1 {
                    skipped: r.skipped,
                    next: r.next,
                    t: Exact(r.t),
                    row: exact(&r.row),
                    drow: exact(&r.drow),
                    started: r.started,
                },
            },
        }
        .serialize(s)
    }
}

impl<'de> Deserialize<'de> for Solution {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let v = SolutionV1::deserialize(d)?;
        if v.schema != SCHEMA {
            return Err(de::Error::custom(format!(
                "schema `{}`: this version of filippov reads `{SCHEMA}`",
                v.schema
            )));
        }
        let (n, dim) = (v.t.len(), v.columns.len());
        if let Some(c) = v.columns.iter().find(|c| c.values.len() != n) {
            return Err(de::Error::custom(format!(
                "column `{}` has {} values for {n} times",
                c.name,
                c.values.len()
            )));
        }
        if v.dense.derivatives.len() != n || v.dense.derivatives.iter().any(|d| d.len() != dim) {
            return Err(de::Error::custom(format!(
                "dense.derivatives must hold {n} rows of {dim} values"
            )));
        }
        if v.dense.segments.len() != n {
            return Err(de::Error::custom(format!(
                "dense.segments must hold one entry per row ({n})"
            )));
        }
        let dense_dim = v.dense.columns.min(dim);
        if let Some(i) = v.dense.segments.iter().position(|g| {
            g.coefficients.len()
                != if g.degree > 0 {
                    (g.degree + 1) * dense_dim
                } else {
                    0
                }
        }) {
            return Err(de::Error::custom(format!(
                "dense.segments[{i}] needs (degree + 1) · {dense_dim} coefficients"
            )));
        }
        let mut y = vec![0.0; n * dim];
        for (j, c) in v.columns.iter().enumerate() {
            for (i, x) in c.values.iter().enumerate() {
                y[i * dim + j] = x.0;
            }
        }
        let mut coeffs = Vec::new();
        let seg = v
            .dense
            .segments
            .iter()
            .map(|g| {
                let offset = if g.degree > 0 { coeffs.len() } else { 0 };
                coeffs.extend(g.coefficients.iter().map(|e| e.0));
                Segment {
                    offset,
                    degree: g.degree,
                    one_step: g.one_step,
                }
            })
            .collect();
        let f = v.dense.filter;
        Ok(Solution {
            dim,
            dense_dim,
            names: v.columns.into_iter().map(|c| c.name).collect(),
            t: plain(&v.t),
            y,
            dy: v.dense.derivatives.iter().flat_map(|d| plain(d)).collect(),
            seg,
            coeffs,
            stats: v.stats,
            switches: v
                .switches
                .into_iter()
                .map(|w| Switch {
                    t: w.t.0,
                    kind: w.kind,
                    element: w.element,
                    index: w.index,
                    from: w.from,
                    to: w.to,
                    jump: w.jump.0,
                    accumulation: w.accumulation.map(|a| a.0),
                    before: plain(&w.before),
                    after: plain(&w.after),
                })
                .collect(),
            events: v
                .events
                .into_iter()
                .map(|e| EventHit {
                    event: e.event,
                    t: e.t.0,
                    state: plain(&e.state),
                })
                .collect(),
            output: match v.output {
                OutputV1::Steps => Output::Steps,
                OutputV1::Every(k) => Output::Every(k),
                OutputV1::Times(ts) => Output::Times(plain(&ts)),
            },
            recorder: Recorder {
                skipped: f.skipped,
                next: f.next,
                t: f.t.0,
                row: plain(&f.row),
                drow: plain(&f.drow),
                started: f.started,
            },
            dense_positions: v.dense.positions,
        })
    }
}
