//! Accuracy study: work-precision charts (Hairer, Nørsett & Wanner, *Solving ODEs I* §II.10) —
//! error against a converged reference versus cost — for each integrator over step sizes
//! (tolerance for Adaptive), for the mesh resolution and for the water cell size.
//!
//! The reference of a throw is Adaptive at tolerance 1e-12, checked against RK4 at a tiny step.
//! Errors: landing distance (relative), skip count (difference), contact durations (largest
//! relative error over the matched contacts; a skip-count mismatch counts as 100 %) and contact
//! entry times (largest absolute error). Costs: force evaluations per throw (deterministic, the
//! primary measure) and wall-clock time per simulated second (`std::time::Instant`, noisy).

use std::time::Instant;

use rayon::prelude::*;

use stoneskip_physics::sim::params::{Integrator, Preset};
use stoneskip_physics::sim::{simulate, Simulation};

use super::style::{colors, integrator_color, integrator_name, Rgb};
use super::table::sig;
use super::throws::{self, throw_list, Throw};
use super::{check_cancel, logspace, rel_err, Ctx, StudyError};

mod front;
mod report;

pub use front::{Front, FrontPoint};

/// The triangles of a stone's mesh, built alone (a whole `Stone` would build the force kernel's
/// structures too).
pub(super) fn triangles(stone: &stoneskip_physics::sim::params::StoneParams) -> usize {
    stoneskip_physics::sim::stone::build_mesh(&stone.shape, stone.segments, stone.bands)
        .triangles
        .len()
}

/// Error floor for log axes: an exact match is drawn here.
pub const FLOOR: f64 = 1e-12;

/// What one run gives.
#[derive(Debug, Clone, PartialEq)]
pub struct RunStats {
    pub distance: f64,
    pub skips: usize,
    /// Durations of the contacts that ended in a skip (s).
    pub durations: Vec<f64>,
    /// Start times of every contact (s).
    pub starts: Vec<f64>,
    /// Time the outcome was decided (s).
    pub final_time: f64,
    pub force_evals: u64,
    pub steps: u64,
    /// Wall-clock time of the run (s).
    pub wall: f64,
    pub outcome: &'static str,
}

impl RunStats {
    /// Wall-clock seconds per simulated second.
    pub fn wall_per_sim_s(&self) -> f64 {
        self.wall / self.final_time.max(1e-9)
    }
}

/// Runs `p` to its end, timing it.
pub fn measure(p: &Preset) -> Result<RunStats, StudyError> {
    let t0 = Instant::now();
    let s = simulate(p)?;
    let wall = t0.elapsed().as_secs_f64();
    Ok(RunStats {
        distance: s.distance,
        skips: s.skips,
        durations: s
            .contacts
            .iter()
            .filter(|c| c.skip)
            .map(|c| c.t_end - c.t_start)
            .collect(),
        starts: s.contacts.iter().map(|c| c.t_start).collect(),
        final_time: s.final_time,
        force_evals: s.force_evals,
        steps: s.steps,
        wall,
        outcome: s.outcome.map_or("running", |o| o.as_str()),
    })
}

/// Errors of a run against the reference.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Errors {
    /// |d − d_ref| / d_ref.
    pub distance: f64,
    /// skips − skips_ref.
    pub skips: i64,
    /// Largest relative error of the matched contact durations; 1 when the skip counts differ.
    pub contact: f64,
    /// Largest |t_start − t_start_ref| over the matched contacts (s).
    pub entry: f64,
}

impl Errors {
    /// The error the defaults are judged by: the larger of distance and contact errors, and 1
    /// (100 %) when the skip count is wrong.
    pub fn worst(&self) -> f64 {
        if self.skips != 0 {
            1.0
        } else {
            self.distance.max(self.contact)
        }
    }
}

pub fn errors(run: &RunStats, reference: &RunStats) -> Errors {
    let mut contact = run
        .durations
        .iter()
        .zip(&reference.durations)
        .map(|(a, b)| rel_err(*a, *b))
        .fold(0.0, f64::max);
    if run.durations.len() != reference.durations.len() {
        contact = contact.max(1.0);
    }
    let entry = run
        .starts
        .iter()
        .zip(&reference.starts)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max);
    Errors {
        distance: rel_err(run.distance, reference.distance),
        skips: run.skips as i64 - reference.skips as i64,
        contact,
        entry,
    }
}

