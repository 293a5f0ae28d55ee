//! The app's model: the run, the settings being edited, the camera, the readouts — everything but
//! the window and the GPU (no winit or wgpu type here), so its rules are unit tests: the fixed-step
//! loop ([`FixedClock`]), replay ([`ReplayLog`]), the rest rule ([`rest_due`]), outcomes in words,
//! warnings for implausible setups, the throw gesture and where files go.

use std::collections::VecDeque;
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use anyhow::{Context as _, Result};
use glam::{DQuat, DVec3, Vec2, Vec3};

use super::clock::FixedClock;
use super::experiments::{Experiment, Knob, Plan, Spec};
use super::files;
use super::lake::{self, Rect};
use super::options::Options;
use super::replay::ReplayLog;
use crate::ui::{
    contact_kind, slide_distance, Action, ContactKind, FrameTiming, Message, Phase, PlotSeries,
    PresetLibrary, Readouts, Section, ViewRequest, ViewSettings,
};
use stoneskip_physics::preset;
use stoneskip_physics::sim::params::{Integrator, Launch, Preset, Rotation};
use stoneskip_physics::sim::stone::reported_attitude;
use stoneskip_physics::sim::{
    LakeJob as LakeWork, Simulation, StepSample, SteppedLake, TickProgress,
};
use stoneskip_render::build::{self, aim_preview, framing_of, ghost_lines, side_guides, thinned};
use stoneskip_render::camera::{camera_for, Framing, ViewMode};
use stoneskip_render::{Camera, Scene, SceneStyle, Trail, WaterHeights};

/// Most simulated time one frame may run (s, at the highest playback speed); the rest is skipped.
pub const MAX_SIM_PER_FRAME: f64 = 0.25;
/// Most wall time one frame may spend ticking; a frame stops at it even inside a tick (between two
/// steps of the stone), and the tick resumes at the next frame.
pub const PHYSICS_BUDGET: Duration = Duration::from_millis(60);
/// The wall-time budget while the physics runs behind ([`Pace::behind`]): it cannot catch up
/// anyway, so the frames come at about 30 a second instead of 15.
pub const PHYSICS_BUDGET_BEHIND: Duration = Duration::from_millis(25);
/// Most force evaluations one frame may spend ticking, whatever the clock says: a backstop that
/// bounds a frame's work by count (about 0.2 s of the costliest throws found, finding S1 in
/// docs/reliability.md, on the development machine; a shipped preset needs at most about 2·10⁴ a
/// frame at 60 frames a second, `too_steep`).
pub const PHYSICS_EVAL_BUDGET: u64 = 250_000;
/// Real time over which the pace of the physics is measured (s).
pub const PACE_WINDOW: f64 = 1.0;
/// Most step samples kept for the CSV export.
pub const MAX_SAMPLES: usize = 1_000_000;
/// Refresh rate of the numbers and plots while a throw animates …
pub const READOUT_HZ: f64 = 2.0;
/// … and the fewest frames between two refreshes.
pub const READOUT_MIN_FRAMES: u64 = 4;
/// Ripples lower than this (m) are below what the eye sees at the app's views: about a tenth of a
/// pixel of a 1 m wide view at 1000 pixels, and a slope the shading shows as nothing.
pub const ETA_VISIBLE: f64 = 2e-4;
/// Simulated seconds after the outcome at which the app rests even if the water still moves (a
/// swell never calms).
pub const REST_AFTER: f64 = 8.0;
/// Ghosts of earlier throws kept.
pub const MAX_GHOSTS: usize = 4;
/// How long an information message stays (errors stay until dismissed, or this × 5).
pub const MESSAGE_SECONDS: f64 = 6.0;

/// The rest rule: once the stone's run is over and the rings have calmed below what the eye sees
/// (or [`REST_AFTER`] has passed since the outcome), stop stepping and drawing until there is input.
pub fn rest_due(finished: bool, since_outcome: f64, max_abs_eta: Option<f64>) -> bool {
    if !finished {
        return false;
    }
    let calm = max_abs_eta.is_none_or(|e| !e.is_finite() || e < ETA_VISIBLE);
    calm || since_outcome >= REST_AFTER
}

/// Largest stable tick and largest within 1 % of each fixed-step integrator on the default stone
/// (docs/studies/stability, table A); thinner or lighter stones need smaller steps.
pub fn stable_step(integrator: Integrator) -> Option<(f64, f64)> {
    match integrator {
        Integrator::Paper => Some((0.0033, 7.0e-5)),
        Integrator::SymplecticEuler => Some((0.0049, 0.0023)),
        Integrator::Rk4 => Some((0.011, 0.0033)),
        _ => None,
    }
}

/// Warnings for setups that run but are implausible or unreliable: each one plain sentence on
/// what it means and what to do (the app cannot open the studies they rest on, so they name none).
pub fn setup_warnings(p: &Preset) -> Vec<String> {
    let mut w = Vec::new();
    let dt = p.physics.dt;
    let ms = dt * 1e3;
    // The stability study's table A (docs/studies/stability): past the stable step a fixed-step
    // integrator's contact bounces super-elastically; past the accurate one it is off by over 1 %.
    // A shipped preset's step is its design: [`design_note`] says what it shows instead.
    let step = stable_step(p.physics.integrator).filter(|_| as_shipped(p).is_none());
    if let Some((stable, accurate)) = step {
        if dt > stable {
            w.push(format!(
                "The time step ({ms:.2} ms) is too long for the {:?} integrator: bounces may gain \
                 energy. Lower the time step below {:.2} ms or choose Adaptive.",
                p.physics.integrator,
                stable * 1e3
            ));
        } else if dt > accurate {
            w.push(format!(
                "The time step ({ms:.3} ms) is too long for the {:?} integrator to be accurate: \
                 skips and distance may be off by more than 1 %. Lower the time step below \
                 {:.3} ms or choose Adaptive.",
                p.physics.integrator,
                accurate * 1e3
            ));
        }
    }
    if let Some(volume) = stone_volume(p) {
        let density = p.stone.mass / volume;
        if density < p.physics.water_density {
            w.push(format!(
                "This stone is lighter than water ({density:.0} kg/m³, the water {:.0} kg/m³): \
                 a real one would float. Raise its mass or shrink it.",
                p.physics.water_density
            ));
        } else if density > DENSEST_ROCK {
            w.push(format!(
                "This stone is denser than any rock ({density:.0} kg/m³; rocks weigh 2 000 to \
                 3 500 kg/m³, iron ore up to {DENSEST_ROCK:.0}): a lump of lead is 11 000. Lower \
                 its mass or make it bigger."
            ));
        }
    }
    if p.water.enabled && p.water.wavy_contact {
        // docs/studies/fidelity §9 and §11: from 5 cm to 7 mm columns the near field has not
        // converged (planing glides come back below 1.4 cm), it changes with the rest depth, and
        // coupled once a tick the stone runs up to a tick ahead of its own wave.
        w.push(format!(
            "Wavy contact is on ({:.1} cm cells, {ms:.2} ms time step): the result changes \
             with the water's cell size, its depth and the time step, so trust trends, not \
             exact skip counts. Turn it off in Water for a converged throw.",
            p.water.cell * 100.0
        ));
    }
    w
}

/// The file stem of the shipped preset `p` is, unchanged (issue 48: a shipped preset never
/// warns about its own design); `None` for a user's own or an edited one.
pub fn as_shipped(p: &Preset) -> Option<&'static str> {
    let quoted = format!("name: \"{}\"", p.name);
    preset::SHIPPED
        .iter()
        .filter(|(_, text)| text.contains(&quoted))
        .find(|(stem, _)| preset::shipped(stem).and_then(Result::ok).as_ref() == Some(p))
        .map(|(stem, _)| *stem)
}

