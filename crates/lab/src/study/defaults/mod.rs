//! Defaults study (design.md §8: "defaults are the cheapest settings whose error is under 1 % on the
//! chart"): for the Adaptive tolerance, the tick dt, the mesh's rim segments and the water cell,
//! the cheapest value whose error stays under 1 % — at that value and every finer one — on the
//! accuracy study's three throws, then a check of the chosen settings together, and a comparison
//! with `Preset::version_1()` and the shipped presets (`assets/presets/*.ron`).

use rayon::prelude::*;

use stoneskip_physics::sim::params::{Integrator, Preset};

use super::accuracy::{
    self, errors, measure, throw_preset, Errors, MeshPoint, Setting, WaterPoint, REF_TICK,
    REF_TOLERANCE,
};
use super::throws::{self, throw_list, Throw};
use super::{check_cancel, Ctx, StudyError};

mod report;

/// The error bound of the defaults.
pub const TARGET: f64 = 0.01;

/// One run of a knob on a throw.
#[derive(Debug, Clone)]
pub struct KnobPoint {
    pub throw: Throw,
    pub setting: Setting,
    pub value: f64,
    pub force_evals: u64,
    pub wall_per_sim_s: f64,
    pub err: Errors,
}

/// Runs `settings` on every throw against the references (Adaptive at 1e-12).
fn knob_sweep(
    references: &[(Throw, accuracy::RunStats)],
    settings: &[Setting],
    value: impl Fn(&Setting) -> f64 + Sync,
) -> Result<Vec<KnobPoint>, StudyError> {
    let jobs: Vec<(usize, Setting)> = (0..references.len())
        .flat_map(|k| settings.iter().map(move |s| (k, *s)))
        .collect();
    jobs.par_iter()
        .map(|(k, s)| {
            check_cancel()?;
            let (t, r) = &references[*k];
            let stats = measure(&throw_preset(t, s)?)?;
            Ok(KnobPoint {
                throw: *t,
                setting: *s,
                value: value(s),
                force_evals: stats.force_evals,
                wall_per_sim_s: stats.wall_per_sim_s(),
                err: errors(&stats, r),
            })
        })
        .collect()
}

/// The cheapest value: the one, among those where every throw is under the target at that value
/// and every finer one, that is coarsest. `finer_is_smaller`: finer values are smaller numbers.
pub fn cheapest<T: Copy>(
    values: &[f64],
    ok_at: impl Fn(f64) -> Option<T>,
    finer_is_smaller: bool,
) -> Option<(f64, T)> {
    let mut v: Vec<f64> = values.to_vec();
    v.sort_by(|a, b| {
        if finer_is_smaller {
            a.total_cmp(b)
        } else {
            b.total_cmp(a)
        }
    });
    let mut best = None;
    for x in v {
        match ok_at(x) {
            Some(t) => best = Some((x, t)),
            None => break,
        }
    }
    best
}

pub fn worst_at(points: &[KnobPoint], value: f64) -> f64 {
    points
        .iter()
        .filter(|p| p.value == value)
        .map(|p| p.err.worst())
        .fold(0.0, f64::max)
}

pub fn evals_at(points: &[KnobPoint], value: f64) -> u64 {
    points
        .iter()
        .filter(|p| p.value == value)
        .map(|p| p.force_evals)
        .sum()
}

/// The recommended settings.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Recommendation {
    /// Cheapest (tolerance, tick) with the tick at most one 60 Hz frame.
    pub tolerance: Option<f64>,
    pub tick: Option<f64>,
    /// Cheapest (tolerance, tick) over every swept tick, and its force evaluations.
    pub free: Option<(f64, f64, u64)>,
    pub segments: Option<u32>,
    pub cell: Option<f64>,
    pub cell_10pct: Option<f64>,
}

