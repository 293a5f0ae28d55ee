//! The platform layer: the winit window and its wgpu surface, the egui integration, and the event
//! loop's handler. It turns window events into frames ([`super::frame`]) and decides when to draw:
//! continuously while something animates, otherwise only on input (`ControlFlow::Wait`) — the
//! app rests once the run is over and the water calm.

use std::sync::Arc;
use std::time::Instant;

use anyhow::{anyhow, Result};
use winit::application::ApplicationHandler;
use winit::event::WindowEvent;
use winit::event_loop::{ActiveEventLoop, ControlFlow};
use winit::window::{Window, WindowId};

use super::model::Model;
use super::options::Options;
use crate::render::gpu::{
    describe_adapter, no_adapter_error, request_adapter, request_device, Gpu,
};
use crate::render::{RendererConfig, SceneRenderer};
use crate::ui;

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
        })
    }

    pub fn resize(&mut self, width: u32, height: u32) {
        if width == 0 || height == 0 {
            return;
        }
        self.config.width = width;
        self.config.height = height;
        self.surface.configure(&self.gpu.device, &self.config);
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
        .get_texture_format_features(crate::render::renderer::DEPTH_FORMAT)
        .flags;
    if color.sample_count_supported(4) && depth.sample_count_supported(4) {
        4
    } else {
        1
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
                if g.software && self.options.render_scale.is_none() {
                    // Half resolution while animating: about 4× fewer pixels to shade.
                    self.model.view.render_scale = 0.5;
                }
                self.title = title;
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
                    // Input wakes a resting app: it draws (and steps, if a new throw asks).
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