/// What a shipped preset whose time step would be warned about in a user's own shows instead
/// (`paper`: the 2005 paper's integrator at its own step); `None` for every other preset.
pub fn design_note(p: &Preset) -> Option<String> {
    let (_, accurate) = stable_step(p.physics.integrator)?;
    if p.physics.dt <= accurate {
        return None;
    }
    as_shipped(p)?;
    Some(format!(
        "{}: the {:?} integrator at its own {:.2} ms time step, as its authors ran it, to compare \
         with the shipped model's skips and distance.",
        p.name,
        p.physics.integrator,
        p.physics.dt * 1e3
    ))
}

/// The densest rock a stone may be (kg/m³): haematite, an iron ore, about 5 300.
const DENSEST_ROCK: f64 = 5300.0;

/// The stone's volume from its shape (m³), when the shape has a closed form.
fn stone_volume(p: &Preset) -> Option<f64> {
    use stoneskip_physics::sim::params::Shape;
    let v = match p.stone.shape {
        Shape::Disk { radius, thickness } => std::f64::consts::PI * radius * radius * thickness,
        Shape::Lens { radius, thickness } => {
            4.0 / 3.0 * std::f64::consts::PI * radius * radius * 0.5 * thickness
        }
        Shape::Plate {
            length,
            width,
            thickness,
        } => length * width * thickness,
    };
    (v.is_finite() && v > 0.0).then_some(v)
}

/// The launch a drag-and-release gesture gives: `drag` in pixels (x right, y down) in a view
/// `view_height` pixels tall, seen by a camera looking along `camera_yaw`. The drag's direction on
/// screen is the throw's direction on the water (up the screen = away from the camera), its
/// length the speed (a third of the view's height is 10 m/s, 1–30 m/s); the elevation of the
/// velocity, the attitude relative to travel and the spin stay as the panel set them.
pub fn gesture_launch(base: &Launch, drag: Vec2, view_height: f32, camera_yaw: f32) -> Launch {
    let mut l = *base;
    let len = drag.length();
    if !len.is_finite() || len < 4.0 {
        return l;
    }
    let speed = (30.0 * len / view_height.max(1.0)).clamp(1.0, 30.0) as f64;
    // Screen up is the camera's horizontal forward, screen right its right.
    let screen_angle = (drag.x).atan2(-drag.y);
    let heading = (camera_yaw - screen_angle) as f64;
    let heading = wrap(heading).clamp(-90f64.to_radians(), 90f64.to_radians());
    let v = DVec3::from_array(base.velocity);
    let elevation = if v.length() > 1e-9 {
        (v.z / v.length()).clamp(-1.0, 1.0).asin()
    } else {
        -0.05
    };
    l.velocity = [
        speed * elevation.cos() * heading.cos(),
        speed * elevation.cos() * heading.sin(),
        speed * elevation.sin(),
    ];
    l.attitude.heading_deg = heading.to_degrees();
    l
}

fn wrap(a: f64) -> f64 {
    let tau = std::f64::consts::TAU;
    let w = a.rem_euclid(tau);
    if w > std::f64::consts::PI {
        w - tau
    } else {
        w
    }
}

/// What one frame may spend on physics: the first of its wall time and its force evaluations
/// that runs out stops it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct FrameBudget {
    pub wall: Duration,
    /// The wall time while the physics runs behind.
    pub wall_behind: Duration,
    pub force_evals: u64,
}

impl Default for FrameBudget {
    fn default() -> Self {
        Self {
            wall: PHYSICS_BUDGET,
            wall_behind: PHYSICS_BUDGET_BEHIND,
            force_evals: PHYSICS_EVAL_BUDGET,
        }
    }
}

/// The pace of the physics over the last [`PACE_WINDOW`] of real time: per frame, the real
/// seconds, the simulated seconds advanced, and whether the frame ran out of its budget.
#[derive(Debug, Clone, Default)]
pub struct Pace {
    frames: VecDeque<(f64, f64, bool)>,
}

impl Pace {
    /// Records a frame of `real` seconds that advanced the run by `simulated` seconds.
    pub fn record(&mut self, real: f64, simulated: f64, short: bool) {
        let real = if real.is_finite() {
            real.clamp(0.0, super::clock::MAX_FRAME_DT)
        } else {
            0.0
        };
        self.frames.push_back((real, simulated.max(0.0), short));
        let mut total: f64 = self.frames.iter().map(|f| f.0).sum();
        while self.frames.len() > 1 && total - self.frames[0].0 >= PACE_WINDOW {
            total -= self.frames[0].0;
            self.frames.pop_front();
        }
    }

    pub fn clear(&mut self) {
        self.frames.clear();
    }

    /// Real seconds per simulated second over the window (∞ when the run did not advance), while
    /// a frame of the window ran out of its budget; `None` when the physics kept up.
    pub fn behind(&self) -> Option<f64> {
        if !self.frames.iter().any(|f| f.2) {
            return None;
        }
        let real: f64 = self.frames.iter().map(|f| f.0).sum();
        let simulated: f64 = self.frames.iter().map(|f| f.1).sum();
        Some(if simulated > 0.0 {
            real / simulated
        } else {
            f64::INFINITY
        })
    }
}

/// A status message and when it was posted.
#[derive(Debug, Clone)]
pub struct Status {
    pub message: Message,
    pub at: Instant,
}

impl Status {
    /// Information fades after [`MESSAGE_SECONDS`], errors after five times that.
    pub fn expired(&self) -> bool {
        let life = if self.message.error { 5.0 } else { 1.0 } * MESSAGE_SECONDS;
        self.at.elapsed().as_secs_f64() > life
    }
}

/// An earlier throw kept as a ghost: its trail and score.
#[derive(Debug, Clone)]
pub struct Ghost {
    pub number: u64,
    pub points: Vec<Vec3>,
    pub skips: usize,
    pub distance: f64,
    pub outcome: String,
}

/// What the panels show of the run, refreshed at most [`READOUT_HZ`] times a second while the
/// throw animates (the panels then stay pixel-identical between refreshes).
#[derive(Debug, Clone, Default)]
pub struct Shown {
    pub readouts: Readouts,
    pub contacts: Vec<stoneskip_physics::sim::ContactEvent>,
    pub plots: [Vec<egui_plot::PlotPoint>; 4],
    pub plot_end: f64,
    pub timing: FrameTiming,
    /// The outcome in a word or two, for the top bar ("sank").
    pub outcome: Option<String>,
    /// Why the throw ended, in full ([`stoneskip_physics::sim::ending()`]), for the contacts table.
    pub ending: Option<String>,
    pub dropping_now: bool,
    pub dropped_total: f64,
    /// Real seconds per simulated second while the physics runs behind ([`Pace::behind`]).
    pub behind: Option<f64>,
    pub at: Option<Instant>,
    pub frame: u64,
}

/// The lake's own thread: its grid as stepped and the seconds it took (`None`: it found no job).
type LakeThread = std::thread::JoinHandle<Option<(SteppedLake, f64)>>;

/// Frame time totals (s) for the `--frames` report.
#[derive(Debug, Clone, Copy, Default)]
pub struct FrameStats {
    pub frames: u64,
    pub wall: f64,
    pub physics: f64,
    pub water: f64,
    /// The lake's own thread (off the frame).
    pub lake: f64,
    pub render: f64,
    pub ui: f64,
    pub full_redraws: u64,
    pub full_render: f64,
}

/// A screenshot asked for: with or without the panels.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Shot {
    Window,
    ViewOnly,
}

