//! Ensembles: many non-smooth runs of one scene, each with its own parameters and
//! initial state, drawn reproducibly, reduced to a row of numbers, and gathered into a
//! table that keeps failed runs with their error.
//!
//! A run's inputs are a pure function of the ensemble and the run's index: grid values
//! by the index, random values from a generator seeded by `(seed, index)` alone. So any
//! range of runs, on any thread, process or machine, gives the same rows as a plain
//! loop — the property that lets an ensemble be cut into chunks for a cluster
//! (docs/python.md) and still equal the single-machine table bit for bit.
//!
//! ```
//! # use filippov_runtime::ensemble::{Draw, Ensemble};
//! # fn demo<S: filippov_runtime::nonsmooth::NonSmooth<1> + filippov_runtime::system::Parameters + Sync>() {
//! let ens = Ensemble::<S, 1>::new(
//!     vec![Draw::Fixed(1.0), Draw::Uniform { low: 0.1, high: 2.0 }],
//!     vec![Draw::Grid(vec![0.5, 1.0, 1.5])],
//!     vec![Draw::Fixed(0.0)],
//!     100, // random samples per grid point
//!     7,   // seed
//!     5.0, // t_end
//! )
//! .unwrap();
//! let table = ens.table(0..ens.len(), None, false); // on every core (feature `parallel`)
//! # }
//! ```
//!
//! Runs go through [`solve_nonsmooth`] with the ensemble's
//! [`NonSmoothMethod`]; the default reduction is the final state `[q; v]`, the number of
//! switch-log entries and of steps ([`final_state`]); [`Ensemble::table_with`] takes any.

use std::marker::PhantomData;
use std::ops::Range;

use nalgebra::SVector;

use crate::nonsmooth::NonSmooth;
use crate::system::Parameters;
use crate::{NonSmoothMethod, NonSmoothProblem, Solution, solve_nonsmooth};

/// How one input of the runs is chosen.
#[derive(Clone, Debug, PartialEq)]
pub enum Draw {
    /// The same value in every run.
    Fixed(f64),
    /// Uniform in `[low, high)`, drawn per run.
    Uniform { low: f64, high: f64 },
    /// Each of these values: the ensemble runs the Cartesian product of its grids.
    Grid(Vec<f64>),
}

/// Why a run of an ensemble failed: the error's kind (`"MaxSteps"`, …, or
/// `"InvalidParameters"` for drawn parameters the scene refuses) and its message.
#[derive(Clone, Debug, PartialEq)]
pub struct RunError {
    pub kind: String,
    pub message: String,
}

/// The rows of an ensemble, one per run, in run order.
#[derive(Clone, Debug, PartialEq)]
pub struct Table {
    /// The inputs' names: the parameters, then `q0_<joint>`, then `v0_<joint>`.
    pub input_names: Vec<String>,
    /// The reduction's names.
    pub output_names: Vec<String>,
    /// The runs' indices.
    pub runs: Vec<usize>,
    /// The inputs, row by row.
    pub inputs: Vec<f64>,
    /// The outputs, row by row (NaN for a failed run).
    pub outputs: Vec<f64>,
    /// `None` for a run that finished, its error otherwise.
    pub errors: Vec<Option<RunError>>,
}

impl Table {
    /// The inputs of the `k`-th row.
    pub fn input_row(&self, k: usize) -> &[f64] {
        let w = self.input_names.len();
        &self.inputs[k * w..(k + 1) * w]
    }

    /// The outputs of the `k`-th row.
    pub fn output_row(&self, k: usize) -> &[f64] {
        let w = self.output_names.len();
        &self.outputs[k * w..(k + 1) * w]
    }
}

/// The default reduction's names for a scene with these joints.
pub fn final_state_names(joints: &[&str]) -> Vec<String> {
    let mut names: Vec<String> = joints.iter().map(|j| format!("q_{j}")).collect();
    names.extend(joints.iter().map(|j| format!("v_{j}")));
    names.extend(["switches".to_string(), "steps".to_string()]);
    names
}

/// The default reduction: the final `[q; v]`, the switch-log entries, the steps.
pub fn final_state(n: usize, sol: &Solution) -> Vec<f64> {
    let mut out: Vec<f64> = sol
        .last()
        .map_or(vec![f64::NAN; 2 * n], |(_, y)| y[..2 * n].to_vec());
    out.push(sol.switches.len() as f64);
    out.push(sol.stats.steps as f64);
    out
}

/// A reproducible generator for one run: SplitMix64 (Steele, Lea & Flood 2014), seeded
/// by the ensemble's seed and the run's index.
struct SplitMix(u64);

