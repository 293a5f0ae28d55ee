//! The platform layer: the winit window and its wgpu surface, the egui integration, and the event
//! loop's handler. It turns window events into frames ([`super::frame`]) and decides when to draw:
//! continuously while something animates, otherwise only on input (`ControlFlow::Wait`) — the
//! app rests once the run is over and the water calm.
//!
//! GPU faults: a zero-size window configures no surface (the last size stays until a real one
//! comes); a lost device (wgpu's device-lost callback, or an uncaptured error once the device is
//! gone) is recovered by building the GPU context, the renderers and the panels' state again on
//! the same window; an uncaptured error on a live device is reported in one message and the app
//! exits with a non-zero code.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};
use std::time::Instant;

use anyhow::{anyhow, Result};
use winit::application::ApplicationHandler;
use winit::event::WindowEvent;
use winit::event_loop::{ActiveEventLoop, ControlFlow};
use winit::window::{Window, WindowId};

use super::model::Model;
use super::options::{FaultKind, Options};
use super::soak::Soak;
use crate::ui;
use stoneskip_render::gpu::{
    describe_adapter, no_adapter_error, request_adapter, request_device, Gpu,
};
use stoneskip_render::{RendererConfig, SceneRenderer};

/// The app: the model, the window once it exists, and the frame loop's bookkeeping.
pub struct App {
    pub model: Model,
    pub options: Options,
    pub gfx: Option<Gfx>,
    pub frames_limit: Option<u64>,
    pub frames_drawn: u64,
    pub fatal: Option<anyhow::Error>,
    pub last_frame: Option<Instant>,
    pub repaint_at: Option<Instant>,
    /// The last frame asked for the next one at once (so the gap between them is frame time, not
    /// idle time).
    pub continuous: bool,
    /// The window title set last.
    pub title: String,
    /// The soak (`STONESKIP_SOAK`), while it runs.
    pub soak: Option<Soak>,
    /// GPU faults still to inject (`STONESKIP_FAULT`), in frame order.
    pub faults: Vec<super::options::Fault>,
    /// Faults survived: devices rebuilt after a loss, surfaces reconfigured.
    pub recoveries: Recoveries,
}

/// What the app recovered from (reported with `--frames` and by the soak).
#[derive(Debug, Default, Clone, Copy, PartialEq, Eq)]
pub struct Recoveries {
    pub devices: u32,
    pub surfaces: u32,
    /// A surface request that gave no frame (timeout, occluded window).
    pub skipped: u32,
}

/// Most device losses one run recovers from before it gives up with a message.
pub const MAX_DEVICE_RECOVERIES: u32 = 8;

/// What the device's callbacks saw: set from wgpu's threads, read once a frame.
#[derive(Debug, Default)]
pub struct DeviceWatch {
    pub lost: AtomicBool,
    /// The loss's reason and wgpu's message, or the first uncaptured error.
    pub message: Mutex<Option<String>>,
    pub error: AtomicBool,
}

impl DeviceWatch {
    /// Registers the callbacks on `device`: a loss is recorded (never a panic), and so is an
    /// uncaptured error (wgpu's default handler would panic).
    pub fn attach(device: &wgpu::Device) -> Arc<Self> {
        let watch = Arc::new(Self::default());
        let w = watch.clone();
        device.set_device_lost_callback(move |reason, message| {
            w.lost.store(true, Ordering::Release);
            let reason = match reason {
                wgpu::DeviceLostReason::Destroyed => "destroyed",
                wgpu::DeviceLostReason::Unknown => "lost by the driver",
            };
            w.note(if message.trim().is_empty() {
                reason.to_owned()
            } else {
                format!("{reason}: {message}")
            });
        });
        let w = watch.clone();
        device.on_uncaptured_error(Arc::new(move |e: wgpu::Error| {
            w.error.store(true, Ordering::Release);
            w.note(e.to_string());
        }));
        watch
    }

    /// Keeps the first message, on one line (wgpu's errors span several).
    fn note(&self, text: String) {
        let line = text.split_whitespace().collect::<Vec<_>>().join(" ");
        if let Ok(mut m) = self.message.lock() {
            m.get_or_insert(line);
        }
    }

    pub fn message(&self) -> String {
        self.message
            .lock()
            .ok()
            .and_then(|m| m.clone())
            .unwrap_or_else(|| "no message".to_owned())
    }
}

/// The GPU's state at the start of a frame.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum DeviceHealth {
    Fine,
    /// Lost (or destroyed): build it again.
    Lost,
    /// A live device reported an error nobody handled: a bug, reported and fatal.
    Failed,
}

/// The surface size for a window of `width` × `height` pixels: none while either is zero
/// (minimised, or resized to nothing), since a zero-size surface is a validation error.
pub fn surface_size(width: u32, height: u32) -> Option<(u32, u32)> {
    (width > 0 && height > 0).then_some((width, height))
}

