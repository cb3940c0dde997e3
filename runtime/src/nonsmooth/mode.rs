//! Modes of the elements, the smooth dynamics inside a mode, switching functions and
//! the selection of a consistent mode when elements switch (theory.md §3).
//!
//! Inside a mode every element's force is either a *function of the state* (slipping
//! dash-pot: the slip force of its velocity; compressed spring-backed stop:
//! `k_s · penetration`; free: 0) or a *constraint force* (stuck dash-pot, rigid stop in
//! contact: `v_c = 0`). The constraint forces `f_A` solve the Delassus system
//!
//! ```text
//! W_AA f_A = (a_free)_A,     W = M⁻¹,   a_free = M⁻¹ (τ + τ_p − bias − Σ_slip f_e e_c)
//! ```
//!
//! so that the constrained accelerations vanish; the constrained coordinates' `q` and
//! `v` are then frozen exactly (their derivatives are set to `0.0`).
//!
//! Sign conventions: a dash-pot force is positive when it resists a positive velocity.
//! A stop has a sign `s = +1` (upper: `q ≤ position`) or `−1` (lower), its gap is
//! `s (position − q) ≥ 0`, its contact magnitude is `λ = s f ≥ 0`.

use nalgebra::{DMatrix, DVector, SMatrix, SVector};

use super::kind::{At, Context, Forces, Kind, with_kind};
use super::law::{Branch, Branches};
use crate::element::{Element, ElementKind, Mode, NonSmooth, StopKind};
use crate::numerics::factor;

/// The branch a dash-pot slips on at speed `w = |v_c| > 0`: approach 2 the unique one
/// whose range holds `w` (its top end excluded); approach 1 the lowest one whose range
/// holds `w`, or, given a force `hint`, the one whose force range holds `|hint|` if its
/// velocity range holds `w` (the branch is part of the state). `0` for monotone laws.
pub(crate) fn branch_of(branches: &Branches, w: f64, hint: Option<f64>) -> usize {
    let holds = |b: &Branch| b.v_lo <= w && w <= b.v_hi;
    if let Some(f) = hint
        && let Some(k) = branches
            .slip
            .iter()
            .position(|b| b.f_lo <= f.abs() && f.abs() <= b.f_hi && holds(b))
    {
        return k;
    }
    branches
        .slip
        .iter()
        .position(|b| b.v_lo <= w && w < b.v_hi)
        .unwrap_or(0)
}

/// Approach 1's jump at a fold: the branch the force jumps to when branch `k` ends at
/// its top (`up`: the lowest higher branch whose range holds `v_hi`) or bottom (the
/// highest lower branch whose range holds `v_lo`).
pub(crate) fn fold_jump(branches: &Branches, k: usize, up: bool) -> usize {
    let b = branches.slip[k];
    if up {
        (k + 1..branches.slip.len())
            .find(|&j| branches.slip[j].v_lo < b.v_hi && b.v_hi < branches.slip[j].v_hi)
            .unwrap_or(k)
    } else {
        (0..k)
            .rev()
            .find(|&j| branches.slip[j].v_lo < b.v_lo && b.v_lo < branches.slip[j].v_hi)
            .unwrap_or(k)
    }
}

/// The end of branch `k`'s velocity range nearer to `w` (`0` for monotone laws).
pub(crate) fn branch_end(branches: &Branches, k: usize, w: f64) -> f64 {
    match branches.slip.get(k) {
        Some(b) if b.v_hi.is_finite() && (w - b.v_hi).abs() < (w - b.v_lo).abs() => b.v_hi,
        Some(b) => b.v_lo,
        None => 0.0,
    }
}

/// Whether the end of branch `k` nearer to `w` is a fold of the law, where `φ' = 0` and
/// the slip force has a square-root singularity in the velocity (not the rest speed `0`
/// nor approach 2's cut at a plateau speed, across which the force is smooth). The
/// solution reaches a fold with a `(t* − t)^{3/2}` term, so a step that straddles it
/// keeps neither its order nor a meaningful error estimate.
pub(crate) fn fold_end(branches: &Branches, k: usize, w: f64) -> bool {
    let Some(b) = branches.slip.get(k) else {
        return false;
    };
    let end = branch_end(branches, k, w);
    (end == b.v_hi && b.v_hi == b.v_top && b.v_top.is_finite()) || (end == b.v_lo && b.v_lo > 0.0)
}

