//! The scene renderer: draws a [`Scene`] into any colour target (the window's surface or an
//! offscreen texture) with wgpu — sky, water, stone, trail, contact markers, shadow and splash cues.
//!
//! The water is a height field: η goes up as an R32Float texture (one texel per column) whenever the
//! grid has stepped; a GPU pass turns it into slopes; the surface is a *projected grid* (Johanson
//! 2004) — a mesh fixed in screen space whose vertices the vertex shader casts onto the water plane
//! and displaces by η there — so it reaches the horizon, spends its vertices where the camera looks,
//! and never hands the rasteriser the giant near-camera triangles a world-space grid makes (which
//! software rasterisers pay dearly for). Normals come from the slopes per pixel.
//!
//! Each pass is its own struct in [`super::passes`] (new / prepare / draw); this one orders them and
//! owns the intermediate targets. It draws a plain [`Scene`], never a simulation.
//!
//! Per frame the CPU writes a few hundred bytes of uniforms and instance data, and copies η only
//! when the water has stepped; everything O(grid) beyond that copy runs on the GPU.

use glam::{Mat4, Vec3};

use super::passes::overlay::{stone_scale, OverlayPass};
use super::passes::sky::SkyPass;
use super::passes::stone::StonePass;
use super::passes::upscale::UpscalePass;
use super::passes::water::WaterPass;
pub use super::passes::{
    projected_grid_size, sun_direction, Viewport, DEPTH_FORMAT, FOG_DISTANCE, GRID_SPACING,
    PREP_FORMAT, SUN_AZIMUTH_DEG, SUN_ELEVATION_DEG,
};
use super::passes::{Globals, Shared};
use super::scene::Scene;

/// Settings fixed when the renderer is made.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RendererConfig {
    /// Format of the colour targets it will draw into.
    pub color_format: wgpu::TextureFormat,
    /// MSAA samples (1 or 4).
    pub sample_count: u32,
}

/// The intermediate targets of one scene size: depth, MSAA colour, the reduced-resolution colour.
struct Targets {
    size: (u32, u32),
    depth: wgpu::TextureView,
    msaa: Option<wgpu::TextureView>,
    /// The reduced-resolution colour target and its blit bind group (render scale < 1).
    low: Option<(wgpu::TextureView, wgpu::BindGroup)>,
}

/// Draws scenes: one struct per pass, run in order sky → water → flat decals → stone → trail,
/// guide lines and crowns → upscale. One per device; reusable across frames and target sizes.
pub struct SceneRenderer {
    config: RendererConfig,
    encode_srgb: bool,
    shared: Shared,
    sky: SkyPass,
    water: WaterPass,
    stone: StonePass,
    overlay: OverlayPass,
    upscale: UpscalePass,
    targets: Option<Targets>,
    render_scale: f32,
}

impl SceneRenderer {
    /// Builds the passes for targets of `config.color_format`.
    pub fn new(device: &wgpu::Device, queue: &wgpu::Queue, config: RendererConfig) -> Self {
        let sample_count = if config.sample_count >= 4 { 4 } else { 1 };
        let config = RendererConfig {
            sample_count,
            ..config
        };
        let shared = Shared::new(device, config.color_format, sample_count);
        Self {
            config,
            encode_srgb: !config.color_format.is_srgb(),
            sky: SkyPass::new(device, &shared),
            water: WaterPass::new(device, queue, &shared),
            stone: StonePass::new(device, &shared),
            overlay: OverlayPass::new(device, &shared),
            upscale: UpscalePass::new(device, &shared),
            shared,
            targets: None,
            render_scale: 1.0,
        }
    }

    pub fn config(&self) -> RendererConfig {
        self.config
    }

