//! Sweeps (issue 48): one launch value (speed, tilt, spin, height or mass) varied over a range,
//! each throw run headless ([`throw`]: the same calls as `stoneskip simulate`) with the rest of
//! the preset as it is, and the table written as CSV ([`write_csv`]). The app's Experiments panel
//! (in the background, results as they arrive) and `stoneskip sweep` (on every core) share these
//! functions, so the two give the same rows byte for byte. No window or GPU type here.

use std::io::Write;
use std::sync::atomic::{AtomicBool, Ordering};

use anyhow::{Context as _, Result};
use rayon::prelude::*;

use stoneskip_physics::sim::params::Preset;

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
    /// degrees below the horizontal at the first touch: Clanet et al. (2004) measured no bounce
    /// above about 45°; their phase diagram spans 0°–80°.
    pub const IMPACT_ANGLE: RangeInclusive<f64> = 1.0..=80.0;
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
    /// Degrees: the impact angle β, the velocity's descent below the horizontal when the stone
    /// first touches the water (Clanet et al. 2004's β). Setting it launches the throw at the
    /// water ([`launch_at_touch`]), so the first touch comes in at exactly this angle.
    ImpactAngle,
}

impl Knob {
    pub const ALL: [Knob; 6] = [
        Knob::Speed,
        Knob::Tilt,
        Knob::ImpactAngle,
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
            Knob::ImpactAngle => "Impact angle",
        }
    }

    pub fn unit(self) -> &'static str {
        match self {
            Knob::Speed => "m/s",
            Knob::Tilt => "°",
            Knob::Spin => "rev/s",
            Knob::Height => "m",
            Knob::Mass => "kg",
            Knob::ImpactAngle => "°",
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
            Knob::ImpactAngle => ranges::IMPACT_ANGLE,
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
            Knob::ImpactAngle => (2.0, 60.0),
        }
    }

    /// Throws over [`Knob::suggested`]: a round step (1 m/s … 0.5 m/s, 1°, 1 rev/s, 5 cm, 20 g).
    pub fn suggested_count(self) -> usize {
        match self {
            Knob::Speed => 29,       // 1 to 15 m/s by 0.5
            Knob::Tilt => 46,        // 0 to 45° by 1
            Knob::Spin => 31,        // 0 to 30 rev/s by 1
            Knob::Height => 30,      // 0.05 to 1.5 m by 0.05
            Knob::Mass => 25,        // 0.02 to 0.5 kg by 0.02
            Knob::ImpactAngle => 30, // 2 to 60° by 2
        }
    }

    /// The knob named `name` (its name, any case, a space or `_` or `-` between words:
    /// "tilt", "Speed", "impact_angle").
    pub fn parse(name: &str) -> Option<Knob> {
        let n = name.trim().to_lowercase().replace(['_', '-'], " ");
        Knob::ALL.into_iter().find(|k| k.name().to_lowercase() == n)
    }

    /// The name in a CSV column or on the command line: "impact_angle".
    pub fn snake(self) -> String {
        self.name().to_lowercase().replace(' ', "_")
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
            // The launch's descent: the first touch's when the launch is at the water, as
            // `set` makes it.
            Knob::ImpactAngle => (-v[2]).atan2(v[0].hypot(v[1])).to_degrees(),
        }
    }

    /// `p` with this value set to `value` (clamped to [`Knob::range`]); a speed keeps the launch
    /// direction (straight ahead when the preset's speed is zero); an impact angle keeps the
    /// speed and the heading and moves the launch to the water ([`launch_at_touch`]: the height
    /// is then the touch's, so set the tilt or the stone before it, never the height after).
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
            Knob::ImpactAngle => launch_at_touch(&mut q, x.to_radians()),
        }
        q
    }
}

/// The gap (m) between the stone's lowest point and the water at an impact-angle launch
/// ([`launch_at_touch`]): the literature's state at impact (design.md §8).
pub const TOUCH_GAP: f64 = stoneskip_physics::sim::scenario::IMPACT_CLEARANCE;

