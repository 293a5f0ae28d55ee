//! The phase study's spin axis (issue 6; physics.md §1.7, §7.3, VC-12, VC-13): the stone as a free
//! rigid body. Three parts:
//!
//! * **Spin × tilt map.** Skips of Clanet's disc (Clanet, Hersen & Bocquet, Nature 2004) thrown at
//!   U = 3.5 m/s, β = 20° under `rotation: Free`, over spin and tilt, with the pressure at the faces
//!   (the paper's eqs. 25–26; Savitsky's planing centre, compared here before, is retired and its
//!   rows are kept in docs/studies/retired.md). The spin
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

use stoneskip_physics::sim::params::{ForceLaw, Preset, Rotation};
use stoneskip_physics::sim::scenario::{at_impact, IMPACT_CLEARANCE};
use stoneskip_physics::sim::Simulation;

use super::throws::{clanet_disc, EVAL_CAP};
use super::{check_cancel, linspace_step, logspace, Ctx, StudyError};

mod report;

pub use stoneskip_physics::sim::metrics::fit_exponent;
pub use stoneskip_physics::sim::scenario::{typical, TYPICAL_RADIUS};
pub use stoneskip_physics::sim::stone::{axis_from_reported as axis, inclination};

pub const REV: f64 = std::f64::consts::TAU;

/// Speed and impact angle of the map and of VC-12 (Clanet's reference throw).
pub const MAP_SPEED: f64 = 3.5;
pub const MAP_BETA_DEG: f64 = 20.0;
/// VC-12: α = β = 20° at 65 rev/s.
pub const VC12_TILT_DEG: f64 = 20.0;
pub const VC12_SPIN_REV_S: f64 = 65.0;
/// VC-13's tilt, at which the spin threshold is located precisely.
pub const VC13_TILT_DEG: f64 = 35.0;

/// Where the pressure acts, as the tables and charts name it: at each wetted face's centroid (the
/// only model since the planing centre was retired: docs/studies/retired.md).
pub const CENTRE_NAME: &str = "faces (area centroids)";
/// [`CENTRE_NAME`] in the CSVs' `centre` column.
pub const CENTRE_KEY: &str = "faces";

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
pub fn clanet_spun(tilt: f64, rev_s: f64) -> Result<Preset, StudyError> {
    let mut p = clanet_disc(ForceLaw::Rosellini, tilt);
    p.physics.rotation = Rotation::Free;
    p.launch.spin = rev_s * REV;
    Ok(at_impact(
        &p,
        MAP_SPEED,
        MAP_BETA_DEG.to_radians(),
        IMPACT_CLEARANCE,
    )?)
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
pub fn spin_point(tilt: f64, rev_s: f64) -> Result<SpinPoint, StudyError> {
    let p = clanet_spun(tilt, rev_s)?;
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
pub fn spin_map(g: &SpinGrid) -> Result<Vec<SpinPoint>, StudyError> {
    let throws: Vec<(f64, f64)> = g
        .tilts
        .iter()
        .flat_map(|&t| g.spins.iter().map(move |&s| (t, s)))
        .collect();
    throws
        .par_iter()
        .map(|&(t, s)| {
            check_cancel()?;
            spin_point(t, s)
        })
        .collect()
}

/// Smallest spin (rev/s) in [0, `hi`] whose first contact skips at `tilt`, by bisection to `tol`
/// rev/s, with that contact's duration (s). `None` when `hi` does not skip.
pub fn spin_threshold(tilt: f64, hi: f64, tol: f64) -> Result<Option<(f64, f64)>, StudyError> {
    let first = |s: f64| -> Result<(bool, f64), StudyError> {
        let p = clanet_spun(tilt, s)?;
        let c = stoneskip_physics::sim::scenario::first_contact(&p)?;
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
pub fn spin_counts(spins: &[f64]) -> Result<Vec<CountPoint>, StudyError> {
    let mut runs: Vec<Option<f64>> = spins.iter().map(|&s| Some(s)).collect();
    runs.push(None);
    runs.par_iter()
        .map(|&rev_s| {
            check_cancel()?;
            let s = stoneskip_physics::sim::simulate(&typical(rev_s))?;
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

/// Everything the spin part measures.
#[derive(Debug, Clone)]
pub struct SpinResult {
    pub map: Vec<SpinPoint>,
    /// Spin threshold at VC-13's tilt: (rev/s, first-contact duration s).
    pub threshold: Option<(f64, f64)>,
    pub vc12: SpinPoint,
    pub vc12_no_spin: SpinPoint,
    pub counts: Vec<CountPoint>,
}

/// Runs the spin part, writes its CSV and charts; returns the Markdown section the phase report
/// appends.
pub fn run(ctx: &Ctx) -> Result<String, StudyError> {
    let g = grid(ctx.quick);
    ctx.progress(&format!(
        "spin: spin × tilt map ({} runs)",
        g.tilts.len() * g.spins.len()
    ));
    let map = spin_map(&g)?;
    ctx.progress("spin: threshold, VC-12, spin-limited count");
    let threshold = spin_threshold(VC13_TILT_DEG, 100.0, if ctx.quick { 2.0 } else { 0.25 })?;
    let vc12 = spin_point(VC12_TILT_DEG, VC12_SPIN_REV_S)?;
    let vc12_no_spin = spin_point(VC12_TILT_DEG, 0.0)?;
    let counts = spin_counts(&g.curve_spins)?;
    let results = [SpinResult {
        map,
        threshold,
        vc12,
        vc12_no_spin,
        counts,
    }];
    report::write(ctx, &g, &results)
}
