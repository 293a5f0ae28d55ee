//! Whole throws as a converged result (issue 38): the shipped model — the contact on the ambient
//! water with the wetted-extent memory (`sim/memory.rs`; Wagner 1932, Hewitt, Balmforth &
//! McElwaine 2011, the lag derived in docs/studies/wagner_lag) — against the model it replaced, the
//! stone on its own near field (wavy contact on 2 cm columns, quasi-steady contact; the fidelity
//! study's presets). Compute (this module), then results ([`WholeThrow`]), then report
//! (`report.rs`):
//! - convergence: the tick 4× finer, the cell 2× finer, the mesh 2× finer, the tolerance 100×
//!   tighter, on the default, magic-angle and record throws;
//! - smoothness: launches 0.02 m/s and 0.5 mm apart;
//! - Hewitt's structure: the held pebble touching flat water tangentially at each speed, its
//!   small-amplitude restitution and the speed U* where planing turns unstable;
//! - the first bounce: Clanet's disc, its minimal speed against tilt, its steepest bounce and its
//!   contact time;
//! - the record class, slower throws of it, its hops; the spin sweep;
//! - the lag: λ ± 20 % and the reduced form τ = κ R/|U| beside the shipped τ = λ s_g/|U|.

pub mod report;

use stoneskip_physics::sim::metrics::{throw_shape, ThrowShape};
use stoneskip_physics::sim::params::{
    LagLength, MemoryParams, Preset, Rotation, MAX_WATER_COLUMNS,
};
use stoneskip_physics::sim::scenario::{at_impact, first_contact, min_speed, IMPACT_CLEARANCE};
use stoneskip_physics::sim::{simulate, Summary};

use super::par_map;
use super::{check_cancel, Ctx, StudyError};

/// The whole throws the issue checks.
pub const THROWS: [&str; 3] = ["default", "magic_angle", "record_throw"];

/// Which model a run is on.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Model {
    /// Issue 11's: the stone on its own near field, quasi-steady (docs/studies/fidelity/presets).
    Before,
    /// The shipped presets: the ambient water and the wetted-extent memory.
    After,
}

impl Model {
    pub fn name(self) -> &'static str {
        match self {
            Model::Before => "before",
            Model::After => "after",
        }
    }
}

fn parse(stem: &str, text: &str) -> Result<Preset, StudyError> {
    let path = format!("assets/presets/{stem}.ron");
    stoneskip_physics::preset::parse(text, std::path::Path::new(&path))
        .map_err(|e| StudyError::Failed(e.to_string()))
}

/// A preset of `model` by file stem.
pub fn preset(model: Model, stem: &str) -> Result<Preset, StudyError> {
    let list: &[(&str, &str)] = match model {
        Model::Before => &super::fidelity::common::SHIPPED,
        Model::After => &stoneskip_physics::preset::SHIPPED,
    };
    let (_, text) = list
        .iter()
        .find(|(s, _)| *s == stem)
        .ok_or_else(|| StudyError::Failed(format!("no preset `{stem}`")))?;
    parse(stem, text)
}

/// One run's result.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Run {
    pub shape: ThrowShape,
    pub force_evals: u64,
}

fn run(p: &Preset) -> Result<Run, StudyError> {
    check_cancel()?;
    let s = simulate(p)?;
    Ok(Run {
        shape: shape_of(&s, p),
        force_evals: s.force_evals,
    })
}

pub(crate) fn shape_of(s: &Summary, p: &Preset) -> ThrowShape {
    throw_shape(s, [p.launch.position[0], p.launch.position[1]])
}

/// A throw under one change of its numerics or its launch.
#[derive(Debug, Clone)]
pub struct Variant {
    pub model: Model,
    pub stem: &'static str,
    pub change: &'static str,
    pub run: Run,
}

