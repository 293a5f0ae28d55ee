//! Shared fixtures of the physics tests: the reference stones of the literature, defined once —
//! Bocquet's square plate (Bocquet 2003; physics.md §6) and Clanet, Hersen & Bocquet's aluminium disc
//! (Clanet et al. 2004: R 2.5 cm, e 2.75 mm, 14.6 g) — and the throws of the spin tests (physics.md
//! §1.7, §7.3), so that no physics test depends on a study module.

#![allow(dead_code, unused_imports, clippy::field_reassign_with_default)]

use rayon::prelude::*;
use stoneskip_physics::sim::params::{
    Attitude, ForceLaw, Integrator, Preset, Rotation, Shape, StoneParams,
};
use stoneskip_physics::sim::scenario::{at_impact, IMPACT_CLEARANCE};
use stoneskip_physics::sim::{SimError, Simulation};
use stoneskip_reference::{CLANET_MASS, CLANET_RADIUS, CLANET_THICKNESS};

/// One revolution (rad).
pub use stoneskip_physics::sim::metrics::fit_exponent;
pub use stoneskip_physics::sim::scenario::typical;
pub use stoneskip_physics::sim::stone::{axis_from_reported as axis, inclination};

pub const REV: f64 = std::f64::consts::TAU;

/// Relative difference |a − b| / |b|.
pub fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs().max(1e-12)
}

/// Bocquet's reference stone as a thin 3D plate (physics.md §6 "square ref. stone"): 10 cm square,
/// 2 mm thick, 100 g, at 10° tilt, Bocquet law with C_l = C_f = 1, ventilated, locked, water off.
pub fn bocquet_plate() -> Preset {
    let mut p = Preset::version_1();
    p.name = "Bocquet plate".into();
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
    p.launch.attitude = Attitude {
        tilt_deg: 10.0,
        bank_deg: 0.0,
        heading_deg: 0.0,
    };
    p.launch.spin = 0.0;
    p.physics.force_law = ForceLaw::Bocquet;
    p.physics.lift_coefficient = Some(1.0);
    p.physics.friction_coefficient = Some(1.0);
    p.physics.ventilated = true;
    p.physics.rotation = Rotation::Locked;
    p.water.enabled = false;
    p
}

/// Clanet's aluminium disc, 48 segments.
pub fn clanet_stone() -> StoneParams {
    StoneParams {
        shape: Shape::Disk {
            radius: CLANET_RADIUS,
            thickness: CLANET_THICKNESS,
        },
        mass: CLANET_MASS,
        segments: 48,
        bands: None,
        quadrature: Default::default(),
    }
}

/// Clanet's disc at fixed attitude under `law`, without friction: the published 2D curves load the
/// bottom face only.
pub fn clanet_disc(law: ForceLaw, tilt_deg: f64) -> Preset {
    let mut p = Preset::version_1();
    p.stone = clanet_stone();
    p.launch.attitude = Attitude {
        tilt_deg,
        bank_deg: 0.0,
        heading_deg: 0.0,
    };
    p.physics.force_law = law;
    p.physics.friction_coefficient = Some(0.0);
    p.physics.rotation = Rotation::Locked;
    p.water.enabled = false;
    p
}

/// Clanet's disc as a free rigid body spun at `spin_rev_s` about its axis, Rosellini law (with its
/// default friction), pressure at the faces, water off.
pub fn clanet_free(tilt_deg: f64, spin_rev_s: f64) -> Preset {
    let mut p = Preset::version_1();
    p.stone = clanet_stone();
    p.launch.attitude = Attitude {
        tilt_deg,
        bank_deg: 0.0,
        heading_deg: 0.0,
    };
    p.launch.spin = spin_rev_s * REV;
    p.physics.force_law = ForceLaw::Rosellini;
    p.physics.rotation = Rotation::Free;
    p.water.enabled = false;
    p
}

/// The speed and angle of Clanet's throws at impact: U = 3.5 m/s, β = 20°.
pub const CLANET_SPEED: f64 = 3.5;
pub const CLANET_BETA_DEG: f64 = 20.0;

