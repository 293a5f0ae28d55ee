//! The desktop app: a winit window with the 3D view (the scene renderer) and the egui panels.
//!
//! The loop follows "Fix your timestep": real time accumulates (scaled by the slow-motion factor),
//! whole fixed ticks of `physics.dt` run, and the drawn stone pose is interpolated between the last
//! two ticks, so the frame rate never changes the result. Pause stops accumulating; Step runs exactly
//! one tick; a slow frame runs at most a capped number of ticks and drops the rest of the time
//! (shown in the top bar) instead of spiralling. Replaying rebuilds the simulation from the same
//! preset and replays the live physics changes at the same ticks: bit-identical.

use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::{Duration, Instant};

use anyhow::{anyhow, Context as _, Result};
use glam::{DQuat, DVec3, Vec3};
use winit::application::ApplicationHandler;
use winit::event::WindowEvent;
use winit::event_loop::{ActiveEventLoop, ControlFlow, EventLoop};
use winit::window::{Window, WindowId};

use crate::preset;
use crate::render::camera::throw_heading;
use crate::render::gpu::{
    describe_adapter, no_adapter_error, request_adapter, request_device, Gpu,
};
use crate::render::offscreen::read_rgba8;
use crate::render::{
    Camera, RendererConfig, Scene, SceneRenderer, SceneStyle, Trail, Viewport, WaterHeights,
};
use crate::report::CsvWriter;
use crate::sim::params::{Physics, Preset, Rotation};
use crate::sim::{Simulation, StepSample};
use crate::ui::{
    self, Action, FrameTiming, Message, Phase, PlotSeries, PresetLibrary, Readouts, SimControls,
    ViewRequest, ViewSettings,
};

/// Most simulated time one frame may run (s, before slow motion); the rest is dropped.
pub const MAX_SIM_PER_FRAME: f64 = 0.25;
/// Most wall time one frame may spend ticking.
pub const PHYSICS_BUDGET: Duration = Duration::from_millis(60);
/// Most step samples kept for the CSV export.
pub const MAX_SAMPLES: usize = 1_000_000;
/// Longest real time one frame may add (a stalled window does not fast-forward).
pub const MAX_FRAME_DT: f64 = 0.25;

