//! The app soak (`STONESKIP_SOAK=N`, issue 14): N automatic throws one after another, each with
//! the next shipped preset (`assets/presets/*.ron`, in name order, cycling), played at the
//! clock's top speed. Per throw it records the resident memory after it (`VmRSS` of
//! `/proc/self/status`) and the median and largest frame time, and writes them as CSV when done
//! (`STONESKIP_SOAK_CSV`). A throw ends where the app would rest (the run over and the rings calm,
//! or [`super::model::REST_AFTER`] simulated seconds after the outcome) — or at its outcome with
//! `STONESKIP_SOAK_UNTIL=outcome` — or after [`MAX_THROW_FRAMES`] frames.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use anyhow::{anyhow, Context as _, Result};

/// Playback speed of the soak's throws: the panel's top speed (its slider clamps to 4×).
pub const SOAK_SPEED: f64 = 4.0;
/// A throw that has not come to rest after this many frames is cut short (and counted).
pub const MAX_THROW_FRAMES: usize = 5_000;

/// One finished throw.
#[derive(Debug, Clone, PartialEq)]
pub struct Row {
    pub throw: u64,
    pub preset: String,
    pub rss_mb: f64,
    pub frames: usize,
    /// Work per frame (panels, physics, drawing), ms.
    pub frame_median_ms: f64,
    pub frame_max_ms: f64,
    /// Real time between frames drawn back to back, ms.
    pub interval_median_ms: f64,
    pub interval_max_ms: f64,
    /// Simulated time of the throw, s.
    pub simulated_s: f64,
    pub outcome: String,
    /// Ended by [`MAX_THROW_FRAMES`], not by the rest rule.
    pub cut: bool,
}

/// The soak's progress.
#[derive(Debug)]
pub struct Soak {
    pub total: u64,
    presets: Vec<PathBuf>,
    csv: PathBuf,
    /// Throws started so far.
    pub started: u64,
    frame_ms: Vec<f64>,
    interval_ms: Vec<f64>,
    pub rows: Vec<Row>,
}

impl Soak {
    /// A soak of `total` throws through `presets`; refuses an empty list.
    pub fn new(total: u64, mut presets: Vec<PathBuf>, csv: PathBuf) -> Result<Self> {
        if presets.is_empty() {
            return Err(anyhow!(
                "STONESKIP_SOAK: no shipped presets found (assets/presets/*.ron)"
            ));
        }
        presets.sort();
        Ok(Self {
            total,
            presets,
            csv,
            started: 0,
            frame_ms: Vec::new(),
            interval_ms: Vec::new(),
            rows: Vec::new(),
        })
    }

    /// The preset of the next throw.
    pub fn next_preset(&mut self) -> PathBuf {
        let i = (self.started % self.presets.len() as u64) as usize;
        self.started += 1;
        self.presets[i].clone()
    }

    /// Records one frame of the running throw (ms); a zero interval (after a wait) is not one.
    pub fn frame(&mut self, frame_ms: f64, interval_ms: f64) {
        self.frame_ms.push(frame_ms);
        if interval_ms > 0.0 {
            self.interval_ms.push(interval_ms);
        }
    }

    /// Frames recorded for the running throw.
    pub fn frames(&self) -> usize {
        self.frame_ms.len()
    }

    /// Closes the running throw.
    pub fn finish_throw(&mut self, preset: &Path, simulated_s: f64, outcome: String, cut: bool) {
        let (fm, fx) = median_max(&mut self.frame_ms);
        let (im, ix) = median_max(&mut self.interval_ms);
        self.rows.push(Row {
            throw: self.rows.len() as u64 + 1,
            preset: preset
                .file_stem()
                .map_or_else(String::new, |s| s.to_string_lossy().into_owned()),
            rss_mb: resident_mb().unwrap_or(f64::NAN),
            frames: self.frame_ms.len(),
            frame_median_ms: fm,
            frame_max_ms: fx,
            interval_median_ms: im,
            interval_max_ms: ix,
            simulated_s,
            outcome,
            cut,
        });
        self.frame_ms.clear();
        self.interval_ms.clear();
    }

    pub fn done(&self) -> bool {
        self.rows.len() as u64 >= self.total
    }

