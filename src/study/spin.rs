//! The phase study's spin axis (issue 6; physics.md §1.7, §7.3, VC-12, VC-13): the stone as a free
//! rigid body. Three parts:
//!
//! * **Spin × tilt map.** Skips of Clanet's disc (Clanet, Hersen & Bocquet, Nature 2004) thrown at
//!   U = 3.5 m/s, β = 20° under `rotation: Free`, over spin and tilt, with the pressure at the faces
//!   (the paper's eqs. 25–26) and at Savitsky's planing centre (0.75 of the wetted length). The spin
//!   threshold per tilt (first contact skips) is drawn over it, with the literature's rule of thumb of
//!   about one revolution per contact (VC-13).
//! * **VC-12.** The reference throw, α = β = 20° at 65 rev/s: how far the stone's plane turns in its
//!   first contact, split into the change of its inclination to the water (Clanet's α, which should
//!   stay nearly constant) and the turn of its azimuth (the gyroscopic precession into bank).
//! * **Spin-limited count.** Skips of a typical stone (R 5 cm, 8 mm, 150 g; 12 m/s) over two decades of
//!   spin, beside the locked attitude (the infinite-spin limit) and Bocquet's reported N ≈ Rω²/g; the
//!   exponent of N ∝ ω^p is fitted where the count is spin-limited.
//!
//! Every run is deterministic; runs go over the cores with rayon and are collected in grid order.

use rayon::prelude::*;

use crate::sim::params::{
    Attitude, ForceLaw, Preset, PressureCentre, Rotation, Shape, StoneParams,
};
use crate::sim::scenario::{at_impact, IMPACT_CLEARANCE};
use crate::sim::Simulation;

use super::plot::{self, half_steps, Cell, Chart, Heatmap, Legend, Mark, Panel, RefLine, Series};
use super::style::{colors, skip_class, skip_classes};
use super::table::{md_table, sig, Csv};
use super::throws::{clanet_disc, EVAL_CAP};
use super::{check_cancel, linspace_step, logspace, Ctx, StudyError};

const REV: f64 = std::f64::consts::TAU;

/// Speed and impact angle of the map and of VC-12 (Clanet's reference throw).
pub const MAP_SPEED: f64 = 3.5;
pub const MAP_BETA_DEG: f64 = 20.0;
/// VC-12: α = β = 20° at 65 rev/s.
pub const VC12_TILT_DEG: f64 = 20.0;
pub const VC12_SPIN_REV_S: f64 = 65.0;
/// VC-13's tilt, at which the spin threshold is located precisely.
pub const VC13_TILT_DEG: f64 = 35.0;

/// The two centre-of-pressure models compared.
pub const CENTRES: [PressureCentre; 2] = [
    PressureCentre::Faces,
    PressureCentre::Planing(crate::sim::params::SAVITSKY_CENTRE),
];

pub fn centre_name(c: PressureCentre) -> String {
    match c {
        PressureCentre::Faces => "faces (area centroids)".into(),
        PressureCentre::Planing(f) => format!("planing ({f} of wetted length)"),
    }
}

fn centre_key(c: PressureCentre) -> &'static str {
    match c {
        PressureCentre::Faces => "faces",
        PressureCentre::Planing(_) => "planing",
    }
}

/// Grids of the spin study.
#[derive(Debug, Clone)]
pub struct SpinGrid {
    /// Tilts of the map (degrees).
    pub tilts: Vec<f64>,
    /// Spins of the map (rev/s).
    pub spins: Vec<f64>,
    /// Spins of the spin-limited count (rev/s, log-spaced).
    pub curve_spins: Vec<f64>,
}

pub fn grid(quick: bool) -> SpinGrid {
    if quick {
        SpinGrid {
            tilts: linspace_step(5.0, 45.0, 10.0),
            spins: linspace_step(0.0, 100.0, 25.0),
            curve_spins: logspace(4.0, 150.0, 5),
        }
    } else {
        SpinGrid {
            tilts: linspace_step(5.0, 45.0, 2.5),
            spins: linspace_step(0.0, 100.0, 2.5),
            curve_spins: logspace(2.0, 155.0, 31),
        }
    }
}

