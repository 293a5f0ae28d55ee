//! The throws the studies use, stated at impact as the literature states them (Clanet et al. 2004;
//! design.md §8): speed U, impact angle β below the horizontal, attack (tilt) angle α, the stone's
//! lowest point just above the surface (`scenario::at_impact`). The stone is the shipped default
//! (`Preset::version_1()`: a 5 cm, 100 g lens, Rosellini law, locked attitude); the phase study uses
//! Clanet's aluminium disc (R 2.5 cm, e 2.75 mm, 14.579 g).

use stoneskip_physics::sim::params::{ForceLaw, Integrator, Preset, Rotation, Shape, StoneParams};
use stoneskip_physics::sim::scenario::{at_impact, IMPACT_CLEARANCE};
use stoneskip_reference::{CLANET_MASS, CLANET_RADIUS, CLANET_THICKNESS};

use super::StudyError;

/// Most force evaluations one phase-map run may take; a run stopped there counts its skips so far.
pub const EVAL_CAP: u64 = 300_000;

/// A throw at impact.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Throw {
    /// Short name (CSV, file names).
    pub key: &'static str,
    /// Description for the reports.
    pub label: &'static str,
    /// Speed U (m/s).
    pub speed: f64,
    /// Impact angle β below the horizontal (degrees).
    pub beta_deg: f64,
    /// Attack (tilt) angle α (degrees).
    pub tilt_deg: f64,
}

/// A fast, flat throw that skips many times.
pub const FAST: Throw = Throw {
    key: "fast",
    label: "fast: U 12 m/s, β 10°, α 20°",
    speed: 12.0,
    beta_deg: 10.0,
    tilt_deg: 20.0,
};

/// A throw 1.4 % above the minimal speed of the default stone at α = β = 20° (3.353 m/s): one
/// skip, barely.
pub const MARGINAL: Throw = Throw {
    key: "marginal",
    label: "marginal: U 3.4 m/s, β 20°, α 20°",
    speed: 3.4,
    beta_deg: 20.0,
    tilt_deg: 20.0,
};

/// A steep throw, near the largest impact angle that still skips.
pub const STEEP: Throw = Throw {
    key: "steep",
    label: "steep: U 8 m/s, β 35°, α 25°",
    speed: 8.0,
    beta_deg: 35.0,
    tilt_deg: 25.0,
};

/// The three throws of the accuracy and defaults studies.
pub const THROWS: [Throw; 3] = [FAST, MARGINAL, STEEP];

/// The throws a study runs: all three, or the two short ones when `quick`.
pub fn throw_list(quick: bool) -> Vec<Throw> {
    if quick {
        vec![MARGINAL, STEEP]
    } else {
        THROWS.to_vec()
    }
}

/// The shipped default stone and physics with the water off (it does not act on the stone unless
/// `wavy_contact` is on), a given integrator, tick `dt` and Adaptive tolerance.
pub fn base(integrator: Integrator, dt: f64, tolerance: f64) -> Preset {
    let mut p = Preset {
        name: "study".into(),
        ..Preset::version_1()
    };
    p.water.enabled = false;
    p.physics.integrator = integrator;
    p.physics.dt = dt;
    p.physics.tolerance = tolerance;
    p.physics.max_time = 20.0;
    p
}

/// `base` thrown as `t`.
pub fn preset(t: &Throw, base: &Preset) -> Result<Preset, StudyError> {
    let mut b = base.clone();
    b.launch.attitude.tilt_deg = t.tilt_deg;
    b.launch.attitude.bank_deg = 0.0;
    b.launch.attitude.heading_deg = 0.0;
    Ok(at_impact(
        &b,
        t.speed,
        t.beta_deg.to_radians(),
        IMPACT_CLEARANCE,
    )?)
}

/// Clanet, Hersen & Bocquet's aluminium disc at tilt `tilt_deg`, locked attitude (the high-spin
/// limit), water off, under `law` with that law's default coefficients (design.md §4).
pub fn clanet_disc(law: ForceLaw, tilt_deg: f64) -> Preset {
    let mut p = Preset {
        name: "Clanet disc".into(),
        ..Preset::version_1()
    };
    p.stone = StoneParams {
        shape: Shape::Disk {
            radius: CLANET_RADIUS,
            thickness: CLANET_THICKNESS,
        },
        mass: CLANET_MASS,
        segments: 48,
        bands: None,
        quadrature: Default::default(),
    };
    p.launch.attitude.tilt_deg = tilt_deg;
    p.launch.spin = 0.0;
    p.physics.force_law = law;
    p.physics.lift_coefficient = None;
    p.physics.friction_coefficient = None;
    p.physics.rotation = Rotation::Locked;
    p.physics.integrator = Integrator::Adaptive;
    p.physics.max_time = 5.0;
    p.water.enabled = false;
    p
}