/// Everything but the window and the GPU.
pub struct Model {
    /// The settings the panels edit.
    pub edit: Preset,
    /// The preset as loaded (or saved): what the panels mark differences from.
    pub loaded: Preset,
    /// The flat-water track of `edit`'s throw, and the lake edges it crosses (see [`lake`]).
    pub lake_track: Option<Rect>,
    pub lake_exit: Option<String>,
    /// `edit` changed since the lake check (it costs a flat-water run: done once a drag ends).
    pub lake_stale: bool,
    /// The lake check running in the background: its result, and its stop flag (set when a newer
    /// edit replaces it).
    lake_job: Option<LakeJob>,
    pub sim: Simulation,
    /// The lake steps on its own thread while the frame draws (`sim::lake`): handed out at the
    /// end of [`Model::update`], back at the start of the next (`Options::lake_thread`).
    pub lake_thread: bool,
    /// The lake's grid stepping on its own thread, and the run it belongs to (`generation`).
    lake_step: Option<(u64, LakeThread)>,
    /// What a frame may spend on physics.
    pub budget: FrameBudget,
    /// How fast the physics went over the last second of real time.
    pub pace: Pace,
    /// A physics edit made while a tick was in progress: applied when that tick is complete (so
    /// that a replay, which applies it between ticks, gives the same run).
    deferred_physics: Option<stoneskip_physics::sim::params::Physics>,
    /// Changes whenever `sim` is rebuilt.
    pub generation: u64,
    pub phase: Phase,
    pub clock: FixedClock,
    pub prev_pose: (DVec3, DQuat),
    pub cur_pose: (DVec3, DQuat),
    pub trail: Trail,
    pub heights: WaterHeights,
    pub samples: Vec<StepSample>,
    pub plots: PlotSeries,
    pub replay_log: ReplayLog,
    pub ticks: u64,
    pub camera: Camera,
    pub view_mode: ViewMode,
    pub exaggeration: f32,
    pub view: ViewSettings,
    pub timing: FrameTiming,
    /// Mean wall time of a tick that did not step the water (s).
    stone_tick: f64,
    pub pending_changes: bool,
    pub invalid: Option<String>,
    pub warnings: Vec<String>,
    /// Notices of the run shown over the view (text, is an error).
    pub notices: Vec<(String, bool)>,
    pub library: PresetLibrary,
    pub status: Option<Status>,
    pub screenshot: Option<Shot>,
    pub ticks_last_frame: u32,
    /// The 3D view's rectangle in points.
    pub view_rect: egui::Rect,
    pub frame_physics: f64,
    pub frame_water: f64,
    /// Seconds the lake's own thread took for the ticks of the last frame it was handed.
    pub frame_lake: f64,
    pub frames: u64,
    pub stats: FrameStats,
    pub shown: Shown,
    pub camera_moved_at: Option<Instant>,
    pub sharp_pending: bool,
    /// The last frame redrew the panels too.
    pub last_full_redraw: bool,
    /// The app has just come to rest: one more frame, sharp and with the panels up to date.
    pub just_rested: bool,
    /// The run is over and the water calm: nothing steps or draws until there is input.
    pub resting: bool,
    /// Simulated time at which the outcome was first seen.
    outcome_time: Option<f64>,
    pub last_drop: Option<Instant>,
    pub ghosts: VecDeque<Ghost>,
    pub throws: u64,
    pub show_help: bool,
    pub show_about: bool,
    /// A throw gesture in progress: where it started (points).
    pub gesture: Option<egui::Pos2>,
    pub out_dir: PathBuf,
    /// The Experiments window: shown, the sweep being edited, the last one run and the point
    /// whose throw was loaded.
    pub show_experiments: bool,
    /// Whether the letter and digit shortcuts (cameras, pause, panels) go to the 3D view: the
    /// last press landed in it (or none has yet). A press on a panel (beside a field, in
    /// Experiments) takes them away until the pointer is over the view or a press lands there.
    pub keys_to_view: bool,
    pub experiment_draft: Spec,
    /// A map's second value (along y) being edited; `None`: one value.
    pub experiment_second: Option<Spec>,
    pub experiment: Option<Experiment>,
    pub experiment_chosen: Option<usize>,
}

/// A lake check in the background ([`Model::start_lake_check`]).
struct LakeJob {
    receiver: std::sync::mpsc::Receiver<Option<Rect>>,
    stop: std::sync::Arc<std::sync::atomic::AtomicBool>,
    /// The lake it is checked against.
    rect: Rect,
}

impl Drop for LakeJob {
    fn drop(&mut self) {
        self.stop.store(true, std::sync::atomic::Ordering::Relaxed);
    }
}

impl Model {
    pub fn new(preset: Preset, source: Option<PathBuf>, options: Options) -> Result<Self> {
        let sim = Simulation::new(&preset).context("the initial preset")?;
        let pose = sim.world_from_stone();
        let mut library = PresetLibrary::discover();
        library.current = source;
        library.save_name = preset.name.clone();
        let camera = Camera::default_for(&preset);
        let dt = preset.physics.dt;
        let mut m = Self {
            warnings: setup_warnings(&preset),
            notices: Vec::new(),
            loaded: preset.clone(),
            lake_track: None,
            lake_exit: None,
            lake_stale: true,
            lake_job: None,
            edit: preset,
            sim,
            lake_thread: options.lake_thread,
            lake_step: None,
            budget: FrameBudget::default(),
            pace: Pace::default(),
            deferred_physics: None,
            generation: 0,
            phase: Phase::Ready,
            clock: FixedClock::new(dt, 1),
            prev_pose: pose,
            cur_pose: pose,
            trail: Trail::new(),
            heights: WaterHeights::new(),
            samples: Vec::new(),
            plots: PlotSeries::default(),
            replay_log: ReplayLog::default(),
            ticks: 0,
            camera,
            view_mode: options.view.unwrap_or(ViewMode::Behind),
            exaggeration: options.exaggeration.unwrap_or(10.0),
            view: ViewSettings::default(),
            timing: FrameTiming::default(),
            stone_tick: 0.0,
            pending_changes: false,
            invalid: None,
            library,
            status: None,
            screenshot: None,
            ticks_last_frame: 0,
            view_rect: egui::Rect::from_min_size(egui::Pos2::ZERO, egui::vec2(1280.0, 800.0)),
            frame_physics: 0.0,
            frame_water: 0.0,
            frame_lake: 0.0,
            frames: 0,
            stats: FrameStats::default(),
            shown: Shown::default(),
            camera_moved_at: None,
            sharp_pending: false,
            last_full_redraw: true,
            just_rested: false,
            resting: false,
            outcome_time: None,
            last_drop: None,
            ghosts: VecDeque::new(),
            throws: 0,
            show_help: false,
            show_about: false,
            gesture: None,
            out_dir: files::output_dir(options.output_dir.as_deref()),
            show_experiments: false,
            keys_to_view: true,
            experiment_draft: Spec::suggested(Knob::Tilt),
            experiment_second: None,
            experiment: None,
            experiment_chosen: None,
        };
        if let Some(s) = options.render_scale {
            m.view.render_scale = s;
        }
        m.start_run();
        m.refresh_lake();
        Ok(m)
    }

    /// Runs the edited throw on flat water and notes whether it would leave the lake, if the
    /// edit changed since the last check.
    pub fn refresh_lake(&mut self) {
        if !self.lake_stale {
            return;
        }
        self.lake_job = None;
        self.lake_stale = false;
        self.lake_track = None;
        self.lake_exit = None;
        let Some(rect) = lake::lake_rect(&self.edit) else {
            return;
        };
        if let Ok(track) = lake::flat_track(&self.edit) {
            self.lake_exit = lake::leaves_lake(track, rect, lake::WARN_MARGIN);
            self.lake_track = Some(track);
        }
    }

    /// Starts the lake check of the edited throw in the background (at the lowest CPU priority),
    /// replacing one still running: the panels never wait for a throw to be simulated.
    pub fn start_lake_check(&mut self) {
        self.lake_stale = false;
        self.lake_track = None;
        self.lake_exit = None;
        self.lake_job = None;
        let Some(rect) = lake::lake_rect(&self.edit) else {
            return;
        };
        let preset = self.edit.clone();
        let (sender, receiver) = std::sync::mpsc::channel();
        let stop = std::sync::Arc::new(std::sync::atomic::AtomicBool::new(false));
        let flag = stop.clone();
        std::thread::spawn(move || {
            super::experiments::lower_priority();
            let given_up = || flag.load(std::sync::atomic::Ordering::Relaxed);
            let _ = sender.send(lake::flat_track_until(&preset, &given_up).ok());
        });
        self.lake_job = Some(LakeJob {
            receiver,
            stop,
            rect,
        });
    }

