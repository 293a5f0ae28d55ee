//! The physics of stoneskip: a stone (a triangle mesh of revolution) thrown at water, per-triangle
//! hydrodynamic forces in contact (paper §3.2, eqs. 11–29), time stepping (eqs. 4–8, 30–38 and
//! better schemes), and the O'Brien–Hodgins column-and-pipe water (paper §3.3, eqs. 39–41).
//!
//! [`Simulation`] advances in ticks of `physics.dt` (Adaptive sub-steps inside a tick, never across
//! one, unless `physics.steps_across_ticks` and no water takes the stone's loads: then its contact
//! steps may end past the tick, the pose drawn at the tick interpolated inside them). The time
//! step is a parameter, never read from a clock, and nothing is random: the same preset gives
//! bit-identical results. A tick may be split between two steps of the stone and
//! resumed ([`Simulation::tick_until`], the app's cost guard) without changing a bit. Depends on
//! glam, serde, thiserror and rayon only; knows nothing of frames, windows or wall-clock time.
//!
//! Events are located, not sampled at step ends: the first touch along the exact flight (its
//! clearance bounded along the torque-free motion and over the waves, so a tumbling stone's or a
//! crest's graze inside a tick is found), the exit, and the sinking instant inside the step that
//! sinks (and, across ticks, a step that leaves the water at one of its stages is retried up to
//! that stage, so a hop shorter than the step is found). A step reports the forces of its end, and
//! the water receives the stone's whole impulse, vertical and horizontal (Newton's third law, to
//! rounding).

pub mod air;
pub mod contact;
pub mod ending;
pub mod hydro;
pub mod integrate;
pub mod kernel;
pub mod lake;
pub mod law;
pub mod memory;
pub mod mesh;
pub mod metrics;
pub mod params;
pub mod scenario;
pub mod smooth;
pub mod stone;
pub mod water;
pub mod world;

#[cfg(test)]
mod touch_tests;

use std::cell::Cell;

use glam::{DMat3, DQuat, DVec3};
use serde::Serialize;

use air::Air;
pub use ending::{ending, Ending};
use hydro::{
    lowest_clearance, underside_submerged, FaceLoad, FlatSurface, ForceSum, HydroParams, Scratch,
    Surface,
};
use integrate::{
    first_touch, fly, mesh_orientation, q4, resal_applies, step_dp5, step_paper, step_rk4,
    step_symplectic_euler, BodyState, Deriv, Dynamics, ErrorScales, FlightBound, RevolutionBound,
    WaveBound,
};
pub use lake::{LakeGeometry, LakeJob, SteppedLake};
use memory::WettedMemory;
use params::{Integrator, ParamError, Physics, Preset, Rotation, Shape};
use stone::{orientation_from_attitude, reported_attitude, Stone};
use water::{EtaPatch, PatchReader, WaterGrid};

/// Errors of building or driving a simulation.
#[derive(Debug, thiserror::Error)]
pub enum SimError {
    /// The preset is invalid: a value out of range or inconsistent with another.
    #[error(transparent)]
    Param(#[from] ParamError),
}

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
    /// [`Simulation::skip_unread_water`].
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

/// Horizontal distance beyond which a run without water counts as `left_domain` (m).
pub(crate) const OPEN_WATER_LIMIT: f64 = 1000.0;

/// Most steps one tick may take before the run is declared diverged (a runaway step loop; cannot
/// happen with a positive minimum step, kept so a bug cannot hang the program).
pub(crate) const MAX_STEPS_PER_TICK: u32 = 1_000_000;

/// Most force evaluations one tick may use before the run is declared diverged: the work bound
/// the step guard alone does not give (each accepted step may follow up to ~180 rejected attempts
/// as the step shrinks from the tick to its 10⁻¹⁰ s floor; the headless soak, through the simulate
/// fuzz harness, found ticks of 2·10⁷ evaluations, minutes of CPU, at tolerances near 10⁻¹⁰,
/// finding S2). At ~10 µs an evaluation this is about 2 minutes.
pub const MAX_EVALS_PER_TICK: u64 = 10_000_000;

/// Face impulses a tick may gather before they are handed to the water mid-tick (48 B each, so
/// 3 MB). The grid sums them per column until it steps, so handing them over early gives the
/// same sums in the same order; without it a costly tick kept every loaded face of every step
/// (finding S3: 7 GB resident and growing in one tick of the session-10 soak).
pub(crate) const PENDING_FLUSH: usize = 1 << 16;

/// One face's impulse on the water over an accepted step, spread over a square of the face's wetted
/// footprint (Newton's third law of the face force, design.md §5): a footprint rather than a point, so
/// the forcing, and the rings, converge as the water's cells shrink below the stone's wetted area.
#[derive(Debug, Clone, Copy, PartialEq)]
struct PendingLoad {
    x: f64,
    y: f64,
    /// Half the side of the square of the footprint's area (m).
    half: f64,
    /// N·s, down.
    impulse: f64,
    /// N·s on the water along +x and +y (the stone's drag pushes the water forward).
    horizontal: [f64; 2],
}

/// The water's impulse on the stone over an accepted step from `a` to `b`, as the integrator itself
/// applied it: m·Δv + m·g·h ẑ (gravity is the only other force). The water receives its opposite.
fn water_impulse(mass: f64, gravity: f64, a: &BodyState, b: &BodyState, h: f64) -> DVec3 {
    mass * (b.velocity - a.velocity) + DVec3::Z * (mass * gravity * h)
}

impl Motion {
    /// Gives the water an accepted contact step's impulse: `j` is the water's impulse on the stone
    /// (N·s), the water receives −j exactly (Newton's third law, to rounding). The vertical part is
    /// spread over the faces loaded at the step's start and end, half the step each (a trapezoid over
    /// the faces), scaled so the parts sum to j_z; end-of-step loads alone (a rectangle rule) lose ~5 %
    /// of a contact's impulse at the default tolerance's few, long steps. The horizontal part goes to
    /// the same footprints in proportion to their |vertical| shares (the faces carry no separate
    /// record of their horizontal load; the sum is exact). The end loads become the next step's
    /// start loads.
    fn push_step_loads(&mut self, j: DVec3, h: f64, at: DVec3) {
        let end = &self.scratch.loads;
        let sum = |v: &[FaceLoad]| v.iter().map(|l| l.fz).sum::<f64>();
        let sum_abs = |v: &[FaceLoad]| v.iter().map(|l| l.fz.abs()).sum::<f64>();
        let trapezoid = 0.5 * h * (sum(&self.prev_loads) + sum(end));
        let weight = 0.5 * h * (sum_abs(&self.prev_loads) + sum_abs(end));
        let horizontal = if j.is_finite() {
            [-j.x, -j.y]
        } else {
            [0.0, 0.0]
        };
        if trapezoid == 0.0 || weight == 0.0 {
            // No face loaded at either end (wet only at inner stages, or only culled faces): the
            // impulse goes under the centre of mass.
            if j.is_finite() && j != DVec3::ZERO {
                self.pending.push(PendingLoad {
                    x: at.x,
                    y: at.y,
                    half: 0.0,
                    impulse: j.z,
                    horizontal,
                });
            }
            self.prev_loads.clear();
            return;
        }
        // The loads' own trapezoid if j is not finite (a diverging explicit scheme).
        let scale = if j.z.is_finite() {
            j.z / trapezoid
        } else {
            1.0
        };
        let dt = 0.5 * h * scale;
        let share = 0.5 * h / weight;
        self.pending
            .extend(self.prev_loads.iter().chain(end).map(|l| PendingLoad {
                x: l.x,
                y: l.y,
                half: 0.5 * l.footprint.max(0.0).sqrt(),
                impulse: l.fz * dt,
                horizontal: horizontal.map(|c| c * l.fz.abs() * share),
            }));
        self.prev_loads.clear();
        self.prev_loads.extend_from_slice(end);
    }
}

/// The surface the stone touches: z = 0, or the water grid's heights (wavy contact).
enum SurfaceRef<'a> {
    Flat,
    Water {
        /// The grid through the columns within the stone's reach this tick, copied once (read
        /// many times a step).
        reader: PatchReader<'a>,
        max: f64,
        slope: f64,
    },
}

impl<'a> SurfaceRef<'a> {
    fn new(
        water: &'a Option<WaterGrid>,
        patch: &'a EtaPatch,
        wavy: bool,
        max: f64,
        slope: f64,
    ) -> Self {
        match (water, wavy) {
            (Some(grid), true) => SurfaceRef::Water {
                reader: PatchReader::new(grid, patch),
                max,
                slope,
            },
            _ => SurfaceRef::Flat,
        }
    }

    /// An upper bound of the surface's slope |∇η| (0 when flat).
    fn max_slope(&self) -> f64 {
        match self {
            SurfaceRef::Flat => 0.0,
            SurfaceRef::Water { slope, .. } => *slope,
        }
    }
}

impl Surface for SurfaceRef<'_> {
    fn height(&self, x: f64, y: f64) -> f64 {
        match self {
            SurfaceRef::Flat => FlatSurface.height(x, y),
            SurfaceRef::Water { reader, .. } => reader.height(x, y),
        }
    }
    fn max_height(&self) -> f64 {
        match self {
            SurfaceRef::Flat => 0.0,
            SurfaceRef::Water { max, .. } => *max,
        }
    }
    fn max_height_over(&self, lo: [f64; 2], hi: [f64; 2]) -> f64 {
        match self {
            SurfaceRef::Flat => 0.0,
            SurfaceRef::Water { reader, max, .. } => reader.max_height_over(lo, hi).unwrap_or(*max),
        }
    }
    fn is_flat(&self) -> bool {
        matches!(self, SurfaceRef::Flat)
    }
}

/// The stone's motion and its bookkeeping (split from [`Simulation`] so the stone can step while
/// the mesh and water are borrowed).
#[derive(Debug, Clone)]
struct Motion {
    state: BodyState,
    time: f64,
    in_contact: bool,
    contacts: Vec<ContactEvent>,
    outcome: Option<Outcome>,
    diverged: Option<String>,
    end_time: f64,
    steps: u64,
    force_evals: u64,
    last_force: ForceSum,
    h_adaptive: f64,
    /// Derivative and forces at the current state, from the last contact step's end (the next
    /// step's first stage); `None` in flight or after a change of the physics or of the surface.
    fsal: Option<(Deriv, ForceSum)>,
    scratch: Scratch,
    /// Face impulses pushing the water down, gathered during the tick.
    pending: Vec<PendingLoad>,
    /// Face loads at the end of the last accepted contact step (the next step's start); empty in
    /// flight.
    prev_loads: Vec<FaceLoad>,
}

/// A throw in progress: stone, water and simulated time.
#[derive(Debug, Clone)]
pub struct Simulation {
    preset: Preset,
    stone: Stone,
    hydro: HydroParams,
    /// The air in flight (`physics.air`), `None`: exact force-free flight.
    air: Option<Air>,
    water: Option<WaterGrid>,
    water_max_eta: f64,
    /// Upper bound of the water surface's slope (wavy contact), for the flight's clearance bound.
    water_max_slope: f64,
    /// η of the columns within the stone's reach this tick (wavy contact), refreshed with the bounds.
    water_patch: EtaPatch,
    volume_initial: f64,
    /// Whether `tick` advances the water (and gives it the stone's impulses).
    step_water: bool,
    launch_position: DVec3,
    motion: Motion,
    /// The end of the last tick: the stone's own time, unless `physics.steps_across_ticks` let
    /// its last step end past it.
    clock: f64,
    /// That step, while the clock is inside it: the pose at the clock is drawn from it.
    overshoot: Option<Overshoot>,
    /// The tick begun by [`Simulation::tick_until`] and not yet finished (it yielded inside).
    open_tick: Option<OpenTick>,
    /// [`MAX_EVALS_PER_TICK`] (a field so a unit test can reach it cheaply).
    max_evals_per_tick: u64,
    /// [`PENDING_FLUSH`] (a field so a unit test can flush at every few loads).
    pending_flush: usize,
    /// The most face impulses held at once so far (the memory a tick's loads took).
    pending_high: usize,
    /// The lake is deferred ([`Simulation::defer_lake`]): the water's work is queued in `lake_ops`.
    defer_lake: bool,
    /// The water's work the ticks queued while deferred, in order.
    lake_ops: Vec<lake::LakeOp>,
    /// While the grid is handed out ([`Simulation::take_lake`]): where it lies, and the key it
    /// must come back with.
    lake_out: Option<(LakeGeometry, u64)>,
}

