//! Building a throwaway release crate, as a user's `cargo build --release` does, for the
//! sections that time builds or run the binaries they build (compile times, scaling,
//! CPU flags).

use std::path::Path;
use std::process::Command;
use std::time::Instant;

/// `cargo build --release` of the crate in `dir` into `target`; the wall time in
/// seconds, or cargo's error output. `rustflags`: `None` leaves the environment's flags
/// as they are; `Some(flags)` builds with exactly those (`""`: the default target).
pub fn release_build(dir: &Path, target: &Path, rustflags: Option<&str>) -> Result<f64, String> {
    let start = Instant::now();
    let mut cmd = Command::new(env!("CARGO"));
    cmd.args(["build", "--release", "--quiet"])
        .current_dir(dir)
        .env("CARGO_TARGET_DIR", target);
    if let Some(flags) = rustflags {
        cmd.env("RUSTFLAGS", flags)
            .env_remove("CARGO_ENCODED_RUSTFLAGS");
    }
    match cmd.output() {
        Ok(o) if o.status.success() => Ok(start.elapsed().as_secs_f64()),
        Ok(o) => Err(String::from_utf8_lossy(&o.stderr)
            .chars()
            .take(2000)
            .collect()),
        Err(e) => Err(format!("could not start cargo: {e}")),
    }
}

/// [`release_build`] with the environment's flags; a failure is reported on standard
/// error and gives `None`.
pub fn timed_build(dir: &Path, target: &Path) -> Option<f64> {
    release_build(dir, target, None)
        .map_err(|e| eprintln!("report: building {} failed:\n{e}", dir.display()))
        .ok()
}
