//! Sweeps (issue 48): one launch value (speed, tilt, spin, height or mass) varied over a range,
//! each throw run headless ([`throw`]: the same calls as `stoneskip simulate`) with the rest of
//! the preset as it is, and the table written as CSV ([`write_csv`]). The app's Experiments panel
//! (in the background, results as they arrive) and `stoneskip sweep` (on every core) share these
//! functions, so the two give the same rows byte for byte. No window or GPU type here.

use std::io::Write;
use std::sync::atomic::{AtomicBool, Ordering};

use anyhow::{Context as _, Result};
use rayon::prelude::*;

use crate::sim::params::Preset;

const TAU: f64 = std::f64::consts::TAU;

/// The launch and stone sliders' ranges, in the panels' units; the Experiments panel sweeps
/// within the same ones ([`Knob::range`]); `ui::ranges` is this module.
pub mod ranges {
    use std::ops::RangeInclusive;
    /// m/s
    pub const SPEED: RangeInclusive<f64> = 0.5..=40.0;
    /// degrees
    pub const TILT: RangeInclusive<f64> = -45.0..=75.0;
    /// rev/s: Clanet et al. (2004) spun their disc at 65 rev/s; the model's high-spin limit
    /// shows above 100, so a class can go past it.
    pub const SPIN: RangeInclusive<f64> = -150.0..=150.0;
    /// m, the launch height
    pub const HEIGHT: RangeInclusive<f64> = 0.0..=5.0;
    /// kg
    pub const MASS: RangeInclusive<f64> = 0.005..=3.0;
}

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

    /// Throws over [`Knob::suggested`]: a round step (1 m/s … 0.5 m/s, 1°, 1 rev/s, 5 cm, 20 g).
    pub fn suggested_count(self) -> usize {
        match self {
            Knob::Speed => 29,  // 1 to 15 m/s by 0.5
            Knob::Tilt => 46,   // 0 to 45° by 1
            Knob::Spin => 31,   // 0 to 30 rev/s by 1
            Knob::Height => 30, // 0.05 to 1.5 m by 0.05
            Knob::Mass => 25,   // 0.02 to 0.5 kg by 0.02
        }
    }

    /// The knob named `name` (its name or unit tag, any case: "tilt", "Speed").
    pub fn parse(name: &str) -> Option<Knob> {
        let n = name.trim().to_lowercase();
        Knob::ALL.into_iter().find(|k| k.name().to_lowercase() == n)
    }

    /// The CSV column's unit tag ("deg", "m_s").
    pub fn unit_tag(self) -> &'static str {
        unit_tag(self)
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
    /// The suggested sweep of `knob`, in round steps (0–45° in 46 throws: every degree).
    pub fn suggested(knob: Knob) -> Self {
        let (from, to) = knob.suggested();
        Self {
            knob,
            from,
            to,
            count: knob.suggested_count(),
        }
    }

    /// The values thrown, in order (ends included; clamped to the knob's range; 2 to
    /// [`MAX_THROWS`] of them).
    pub fn values(&self) -> Vec<f64> {
        let (lo, hi) = self.knob.range();
        let clean = |x: f64, d: f64| if x.is_finite() { x.clamp(lo, hi) } else { d };
        let (a, b) = (clean(self.from, lo), clean(self.to, hi));
        let n = self.count.clamp(2, MAX_THROWS);
        // Rounded to 10⁻⁹ of the unit, so a step of 0.25 gives 6.25, not 6.249999999999999.
        (0..n)
            .map(|i| ((a + (b - a) * i as f64 / (n - 1) as f64) * 1e9).round() / 1e9)
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
    /// Why it ended in words ([`crate::sim::ending()`]: "too slow to skip", "dug in nose-down at
    /// touch 3 (tilt -1.1°)", …), or why the throw could not start.
    pub outcome: String,
    /// Whether the numbers are the throw's result, not a bound of the simulation's (the lake's
    /// edge under wavy contact, the time limit, a failed run): charted hollow, out of the trend.
    pub result: bool,
    /// Force evaluations it took (what it cost).
    pub force_evals: u64,
}

/// The presets a sweep throws, in value order: `base` with the knob set to each value.
pub fn presets(base: &Preset, spec: &Spec) -> Vec<Preset> {
    spec.values()
        .into_iter()
        .map(|x| spec.knob.set(base, x))
        .collect()
}

