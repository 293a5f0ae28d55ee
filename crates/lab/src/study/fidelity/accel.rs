//! The fidelity study's §12, the bounce threshold (whole_throw.md §1 and §5). Tang, Zhao, Chen &
//! Cao, "Trajectory and attitude study of a skipping stone", Phys. Fluids 33 (2021), doi
//! 10.1063/5.0040158: their spun aluminium disc bounced only when the water's force gave it an
//! acceleration above **a = 3.80 g**; near that (press: ~3.8 g) it surfed on without bouncing.
//! The model has no such rule: a contact is a skip when the water's vertical impulse turns the fall
//! (design.md §4). This section reads the peak upward acceleration the water gives a contact,
//! a_z = F_z / m (F_z: the vertical part of the summed face forces, pressure, friction and
//! Archimedes, at every accepted step's end), and asks whether the model's bounces and its
//! non-bounces are split near 3.8 g as Tang's were:
//! - the model's own threshold: the first contact at the minimal speed U_min that skips
//!   (`scenario::min_speed`, thrown at impact), just above it and just below it, which is
//!   where Tang's 3.80 g sits; and the peak against impact speed around it;
//! - every contact of the shipped pebbles' whole throws, bounces and the last contact.
//!
//! Compute, then results, then the report.

use stoneskip_physics::sim::params::Preset;
use stoneskip_physics::sim::scenario::{at_impact, min_speed, IMPACT_CLEARANCE};
use stoneskip_physics::sim::{Outcome, Simulation};

use super::super::table::{md_table, sig, Csv};
use super::super::{check_cancel, Ctx, StudyError};
use super::common::{before, shipped_for, QUICK_CELL};
use crate::study::par_map;

/// Tang et al.'s threshold: a bounce needs an acceleration above this many g.
pub const TANG_G: f64 = stoneskip_physics::sim::TANG_BOUNCE_G;

/// The impact angle of the first-contact sweeps (°): the default throw, released level from
/// 30 cm at 12 m/s, meets the water at 11°.
const BETA_DEG: f64 = 10.0;

/// Relative precision of the minimal speed, and how far above and below it the two sides are
/// thrown.
const U_TOL: f64 = 1e-3;

/// The lake of the first contacts on columns (m): the stone starts at the origin and moves along
/// +x; one contact at 15 m/s covers well under a metre.
const LAKE_SIZE: [f64; 2] = [4.0, 1.2];
const LAKE_ORIGIN: [f64; 2] = [-0.5, -0.6];

/// The model a first contact is thrown under.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Model {
    /// The model before issue 11: attitude locked, flat water, no buoyancy, no air.
    Before,
    /// The default preset's physics on flat water (wavy contact off).
    Flat,
    /// The same with the attitude held (`rotation: Locked`): what the free rotation changes.
    FlatLocked,
    /// The default preset's physics on its near-field columns (a small still lake).
    Columns,
}

impl Model {
    pub const ALL: [Model; 4] = [
        Model::Before,
        Model::Flat,
        Model::FlatLocked,
        Model::Columns,
    ];

    pub fn label(self) -> &'static str {
        match self {
            Model::Before => "before (locked, flat water)",
            Model::Flat => "shipped physics, flat water",
            Model::FlatLocked => "shipped physics, flat water, attitude locked",
            Model::Columns => "shipped physics, near-field columns",
        }
    }
}

/// How a contact ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Kind {
    /// A skip: the water turned the stone upward and it left the surface.
    Bounce,
    /// A crest's brush (wavy contact): left the surface without being turned upward.
    Graze,
    /// Did not leave the water: the run's last contact (sank, or ran out of time).
    Stay,
}

impl Kind {
    pub fn as_str(self) -> &'static str {
        match self {
            Kind::Bounce => "bounce",
            Kind::Graze => "graze",
            Kind::Stay => "stay",
        }
    }
}

