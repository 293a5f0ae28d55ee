//! Experiments: one launch value (speed, tilt, spin, height or mass) swept over a range, each
//! throw run headless ([`stoneskip_physics::sim::simulate`], the same calls as `stoneskip simulate`) with the
//! current physics, in the background on all cores but one (the view keeps its own), results
//! arriving as they finish. A class finds the magic angle or the minimal speed for itself
//! (Clanet et al. 2004's curves, drawn from its own throws). No window or GPU type here.

use std::path::Path;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc::{channel, Receiver};
use std::sync::Arc;
use std::time::Instant;

use anyhow::{Context as _, Result};
use rayon::prelude::*;

use stoneskip_physics::sim::params::Preset;

pub use crate::sweep::{Attitude, Knob, Plan, Point, Spec, MAX_SIDE, MAX_THROWS};

/// A sweep under way or done: its throws' presets, the results so far (in value order, `None`
/// until a throw finishes), the background work's receiver and its stop flag.
pub struct Experiment {
    /// The value swept (a map's first, along x).
    pub spec: Spec,
    /// A map's second value (along y), or `None`.
    pub second: Option<Spec>,
    /// The preset as loaded when the sweep started (its name is the charts'; the CSV's header
    /// lists what `base` changed from it).
    pub loaded: Preset,
    /// The settings the sweep varied one value of.
    pub base: Preset,
    pub presets: Vec<Preset>,
    pub points: Vec<Option<Point>>,
    receiver: Receiver<(usize, Point)>,
    stop: Arc<AtomicBool>,
    started: Instant,
    /// Wall seconds from the start to the last result.
    pub elapsed: f64,
}

impl Experiment {
    /// Starts the experiment `plan` (one value, or a map of two) on `base` (its physics, stone
    /// and water as they are now; `loaded`: the preset as loaded) in the background.
    pub fn start(base: &Preset, loaded: &Preset, plan: impl Into<Plan>) -> Self {
        let plan = plan.into();
        let presets = crate::sweep::presets(base, &plan);
        let (sender, receiver) = channel();
        let stop = Arc::new(AtomicBool::new(false));
        // The values as swept (the CSV's first columns, as `stoneskip sweep` writes them).
        let jobs: Vec<(usize, (f64, Option<f64>), Preset)> = plan
            .cells()
            .into_iter()
            .zip(&presets)
            .enumerate()
            .map(|(i, (c, p))| (i, c, p.clone()))
            .collect();
        let flag = stop.clone();
        // All cores but one: the app's own thread keeps drawing.
        let threads = std::thread::available_parallelism()
            .map_or(1, |n| n.get().saturating_sub(1))
            .max(1);
        std::thread::spawn(move || {
            let work = move || {
                jobs.into_par_iter().for_each_with(sender, |tx, (i, x, p)| {
                    if flag.load(Ordering::Relaxed) {
                        return;
                    }
                    let _ = tx.send((i, crate::sweep::throw(x, &p, &flag)));
                });
            };
            lower_priority();
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .start_handler(|_| lower_priority());
            match pool.build() {
                Ok(pool) => pool.install(work),
                Err(_) => work(),
            }
        });
        Self {
            points: vec![None; presets.len()],
            presets,
            spec: plan.x,
            second: plan.y,
            loaded: loaded.clone(),
            base: base.clone(),
            receiver,
            stop,
            started: Instant::now(),
            elapsed: 0.0,
        }
    }

    /// Takes the results that have arrived; true when any did.
    pub fn poll(&mut self) -> bool {
        let mut any = false;
        while let Ok((i, p)) = self.receiver.try_recv() {
            if let Some(slot) = self.points.get_mut(i) {
                *slot = Some(p);
                any = true;
            }
        }
        if any {
            self.elapsed = self.started.elapsed().as_secs_f64();
        }
        any
    }

    pub fn done(&self) -> usize {
        self.points.iter().filter(|p| p.is_some()).count()
    }

    pub fn finished(&self) -> bool {
        self.done() == self.points.len()
    }

    /// Stops the throws not yet started (and the ones running, at their next step).
    pub fn stop(&self) {
        self.stop.store(true, Ordering::Relaxed);
    }

    pub fn stopped(&self) -> bool {
        self.stop.load(Ordering::Relaxed)
    }

    /// What was thrown: the value, and a map's second.
    pub fn plan(&self) -> Plan {
        Plan {
            x: self.spec,
            y: self.second,
        }
    }