/// Clanet's disc at impact (U = 3.5 m/s, β = 20°), free rotation, `rev_s` about its axis.
pub fn clanet_spun(tilt: f64, rev_s: f64, centre: PressureCentre) -> Result<Preset, StudyError> {
    let mut p = clanet_disc(ForceLaw::Rosellini, tilt);
    p.physics.rotation = Rotation::Free;
    p.physics.pressure_centre = centre;
    p.launch.spin = rev_s * REV;
    Ok(at_impact(
        &p,
        MAP_SPEED,
        MAP_BETA_DEG.to_radians(),
        IMPACT_CLEARANCE,
    )?)
}

/// The typical stone of the spin-limited count: a 10 cm, 150 g disc thrown at 12 m/s from 25 cm with
/// V_z = −0.5 m/s at a 15° tilt, Rosellini law, water off; `None`: locked attitude.
pub fn typical(rev_s: Option<f64>, centre: PressureCentre) -> Preset {
    let mut p = Preset {
        name: "typical spun stone".into(),
        ..Preset::default()
    };
    p.stone = StoneParams {
        shape: Shape::Disk {
            radius: TYPICAL_RADIUS,
            thickness: 0.008,
        },
        mass: 0.15,
        segments: 48,
    };
    p.launch.position = [0.0, 0.0, 0.25];
    p.launch.velocity = [12.0, 0.0, -0.5];
    p.launch.attitude = Attitude {
        tilt_deg: 15.0,
        bank_deg: 0.0,
        heading_deg: 0.0,
    };
    p.physics.force_law = ForceLaw::Rosellini;
    p.physics.pressure_centre = centre;
    p.physics.max_time = 20.0;
    match rev_s {
        Some(s) => {
            p.physics.rotation = Rotation::Free;
            p.launch.spin = s * REV;
        }
        None => p.physics.rotation = Rotation::Locked,
    }
    p.water.enabled = false;
    p
}

/// Radius of the typical stone (m): Bocquet's R in N ≈ Rω²/g.
pub const TYPICAL_RADIUS: f64 = 0.05;

/// Inclination of the stone's plane to the water (degrees) from a reported [tilt, bank, heading]:
/// the axis has a_z = cos(tilt)·cos(bank).
pub fn inclination(att: [f64; 3]) -> f64 {
    (att[0].to_radians().cos() * att[1].to_radians().cos())
        .clamp(-1.0, 1.0)
        .acos()
        .to_degrees()
}

/// The stone's axis (world) from a reported [tilt, bank, heading] (stone::reported_attitude inverted).
pub fn axis(att: [f64; 3]) -> glam::DVec3 {
    let (t, b, h) = (
        att[0].to_radians(),
        att[1].to_radians(),
        att[2].to_radians(),
    );
    let d = glam::DVec3::new(h.cos(), h.sin(), 0.0);
    let s = glam::DVec3::Z.cross(d);
    let az = t.cos() * b.cos();
    d * (-t.sin()) + s * (-b.tan() * az) + glam::DVec3::Z * az
}

/// One throw of the map.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SpinPoint {
    pub tilt: f64,
    pub rev_s: f64,
    pub skips: usize,
    pub first_skip: bool,
    /// Duration of the first contact (s).
    pub first_duration: f64,
    /// Change of the inclination to the water through the first contact (degrees, signed).
    pub inclination_change: f64,
    /// Angle the axis turned through the first contact (degrees).
    pub axis_turn: f64,
    pub capped: bool,
}