/// Least relative [`arming_distance`] of the ends `v_lo > 0`, `v_hi` of a non-monotone
/// law's branch (the end `v = 0` needs none).
pub(crate) const MIN_ARMING_DISTANCE: f64 = 1e-10;

/// How far inside its velocity range the speed must be before a branch entered at its
/// end `v_end` arms its switching function: the integrator's accuracy in that speed,
/// `atol + rtol · v_end` (`tol = (atol, rtol)`), at least
/// [`MIN_ARMING_DISTANCE`]` · v_end`; none at `v_end = 0`.
///
/// A branch entered at its end leaves it only quadratically in time (leaving a
/// plateau, the force imbalance grows from zero), and at a fold the force has its
/// square-root singularity: within the first steps the computed speed may dip back past
/// the end by the local error. Until armed, such a dip is an event only if the mode's
/// acceleration points out of the range there (the event driver's dip test). The
/// switching function itself is the exact distance to the end, so a branch left from
/// inside is left where the speed reaches the end, not a slack later. (With a slack in
/// the function, each fold was located late by `slack / v̇`: 9·10⁻¹⁰ s on S4 approach 1
/// at every rtol ≤ 1e-10, and the event state was moved by the slack.)
pub(crate) fn arming_distance(v_end: f64, tol: (f64, f64)) -> f64 {
    if v_end == 0.0 || !v_end.is_finite() {
        0.0
    } else {
        (tol.0 + tol.1 * v_end).max(MIN_ARMING_DISTANCE * v_end)
    }
}

/// The plateau at speed `w` exactly, if any.
pub(crate) fn plateau_at(branches: &Branches, w: f64) -> Option<usize> {
    branches.plateaus.iter().position(|p| p.velocity == w)
}

/// Every mode an element can take at a mode selection.
pub(crate) fn candidates(element: &Element) -> &'static [Mode] {
    with_kind!(element, |k| k.candidates())
}

/// Checks one element's parameters for the event-driven integrator.
pub(crate) fn validate_element(e: &Element, dof: usize) -> Result<(), String> {
    if e.coordinate >= dof {
        return Err(format!(
            "element `{}` acts on coordinate {} but the mechanism has {dof}",
            e.name, e.coordinate
        ));
    }
    with_kind!(e, |k| k.check()).map_err(|what| format!("element `{}`: {what}", e.name))
}

pub(crate) use super::kind::stop::side_sign;

/// A rigid stop may not start penetrated beyond round-off (`10⁻¹² (1 + |position|)`):
/// neither integrator can give it a meaning (time-stepping would hold the violation for
/// the whole run). Other elements always pass.
/// `joints` names the coordinates in the message.
pub fn check_not_penetrating(el: &Element, q_c: f64, joints: &[&str]) -> Result<(), String> {
    if let ElementKind::Stop {
        kind: StopKind::Rigid { .. },
        position,
        ..
    } = el.kind
        && gap(el, q_c) < -1e-12 * (1.0 + position.abs())
    {
        let side = match el.kind {
            ElementKind::Stop {
                side: crate::element::Side::Upper,
                ..
            } => "at or below",
            _ => "at or above",
        };
        return Err(format!(
            "{} starts at {q_c}, inside the rigid stop `{}` at {position}; start it {side} {position}",
            crate::element::joint_name(joints, el.coordinate),
            el.name
        ));
    }
    Ok(())
}

/// Gap `s (position − q)` of a stop (`≥ 0` when admissible); `+∞` for dash-pots.
pub(crate) fn gap(element: &Element, qc: f64) -> f64 {
    with_kind!(element, |k| k.gap(qc))
}