/// Makes `p`'s launch a throw at impact: the velocity keeps its speed and horizontal heading and
/// comes down at `beta` (rad) below the horizontal, and the stone, in its launch attitude, is
/// lowered until its lowest point is [`TOUCH_GAP`] above the still water (x and y unchanged).
///
/// Why at the water and not a launch aimed from the hand's height: from a height h a stone
/// arrives at least atan(√(2gh)/U) steep (11° from 30 cm at 12 m/s), so a map of impact angles
/// would leave its shallow rows out; and with the air on, the flight is no parabola, so an aimed
/// launch would need a root solve per cell that holds to its tolerance only. At the water the
/// descent changes only while the lowest point falls the gap: in t ≤ gap/(U sin β) gravity and
/// the air (less than gravity while the stone still falls) change it by less than
/// 2g·gap/(U² sin β) rad — under 10⁻³° at 1 m/s and 5°. The lowest point is the one the
/// simulation tests (the smooth lens's, or the mesh's in the frame it meets the water in).
/// A stone that cannot be built leaves `p` as it is (its run then says why).
pub fn launch_at_touch(p: &mut Preset, beta: f64) {
    use glam::{DQuat, DVec3};
    use stoneskip_physics::sim::params::{AxialSpin, Rotation};
    let v = DVec3::from_array(p.launch.velocity);
    let speed = v.length();
    let heading = if v.x == 0.0 && v.y == 0.0 {
        p.launch.attitude.heading_deg.to_radians()
    } else {
        v.y.atan2(v.x)
    };
    let dir = DVec3::new(
        beta.cos() * heading.cos(),
        beta.cos() * heading.sin(),
        -beta.sin(),
    );
    let velocity = dir * speed;
    p.launch.velocity = velocity.to_array();
    let Ok(stone) = stoneskip_physics::sim::stone::Stone::new(&p.stone) else {
        return;
    };
    let mut q = stoneskip_physics::sim::stone::orientation_from_attitude(&p.launch.attitude);
    // `axial_spin: Resal` on a free mesh of revolution meets the water in the frame turned
    // about the axis to face the flow (`integrate::mesh_orientation`).
    let ph = &p.physics;
    if ph.axial_spin == AxialSpin::Resal
        && ph.rotation == Rotation::Free
        && stone.shape.is_revolution()
        && stone.smooth.is_none()
    {
        let vb = q.inverse() * velocity;
        if vb.x != 0.0 || vb.y != 0.0 {
            q *= DQuat::from_rotation_z(vb.y.atan2(vb.x));
        }
    }
    let lowest = stoneskip_physics::sim::hydro::lowest_clearance(
        &stone,
        DVec3::ZERO,
        q,
        &stoneskip_physics::sim::law::FlatSurface,
    );
    p.launch.position[2] = TOUCH_GAP - lowest;
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

    /// A map's side of `knob` worth trying first: the suggested range in 2 to [`MAX_SIDE`]
    /// round steps (tilt 0–45° by 5°, impact angle 5–60° by 5°, speed 1–15 m/s by 1).
    pub fn for_map(knob: Knob) -> Self {
        let (from, to, count) = match knob {
            Knob::Speed => (1.0, 15.0, 15),
            Knob::Tilt => (0.0, 45.0, 10),
            Knob::ImpactAngle => (5.0, 60.0, 12),
            Knob::Spin => (0.0, 30.0, 16),
            Knob::Height => (0.1, 1.5, 15),
            Knob::Mass => (0.02, 0.5, 13),
        };
        Self {
            knob,
            from,
            to,
            count,
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

/// The most values along each side of a two-value map: 20 × 20 = 400 throws.
pub const MAX_SIDE: usize = 20;

/// An experiment: one value swept (`y: None`), or two on a grid (a map: every `x` with every
/// `y`, each side 2 to [`MAX_SIDE`] values).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Plan {
    pub x: Spec,
    pub y: Option<Spec>,
}

impl From<Spec> for Plan {
    fn from(x: Spec) -> Self {
        Self { x, y: None }
    }
}

impl Plan {
    /// The values along x (a map's side holds at most [`MAX_SIDE`]).
    pub fn x_values(&self) -> Vec<f64> {
        match self.y {
            None => self.x.values(),
            Some(_) => side(&self.x).values(),
        }
    }

    /// The values along y (none for one value).
    pub fn y_values(&self) -> Vec<f64> {
        self.y.map_or(Vec::new(), |y| side(&y).values())
    }

    /// Every throw's values, in the table's order: x by x, and for each x every y.
    pub fn cells(&self) -> Vec<(f64, Option<f64>)> {
        let ys = self.y_values();
        self.x_values()
            .into_iter()
            .flat_map(|x| {
                let one = ys.is_empty().then_some((x, None));
                one.into_iter().chain(ys.iter().map(move |&y| (x, Some(y))))
            })
            .collect()
    }

    /// Why the two values cannot be mapped together, in words; `None` when they can.
    pub fn conflict(&self) -> Option<String> {
        let y = self.y?;
        if y.knob == self.x.knob {
            return Some(format!("{} is already the first value", y.knob.name()));
        }
        let pair = [self.x.knob, y.knob];
        (pair.contains(&Knob::ImpactAngle) && pair.contains(&Knob::Height)).then(|| {
            "an impact angle launches the stone at the water, so the height is not free to vary"
                .to_owned()
        })
    }

    /// The preset of the throw at `(x, y)`: `base` with both values set, an impact angle last
    /// (it launches at the water in the attitude and stone the other value set).
    pub fn preset(&self, base: &Preset, (x, y): (f64, Option<f64>)) -> Preset {
        let Some((sy, y)) = self.y.zip(y) else {
            return self.x.knob.set(base, x);
        };
        if self.x.knob == Knob::ImpactAngle {
            self.x.knob.set(&sy.knob.set(base, y), x)
        } else {
            sy.knob.set(&self.x.knob.set(base, x), y)
        }
    }
}

/// `s` with its count held to a map's side.
fn side(s: &Spec) -> Spec {
    Spec {
        count: s.count.min(MAX_SIDE),
        ..*s
    }
}

/// One throw's result.
#[derive(Debug, Clone, PartialEq)]
pub struct Point {
    pub value: f64,
    /// A map's second value (`None` in a one-value sweep).
    pub second: Option<f64>,
    pub skips: usize,
    /// m, along the ground from the launch point to where it ended.
    pub distance: f64,
    /// Why it ended in words ([`stoneskip_physics::sim::ending()`]: "too slow to skip", "dug in nose-down at
    /// touch 3 (tilt -1.1°)", …), or why the throw could not start.
    pub outcome: String,
    /// Whether the numbers are the throw's result, not a bound of the simulation's (the lake's
    /// edge under wavy contact, the time limit, a failed run): charted hollow, out of the trend.
    pub result: bool,
    /// Force evaluations it took (what it cost).
    pub force_evals: u64,
    /// The stone's attitude relative to its travel when it met the water first and last (the
    /// first and the last contact's start; `None`: it never touched).
    pub first_landing: Option<Landing>,
    pub last_landing: Option<Landing>,
}

/// The stone's attitude when a contact began, relative to its travel (design.md §3): what
/// decides whether it skips on, digs in nose-down (tilt below zero) or lands on its edge.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Landing {
    /// Degrees, leading edge up (the attack angle).
    pub tilt: f64,
    /// Degrees, rolled about the direction of travel.
    pub bank: f64,
}

impl Landing {
    fn of(c: &stoneskip_physics::sim::ContactEvent) -> Self {
        Self {
            tilt: c.attitude_in[0],
            bank: c.attitude_in[1],
        }
    }
}

/// What a one-value sweep charts beside skips and distance: tilt or bank, at the first or the
/// last landing.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Attitude {
    FirstTilt,
    /// The landing the throw ended at, for one that sank: what decided its ending.
    #[default]
    LastTilt,
    FirstBank,
    LastBank,
}