    /// Draws `scene` into `target` (a `target_size` texture of the configured format) inside
    /// `viewport`. With `clear`, the whole target is cleared to it first; without, the pixels outside
    /// the viewport are left as they are (the app redraws only its 3D view; not with MSAA, whose
    /// resolve writes the whole target). Records the water preparation pass and the scene pass
    /// into `encoder`; the caller submits.
    #[allow(clippy::too_many_arguments)]
    pub fn render(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        encoder: &mut wgpu::CommandEncoder,
        target: &wgpu::TextureView,
        target_size: (u32, u32),
        viewport: Viewport,
        scene: &Scene,
        clear: Option<wgpu::Color>,
    ) {
        let target_size = (target_size.0.max(1), target_size.1.max(1));
        // The caller's target is cleared or kept; internal targets are always cleared (the sky
        // covers them).
        let outer_load = clear.map_or(wgpu::LoadOp::Load, wgpu::LoadOp::Clear);
        let vp = clamp_viewport(viewport, target_size);
        let scaled = self.render_scale < 0.999;
        // The scene's own resolution: the view's, or a reduced one upscaled at the end.
        let (scene_size, scene_vp) = if scaled {
            let w = (vp.width * self.render_scale).round().max(1.0) as u32;
            let h = (vp.height * self.render_scale).round().max(1.0) as u32;
            ((w, h), Viewport::full(w, h))
        } else {
            (target_size, vp)
        };
        self.ensure_targets(device, scene_size, scaled);
        // Prepare: every pass uploads what changed.
        self.water
            .prepare(device, &self.shared, scene.water.as_ref(), scene_vp);
        self.stone.prepare(device, scene);
        self.overlay
            .prepare(device, queue, scene, scene_vp, self.render_scale);
        let globals = self.globals_for(scene, scene_vp);
        queue.write_buffer(&self.shared.globals, 0, bytemuck::bytes_of(&globals));
        self.water
            .upload(queue, encoder, &self.shared, scene.water.as_ref());

        let Some(targets) = self.targets.as_ref() else {
            return;
        };
        let scene_target = match &targets.low {
            Some((view, _)) => view,
            None => target,
        };
        let (color_view, resolve) = match &targets.msaa {
            Some(ms) => (ms, Some(scene_target)),
            None => (scene_target, None),
        };
        let scene_load = if targets.msaa.is_none() && targets.low.is_none() {
            outer_load
        } else {
            wgpu::LoadOp::Clear(wgpu::Color::BLACK)
        };
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("scene"),
            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                view: color_view,
                depth_slice: None,
                resolve_target: resolve,
                ops: wgpu::Operations {
                    load: scene_load,
                    store: wgpu::StoreOp::Store,
                },
            })],
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: &targets.depth,
                depth_ops: Some(wgpu::Operations {
                    load: wgpu::LoadOp::Clear(0.0),
                    store: wgpu::StoreOp::Discard,
                }),
                stencil_ops: None,
            }),
            timestamp_writes: None,
            occlusion_query_set: None,
            multiview_mask: None,
        });
        let svp = scene_vp;
        pass.set_viewport(svp.x, svp.y, svp.width, svp.height, 0.0, 1.0);
        pass.set_scissor_rect(
            svp.x as u32,
            svp.y as u32,
            svp.width as u32,
            svp.height as u32,
        );
        pass.set_bind_group(0, &self.shared.globals_bind, &[]);
        // Draw: in order, each pass records its own draws.
        self.sky.draw(&mut pass);
        self.water.draw(&mut pass, globals.options[3]);
        self.overlay.draw_under(&mut pass);
        self.stone.draw(&mut pass, scene);
        self.overlay.draw_over(&mut pass, scene);
        drop(pass);
        if let Some((_, bind)) = &targets.low {
            self.upscale
                .draw(encoder, bind, target, Some(vp), outer_load);
        }
    }

    /// Copies `source` (a texture of the configured format, bindable) over the whole of `target`
    /// by drawing: a write-only pass, which is what a window's swapchain image likes best.
    pub fn blit_to(
        &self,
        device: &wgpu::Device,
        encoder: &mut wgpu::CommandEncoder,
        source: &wgpu::TextureView,
        target: &wgpu::TextureView,
    ) {
        let bind = self.shared.texture_bind(device, source);
        self.upscale.draw(
            encoder,
            &bind,
            target,
            None,
            wgpu::LoadOp::Clear(wgpu::Color::BLACK),
        );
    }

    /// Draws the scene at `scale` × the view's resolution and upscales it (1 = full resolution;
    /// software rasterisers pay per pixel). Clamped to [0.25, 1].
    pub fn set_render_scale(&mut self, scale: f32) {
        if scale.is_finite() {
            self.render_scale = scale.clamp(0.25, 1.0);
        }
    }

    pub fn render_scale(&self) -> f32 {
        self.render_scale
    }

    /// Pixels between the projected water grid's vertices (default [`GRID_SPACING`]; smaller shows
    /// finer displacement, costs more triangles).
    pub fn set_grid_spacing(&mut self, pixels: f32) {
        self.water.set_grid_spacing(pixels);
    }

    fn ensure_targets(&mut self, device: &wgpu::Device, size: (u32, u32), low_res: bool) {
        if self
            .targets
            .as_ref()
            .is_some_and(|t| t.size == size && t.low.is_some() == low_res)
        {
            return;
        }
        let samples = self.config.sample_count;
        let texture = |label: &str, samples: u32, format, usage| {
            device
                .create_texture(&wgpu::TextureDescriptor {
                    label: Some(label),
                    size: wgpu::Extent3d {
                        width: size.0,
                        height: size.1,
                        depth_or_array_layers: 1,
                    },
                    mip_level_count: 1,
                    sample_count: samples,
                    dimension: wgpu::TextureDimension::D2,
                    format,
                    usage,
                    view_formats: &[],
                })
                .create_view(&wgpu::TextureViewDescriptor::default())
        };
        let attachment = wgpu::TextureUsages::RENDER_ATTACHMENT;
        let color = self.config.color_format;
        let depth = texture("depth", samples, DEPTH_FORMAT, attachment);
        let msaa = (samples > 1).then(|| texture("msaa", samples, color, attachment));
        let low = low_res.then(|| {
            let usage = attachment | wgpu::TextureUsages::TEXTURE_BINDING;
            let view = texture("scene_low_res", 1, color, usage);
            let bind = self.shared.texture_bind(device, &view);
            (view, bind)
        });
        self.targets = Some(Targets {
            size,
            depth,
            msaa,
            low,
        });
    }

    fn globals_for(&self, scene: &Scene, viewport: Viewport) -> Globals {
        let cam = &scene.camera;
        let clip_from_world = cam.clip_from_world(viewport.aspect());
        let world_from_clip = clip_from_world.inverse();
        // A far stone is drawn enlarged (never below MIN_STONE_PX across).
        let scale = stone_scale(scene, viewport.height / self.render_scale.max(0.25));
        let (world_from_stone, radius) = match &scene.stone {
            // Under vertical exaggeration the stone keeps its true shape at its exaggerated place.
            Some(s) => (
                Mat4::from_translation(s.position.as_vec3())
                    * Mat4::from_scale(Vec3::new(1.0, 1.0, 1.0 / cam.exaggeration.max(1e-3)))
                    * Mat4::from_scale_rotation_translation(
                        Vec3::splat(scale),
                        s.orientation.as_quat(),
                        Vec3::ZERO,
                    ),
                s.radius as f32 * scale,
            ),
            None => (Mat4::IDENTITY, 0.05),
        };
        let eye = cam.eye_world();
        let sun = sun_direction();
        let (rect, has_grid) = match self.water.rect() {
            Some(r) if scene.water.is_some() => (r, 1.0),
            _ => ([0.0; 4], 0.0),
        };
        let (gx, gy) = self.water.grid_size();
        let horizon = horizon_ndc_y(&clip_from_world, eye, cam.yaw);
        Globals {
            clip_from_world: clip_from_world.to_cols_array(),
            world_from_clip: world_from_clip.to_cols_array(),
            world_from_stone: world_from_stone.to_cols_array(),
            camera_pos: [eye.x, eye.y, eye.z, (scene.time % 10_000.0) as f32],
            sun_dir: [sun.x, sun.y, sun.z, 1.0],
            viewport: [
                viewport.width.max(1.0),
                viewport.height.max(1.0),
                1.0 / viewport.width.max(1.0),
                1.0 / viewport.height.max(1.0),
            ],
            water_rect: rect,
            water_mesh: [gx as f32, gy as f32, scene.style.ripple_gain, has_grid],
            options: [
                if self.encode_srgb { 1.0 } else { 0.0 },
                FOG_DISTANCE,
                radius,
                horizon,
            ],
        }
    }
}

/// NDC height of the horizon (the water plane's vanishing line) seen from `eye`; −2 when it lies
/// below the view, 2 when above. The camera never rolls, so the horizon is level on screen.
pub fn horizon_ndc_y(clip_from_world: &Mat4, eye: Vec3, yaw: f32) -> f32 {
    // A point far away at eye height, straight ahead horizontally, projects onto the horizon.
    let far = eye + Vec3::new(yaw.cos(), yaw.sin(), 0.0) * 1.0e6;
    let clip = *clip_from_world * far.extend(1.0);
    if clip.w <= 0.0 {
        return 2.0;
    }
    let y = clip.y / clip.w;
    if y.is_finite() {
        y.clamp(-2.0, 2.0)
    } else {
        2.0
    }
}

fn clamp_viewport(vp: Viewport, size: (u32, u32)) -> Viewport {
    let (w, h) = (size.0 as f32, size.1 as f32);
    let x = vp.x.clamp(0.0, w - 1.0).floor();
    let y = vp.y.clamp(0.0, h - 1.0).floor();
    Viewport {
        x,
        y,
        width: vp.width.clamp(1.0, w - x).floor().max(1.0),
        height: vp.height.clamp(1.0, h - y).floor().max(1.0),
    }
}