pub type Change = (&'static str, fn(&mut Preset));

/// The numerics refined as the issue asks.
pub const REFINEMENTS: [Change; 5] = [
    ("as shipped", |_| {}),
    ("tick / 4", |p| p.physics.dt /= 4.0),
    ("cell / 2", halve_cell),
    ("mesh × 2", |p| p.stone.segments *= 2),
    ("tolerance / 100", |p| p.physics.tolerance /= 100.0),
];

/// The lake's cell halved; a lake that would then pass the grid's column limit is narrowed about
/// its middle to fit (the record throw's 140 m lake: 1.4 m either side at 1 cm).
pub(crate) fn halve_cell(p: &mut Preset) {
    let w = &mut p.water;
    w.cell /= 2.0;
    let along = (w.size[0] / w.cell).ceil();
    let most = (MAX_WATER_COLUMNS as f64 / along).floor() * w.cell;
    if w.size[1] > most {
        let centre = w.origin.map_or(0.0, |o| o[1] + 0.5 * w.size[1]);
        w.size[1] = most;
        if let Some(o) = w.origin.as_mut() {
            o[1] = centre - 0.5 * most;
        }
    }
}

/// Launches 0.02 m/s and 0.5 mm apart.
pub const NEIGHBOURS: [Change; 4] = [
    ("speed − 0.02 m/s", |p| scale_speed(p, -0.02)),
    ("speed + 0.02 m/s", |p| scale_speed(p, 0.02)),
    ("height − 0.5 mm", |p| p.launch.position[2] -= 0.0005),
    ("height + 0.5 mm", |p| p.launch.position[2] += 0.0005),
];

/// The launch's horizontal speed changed by `dv`, its direction and vertical speed kept.
fn scale_speed(p: &mut Preset, dv: f64) {
    let [vx, vy, vz] = p.launch.velocity;
    let h = vx.hypot(vy);
    if h > 0.0 {
        let k = (h + dv) / h;
        p.launch.velocity = [vx * k, vy * k, vz];
    }
}

/// Every throw of [`THROWS`] under every change of `changes`, on both models (the before model
/// only where `before`).
fn variants(changes: &[Change], before: bool, quick: bool) -> Result<Vec<Variant>, StudyError> {
    let models: &[Model] = if before {
        &[Model::Before, Model::After]
    } else {
        &[Model::After]
    };
    let throws: &[&'static str] = if quick { &THROWS[..1] } else { &THROWS };
    let mut jobs = Vec::new();
    for &model in models {
        for &stem in throws {
            for &(change, f) in changes {
                jobs.push((model, stem, change, f));
            }
        }
    }
    par_map(jobs, |(model, stem, change, f)| {
        let mut p = preset(model, stem)?;
        if quick {
            p.water.cell = p.water.cell.max(super::fidelity::common::QUICK_CELL);
        }
        f(&mut p);
        Ok(Variant {
            model,
            stem,
            change,
            run: run(&p)?,
        })
    })
}

/// The held default pebble touching flat water almost tangentially at one speed.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Tangential {
    pub speed: f64,
    pub run: Run,
    /// The second contact's vertical restitution v_z,out / −v_z,in: the return map of a small
    /// heave oscillation about planing (the first contact takes the stone from the air to it); 0
    /// when there is no second skip.
    pub restitution: f64,
}

/// The vertical speed of the tangential touches (m/s).
pub const TANGENTIAL_VZ: f64 = -0.1;

/// The shipped default pebble held at its launch attitude, without air or spin, its lowest point
/// 0.5 mm above flat water, moving at `speed` and [`TANGENTIAL_VZ`].
pub fn tangential_preset(speed: f64) -> Result<Preset, StudyError> {
    let mut p = preset(Model::After, "default")?;
    p.physics.rotation = Rotation::Locked;
    p.physics.air = None;
    p.water.enabled = false;
    p.launch.spin = 0.0;
    let mut p = at_impact(&p, speed, 0.0, 0.0005)?;
    p.launch.velocity = [speed, 0.0, TANGENTIAL_VZ];
    Ok(p)
}

fn tangential(speed: f64) -> Result<Tangential, StudyError> {
    check_cancel()?;
    let p = tangential_preset(speed)?;
    let s = simulate(&p)?;
    let restitution = s
        .contacts
        .get(1)
        .filter(|c| c.skip)
        .map_or(0.0, |c| c.v_out[2] / -c.v_in[2]);
    Ok(Tangential {
        speed,
        run: Run {
            shape: shape_of(&s, &p),
            force_evals: s.force_evals,
        },
        restitution,
    })
}

/// Speeds of the tangential touches (m/s).
fn hewitt_speeds(quick: bool) -> Vec<f64> {
    if quick {
        vec![3.0, 12.0]
    } else {
        vec![
            1.5, 2.0, 2.5, 3.0, 3.5, 4.0, 5.0, 6.0, 8.0, 10.0, 12.0, 15.0, 19.0,
        ]
    }
}

/// U*: the speed where the restitution of the tangential touch's second contact crosses 1 (a
/// small heave oscillation about planing grows: planing turns unstable), by bisection between the
/// sweep's speeds that bracket it; `None` if none do.
fn unstable_speed(sweep: &[Tangential], quick: bool) -> Result<Option<f64>, StudyError> {
    let Some(w) = sweep
        .windows(2)
        .find(|w| w[0].restitution < 1.0 && w[1].restitution >= 1.0)
    else {
        return Ok(None);
    };
    let (mut a, mut b) = (w[0].speed, w[1].speed);
    let steps = if quick { 3 } else { 12 };
    for _ in 0..steps {
        let m = 0.5 * (a + b);
        if tangential(m)?.restitution >= 1.0 {
            b = m;
        } else {
            a = m;
        }
    }
    Ok(Some(0.5 * (a + b)))
}

/// Clanet's disc (the shipped `clanet_disc`: R 2.5 cm, 65 rev/s, free) at impact under `model`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FirstBounce {
    pub model: Model,
    pub tilt_deg: f64,
    /// Minimal speed at β = 20° (m/s), `None` above 10 m/s.
    pub min_speed: Option<f64>,
}

