//! Phase study: the skipping domain of Clanet, Hersen & Bocquet (Nature 427, 29, 2004) and
//! Rosellini et al. (JFM 543, 2005) for their aluminium disc (R 2.5 cm, e 2.75 mm, 14.579 g) at
//! fixed attitude (the high-spin limit), water off: number of skips over tilt × speed (β = 20°,
//! their Fig. 1b) and tilt × impact angle (U = 3.5 m/s, Fig. 1c), under each force law; the
//! minimal speed per tilt beside the published magic angle (~20°), the measured ~2.5 m/s and the
//! 2D model's 2.3 m/s (physics.md §3, VC-8, VC-11), and the largest impact angle (~45° measured).
//!
//! Runs are independent and deterministic; they go over the cores with rayon and are collected in
//! grid order, so the results do not depend on the thread count.

use rayon::prelude::*;

use stoneskip_physics::sim::params::ForceLaw;
use stoneskip_physics::sim::params::Preset;
use stoneskip_physics::sim::scenario::{at_impact, first_contact, min_speed, IMPACT_CLEARANCE};
use stoneskip_physics::sim::Simulation;
use stoneskip_reference::{MinSpeedOptions, Plate2d};

use super::style::law_name;
use super::throws::{clanet_disc, EVAL_CAP};

use super::{check_cancel, linspace_step, Ctx, StudyError};

mod report;

/// Impact angle of the tilt × speed map and of the minimal-speed curves (Clanet's Fig. 1b).
pub const BETA_DEG: f64 = 20.0;
/// Speed of the tilt × impact-angle map (Clanet's Fig. 1c).
pub const SPEED_BETA_MAP: f64 = 3.5;

/// The grids of the maps.
#[derive(Debug, Clone)]
pub struct Grid {
    pub tilts: Vec<f64>,
    pub speeds: Vec<f64>,
    pub betas: Vec<f64>,
}

pub fn grid(quick: bool) -> Grid {
    if quick {
        Grid {
            tilts: linspace_step(5.0, 45.0, 10.0),
            speeds: linspace_step(1.0, 7.0, 1.0),
            betas: linspace_step(10.0, 60.0, 10.0),
        }
    } else {
        Grid {
            tilts: linspace_step(5.0, 45.0, 2.5),
            speeds: linspace_step(0.5, 8.0, 0.25),
            betas: linspace_step(2.5, 60.0, 2.5),
        }
    }
}

/// The 2D model (reference.rs) with the same law and coefficients as the 3D defaults, ventilated
/// like the 3D solver.
pub fn plate_2d(law: ForceLaw, tilt_deg: f64) -> Plate2d {
    let (cl, cf) = law.default_coefficients();
    let l2 = match law {
        ForceLaw::Rosellini => stoneskip_reference::ForceLaw::Rosellini { c_l: cl, c_f: cf },
        ForceLaw::Paper => stoneskip_reference::ForceLaw::Newtonian { c_d: cl, c_f: cf },
        ForceLaw::Bocquet => stoneskip_reference::ForceLaw::bocquet(cl, cf),
    };
    Plate2d::clanet_disc(tilt_deg.to_radians())
        .with_law(l2)
        .with_ventilated(true)
}

/// Adaptive tolerance of the phase runs: the shipped 1e-6, but 1e-4 under Bocquet's law. With his
/// C_f = 1 on the light disc, tolerance 1e-6 drives Adaptive to sub-microsecond steps (up to 8e5
/// force evaluations for a 20 ms contact, see the stability study); 1e-4 gives the same skips.
pub fn tolerance(law: ForceLaw) -> f64 {
    match law {
        ForceLaw::Bocquet => 1e-4,
        _ => 1e-6,
    }
}

/// Clanet's disc under `law` at `tilt` (degrees), with the phase tolerance.
pub fn disc(law: ForceLaw, tilt: f64) -> Preset {
    let mut p = clanet_disc(law, tilt);
    p.physics.tolerance = tolerance(law);
    p
}

/// One map cell: the skips of a whole run (water off, 5 s at most).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MapPoint {
    pub law: ForceLaw,
    pub tilt: f64,
    pub speed: f64,
    pub beta: f64,
    pub skips: usize,
    /// Stopped at [`EVAL_CAP`] force evaluations.
    pub capped: bool,
}

/// Skips of the disc at tilt, speed and impact angle (degrees), and whether the run hit the cap.
pub fn skips(law: ForceLaw, tilt: f64, speed: f64, beta: f64) -> Result<(usize, bool), StudyError> {
    let p = at_impact(&disc(law, tilt), speed, beta.to_radians(), IMPACT_CLEARANCE)?;
    let mut sim = Simulation::new(&p)?;
    while !sim.is_finished() && sim.cost().1 < EVAL_CAP {
        sim.tick();
    }
    Ok((sim.skips(), !sim.is_finished()))
}

/// Whether the first contact skips.
pub fn first_skips(law: ForceLaw, tilt: f64, speed: f64, beta: f64) -> Result<bool, StudyError> {
    let p = at_impact(&disc(law, tilt), speed, beta.to_radians(), IMPACT_CLEARANCE)?;
    Ok(first_contact(&p)?.is_some_and(|c| c.skipped))
}

/// The tilt × speed map at β = 20°.
pub fn speed_map(law: ForceLaw, g: &Grid) -> Result<Vec<MapPoint>, StudyError> {
    let throws: Vec<(f64, f64, f64)> = g
        .tilts
        .iter()
        .flat_map(|&t| g.speeds.iter().map(move |&u| (t, u, BETA_DEG)))
        .collect();
    map_throws(law, &throws)
}