/// Throws the whole sweep on rayon's pool (every core), in value order; `stop` ends it early
/// (throws not run are left out).
pub fn run(base: &Preset, spec: &Spec, stop: &AtomicBool) -> Vec<Point> {
    let jobs: Vec<(f64, Preset)> = spec.values().into_iter().zip(presets(base, spec)).collect();
    // Each point keeps the value as swept (7, not the 6.999999999999999 a speed reads back
    // from its velocity).
    let points: Vec<Option<Point>> = jobs
        .par_iter()
        .map(|(x, p)| (!stop.load(Ordering::Relaxed)).then(|| throw(*x, p, stop)))
        .collect();
    points.into_iter().flatten().collect()
}

/// One headless throw (the water left at rest, as `simulate` does), stopped early by `stop`.
pub fn throw(value: f64, p: &Preset, stop: &AtomicBool) -> Point {
    let mut sim = match crate::sim::Simulation::new(p) {
        Ok(s) => s,
        Err(e) => {
            return Point {
                value,
                skips: 0,
                distance: 0.0,
                outcome: format!("not thrown: {e}"),
                result: false,
                force_evals: 0,
            }
        }
    };
    sim.skip_unread_water();
    let s = sim.run(&mut |_| {}, &|| stop.load(Ordering::Relaxed));
    let end = crate::sim::ending(&s);
    Point {
        value,
        skips: s.skips,
        distance: s.distance,
        outcome: end.words(),
        result: end.is_result(),
        force_evals: s.force_evals,
    }
}

/// The values of `base` that differ from `loaded` (the preset as loaded), one line each:
/// "launch.velocity = [6.0,0.0,-0.5] (the preset: [13.5,0.0,-1.0])", over the launch, the stone,
/// the physics and the water.
pub fn differences(loaded: &Preset, base: &Preset) -> Vec<String> {
    fn walk(path: &str, a: &serde_json::Value, b: &serde_json::Value, out: &mut Vec<String>) {
        match (a, b) {
            (serde_json::Value::Object(x), serde_json::Value::Object(y)) => {
                for (k, vb) in y {
                    let p = format!("{path}.{k}");
                    match x.get(k) {
                        Some(va) => walk(&p, va, vb, out),
                        None => out.push(format!("{p} = {vb}")),
                    }
                }
            }
            _ if a != b => out.push(format!("{path} = {b} (the preset: {a})")),
            _ => {}
        }
    }
    let json = |p: &Preset| {
        serde_json::json!({
            "launch": p.launch,
            "stone": p.stone,
            "physics": p.physics,
            "water": p.water,
        })
    };
    let mut out = Vec::new();
    if let (serde_json::Value::Object(a), serde_json::Value::Object(b)) = (json(loaded), json(base))
    {
        for section in ["launch", "stone", "physics", "water"] {
            if let (Some(x), Some(y)) = (a.get(section), b.get(section)) {
                walk(section, x, y, &mut out);
            }
        }
    }
    out
}

