//! Fuzz harness (b): a valid preset anywhere in the app's slider ranges (src/ui/settings.rs) →
//! simulate. Never a panic, never a NaN in the state, the energy or the summary; the run always ends
//! with an outcome within its ticks; the work per tick stays under the stepper's own bound. To keep
//! each run short, `max_time` is capped at 0.25 s and the lake at 2–4 m (cells of 2 cm or more).

use std::sync::atomic::{AtomicU64, Ordering};

use arbitrary::{Result, Unstructured};
use stoneskip_physics::sim::params::{
    AirParams, AxialSpin, ForceLaw, Hydrostatic, Integrator, Limiter, Precision, Preset,
    PressureSign, Quadrature, Rotation, Shape, Swell,
};
use stoneskip_physics::sim::Simulation;

/// A number in [lo, hi].
fn num(u: &mut Unstructured, lo: f64, hi: f64) -> Result<f64> {
    let k: u32 = u.arbitrary()?;
    Ok(lo + (hi - lo) * f64::from(k) / f64::from(u32::MAX))
}

/// A number in [lo, hi] on a log scale.
fn log_num(u: &mut Unstructured, lo: f64, hi: f64) -> Result<f64> {
    Ok(num(u, lo.ln(), hi.ln())?.exp())
}

fn pick<T: Copy>(u: &mut Unstructured, v: &[T]) -> Result<T> {
    Ok(*u.choose(v)?)
}

fn stone(u: &mut Unstructured, p: &mut Preset) -> Result<()> {
    p.stone.shape = match u.int_in_range(0..=2)? {
        0 => Shape::Disk {
            radius: num(u, 0.01, 0.3)?,
            thickness: num(u, 0.001, 0.1)?,
        },
        1 => Shape::Lens {
            radius: num(u, 0.01, 0.3)?,
            thickness: num(u, 0.001, 0.1)?,
        },
        _ => Shape::Plate {
            length: num(u, 0.02, 0.6)?,
            width: num(u, 0.02, 0.6)?,
            thickness: num(u, 0.001, 0.1)?,
        },
    };
    p.stone.mass = log_num(u, 0.005, 3.0)?;
    p.stone.segments = u.int_in_range(8..=128)?;
    Ok(())
}

fn launch(u: &mut Unstructured, p: &mut Preset) -> Result<()> {
    let l = &mut p.launch;
    l.position = [
        num(u, -50.0, 50.0)?,
        num(u, -50.0, 50.0)?,
        num(u, 0.0, 5.0)?,
    ];
    let (speed, el, hd) = (
        num(u, 0.5, 40.0)?,
        num(u, -60.0, 45.0)?.to_radians(),
        num(u, -90.0, 90.0)?.to_radians(),
    );
    l.velocity = [
        speed * el.cos() * hd.cos(),
        speed * el.cos() * hd.sin(),
        speed * el.sin(),
    ];
    l.attitude.tilt_deg = num(u, -45.0, 75.0)?;
    l.attitude.bank_deg = num(u, -60.0, 60.0)?;
    l.attitude.heading_deg = num(u, -180.0, 180.0)?;
    l.spin = num(u, -75.0, 75.0)? * std::f64::consts::TAU;
    l.angular_velocity = [
        num(u, -100.0, 100.0)?,
        num(u, -100.0, 100.0)?,
        num(u, -100.0, 100.0)?,
    ];
    Ok(())
}

fn physics(u: &mut Unstructured, p: &mut Preset) -> Result<()> {
    let ph = &mut p.physics;
    ph.gravity = num(u, 0.0, 30.0)?;
    ph.water_density = num(u, 100.0, 3000.0)?;
    ph.force_law = pick(u, &ForceLaw::ALL)?;
    ph.lift_coefficient = if u.arbitrary()? {
        Some(num(u, 0.0, 5.0)?)
    } else {
        None
    };
    ph.friction_coefficient = if u.arbitrary()? {
        Some(num(u, 0.0, 2.0)?)
    } else {
        None
    };
    ph.ventilated = u.arbitrary()?;
    ph.integrator = pick(u, &Integrator::ALL)?;
    ph.tolerance = log_num(u, 1e-10, 1e-3)?;
    ph.rotation = pick(u, &[Rotation::Locked, Rotation::Free])?;
    // The retired planing centre's bytes are still read, so a stored input means what it did.
    if !u.arbitrary::<bool>()? {
        num(u, 0.0, 1.0)?;
    }
    ph.dt = log_num(u, 5e-5, 0.02)?;
    ph.max_time = num(u, 0.01, 0.25)?;
    Ok(())
}