/// Opens the app with `preset` (or the shipped default) and runs until the window closes, or for
/// `frames` frames (smoke tests: then exits 0).
pub fn run_app(preset: Option<PathBuf>, frames: Option<u64>) -> Result<()> {
    let (initial, source) = match &preset {
        Some(p) => (preset::load(p)?, Some(p.clone())),
        None => default_preset(),
    };
    let mut model = Model::new(initial, source)?;
    if std::env::var("STONESKIP_AUTOTHROW").is_ok_and(|v| v == "1") {
        model.throw();
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
    let mut app = App {
        model,
        gfx: None,
        frames_limit: frames,
        frames_drawn: 0,
        fatal: None,
        last_frame: None,
        repaint_at: Some(Instant::now()),
    };
    event_loop
        .run_app(&mut app)
        .map_err(|e| anyhow!("the window's event loop failed: {e}"))?;
    if let Some(e) = app.fatal.take() {
        return Err(e);
    }
    Ok(())
}

/// The shipped default preset, or the built-in one.
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

struct App {
    model: Model,
    gfx: Option<Gfx>,
    frames_limit: Option<u64>,
    frames_drawn: u64,
    fatal: Option<anyhow::Error>,
    last_frame: Option<Instant>,
    repaint_at: Option<Instant>,
}

/// The window and everything on the GPU.
struct Gfx {
    /// A software rasteriser (llvmpipe, lavapipe): every pixel costs.
    software: bool,
    window: Arc<Window>,
    surface: wgpu::Surface<'static>,
    gpu: Gpu,
    config: wgpu::SurfaceConfiguration,
    scene: SceneRenderer,
    egui_ctx: egui::Context,
    egui_state: egui_winit::State,
    egui_renderer: egui_wgpu::Renderer,
    adapter: String,
    /// The frame is drawn here first (see [`canvas_view`]).
    canvas: Option<((u32, u32), wgpu::Texture, wgpu::TextureView)>,
    /// egui's output last frame (see [`ui_fingerprint`]).
    ui_fingerprint: Option<u64>,
}

impl Gfx {
    fn new(event_loop: &ActiveEventLoop, title: &str) -> Result<Self> {
        let attrs = Window::default_attributes()
            .with_title(title)
            .with_inner_size(window_size())
            .with_min_inner_size(winit::dpi::LogicalSize::new(640.0, 400.0));
        let window = Arc::new(
            event_loop
                .create_window(attrs)
                .map_err(|e| anyhow!("cannot create the window: {e}"))?,
        );
        let instance =
            wgpu::Instance::new(wgpu::InstanceDescriptor::new_with_display_handle_from_env(
                Box::new(event_loop.owned_display_handle()),
            ));
        let surface = instance.create_surface(window.clone()).map_err(|e| {
            no_adapter_error(&format!("no backend could draw into the window ({e})"))
        })?;
        let adapter = request_adapter(&instance, Some(&surface))?;
        let (device, queue) = request_device(&adapter)?;
        let caps = surface.get_capabilities(&adapter);
        // Non-sRGB first: egui and the scene shaders both write encoded colours.
        let format = caps
            .formats
            .iter()
            .copied()
            .find(|f| {
                matches!(
                    f,
                    wgpu::TextureFormat::Bgra8Unorm | wgpu::TextureFormat::Rgba8Unorm
                )
            })
            .or_else(|| caps.formats.first().copied())
            .ok_or_else(|| {
                anyhow!(
                    "the window's surface offers no colour format on {}",
                    describe_adapter(&adapter)
                )
            })?;
        let no_vsync = std::env::var("STONESKIP_NO_VSYNC").is_ok_and(|v| v == "1");
        let present_mode = if no_vsync {
            wgpu::PresentMode::AutoNoVsync
        } else {
            wgpu::PresentMode::AutoVsync
        };
        let size = window.inner_size();
        let config = wgpu::SurfaceConfiguration {
            // Copying the finished frame in is cheaper than drawing it in, where allowed.
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT
                | (caps.usages & wgpu::TextureUsages::COPY_DST),
            format,
            color_space: wgpu::SurfaceColorSpace::Auto,
            width: size.width.max(1),
            height: size.height.max(1),
            present_mode,
            desired_maximum_frame_latency: 2,
            alpha_mode: caps
                .alpha_modes
                .first()
                .copied()
                .unwrap_or(wgpu::CompositeAlphaMode::Auto),
            view_formats: vec![],
        };
        surface.configure(&device, &config);
        let samples = msaa_samples(&adapter, format);
        let scene = SceneRenderer::new(
            &device,
            &queue,
            RendererConfig {
                color_format: format,
                sample_count: samples,
            },
        );
        let egui_ctx = egui::Context::default();
        ui::apply_style(&egui_ctx);
        let egui_state = egui_winit::State::new(
            egui_ctx.clone(),
            egui::ViewportId::ROOT,
            &*window,
            Some(window.scale_factor() as f32),
            window.theme(),
            Some(device.limits().max_texture_dimension_2d as usize),
        );
        let egui_renderer = egui_wgpu::Renderer::new(
            &device,
            format,
            egui_wgpu::RendererOptions {
                msaa_samples: 1,
                depth_stencil_format: None,
                // Dithering costs per pixel on software rasterisers and 8-bit panels do not band.
                dithering: false,
                predictable_texture_filtering: false,
            },
        );
        let adapter_name = format!(
            "{}{}",
            describe_adapter(&adapter),
            if samples > 1 { ", 4× MSAA" } else { "" }
        );
        let software = adapter.get_info().device_type == wgpu::DeviceType::Cpu;
        Ok(Self {
            software,
            window,
            surface,
            gpu: Gpu {
                instance,
                adapter,
                device,
                queue,
            },
            config,
            scene,
            egui_ctx,
            egui_state,
            egui_renderer,
            adapter: adapter_name,
            canvas: None,
            ui_fingerprint: None,
        })
    }

    fn resize(&mut self, width: u32, height: u32) {
        if width == 0 || height == 0 {
            return;
        }
        self.config.width = width;
        self.config.height = height;
        self.surface.configure(&self.gpu.device, &self.config);
    }
}

/// The window's first size: `STONESKIP_WINDOW_SIZE=WxH` (e.g. 1280x720), else 1280 × 800.
fn window_size() -> winit::dpi::LogicalSize<f64> {
    let parsed = std::env::var("STONESKIP_WINDOW_SIZE").ok().and_then(|v| {
        let (w, h) = v.split_once('x')?;
        Some((w.trim().parse::<f64>().ok()?, h.trim().parse::<f64>().ok()?))
    });
    match parsed {
        Some((w, h)) if (320.0..=8192.0).contains(&w) && (240.0..=8192.0).contains(&h) => {
            winit::dpi::LogicalSize::new(w, h)
        }
        _ => winit::dpi::LogicalSize::new(1280.0, 800.0),
    }
}

/// MSAA samples for the 3D view: 4 where a hardware adapter can; `STONESKIP_MSAA=1` or `=4` overrides.
fn msaa_samples(adapter: &wgpu::Adapter, format: wgpu::TextureFormat) -> u32 {
    // Software rasterisers pay for every sample: off there unless asked for (STONESKIP_MSAA=4).
    let asked = std::env::var("STONESKIP_MSAA").ok();
    let software = adapter.get_info().device_type == wgpu::DeviceType::Cpu;
    if asked.as_deref() == Some("1") || (software && asked.as_deref() != Some("4")) {
        return 1;
    }
    let color = adapter.get_texture_format_features(format).flags;
    let depth = adapter
        .get_texture_format_features(crate::render::renderer::DEPTH_FORMAT)
        .flags;
    if color.sample_count_supported(4) && depth.sample_count_supported(4) {
        4
    } else {
        1
    }
}

/// Everything but the GPU: the run, the settings being edited, the view, the readouts.
struct Model {
    /// The settings the panels edit.
    edit: Preset,
    sim: Simulation,
    /// Changes whenever `sim` is rebuilt.
    generation: u64,
    phase: Phase,
    speed: f64,
    accumulator: f64,
    prev_pose: (DVec3, DQuat),
    cur_pose: (DVec3, DQuat),
    trail: Trail,
    heights: WaterHeights,
    samples: Vec<StepSample>,
    plots: PlotSeries,
    /// The preset of the last throw and its live physics changes (tick, physics).
    last_throw: Option<Preset>,
    physics_log: Vec<(u64, Physics)>,
    /// Physics changes still to apply while replaying.
    replay_queue: Vec<(u64, Physics)>,
    ticks: u64,
    camera: Camera,
    view: ViewSettings,
    dropped_total: f64,
    last_drop: Option<Instant>,
    timing: FrameTiming,
    /// Mean wall time of a tick that did not step the water (s).
    stone_tick: f64,
    pending_changes: bool,
    invalid: Option<String>,
    library: PresetLibrary,
    status: Option<Message>,
    screenshot: bool,
    ticks_last_frame: u32,
    /// The 3D view's rectangle in points.
    view_rect: egui::Rect,
    /// Wall time this frame spent on stone ticks and water steps (s).
    frame_physics: f64,
    frame_water: f64,
    frames: u64,
    stats: FrameStats,
    shown: Shown,
    /// What the last frame redrew.
    last_redraw: Redraw,
    /// When the user last moved the camera (frames drawn then may use the reduced resolution).
    camera_moved_at: Option<Instant>,
    /// The last frame was drawn at a reduced resolution although nothing animates: draw a sharp one.
    sharp_pending: bool,
}

/// What the panels show of the run, refreshed at most [`READOUT_HZ`] times a second while the
/// throw animates: the panels then stay pixel-identical between refreshes and only the 3D view
/// is redrawn (software rasterisers pay for every panel pixel).
#[derive(Debug, Clone, Default)]
struct Shown {
    readouts: Readouts,
    contacts: Vec<crate::sim::ContactEvent>,
    plots: [Vec<egui_plot::PlotPoint>; 3],
    plot_end: f64,
    timing: FrameTiming,
    outcome: Option<&'static str>,
    dropping_now: bool,
    dropped_total: f64,
    at: Option<Instant>,
    /// Frame number of the snapshot.
    frame: u64,
}

/// Refresh rate of the numbers and plots while a throw animates …
pub const READOUT_HZ: f64 = 4.0;
/// … and the fewest frames between two refreshes (a slow renderer still gets frames that redraw
/// only the 3D view).
pub const READOUT_MIN_FRAMES: u64 = 4;

/// Frame time totals (s) for the `--frames` report.
#[derive(Debug, Clone, Copy, Default)]
struct FrameStats {
    frames: u64,
    wall: f64,
    physics: f64,
    water: f64,
    render: f64,
    ui: f64,
    /// Frames that redrew the panels too, and their render time (s).
    full_redraws: u64,
    full_render: f64,
}

impl Model {
    fn new(preset: Preset, source: Option<PathBuf>) -> Result<Self> {
        let sim = Simulation::new(&preset).context("the initial preset")?;
        let pose = sim.world_from_stone();
        let mut library = PresetLibrary::discover();
        library.current = source;
        library.save_name = preset.name.clone();
        let camera = Camera::default_for(&preset);
        let mut m = Self {
            edit: preset,
            sim,
            generation: 0,
            phase: Phase::Ready,
            speed: 1.0,
            accumulator: 0.0,
            prev_pose: pose,
            cur_pose: pose,
            trail: Trail::new(),
            heights: WaterHeights::new(),
            samples: Vec::new(),
            plots: PlotSeries::default(),
            last_throw: None,
            physics_log: Vec::new(),
            replay_queue: Vec::new(),
            ticks: 0,
            camera,
            view: ViewSettings::default(),
            dropped_total: 0.0,
            last_drop: None,
            timing: FrameTiming::default(),
            stone_tick: 0.0,
            pending_changes: false,
            invalid: None,
            library,
            status: None,
            screenshot: false,
            ticks_last_frame: 0,
            view_rect: egui::Rect::from_min_size(egui::Pos2::ZERO, egui::vec2(1280.0, 800.0)),
            frame_physics: 0.0,
            frame_water: 0.0,
            frames: 0,
            stats: FrameStats::default(),
            shown: Shown::default(),
            last_redraw: Redraw::Full,
            camera_moved_at: None,
            sharp_pending: false,
        };
        m.start_run();
        Ok(m)
    }

    /// Resets the run's bookkeeping after `sim` was (re)built.
    fn start_run(&mut self) {
        self.generation += 1;
        self.ticks = 0;
        self.accumulator = 0.0;
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
        self.plots.push(&first);
        self.heights.refresh(&self.sim, self.generation);
    }

    /// A new simulation from `preset`, or why not (the current one stays).
    fn rebuild(&mut self, preset: &Preset) -> Result<(), String> {
        let sim = Simulation::new(preset).map_err(|e| e.to_string())?;
        self.sim = sim;
        self.start_run();
        Ok(())
    }

    fn throw(&mut self) {
        let preset = self.edit.clone();
        match self.rebuild(&preset) {
            Ok(()) => {
                self.last_throw = Some(preset);
                self.physics_log.clear();
                self.replay_queue.clear();
                self.pending_changes = false;
                self.phase = Phase::Running;
            }
            Err(e) => self.status = Some(Message::error(format!("cannot throw: {e}"))),
        }
    }

    fn reset(&mut self) {
        let preset = self.edit.clone();
        match self.rebuild(&preset) {
            Ok(()) => {
                self.pending_changes = false;
                self.phase = Phase::Ready;
                self.replay_queue.clear();
            }
            Err(e) => self.status = Some(Message::error(format!("cannot reset: {e}"))),
        }
    }

    fn replay(&mut self) {
        let Some(preset) = self.last_throw.clone() else {
            return;
        };
        match self.rebuild(&preset) {
            Ok(()) => {
                self.replay_queue = self.physics_log.iter().rev().copied().collect();
                self.phase = Phase::Running;
                self.status = Some(Message::info(format!(
                    "replaying \"{}\" ({} live physics change{})",
                    preset.name,
                    self.physics_log.len(),
                    if self.physics_log.len() == 1 { "" } else { "s" }
                )));
            }
            Err(e) => self.status = Some(Message::error(format!("cannot replay: {e}"))),
        }
    }

    /// One tick, recording the trail, samples and plots, and the time it took.
    fn tick_once(&mut self) {
        while self
            .replay_queue
            .last()
            .is_some_and(|(t, _)| *t <= self.ticks)
        {
            if let Some((_, p)) = self.replay_queue.pop() {
                // The logged physics was accepted once; a failure here would be a bug, not input.
                let _ = self.sim.set_physics(p);
            }
        }
        self.prev_pose = self.cur_pose;
        let water_steps = self.sim.water().map(|w| w.steps());
        let start = Instant::now();
        let Self {
            sim,
            trail,
            samples,
            plots,
            ..
        } = self;
        sim.tick_with(&mut |s| {
            trail.push(s);
            if samples.len() < MAX_SAMPLES {
                samples.push(*s);
            }
            plots.push(s);
        });
        let took = start.elapsed().as_secs_f64();
        let stepped_water = self.sim.water().map(|w| w.steps()) != water_steps;
        if stepped_water {
            let stone = self.stone_tick.min(took);
            self.frame_physics += stone;
            self.frame_water += took - stone;
        } else {
            self.stone_tick = if self.stone_tick == 0.0 {
                took
            } else {
                0.95 * self.stone_tick + 0.05 * took
            };
            self.frame_physics += took;
        }
        self.ticks += 1;
        self.cur_pose = self.sim.world_from_stone();
    }

    /// Runs the ticks due after `real_dt` seconds of real time.
    fn advance(&mut self, real_dt: f64) {
        self.ticks_last_frame = 0;
        if self.phase != Phase::Running {
            return;
        }
        self.accumulator += real_dt.clamp(0.0, MAX_FRAME_DT) * self.speed;
        let start = Instant::now();
        let dt0 = self.sim.preset().physics.dt;
        let cap = (MAX_SIM_PER_FRAME / dt0).ceil().max(1.0) as u32;
        loop {
            let dt = self.sim.preset().physics.dt;
            if self.accumulator < dt {
                break;
            }
            if self.ticks_last_frame >= cap || start.elapsed() > PHYSICS_BUDGET {
                let whole = (self.accumulator / dt).floor() * dt;
                self.accumulator -= whole;
                self.dropped_total += whole;
                self.last_drop = Some(Instant::now());
                break;
            }
            self.tick_once();
            self.accumulator -= dt;
            self.ticks_last_frame += 1;
        }
    }

    /// The stone's pose to draw: between the last two ticks while running.
    fn drawn_pose(&self) -> (DVec3, DQuat) {
        if self.phase != Phase::Running {
            return self.cur_pose;
        }
        let dt = self.sim.preset().physics.dt;
        let alpha = (self.accumulator / dt).clamp(0.0, 1.0);
        let (p0, q0) = self.prev_pose;
        let (p1, q1) = self.cur_pose;
        (p0.lerp(p1, alpha), q0.slerp(q1, alpha))
    }

    fn style(&self) -> SceneStyle {
        SceneStyle {
            show_trail: self.view.show_trail,
            show_markers: self.view.show_markers,
            show_splashes: self.view.show_splashes,
            ripple_gain: self.view.ripple_gain,
        }
    }

    fn scene(&self) -> Scene<'_> {
        Scene::from_simulation(
            &self.sim,
            Some(self.drawn_pose()),
            &self.trail,
            &self.heights,
            self.camera,
            self.style(),
        )
    }

    /// The user is moving the camera (within the last quarter second).
    fn camera_moving(&self) -> bool {
        self.camera_moved_at
            .is_some_and(|t| t.elapsed() < Duration::from_millis(250))
    }

    /// Frames are being drawn one after another: the run animates, the camera moves or follows.
    fn animating(&self) -> bool {
        self.phase == Phase::Running || self.view.follow || self.camera_moving()
    }

    fn view_aspect(&self) -> f32 {
        self.view_rect.width() / self.view_rect.height().max(1.0)
    }

    /// Bounds of what was thrown so far, or of the launch and a few metres ahead.
    fn bounds(&self) -> (Vec3, Vec3) {
        let scene = self.scene();
        let launch = self.sim.launch_position().as_vec3();
        let heading = throw_heading(self.sim.preset());
        let ahead = launch + Vec3::new(heading.cos(), heading.sin(), 0.0) * 4.0;
        match scene.bounds() {
            Some((lo, hi)) if (hi - lo).length() > 0.5 => (lo, hi),
            _ => (launch.min(ahead).with_z(0.0), launch.max(ahead)),
        }
    }

    fn apply_view(&mut self, req: ViewRequest) {
        self.camera_moved_at = Some(Instant::now());
        let aspect = self.view_aspect();
        match req {
            ViewRequest::Default => {
                self.camera = Camera::default_for(self.sim.preset());
                self.view.follow = false;
            }
            ViewRequest::Side => {
                let (lo, hi) = self.bounds();
                self.camera = Camera::side_view(lo, hi, throw_heading(self.sim.preset()), aspect);
                self.view.follow = false;
            }
            ViewRequest::FrameAll => {
                let (lo, hi) = self.bounds();
                self.camera.frame(lo, hi, aspect);
                self.view.follow = false;
            }
        }
    }

    fn load_preset(&mut self, path: &Path) {
        let message = match preset::load(path) {
            Ok(p) => match Simulation::new(&p) {
                Ok(_) => {
                    self.edit = p;
                    self.library.current = Some(path.to_owned());
                    self.library.save_name = self.edit.name.clone();
                    self.reset();
                    self.last_throw = None;
                    self.physics_log.clear();
                    self.camera = Camera::default_for(&self.edit);
                    self.view.follow = false;
                    self.invalid = None;
                    Message::info(format!("loaded {}", path.display()))
                }
                Err(e) => Message::error(format!("{}: {e}", path.display())),
            },
            // The error names file:line:col; the current scene stays as it is.
            Err(e) => Message::error(format!("preset not loaded: {e}")),
        };
        self.library.message = Some(message.clone());
        self.status = Some(message);
    }

    fn save_preset(&mut self, name: &str) {
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
                self.edit.name = p.name;
                self.library.current = Some(path.clone());
                self.library.refresh();
                self.library.message = Some(Message::info(format!("saved {}", path.display())));
            }
            Err(e) => self.library.message = Some(Message::error(e)),
        }
    }

    fn export_csv(&mut self) {
        let name = format!(
            "stoneskip-{}-{}.csv",
            crate::ui::file_stem_for(&self.sim.preset().name),
            unix_secs()
        );
        let path = PathBuf::from(name);
        let result = (|| -> Result<()> {
            let file = std::fs::File::create(&path)
                .with_context(|| format!("creating {}", path.display()))?;
            let physics = self.sim.preset().physics;
            let mut w = CsvWriter::new(
                std::io::BufWriter::new(file),
                self.sim.stone().clone(),
                physics.rotation,
                physics.gravity,
            )?;
            let mut it = self.samples.iter();
            if let Some(first) = it.next() {
                w.start(first)?;
            }
            for s in it {
                w.step(s)?;
            }
            w.finish()?;
            Ok(())
        })();
        self.status = Some(match result {
            Ok(()) => {
                let full = std::fs::canonicalize(&path).unwrap_or(path);
                let note = if self.samples.len() >= MAX_SAMPLES {
                    " (truncated: the run outgrew the sample buffer)"
                } else {
                    ""
                };
                Message::info(format!("trajectory written to {}{note}", full.display()))
            }
            Err(e) => Message::error(format!("CSV export failed: {e:#}")),
        });
    }

    fn handle(&mut self, action: Action) {
        match action {
            Action::Throw => self.throw(),
            Action::TogglePause => {
                self.phase = match self.phase {
                    Phase::Running => Phase::Paused,
                    Phase::Paused => Phase::Running,
                    Phase::Ready => Phase::Ready,
                };
            }
            Action::Step => {
                if self.phase == Phase::Ready {
                    if self.pending_changes || self.invalid.is_some() {
                        self.reset();
                    }
                    self.last_throw = Some(self.sim.preset().clone());
                    self.physics_log.clear();
                }
                self.phase = Phase::Paused;
                self.accumulator = 0.0;
                self.tick_once();
            }
            Action::Reset => self.reset(),
            Action::Replay => self.replay(),
            Action::LoadPreset(p) => self.load_preset(&p),
            Action::SavePresetAs(name) => self.save_preset(&name),
            Action::RefreshPresets => self.library.refresh(),
            Action::ExportCsv => self.export_csv(),
            Action::Screenshot => self.screenshot = true,
            Action::View(v) => self.apply_view(v),
            Action::SceneEdited => match self.edit.validate() {
                Err(e) => self.invalid = Some(e.to_string()),
                Ok(()) => {
                    self.invalid = None;
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
            },
            Action::PhysicsEdited => match self.edit.physics.validate() {
                Err(e) => self.invalid = Some(e.to_string()),
                Ok(()) => {
                    self.invalid = None;
                    let physics = self.edit.physics;
                    match self.sim.set_physics(physics) {
                        Ok(()) => {
                            if self.phase != Phase::Ready {
                                // Replay takes over the user's change from here on.
                                self.replay_queue.clear();
                                let now = self.ticks;
                                self.physics_log.retain(|(t, _)| *t <= now);
                                self.physics_log.push((now, physics));
                            }
                        }
                        Err(e) => self.invalid = Some(e.to_string()),
                    }
                }
            },
        }
    }

    /// Takes a new snapshot of what the panels show (every frame when still, at
    /// [`READOUT_HZ`] while animating).
    fn refresh_shown(&mut self) {
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
            outcome: self.sim.outcome().map(|o| o.as_str()),
            dropping_now: self
                .last_drop
                .is_some_and(|t| t.elapsed() < Duration::from_secs(2)),
            dropped_total: self.dropped_total,
            at: Some(Instant::now()),
            frame: self.frames,
        };
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
            in_contact: self.sim.in_contact(),
            wetted_area: if self.sim.in_contact() {
                f.wetted_area
            } else {
                0.0
            },
            outcome: self.sim.outcome().map(|o| o.as_str()),
            ticks_last_frame: self.ticks_last_frame,
            dt: self.sim.preset().physics.dt,
        }
    }

    /// All panels and the 3D view's input; pushes what the user asked for.
    fn build_ui(&mut self, ui: &mut egui::Ui, adapter: &str, actions: &mut Vec<Action>) {
        let ctx = ui.ctx().clone();
        if !ctx.egui_wants_keyboard_input() {
            ctx.input(|i| {
                if i.key_pressed(egui::Key::Space) && self.invalid.is_none() {
                    actions.push(Action::Throw);
                }
                if i.key_pressed(egui::Key::P) {
                    actions.push(Action::TogglePause);
                }
                if i.key_pressed(egui::Key::S) {
                    actions.push(Action::Step);
                }
                if i.key_pressed(egui::Key::R) {
                    actions.push(Action::Reset);
                }
                if i.key_pressed(egui::Key::F) {
                    self.view.follow = !self.view.follow;
                }
                if i.key_pressed(egui::Key::Num1) {
                    actions.push(Action::View(ViewRequest::Default));
                }
                if i.key_pressed(egui::Key::Num2) {
                    actions.push(Action::View(ViewRequest::Side));
                }
                if i.key_pressed(egui::Key::Num3) {
                    actions.push(Action::View(ViewRequest::FrameAll));
                }
            });
        }
        self.refresh_shown();
        let mut controls = SimControls {
            phase: self.phase,
            speed: self.speed,
            time: self.shown.readouts.time,
            outcome: self.shown.outcome,
            pending_changes: self.pending_changes,
            dropped_total: self.shown.dropped_total,
            dropping_now: self.shown.dropping_now,
            can_replay: self.last_throw.is_some(),
            invalid: self.invalid.clone(),
        };
        egui::Panel::top("top_bar").show(ui, |ui| {
            ui.add_space(2.0);
            ui.horizontal_wrapped(|ui| {
                ui.heading("stoneskip");
                ui.separator();
                ui::simulation_ui(ui, &mut controls, actions);
            });
            ui.horizontal_wrapped(|ui| {
                ui::view_ui(ui, &mut self.view, actions);
                if let Some(m) = &self.status {
                    ui.separator();
                    ui::message_ui(ui, m);
                }
            });
            ui.add_space(2.0);
        });
        self.speed = controls.speed;

        if self.view.show_settings {
            egui::Panel::left("settings")
                .default_size(330.0)
                .resizable(true)
                .show(ui, |ui| {
                    egui::ScrollArea::vertical().show(ui, |ui| {
                        self.settings_ui(ui, actions);
                    });
                });
        }
        if self.view.show_readouts {
            let shown = &self.shown;
            egui::Panel::right("readouts")
                .default_size(320.0)
                .resizable(true)
                .show(ui, |ui| {
                    egui::ScrollArea::vertical().show(ui, |ui| {
                        egui::CollapsingHeader::new(egui::RichText::new("Readouts").heading())
                            .default_open(true)
                            .show(ui, |ui| ui::readouts_ui(ui, &shown.readouts));
                        egui::CollapsingHeader::new(egui::RichText::new("Contacts").heading())
                            .default_open(true)
                            .show(ui, |ui| ui::contacts_ui(ui, &shown.contacts));
                        egui::CollapsingHeader::new(egui::RichText::new("Plots").heading())
                            .default_open(true)
                            .show(ui, |ui| ui::plots_ui(ui, &shown.plots, shown.plot_end));
                        egui::CollapsingHeader::new(egui::RichText::new("Frame time").heading())
                            .default_open(true)
                            .show(ui, |ui| ui::timing_ui(ui, &shown.timing, adapter));
                        egui::CollapsingHeader::new(egui::RichText::new("Export").heading())
                            .default_open(true)
                            .show(ui, |ui| ui::export_ui(ui, self.samples.len() > 1, actions));
                    });
                });
        }
        egui::CentralPanel::no_frame().show(ui, |ui| self.view_input(ui, actions));
    }

    fn settings_ui(&mut self, ui: &mut egui::Ui, actions: &mut Vec<Action>) {
        let head = |s: &str| egui::RichText::new(s).heading();
        egui::CollapsingHeader::new(head("Launch"))
            .default_open(true)
            .show(ui, |ui| {
                if ui::launch_ui(ui, &mut self.edit.launch) {
                    actions.push(Action::SceneEdited);
                }
                if self.edit.physics.rotation == Rotation::Locked {
                    // A spin slider that silently does nothing would mislead: say so, offer the fix.
                    ui.horizontal_wrapped(|ui| {
                        ui.weak("Spin has no effect while the attitude is Locked (the paper's high-spin limit).");
                        if ui
                            .small_button("Free rotation")
                            .on_hover_text("Physics ▸ Rotation: Free — torque, spin and gyroscope")
                            .clicked()
                        {
                            self.edit.physics.rotation = Rotation::Free;
                            actions.push(Action::PhysicsEdited);
                        }
                    });
                }
            });
        egui::CollapsingHeader::new(head("Stone"))
            .default_open(true)
            .show(ui, |ui| {
                if ui::stone_ui(ui, &mut self.edit.stone) {
                    actions.push(Action::SceneEdited);
                }
            });
        egui::CollapsingHeader::new(head("Physics"))
            .default_open(false)
            .show(ui, |ui| {
                ui.weak("Applied live, at the next step.");
                if ui::physics_ui(ui, &mut self.edit.physics) {
                    actions.push(Action::PhysicsEdited);
                }
            });
        egui::CollapsingHeader::new(head("Water"))
            .default_open(false)
            .show(ui, |ui| {
                ui.weak("Needs a new simulation: applied on the next throw or reset.");
                if ui::water_ui(ui, &mut self.edit.water) {
                    actions.push(Action::SceneEdited);
                }
            });
        egui::CollapsingHeader::new(head("Presets"))
            .default_open(true)
            .show(ui, |ui| {
                let can_replay = self.last_throw.is_some();
                ui::presets_ui(ui, &mut self.library, can_replay, actions);
            });
        egui::CollapsingHeader::new(head("Display"))
            .default_open(false)
            .show(ui, |ui| ui::display_ui(ui, &mut self.view));
    }

    /// The 3D view: orbit (drag), pan (right or middle drag), zoom (wheel), frame all (double
    /// click); a small overlay with the score.
    fn view_input(&mut self, ui: &mut egui::Ui, actions: &mut Vec<Action>) {
        let rect = ui.max_rect();
        self.view_rect = rect;
        let resp = ui.allocate_rect(rect, egui::Sense::click_and_drag());
        let delta = resp.drag_delta();
        if resp.dragged() && delta != egui::Vec2::ZERO {
            self.camera_moved_at = Some(Instant::now());
        }
        if resp.dragged_by(egui::PointerButton::Primary) {
            self.camera.orbit(-delta.x * 0.006, -delta.y * 0.006);
        } else if resp.dragged_by(egui::PointerButton::Secondary)
            || resp.dragged_by(egui::PointerButton::Middle)
        {
            self.camera.pan(delta.x, delta.y, rect.height());
            self.view.follow = false;
        }
        if resp.hovered() {
            let scroll = ui.input(|i| i.smooth_scroll_delta.y);
            if scroll != 0.0 {
                self.camera.zoom((-scroll * 0.0025).exp());
                self.camera_moved_at = Some(Instant::now());
            }
        }
        if resp.double_clicked() {
            actions.push(Action::View(ViewRequest::FrameAll));
        }
        let painter = ui.painter_at(rect);
        let score = format!(
            "{} skip{}   {:.2} m",
            self.shown.readouts.skips,
            if self.shown.readouts.skips == 1 {
                ""
            } else {
                "s"
            },
            self.shown.readouts.distance
        );
        let pos = rect.left_top() + egui::vec2(14.0, 10.0);
        painter.text(
            pos + egui::vec2(1.5, 1.5),
            egui::Align2::LEFT_TOP,
            &score,
            egui::FontId::proportional(22.0),
            egui::Color32::from_black_alpha(140),
        );
        painter.text(
            pos,
            egui::Align2::LEFT_TOP,
            &score,
            egui::FontId::proportional(22.0),
            egui::Color32::WHITE,
        );
        let hint = if self.phase == Phase::Ready {
            "Space: throw   ·   drag: orbit   right-drag: pan   wheel: zoom   F: follow"
        } else {
            "drag: orbit   right-drag: pan   wheel: zoom   double-click: frame all"
        };
        painter.text(
            rect.left_bottom() + egui::vec2(14.0, -10.0),
            egui::Align2::LEFT_BOTTOM,
            hint,
            egui::FontId::proportional(13.0),
            egui::Color32::from_white_alpha(190),
        );
    }
}