/// A tick in progress: its target time, its length and its step guard, so that the next call of
/// [`Simulation::tick_until`] continues the same tick exactly.
#[derive(Debug, Clone, Copy, PartialEq)]
struct OpenTick {
    t_end: f64,
    dt: f64,
    /// Steps taken in this tick so far (against [`MAX_STEPS_PER_TICK`]).
    steps: u32,
    /// The run's force evaluations when the tick began (against [`MAX_EVALS_PER_TICK`]).
    evals_start: u64,
}

/// How far a call of [`Simulation::tick_until`] got.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TickProgress {
    /// The tick is complete: the stone reached its end (or its outcome) and the water advanced.
    Done,
    /// The caller asked to yield between two steps of the stone; the next call continues the tick.
    Partial,
}

/// How far the stone got towards the tick's end.
enum StoneProgress {
    /// Reached the tick's end or the outcome.
    Reached,
    /// Yielded after this many steps of the tick.
    Yielded(u32),
}

impl Simulation {
    /// Builds a run from a preset (validated here).
    pub fn new(preset: &Preset) -> Result<Self, SimError> {
        preset.validate()?;
        let stone = Stone::new(&preset.stone)?;
        let l = &preset.launch;
        let state = launch_state(preset, &stone);
        let water = if preset.water.enabled {
            let origin = preset.water.origin_for([l.position[0], l.position[1]]);
            Some(WaterGrid::new(
                &preset.water,
                origin,
                preset.physics.gravity,
                preset.physics.water_density,
            )?)
        } else {
            None
        };
        let volume_initial = water.as_ref().map_or(0.0, |w| w.volume());
        let mut sim = Self {
            hydro: HydroParams::from_physics(&preset.physics),
            air: air_model(&preset.physics, &preset.stone.shape),
            preset: preset.clone(),
            water_max_eta: 0.0,
            water_max_slope: 0.0,
            water_patch: EtaPatch::default(),
            volume_initial,
            step_water: true,
            defer_lake: false,
            lake_ops: Vec::new(),
            lake_out: None,
            launch_position: state.position,
            motion: Motion {
                state,
                time: 0.0,
                in_contact: false,
                contacts: Vec::new(),
                outcome: None,
                diverged: None,
                end_time: 0.0,
                steps: 0,
                force_evals: 0,
                last_force: ForceSum::default(),
                h_adaptive: 0.0,
                fsal: None,
                scratch: Scratch::default(),
                pending: Vec::new(),
                prev_loads: Vec::new(),
            },
            stone,
            water,
            clock: 0.0,
            overshoot: None,
            open_tick: None,
            max_evals_per_tick: MAX_EVALS_PER_TICK,
            pending_flush: PENDING_FLUSH,
            pending_high: 0,
        };
        sim.refresh_water_max();
        let clearance = sim.clearance(&state);
        if clearance <= 0.0 {
            sim.motion.in_contact = true;
            let ev = sim.start_event(0.0, &state);
            sim.motion.contacts.push(ev);
        }
        Ok(sim)
    }

    /// The preset the run was built from, with the physics last given to
    /// [`Simulation::set_physics`].
    pub fn preset(&self) -> &Preset {
        &self.preset
    }
    /// The stone: its mesh, mass and inertia.
    pub fn stone(&self) -> &Stone {
        &self.stone
    }
    /// The air's model in flight (`None`: none, the exact parabola).
    pub fn air(&self) -> Option<&Air> {
        self.air.as_ref()
    }
    /// The stone's state at [`Simulation::time`].
    pub fn state(&self) -> &BodyState {
        &self.motion.state
    }
    /// Angular velocity (world, rad/s); zero with a locked attitude.
    pub fn angular_velocity(&self) -> DVec3 {
        integrate::angular_velocity(
            &self.stone,
            self.preset.physics.rotation,
            &self.motion.state,
        )
    }
    /// Position and orientation of the stone's body frame in the world at the last tick's end:
    /// the stone's own, or, when `physics.steps_across_ticks` let its last step end past the
    /// tick, interpolated inside that step (for drawing at the tick's time).
    pub fn world_from_stone(&self) -> (DVec3, DQuat) {
        match self.overshoot {
            Some(o) if self.clock > o.t0 && self.clock < self.motion.time => {
                o.pose_at(self.clock, self.motion.time, &self.motion.state)
            }
            _ => (self.motion.state.position, self.motion.state.orientation),
        }
    }
    /// Simulated time (s): the stone's, which is the last tick's end unless
    /// `physics.steps_across_ticks` let its last step end up to one step past it.
    pub fn time(&self) -> f64 {
        self.motion.time
    }
    /// How the run ended; `None` while it goes on.
    pub fn outcome(&self) -> Option<Outcome> {
        self.motion.outcome
    }
    /// When the outcome was decided (s): the sinking instant, the step that left the lake, the
    /// time limit; `None` while the run goes on. After it only the water moves on, and
    /// [`Simulation::time`] with it.
    pub fn end_time(&self) -> Option<f64> {
        self.motion.outcome.map(|_| self.motion.end_time)
    }
    /// Why the run diverged, when its outcome is [`Outcome::Diverged`].
    pub fn diverged_reason(&self) -> Option<&str> {
        self.motion.diverged.as_deref()
    }
    /// Whether the outcome is decided.
    pub fn is_finished(&self) -> bool {
        self.motion.outcome.is_some()
    }
    /// The contact episodes so far, in time order; the last may still be open.
    pub fn contacts(&self) -> &[ContactEvent] {
        &self.motion.contacts
    }
    /// Whether some vertex is at or below the water surface now (the last accepted step's end).
    pub fn in_contact(&self) -> bool {
        self.motion.in_contact
    }
    /// How many contact episodes so far are skips ([`ContactEvent::skip`]).
    pub fn skips(&self) -> usize {
        self.motion.contacts.iter().filter(|c| c.skip).count()
    }
    /// Forces at the end of the last accepted step.
    pub fn last_force(&self) -> ForceSum {
        self.motion.last_force
    }
    /// The column-and-pipe water; `None` with the water off, and while a deferred lake's grid is
    /// handed out ([`Simulation::take_lake`]).
    pub fn water(&self) -> Option<&WaterGrid> {
        self.water.as_ref()
    }

    /// Where the lake lies, also while its grid is handed out; `None` with the water off.
    pub fn lake_geometry(&self) -> Option<LakeGeometry> {
        match (&self.water, self.lake_out) {
            (Some(w), _) => Some(w.geometry()),
            (None, Some((g, _))) => Some(g),
            (None, None) => None,
        }
    }

    /// Defers the lake's work (`lake.rs`): the face impulses and the step at each tick's end are
    /// queued for [`Simulation::take_lake`] instead of done where the stone steps. Only where the
    /// stone does not read the columns (wavy contact off) and the water steps; returns whether the
    /// lake is now deferred. Turning it off does the queued work here (the grid must be home).
    pub fn defer_lake(&mut self, on: bool) -> bool {
        let can = self.water.is_some() && self.step_water && !self.preset.water.wavy_contact;
        if !on {
            self.settle_lake();
        }
        self.defer_lake = on && can;
        self.defer_lake
    }

    /// Hands the deferred lake's grid out with the work queued for it, to be run anywhere
    /// ([`LakeJob::run`]) and given back with [`Simulation::return_lake`]; `None` when the lake is
    /// not deferred, is already out, or has no work queued. While it is out the stone runs on
    /// (its motion never reads the grid) and its ticks queue more work.
    pub fn take_lake(&mut self) -> Option<LakeJob> {
        if !self.defer_lake || self.lake_ops.is_empty() {
            return None;
        }
        let grid = self.water.take()?;
        let key = lake::next_key();
        self.lake_out = Some((grid.geometry(), key));
        Some(LakeJob {
            grid,
            ops: std::mem::take(&mut self.lake_ops),
            key,
        })
    }

    /// Puts back a grid [`Simulation::take_lake`] handed out, once its job ran; false (and the
    /// grid dropped) when it is not this run's.
    pub fn return_lake(&mut self, stepped: SteppedLake) -> bool {
        match self.lake_out {
            Some((_, key)) if key == stepped.key => {
                self.water = Some(stepped.grid);
                self.lake_out = None;
                true
            }
            _ => false,
        }
    }

    /// Does the deferred lake's queued work here, if its grid is home.
    fn settle_lake(&mut self) {
        if let Some(w) = self.water.as_mut() {
            lake::apply(w, std::mem::take(&mut self.lake_ops));
        }
    }
    /// (accepted steps, force evaluations).
    pub fn cost(&self) -> (u64, u64) {
        (self.motion.steps, self.motion.force_evals)
    }
    /// The centre of mass at launch (m, world): where [`Simulation::distance`] is measured from.
    pub fn launch_position(&self) -> DVec3 {
        self.launch_position
    }
    /// Horizontal distance from the launch position to the centre of mass now.
    pub fn distance(&self) -> f64 {
        let d = self.motion.state.position - self.launch_position;
        (d.x * d.x + d.y * d.y).sqrt()
    }
    /// Mechanical energy (J): kinetic (translation and rotation) plus potential m g z.
    pub fn energy(&self) -> f64 {
        self.energy_of(&self.motion.state)
    }

    /// [`Simulation::energy`] of state `s`.
    fn energy_of(&self, s: &BodyState) -> f64 {
        let w = integrate::angular_velocity(&self.stone, self.preset.physics.rotation, s);
        0.5 * self.stone.mass * s.velocity.length_squared()
            + 0.5 * w.dot(s.angular_momentum)
            + self.stone.mass * self.preset.physics.gravity * s.position.z
    }

    /// Changes the physical constants live; takes effect at the next step, for the stone and the
    /// water grid alike (gravity and density set the grid's flow law and its automatic step).
    pub fn set_physics(&mut self, physics: Physics) -> Result<(), ParamError> {
        physics.validate()?;
        // The smooth quadrature's own conditions (a smooth spin).
        Preset {
            physics,
            ..self.preset.clone()
        }
        .check_quadrature()?;
        if self.lake_out.is_some() {
            return Err(ParamError::new(
                "physics",
                "the lake is being stepped elsewhere: give it back (return_lake) before changing the physics",
            ));
        }
        // The queued ticks ran under the old constants.
        self.settle_lake();
        if let Some(w) = self.water.as_mut() {
            w.set_constants(physics.gravity, physics.water_density)?;
        }
        self.preset.physics = physics;
        self.hydro = HydroParams::from_physics(&physics);
        self.air = air_model(&physics, &self.preset.stone.shape);
        self.motion.fsal = None;
        // The reach of the next tick depends on the tick.
        self.refresh_water_max();
        Ok(())
    }

    /// The run's result so far.
    pub fn summary(&self) -> Summary {
        let final_time = self.end_time().unwrap_or(self.motion.time);
        Summary {
            schema: 1,
            name: self.preset.name.clone(),
            outcome: self.motion.outcome,
            diverged_reason: self.motion.diverged.clone(),
            skips: self.skips(),
            distance: self.distance(),
            final_time,
            steps: self.motion.steps,
            force_evals: self.motion.force_evals,
            contacts: self.motion.contacts.clone(),
            water: self.water.as_ref().map(|w| WaterSummary {
                volume_initial: self.volume_initial,
                volume_final: w.volume(),
                stepped: self.step_water,
            }),
        }
    }

    /// Why the run ended, from its outcome and its last touch ([`ending()`]): the same words
    /// as the summary's, without copying the contacts.
    pub fn ending(&self) -> Ending {
        ending::read(
            self.motion.outcome,
            &self.motion.contacts,
            self.skips(),
            self.distance(),
            self.end_time().unwrap_or(self.motion.time),
        )
    }