    /// Takes the background lake check's result when it has come; true while one is running.
    pub fn poll_lake_check(&mut self) -> bool {
        let Some(job) = &self.lake_job else {
            return false;
        };
        match job.receiver.try_recv() {
            Ok(track) => {
                if let Some(track) = track {
                    self.lake_exit = lake::leaves_lake(track, job.rect, lake::WARN_MARGIN);
                    self.lake_track = Some(track);
                }
                self.lake_job = None;
                false
            }
            Err(std::sync::mpsc::TryRecvError::Empty) => true,
            Err(std::sync::mpsc::TryRecvError::Disconnected) => {
                self.lake_job = None;
                false
            }
        }
    }

    /// Puts one panel's values back to the loaded preset's.
    pub fn revert(&mut self, section: Section) {
        match section {
            Section::Launch => self.edit.launch = self.loaded.launch,
            Section::Stone => self.edit.stone = self.loaded.stone.clone(),
            Section::Water => self.edit.water = self.loaded.water,
            Section::Physics => {
                self.edit.physics = self.loaded.physics;
                self.physics_edited();
                return;
            }
        }
        self.scene_edited();
    }

    /// Fits the lake to the edited throw (cell size kept), or says why not.
    pub fn fit_lake(&mut self) {
        self.refresh_lake();
        let Some(track) = self.lake_track else {
            return;
        };
        match lake::fit_lake(&self.edit, track) {
            Ok(p) => {
                self.edit.water = p.water;
                self.scene_edited();
                self.refresh_lake();
                let w = &self.edit.water;
                let when = if self.pending_changes {
                    ", applied on the next throw or reset"
                } else {
                    ""
                };
                self.post(Message::info(format!(
                    "lake fitted to the throw: {:.1} × {:.1} m in {:.1} cm cells ({:.2} million \
                     columns){when}",
                    w.size[0],
                    w.size[1],
                    w.cell * 100.0,
                    (w.size[0] / w.cell).round() * (w.size[1] / w.cell).round() / 1e6
                )));
            }
            Err(e) => self.post(Message::error(format!("lake not fitted: {e}"))),
        }
    }

    /// The window's title: the loaded preset's name.
    pub fn title(&self) -> String {
        format!("stoneskip — {}", self.edit.name)
    }

    pub fn post(&mut self, message: Message) {
        self.status = Some(Status {
            message,
            at: Instant::now(),
        });
    }

    /// Resets the run's bookkeeping after `sim` was (re)built.
    fn start_run(&mut self) {
        self.generation += 1;
        // A lake still stepping belongs to the run before: it is dropped when it ends.
        self.lake_step = None;
        self.sim.defer_lake(self.lake_thread);
        self.ticks = 0;
        let dt = self.sim.preset().physics.dt;
        self.clock.set_step(dt);
        self.clock
            .set_max_steps((MAX_SIM_PER_FRAME * self.clock.speed().max(1.0) / dt).ceil() as u64);
        self.clock.reset();
        self.clock.clear_skipped();
        self.last_drop = None;
        self.resting = false;
        self.outcome_time = None;
        self.pace.clear();
        self.deferred_physics = None;
        let pose = self.sim.world_from_stone();
        self.prev_pose = pose;
        self.cur_pose = pose;
        self.trail.start(pose.0);
        self.samples.clear();
        self.plots.clear();
        let first = StepSample {
            time: self.sim.time(),
            state: *self.sim.state(),
            angular_velocity: self.sim.angular_velocity(),
            in_contact: self.sim.in_contact(),
            wetted_area: 0.0,
            force: DVec3::ZERO,
        };
        self.samples.push(first);
        self.plots.push(&first, self.weight());
        self.heights.refresh(&self.sim, self.generation);
        self.warnings = setup_warnings(self.sim.preset());
    }

    /// A new simulation from `preset`, or why not (the current one stays).
    fn rebuild(&mut self, preset: &Preset) -> Result<(), String> {
        let sim = Simulation::new(preset).map_err(|e| e.to_string())?;
        self.sim = sim;
        self.start_run();
        Ok(())
    }

    /// Keeps the run that ends now as a ghost (if anything was thrown).
    fn keep_ghost(&mut self) {
        if self.phase == Phase::Ready || self.trail.points().len() < 3 {
            return;
        }
        self.ghosts.push_back(Ghost {
            number: self.throws,
            points: thinned(self.trail.points(), 400),
            skips: self.sim.skips(),
            distance: self.sim.distance(),
            outcome: self.sim.ending().words(),
        });
        while self.ghosts.len() > MAX_GHOSTS {
            self.ghosts.pop_front();
        }
    }

    pub fn throw(&mut self) {
        let preset = self.edit.clone();
        self.keep_ghost();
        match self.rebuild(&preset) {
            Ok(()) => {
                self.throws += 1;
                self.replay_log.start_throw(preset);
                self.pending_changes = false;
                self.phase = Phase::Running;
                self.clock.set_paused(false);
                if self.view_mode == ViewMode::Behind {
                    // The chase camera is the default while a throw runs.
                    self.view_mode = ViewMode::Follow;
                }
            }
            Err(e) => self.post(Message::error(format!("cannot throw: {e}"))),
        }
    }

    pub fn reset(&mut self) {
        let preset = self.edit.clone();
        self.keep_ghost();
        match self.rebuild(&preset) {
            Ok(()) => {
                self.pending_changes = false;
                self.phase = Phase::Ready;
                self.replay_log.stop();
                if self.view_mode == ViewMode::Follow {
                    self.view_mode = ViewMode::Behind;
                }
            }
            Err(e) => self.post(Message::error(format!("cannot reset: {e}"))),
        }
    }

    pub fn replay(&mut self) {
        self.keep_ghost();
        let Some(preset) = self.replay_log.start_replay() else {
            return;
        };
        match self.rebuild(&preset) {
            Ok(()) => {
                // A replay is a throw of its own in Earlier throws (#1, #2), not #1 twice.
                self.throws += 1;
                self.phase = Phase::Running;
                self.clock.set_paused(false);
            }
            Err(e) => self.post(Message::error(format!("cannot replay: {e}"))),
        }
    }

    /// One tick, recording the trail, samples and plots, and the time it took.
    pub fn tick_once(&mut self) {
        self.tick_part(&|_| false);
    }

    /// One tick or the part of it before `should_yield` (given the run's (steps, force
    /// evaluations)) says stop (see [`Simulation::tick_until`]): true when the tick is complete.
    /// Replay's changes and deferred physics edits apply at a tick's start only.
    fn tick_part(&mut self, should_yield: &dyn Fn((u64, u64)) -> bool) -> bool {
        if !self.sim.tick_in_progress() {
            if let Some(physics) = self.deferred_physics.take() {
                self.apply_physics(physics);
            }
            self.replay_log.apply_due(self.ticks, &mut self.sim);
        }
        self.prev_pose = self.cur_pose;
        let water_steps = self.sim.water().map(|w| w.steps());
        let start = Instant::now();
        let weight = self.weight();
        let Self {
            sim,
            trail,
            samples,
            plots,
            ..
        } = self;
        let progress = sim.tick_until(
            &mut |s| {
                trail.push(s);
                if samples.len() < MAX_SAMPLES {
                    samples.push(*s);
                }
                plots.push(s, weight);
            },
            should_yield,
        );
        let took = start.elapsed().as_secs_f64();
        if self.sim.water().map(|w| w.steps()) != water_steps {
            let stone = self.stone_tick.min(took);
            self.frame_physics += stone;
            self.frame_water += took - stone;
        } else {
            if progress == TickProgress::Done {
                self.stone_tick = if self.stone_tick == 0.0 {
                    took
                } else {
                    0.95 * self.stone_tick + 0.05 * took
                };
            }
            self.frame_physics += took;
        }
        self.cur_pose = self.sim.world_from_stone();
        let done = progress == TickProgress::Done;
        if done {
            self.ticks += 1;
        }
        done
    }