fn unix_secs() -> u64 {
    std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0, |d| d.as_secs())
}

impl App {
    fn frame(&mut self, event_loop: &ActiveEventLoop) {
        let Some(gfx) = self.gfx.as_mut() else {
            return;
        };
        let model = &mut self.model;
        let frame_start = Instant::now();
        let real_dt = self
            .last_frame
            .map_or(0.0, |t| frame_start.duration_since(t).as_secs_f64());
        self.last_frame = Some(frame_start);

        // Panels first: they decide the 3D view's rectangle and what the user asked for.
        let raw = gfx.egui_state.take_egui_input(&gfx.window);
        let mut actions = Vec::new();
        let adapter = gfx.adapter.clone();
        let mut full = gfx
            .egui_ctx
            .run_ui(raw, |ui| model.build_ui(ui, &adapter, &mut actions));
        let ui_s = frame_start.elapsed().as_secs_f64();
        gfx.egui_state
            .handle_platform_output(&gfx.window, std::mem::take(&mut full.platform_output));
        self.repaint_at = full
            .viewport_output
            .get(&egui::ViewportId::ROOT)
            .and_then(|v| frame_start.checked_add(v.repaint_delay));
        for a in actions {
            model.handle(a);
        }

        // Physics: whole ticks of the accumulated time.
        model.frame_physics = 0.0;
        model.frame_water = 0.0;
        model.advance(real_dt);
        let copy_start = Instant::now();
        model.heights.refresh(&model.sim, model.generation);
        model.frame_water += copy_start.elapsed().as_secs_f64();
        if model.view.follow {
            let target = model.drawn_pose().0.as_vec3();
            let k = 1.0 - (-(real_dt as f32) * 6.0).exp();
            let t = model.camera.target;
            model
                .camera
                .follow(t + (target - t) * if model.frames == 0 { 1.0 } else { k });
        }

        // Draw: the scene in the 3D view's rectangle, then the panels over it.
        let render_start = Instant::now();
        let ppp = full.pixels_per_point;
        let prims = gfx
            .egui_ctx
            .tessellate(std::mem::take(&mut full.shapes), ppp);
        let result = draw(gfx, model, &prims, &mut full.textures_delta, ppp);
        if let Err(e) = result {
            self.fatal = Some(e);
            event_loop.exit();
            return;
        }
        let render_s = render_start.elapsed().as_secs_f64();

        let frame_s = frame_start.elapsed().as_secs_f64();
        let smooth = |old: f64, new: f64| {
            if old == 0.0 {
                new
            } else {
                0.9 * old + 0.1 * new
            }
        };
        let continuous = self.frames_limit.is_some() || model.animating();
        let t = &mut model.timing;
        t.frame_ms = smooth(t.frame_ms, 1000.0 * frame_s);
        if continuous && real_dt > 0.0 {
            t.interval_ms = smooth(t.interval_ms, 1000.0 * real_dt);
        }
        t.physics_ms = smooth(t.physics_ms, 1000.0 * model.frame_physics);
        t.water_ms = smooth(t.water_ms, 1000.0 * model.frame_water);
        t.render_ms = smooth(t.render_ms, 1000.0 * render_s);
        t.ui_ms = smooth(t.ui_ms, 1000.0 * ui_s);
        // Totals past the first frames (shader compilation), for the --frames report.
        if model.frames >= 10 {
            let st = &mut model.stats;
            st.frames += 1;
            st.wall += real_dt;
            st.physics += model.frame_physics;
            st.water += model.frame_water;
            st.render += render_s;
            st.ui += ui_s;
            if model.last_redraw == Redraw::Full {
                st.full_redraws += 1;
                st.full_render += render_s;
            }
        }
        model.frames += 1;

        self.frames_drawn += 1;
        if self.frames_limit.is_some_and(|n| self.frames_drawn >= n) {
            if std::env::var("STONESKIP_FPS_REPORT").is_ok_and(|v| v == "1") {
                let st = &model.stats;
                let n = st.frames.max(1) as f64;
                eprintln!(
                    "stoneskip: {} frames at {}x{}; mean over the last {}: {:.1} fps ({:.2} ms a frame): physics {:.2} ms, water {:.2} ms, render {:.2} ms ({} full redraws at {:.2} ms, the rest {:.2} ms), panels {:.2} ms; {} ticks, {:.3} s simulated, {:.3} s dropped; {}",
                    self.frames_drawn,
                    gfx.config.width,
                    gfx.config.height,
                    st.frames,
                    n / st.wall.max(1e-9),
                    1000.0 * st.wall / n,
                    1000.0 * st.physics / n,
                    1000.0 * st.water / n,
                    1000.0 * st.render / n,
                    st.full_redraws,
                    1000.0 * st.full_render / st.full_redraws.max(1) as f64,
                    1000.0 * (st.render - st.full_render) / (st.frames - st.full_redraws).max(1) as f64,
                    1000.0 * st.ui / n,
                    model.ticks,
                    model.sim.time(),
                    model.dropped_total,
                    gfx.adapter
                );
            }
            event_loop.exit();
        }
    }
}