/// Settings of the shipped presets.
#[derive(Debug, Clone)]
pub struct Shipped {
    pub name: String,
    pub integrator: Integrator,
    pub tolerance: f64,
    pub dt: f64,
    pub segments: u32,
    pub cell: f64,
    pub water: bool,
    /// The stone is a lens (the shape the segments were swept for).
    pub lens: bool,
}

fn shipped_of(name: &str, p: &Preset) -> Shipped {
    Shipped {
        name: name.to_owned(),
        integrator: p.physics.integrator,
        tolerance: p.physics.tolerance,
        dt: p.physics.dt,
        segments: p.stone.segments,
        cell: p.water.cell,
        water: p.water.enabled,
        lens: matches!(
            p.stone.shape,
            stoneskip_physics::sim::params::Shape::Lens { .. }
        ),
    }
}

/// `Preset::version_1()` and every shipped preset (`assets/presets`, as compiled in), in file-name
/// order.
pub fn shipped_presets() -> Vec<Shipped> {
    let mut out = vec![shipped_of("Preset::version_1()", &Preset::version_1())];
    let mut stems: Vec<&str> = stoneskip_physics::preset::SHIPPED
        .iter()
        .map(|(s, _)| *s)
        .collect();
    stems.sort_unstable();
    for stem in stems {
        if let Some(Ok(p)) = stoneskip_physics::preset::shipped(stem) {
            out.push(shipped_of(&format!("{stem}.ron"), &p));
        }
    }
    out
}

/// One 60 Hz frame (s): the longest tick the app can show without dropping to a slower pace.
pub const FRAME: f64 = 1.0 / 60.0;

pub fn tolerances(quick: bool) -> Vec<f64> {
    if quick {
        vec![1e-3, 1e-5, 1e-7]
    } else {
        vec![1e-3, 3e-4, 1e-4, 3e-5, 1e-5, 3e-6, 1e-6, 1e-7, 1e-8]
    }
}

pub fn ticks(quick: bool) -> Vec<f64> {
    if quick {
        vec![0.05, 0.01, 2e-3, 5e-4]
    } else {
        vec![0.05, 0.02, FRAME, 0.01, 5e-3, 2e-3, 1e-3, 5e-4]
    }
}

pub fn worst_of(points: &[KnobPoint], tick: f64, tol: f64) -> f64 {
    points
        .iter()
        .filter(|p| p.setting.dt == tick && p.setting.tolerance == tol)
        .map(|p| p.err.worst())
        .fold(0.0, f64::max)
}

pub fn evals_of(points: &[KnobPoint], tick: f64, tol: f64) -> u64 {
    points
        .iter()
        .filter(|p| p.setting.dt == tick && p.setting.tolerance == tol)
        .map(|p| p.force_evals)
        .sum()
}

/// The cheapest (tolerance, tick, force evals) with tick ≤ `max_tick` whose worst error is under
/// the target there and at every finer pair (smaller or equal tick and tolerance).
pub fn best_pair(
    points: &[KnobPoint],
    ticks: &[f64],
    tols: &[f64],
    max_tick: f64,
) -> Option<(f64, f64, u64)> {
    let mut best: Option<(f64, f64, u64)> = None;
    for &tk in ticks.iter().filter(|&&t| t <= max_tick * (1.0 + 1e-9)) {
        for &tl in tols {
            let robust = ticks.iter().filter(|&&t| t <= tk).all(|&t| {
                tols.iter()
                    .filter(|&&l| l <= tl)
                    .all(|&l| worst_of(points, t, l) < TARGET)
            });
            if !robust {
                continue;
            }
            let e = evals_of(points, tk, tl);
            if best.is_none_or(|b| e < b.2) {
                best = Some((tl, tk, e));
            }
        }
    }
    best
}

/// A fixed-step scheme's sweep: (integrator, largest step under 1 %, its force evaluations, runs).
pub type FixedResult = (Integrator, Option<f64>, Option<u64>, Vec<KnobPoint>);