/// One integrator setting: the step (fixed) or the tick and tolerance (Adaptive).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Setting {
    pub integrator: Integrator,
    pub dt: f64,
    pub tolerance: f64,
    /// Adaptive's contact steps free of the tick (`physics.steps_across_ticks`).
    pub across: bool,
}

impl Setting {
    /// The swept parameter: the step for fixed-step schemes, the tolerance for Adaptive.
    pub fn knob(&self) -> f64 {
        if self.integrator == Integrator::Adaptive {
            self.tolerance
        } else {
            self.dt
        }
    }
    pub fn describe(&self) -> String {
        if self.integrator == Integrator::Adaptive && self.across {
            format!("tol {}, across ticks", sig(self.tolerance, 1))
        } else if self.integrator == Integrator::Adaptive {
            format!("tol {}, tick {} s", sig(self.tolerance, 1), sig(self.dt, 1))
        } else {
            format!("dt {} s", sig(self.dt, 2))
        }
    }

    /// The curve a setting belongs to: the integrator, and for Adaptive its tick.
    pub fn family(&self) -> String {
        if self.integrator == Integrator::Adaptive && self.across {
            "Adaptive, across ticks".to_string()
        } else if self.integrator == Integrator::Adaptive {
            format!("Adaptive, tick {} ms", sig(1e3 * self.dt, 2))
        } else {
            integrator_name(self.integrator).to_string()
        }
    }

    pub fn color(&self) -> Rgb {
        match self.integrator {
            Integrator::Adaptive if self.across => colors::BLACK,
            Integrator::Adaptive if self.dt > 0.02 => colors::PURPLE,
            Integrator::Adaptive if self.dt > 1e-3 => colors::SKY,
            i => integrator_color(i),
        }
    }
}

/// Adaptive's largest tick (the validation bound, `DT_RANGE.1`): the tolerance alone sets its steps.
pub const LONG_TICK: f64 = 0.05;

/// Tick of the reference, mesh and water runs (s): Adaptive's step bound there.
pub const REF_TICK: f64 = 5e-4;

/// The shipped tick (`Preset::version_1()`), Adaptive's step bound in contact.
pub fn shipped_tick() -> f64 {
    Preset::version_1().physics.dt
}
/// Tolerance of the reference runs.
pub const REF_TOLERANCE: f64 = 1e-12;

/// The swept settings of every integrator.
pub fn settings(quick: bool) -> Vec<Setting> {
    let mut v = Vec::new();
    let fixed: Vec<f64> = if quick {
        vec![2e-3, 5e-4, 1e-4]
    } else {
        logspace(2e-5, 5e-3, 8)
    };
    for integrator in [
        Integrator::Paper,
        Integrator::SymplecticEuler,
        Integrator::Rk4,
    ] {
        for &dt in &fixed {
            v.push(Setting {
                integrator,
                dt,
                tolerance: 1e-6,
                across: false,
            });
        }
    }
    let tols: Vec<f64> = if quick {
        vec![1e-3, 1e-5, 1e-7]
    } else {
        (2..=11).map(|k| 10f64.powi(-k)).collect()
    };
    let mut ticks = vec![REF_TICK, shipped_tick(), LONG_TICK];
    ticks.sort_by(f64::total_cmp);
    ticks.dedup();
    for dt in ticks {
        for &tolerance in &tols {
            v.push(Setting {
                integrator: Integrator::Adaptive,
                dt,
                tolerance,
                across: false,
            });
        }
    }
    // The shipped tick with the contact steps free of it (`physics.steps_across_ticks`).
    for &tolerance in &tols {
        v.push(Setting {
            integrator: Integrator::Adaptive,
            dt: shipped_tick(),
            tolerance,
            across: true,
        });
    }
    v
}

/// The curves of the work-precision charts, in drawing order: (family, colour).
pub fn families(settings: &[Setting]) -> Vec<(String, Rgb)> {
    let mut out: Vec<(String, Rgb)> = Vec::new();
    for s in settings {
        let f = s.family();
        if !out.iter().any(|(g, _)| *g == f) {
            out.push((f, s.color()));
        }
    }
    out
}