fn water(u: &mut Unstructured, p: &mut Preset) -> Result<()> {
    let w = &mut p.water;
    w.enabled = u.arbitrary()?;
    w.wavy_contact = u.arbitrary()?;
    w.size = [num(u, 2.0, 4.0)?, num(u, 2.0, 4.0)?];
    w.origin = None;
    let max_cell = (w.size[0].min(w.size[1]) / 4.5).min(1.0);
    w.cell = log_num(u, 0.02, max_cell)?;
    w.depth = log_num(u, 0.02, 5.0)?;
    w.damping = num(u, 0.0, 5.0)?;
    w.diagonal_pipes = u.arbitrary()?;
    w.limiter = pick(u, &[Limiter::MassConserving, Limiter::PaperClamp])?;
    w.precision = pick(u, &[Precision::F32, Precision::F64])?;
    w.swell = if u.arbitrary()? {
        Some(Swell {
            amplitude: num(u, 0.0, (0.5 * w.depth).min(0.3))?,
            wavelength: num(u, 0.2, 30.0)?,
            heading_deg: num(u, -180.0, 180.0)?,
        })
    } else {
        None
    };
    Ok(())
}

/// The options added since the first campaigns (issue 11's physics, the Résal frame, a lens's
/// bands), in the UI's ranges. Drawn last, so the bytes before them keep their meaning: an input
/// that runs out before them gets the defaults, the model the earlier campaigns fuzzed.
fn options(u: &mut Unstructured, p: &mut Preset) -> Result<()> {
    let ph = &mut p.physics;
    ph.pressure_sign = pick(u, &[PressureSign::AsPrinted, PressureSign::OpposesMotion])?;
    ph.axial_spin = pick(
        u,
        // The retired `Smooth`'s slot reads as `Resal`, so a stored input keeps its bytes' meaning.
        &[AxialSpin::Faceted, AxialSpin::Resal, AxialSpin::Resal],
    )?;
    ph.buoyancy = u.arbitrary()?;
    ph.hydrostatic = pick(u, &[Hydrostatic::LoadedFaces, Hydrostatic::WettedFaces])?;
    ph.air = if u.arbitrary()? {
        Some(AirParams {
            density: num(u, 0.0, 5.0)?,
            lift_slope: num(u, 0.0, 5.0)?,
            drag_zero: num(u, 0.0, 1.0)?,
            drag_slope: num(u, 0.0, 5.0)?,
            moment_slope: num(u, -2.0, 2.0)?,
        })
    } else {
        None
    };
    p.stone.bands = if u.arbitrary()? {
        Some(u.int_in_range(4..=128)?)
    } else {
        None
    };
    Ok(())
}

/// The retired spectral near field's bytes (session 15): still read, so a stored input means what
/// it did; the run stays on the columns.
fn near_field(u: &mut Unstructured, p: &mut Preset) -> Result<()> {
    if p.water.swell.is_some() || !u.arbitrary::<bool>()? {
        return Ok(());
    }
    pick(u, &[16, 32, 64, 128])?;
    log_num(u, 0.001, 0.5)?;
    num(u, 0.0, 1.0)?;
    num(u, 0.0, 0.01)?;
    Ok(())
}

/// `Adaptive`'s contact steps across the tick (session 20), drawn last for the same reason.
fn numerics(u: &mut Unstructured, p: &mut Preset) -> Result<()> {
    p.physics.steps_across_ticks = u.arbitrary()?;
    Ok(())
}

pub fn preset(u: &mut Unstructured) -> Result<Preset> {
    let mut p = Preset::version_1();
    stone(u, &mut p)?;
    launch(u, &mut p)?;
    physics(u, &mut p)?;
    water(u, &mut p)?;
    options(u, &mut p)?;
    near_field(u, &mut p)?;
    numerics(u, &mut p)?;
    quadrature(u, &mut p)?;
    Ok(p)
}