/// One contact: how it ended and the peak upward acceleration the water gave.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Touch {
    pub kind: Kind,
    /// |v| at the contact's start (m/s).
    pub speed_in: f64,
    /// Peak of F_z / (m g) over the contact's accepted steps.
    pub peak_g: f64,
    /// s
    pub duration: f64,
}

/// The first contact at one impact speed.
#[derive(Debug, Clone, Copy)]
pub struct SweepPoint {
    pub model: Model,
    pub tilt_deg: f64,
    /// Impact speed (m/s).
    pub speed: f64,
    pub touch: Option<Touch>,
}

/// The model's threshold at one tilt: the minimal speed that skips and the first contact just
/// above and just below it.
#[derive(Debug, Clone, Copy)]
pub struct Threshold {
    pub model: Model,
    pub tilt_deg: f64,
    pub u_min: Option<f64>,
    pub above: Option<Touch>,
    pub below: Option<Touch>,
}

/// Every contact of one whole throw.
#[derive(Debug, Clone)]
pub struct ThrowTouches {
    pub stem: &'static str,
    /// Under the model before issue 11 rather than as shipped.
    pub before: bool,
    pub outcome: Option<Outcome>,
    pub touches: Vec<Touch>,
}

/// What §12 measured.
#[derive(Debug, Clone)]
pub struct AccelStudy {
    pub sweep: Vec<SweepPoint>,
    pub thresholds: Vec<Threshold>,
    pub throws: Vec<ThrowTouches>,
}

fn tilts(quick: bool) -> Vec<f64> {
    if quick {
        vec![20.0]
    } else {
        vec![10.0, 20.0, 30.0]
    }
}

fn speeds(quick: bool) -> Vec<f64> {
    if quick {
        vec![2.0, 4.0, 8.0, 12.0]
    } else {
        (1..=15).map(f64::from).collect()
    }
}

fn throw_stems(quick: bool) -> Vec<&'static str> {
    if quick {
        vec!["default"]
    } else {
        vec!["default", "magic_angle", "record_throw"]
    }
}

/// The default pebble under `model` at launch tilt `tilt_deg`, ready to be thrown at impact.
fn base(model: Model, tilt_deg: f64, quick: bool) -> Result<Preset, StudyError> {
    let shipped = shipped_for("default", quick)?;
    let mut p = match model {
        Model::Before => before(&shipped),
        Model::Flat | Model::FlatLocked => {
            let mut p = shipped;
            p.water.wavy_contact = false;
            if model == Model::FlatLocked {
                p.physics.rotation = stoneskip_physics::sim::params::Rotation::Locked;
            }
            p
        }
        Model::Columns => {
            let mut p = shipped;
            p.water.size = LAKE_SIZE;
            p.water.origin = Some(LAKE_ORIGIN);
            if quick {
                p.water.cell = p.water.cell.max(QUICK_CELL);
            }
            p
        }
    };
    p.launch.attitude.tilt_deg = tilt_deg;
    Ok(p)
}