impl Attitude {
    pub const ALL: [Attitude; 4] = [
        Attitude::FirstTilt,
        Attitude::LastTilt,
        Attitude::FirstBank,
        Attitude::LastBank,
    ];

    pub fn name(self) -> &'static str {
        match self {
            Attitude::FirstTilt => "Tilt at the first landing",
            Attitude::LastTilt => "Tilt at the last landing",
            Attitude::FirstBank => "Bank at the first landing",
            Attitude::LastBank => "Bank at the last landing",
        }
    }

    /// Its value in `p` (°), `None` when the throw never touched the water.
    pub fn of(self, p: &Point) -> Option<f64> {
        let (landing, tilt) = match self {
            Attitude::FirstTilt => (p.first_landing, true),
            Attitude::LastTilt => (p.last_landing, true),
            Attitude::FirstBank => (p.first_landing, false),
            Attitude::LastBank => (p.last_landing, false),
        };
        landing.map(|l| if tilt { l.tilt } else { l.bank })
    }
}

/// The presets an experiment throws, in the order of [`Plan::cells`].
pub fn presets(base: &Preset, plan: &Plan) -> Vec<Preset> {
    plan.cells()
        .into_iter()
        .map(|c| plan.preset(base, c))
        .collect()
}

/// Throws the whole experiment on rayon's pool (every core), in the order of [`Plan::cells`];
/// `stop` ends it early (throws not run are left out).
pub fn run(base: &Preset, plan: &Plan, stop: &AtomicBool) -> Vec<Point> {
    let jobs: Vec<((f64, Option<f64>), Preset)> =
        plan.cells().into_iter().zip(presets(base, plan)).collect();
    // Each point keeps the values as swept (7, not the 6.999999999999999 a speed reads back
    // from its velocity).
    let points: Vec<Option<Point>> = jobs
        .par_iter()
        .map(|(c, p)| (!stop.load(Ordering::Relaxed)).then(|| throw(*c, p, stop)))
        .collect();
    points.into_iter().flatten().collect()
}

