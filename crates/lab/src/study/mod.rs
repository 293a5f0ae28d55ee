//! Speed-versus-accuracy studies (design.md §8, issue 5): work-precision charts — error against a
//! converged reference versus cost, after Hairer, Nørsett & Wanner, *Solving ODEs I* §II.10 — for
//! the integrators, the mesh and the water grid; stability limits where methods fail (the contact
//! oscillator of physics.md §1.3 and §7.4, the water's Courant limit of water.md §3, the paper's
//! eq. 41 clamp, Heron's formula on slivers); the skipping phase diagram of Clanet, Hersen &
//! Bocquet (Nature 2004) and Rosellini et al. (JFM 2005); and the cheapest settings under 1 % error.
//!
//! Each study writes CSV data, PNG charts and a Markdown `README.md` into its output folder. This
//! module is an edge of the program: it reads the wall clock (`std::time::Instant`) for the
//! wall-time cost axis; the deterministic cost is the simulation's force-evaluation count.

pub mod accuracy;
pub mod attitude;
pub mod defaults;
pub mod fidelity;
pub mod first_bounce;
pub mod phase;
pub mod plot;
pub mod spin;
pub mod stability;
pub mod style;
pub mod table;
pub mod throws;
pub mod whole_throw;

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Once;
use std::time::Instant;

use stoneskip_physics::sim::params::ParamError;
use stoneskip_physics::sim::SimError;
use stoneskip_reference::ReferenceError;

/// The studies `run_study` knows, in the order `all` runs them.
pub const STUDIES: [&str; 8] = [
    "accuracy",
    "stability",
    "phase",
    "defaults",
    "fidelity",
    "whole_throw",
    "first_bounce",
    "attitude",
];