/// Each throw with the chosen settings: (throw, errors, force evals, wall s per sim s).
pub type ComboRun = (Throw, Errors, u64, f64);

/// Everything the defaults study computes.
#[derive(Debug, Clone)]
pub struct Results {
    pub rec: Recommendation,
    /// Adaptive over tolerance × tick, every throw.
    pub grid: Vec<KnobPoint>,
    pub fixed: Vec<FixedResult>,
    pub mesh: Vec<MeshPoint>,
    /// The finest (reference) rim resolution.
    pub finest: u32,
    pub water: Vec<WaterPoint>,
    pub combo: Vec<ComboRun>,
}

/// The references of the throws: Adaptive at 1e-12.
fn references(ctx: &Ctx) -> Result<Vec<(Throw, accuracy::RunStats)>, StudyError> {
    let mut refs = Vec::new();
    for t in &throw_list(ctx.quick) {
        ctx.progress(&format!("reference of the {} throw", t.key));
        let s = Setting {
            integrator: Integrator::Adaptive,
            dt: REF_TICK,
            tolerance: REF_TOLERANCE,
            across: false,
        };
        refs.push((*t, measure(&throw_preset(t, &s)?)?));
    }
    Ok(refs)
}

/// 1–2. Tolerance × tick of the Adaptive integrator.
fn adaptive_grid(
    ctx: &Ctx,
    refs: &[(Throw, accuracy::RunStats)],
) -> Result<Vec<KnobPoint>, StudyError> {
    ctx.progress("Adaptive tolerance × tick");
    let tols = tolerances(ctx.quick);
    let grid_set: Vec<Setting> = ticks(ctx.quick)
        .iter()
        .flat_map(|&dt| {
            tols.iter().map(move |&tolerance| Setting {
                integrator: Integrator::Adaptive,
                dt,
                tolerance,
                across: false,
            })
        })
        .collect();
    knob_sweep(refs, &grid_set, |s| s.tolerance)
}

/// 3. Fixed-step schemes: their largest step under 1 %, for the cost comparison.
fn fixed_sweeps(
    ctx: &Ctx,
    refs: &[(Throw, accuracy::RunStats)],
) -> Result<Vec<FixedResult>, StudyError> {
    ctx.progress("fixed-step schemes under 1 %");
    let mut fixed = Vec::new();
    for i in [
        Integrator::Paper,
        Integrator::SymplecticEuler,
        Integrator::Rk4,
    ] {
        // RK4 meets 1 % at millisecond steps (accuracy study); the first-order schemes need
        // tens of microseconds.
        let fixed_dts: Vec<f64> = match (ctx.quick, i) {
            (true, _) => vec![1e-3, 2e-4, 5e-5],
            (false, Integrator::Rk4) => super::logspace(1e-4, 5e-3, 6),
            (false, _) => super::logspace(1e-5, 2e-3, 7),
        };
        let set: Vec<Setting> = fixed_dts
            .iter()
            .map(|&dt| Setting {
                integrator: i,
                dt,
                tolerance: 1e-6,
                across: false,
            })
            .collect();
        let pts = knob_sweep(refs, &set, |s| s.dt)?;
        let pick = cheapest(
            &fixed_dts,
            |v| (worst_at(&pts, v) < TARGET).then_some(()),
            true,
        )
        .map(|p| p.0);
        fixed.push((i, pick, pick.map(|d| evals_at(&pts, d)), pts));
    }
    Ok(fixed)
}

/// 4. The cheapest rim resolution under 1 % (the finest swept is the reference).
fn pick_segments(mesh: &[MeshPoint], segs: &[u32], finest: u32) -> Option<u32> {
    let mesh_ok = |n: f64| {
        let w = mesh
            .iter()
            .filter(|m| f64::from(m.segments) == n)
            .map(|m| m.err.worst())
            .fold(0.0, f64::max);
        (w < TARGET).then_some(())
    };
    let seg_values: Vec<f64> = segs
        .iter()
        .filter(|&&n| n != finest)
        .map(|&n| f64::from(n))
        .collect();
    cheapest(&seg_values, mesh_ok, false).map(|p| p.0 as u32)
}

