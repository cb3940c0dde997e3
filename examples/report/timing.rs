//! Medians of repeated timings, after a warm-up, with their spread; the machine and its
//! load.
//!
//! Every timing taken through [`timed`] (and so [`ns_timed`]) is also
//! recorded, so that the report can say how much the repetitions of this run spread
//! ([`spread_note`]): on a shared machine that is the honest error bar of every time.

use std::sync::Mutex;
use std::time::Instant;

/// The median of repeated runs and the fastest and slowest of them.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Timing {
    pub median: f64,
    pub min: f64,
    pub max: f64,
}

impl Timing {
    /// `(max − min) / median`.
    pub fn spread(&self) -> f64 {
        (self.max - self.min) / self.median
    }

    /// Scaled by `k` (units).
    pub fn scaled(&self, k: f64) -> Timing {
        Timing {
            median: self.median * k,
            min: self.min * k,
            max: self.max * k,
        }
    }

    /// How many times `self` takes as long as `fast`, `r× (lo–hi)` with `digits` decimals;
    /// the range pairs the fastest repetition of one with the slowest of the other.
    pub fn ratio_to(&self, fast: &Timing, digits: usize) -> String {
        format!(
            "{:.d$}× ({:.d$}–{:.d$})",
            self.median / fast.median,
            self.min / fast.max,
            self.max / fast.min,
            d = digits
        )
    }

    /// `median (min–max)` with `digits` decimals, in the timing's units.
    pub fn show(&self, digits: usize) -> String {
        format!(
            "{:.d$} ({:.d$}–{:.d$})",
            self.median,
            self.min,
            self.max,
            d = digits
        )
    }
}

/// Relative spreads of every timing of this run.
static SPREADS: Mutex<Vec<f64>> = Mutex::new(Vec::new());

/// Wall time in seconds of `f` over `repeats` runs after one warm-up run (median, min,
/// max); also returns the last result.
pub fn timed<T>(repeats: usize, mut f: impl FnMut() -> T) -> (Timing, T) {
    let mut out = f();
    let mut times = Vec::with_capacity(repeats);
    for _ in 0..repeats.max(1) {
        let t = Instant::now();
        out = f();
        times.push(t.elapsed().as_secs_f64());
    }
    times.sort_by(f64::total_cmp);
    let timing = Timing {
        median: times[times.len() / 2],
        min: times[0],
        max: times[times.len() - 1],
    };
    if times.len() >= 3 && timing.median > 0.0 {
        SPREADS
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .push(timing.spread());
    }
    (timing, out)
}

/// ns per call of `f` over batches of `calls` calls: median, min and max over batches.
///
/// Each result is kept where `f` returns it and only its address goes through
/// `black_box` (the compiler must still assume all of it is read). Passed by value, a
/// result is first copied into `black_box`'s argument: for a 36 × 36 mass matrix that
/// copy of 10 KB is a cost of the harness, not of the kernel (Pinocchio's timings
/// beside ours write into their `Data` in place).
pub fn ns_timed<T>(repeats: usize, calls: usize, mut f: impl FnMut() -> T) -> Timing {
    let calls = calls.max(1);
    let (t, _) = timed(repeats, || {
        for _ in 0..calls {
            let r = f();
            std::hint::black_box(&r);
        }
    });
    t.scaled(1e9 / calls as f64)
}

/// Timings of several programs taken in `rounds` interleaved rounds: round `r` runs
/// every job once, starting from job `r` (so none is always first), and each job returns
/// its own timing (or `None` when it cannot run). A change of the shared machine's load
/// during the rounds reaches every job alike, so ratios between the results are
/// meaningful. Each job's result: the median of its rounds' medians, with the fastest and
/// slowest repetition over all rounds.
pub fn in_rounds(
    rounds: usize,
    jobs: &mut [&mut dyn FnMut() -> Option<Timing>],
) -> Vec<Option<Timing>> {
    let n = jobs.len();
    let mut got: Vec<Vec<Timing>> = vec![Vec::new(); n];
    let mut failed = vec![false; n];
    for round in 0..rounds.max(1) {
        for k in 0..n {
            let j = (round + k) % n;
            if failed[j] {
                continue;
            }
            match jobs[j]() {
                Some(t) => got[j].push(t),
                None => failed[j] = true,
            }
        }
    }
    got.into_iter()
        .zip(failed)
        .map(|(ts, failed)| (!failed && !ts.is_empty()).then(|| combine(&ts)))
        .collect()
}