/// Errors of the studies.
#[derive(Debug, thiserror::Error)]
pub enum StudyError {
    #[error(
        "unknown study `{0}`; valid names: accuracy, stability, phase, defaults, fidelity, whole_throw, first_bounce, spin, attitude, all"
    )]
    Unknown(String),
    #[error(transparent)]
    Sim(#[from] SimError),
    #[error(transparent)]
    Param(#[from] ParamError),
    #[error(transparent)]
    Reference(#[from] ReferenceError),
    #[error("{path}: {source}")]
    Io {
        path: PathBuf,
        source: std::io::Error,
    },
    #[error("drawing {path}: {message}")]
    Plot { path: PathBuf, message: String },
    #[error("interrupted (Ctrl-C)")]
    Interrupted,
    #[error("{0}")]
    Failed(String),
}

static CANCEL: AtomicBool = AtomicBool::new(false);

/// Installs a Ctrl-C handler (once per process) that makes the studies stop at the next run.
fn install_ctrlc() {
    static ONCE: Once = Once::new();
    ONCE.call_once(|| {
        // Failing to install the handler (another one exists) only loses the clean stop.
        let _ = ctrlc::set_handler(|| CANCEL.store(true, Ordering::SeqCst));
    });
}

/// `Err(Interrupted)` once Ctrl-C was pressed.
pub fn check_cancel() -> Result<(), StudyError> {
    if CANCEL.load(Ordering::SeqCst) {
        Err(StudyError::Interrupted)
    } else {
        Ok(())
    }
}

/// Where a study writes, whether it is the quick version, and its progress clock.
#[derive(Debug, Clone)]
pub struct Ctx {
    pub out: PathBuf,
    pub quick: bool,
    pub name: &'static str,
    started: Instant,
}

impl Ctx {
    pub fn new(name: &'static str, out: &Path, quick: bool) -> Result<Self, StudyError> {
        std::fs::create_dir_all(out).map_err(|source| StudyError::Io {
            path: out.to_path_buf(),
            source,
        })?;
        Ok(Self {
            out: out.to_path_buf(),
            quick,
            name,
            started: Instant::now(),
        })
    }

    /// Path of an output file.
    pub fn path(&self, file: &str) -> PathBuf {
        self.out.join(file)
    }

    /// Prints a progress line on stderr.
    pub fn progress(&self, msg: &str) {
        eprintln!(
            "[{} {:6.1} s] {msg}",
            self.name,
            self.started.elapsed().as_secs_f64()
        );
    }

    /// Seconds since the study started.
    pub fn elapsed(&self) -> f64 {
        self.started.elapsed().as_secs_f64()
    }

    /// Writes a text file atomically (temporary file, then rename).
    pub fn write(&self, file: &str, text: &str) -> Result<(), StudyError> {
        write_atomic(&self.out, file, text)
    }

    /// Writes a CSV table.
    pub fn write_csv(&self, file: &str, csv: &table::Csv) -> Result<(), StudyError> {
        self.write(file, &csv.render())
    }
}

/// Runs study `name` ("accuracy", "stability", "phase", "defaults", "fidelity", "whole_throw",
/// "first_bounce", "spin", "attitude" or "all") into `out`; `quick`
/// takes coarse grids (CI). With "all", each study writes into its own subfolder of `out`.
pub fn run_study(name: &str, out: &Path, quick: bool) -> anyhow::Result<()> {
    install_ctrlc();
    plot::ensure_font()?;
    let started = Instant::now();
    match name {
        "all" => {
            let mut index = Vec::new();
            for n in STUDIES {
                let dir = out.join(n);
                let secs = run_one(n, &dir, quick)?;
                index.push((n, secs));
            }
            for (n, s) in index {
                eprintln!("stoneskip study: {n} took {s:.1} s");
            }
        }
        other => {
            run_one(other, out, quick)?;
        }
    }
    eprintln!(
        "stoneskip study {name}: done in {:.1} s, output in {}",
        started.elapsed().as_secs_f64(),
        out.display()
    );
    Ok(())
}

/// Runs one named study; returns its wall time (s).
fn run_one(name: &str, out: &Path, quick: bool) -> Result<f64, StudyError> {
    let started = Instant::now();
    match name {
        "accuracy" => accuracy::run(&Ctx::new("accuracy", out, quick)?)?,
        "stability" => stability::run(&Ctx::new("stability", out, quick)?)?,
        "phase" => phase::run(&Ctx::new("phase", out, quick)?)?,
        "defaults" => defaults::run(&Ctx::new("defaults", out, quick)?)?,
        "fidelity" => fidelity::run(&Ctx::new("fidelity", out, quick)?)?,
        "whole_throw" => whole_throw::run_study(&Ctx::new("whole_throw", out, quick)?)?,
        "first_bounce" => first_bounce::run_study(&Ctx::new("first_bounce", out, quick)?)?,
        "attitude" => attitude::run(&Ctx::new("attitude", out, quick)?)?,
        // The phase study's spin axis alone (`phase` runs it too).
        "spin" => {
            let ctx = Ctx::new("spin", out, quick)?;
            let section = spin::run(&ctx)?;
            ctx.write(
                "README.md",
                &format!("# Spin study (the phase study's spin axis)\n\n{section}"),
            )?;
        }
        other => return Err(StudyError::Unknown(other.to_owned())),
    }
    if !plot::CHARTS {
        note_no_charts(out)?;
    }
    Ok(started.elapsed().as_secs_f64())
}

/// Says at the top of a study's report that its charts were not drawn (a build without the
/// `charts` feature), so the images it links to are missing.
fn note_no_charts(out: &Path) -> Result<(), StudyError> {
    let path = out.join("README.md");
    let text = std::fs::read_to_string(&path).map_err(|source| StudyError::Io {
        path: path.clone(),
        source,
    })?;
    let note = "> Charts not drawn: this stoneskip was built without the `charts` feature, so the \
                PNG images this report links to are missing; the CSV files hold the data.\n\n";
    write_atomic(out, "README.md", &format!("{note}{text}"))
}

/// Writes `dir/file` atomically: a temporary file beside it, then a rename.
fn write_atomic(dir: &Path, file: &str, text: &str) -> Result<(), StudyError> {
    let path = dir.join(file);
    let tmp = dir.join(format!(".{file}.tmp"));
    let io = |source| StudyError::Io {
        path: path.clone(),
        source,
    };
    std::fs::write(&tmp, text).map_err(io)?;
    std::fs::rename(&tmp, &path).map_err(io)
}

/// The relative difference |a − b| / |b| (|b| floored at 1e-300, so never NaN for finite input).
pub fn rel_err(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs().max(1e-300)
}

/// `n` values from `lo` to `hi` evenly spaced on a log scale.
pub fn logspace(lo: f64, hi: f64, n: usize) -> Vec<f64> {
    if n < 2 || lo <= 0.0 || hi <= 0.0 {
        return vec![lo];
    }
    let (a, b) = (lo.ln(), hi.ln());
    (0..n)
        .map(|i| match i {
            0 => lo,
            i if i == n - 1 => hi,
            i => (a + (b - a) * i as f64 / (n - 1) as f64).exp(),
        })
        .collect()
}

/// `lo`, `lo + step`, … up to `hi` (inclusive within rounding).
pub fn linspace_step(lo: f64, hi: f64, step: f64) -> Vec<f64> {
    if step.is_nan() || step <= 0.0 || hi < lo {
        return vec![lo];
    }
    let n = ((hi - lo) / step + 1e-9).floor() as usize;
    (0..=n).map(|i| lo + step * i as f64).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn unknown_study_lists_the_names() {
        let dir = std::env::temp_dir().join("stoneskip-unknown-study");
        let e = run_study("nope", &dir, true).unwrap_err().to_string();
        assert!(
            e.contains("nope")
                && e.contains(
                    "accuracy, stability, phase, defaults, fidelity, whole_throw, first_bounce, spin, attitude, all"
                ),
            "{e}"
        );
    }

    #[test]
    fn spacings() {
        let v = logspace(1e-4, 1e-2, 3);
        assert!((v[1] - 1e-3).abs() < 1e-15);
        assert_eq!(linspace_step(0.0, 1.0, 0.25).len(), 5);
    }
}