/// Accelerations and element forces in one mode assignment.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Evaluation<const N: usize> {
    pub a: SVector<f64, N>,
    pub f: Vec<f64>,
}

/// The smooth dynamics of mode assignment `modes` at `(q, v)` with input `τ`; `None`
/// when the constraints are dependent (two constrained elements on one coordinate,
/// except a rigid stop in contact with a stuck dash-pot, which hold it together).
pub(crate) fn evaluate<S: NonSmooth<N>, const N: usize>(
    system: &S,
    elements: &[Element],
    branches: &[Branches],
    modes: &[Mode],
    q: &SVector<f64, N>,
    v: &SVector<f64, N>,
    tau: &SVector<f64, N>,
) -> Option<Evaluation<N>> {
    let mut tau_net = *tau;
    let mut f = vec![0.0; elements.len()];
    let mut active = Vec::new();
    for (i, el) in elements.iter().enumerate() {
        let c = el.coordinate;
        if modes[i].is_constraint() {
            active.push(i);
        } else {
            let cx = Context {
                system,
                index: i,
                branches: &branches[i],
                folds: &[],
            };
            let at = At::state(q[c], v[c], 0.0);
            f[i] = with_kind!(el, |k| k.force(&cx, modes[i], &at));
        }
        tau_net[c] -= f[i];
    }
    let mut a = system.forward_dynamics(q, v, &tau_net);
    // A rigid stop in contact and a stuck dash-pot on one coordinate hold it together:
    // one constraint row, its force split by `split_stop_and_stick`. Any other pair of
    // holders on one coordinate is dependent.
    let mut pairs: Vec<(usize, usize)> = Vec::new();
    let mut rows: Vec<usize> = Vec::new();
    for &e in &active {
        let c = elements[e].coordinate;
        match rows.iter().position(|&r| elements[r].coordinate == c) {
            None => rows.push(e),
            Some(k) => {
                let (stop, stick) = stop_and_stick(elements, modes, rows[k], e)?;
                rows[k] = stop;
                pairs.push((stop, stick));
            }
        }
    }
    if !rows.is_empty() {
        let w = system.inverse_mass_matrix(q);
        let k = rows.len();
        let coord = |i: usize| elements[rows[i]].coordinate;
        let waa = DMatrix::from_fn(k, k, |i, j| w[(coord(i), coord(j))]);
        let rhs = DVector::from_fn(k, |i, _| a[coord(i)]);
        let fa = factor::cholesky_solve(waa, &rhs)?;
        if fa.iter().any(|x| !x.is_finite()) {
            return None;
        }
        for (i, &e) in rows.iter().enumerate() {
            f[e] = fa[i];
            a -= w.column(coord(i)) * fa[i];
        }
        for i in 0..k {
            a[coord(i)] = 0.0;
        }
        for &(stop, stick) in &pairs {
            (f[stop], f[stick]) = split_stop_and_stick(&elements[stop], f[stop]);
        }
    }
    Some(Evaluation { a, f })
}

/// `(stop, dash-pot)` when elements `a` and `b` are a rigid stop in contact and a stuck
/// dash-pot (in either order); `None` for any other pair of holders.
fn stop_and_stick(
    elements: &[Element],
    modes: &[Mode],
    a: usize,
    b: usize,
) -> Option<(usize, usize)> {
    let is_stop = |e: usize| {
        matches!(
            (elements[e].kind, modes[e]),
            (ElementKind::Stop { .. }, Mode::Contact)
        )
    };
    let is_stick = |e: usize| {
        matches!(
            (elements[e].kind, modes[e]),
            (ElementKind::DashPot { .. }, Mode::Stick)
        )
    };
    if is_stop(a) && is_stick(b) {
        Some((a, b))
    } else if is_stop(b) && is_stick(a) {
        Some((b, a))
    } else {
        None
    }
}

