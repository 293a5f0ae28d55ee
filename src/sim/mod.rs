//! The physics of stoneskip: a stone (a triangle mesh of revolution) thrown at water, per-triangle
//! hydrodynamic forces in contact (paper §3.2, eqs. 11–29), time stepping (eqs. 4–8, 30–38 and
//! better schemes), and the O'Brien–Hodgins column-and-pipe water (paper §3.3, eqs. 39–41).
//!
//! [`Simulation`] advances in ticks of `physics.dt` (Adaptive sub-steps inside a tick, never across
//! one). The time step is a parameter, never read from a clock, and nothing is random: the same
//! preset gives bit-identical results. Depends on glam, serde, thiserror and rayon only; knows
//! nothing of frames, windows or wall-clock time.

pub mod contact;
pub mod hydro;
pub mod integrate;
pub mod kernel;
pub mod params;
pub mod reference;
pub mod scenario;
pub mod stone;
pub mod water;

use glam::{DMat3, DQuat, DVec3};
use serde::Serialize;

use hydro::{
    lowest_clearance, underside_submerged, FaceLoad, FlatSurface, ForceSum, HydroParams, Scratch,
    Surface,
};
use integrate::{
    flight, step_dp5, step_paper, step_rk4, step_symplectic_euler, BodyState, Deriv, Dynamics,
    ErrorScales,
};
use params::{Integrator, ParamError, Physics, Preset};
use stone::{orientation_from_attitude, reported_attitude, Stone};
use water::WaterGrid;

/// Errors of building or driving a simulation.
#[derive(Debug, thiserror::Error)]
pub enum SimError {
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
}

impl Outcome {
    pub fn as_str(self) -> &'static str {
        match self {
            Outcome::Sank => "sank",
            Outcome::Timeout => "timeout",
            Outcome::LeftDomain => "left_domain",
        }
    }
}

/// One contact episode: from the first vertex reaching the surface until none is at or below it
/// (a skip), or until the stone sinks or the run ends.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct ContactEvent {
    pub t_start: f64,
    pub t_end: f64,
    /// Ended with the stone wholly above the surface.
    pub skip: bool,
    /// Centre of mass when the episode started.
    pub x: f64,
    pub y: f64,
    pub v_in: [f64; 3],
    pub v_out: [f64; 3],
    /// [tilt, bank, heading] in degrees, relative to the direction of travel.
    pub attitude_in: [f64; 3],
    pub attitude_out: [f64; 3],
    /// Angle of the velocity below the horizontal at the start (degrees).
    pub beta_in: f64,
    #[serde(skip)]
    pub open: bool,
}

/// Water volumes of a run (m³).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct WaterSummary {
    pub volume_initial: f64,
    pub volume_final: f64,
}

/// The result of a run, as `simulate --json` prints it (design.md §7).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Summary {
    pub schema: u32,
    pub name: String,
    pub outcome: Option<Outcome>,
    pub skips: usize,
    pub distance: f64,
    pub final_time: f64,
    pub steps: u64,
    pub force_evals: u64,
    pub contacts: Vec<ContactEvent>,
    pub water: Option<WaterSummary>,
}

/// One accepted integration step, for trajectories and plots.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StepSample {
    pub time: f64,
    pub state: BodyState,
    pub angular_velocity: DVec3,
    pub in_contact: bool,
    pub wetted_area: f64,
    pub force: DVec3,
}

/// Horizontal distance beyond which a run without water counts as `left_domain` (m).
pub const OPEN_WATER_LIMIT: f64 = 1000.0;

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
}

impl PendingLoad {
    /// Face load `l` acting for `dt` (s).
    fn new(l: &FaceLoad, dt: f64) -> Self {
        Self {
            x: l.x,
            y: l.y,
            half: 0.5 * l.footprint.max(0.0).sqrt(),
            impulse: l.fz * dt,
        }
    }
}