    /// Runs until the stone's outcome is decided, calling `on_step` after every accepted step.
    /// `cancel` is polled once per tick; a cancelled run ends as it stands (no outcome).
    pub fn run(
        &mut self,
        on_step: &mut dyn FnMut(&StepSample),
        cancel: &dyn Fn() -> bool,
    ) -> Summary {
        while !self.is_finished() && !cancel() {
            self.tick_with(on_step);
        }
        self.summary()
    }

    /// Stops stepping the water when nothing the run reports depends on it: with wavy contact off
    /// the stone meets the plane z = 0, so its motion,
    /// contacts and outcome are the same with the water at rest (and the lake's edge does not end
    /// the run: only the far limit does). Headless runs call this; the app does not (it shows the rings).
    /// Returns whether the water is now left at rest; the summary says so (`water.stepped`).
    pub fn skip_unread_water(&mut self) -> bool {
        if self.water.is_some() && !self.preset.water.wavy_contact {
            self.step_water = false;
        }
        !self.step_water
    }

    /// Advances by one tick (`physics.dt`).
    pub fn tick(&mut self) {
        self.tick_with(&mut |_| {});
    }

    /// Advances by one tick, calling `on_step` after every accepted step of the stone. After the
    /// outcome the stone stays where it ended and only the water moves on. A tick that never
    /// yields: it also completes a tick left open by [`Simulation::tick_until`].
    pub fn tick_with(&mut self, on_step: &mut dyn FnMut(&StepSample)) {
        self.tick_until(on_step, &|_| false);
    }

    /// A tick that can stop early: `should_yield`, given the run's cost so far ([`Simulation::cost`]:
    /// accepted steps, force evaluations), is polled after every accepted step of the stone that
    /// leaves the tick unfinished (never inside a step, and never before the call's first step, so
    /// every call makes progress). When it says yield, the call returns
    /// [`TickProgress::Partial`] with the tick's target time and step guard kept, and the next call
    /// continues that same tick: a tick split over any number of calls gives bit-identical results
    /// to [`Simulation::tick_with`]. The water advances only once the stone's part of the tick is
    /// complete. The closure is how a caller brings in a wall clock; the simulation reads none.
    ///
    /// A tick once begun keeps its length even if [`Simulation::set_physics`] changes `dt` before
    /// it is complete; the new `dt` applies from the next tick.
    pub fn tick_until(
        &mut self,
        on_step: &mut dyn FnMut(&StepSample),
        should_yield: &dyn Fn((u64, u64)) -> bool,
    ) -> TickProgress {
        let tick = self.open_tick.take().unwrap_or_else(|| {
            let dt = self.preset.physics.dt;
            OpenTick {
                t_end: self.clock + dt,
                dt,
                steps: 0,
                evals_start: self.motion.force_evals,
            }
        });
        if !self.is_finished() {
            if let StoneProgress::Yielded(steps) = self.advance_stone(&tick, on_step, should_yield)
            {
                self.open_tick = Some(OpenTick { steps, ..tick });
                // The water takes the impulses only when it steps, at the tick's end, and nothing
                // reads them before: handing over those of the tick so far now gives the very sums
                // (same order) and spreads a costly tick's deposits (S1b: 3.6·10⁵ face loads a
                // tick) over the calls.
                self.deposit_pending();
                return TickProgress::Partial;
            }
        }
        self.finish_tick(tick.t_end, tick.dt);
        TickProgress::Done
    }

    /// A tick began and not yet complete (a [`Simulation::tick_until`] that yielded).
    pub fn tick_in_progress(&self) -> bool {
        self.open_tick.is_some()
    }

    /// The end of a tick once the stone is at `t_end`: the timeout, then the water's step of `dt`
    /// with the stone's impulses of the tick.
    fn finish_tick(&mut self, t_end: f64, dt: f64) {
        self.clock = t_end;
        // A stone whose last step ended past the tick (`steps_across_ticks`) keeps its time.
        self.motion.time = self.motion.time.max(t_end);
        if !self.is_finished() && self.clock >= self.preset.physics.max_time - 1e-12 {
            self.finish(Outcome::Timeout);
        }
        self.deposit_pending();
        // With wavy contact the stone reads the columns.
        let reads_columns = self.preset.water.wavy_contact;
        let mut moved = false;
        if self.defer_lake {
            self.lake_ops.push(lake::LakeOp::Advance(dt));
        } else if let Some(w) = self.water.as_mut().filter(|_| self.step_water) {
            let before = w.time();
            w.advance(dt);
            if w.time() != before && reads_columns {
                // The surface the last forces were evaluated on has moved.
                self.motion.fsal = None;
            }
            moved = true;
        }
        if moved {
            // Every tick: the bounds cover the region the stone can reach in the next one.
            self.refresh_water_max();
        }
    }

    /// Hands the face impulses gathered so far in the tick to the water, in their order (the grid
    /// sums them into its pending loads, applied when it next steps).
    fn deposit_pending(&mut self) {
        if self.defer_lake {
            if !self.motion.pending.is_empty() {
                let loads = std::mem::take(&mut self.motion.pending);
                self.lake_ops.push(lake::LakeOp::Deposit(loads));
            }
            return;
        }
        if let Some(w) = self.water.as_mut().filter(|_| self.step_water) {
            for l in &self.motion.pending {
                w.deposit_load_box(l.x, l.y, l.half, l.impulse, l.horizontal);
            }
        }
        self.motion.pending.clear();
    }

    /// The highest η and an upper bound of the slope |∇η| of the surface the stone can touch during
    /// the next tick: over the columns within its reach, the bounding radius plus twice the distance
    /// it can travel in a tick (its speed, plus what gravity adds, times the tick; the water only
    /// slows it) plus two cells. The bilinear surface's ∂η/∂x within a cell interpolates the
    /// x-differences of its two rows, so it is at most the largest |Δη| between neighbouring columns
    /// over l (likewise for y). Local, so its cost does not grow with the lake.
    fn refresh_water_max(&mut self) {
        if !self.preset.water.wavy_contact {
            self.water_max_eta = 0.0;
            self.water_max_slope = 0.0;
            return;
        }
        let reach = self.reach();
        let p = self.motion.state.position;
        let (m, slope) = if let Some(w) = &self.water {
            let r = reach + 2.0 * w.cell();
            local_bounds(w, &mut self.water_patch, p.x, p.y, r)
        } else {
            return;
        };
        self.water_max_eta = if m.is_finite() { m } else { 0.0 };
        self.water_max_slope = if slope.is_finite() {
            slope
        } else {
            f64::INFINITY
        };
    }

    /// How far from its centre of mass the stone can reach the water in the next tick: its bounding
    /// radius plus twice the distance it can travel (its speed, plus what gravity adds, times the
    /// tick; the water only slows it).
    fn reach(&self) -> f64 {
        let s = &self.motion.state;
        // Inside an open tick (a live change of the physics) the rest of that tick, too.
        let dt = self
            .open_tick
            .map_or(self.preset.physics.dt, |t| t.dt.max(self.preset.physics.dt));
        let speed = s.velocity.length() + self.preset.physics.gravity * dt;
        self.stone.bounding_radius + 2.0 * speed * dt
    }

