//! A non-smooth initial value problem and the choice of integrator.

use nalgebra::SVector;

use crate::Method;
use crate::Output;
use crate::options::Options;

/// `q(t0) = q0`, `v(t0) = v0` on `[t0, tf]`. Where the initial state leaves an element's
/// force undetermined (a stuck friction element: any `|f| ≤ f_crit` holds it), the force
/// the thesis starts with may be given in `forces0` (one entry per element, `None` =
/// determined by consistent initialisation).
#[derive(Clone, Debug, PartialEq)]
pub struct NonSmoothProblem<const N: usize> {
    pub t0: f64,
    pub tf: f64,
    pub q0: SVector<f64, N>,
    pub v0: SVector<f64, N>,
    pub forces0: Vec<Option<f64>>,
    /// Which rows the solution keeps (every step by default; event rows always).
    pub output: Output,
    /// Times where the input may jump (a sampled controller's updates given as a
    /// function of time): steps end exactly there, and the event-driven method selects
    /// the modes again and restarts its smooth method, as at a
    /// [`set_input`](super::Integrator::set_input). Increasing, inside `(t0, tf)`.
    /// A step that ends at a stop `s` reads the input at no time later than the float
    /// just below `s`, so a function that takes its value `u_k` on `[s_k, s_{k+1})`
    /// acts with `u_k` over that whole interval.
    pub tstops: Vec<f64>,
}

impl<const N: usize> NonSmoothProblem<N> {
    /// A finite time span `t0 ≤ tf` and a finite start, the coordinate that is not named
    /// by its state column (`joints` the scene's joint names).
    pub(crate) fn check_span_and_start(&self, joints: &[&str]) -> Result<(), String> {
        if !self.t0.is_finite() || !self.tf.is_finite() || self.tf < self.t0 {
            return Err(format!(
                "need finite t0 ≤ tf (t0 = {}, tf = {})",
                self.t0, self.tf
            ));
        }
        if let Some(i) = self
            .q0
            .iter()
            .chain(self.v0.iter())
            .position(|x| !x.is_finite())
        {
            let name = &crate::system::state_names(joints)[i];
            return Err(format!("initial state `{name}` is not finite"));
        }
        Ok(())
    }

    pub fn new(t0: f64, tf: f64, q0: SVector<f64, N>, v0: SVector<f64, N>) -> Self {
        NonSmoothProblem {
            t0,
            tf,
            q0,
            v0,
            forces0: Vec::new(),
            output: Output::Steps,
            tstops: Vec::new(),
        }
    }

    /// The same problem keeping the rows `output` says.
    pub fn with_output(mut self, output: Output) -> Self {
        self.output = output;
        self
    }

    /// With times where the input may jump (see [`tstops`](Self::tstops)).
    pub fn with_tstops(mut self, tstops: Vec<f64>) -> Self {
        self.tstops = tstops;
        self
    }

    /// With initial element forces (see the type's documentation).
    pub fn with_forces(mut self, forces0: Vec<Option<f64>>) -> Self {
        self.forces0 = forces0;
        self
    }
}

/// How to integrate a non-smooth problem.
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub enum NonSmoothMethod {
    /// Event-driven: a smooth [`Method`] between switches (DOPRI5 for non-stiff arcs,
    /// SDIRK4 for stiff arcs with many switches, BDF for stiff arcs long between
    /// switches — it restarts at order 1 after each; RK4 at a fixed step), switches
    /// located on its dense output, exact mode transitions; accumulating events hand
    /// over to time-stepping.
    EventDriven(Method),
    /// Implicit (Moreau-type) θ-method time-stepping with fixed step `h`: each step
    /// intersects the discrete momentum line with the constitutive graphs. First order,
    /// robust, never chatters. `theta = 1.0`: implicit Euler, numerically dissipative
    /// (a stiff support hit at `h ≫ √(m/k)` loses much of its energy); `theta = 0.5`:
    /// implicit midpoint, which keeps the energy of springs and stiff supports at any
    /// `h`, except on coordinates carrying a rigid stop, which keep implicit Euler's
    /// positions (see [`time_stepping`](crate::nonsmooth::time_stepping)). At every θ no
    /// step gains energy beyond the input's work, and no rigid stop is ever passed.
    TimeStepping { h: f64, theta: f64 },
}

impl Default for NonSmoothMethod {
    /// Event-driven with DOPRI5 at `rtol = 1e-8`, `atol = 1e-10`: exact switch times and
    /// sticking, high order between events.
    fn default() -> Self {
        NonSmoothMethod::EventDriven(Method::Dopri5(Options::tolerances(1e-8, 1e-10)))
    }
}
