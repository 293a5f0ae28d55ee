//! Stability study: where methods fail.
//!
//! * The contact is a stiff spring (Bocquet 2003; physics.md §1.3, §7.4): with V_x nearly frozen
//!   the vertical motion is a harmonic oscillator of ω₀ ≈ 580 rad/s for Bocquet's plate at 12 m/s,
//!   which explicit schemes integrate super-elastically once ω₀Δt is large. Measured: the largest
//!   step at which each integrator's single bounce stays bounded, skips and does not gain energy.
//! * The water's Courant limit (water.md §3): von Neumann gives r = cΔt/l ≤ 1/√2 with 4 pipes and
//!   √3/2 with 8 isotropic pipes; found here by bisection on seeded noise.
//! * The paper's eq. 41 clamp against Mei et al.'s (2007) K limiter: volume drift.
//! * Heron's formula (paper eqs. 9–10) against the cross product on slivers.
//! * The paper's integrator (eqs. 30–38) at the paper's own 20 frames/s (Δt = 0.05 s).

use glam::{DMat3, DVec3};
use rayon::prelude::*;

use stoneskip_physics::sim::contact::{heron_area, polygon_area_centroid};
use stoneskip_physics::sim::params::{
    ForceLaw, Integrator, Limiter, Preset, Rotation, Shape, StoneParams,
};
use stoneskip_physics::sim::scenario::{at_impact, first_contact, IMPACT_CLEARANCE};
use stoneskip_physics::sim::water::{WaterConfig, WaterGrid, COURANT_LIMIT_4, COURANT_LIMIT_8};
use stoneskip_physics::sim::{Simulation, StepSample};

use super::throws::{self, FAST};
use super::{check_cancel, logspace, rel_err, Ctx, StudyError};

mod report;

// ------------------------------------------------------------------------------------------------
// A. The contact spring
// ------------------------------------------------------------------------------------------------

/// A single-bounce case.
#[derive(Debug, Clone)]
pub struct BounceCase {
    pub key: &'static str,
    pub label: &'static str,
    /// The preset at impact (integrator and dt are set per run).
    pub preset: Preset,
}

/// Bocquet's reference plate (physics.md §6 VC-1 (ii)) as a thin 3D plate: 10 cm, 100 g, tilt 10°,
/// Bocquet law with C_l = 1 and no friction, entering at V_x = 12, V_z = −0.5 m/s. With V_x frozen
/// the exit speed would be exactly +0.5 m/s (eq. 7); V_x free loses a little.
pub fn bocquet_case() -> Result<BounceCase, StudyError> {
    let mut p = Preset {
        name: "Bocquet plate".into(),
        ..Preset::version_1()
    };
    p.stone = StoneParams {
        shape: Shape::Plate {
            length: 0.1,
            width: 0.1,
            thickness: 0.002,
        },
        mass: 0.1,
        segments: 8,
        bands: None,
        quadrature: Default::default(),
    };
    p.launch.attitude.tilt_deg = 10.0;
    p.launch.spin = 0.0;
    p.physics.force_law = ForceLaw::Bocquet;
    p.physics.lift_coefficient = Some(1.0);
    p.physics.friction_coefficient = Some(0.0);
    p.physics.rotation = Rotation::Locked;
    p.physics.max_time = 1.0;
    p.water.enabled = false;
    let (vx, vz) = (12.0_f64, 0.5_f64);
    let speed = (vx * vx + vz * vz).sqrt();
    let preset = at_impact(&p, speed, (vz / vx).atan(), IMPACT_CLEARANCE)?;
    Ok(BounceCase {
        key: "bocquet_plate",
        label: "Bocquet plate, V_x 12, V_z −0.5 m/s (C_l 1, C_f 0)",
        preset,
    })
}

/// The first contact of the accuracy study's fast throw (default stone, Rosellini law).
pub fn default_case() -> Result<BounceCase, StudyError> {
    let mut b = throws::base(Integrator::Adaptive, 5e-4, 1e-6);
    b.physics.max_time = 1.0;
    Ok(BounceCase {
        key: "default_stone",
        label: "default stone, fast throw (U 12 m/s, β 10°, α 20°)",
        preset: throws::preset(&FAST, &b)?,
    })
}