    fn surface(&self) -> SurfaceRef<'_> {
        SurfaceRef::new(
            &self.water,
            &self.water_patch,
            self.preset.water.wavy_contact,
            self.water_max_eta,
            self.water_max_slope,
        )
    }

    fn clearance(&self, s: &BodyState) -> f64 {
        let q = mesh_orientation(self.resal(), s);
        lowest_clearance(&self.stone, s.position, q, &self.surface())
    }

    /// Whether the stone meets the water in the Résal frame (`axial_spin: Resal`).
    fn resal(&self) -> bool {
        let p = &self.preset.physics;
        resal_applies(&self.stone, p.rotation, p.axial_spin)
    }

    fn start_event(&self, t: f64, s: &BodyState) -> ContactEvent {
        let v = s.velocity;
        let vh = (v.x * v.x + v.y * v.y).sqrt();
        let att = reported_attitude(s.orientation, v);
        ContactEvent {
            t_start: t,
            t_end: t,
            skip: false,
            graze: false,
            x: s.position.x,
            y: s.position.y,
            v_in: v.to_array(),
            v_out: v.to_array(),
            attitude_in: att,
            attitude_out: att,
            beta_in: (-v.z).atan2(vh).to_degrees(),
            peak_lift: 0.0,
            touches: 1,
            weight: self.stone.mass * self.preset.physics.gravity,
            exit_xy: [s.position.x, s.position.y],
            open: true,
        }
    }

    /// The closed contact a touch at `at` continues: the last one, if it ended in the air less
    /// than the stone's diameter (horizontally) before `at`.
    fn continued_contact(&mut self, at: &BodyState) -> Option<&mut ContactEvent> {
        let diameter = 2.0 * self.preset.stone.shape.half_extent();
        self.motion.contacts.last_mut().filter(|ev| {
            let hop = (at.position.x - ev.exit_xy[0]).hypot(at.position.y - ev.exit_xy[1]);
            !ev.open && (ev.skip || ev.graze) && hop < diameter
        })
    }

    fn finish(&mut self, outcome: Outcome) {
        let s = self.motion.state;
        let t = self.motion.time;
        if let Some(ev) = self.motion.contacts.last_mut() {
            if ev.open {
                ev.open = false;
                ev.t_end = t;
                ev.skip = false;
                ev.graze = false;
                ev.v_out = s.velocity.to_array();
                ev.attitude_out = reported_attitude(s.orientation, s.velocity);
            }
        }
        self.motion.outcome = Some(outcome);
        self.motion.end_time = t;
    }

    /// Ends the run as diverged at the last finite state, with the reason.
    fn diverge(&mut self, reason: String) {
        self.motion.diverged = Some(reason);
        self.finish(Outcome::Diverged);
    }

    /// Steps the stone until `t_end` or its outcome, `steps` steps of the tick having been taken
    /// before; after every step that leaves the tick unfinished, yields if `should_yield` says so.
    fn advance_stone(
        &mut self,
        tick: &OpenTick,
        on_step: &mut dyn FnMut(&StepSample),
        should_yield: &dyn Fn((u64, u64)) -> bool,
    ) -> StoneProgress {
        let t_end = tick.t_end;
        let mut guard = tick.steps;
        let mut first = true;
        while self.motion.time < t_end && self.motion.outcome.is_none() {
            if !first && should_yield((self.motion.steps, self.motion.force_evals)) {
                return StoneProgress::Yielded(guard);
            }
            first = false;
            guard += 1;
            if guard > MAX_STEPS_PER_TICK {
                self.diverge(format!(
                    "more than {MAX_STEPS_PER_TICK} steps in one tick at t = {:.6} s (a runaway step loop)",
                    self.motion.time
                ));
                return StoneProgress::Reached;
            }
            let evals = self.motion.force_evals - tick.evals_start;
            if evals > self.max_evals_per_tick {
                self.diverge(format!(
                    "more than {} force evaluations in one tick at t = {:.6} s (after {guard} \
                     steps; a looser tolerance or a coarser mesh is cheaper)",
                    self.max_evals_per_tick, self.motion.time
                ));
                return StoneProgress::Reached;
            }
            let prev = self.motion.state;
            let t0 = self.motion.time;
            let h_max = t_end - t0;
            let h_contact = if self.steps_across_ticks() {
                (self.preset.physics.max_time - t0).max(h_max)
            } else {
                h_max
            };
            let step = self.take_step(h_max, h_contact);
            if !step.state.is_finite() || !self.energy_of(&step.state).is_finite() {
                // A diverging explicit scheme (e.g. Paper at a huge step): stop at the last finite
                // state rather than report NaN. A state can stay finite while its energy overflows
                // (finding S4: speeds of 1e223 m/s within one tick), so the energy is checked too.
                self.diverge(format!(
                    "the {:?} integrator's state (or its energy) became non-finite in a step of {:.3e} s from t = {t0:.6} s \
                     (unstable at this step; a smaller dt or the Adaptive integrator avoids it)",
                    self.preset.physics.integrator, step.h
                ));
                return StoneProgress::Reached;
            }
            if step.contact && self.water_takes_loads() {
                let j = water_impulse(
                    self.stone.mass,
                    self.preset.physics.gravity,
                    &prev,
                    &step.state,
                    step.h,
                );
                self.motion.push_step_loads(j, step.h, step.state.position);
                self.pending_high = self.pending_high.max(self.motion.pending.len());
                if self.motion.pending.len() >= self.pending_flush {
                    self.deposit_pending();
                }
            }
            self.overshoot = match (step.h > h_max && !step.sunk, step.k1, self.motion.fsal) {
                (true, Some(d0), Some((d1, _))) => Some(Overshoot {
                    t0,
                    s0: prev,
                    d0,
                    d1,
                }),
                _ => None,
            };
            self.motion.state = step.state;
            // A step to the tick's end ends exactly there; one past it (`steps_across_ticks`)
            // where it ends.
            self.motion.time = if step.h == h_max { t_end } else { t0 + step.h };
            self.motion.steps += 1;
            self.motion.last_force = step.force;
            self.after_step(&prev, step.h, step.sunk, on_step);
        }
        StoneProgress::Reached
    }

    /// Whether `Adaptive`'s contact steps may end past the tick: the preset asks for it and no
    /// water takes the stone's loads (nothing is coupled at the tick's end).
    fn steps_across_ticks(&self) -> bool {
        let physics = &self.preset.physics;
        physics.steps_across_ticks
            && physics.integrator == Integrator::Adaptive
            && !self.water_takes_loads()
    }

    /// One step with the preset's integrator: exact flight of at most `h_max`, or a contact step
    /// of at most `h_contact` (`Adaptive`; the fixed-step schemes take `h_max`) whose forces and
    /// face loads (in the scratch) are those of its end.
    fn take_step(&mut self, h_max: f64, h_contact: f64) -> Step {
        let physics = self.preset.physics;
        let surface = SurfaceRef::new(
            &self.water,
            &self.water_patch,
            self.preset.water.wavy_contact,
            self.water_max_eta,
            self.water_max_slope,
        );
        let cx = StepContext {
            dy: Dynamics {
                stone: &self.stone,
                hydro: self.hydro,
                gravity: physics.gravity,
                rotation: physics.rotation,
                surface: &surface,
                record_loads: self.water_takes_loads(),
                resal: self.resal(),
                memory: WettedMemory::new(physics.wetted_memory, &self.preset.stone.shape),
            },
            integrator: physics.integrator,
            tolerance: physics.tolerance,
            slope: surface.max_slope(),
            air: self.air,
            hidden_exits: h_contact > h_max,
            last_flight: Cell::new(None),
        };
        let m = &mut self.motion;
        let prev = m.state;
        let step = match physics.integrator {
            Integrator::Adaptive => adaptive_step(&cx, m, h_max, h_contact),
            _ => fixed_step(&cx, m, h_max),
        };
        match step.k1 {
            Some(k1) if step.contact && step.state.is_finite() => {
                locate_sink(&cx, m, &prev, &k1, step)
            }
            _ => step,
        }
    }

    /// Contact episodes and outcomes after an accepted step from `prev` over `h`; `sunk`: the step
    /// ended with the underside submerged.
    fn after_step(
        &mut self,
        prev: &BodyState,
        h: f64,
        sunk: bool,
        on_step: &mut dyn FnMut(&StepSample),
    ) {
        let s = self.motion.state;
        let t = self.motion.time;
        let now = self.clearance(&s) <= 0.0;
        let was = self.motion.in_contact;
        if now && !was {
            // Entry: the motion before it was flight; locate the first touch on that parabola.
            let sstar = self.bisect_crossing(prev, h, true);
            let at = self.fly(prev, sstar);
            if let Some(ev) = self.continued_contact(&at) {
                // A hop shorter than the stone: the same contact, one touch more.
                ev.open = true;
                ev.skip = false;
                ev.graze = false;
                ev.touches += 1;
            } else {
                let ev = self.start_event(t - h + sstar, &at);
                self.motion.contacts.push(ev);
            }
        } else if was && !now {
            // Exit: the motion after it is flight; locate the last touch backwards from here.
            let surface_flat = self.surface().is_flat();
            let sstar = self.bisect_crossing(&s, h, false);
            let at = self.fly(&s, -sstar);
            if let Some(ev) = self.motion.contacts.last_mut() {
                if ev.open {
                    ev.open = false;
                    // A touch shorter than the crossings' bisection tolerance can locate its exit
                    // a rounding before its entry: it ends where it began.
                    ev.t_end = (t - sstar).max(ev.t_start);
                    ev.v_out = at.velocity.to_array();
                    ev.exit_xy = [at.position.x, at.position.y];
                    ev.attitude_out = reported_attitude(at.orientation, at.velocity);
                    // On a moving surface, turned upward by the water: a skip; else a graze
                    // (see `ContactEvent`). On flat water every exit is a skip.
                    ev.graze = !surface_flat && ev.v_out[2] <= ev.v_in[2];
                    ev.skip = !ev.graze;
                }
            }
            // The stone cleared the ambient surface: the wetted-extent memory starts afresh.
            if self.motion.state.memory != 0.0 {
                self.motion.state.memory = 0.0;
                self.motion.fsal = None;
            }
        }
        self.motion.in_contact = now;
        let f = self.motion.last_force;
        if now {
            if let Some(ev) = self.motion.contacts.last_mut().filter(|e| e.open) {
                ev.peak_lift = ev.peak_lift.max(f.force.z);
            }
        }
        on_step(&StepSample {
            time: t,
            state: s,
            angular_velocity: self.angular_velocity(),
            in_contact: now,
            wetted_area: f.wetted_area,
            force: f.force,
        });
        if now && sunk {
            self.finish(Outcome::Sank);
            return;
        }
        // The lake's edge ends a throw only where the contact reads the columns (wavy contact);
        // on the ambient water the columns are a window of the rings the stone leaves, and the
        // throw runs on past them to the far limit (design.md §4).
        let left = match self
            .lake_geometry()
            .filter(|_| self.preset.water.wavy_contact)
        {
            Some(g) => !g.contains(s.position.x, s.position.y),
            None => self.distance() > OPEN_WATER_LIMIT,
        };
        if left {
            self.finish(Outcome::LeftDomain);
        }
    }

    /// Whether a lake will take the stone's face loads (there is one, and it steps).
    fn water_takes_loads(&self) -> bool {
        (self.water.is_some() || self.lake_out.is_some()) && self.step_water
    }

    /// The flight from `s` over `t` (with the air when the preset has it).
    fn fly(&self, s: &BodyState, t: f64) -> BodyState {
        let physics = &self.preset.physics;
        fly(
            &self.stone,
            physics.rotation,
            physics.gravity,
            self.air.as_ref(),
            s,
            t,
        )
    }

    /// Along the flight from `from` (forwards when `forward`, else backwards) over [0, h], the
    /// offset at which the lowest vertex reaches the surface.
    fn bisect_crossing(&self, from: &BodyState, h: f64, forward: bool) -> f64 {
        let sign = if forward { 1.0 } else { -1.0 };
        let clear = |s: f64| self.clearance(&self.fly(from, sign * s));
        // Forwards: dry at 0, wet at h. Backwards from a dry state: dry at 0, wet at h.
        let c_h = clear(h);
        if c_h > 0.0 {
            return h;
        }
        first_wet_between((0.0, clear(0.0)), (h, c_h), 60, clear)
    }
}

/// The stone's state at the launch.
fn launch_state(preset: &Preset, stone: &Stone) -> BodyState {
    let l = &preset.launch;
    let orientation = orientation_from_attitude(&l.attitude);
    let axis = orientation * DVec3::Z;
    let omega = axis * l.spin + DVec3::from_array(l.angular_velocity);
    let r = DMat3::from_quat(orientation);
    BodyState {
        position: DVec3::from_array(l.position),
        velocity: DVec3::from_array(l.velocity),
        orientation,
        angular_momentum: r * (stone.inertia * (r.transpose() * omega)),
        memory: 0.0,
    }
}

/// The centre of mass's path in the first flight of `preset` with `stone` (the aim preview), every
/// `dt` seconds from the launch until it reaches z = 0 (that point last) or `max_time` passes: the
/// run's own flight model, the air's forces included when the preset has them.
pub fn launch_arc(preset: &Preset, stone: &Stone, dt: f64, max_time: f64) -> Vec<DVec3> {
    let physics = &preset.physics;
    let air = air_model(physics, &preset.stone.shape);
    let fly_by =
        |s: &BodyState, t: f64| fly(stone, physics.rotation, physics.gravity, air.as_ref(), s, t);
    let mut s = launch_state(preset, stone);
    let mut path = vec![s.position];
    let steps = (max_time / dt).ceil().clamp(1.0, 10_000.0) as usize;
    for _ in 0..steps {
        let next = fly_by(&s, dt);
        if next.position.z <= 0.0 && s.position.z > 0.0 {
            // The last leg to the water, by bisection on its length.
            let t = first_wet(0.0, dt, 50, |t| fly_by(&s, t).position.z <= 0.0);
            path.push(fly_by(&s, t).position);
            break;
        }
        s = next;
        path.push(s.position);
    }
    path
}

/// The air of a physics setting for a stone of this shape.
fn air_model(physics: &Physics, shape: &Shape) -> Option<Air> {
    physics.air.map(|p| Air::for_shape(p, shape))
}

