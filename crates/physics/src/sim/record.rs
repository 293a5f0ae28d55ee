//! The record of a run: how it ended ([`Outcome`]), each contact episode ([`ContactEvent`]: when,
//! where, how fast and at what attitude the stone came in and left, its peak lift, whether it
//! counts as a skip, design.md §4), the water's volumes, the summary `simulate --json` prints
//! (design.md §7) and one accepted step for trajectories ([`StepSample`]). Tang et al. (2021)'s
//! bounce threshold is kept beside the peak lift it is read against.

use glam::DVec3;
use serde::Serialize;

use super::integrate::BodyState;

/// How a run ended (design.md §4, contract).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Outcome {
    /// The stone's whole underside went below the surface.
    Sank,
    /// `max_time` reached.
    Timeout,
    /// Left the water grid (or 1 km with the water off).
    LeftDomain,
    /// The integration failed: a non-finite state (an explicit scheme unstable at its step) or a
    /// runaway step loop. [`Summary::diverged_reason`] says which.
    Diverged,
}

impl Outcome {
    /// The snake_case name the JSON summary writes (`sank`, `timeout`, `left_domain`, `diverged`).
    pub fn as_str(self) -> &'static str {
        match self {
            Outcome::Sank => "sank",
            Outcome::Timeout => "timeout",
            Outcome::LeftDomain => "left_domain",
            Outcome::Diverged => "diverged",
        }
    }

    /// The outcome as a person says it (the app and the text summary; the JSON keeps
    /// [`Outcome::as_str`]).
    pub fn words(self) -> &'static str {
        match self {
            Outcome::Sank => "sank",
            Outcome::Timeout => "still going at the time limit",
            Outcome::LeftDomain => "left the lake",
            Outcome::Diverged => "diverged (the numbers stopped being finite)",
        }
    }
}

/// One contact episode: from the first vertex reaching the surface until none is at or below it,
/// or until the stone sinks or the run ends.
///
/// On flat water (z = 0: wavy contact off) every episode that ends with the stone wholly above the
/// surface is a **skip** (design.md §4). With wavy contact the surface moves by itself — a swell's
/// crests and the rings of earlier contacts rise into the stone — so there an episode that ends in
/// the air is a skip only when the water turned the stone upward, `v_out.z > v_in.z`: the water's
/// vertical impulse over the episode, J_z = m (v_out.z − v_in.z) + m g (t_end − t_start), exceeded
/// what gravity took, i.e. its mean upward force beat the stone's weight. Otherwise it is a
/// **graze**: a crest brushed a stone that gravity kept decelerating (typically one still climbing
/// from the bounce before), listed but not counted. A bounce always qualifies (it turns a fall,
/// v_in.z < 0, into a climb, v_out.z > 0), and so does a rock-off that only slows a fall. The rule
/// has no parameter and does not depend on the tick.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct ContactEvent {
    /// When the first vertex reached the surface (s).
    pub t_start: f64,
    /// When the last touch ended, or the run did (s); not yet final while the contact is open.
    pub t_end: f64,
    /// Ended with the stone wholly above the surface (with wavy contact: turned upward, see above).
    pub skip: bool,
    /// With wavy contact: ended with the stone wholly above the surface without the water turning
    /// it upward (a crest's brush, not counted). Always false on flat water.
    pub graze: bool,
    /// Centre of mass when the episode started.
    pub x: f64,
    /// y of the centre of mass when the episode started (m).
    pub y: f64,
    /// Centre-of-mass velocity at the first touch (m/s, world).
    pub v_in: [f64; 3],
    /// Centre-of-mass velocity when the last touch ended, or the run did (m/s, world).
    pub v_out: [f64; 3],
    /// [tilt, bank, heading] in degrees, relative to the direction of travel.
    pub attitude_in: [f64; 3],
    /// [tilt, bank, heading] in degrees at the end, as `attitude_in`.
    pub attitude_out: [f64; 3],
    /// Angle of the velocity below the horizontal at the start (degrees).
    pub beta_in: f64,
    /// The largest upward force the water gave during the episode (N), read at every accepted
    /// step's end (0 if it never pushed up). Over the stone's weight it is the peak acceleration
    /// that Tang et al. (2021, Phys. Fluids 33, 037101) found a bounce needs, above 3.80 g.
    pub peak_lift: f64,
    /// How many touches the contact holds: episodes separated by flights shorter than the
    /// stone's diameter belong to one contact (a hop you cannot see is not a skip; design.md §4).
    pub touches: u32,
    /// The stone's weight (N) when the contact began, what its peak is read in g against: a
    /// later live change of gravity does not rewrite it.
    #[serde(skip)]
    pub weight: f64,
    /// Centre of mass (x, y) when the last touch ended (the start of the flight after it).
    #[serde(skip)]
    pub exit_xy: [f64; 2],
    /// The contact is still going on: the stone has not left the water since its last touch
    /// and the run has not ended.
    #[serde(skip)]
    pub open: bool,
}