/// The split of the force `λ` holding a coordinate between a rigid stop in contact and a
/// stuck dash-pot on it: the stop takes the part pressing the coordinate against it
/// (it cannot pull), the dash-pot the rest. The motion does not depend on the split;
/// this one keeps the dash-pot force zero while the stop bears the load, so friction
/// only acts when the load pulls away from the stop.
pub(crate) fn split_stop_and_stick(stop: &Element, lambda: f64) -> (f64, f64) {
    let s = match stop.kind {
        ElementKind::Stop { side, .. } => side_sign(side),
        ElementKind::DashPot { .. } => 1.0,
    };
    if s * lambda >= 0.0 {
        (lambda, 0.0)
    } else {
        (0.0, lambda)
    }
}

/// For a rigid stop in contact with a stuck dash-pot on the same coordinate, the
/// dash-pot's index: the pair holds until the load pulls away from the stop by more
/// than the dash-pot's critical force.
pub(crate) fn stuck_partner(elements: &[Element], modes: &[Mode], stop: usize) -> Option<usize> {
    (0..elements.len()).find(|&e| {
        e != stop
            && elements[e].coordinate == elements[stop].coordinate
            && stop_and_stick(elements, modes, stop, e) == Some((stop, e))
    })
}

/// Switching function of `element` in `mode`: positive while the mode holds, crossing
/// zero where it ends (each kind's [`Kind::switching`]: stick `f_crit − |f|`; slip
/// `±v_c`, or on a branch of a non-monotone law the distance to the nearer end of its
/// velocity range; plateau: the distance of `±f` to the nearer end of its force
/// interval; free: gap; contact: `λ`; compressed: penetration). A branch entered at its
/// end arms its function only a little inside the range ([`arming_distance`]).
pub(crate) fn switching(
    element: &Element,
    branches: &Branches,
    mode: Mode,
    qc: f64,
    vc: f64,
    f: f64,
) -> f64 {
    with_kind!(element, |k| k.switching(
        branches,
        mode,
        &At::state(qc, vc, f)
    ))
}

/// How consistently `mode` holds for `element` at an event, in force units: `≥ 0`
/// consistent. Stick: `f_crit − |f|`; slip at `v_c = 0`: the acceleration in the slip
/// direction divided by `W_cc`; slip on a non-monotone branch at an end of its velocity
/// range: the acceleration into the range divided by `W_cc`; plateau at its speed: the
/// distance of the constraint force to the ends of its interval; contact: `λ`; free at
/// gap `0` and rest: the gap acceleration divided by `W_cc`. States that already move in
/// (out of) the mode's direction or range give `+∞` (`−∞`).
#[allow(clippy::too_many_arguments)]
pub(crate) fn margin(
    element: &Element,
    branches: &Branches,
    mode: Mode,
    qc: f64,
    vc: f64,
    ac: f64,
    f: f64,
    wcc: f64,
) -> f64 {
    let at = At { qc, vc, ac, f, wcc };
    with_kind!(element, |k| k.margin(branches, mode, &at))
}

/// The elements that take part in a mode selection, each with its candidate modes.
pub(crate) type Choices = Vec<(usize, Vec<Mode>)>;

/// Relative tolerance of the consistency margins: a margin within `MARGIN_TOL · scale`
/// of zero counts as on the boundary.
const MARGIN_TOL: f64 = 1e-9;

/// How far the located event state may be from the true one, per component, in units of
/// the integrator's accuracy `atol + rtol |x|`: the local error of the step that located
/// it and the root finder's tolerance together.
const EVENT_STATE_ERROR: f64 = 10.0;

/// What a mode selection evaluates combinations against: the system and its elements,
/// which elements choose, the input and `W = M⁻¹` at the selection's state.
struct Selection<'a, S, const N: usize> {
    system: &'a S,
    elements: &'a [Element],
    branches: &'a [Branches],
    choices: &'a Choices,
    tau: &'a SVector<f64, N>,
    w: SMatrix<f64, N, N>,
}