/// Bisection on [lo, hi] for the first offset that is wet, given dry at `lo` and wet at `hi`: at
/// most `iterations` halvings, stopping early when the interval reaches floating-point resolution.
fn first_wet(lo: f64, hi: f64, iterations: u32, wet: impl Fn(f64) -> bool) -> f64 {
    let (mut lo, mut hi) = (lo, hi);
    for _ in 0..iterations {
        let mid = 0.5 * (lo + hi);
        if mid <= lo || mid >= hi {
            break;
        }
        if wet(mid) {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    hi
}

/// The first wet offset in [lo, hi] of a flight whose clearance is `clear(t)`, dry at `lo` and wet
/// at `hi`: Illinois false position on the clearance with the bracket kept (the clearance is smooth
/// along a flight, so it takes a few flights where bisection takes fifty), to floating-point
/// resolution or `iterations` steps; the wet end. Ends that do not bracket fall back to halving
/// on wet or dry, as [`first_wet`].
fn first_wet_by(lo: f64, hi: f64, iterations: u32, clear: impl Fn(f64) -> f64) -> f64 {
    first_wet_between((lo, clear(lo)), (hi, clear(hi)), iterations, clear)
}

/// [`first_wet_by`] from ends whose clearances are known.
fn first_wet_between(
    (mut lo, mut c_lo): (f64, f64),
    (mut hi, mut c_hi): (f64, f64),
    iterations: u32,
    clear: impl Fn(f64) -> f64,
) -> f64 {
    if !(c_lo > 0.0 && c_hi <= 0.0 && c_lo.is_finite() && c_hi.is_finite()) {
        return first_wet(lo, hi, iterations, |t| clear(t) <= 0.0);
    }
    let mut side = 0;
    for _ in 0..iterations {
        let mut t = lo + (hi - lo) * (c_lo / (c_lo - c_hi));
        if !(t > lo && t < hi) {
            t = 0.5 * (lo + hi);
            if t <= lo || t >= hi {
                break;
            }
        }
        let c = clear(t);
        if c <= 0.0 {
            hi = t;
            c_hi = c;
            if side == -1 {
                c_lo *= 0.5;
            }
            side = -1;
        } else {
            lo = t;
            c_lo = c;
            if side == 1 {
                c_hi *= 0.5;
            }
            side = 1;
        }
        if hi - lo <= 2.0 * f64::EPSILON * hi.abs().max(f64::MIN_POSITIVE) {
            break;
        }
    }
    hi
}

/// A contact step that ended past the tick's end (`steps_across_ticks`): its start and the
/// derivatives at both ends. Its end is the stone's current state and time, which stay so until
/// the next step replaces this.
#[derive(Debug, Clone, Copy)]
struct Overshoot {
    t0: f64,
    s0: BodyState,
    d0: Deriv,
    d1: Deriv,
}

impl Overshoot {
    /// Position and orientation at `t` inside the step that ends at `t1` in `s1`: cubic Hermite
    /// on its ends' values and derivatives (third order; the orientation renormalised), for
    /// drawing only.
    fn pose_at(&self, t: f64, t1: f64, s1: &BodyState) -> (DVec3, DQuat) {
        let h = t1 - self.t0;
        let x = (t - self.t0) / h;
        let (x2, x3) = (x * x, x * x * x);
        let (h00, h10) = (2.0 * x3 - 3.0 * x2 + 1.0, x3 - 2.0 * x2 + x);
        let (h01, h11) = (-2.0 * x3 + 3.0 * x2, x3 - x2);
        let position = self.s0.position * h00
            + self.d0.dx * (h * h10)
            + s1.position * h01
            + self.d1.dx * (h * h11);
        let v = q4(self.s0.orientation) * h00
            + self.d0.dq * (h * h10)
            + q4(s1.orientation) * h01
            + self.d1.dq * (h * h11);
        let orientation = DQuat::from_xyzw(v.x, v.y, v.z, v.w).normalize();
        (position, orientation)
    }
}

/// One accepted step of the stone.
struct Step {
    state: BodyState,
    h: f64,
    /// Forces at the step's end.
    force: ForceSum,
    /// Integrated with the water's forces (its loads go to the water); false for exact flight.
    contact: bool,
    /// The derivative at the step's start (contact steps).
    k1: Option<Deriv>,
    /// Ended with the underside submerged.
    sunk: bool,
}

impl Step {
    fn flight(state: BodyState, h: f64) -> Self {
        Self {
            state,
            h,
            force: ForceSum::default(),
            contact: false,
            k1: None,
            sunk: false,
        }
    }
}

/// Everything a step needs besides the motion.
struct StepContext<'a> {
    dy: Dynamics<'a>,
    integrator: Integrator,
    tolerance: f64,
    /// Upper bound of the surface's slope (0 when flat).
    slope: f64,
    air: Option<Air>,
    /// A contact step that ends in the water but left it at a stage is shortened to that stage
    /// (`steps_across_ticks`: steps longer than the tick could hide a short hop).
    hidden_exits: bool,
    /// The last flight flown (start, duration, end): a flight step flies the interval its touch
    /// probe has just flown to prove it clear.
    last_flight: Cell<Option<(BodyState, f64, BodyState)>>,
}

impl StepContext<'_> {
    fn clear(&self, st: &BodyState) -> f64 {
        let q = mesh_orientation(self.dy.resal, st);
        lowest_clearance(self.dy.stone, st.position, q, self.dy.surface)
    }

    /// The underside wholly below the waterline the water's law sees (with the wetted-extent
    /// memory, the ambient surface raised by d_e − d_g).
    fn submerged(&self, st: &BodyState) -> bool {
        let q = mesh_orientation(self.dy.resal, st);
        underside_submerged(
            self.dy.stone,
            self.dy.wetted_position(st),
            q,
            self.dy.surface,
        )
    }

    fn flight(&self, s: &BodyState, t: f64) -> BodyState {
        if let Some((s0, t0, end)) = self.last_flight.get() {
            if s0 == *s && t0 == t {
                return end;
            }
        }
        let end = fly(
            self.dy.stone,
            self.dy.rotation,
            self.dy.gravity,
            self.air.as_ref(),
            s,
            t,
        );
        self.last_flight.set(Some((*s, t, end)));
        end
    }

    /// The first touch along the exact flight from `s` over [0, h] (see [`first_touch`]): `None`
    /// when proven clear, else the bracket of the first touch.
    fn touch(&self, s: &BodyState, h: f64) -> Option<(f64, f64)> {
        let stone = self.dy.stone;
        // With air the speed and the angular momentum change in flight: bound them over [0, h].
        let (a_air, m_air) = match &self.air {
            Some(air) => {
                let (f, m) = air.bounds(s.velocity.length() + 2.0 * self.dy.gravity * h);
                (f / stone.mass, m)
            }
            None => (0.0, 0.0),
        };
        let omega = match self.dy.rotation {
            Rotation::Locked => 0.0,
            Rotation::Free => {
                (s.angular_momentum.length() + m_air * h) / stone.principal_moments().min_element()
            }
        };
        let speed_h = s.velocity.x.hypot(s.velocity.y) + a_air * h;
        let max_eta = self.dy.surface.max_height();
        let radius = stone.bounding_radius;
        let mut bound =
            FlightBound::new(radius, speed_h, omega, self.slope, max_eta).with_air(a_air);
        let axis = self.axis_turn(s, m_air * h);
        if let Some((perp, _)) = axis {
            let facet = stone.facet_gap(self.slope).unwrap_or(f64::INFINITY);
            bound = bound.with_revolution(radius, speed_h, perp, self.slope, facet);
        }
        // At the origin no early-out applies: the lowest vertex's offset itself.
        let rise = |st: &BodyState| {
            let q = mesh_orientation(self.dy.resal, st);
            lowest_clearance(stone, DVec3::ZERO, q, &FlatSurface)
        };
        let crest = |lo: [f64; 2], hi: [f64; 2]| self.dy.surface.max_height_over(lo, hi);
        let wave = (!self.dy.surface.is_flat()).then(|| WaveBound {
            rise: &rise,
            crest: &crest,
            radius,
            rate: omega * radius,
            revolution: axis.map(|(perp, flat)| RevolutionBound {
                rate: perp * radius,
                facet: flat,
            }),
            drift: a_air,
        });
        first_touch(
            &|st: &BodyState, t: f64| self.flight(st, t),
            &|st: &BodyState| self.clear(st),
            &bound,
            wave.as_ref(),
            s,
            h,
        )
    }

    /// For a free body of revolution: a bound of the angular speed of its symmetry axis over a
    /// flight from `s` whose torques change the angular momentum by at most `kick` (N·m·s), and
    /// the facet gap of its rings on flat water. The axis turns at |ω⊥| = |L × a| / I₁, and a
    /// torque changes |L × a| by at most its own size. `None` for any other body or rotation.
    fn axis_turn(&self, s: &BodyState, kick: f64) -> Option<(f64, f64)> {
        let stone = self.dy.stone;
        if self.dy.rotation != Rotation::Free || !stone.is_axisymmetric() {
            return None;
        }
        let flat = stone.facet_gap(0.0)?;
        let a = s.orientation * DVec3::Z;
        let m = stone.principal_moments();
        Some((
            (s.angular_momentum.cross(a).length() + kick) / m.x.min(m.y),
            flat,
        ))
    }

    /// The contact step of this context's integrator from `s` (derivative `k1`) over `h`, with
    /// the forces evaluated (and the face loads recorded) at its end: (state, end derivative, end
    /// forces, force evaluations). Adaptive: one Dormand–Prince step, without error control.
    fn contact_step(
        &self,
        s: &BodyState,
        k1: &Deriv,
        h: f64,
        scratch: &mut Scratch,
    ) -> (BodyState, Deriv, ForceSum, u64) {
        let dy = &self.dy;
        let (state, evals) = match self.integrator {
            Integrator::Adaptive => {
                let scales = error_scales(dy, s);
                let a = step_dp5(dy, s, k1, h, self.tolerance, &scales, scratch);
                return (a.state, a.k_end, a.force_end, a.evals);
            }
            Integrator::Paper => (step_paper(dy, s, k1, h), 0),
            Integrator::SymplecticEuler => (step_symplectic_euler(dy, s, k1, h), 0),
            Integrator::Rk4 => (step_rk4(dy, s, k1, h, scratch), 3),
        };
        let (k_end, f_end) = dy.derivative(&state, scratch, true);
        (state, k_end, f_end, evals + 1)
    }
}

/// Scales of the Dormand–Prince error norm at state `s`.
fn error_scales(dy: &Dynamics, s: &BodyState) -> ErrorScales {
    let r = dy.stone.bounding_radius;
    let g = dy.gravity.max(1e-3);
    ErrorScales {
        position: r,
        velocity: s.velocity.length().max((g * r).sqrt()),
        angular_momentum: s
            .angular_momentum
            .length()
            .max(dy.stone.principal_moments().max_element() * (g / r).sqrt()),
    }
}

/// The derivative at the motion's state: the last step's end (FSAL) or a fresh evaluation.
fn start_derivative(dy: &Dynamics, m: &mut Motion) -> Deriv {
    match m.fsal {
        Some((k, _)) => k,
        None => {
            m.force_evals += 1;
            dy.derivative(&m.state, &mut m.scratch, false).0
        }
    }
}

/// One step of a fixed-step scheme over the rest of the tick `h_max`. Every scheme flies exactly
/// (eqs. 4–8 are exact for a parabola; the torque-free rotation has a closed form): they differ in
/// contact only. A flight that touches the water inside the tick but is clear again at its end (a
/// graze of a spinning stone, or over a wave) flies exactly to the touch; the scheme then steps from
/// there over the tick's rest.
fn fixed_step(cx: &StepContext, m: &mut Motion, h_max: f64) -> Step {
    let prev = m.state;
    let in_flight = |m: &mut Motion| {
        m.fsal = None;
        m.prev_loads.clear();
    };
    match cx.touch(&prev, h_max) {
        None => {
            in_flight(m);
            return Step::flight(cx.flight(&prev, h_max), h_max);
        }
        Some((lo, hi)) if hi > 0.0 && cx.clear(&cx.flight(&prev, h_max)) > 0.0 => {
            in_flight(m);
            let t = first_wet_by(lo, hi, 60, |t| cx.clear(&cx.flight(&prev, t)));
            return Step::flight(cx.flight(&prev, t), t);
        }
        Some(_) => {}
    }
    let k1 = start_derivative(&cx.dy, m);
    let (state, k_end, force, evals) = cx.contact_step(&prev, &k1, h_max, &mut m.scratch);
    m.force_evals += evals;
    m.fsal = Some((k_end, force));
    Step {
        state,
        h: h_max,
        force,
        contact: true,
        k1: Some(k1),
        sunk: false,
    }
}

/// How far the highest vertex of the faces whose outward normal points down is above the surface
/// (m): the underside is submerged (design.md §4 "sank", [`underside_submerged`]) exactly when this
/// is negative; +∞ without a downward face. Continuous in the state, so the sinking instant can be
/// found by a secant method.
fn underside_height(stone: &Stone, resal: bool, st: &BodyState, surface: &dyn Surface) -> f64 {
    let rot = DMat3::from_quat(mesh_orientation(resal, st));
    let mut highest = f64::NEG_INFINITY;
    let mut any_down = false;
    for (t, tri) in stone.mesh.triangles.iter().enumerate() {
        if (rot * stone.normals[t]).z >= 0.0 {
            continue;
        }
        any_down = true;
        for &i in tri {
            let w = st.position + rot * stone.mesh.positions[i as usize];
            highest = highest.max(w.z - surface.height(w.x, w.y));
        }
    }
    if any_down {
        highest
    } else {
        f64::INFINITY
    }
}

