//! Shared by the S9 example, its test and the report: the arm with joint friction and
//! stops (theory S9), its standard run, and the energy balance
//! `E(t) − E(0) = W_in(t) − D_friction(t) − L_impacts(t)`.
#![allow(dead_code)]

use filippov::nalgebra::SVector;
use filippov::prelude::*;
use filippov::runtime::{
    NonSmooth, NonSmoothMethod, NonSmoothProblem, Solution, SolveError, solve_nonsmooth,
};
use filippov::scenes::PandaS9;

pub type V7 = SVector<f64, 7>;

/// The applied joint torques of the standard run: a sway on j1, and on j5 and j7
/// amplitudes just above their friction levels (stick–slip).
pub fn s9_torque(t: f64) -> V7 {
    V7::from([
        3.0 * (1.5 * t).sin(),
        0.0,
        0.0,
        0.0,
        1.2 * (3.0 * t).sin(),
        0.0,
        0.8 * (2.0 * t).cos(),
    ])
}

/// The standard S9 run: from a bent pose with j2 swinging towards its limit and j4
/// towards its upper limit, under gravity and [`s9_torque`], `t ∈ [0, t_end]`.
pub fn s9_problem(t_end: f64) -> NonSmoothProblem<7> {
    let q0 = V7::from([0.0, 1.2, 0.0, -0.5, 0.0, 1.6, 0.8]);
    let v0 = V7::from([0.5, 1.5, 0.0, 1.0, 0.0, 0.0, 0.0]);
    NonSmoothProblem::new(0.0, t_end, q0, v0)
}

pub fn s9_run(arm: &PandaS9, t_end: f64, method: &NonSmoothMethod) -> Result<Solution, SolveError> {
    let input = |t: f64, _q: &V7, _v: &V7| s9_torque(t);
    solve_nonsmooth(arm, &input, &s9_problem(t_end), method)
}

/// The energy balance along a run.
pub struct Balance {
    /// Largest `|E(t) − E(0) − W + D + L|` at the rows, over `max(E-scale)`.
    pub relative_residual: f64,
    pub work_in: f64,
    pub friction_dissipation: f64,
    /// Energy lost at impacts, from the switch log's impulses (not from the rows).
    pub impact_loss: f64,
    /// Switch-log entries of kind `Impact` (a stop's rebound; not stick–slip switches).
    pub impacts: usize,
    /// Switch-log entries of kind `Settled` (rebounds taken as plastic).
    pub settled: usize,
    /// Hand-overs to time-stepping: their impacts are not in the log, so the balance
    /// holds only for a run without them.
    pub handovers: usize,
    /// Smallest friction power `f_crit |v|` contribution check: the most negative
    /// element power `f_e v_e` seen at a row (≥ 0 up to round-off when dissipative).
    pub min_element_power: f64,
}

/// The kinetic energy an impact takes out, from its impulses alone (theory §1): stops
/// `k` hit at once take impulses `P_k` along their coordinates with
/// `v⁺ = v⁻ − M⁻¹ Σ_k e_k P_k`; where Newton's law `v⁺_k = −ε_k v⁻_k` holds, `W P = (1 + ε) v⁻`
/// with `W = (M⁻¹)` at the stops' coordinates, and `T⁻ − T⁺ = ½ Σ_k P_k (v⁻_k + v⁺_k)`
/// becomes `½ Σ_k P_k (WP)_k (1 − ε_k)/(1 + ε_k)`. A settled stop comes to rest
/// (`ε = 0`).
fn impact_loss(minv: &filippov::nalgebra::SMatrix<f64, 7, 7>, hits: &[(usize, f64, f64)]) -> f64 {
    hits.iter()
        .map(|&(c, p, eps)| {
            let wp: f64 = hits.iter().map(|&(c2, p2, _)| minv[(c, c2)] * p2).sum();
            0.5 * p * wp * (1.0 - eps) / (1.0 + eps)
        })
        .sum()
}