/// Clanet's disc (`clanet_disc`, a validation preset on the quasi-steady contact) on `model`:
/// before as it ships, after with the shipped default's memory.
fn clanet(model: Model) -> Result<Preset, StudyError> {
    let mut p = preset(Model::After, "clanet_disc")?;
    p.physics.wetted_memory = match model {
        Model::Before => None,
        Model::After => preset(Model::After, "default")?.physics.wetted_memory,
    };
    Ok(p)
}

fn first_bounce_tilts(quick: bool) -> Vec<f64> {
    if quick {
        vec![20.0]
    } else {
        vec![10.0, 15.0, 20.0, 25.0, 30.0]
    }
}

fn first_bounces(quick: bool) -> Result<Vec<FirstBounce>, StudyError> {
    let mut jobs = Vec::new();
    for model in [Model::Before, Model::After] {
        for tilt in first_bounce_tilts(quick) {
            jobs.push((model, tilt));
        }
    }
    let tol = if quick { 2e-2 } else { 2e-3 };
    par_map(jobs, |(model, tilt_deg)| {
        check_cancel()?;
        let mut p = clanet(model)?;
        p.launch.attitude.tilt_deg = tilt_deg;
        Ok(FirstBounce {
            model,
            tilt_deg,
            min_speed: min_speed(&p, 20f64.to_radians(), 0.5, 10.0, tol)?,
        })
    })
}

/// Clanet's reference contact (U 3.5 m/s, α = β = 20°) and the steepest bounce at that speed.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ClanetContact {
    pub model: Model,
    /// Duration of the first contact (s).
    pub duration: f64,
    /// Largest impact angle that still bounces at 3.5 m/s (degrees).
    pub steepest_deg: f64,
}

/// Clanet's reference throw (3.5 m/s, β = 20°).
pub const CLANET_SPEED: f64 = 3.5;

fn clanet_contact(model: Model, quick: bool) -> Result<ClanetContact, StudyError> {
    let p = clanet(model)?;
    let at = |beta_deg: f64| at_impact(&p, CLANET_SPEED, beta_deg.to_radians(), IMPACT_CLEARANCE);
    let duration = first_contact(&at(20.0)?)?.map_or(f64::NAN, |c| c.duration);
    let bounces = |beta: f64| -> Result<bool, StudyError> {
        check_cancel()?;
        Ok(first_contact(&at(beta)?)?.is_some_and(|c| c.skipped))
    };
    let (mut a, mut b) = (20.0, 80.0);
    if !bounces(a)? {
        return Ok(ClanetContact {
            model,
            duration,
            steepest_deg: f64::NAN,
        });
    }
    for _ in 0..if quick { 4 } else { 12 } {
        let m = 0.5 * (a + b);
        if bounces(m)? {
            a = m;
        } else {
            b = m;
        }
    }
    Ok(ClanetContact {
        model,
        duration,
        steepest_deg: 0.5 * (a + b),
    })
}