/// One single-bounce run.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Bounce {
    pub integrator: Integrator,
    pub dt: f64,
    pub skipped: bool,
    pub finite: bool,
    /// v_z,out / |v_z,in| (0 when it did not leave the water).
    pub restitution: f64,
    /// |v_out|² / |v_in|²: the kinetic-energy ratio across the contact (the lowest point is on the
    /// surface at both ends and the attitude is locked, so the potential energy is the same).
    pub energy_ratio: f64,
    pub duration: f64,
    pub force_evals: u64,
}

impl Bounce {
    /// Bounded, skipped and not super-elastic: neither the vertical bounce (the contact spring)
    /// nor the kinetic energy comes out larger than it went in.
    pub fn stable(&self) -> bool {
        self.finite && self.skipped && self.restitution <= 1.0 && self.energy_ratio <= 1.0 + 1e-9
    }
}

/// Runs the first contact of `case` with `integrator` at step `dt` (the tick for Adaptive, at
/// `tolerance`).
pub fn bounce(
    case: &BounceCase,
    integrator: Integrator,
    dt: f64,
    tolerance: f64,
) -> Result<Bounce, StudyError> {
    let mut p = case.preset.clone();
    p.physics.integrator = integrator;
    p.physics.dt = dt;
    p.physics.tolerance = tolerance;
    let v_in = DVec3::from_array(p.launch.velocity);
    let fc = first_contact(&p)?;
    Ok(match fc {
        Some(c) => {
            let v_out = DVec3::from_array(c.v_out);
            let finite = v_out.is_finite() && c.duration.is_finite();
            let (restitution, energy_ratio) = if c.skipped && finite {
                (
                    v_out.z / (-v_in.z).max(1e-12),
                    v_out.length_squared() / v_in.length_squared().max(1e-300),
                )
            } else {
                (0.0, 0.0)
            };
            Bounce {
                integrator,
                dt,
                skipped: c.skipped,
                finite,
                restitution,
                energy_ratio,
                duration: if c.duration.is_finite() {
                    c.duration
                } else {
                    0.0
                },
                force_evals: c.force_evals,
            }
        }
        None => Bounce {
            integrator,
            dt,
            skipped: false,
            finite: true,
            restitution: 0.0,
            energy_ratio: 0.0,
            duration: 0.0,
            force_evals: 0,
        },
    })
}

/// Steps swept for the contact study.
pub fn contact_steps(quick: bool) -> Vec<f64> {
    if quick {
        logspace(1e-5, 0.05, 8)
    } else {
        logspace(1e-6, 0.05, 29)
    }
}

/// Every integrator at every step on a case, plus its reference (Adaptive, tolerance 1e-12).
pub fn bounce_sweep(case: &BounceCase, steps: &[f64]) -> Result<(Bounce, Vec<Bounce>), StudyError> {
    let reference = bounce(case, Integrator::Adaptive, 5e-4, 1e-12)?;
    let jobs: Vec<(Integrator, f64)> = Integrator::ALL
        .iter()
        .flat_map(|&i| steps.iter().map(move |&dt| (i, dt)))
        .collect();
    let runs = jobs
        .par_iter()
        .map(|&(i, dt)| {
            check_cancel()?;
            bounce(case, i, dt, 1e-6)
        })
        .collect::<Result<Vec<_>, StudyError>>()?;
    Ok((reference, runs))
}

/// The largest swept step at which `integrator` is stable at that step and every smaller one.
pub fn largest_stable(
    runs: &[Bounce],
    integrator: Integrator,
    ok: impl Fn(&Bounce) -> bool,
) -> Option<f64> {
    let mut own: Vec<&Bounce> = runs.iter().filter(|b| b.integrator == integrator).collect();
    own.sort_by(|a, b| a.dt.total_cmp(&b.dt));
    let mut best = None;
    for b in own {
        if ok(b) {
            best = Some(b.dt);
        } else {
            break;
        }
    }
    best
}