/// Runs `p` (to the end of its first contact when `first_only`, else to its outcome) and reads
/// every contact's peak upward acceleration (`ContactEvent::peak_lift` over the weight).
pub(super) fn touches(
    p: &Preset,
    first_only: bool,
) -> Result<(Vec<Touch>, Option<Outcome>), StudyError> {
    check_cancel()?;
    let mut sim = Simulation::new(p)?;
    sim.skip_unread_water();
    let weight = sim.stone().mass * p.physics.gravity;
    // Stop at the outcome, or once the first contact has closed when that is all we read.
    let done = |sim: &Simulation| {
        sim.is_finished() || (first_only && sim.contacts().first().is_some_and(|c| !c.open))
    };
    while !done(&sim) {
        sim.tick();
    }
    let contacts = sim.contacts();
    let take = if first_only { 1 } else { contacts.len() };
    let touches = contacts
        .iter()
        .take(take)
        .map(|c| {
            let v = c.v_in;
            Touch {
                kind: if c.skip {
                    Kind::Bounce
                } else if c.graze {
                    Kind::Graze
                } else {
                    Kind::Stay
                },
                speed_in: (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt(),
                peak_g: c.peak_lift / weight,
                duration: c.t_end - c.t_start,
            }
        })
        .collect();
    Ok((touches, sim.outcome()))
}

/// The first contact of `base` thrown at impact at `speed`.
fn first_touch(base: &Preset, speed: f64) -> Result<Option<Touch>, StudyError> {
    let p = at_impact(base, speed, BETA_DEG.to_radians(), IMPACT_CLEARANCE)?;
    Ok(touches(&p, true)?.0.first().copied())
}

fn sweep(quick: bool) -> Result<Vec<SweepPoint>, StudyError> {
    let mut jobs = Vec::new();
    for model in Model::ALL {
        for tilt in tilts(quick) {
            jobs.extend(speeds(quick).into_iter().map(|u| (model, tilt, u)));
        }
    }
    par_map(jobs, |(model, tilt_deg, speed)| {
        let touch = first_touch(&base(model, tilt_deg, quick)?, speed)?;
        Ok(SweepPoint {
            model,
            tilt_deg,
            speed,
            touch,
        })
    })
}

fn thresholds(quick: bool) -> Result<Vec<Threshold>, StudyError> {
    let mut jobs = Vec::new();
    for model in Model::ALL {
        jobs.extend(tilts(quick).into_iter().map(|t| (model, t)));
    }
    // Every model and tilt skips at 10 m/s (the sweep); faster, the columns can trip the stone.
    let (lo, hi) = (0.5, 10.0);
    par_map(jobs, |(model, tilt_deg)| {
        check_cancel()?;
        let b = base(model, tilt_deg, quick)?;
        let u_min = min_speed(&b, BETA_DEG.to_radians(), lo, hi, U_TOL)?;
        let side = |f: f64| -> Result<Option<Touch>, StudyError> {
            match u_min {
                Some(u) if u > lo => first_touch(&b, u * f),
                _ => Ok(None),
            }
        };
        Ok(Threshold {
            model,
            tilt_deg,
            u_min,
            above: side(1.0 + U_TOL)?,
            below: side(1.0 - U_TOL)?,
        })
    })
}

fn whole_throws(quick: bool) -> Result<Vec<ThrowTouches>, StudyError> {
    let jobs: Vec<(&'static str, bool)> = throw_stems(quick)
        .into_iter()
        .flat_map(|s| [(s, true), (s, false)])
        .collect();
    par_map(jobs, |(stem, old)| {
        let shipped = shipped_for(stem, quick)?;
        let p = if old { before(&shipped) } else { shipped };
        let (touches, outcome) = touches(&p, false)?;
        Ok(ThrowTouches {
            stem,
            before: old,
            outcome,
            touches,
        })
    })
}

pub fn compute(ctx: &Ctx) -> Result<AccelStudy, StudyError> {
    let q = ctx.quick;
    ctx.progress("the bounce threshold");
    Ok(AccelStudy {
        sweep: sweep(q)?,
        thresholds: thresholds(q)?,
        throws: whole_throws(q)?,
    })
}

// ---------------------------------------------------------------------------------------------
// Results
// ---------------------------------------------------------------------------------------------

impl ThrowTouches {
    fn model_label(&self) -> &'static str {
        if self.before {
            "before"
        } else {
            "as shipped"
        }
    }

    /// The bounces' peaks (g), sorted.
    pub fn bounce_peaks(&self) -> Vec<f64> {
        let mut v: Vec<f64> = self
            .touches
            .iter()
            .filter(|t| t.kind == Kind::Bounce)
            .map(|t| t.peak_g)
            .collect();
        v.sort_by(f64::total_cmp);
        v
    }

    /// Bounces whose peak stayed below Tang's threshold.
    pub fn bounces_below_tang(&self) -> usize {
        self.bounce_peaks().iter().filter(|&&a| a < TANG_G).count()
    }

    /// The contact the stone did not leave, if the run ended in one.
    pub fn stay(&self) -> Option<&Touch> {
        self.touches.last().filter(|t| t.kind == Kind::Stay)
    }

    fn count(&self, kind: Kind) -> usize {
        self.touches.iter().filter(|t| t.kind == kind).count()
    }
}

impl Threshold {
    /// The peak at the minimal speed (g): the mean of the two sides, which agree closely
    /// (the peak is continuous in the speed; what changes is whether the stone gets out).
    pub fn peak_g(&self) -> Option<f64> {
        Some(0.5 * (self.above?.peak_g + self.below?.peak_g))
    }
}

/// The thresholds of `model`, by tilt.
fn thresholds_of(s: &AccelStudy, model: Model) -> Vec<&Threshold> {
    s.thresholds.iter().filter(|t| t.model == model).collect()
}

/// "4.7 g at 20°, …" for the lead table.
fn threshold_words(s: &AccelStudy, model: Model) -> String {
    let parts: Vec<String> = thresholds_of(s, model)
        .iter()
        .map(|t| match t.peak_g() {
            Some(a) => format!("{} g at {}°", sig(a, 2), t.tilt_deg),
            None => format!("none at {}°", t.tilt_deg),
        })
        .collect();
    parts.join(", ")
}

/// Bounces below Tang's threshold over the whole throws of one model: (below, bounces).
fn below_tang(s: &AccelStudy, before: bool) -> (usize, usize) {
    s.throws
        .iter()
        .filter(|t| t.before == before)
        .fold((0, 0), |(b, n), t| {
            (b + t.bounces_below_tang(), n + t.bounce_peaks().len())
        })
}

/// The lead table's two cells: the model before, the model after.
pub fn lead_words(s: &AccelStudy) -> (String, String) {
    let whole = |before: bool| {
        let (below, n) = below_tang(s, before);
        format!("whole throws: {below} of {n} bounces peak below {TANG_G:.2} g")
    };
    (
        format!(
            "at U_min: {}; {}",
            threshold_words(s, Model::Before),
            whole(true)
        ),
        format!(
            "at U_min, flat water: {}; on the columns: {}; {}",
            threshold_words(s, Model::Flat),
            threshold_words(s, Model::Columns),
            whole(false)
        ),
    )
}

pub fn write_csvs(ctx: &Ctx, s: &AccelStudy) -> Result<(), StudyError> {
    let touch_cells = |t: Option<&Touch>| -> Vec<super::super::table::Val> {
        match t {
            Some(t) => vec![
                t.kind.as_str().into(),
                t.speed_in.into(),
                t.peak_g.into(),
                t.duration.into(),
            ],
            None => vec![
                "none".into(),
                f64::NAN.into(),
                f64::NAN.into(),
                f64::NAN.into(),
            ],
        }
    };
    let touch_header = ["kind", "speed_in_m_s", "peak_g", "duration_s"];
    let mut first = Csv::new(
        &[
            &["model", "tilt_deg", "impact_speed_m_s"],
            &touch_header[..],
        ]
        .concat(),
    );
    for p in &s.sweep {
        let mut row = vec![p.model.label().into(), p.tilt_deg.into(), p.speed.into()];
        row.extend(touch_cells(p.touch.as_ref()));
        first.push(row);
    }
    ctx.write_csv("bounce_threshold_sweep.csv", &first)?;
    let mut th = Csv::new(&[
        "model",
        "tilt_deg",
        "u_min_m_s",
        "side",
        "kind",
        "speed_in_m_s",
        "peak_g",
        "duration_s",
    ]);
    for t in &s.thresholds {
        for (side, touch) in [("above", t.above), ("below", t.below)] {
            let mut row = vec![
                t.model.label().into(),
                t.tilt_deg.into(),
                t.u_min.unwrap_or(f64::NAN).into(),
                side.into(),
            ];
            row.extend(touch_cells(touch.as_ref()));
            th.push(row);
        }
    }
    ctx.write_csv("bounce_threshold.csv", &th)?;
    let mut whole = Csv::new(&[&["throw", "model", "contact"], &touch_header[..]].concat());
    for w in &s.throws {
        for (i, t) in w.touches.iter().enumerate() {
            let mut row = vec![w.stem.into(), w.model_label().into(), (i + 1).into()];
            row.extend(touch_cells(Some(t)));
            whole.push(row);
        }
    }
    ctx.write_csv("bounce_threshold_contacts.csv", &whole)
}

// ---------------------------------------------------------------------------------------------
// Report
// ---------------------------------------------------------------------------------------------

/// A touch as the tables show it: "4.7 g, bounce (0.069 s)".
fn touch_cell(t: Option<&Touch>) -> String {
    match t {
        Some(t) => format!(
            "{} g, {} ({} s)",
            sig(t.peak_g, 3),
            t.kind.as_str(),
            sig(t.duration, 2)
        ),
        None => "—".into(),
    }
}

fn threshold_rows(s: &AccelStudy) -> Vec<Vec<String>> {
    s.thresholds
        .iter()
        .map(|t| {
            vec![
                t.model.label().into(),
                format!("{}", t.tilt_deg),
                t.u_min.map_or("none ≤ 10".into(), |u| sig(u, 3)),
                touch_cell(t.above.as_ref()),
                touch_cell(t.below.as_ref()),
                t.peak_g()
                    .map_or("—".into(), |a| format!("{:.2}", a / TANG_G)),
            ]
        })
        .collect()
}

fn throw_rows(s: &AccelStudy) -> Vec<Vec<String>> {
    s.throws
        .iter()
        .map(|w| {
            let peaks = w.bounce_peaks();
            let range = match (
                peaks.first(),
                peaks.get(peaks.len().saturating_sub(1) / 2),
                peaks.last(),
            ) {
                (Some(lo), Some(mid), Some(hi)) => {
                    format!("{} ({}–{})", sig(*mid, 3), sig(*lo, 3), sig(*hi, 3))
                }
                _ => "—".into(),
            };
            vec![
                format!("{}, {}", w.stem, w.model_label()),
                w.count(Kind::Bounce).to_string(),
                range,
                w.bounces_below_tang().to_string(),
                w.count(Kind::Graze).to_string(),
                w.stay().map_or("—".into(), |t| {
                    format!(
                        "{} g at {} m/s, {} s",
                        sig(t.peak_g, 3),
                        sig(t.speed_in, 3),
                        sig(t.duration, 2)
                    )
                }),
            ]
        })
        .collect()
}

/// The lowest and highest of the thresholds' peaks (g) over every model and tilt.
fn threshold_span(s: &AccelStudy) -> Option<(f64, f64)> {
    let v: Vec<f64> = s.thresholds.iter().filter_map(Threshold::peak_g).collect();
    let lo = v.iter().copied().reduce(f64::min)?;
    let hi = v.iter().copied().reduce(f64::max)?;
    Some((lo, hi))
}

/// The largest relative difference between the peaks just above and just below U_min.
fn side_gap(s: &AccelStudy) -> f64 {
    s.thresholds
        .iter()
        .filter_map(|t| {
            let (a, b) = (t.above?.peak_g, t.below?.peak_g);
            Some((a - b).abs() / a.max(b))
        })
        .fold(0.0, f64::max)
}

/// The split of one model's whole throws: (weakest bounce, strongest stay) in g.
fn split(s: &AccelStudy, before: bool) -> (Option<f64>, Option<f64>) {
    let of = s.throws.iter().filter(|w| w.before == before);
    let weakest = of
        .clone()
        .filter_map(|w| w.bounce_peaks().first().copied())
        .reduce(f64::min);
    let strongest = of
        .filter_map(|w| w.stay().map(|t| t.peak_g))
        .reduce(f64::max);
    (weakest, strongest)
}

/// The thresholds whose two sides are the wrong way round: the stone stays just above U_min or
/// bounces just below it, so whether it skips is not monotone in the speed there.
fn crossed(s: &AccelStudy) -> Vec<&Threshold> {
    s.thresholds
        .iter()
        .filter(|t| {
            t.above.is_some_and(|a| a.kind != Kind::Bounce)
                || t.below.is_some_and(|b| b.kind == Kind::Bounce)
        })
        .collect()
}

/// Where the bisection's bracket sits in a speed band whose outcome flips more than once.
fn crossed_words(s: &AccelStudy) -> String {
    let c = crossed(s);
    if c.is_empty() {
        return String::new();
    }
    let cases: Vec<String> = c
        .iter()
        .map(|t| format!("{}, {}°", t.model.label(), t.tilt_deg))
        .collect();
    let only_columns = c.iter().all(|t| t.model == Model::Columns);
    format!(
        "- Not monotone near U_min ({}): the bisection found a speed where the outcome flips, but \
         {:.1} % either side of it the stone stays above or bounces below, so skipping there is \
         not one threshold in the speed.{} The peaks on the two sides still agree, so the \
         acceleration at which the outcome turns is sharper than the speed.\n",
        cases.join("; "),
        100.0 * U_TOL,
        if only_columns {
            " Only on the columns: flat water has no waves of the stone's own making, and there \
             the outcome is monotone."
        } else {
            ""
        }
    )
}

/// What holding the attitude does to the flat-water threshold, at each tilt.
fn rotation_words(s: &AccelStudy) -> String {
    let pairs: Vec<String> = thresholds_of(s, Model::Flat)
        .iter()
        .filter_map(|free| {
            let locked = thresholds_of(s, Model::FlatLocked)
                .into_iter()
                .find(|l| l.tilt_deg == free.tilt_deg)?;
            Some(format!(
                "{}°: {} m/s and {} g free, {} m/s and {} g locked",
                free.tilt_deg,
                sig(free.u_min?, 3),
                sig(free.peak_g()?, 2),
                sig(locked.u_min?, 3),
                sig(locked.peak_g()?, 2)
            ))
        })
        .collect();
    if pairs.is_empty() {
        return String::new();
    }
    format!(
        "- On flat water, the shipped physics with the attitude held has the lower minimal speed \
         and threshold ({}): the stone's own turn during a slow contact at 14 rev/s (about one \
         turn per contact at U_min, Clanet's stability limit) is what raises the shipped model's \
         threshold above the locked one's.\n",
        pairs.join("; ")
    )
}

/// What the tables say, in words.
fn findings(s: &AccelStudy) -> String {
    let mut w = String::from("\n");
    if let Some((lo, hi)) = threshold_span(s) {
        w.push_str(&format!(
            "- At its minimal speed a first contact peaks at {} to {} g over the {} models and \
             tilts ({:.1}× to {:.1}× Tang's {TANG_G:.2} g). The peak is continuous in the speed: just \
             above and just below U_min it differs by at most {:.1} %, and what changes is whether \
             the stone gets out. So the model, like Tang's disc, has a threshold acceleration, of \
             the same order as theirs; it depends on the tilt and on the model, and Tang's disc, \
             angles and spin are not the default pebble's, so this is a comparison of order, not \
             a check to a tolerance.\n",
            sig(lo, 2),
            sig(hi, 2),
            Model::ALL.len(),
            lo / TANG_G,
            hi / TANG_G,
            100.0 * side_gap(s)
        ));
    }
    w.push_str(&crossed_words(s));
    w.push_str(&rotation_words(s));
    for (before, name) in [(true, "Before"), (false, "As shipped")] {
        let (below, n) = below_tang(s, before);
        let (weak, strong) = split(s, before);
        let g = |x: Option<f64>| x.map_or("n/a".into(), |a| sig(a, 3));
        w.push_str(&format!(
            "- {name}, whole throws: {below} of {n} bounces peak below {TANG_G:.2} g; the weakest \
             bounce peaks at {} g, and the strongest last contact the stone did not leave at {} \
             g. {}\n",
            g(weak),
            g(strong),
            match (weak, strong) {
                (Some(a), Some(b)) if b < a => format!(
                    "Bounces and the final contacts are split between {} and {} g, as Tang's \
                     bounces and surfing were near 3.8 g.",
                    sig(b, 3),
                    sig(a, 3)
                ),
                (Some(_), Some(_)) => "Bounces and final contacts overlap: the peak alone does \
                                       not say whether a contact of a whole throw bounces."
                    .into(),
                _ => String::new(),
            }
        ));
    }
    w
}

/// §12 of the report.
pub fn section(s: &AccelStudy) -> String {
    let mut out = format!(
        "\n## 12. The bounce threshold\n\nTang et al. (2021) found that their spun aluminium disc \
         bounced only when the water gave it an acceleration above {TANG_G:.2} g; at about 3.8 g it \
         surfed on without bouncing (whole_throw.md §1). The model has no such rule (a skip is a \
         contact the stone leaves turned upward, design.md §4). Here, the peak of the water's \
         upward force over the stone's weight, F_z/(m g), over each contact's accepted steps. \
         First, the model's own threshold: the default pebble thrown at impact (β = {BETA_DEG}°, \
         its 14 rev/s) at its minimal speed U_min (bisection to {:.1} %), just above and just \
         below it.\n\n",
        100.0 * U_TOL
    );
    out.push_str(&md_table(
        &[
            "model",
            "tilt (°)",
            "U_min (m/s)",
            "just above U_min",
            "just below U_min",
            "peak / 3.80 g",
        ],
        &threshold_rows(s),
    ));
    out.push_str(
        "\n![peak acceleration](bounce_threshold.png)\n\nThen every contact of the shipped \
         pebbles' whole throws, before and as shipped (\"stay\": the contact the stone did not \
         leave; grazes: crests brushing a stone the water did not turn upward).\n\n",
    );
    out.push_str(&md_table(
        &[
            "throw, model",
            "bounces",
            "their peaks (g): median (range)",
            "bounces below 3.80 g",
            "grazes",
            "last contact, not left",
        ],
        &throw_rows(s),
    ));
    out.push_str(&findings(s));
    out
}

/// The chart: the first contact's peak against impact speed at the middle tilt, per model; and
/// every contact of the whole throws against its entry speed.
pub fn write_chart(ctx: &Ctx, s: &AccelStudy) -> Result<(), StudyError> {
    use super::super::plot::{self, Chart, Legend, Mark, Panel, RefLine, Series};
    use super::super::style::colors;
    let tilt = tilts(ctx.quick)[tilts(ctx.quick).len() / 2];
    let tang = || RefLine::h(format!("Tang 2021: {TANG_G:.2} g"), TANG_G, colors::GREY);
    let mut first = Chart::new(
        format!("First contact at {tilt}° tilt, β = {BETA_DEG}°: peak F_z/(m g)"),
        "impact speed (m/s)",
        "peak (g)",
    )
    .log_y()
    .line(tang())
    .legend(Legend::UpperLeft);
    for (k, model) in Model::ALL.into_iter().enumerate() {
        for bounced in [true, false] {
            let pts: Vec<(f64, f64)> = s
                .sweep
                .iter()
                .filter(|p| p.model == model && p.tilt_deg == tilt)
                .filter_map(|p| p.touch.map(|t| (p.speed, t)))
                .filter(|(_, t)| (t.kind == Kind::Bounce) == bounced)
                .map(|(u, t)| (u, t.peak_g))
                .collect();
            first = first.series(Series::new(
                format!(
                    "{}: {}",
                    model.label(),
                    if bounced { "bounce" } else { "no bounce" }
                ),
                pts,
                colors::CYCLE[k],
                if bounced {
                    Mark::LinePoints
                } else {
                    Mark::Dashed
                },
            ));
        }
    }
    let mut whole = Chart::new(
        "Whole throws: every contact's peak against its entry speed",
        "entry speed (m/s)",
        "peak (g)",
    )
    .log_y()
    .line(tang())
    .legend(Legend::UpperLeft);
    for (k, before) in [true, false].into_iter().enumerate() {
        for kind in [Kind::Bounce, Kind::Stay] {
            let pts: Vec<(f64, f64)> = s
                .throws
                .iter()
                .filter(|w| w.before == before)
                .flat_map(|w| w.touches.iter())
                .filter(|t| t.kind == kind)
                .map(|t| (t.speed_in, t.peak_g))
                .collect();
            whole = whole.series(Series::new(
                format!(
                    "{}: {}",
                    if before { "before" } else { "as shipped" },
                    if kind == Kind::Bounce {
                        "bounces"
                    } else {
                        "last contact (not left)"
                    }
                ),
                pts,
                if kind == Kind::Bounce {
                    colors::CYCLE[k]
                } else {
                    colors::CYCLE[k + 3]
                },
                Mark::Points,
            ));
        }
    }
    plot::draw(
        &ctx.path("bounce_threshold.png"),
        (1400, 560),
        2,
        None,
        &[Panel::Chart(first), Panel::Chart(whole)],
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    fn touch(kind: Kind, peak_g: f64) -> Touch {
        Touch {
            kind,
            speed_in: 5.0,
            peak_g,
            duration: 0.05,
        }
    }

    fn throw(before: bool, touches: Vec<Touch>) -> ThrowTouches {
        ThrowTouches {
            stem: "default",
            before,
            outcome: Some(Outcome::Sank),
            touches,
        }
    }

    #[test]
    fn a_flat_water_bounce_peaks_above_the_weight() {
        // On flat water a bounce turns a fall into a climb: the water's mean upward force over
        // the contact, m g + m Δv_z / T, exceeds the weight, so its peak does too.
        for model in [Model::Before, Model::Flat] {
            let b = base(model, 20.0, true).unwrap();
            let t = first_touch(&b, 8.0).unwrap().unwrap();
            assert_eq!(t.kind, Kind::Bounce, "{model:?}");
            assert!(t.peak_g > 1.0, "{model:?}: {t:?}");
            assert!((t.speed_in - 8.0).abs() < 1e-3, "{t:?}");
        }
    }

    #[test]
    fn a_whole_throw_reads_every_contact_and_its_skips() {
        let p = before(&shipped_for("default", true).unwrap());
        let (touches, outcome) = touches(&p, false).unwrap();
        let summary = stoneskip_physics::sim::simulate(&p).unwrap();
        assert_eq!(outcome, summary.outcome);
        assert_eq!(touches.len(), summary.contacts.len());
        let bounces = touches.iter().filter(|t| t.kind == Kind::Bounce).count();
        assert_eq!(bounces, summary.skips);
        assert!(touches.iter().all(|t| t.peak_g.is_finite()));
    }

    #[test]
    fn bounces_and_stays_split_or_overlap() {
        let s = AccelStudy {
            sweep: Vec::new(),
            thresholds: Vec::new(),
            throws: vec![
                throw(
                    true,
                    vec![
                        touch(Kind::Bounce, 9.0),
                        touch(Kind::Bounce, 3.2),
                        touch(Kind::Stay, 2.6),
                    ],
                ),
                throw(
                    false,
                    vec![
                        touch(Kind::Bounce, 1.6),
                        touch(Kind::Graze, 0.1),
                        touch(Kind::Stay, 2.6),
                    ],
                ),
            ],
        };
        assert_eq!(split(&s, true), (Some(3.2), Some(2.6)));
        assert_eq!(below_tang(&s, true), (1, 2));
        assert_eq!(below_tang(&s, false), (1, 1));
        let w = findings(&s);
        assert!(w.contains("split between 2.60 and 3.20 g"), "{w}");
        assert!(w.contains("overlap"), "{w}");
    }
}