/// A throw's preset with a setting.
pub fn throw_preset(t: &Throw, s: &Setting) -> Result<Preset, StudyError> {
    let mut base = throws::base(s.integrator, s.dt, s.tolerance);
    base.physics.steps_across_ticks = s.across;
    throws::preset(t, &base)
}

/// The converged reference of a throw and its check.
#[derive(Debug, Clone)]
pub struct Reference {
    pub throw: Throw,
    /// Adaptive at [`REF_TOLERANCE`].
    pub adaptive: RunStats,
    /// RK4 at `rk4_dt`.
    pub rk4: RunStats,
    pub rk4_dt: f64,
}

/// Computes the reference of `t`: Adaptive at 1e-12, and RK4 at 10 µs (100 µs when quick) beside it.
pub fn reference(t: &Throw, quick: bool) -> Result<Reference, StudyError> {
    let rk4_dt = if quick { 1e-4 } else { 1e-5 };
    let a = Setting {
        integrator: Integrator::Adaptive,
        dt: REF_TICK,
        tolerance: REF_TOLERANCE,
        across: false,
    };
    let r = Setting {
        integrator: Integrator::Rk4,
        dt: rk4_dt,
        tolerance: 1e-6,
        across: false,
    };
    let (adaptive, rk4) = rayon::join(
        || measure(&throw_preset(t, &a)?),
        || measure(&throw_preset(t, &r)?),
    );
    Ok(Reference {
        throw: *t,
        adaptive: adaptive?,
        rk4: rk4?,
        rk4_dt,
    })
}

/// One point of a work-precision chart.
#[derive(Debug, Clone)]
pub struct Point {
    pub throw: Throw,
    pub setting: Setting,
    pub stats: RunStats,
    pub err: Errors,
}

/// Runs every setting on a throw (in parallel; each run is single-threaded and deterministic).
pub fn sweep(
    t: &Throw,
    settings: &[Setting],
    reference: &RunStats,
) -> Result<Vec<Point>, StudyError> {
    settings
        .par_iter()
        .map(|s| {
            check_cancel()?;
            let stats = measure(&throw_preset(t, s)?)?;
            let err = errors(&stats, reference);
            Ok(Point {
                throw: *t,
                setting: *s,
                stats,
                err,
            })
        })
        .collect()
}

/// The cheapest point of curve `family` whose `metric` is at most `target` there and at every
/// finer setting of the curve (so a lucky coarse point does not count).
pub fn cheapest_reaching<'a>(
    points: &'a [Point],
    family: &str,
    target: f64,
    metric: impl Fn(&Errors) -> f64,
) -> Option<&'a Point> {
    let mut own: Vec<&Point> = points
        .iter()
        .filter(|p| p.setting.family() == family)
        .collect();
    // From the finest setting to the coarsest: keep going while the target holds.
    own.sort_by(|a, b| a.setting.knob().total_cmp(&b.setting.knob()));
    let mut best = None;
    for p in own {
        if metric(&p.err) <= target {
            best = Some(p);
        } else {
            break;
        }
    }
    best
}

// ------------------------------------------------------------------------------------------------
// Mesh resolution
// ------------------------------------------------------------------------------------------------

/// One mesh-resolution run.
#[derive(Debug, Clone)]
pub struct MeshPoint {
    pub throw: Throw,
    pub segments: u32,
    pub triangles: usize,
    pub stats: RunStats,
    pub err: Errors,
}

/// Rim resolutions swept (the finest is the reference).
pub fn mesh_segments(quick: bool) -> Vec<u32> {
    if quick {
        vec![8, 16, 32]
    } else {
        vec![8, 12, 16, 24, 32, 48, 64, 96, 128, 192]
    }
}

/// Tolerance of the mesh and water runs: integration error well below the resolution errors.
pub const RESOLUTION_TOLERANCE: f64 = 1e-9;