/// Runs one throw to its end (or [`EVAL_CAP`] force evaluations).
pub fn spin_point(tilt: f64, rev_s: f64, centre: PressureCentre) -> Result<SpinPoint, StudyError> {
    let p = clanet_spun(tilt, rev_s, centre)?;
    let mut sim = Simulation::new(&p)?;
    while !sim.is_finished() && sim.cost().1 < EVAL_CAP {
        sim.tick();
    }
    let first = sim.contacts().first().copied();
    Ok(SpinPoint {
        tilt,
        rev_s,
        skips: sim.skips(),
        first_skip: first.is_some_and(|c| c.skip && !c.open),
        first_duration: first.map_or(0.0, |c| c.t_end - c.t_start),
        inclination_change: first.map_or(0.0, |c| {
            inclination(c.attitude_out) - inclination(c.attitude_in)
        }),
        axis_turn: first.map_or(0.0, |c| {
            axis(c.attitude_in)
                .angle_between(axis(c.attitude_out))
                .to_degrees()
        }),
        capped: !sim.is_finished(),
    })
}

/// The spin × tilt map, in grid order (tilt-major).
pub fn spin_map(centre: PressureCentre, g: &SpinGrid) -> Result<Vec<SpinPoint>, StudyError> {
    let throws: Vec<(f64, f64)> = g
        .tilts
        .iter()
        .flat_map(|&t| g.spins.iter().map(move |&s| (t, s)))
        .collect();
    throws
        .par_iter()
        .map(|&(t, s)| {
            check_cancel()?;
            spin_point(t, s, centre)
        })
        .collect()
}