/// The record preset at one launch.
#[derive(Debug, Clone)]
pub struct RecordRun {
    pub label: String,
    pub speed: f64,
    pub run: Run,
    /// Mean touchdown spacing over the first and the last quarter of the hops (m).
    pub first_quarter_hop: f64,
    pub last_quarter_hop: f64,
    /// Touchdown spacings in order (m).
    pub hops: Vec<f64>,
}

fn record_run(label: String, p: &Preset) -> Result<RecordRun, StudyError> {
    check_cancel()?;
    let s = simulate(p)?;
    let hops: Vec<f64> = s
        .contacts
        .windows(2)
        .map(|w| (w[1].x - w[0].x).hypot(w[1].y - w[0].y))
        .collect();
    let q = (hops.len() / 4).max(1).min(hops.len());
    let mean = |h: &[f64]| {
        if h.is_empty() {
            f64::NAN
        } else {
            h.iter().sum::<f64>() / h.len() as f64
        }
    };
    Ok(RecordRun {
        label,
        speed: p.launch.velocity[0].hypot(p.launch.velocity[1]),
        run: Run {
            shape: shape_of(&s, p),
            force_evals: s.force_evals,
        },
        first_quarter_hop: mean(&hops[..q]),
        last_quarter_hop: mean(&hops[hops.len() - q..]),
        hops,
    })
}

fn record(quick: bool) -> Result<Vec<RecordRun>, StudyError> {
    let base = preset(Model::After, "record_throw")?;
    let mut jobs: Vec<(String, Preset)> = Vec::new();
    let factors: &[f64] = if quick {
        &[1.0]
    } else {
        &[1.0, 0.9, 0.85, 12.0 / 19.0]
    };
    for &k in factors {
        let mut p = base.clone();
        p.launch.velocity = [base.launch.velocity[0] * k, 0.0, 0.0];
        jobs.push((format!("{:.0} % of the speed", 100.0 * k), p));
    }
    if !quick {
        let mut p = base.clone();
        p.launch.position[2] = 0.3;
        jobs.push(("released from 30 cm".to_owned(), p));
    }
    par_map(jobs, |(label, p)| record_run(label, &p))
}

/// The default throw at one spin.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SpinPoint {
    /// rev/s; `None`: the attitude held.
    pub rev_s: Option<f64>,
    pub run: Run,
}

fn spin_revs(quick: bool) -> Vec<f64> {
    if quick {
        vec![0.0, 20.0]
    } else {
        vec![
            0.0, 2.5, 5.0, 7.5, 10.0, 15.0, 20.0, 25.0, 30.0, 40.0, 50.0, 60.0, 80.0, 100.0, 125.0,
            150.0,
        ]
    }
}

fn spin(quick: bool) -> Result<Vec<SpinPoint>, StudyError> {
    let mut jobs: Vec<Option<f64>> = spin_revs(quick).into_iter().map(Some).collect();
    jobs.push(None);
    par_map(jobs, |rev_s| {
        let mut p = preset(Model::After, "default")?;
        match rev_s {
            Some(r) => p.launch.spin = r * std::f64::consts::TAU,
            None => p.physics.rotation = Rotation::Locked,
        }
        Ok(SpinPoint {
            rev_s,
            run: run(&p)?,
        })
    })
}

/// One lag setting on one throw.
#[derive(Debug, Clone)]
pub struct LagRun {
    pub memory: MemoryParams,
    pub stem: &'static str,
    pub run: Run,
    /// The first contact of Clanet's reference throw (s), on `clanet_disc`.
    pub clanet_contact: f64,
}

