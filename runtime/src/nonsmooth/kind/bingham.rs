//! Bingham dash-pots (theory.md §3): a dead zone `|f| ≤ f_crit` where the coordinate
//! sticks, and outside it a slip law — linear `v = (f − sgn(f) f_crit)/η`, a monotone
//! user law `v = φ(f)`, or a non-monotone one with its selection rule (approach 1: no
//! velocity jumps, the force jumps at a fold; approach 2: maximal dissipation, plateaus
//! at constant speed). The folds, branches and plateaus of a non-monotone law are found
//! once, by `law::Graph`; here is what a Bingham element does with
//! them.

use super::dashpot::{self, DashPot};
use super::graph::{Fold, LawError, Line, MAX_ITER, Part, Point, StepState, bisect, upper_bound};
use super::traits::{At, Context, Forces, Found, Slip};
use crate::element::{Law, Mode, NonSmooth, Selection};

/// A Bingham dash-pot: its slip law (one of the `Bingham*` variants of [`Law`]) and its
/// critical force.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Bingham {
    pub law: Law,
    pub f_crit: f64,
}

impl Bingham {
    /// Slip force of the element slipping in direction `d = ±1` on branch `k` at velocity
    /// `vc`.
    ///
    /// Linear: `d f_crit + η vc` (the mode's direction, not `sgn vc`, so the force stays
    /// smooth while a root finder looks just past `vc = 0`). Monotone user law: the `f`
    /// with `φ(f) = vc` on the branch `d f > f_crit`, by safeguarded Newton
    /// ([`invert_monotone`]); where `d vc ≤ 0`, the law's tangent at `f_crit`
    /// ([`below_branch`]). Non-monotone law: the same inside branch `k`'s force interval
    /// `[f_lo, f_hi]` (bracketed by its folds), continued by the tangent below the
    /// branch's velocity range; above it, continued along the law's increasing piece up
    /// to the piece's fold (`Branch::f_top`: smooth past approach 2's cut at a plateau
    /// speed) and clamped there (so the force stays continuous while a root finder or a
    /// stage looks just past the end).
    pub(crate) fn slip_force<S: NonSmooth<N>, const N: usize>(
        &self,
        cx: &Context<S>,
        k: usize,
        vc: f64,
        d: f64,
    ) -> f64 {
        let (system, index, branches, f_crit) = (cx.system, cx.index, cx.branches, self.f_crit);
        let w = d * vc;
        match self.law {
            Law::BinghamLinear { eta } => d * f_crit + eta * vc,
            Law::BinghamNonMonotone { .. } if !branches.slip.is_empty() => {
                let b = branches.slip[k];
                if w <= b.v_lo {
                    d * below_branch(system, index, b.f_lo, w - b.v_lo)
                } else if w >= b.v_top {
                    d * b.f_top
                } else if w >= b.v_hi {
                    // Past a cut end (approach 2's plateau speed): on along the piece.
                    d * invert_monotone(|f| system.law(index, f), b.f_hi, b.f_top, w)
                } else {
                    d * invert_monotone(|f| system.law(index, f), b.f_lo, b.f_hi, w)
                }
            }
            _ => {
                if w <= 0.0 {
                    d * below_branch(system, index, f_crit, w)
                } else {
                    d * invert_monotone(|f| system.law(index, f), f_crit, f64::INFINITY, w)
                }
            }
        }
    }
}

impl DashPot for Bingham {
    fn check(&self) -> Result<(), String> {
        dashpot::check_limit("critical force f_crit", self.f_crit)?;
        match self.law {
            Law::BinghamLinear { eta } if !(eta.is_finite() && eta > 0.0) => Err(format!(
                "viscosity η = {eta} must be finite and > 0 (η → 0 is Coulomb friction)"
            )),
            _ => Ok(()),
        }
    }

    fn limit(&self) -> f64 {
        self.f_crit
    }
}

impl<S: NonSmooth<N>, const N: usize> Forces<S, N> for Bingham {
    fn force(&self, cx: &Context<S>, mode: Mode, at: &At) -> f64 {
        mode.slip()
            .map_or(0.0, |(d, k)| self.slip_force(cx, k, at.vc, d))
    }