/// The median of the timings' medians, the fastest minimum and the slowest maximum.
pub fn combine(ts: &[Timing]) -> Timing {
    let mut m: Vec<f64> = ts.iter().map(|t| t.median).collect();
    m.sort_by(f64::total_cmp);
    Timing {
        median: m[m.len() / 2],
        min: ts.iter().map(|t| t.min).fold(f64::INFINITY, f64::min),
        max: ts.iter().map(|t| t.max).fold(f64::NEG_INFINITY, f64::max),
    }
}

/// Runs `program` with `args` and reads the timing `KEY median min max` (or `KEY median`
/// with a `KEY_range min max` line) from its output; `None`, with a message on standard
/// error, when it fails.
pub fn program_timing(
    program: &std::path::Path,
    args: &[&std::ffi::OsStr],
    key: &str,
) -> Option<Timing> {
    let out = match std::process::Command::new(program).args(args).output() {
        Ok(out) if out.status.success() => out,
        Ok(out) => {
            eprintln!(
                "report: {} failed: {}",
                program.display(),
                String::from_utf8_lossy(&out.stderr)
            );
            return None;
        }
        Err(e) => {
            eprintln!("report: cannot run {}: {e}", program.display());
            return None;
        }
    };
    let text = String::from_utf8_lossy(&out.stdout);
    let field = |k: &str| -> Option<Vec<f64>> {
        text.lines().find_map(|l| {
            let mut w = l.split_whitespace();
            (w.next()? == k).then(|| w.filter_map(|x| x.parse().ok()).collect())
        })
    };
    let v = field(key)?;
    let (min, max) = match (v.get(1), v.get(2)) {
        (Some(&a), Some(&b)) => (a, b),
        _ => {
            let r = field(&format!("{key}_range"))?;
            (*r.first()?, *r.get(1)?)
        }
    };
    Some(Timing {
        median: *v.first()?,
        min,
        max,
    })
}

/// How much the repetitions of this run's timings spread: `(max − min) / median` over
/// every timing with at least three repetitions.
pub fn spread_note() -> String {
    let mut s = SPREADS.lock().unwrap_or_else(|e| e.into_inner()).clone();
    if s.is_empty() {
        return "No timing of this run had three or more repetitions.".into();
    }
    s.sort_by(f64::total_cmp);
    let q = |p: f64| s[((s.len() - 1) as f64 * p).round() as usize] * 100.0;
    format!(
        "Spread of the repetitions, (max − min)/median over the {} timings of this run: median {:.0} %, 90th percentile {:.0} %, largest {:.0} %. \
         A ratio between two times differs from 1 meaningfully only beyond that.",
        s.len(),
        q(0.5),
        q(0.9),
        q(1.0)
    )
}

/// The 1-, 5- and 15-minute load averages (Linux), or `None`.
pub fn load() -> Option<String> {
    let s = std::fs::read_to_string("/proc/loadavg").ok()?;
    let v: Vec<&str> = s.split_whitespace().take(3).collect();
    (v.len() == 3).then(|| format!("{} / {} / {}", v[0], v[1], v[2]))
}

/// A short description of the machine.
pub fn machine() -> String {
    let cores = std::thread::available_parallelism()
        .map(|n| n.get())
        .unwrap_or(1);
    let cpu = std::fs::read_to_string("/proc/cpuinfo")
        .ok()
        .and_then(|s| {
            s.lines()
                .find(|l| l.starts_with("model name"))
                .map(|l| l.split(':').nth(1).unwrap_or("").trim().to_string())
        })
        .unwrap_or_else(|| "unknown CPU".into());
    format!("{cores} cores, {cpu}")
}
