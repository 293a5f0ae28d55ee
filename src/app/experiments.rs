//! Experiments: one launch value (speed, tilt, spin, height or mass) swept over a range, each
//! throw run headless ([`crate::sim::simulate`], the same calls as `stoneskip simulate`) with the
//! current physics, in the background on all cores but one (the view keeps its own), results
//! arriving as they finish. A class finds the magic angle or the minimal speed for itself
//! (Clanet et al. 2004's curves, drawn from its own throws). No window or GPU type here.

use std::io::Write as _;
use std::path::Path;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc::{channel, Receiver};
use std::sync::Arc;
use std::time::Instant;

use anyhow::{Context as _, Result};
use rayon::prelude::*;

use crate::sim::params::Preset;
use crate::sim::Outcome;

const TAU: f64 = std::f64::consts::TAU;

/// The most throws one experiment runs.
pub const MAX_THROWS: usize = 200;

/// The launch value an experiment varies, in the units the panels show.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Knob {
    /// m/s, along the launch direction.
    Speed,
    /// Degrees: the attack angle (the magic angle is near 20°).
    Tilt,
    /// rev/s about the stone's axis.
    Spin,
    /// m: the launch height above the water.
    Height,
    /// kg.
    Mass,
}

impl Knob {
    pub const ALL: [Knob; 5] = [
        Knob::Speed,
        Knob::Tilt,
        Knob::Spin,
        Knob::Height,
        Knob::Mass,
    ];

    pub fn name(self) -> &'static str {
        match self {
            Knob::Speed => "Speed",
            Knob::Tilt => "Tilt",
            Knob::Spin => "Spin",
            Knob::Height => "Height",
            Knob::Mass => "Mass",
        }
    }

    pub fn unit(self) -> &'static str {
        match self {
            Knob::Speed => "m/s",
            Knob::Tilt => "°",
            Knob::Spin => "rev/s",
            Knob::Height => "m",
            Knob::Mass => "kg",
        }
    }

    /// The panels' range for this value (inside `Preset::validate`'s).
    pub fn range(self) -> (f64, f64) {
        use crate::ui::ranges;
        let r = match self {
            Knob::Speed => ranges::SPEED,
            Knob::Tilt => ranges::TILT,
            Knob::Spin => ranges::SPIN,
            Knob::Height => ranges::HEIGHT,
            Knob::Mass => ranges::MASS,
        };
        (*r.start(), *r.end())
    }

    /// A range worth sweeping first: around the magic angle, the minimal speed, …
    pub fn suggested(self) -> (f64, f64) {
        match self {
            Knob::Speed => (1.0, 15.0),
            Knob::Tilt => (0.0, 45.0),
            Knob::Spin => (0.0, 30.0),
            Knob::Height => (0.05, 1.5),
            Knob::Mass => (0.02, 0.5),
        }
    }

    /// The value in `p`, in the panels' units.
    pub fn get(self, p: &Preset) -> f64 {
        let v = p.launch.velocity;
        match self {
            Knob::Speed => (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt(),
            Knob::Tilt => p.launch.attitude.tilt_deg,
            Knob::Spin => p.launch.spin / TAU,
            Knob::Height => p.launch.position[2],
            Knob::Mass => p.stone.mass,
        }
    }

    /// `p` with this value set to `value` (clamped to [`Knob::range`]); a speed keeps the launch
    /// direction (straight ahead when the preset's speed is zero).
    pub fn set(self, p: &Preset, value: f64) -> Preset {
        let (lo, hi) = self.range();
        let x = value.clamp(lo, hi);
        let mut q = p.clone();
        match self {
            Knob::Speed => {
                let v = glam::DVec3::from_array(q.launch.velocity);
                let dir = v.try_normalize().unwrap_or(glam::DVec3::X);
                q.launch.velocity = (dir * x).to_array();
            }
            Knob::Tilt => q.launch.attitude.tilt_deg = x,
            Knob::Spin => q.launch.spin = x * TAU,
            Knob::Height => q.launch.position[2] = x,
            Knob::Mass => q.stone.mass = x,
        }
        q
    }
}

/// What to sweep: `knob` from `from` to `to` in `count` evenly spaced throws.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Spec {
    pub knob: Knob,
    pub from: f64,
    pub to: f64,
    pub count: usize,
}

impl Spec {
    /// The suggested sweep of `knob`, 24 throws.
    pub fn suggested(knob: Knob) -> Self {
        let (from, to) = knob.suggested();
        Self {
            knob,
            from,
            to,
            count: 24,
        }
    }

    /// The values thrown, in order (ends included; clamped to the knob's range; 2 to
    /// [`MAX_THROWS`] of them).
    pub fn values(&self) -> Vec<f64> {
        let (lo, hi) = self.knob.range();
        let clean = |x: f64, d: f64| if x.is_finite() { x.clamp(lo, hi) } else { d };
        let (a, b) = (clean(self.from, lo), clean(self.to, hi));
        let n = self.count.clamp(2, MAX_THROWS);
        (0..n)
            .map(|i| a + (b - a) * i as f64 / (n - 1) as f64)
            .collect()
    }
}