    /// Writes the finished throws as CSV ([`crate::sweep::write_csv`], the table
    /// `stoneskip sweep` writes).
    pub fn write_csv(&self, path: &Path) -> Result<()> {
        let points: Vec<Point> = self.points.iter().flatten().cloned().collect();
        let mut f = super::files::create_file(path)?;
        crate::sweep::write_csv(&mut f, &self.loaded, &self.base, &self.plan(), &points)
            .with_context(|| format!("writing {}", path.display()))
    }
}

impl Drop for Experiment {
    fn drop(&mut self) {
        self.stop();
    }
}

/// Puts the calling thread at the lowest CPU priority (nice 19), so the throws run on what the
/// view leaves: on Linux a thread is its own task, and `setpriority(PRIO_PROCESS, 0, …)` sets the
/// calling one's. Elsewhere the throws keep the default priority.
pub(crate) fn lower_priority() {
    #[cfg(target_os = "linux")]
    // SAFETY: setpriority reads no memory of ours; a failure leaves the priority as it was.
    unsafe {
        libc::setpriority(libc::PRIO_PROCESS, 0, 19);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn shipped(name: &str) -> Preset {
        stoneskip_physics::preset::shipped(name).unwrap().unwrap()
    }

    #[test]
    fn values_span_the_range_with_both_ends() {
        let s = Spec {
            knob: Knob::Tilt,
            from: 0.0,
            to: 45.0,
            count: 10,
        };
        let v = s.values();
        assert_eq!(v.len(), 10);
        assert_eq!((v[0], v[9]), (0.0, 45.0));
        // Outside the panels' range, non-finite, too few or too many: clamped, never NaN.
        let wild = Spec {
            knob: Knob::Speed,
            from: f64::NAN,
            to: 1e308,
            count: 100_000,
        };
        let v = wild.values();
        assert_eq!(v.len(), MAX_THROWS);
        assert_eq!((v[0], v[v.len() - 1]), Knob::Speed.range());
        assert_eq!(Spec { count: 0, ..s }.values().len(), 2);
    }

    #[test]
    fn each_knob_sets_what_it_reads() {
        let p = shipped("default");
        for k in Knob::ALL {
            let (lo, hi) = k.range();
            let x = lo + 0.37 * (hi - lo);
            let q = k.set(&p, x);
            assert!((k.get(&q) - x).abs() < 1e-9 * (1.0 + x.abs()), "{k:?}");
            q.validate().unwrap();
            // The other knobs keep their values (to rounding: a speed is a velocity's length),
            // but an impact angle launches at the water, at the touch's height.
            for other in Knob::ALL.into_iter().filter(|o| *o != k) {
                if (k, other) == (Knob::ImpactAngle, Knob::Height) {
                    continue;
                }
                let (a, b) = (other.get(&q), other.get(&p));
                assert!(
                    (a - b).abs() <= 1e-12 * (1.0 + b.abs()),
                    "{k:?} moved {other:?}"
                );
            }
        }
    }

    /// Every result equals the headless run of its own preset, bit for bit, whatever order the
    /// threads finish in.
    #[test]
    fn a_sweep_gives_the_headless_results() {
        let base = shipped("magic_angle");
        let spec = Spec {
            knob: Knob::Tilt,
            from: 10.0,
            to: 40.0,
            count: 4,
        };
        let mut e = Experiment::start(&base, &base, spec);
        let t0 = Instant::now();
        while !e.finished() && t0.elapsed().as_secs() < 120 {
            e.poll();
            std::thread::sleep(std::time::Duration::from_millis(5));
        }
        assert!(e.finished());
        for (p, point) in e.presets.iter().zip(&e.points) {
            let point = point.as_ref().unwrap();
            let s = stoneskip_physics::sim::simulate(p).unwrap();
            assert_eq!((point.skips, point.distance), (s.skips, s.distance));
            assert_eq!(point.value, p.launch.attitude.tilt_deg);
        }
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("tilt.csv");
        e.write_csv(&path).unwrap();
        let text = std::fs::read_to_string(&path).unwrap();
        let rows: Vec<&str> = text.lines().filter(|l| !l.starts_with('#')).collect();
        assert_eq!(
            rows[0],
            "tilt_deg,skips,distance_m,ending,result,force_evals,first_tilt_deg,first_bank_deg,\
             last_tilt_deg,last_bank_deg"
        );
        assert_eq!(rows.len(), 5);
    }

    #[test]
    fn a_stopped_sweep_ends_early() {
        let base = shipped("record_throw");
        let e = Experiment::start(&base, &base, Spec::suggested(Knob::Speed));
        e.stop();
        assert!(e.stopped());
    }
}