/// 5. The cheapest water cell whose averaged η error is under `tol` (the finest is the reference).
fn pick_cell(water: &[WaterPoint], tol: f64) -> Option<f64> {
    let wref = water.last().map_or(0.0, |w| w.cell);
    let cells: Vec<f64> = water
        .iter()
        .map(|w| w.cell)
        .filter(|c| *c != wref)
        .collect();
    let ok = |c: f64| {
        water
            .iter()
            .find(|w| w.cell == c)
            .filter(|w| w.eta_smooth_err < tol)
            .map(|_| ())
    };
    cheapest(&cells, ok, true).map(|p| p.0)
}

/// Runs every sweep, picks the cheapest settings and checks them together.
pub fn compute(ctx: &Ctx) -> Result<Results, StudyError> {
    let quick = ctx.quick;
    let refs = references(ctx)?;
    let grid = adaptive_grid(ctx, &refs)?;
    let (tols, ticks) = (tolerances(quick), ticks(quick));
    let framed = best_pair(&grid, &ticks, &tols, FRAME);
    let free = best_pair(&grid, &ticks, &tols, f64::INFINITY);
    let fixed = fixed_sweeps(ctx, &refs)?;
    // 4. Mesh and 5. water, from the accuracy study's sweeps.
    ctx.progress("mesh resolution");
    let mesh = accuracy::mesh_sweep(ctx, &throw_list(quick))?;
    let segs = accuracy::mesh_segments(quick);
    let finest = segs.last().copied().unwrap_or(32);
    ctx.progress("water cell");
    let water = accuracy::water_sweep(ctx)?;
    let rec = Recommendation {
        tolerance: framed.map(|p| p.0),
        tick: framed.map(|p| p.1),
        free,
        segments: pick_segments(&mesh, &segs, finest),
        cell: pick_cell(&water, TARGET),
        cell_10pct: pick_cell(&water, 0.1),
    };
    // 6. The chosen settings together, against the fine reference (finest mesh, tolerance 1e-12).
    ctx.progress("check of the chosen settings together");
    let combo = combined_check(&rec, &mesh, finest, quick)?;
    Ok(Results {
        rec,
        grid,
        fixed,
        mesh,
        finest,
        water,
        combo,
    })
}

/// Computes the study and writes its CSV, chart and report.
pub fn run(ctx: &Ctx) -> Result<(), StudyError> {
    let res = compute(ctx)?;
    report::write(ctx, &res)
}

/// Each throw with the recommended tolerance, tick and segments against the finest mesh at
/// tolerance 1e-9 (the mesh sweep's reference runs): (throw, errors, force evals, wall s per sim s).
fn combined_check(
    rec: &Recommendation,
    mesh: &[MeshPoint],
    finest: u32,
    quick: bool,
) -> Result<Vec<ComboRun>, StudyError> {
    throw_list(quick)
        .par_iter()
        .map(|t| {
            let r = mesh
                .iter()
                .find(|m| m.throw.key == t.key && m.segments == finest)
                .map(|m| m.stats.clone())
                .ok_or_else(|| {
                    StudyError::Failed(format!("no {finest}-segment run of {}", t.key))
                })?;
            let mut b = throws::base(
                Integrator::Adaptive,
                rec.tick.unwrap_or_else(accuracy::shipped_tick),
                rec.tolerance.unwrap_or(1e-6),
            );
            b.stone.segments = rec.segments.unwrap_or(32);
            let s = measure(&throws::preset(t, &b)?)?;
            Ok((*t, errors(&s, &r), s.force_evals, s.wall_per_sim_s()))
        })
        .collect()
}