/// Runs each throw at each rim resolution, against the finest.
pub fn mesh_sweep(ctx: &Ctx, throw_list: &[Throw]) -> Result<Vec<MeshPoint>, StudyError> {
    let segs = mesh_segments(ctx.quick);
    let finest = segs.last().copied().unwrap_or(32);
    let mut out = Vec::new();
    for t in throw_list {
        ctx.progress(&format!("mesh resolution: {}", t.key));
        let runs: Vec<(u32, usize, RunStats)> = segs
            .par_iter()
            .map(|&n| {
                check_cancel()?;
                let mut b = throws::base(Integrator::Adaptive, REF_TICK, RESOLUTION_TOLERANCE);
                b.stone.segments = n;
                let tri = triangles(&b.stone);
                Ok((n, tri, measure(&throws::preset(t, &b)?)?))
            })
            .collect::<Result<_, StudyError>>()?;
        let reference = runs
            .iter()
            .find(|r| r.0 == finest)
            .map(|r| r.2.clone())
            .ok_or_else(|| StudyError::Failed("mesh reference missing".into()))?;
        for (segments, triangles, stats) in runs {
            let err = errors(&stats, &reference);
            out.push(MeshPoint {
                throw: *t,
                segments,
                triangles,
                stats,
                err,
            });
        }
    }
    Ok(out)
}

// ------------------------------------------------------------------------------------------------
// Segments and bands
// ------------------------------------------------------------------------------------------------

/// One run of a lens whose latitude bands are set apart from its segments.
#[derive(Debug, Clone)]
pub struct BandsPoint {
    /// The throw's key, or "default" for the shipped default throw with the water off.
    pub case: String,
    pub segments: u32,
    pub bands: u32,
    pub triangles: usize,
    /// `stone.quadrature: Smooth` (meridian × around): the forces on the smooth lens, not on
    /// this mesh's faces.
    pub smooth: Option<(u32, u32)>,
    pub stats: RunStats,
    pub err: Errors,
}

impl BandsPoint {
    pub fn discretisation(&self) -> Discretisation {
        ((self.segments, self.bands), self.smooth)
    }
}

/// What a run sums the forces over: its mesh (segments, bands), or the smooth quadrature's
/// (meridian, around) nodes, the same discretisation whatever mesh draws the stone.
pub type Discretisation = ((u32, u32), Option<(u32, u32)>);

/// Whether a run's discretisation is `key`'s.
pub fn is_discretisation(run: Discretisation, key: Discretisation) -> bool {
    run.1 == key.1 && (key.1.is_some() || run.0 == key.0)
}

/// A discretisation in the reports: `segments × bands`, or `smooth meridian × around`.
pub fn discretisation_name((mesh, smooth): Discretisation) -> String {
    match smooth {
        Some((m, a)) => format!("smooth {m} × {a}"),
        None => format!("{} × {}", mesh.0, mesh.1),
    }
}

/// The smooth quadratures (meridian × around nodes) run beside the meshes of the bands sweep.
pub fn band_smooth(quick: bool) -> Vec<(u32, u32)> {
    if quick {
        vec![(8, 2)]
    } else {
        vec![(8, 2), (10, 2), (12, 2), (16, 2), (12, 6)]
    }
}

/// The (segments, bands) meshes of the bands sweep, the reference first (the finest mesh of
/// [`mesh_segments`] with its default bands). The shipped 64 × 32 is among them.
pub fn band_meshes(quick: bool) -> Vec<(u32, u32)> {
    if quick {
        vec![(32, 16), (16, 4), (16, 8), (24, 8)]
    } else {
        vec![
            (192, 96),
            (64, 32),
            (64, 8),
            (64, 12),
            (64, 16),
            (64, 24),
            (64, 48),
            (32, 32),
            (40, 32),
            (48, 32),
            (48, 24),
            (48, 28),
            (96, 24),
        ]
    }
}

/// The cases of the bands sweep: the study's throws, and (full run) the shipped default throw
/// with the water off (free rotation, smooth axial spin, Archimedes on the wetted faces, the air),
/// at the mesh runs' tick and tolerance.
fn band_cases(ctx: &Ctx, throw_list: &[Throw]) -> Result<Vec<(String, Preset)>, StudyError> {
    let b = throws::base(Integrator::Adaptive, REF_TICK, RESOLUTION_TOLERANCE);
    let mut cases = throw_list
        .iter()
        .map(|t| Ok((t.key.to_string(), throws::preset(t, &b)?)))
        .collect::<Result<Vec<_>, StudyError>>()?;
    if !ctx.quick {
        let mut d = Preset::default();
        d.water.enabled = false;
        d.physics.dt = REF_TICK;
        d.physics.tolerance = RESOLUTION_TOLERANCE;
        cases.push(("default".to_string(), d));
    }
    Ok(cases)
}