    /// Writes the CSV; returns its path.
    pub fn write(&self) -> Result<PathBuf> {
        if let Some(dir) = self.csv.parent().filter(|d| !d.as_os_str().is_empty()) {
            std::fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))?;
        }
        std::fs::write(&self.csv, to_csv(&self.rows))
            .with_context(|| format!("writing {}", self.csv.display()))?;
        Ok(self.csv.clone())
    }

    pub fn csv(&self) -> &Path {
        &self.csv
    }

    /// One line for stderr at the end.
    pub fn summary(&self) -> String {
        let rss = |i: usize| self.rows.get(i).map_or(f64::NAN, |r| r.rss_mb);
        let worst = self.rows.iter().map(|r| r.frame_max_ms).fold(0.0, f64::max);
        let cut = self.rows.iter().filter(|r| r.cut).count();
        format!(
            "stoneskip soak: {} throws over {} presets; resident {:.1} MB after throw 1, {:.1} MB after throw {}, {:.1} MB after the last; worst frame {:.1} ms; {cut} cut short",
            self.rows.len(),
            self.presets.len(),
            rss(0),
            rss(49.min(self.rows.len().saturating_sub(1))),
            50.min(self.rows.len()),
            rss(self.rows.len().saturating_sub(1)),
            worst
        )
    }
}

/// The median and the largest value (NaN, NaN when empty); sorts `v`.
pub fn median_max(v: &mut [f64]) -> (f64, f64) {
    if v.is_empty() {
        return (f64::NAN, f64::NAN);
    }
    v.sort_by(f64::total_cmp);
    let n = v.len();
    let median = if n % 2 == 1 {
        v[n / 2]
    } else {
        0.5 * (v[n / 2 - 1] + v[n / 2])
    };
    (median, v[n - 1])
}

/// The CSV text of the rows, with a header.
pub fn to_csv(rows: &[Row]) -> String {
    let mut s = String::from(
        "throw,preset,rss_mb,frames,frame_median_ms,frame_max_ms,interval_median_ms,interval_max_ms,simulated_s,outcome,cut\n",
    );
    for r in rows {
        let _ = writeln!(
            s,
            "{},{},{:.2},{},{:.3},{:.3},{:.3},{:.3},{:.3},{},{}",
            r.throw,
            r.preset,
            r.rss_mb,
            r.frames,
            r.frame_median_ms,
            r.frame_max_ms,
            r.interval_median_ms,
            r.interval_max_ms,
            r.simulated_s,
            r.outcome.replace([',', '\n'], ";"),
            r.cut
        );
    }
    s
}

/// This process's resident memory (MB) from `/proc/self/status` (Linux); `None` elsewhere.
pub fn resident_mb() -> Option<f64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    parse_vm_rss(&status)
}

/// The `VmRSS:   1234 kB` line in MB.
fn parse_vm_rss(status: &str) -> Option<f64> {
    let line = status.lines().find(|l| l.starts_with("VmRSS:"))?;
    let kb: f64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb / 1024.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn median_and_max() {
        assert_eq!(median_max(&mut [3.0, 1.0, 2.0]), (2.0, 3.0));
        assert_eq!(median_max(&mut [4.0, 1.0, 2.0, 3.0]), (2.5, 4.0));
        assert!(median_max(&mut []).0.is_nan());
    }

    #[test]
    fn resident_memory_is_read() {
        assert_eq!(parse_vm_rss("Name:\tx\nVmRSS:\t  2048 kB\n"), Some(2.0));
        assert_eq!(parse_vm_rss("Name:\tx\n"), None);
        if cfg!(target_os = "linux") {
            // This test process holds at least its own code and the test harness.
            assert!(resident_mb().is_some_and(|m| m > 1.0 && m < 1.0e5));
        }
    }

    #[test]
    fn presets_cycle_and_rows_become_csv() {
        let dir = tempfile::tempdir().expect("temp dir");
        let csv = dir.path().join("sub").join("soak.csv");
        let mut s = Soak::new(
            3,
            vec![PathBuf::from("b.ron"), PathBuf::from("a.ron")],
            csv.clone(),
        )
        .expect("soak");
        let order: Vec<PathBuf> = (0..3).map(|_| s.next_preset()).collect();
        assert_eq!(
            order,
            ["a.ron", "b.ron", "a.ron"].map(PathBuf::from).to_vec()
        );
        for p in &order {
            s.frame(2.0, 0.0);
            s.frame(4.0, 16.0);
            s.frame(9.0, 20.0);
            s.finish_throw(p, 1.5, "sank, after 2 skips".into(), false);
        }
        assert!(s.done());
        let written = std::fs::read_to_string(s.write().expect("written")).expect("read");
        let lines: Vec<&str> = written.lines().collect();
        assert_eq!(lines.len(), 4);
        assert!(lines[1].starts_with("1,a,"), "{}", lines[1]);
        // Median 4 ms and max 9 ms of the work; the interval after a wait is left out.
        assert!(
            lines[1].contains(",3,4.000,9.000,18.000,20.000,1.500,sank; after 2 skips,false"),
            "{}",
            lines[1]
        );
        assert!(Soak::new(1, vec![], csv).is_err());
    }
}