/// Records and presents one frame; writes a screenshot when asked.
fn draw(
    gfx: &mut Gfx,
    model: &mut Model,
    prims: &[egui::ClippedPrimitive],
    textures: &mut egui::TexturesDelta,
    ppp: f32,
) -> Result<()> {
    let device = &gfx.gpu.device;
    let queue = &gfx.gpu.queue;
    let textures_changed = !textures.set.is_empty() || !textures.free.is_empty();
    for (id, deltas) in textures.set.drain() {
        for d in deltas {
            gfx.egui_renderer.update_texture(device, queue, id, &d);
        }
    }
    let frame = match gfx.surface.get_current_texture() {
        wgpu::CurrentSurfaceTexture::Success(f) | wgpu::CurrentSurfaceTexture::Suboptimal(f) => {
            Some(f)
        }
        wgpu::CurrentSurfaceTexture::Outdated | wgpu::CurrentSurfaceTexture::Lost => {
            gfx.surface.configure(device, &gfx.config);
            None
        }
        wgpu::CurrentSurfaceTexture::Timeout | wgpu::CurrentSurfaceTexture::Occluded => None,
        wgpu::CurrentSurfaceTexture::Validation => {
            return Err(anyhow!("the window's surface failed validation"));
        }
    };
    if let Some(frame) = frame {
        let view = frame
            .texture
            .create_view(&wgpu::TextureViewDescriptor::default());
        let size = (gfx.config.width, gfx.config.height);
        // Everything is drawn into an ordinary texture, then copied to the window by a
        // write-only pass: blending straight into a software swapchain image reads it back, which
        // lavapipe makes very slow (the panels cost 5× more).
        let fresh_canvas = gfx.canvas.as_ref().is_none_or(|(s, _, _)| *s != size);
        let (canvas_tex, canvas) = canvas_view(gfx, size);
        // Software rasterisers without MSAA redraw only the 3D view while the panels are unchanged.
        let fingerprint = ui_fingerprint(prims, ppp);
        let redraw = if gfx.scene.config().sample_count == 1
            && !fresh_canvas
            && !textures_changed
            && gfx.ui_fingerprint == Some(fingerprint)
        {
            Redraw::ViewOnly
        } else {
            Redraw::Full
        };
        gfx.ui_fingerprint = Some(fingerprint);
        model.last_redraw = redraw;
        // A reduced-resolution frame of a still scene: follow it with a sharp one.
        model.sharp_pending =
            model.animating() && model.view.render_scale < 1.0 && model.phase != Phase::Running;
        let mut bufs = render_frame(
            gfx,
            model,
            prims,
            ppp,
            FrameTarget {
                view: &canvas,
                size,
                full_res: false,
                redraw,
            },
        );
        let mut encoder = gfx
            .gpu
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("present"),
            });
        if gfx.config.usage.contains(wgpu::TextureUsages::COPY_DST) {
            encoder.copy_texture_to_texture(
                canvas_tex.as_image_copy(),
                frame.texture.as_image_copy(),
                wgpu::Extent3d {
                    width: size.0,
                    height: size.1,
                    depth_or_array_layers: 1,
                },
            );
        } else {
            gfx.scene
                .blit_to(&gfx.gpu.device, &mut encoder, &canvas, &view);
        }
        bufs.push(encoder.finish());
        gfx.gpu.queue.submit(bufs);
        gfx.gpu.queue.present(frame);
    }
    if std::mem::take(&mut model.screenshot) {
        model.status = Some(match screenshot(gfx, model, prims, ppp) {
            Ok(p) => Message::info(format!("screenshot saved to {}", p.display())),
            Err(e) => Message::error(format!("screenshot failed: {e:#}")),
        });
    }
    for id in textures.free.drain() {
        gfx.egui_renderer.free_texture(&id);
    }
    Ok(())
}