    /// Runs the ticks due after `real_dt` seconds of real time within the frame's [`budget`],
    /// then applies the rest rule. The budget stops the frame even inside a tick (between two
    /// steps of the stone); the tick resumes first thing at the next frame, and the steps the
    /// clock promised but the frame could not run are skipped (the clock does not pile up).
    ///
    /// [`budget`]: Model::budget
    /// One frame after the panels: the actions they pushed, whole ticks of the accumulated time
    /// (`real_dt` seconds since the last frame), the water's heights for the renderer, the
    /// camera. The app's frame and the UI tests both run it.
    pub fn update(&mut self, actions: Vec<Action>, real_dt: f64) {
        self.frame_lake = 0.0;
        let waited = self.lake_home();
        for a in actions {
            self.handle(a);
        }
        if let Some(e) = self.experiment.as_mut() {
            e.poll();
        }
        self.frame_physics = 0.0;
        self.frame_water = waited;
        self.advance(real_dt);
        let copy_start = Instant::now();
        self.heights.refresh(&self.sim, self.generation);
        self.frame_water += copy_start.elapsed().as_secs_f64();
        self.send_lake();
        self.update_camera(real_dt);
        self.frames += 1;
    }

    /// Takes back the lake handed to its own thread at the last frame's end (waiting for it if it
    /// has not finished): seconds waited. A run rebuilt since keeps its own lake. A thread that
    /// failed leaves the run without its water, said once.
    fn lake_home(&mut self) -> f64 {
        let Some((generation, handle)) = self.lake_step.take() else {
            return 0.0;
        };
        let start = Instant::now();
        match handle.join() {
            Ok(Some((stepped, took))) => {
                if generation == self.generation && self.sim.return_lake(stepped) {
                    self.frame_lake = took;
                }
            }
            Ok(None) | Err(_) => self.post(Message::error(
                "the lake's thread failed: the water stops here (the stone runs on)",
            )),
        }
        start.elapsed().as_secs_f64()
    }

    /// Hands the lake's queued ticks to a thread of its own, to step while the frame draws
    /// (`sim::lake`); where no thread can be started they step here.
    fn send_lake(&mut self) {
        if !self.lake_thread {
            return;
        }
        let Some(job) = self.sim.take_lake() else {
            return;
        };
        let slot = Arc::new(Mutex::new(Some(job)));
        let theirs = Arc::clone(&slot);
        let spawned = std::thread::Builder::new()
            .name("stoneskip-lake".into())
            .spawn(move || {
                let start = Instant::now();
                let job: Option<LakeWork> = theirs.lock().ok().and_then(|mut j| j.take());
                job.map(|j| (j.run(), start.elapsed().as_secs_f64()))
            });
        match spawned {
            Ok(handle) => self.lake_step = Some((self.generation, handle)),
            Err(_) => {
                let job = slot.lock().ok().and_then(|mut j| j.take());
                if let Some(job) = job {
                    let start = Instant::now();
                    self.sim.return_lake(job.run());
                    self.frame_water += start.elapsed().as_secs_f64();
                }
            }
        }
    }

    pub fn advance(&mut self, real_dt: f64) {
        self.ticks_last_frame = 0;
        if self.phase == Phase::Ready || self.resting {
            self.pace.clear();
            return;
        }
        self.clock.set_paused(self.phase == Phase::Paused);
        let due = self.clock.advance(real_dt);
        if due.skipped > 0.0 {
            self.last_drop = Some(Instant::now());
        }
        let t_before = self.sim.time();
        let start = Instant::now();
        let budget = self.budget;
        let wall = if self.pace.behind().is_some() {
            budget.wall_behind.min(budget.wall)
        } else {
            budget.wall
        };
        let evals_before = self.sim.cost().1;
        let spent = move |(_, evals): (u64, u64)| {
            evals.saturating_sub(evals_before) >= budget.force_evals || start.elapsed() > wall
        };
        let mut todo = due.steps;
        let mut short = false;
        if self.sim.tick_in_progress() {
            // Promised by an earlier frame; while paused it is the tick a Step asks for.
            if self.phase == Phase::Paused {
                todo = todo.saturating_sub(1);
            }
            if self.tick_part(&spent) {
                self.ticks_last_frame += 1;
            } else {
                short = true;
            }
        }
        let mut begun = 0;
        while !short && begun < todo {
            if spent(self.sim.cost()) {
                short = true;
                break;
            }
            begun += 1;
            if self.tick_part(&spent) {
                self.ticks_last_frame += 1;
            } else {
                short = true;
            }
        }
        if short {
            self.clock.skip_steps(todo - begun);
            self.last_drop = Some(Instant::now());
        }
        if self.phase == Phase::Running {
            let simulated = self.sim.time() - t_before;
            self.pace
                .record(real_dt, simulated, short || due.skipped > 0.0);
        } else {
            self.pace.clear();
        }
        self.check_rest();
    }

    /// Applies the rest rule (see [`rest_due`]).
    pub fn check_rest(&mut self) {
        if !self.sim.is_finished() {
            return;
        }
        let t = self.sim.time();
        let since = t - *self.outcome_time.get_or_insert(t);
        let eta = self
            .sim
            .water()
            .map(|w| w.max_abs_eta() - swell_amplitude(&self.edit));
        if rest_due(true, since, eta) {
            self.resting = true;
            self.just_rested = true;
            self.heights.refresh(&self.sim, self.generation);
        }
    }

    /// The stone's pose to draw: between the last two ticks while running.
    pub fn drawn_pose(&self) -> (DVec3, DQuat) {
        if self.phase != Phase::Running || self.resting {
            return self.cur_pose;
        }
        let alpha = self.clock.alpha();
        let (p0, q0) = self.prev_pose;
        let (p1, q1) = self.cur_pose;
        (p0.lerp(p1, alpha), q0.slerp(q1, alpha))
    }

    pub fn style(&self) -> SceneStyle {
        SceneStyle {
            show_trail: self.view.show_trail,
            show_markers: self.view.show_markers,
            show_splashes: self.view.show_splashes,
            ripple_gain: self.view.ripple_gain,
        }
    }

    pub fn framing(&self) -> Framing {
        framing_of(&self.sim, &self.trail, Some(self.drawn_pose()))
    }