impl ContactEvent {
    /// `peak_lift` as a multiple of the weight when the contact began; `None` without gravity
    /// (or with so little that the ratio overflows).
    pub fn peak_g(&self) -> Option<f64> {
        Some(self.peak_lift / self.weight).filter(|g| self.weight > 0.0 && g.is_finite())
    }
}

/// Tang et al. (2021, Phys. Fluids 33, 037101): their spun disc bounced only when the water gave
/// it an upward acceleration above this many g (a contact's [`ContactEvent::peak_lift`] over the
/// weight). A reference the app and the fidelity study draw, not a rule of the model.
pub const TANG_BOUNCE_G: f64 = 3.80;

/// Water volumes of a run (m³).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct WaterSummary {
    /// The grid's water volume at the start (m³).
    pub volume_initial: f64,
    /// The grid's water volume when the summary was taken (m³).
    pub volume_final: f64,
    /// Whether the water was stepped. A headless run whose results do not read the water (wavy
    /// contact off: the stone sees the plane z = 0) leaves it at rest; see
    /// [`Simulation::skip_unread_water`](super::Simulation::skip_unread_water).
    pub stepped: bool,
}

/// The result of a run, as `simulate --json` prints it (design.md §7).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Summary {
    /// Version of this JSON format (1).
    pub schema: u32,
    /// The preset's name.
    pub name: String,
    /// How the run ended; `None` (JSON `null`) while it goes on or when it was cancelled.
    pub outcome: Option<Outcome>,
    /// Why the run diverged (`outcome` "diverged"); `null` otherwise.
    pub diverged_reason: Option<String>,
    /// Contact episodes counted as skips ([`ContactEvent::skip`]).
    pub skips: usize,
    /// Horizontal distance from the launch position to where the stone is (where it ended, once
    /// the outcome is decided) (m).
    pub distance: f64,
    /// When the outcome was decided, or the simulated time so far while it is not (s).
    pub final_time: f64,
    /// Accepted integration steps of the stone.
    pub steps: u64,
    /// Evaluations of the stone's derivative (the water's forces), the run's cost.
    pub force_evals: u64,
    /// Every contact episode, in time order (skips and grazes, the last one possibly open).
    pub contacts: Vec<ContactEvent>,
    /// The water's volumes; `None` (JSON `null`) with the water off.
    pub water: Option<WaterSummary>,
}

/// One accepted integration step, for trajectories and plots: everything at the step's end.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StepSample {
    /// Simulated time at the step's end (s).
    pub time: f64,
    /// The stone's state at the step's end.
    pub state: BodyState,
    /// Angular velocity (world, rad/s); zero with a locked attitude.
    pub angular_velocity: DVec3,
    /// Some vertex is at or below the water surface.
    pub in_contact: bool,
    /// Wetted area (m²) and the water's force (N) at `state`, under every integrator.
    pub wetted_area: f64,
    /// The water's force on the stone at `state` (N, world).
    pub force: DVec3,
}