/// The window-sized texture every frame is drawn into before it is copied to the window; it keeps
/// the panels' pixels between frames.
fn canvas_view(gfx: &mut Gfx, size: (u32, u32)) -> (wgpu::Texture, wgpu::TextureView) {
    if let Some((s, tex, view)) = &gfx.canvas {
        if *s == size {
            return (tex.clone(), view.clone());
        }
    }
    let tex = gfx.gpu.device.create_texture(&wgpu::TextureDescriptor {
        label: Some("canvas"),
        size: wgpu::Extent3d {
            width: size.0,
            height: size.1,
            depth_or_array_layers: 1,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: gfx.config.format,
        usage: wgpu::TextureUsages::RENDER_ATTACHMENT
            | wgpu::TextureUsages::TEXTURE_BINDING
            | wgpu::TextureUsages::COPY_SRC,
        view_formats: &[],
    });
    let view = tex.create_view(&wgpu::TextureViewDescriptor::default());
    gfx.canvas = Some((size, tex.clone(), view.clone()));
    (tex, view)
}

/// Where and how a frame is drawn.
struct FrameTarget<'a> {
    view: &'a wgpu::TextureView,
    size: (u32, u32),
    /// The 3D view at full resolution even while animating (screenshots).
    full_res: bool,
    redraw: Redraw,
}