/// The window and everything on the GPU.
pub struct Gfx {
    /// A software rasteriser (llvmpipe, lavapipe): every pixel costs.
    pub software: bool,
    pub window: Arc<Window>,
    pub surface: wgpu::Surface<'static>,
    pub gpu: Gpu,
    pub config: wgpu::SurfaceConfiguration,
    pub scene: SceneRenderer,
    pub egui_ctx: egui::Context,
    pub egui_state: egui_winit::State,
    pub egui_renderer: egui_wgpu::Renderer,
    pub adapter: String,
    /// The frame is drawn here first (see [`canvas_view`]).
    pub canvas: Option<((u32, u32), wgpu::Texture, wgpu::TextureView)>,
    /// The panels' tile fingerprints last frame (see [`super::redraw`]).
    pub ui_tiles: Option<super::redraw::PanelTiles>,
    pub watch: Arc<DeviceWatch>,
    /// The next frame treats the surface as lost (fault injection).
    pub surface_lost: bool,
}

impl Gfx {
    pub fn new(event_loop: &ActiveEventLoop, title: &str, options: &Options) -> Result<Self> {
        let attrs = Window::default_attributes()
            .with_title(title)
            .with_inner_size(winit::dpi::LogicalSize::new(
                options.window_size.0,
                options.window_size.1,
            ))
            .with_min_inner_size(winit::dpi::LogicalSize::new(640.0, 400.0));
        let window = Arc::new(
            event_loop
                .create_window(attrs)
                .map_err(|e| anyhow!("cannot create the window: {e}"))?,
        );
        Self::on_window(event_loop, window, options)
    }

    /// Everything on the GPU for an existing window (at start, and again after a lost device).
    pub fn on_window(
        event_loop: &ActiveEventLoop,
        window: Arc<Window>,
        options: &Options,
    ) -> Result<Self> {
        let instance =
            wgpu::Instance::new(wgpu::InstanceDescriptor::new_with_display_handle_from_env(
                Box::new(event_loop.owned_display_handle()),
            ));
        let surface = instance.create_surface(window.clone()).map_err(|e| {
            no_adapter_error(&format!("no backend could draw into the window ({e})"))
        })?;
        let adapter = request_adapter(&instance, Some(&surface))?;
        let (device, queue) = request_device(&adapter)?;
        let watch = DeviceWatch::attach(&device);
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
        let present_mode = if options.no_vsync {
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
        let samples = msaa_samples(&adapter, format, options.msaa);
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
            ui_tiles: None,
            watch,
            surface_lost: false,
        })
    }

    /// Reconfigures the surface for a new window size; a zero size keeps the old configuration.
    pub fn resize(&mut self, width: u32, height: u32) {
        let Some((width, height)) = surface_size(width, height) else {
            return;
        };
        self.config.width = width;
        self.config.height = height;
        self.surface.configure(&self.gpu.device, &self.config);
    }

    /// The device's state (polls it once when something was reported, so that a pending loss
    /// reaches its callback).
    pub fn health(&self) -> DeviceHealth {
        if self.watch.error.load(Ordering::Acquire) && !self.watch.lost.load(Ordering::Acquire) {
            let _ = self.gpu.device.poll(wgpu::PollType::Poll);
        }
        if self.watch.lost.load(Ordering::Acquire) {
            DeviceHealth::Lost
        } else if self.watch.error.load(Ordering::Acquire) {
            DeviceHealth::Failed
        } else {
            DeviceHealth::Fine
        }
    }

    /// Injects a fault (`STONESKIP_FAULT`).
    pub fn inject(&mut self, kind: FaultKind) {
        match kind {
            FaultKind::DeviceLost => {
                self.gpu.device.destroy();
                // The loss reaches its callback once the device is polled.
                let _ = self.gpu.device.poll(wgpu::PollType::Poll);
            }
            FaultKind::SurfaceLost => self.surface_lost = true,
            FaultKind::GpuError => {
                // Mapping for both reading and writing is invalid without a feature.
                let _ = self.gpu.device.create_buffer(&wgpu::BufferDescriptor {
                    label: Some("injected fault"),
                    size: 4,
                    usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::MAP_WRITE,
                    mapped_at_creation: false,
                });
            }
        }
    }
}

/// MSAA samples for the 3D view: 4 where a hardware adapter can; `STONESKIP_MSAA=1` or `=4` overrides.
fn msaa_samples(adapter: &wgpu::Adapter, format: wgpu::TextureFormat, asked: Option<u32>) -> u32 {
    // Software rasterisers pay for every sample: off there unless asked for (STONESKIP_MSAA=4).
    let software = adapter.get_info().device_type == wgpu::DeviceType::Cpu;
    if asked == Some(1) || (software && asked != Some(4)) {
        return 1;
    }
    let color = adapter.get_texture_format_features(format).flags;
    let depth = adapter
        .get_texture_format_features(stoneskip_render::renderer::DEPTH_FORMAT)
        .flags;
    if color.sample_count_supported(4) && depth.sample_count_supported(4) {
        4
    } else {
        1
    }
}