/// The tilt × impact-angle map at U = 3.5 m/s.
pub fn beta_map(law: ForceLaw, g: &Grid) -> Result<Vec<MapPoint>, StudyError> {
    let throws: Vec<(f64, f64, f64)> = g
        .tilts
        .iter()
        .flat_map(|&t| g.betas.iter().map(move |&b| (t, SPEED_BETA_MAP, b)))
        .collect();
    map_throws(law, &throws)
}

/// Skips of each (tilt, speed, β) throw, in parallel; the order of `throws` is kept.
fn map_throws(law: ForceLaw, throws: &[(f64, f64, f64)]) -> Result<Vec<MapPoint>, StudyError> {
    throws
        .par_iter()
        .map(|&(tilt, speed, beta)| {
            check_cancel()?;
            let (skips, capped) = skips(law, tilt, speed, beta)?;
            Ok(MapPoint {
                law,
                tilt,
                speed,
                beta,
                skips,
                capped,
            })
        })
        .collect()
}

/// Minimal speed (first contact skips) per tilt at β = 20°, by bisection to `rel_tol`.
pub fn min_speed_curve(
    law: ForceLaw,
    tilts: &[f64],
    rel_tol: f64,
) -> Result<Vec<Option<f64>>, StudyError> {
    tilts
        .par_iter()
        .map(|&t| {
            check_cancel()?;
            Ok(min_speed(
                &disc(law, t),
                BETA_DEG.to_radians(),
                0.3,
                20.0,
                rel_tol,
            )?)
        })
        .collect()
}

/// The 2D model's minimal speed per tilt at β = 20°.
pub fn min_speed_curve_2d(law: ForceLaw, tilts: &[f64]) -> Result<Vec<Option<f64>>, StudyError> {
    let opts = MinSpeedOptions {
        rel_tol: 1e-4,
        u_max: 50.0,
        ..MinSpeedOptions::default()
    };
    tilts
        .par_iter()
        .map(|&t| {
            Ok(stoneskip_reference::min_speed(
                &plate_2d(law, t),
                BETA_DEG.to_radians(),
                &opts,
            )?)
        })
        .collect()
}

/// The largest impact angle (degrees) whose first contact skips at `speed`, by bisection between
/// a skipping `lo` and a failing `hi`, to `tol` degrees.
pub fn max_beta(
    law: ForceLaw,
    tilt: f64,
    speed: f64,
    lo: f64,
    hi: f64,
    tol: f64,
) -> Result<f64, StudyError> {
    let (mut a, mut b) = (lo, hi);
    while b - a > tol {
        let m = 0.5 * (a + b);
        if first_skips(law, tilt, speed, m)? {
            a = m;
        } else {
            b = m;
        }
    }
    Ok(0.5 * (a + b))
}

/// β_max per tilt at U = 3.5 m/s: bracketed by the map (largest skipping β, next β), refined.
pub fn max_beta_curve(
    law: ForceLaw,
    g: &Grid,
    map: &[MapPoint],
    tol: f64,
) -> Result<Vec<Option<f64>>, StudyError> {
    g.tilts
        .par_iter()
        .map(|&t| {
            check_cancel()?;
            let own: Vec<&MapPoint> = map.iter().filter(|m| m.law == law && m.tilt == t).collect();
            let Some(last) = own
                .iter()
                .filter(|m| m.skips > 0)
                .map(|m| m.beta)
                .reduce(f64::max)
            else {
                return Ok(None);
            };
            let next = g.betas.iter().copied().find(|&b| b > last).unwrap_or(80.0);
            if !first_skips(law, t, SPEED_BETA_MAP, last)? {
                return Ok(Some(last));
            }
            Ok(Some(max_beta(law, t, SPEED_BETA_MAP, last, next, tol)?))
        })
        .collect()
}

/// The lowest point of a curve: (tilt, value).
pub fn argmin(tilts: &[f64], v: &[Option<f64>]) -> Option<(f64, f64)> {
    tilts
        .iter()
        .zip(v)
        .filter_map(|(t, u)| u.map(|u| (*t, u)))
        .min_by(|a, b| a.1.total_cmp(&b.1))
}

/// Everything per law.
#[derive(Debug, Clone)]
pub struct LawResult {
    pub law: ForceLaw,
    pub speed_map: Vec<MapPoint>,
    pub beta_map: Vec<MapPoint>,
    pub min_speed: Vec<Option<f64>>,
    pub min_speed_2d: Vec<Option<f64>>,
    pub beta_max: Vec<Option<f64>>,
}

/// Computes the maps and curves of every law, then writes the CSV, charts and report (with the
/// spin section appended).
pub fn run(ctx: &Ctx) -> Result<(), StudyError> {
    let g = grid(ctx.quick);
    let rel_tol = if ctx.quick { 1e-2 } else { 2e-3 };
    let mut results = Vec::new();
    for law in ForceLaw::ALL {
        ctx.progress(&format!(
            "{}: tilt × speed map ({} runs)",
            law_name(law),
            g.tilts.len() * g.speeds.len()
        ));
        let sm = speed_map(law, &g)?;
        ctx.progress(&format!("{}: tilt × impact-angle map", law_name(law)));
        let bm = beta_map(law, &g)?;
        ctx.progress(&format!(
            "{}: minimal speed and largest impact angle per tilt",
            law_name(law)
        ));
        let ms = min_speed_curve(law, &g.tilts, rel_tol)?;
        let ms2 = min_speed_curve_2d(law, &g.tilts)?;
        let bmax = max_beta_curve(law, &g, &bm, if ctx.quick { 1.0 } else { 0.25 })?;
        results.push(LawResult {
            law,
            speed_map: sm,
            beta_map: bm,
            min_speed: ms,
            min_speed_2d: ms2,
            beta_max: bmax,
        });
    }
    report::write(ctx, &g, &results)
}
