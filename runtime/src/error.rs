//! Why an integration stopped early. The solution up to the failure is always kept.

use std::fmt;

use crate::Solution;

/// The reason an integration failed.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub enum ErrorKind {
    /// The step size fell below `h_min` or the round-off limit at time `t`.
    StepSizeUnderflow { t: f64, h: f64 },
    /// The simplified Newton iteration kept failing at time `t`, even after step-size
    /// reductions and a fresh Jacobian.
    NewtonDivergence { t: f64 },
    /// The right-hand side (or the new state) has a NaN or infinite `component` at `t`.
    NonFinite { t: f64, component: usize },
    /// `max_steps` step attempts were made; the last accepted time is `t`.
    MaxSteps { t: f64 },
    /// The problem or the options are invalid; nothing was integrated.
    InvalidInput(String),
    /// The initial state of a non-smooth problem violates an element's law and cannot
    /// be repaired (penetrating a rigid stop, a given stuck force beyond `f_crit`).
    InconsistentInitialData(String),
    /// At time `t` no mode, or more than one, of the switching elements is consistent
    /// (Painlevé-type or non-unique); `detail` names the candidates.
    IllPosedMode { t: f64, detail: String },
    /// The [`Observer`](crate::Observer) asked to stop after the step ending at `t`.
    Cancelled { t: f64 },
    /// A time-stepping step to `t` could not be solved: `detail` says which part (the
    /// linearised smooth step, the coupled elements' forces, one element's law) and
    /// what may help.
    StepNotSolved { t: f64, detail: String },
    /// Event-driven integration gave up near `t` because `element` kept switching
    /// through the modes in `cycle` (the last ones, in order) faster than events can be
    /// resolved; time-stepping integrates such spans.
    KeepsSwitching {
        t: f64,
        element: String,
        cycle: String,
    },
    /// At time `t` the closed mechanism could not be kept on its loops' constraints:
    /// they became singular (a change point, a dead centre) or would not close (see
    /// [`LoopError`](crate::loops::error::LoopError)).
    Loops {
        t: f64,
        error: crate::loops::error::LoopError,
    },
}

impl ErrorKind {
    /// The variant's name (`"MaxSteps"`, `"NonFinite"`, …): what an ensemble's table and
    /// the Python exceptions record as the error's kind.
    pub fn name(&self) -> &'static str {
        match self {
            ErrorKind::StepSizeUnderflow { .. } => "StepSizeUnderflow",
            ErrorKind::NewtonDivergence { .. } => "NewtonDivergence",
            ErrorKind::NonFinite { .. } => "NonFinite",
            ErrorKind::MaxSteps { .. } => "MaxSteps",
            ErrorKind::InvalidInput(_) => "InvalidInput",
            ErrorKind::InconsistentInitialData(_) => "InconsistentInitialData",
            ErrorKind::IllPosedMode { .. } => "IllPosedMode",
            ErrorKind::Cancelled { .. } => "Cancelled",
            ErrorKind::StepNotSolved { .. } => "StepNotSolved",
            ErrorKind::KeepsSwitching { .. } => "KeepsSwitching",
            ErrorKind::Loops { .. } => "Loops",
        }
    }

    /// The time the error happened at, for the kinds that have one.
    pub fn t(&self) -> Option<f64> {
        match self {
            ErrorKind::StepSizeUnderflow { t, .. }
            | ErrorKind::NewtonDivergence { t }
            | ErrorKind::NonFinite { t, .. }
            | ErrorKind::MaxSteps { t }
            | ErrorKind::IllPosedMode { t, .. }
            | ErrorKind::Cancelled { t }
            | ErrorKind::StepNotSolved { t, .. }
            | ErrorKind::KeepsSwitching { t, .. }
            | ErrorKind::Loops { t, .. } => Some(*t),
            ErrorKind::InvalidInput(_) | ErrorKind::InconsistentInitialData(_) => None,
        }
    }
}