impl<S: NonSmooth<N>, const N: usize> Selection<'_, S, N> {
    /// The least margin over the elements in `choices` of the combination `modes`, with
    /// the forces and accelerations evaluated at `(qe, ve)` and the element states (which
    /// decide a margin's form) taken at `(q, v)`; `None` where the mode's constraints are
    /// dependent.
    fn least_margin(
        &self,
        modes: &[Mode],
        (qe, ve): (&SVector<f64, N>, &SVector<f64, N>),
        (q, v): (&SVector<f64, N>, &SVector<f64, N>),
    ) -> Option<f64> {
        let ev = evaluate(
            self.system,
            self.elements,
            self.branches,
            modes,
            qe,
            ve,
            self.tau,
        )?;
        Some(
            self.choices
                .iter()
                .map(|(e, _)| {
                    let c = self.elements[*e].coordinate;
                    margin(
                        &self.elements[*e],
                        &self.branches[*e],
                        modes[*e],
                        q[c],
                        v[c],
                        ev.a[c],
                        ev.f[*e],
                        self.w[(c, c)],
                    )
                })
                .fold(f64::INFINITY, f64::min),
        )
    }

    /// How much the least margin `m0` of `modes` at `(q, v)` can move when the state moves
    /// within its error at an event: `Σ_i |Δm_i|`, each `Δm_i` the change when coordinate
    /// or velocity `i` alone moves by `EVENT_STATE_ERROR · (atol + rtol |x_i|)` (a
    /// first-order bound, by one-sided differences). A stiff spring makes it large in
    /// force units — on the two-block chain with k₂/k₁ = 1e9 a position error of 1e-13
    /// moves the stuck force by 1e-4 — where a slack relative to the force scale alone
    /// would refuse every mode.
    fn margin_uncertainty(
        &self,
        modes: &[Mode],
        m0: f64,
        q: &SVector<f64, N>,
        v: &SVector<f64, N>,
        (atol, rtol): (f64, f64),
    ) -> f64 {
        if !m0.is_finite() {
            return 0.0;
        }
        let mut sum = 0.0;
        for i in 0..2 * N {
            let (mut qe, mut ve) = (*q, *v);
            let x = if i < N { &mut qe[i] } else { &mut ve[i - N] };
            *x += EVENT_STATE_ERROR * (atol + rtol * x.abs());
            if let Some(m) = self
                .least_margin(modes, (&qe, &ve), (q, v))
                .filter(|m| m.is_finite())
            {
                sum += (m - m0).abs();
            }
        }
        sum
    }
}

/// Largest number of mode combinations enumerated (`3^k`, so up to 9 dash-pots at once).
const MAX_COMBINATIONS: usize = 20_000;

