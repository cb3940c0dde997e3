//! Medians of repeated timings, after a warm-up.

use std::time::Instant;

/// Median wall time in seconds of `f` over `repeats` runs after one warm-up run; also
/// returns the last result.
pub fn median<T>(repeats: usize, mut f: impl FnMut() -> T) -> (f64, T) {
    let mut out = f();
    let mut times = Vec::with_capacity(repeats);
    for _ in 0..repeats.max(1) {
        let t = Instant::now();
        out = f();
        times.push(t.elapsed().as_secs_f64());
    }
    times.sort_by(f64::total_cmp);
    (times[times.len() / 2], out)
}

/// Median ns per call of `f` over batches of `calls` calls.
pub fn ns_per_call<T>(repeats: usize, calls: usize, mut f: impl FnMut() -> T) -> f64 {
    let calls = calls.max(1);
    let (t, _) = median(repeats, || {
        for _ in 0..calls {
            std::hint::black_box(f());
        }
    });
    t * 1e9 / calls as f64
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