/// The water's vertical impulse on the stone over an accepted step from `a` to `b`, as the
/// integrator itself applied it: m·Δv_z + m·g·h (gravity is the only other vertical force).
fn water_impulse(mass: f64, gravity: f64, a: &BodyState, b: &BodyState, h: f64) -> f64 {
    mass * (b.velocity.z - a.velocity.z) + mass * gravity * h
}

impl Motion {
    /// Gives the water an accepted contact step's impulse `j` (N·s, down on the water), exactly what
    /// the stone received (Newton's third law, to rounding): spread over the faces loaded at the step's
    /// start and end, half the step each (a trapezoid over the faces), scaled so the parts sum to `j`.
    /// End-of-step loads alone (a rectangle rule) lose ~5 % of a contact's impulse at the default
    /// tolerance's few, long steps. The end loads become the next step's start loads.
    fn push_step_loads(&mut self, j: f64, h: f64, at: DVec3) {
        let end = &self.scratch.loads;
        let sum = |v: &[FaceLoad]| v.iter().map(|l| l.fz).sum::<f64>();
        let trapezoid = 0.5 * h * (sum(&self.prev_loads) + sum(end));
        if trapezoid == 0.0 {
            // No face loaded at either end (wet only at inner stages, or only culled faces): the
            // impulse goes under the centre of mass.
            if j.is_finite() && j != 0.0 {
                self.pending.push(PendingLoad {
                    x: at.x,
                    y: at.y,
                    half: 0.0,
                    impulse: j,
                });
            }
            self.prev_loads.clear();
            return;
        }
        // The loads' own trapezoid if j is not finite (a diverging explicit scheme).
        let scale = if j.is_finite() { j / trapezoid } else { 1.0 };
        let dt = 0.5 * h * scale;
        self.pending.extend(
            self.prev_loads
                .iter()
                .chain(end)
                .map(|l| PendingLoad::new(l, dt)),
        );
        self.prev_loads.clear();
        self.prev_loads.extend_from_slice(end);
    }
}

/// The surface the stone touches: z = 0, or the water grid's heights (wavy contact).
enum SurfaceRef<'a> {
    Flat,
    Water { grid: &'a WaterGrid, max: f64 },
}

impl<'a> SurfaceRef<'a> {
    fn new(water: &'a Option<WaterGrid>, wavy: bool, max: f64) -> Self {
        match (water, wavy) {
            (Some(grid), true) => SurfaceRef::Water { grid, max },
            _ => SurfaceRef::Flat,
        }
    }
}

