//! The app's egui panels, grouped as a user thinks: the throw (launch, stone), the physical
//! constants, the water, the simulation controls, presets, and the readouts (numbers, contacts,
//! plots, frame time, export).
//!
//! Panels edit plain data (the [`Preset`](stoneskip_physics::sim::params::Preset) being prepared, the view
//! settings) and report what the user asked for as [`Action`]s; the app carries them out. Every
//! slider's range lies inside what `Preset::validate` accepts; angles are shown in degrees and spin
//! in rev/s, converted to radians and rad/s here.

mod controls;
mod help;
mod presets;
mod readouts;
mod settings;

use std::path::PathBuf;

pub use controls::{behind_words, notices, simulation_ui, view_ui};
pub use help::{about_ui, help_ui, SHORTCUTS};
pub use presets::{file_stem_for, presets_ui, PresetLibrary};
pub use readouts::{
    contact_kind, contacts_ui, export_ui, ghosts_ui, plots_ui, readouts_ui, slide_distance,
    timing_ui, ContactKind, GhostRow, PlotSeries,
};
pub use settings::{
    clamp_note, display_ui, launch_ui, parse_finite, physics_ui, ranges, stone_ui, water_ui, Marks,
    World, MARK_COLOR,
};

/// What the user asked for this frame.
#[derive(Debug, Clone, PartialEq)]
pub enum Action {
    /// Build a new run from the edited preset and start it.
    Throw,
    TogglePause,
    /// Run exactly one tick (pauses first).
    Step,
    /// Back to the launch, waiting (applies pending changes).
    Reset,
    /// Run the last throw again, bit for bit (with its live physics changes at the same ticks).
    Replay,
    LoadPreset(PathBuf),
    SavePresetAs(String),
    RefreshPresets,
    ExportCsv,
    /// Save a PNG of the window (`panels`) or of the 3D view alone.
    Screenshot {
        panels: bool,
    },
    View(ViewRequest),
    /// The side view's vertical exaggeration (1, 5, 10, 20).
    Exaggerate(f32),
    /// Close the status message.
    DismissMessage,
    /// The launch, stone or water changed: needs a new simulation.
    SceneEdited,
    /// The physical constants changed: applied live.
    PhysicsEdited,
    /// Resize the lake to the edited throw's flat-water track (plus a margin, same cells).
    FitLake,
    /// Put one settings panel back to the loaded preset's values.
    Revert(Section),
    /// Experiments: throw the sweep being edited in the background.
    RunExperiment,
    StopExperiment,
    /// Load the experiment's throw of this index into the settings and throw it.
    LoadExperimentPoint(usize),
    ExportExperiment,
}

/// A settings panel that edits one section of the preset.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Section {
    Launch,
    Stone,
    Physics,
    Water,
}

/// Camera requests.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ViewRequest {
    /// Behind and above the launch point, looking along the throw.
    Default,
    /// From the side, the whole trajectory in view (the paper's Fig. 13), heights exaggerated.
    Side,
    /// A chase camera close behind the stone.
    Follow,
    /// From above.
    Top,
    /// Keep the direction, fit everything (then the camera is free).
    FrameAll,
}

/// Where the run stands.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Phase {
    /// At the launch point, not thrown yet.
    Ready,
    Running,
    Paused,
}

/// The simulation controls' state, shown and edited by [`simulation_ui`].
#[derive(Debug, Clone, PartialEq)]
pub struct SimControls {
    pub phase: Phase,
    /// Playback: simulated seconds per real second (0.01 – 4).
    pub speed: f64,
    /// Simulated time (s).
    pub time: f64,
    /// The stone's outcome in words, once decided ("sank", "left the lake", …).
    pub outcome: Option<String>,
    /// The run is over and the water calm: the app rests until there is input.
    pub resting: bool,
    /// A replay is running, with this many live physics changes.
    pub replaying: Option<usize>,
    /// Edits to the launch, stone or water wait for the next throw or reset.
    pub pending_changes: bool,
    /// Simulated time dropped because the physics could not keep up (s), in all and in the last
    /// second.
    pub dropped_total: f64,
    pub dropping_now: bool,
    /// Real seconds per simulated second over the last second, while the physics runs behind.
    pub behind: Option<f64>,
    /// A last throw exists to replay.
    pub can_replay: bool,
    /// Why the edited preset is refused, if it is.
    pub invalid: Option<String>,
}