/// The smooth quadrature (read last, so inputs saved before it keep their meaning): on a lens
/// over flat water, with a smooth spin, as its validation asks.
fn quadrature(u: &mut Unstructured, p: &mut Preset) -> Result<()> {
    if u.arbitrary()? {
        p.stone.quadrature = Quadrature::Smooth {
            meridian: u.int_in_range(2..=64)?,
            around: u.int_in_range(2..=64)?,
        };
        p.water.wavy_contact = false;
        if p.physics.rotation == Rotation::Free {
            p.physics.axial_spin = AxialSpin::Resal;
        }
    }
    Ok(())
}

/// The largest force evaluations per simulated second seen in this process (f64 bits).
static WORST: AtomicU64 = AtomicU64::new(0);

/// The stepper's own bound on the work of one tick: its evaluation guard
/// ([`stoneskip_physics::sim::MAX_EVALS_PER_TICK`], checked before each step) plus the last step's own work
/// (at most ~180 shrinking attempts of 6 evaluations from a 20 ms tick to the 10⁻¹⁰ s floor, and
/// the event location's few more). The step guard alone bounded nothing: a step may follow many
/// rejected attempts (2·10⁷ evaluations in one tick were found by the headless soak).
const MAX_EVALS_PER_TICK: u64 = stoneskip_physics::sim::MAX_EVALS_PER_TICK + 10_000;

/// Runs the target on one input; panics on a finding.
pub fn run(data: &[u8]) {
    let mut u = Unstructured::new(data);
    let Ok(p) = preset(&mut u) else {
        return;
    };
    if p.validate().is_err() {
        // Outside the validator's joint constraints (e.g. a disc thicker than it is wide), which
        // the UI's sliders also keep to.
        return;
    }
    if std::env::var_os("STONESKIP_FUZZ_TRACE").is_some() {
        eprintln!("{p:?}");
    }
    let mut sim = match Simulation::new(&p) {
        Ok(s) => s,
        Err(e) => panic!("a valid preset must build: {e}\n{p:?}"),
    };
    let ticks = (p.physics.max_time / p.physics.dt).ceil() as u64 + 2;
    let mut last_evals = 0;
    for _ in 0..ticks {
        if sim.is_finished() {
            break;
        }
        sim.tick();
        let s = sim.state();
        assert!(
            s.position.is_finite() && s.velocity.is_finite() && sim.energy().is_finite(),
            "non-finite state at t = {}: {s:?}\n{p:?}",
            sim.time()
        );
        let evals = sim.cost().1;
        assert!(
            evals - last_evals <= MAX_EVALS_PER_TICK,
            "{} evaluations in one tick\n{p:?}",
            evals - last_evals
        );
        last_evals = evals;
        if let Some(w) = sim.water() {
            // Finding W1 (docs/reliability.md): the K limiter can leave a drained column a
            // rounding below zero; let that through (a few units of the storage's rounding of the
            // deepest possible column) so the campaign goes on; crates/physics/tests/fuzz_regressions.rs holds
            // the strict bound.
            let eps = match p.water.precision {
                Precision::F32 => 4.0 * f64::from(f32::EPSILON),
                Precision::F64 => 4.0 * f64::EPSILON,
            };
            let deepest = w.volume() / (w.cell() * w.cell());
            assert!(
                w.min_depth() >= -eps * deepest,
                "negative depth {}",
                w.min_depth()
            );
            assert!(w.volume().is_finite(), "water volume {}", w.volume());
        }
    }
    assert!(sim.is_finished(), "no outcome after {ticks} ticks\n{p:?}");
    // The costliest run so far, in force evaluations per simulated second: printed when beaten, so
    // a campaign's log shows the worst case it found (a cost, not a failure).
    let per_s = sim.cost().1 as f64 / sim.time().max(1e-9);
    if per_s > f64::from_bits(WORST.load(Ordering::Relaxed)) {
        WORST.store(per_s.to_bits(), Ordering::Relaxed);
        eprintln!(
            "worst cost so far: {per_s:.3e} force evaluations per simulated second ({} in {} s)",
            sim.cost().1,
            sim.time()
        );
    }
    if std::env::var_os("STONESKIP_FUZZ_TRACE").is_some() {
        eprintln!(
            "{p:?}\n{:?} after {} s: {} steps, {} force evaluations",
            sim.outcome(),
            sim.time(),
            sim.cost().0,
            sim.cost().1
        );
    }
    let summary = sim.summary();
    assert!(
        summary.distance.is_finite() && summary.final_time.is_finite(),
        "{summary:?}"
    );
}