/// Records the scene and the panels into the target; returns the command buffers to submit.
fn render_frame(
    gfx: &mut Gfx,
    model: &Model,
    prims: &[egui::ClippedPrimitive],
    ppp: f32,
    out: FrameTarget,
) -> Vec<wgpu::CommandBuffer> {
    let FrameTarget {
        view: target,
        size,
        full_res,
        redraw,
    } = out;
    let device = &gfx.gpu.device;
    let queue = &gfx.gpu.queue;
    let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
        label: Some("frame"),
    });
    let r = model.view_rect;
    let viewport = Viewport {
        x: r.min.x * ppp,
        y: r.min.y * ppp,
        width: (r.width() * ppp).max(1.0),
        height: (r.height() * ppp).max(1.0),
    };
    let scene = model.scene();
    // Reduced resolution while things move (stills are always sharp).
    let scale = if model.animating() && !full_res {
        model.view.render_scale
    } else {
        1.0
    };

    gfx.scene.set_render_scale(scale);
    gfx.scene.render(
        device,
        queue,
        &mut encoder,
        target,
        size,
        viewport,
        &scene,
        (redraw == Redraw::Full).then_some(wgpu::Color {
            r: 0.1,
            g: 0.1,
            b: 0.11,
            a: 1.0,
        }),
    );
    let screen = egui_wgpu::ScreenDescriptor {
        size_in_pixels: [size.0, size.1],
        pixels_per_point: ppp,
    };
    // A partial redraw keeps the panels' pixels: only what egui draws over the 3D view is drawn
    // again, clipped to it.
    let clipped: Vec<egui::ClippedPrimitive>;
    let prims = match redraw {
        Redraw::Full => prims,
        Redraw::ViewOnly => {
            clipped = prims
                .iter()
                .filter_map(|p| {
                    let clip = p.clip_rect.intersect(r);
                    (clip.is_positive()).then(|| egui::ClippedPrimitive {
                        clip_rect: clip,
                        primitive: p.primitive.clone(),
                    })
                })
                .collect();
            &clipped
        }
    };
    let mut bufs = gfx
        .egui_renderer
        .update_buffers(device, queue, &mut encoder, prims, &screen);
    {
        let mut pass = encoder
            .begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("egui"),
                color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                    view: target,
                    depth_slice: None,
                    resolve_target: None,
                    ops: wgpu::Operations {
                        load: wgpu::LoadOp::Load,
                        store: wgpu::StoreOp::Store,
                    },
                })],
                depth_stencil_attachment: None,
                timestamp_writes: None,
                occlusion_query_set: None,
                multiview_mask: None,
            })
            .forget_lifetime();
        gfx.egui_renderer.render(&mut pass, prims, &screen);
    }
    bufs.push(encoder.finish());
    bufs
}

