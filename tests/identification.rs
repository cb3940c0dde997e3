//! Identification on the generated kernels' parameter sensitivities
//! (`examples/support/identification.rs`): Gauss–Newton on `∂τ/∂p` from dual numbers
//! recovers the Panda's link masses and joint friction from noisy torques to within the
//! Cramér–Rao bound, and over fresh noise draws the estimates spread as the bound says.
//! Wrong sensitivities fail both: Gauss–Newton would stop off the truth, or the bound
//! (computed from the same Jacobian) would not describe the spread.

#[path = "../examples/support/identification.rs"]
mod identification;

use filippov::prelude::*;
use identification::{P, TRUTH, gauss_newton, measure, names};

const SAMPLES: usize = 200;
const DURATION: f64 = 10.0;
const SIGMA: f64 = 0.5;

#[test]
fn gauss_newton_recovers_the_parameters_within_the_bound() {
    let truth = TRUTH.parameters();
    let start = truth.map(|x| 1.3 * x);
    let est = gauss_newton(&measure(SAMPLES, DURATION, SIGMA, 7), start, SIGMA)
        .expect("the trajectory excites every parameter");
    for (k, name) in names().iter().enumerate() {
        let sd = est.covariance[(k, k)].sqrt();
        let z = (est.parameters[k] - truth[k]) / sd;
        eprintln!(
            "{name}: {:.4} against {:.4}, {z:+.2} σ",
            est.parameters[k], truth[k]
        );
        assert!(z.abs() < 4.0, "{name}: {z} σ off");
    }
    // The residuals are the noise: their RMS estimates σ (to a few per cent with 1,400
    // torques).
    assert!((est.rms / SIGMA - 1.0).abs() < 0.1, "RMS {}", est.rms);
}

/// Over 60 draws of the noise the estimates' standard deviation matches the bound per
/// parameter (a sample standard deviation of 60 draws is within ±9 % of the true one at
/// one sigma: ±30 % is more than 3 of them), and their mean is within 4 standard errors
/// of the truth (no bias).
#[test]
fn the_estimates_spread_as_the_cramer_rao_bound_says() {
    let truth = TRUTH.parameters();
    let start = truth.map(|x| 1.3 * x);
    let reps = 60;
    let mut sum = [0.0; P];
    let mut sq = [0.0; P];
    let mut bound = [0.0; P];
    for r in 0..reps {
        let est = gauss_newton(&measure(SAMPLES, DURATION, SIGMA, 1000 + r), start, SIGMA)
            .expect("identifiable");
        for k in 0..P {
            let e = est.parameters[k] - truth[k];
            sum[k] += e;
            sq[k] += e * e;
            bound[k] = est.covariance[(k, k)].sqrt();
        }
    }
    for (k, name) in names().iter().enumerate() {
        let n = reps as f64;
        let sd = (sq[k] / n).sqrt();
        let mean = sum[k] / n;
        eprintln!(
            "{name}: spread / bound {:.3}, mean error {:+.2} standard errors",
            sd / bound[k],
            mean / (bound[k] / n.sqrt())
        );
        assert!(
            (sd / bound[k] - 1.0).abs() < 0.3,
            "{name}: {}",
            sd / bound[k]
        );
        assert!(mean.abs() < 4.0 * bound[k] / n.sqrt(), "{name}: biased");
    }
}