/// Clanet's spun disc at impact (U = 3.5 m/s, β = 20°), the lowest point just above the water.
pub fn clanet_at_impact(tilt_deg: f64, spin_rev_s: f64) -> Preset {
    at_impact(
        &clanet_free(tilt_deg, spin_rev_s),
        CLANET_SPEED,
        CLANET_BETA_DEG.to_radians(),
        IMPACT_CLEARANCE,
    )
    .unwrap()
}

/// Clanet's spun disc at impact, default coefficients, Adaptive, capped at 5 s.
pub fn clanet_spun(tilt_deg: f64, rev_s: f64) -> Result<Preset, SimError> {
    let mut p = clanet_free(tilt_deg, rev_s);
    p.name = "Clanet disc".into();
    p.physics.lift_coefficient = None;
    p.physics.friction_coefficient = None;
    p.physics.integrator = Integrator::Adaptive;
    p.physics.max_time = 5.0;
    at_impact(
        &p,
        CLANET_SPEED,
        CLANET_BETA_DEG.to_radians(),
        IMPACT_CLEARANCE,
    )
}

/// Force evaluations after which a spin throw is cut short.
pub const EVAL_CAP: u64 = 300_000;

/// One spun throw of Clanet's disc and its first contact.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SpinPoint {
    pub skips: usize,
    pub first_skip: bool,
    /// Change of the inclination to the water through the first contact (degrees, signed).
    pub inclination_change: f64,
    /// Angle the axis turned through the first contact (degrees).
    pub axis_turn: f64,
}

/// Runs one spun throw of Clanet's disc to its end (or [`EVAL_CAP`] force evaluations).
pub fn spin_point(tilt: f64, rev_s: f64) -> Result<SpinPoint, SimError> {
    let p = clanet_spun(tilt, rev_s)?;
    let mut sim = Simulation::new(&p)?;
    while !sim.is_finished() && sim.cost().1 < EVAL_CAP {
        sim.tick();
    }
    let first = sim.contacts().first().copied();
    Ok(SpinPoint {
        skips: sim.skips(),
        first_skip: first.is_some_and(|c| c.skip && !c.open),
        inclination_change: first.map_or(0.0, |c| {
            inclination(c.attitude_out) - inclination(c.attitude_in)
        }),
        axis_turn: first.map_or(0.0, |c| {
            axis(c.attitude_in)
                .angle_between(axis(c.attitude_out))
                .to_degrees()
        }),
    })
}

/// One point of the spin-limited count.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CountPoint {
    /// rev/s; `None`: locked attitude.
    pub rev_s: Option<f64>,
    pub skips: usize,
    /// Contacts that end with the stone rising (a rebound, not a graze).
    pub rebounds: usize,
}

/// Skips of the typical stone at each spin (and locked, last).
pub fn spin_counts(spins: &[f64]) -> Result<Vec<CountPoint>, SimError> {
    let mut runs: Vec<Option<f64>> = spins.iter().map(|&s| Some(s)).collect();
    runs.push(None);
    runs.par_iter()
        .map(|&rev_s| {
            let s = stoneskip_physics::sim::simulate(&typical(rev_s))?;
            Ok(CountPoint {
                rev_s,
                skips: s.skips,
                rebounds: s
                    .contacts
                    .iter()
                    .filter(|c| c.skip && c.v_out[2] > 0.0)
                    .count(),
            })
        })
        .collect()
}

/// `n` points from `lo` to `hi`, evenly spaced in the logarithm (the ends exact).
pub fn logspace(lo: f64, hi: f64, n: usize) -> Vec<f64> {
    if n < 2 || lo <= 0.0 || hi <= 0.0 {
        return vec![lo];
    }
    let (a, b) = (lo.ln(), hi.ln());
    (0..n)
        .map(|i| match i {
            0 => lo,
            i if i == n - 1 => hi,
            i => (a + (b - a) * i as f64 / (n - 1) as f64).exp(),
        })
        .collect()
}

/// The spin-limited part of a count curve, counted in rebounds: spins whose count N is at least 2
/// and at most half the locked count N_L. Returns (spin, N) and (spin, N_spin) with
/// N_spin = N·N_L/(N_L − N): the spin limit alone when 1/N = 1/N_spin + 1/N_L.
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