/// One headless throw (the water left at rest, as `simulate` does), stopped early by `stop`.
pub fn throw((value, second): (f64, Option<f64>), p: &Preset, stop: &AtomicBool) -> Point {
    let mut sim = match stoneskip_physics::sim::Simulation::new(p) {
        Ok(s) => s,
        Err(e) => {
            return Point {
                value,
                second,
                skips: 0,
                distance: 0.0,
                outcome: format!("not thrown: {e}"),
                result: false,
                force_evals: 0,
                first_landing: None,
                last_landing: None,
            }
        }
    };
    sim.skip_unread_water();
    let s = sim.run(&mut |_| {}, &|| stop.load(Ordering::Relaxed));
    let end = stoneskip_physics::sim::ending(&s);
    Point {
        value,
        second,
        skips: s.skips,
        distance: s.distance,
        outcome: end.words(),
        result: end.is_result(),
        force_evals: s.force_evals,
        first_landing: s.contacts.first().map(Landing::of),
        last_landing: s.contacts.last().map(Landing::of),
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

/// Writes the experiment's table as CSV: comment lines (`#`) naming the preset, the sweep and
/// every value of `base` that differs from `loaded`, then a header row and one row per throw
/// (the value, a map's second value, skips, distance to the millimetre, the ending in words,
/// whether it is a result, the force evaluations, the tilt and bank at the first and last
/// landing to 0.1°), through the `csv` crate (quoting as needed).
pub fn write_csv<W: Write>(
    mut out: W,
    loaded: &Preset,
    base: &Preset,
    plan: &Plan,
    points: &[Point],
) -> Result<()> {
    out.write_all(csv_head(loaded, base, plan).as_bytes())
        .context("writing the CSV")?;
    let mut w = csv::Writer::from_writer(&mut out);
    let column = |k: Knob| format!("{}_{}", k.snake(), k.unit_tag());
    let mut header = vec![column(plan.x.knob)];
    header.extend(plan.y.map(|y| column(y.knob)));
    header.extend(
        [
            "skips",
            "distance_m",
            "ending",
            "result",
            "force_evals",
            "first_tilt_deg",
            "first_bank_deg",
            "last_tilt_deg",
            "last_bank_deg",
        ]
        .map(str::to_owned),
    );
    w.write_record(&header).context("writing the CSV")?;
    // Attitudes to a tenth of a degree (what a landing's tilt means); empty: never touched.
    let deg = |a: Attitude, p: &Point| a.of(p).map_or(String::new(), |x| format!("{x:.1}"));
    for p in points {
        let mut row = vec![format!("{}", p.value)];
        if plan.y.is_some() {
            row.push(p.second.map_or(String::new(), |y| format!("{y}")));
        }
        row.extend([
            p.skips.to_string(),
            format!("{:.3}", p.distance),
            p.outcome.clone(),
            if p.result { "yes" } else { "no" }.to_owned(),
            p.force_evals.to_string(),
            deg(Attitude::FirstTilt, p),
            deg(Attitude::FirstBank, p),
            deg(Attitude::LastTilt, p),
            deg(Attitude::LastBank, p),
        ]);
        w.write_record(&row).context("writing the CSV")?;
    }
    w.flush().context("writing the CSV")?;
    drop(w);
    out.flush().context("writing the CSV")
}

/// The CSV's comment lines: the preset, what was swept, what differs from the preset.
fn csv_head(loaded: &Preset, base: &Preset, plan: &Plan) -> String {
    let range = |k: Knob, values: &[f64], spec: &Spec| {
        format!(
            "{} from {} to {} {}",
            k.name().to_lowercase(),
            values.first().copied().unwrap_or(spec.from),
            values.last().copied().unwrap_or(spec.to),
            k.unit(),
        )
    };
    let mut what = range(plan.x.knob, &plan.x_values(), &plan.x);
    if let Some(y) = plan.y {
        what.push_str(&format!(" × {}", range(y.knob, &plan.y_values(), &y)));
    }
    let mut head = format!(
        "# stoneskip sweep of the preset \"{}\"\n",
        base.name.replace(['\n', '\r', '"'], " ")
    );
    head.push_str(&format!(
        "# {what} in {} throws; distance in m along the ground from the launch point; result no: \
         ended by a bound of the simulation (the lake's edge under wavy contact, the time limit), \
         not by the throw\n",
        plan.cells().len()
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
    head
}

fn unit_tag(k: Knob) -> &'static str {
    match k {
        Knob::Speed => "m_s",
        Knob::Tilt => "deg",
        Knob::Spin => "rev_s",
        Knob::Height => "m",
        Knob::Mass => "kg",
        Knob::ImpactAngle => "deg",
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn shipped(name: &str) -> Preset {
        stoneskip_physics::preset::shipped(name).unwrap().unwrap()
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
            second: None,
            skips: 3,
            distance: 12.345_678,
            outcome: "landed on its edge at touch 4 (bank 26°, over 20°)".into(),
            result: true,
            force_evals: 99,
            first_landing: Some(Landing {
                tilt: 20.04,
                bank: -0.26,
            }),
            last_landing: Some(Landing {
                tilt: -1.14,
                bank: 26.0,
            }),
        }];
        let mut out = Vec::new();
        write_csv(&mut out, &loaded, &base, &spec.into(), &points).unwrap();
        let text = String::from_utf8(out).unwrap();
        assert!(text.starts_with("# stoneskip sweep of the preset \"Magic angle\"\n"));
        assert!(text.contains("# changed from the preset: launch.velocity"));
        assert!(text.contains("# changed from the preset: physics.gravity"));
        let rows: Vec<&str> = text.lines().filter(|l| !l.starts_with('#')).collect();
        assert_eq!(
            rows[0],
            "mass_kg,skips,distance_m,ending,result,force_evals,first_tilt_deg,first_bank_deg,\
             last_tilt_deg,last_bank_deg"
        );
        // The ending's comma is quoted by the writer, not replaced.
        assert_eq!(
            rows[1],
            "0.1,3,12.346,\"landed on its edge at touch 4 (bank 26°, over 20°)\",yes,99,20.0,-0.3,\
             -1.1,26.0"
        );
    }

    /// Issue 48: an impact angle set as a launch value is the first touch's descent, exactly:
    /// the launch is at the water, so only the fall through [`TOUCH_GAP`] changes it, by less
    /// than 2g·gap/(U² sin β) (see [`launch_at_touch`]); the speed keeps to U within 2g·t.
    #[test]
    fn an_impact_angle_is_the_first_touchs_descent() {
        let g = 9.81;
        for (name, speed) in [("clanet_disc", 3.5), ("default", 12.0)] {
            let base = Knob::Speed.set(&shipped(name), speed);
            for beta in [3.0_f64, 10.0, 20.0, 45.0, 70.0] {
                let p = Knob::ImpactAngle.set(&Knob::Tilt.set(&base, 25.0), beta);
                assert!((Knob::ImpactAngle.get(&p) - beta).abs() < 1e-9);
                let mut sim = stoneskip_physics::sim::Simulation::new(&p).unwrap();
                while sim.contacts().is_empty() && !sim.is_finished() {
                    sim.tick();
                }
                let c = sim.contacts().first().expect("a first touch");
                let sin = beta.to_radians().sin();
                let fall = TOUCH_GAP / (speed * sin);
                let tol = (2.0 * g * TOUCH_GAP / (speed * speed * sin)).to_degrees() + 1e-9;
                assert!(
                    (c.beta_in - beta).abs() <= tol,
                    "{name} β {beta}: touched at {}° (tolerance {tol:.1e}°)",
                    c.beta_in
                );
                assert!(c.t_start <= 2.0 * fall, "{name} β {beta}: t {}", c.t_start);
                let u = glam::DVec3::from_array(c.v_in).length();
                assert!(
                    (u - speed).abs() <= 2.0 * g * c.t_start + 1e-9,
                    "{name}: {u}"
                );
            }
        }
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
        let ambient = throw((13.5, None), &p, &stop);
        assert!(ambient.result, "{}", ambient.outcome);
        p.water.wavy_contact = true;
        let wavy = throw((13.5, None), &p, &stop);
        assert!(!wavy.result, "{}", wavy.outcome);
        assert!(
            wavy.outcome.starts_with("left the lake"),
            "{}",
            wavy.outcome
        );
    }
}
