//! The contacts section: the planar scenes' closed forms (theory §8) against the
//! event-driven integrator at a tight and at the default tolerance and against
//! time-stepping, each timed; and the randomized agreement suite of contact scenes.

use filippov::nalgebra::SVector;
use filippov::runtime::{
    Method, Mode, NonSmoothProblem, Options, Solution, SwitchKind, contact_event_driven,
    contact_time_stepping,
};
use filippov_scenes::{FallingRod, Puck, SlidingBox, SpinningBall, Table};

use super::config::Config;
use super::contact_agreement;
use super::contact_closed_forms::{Housner, rod_slip_angle};
use super::markdown::{Page, sci};
use super::support::{Scale, Series, line_plot};
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
    // Below its friction angle on an incline, over 10⁴ s (10² s in the tiny
    // configuration, whose runs are unoptimised: 10⁶ time steps there took minutes).
    let below = SlidingBox {
        phi: 0.3,
        ..SlidingBox::default()
    };
    let q0 = resting(&below);
    let still_for = if config.name == "tiny" { 1e2 } else { 1e4 };
    let p = NonSmoothProblem::new(0.0, still_for, q0, V3::zeros());
    for how in [How::Event(1e-12), How::Event(1e-6), How::Steps(1e-2)] {
        let (t, sol) = timed(1, || run(&below, &p, how));
        let moved = sol.map(|s| {
            s.rows()
                .map(|(_, y)| (0..3).map(|j| (y[j] - q0[j]).abs()).fold(0.0, f64::max))
                .fold(0.0, f64::max)
        });
        add(
            &format!(
                "incline below its friction angle: largest displacement over {still_for:e} s [m]"
            ),
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
    // Its impact times and amplitudes, from the energy equation by quadrature.
    let housner = Housner::new(block.a, block.b, block.g);
    let reference = housner.impacts(theta0, 8);
    let last = reference[7];
    for how in [How::Event(1e-12), How::Event(1e-6)] {
        let (t, sol) = timed(repeats, || run(&block, &p, how));
        let times: Result<Vec<f64>, String> = sol.as_ref().map_err(Clone::clone).map(|s| {
            let mut times: Vec<f64> = Vec::new();
            for sw in &s.switches {
                let rocking = matches!(sw.kind, SwitchKind::Impact | SwitchKind::Settled)
                    && sw.after[5].abs() > 1e-9;
                if rocking && times.last().is_none_or(|&x| sw.t > x) {
                    times.push(sw.t);
                }
            }
            times
        });
        let eighth = times.and_then(|x| x.get(7).copied().ok_or("fewer than 8 impacts".into()));
        add(
            "Housner block: 8th impact time [s]",
            last.t,
            how,
            eighth.map(|x| (x, t)),
        );
        let amplitude = sol.and_then(|s| {
            s.at(last.apex)
                .map(|y| y[2].abs())
                .ok_or("the apex is outside the run".to_string())
        });
        add(
            "Housner block: amplitude after the 8th impact [rad]",
            last.amplitude,
            how,
            amplitude.map(|x| (x, t)),
        );
    }
    // A rod tipping over on rough ground: the angle where its foot starts to slip.
    let rod = FallingRod::default();
    let lean0: f64 = 0.05;
    if let Some((angle, _)) = rod_slip_angle(rod.mu, lean0) {
        let q0 = V3::from([-rod.l * lean0.sin(), rod.l * lean0.cos(), lean0]);
        let p = NonSmoothProblem::new(0.0, 1.0, q0, V3::zeros());
        for how in hows {
            let (t, sol) = timed(repeats, || run(&rod, &p, how));
            let slip = sol.and_then(|s| {
                s.switches
                    .iter()
                    .find(|sw| {
                        sw.element.as_deref() == Some("foot")
                            && matches!(sw.to, Some(Mode::SlipPos(_) | Mode::SlipNeg(_)))
                    })
                    .map(|sw| sw.after[2])
                    .ok_or("the foot never slips".to_string())
            });
            add(
                "rod tipping on rough ground (μ = 0.3): slip-start angle [rad]",
                angle,
                how,
                slip.map(|x| (x, t)),
            );
        }
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
    spatial(config, &mut page, &mut summary);
    bearings(config, &mut page, &mut summary);
    woodpecker(config, &mut page, &mut summary);
    for r in &rows {
        if r[1].contains("1e-12") && !r[4].is_empty() {
            summary.push(format!(
                "Contacts, {}: error {} (event-driven, rtol 1e-12)",
                r[0], r[4]
            ));
        }
    }

    mujoco_side_by_side(config, &mut page, &mut summary);

    // The randomized agreement suite.
    // The tiny configuration runs a few (`cargo test` runs 30 of its own).
    let count = if config.name == "tiny" { 8 } else { 500 };
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
         restitution launched along inclines of random angle, balls dropped spinning, rods tipping over or dropped on \
         an end), each integrated \
         event-driven (rtol 1e-10) and by time-stepping at h = 1e-3, 1e-4 and 1e-5 over {} s. A scene passes when \
         its energy never rises by more than 1e-8 of its scale, no contact penetrates deeper than 1e-8, no \
         friction force leaves its cone by more than 1e-9 of the weight, and \
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
            "largest friction beyond its cone (/ weight)",
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
            sci(worst(&|r| r.cone_excess)),
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

/// Twelve decimals, or powers of ten below a thousandth.
fn fixed(x: f64) -> String {
    if x != 0.0 && x.abs() < 1e-3 {
        sci(x)
    } else {
        format!("{x:.12}")
    }
}

/// Spatial contacts by time-stepping on the exact cone: the puck and the table against
/// closed forms and invariants.
fn spatial(config: &Config, page: &mut Page, summary: &mut Vec<String>) {
    type V6 = SVector<f64, 6>;
    page.h3("Spatial contacts");
    page.para(
        "Contacts that can slide in two directions, by Moreau–Jean time-stepping with Coulomb's isotropic cone \
         (`contact_time_stepping`; each step's contact problem solved by Gauss–Seidel over the contacts, each \
         contact's own problem exactly, to a natural-map residual of 1e-12 that the solution's statistics \
         report). The puck is a point mass on a plane (`Puck`); the table a slab on three point legs with six \
         coordinates (`Table`). Rows marked `ED 1e-12` are the event-driven integrator (`contact_event_driven`, \
         DOPRI5 at rtol 1e-12), which takes spatial contacts whose slips stop along a fixed direction. Time = \
         median (min–max) of repeated runs.",
    );
    let repeats = config.repeats;
    let mut rows: Vec<Vec<String>> = Vec::new();
    let mut row =
        |what: &str, h: &str, exact: f64, got: f64, t: super::timing::Timing, note: String| {
            rows.push(vec![
                what.to_string(),
                h.to_string(),
                fixed(exact),
                fixed(got),
                sci((got - exact).abs()),
                t.scaled(1e3).show(2),
                note,
            ]);
        };
    let free3 = |_: f64, _: &V3, _: &V3| V3::zeros();
    let free6 = |_: f64, _: &V6, _: &V6| V6::zeros();
    // The puck launched in twelve directions on level ground.
    let puck = Puck::default();
    let v0 = 1.5;
    let h = 1e-3;
    // The k-th of 12 launch directions on level ground: its cosine, sine and problem.
    let launch = |k: usize| {
        let th = 0.37 + k as f64 * std::f64::consts::TAU / 12.0;
        let (sn, c) = th.sin_cos();
        let p = NonSmoothProblem::new(0.0, 1.0, V3::zeros(), V3::from([v0 * c, v0 * sn, 0.0]));
        (c, sn, p)
    };
    let (t, worst) = timed(repeats, || {
        let mut worst = (0.0f64, 0.0f64);
        for k in 0..12 {
            let (c, sn, p) = launch(k);
            if let Ok(sol) = contact_time_stepping(&puck, &free3, &p, h) {
                let y = sol.last().expect("rows").1;
                let along = y[0] * c + y[1] * sn;
                let across = (-y[0] * sn + y[1] * c).abs();
                let exact = v0 * v0 / (2.0 * puck.mu * puck.g);
                worst.0 = worst.0.max((along - exact).abs());
                worst.1 = worst.1.max(across);
            } else {
                worst = (f64::NAN, f64::NAN);
            }
        }
        worst
    });
    row(
        "puck launched in 12 directions: largest distance off its line [m]",
        &format!("{h:.0e}"),
        0.0,
        worst.1,
        t,
        format!("stop distance within {} of v0²/(2μg)", sci(worst.0)),
    );
    // Across an incline at its friction angle: v·d + |v| = v0.
    let phi: f64 = 0.3;
    let incline = Puck {
        phi,
        mu: phi.tan(),
        ..Puck::default()
    };
    let down = V3::from([0.0, -phi.cos(), -phi.sin()]);
    // v·d + |v| at its farthest from v0 = 2 over a run.
    let farthest = |sol: &Solution| {
        sol.rows()
            .map(|(_, y)| {
                let v = V3::from([y[3], y[4], y[5]]);
                v.dot(&down) + v.norm()
            })
            .max_by(|a, b| (a - 2.0).abs().total_cmp(&(b - 2.0).abs()))
            .unwrap_or(f64::NAN)
    };
    for h in [1e-3, 1e-4] {
        let p = NonSmoothProblem::new(0.0, 3.0, V3::zeros(), V3::from([2.0, 0.0, 0.0]));
        let (t, sol) = timed(repeats, || contact_time_stepping(&incline, &free3, &p, h));
        if let Ok(sol) = sol {
            let worst = farthest(&sol);
            row(
                "puck across an incline at μ = tan φ: v·d + |v|, its farthest from v0 [m/s]",
                &format!("{h:.0e}"),
                2.0,
                worst,
                t,
                String::new(),
            );
        }
    }
    // The table below its friction angle, 10⁴ s.
    let table = Table {
        phi: 0.3,
        ..Table::default()
    };
    let q0 = V6::from([
        0.0,
        -table.d * table.phi.sin(),
        table.d * table.phi.cos(),
        0.0,
        0.0,
        table.phi,
    ]);
    // 10⁴ s (10² s in the tiny configuration, whose runs are unoptimised).
    let horizon = if config.name == "tiny" { 1e2 } else { 1e4 };
    let moved = |sol: &Solution| {
        sol.rows()
            .map(|(_, y)| (0..6).map(|j| (y[j] - q0[j]).abs()).fold(0.0, f64::max))
            .fold(0.0, f64::max)
    };
    let still = format!(
        "table on an incline below its friction angle: largest displacement over {horizon:e} s"
    );
    let p = NonSmoothProblem::new(0.0, horizon, q0, V6::zeros());
    let (t, sol) = timed(1, || contact_time_stepping(&table, &free6, &p, 1e-2));
    if let Ok(sol) = sol {
        let moved = moved(&sol);
        row(&still, "1e-2", 0.0, moved, t, format!("{}", sol.stats));
        summary.push(format!(
            "Spatial contacts: the three-legged table below its friction angle moves {} over {horizon:e} s (time-stepping, exact cone)",
            sci(moved)
        ));
    }
    // Sliding and spinning to rest: the solver's residual and sweeps.
    let flat = Table::default();
    let start = V6::from([0.0, 0.0, flat.d, 0.0, 0.0, 0.0]);
    let p = NonSmoothProblem::new(0.0, 1.0, start, V6::from([1.2, -0.7, 0.0, 4.0, 0.0, 0.0]));
    for h in [1e-3, 1e-4] {
        let (t, sol) = timed(repeats, || contact_time_stepping(&flat, &free6, &p, h));
        if let Ok(sol) = sol {
            let y = sol.last().expect("rows").1;
            let still = y[6..12].iter().all(|&x| x == 0.0);
            row(
                "table sliding and spinning to rest: largest residual of a step's contact problem",
                &format!("{h:.0e}"),
                0.0,
                sol.stats.contact_residual,
                t,
                format!(
                    "{:.1} sweeps per step; {}",
                    sol.stats.contact_sweeps as f64 / sol.stats.steps.max(1) as f64,
                    if still {
                        "at rest, exactly"
                    } else {
                        "still moving"
                    }
                ),
            );
        }
    }
    // Event-driven (DOPRI5 at rtol 1e-12): the slips that stop along a fixed direction
    // located exactly.
    let ed = "ED 1e-12";
    let tight = Method::Dopri5(Options {
        max_steps: 1_000_000,
        ..Options::tolerances(1e-12, 1e-14)
    });
    let (t, worst) = timed(repeats, || {
        let mut worst = (0.0f64, 0.0f64);
        for k in 0..12 {
            let (c, sn, p) = launch(k);
            match contact_event_driven(&puck, &free3, &p, &tight) {
                Ok(sol) => {
                    let stop = sol
                        .switches
                        .iter()
                        .find(|w| w.to == Some(Mode::Stick))
                        .map_or(f64::NAN, |w| w.t);
                    let y = sol.last().expect("rows").1;
                    let exact = v0 * v0 / (2.0 * puck.mu * puck.g);
                    let along = y[0] * c + y[1] * sn;
                    worst.0 = worst.0.max((stop - v0 / (puck.mu * puck.g)).abs());
                    worst.1 = worst.1.max((along - exact).abs());
                }
                Err(_) => worst = (f64::NAN, f64::NAN),
            }
        }
        worst
    });
    row(
        "puck launched in 12 directions: stop time, largest error [s]",
        ed,
        0.0,
        worst.0,
        t,
        format!("stop distance within {} of v0²/(2μg)", sci(worst.1)),
    );
    let p = NonSmoothProblem::new(0.0, 3.0, V3::zeros(), V3::from([2.0, 0.0, 0.0]));
    let (t, sol) = timed(repeats, || {
        contact_event_driven(&incline, &free3, &p, &tight)
    });
    if let Ok(sol) = sol {
        let worst = farthest(&sol);
        row(
            "puck across an incline at μ = tan φ: v·d + |v|, its farthest from v0 [m/s]",
            ed,
            2.0,
            worst,
            t,
            String::new(),
        );
    }
    let p = NonSmoothProblem::new(0.0, horizon, q0, V6::zeros());
    let (t, sol) = timed(1, || contact_event_driven(&table, &free6, &p, &tight));
    if let Ok(sol) = sol {
        let moved = moved(&sol);
        row(&still, ed, 0.0, moved, t, format!("{} rows", sol.len()));
    }
    let (c, sn, v_push) = (0.6, -0.8, 1.2);
    let p = NonSmoothProblem::new(
        0.0,
        1.0,
        start,
        V6::from([v_push * c, v_push * sn, 0.0, 0.0, 0.0, 0.0]),
    );
    let (t, sol) = timed(repeats, || contact_event_driven(&flat, &free6, &p, &tight));
    if let Ok(sol) = sol {
        let stop = sol
            .switches
            .iter()
            .filter(|w| w.to == Some(Mode::Stick))
            .map(|w| w.t)
            .fold(f64::NAN, f64::max);
        let exact = v_push / (flat.mu * flat.g);
        row(
            "table pushed without spin: stop time [s]",
            ed,
            exact,
            stop,
            t,
            "all three legs sliding along the push".into(),
        );
    }
    page.table(
        &[
            "scene and quantity",
            "h / method",
            "exact",
            "computed",
            "error",
            "time [ms]",
            "notes",
        ],
        &rows,
    );
    spatial_suite(config, page, summary);
}

/// Bearing friction (`#[friction(x, mu = …)]`): the loaded slider by time-stepping
/// against the same mechanism resting on its rail through two skids (contacts,
/// event-driven), and what a limit that ignores the load gives.
fn bearings(config: &Config, page: &mut Page, summary: &mut Vec<String>) {
    use filippov::runtime::{NonSmoothMethod, solve_nonsmooth};
    use filippov_scenes::{CartOnRail, FixedLimitSlider, LoadedSlider};
    type V2 = SVector<f64, 2>;
    type V4 = SVector<f64, 4>;
    page.h3("Bearings: joint friction that carries the joint's load");
    page.para(
        "A slider on a rail with a pendulum hanging from it (`LoadedSlider`), the rail's friction a bearing: its \
         limit is μ times the force the rail carries, from the generated recursive Newton–Euler algorithm, each \
         step solving for the friction and the load together (`time_stepping`, θ = ½). The reference is the same \
         mechanism resting on the rail through two skids (`CartOnRail`, contacts, event-driven at rtol 1e-12), \
         whose friction is μ times the skids' normal forces. Released at 1.2 rad with the slider moving at \
         0.8 m/s, compared at 1.5 s (slider position and velocity, swing angle and rate: the largest \
         difference). The last row fixes the limit at μ (m_c + m_p) g, the load at rest.",
    );
    let (tf, swing, v0) = (1.5, 1.2, 0.8);
    let cart = CartOnRail::default();
    let tight = Method::Dopri5(Options {
        max_steps: 1_000_000,
        ..Options::tolerances(1e-12, 1e-14)
    });
    let pc = NonSmoothProblem::new(
        0.0,
        tf,
        V4::from([0.0, cart.b, 0.0, swing]),
        V4::from([v0, 0.0, 0.0, 0.0]),
    );
    let free4 = |_: f64, _: &V4, _: &V4| V4::zeros();
    let Ok(reference) = contact_event_driven(&cart, &free4, &pc, &tight) else {
        page.para("The reference run failed.");
        return;
    };
    let y = reference.last().expect("rows").1;
    let exact = [y[0], y[3], y[4], y[7]];
    let free2 = |_: f64, _: &V2, _: &V2| V2::zeros();
    let p = NonSmoothProblem::new(0.0, tf, V2::new(0.0, swing), V2::new(v0, 0.0));
    let off = |sol: &Solution| {
        let y = sol.last().expect("rows").1;
        (0..4).map(|j| (y[j] - exact[j]).abs()).fold(0.0, f64::max)
    };
    let mut rows = Vec::new();
    let slider = LoadedSlider::default();
    // FixedLimit is written with these.
    assert_eq!(
        (slider.mc, slider.mp, slider.l, slider.g),
        (2.0, 1.0, 0.5, 9.81)
    );
    for h in [1e-3, 1e-4] {
        let method = NonSmoothMethod::TimeStepping { h, theta: 0.5 };
        let (t, sol) = timed(config.repeats, || {
            solve_nonsmooth(&slider, &free2, &p, &method)
        });
        if let Ok(sol) = sol {
            let d = off(&sol);
            rows.push(vec![
                "bearing, limit μ F_⊥".to_string(),
                format!("{h:.0e}"),
                sci(d),
                t.scaled(1e3).show(2),
            ]);
            if h == 1e-4 {
                summary.push(format!(
                    "Bearings: the loaded slider (time-stepping, h = 1e-4) ends within {} of the cart on two skids (contacts, event-driven)",
                    sci(d)
                ));
            }
        }
    }
    let fixed = FixedLimitSlider::resting_load_of(&slider);
    let method = NonSmoothMethod::TimeStepping {
        h: 1e-4,
        theta: 0.5,
    };
    let (t, sol) = timed(config.repeats, || {
        solve_nonsmooth(&fixed, &free2, &p, &method)
    });
    if let Ok(sol) = sol {
        rows.push(vec![
            "fixed limit μ (m_c + m_p) g".to_string(),
            "1e-4".to_string(),
            sci(off(&sol)),
            t.scaled(1e3).show(2),
        ]);
    }
    page.table(
        &[
            "model",
            "h",
            "largest difference from the skids",
            "time [ms]",
        ],
        &rows,
    );
}

/// Glocker's woodpecker against Siconos's reference run.
fn woodpecker(config: &Config, page: &mut Page, summary: &mut Vec<String>) {
    use super::woodpecker::{GLOCKER, PUBLISHED_START, largest_difference};
    page.h3("The woodpecker toy, beside Siconos's reference run");
    page.para(
        "Glocker's woodpecker (theory §8): the published linearised model from the published state, three \
         contacts with friction (the beak, the sleeve's two edges), over 0.3 s (two pecks). The reference is the \
         run Siconos ships with its example of the same model (Moreau–Jean, θ = ½, h = 2e-5), sampled every \
         millisecond; the differences are the largest over those samples. Time-stepping here is explicit in the \
         smooth forces (Siconos's is implicit in the spring), so its rows at Siconos's step are not the same \
         scheme. The last column is the largest difference from the event-driven run at rtol 1e-10.",
    );
    let (q0, v0) = PUBLISHED_START;
    let p = NonSmoothProblem::new(0.0, 0.3, V3::from(q0), V3::from(v0));
    let show = |d: [f64; 3]| format!("{} m, {} rad, {} rad", sci(d[0]), sci(d[1]), sci(d[2]));
    let mut rows = Vec::new();
    let mut exact: Option<Solution> = None;
    for rtol in [1e-10, 1e-6] {
        let method = Method::Dopri5(Options {
            max_steps: 1_000_000,
            ..Options::tolerances(rtol, rtol * 1e-3)
        });
        let (t, sol) = timed(config.repeats, || {
            contact_event_driven(&GLOCKER, &no_input, &p, &method)
        });
        match sol {
            Ok(sol) => {
                let d = largest_difference(&sol, None);
                let e = exact
                    .as_ref()
                    .map_or(String::new(), |x| show(largest_difference(&sol, Some(x))));
                if rtol == 1e-10 {
                    summary.push(format!(
                        "Woodpecker (Glocker): event-driven within {} of Siconos's reference run (y, φ_M, φ_S)",
                        show(d)
                    ));
                }
                rows.push(vec![
                    format!("event-driven, rtol {rtol:.0e}"),
                    show(d),
                    e,
                    t.scaled(1e3).show(2),
                ]);
                if exact.is_none() {
                    exact = Some(sol);
                }
            }
            Err(err) => rows.push(vec![
                format!("event-driven, rtol {rtol:.0e}"),
                format!("failed: {err}"),
                String::new(),
                String::new(),
            ]),
        }
    }
    for h in [1e-4, 2e-5, 1e-5] {
        let (t, sol) = timed(config.repeats, || {
            contact_time_stepping(&GLOCKER, &no_input, &p, h)
        });
        let Ok(sol) = sol else {
            continue;
        };
        let e = exact
            .as_ref()
            .map_or(String::new(), |x| show(largest_difference(&sol, Some(x))));
        rows.push(vec![
            format!("time-stepping, h = {h:.0e}"),
            show(largest_difference(&sol, None)),
            e,
            t.scaled(1e3).show(2),
        ]);
    }
    page.table(
        &[
            "run",
            "from Siconos (y, φ_M, φ_S)",
            "from event-driven, rtol 1e-10",
            "time [ms]",
        ],
        &rows,
    );
}

/// The random spatial scenes' suite.
fn spatial_suite(config: &Config, page: &mut Page, summary: &mut Vec<String>) {
    use super::spatial_agreement::{Checked, HORIZON, run};
    let count = if config.name == "tiny" { 3 } else { 120 };
    let results: Vec<Checked> = (0..count as u64).map(run).collect();
    let failed: Vec<String> = results
        .iter()
        .filter(|r| !r.passed())
        .map(|r| {
            let why = if let Some(f) = &r.failure {
                f.clone()
            } else if r.residual > 1e-12 {
                format!("residual {}", sci(r.residual))
            } else if !r.first_order() {
                let finer = r.finer.map_or(String::new(), |[a, b]| {
                    format!("; against h = 4e-6, {} → {}", sci(a), sci(b))
                });
                format!(
                    "distance {} → {}{finer}",
                    sci(r.distance[0]),
                    sci(r.distance[1])
                )
            } else {
                format!(
                    "energy gain {}, sinking {}",
                    sci(r.energy_gain),
                    sci(r.sinking)
                )
            };
            format!("{} ({why})", r.seed)
        })
        .collect();
    let worst = |f: &dyn Fn(&Checked) -> f64| results.iter().map(f).fold(0.0f64, f64::max);
    let mut ratios: Vec<f64> = results
        .iter()
        .map(|r| r.distance[1] / r.distance[0])
        .filter(|x| x.is_finite())
        .collect();
    ratios.sort_by(f64::total_cmp);
    let median = ratios.get(ratios.len() / 2).copied().unwrap_or(f64::NAN);
    let escalated = results.iter().filter(|r| r.finer.is_some()).count();
    page.para(&format!(
        "{count} random spatial scenes (`examples/support/spatial_agreement.rs`: three-legged tables of random size, \
         mass and friction on level ground (spun) or inclines, some dropped tilted; pucks thrown onto random \
         inclines), each by time-stepping at h = 2e-3, 2e-4 and 2e-5 over {HORIZON} s. A scene passes when every \
         step's contact problem is solved to a residual of 1e-12, the energy at the end is no more than at the \
         start, no leg sinks deeper than 1e-8 at the finest step, and the distance from the finest run shrinks \
         at least 0.3× from h = 2e-3 to 2e-4 — or, where that first decade does not (a coarsest step too \
         coarse for the scene's impacts; {escalated} scenes here), from h = 2e-4 to 2e-5 against a run at \
         h = 4e-6."
    ));
    page.table(
        &[
            "scenes",
            "failed",
            "worst residual",
            "worst energy gain",
            "deepest sinking [m]",
            "median distance ratio (2e-4 / 2e-3)",
        ],
        &[vec![
            count.to_string(),
            if failed.is_empty() {
                "0".to_string()
            } else {
                format!("{}: {}", failed.len(), failed.join("; "))
            },
            sci(worst(&|r| r.residual)),
            sci(worst(&|r| r.energy_gain)),
            sci(worst(&|r| r.sinking)),
            format!("{median:.3}"),
        ]],
    );
    summary.push(format!(
        "Spatial contacts' random suite (time-stepping, exact cone): {count} scenes, {} failed",
        failed.len()
    ));
}

/// One of MuJoCo's rows (`peers/mujoco_contacts.py`'s TSV): scene, setting, quantity,
/// value, closed form, seconds per simulated second.
struct MjRow {
    scene: String,
    setting: String,
    quantity: String,
    value: f64,
    cost: f64,
}

/// MuJoCo's traces: (trace, setting) → points.
type Traces = Vec<((String, String), Vec<(f64, f64)>)>;

fn read_mujoco(path: &std::path::Path) -> Option<(String, Vec<MjRow>, Traces)> {
    let text = std::fs::read_to_string(path).ok()?;
    let mut version = String::new();
    let mut rows = Vec::new();
    let mut traces: Traces = Vec::new();
    for line in text.lines() {
        if let Some(v) = line.strip_prefix("# ") {
            version = v.to_string();
            continue;
        }
        let f: Vec<&str> = line.split('\t').collect();
        if f.len() == 5 && f[0] == "trace" {
            let key = (f[1].to_string(), f[2].to_string());
            let point = (f[3].parse().ok()?, f[4].parse().ok()?);
            match traces.iter_mut().find(|(k, _)| *k == key) {
                Some((_, points)) => points.push(point),
                None => traces.push((key, vec![point])),
            }
        } else if f.len() == 6 {
            rows.push(MjRow {
                scene: f[0].to_string(),
                setting: f[1].to_string(),
                quantity: f[2].to_string(),
                value: f[3].parse().ok()?,
                cost: f[5].parse().ok()?,
            });
        }
    }
    Some((version, rows, traces))
}

/// Ours on MuJoCo's scenes, event-driven at the default tolerance: the same quantities
/// as `peers/mujoco_contacts.py` measures, with the run time per simulated second.
fn ours_on_mujoco_scenes(repeats: usize) -> Vec<(&'static str, &'static str, f64, f64, f64)> {
    let how = How::Event(1e-6);
    let mut out = Vec::new();
    // Creep below the friction angle, over 10 s.
    let below = SlidingBox {
        phi: 0.3,
        ..SlidingBox::default()
    };
    let q0 = resting(&below);
    let p = NonSmoothProblem::new(0.0, 10.0, q0, V3::zeros());
    let (t, sol) = timed(repeats, || run(&below, &p, how));
    if let Ok(sol) = sol {
        let moved = sol
            .rows()
            .map(|(_, y)| ((y[0] - q0[0]).powi(2) + (y[1] - q0[1]).powi(2)).sqrt())
            .fold(0.0, f64::max);
        out.push((
            "incline below its friction angle",
            "displacement in 10 s [m]",
            moved,
            0.0,
            t.median / 10.0,
        ));
    }
    // Launched at 2 m/s.
    let b = SlidingBox::default();
    let p = NonSmoothProblem::new(0.0, 1.0, resting(&b), V3::from([2.0, 0.0, 0.0]));
    let (t, sol) = timed(repeats, || run(&b, &p, how));
    if let Ok(sol) = sol {
        if let Some(stop) = stuck_at(&sol, 3) {
            out.push((
                "box sliding to rest",
                "stop time [s]",
                stop,
                2.0 / (b.mu * b.g),
                t.median,
            ));
        }
        let d = sol.last().expect("rows").1[0];
        out.push((
            "box sliding to rest",
            "distance [m]",
            d,
            4.0 / (2.0 * b.mu * b.g),
            t.median,
        ));
    }
    // The ball dropped from 0.2 m asking for e = 0.5, then at rest.
    let ball = SpinningBall::default();
    let p = NonSmoothProblem::new(0.0, 3.0, V3::from([0.0, ball.r + 0.2, 0.0]), V3::zeros());
    let (t, sol) = timed(repeats, || run(&ball, &p, how));
    if let Ok(sol) = sol {
        if let Some(first) = sol.switches.iter().find(|sw| sw.kind == SwitchKind::Impact) {
            out.push((
                "dropped ball",
                "restitution (e = 0.5 asked)",
                first.after[4] / -first.before[4],
                ball.e,
                t.median / 3.0,
            ));
        }
        // Over the last second, at rest.
        let heights: Vec<f64> = sol
            .rows()
            .filter(|(t, _)| *t >= 2.0)
            .map(|(_, y)| y[1])
            .collect();
        if !heights.is_empty() {
            let mean = heights.iter().sum::<f64>() / heights.len() as f64;
            let var =
                heights.iter().map(|h| (h - mean).powi(2)).sum::<f64>() / heights.len() as f64;
            out.push((
                "ball at rest",
                "penetration [m]",
                ball.r - mean,
                0.0,
                t.median / 3.0,
            ));
            out.push((
                "ball at rest",
                "height jitter (std) [m]",
                var.sqrt(),
                0.0,
                t.median / 3.0,
            ));
        }
    }
    out
}

fn mujoco_side_by_side(config: &Config, page: &mut Page, summary: &mut Vec<String>) {
    page.h3("Beside MuJoCo");
    let path = config.out_dir.join("peers").join("mujoco_contacts.tsv");
    let Some((version, mj, traces)) = read_mujoco(&path) else {
        page.para(
            "MuJoCo was not run in this report (`peers/run.sh` runs `peers/mujoco_contacts.py`; `--no-peers` skips it).",
        );
        return;
    };
    let ours = ours_on_mujoco_scenes(config.repeats);
    let find = |scene: &str, setting: &str, quantity: &str| {
        mj.iter()
            .find(|r| r.scene == scene && r.setting == setting && r.quantity == quantity)
    };
    let show = |x: f64| {
        if x == 0.0 {
            "0".to_string()
        } else if (1e-3..1e3).contains(&x.abs()) {
            format!("{x:.6}")
        } else {
            sci(x)
        }
    };
    let mut rows = Vec::new();
    for (scene, quantity, value, exact, cost) in &ours {
        let mj_cell = |setting: &str| match find(scene, setting, quantity) {
            Some(r) => (show(r.value), sci(r.cost)),
            None => ("—".to_string(), "—".to_string()),
        };
        let (d, dc) = mj_cell("default");
        let (st, sc) = mj_cell("stiff");
        rows.push(vec![
            format!("{scene}: {quantity}"),
            show(*exact),
            show(*value),
            sci(*cost),
            d,
            dc,
            st,
            sc,
        ]);
        if let (Some(dr), Some(sr)) = (
            find(scene, "default", quantity),
            find(scene, "stiff", quantity),
        ) {
            summary.push(format!(
                "Contacts beside MuJoCo, {scene}, {quantity}: closed form {}, ours {}, MuJoCo {} (default) and {} (stiffest)",
                show(*exact),
                show(*value),
                show(dr.value),
                show(sr.value)
            ));
        }
    }
    page.para(&format!(
        "{version} (`peers/mujoco_contacts.py`) on the same scenes in 3-D: the box 0.4 × 0.2 m (0.1 m deep), the ball \
         of radius 0.1 m, friction and restitution as ours. Default: MuJoCo's defaults (timestep 2 ms, solref 0.02 1, \
         pyramidal cone). Stiffest: timestep 0.2 ms, solref 0.0004 1, solimp 0.99 0.999 0.0001, elliptic cone, \
         impratio 10. Restitution is asked of MuJoCo through solref's negative (stiffness, damping) form, with the \
         damping that gives e = 0.5 for a linear spring-damper. Ours: event-driven DOPRI5 at the default rtol 1e-6. \
         Cost = run time per simulated second (one run for MuJoCo, stepped by `mj_step` from a Python loop whose \
         overhead is included; the median of repeated runs for ours)."
    ));
    page.table(
        &[
            "scene: quantity",
            "closed form",
            "ours",
            "ours [s / s]",
            "MuJoCo default",
            "[s / s]",
            "MuJoCo stiffest",
            "[s / s]",
        ],
        &rows,
    );
    plot_beside_mujoco(config, page, &traces);
}

/// Ours and MuJoCo's traces on the same axes: the box on the incline below its friction
/// angle, the box launched on level ground, the dropped ball.
fn plot_beside_mujoco(config: &Config, page: &mut Page, traces: &Traces) {
    let how = How::Event(1e-6);
    let grid =
        |t1: f64, n: usize| -> Vec<f64> { (0..=n).map(|i| t1 * i as f64 / n as f64).collect() };
    let theirs = |trace: &str, scale: f64| -> Vec<Series> {
        traces
            .iter()
            .filter(|((name, _), _)| name == trace)
            .map(|((_, setting), points)| {
                let label = if setting == "stiff" {
                    "MuJoCo, stiffest".to_string()
                } else {
                    format!("MuJoCo, {setting}")
                };
                Series::new(label, points.iter().map(|&(t, x)| (t, x * scale)).collect())
            })
            .collect()
    };
    // Each: the trace, our scene's run, the quantity from our row, the axis.
    let below = SlidingBox {
        phi: 0.3,
        ..SlidingBox::default()
    };
    let q0 = resting(&below);
    let ball = SpinningBall::default();
    let level = SlidingBox::default();
    let plots: [(&str, &str, &str, f64, Vec<(f64, f64)>); 3] = [
        (
            "incline",
            "Box on an incline below its friction angle",
            "displacement [mm]",
            1e3,
            run(
                &below,
                &NonSmoothProblem::new(0.0, 10.0, q0, V3::zeros()),
                how,
            )
            .ok()
            .and_then(|s| {
                let ts = grid(10.0, 500);
                s.sample(&ts).map(|ys| {
                    ts.iter()
                        .zip(ys)
                        .map(|(&t, y)| (t, 1e3 * (y[0] - q0[0]).hypot(y[1] - q0[1])))
                        .collect()
                })
            })
            .unwrap_or_default(),
        ),
        (
            "box",
            "Box launched at 2 m/s on level ground",
            "position [m]",
            1.0,
            run(
                &level,
                &NonSmoothProblem::new(0.0, 1.0, resting(&level), V3::from([2.0, 0.0, 0.0])),
                how,
            )
            .ok()
            .and_then(|s| {
                let ts = grid(1.0, 400);
                s.sample(&ts)
                    .map(|ys| ts.iter().zip(ys).map(|(&t, y)| (t, y[0])).collect())
            })
            .unwrap_or_default(),
        ),
        (
            "ball",
            "Ball dropped from 0.2 m, e = 0.5",
            "height above the ground [m]",
            1.0,
            run(
                &ball,
                &NonSmoothProblem::new(0.0, 1.5, V3::from([0.0, ball.r + 0.2, 0.0]), V3::zeros()),
                how,
            )
            .ok()
            .and_then(|s| {
                let ts = grid(1.5, 1500);
                s.sample(&ts).map(|ys| {
                    ts.iter()
                        .zip(ys)
                        .map(|(&t, y)| (t, y[1] - ball.r))
                        .collect()
                })
            })
            .unwrap_or_default(),
        ),
    ];
    for (trace, title, y_label, scale, ours) in plots {
        let mut series = vec![Series::new("ours (event-driven, rtol 1e-6)", ours)];
        series.extend(theirs(trace, scale));
        let file = format!("contacts_{trace}_mujoco.svg");
        line_plot(
            &config.out_dir.join(&file),
            title,
            "t [s]",
            y_label,
            &series,
            Scale::Linear,
            Scale::Linear,
        );
        page.image(title, &file);
    }
}