fn lags(quick: bool) -> Result<Vec<LagRun>, StudyError> {
    let shipped = preset(Model::After, "default")?
        .physics
        .wetted_memory
        .unwrap_or_default();
    let mut memories = vec![
        MemoryParams {
            lag: 0.8 * shipped.lag,
            ..shipped
        },
        shipped,
        MemoryParams {
            lag: 1.2 * shipped.lag,
            ..shipped
        },
    ];
    if !quick {
        for lag in [0.5, 1.0, 3.0] {
            memories.push(MemoryParams {
                lag,
                length: LagLength::Wetted,
                ..MemoryParams::default()
            });
        }
        for kappa in [0.2, 0.5, 1.0, 1.5] {
            memories.push(MemoryParams {
                lag: kappa,
                length: LagLength::Radius,
                ..MemoryParams::default()
            });
        }
    }
    let stems: &[&'static str] = if quick {
        &["default"]
    } else {
        &["default", "record_throw"]
    };
    let mut jobs = Vec::new();
    for &m in &memories {
        for &stem in stems {
            jobs.push((m, stem));
        }
    }
    par_map(jobs, |(memory, stem)| {
        let mut p = preset(Model::After, stem)?;
        p.physics.wetted_memory = Some(memory);
        let mut c = clanet(Model::After)?;
        c.physics.wetted_memory = Some(memory);
        let c = at_impact(&c, CLANET_SPEED, 20f64.to_radians(), IMPACT_CLEARANCE)?;
        Ok(LagRun {
            memory,
            stem,
            run: run(&p)?,
            clanet_contact: first_contact(&c)?.map_or(f64::NAN, |f| f.duration),
        })
    })
}

/// Everything the study measured.
#[derive(Debug, Clone)]
pub struct WholeThrow {
    pub convergence: Vec<Variant>,
    pub neighbours: Vec<Variant>,
    pub tangential: Vec<Tangential>,
    pub unstable_speed: Option<f64>,
    /// The held pebble's minimal speed at α = β = 20° on the shipped model (m/s).
    pub pebble_min_speed: Option<f64>,
    pub first_bounces: Vec<FirstBounce>,
    pub clanet: Vec<ClanetContact>,
    pub record: Vec<RecordRun>,
    pub spin: Vec<SpinPoint>,
    /// The shipped memory (the default preset's).
    pub shipped: MemoryParams,
    pub lags: Vec<LagRun>,
}

/// Runs every part of the study.
pub fn compute(ctx: &Ctx) -> Result<WholeThrow, StudyError> {
    let quick = ctx.quick;
    ctx.progress("convergence under the numerics, both models");
    let convergence = variants(&REFINEMENTS, true, quick)?;
    ctx.progress("neighbouring launches, both models");
    let neighbours = variants(&NEIGHBOURS, true, quick)?;
    ctx.progress("tangential touches of the held pebble (Hewitt)");
    let tangential = par_map(hewitt_speeds(quick), tangential)?;
    let unstable_speed = unstable_speed(&tangential, quick)?;
    let mut held = tangential_preset(3.0)?;
    held.launch.attitude.tilt_deg = 20.0;
    let tol = if quick { 2e-2 } else { 2e-3 };
    let pebble_min_speed = min_speed(&held, 20f64.to_radians(), 0.5, 10.0, tol)?;
    ctx.progress("first bounces of Clanet's disc");
    let first_bounces = first_bounces(quick)?;
    let clanet = par_map(vec![Model::Before, Model::After], |m| {
        clanet_contact(m, quick)
    })?;
    ctx.progress("record class");
    let record = record(quick)?;
    ctx.progress("spin sweep");
    let spin = spin(quick)?;
    ctx.progress("the lag's constant and length");
    let lags = lags(quick)?;
    let shipped = preset(Model::After, "default")?
        .physics
        .wetted_memory
        .unwrap_or_default();
    Ok(WholeThrow {
        convergence,
        neighbours,
        tangential,
        unstable_speed,
        pebble_min_speed,
        first_bounces,
        clanet,
        record,
        spin,
        shipped,
        lags,
    })
}

/// Computes, then writes the CSVs and the report.
pub fn run_study(ctx: &Ctx) -> Result<(), StudyError> {
    let w = compute(ctx)?;
    report::write_csvs(ctx, &w)?;
    report::write_chart(ctx, &w)?;
    ctx.write("README.md", &report::report(ctx, &w))?;
    Ok(())
}
