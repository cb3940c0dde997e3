//! The contacts section: the planar scenes' closed forms (theory §8) against the
//! event-driven integrator at a tight and at the default tolerance and against
//! time-stepping, each timed; and the randomized agreement suite of contact scenes.

use filippov::nalgebra::SVector;
use filippov::runtime::{
    Method, Mode, NonSmoothProblem, Options, Solution, SwitchKind, contact_event_driven,
    contact_time_stepping,
};
use filippov_scenes::{SlidingBox, SpinningBall};

use super::config::Config;
use super::contact_agreement;
use super::markdown::{Page, sci};
use super::timing::timed;
use super::workprecision::Section;

type V3 = SVector<f64, 3>;

fn no_input(_: f64, _: &V3, _: &V3) -> V3 {
    V3::zeros()
}

fn resting(s: &SlidingBox) -> V3 {
    V3::from([-s.b * s.phi.sin(), s.b * s.phi.cos(), s.phi])
}

/// How a run is made: event-driven at a tolerance, or time-stepping with a step.
#[derive(Clone, Copy)]
enum How {
    Event(f64),
    Steps(f64),
}

impl How {
    fn label(self) -> String {
        match self {
            How::Event(rtol) => format!("event-driven DOPRI5, rtol {rtol:.0e}"),
            How::Steps(h) => format!("time-stepping, h = {h:.0e}"),
        }
    }
}

fn run<S, const K: usize, const T: usize>(
    s: &S,
    p: &NonSmoothProblem<3>,
    how: How,
) -> Result<Solution, String>
where
    S: filippov::runtime::system::Mechanism<3> + filippov::runtime::contacts::Contacts<3, K, T>,
{
    match how {
        How::Event(rtol) => {
            let options = Options {
                max_steps: 10_000_000,
                ..Options::tolerances(rtol, rtol * 1e-2)
            };
            contact_event_driven(s, &no_input, p, &Method::Dopri5(options))
        }
        How::Steps(h) => contact_time_stepping(s, &no_input, p, h),
    }
    .map_err(|e| e.to_string())
}

/// The time of the first switch into `mode`, or of the first row whose coordinate
/// `velocity` is exactly zero (time-stepping logs a stick in the step it happens).
fn stuck_at(sol: &Solution, velocity: usize) -> Option<f64> {
    sol.switches
        .iter()
        .find(|sw| sw.to == Some(Mode::Stick))
        .map(|sw| sw.t)
        .or_else(|| sol.rows().find(|(_, y)| y[velocity] == 0.0).map(|(t, _)| t))
}