// ------------------------------------------------------------------------------------------------
// B. The water's Courant limit
// ------------------------------------------------------------------------------------------------

/// Deterministic uniform numbers in [0, 1) (SplitMix64).
struct Rng(u64);
impl Rng {
    fn next(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^= z >> 31;
        (z >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// Amplitude of the seeded noise (m): small enough (H = 1 m) that growth stays linear for 9 decades.
pub const NOISE: f64 = 1e-9;

/// Growth max|η(N)| / max|η(0)| of seeded noise of amplitude [`NOISE`] on an n × n unit grid after `steps` steps at
/// Courant number r (stops early, returning the growth so far, once it passes `cap`).
pub fn noise_growth(
    diagonal: bool,
    n: usize,
    r: f64,
    steps: usize,
    cap: f64,
) -> Result<f64, StudyError> {
    let cfg = WaterConfig {
        diagonal_pipes: diagonal,
        ..WaterConfig::unit(n, n)
    }
    .with_courant(r);
    let mut w = WaterGrid::with_config(cfg)?;
    let mut rng = Rng(6);
    for iy in 0..n {
        for ix in 0..n {
            w.set_eta(ix, iy, NOISE * (2.0 * rng.next() - 1.0));
        }
    }
    let e0 = w.max_abs_eta().max(1e-300);
    let mut g = 1.0;
    for s in 0..steps {
        w.step();
        if s % 10 == 9 || s + 1 == steps {
            g = w.max_abs_eta() / e0;
            if g >= cap || g.is_nan() {
                return Ok(if g.is_finite() { g } else { cap });
            }
        }
    }
    Ok(g)
}

/// Whether the noise grows 100× within 3000 steps.
pub fn blows_up(diagonal: bool, n: usize, r: f64) -> Result<bool, StudyError> {
    Ok(noise_growth(diagonal, n, r, 3000, 100.0)? >= 100.0)
}

/// The Courant threshold found by bisection between 0.9 and 1.1 × the theory on an n × n grid:
/// (stable lower end, unstable upper end).
pub fn courant_threshold(
    diagonal: bool,
    n: usize,
    iterations: usize,
) -> Result<(f64, f64), StudyError> {
    let limit = if diagonal {
        COURANT_LIMIT_8
    } else {
        COURANT_LIMIT_4
    };
    let (mut lo, mut hi) = (0.9 * limit, 1.1 * limit);
    if blows_up(diagonal, n, lo)? || !blows_up(diagonal, n, hi)? {
        return Err(StudyError::Failed(format!(
            "Courant threshold not bracketed in [{lo}, {hi}] (diagonal {diagonal})"
        )));
    }
    for _ in 0..iterations {
        check_cancel()?;
        let mid = 0.5 * (lo + hi);
        if blows_up(diagonal, n, mid)? {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    Ok((lo, hi))
}

/// The largest eigenvalue of the walled n × n grid moves the threshold up by a little from the
/// periodic von Neumann value: 2/√λ with λ the largest eigenvalue of −l²·Laplacian.
pub fn walled_prediction(diagonal: bool, n: usize) -> f64 {
    let cpi = (std::f64::consts::PI / n as f64).cos();
    let lam = if diagonal {
        8.0 / 3.0 * (1.0 + cpi) + 2.0 / 3.0 * (1.0 - cpi * cpi)
    } else {
        4.0 * (1.0 + cpi)
    };
    2.0 / lam.sqrt()
}

// ------------------------------------------------------------------------------------------------
// C. Volume: the paper's clamp against the K limiter
// ------------------------------------------------------------------------------------------------

/// Relative volume change after each step of a thin sheet (1 cm) draining down a steep slope
/// (water.md T3), 64 × 64 unit cells at r = 0.35.
pub fn thin_sheet_drift(limiter: Limiter, n: usize, steps: usize) -> Result<Vec<f64>, StudyError> {
    let cfg = WaterConfig {
        limiter,
        ..WaterConfig::unit(n, n)
    }
    .with_courant(0.35);
    let mut w = WaterGrid::with_config(cfg)?;
    for iy in 0..n {
        for ix in 0..n {
            w.set_bed(ix, iy, 0.5 * (n - 1 - ix) as f64 - 1.0);
            w.set_depth(ix, iy, 0.01);
        }
    }
    let v0 = w.volume();
    let mut out = Vec::with_capacity(steps);
    for _ in 0..steps {
        w.step();
        out.push((w.volume() - v0) / v0);
    }
    Ok(out)
}

/// A stone (the fast throw) skipping over a 1 cm deep lake, 8 m × 3 m, 5 cm cells: the relative
/// volume change at each tick for `t_end` seconds, and the number of skips.
pub fn shallow_lake_drift(
    limiter: Limiter,
    t_end: f64,
) -> Result<(Vec<(f64, f64)>, usize), StudyError> {
    let mut b = throws::base(Integrator::Adaptive, 5e-4, 1e-6);
    b.water.enabled = true;
    b.water.depth = 0.01;
    b.water.cell = 0.05;
    b.water.size = [8.0, 3.0];
    b.water.origin = Some([-1.0, -1.5]);
    b.water.limiter = limiter;
    // f64 storage: the limiters' own drift, not the rounding of f32 depths (~1e-7).
    b.water.precision = stoneskip_physics::sim::params::Precision::F64;
    let p = throws::preset(&FAST, &b)?;
    let mut sim = Simulation::new(&p)?;
    let v0 = sim.water().map_or(1.0, |w| w.volume());
    let mut out = Vec::new();
    let mut k = 0usize;
    while sim.time() < t_end {
        sim.tick();
        k += 1;
        if k.is_multiple_of(20) {
            if let Some(w) = sim.water() {
                out.push((sim.time(), (w.volume() - v0) / v0));
            }
        }
    }
    Ok((out, sim.skips()))
}

// ------------------------------------------------------------------------------------------------
// D. Heron against the cross product
// ------------------------------------------------------------------------------------------------

/// A sliver of base 1/16 m and height base/aspect, turned into a generic plane and moved to
/// `offset`: relative errors of Heron and of the cross product against the intended area b·h/2
/// (the world-frame vertices carry rounding, as the clipped triangles of a real stone do).
pub fn sliver_errors(aspect: f64, offset: DVec3) -> (f64, f64) {
    let base = 0.0625;
    let h = base / aspect;
    let rot = DMat3::from_euler(glam::EulerRot::ZYX, 0.7, 0.4, 0.25);
    let local = [
        DVec3::ZERO,
        DVec3::new(base, 0.0, 0.0),
        DVec3::new(0.3 * base, h, 0.0),
    ];
    let p = local.map(|v| offset + rot * v);
    let exact = 0.5 * base * h;
    let heron = heron_area(p);
    let (cross, _) = polygon_area_centroid(&p);
    (rel_err(heron, exact), rel_err(cross, exact))
}

// ------------------------------------------------------------------------------------------------
// E. The paper at 20 frames/s
// ------------------------------------------------------------------------------------------------

/// The shipped paper preset (assets/presets/paper.ron): Paper law on every wetted face, C_l 1.4,
/// the paper's integrator, locked attitude; the water off (it does not act on the stone).
pub fn paper_preset() -> Result<Preset, StudyError> {
    let text = include_str!("../../../../../assets/presets/paper.ron");
    let mut p =
        stoneskip_physics::preset::parse(text, std::path::Path::new("assets/presets/paper.ron"))
            .map_err(|e| StudyError::Failed(e.to_string()))?;
    p.water.enabled = false;
    p.physics.max_time = 10.0;
    Ok(p)
}

/// One run of the paper preset.
#[derive(Debug, Clone)]
pub struct PaperRun {
    pub integrator: Integrator,
    pub dt: f64,
    pub skips: usize,
    pub distance: f64,
    pub outcome: &'static str,
    pub force_evals: u64,
    /// Largest |v_out|²/|v_in|² over the contacts that skipped (0 if none).
    pub max_energy_ratio: f64,
    /// (x, z) of the centre of mass at each accepted step (thinned).
    pub path: Vec<(f64, f64)>,
}

/// The shipped default throw (`Preset::version_1()`: launched from 0.3 m at (10, 0, −1) m/s, tilt 20°,
/// Rosellini law), water off.
pub fn default_throw() -> Preset {
    let mut p = Preset::version_1();
    p.water.enabled = false;
    p.physics.max_time = 20.0;
    p
}

pub fn paper_run(
    base: &Preset,
    integrator: Integrator,
    dt: f64,
    tolerance: f64,
) -> Result<PaperRun, StudyError> {
    let mut p = base.clone();
    p.physics.integrator = integrator;
    p.physics.dt = dt;
    p.physics.tolerance = tolerance;
    let mut sim = Simulation::new(&p)?;
    let mut path = Vec::new();
    let mut last_x = f64::NEG_INFINITY;
    let s = sim.run(
        &mut |st: &StepSample| {
            let x = st.state.position.x;
            if x - last_x >= 0.005 || st.in_contact {
                path.push((x, st.state.position.z));
                last_x = x;
            }
        },
        &|| false,
    );
    let max_energy_ratio = s
        .contacts
        .iter()
        .filter(|c| c.skip)
        .map(|c| {
            let vi = DVec3::from_array(c.v_in);
            let vo = DVec3::from_array(c.v_out);
            vo.length_squared() / vi.length_squared().max(1e-300)
        })
        .fold(0.0, f64::max);
    Ok(PaperRun {
        integrator,
        dt,
        skips: s.skips,
        distance: s.distance,
        outcome: s.outcome.map_or("running", |o| o.as_str()),
        force_evals: s.force_evals,
        max_energy_ratio,
        path,
    })
}

// ------------------------------------------------------------------------------------------------
// F. A discontinuous force law
// ------------------------------------------------------------------------------------------------

/// One run of Clanet's disc under Bocquet's law with C_f = 1 (β = 20°, water off).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FrictionRun {
    pub tilt: f64,
    pub speed: f64,
    pub tolerance: f64,
    pub skips: usize,
    pub final_time: f64,
    pub force_evals: u64,
    pub steps: u64,
}

/// Adaptive at `tolerance` on Clanet's disc under Bocquet's law at `tilt` (°) and `speed` (m/s).
pub fn friction_run(tilt: f64, speed: f64, tolerance: f64) -> Result<FrictionRun, StudyError> {
    let mut b = throws::clanet_disc(ForceLaw::Bocquet, tilt);
    b.physics.tolerance = tolerance;
    let p = at_impact(&b, speed, 20f64.to_radians(), IMPACT_CLEARANCE)?;
    let s = stoneskip_physics::sim::simulate(&p)?;
    Ok(FrictionRun {
        tilt,
        speed,
        tolerance,
        skips: s.skips,
        final_time: s.final_time,
        force_evals: s.force_evals,
        steps: s.steps,
    })
}

// ------------------------------------------------------------------------------------------------
// The study: compute, then report
// ------------------------------------------------------------------------------------------------

/// A. One bounce case swept over the steps.
#[derive(Debug, Clone)]
pub struct ContactSweep {
    pub case: BounceCase,
    /// Adaptive at tolerance 1e-12.
    pub reference: Bounce,
    pub runs: Vec<Bounce>,
}

/// B. The noise growth of one pipe stencil over Courant numbers, and its bisected threshold.
#[derive(Debug, Clone)]
pub struct CourantCurve {
    pub diagonal: bool,
    /// (r, growth after 1000 steps).
    pub growth: Vec<(f64, f64)>,
    /// Bisected threshold: (stable lower end, unstable upper end).
    pub threshold: (f64, f64),
}

/// B. The Courant part: grid size, bisection steps, and both stencils.
#[derive(Debug, Clone)]
pub struct Courant {
    pub n: usize,
    pub iterations: usize,
    pub curves: Vec<CourantCurve>,
}

/// C. Volume drift of both limiters on the thin sheet and the shallow lake.
#[derive(Debug, Clone)]
pub struct Volume {
    pub sheet_n: usize,
    pub sheet_steps: usize,
    pub sheet_k: Vec<f64>,
    pub sheet_clamp: Vec<f64>,
    pub lake_time: f64,
    pub lake_k: Vec<(f64, f64)>,
    pub lake_clamp: Vec<(f64, f64)>,
    pub lake_skips_k: usize,
    pub lake_skips_clamp: usize,
}

/// D. Area errors of a sliver: (aspect, Heron at the origin, cross at the origin, Heron offset,
/// cross offset).
pub type HeronRow = (f64, f64, f64, f64, f64);

/// E. One scene of the paper's integrator sweep.
#[derive(Debug, Clone)]
pub struct PaperScene {
    pub key: &'static str,
    pub label: &'static str,
    /// Adaptive at 1e-10.
    pub reference: PaperRun,
    pub runs: Vec<PaperRun>,
}

/// Everything the stability study computes.
#[derive(Debug, Clone)]
pub struct Results {
    pub contact: Vec<ContactSweep>,
    pub courant: Courant,
    pub volume: Volume,
    pub heron: Vec<HeronRow>,
    pub paper: Vec<PaperScene>,
    pub friction: Vec<FrictionRun>,
}

/// A: every integrator over the steps on both bounce cases.
pub fn compute_contact(ctx: &Ctx) -> Result<Vec<ContactSweep>, StudyError> {
    let steps = contact_steps(ctx.quick);
    let mut out = Vec::new();
    for case in [bocquet_case()?, default_case()?] {
        ctx.progress(&format!("contact stability: {}", case.key));
        let (reference, runs) = bounce_sweep(&case, &steps)?;
        out.push(ContactSweep {
            case,
            reference,
            runs,
        });
    }
    Ok(out)
}

/// B: noise growth over r and the bisected threshold, for 4 and 8 pipes.
pub fn compute_courant(ctx: &Ctx) -> Result<Courant, StudyError> {
    ctx.progress("water Courant threshold");
    let quick = ctx.quick;
    let n = if quick { 16 } else { 32 };
    let iterations = if quick { 6 } else { 12 };
    let mut curves = Vec::new();
    for diagonal in [false, true] {
        let rs: Vec<f64> = (0..if quick { 8 } else { 31 })
            .map(|k| 0.5 + 0.6 * k as f64 / if quick { 7.0 } else { 30.0 })
            .collect();
        let growth = rs
            .par_iter()
            .map(|&r| noise_growth(diagonal, n, r, 1000, 1e8).map(|g| (r, g)))
            .collect::<Result<Vec<_>, StudyError>>()?;
        let threshold = courant_threshold(diagonal, n, iterations)?;
        curves.push(CourantCurve {
            diagonal,
            growth,
            threshold,
        });
    }
    Ok(Courant {
        n,
        iterations,
        curves,
    })
}

/// C: both limiters on the thin sheet and under the fast throw over the shallow lake.
pub fn compute_volume(ctx: &Ctx) -> Result<Volume, StudyError> {
    ctx.progress("volume drift: paper clamp vs K limiter");
    let quick = ctx.quick;
    let sheet_steps = if quick { 100 } else { 400 };
    let sheet_n = if quick { 32 } else { 64 };
    let (k_sheet, c_sheet) = rayon::join(
        || thin_sheet_drift(Limiter::MassConserving, sheet_n, sheet_steps),
        || thin_sheet_drift(Limiter::PaperClamp, sheet_n, sheet_steps),
    );
    let lake_time = if quick { 0.5 } else { 2.0 };
    let (lake_k, lake_skips_k) = shallow_lake_drift(Limiter::MassConserving, lake_time)?;
    let (lake_clamp, lake_skips_clamp) = shallow_lake_drift(Limiter::PaperClamp, lake_time)?;
    Ok(Volume {
        sheet_n,
        sheet_steps,
        sheet_k: k_sheet?,
        sheet_clamp: c_sheet?,
        lake_time,
        lake_k,
        lake_clamp,
        lake_skips_k,
        lake_skips_clamp,
    })
}

/// D: Heron and the cross product over aspect ratios, at the origin and offset.
pub fn compute_heron(ctx: &Ctx) -> Vec<HeronRow> {
    ctx.progress("Heron vs cross product on slivers");
    let quick = ctx.quick;
    let offset = DVec3::new(5.0, 0.3, -0.01);
    (0..=if quick { 10 } else { 40 })
        .map(|k| 2f64.powi(if quick { 4 * k } else { k }))
        .map(|a| {
            let (h0, c0) = sliver_errors(a, DVec3::ZERO);
            let (h1, c1) = sliver_errors(a, offset);
            (a, h0, c0, h1, c1)
        })
        .collect()
}

/// E: the Paper integrator over steps down from 1/20 s, on the default throw and the paper preset.
pub fn compute_paper(ctx: &Ctx) -> Result<Vec<PaperScene>, StudyError> {
    ctx.progress("the paper's integrator at 20 frames/s");
    let dts: Vec<f64> = if ctx.quick {
        vec![0.05, 0.01, 1e-3, 2e-4]
    } else {
        vec![
            0.05, 0.02, 0.01, 5e-3, 2e-3, 1e-3, 5e-4, 2e-4, 1e-4, 5e-5, 2e-5,
        ]
    };
    let scenes = [
        ("default", "the default throw (Preset::version_1(): lens, 0.3 m up, (10, 0, −1) m/s, tilt 20°, Rosellini law)", default_throw()),
        ("paper", "the paper preset (assets/presets/paper.ron: lens, tilt 25°, Paper law with C_l 1.4 on every wetted face)", paper_preset()?),
    ];
    let mut out = Vec::new();
    for (key, label, base) in &scenes {
        let reference = paper_run(base, Integrator::Adaptive, 5e-4, 1e-10)?;
        let runs = dts
            .par_iter()
            .map(|&dt| {
                check_cancel()?;
                paper_run(base, Integrator::Paper, dt, 1e-6)
            })
            .collect::<Result<Vec<_>, StudyError>>()?;
        out.push(PaperScene {
            key,
            label,
            reference,
            runs,
        });
    }
    Ok(out)
}

/// F: Adaptive over tolerances on two throws under Bocquet's discontinuous friction.
pub fn compute_friction(ctx: &Ctx) -> Result<Vec<FrictionRun>, StudyError> {
    ctx.progress("Adaptive on Bocquet's law with C_f = 1 (discontinuous friction)");
    let tols: Vec<f64> = if ctx.quick {
        vec![1e-3, 1e-4]
    } else {
        vec![1e-3, 1e-4, 1e-5, 1e-6]
    };
    let jobs: Vec<(f64, f64, f64)> = [(45.0, 5.0), (5.0, 3.0)]
        .iter()
        .flat_map(|&(a, u)| tols.iter().map(move |&t| (a, u, t)))
        .collect();
    jobs.par_iter()
        .map(|&(tilt, speed, tol)| {
            check_cancel()?;
            friction_run(tilt, speed, tol)
        })
        .collect()
}

/// Runs every part of the study.
pub fn compute(ctx: &Ctx) -> Result<Results, StudyError> {
    Ok(Results {
        contact: compute_contact(ctx)?,
        courant: compute_courant(ctx)?,
        volume: compute_volume(ctx)?,
        heron: compute_heron(ctx),
        paper: compute_paper(ctx)?,
        friction: compute_friction(ctx)?,
    })
}

/// Computes the study and writes its CSV, charts and report.
pub fn run(ctx: &Ctx) -> Result<(), StudyError> {
    let res = compute(ctx)?;
    report::write(ctx, &res)
}