/// The sinking instant inside a contact step, located as entry and exit are: if the step from
/// `prev` ends with the underside submerged and did not start so, the step is cut to where the
/// underside's highest point reaches the surface, by the Illinois (regula falsi) method on the
/// integrator's own step from `prev`, to 1e-9 of the stone's size in height or of the step in time.
/// So the sinking time and place converge with the integrator rather than stopping at the step's
/// end.
fn locate_sink(cx: &StepContext, m: &mut Motion, prev: &BodyState, k1: &Deriv, step: Step) -> Step {
    if !cx.submerged(&step.state) {
        return step;
    }
    if cx.submerged(prev) {
        return Step { sunk: true, ..step };
    }
    let height = |st: &BodyState| {
        let wetted = BodyState {
            position: cx.dy.wetted_position(st),
            ..*st
        };
        underside_height(cx.dy.stone, cx.dy.resal, &wetted, cx.dy.surface)
    };
    let eps = 1e-9 * cx.dy.stone.bounding_radius;
    let (mut lo, mut f_lo) = (0.0, height(prev).max(0.0));
    let (mut hi, mut f_hi) = (step.h, height(&step.state).min(0.0));
    let mut side = 0i8;
    // The step to `hi` when the last trial set it (its end loads are the scratch's).
    let mut at_hi = None;
    for _ in 0..60 {
        if hi - lo <= 1e-9 * step.h || -f_hi <= eps {
            break;
        }
        let mut x = hi - f_hi * (hi - lo) / (f_hi - f_lo);
        if !(x > lo && x < hi) {
            x = 0.5 * (lo + hi);
        }
        let (s, k_end, force, evals) = cx.contact_step(prev, k1, x, &mut m.scratch);
        m.force_evals += evals;
        let fx = height(&s);
        at_hi = None;
        if fx < 0.0 && cx.submerged(&s) {
            (hi, f_hi) = (x, fx);
            at_hi = Some((s, k_end, force));
            if side == 1 {
                f_lo *= 0.5;
            }
            side = 1;
        } else {
            (lo, f_lo) = (x, fx.max(0.0));
            if side == -1 {
                f_hi *= 0.5;
            }
            side = -1;
        }
    }
    let (state, k_end, force) = at_hi.unwrap_or_else(|| {
        let (s, k, f, evals) = cx.contact_step(prev, k1, hi, &mut m.scratch);
        m.force_evals += evals;
        (s, k, f)
    });
    m.fsal = Some((k_end, force));
    Step {
        state,
        h: hi,
        force,
        contact: true,
        k1: Some(*k1),
        sunk: cx.submerged(&state),
    }
}

/// One Adaptive step: exact flight to `h_max` or to the first touch; error-controlled
/// Dormand–Prince steps of at most `h_contact` in contact.
fn adaptive_step(cx: &StepContext, m: &mut Motion, h_max: f64, h_contact: f64) -> Step {
    let dy = &cx.dy;
    let s = m.state;
    if !m.in_contact && cx.clear(&s) > 0.0 {
        m.fsal = None;
        m.prev_loads.clear();
        return match cx.touch(&s, h_max) {
            None => Step::flight(cx.flight(&s, h_max), h_max),
            Some((lo, hi)) => {
                // Locate the first touch by bisection on the exact flight.
                let t = first_wet_by(lo, hi, 80, |t| cx.clear(&cx.flight(&s, t)));
                Step::flight(cx.flight(&s, t), t)
            }
        };
    }
    let k1 = start_derivative(dy, m);
    let scales = error_scales(dy, &s);
    if m.h_adaptive <= 0.0 {
        // First contact: a fraction of the contact's time scale r / |v|.
        m.h_adaptive = 0.01 * dy.stone.bounding_radius / s.velocity.length().max(0.1);
    }
    let h_min = 1e-10;
    let mut h = m.h_adaptive.min(h_contact);
    let c0 = cx.clear(&s).min(0.0);
    let mut exit_refinements = 0;
    let mut hidden_refinements = 0;
    // With the memory: the estimated time to the exit from `s` once a step has been shortened
    // towards it ([`EXIT_APPROACH`]).
    let mut approach = None;
    loop {
        let attempt = step_dp5(dy, &s, &k1, h, cx.tolerance, &scales, &mut m.scratch);
        m.force_evals += attempt.evals;
        let err = attempt.error;
        let c1 = cx.clear(&attempt.state);
        if dy.memory.is_some() && c1 > 0.0 && err > 1.0 && exit_refinements < MAX_EXIT_APPROACHES {
            let exit = h * (-c0 / (c1 - c0));
            if exit > 0.0 && exit < h {
                exit_refinements += 1;
                approach = Some(exit);
                h = (exit * EXIT_APPROACH).max(h_min);
                continue;
            }
        }
        if err <= 1.0 || h <= h_min {
            // Leaving the water inside the step: the force has a kink there, which the error
            // estimate does not see. Shorten the step to end at the exit (secant on the lowest
            // vertex's clearance), so no step integrates across it.
            if c1 > 0.0 && exit_refinements < 3 && h > 64.0 * h_min {
                let f = -c0 / (c1 - c0);
                if f < 0.99 {
                    exit_refinements += 1;
                    h = (h * f * 1.0001).max(h_min);
                    continue;
                }
            }
            // In the water at both ends but out of it at a stage: the step may have jumped a
            // short hop. Retry it shortened to that stage, so the exit, if there is one, falls at
            // or before its end and is located as above.
            if let Some(c) = attempt.first_dry.filter(|_| cx.hidden_exits && c1 <= 0.0) {
                if hidden_refinements < 3 && h > 64.0 * h_min {
                    hidden_refinements += 1;
                    exit_refinements += 1;
                    h = (h * c).max(h_min);
                    continue;
                }
            }
            let grow = if err > 0.0 {
                (0.9 * err.powf(-0.2)).clamp(0.2, 5.0)
            } else {
                5.0
            };
            // A step clipped by the tick boundary or shortened to the exit keeps the
            // controller's earlier proposal.
            let clipped = (h >= h_contact && m.h_adaptive > h_contact) || exit_refinements > 0;
            if let Some(exit) = approach {
                // Approaching the memory's exit: the next step tries to reach past it.
                m.h_adaptive = (h * grow).min((exit - h) * EXIT_REACH).max(h_min);
            } else if !clipped || grow < 1.0 {
                m.h_adaptive = (h * grow).max(h_min);
            }
            m.fsal = Some((attempt.k_end, attempt.force_end));
            return Step {
                state: attempt.state,
                h,
                force: attempt.force_end,
                contact: true,
                k1: Some(k1),
                sunk: false,
            };
        }
        let shrink = if err.is_finite() {
            (0.9 * err.powf(-0.2)).clamp(0.1, 0.9)
        } else {
            0.1
        };
        h = (h * shrink).max(h_min);
    }
}

/// A contact with the wetted-extent memory ends in a singular tail: as the stone leaves, its
/// geometric wetted length s_g goes to 0, so the memory's relaxation rate |U|/(λ s_g) grows
/// without bound while d_e still holds millimetres (`memory.rs`), and at the geometric exit the
/// load drops from that of d_e to nothing. A step that reaches across the exit sees d_e change at
/// tens of m/s and its error estimate explodes; shrinking by that estimate alone approached the
/// exit geometrically with a rejection each time (4 in 10 of the default throw's force
/// evaluations). Such a step is instead shortened to this share of the estimated time to the exit
/// (secant on the lowest point's clearance), and the next one reaches [`EXIT_REACH`] times past
/// what is left, until a step that crosses passes its error test and is cut at the exit.
const EXIT_APPROACH: f64 = 0.8;

/// After a step shortened towards the exit ([`EXIT_APPROACH`]), the next tries this many times the
/// estimated rest.
const EXIT_REACH: f64 = 1.25;

/// Most times one contact step is shortened towards the exit ([`EXIT_APPROACH`]).
const MAX_EXIT_APPROACHES: u32 = 4;

/// The highest η (−∞ when no column lies within `reach` of (x, y)) and the largest
/// |Δη|/l between neighbouring columns there, over the columns whose centres lie within `reach`
/// (m) of (x, y) in x and y, and one more on each side; those columns are left in `patch`.
fn local_bounds(w: &WaterGrid, patch: &mut EtaPatch, x: f64, y: f64, reach: f64) -> (f64, f64) {
    let [ox, oy] = w.origin();
    let l = w.cell();
    let span = |c: f64, o: f64, n: usize| {
        let lo = ((c - reach - o) / l - 1.5).floor().max(0.0);
        let hi = ((c + reach - o) / l + 0.5).ceil().min(n as f64 - 1.0);
        (lo as usize, hi as usize, hi >= lo)
    };
    let (x0, x1, okx) = span(x, ox, w.nx());
    let (y0, y1, oky) = span(y, oy, w.ny());
    w.fill_patch(patch, (x0, x1), (y0, y1));
    if !(okx && oky) {
        return (f64::NEG_INFINITY, 0.0);
    }
    // Beyond the grid the surface is at rest (η = 0): count it when the reach extends past an edge.
    let inside = |c: f64, o: f64, n: usize| c - reach > o && c + reach < o + n as f64 * l;
    let mut m = if inside(x, ox, w.nx()) && inside(y, oy, w.ny()) {
        f64::NEG_INFINITY
    } else {
        0.0
    };
    let (mut sx, mut sy) = (0.0f64, 0.0f64);
    for iy in y0..=y1 {
        for ix in x0..=x1 {
            let e = patch.at(ix, iy);
            m = m.max(e);
            if ix > x0 {
                sx = sx.max((e - patch.at(ix - 1, iy)).abs());
            }
            if iy > y0 {
                sy = sy.max((e - patch.at(ix, iy - 1)).abs());
            }
        }
    }
    (m, sx.hypot(sy) / l)
}