    /// Monotone laws (and approach 2's monotone envelope `ψ`): the stick segment, else
    /// the unique slip point. Approach 1: the first intersection met from the force
    /// before (the branch is part of the state).
    fn on_line(&self, cx: &Context<S>, line: Line, state: &StepState) -> Found {
        let system = cx.system;
        let (law, f_crit, previous) = (self.law, self.f_crit, state.force);
        let Line { v_free, w } = line;
        let e = cx.index;
        let slip = |f: f64| dashpot::slip_on_line(line, f);
        if let Law::BinghamNonMonotone {
            selection: Selection::NoVelocityJumps,
        } = law
        {
            if !previous.is_finite() {
                return Err(LawError::NonFinite);
            }
            let f = first_root(
                cx.folds,
                |f| phi(system, e, law, f_crit, f) + w * f - v_free,
                f_crit,
                previous,
            )?;
            return Ok(if f.abs() <= f_crit {
                Point {
                    v: 0.0,
                    f,
                    part: Part::Stick,
                    dq: None,
                }
            } else {
                slip(f)
            });
        }
        // Monotone graphs (and approach 2's monotone envelope): stick iff the line meets
        // the dead zone's vertical segment.
        if let Some(stick) = dashpot::stick_on_line(line, f_crit) {
            return Ok(stick);
        }
        let s = v_free.signum();
        let a = v_free.abs();
        Ok(match law {
            // a − w x = (x − f_crit)/η.
            Law::BinghamLinear { eta } => slip(s * (a + f_crit / eta) / (w + 1.0 / eta)),
            Law::BinghamNonMonotone { .. } => {
                let x = bisect(|x| psi(cx, s, f_crit, x) + w * x - a, f_crit, a / w)?;
                // On a plateau (ψ < φ) the velocity is exactly the local minimum.
                match plateau_below(cx, s, f_crit, x) {
                    Some(v_min) => Point {
                        v: s * v_min,
                        f: s * (a - v_min) / w,
                        part: Part::Plateau,
                        dq: None,
                    },
                    None => slip(s * x),
                }
            }
            // φ(x) + w x = a on [f_crit, a/w]: φ ≥ 0 there, so a/w brackets the root.
            _ => slip(s * newton_bisect(system, e, s, w, a, f_crit, a / w)?),
        })
    }

    /// Monotone laws: the unique force, by safeguarded Newton on `Φ(f) = v`. Non-monotone
    /// laws: approach 2 the force of the maximal-dissipation graph; approach 1 the first
    /// force met from `previous` in the direction of `v − Φ(previous)`.
    fn force_of_velocity(&self, cx: &Context<S>, v: f64, previous: f64) -> Slip {
        let (law, f_crit, e, system) = (self.law, self.f_crit, cx.index, cx.system);
        let s = v.signum();
        Ok(Some(match law {
            Law::BinghamLinear { eta } => s * (f_crit + eta * v.abs()),
            Law::BinghamNonMonotone {
                selection: Selection::MaximalDissipation,
            } => {
                let psi = |x: f64| psi(cx, s, f_crit, x) - v.abs();
                let hi = upper_bound(psi, f_crit)?;
                s * bisect(psi, f_crit, hi)?
            }
            Law::BinghamNonMonotone {
                selection: Selection::NoVelocityJumps,
            } => {
                let g = |f: f64| phi(system, e, law, f_crit, f) - v;
                first_root(cx.folds, g, f_crit, previous)?
            }
            _ => {
                let hi = upper_bound(|x| side_phi(system, e, s, x) - v.abs(), f_crit)?;
                s * newton_bisect(system, e, s, 0.0, v.abs(), f_crit, hi)?
            }
        }))
    }

    fn velocity_of_force(&self, cx: &Context<S>, f: f64) -> Option<f64> {
        Some(phi(cx.system, cx.index, self.law, self.f_crit, f))
    }
}