/// One throw's result.
#[derive(Debug, Clone, PartialEq)]
pub struct Point {
    pub value: f64,
    pub skips: usize,
    /// m, along the ground from the launch point to where it ended.
    pub distance: f64,
    /// In words ("sank", "left the lake", …), or why the throw could not start.
    pub outcome: String,
    /// Force evaluations it took (what it cost).
    pub force_evals: u64,
}

/// A sweep under way or done: its throws' presets, the results so far (in value order, `None`
/// until a throw finishes), the background work's receiver and its stop flag.
pub struct Experiment {
    pub spec: Spec,
    pub presets: Vec<Preset>,
    pub points: Vec<Option<Point>>,
    receiver: Receiver<(usize, Point)>,
    stop: Arc<AtomicBool>,
    started: Instant,
    /// Wall seconds from the start to the last result.
    pub elapsed: f64,
}

impl Experiment {
    /// Starts the sweep of `spec` on `base` (its physics, stone and water as they are now) in
    /// the background.
    pub fn start(base: &Preset, spec: Spec) -> Self {
        let presets: Vec<Preset> = spec
            .values()
            .into_iter()
            .map(|x| spec.knob.set(base, x))
            .collect();
        let (sender, receiver) = channel();
        let stop = Arc::new(AtomicBool::new(false));
        let jobs: Vec<(usize, f64, Preset)> = presets
            .iter()
            .enumerate()
            .map(|(i, p)| (i, spec.knob.get(p), p.clone()))
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
                    let _ = tx.send((i, throw(x, &p, &flag)));
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
            spec,
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

    /// Writes the finished throws as CSV, with comment lines naming the sweep and the units.
    pub fn write_csv(&self, path: &Path, preset_name: &str) -> Result<()> {
        let k = self.spec.knob;
        let mut text = format!(
            "# stoneskip experiment on the preset \"{}\"\n",
            preset_name.replace(['\n', '"'], " ")
        );
        text.push_str(&format!(
            "# {} from {} to {} {} in {} throws, the rest of the preset as it was; distance in m \
             along the ground from the launch point\n",
            k.name(),
            self.spec.from,
            self.spec.to,
            k.unit(),
            self.points.len()
        ));
        text.push_str(&format!(
            "{}_{},skips,distance_m,outcome,force_evals\n",
            k.name().to_lowercase(),
            unit_tag(k)
        ));
        for p in self.points.iter().flatten() {
            text.push_str(&format!(
                "{},{},{:.4},{},{}\n",
                p.value,
                p.skips,
                p.distance,
                p.outcome.replace(',', ";"),
                p.force_evals
            ));
        }
        let mut f = super::files::create_file(path)?;
        f.write_all(text.as_bytes())
            .and_then(|()| f.flush())
            .with_context(|| format!("writing {}", path.display()))
    }
}

impl Drop for Experiment {
    fn drop(&mut self) {
        self.stop();
    }
}

fn unit_tag(k: Knob) -> &'static str {
    match k {
        Knob::Speed => "m_s",
        Knob::Tilt => "deg",
        Knob::Spin => "rev_s",
        Knob::Height => "m",
        Knob::Mass => "kg",
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

/// One headless throw (the water left at rest, as `simulate` does), stopped early by `stop`.
fn throw(value: f64, p: &Preset, stop: &AtomicBool) -> Point {
    let mut sim = match crate::sim::Simulation::new(p) {
        Ok(s) => s,
        Err(e) => {
            return Point {
                value,
                skips: 0,
                distance: 0.0,
                outcome: format!("not thrown: {e}"),
                force_evals: 0,
            }
        }
    };
    sim.skip_unread_water();
    let s = sim.run(&mut |_| {}, &|| stop.load(Ordering::Relaxed));
    Point {
        value,
        skips: s.skips,
        distance: s.distance,
        outcome: s.outcome.map_or("stopped", Outcome::words).to_owned(),
        force_evals: s.force_evals,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn shipped(name: &str) -> Preset {
        crate::preset::shipped(name).unwrap().unwrap()
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
            // The other knobs keep their values.
            for other in Knob::ALL.into_iter().filter(|o| *o != k) {
                assert_eq!(other.get(&q), other.get(&p), "{k:?} moved {other:?}");
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
        let mut e = Experiment::start(&base, spec);
        let t0 = Instant::now();
        while !e.finished() && t0.elapsed().as_secs() < 120 {
            e.poll();
            std::thread::sleep(std::time::Duration::from_millis(5));
        }
        assert!(e.finished());
        for (p, point) in e.presets.iter().zip(&e.points) {
            let point = point.as_ref().unwrap();
            let s = crate::sim::simulate(p).unwrap();
            assert_eq!((point.skips, point.distance), (s.skips, s.distance));
            assert_eq!(point.value, p.launch.attitude.tilt_deg);
        }
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("tilt.csv");
        e.write_csv(&path, "magic").unwrap();
        let text = std::fs::read_to_string(&path).unwrap();
        let rows: Vec<&str> = text.lines().filter(|l| !l.starts_with('#')).collect();
        assert_eq!(rows[0], "tilt_deg,skips,distance_m,outcome,force_evals");
        assert_eq!(rows.len(), 5);
    }

    #[test]
    fn a_stopped_sweep_ends_early() {
        let base = shipped("record_throw");
        let e = Experiment::start(&base, Spec::suggested(Knob::Speed));
        e.stop();
        assert!(e.stopped());
    }
}
