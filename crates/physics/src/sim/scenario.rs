//! Throws stated at impact, as the literature states them (Clanet et al. 2004; design.md §8):
//! speed U, impact angle β below the horizontal, attack (tilt) angle α, the stone's lowest point
//! just above the surface. The first contact's outcome and the minimal speed that skips
//! (bisection), for the magic-angle curves of physics.md §2–3.

use glam::DMat3;

use super::params::{Attitude, ForceLaw, Preset, Rotation, Shape, StoneParams};
use super::stone::{orientation_from_attitude, Stone};
use super::{SimError, Simulation};

/// Gap between the lowest point and the surface at the start of an impact throw (m): small
/// enough that gravity changes the velocity by less than 1e-5 m/s before the touch.
pub const IMPACT_CLEARANCE: f64 = 1e-6;

/// `base` with the launch replaced by a throw at impact along +x: speed `speed` (m/s) at angle
/// `beta` (rad) below the horizontal, the preset's attitude, the lowest point `clearance` above
/// z = 0.
pub fn at_impact(base: &Preset, speed: f64, beta: f64, clearance: f64) -> Result<Preset, SimError> {
    let mut p = base.clone();
    let stone = Stone::new(&p.stone)?;
    let r = DMat3::from_quat(orientation_from_attitude(&p.launch.attitude));
    let lowest = stone
        .mesh
        .positions
        .iter()
        .map(|&v| (r * v).z)
        .fold(f64::INFINITY, f64::min);
    p.launch.position = [0.0, 0.0, clearance - lowest];
    p.launch.velocity = [speed * beta.cos(), 0.0, -speed * beta.sin()];
    p.validate()?;
    Ok(p)
}

/// How the first contact of a throw ended.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FirstContact {
    /// Left the water (a skip).
    pub skipped: bool,
    /// Duration of the contact (s).
    pub duration: f64,
    /// Velocity after it (m/s).
    pub v_out: [f64; 3],
    /// Force evaluations spent.
    pub force_evals: u64,
}

/// Runs `preset` until its first contact episode ends (or the run ends). `None` if the stone
/// never touched the water.
pub fn first_contact(preset: &Preset) -> Result<Option<FirstContact>, SimError> {
    let mut sim = Simulation::new(preset)?;
    loop {
        let done = sim.contacts().first().is_some_and(|c| !c.open);
        if done || sim.is_finished() {
            break;
        }
        sim.tick();
    }
    Ok(sim.contacts().first().map(|c| FirstContact {
        skipped: c.skip,
        duration: c.t_end - c.t_start,
        v_out: c.v_out,
        force_evals: sim.cost().1,
    }))
}

/// Smallest impact speed in [`lo`, `hi`] m/s at impact angle `beta` whose first contact is a skip,
/// to relative precision `rel_tol`, by bisection (skipping is taken as monotone in speed). `None`
/// when even `hi` does not skip; `Some(lo)` when `lo` already skips.
pub fn min_speed(
    base: &Preset,
    beta: f64,
    lo: f64,
    hi: f64,
    rel_tol: f64,
) -> Result<Option<f64>, SimError> {
    let skips = |u: f64| -> Result<bool, SimError> {
        let p = at_impact(base, u, beta, IMPACT_CLEARANCE)?;
        Ok(first_contact(&p)?.is_some_and(|c| c.skipped))
    };
    if !skips(hi)? {
        return Ok(None);
    }
    if skips(lo)? {
        return Ok(Some(lo));
    }
    let (mut a, mut b) = (lo, hi);
    while (b - a) > rel_tol * b {
        let m = 0.5 * (a + b);
        if skips(m)? {
            b = m;
        } else {
            a = m;
        }
    }
    Ok(Some(0.5 * (a + b)))
}

/// Sizes the water grid to the throw (model no more than the scene needs): the stone is run once
/// without water (cheap), and the grid is made to cover its whole track plus `margin` metres on
/// every side, in whole cells. The lake's other settings are kept. With wavy contact the stone
/// rides on the water it moves and its track differs from the flat-water one it was sized on.
pub fn fit_water_to_throw(preset: &Preset, margin: f64) -> Result<Preset, SimError> {
    let mut dry = preset.clone();
    dry.water.enabled = false;
    let mut sim = Simulation::new(&dry)?;
    let start = sim.state().position;
    let (mut lo, mut hi) = ([start.x, start.y], [start.x, start.y]);
    sim.run(
        &mut |s| {
            let p = s.state.position;
            lo = [lo[0].min(p.x), lo[1].min(p.y)];
            hi = [hi[0].max(p.x), hi[1].max(p.y)];
        },
        &|| false,
    );
    let mut out = preset.clone();
    let cell = preset.water.cell;
    let span = |a: f64, b: f64| ((b - a + 2.0 * margin) / cell).ceil().max(8.0) * cell;
    out.water.origin = Some([lo[0] - margin, lo[1] - margin]);
    out.water.size = [span(lo[0], hi[0]), span(lo[1], hi[1])];
    out.validate()?;
    Ok(out)
}

/// Radius of the typical stone (m): Bocquet's R in N ≈ Rω²/g.
pub const TYPICAL_RADIUS: f64 = 0.05;

/// The typical stone of the spin-limited count: a 10 cm, 150 g disc thrown at 12 m/s from 25 cm with
/// V_z = −0.5 m/s at a 15° tilt, Rosellini law, water off; `None`: locked attitude.
pub fn typical(rev_s: Option<f64>) -> Preset {
    let mut p = Preset {
        name: "typical spun stone".into(),
        ..Preset::version_1()
    };
    p.stone = StoneParams {
        shape: Shape::Disk {
            radius: TYPICAL_RADIUS,
            thickness: 0.008,
        },
        mass: 0.15,
        segments: 48,
        bands: None,
        quadrature: Default::default(),
    };
    p.launch.position = [0.0, 0.0, 0.25];
    p.launch.velocity = [12.0, 0.0, -0.5];
    p.launch.attitude = Attitude {
        tilt_deg: 15.0,
        bank_deg: 0.0,
        heading_deg: 0.0,
    };
    p.physics.force_law = ForceLaw::Rosellini;
    p.physics.max_time = 20.0;
    match rev_s {
        Some(s) => {
            p.physics.rotation = Rotation::Free;
            p.launch.spin = s * std::f64::consts::TAU;
        }
        None => p.physics.rotation = Rotation::Locked,
    }
    p.water.enabled = false;
    p
}