/// `ψ(x) = inf_{y ≥ x} φ₊(y)` on the side `s` (`x ≥ f_crit`): the smaller of `φ₊(x)`
/// and the local minima beyond `x` (φ increases beyond its last fold).
fn psi<S: NonSmooth<N>, const N: usize>(cx: &Context<S>, s: f64, f_crit: f64, x: f64) -> f64 {
    let here = if x <= f_crit {
        0.0
    } else {
        side_phi(cx.system, cx.index, s, x)
    };
    cx.folds
        .iter()
        .filter(|fold| fold.minimum && fold.force > x)
        .fold(here, |m, fold| m.min(fold.velocity))
}

/// The plateau velocity if `x` lies on a filled jump of approach 2's graph.
fn plateau_below<S: NonSmooth<N>, const N: usize>(
    cx: &Context<S>,
    s: f64,
    f_crit: f64,
    x: f64,
) -> Option<f64> {
    let here = side_phi(cx.system, cx.index, s, x.max(f_crit));
    cx.folds
        .iter()
        .filter(|fold| fold.minimum && fold.force > x && fold.velocity < here)
        .map(|fold| fold.velocity)
        .reduce(f64::min)
}

/// Approach 1: the first root of the continuous `g` met from `start`, moving in the
/// direction `−sgn g(start)`. The scan visits the breakpoints `±f_crit`, `±folds`;
/// between breakpoints it uses 64 cells on decreasing pieces of `φ` (where `g` need
/// not be monotone) and one cell on increasing ones; beyond the last breakpoint the
/// bracket is found by doubling. The root is refined by bisection.
fn first_root(
    folds: &[Fold],
    g: impl Fn(f64) -> f64,
    f_crit: f64,
    start: f64,
) -> Result<f64, LawError> {
    let g0 = g(start);
    if !g0.is_finite() {
        return Err(LawError::NonFinite);
    }
    if g0 == 0.0 {
        return Ok(start);
    }
    let d = -g0.signum();
    // Breakpoints strictly beyond `start` in direction d, in order.
    let mut marks: Vec<f64> = std::iter::once(f_crit)
        .chain(folds.iter().map(|fold| fold.force))
        .flat_map(|x| [x, -x])
        .filter(|&x| (x - start) * d > 0.0)
        .collect();
    marks.sort_by(|a, b| (d * a).total_cmp(&(d * b)));
    marks.dedup();
    let decreasing = |a: f64, b: f64| {
        let mid = 0.5 * (a.abs() + b.abs());
        let mut inside = folds.iter().filter(|fold| fold.force < mid);
        // φ decreases between a maximum and the following minimum.
        inside.next_back().is_some_and(|fold| !fold.minimum) && mid > f_crit
    };
    let mut a = start;
    for &b in &marks {
        let cells = if decreasing(a, b) { 64 } else { 1 };
        let mut lo = a;
        for k in 1..=cells {
            let hi = a + (b - a) * k as f64 / cells as f64;
            let gh = g(hi);
            if !gh.is_finite() {
                return Err(LawError::NonFinite);
            }
            if gh * d >= 0.0 {
                return bisect(&g, lo, hi);
            }
            lo = hi;
        }
        a = b;
    }
    // Beyond all breakpoints: φ is monotone there; double the step until g changes sign.
    let mut step = (a.abs() + f_crit + 1.0) * d;
    for _ in 0..MAX_ITER {
        let b = a + step;
        let gb = g(b);
        if !gb.is_finite() {
            return Err(LawError::NonFinite);
        }
        if gb * d >= 0.0 {
            return bisect(&g, a, b);
        }
        a = b;
        step *= 2.0;
    }
    Err(LawError::NoConvergence)
}

/// The slip force a distance `dw ≤ 0` below the lower end `(v_lo, f_lo)` of a branch:
/// the tangent `f_lo + dw / φ'(f_lo)` where the law has a finite positive slope there,
/// else `f_lo`. Only trial states past the switching point `v = v_lo` see it (the
/// integrator's stages, the root finder); continuing the law with its tangent keeps the
/// right-hand side C¹ across that point, so a tight tolerance does not drive the step
/// size to zero against a kink before the event is seen.
fn below_branch<S: NonSmooth<N>, const N: usize>(
    system: &S,
    index: usize,
    f_lo: f64,
    dw: f64,
) -> f64 {
    let slope = system.law(index, f_lo).1;
    if slope > 0.0 && slope.is_finite() {
        f_lo + dw / slope
    } else {
        f_lo
    }
}