impl Surface for SurfaceRef<'_> {
    fn height(&self, x: f64, y: f64) -> f64 {
        match self {
            SurfaceRef::Flat => FlatSurface.height(x, y),
            SurfaceRef::Water { grid, .. } => grid.surface_height(x, y),
        }
    }
    fn max_height(&self) -> f64 {
        match self {
            SurfaceRef::Flat => 0.0,
            SurfaceRef::Water { max, .. } => *max,
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
    end_time: f64,
    steps: u64,
    force_evals: u64,
    last_force: ForceSum,
    h_adaptive: f64,
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
    water: Option<WaterGrid>,
    water_max_eta: f64,
    volume_initial: f64,
    launch_position: DVec3,
    motion: Motion,
}

impl Simulation {
    /// Builds a run from a preset (validated here).
    pub fn new(preset: &Preset) -> Result<Self, SimError> {
        preset.validate()?;
        let stone = Stone::new(&preset.stone)?;
        let l = &preset.launch;
        let orientation = orientation_from_attitude(&l.attitude);
        let axis = orientation * DVec3::Z;
        let omega = axis * l.spin + DVec3::from_array(l.angular_velocity);
        let r = DMat3::from_quat(orientation);
        let angular_momentum = r * (stone.inertia * (r.transpose() * omega));
        let state = BodyState {
            position: DVec3::from_array(l.position),
            velocity: DVec3::from_array(l.velocity),
            orientation,
            angular_momentum,
        };
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
            preset: preset.clone(),
            water_max_eta: 0.0,
            volume_initial,
            launch_position: state.position,
            motion: Motion {
                state,
                time: 0.0,
                in_contact: false,
                contacts: Vec::new(),
                outcome: None,
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

    pub fn preset(&self) -> &Preset {
        &self.preset
    }
    pub fn stone(&self) -> &Stone {
        &self.stone
    }
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
    /// Position and orientation of the stone's body frame in the world.
    pub fn world_from_stone(&self) -> (DVec3, DQuat) {
        (self.motion.state.position, self.motion.state.orientation)
    }
    /// Simulated time (s).
    pub fn time(&self) -> f64 {
        self.motion.time
    }
    pub fn outcome(&self) -> Option<Outcome> {
        self.motion.outcome
    }
    pub fn is_finished(&self) -> bool {
        self.motion.outcome.is_some()
    }
    pub fn contacts(&self) -> &[ContactEvent] {
        &self.motion.contacts
    }
    pub fn in_contact(&self) -> bool {
        self.motion.in_contact
    }
    pub fn skips(&self) -> usize {
        self.motion.contacts.iter().filter(|c| c.skip).count()
    }
    /// Forces at the last accepted step.
    pub fn last_force(&self) -> ForceSum {
        self.motion.last_force
    }
    pub fn water(&self) -> Option<&WaterGrid> {
        self.water.as_ref()
    }
    /// (accepted steps, force evaluations).
    pub fn cost(&self) -> (u64, u64) {
        (self.motion.steps, self.motion.force_evals)
    }
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
        let s = &self.motion.state;
        let w = self.angular_velocity();
        0.5 * self.stone.mass * s.velocity.length_squared()
            + 0.5 * w.dot(s.angular_momentum)
            + self.stone.mass * self.preset.physics.gravity * s.position.z
    }

    /// Changes the physical constants live; takes effect at the next step.
    pub fn set_physics(&mut self, physics: Physics) -> Result<(), ParamError> {
        physics.validate()?;
        self.preset.physics = physics;
        self.hydro = HydroParams::from_physics(&physics);
        self.motion.fsal = None;
        Ok(())
    }

    /// The run's result so far.
    pub fn summary(&self) -> Summary {
        let final_time = if self.is_finished() {
            self.motion.end_time
        } else {
            self.motion.time
        };
        Summary {
            schema: 1,
            name: self.preset.name.clone(),
            outcome: self.motion.outcome,
            skips: self.skips(),
            distance: self.distance(),
            final_time,
            steps: self.motion.steps,
            force_evals: self.motion.force_evals,
            contacts: self.motion.contacts.clone(),
            water: self.water.as_ref().map(|w| WaterSummary {
                volume_initial: self.volume_initial,
                volume_final: w.volume(),
            }),
        }
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

    /// Advances by one tick (`physics.dt`).
    pub fn tick(&mut self) {
        self.tick_with(&mut |_| {});
    }

    /// Advances by one tick, calling `on_step` after every accepted step of the stone. After the
    /// outcome the stone stays where it ended and only the water moves on.
    pub fn tick_with(&mut self, on_step: &mut dyn FnMut(&StepSample)) {
        let dt = self.preset.physics.dt;
        let t_end = self.motion.time + dt;
        if !self.is_finished() {
            self.advance_stone(t_end, on_step);
        }
        self.motion.time = t_end;
        if !self.is_finished() && self.motion.time >= self.preset.physics.max_time - 1e-12 {
            self.finish(Outcome::Timeout);
        }
        if let Some(w) = self.water.as_mut() {
            for l in &self.motion.pending {
                w.deposit_impulse_box(l.x, l.y, l.half, l.impulse);
            }
            let before = w.time();
            w.advance(dt);
            let stepped = w.time() != before;
            self.motion.pending.clear();
            if stepped {
                self.refresh_water_max();
            }
        } else {
            self.motion.pending.clear();
        }
    }

    fn refresh_water_max(&mut self) {
        if !self.preset.water.wavy_contact {
            self.water_max_eta = 0.0;
            return;
        }
        if let Some(w) = &self.water {
            let mut m = f64::NEG_INFINITY;
            for iy in 0..w.ny() {
                for ix in 0..w.nx() {
                    m = m.max(w.eta(ix, iy));
                }
            }
            self.water_max_eta = if m.is_finite() { m } else { 0.0 };
        }
    }

    fn surface(&self) -> SurfaceRef<'_> {
        SurfaceRef::new(
            &self.water,
            self.preset.water.wavy_contact,
            self.water_max_eta,
        )
    }

    fn clearance(&self, s: &BodyState) -> f64 {
        lowest_clearance(&self.stone, s.position, s.orientation, &self.surface())
    }

    fn start_event(&self, t: f64, s: &BodyState) -> ContactEvent {
        let v = s.velocity;
        let vh = (v.x * v.x + v.y * v.y).sqrt();
        let att = reported_attitude(s.orientation, v);
        ContactEvent {
            t_start: t,
            t_end: t,
            skip: false,
            x: s.position.x,
            y: s.position.y,
            v_in: v.to_array(),
            v_out: v.to_array(),
            attitude_in: att,
            attitude_out: att,
            beta_in: (-v.z).atan2(vh).to_degrees(),
            open: true,
        }
    }

    fn finish(&mut self, outcome: Outcome) {
        let s = self.motion.state;
        let t = self.motion.time;
        if let Some(ev) = self.motion.contacts.last_mut() {
            if ev.open {
                ev.open = false;
                ev.t_end = t;
                ev.skip = false;
                ev.v_out = s.velocity.to_array();
                ev.attitude_out = reported_attitude(s.orientation, s.velocity);
            }
        }
        self.motion.outcome = Some(outcome);
        self.motion.end_time = t;
    }

    /// Steps the stone until `t_end` or its outcome.
    fn advance_stone(&mut self, t_end: f64, on_step: &mut dyn FnMut(&StepSample)) {
        let physics = self.preset.physics;
        let mut guard = 0u32;
        while self.motion.time < t_end && self.motion.outcome.is_none() {
            guard += 1;
            if guard > 1_000_000 {
                // Cannot happen with a positive minimum step; kept so a bug cannot hang the program.
                self.finish(Outcome::Timeout);
                return;
            }
            let prev = self.motion.state;
            let t0 = self.motion.time;
            let h_max = t_end - t0;
            let (next, h, force) = {
                let surface = SurfaceRef::new(
                    &self.water,
                    self.preset.water.wavy_contact,
                    self.water_max_eta,
                );
                let dy = Dynamics {
                    stone: &self.stone,
                    hydro: self.hydro,
                    gravity: physics.gravity,
                    rotation: physics.rotation,
                    surface: &surface,
                };
                let m = &mut self.motion;
                match physics.integrator {
                    Integrator::Adaptive => adaptive_step(&dy, m, h_max, physics.tolerance),
                    fixed => {
                        // Every scheme flies exactly (eqs. 4–8 are exact for a parabola; the
                        // torque-free rotation has a closed form): they differ in contact only.
                        let clear = |st: &BodyState| {
                            lowest_clearance(&self.stone, st.position, st.orientation, &surface)
                        };
                        let end =
                            flight(&self.stone, physics.rotation, physics.gravity, &prev, h_max);
                        if clear(&prev) > 0.0 && clear(&end) > 0.0 {
                            m.prev_loads.clear();
                            (end, h_max, ForceSum::default())
                        } else {
                            let (s, f) = match fixed {
                                Integrator::Paper => step_paper(&dy, &prev, h_max, &mut m.scratch),
                                Integrator::SymplecticEuler => {
                                    step_symplectic_euler(&dy, &prev, h_max, &mut m.scratch)
                                }
                                _ => step_rk4(&dy, &prev, h_max, &mut m.scratch),
                            };
                            m.force_evals += if fixed == Integrator::Rk4 { 4 } else { 1 };
                            let j =
                                water_impulse(self.stone.mass, physics.gravity, &prev, &s, h_max);
                            m.push_step_loads(j, h_max, s.position);
                            (s, h_max, f)
                        }
                    }
                }
            };
            if !next.is_finite() {
                // A diverging explicit scheme (e.g. Paper at a huge step): stop at the last finite
                // state rather than report NaN.
                self.finish(Outcome::Sank);
                return;
            }
            self.motion.state = next;
            self.motion.time = if h >= h_max { t_end } else { t0 + h };
            self.motion.steps += 1;
            self.motion.last_force = force;
            self.after_step(&prev, h, on_step);
        }
    }

    /// Contact episodes and outcomes after an accepted step from `prev` over `h`.
    fn after_step(&mut self, prev: &BodyState, h: f64, on_step: &mut dyn FnMut(&StepSample)) {
        let physics = self.preset.physics;
        let s = self.motion.state;
        let t = self.motion.time;
        let now = self.clearance(&s) <= 0.0;
        let was = self.motion.in_contact;
        if now && !was {
            // Entry: the motion before it was flight; locate the first touch on that parabola.
            let sstar = self.bisect_crossing(prev, h, true);
            let at = flight(&self.stone, physics.rotation, physics.gravity, prev, sstar);
            let ev = self.start_event(t - h + sstar, &at);
            self.motion.contacts.push(ev);
        } else if was && !now {
            // Exit: the motion after it is flight; locate the last touch backwards from here.
            let sstar = self.bisect_crossing(&s, h, false);
            let at = flight(&self.stone, physics.rotation, physics.gravity, &s, -sstar);
            if let Some(ev) = self.motion.contacts.last_mut() {
                if ev.open {
                    ev.open = false;
                    ev.skip = true;
                    ev.t_end = t - sstar;
                    ev.v_out = at.velocity.to_array();
                    ev.attitude_out = reported_attitude(at.orientation, at.velocity);
                }
            }
        }
        self.motion.in_contact = now;
        let f = self.motion.last_force;
        on_step(&StepSample {
            time: t,
            state: s,
            angular_velocity: self.angular_velocity(),
            in_contact: now,
            wetted_area: f.wetted_area,
            force: f.force,
        });
        if now && underside_submerged(&self.stone, s.position, s.orientation, &self.surface()) {
            self.finish(Outcome::Sank);
            return;
        }
        let left = match &self.water {
            Some(w) => !w.contains(s.position.x, s.position.y),
            None => self.distance() > OPEN_WATER_LIMIT,
        };
        if left {
            self.finish(Outcome::LeftDomain);
        }
    }

    /// Along the flight from `from` (forwards when `forward`, else backwards) over [0, h], the
    /// offset at which the lowest vertex reaches the surface.
    fn bisect_crossing(&self, from: &BodyState, h: f64, forward: bool) -> f64 {
        let physics = &self.preset.physics;
        let sign = if forward { 1.0 } else { -1.0 };
        let wet = |s: f64| {
            let st = flight(
                &self.stone,
                physics.rotation,
                physics.gravity,
                from,
                sign * s,
            );
            self.clearance(&st) <= 0.0
        };
        // Forwards: dry at 0, wet at h. Backwards from a dry state: dry at 0, wet at h.
        if !wet(h) {
            return h;
        }
        first_wet(h, 60, wet)
    }
}

/// Bisection on [0, h] for the first offset that is wet, given dry at 0 and wet at `h`: at most
/// `iterations` halvings, stopping early when the interval reaches floating-point resolution.
fn first_wet(h: f64, iterations: u32, wet: impl Fn(f64) -> bool) -> f64 {
    let (mut lo, mut hi) = (0.0, h);
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

/// One Adaptive step: exact flight to `h_max` or to the first touch; error-controlled
/// Dormand–Prince steps in contact. Returns the new state, the step taken and the forces there.
fn adaptive_step(
    dy: &Dynamics,
    m: &mut Motion,
    h_max: f64,
    tol: f64,
) -> (BodyState, f64, ForceSum) {
    let s = m.state;
    let clear =
        |st: &BodyState| lowest_clearance(dy.stone, st.position, st.orientation, dy.surface);
    if !m.in_contact && clear(&s) > 0.0 {
        m.fsal = None;
        m.prev_loads.clear();
        let end = flight(dy.stone, dy.rotation, dy.gravity, &s, h_max);
        if clear(&end) > 0.0 {
            return (end, h_max, ForceSum::default());
        }
        // Locate the first touch by bisection on the exact flight.
        let hi = first_wet(h_max, 80, |t| {
            clear(&flight(dy.stone, dy.rotation, dy.gravity, &s, t)) <= 0.0
        });
        let at = flight(dy.stone, dy.rotation, dy.gravity, &s, hi);
        return (at, hi, ForceSum::default());
    }
    let (k1, _f1) = match m.fsal {
        Some(k) => k,
        None => {
            m.force_evals += 1;
            dy.derivative(&s, &mut m.scratch, false)
        }
    };
    let r = dy.stone.bounding_radius;
    let g = dy.gravity.max(1e-3);
    let scales = ErrorScales {
        position: r,
        velocity: s.velocity.length().max((g * r).sqrt()),
        angular_momentum: s
            .angular_momentum
            .length()
            .max(dy.stone.principal_moments().max_element() * (g / r).sqrt()),
    };
    if m.h_adaptive <= 0.0 {
        // First contact: a fraction of the contact's time scale r / |v|.
        m.h_adaptive = 0.01 * r / s.velocity.length().max(0.1);
    }
    let h_min = 1e-10;
    let mut h = m.h_adaptive.min(h_max);
    let c0 = clear(&s).min(0.0);
    let mut exit_refinements = 0;
    loop {
        let attempt = step_dp5(dy, &s, &k1, h, tol, &scales, &mut m.scratch);
        m.force_evals += attempt.evals;
        let err = attempt.error;
        if err <= 1.0 || h <= h_min {
            // Leaving the water inside the step: the force has a kink there, which the error
            // estimate does not see. Shorten the step to end at the exit (secant on the lowest
            // vertex's clearance), so no step integrates across it.
            let c1 = clear(&attempt.state);
            if c1 > 0.0 && exit_refinements < 3 && h > 64.0 * h_min {
                let f = -c0 / (c1 - c0);
                if f < 0.99 {
                    exit_refinements += 1;
                    h = (h * f * 1.0001).max(h_min);
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
            let clipped = (h >= h_max && m.h_adaptive > h_max) || exit_refinements > 0;
            if !clipped || grow < 1.0 {
                m.h_adaptive = (h * grow).max(h_min);
            }
            let j = water_impulse(dy.stone.mass, dy.gravity, &s, &attempt.state, h);
            m.push_step_loads(j, h, attempt.state.position);
            m.fsal = Some((attempt.k_end, attempt.force_end));
            return (attempt.state, h, attempt.force_end);
        }
        let shrink = if err.is_finite() {
            (0.9 * err.powf(-0.2)).clamp(0.1, 0.9)
        } else {
            0.1
        };
        h = (h * shrink).max(h_min);
    }
}

/// Convenience: runs a preset to its end and returns the summary.
pub fn simulate(preset: &Preset) -> Result<Summary, SimError> {
    let mut sim = Simulation::new(preset)?;
    Ok(sim.run(&mut |_| {}, &|| false))
}
