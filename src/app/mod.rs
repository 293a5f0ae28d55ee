//! The desktop app: a winit window with the 3D view (the scene renderer) and the egui panels.
//!
//! Layers, each its own module:
//! - [`options`]: the environment hooks, read once;
//! - [`clock`]: the fixed-step clock ("Fix your timestep": accumulate real time scaled by the
//!   playback speed, run whole ticks of `physics.dt`, interpolate the drawn pose; pause, step,
//!   a per-frame cap that reports the time it skipped), so the frame rate never changes a result;
//! - [`replay`]: the last throw and its live physics changes, replayed bit for bit;
//! - [`model`]: the run, the edited settings, the cameras, the readouts, the rest rule — no window
//!   or GPU type, so it is unit-tested;
//! - [`files`]: where exports and screenshots go;
//! - `panels` and `overlays`: the egui panels and what is drawn over the 3D view;
//! - `frame`: one frame (panels → ticks → camera → draw);
//! - `platform`: the window, the surface and the event loop.

pub mod clock;
pub mod edits;
mod experiment_panel;
pub mod experiments;
pub mod files;
mod frame;
pub mod lake;
mod map_panel;
pub mod model;
pub mod options;
mod overlays;
mod panels;
mod platform;
mod redraw;
pub mod replay;
pub mod soak;

use std::path::PathBuf;
use std::time::Instant;

use anyhow::{anyhow, Result};
use winit::event_loop::EventLoop;

use crate::ui::PresetLibrary;
pub use model::Model;
pub use options::Options;
use platform::App;
use stoneskip_physics::preset;
use stoneskip_physics::sim::params::Preset;

/// Opens the app with `preset` (or the shipped default) and runs until the window closes, or for
/// `frames` frames (smoke tests: then exits 0).
pub fn run_app(preset: Option<PathBuf>, frames: Option<u64>) -> Result<()> {
    let options = Options::from_env();
    let (initial, source) = match &preset {
        // A file, or a shipped preset's name (as `simulate` takes it); Save As starts beside a file.
        Some(p) => (
            preset::load_file_or_shipped(p)?,
            p.exists().then(|| p.clone()),
        ),
        None => default_preset(),
    };
    let mut model = Model::new(initial, source, options.clone())?;
    if options.autothrow {
        model.throw();
    }
    if let Some((knob, count)) = options.experiment {
        model.show_experiments = true;
        model.experiment_draft = experiments::Spec {
            count,
            ..experiments::Spec::suggested(knob)
        };
        // A map: both sides over their map ranges, so many values a side.
        if let Some((second, n)) = options.experiment_map {
            let side = |k, n: usize| experiments::Spec {
                count: n.clamp(2, experiments::MAX_SIDE),
                ..experiments::Spec::for_map(k)
            };
            model.experiment_draft = side(knob, count);
            model.experiment_second = Some(side(second, n));
        }
        if let Some((from, to)) = options.experiment_range {
            model.experiment_draft.from = from;
            model.experiment_draft.to = to;
        }
        model.handle(crate::ui::Action::RunExperiment);
    }
    let event_loop = EventLoop::new().map_err(|e| {
        let why = e.to_string();
        anyhow!(
            "cannot open a window: {}. Is a display available (DISPLAY or WAYLAND_DISPLAY)? \
             Without one, run it under a virtual display: `xvfb-run -a stoneskip gui`, or render a \
             picture with `stoneskip render --preset FILE --out FILE.png`",
            why.trim_end_matches('.')
        )
    })?;
    // Ctrl+C (SIGINT) ends the app cleanly, with its report: the event loop is woken to exit.
    let proxy = event_loop.create_proxy();
    let _ = ctrlc::set_handler(move || {
        let _ = proxy.send_event(());
    });
    let soak = match options.soak {
        Some(n) => Some(soak::Soak::new(
            n,
            model.library.shipped.clone(),
            options.soak_csv.clone(),
        )?),
        None => None,
    };
    let mut app = App {
        soak,
        faults: options.faults.clone(),
        recoveries: Default::default(),
        title: model.title(),
        model,
        options,
        gfx: None,
        frames_limit: frames,
        frames_drawn: 0,
        fatal: None,
        last_frame: None,
        repaint_at: Some(Instant::now()),
        continuous: false,
    };
    event_loop
        .run_app(&mut app)
        .map_err(|e| anyhow!("the window's event loop failed: {e}"))?;
    if let Some(e) = app.fatal.take() {
        return Err(e);
    }
    Ok(())
}

/// The shipped default preset: its file when one is found (so Save As starts beside it), else the
/// same preset as compiled in ([`Preset::default`]).
fn default_preset() -> (Preset, Option<PathBuf>) {
    let lib = PresetLibrary::discover();
    if let Some(p) = lib
        .shipped
        .iter()
        .find(|p| p.file_stem().is_some_and(|s| s == "default"))
    {
        if let Ok(preset) = preset::load(p) {
            return (preset, Some(p.clone()));
        }
    }
    (Preset::default(), None)
}
