//! The physics of stoneskip: a stone (a triangle mesh of revolution) thrown at water, per-triangle
//! hydrodynamic forces in contact (paper §3.2, eqs. 11–29), time stepping (eqs. 4–8, 30–38 and
//! better schemes), and the O'Brien–Hodgins column-and-pipe water (paper §3.3, eqs. 39–41).
//!
//! Here is the run, [`Simulation`]: the clock, the stepping and the water it hands loads to. One
//! step of the stone is `step.rs`, the search for its next touch `touch.rs`, the record of the
//! run (outcome, contacts, summary) `record.rs`.
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

mod record;
mod step;
mod touch;
#[cfg(test)]
mod touch_tests;

use std::cell::Cell;

use glam::{DMat3, DQuat, DVec3};

use air::Air;
pub use ending::{ending, Ending};
use hydro::{lowest_clearance, FaceLoad, FlatSurface, ForceSum, HydroParams, Scratch, Surface};
use integrate::{fly, mesh_orientation, resal_applies, BodyState, Deriv, Dynamics};
pub use lake::{LakeGeometry, LakeJob, SteppedLake};
use memory::WettedMemory;
use params::{Integrator, ParamError, Physics, Preset, Shape};
pub use record::{ContactEvent, Outcome, StepSample, Summary, WaterSummary, TANG_BOUNCE_G};
use step::{adaptive_step, fixed_step, local_bounds, locate_sink, Overshoot, Step, StepContext};
use stone::{orientation_from_attitude, reported_attitude, Stone};
use touch::{first_wet, first_wet_between};
use water::{EtaPatch, PatchReader, WaterGrid};

/// Errors of building or driving a simulation.
#[derive(Debug, thiserror::Error)]
pub enum SimError {
    /// The preset is invalid: a value out of range or inconsistent with another.
    #[error(transparent)]
    Param(#[from] ParamError),
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

/// Runs a preset to its end, headless: the water is left at rest when nothing reads it
/// ([`Simulation::skip_unread_water`]).
pub fn simulate(preset: &Preset) -> Result<Summary, SimError> {
    let mut sim = Simulation::new(preset)?;
    sim.skip_unread_water();
    Ok(sim.run(&mut |_| {}, &|| false))
}

#[cfg(test)]
mod tests;
