//! Shared by the S9 example, its test and the report: the arm with joint friction and
//! stops (theory S9), its standard run, and the energy balance
//! `E(t) − E(0) = W_in(t) − D_friction(t) − L_impacts(t)`.
#![allow(dead_code)]

use filippov::nalgebra::SVector;
use filippov::prelude::*;
use filippov::runtime::{
    NonSmooth, NonSmoothMethod, NonSmoothProblem, Solution, SolveError, solve_nonsmooth,
};
use filippov_scenes::PandaS9;

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
    pub impact_loss: f64,
    pub impacts: usize,
    /// Smallest friction power `f_crit |v|` contribution check: the most negative
    /// element power `f_e v_e` seen at a row (≥ 0 up to round-off when dissipative).
    pub min_element_power: f64,
}

/// `E = T + U`; the work of the applied torques and the friction dissipation
/// `Σ f_crit |v|` are integrated on each smooth arc between rows (Simpson's rule on the
/// dense output, `sub` panels per arc); rows sharing a time are impacts, whose energy
/// jump is the impact loss.
pub fn s9_balance(arm: &PandaS9, traj: &Solution, sub: usize) -> Balance {
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
                filippov::runtime::nonsmooth::ElementKind::DashPot { f_crit, .. } => {
                    Some((el.coordinate, f_crit))
                }
                _ => None,
            }
        })
        .collect();
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
    let mut impacts = 0;
    let mut worst = 0.0f64;
    let mut scale = e0.abs().max(1.0);
    let mut min_power = f64::INFINITY;
    let sub = sub.max(2) & !1; // even, for Simpson
    for i in 1..traj.len() {
        let (ta, tb) = (traj.times()[i - 1], traj.times()[i]);
        let (ya, yb) = (traj.state(i - 1), traj.state(i));
        if tb == ta {
            impacts += 1;
            l -= energy(yb) - energy(ya);
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
        min_element_power: min_power,
    }
}