impl fmt::Display for ErrorKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ErrorKind::StepSizeUnderflow { t, h } => {
                write!(f, "step size underflow at t = {t} (h = {h:e})")
            }
            ErrorKind::NewtonDivergence { t } => {
                write!(
                    f,
                    "Newton iteration diverges at t = {t} despite step-size reductions"
                )
            }
            ErrorKind::NonFinite { t, component } => {
                write!(f, "non-finite value in component {component} at t = {t}")
            }
            ErrorKind::MaxSteps { t } => write!(f, "maximum number of steps reached at t = {t}"),
            ErrorKind::InvalidInput(msg) => write!(f, "invalid input: {msg}"),
            ErrorKind::InconsistentInitialData(msg) => {
                write!(f, "inconsistent initial data: {msg}")
            }
            ErrorKind::IllPosedMode { t, detail } => {
                write!(f, "no unique consistent mode at t = {t}: {detail}")
            }
            ErrorKind::Cancelled { t } => write!(f, "cancelled by the observer at t = {t}"),
            ErrorKind::StepNotSolved { t, detail } => {
                write!(
                    f,
                    "the time-stepping step to t = {t} could not be solved: {detail}"
                )
            }
            ErrorKind::KeepsSwitching { t, element, cycle } => write!(
                f,
                "element `{element}` keeps switching near t = {t} ({cycle}); event-driven \
                 integration cannot resolve it — use NonSmoothMethod::TimeStepping for this \
                 run (or span)"
            ),
            ErrorKind::Loops { t, error } => write!(f, "at t = {t}: {error}"),
        }
    }
}

/// A failed integration: what went wrong, and everything computed before.
#[derive(Clone)]
pub struct SolveError {
    pub kind: ErrorKind,
    /// Everything computed up to the failure (empty for [`ErrorKind::InvalidInput`]);
    /// boxed to keep `Result<Solution, SolveError>` small.
    pub solution: Box<Solution>,
}

impl SolveError {
    pub(crate) fn new(kind: ErrorKind, solution: Solution) -> Self {
        SolveError {
            kind,
            solution: Box::new(solution),
        }
    }
}

/// The kind's message with the names the solution knows: a non-finite component by its
/// column (`v_rail`), a run out of steps with the step size it ended at and what to try.
impl fmt::Display for SolveError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let steps = self.solution.stats.steps;
        match &self.kind {
            ErrorKind::NonFinite { t, component } => match self.solution.names().get(*component) {
                Some(name) => write!(
                    f,
                    "non-finite value in `{name}` (component {component}) at t = {t}"
                )?,
                None => write!(f, "{}", self.kind)?,
            },
            ErrorKind::MaxSteps { .. } => {
                write!(f, "{}", self.kind)?;
                let times = self.solution.times();
                if let [.., a, b] = times {
                    let h = b - a;
                    if h > 0.0 {
                        write!(f, ", the last step {h:.3e} long")?;
                    }
                }
                write!(
                    f,
                    ": raise `Options::max_steps`, loosen `rtol`/`atol`, or, if the steps \
                     are held short by stiffness (a stiff spring or support: steps far \
                     shorter than the motion you see), use a stiff method (`Method::Sdirk4`, \
                     `Method::Bdf`) or `NonSmoothMethod::TimeStepping`"
                )?;
            }
            kind => write!(f, "{kind}")?,
        }
        write!(f, " (after {steps} accepted steps)")
    }
}

/// Short: the kind and the extent of the kept solution, not its rows (an `expect` on
/// a long run would otherwise print megabytes).
impl fmt::Debug for SolveError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let t = self.solution.times();
        f.debug_struct("SolveError")
            .field("kind", &self.kind)
            .field(
                "solution",
                &format_args!(
                    "{} rows{}",
                    t.len(),
                    match (t.first(), t.last()) {
                        (Some(a), Some(b)) => format!(", t ∈ [{a}, {b}]"),
                        _ => String::new(),
                    }
                ),
            )
            .field("stats", &self.solution.stats)
            .finish()
    }
}

impl std::error::Error for SolveError {}

impl std::error::Error for ErrorKind {}