/// Selects the modes of the elements in `choices` (the others keep `modes`) at
/// `(q, v)`: enumerates every combination of their candidate modes, evaluates the
/// dynamics and the margins, and returns the unique consistent combination.
///
/// Combinations within the tolerance of the boundary are consistent. If more than one
/// is consistent with a margin above the tolerance, those with the most elements at
/// rest whose law prefers rest ([`Kind::rest_persists`]: static friction) are kept; if
/// still more than one, the choice is not unique and an error (the text of
/// [`ErrorKind::IllPosedMode`](crate::ErrorKind)) is returned; otherwise the largest
/// margin wins. When none is consistent, the least violated one is taken if it misses
/// by less than the state's error can move its margin (`Selection::margin_uncertainty`
/// with the integrator's `accuracy = (atol, rtol)`; at a switching instant located to
/// round-off, the old mode and the new one may both sit on the boundary; the new one has
/// the larger margin on the far side of the located root).
#[allow(clippy::too_many_arguments)]
pub(crate) fn select<S: NonSmooth<N>, const N: usize>(
    system: &S,
    elements: &[Element],
    branches: &[Branches],
    modes: &[Mode],
    choices: &Choices,
    q: &SVector<f64, N>,
    v: &SVector<f64, N>,
    tau: &SVector<f64, N>,
    accuracy: (f64, f64),
) -> Result<Vec<Mode>, String> {
    if choices.is_empty() {
        return Ok(modes.to_vec());
    }
    let total: usize = choices.iter().map(|(_, c)| c.len()).product();
    if total == 0 {
        return Err("an element has no admissible mode".into());
    }
    if total > MAX_COMBINATIONS {
        return Err(format!(
            "{total} mode combinations: too many elements switch at once"
        ));
    }
    let w = system.inverse_mass_matrix(q);
    let selection = Selection {
        system,
        elements,
        branches,
        choices,
        tau,
        w,
    };
    // Scale of the margins: the largest critical force and the largest force needed
    // to hold a switching coordinate at rest.
    let mut free_modes = modes.to_vec();
    for (e, _) in choices {
        free_modes[*e] = with_kind!(elements[*e], |k| k.unconstrained());
    }
    let mut scale: f64 = 1.0;
    if let Some(ev) = evaluate(system, elements, branches, &free_modes, q, v, tau) {
        for (e, _) in choices {
            let c = elements[*e].coordinate;
            scale = scale.max((ev.a[c] / w[(c, c)]).abs());
        }
    }
    for el in elements {
        scale = scale.max(with_kind!(el, |k| k.force_scale()));
    }
    let tol = MARGIN_TOL * scale;
    let mut consistent: Vec<(f64, Vec<Mode>)> = Vec::new();
    let mut best_violation: Option<(f64, Vec<Mode>)> = None;
    let mut trial = modes.to_vec();
    for index in 0..total {
        let mut rest = index;
        for (e, cands) in choices {
            trial[*e] = cands[rest % cands.len()];
            rest /= cands.len();
        }
        let Some(m) = selection.least_margin(&trial, (q, v), (q, v)) else {
            continue;
        };
        if m >= -tol {
            consistent.push((m, trial.clone()));
        } else if best_violation.as_ref().is_none_or(|(b, _)| m > *b) {
            best_violation = Some((m, trial.clone()));
        }
    }
    let describe = |ms: &[Mode]| {
        choices
            .iter()
            .map(|(e, _)| format!("{}: {:?}", elements[*e].name, ms[*e]))
            .collect::<Vec<_>>()
            .join(", ")
    };
    let mut robust: Vec<_> = consistent.iter().filter(|(m, _)| *m > tol).collect();
    if robust.len() > 1 {
        // Rest persists: of the robust combinations, those with the most elements at rest
        // whose law prefers rest (static friction holding where it could also slip).
        let resting = |ms: &[Mode]| {
            choices
                .iter()
                .filter(|(e, _)| {
                    ms[*e] == Mode::Stick && with_kind!(elements[*e], |k| k.rest_persists())
                })
                .count()
        };
        let most = robust.iter().map(|(_, ms)| resting(ms)).max().unwrap_or(0);
        robust.retain(|(_, ms)| resting(ms) == most);
    }
    if let [(_, ms)] = robust.as_slice() {
        return Ok(ms.clone());
    }
    if robust.len() > 1 {
        let list: Vec<String> = robust
            .iter()
            .map(|(_, ms)| format!("[{}]", describe(ms)))
            .collect();
        return Err(format!(
            "several modes are consistent (non-unique): {}",
            list.join(" or ")
        ));
    }
    match consistent.into_iter().max_by(|a, b| a.0.total_cmp(&b.0)) {
        Some((_, ms)) => Ok(ms),
        // The event state is known only to the integrator's accuracy: at a transition
        // whose margins all vanish there (entering a plateau of a non-monotone law, a
        // stiff spring holding a stuck element, say) the best candidate may miss by what
        // that error does to its margin. It is taken when it misses by less than that
        // (`margin_uncertainty`); beyond it, no mode fits.
        None if best_violation.as_ref().is_some_and(|(m, ms)| {
            *m >= -tol - selection.margin_uncertainty(ms, *m, q, v, accuracy)
        }) =>
        {
            Ok(best_violation.map(|(_, ms)| ms).unwrap_or_default())
        }
        None => Err(match best_violation {
            Some((m, ms)) => format!(
                "no mode is consistent (Painlevé-type); least violated [{}] by {m:e}",
                describe(&ms)
            ),
            None => "no mode has independent constraints".into(),
        }),
    }
}