    /// The scene to draw: the run, the guides of the view, the aim preview, the ghosts.
    pub fn scene(&self) -> Scene<'_> {
        let mut scene = build::scene_of(
            &self.sim,
            Some(self.drawn_pose()),
            &self.trail,
            &self.heights,
            self.camera,
            self.style(),
        );
        if self.view_mode == ViewMode::Side {
            scene.side_view = true;
            // The lake's rim stays; the side view's guides replace nothing else.
            let framing = self.framing();
            scene
                .lines
                .extend(side_guides(&framing, self.sim.contacts(), &self.camera));
            scene.lines.extend(build::attitude_glyphs(
                &framing,
                self.sim.contacts(),
                &self.camera,
                build::dug_in_touch(&self.sim),
            ));
        }
        if self.phase == Phase::Ready && self.invalid.is_none() {
            scene
                .lines
                .extend(aim_preview(self.sim.preset(), self.sim.stone()));
        }
        let ghosts: Vec<Vec<Vec3>> = self.ghosts.iter().map(|g| g.points.clone()).collect();
        scene.lines.extend(ghost_lines(&ghosts));
        scene
    }

    /// Moves the camera towards its view's (smoothly, `real_dt` s since the last frame).
    pub fn update_camera(&mut self, real_dt: f64) {
        let aspect = self.view_aspect();
        let Some(target) = camera_for(self.view_mode, &self.framing(), aspect, self.exaggeration)
        else {
            return;
        };
        let rate = if self.view_mode == ViewMode::Follow {
            8.0
        } else {
            5.0
        };
        let k = if self.frames == 0 || real_dt <= 0.0 {
            1.0
        } else {
            1.0 - (-(real_dt as f32) * rate).exp()
        };
        self.camera.blend(&target, k);
    }

    /// The camera is still travelling to its view.
    fn camera_settling(&self) -> bool {
        let Some(target) = camera_for(
            self.view_mode,
            &self.framing(),
            self.view_aspect(),
            self.exaggeration,
        ) else {
            return false;
        };
        let c = &self.camera;
        (c.target - target.target).length() > 1e-3 * c.distance.max(0.1)
            || (c.distance - target.distance).abs() > 1e-3 * c.distance.max(0.1)
            || (c.yaw - target.yaw).abs() > 1e-3
            || (c.pitch - target.pitch).abs() > 1e-3
    }

    /// The user is moving the camera (within the last quarter second).
    pub fn camera_moving(&self) -> bool {
        self.camera_moved_at
            .is_some_and(|t| t.elapsed() < Duration::from_millis(250))
    }

    /// Frames are being drawn one after another: the run animates or the camera moves.
    pub fn animating(&self) -> bool {
        (self.phase == Phase::Running && !self.resting)
            || self.sim.tick_in_progress()
            || self.camera_moving()
            || self.camera_settling()
            || self.gesture.is_some()
    }

    pub fn view_aspect(&self) -> f32 {
        self.view_rect.width() / self.view_rect.height().max(1.0)
    }

    pub fn apply_view(&mut self, req: ViewRequest) {
        self.camera_moved_at = Some(Instant::now());
        self.view_mode = match req {
            ViewRequest::Default => ViewMode::Behind,
            ViewRequest::Side => ViewMode::Side,
            ViewRequest::Follow => ViewMode::Follow,
            ViewRequest::Top => ViewMode::Top,
            ViewRequest::FrameAll => {
                let f = self.framing();
                self.camera
                    .frame(f.bounds.0, f.bounds.1, self.view_aspect());
                ViewMode::Free
            }
        };
    }

    pub fn load_preset(&mut self, path: &Path) {
        let message = match preset::load(path) {
            Ok(p) => match Simulation::new(&p) {
                Ok(_) => {
                    self.loaded = p.clone();
                    self.edit = p;
                    self.library.current = Some(path.to_owned());
                    self.library.save_name = self.edit.name.clone();
                    self.reset();
                    self.replay_log.forget();
                    self.ghosts.clear();
                    self.view_mode = ViewMode::Behind;
                    self.camera = Camera::default_for(&self.edit);
                    self.invalid = None;
                    self.lake_stale = true;
                    Message::info(format!("loaded {}", path.display()))
                }
                Err(e) => Message::error(format!("{}: {e}", path.display())),
            },
            // The error names file:line:col; the current scene stays as it is.
            Err(e) => Message::error(format!("preset not loaded: {e}")),
        };
        self.library.message = Some(message.clone());
        self.post(message);
    }

    pub fn save_preset(&mut self, name: &str) {
        let Some(path) = self.library.user_path(name) else {
            self.library.message =
                Some(Message::error("give the preset a name (letters or digits)"));
            return;
        };
        let mut p = self.edit.clone();
        p.name = name.trim().to_owned();
        let result = path
            .parent()
            .map_or(Ok(()), std::fs::create_dir_all)
            .map_err(|e| format!("{}: {e}", path.display()))
            .and_then(|()| preset::save(&path, &p).map_err(|e| e.to_string()));
        match result {
            Ok(()) => {
                self.edit.name = p.name.clone();
                self.loaded = p;
                self.library.current = Some(path.clone());
                self.library.refresh();
                self.library.message = Some(Message::info(format!("saved {}", path.display())));
            }
            Err(e) => self.library.message = Some(Message::error(e)),
        }
    }

    pub fn export_csv(&mut self) {
        let path = files::output_path(&self.out_dir, &self.sim.preset().name, "csv");
        let result = files::write_csv(&path, &self.sim, &self.samples);
        let message = match result {
            Ok(()) => {
                let note = if self.samples.len() >= MAX_SAMPLES {
                    " (truncated: the run outgrew the sample buffer)"
                } else {
                    ""
                };
                Message::info(format!("trajectory written to {}{note}", path.display()))
            }
            Err(e) => Message::error(format!("CSV export failed: {e:#}")),
        };
        self.post(message);
    }

    pub fn handle(&mut self, action: Action) {
        match action {
            Action::Throw => self.throw(),
            Action::TogglePause => {
                self.phase = match self.phase {
                    Phase::Running => Phase::Paused,
                    Phase::Paused => Phase::Running,
                    Phase::Ready => Phase::Ready,
                };
            }
            Action::Step => self.step(),
            Action::Reset => self.reset(),
            Action::Replay => self.replay(),
            Action::LoadPreset(p) => self.load_preset(&p),
            Action::SavePresetAs(name) => self.save_preset(&name),
            Action::RefreshPresets => self.library.refresh(),
            Action::ExportCsv => self.export_csv(),
            Action::Screenshot { panels } => {
                self.screenshot = Some(if panels { Shot::Window } else { Shot::ViewOnly })
            }
            Action::View(v) => self.apply_view(v),
            Action::Exaggerate(k) => self.exaggeration = k,
            Action::DismissMessage => {
                self.status = None;
                self.library.message = None;
            }
            Action::SceneEdited => self.scene_edited(),
            Action::PhysicsEdited => self.physics_edited(),
            Action::FitLake => self.fit_lake(),
            Action::Revert(section) => self.revert(section),
            Action::RunExperiment => {
                self.experiment_chosen = None;
                let plan = Plan {
                    x: self.experiment_draft,
                    y: self.experiment_second,
                };
                // The panel offers no conflicting pair; a pair that conflicts runs one value.
                let plan = if plan.conflict().is_some() {
                    Plan::from(plan.x)
                } else {
                    plan
                };
                self.experiment = Some(Experiment::start(&self.edit, &self.loaded, plan));
            }
            Action::StopExperiment => {
                if let Some(e) = &self.experiment {
                    e.stop();
                }
            }
            Action::LoadExperimentPoint(i) => self.load_experiment_point(i),
            Action::ExportExperiment => self.export_experiment(),
        }
    }

    /// Loads the experiment's throw `i` into the settings and throws it (the same preset the
    /// background ran, so the same result).
    fn load_experiment_point(&mut self, i: usize) {
        let Some(p) = self.experiment.as_ref().and_then(|e| e.presets.get(i)) else {
            return;
        };
        self.edit = p.clone();
        self.experiment_chosen = Some(i);
        self.scene_edited();
        self.throw();
    }

    fn export_experiment(&mut self) {
        let Some(e) = &self.experiment else {
            return;
        };
        let mut name = format!("{}-{}", self.edit.name, e.spec.knob.snake());
        if let Some(y) = e.second {
            name.push_str(&format!("-{}", y.knob.snake()));
        }
        let path = files::output_path(&self.out_dir, &name, "csv");
        let message = match e.write_csv(&path) {
            Ok(()) => Message::info(format!("experiment written to {}", path.display())),
            Err(e) => Message::error(format!("experiment export failed: {e:#}")),
        };
        self.post(message);
    }

    fn step(&mut self) {
        if self.phase == Phase::Ready {
            if self.pending_changes || self.invalid.is_some() {
                self.reset();
            }
            self.replay_log.start_throw(self.sim.preset().clone());
        }
        self.phase = Phase::Paused;
        self.resting = false;
        self.clock.set_paused(true);
        // The clock runs exactly one tick at the next advance.
        self.clock.request_step();
    }

    fn scene_edited(&mut self) {
        match self.edit.validate() {
            Err(e) => self.invalid = Some(e.to_string()),
            Ok(()) => {
                self.invalid = None;
                self.warnings = setup_warnings(&self.edit);
                self.lake_stale = true;
                if self.phase == Phase::Ready {
                    // Nothing thrown yet: show the change at once.
                    let preset = self.edit.clone();
                    if let Err(e) = self.rebuild(&preset) {
                        self.invalid = Some(e);
                    }
                } else {
                    self.pending_changes = true;
                }
            }
        }
    }

    fn physics_edited(&mut self) {
        match self.edit.physics.validate() {
            Err(e) => self.invalid = Some(e.to_string()),
            Ok(()) => {
                self.invalid = None;
                self.warnings = setup_warnings(&self.edit);
                self.lake_stale = true;
                if self.sim.tick_in_progress() {
                    // Between ticks, where a replay would apply it too.
                    self.deferred_physics = Some(self.edit.physics);
                } else {
                    self.apply_physics(self.edit.physics);
                }
            }
        }
    }

    /// A live change of the physics, recorded for replay.
    fn apply_physics(&mut self, physics: stoneskip_physics::sim::params::Physics) {
        match self.sim.set_physics(physics) {
            Ok(()) => {
                self.clock.set_step(physics.dt);
                if self.phase != Phase::Ready {
                    // Replay takes over the user's change from here on.
                    self.replay_log.record(self.ticks, physics);
                    self.resting = false;
                }
            }
            Err(e) => self.invalid = Some(e.to_string()),
        }
    }

    /// Real seconds per simulated second while the physics runs behind (see [`Pace::behind`]).
    pub fn running_behind(&self) -> Option<f64> {
        self.pace.behind()
    }

    /// Takes a new snapshot of what the panels show (every frame when still, at
    /// [`READOUT_HZ`] while animating).
    pub fn refresh_shown(&mut self) {
        let due = !self.animating()
            || self.shown.at.is_none_or(|t| {
                t.elapsed().as_secs_f64() >= 1.0 / READOUT_HZ
                    && self.frames >= self.shown.frame + READOUT_MIN_FRAMES
            });
        if !due {
            return;
        }
        // After the outcome only the water moves: keep the stone's run in the plots.
        let end = if self.sim.is_finished() {
            self.sim.summary().final_time
        } else {
            self.sim.time()
        };
        self.shown = Shown {
            readouts: self.readouts(),
            contacts: self.sim.contacts().to_vec(),
            plots: self.plots.decimated(400, end),
            plot_end: end,
            timing: self.timing,
            outcome: self.sim.outcome().map(|o| o.words().to_owned()),
            ending: self.sim.outcome().map(|_| self.sim.ending().words()),
            dropping_now: !self.resting
                && self
                    .last_drop
                    .is_some_and(|t| t.elapsed() < Duration::from_secs(2)),
            dropped_total: self.clock.skipped_total(),
            behind: if self.resting {
                None
            } else {
                self.running_behind()
            },
            at: Some(Instant::now()),
            frame: self.frames,
        };
    }

    /// The stone's weight now (N): what the lift plot's new points are read in g against.
    fn weight(&self) -> f64 {
        self.sim.stone().mass * self.sim.preset().physics.gravity
    }

    fn readouts(&self) -> Readouts {
        let s = self.sim.state();
        let f = self.sim.last_force();
        Readouts {
            time: self.sim.time(),
            skips: self.sim.skips(),
            distance: self.sim.distance(),
            speed: s.velocity.length(),
            height: s.position.z,
            attitude_deg: {
                let a = reported_attitude(s.orientation, s.velocity);
                [a[0], a[1]]
            },
            spin_rev_s: (self.sim.preset().physics.rotation == Rotation::Free).then(|| {
                self.sim
                    .angular_velocity()
                    .dot(s.orientation * glam::DVec3::Z)
                    / std::f64::consts::TAU
            }),
            in_contact: self.sim.in_contact(),
            wetted_area: if self.sim.in_contact() {
                f.wetted_area
            } else {
                0.0
            },
            // With the instant: after it the clock above runs on with the water's rings.
            outcome: self
                .sim
                .outcome()
                .zip(self.sim.end_time())
                .map(|(_, t)| format!("{} at {t:.2} s", self.sim.ending().words())),
            glide: self.sim.contacts().last().and_then(|c| {
                let radius = self.sim.stone().shape.half_extent();
                (contact_kind(c, radius) == ContactKind::Glide).then(|| slide_distance(c))
            }),
            ticks_last_frame: self.ticks_last_frame,
            dt: self.sim.preset().physics.dt,
        }
    }

    /// The stone's position on screen (points), for the throw gesture.
    pub fn stone_on_screen(&self) -> Option<egui::Pos2> {
        let r = self.view_rect;
        let p = self.camera.project(
            self.drawn_pose().0.as_vec3(),
            r.width().max(1.0) as u32,
            r.height().max(1.0) as u32,
        )?;
        Some(r.min + egui::vec2(p.x, p.y))
    }
}