pub fn contacts(config: &Config) -> Section {
    let mut page = Page::empty();
    let mut summary = Vec::new();
    page.h2("Contacts");
    page.para(
        "The planar scenes of theory §8 against their closed forms: event-driven (`contact_event_driven`, \
         DOPRI5) at rtol 1e-12 and at the default rtol 1e-6, and Moreau–Jean time-stepping \
         (`contact_time_stepping`). Time = median (min–max) of repeated runs.",
    );
    let hows = [How::Event(1e-12), How::Event(1e-6), How::Steps(1e-3)];
    let mut rows: Vec<Vec<String>> = Vec::new();
    let mut add =
        |what: &str, exact: f64, how: How, got: Result<(f64, super::timing::Timing), String>| {
            let row = match got {
                Ok((value, t)) => vec![
                    what.to_string(),
                    how.label(),
                    format!("{exact:.12}"),
                    format!("{value:.12}"),
                    sci((value - exact).abs()),
                    t.scaled(1e3).show(2),
                ],
                Err(e) => vec![
                    what.to_string(),
                    how.label(),
                    format!("{exact:.12}"),
                    format!("failed: {e}"),
                    String::new(),
                    String::new(),
                ],
            };
            rows.push(row);
        };
    let repeats = config.repeats;
    // A box sliding to rest on level ground.
    let b = SlidingBox::default();
    let v0 = 2.0;
    let p = NonSmoothProblem::new(0.0, 1.0, resting(&b), V3::from([v0, 0.0, 0.0]));
    for how in hows {
        let (t, sol) = timed(repeats, || run(&b, &p, how));
        let stop = sol
            .as_ref()
            .map_err(Clone::clone)
            .and_then(|s| stuck_at(s, 3).ok_or("no stop".to_string()));
        add(
            "box sliding to rest: stop time [s]",
            v0 / (b.mu * b.g),
            how,
            stop.map(|x| (x, t)),
        );
        let dist = sol
            .as_ref()
            .map_err(Clone::clone)
            .map(|s| s.last().expect("rows").1[0]);
        add(
            "box sliding to rest: distance [m]",
            v0 * v0 / (2.0 * b.mu * b.g),
            how,
            dist.map(|x| (x, t)),
        );
    }
    // Below its friction angle on an incline, over 10⁴ s.
    let below = SlidingBox {
        phi: 0.3,
        ..SlidingBox::default()
    };
    let q0 = resting(&below);
    let p = NonSmoothProblem::new(0.0, 1e4, q0, V3::zeros());
    for how in [How::Event(1e-12), How::Event(1e-6), How::Steps(1e-2)] {
        let (t, sol) = timed(1, || run(&below, &p, how));
        let moved = sol.map(|s| {
            s.rows()
                .map(|(_, y)| (0..3).map(|j| (y[j] - q0[j]).abs()).fold(0.0, f64::max))
                .fold(0.0, f64::max)
        });
        add(
            "incline below its friction angle: largest displacement over 10⁴ s [m]",
            0.0,
            how,
            moved.map(|x| (x, t)),
        );
    }
    // Above it: the speed after 2 s.
    let above = SlidingBox {
        phi: 0.6,
        ..SlidingBox::default()
    };
    let a = above.g * (above.phi.sin() - above.mu * above.phi.cos());
    let p = NonSmoothProblem::new(0.0, 2.0, resting(&above), V3::zeros());
    for how in hows {
        let (t, sol) = timed(repeats, || run(&above, &p, how));
        let speed = sol.map(|s| {
            let y = s.last().expect("rows").1;
            -(y[3] * above.phi.cos() + y[4] * above.phi.sin())
        });
        add(
            "incline above its friction angle: speed at 2 s [m/s]",
            2.0 * a,
            how,
            speed.map(|x| (x, t)),
        );
    }
    // A ball spun on the ground.
    let ball = SpinningBall::default();
    let omega = 20.0;
    let p = NonSmoothProblem::new(
        0.0,
        1.0,
        V3::from([0.0, ball.r, 0.0]),
        V3::from([0.0, 0.0, omega]),
    );
    for how in hows {
        let (t, sol) = timed(repeats, || run(&ball, &p, how));
        let rolls = sol.as_ref().map_err(Clone::clone).and_then(|s| {
            s.rows()
                .find(|(_, y)| (y[3] + ball.r * y[5]).abs() < 1e-12)
                .map(|(t, _)| t)
                .ok_or("never rolls".to_string())
        });
        add(
            "spinning ball: rolling from [s]",
            2.0 * ball.r * omega / (7.0 * ball.mu * ball.g),
            how,
            rolls.map(|x| (x, t)),
        );
        let speed = sol.map(|s| s.last().expect("rows").1[3]);
        add(
            "spinning ball: rolling speed [m/s]",
            -2.0 / 7.0 * ball.r * omega,
            how,
            speed.map(|x| (x, t)),
        );
    }
    // A ball dropped from 0.2 m: first impact, accumulation, resting force.
    let height = 0.2;
    let p = NonSmoothProblem::new(0.0, 1.5, V3::from([0.0, ball.r + height, 0.0]), V3::zeros());
    let (t1, v1) = (
        (2.0 * height / ball.g).sqrt(),
        (2.0 * ball.g * height).sqrt(),
    );
    let t_inf = t1 + 2.0 * ball.e * v1 / (ball.g * (1.0 - ball.e));
    for how in hows {
        let (t, sol) = timed(repeats, || run(&ball, &p, how));
        let first = sol.as_ref().map_err(Clone::clone).and_then(|s| {
            s.switches
                .iter()
                .find(|sw| matches!(sw.kind, SwitchKind::Impact | SwitchKind::Settled))
                .map(|sw| sw.t)
                .ok_or("no impact".to_string())
        });
        add(
            "dropped ball: first impact [s]",
            t1,
            how,
            first.map(|x| (x, t)),
        );
        if let How::Event(_) = how {
            let settled = sol.as_ref().map_err(Clone::clone).and_then(|s| {
                s.switches
                    .iter()
                    .find(|sw| sw.kind == SwitchKind::Settled)
                    .map(|sw| sw.accumulation.unwrap_or(sw.t))
                    .ok_or("never settles".to_string())
            });
            add(
                "dropped ball: settled (accumulation point) [s]",
                t_inf,
                how,
                settled.map(|x| (x, t)),
            );
        }
        let force = sol.map(|s| {
            let i = s.column_index("λ_bottom.n").expect("a force column");
            s.last().expect("rows").1[i]
        });
        add(
            "dropped ball: resting normal force [N]",
            ball.m * ball.g,
            how,
            force.map(|x| (x, t)),
        );
    }
    // Housner's rocking block: the angular velocity ratio at every impact.
    let block = SlidingBox {
        a: 0.2,
        b: 0.4,
        mu: 1.0,
        e: 0.0,
        ..SlidingBox::default()
    };
    let alpha = (block.a / block.b).atan();
    let ratio = 1.0 - 1.5 * alpha.sin().powi(2);
    let theta0: f64 = 0.1;
    let (st, ct) = theta0.sin_cos();
    let q0 = V3::from([
        block.a * ct - block.b * st,
        block.a * st + block.b * ct,
        theta0,
    ]);
    let p = NonSmoothProblem::new(0.0, 3.0, q0, V3::zeros());
    for how in [How::Event(1e-12), How::Event(1e-6)] {
        let (t, sol) = timed(repeats, || run(&block, &p, how));
        let worst = sol.map(|s| {
            let ratios: Vec<f64> = s
                .switches
                .iter()
                .filter(|sw| {
                    matches!(sw.kind, SwitchKind::Impact | SwitchKind::Settled)
                        && sw.after[5].abs() > 1e-9
                })
                .map(|sw| sw.after[5] / sw.before[5])
                .collect();
            // The ratio farthest from the closed form.
            ratios
                .into_iter()
                .max_by(|x, y| (x - ratio).abs().total_cmp(&(y - ratio).abs()))
                .unwrap_or(f64::NAN)
        });
        add(
            "Housner block: θ̇⁺/θ̇⁻ at the worst impact",
            ratio,
            how,
            worst.map(|x| (x, t)),
        );
    }
    page.table(
        &[
            "scene and quantity",
            "method",
            "closed form",
            "computed",
            "error",
            "time [ms]",
        ],
        &rows,
    );
    for r in &rows {
        if r[1].contains("1e-12") && !r[4].is_empty() {
            summary.push(format!(
                "Contacts, {}: error {} (event-driven, rtol 1e-12)",
                r[0], r[4]
            ));
        }
    }

    // The randomized agreement suite.
    let count = if config.name == "tiny" { 30 } else { 500 };
    page.h3("Randomized agreement suite");
    let results: Vec<_> = (0..count as u64).map(contact_agreement::run).collect();
    let failed: Vec<String> = results
        .iter()
        .filter(|r| !r.passed())
        .map(|r| r.seed.to_string())
        .collect();
    let worst = |f: &dyn Fn(&contact_agreement::Checked) -> f64| {
        results.iter().map(f).fold(0.0f64, f64::max)
    };
    let mut ratios: Vec<f64> = results
        .iter()
        .map(|r| r.distance[2] / r.distance[1])
        .filter(|x| x.is_finite())
        .collect();
    ratios.sort_by(f64::total_cmp);
    let median = ratios.get(ratios.len() / 2).copied().unwrap_or(f64::NAN);
    page.para(&format!(
        "{count} random scenes (`examples/support/contact_agreement.rs`: boxes of random size, mass, friction and \
         restitution launched along inclines of random angle, balls dropped spinning), each integrated \
         event-driven (rtol 1e-10) and by time-stepping at h = 1e-3, 1e-4 and 1e-5 over {} s. A scene passes when \
         its energy never rises by more than 1e-8 of its scale, no contact penetrates deeper than 1e-8, and \
         time-stepping's largest position difference from the event-driven run shrinks at least 0.3× over one of \
         the two decades of steps (first order; over one decade alone two first-order errors of opposite sign can \
         cancel).",
        contact_agreement::HORIZON
    ));
    page.table(
        &[
            "scenes",
            "failed",
            "worst energy rise",
            "deepest penetration",
            "median distance ratio (h = 1e-5 / 1e-4)",
            "switches",
        ],
        &[vec![
            count.to_string(),
            if failed.is_empty() {
                "0".to_string()
            } else {
                format!("{} ({})", failed.len(), failed.join(", "))
            },
            sci(worst(&|r| r.energy_rise)),
            sci(worst(&|r| r.penetration)),
            format!("{median:.3}"),
            results
                .iter()
                .map(|r| r.switches)
                .sum::<usize>()
                .to_string(),
        ]],
    );
    summary.push(format!(
        "Contacts' agreement suite: {count} random scenes, {} failed; time-stepping's distance from event-driven shrinks {median:.3}× (median) from h = 1e-4 to 1e-5",
        failed.len()
    ));
    Section { page, summary }
}
