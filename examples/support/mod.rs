//! Shared by the examples: where plots go, and a small line-plot helper over plotters'
//! SVG backend (no system fonts or C libraries needed).
#![allow(dead_code)]

use std::path::PathBuf;

use plotters::prelude::*;

/// `target/plots/<name>.svg`, creating the folder.
pub fn plot_path(name: &str) -> PathBuf {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("target")
        .join("plots");
    std::fs::create_dir_all(&dir).expect("create target/plots");
    dir.join(format!("{name}.svg"))
}

/// One curve: a legend label and its points.
pub struct Series {
    pub label: String,
    pub points: Vec<(f64, f64)>,
}

impl Series {
    pub fn new(label: impl Into<String>, points: Vec<(f64, f64)>) -> Self {
        Series {
            label: label.into(),
            points,
        }
    }
}

/// Axis scaling.
#[derive(Clone, Copy, PartialEq)]
pub enum Scale {
    Linear,
    Log,
}

/// Writes a line plot of `series` to `path`; log axes drop non-positive values.
pub fn line_plot(
    path: &PathBuf,
    title: &str,
    x_label: &str,
    y_label: &str,
    series: &[Series],
    xs: Scale,
    ys: Scale,
) {
    let keep = |v: f64, s: Scale| v.is_finite() && (s == Scale::Linear || v > 0.0);
    let pts: Vec<Vec<(f64, f64)>> = series
        .iter()
        .map(|s| {
            s.points
                .iter()
                .copied()
                .filter(|&(x, y)| keep(x, xs) && keep(y, ys))
                .collect()
        })
        .collect();
    let all: Vec<(f64, f64)> = pts.iter().flatten().copied().collect();
    if all.is_empty() {
        return;
    }
    let (mut x0, mut x1, mut y0, mut y1) = (f64::MAX, f64::MIN, f64::MAX, f64::MIN);
    for &(x, y) in &all {
        x0 = x0.min(x);
        x1 = x1.max(x);
        y0 = y0.min(y);
        y1 = y1.max(y);
    }
    let pad = |a: f64, b: f64, s: Scale| match s {
        Scale::Log => (a / 2.0, b * 2.0),
        Scale::Linear => {
            let d = (b - a).abs().max(1e-12) * 0.05;
            (a - d, b + d)
        }
    };
    let (x0, x1) = pad(x0, x1, xs);
    let (y0, y1) = pad(y0, y1, ys);
    let legend_corner = legend_corner(&all, (x0, x1, xs), (y0, y1, ys), series.len());
    let root = SVGBackend::new(path, (900, 560)).into_drawing_area();
    root.fill(&WHITE).expect("fill");
    macro_rules! body {
        ($chart:expr) => {{
            let mut chart = $chart;
            chart
                .configure_mesh()
                .x_desc(x_label)
                .y_desc(y_label)
                .x_label_formatter(&|v: &f64| tick(*v))
                .y_label_formatter(&|v: &f64| tick(*v))
                .draw()
                .expect("mesh");
            for (i, (s, p)) in series.iter().zip(&pts).enumerate() {
                let color = Palette99::pick(i).to_rgba();
                chart
                    .draw_series(LineSeries::new(p.iter().copied(), color.stroke_width(2)))
                    .expect("series")
                    .label(s.label.clone())
                    .legend(move |(x, y)| {
                        PathElement::new(vec![(x, y), (x + 18, y)], color.stroke_width(2))
                    });
            }
            chart
                .configure_series_labels()
                .position(legend_corner)
                .background_style(WHITE.mix(0.85))
                .border_style(BLACK)
                .draw()
                .expect("legend");
        }};
    }
    let mut builder = ChartBuilder::on(&root);
    builder
        .caption(title, ("sans-serif", 22))
        .margin(12)
        .x_label_area_size(45)
        .y_label_area_size(70);
    match (xs, ys) {
        (Scale::Linear, Scale::Linear) => {
            body!(builder.build_cartesian_2d(x0..x1, y0..y1).expect("axes"))
        }
        (Scale::Log, Scale::Log) => {
            body!(
                builder
                    .build_cartesian_2d((x0..x1).log_scale(), (y0..y1).log_scale())
                    .expect("axes")
            )
        }
        (Scale::Linear, Scale::Log) => body!(
            builder
                .build_cartesian_2d(x0..x1, (y0..y1).log_scale())
                .expect("axes")
        ),
        (Scale::Log, Scale::Linear) => body!(
            builder
                .build_cartesian_2d((x0..x1).log_scale(), y0..y1)
                .expect("axes")
        ),
    }
    root.present().expect("write plot");
}

/// The corner where the legend hides the fewest points: the legend box is taken as
/// 40 % of the width and 6 % of the height per series (in the axes' own scale).
fn legend_corner(
    points: &[(f64, f64)],
    (x0, x1, xs): (f64, f64, Scale),
    (y0, y1, ys): (f64, f64, Scale),
    n: usize,
) -> SeriesLabelPosition {
    let unit = |v: f64, a: f64, b: f64, s: Scale| match s {
        Scale::Linear => (v - a) / (b - a),
        Scale::Log => (v.ln() - a.ln()) / (b.ln() - a.ln()),
    };
    let (w, h) = (0.4, (0.06 * n as f64 + 0.04).min(0.9));
    let corners = [
        (SeriesLabelPosition::UpperRight, true, true),
        (SeriesLabelPosition::UpperLeft, false, true),
        (SeriesLabelPosition::LowerRight, true, false),
        (SeriesLabelPosition::LowerLeft, false, false),
    ];
    let hidden = |right: bool, upper: bool| {
        points
            .iter()
            .filter(|&&(x, y)| {
                let (u, v) = (unit(x, x0, x1, xs), unit(y, y0, y1, ys));
                (if right { u >= 1.0 - w } else { u <= w })
                    && (if upper { v >= 1.0 - h } else { v <= h })
            })
            .count()
    };
    corners
        .into_iter()
        .min_by_key(|&(_, r, u)| hidden(r, u))
        .map(|(p, _, _)| p)
        .unwrap_or(SeriesLabelPosition::UpperRight)
}

/// A short tick label that tells neighbouring ticks apart: `1e-6` rather than
/// `9.999999999999999e-7`, `1.5e4` beside `2e4` (not both `2e4`).
fn tick(v: f64) -> String {
    if v == 0.0 {
        "0".into()
    } else if v.abs() < 1e-2 || v.abs() >= 1e4 {
        let s = format!("{v:.2e}");
        match s.split_once('e') {
            Some((m, e)) => {
                let m = if m.contains('.') {
                    m.trim_end_matches('0').trim_end_matches('.')
                } else {
                    m
                };
                format!("{m}e{e}")
            }
            None => s,
        }
    } else {
        let s = format!("{v:.3}");
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    }
}

/// One series per label: component `j` of the trajectory against time, labelled
/// `labels[j]`.
pub fn time_series(traj: &filippov::runtime::Solution, labels: &[&str]) -> Vec<Series> {
    labels
        .iter()
        .enumerate()
        .map(|(j, l)| {
            Series::new(
                *l,
                traj.times()
                    .iter()
                    .copied()
                    .zip(traj.component(j))
                    .collect(),
            )
        })
        .collect()
}

/// A linear plot against time `t [s]`, written to `target/plots/<name>.svg` and announced.
pub fn plot_over_time(name: &str, title: &str, y_label: &str, series: &[Series]) {
    let path = plot_path(name);
    line_plot(
        &path,
        title,
        "t [s]",
        y_label,
        series,
        Scale::Linear,
        Scale::Linear,
    );
    println!("wrote {}", path.display());
}