/// Runs each case at each mesh of [`band_meshes`], and with each smooth quadrature of
/// [`band_smooth`] on its own mesh, against the first mesh.
pub fn bands_sweep(ctx: &Ctx, throw_list: &[Throw]) -> Result<Vec<BandsPoint>, StudyError> {
    type Setting = (Option<(u32, u32)>, Option<(u32, u32)>);
    let mut settings: Vec<Setting> = band_meshes(ctx.quick)
        .into_iter()
        .map(|m| (Some(m), None))
        .collect();
    settings.extend(band_smooth(ctx.quick).into_iter().map(|s| (None, Some(s))));
    let mut out = Vec::new();
    for (case, preset) in band_cases(ctx, throw_list)? {
        ctx.progress(&format!("segments and bands: {case}"));
        type Run = (u32, u32, usize, Option<(u32, u32)>, RunStats);
        let runs: Vec<Run> = settings
            .par_iter()
            .map(|&(mesh, smooth)| {
                check_cancel()?;
                let mut p = preset.clone();
                if let Some((n, bands)) = mesh {
                    p.stone.segments = n;
                    p.stone.bands = Some(bands);
                }
                if let Some((meridian, around)) = smooth {
                    p.stone.quadrature =
                        stoneskip_physics::sim::params::Quadrature::Smooth { meridian, around };
                }
                let bands =
                    stoneskip_physics::sim::stone::lens_bands(p.stone.segments, p.stone.bands);
                let tri = if smooth.is_some() {
                    0
                } else {
                    triangles(&p.stone)
                };
                Ok((p.stone.segments, bands, tri, smooth, measure(&p)?))
            })
            .collect::<Result<_, StudyError>>()?;
        let reference = runs
            .first()
            .map(|r| r.4.clone())
            .ok_or_else(|| StudyError::Failed("bands reference missing".into()))?;
        for (segments, bands, triangles, smooth, stats) in runs.into_iter().skip(1) {
            let err = errors(&stats, &reference);
            out.push(BandsPoint {
                case: case.clone(),
                segments,
                bands,
                triangles,
                smooth,
                stats,
                err,
            });
        }
    }
    Ok(out)
}

// ------------------------------------------------------------------------------------------------
// Water cell size
// ------------------------------------------------------------------------------------------------

/// The water scene: a throw over a 6 m × 3 m lake, 0.3 m deep, sampled for 1.5 s.
pub const WATER_THROW: Throw = Throw {
    key: "water",
    label: "U 6 m/s, β 10°, α 20° over a 6 m × 3 m lake, 0.3 m deep",
    speed: 6.0,
    beta_deg: 10.0,
    tilt_deg: 20.0,
};

/// One water-resolution run.
#[derive(Debug, Clone)]
pub struct WaterPoint {
    pub cell: f64,
    pub columns: usize,
    pub water_step: f64,
    /// Column updates per simulated second.
    pub column_steps_per_s: f64,
    pub wall_per_sim_s: f64,
    /// η at the probes at the sample times (m).
    pub eta: Vec<f64>,
    /// Relative L2 error of η against the finest grid.
    pub eta_err: f64,
    /// η averaged over a 20 cm square around each probe (what a viewer sees of the rings).
    pub eta_smooth: Vec<f64>,
    /// Relative L2 error of the averaged η against the finest grid.
    pub eta_smooth_err: f64,
    /// Largest |η| seen at the probes (m).
    pub eta_max: f64,
    /// Distance of the throw with `wavy_contact` on, and its relative error.
    pub wavy_distance: f64,
    pub wavy_err: f64,
    pub volume_drift: f64,
}

/// Cell sizes swept (the last is the reference).
pub fn water_cells(quick: bool) -> Vec<f64> {
    if quick {
        vec![0.2, 0.1, 0.05]
    } else {
        // Halving from 16 cm to the finest cell the presets accept (5 mm), plus the built-in 5 cm
        // and the shipped default's 3 cm (issue 39); 2 cm is the other shipped lakes' cell.
        vec![0.16, 0.08, 0.05, 0.04, 0.03, 0.02, 0.01, 0.005]
    }
}