impl SplitMix {
    fn new(seed: u64, run: usize) -> Self {
        SplitMix(
            seed ^ (run as u64)
                .wrapping_add(1)
                .wrapping_mul(0x9E37_79B9_7F4A_7C15),
        )
    }

    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in `[0, 1)` with 53 random bits.
    fn uniform(&mut self) -> f64 {
        (self.next() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
    }
}

/// An ensemble of non-smooth runs of the scene `S` (see the module documentation).
#[derive(Clone)]
pub struct Ensemble<S, const N: usize> {
    draws: Vec<Draw>,
    samples: usize,
    grid_points: usize,
    seed: u64,
    t_end: f64,
    method: NonSmoothMethod,
    scene: PhantomData<fn() -> S>,
}

impl<S, const N: usize> std::fmt::Debug for Ensemble<S, N> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Ensemble")
            .field("draws", &self.draws)
            .field("samples", &self.samples)
            .field("grid_points", &self.grid_points)
            .field("seed", &self.seed)
            .field("t_end", &self.t_end)
            .field("method", &self.method)
            .finish()
    }
}

impl<S, const N: usize> Ensemble<S, N>
where
    S: NonSmooth<N> + Parameters + Sync,
{
    /// An ensemble over `parameters` (one draw per [`Parameters::NAMES`]), `q0` and `v0`
    /// (one each per coordinate): `samples` random draws at each point of the grids'
    /// product, from `seed`, each run from `t = 0` to `t_end` with the default
    /// [`NonSmoothMethod`]. Errors name the input that is wrong.
    pub fn new(
        parameters: Vec<Draw>,
        q0: Vec<Draw>,
        v0: Vec<Draw>,
        samples: usize,
        seed: u64,
        t_end: f64,
    ) -> Result<Self, String> {
        if parameters.len() != S::NAMES.len() {
            return Err(format!(
                "{} parameter draws for the {} parameters ({})",
                parameters.len(),
                S::NAMES.len(),
                S::NAMES.join(", ")
            ));
        }
        for (what, d) in [("q0", &q0), ("v0", &v0)] {
            if d.len() != N {
                return Err(format!("{what} has {} draws for {N} coordinates", d.len()));
            }
        }
        if samples == 0 {
            return Err("samples must be at least 1".into());
        }
        if !(t_end.is_finite() && t_end > 0.0) {
            return Err(format!("t_end = {t_end} must be positive and finite"));
        }
        let mut draws = parameters;
        draws.extend(q0);
        draws.extend(v0);
        let names = Self::names();
        let mut grid_points: usize = 1;
        for (d, name) in draws.iter().zip(&names) {
            match d {
                Draw::Fixed(x) if !x.is_finite() => {
                    return Err(format!("{name} = {x} is not finite"));
                }
                Draw::Uniform { low, high }
                    if !(low.is_finite() && high.is_finite() && low <= high) =>
                {
                    return Err(format!(
                        "{name}: uniform draws need finite low ≤ high (low = {low}, high = {high})"
                    ));
                }
                Draw::Grid(v) if v.is_empty() || v.iter().any(|x| !x.is_finite()) => {
                    return Err(format!("{name}: a grid needs finite values, at least one"));
                }
                Draw::Grid(v) => {
                    grid_points = grid_points
                        .checked_mul(v.len())
                        .ok_or("the grids' product overflows")?;
                }
                _ => {}
            }
        }
        grid_points
            .checked_mul(samples)
            .ok_or("runs = grid points × samples overflows")?;
        Ok(Ensemble {
            draws,
            samples,
            grid_points,
            seed,
            t_end,
            method: NonSmoothMethod::default(),
            scene: PhantomData,
        })
    }

    /// The same ensemble run with `method`.
    pub fn with_method(mut self, method: NonSmoothMethod) -> Self {
        self.method = method;
        self
    }

    /// The number of runs: the grids' points times the samples at each.
    pub fn len(&self) -> usize {
        self.grid_points * self.samples
    }

    /// Whether it has no runs (never: `samples ≥ 1` and grids are not empty).
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The inputs' names: the parameters, then `q0_<joint>`, then `v0_<joint>`.
    pub fn names() -> Vec<String> {
        let mut names: Vec<String> = S::NAMES.iter().map(|s| s.to_string()).collect();
        names.extend(S::JOINTS.iter().map(|j| format!("q0_{j}")));
        names.extend(S::JOINTS.iter().map(|j| format!("v0_{j}")));
        names
    }

    /// Run `i`'s inputs, in the order of [`names`](Self::names): grid values by the
    /// grid point `i / samples` (the first grid varying slowest), random ones drawn in
    /// input order from the generator of `(seed, i)`.
    pub fn inputs(&self, i: usize) -> Vec<f64> {
        let mut rng = SplitMix::new(self.seed, i);
        let mut point = i / self.samples;
        let mut stride = self.grid_points;
        self.draws
            .iter()
            .map(|d| match d {
                Draw::Fixed(x) => *x,
                Draw::Uniform { low, high } => low + (high - low) * rng.uniform(),
                Draw::Grid(v) => {
                    stride /= v.len();
                    let k = point / stride;
                    point %= stride;
                    v[k]
                }
            })
            .collect()
    }

    /// Run `i`, reduced by `reduce`.
    pub fn run_with<R>(&self, i: usize, reduce: &R) -> (Vec<f64>, Result<Vec<f64>, RunError>)
    where
        R: Fn(&Solution) -> Vec<f64>,
    {
        let x = self.inputs(i);
        let np = S::NAMES.len();
        let scene = S::from_values(&x[..np]).expect("one value per parameter");
        if let Err(e) = scene.validate() {
            let err = RunError {
                kind: "InvalidParameters".into(),
                message: e.to_string(),
            };
            return (x, Err(err));
        }
        let q0 = SVector::<f64, N>::from_column_slice(&x[np..np + N]);
        let v0 = SVector::<f64, N>::from_column_slice(&x[np + N..]);
        let problem = NonSmoothProblem::new(0.0, self.t_end, q0, v0);
        let zero = |_t: f64, _q: &SVector<f64, N>, _v: &SVector<f64, N>| SVector::zeros();
        let out = match solve_nonsmooth(&scene, &zero, &problem, &self.method) {
            Ok(sol) => Ok(reduce(&sol)),
            Err(e) => Err(RunError {
                kind: e.kind.name().to_string(),
                message: e.to_string(),
            }),
        };
        (x, out)
    }

    /// The table of `runs` with the default reduction ([`final_state`]); `threads`:
    /// `None` for every core (feature `parallel`; one thread without it), `Some(1)` for
    /// a plain loop on this thread.
    pub fn table(&self, runs: Range<usize>, threads: Option<usize>, progress: bool) -> Table {
        let names = final_state_names(&S::JOINTS);
        self.table_with(runs, names, &|sol| final_state(N, sol), threads, progress)
    }

    /// The table of `runs` reduced by `reduce` (its outputs called `names`).
    pub fn table_with<R>(
        &self,
        runs: Range<usize>,
        names: Vec<String>,
        reduce: &R,
        threads: Option<usize>,
        progress: bool,
    ) -> Table
    where
        R: Fn(&Solution) -> Vec<f64> + Sync,
    {
        let runs = runs.start.min(self.len())..runs.end.min(self.len());
        let width = names.len();
        let rows = parallel::map(runs.clone(), threads, progress, &|i| {
            self.run_with(i, reduce)
        });
        let mut table = Table {
            input_names: Self::names(),
            output_names: names,
            runs: runs.collect(),
            inputs: Vec::new(),
            outputs: Vec::new(),
            errors: Vec::new(),
        };
        for (x, out) in rows {
            table.inputs.extend(x);
            match out {
                Ok(y) => {
                    assert_eq!(
                        y.len(),
                        width,
                        "the reduction gave {} values for {width} names",
                        y.len()
                    );
                    table.outputs.extend(y);
                    table.errors.push(None);
                }
                Err(e) => {
                    table.outputs.extend(std::iter::repeat_n(f64::NAN, width));
                    table.errors.push(Some(e));
                }
            }
        }
        table
    }
}