/// `E = T + U`; the work of the applied torques and the friction dissipation
/// `Σ f_crit |v|` are integrated on each smooth arc between rows (Simpson's rule on the
/// dense output, `sub` panels per arc); impacts lose what [`impact_loss`] computes from
/// the switch log's impulses, booked at the row just after them.
pub fn s9_balance(arm: &PandaS9, traj: &Solution, sub: usize) -> Balance {
    use filippov::runtime::SwitchKind;
    use filippov::runtime::nonsmooth::{ElementKind, StopKind};
    let n = 7;
    let energy = |y: &[f64]| {
        let q = V7::from_column_slice(&y[..n]);
        let v = V7::from_column_slice(&y[n..2 * n]);
        arm.kinetic_energy(&q, &v) + arm.potential_energy(&q)
    };
    let f_crit: Vec<(usize, f64)> = (0..PandaS9::ELEMENTS)
        .filter_map(|e| {
            let el = arm.element(e);
            match el.kind {
                ElementKind::DashPot { f_crit, .. } => Some((el.coordinate, f_crit)),
                _ => None,
            }
        })
        .collect();
    // Each impact time with its stops: (coordinate, impulse, restitution in effect).
    let mut hits: Vec<(f64, Vec<(usize, f64, f64)>)> = Vec::new();
    let (mut impacts, mut settled) = (0, 0);
    for s in &traj.switches {
        // A settled stop comes to rest (ε = 0); a rebound follows Newton's law.
        let settles = match s.kind {
            SwitchKind::Impact => false,
            SwitchKind::Settled => true,
            _ => continue,
        };
        if settles {
            settled += 1;
        } else {
            impacts += 1;
        }
        let name = s.element.as_deref().expect("an impact names its stop");
        let el = (0..PandaS9::ELEMENTS)
            .map(|e| arm.element(e))
            .find(|el| el.name == name)
            .expect("the stop is an element of the arm");
        let eps = match el.kind {
            ElementKind::Stop {
                kind: StopKind::Rigid { restitution },
                ..
            } if !settles => restitution,
            _ => 0.0,
        };
        match hits.last_mut() {
            Some((t, list)) if *t == s.t => list.push((el.coordinate, s.jump, eps)),
            _ => hits.push((s.t, vec![(el.coordinate, s.jump, eps)])),
        }
    }
    let handovers = traj
        .switches
        .iter()
        .filter(|s| s.kind == SwitchKind::HandOverToTimeStepping)
        .count();
    let power_in = |t: f64| -> f64 {
        let y = traj.at(t).expect("inside the run");
        let v = V7::from_column_slice(&y[n..2 * n]);
        s9_torque(t).dot(&v)
    };
    let power_loss = |t: f64| -> f64 {
        let y = traj.at(t).expect("inside the run");
        f_crit.iter().map(|&(c, fc)| fc * y[n + c].abs()).sum()
    };
    let e0 = energy(traj.state(0));
    let (mut w, mut d, mut l) = (0.0, 0.0, 0.0);
    let mut worst = 0.0f64;
    let mut scale = e0.abs().max(1.0);
    let mut min_power = f64::INFINITY;
    let mut next_hit = 0;
    let sub = sub.max(2) & !1; // even, for Simpson
    for i in 1..traj.len() {
        let (ta, tb) = (traj.times()[i - 1], traj.times()[i]);
        let (ya, yb) = (traj.state(i - 1), traj.state(i));
        if tb == ta {
            // An event's second row: the impacts at this time (if any) have happened.
            while next_hit < hits.len() && hits[next_hit].0 <= tb {
                if hits[next_hit].0 == tb {
                    let q = V7::from_column_slice(&ya[..n]);
                    l += impact_loss(&arm.inverse_mass_matrix(&q), &hits[next_hit].1);
                }
                next_hit += 1;
            }
        } else {
            let h = (tb - ta) / sub as f64;
            // Simpson on the open arc: the end points from the rows' own states.
            let pa = s9_torque(ta).dot(&V7::from_column_slice(&ya[n..2 * n]));
            let pb = s9_torque(tb).dot(&V7::from_column_slice(&yb[n..2 * n]));
            let la: f64 = f_crit.iter().map(|&(c, fc)| fc * ya[n + c].abs()).sum();
            let lb: f64 = f_crit.iter().map(|&(c, fc)| fc * yb[n + c].abs()).sum();
            let (mut sw, mut sd) = (pa + pb, la + lb);
            for k in 1..sub {
                let t = ta + h * k as f64;
                let c = if k % 2 == 1 { 4.0 } else { 2.0 };
                sw += c * power_in(t);
                sd += c * power_loss(t);
            }
            w += sw * h / 3.0;
            d += sd * h / 3.0;
        }
        for (e, &(c, _)) in f_crit.iter().enumerate() {
            min_power = min_power.min(yb[2 * n + e] * yb[n + c]);
        }
        let e = energy(yb);
        scale = scale.max(e.abs()).max(w.abs());
        worst = worst.max((e - e0 - w + d + l).abs());
    }
    Balance {
        relative_residual: worst / scale,
        work_in: w,
        friction_dissipation: d,
        impact_loss: l,
        impacts,
        settled,
        handovers,
        min_element_power: min_power,
    }
}
