//! What every study shares: the error type, Ctrl-C cancellation, the output folder and its
//! progress clock ([`Ctx`], atomic writes), the grids (`logspace`, `linspace_step`), the relative
//! error and the ordered parallel map the sweeps run on. The dispatcher is `mod.rs`.

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Once;
use std::time::Instant;

use stoneskip_physics::sim::params::ParamError;
use stoneskip_physics::sim::SimError;
use stoneskip_reference::ReferenceError;

use super::table;

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
pub(super) fn install_ctrlc() {
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

/// Writes `dir/file` atomically: a temporary file beside it, then a rename.
pub(super) fn write_atomic(dir: &Path, file: &str, text: &str) -> Result<(), StudyError> {
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

/// `f` over `items` on rayon's pool, in order; the first error wins.
pub fn par_map<T: Send, R: Send>(
    items: Vec<T>,
    f: impl Fn(T) -> Result<R, StudyError> + Sync + Send,
) -> Result<Vec<R>, StudyError> {
    use rayon::prelude::*;
    items.into_par_iter().map(f).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn spacings() {
        let v = logspace(1e-4, 1e-2, 3);
        assert!((v[1] - 1e-3).abs() < 1e-15);
        assert_eq!(linspace_step(0.0, 1.0, 0.25).len(), 5);
    }
}