/// Writes the sweep's table as CSV: comment lines (`#`) naming the preset, the sweep and every
/// value of `base` that differs from `loaded`, then a header row and one row per throw (value,
/// skips, distance to the millimetre, the ending in words, whether it is a result, the force
/// evaluations), through the `csv` crate (quoting as needed).
pub fn write_csv<W: Write>(
    mut out: W,
    loaded: &Preset,
    base: &Preset,
    spec: &Spec,
    points: &[Point],
) -> Result<()> {
    let k = spec.knob;
    let values = spec.values();
    let (from, to) = (values.first().copied(), values.last().copied());
    let mut head = format!(
        "# stoneskip sweep of the preset \"{}\"\n",
        base.name.replace(['\n', '\r', '"'], " ")
    );
    head.push_str(&format!(
        "# {} from {} to {} {} in {} throws; distance in m along the ground from the launch point; \
         result no: ended by a bound of the simulation (the lake's edge under wavy contact, the \
         time limit), not by the throw\n",
        k.name().to_lowercase(),
        from.unwrap_or(spec.from),
        to.unwrap_or(spec.to),
        k.unit(),
        values.len()
    ));
    let diffs = differences(loaded, base);
    if diffs.is_empty() {
        head.push_str("# every other value as in the preset\n");
    }
    for d in diffs {
        head.push_str(&format!(
            "# changed from the preset: {}\n",
            d.replace('\n', " ")
        ));
    }
    out.write_all(head.as_bytes()).context("writing the CSV")?;
    let mut w = csv::Writer::from_writer(&mut out);
    let column = format!("{}_{}", k.name().to_lowercase(), k.unit_tag());
    w.write_record([
        column.as_str(),
        "skips",
        "distance_m",
        "ending",
        "result",
        "force_evals",
    ])
    .context("writing the CSV")?;
    for p in points {
        w.write_record([
            format!("{}", p.value),
            p.skips.to_string(),
            format!("{:.3}", p.distance),
            p.outcome.clone(),
            if p.result { "yes" } else { "no" }.to_owned(),
            p.force_evals.to_string(),
        ])
        .context("writing the CSV")?;
    }
    w.flush().context("writing the CSV")?;
    drop(w);
    out.flush().context("writing the CSV")
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

#[cfg(test)]
mod tests {
    use super::*;

    fn shipped(name: &str) -> Preset {
        crate::preset::shipped(name).unwrap().unwrap()
    }

    /// Issue 48, finding 5: the suggested sweeps step by round numbers (0–45° in 46 throws, not
    /// 24 throws by 1.957°), and a quarter step is written 6.25, not 6.249999999999999.
    #[test]
    fn suggested_sweeps_step_by_round_numbers() {
        for k in Knob::ALL {
            let v = Spec::suggested(k).values();
            let step = v[1] - v[0];
            let mantissa = step / 10f64.powf(step.log10().floor());
            assert!(
                [1.0, 2.0, 5.0].iter().any(|m| (mantissa - m).abs() < 1e-9),
                "{k:?} steps by {step}"
            );
        }
        assert_eq!(Spec::suggested(Knob::Tilt).values().len(), 46);
        let quarter = Spec {
            knob: Knob::Speed,
            from: 1.0,
            to: 11.0,
            count: 41,
        };
        assert!(quarter.values().iter().any(|x| format!("{x}") == "6.25"));
        assert!(quarter.values().iter().all(|x| format!("{x}").len() <= 5));
    }

    /// The CSV's header names the preset and every value that differs from it (a speed set in
    /// the Launch panel), and its numbers are rounded.
    #[test]
    fn the_csv_records_the_preset_and_what_differs() {
        let loaded = shipped("magic_angle");
        let mut base = loaded.clone();
        base.launch.velocity = [6.0, 0.0, -0.5];
        base.physics.gravity = 1.62;
        let d = differences(&loaded, &base);
        assert_eq!(d.len(), 2, "{d:?}");
        assert!(
            d[0].starts_with("launch.velocity = [6.0,0.0,-0.5]"),
            "{d:?}"
        );
        assert!(
            d[1].starts_with("physics.gravity = 1.62 (the preset: 9.81)"),
            "{d:?}"
        );
        assert!(differences(&loaded, &loaded).is_empty());
        let spec = Spec {
            knob: Knob::Mass,
            from: 0.1,
            to: 0.2,
            count: 2,
        };
        let points = vec![Point {
            value: 0.1,
            skips: 3,
            distance: 12.345_678,
            outcome: "landed on its edge at touch 4 (bank 26°, over 20°)".into(),
            result: true,
            force_evals: 99,
        }];
        let mut out = Vec::new();
        write_csv(&mut out, &loaded, &base, &spec, &points).unwrap();
        let text = String::from_utf8(out).unwrap();
        assert!(text.starts_with("# stoneskip sweep of the preset \"Magic angle\"\n"));
        assert!(text.contains("# changed from the preset: launch.velocity"));
        assert!(text.contains("# changed from the preset: physics.gravity"));
        let rows: Vec<&str> = text.lines().filter(|l| !l.starts_with('#')).collect();
        assert_eq!(
            rows[0],
            "mass_kg,skips,distance_m,ending,result,force_evals"
        );
        // The ending's comma is quoted by the writer, not replaced.
        assert_eq!(
            rows[1],
            "0.1,3,12.346,\"landed on its edge at touch 4 (bank 26°, over 20°)\",yes,99"
        );
    }

    /// Issue 48, finding 1: where wavy contact makes the lake's edge end a throw, the sweep
    /// marks it as no result (the panel draws it hollow, out of the line); on the ambient water
    /// the same throw flies on and is a result.
    #[test]
    fn a_throw_stopped_by_the_lake_edge_is_no_result() {
        let mut p = shipped("default");
        p.water.size = [3.0, 2.0];
        p.water.origin = Some([-1.0, -1.0]);
        p.water.cell = 0.05;
        let stop = AtomicBool::new(false);
        let ambient = throw(13.5, &p, &stop);
        assert!(ambient.result, "{}", ambient.outcome);
        p.water.wavy_contact = true;
        let wavy = throw(13.5, &p, &stop);
        assert!(!wavy.result, "{}", wavy.outcome);
        assert!(
            wavy.outcome.starts_with("left the lake"),
            "{}",
            wavy.outcome
        );
    }
}