/// `f` over a range of runs, in order: on a rayon pool (feature `parallel`), or a loop.
mod parallel {
    use std::ops::Range;

    /// Without the feature: a loop on this thread (`progress` is not drawn).
    #[cfg(not(feature = "parallel"))]
    pub fn map<T: Send>(
        runs: Range<usize>,
        _threads: Option<usize>,
        _progress: bool,
        f: &(dyn Fn(usize) -> T + Sync),
    ) -> Vec<T> {
        runs.map(f).collect()
    }

    /// `threads`: `None` for rayon's global pool (every core), `Some(1)` for a loop on
    /// this thread, `Some(n)` for a pool of `n`. `progress` draws a bar on stderr (when
    /// it is a terminal).
    #[cfg(feature = "parallel")]
    pub fn map<T: Send>(
        runs: Range<usize>,
        threads: Option<usize>,
        progress: bool,
        f: &(dyn Fn(usize) -> T + Sync),
    ) -> Vec<T> {
        use rayon::prelude::*;
        let bar = if progress {
            indicatif::ProgressBar::new(runs.len() as u64)
        } else {
            indicatif::ProgressBar::hidden()
        };
        bar.set_style(
            indicatif::ProgressStyle::with_template(
                "{bar:40} {pos}/{len} runs, {elapsed}, eta {eta}",
            )
            .expect("a valid template"),
        );
        let one = |i: usize| {
            let out = f(i);
            bar.inc(1);
            out
        };
        let out = match threads {
            Some(1) => runs.map(one).collect(),
            None => runs.into_par_iter().map(one).collect(),
            Some(n) => match rayon::ThreadPoolBuilder::new().num_threads(n).build() {
                Ok(pool) => pool.install(|| runs.into_par_iter().map(one).collect()),
                // No pool to be had: the global one.
                Err(_) => runs.into_par_iter().map(one).collect(),
            },
        };
        bar.finish_and_clear();
        out
    }
}