/// Solves `φ(f) = w` for `f ∈ [lo, hi]` (`hi = ∞`: bracketed by doubling) where `φ`
/// increases (`f > 0`: for an odd law the positive side serves both directions),
/// `phi(f) = (φ(f), φ'(f))`: Newton kept inside the bracket, bisecting whenever the
/// Newton point leaves it (a "safeguarded" Newton, Press et al., *Numerical Recipes*,
/// 3rd ed., §9.4, `rtsafe`). At a fold end `φ' = 0` and the bisection takes over.
fn invert_monotone<P: Fn(f64) -> (f64, f64)>(phi: P, lo: f64, hi: f64, w: f64) -> f64 {
    let value = |f: f64| phi(f);
    let base = lo;
    let mut lo = lo;
    let mut hi = hi;
    if !hi.is_finite() {
        let mut step = base.max(1.0);
        hi = base + step;
        for _ in 0..200 {
            if value(hi).0 >= w {
                break;
            }
            lo = hi;
            step *= 2.0;
            hi = base + step;
        }
    }
    let mut x = 0.5 * (lo + hi);
    for _ in 0..200 {
        let (p, dp) = value(x);
        let r = p - w;
        if r == 0.0 {
            return x;
        }
        if r < 0.0 {
            lo = x;
        } else {
            hi = x;
        }
        let newton = x - r / dp;
        let next = if dp > 0.0 && newton > lo && newton < hi {
            newton
        } else {
            0.5 * (lo + hi)
        };
        if (next - x).abs() <= 2.0 * f64::EPSILON * x.abs() || hi - lo <= 2.0 * f64::EPSILON * hi {
            return next;
        }
        x = next;
    }
    x
}

/// `Φ(f)`: 0 in the dead zone, the slip law outside (Bingham laws; friction gives 0).
pub(crate) fn phi<S: NonSmooth<N>, const N: usize>(
    system: &S,
    e: usize,
    law: Law,
    f_crit: f64,
    f: f64,
) -> f64 {
    if f.abs() <= f_crit {
        return 0.0;
    }
    match law {
        Law::BinghamLinear { eta } => (f - f.signum() * f_crit) / eta,
        Law::BinghamMonotone | Law::BinghamNonMonotone { .. } => system.law(e, f).0,
        _ => 0.0,
    }
}

/// The user slip law on side `s` as a function of `x = |f| > f_crit`: `s φ(s x)`.
pub(crate) fn side_phi<S: NonSmooth<N>, const N: usize>(
    system: &S,
    e: usize,
    s: f64,
    x: f64,
) -> f64 {
    s * system.law(e, s * x).0
}

/// Root of `s φ(s x) + w x = a` on `[lo, hi]` (increasing, sign change): Newton with the
/// law's derivative, kept inside a shrinking bracket, bisection when Newton leaves it.
pub(crate) fn newton_bisect<S: NonSmooth<N>, const N: usize>(
    system: &S,
    e: usize,
    s: f64,
    w: f64,
    a: f64,
    mut lo: f64,
    mut hi: f64,
) -> Result<f64, LawError> {
    let mut x = 0.5 * (lo + hi);
    for _ in 0..MAX_ITER {
        let (p, dp) = system.law(e, s * x);
        let (g, dg) = (s * p + w * x - a, dp + w);
        if !(g.is_finite() && dg.is_finite()) {
            return Err(LawError::NonFinite);
        }
        if g == 0.0 {
            return Ok(x);
        }
        if g < 0.0 {
            lo = x
        } else {
            hi = x
        }
        let newton = x - g / dg;
        let next = if dg > 0.0 && newton > lo && newton < hi {
            newton
        } else {
            0.5 * (lo + hi)
        };
        if (next - x).abs() <= 4.0 * f64::EPSILON * x.abs()
            || hi - lo <= 4.0 * f64::EPSILON * hi.abs()
        {
            return Ok(next);
        }
        x = next;
    }
    Err(LawError::NoConvergence)
}