/// The swell's amplitude (m): the part of max |η| that is the lake's own waves, not rings.
fn swell_amplitude(p: &Preset) -> f64 {
    p.water.swell.map_or(0.0, |s| s.amplitude.abs())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rests_only_after_the_outcome_once_the_rings_are_invisible() {
        assert!(!rest_due(false, 100.0, Some(0.0)));
        assert!(!rest_due(true, 0.5, Some(10.0 * ETA_VISIBLE)));
        assert!(rest_due(true, 0.5, Some(0.5 * ETA_VISIBLE)));
        assert!(rest_due(true, 0.0, None));
        // A swell never calms: rest a while after the outcome anyway.
        assert!(rest_due(true, REST_AFTER, Some(0.02)));
    }

    /// The lake on its own thread (issue 41): frame after frame the stone is the one of a model
    /// that steps the lake inside the frame, and once the lake is back its columns are too, bit
    /// for bit; the heights drawn are at most one frame's ticks behind.
    #[test]
    fn a_lake_on_its_own_thread_is_the_lake_stepped_in_the_frame() {
        let mut p = Preset::default();
        p.water.size = [8.0, 3.0];
        p.water.origin = Some([-1.0, -1.5]);
        p.water.cell = 0.05;
        let model = |lake_thread: bool| {
            let options = Options {
                lake_thread,
                ..Options::default()
            };
            let mut m = Model::new(p.clone(), None, options).unwrap();
            m.throw();
            m
        };
        let (mut inline, mut threaded) = (model(false), model(true));
        let mut handed = 0;
        for _ in 0..90 {
            inline.update(Vec::new(), 1.0 / 60.0);
            threaded.update(Vec::new(), 1.0 / 60.0);
            handed += usize::from(threaded.lake_step.is_some());
            assert_eq!(inline.sim.state(), threaded.sim.state());
            assert!(threaded.sim.lake_geometry().is_some());
        }
        assert!(handed > 60, "the lake went to its thread {handed} times");
        // A frame that runs no tick brings the lake home and hands nothing out.
        threaded.update(Vec::new(), 0.0);
        assert!(threaded.lake_step.is_none());
        let (a, b) = (inline.sim.water().unwrap(), threaded.sim.water().unwrap());
        assert_eq!(a.steps(), b.steps());
        assert!(a.max_abs_eta() > 1e-4);
        for iy in 0..a.ny() {
            for ix in 0..a.nx() {
                assert_eq!(a.eta(ix, iy).to_bits(), b.eta(ix, iy).to_bits());
            }
        }
    }

    #[test]
    fn the_app_stops_stepping_once_it_rests() {
        let mut p = Preset::version_1();
        p.water.size = [6.0, 2.0];
        p.physics.max_time = 3.0;
        let mut m = Model::new(p, None, Options::default()).unwrap();
        m.throw();
        let mut frames = 0;
        while !m.resting && frames < 20_000 {
            m.advance(1.0 / 60.0);
            frames += 1;
        }
        assert!(m.resting, "never rested");
        assert!(m.sim.is_finished());
        let eta = m.sim.water().map_or(0.0, |w| w.max_abs_eta());
        let since = m.sim.time() - m.sim.summary().final_time;
        assert!(
            eta < ETA_VISIBLE || since >= REST_AFTER - 1e-9,
            "{eta} {since}"
        );
        // Resting: time stands still and nothing animates.
        let t = m.sim.time();
        for _ in 0..10 {
            m.advance(1.0 / 60.0);
        }
        assert_eq!(m.sim.time(), t);
        assert_eq!(m.ticks_last_frame, 0);
        assert!(!m.animating() || m.camera_settling());
    }

    /// Issue 48, finding 7: a replay gets its own number in Earlier throws (#1, #2), and the
    /// ghost says why the throw ended.
    #[test]
    fn a_replay_is_numbered_as_a_throw_of_its_own() {
        let mut p = Preset::version_1();
        p.water.enabled = false;
        p.physics.max_time = 2.0;
        let mut m = Model::new(p, None, Options::default()).unwrap();
        m.throw();
        for _ in 0..200 {
            m.advance(1.0 / 30.0);
        }
        m.replay();
        for _ in 0..200 {
            m.advance(1.0 / 30.0);
        }
        m.throw();
        let numbers: Vec<u64> = m.ghosts.iter().map(|g| g.number).collect();
        assert_eq!(numbers, vec![1, 2], "{numbers:?}");
        assert!(m.ghosts.iter().all(|g| !g.outcome.is_empty()));
    }

    #[test]
    fn step_runs_one_tick_and_stays_paused() {
        let mut p = Preset::version_1();
        p.water.enabled = false;
        let mut m = Model::new(p, None, Options::default()).unwrap();
        m.handle(Action::Step);
        m.advance(0.5);
        assert_eq!(m.ticks, 1);
        assert_eq!(m.phase, Phase::Paused);
        m.advance(0.5);
        assert_eq!(m.ticks, 1);
        m.handle(Action::Step);
        m.advance(0.0);
        assert_eq!(m.ticks, 2);
        // Resume: real time runs ticks again (0.1 s at the preset's dt).
        m.handle(Action::TogglePause);
        m.advance(0.1);
        let due = (0.1 / m.sim.preset().physics.dt).round() as u64;
        assert_eq!(m.ticks, 2 + due);
    }

    #[test]
    fn warns_of_implausible_setups() {
        let ok = Preset::version_1();
        assert!(setup_warnings(&ok).is_empty(), "{:?}", setup_warnings(&ok));
        let mut fast = ok.clone();
        fast.physics.integrator = Integrator::Paper;
        fast.physics.dt = 0.005;
        let w = &setup_warnings(&fast)[0];
        assert!(
            w.contains("too long for the Paper integrator: bounces may gain energy"),
            "{w}"
        );
        // Between the accurate and the stable step: the accuracy warning.
        fast.physics.dt = 0.001;
        let w = &setup_warnings(&fast)[0];
        assert!(
            w.contains("to be accurate") && w.contains("1.000 ms"),
            "{w}"
        );
        let mut light = ok.clone();
        light.stone.mass = 1e-3;
        let w = &setup_warnings(&light)[0];
        assert!(
            w.contains("lighter than water") && w.contains("float"),
            "{w}"
        );
        // Issue 48: a 3 kg lens (48 000 kg/m³) is denser than any rock, and says so.
        let mut heavy = ok.clone();
        heavy.stone.mass = 3.0;
        let w = setup_warnings(&heavy);
        assert!(
            w.iter().any(|w| w.contains("denser than any rock")),
            "{w:?}"
        );
        let mut wavy = ok.clone();
        wavy.water.wavy_contact = true;
        wavy.water.cell = 0.05;
        let w = &setup_warnings(&wavy)[0];
        assert!(w.starts_with("Wavy contact is on (5.0 cm cells"), "{w}");
        // No cell is converged (fidelity §9): the finest one the UI allows is warned of too, and
        // the tick is named (§11).
        wavy.water.cell = 0.005;
        let w = &setup_warnings(&wavy)[0];
        assert!(w.contains("trust trends, not exact skip counts"), "{w}");
        assert!(w.contains("5.00 ms time step"), "{w}");
        // No warning cites a study section the app cannot open.
        for p in [&fast, &light, &wavy] {
            for w in setup_warnings(p) {
                assert!(!w.contains('§') && !w.contains("study"), "{w}");
            }
        }
    }

    #[test]
    fn a_drag_up_the_screen_throws_straight_ahead() {
        let base = Preset::version_1().launch;
        // A third of a 600 px view, straight up: 10 m/s along the camera's heading (0).
        let l = gesture_launch(&base, Vec2::new(0.0, -200.0), 600.0, 0.0);
        let v = DVec3::from_array(l.velocity);
        assert!((v.length() - 10.0).abs() < 1e-4, "{v:?}");
        assert!(v.y.abs() < 1e-9 && v.x > 0.0);
        // The elevation of the panel's velocity is kept.
        let v0 = DVec3::from_array(base.velocity);
        assert!((v.z / v.length() - v0.z / v0.length()).abs() < 1e-9);
        // A drag up and to the right turns the throw right (negative heading, z up).
        let r = gesture_launch(&base, Vec2::new(100.0, -100.0), 600.0, 0.0);
        assert!(
            (r.attitude.heading_deg + 45.0).abs() < 1e-4,
            "{}",
            r.attitude.heading_deg
        );
        assert!(r.velocity[1] < 0.0);
        // A click is not a throw.
        assert_eq!(gesture_launch(&base, Vec2::new(1.0, 1.0), 600.0, 0.0), base);
    }

    /// The panels start the lake check in the background and take its answer when it comes:
    /// the same answer as the check done in place.
    #[test]
    fn the_lake_check_runs_in_the_background() {
        let mut p = Preset::version_1();
        p.water.size = [10.0, 3.0];
        p.water.cell = 0.05;
        let v = DVec3::from_array(p.launch.velocity);
        p.launch.velocity = (v * 1.5).to_array();
        let mut m = Model::new(p, None, Options::default()).unwrap();
        let in_place = m.lake_exit.clone().expect("leaves the lake");
        m.lake_stale = true;
        m.start_lake_check();
        assert_eq!(m.lake_exit, None, "not answered yet");
        let t0 = Instant::now();
        while m.poll_lake_check() {
            assert!(t0.elapsed().as_secs() < 60, "no answer");
            std::thread::sleep(Duration::from_millis(2));
        }
        assert_eq!(m.lake_exit, Some(in_place));
        // A newer edit replaces a check still running; its answer never lands.
        m.lake_stale = true;
        m.start_lake_check();
        m.start_lake_check();
        while m.poll_lake_check() {
            std::thread::sleep(Duration::from_millis(2));
        }
        assert!(m.lake_exit.is_some());
    }

    #[test]
    fn a_throw_that_would_leave_the_lake_is_told_and_fitted() {
        let mut p = Preset::version_1();
        p.water.size = [10.0, 3.0];
        p.water.cell = 0.05;
        let mut m = Model::new(p.clone(), None, Options::default()).unwrap();
        let within = m.lake_exit.clone();
        // Faster: the flat-water track now runs past the far edge.
        let v = DVec3::from_array(m.edit.launch.velocity);
        m.edit.launch.velocity = (v * 1.5).to_array();
        m.handle(Action::SceneEdited);
        m.refresh_lake();
        let exit = m.lake_exit.clone().expect("no warning");
        assert!(exit.contains("far"), "{exit} (before: {within:?})");
        m.handle(Action::FitLake);
        assert_eq!(m.lake_exit, None, "still leaves after the fit");
        assert_eq!(m.edit.water.cell, 0.05);
        assert!(m.edit.water.size[0] > 10.0);
        // The launch and the water now differ from the loaded preset; revert puts them back.
        m.handle(Action::Revert(Section::Launch));
        m.handle(Action::Revert(Section::Water));
        m.refresh_lake();
        assert_eq!(m.edit.launch, p.launch);
        assert_eq!(m.edit.water, p.water);
        assert_eq!(m.lake_exit, within);
    }
}
