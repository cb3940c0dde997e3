//! What the report runs: default, `--long` or `--tiny`; `--no-compile` skips the
//! compile-time measurements, `--no-peers` the diffsol peer package, and
//! `--only KEY[,KEY…]` runs only the named sections ([`SECTIONS`]).

use std::path::PathBuf;

use indicatif::{ProgressBar, ProgressStyle};

/// The sections' keys for `--only`, in the report's order.
pub const SECTIONS: [&str; 18] = [
    "smooth",
    "nonsmooth",
    "dense",
    "agreement",
    "s9",
    "lie",
    "loops",
    "contacts",
    "kernels",
    "expansion",
    "compile",
    "scaling",
    "chains",
    "urdf",
    "ops",
    "scalars",
    "ensembles",
    "flags",
];

pub struct Config {
    pub name: &'static str,
    /// The sections to run (`None`: all); the peers' comparison runs with `kernels`.
    pub only: Option<Vec<String>>,
    /// Timed repetitions per measurement (after one warm-up).
    pub repeats: usize,
    /// Tolerances of the adaptive sweeps.
    pub tolerances: Vec<f64>,
    /// Steps of the RK4 sweeps (as fractions of the horizon: h = horizon / steps).
    pub rk4_steps: Vec<usize>,
    /// Integration horizon scale (1 = the scenes' horizons).
    pub horizon: f64,
    /// Calls per kernel timing batch.
    pub kernel_calls: usize,
    /// Measure release compile time of each scene (builds temporary crates).
    pub compile: bool,
    /// Build and run the diffsol peer package (`peers/diffsol`, its own target directory;
    /// minutes the first time); off with `--no-peers` and on the tiny configuration.
    pub peers: bool,
    pub show_progress: bool,
    pub out_dir: PathBuf,
}

impl Config {
    pub fn default_run() -> Config {
        Config {
            name: "default",
            only: None,
            repeats: 5,
            tolerances: vec![1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-10],
            rk4_steps: vec![100, 200, 400, 800, 1600, 3200, 6400],
            horizon: 1.0,
            kernel_calls: 20_000,
            compile: true,
            peers: true,
            show_progress: true,
            out_dir: PathBuf::from(env!("CARGO_MANIFEST_DIR"))
                .join("target")
                .join("report"),
        }
    }

    pub fn long() -> Config {
        Config {
            name: "long",
            repeats: 11,
            tolerances: vec![
                1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-10, 1e-11, 1e-12,
            ],
            rk4_steps: vec![100, 200, 400, 800, 1600, 3200, 6400, 12800, 25600],
            kernel_calls: 200_000,
            ..Config::default_run()
        }
    }

    /// Every code path, tiny sizes: what the tests run.
    pub fn tiny(out_dir: PathBuf) -> Config {
        Config {
            name: "tiny",
            only: None,
            repeats: 1,
            tolerances: vec![1e-4, 1e-6],
            rk4_steps: vec![50, 100],
            horizon: 0.1,
            kernel_calls: 10,
            compile: false,
            peers: false,
            show_progress: false,
            out_dir,
        }
    }

    pub fn from_args(mut args: impl Iterator<Item = String>) -> Config {
        let mut config = Config::default_run();
        let (mut no_compile, mut no_peers) = (false, false);
        let mut only: Option<Vec<String>> = None;
        while let Some(a) = args.next() {
            match a.as_str() {
                "--only" => {
                    let keys: Vec<String> = args
                        .next()
                        .unwrap_or_default()
                        .split(',')
                        .map(|k| k.trim().to_string())
                        .filter(|k| !k.is_empty())
                        .collect();
                    if let Some(bad) = keys.iter().find(|k| !SECTIONS.contains(&k.as_str())) {
                        eprintln!(
                            "unknown section `{bad}` after --only; the sections are {}",
                            SECTIONS.join(", ")
                        );
                        std::process::exit(2);
                    }
                    if keys.is_empty() {
                        eprintln!(
                            "--only needs sections, e.g. `--only dense,s9`; the sections are {}",
                            SECTIONS.join(", ")
                        );
                        std::process::exit(2);
                    }
                    only = Some(keys);
                }
                "--long" => config = Config::long(),
                "--tiny" => config = Config::tiny(config.out_dir.clone()),
                "--no-compile" => no_compile = true,
                "--no-peers" => no_peers = true,
                other => {
                    eprintln!(
                        "unknown argument `{other}`; use --long, --tiny, --no-compile, --no-peers or --only SECTION[,SECTION…]"
                    );
                    std::process::exit(2);
                }
            }
        }
        // The switches apply whatever their order relative to --long / --tiny.
        config.only = only;
        config.compile &= !no_compile;
        config.peers &= !no_peers;
        config
    }

    /// Whether the section `key` (one of [`SECTIONS`]) runs.
    pub fn runs(&self, key: &str) -> bool {
        self.only
            .as_ref()
            .is_none_or(|keys| keys.iter().any(|k| k == key))
    }

    pub fn progress(&self, sections: u64) -> ProgressBar {
        if !self.show_progress {
            return ProgressBar::hidden();
        }
        let bar = ProgressBar::new(sections);
        bar.set_style(
            ProgressStyle::with_template(
                "{spinner} [{elapsed_precise}] {bar:30} {pos}/{len} sections — {msg}",
            )
            .expect("template"),
        );
        bar.enable_steady_tick(std::time::Duration::from_millis(200));
        bar
    }
}