/// Smallest spin (rev/s) in [0, `hi`] whose first contact skips at `tilt`, by bisection to `tol`
/// rev/s, with that contact's duration (s). `None` when `hi` does not skip.
pub fn spin_threshold(
    tilt: f64,
    centre: PressureCentre,
    hi: f64,
    tol: f64,
) -> Result<Option<(f64, f64)>, StudyError> {
    let first = |s: f64| -> Result<(bool, f64), StudyError> {
        let p = clanet_spun(tilt, s, centre)?;
        let c = crate::sim::scenario::first_contact(&p)?;
        Ok(c.map_or((false, 0.0), |c| (c.skipped, c.duration)))
    };
    if !first(hi)?.0 {
        return Ok(None);
    }
    let (mut lo, mut hi) = (0.0, hi);
    if first(lo)?.0 {
        return Ok(Some((0.0, first(0.0)?.1)));
    }
    while hi - lo > tol {
        check_cancel()?;
        let mid = 0.5 * (lo + hi);
        if first(mid)?.0 {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    Ok(Some((hi, first(hi)?.1)))
}

/// One point of the spin-limited count.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CountPoint {
    /// rev/s; `None`: locked attitude.
    pub rev_s: Option<f64>,
    pub skips: usize,
    /// Contacts that end with the stone rising (a rebound, not a graze).
    pub rebounds: usize,
    pub distance: f64,
    /// Sideways drift at the last contact (m).
    pub lateral: f64,
}

/// Skips of the typical stone at each spin (and locked, last).
pub fn spin_counts(centre: PressureCentre, spins: &[f64]) -> Result<Vec<CountPoint>, StudyError> {
    let mut runs: Vec<Option<f64>> = spins.iter().map(|&s| Some(s)).collect();
    runs.push(None);
    runs.par_iter()
        .map(|&rev_s| {
            check_cancel()?;
            let s = crate::sim::simulate(&typical(rev_s, centre))?;
            Ok(CountPoint {
                rev_s,
                skips: s.skips,
                rebounds: s
                    .contacts
                    .iter()
                    .filter(|c| c.skip && c.v_out[2] > 0.0)
                    .count(),
                distance: s.distance,
                lateral: s.contacts.last().map_or(0.0, |c| c.y),
            })
        })
        .collect()
}

/// Least-squares slope of ln y over ln x (the exponent p of y ∝ x^p); `None` below two points.
pub fn fit_exponent(points: &[(f64, f64)]) -> Option<f64> {
    let pts: Vec<(f64, f64)> = points
        .iter()
        .filter(|(x, y)| *x > 0.0 && *y > 0.0)
        .map(|(x, y)| (x.ln(), y.ln()))
        .collect();
    let n = pts.len() as f64;
    if pts.len() < 2 {
        return None;
    }
    let mx = pts.iter().map(|p| p.0).sum::<f64>() / n;
    let my = pts.iter().map(|p| p.1).sum::<f64>() / n;
    let sxx: f64 = pts.iter().map(|p| (p.0 - mx).powi(2)).sum();
    let sxy: f64 = pts.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum();
    (sxx > 0.0).then(|| sxy / sxx)
}

/// The spin-limited part of a count curve, counted in rebounds (a graze that rocks off the surface
/// while sinking is not a bounce): spins whose count N is at least 2 (one skip is set by the
/// first contact's own stability, the VC-13 threshold, not by a drift over contacts) and at most half
/// the locked count N_L (where the attitude, not the speed, ends the run). Returns (spin, N) and
/// (spin, N_spin) with N_spin = N·N_L/(N_L − N): the spin limit alone when the two limits act
/// together, 1/N = 1/N_spin + 1/N_L (the speed-limited count being the locked one).
#[allow(clippy::type_complexity)]
pub fn spin_limited(points: &[CountPoint]) -> (Vec<(f64, f64)>, Vec<(f64, f64)>) {
    let locked = points
        .iter()
        .find(|p| p.rev_s.is_none())
        .map_or(0, |p| p.rebounds);
    points
        .iter()
        .filter_map(|p| {
            let s = p.rev_s?;
            (p.rebounds >= 2 && 2 * p.rebounds <= locked).then(|| {
                let n = p.rebounds as f64;
                let nl = locked as f64;
                ((s, n), (s, n * nl / (nl - n)))
            })
        })
        .unzip()
}

/// Everything per centre-of-pressure model.
#[derive(Debug, Clone)]
pub struct CentreResult {
    pub centre: PressureCentre,
    pub map: Vec<SpinPoint>,
    /// Spin threshold at VC-13's tilt: (rev/s, first-contact duration s).
    pub threshold: Option<(f64, f64)>,
    pub vc12: SpinPoint,
    pub vc12_no_spin: SpinPoint,
    pub counts: Vec<CountPoint>,
}

/// Runs the spin part; returns the Markdown section the phase report appends.
pub fn run(ctx: &Ctx) -> Result<String, StudyError> {
    let g = grid(ctx.quick);
    let mut results = Vec::new();
    for centre in CENTRES {
        ctx.progress(&format!(
            "spin, {}: spin × tilt map ({} runs)",
            centre_name(centre),
            g.tilts.len() * g.spins.len()
        ));
        let map = spin_map(centre, &g)?;
        ctx.progress(&format!(
            "spin, {}: threshold, VC-12, spin-limited count",
            centre_name(centre)
        ));
        let threshold = spin_threshold(
            VC13_TILT_DEG,
            centre,
            100.0,
            if ctx.quick { 2.0 } else { 0.25 },
        )?;
        let vc12 = spin_point(VC12_TILT_DEG, VC12_SPIN_REV_S, centre)?;
        let vc12_no_spin = spin_point(VC12_TILT_DEG, 0.0, centre)?;
        let counts = spin_counts(centre, &g.curve_spins)?;
        results.push(CentreResult {
            centre,
            map,
            threshold,
            vc12,
            vc12_no_spin,
            counts,
        });
    }
    write(ctx, &g, &results)?;
    Ok(report(&g, &results))
}

/// First spin of the map (per tilt) whose first contact skips.
fn map_threshold(g: &SpinGrid, map: &[SpinPoint], tilt: f64) -> Option<f64> {
    g.spins.iter().copied().find(|&s| {
        map.iter()
            .any(|p| p.tilt == tilt && p.rev_s == s && p.first_skip)
    })
}

fn write(ctx: &Ctx, g: &SpinGrid, results: &[CentreResult]) -> Result<(), StudyError> {
    let mut csv = Csv::new(&[
        "centre",
        "tilt_deg",
        "spin_rev_s",
        "skips",
        "first_skip",
        "first_contact_s",
        "inclination_change_deg",
        "axis_turn_deg",
        "capped",
    ]);
    for r in results {
        for p in &r.map {
            csv.push(vec![
                centre_key(r.centre).into(),
                p.tilt.into(),
                p.rev_s.into(),
                p.skips.into(),
                p.first_skip.into(),
                p.first_duration.into(),
                p.inclination_change.into(),
                p.axis_turn.into(),
                p.capped.into(),
            ]);
        }
    }
    ctx.write_csv("spin_map.csv", &csv)?;
    let mut ccsv = Csv::new(&[
        "centre",
        "spin_rev_s",
        "skips",
        "rebounds",
        "distance_m",
        "lateral_m",
    ]);
    for r in results {
        for p in &r.counts {
            ccsv.push(vec![
                centre_key(r.centre).into(),
                p.rev_s.map_or("locked".into(), |s| sig(s, 4)).into(),
                p.skips.into(),
                p.rebounds.into(),
                p.distance.into(),
                p.lateral.into(),
            ]);
        }
    }
    ctx.write_csv("spin_counts.csv", &ccsv)?;

    let tilt_edges = half_steps(&g.tilts);
    let spin_edges = half_steps(&g.spins);
    let mut panels = Vec::new();
    for r in results {
        let cells: Vec<Cell> = r
            .map
            .iter()
            .filter_map(|p| {
                let i = g.tilts.iter().position(|t| *t == p.tilt)?;
                let j = g.spins.iter().position(|s| *s == p.rev_s)?;
                Some(Cell {
                    x0: tilt_edges[i].0,
                    x1: tilt_edges[i].1,
                    y0: spin_edges[j].0,
                    y1: spin_edges[j].1,
                    class: skip_class(p.skips),
                })
            })
            .collect();
        let threshold: Vec<(f64, f64)> = g
            .tilts
            .iter()
            .filter_map(|&t| map_threshold(g, &r.map, t).map(|s| (t, s)))
            .collect();
        // One revolution per contact: Ω = 1/τ with τ the first contact's duration at that tilt
        // and the threshold spin.
        let one_rev: Vec<(f64, f64)> = g
            .tilts
            .iter()
            .filter_map(|&t| {
                let s = map_threshold(g, &r.map, t)?;
                let p = r.map.iter().find(|p| p.tilt == t && p.rev_s == s)?;
                (p.first_duration > 0.0).then(|| (t, 1.0 / p.first_duration))
            })
            .collect();
        panels.push(Panel::Heat(Heatmap {
            title: format!("pressure at {}", centre_name(r.centre)),
            x_label: "tilt (attack angle) α (°)".into(),
            y_label: "spin Ω (rev/s)".into(),
            x_range: (
                tilt_edges.first().map_or(0.0, |e| e.0),
                tilt_edges.last().map_or(50.0, |e| e.1),
            ),
            y_range: (
                spin_edges.first().map_or(0.0, |e| e.0),
                spin_edges.last().map_or(100.0, |e| e.1),
            ),
            cells,
            classes: skip_classes(),
            overlays: vec![
                Series::new(
                    "spin threshold (first contact skips)",
                    threshold,
                    colors::BLACK,
                    Mark::LinePoints,
                ),
                Series::new(
                    "one revolution per contact (Ωτ = 1)",
                    one_rev,
                    colors::ORANGE,
                    Mark::Dashed,
                ),
            ],
            lines: vec![],
            legend: Legend::UpperRight,
        }));
    }
    plot::draw(
        &ctx.path("spin_tilt.png"),
        (1800, 760),
        2,
        Some("Skips of Clanet's disc over spin × tilt (U 3.5 m/s, β 20°, free rotation)"),
        &panels,
    )?;

    let mut chart = Chart::new(
        "typical stone (R 5 cm, 150 g, 12 m/s, α 15°): skips against spin",
        "spin Ω (rev/s)",
        "skips",
    )
    .log_x()
    .log_y()
    .x_range(1.5, 200.0)
    .y_range(0.5, 100.0)
    .legend(Legend::UpperLeft);
    let spins = &g.curve_spins;
    for (r, c) in results.iter().zip([colors::BLUE, colors::RED]) {
        chart = chart.series(Series::new(
            format!("skips, free rotation, {}", centre_name(r.centre)),
            log_curve(&r.counts, |p| p.skips as f64),
            c,
            Mark::LinePoints,
        ));
        chart = chart.series(Series::new(
            format!("rebounds, {}", centre_key(r.centre)),
            log_curve(&r.counts, |p| p.rebounds as f64),
            c,
            Mark::Dashed,
        ));
        if let Some(l) = r.counts.iter().find(|p| p.rev_s.is_none()) {
            chart = chart.line(RefLine::h(
                format!("locked attitude, {}: {}", centre_key(r.centre), l.skips),
                l.skips as f64,
                c,
            ));
        }
    }
    let g_acc = 9.81;
    let bocquet: Vec<(f64, f64)> = spins
        .iter()
        .map(|&s| (s, TYPICAL_RADIUS * (s * REV).powi(2) / g_acc))
        .filter(|p| p.1 >= 0.5 && p.1 <= 100.0)
        .collect();
    chart = chart.series(Series::new(
        "Bocquet (reported): N = Rω²/g",
        bocquet,
        colors::GREY,
        Mark::Dashed,
    ));
    plot::draw(
        &ctx.path("spin_count.png"),
        (1100, 700),
        1,
        None,
        &[Panel::Chart(chart)],
    )
}

/// (spin, value) of the free-rotation runs whose value can stand on a log axis (> 0).
fn log_curve(counts: &[CountPoint], value: impl Fn(&CountPoint) -> f64) -> Vec<(f64, f64)> {
    counts
        .iter()
        .filter_map(|p| Some((p.rev_s?, value(p))))
        .filter(|p| p.1 > 0.0)
        .collect()
}

/// Steps between neighbouring free-rotation spins where more spin gave less of `value`.
fn drops(counts: &[CountPoint], value: impl Fn(&CountPoint) -> f64) -> usize {
    counts
        .windows(2)
        .filter(|w| w[0].rev_s.is_some() && w[1].rev_s.is_some())
        .filter(|w| value(&w[1]) < value(&w[0]))
        .count()
}

fn report(g: &SpinGrid, results: &[CentreResult]) -> String {
    let mut s = String::from("## Spin axis: the stone as a free rigid body\n\n");
    s.push_str(&format!(
        "`rotation: Free`, Rosellini law. Map: Clanet's disc at U {MAP_SPEED} m/s, β {MAP_BETA_DEG}°, tilt {}–{}°, spin {}–{} rev/s; a cell counts the skips of the whole run. Two models of where the pressure acts (only the torque differs): at each wetted face's centroid (the paper's eqs. 25–26, the default), and at Savitsky's planing centre, 0.75 of the wetted length ahead of its trailing edge (`physics.pressure_centre: Planing(0.75)`). Published (VC-12, VC-13): without spin the disc pitches nose-down and dives; about one revolution per contact is enough to skip; at 65 rev/s, α = β = 20°, α stays nearly constant through the contact.\n\n",
        g.tilts.first().copied().unwrap_or(0.0),
        g.tilts.last().copied().unwrap_or(0.0),
        g.spins.first().copied().unwrap_or(0.0),
        g.spins.last().copied().unwrap_or(0.0),
    ));
    let mut rows = Vec::new();
    for r in results {
        let thr = r
            .threshold
            .map_or("none up to 100 rev/s".into(), |(w, tau)| {
                format!(
                    "{} rev/s; contact {} ms: {} rev per contact",
                    sig(w, 3),
                    sig(tau * 1e3, 3),
                    sig(w * tau, 2)
                )
            });
        let v = &r.vc12;
        let v0 = &r.vc12_no_spin;
        rows.push(vec![
            centre_name(r.centre),
            thr,
            format!(
                "{}: inclination {:+.1}°, axis turn {:.1}°",
                if v.first_skip { "skips" } else { "no skip" },
                v.inclination_change,
                v.axis_turn
            ),
            format!(
                "{}: inclination {:+.1}°",
                if v0.first_skip { "skips" } else { "dives" },
                v0.inclination_change
            ),
        ]);
    }
    s.push_str(&md_table(
        &[
            "pressure centre",
            "spin threshold at α = 35° (VC-13)",
            "VC-12: 65 rev/s, α = β = 20°, first contact",
            "same without spin",
        ],
        &rows,
    ));
    s.push_str("\nThe inclination is the angle between the stone's plane and the water (Clanet's α seen from the side); the axis turn is the whole change of the axis direction. At 65 rev/s almost all of the turn is a change of azimuth — gyroscopic precession of the nose-down torque into bank — while the inclination barely moves; without spin the same torque pitches the stone nose-down.\n\n![spin tilt](spin_tilt.png)\n\n");
    s.push_str("### Spin-limited count\n\n");
    let mut rows = Vec::new();
    for r in results {
        let locked = r
            .counts
            .iter()
            .find(|p| p.rev_s.is_none())
            .map_or(0, |p| p.rebounds);
        let (lim, alone) = spin_limited(&r.counts);
        let p = fit_exponent(&lim);
        let p_alone = fit_exponent(&alone);
        let range = match (lim.first(), lim.last()) {
            (Some(a), Some(b)) => format!("{}–{} rev/s", sig(a.0, 3), sig(b.0, 3)),
            _ => "–".into(),
        };
        let mono = drops(&r.counts, |p| p.skips as f64);
        let mono_r = drops(&r.counts, |p| p.rebounds as f64);
        let mono_d = drops(&r.counts, |p| p.distance);
        rows.push(vec![
            centre_name(r.centre),
            locked.to_string(),
            range,
            p.map_or("–".into(), |p| sig(p, 2)),
            p_alone.map_or("–".into(), |p| sig(p, 2)),
            format!("{mono} (rebounds: {mono_r}; distance: {mono_d})"),
        ]);
    }
    s.push_str(&md_table(
        &[
            "pressure centre",
            "locked (the high-spin limit): rebounds",
            "spin-limited range (2 ≤ N ≤ N_L/2)",
            "fitted p in N ∝ Ω^p",
            "p of the spin limit alone, N_spin = N·N_L/(N_L − N)",
            "steps where more spin gave fewer skips",
        ],
        &rows,
    ));
    s.push_str("\nBocquet reports N_spin ∝ ω² (N ≈ Rω²/g fits the press figures of 5, 15 and 38 skips at 5, 9 and 14 rev/s). This rigid-body model does not give it: the angular impulse of each contact turns the axis by about J/(I₃ω), in the same sense every time (the lift always acts behind the centre of mass), so the attitude drifts coherently and the spin limit grows about linearly with the spin (the raw count less, since the slowing stone uses up its speed limit at the same time). An ω² law needs the per-contact kicks to add like a random walk (√N growth of the drift), for which the model has no source. The model's stone is also much less stable than the reported throws: at 14 rev/s it makes one or two skips where the press reports 38.\n\nRebounds are contacts the stone leaves rising; a skip also counts a graze, where a wobbling stone rocks off the surface while still sinking. With the pressure at the faces, more spin never gave fewer rebounds or a shorter run. With the planing centre the count rises to a peak at 20–30 rev/s and falls again before it grows: the centre ahead of the centre of mass on a deeply wetted, nearly flat stone makes a nose-up moment that rights it, and at low spin the stone rocks back up between hops (the \"trout\" regime of VC-13), which stiffer gyroscopes suppress.\n\n![spin count](spin_count.png)\n");
    s
}