/// Runs a preset to its end, headless: the water is left at rest when nothing reads it
/// ([`Simulation::skip_unread_water`]).
pub fn simulate(preset: &Preset) -> Result<Summary, SimError> {
    let mut sim = Simulation::new(preset)?;
    sim.skip_unread_water();
    Ok(sim.run(&mut |_| {}, &|| false))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `stone.quadrature: Smooth` on a disk (as a version-2 file or the app's shape menu leaves
    /// it when the shipped lens becomes a disk) throws exactly as the disk's faces.
    #[test]
    fn a_smooth_flag_on_a_disk_throws_as_its_faces() {
        let mut p = Preset::default();
        p.stone.shape = params::Shape::Disk {
            radius: 0.05,
            thickness: 0.01,
        };
        p.physics.max_time = 1.0;
        assert!(!p.stone.quadrature.is_faces());
        let smooth = simulate(&p).unwrap();
        p.stone.quadrature = params::Quadrature::Faces;
        assert_eq!(smooth, simulate(&p).unwrap());
        assert!(smooth.contacts.len() > 1, "{smooth:?}");
    }

    #[test]
    fn outcomes_read_as_words() {
        assert_eq!(Outcome::Sank.words(), "sank");
        assert_eq!(Outcome::LeftDomain.words(), "left the lake");
        assert_eq!(Outcome::Timeout.words(), "still going at the time limit");
    }

    /// Issue 48: on the ambient water (wavy contact off) the lake's edge ends nothing — the stone
    /// flies on past the columns and the throw ends by its physics; with wavy contact the stone
    /// reads the columns, so their edge still ends the run (`left_domain`).
    #[test]
    fn only_wavy_contact_ends_a_throw_at_the_lake_edge() {
        let mut p = Preset::default();
        p.water.size = [3.0, 2.0];
        p.water.origin = Some([-1.0, -1.0]);
        p.water.cell = 0.05;
        p.physics.max_time = 3.0;
        let ambient = simulate(&p).unwrap();
        assert_ne!(ambient.outcome, Some(Outcome::LeftDomain), "{ambient:?}");
        assert!(ambient.distance > 3.0, "{}", ambient.distance);
        let mut wavy = p.clone();
        wavy.water.wavy_contact = true;
        let edged = simulate(&wavy).unwrap();
        assert_eq!(edged.outcome, Some(Outcome::LeftDomain), "{edged:?}");
        assert!(edged.distance < 2.5, "{}", edged.distance);
    }

    /// Live physics edits keep a smooth stone's conditions: a faceted spin under free rotation or
    /// is refused with the field named, and the run goes on as it was.
    #[test]
    fn live_physics_keeps_the_smooth_quadrature_consistent() {
        let mut p = Preset::version_1();
        p.water.enabled = false;
        p.stone.quadrature = params::Quadrature::Smooth {
            meridian: 8,
            around: 4,
        };
        let mut sim = Simulation::new(&p).unwrap();
        let mut faceted = p.physics;
        faceted.rotation = Rotation::Free;
        faceted.axial_spin = params::AxialSpin::Faceted;
        assert_eq!(
            sim.set_physics(faceted).unwrap_err().field,
            "physics.axial_spin"
        );
        assert_eq!(sim.preset.physics, p.physics);
        let mut heavier = p.physics;
        heavier.gravity = 12.0;
        sim.set_physics(heavier).unwrap();
    }

    /// A deferred lake (`lake.rs`), handed out every few ticks and stepped on another thread while
    /// the stone runs on, ends bit for bit as the lake stepped at every tick's end, and the stone's
    /// run is the same; the stone flies on past the lake's edge (the ambient water's columns are a
    /// window of rings, issue 48), while the grid is out a physics edit is refused, and a grid goes back only to the run it came from.
    #[test]
    fn a_lake_stepped_elsewhere_is_the_lake_stepped_here() {
        let mut p = Preset::default();
        p.water.size = [8.0, 3.0];
        p.water.origin = Some([-1.0, -1.5]);
        p.water.cell = 0.05;
        p.physics.max_time = 1.5;
        let mut here = Simulation::new(&p).unwrap();
        while !here.is_finished() {
            here.tick();
        }
        let mut away = Simulation::new(&p).unwrap();
        assert!(away.defer_lake(true));
        let mut job: Option<std::thread::JoinHandle<SteppedLake>> = None;
        let mut ticks = 0;
        while !away.is_finished() {
            away.tick();
            ticks += 1;
            if ticks % 3 == 0 {
                if let Some(j) = job.take() {
                    assert!(away.return_lake(j.join().unwrap()));
                }
                if let Some(next) = away.take_lake() {
                    assert!(away.water().is_none() && away.lake_geometry().is_some());
                    assert!(away.set_physics(away.preset().physics).is_err());
                    job = Some(std::thread::spawn(move || next.run()));
                }
            }
        }
        if let Some(j) = job.take() {
            assert!(away.return_lake(j.join().unwrap()));
        }
        assert!(!away.defer_lake(false));
        assert_eq!(here.summary(), away.summary());
        assert_ne!(away.outcome(), Some(Outcome::LeftDomain));
        let end = away.state().position;
        let lake = away.lake_geometry().unwrap();
        assert!(
            !lake.contains(end.x, end.y),
            "ended at {end:?}, inside the lake"
        );
        let (a, b) = (here.water().unwrap(), away.water().unwrap());
        assert_eq!(a.steps(), b.steps());
        assert!(a.steps() > 20 && a.max_abs_eta() > 1e-4, "{}", a.steps());
        for iy in 0..a.ny() {
            for ix in 0..a.nx() {
                assert_eq!(a.eta(ix, iy).to_bits(), b.eta(ix, iy).to_bits());
            }
        }
        // A grid from another run is refused (and this run's lake stays out).
        let mut other = Simulation::new(&p).unwrap();
        other.defer_lake(true);
        other.tick();
        let stranger = other.take_lake().unwrap().run();
        away.defer_lake(true);
        away.tick();
        let _out = away.take_lake().unwrap();
        assert!(!away.return_lake(stranger));
        assert!(away.water().is_none());
    }

    /// With wavy contact the stone reads the columns: the lake cannot be deferred.
    #[test]
    fn a_lake_the_stone_reads_is_not_deferred() {
        let mut p = Preset::default();
        p.water.wavy_contact = true;
        p.water.size = [4.0, 2.0];
        p.water.origin = Some([-1.0, -1.0]);
        p.water.cell = 0.05;
        let mut sim = Simulation::new(&p).unwrap();
        assert!(!sim.defer_lake(true));
        sim.tick();
        assert!(sim.take_lake().is_none());
    }

    /// Finding S3: a costly tick's face impulses are handed to the water once they reach the
    /// flush bound, not kept to the tick's end; the grid sums them per column in the same order,
    /// so the run is bit for bit the one that kept them all, stone and water alike.
    #[test]
    fn a_costly_ticks_face_loads_are_flushed_with_the_same_results() {
        let mut p = Preset::version_1();
        p.physics.tolerance = 1e-9;
        p.physics.dt = 0.02;
        p.physics.max_time = 0.6;
        p.water.wavy_contact = true;
        p.water.size = [6.0, 2.0];
        p.water.origin = Some([-1.0, -1.0]);
        p.water.cell = 0.05;
        let run = |flush: usize| {
            let mut sim = Simulation::new(&p).unwrap();
            sim.pending_flush = flush;
            while !sim.is_finished() {
                sim.tick();
            }
            sim
        };
        let (kept, flushed) = (run(usize::MAX), run(64));
        assert!(
            kept.pending_high > 1_000,
            "a tick held {}",
            kept.pending_high
        );
        // At most the bound plus one step's start and end loads.
        let faces = 2 * kept.stone.mesh.triangles.len();
        assert!(
            flushed.pending_high < 64 + faces,
            "{}",
            flushed.pending_high
        );
        assert_eq!(kept.summary(), flushed.summary());
        let (a, b) = (kept.water().unwrap(), flushed.water().unwrap());
        for iy in 0..a.ny() {
            for ix in 0..a.nx() {
                assert_eq!(
                    a.eta(ix, iy).to_bits(),
                    b.eta(ix, iy).to_bits(),
                    "column {ix}, {iy}"
                );
            }
        }
    }

    /// A tick's work is bounded by evaluations, not only by steps: the fuzz-found costly preset
    /// (a 36 cm disc at tolerance 1.3e-10, found by the headless soak: 2.3·10⁷ evaluations in one
    /// tick) with the guard lowered so the test is quick ends `diverged` with the reason, its tick
    /// within the guard plus one step's attempts.
    #[test]
    fn a_tick_past_its_evaluation_guard_is_reported_diverged() {
        let mut p = Preset::version_1();
        p.stone.shape = params::Shape::Disk {
            radius: 0.181,
            thickness: 0.0764,
        };
        p.stone.mass = 0.449;
        p.stone.segments = 79;
        p.launch.position = [0.0, 0.0, 0.17];
        p.launch.velocity = [13.68, -3.57, -10.22];
        p.launch.attitude.tilt_deg = 19.7;
        p.launch.attitude.bank_deg = 56.3;
        p.physics.force_law = params::ForceLaw::Bocquet;
        p.physics.tolerance = 1.29e-10;
        p.physics.dt = 4.06e-4;
        p.physics.max_time = 0.0588;
        p.water.enabled = false;
        let mut sim = Simulation::new(&p).unwrap();
        sim.max_evals_per_tick = 20_000;
        let mut worst = 0;
        while !sim.is_finished() {
            let before = sim.cost().1;
            sim.tick();
            worst = worst.max(sim.cost().1 - before);
        }
        assert_eq!(
            sim.outcome(),
            Some(Outcome::Diverged),
            "{:?}",
            sim.summary()
        );
        let why = sim.diverged_reason().unwrap();
        assert!(why.contains("force evaluations in one tick"), "{why}");
        assert!(worst <= 20_000 + 10_000, "{worst} evaluations in a tick");
    }

    /// The aim preview follows the run's own flight: a vacuum parabola without air, a longer arc
    /// with the lift of a stone tilted into the flow, each ending on the water where the run's
    /// first touch of the centre of mass would be.
    #[test]
    fn the_launch_arc_is_the_runs_first_flight() {
        let mut p = Preset::version_1();
        p.launch.position = [0.0, 0.0, 0.3];
        p.launch.velocity = [12.0, 0.0, 0.0];
        let stone = Stone::new(&p.stone).unwrap();
        let vacuum = launch_arc(&p, &stone, 0.01, 5.0);
        let end = *vacuum.last().unwrap();
        assert!(end.z.abs() < 1e-9, "ends on the water: {end}");
        let t = (2.0 * 0.3 / p.physics.gravity).sqrt();
        assert!(
            (end.x - 12.0 * t).abs() < 1e-9,
            "the parabola lands at {}",
            12.0 * t
        );
        p.physics.air = Some(air::AirParams::default());
        let with_air = launch_arc(&p, &stone, 0.01, 5.0);
        let end_air = *with_air.last().unwrap();
        assert!(end_air.z.abs() < 1e-9);
        assert!(
            end_air.x > end.x,
            "lift carries it farther: {} vs {}",
            end_air.x,
            end.x
        );
        let sim = Simulation::new(&p).unwrap();
        let direct = sim.fly(&launch_state(&p, &stone), 0.1);
        let on_arc = with_air[10];
        assert!(
            (direct.position - on_arc).length() < 1e-6,
            "{direct:?} vs {on_arc}"
        );
    }

    /// With wavy contact off the stone meets the plane z = 0, so leaving the water at rest changes
    /// nothing the run reports about the stone, bit for bit; with wavy contact on, the water is read
    /// and keeps stepping.
    #[test]
    fn unread_water_is_left_at_rest_without_changing_the_stone() {
        let mut p = Preset::version_1();
        p.water.wavy_contact = false;
        p.water.cell = 0.05;
        p.water.size = [16.0, 2.0];
        p.physics.max_time = 1.0;
        let mut stepped = Simulation::new(&p).unwrap();
        let a = stepped.run(&mut |_| {}, &|| false);
        let b = simulate(&p).unwrap();
        let (wa, wb) = (a.water.unwrap(), b.water.unwrap());
        assert!(wa.stepped && !wb.stepped);
        assert_eq!(wb.volume_final, wb.volume_initial);
        assert!(a.skips >= 1, "{a:?}");
        assert_eq!(Summary { water: None, ..a }, Summary { water: None, ..b });
        let mut q = p.clone();
        q.water.wavy_contact = true;
        let mut sim = Simulation::new(&q).unwrap();
        assert!(!sim.skip_unread_water());
        sim.tick();
        assert!(sim.summary().water.unwrap().stepped);
    }

    /// `steps_across_ticks` (numerics): with no water taking the stone's loads, the contact steps
    /// end past the tick, so the same throw takes fewer force evaluations. It is the same equation
    /// solved to the same tolerance, so both runs keep the skips and land within the integration
    /// error of a tight-tolerance run: at most the sum of the local errors, each at most the
    /// tolerance (relative to the error norm's scales), so `steps × tolerance` relative.
    #[test]
    fn steps_across_ticks_take_fewer_evaluations_for_the_same_throw() {
        let mut p = Preset::version_1();
        p.water.enabled = false;
        p.physics.max_time = 10.0;
        let run = |across: bool, tolerance: f64| {
            let mut q = p.clone();
            q.physics.steps_across_ticks = across;
            q.physics.tolerance = tolerance;
            simulate(&q).unwrap()
        };
        let (tick, across, tight) = (run(false, 1e-6), run(true, 1e-6), run(false, 1e-10));
        assert_eq!(tight.outcome, Some(Outcome::Sank), "{tight:?}");
        assert!(tight.skips >= 2, "{tight:?}");
        for s in [&tick, &across] {
            assert_eq!((s.outcome, s.skips), (tight.outcome, tight.skips), "{s:?}");
            let error = (s.distance - tight.distance).abs() / tight.distance;
            assert!(
                error <= s.steps as f64 * 1e-6,
                "error {error} over {} steps",
                s.steps
            );
        }
        assert!(
            (across.force_evals as f64) < 0.9 * tick.force_evals as f64,
            "{} against {}",
            across.force_evals,
            tick.force_evals
        );
    }

    /// The wetted-extent memory's exit tail ([`EXIT_APPROACH`]): the shipped default, stone alone,
    /// to the end of its first contact at the shipped tolerance and at 1e-3 leaves the water when
    /// and as a run at 1e-10 does, to the sum of the
    /// local errors (steps × tolerance relative to the error norm's scales: |v| for the velocity,
    /// the stone's radius over the exit's clearance rate for the instant).
    #[test]
    fn the_memory_exit_is_where_a_tight_tolerance_puts_it() {
        let mut p = Preset::default();
        p.water.enabled = false;
        assert!(p.physics.wetted_memory.is_some());
        let first_exit = |tolerance: f64| {
            let mut q = p.clone();
            q.physics.tolerance = tolerance;
            let mut sim = Simulation::new(&q).unwrap();
            while sim.contacts().is_empty() || sim.in_contact() {
                sim.tick();
                assert!(!sim.is_finished());
            }
            (sim.contacts()[0], sim.cost().0)
        };
        let (tight, _) = first_exit(1e-10);
        for tolerance in [p.physics.tolerance, 1e-3] {
            let (c, steps) = first_exit(tolerance);
            let budget = steps as f64 * tolerance;
            let speed = DVec3::from_array(tight.v_out).length();
            let dv = (DVec3::from_array(c.v_out) - DVec3::from_array(tight.v_out)).length();
            assert!(dv <= budget * speed, "{tolerance}: v_out off by {dv} m/s");
            // A position error of `budget` radii moves the exit by that over the rate the lowest
            // point leaves at, |v_z| + ωR: some metres a second, so 1 m/s bounds it from below.
            let (radius, leaving) = (Simulation::new(&p).unwrap().stone().bounding_radius, 1.0);
            let dt = (c.t_end - tight.t_end).abs();
            assert!(
                dt <= budget * radius / leaving,
                "{tolerance}: exit off by {dt} s"
            );
        }
    }

    /// Steps longer than the tick may jump a hop shorter than themselves: the record throw released
    /// from 30 cm on flat water under the quasi-steady contact has one of 1.4 ms (touch 3 ends at
    /// 0.8233 s with v_z 0.05 m/s, touch 4 begins at 0.8247 s), which an across-ticks step at the
    /// shipped tolerance stepped over (6 touches for 7) until a step that leaves the water at a
    /// stage was retried shortened to it. Every run at tolerance 1e-7 to 1e-10, ticks or not, has
    /// the 7. The hop is shorter than the stone, so the two touches are one contact.
    #[test]
    fn steps_across_ticks_do_not_jump_a_short_hop() {
        let mut p = crate::preset::shipped("record_throw").unwrap().unwrap();
        p.water.enabled = false;
        p.physics.wetted_memory = None;
        p.launch.position[2] = 0.3;
        let run = |across: bool, tolerance: f64| {
            let mut q = p.clone();
            q.physics.steps_across_ticks = across;
            q.physics.tolerance = tolerance;
            simulate(&q).unwrap()
        };
        let converged = run(false, 1e-7);
        let across = run(true, 1e-6);
        assert_eq!(across.skips, converged.skips, "{across:?}");
        let touches = |s: &Summary| s.contacts.iter().map(|c| c.touches).sum::<u32>();
        assert_eq!(touches(&across), touches(&converged), "{across:?}");
        let short_hop = |s: &Summary| s.contacts.iter().any(|c| c.touches > 1);
        assert!(short_hop(&converged) && short_hop(&across));
    }

    /// Across ticks the pose drawn at a tick's end is the stone's at the tick's time, interpolated
    /// inside the step that passed it: at every tick within the integration error of a tick-bound
    /// run, where the stone's own state, up to a step ahead, is many times farther off.
    #[test]
    fn steps_across_ticks_draw_the_pose_at_the_ticks_time() {
        let mut p = Preset::version_1();
        p.water.enabled = false;
        let mut tick_bound = Simulation::new(&p).unwrap();
        p.physics.steps_across_ticks = true;
        let mut across = Simulation::new(&p).unwrap();
        let (mut drawn, mut own, mut turn) = (0.0f64, 0.0f64, 0.0f64);
        while !tick_bound.is_finished() && !across.is_finished() {
            tick_bound.tick();
            across.tick();
            let (x, q) = tick_bound.world_from_stone();
            let (y, r) = across.world_from_stone();
            drawn = drawn.max((y - x).length());
            own = own.max((across.state().position - x).length());
            turn = turn.max(q.angle_between(r));
        }
        assert!(drawn < 1e-3 && turn < 1e-3, "{drawn} m, {turn} rad");
        assert!(own > 10.0 * drawn, "{own} against {drawn}");
    }

    /// Across ticks the clock still keeps the ticks (its n-th tick ends at n dt) and the stone is
    /// at or ahead of it by less than its longest step; with a lake that takes the loads (the
    /// app's case: the rings) the option changes nothing, bit for bit.
    #[test]
    fn steps_across_ticks_keep_the_clock_and_leave_a_coupled_run_alone() {
        let mut p = Preset::version_1();
        p.water.enabled = false;
        p.physics.steps_across_ticks = true;
        let dt = p.physics.dt;
        let mut sim = Simulation::new(&p).unwrap();
        let (mut ticks, mut ahead, mut longest) = (0u32, 0u32, 0.0f64);
        while !sim.is_finished() {
            let mut last = sim.time();
            sim.tick_with(&mut |s| {
                longest = longest.max(s.time - last);
                last = s.time;
            });
            ticks += 1;
            assert!((sim.clock - f64::from(ticks) * dt).abs() < 1e-9 * f64::from(ticks));
            assert!(sim.time() >= sim.clock && sim.time() - sim.clock < longest.max(dt));
            ahead += u32::from(sim.time() > sim.clock);
        }
        assert!(
            ahead > 0 && longest > dt,
            "{ahead} ticks ahead, longest step {longest}"
        );

        let mut q = Preset::version_1();
        q.physics.max_time = 1.0;
        let run = |across: bool| {
            let mut r = q.clone();
            r.physics.steps_across_ticks = across;
            Simulation::new(&r).unwrap().run(&mut |_| {}, &|| false)
        };
        let (on, off) = (run(true), run(false));
        assert!(
            on.skips >= 1 && on.water.as_ref().is_some_and(|w| w.stepped),
            "{on:?}"
        );
        assert_eq!(on, off);
    }

    /// A step whose forces overflow (the velocity of an explicit scheme run far past its stability
    /// limit) ends the run as diverged, at the last finite state, with the reason; it used to be
    /// reported as a sinking.
    #[test]
    fn a_non_finite_step_is_reported_as_diverged() {
        let mut p = Preset::version_1();
        p.water.enabled = false;
        p.physics.integrator = Integrator::Paper;
        let mut sim = Simulation::new(&p).unwrap();
        // In the water, with a speed whose square overflows.
        sim.motion.state.position.z = 0.0;
        sim.motion.state.velocity = DVec3::new(1e200, 0.0, -1e200);
        let before = sim.motion.state;
        sim.tick();
        assert_eq!(sim.outcome(), Some(Outcome::Diverged));
        assert_eq!(sim.state(), &before, "stops at the last finite state");
        let reason = sim.diverged_reason().unwrap();
        assert!(reason.contains("non-finite"), "{reason}");
        let s = sim.summary();
        assert_eq!(s.outcome.map(Outcome::as_str), Some("diverged"));
        assert_eq!(s.diverged_reason.as_deref(), Some(reason));
    }

    /// On flat water a skip turns a fall into a climb, so the water's mean upward force over the
    /// contact, m g + m (v_out.z − v_in.z)/T, exceeds the stone's weight, and so does its peak;
    /// the last contact, the one the stone sank in, has a peak too.
    #[test]
    fn a_skips_peak_lift_exceeds_the_weight() {
        let mut p = Preset::version_1();
        p.water.enabled = false;
        let mut sim = Simulation::new(&p).unwrap();
        let s = sim.run(&mut |_| {}, &|| false);
        let weight = sim.stone().mass * p.physics.gravity;
        assert!(s.skips >= 2, "{s:?}");
        for c in &s.contacts {
            let mean = sim.stone().mass * (c.v_out[2] - c.v_in[2]) / (c.t_end - c.t_start) + weight;
            if c.skip {
                assert!(mean > weight && c.peak_lift > weight, "{c:?}");
                assert!(c.peak_g().unwrap() > 1.0);
            }
            assert!(c.peak_lift > 0.0 && c.peak_lift.is_finite(), "{c:?}");
        }
        let mut weightless = s.contacts[0];
        weightless.weight = 0.0;
        assert_eq!(weightless.peak_g(), None);
        // A subnormal gravity (typed "1e-320"): the ratio would overflow to infinity.
        weightless.weight = 1e-320;
        assert_eq!(weightless.peak_g(), None);
    }

    /// A live change of gravity does not rewrite the past (issue 39, finding 2): the contacts
    /// before it keep the peak g they had, read against the weight they were made with.
    #[test]
    fn a_live_gravity_change_keeps_earlier_peaks() {
        let mut p = Preset::version_1();
        p.water.enabled = false;
        let mut sim = Simulation::new(&p).unwrap();
        while sim.contacts().first().is_none_or(|c| c.open) {
            sim.tick();
        }
        let before = sim.contacts()[0].peak_g().unwrap();
        let mut heavy = p.physics;
        heavy.gravity = 30.0;
        sim.set_physics(heavy).unwrap();
        sim.run(&mut |_| {}, &|| false);
        assert_eq!(sim.contacts()[0].peak_g(), Some(before));
        assert!(before > 1.0, "{before}");
    }

    /// A run that ends otherwise carries no reason.
    #[test]
    fn other_outcomes_carry_no_reason() {
        let mut p = Preset::version_1();
        p.water.enabled = false;
        let s = simulate(&p).unwrap();
        assert_eq!(s.outcome, Some(Outcome::Sank));
        assert_eq!(s.diverged_reason, None);
    }

    /// On the columns' own surface (wavy contact, the near field frozen at each tick of the
    /// magic-angle throw's first contacts) the faceted lens converges as on flat water: 96
    /// segments are nearer 192 than 64 are, by about the square of the facet size ((64/96)² =
    /// 0.44), and 64 are within 1 % (mean force errors 0.21 % and 0.071 % when written). So the
    /// mesh, not the surface, sets the error of a wavy contact's force.
    #[test]
    fn meshes_converge_on_the_columns_surface() {
        use crate::sim::hydro::{evaluate, Scratch};
        let mut p = crate::preset::shipped("magic_angle").unwrap().unwrap();
        p.water.wavy_contact = true;
        p.physics.wetted_memory = None;
        let mesh = |segments: u32| {
            let mut sp = p.stone.clone();
            sp.segments = segments;
            sp.bands = Some(segments / 2);
            Stone::new(&sp).unwrap()
        };
        let (m64, m96, m192) = (mesh(64), mesh(96), mesh(192));
        let mut sim = Simulation::new(&p).unwrap();
        let (mut e64, mut e96, mut poses) = (0.0, 0.0, 0);
        while sim.time() < 0.8 && !sim.is_finished() {
            sim.tick();
            let surface = sim.surface();
            assert!(!surface.is_flat());
            let dy = Dynamics {
                stone: &sim.stone,
                hydro: sim.hydro,
                gravity: p.physics.gravity,
                rotation: p.physics.rotation,
                surface: &surface,
                record_loads: false,
                resal: sim.resal(),
                memory: None,
            };
            let pose = dy.pose(sim.state());
            let mut sc = Scratch::default();
            let mut force =
                |stone: &Stone| evaluate(stone, &sim.hydro, &pose, &surface, &mut sc, false).force;
            let fine = force(&m192);
            if fine.length() < 1.0 {
                continue;
            }
            e64 += (force(&m64) - fine).length() / fine.length();
            e96 += (force(&m96) - fine).length() / fine.length();
            poses += 1;
        }
        assert!(poses >= 10, "{poses} contact poses");
        let (e64, e96) = (e64 / poses as f64, e96 / poses as f64);
        assert!(
            e96 < 0.6 * e64 && e64 < 0.01,
            "64: {e64:.2e}, 96: {e96:.2e}"
        );
    }

    /// The outcome's instant stays put while the clock runs on with the water after it, and it
    /// is the summary's final time.
    #[test]
    fn the_end_time_is_the_outcomes_instant() {
        let mut p = Preset::version_1();
        p.water.enabled = true;
        let mut sim = Simulation::new(&p).unwrap();
        while !sim.is_finished() {
            assert_eq!(sim.end_time(), None);
            sim.tick();
        }
        let end = sim.end_time().unwrap();
        assert!(end <= sim.time() && end > 0.0, "{end} vs {}", sim.time());
        for _ in 0..5 {
            sim.tick();
        }
        assert_eq!(sim.end_time(), Some(end));
        assert!(sim.time() > end + 4.0 * p.physics.dt);
        assert_eq!(sim.summary().final_time, end);
    }
}