impl App {
    /// Takes a new GPU context into use.
    fn install(&mut self, g: Gfx) {
        if g.software && self.options.render_scale.is_none() {
            // Half resolution while animating: about 4× fewer pixels to shade.
            self.model.view.render_scale = 0.5;
        }
        g.window.request_redraw();
        self.gfx = Some(g);
    }

    fn fail(&mut self, event_loop: &ActiveEventLoop, e: anyhow::Error) {
        self.fatal = Some(e);
        event_loop.exit();
    }

    /// Before a frame: injects the faults due (`STONESKIP_FAULT`), then rebuilds a lost device or
    /// reports a failed one. False: no frame now.
    pub(super) fn gpu_checks(&mut self, event_loop: &ActiveEventLoop) -> bool {
        let frame = self.frames_drawn;
        while self.faults.first().is_some_and(|f| f.frame <= frame) {
            let fault = self.faults.remove(0);
            if let Some(g) = self.gfx.as_mut() {
                eprintln!("stoneskip: injecting {:?} before frame {frame}", fault.kind);
                g.inject(fault.kind);
            }
        }
        let Some(gfx) = self.gfx.as_ref() else {
            return false;
        };
        match gfx.health() {
            DeviceHealth::Fine => true,
            DeviceHealth::Failed => {
                let e = anyhow!(
                    "the GPU reported an error on {}: {}",
                    gfx.adapter,
                    gfx.watch.message()
                );
                self.fail(event_loop, e);
                false
            }
            DeviceHealth::Lost => self.recover_device(event_loop),
        }
    }

    /// Drops everything on the lost device (the window stays) and builds it all again: instance,
    /// adapter, device, surface, the scene and panel renderers, and the panels' state (egui's
    /// textures lived on the old device). The model — preset, run, cameras — is untouched.
    fn recover_device(&mut self, event_loop: &ActiveEventLoop) -> bool {
        let Some(old) = self.gfx.take() else {
            return false;
        };
        let why = old.watch.message();
        let window = old.window.clone();
        drop(old);
        self.recoveries.devices += 1;
        if self.recoveries.devices > MAX_DEVICE_RECOVERIES {
            let e = anyhow!(
                "the GPU device was lost {} times (last: {why}); giving up",
                self.recoveries.devices
            );
            self.fail(event_loop, e);
            return false;
        }
        match Gfx::on_window(event_loop, window, &self.options) {
            Ok(g) => {
                eprintln!(
                    "stoneskip: the GPU device was lost ({why}); rebuilt on {}",
                    g.adapter
                );
                self.model.post(crate::ui::Message::info(format!(
                    "the GPU device was lost ({why}) and has been rebuilt"
                )));
                self.install(g);
                true
            }
            Err(e) => {
                let e = e.context(format!(
                    "the GPU device was lost ({why}) and could not be rebuilt"
                ));
                self.fail(event_loop, e);
                false
            }
        }
    }
}

impl ApplicationHandler for App {
    fn resumed(&mut self, event_loop: &ActiveEventLoop) {
        if self.gfx.is_some() {
            return;
        }
        let title = self.model.title();
        match Gfx::new(event_loop, &title, &self.options) {
            Ok(g) => {
                self.title = title;
                self.install(g);
            }
            Err(e) => self.fail(event_loop, e),
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
                    // Input wakes a resting app: it draws (and steps, if a new throw asks).
                    gfx.window.request_redraw();
                }
            }
        }
    }

    /// An interrupt (SIGINT, see [`super::run_app`]): exit 0, with the frame report when asked.
    fn user_event(&mut self, event_loop: &ActiveEventLoop, _event: ()) {
        eprintln!("stoneskip: interrupted after {} frames", self.frames_drawn);
        if self.options.fps_report {
            eprintln!("{}", self.report());
        }
        event_loop.exit();
    }

    fn about_to_wait(&mut self, event_loop: &ActiveEventLoop) {
        let Some(gfx) = self.gfx.as_ref() else {
            return;
        };
        let continuous = self.frames_limit.is_some()
            || self.soak.is_some()
            || self.model.animating()
            || self.model.sharp_pending;
        self.continuous = continuous;
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_zero_size_window_configures_no_surface() {
        assert_eq!(surface_size(0, 0), None);
        assert_eq!(surface_size(0, 600), None);
        assert_eq!(surface_size(800, 0), None);
        assert_eq!(surface_size(1, 1), Some((1, 1)));
        assert_eq!(surface_size(1280, 800), Some((1280, 800)));
    }

    #[test]
    fn device_watch_records_the_first_message() {
        let w = DeviceWatch::default();
        assert_eq!(w.message(), "no message");
        w.note("Validation Error\n\nCaused by:\n  In Device::create_buffer\n".into());
        w.note("later".into());
        assert_eq!(
            w.message(),
            "Validation Error Caused by: In Device::create_buffer"
        );
    }
}