/// View settings edited by [`view_ui`] and [`display_ui`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ViewSettings {
    pub show_settings: bool,
    pub show_readouts: bool,
    pub show_trail: bool,
    pub show_markers: bool,
    pub show_splashes: bool,
    /// Multiplies the water's slopes in the shading (1 = true to the simulation).
    pub ripple_gain: f32,
    /// Resolution of the 3D view while the run animates (stills are drawn at full resolution).
    pub render_scale: f32,
}

impl Default for ViewSettings {
    fn default() -> Self {
        Self {
            show_settings: true,
            show_readouts: true,
            show_trail: true,
            show_markers: true,
            show_splashes: true,
            ripple_gain: 1.0,
            render_scale: 1.0,
        }
    }
}

/// The numbers of the run now.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Readouts {
    pub time: f64,
    pub skips: usize,
    pub distance: f64,
    /// Centre-of-mass speed (m/s).
    pub speed: f64,
    /// Height of the centre of mass (m).
    pub height: f64,
    /// Tilt and bank to the path (°), as the contact table reports them.
    pub attitude_deg: [f64; 2],
    /// Spin about the stone's own axis (rev/s); `None` with the attitude locked.
    pub spin_rev_s: Option<f64>,
    pub in_contact: bool,
    /// Wetted area at the last step (m²).
    pub wetted_area: f64,
    /// In words.
    pub outcome: Option<String>,
    /// Horizontal distance slid in the last contact if it was a glide (m).
    pub glide: Option<f64>,
    /// Ticks run in the last frame.
    pub ticks_last_frame: u32,
    pub dt: f64,
}

/// Where the frame time goes (milliseconds, smoothed).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct FrameTiming {
    /// Work done in a frame (everything below, and the rest).
    pub frame_ms: f64,
    /// Real time between frames while animating (1000 / fps).
    pub interval_ms: f64,
    /// Stone ticks (integration, contact, forces).
    pub physics_ms: f64,
    /// Water grid steps and copying η for the GPU.
    pub water_ms: f64,
    /// Scene and panels drawn, submitted and presented.
    pub render_ms: f64,
    /// Building the panels (egui).
    pub ui_ms: f64,
}

/// A status line: what the last action did, or why it failed.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Message {
    pub text: String,
    pub error: bool,
}

impl Message {
    pub fn info(text: impl Into<String>) -> Self {
        Self {
            text: text.into(),
            error: false,
        }
    }

    pub fn error(text: impl Into<String>) -> Self {
        Self {
            text: text.into(),
            error: true,
        }
    }
}

/// Shows a message in red (error) or the normal colour, wrapped.
pub fn message_ui(ui: &mut egui::Ui, msg: &Message) {
    let color = if msg.error {
        egui::Color32::from_rgb(255, 110, 100)
    } else {
        ui.visuals().text_color()
    };
    ui.add(egui::Label::new(egui::RichText::new(&msg.text).color(color)).wrap());
}

/// The app's look: the dark theme, slightly larger text, roomier spacing.
pub fn apply_style(ctx: &egui::Context) {
    ctx.set_visuals(egui::Visuals::dark());
    ctx.global_style_mut(|style| {
        style.spacing.item_spacing = egui::vec2(8.0, 5.0);
        style.spacing.slider_width = 150.0;
        for (text_style, font) in style.text_styles.iter_mut() {
            font.size = match text_style {
                egui::TextStyle::Heading => 17.0,
                egui::TextStyle::Small => 11.0,
                _ => 13.5,
            };
        }
    });
}