/// How much of the window a frame draws again.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Redraw {
    Full,
    /// The 3D view and what lies over it; the panels' pixels are the last frame's.
    ViewOnly,
}

/// A fingerprint of egui's output: equal fingerprints draw equal pixels.
fn ui_fingerprint(prims: &[egui::ClippedPrimitive], ppp: f32) -> u64 {
    use std::hash::{Hash, Hasher};
    let mut h = std::collections::hash_map::DefaultHasher::new();
    ppp.to_bits().hash(&mut h);
    for p in prims {
        for v in [
            p.clip_rect.min.x,
            p.clip_rect.min.y,
            p.clip_rect.max.x,
            p.clip_rect.max.y,
        ] {
            v.to_bits().hash(&mut h);
        }
        match &p.primitive {
            egui::epaint::Primitive::Mesh(m) => {
                m.texture_id.hash(&mut h);
                bytemuck::cast_slice::<egui::epaint::Vertex, u8>(&m.vertices).hash(&mut h);
                m.indices.hash(&mut h);
            }
            // Callbacks draw what they like: never equal.
            egui::epaint::Primitive::Callback(_) => Instant::now().hash(&mut h),
        }
    }
    h.finish()
}

/// Draws the whole window (scene and panels) into a texture and saves it as a PNG in the current
/// directory.
fn screenshot(
    gfx: &mut Gfx,
    model: &Model,
    prims: &[egui::ClippedPrimitive],
    ppp: f32,
) -> Result<PathBuf> {
    let (w, h) = (gfx.config.width, gfx.config.height);
    let format = gfx.config.format;
    let tex = gfx.gpu.device.create_texture(&wgpu::TextureDescriptor {
        label: Some("screenshot"),
        size: wgpu::Extent3d {
            width: w,
            height: h,
            depth_or_array_layers: 1,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format,
        usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
        view_formats: &[],
    });
    let view = tex.create_view(&wgpu::TextureViewDescriptor::default());
    let bufs = render_frame(
        gfx,
        model,
        prims,
        ppp,
        FrameTarget {
            view: &view,
            size: (w, h),
            full_res: true,
            redraw: Redraw::Full,
        },
    );
    gfx.gpu.queue.submit(bufs);
    let mut pixels = read_rgba8(&gfx.gpu.device, &gfx.gpu.queue, &tex, w, h)?;
    if matches!(
        format,
        wgpu::TextureFormat::Bgra8Unorm | wgpu::TextureFormat::Bgra8UnormSrgb
    ) {
        for px in pixels.chunks_exact_mut(4) {
            px.swap(0, 2);
        }
    }
    for px in pixels.chunks_exact_mut(4) {
        px[3] = 255;
    }
    let img = image::RgbaImage::from_raw(w, h, pixels)
        .ok_or_else(|| anyhow!("pixel count does not match"))?;
    let path = PathBuf::from(format!("stoneskip-screenshot-{}.png", unix_secs()));
    img.save_with_format(&path, image::ImageFormat::Png)?;
    Ok(std::fs::canonicalize(&path).unwrap_or(path))
}

impl ApplicationHandler for App {
    fn resumed(&mut self, event_loop: &ActiveEventLoop) {
        if self.gfx.is_some() {
            return;
        }
        let title = format!("stoneskip — {}", self.model.edit.name);
        match Gfx::new(event_loop, &title) {
            Ok(g) => {
                if g.software {
                    // Half resolution while animating: about 4× fewer pixels to shade.
                    self.model.view.render_scale = 0.5;
                }
                g.window.request_redraw();
                self.gfx = Some(g);
            }
            Err(e) => {
                self.fatal = Some(e);
                event_loop.exit();
            }
        }
    }

    fn window_event(&mut self, event_loop: &ActiveEventLoop, _id: WindowId, event: WindowEvent) {
        let Some(gfx) = self.gfx.as_mut() else {
            return;
        };
        let response = gfx.egui_state.on_window_event(&gfx.window, &event);
        match event {
            WindowEvent::CloseRequested => event_loop.exit(),
            WindowEvent::Resized(size) => {
                gfx.resize(size.width, size.height);
                gfx.window.request_redraw();
            }
            WindowEvent::RedrawRequested => self.frame(event_loop),
            _ => {
                if response.repaint {
                    gfx.window.request_redraw();
                }
            }
        }
    }

    fn about_to_wait(&mut self, event_loop: &ActiveEventLoop) {
        let Some(gfx) = self.gfx.as_ref() else {
            return;
        };
        let continuous =
            self.frames_limit.is_some() || self.model.animating() || self.model.sharp_pending;
        let now = Instant::now();
        if continuous || self.repaint_at.is_some_and(|t| t <= now) {
            event_loop.set_control_flow(ControlFlow::Poll);
            gfx.window.request_redraw();
        } else if let Some(t) = self.repaint_at {
            event_loop.set_control_flow(ControlFlow::WaitUntil(t));
        } else {
            event_loop.set_control_flow(ControlFlow::Wait);
        }
    }
}