fn water_preset(cell: f64, wavy: bool, quick: bool) -> Result<Preset, StudyError> {
    let mut b = throws::base(Integrator::Adaptive, REF_TICK, RESOLUTION_TOLERANCE);
    b.water.enabled = true;
    b.water.wavy_contact = wavy;
    b.water.cell = cell;
    b.water.depth = 0.3;
    if quick {
        b.water.size = [3.0, 1.5];
        b.water.origin = Some([-0.5, -0.75]);
    } else {
        b.water.size = [6.0, 3.0];
        b.water.origin = Some([-1.0, -1.5]);
    }
    throws::preset(&WATER_THROW, &b)
}

/// Probe points (x, y) and sample times of the water comparison.
fn probes(quick: bool) -> (Vec<(f64, f64)>, Vec<f64>) {
    let (x0, x1, y0, y1, h): (f64, f64, f64, f64, f64) = if quick {
        (-0.4, 2.4, -0.7, 0.7, 0.05)
    } else {
        (-0.9, 4.9, -1.4, 1.4, 0.05)
    };
    let nx = ((x1 - x0) / h).round() as usize;
    let ny = ((y1 - y0) / h).round() as usize;
    let mut p = Vec::with_capacity((nx + 1) * (ny + 1));
    for j in 0..=ny {
        for i in 0..=nx {
            p.push((x0 + h * i as f64, y0 + h * j as f64));
        }
    }
    let times = if quick {
        vec![0.5, 1.0]
    } else {
        vec![0.5, 1.0, 1.5]
    };
    (p, times)
}

/// Runs the water scene at one cell size: η at the probes, cost, and the wavy-contact distance.
fn water_run(cell: f64, quick: bool) -> Result<WaterPoint, StudyError> {
    let (pts, times) = probes(quick);
    let p = water_preset(cell, false, quick)?;
    let mut sim = Simulation::new(&p)?;
    let t0 = Instant::now();
    let mut eta = Vec::with_capacity(pts.len() * times.len());
    let mut eta_smooth = Vec::with_capacity(pts.len() * times.len());
    let tick = p.physics.dt;
    for &t in &times {
        while sim.time() < t - 0.5 * tick {
            sim.tick();
        }
        if let Some(w) = sim.water() {
            eta.extend(pts.iter().map(|&(x, y)| w.surface_height(x, y)));
            eta_smooth.extend(pts.iter().map(|&(x, y)| box_mean(w, x, y)));
        }
        check_cancel()?;
    }
    let wall = t0.elapsed().as_secs_f64();
    let (columns, water_step, volume_drift) = match sim.water() {
        Some(w) => (
            w.nx() * w.ny(),
            w.step_dt(),
            rel_err(
                w.volume(),
                sim.summary().water.map_or(w.volume(), |s| s.volume_initial),
            ),
        ),
        None => (0, 1.0, 0.0),
    };
    let sim_time = sim.time().max(1e-9);
    let wavy = measure(&water_preset(cell, true, quick)?)?;
    Ok(WaterPoint {
        cell,
        columns,
        water_step,
        column_steps_per_s: columns as f64 / water_step,
        wall_per_sim_s: wall / sim_time,
        eta_max: eta.iter().fold(0.0, |m: f64, v| m.max(v.abs())),
        eta,
        eta_err: 0.0,
        eta_smooth,
        eta_smooth_err: 0.0,
        wavy_distance: wavy.distance,
        wavy_err: 0.0,
        volume_drift,
    })
}

/// Runs the water scene at every cell size (one at a time: the water step itself is parallel).
pub fn water_sweep(ctx: &Ctx) -> Result<Vec<WaterPoint>, StudyError> {
    let mut runs = Vec::new();
    for cell in water_cells(ctx.quick) {
        ctx.progress(&format!("water cell {cell} m"));
        runs.push(water_run(cell, ctx.quick)?);
    }
    let Some(reference) = runs.last().cloned() else {
        return Ok(runs);
    };
    for r in &mut runs {
        r.eta_err = rel_l2(&r.eta, &reference.eta);
        r.eta_smooth_err = rel_l2(&r.eta_smooth, &reference.eta_smooth);
        r.wavy_err = rel_err(r.wavy_distance, reference.wavy_distance);
    }
    Ok(runs)
}

