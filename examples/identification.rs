//! System identification with the generated kernels' parameter sensitivities: the
//! Panda's link masses (links 2–7) and joint Coulomb friction estimated from noisy joint
//! torques measured along a trajectory, by Gauss–Newton on `∂τ/∂p` from dual numbers
//! (`emit = [generic]`), with the Cramér–Rao bound from the same Jacobian.
//!
//! Then 200 repetitions with fresh noise: the estimates' spread against the bound (least
//! squares on this model, linear in its parameters, attains it).
//!
//! Run: `cargo run --release --example identification` (a plot in `target/plots/`).

#[path = "support/identification.rs"]
mod identification;
#[path = "support/mod.rs"]
mod support;

use filippov::prelude::*;
use identification::{P, TRUTH, gauss_newton, measure, names, torques};
use support::{Series, plot_over_time};

fn main() {
    let (count, duration, sigma) = (500, 10.0, 0.1);
    let samples = measure(count, duration, sigma, 1);
    // Start 30 % off every parameter.
    let start = TRUTH.parameters().map(|x| 1.3 * x);
    let est = match gauss_newton(&samples, start, sigma) {
        Ok(e) => e,
        Err(e) => {
            eprintln!("identification failed: {e}");
            std::process::exit(1);
        }
    };
    println!(
        "{count} samples of 7 joint torques over {duration} s, noise σ = {sigma} N·m; \
         Gauss–Newton from +30 %: {} iterations, residual RMS {:.4} N·m",
        est.iterations, est.rms
    );
    println!(
        "{:<4} {:>10} {:>10} {:>10} {:>8}",
        "", "true", "estimate", "CRB σ", "error/σ"
    );
    let truth = TRUTH.parameters();
    for (k, name) in names().iter().enumerate() {
        let sd = est.covariance[(k, k)].sqrt();
        println!(
            "{name:<4} {:>10.4} {:>10.4} {:>10.4} {:>8.2}",
            truth[k],
            est.parameters[k],
            sd,
            (est.parameters[k] - truth[k]) / sd
        );
    }

    // Monte Carlo: the estimates' standard deviation over fresh noise against the bound.
    let reps = 200;
    let mut errors = vec![[0.0; P]; reps];
    for (r, e) in errors.iter_mut().enumerate() {
        let s = measure(count, duration, sigma, 100 + r as u64);
        let est = gauss_newton(&s, start, sigma).expect("identifiable");
        for k in 0..P {
            e[k] = est.parameters[k] - truth[k];
        }
    }
    println!("\nover {reps} noise draws: the estimates' standard deviation / the Cramér–Rao bound");
    for (k, name) in names().iter().enumerate() {
        let var = errors.iter().map(|e| e[k] * e[k]).sum::<f64>() / reps as f64;
        println!("{name:<4} {:.3}", (var / est.covariance[(k, k)]).sqrt());
    }

    // Measured and fitted torques of joints 2 and 4.
    let fitted: Vec<[f64; 7]> = samples
        .iter()
        .map(|s| torques::<f64>(&est.parameters, &s.q, &s.v, &s.a))
        .collect();
    let mut series = Vec::new();
    for j in [1, 3] {
        series.push(Series::new(
            format!("joint {} measured", j + 1),
            samples.iter().map(|s| (s.t, s.tau[j])).collect(),
        ));
        series.push(Series::new(
            format!("joint {} identified model", j + 1),
            samples
                .iter()
                .zip(&fitted)
                .map(|(s, f)| (s.t, f[j]))
                .collect(),
        ));
    }
    plot_over_time(
        "identification",
        "Panda: measured joint torques and the identified model",
        "τ [N·m]",
        &series,
    );
}