/// ‖a − b‖₂ / ‖b‖₂ (0 when b is zero).
fn rel_l2(a: &[f64], b: &[f64]) -> f64 {
    let norm: f64 = b.iter().map(|v| v * v).sum::<f64>().sqrt();
    let diff: f64 = a
        .iter()
        .zip(b)
        .map(|(x, y)| (x - y) * (x - y))
        .sum::<f64>()
        .sqrt();
    if norm > 0.0 {
        diff / norm
    } else {
        0.0
    }
}

/// Width of the averaging square of [`WaterPoint::eta_smooth`] (m).
pub const SMOOTH_WIDTH: f64 = 0.2;

/// Mean of η over a 9 × 9 lattice spanning a [`SMOOTH_WIDTH`] square centred on (x, y).
fn box_mean(w: &stoneskip_physics::sim::water::WaterGrid, x: f64, y: f64) -> f64 {
    let h = SMOOTH_WIDTH / 8.0;
    let mut sum = 0.0;
    for j in -4..=4 {
        for i in -4..=4 {
            sum += w.surface_height(x + h * f64::from(i), y + h * f64::from(j));
        }
    }
    sum / 81.0
}

// ------------------------------------------------------------------------------------------------
// The study
// ------------------------------------------------------------------------------------------------

/// Everything the accuracy study computes (the defaults study reuses it).
#[derive(Debug, Clone)]
pub struct Results {
    pub references: Vec<Reference>,
    pub points: Vec<Point>,
    pub mesh: Vec<MeshPoint>,
    pub bands: Vec<BandsPoint>,
    pub water: Vec<WaterPoint>,
    /// Real time against error of the stone-only default and of a faster, flatter throw
    /// (`front.rs`).
    pub fronts: Vec<Front>,
}

/// Computes the integrator sweeps of every throw.
pub fn integrator_sweeps(ctx: &Ctx) -> Result<(Vec<Reference>, Vec<Point>), StudyError> {
    let set = settings(ctx.quick);
    let mut refs = Vec::new();
    let mut points = Vec::new();
    for t in &throw_list(ctx.quick) {
        ctx.progress(&format!("reference of the {} throw", t.key));
        let r = reference(t, ctx.quick)?;
        ctx.progress(&format!(
            "  {} skips, {:.4} m; RK4 at {} s: {} skips, {:.4} m; sweeping {} settings",
            r.adaptive.skips,
            r.adaptive.distance,
            r.rk4_dt,
            r.rk4.skips,
            r.rk4.distance,
            set.len()
        ));
        points.extend(sweep(t, &set, &r.adaptive)?);
        refs.push(r);
    }
    Ok((refs, points))
}

pub fn compute(ctx: &Ctx) -> Result<Results, StudyError> {
    let (references, points) = integrator_sweeps(ctx)?;
    let mesh = mesh_sweep(ctx, &throw_list(ctx.quick))?;
    let bands = bands_sweep(ctx, &throw_list(ctx.quick))?;
    let water = water_sweep(ctx)?;
    let fronts = front::front_throws()
        .into_iter()
        .map(|throw| front::front_sweep(ctx, throw))
        .collect::<Result<_, _>>()?;
    Ok(Results {
        references,
        points,
        mesh,
        bands,
        water,
        fronts,
    })
}

/// Computes the study and writes its CSV, charts and report.
pub fn run(ctx: &Ctx) -> Result<(), StudyError> {
    let res = compute(ctx)?;
    report::write(ctx, &res)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The report compares the shipped default's lens and cell with the swept ones: the compiled-in
    /// preset loads, and the full sweeps include its segments and its cell.
    #[test]
    fn the_shipped_lens_and_cell_are_in_the_full_sweeps() {
        let p = Preset::default();
        assert!(mesh_segments(false).contains(&p.stone.segments));
        let shipped_bands =
            stoneskip_physics::sim::stone::lens_bands(p.stone.segments, p.stone.bands);
        assert!(band_meshes(false).contains(&(p.stone.segments, shipped_bands)));
        assert_eq!(band_meshes(false)[0], (192, 96));
        assert!(water_cells(false)
            .iter()
            .any(|&c| (c - p.water.cell).abs() < 1e-12));
    }
}
