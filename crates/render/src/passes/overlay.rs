//! The overlay pass (`shaders/overlay.wgsl`): the trajectory trail and the scene's guide lines —
//! screen-space ribbons of constant pixel width — and the decals: instanced rings, discs and crowns
//! for the contact markers, the stone's shadow and the splash cues. A stone smaller than
//! [`MIN_STONE_PX`] on screen gets a halo ring so it is never lost.

use bytemuck::{Pod, Zeroable};
use glam::Vec3;

use super::{sun_direction, Viewport};
use super::{InstanceBuffer, PipelineDesc, Shared};
use crate::scene::{Line, Scene, SPLASH_DURATION};

/// Smallest drawn stone diameter (pixels): a farther stone is enlarged to it and ringed by a halo.
pub const MIN_STONE_PX: f32 = 12.0;

#[repr(C)]
#[derive(Debug, Clone, Copy, Pod, Zeroable)]
struct LineInstance {
    a: [f32; 4],
    b: [f32; 4],
    color: [f32; 4],
}

#[repr(C)]
#[derive(Debug, Clone, Copy, Pod, Zeroable)]
struct DecalInstance {
    center: [f32; 4],
    shape: [f32; 4],
    fade: [f32; 4],
    color: [f32; 4],
}

/// Vertices of one decal instance: 64 segments × 2 triangles.
const DECAL_VERTICES: u32 = 64 * 6;

pub struct OverlayPass {
    lines_pipe: wgpu::RenderPipeline,
    /// Guide lines: over everything (no depth test), so a halo or a waterline is never hidden.
    guides_pipe: wgpu::RenderPipeline,
    decal_flat: wgpu::RenderPipeline,
    decal_solid: wgpu::RenderPipeline,
    trail_buf: InstanceBuffer,
    trail_key: Option<(usize, [u32; 3])>,
    trail_count: u32,
    guide_buf: InstanceBuffer,
    guide_count: u32,
    decal_buf: InstanceBuffer,
    n_flat: u32,
    n_solid: u32,
}

impl OverlayPass {
    pub fn new(device: &wgpu::Device, shared: &Shared) -> Self {
        let layout = shared.layout(device, "overlay", &[Some(&shared.globals_layout)]);
        let module = shared.shader(
            device,
            "overlay",
            include_str!("../../shaders/overlay.wgsl"),
        );
        let line_buffers = [Some(wgpu::VertexBufferLayout {
            array_stride: std::mem::size_of::<LineInstance>() as u64,
            step_mode: wgpu::VertexStepMode::Instance,
            attributes: &wgpu::vertex_attr_array![0 => Float32x4, 1 => Float32x4, 2 => Float32x4],
        })];
        let decal_buffers = [Some(wgpu::VertexBufferLayout {
            array_stride: std::mem::size_of::<DecalInstance>() as u64,
            step_mode: wgpu::VertexStepMode::Instance,
            attributes: &wgpu::vertex_attr_array![0 => Float32x4, 1 => Float32x4, 2 => Float32x4, 3 => Float32x4],
        })];
        use wgpu::CompareFunction as C;
        let make = |label, vs, buffers, compare| {
            shared.pipeline(
                device,
                PipelineDesc {
                    label,
                    layout: &layout,
                    module: &module,
                    vs,
                    fs: "fs_color",
                    buffers,
                    cull: None,
                    depth: shared.depth(false, compare),
                    targets: &shared.color_target(true),
                    samples: shared.sample_count,
                },
            )
        };
        Self {
            lines_pipe: make("trail", "vs_trail", &line_buffers[..], C::GreaterEqual),
            guides_pipe: make("guides", "vs_trail", &line_buffers[..], C::Always),
            decal_flat: make("decal_flat", "vs_decal", &decal_buffers[..], C::Always),
            decal_solid: make(
                "decal_solid",
                "vs_decal",
                &decal_buffers[..],
                C::GreaterEqual,
            ),
            trail_buf: InstanceBuffer::new(device, "trail", 64 * 1024),
            trail_key: None,
            trail_count: 0,
            guide_buf: InstanceBuffer::new(device, "guides", 16 * 1024),
            guide_count: 0,
            decal_buf: InstanceBuffer::new(device, "decals", 16 * 1024),
            n_flat: 0,
            n_solid: 0,
        }
    }

    /// Uploads the trail (when it grew), the guide lines and the decals. `render_scale` is the
    /// resolution factor of the scene target (line widths are given in full-resolution pixels).
    pub fn prepare(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        scene: &Scene,
        vp: Viewport,
        render_scale: f32,
    ) {
        self.prepare_trail(device, queue, scene, vp, render_scale);
        let mut guides: Vec<LineInstance> = Vec::new();
        let px = render_scale.max(0.25);
        for l in scene.lines.iter().chain(halo(scene, vp, px).iter()) {
            guides.push(LineInstance {
                a: [l.a.x, l.a.y, l.a.z, (l.width_px * px).max(1.0)],
                b: [l.b.x, l.b.y, l.b.z, (l.width_px * px).max(1.0)],
                color: l.color,
            });
        }
        self.guide_count = guides.len() as u32;
        self.guide_buf
            .write(device, queue, bytemuck::cast_slice(&guides));
        let (flat, solid) = decals_for(scene, vp.height);
        self.n_flat = flat.len() as u32;
        self.n_solid = solid.len() as u32;
        let mut all = flat;
        all.extend(solid);
        self.decal_buf
            .write(device, queue, bytemuck::cast_slice(&all));
    }

    /// Flat decals (on the water, under the stone).
    pub fn draw_under(&self, pass: &mut wgpu::RenderPass<'_>) {
        if self.n_flat > 0 {
            let size = std::mem::size_of::<DecalInstance>() as u64;
            pass.set_pipeline(&self.decal_flat);
            pass.set_vertex_buffer(0, self.decal_buf.buffer.slice(..self.n_flat as u64 * size));
            pass.draw(0..DECAL_VERTICES, 0..self.n_flat);
        }
    }

    /// The trail, the guide lines and the solid decals (over the stone).
    pub fn draw_over(&self, pass: &mut wgpu::RenderPass<'_>, scene: &Scene) {
        let line = std::mem::size_of::<LineInstance>() as u64;
        if self.trail_count > 0 && scene.style.show_trail {
            pass.set_pipeline(&self.lines_pipe);
            pass.set_vertex_buffer(
                0,
                self.trail_buf
                    .buffer
                    .slice(..self.trail_count as u64 * line),
            );
            pass.draw(0..6, 0..self.trail_count);
        }
        if self.guide_count > 0 {
            pass.set_pipeline(&self.guides_pipe);
            pass.set_vertex_buffer(
                0,
                self.guide_buf
                    .buffer
                    .slice(..self.guide_count as u64 * line),
            );
            pass.draw(0..6, 0..self.guide_count);
        }
        if self.n_solid > 0 {
            let size = std::mem::size_of::<DecalInstance>() as u64;
            let (a, b) = (
                self.n_flat as u64 * size,
                (self.n_flat + self.n_solid) as u64 * size,
            );
            pass.set_pipeline(&self.decal_solid);
            pass.set_vertex_buffer(0, self.decal_buf.buffer.slice(a..b));
            pass.draw(0..DECAL_VERTICES, 0..self.n_solid);
        }
    }

    fn prepare_trail(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        scene: &Scene,
        vp: Viewport,
        render_scale: f32,
    ) {
        let pts = scene.trail;
        // 1.5–3 pixels of the view (2–4 in the side view), never below one pixel.
        let base = if scene.side_view {
            2.5
        } else if scene.camera.exaggeration > 1.0 {
            2.0
        } else {
            1.5
        };
        let width =
            ((vp.height / render_scale.max(0.25)) / 400.0).clamp(base, 2.0 * base) * render_scale;
        let width = width.max(1.0);
        let last = pts.last().map_or([0; 3], |p| {
            [
                p.x.to_bits(),
                p.y.to_bits(),
                p.z.to_bits() ^ width.to_bits() ^ u32::from(scene.side_view),
            ]
        });
        let key = (pts.len(), last);
        if self.trail_key == Some(key) {
            return;
        }
        self.trail_key = Some(key);
        let n = pts.len().saturating_sub(1);
        let mut inst = Vec::with_capacity(n);
        for (i, w) in pts.windows(2).enumerate() {
            let (a, b) = (w[0], w[1]);
            // Older parts of the path fade a little so the newest flight reads first.
            let age = 1.0 - i as f32 / n.max(1) as f32;
            let color = if scene.side_view {
                crate::build::SIDE_TRAIL_COLOR
            } else {
                [1.0, 0.78, 0.25, 0.9 - 0.35 * age]
            };
            inst.push(LineInstance {
                a: [a.x, a.y, a.z, width],
                b: [b.x, b.y, b.z, width],
                color,
            });
        }
        self.trail_count = inst.len() as u32;
        self.trail_buf
            .write(device, queue, bytemuck::cast_slice(&inst));
    }
}

/// Pixels per metre at unit distance for a view `height_px` tall.
pub fn px_per_m_at_unit_distance(fov_y: f32, height_px: f32) -> f32 {
    height_px.max(1.0) / (2.0 * (0.5 * fov_y).tan())
}

/// Scale that makes the stone at least [`MIN_STONE_PX`] across in a view `height_px` tall.
pub fn stone_scale(scene: &Scene, height_px: f32) -> f32 {
    let Some(s) = &scene.stone else {
        return 1.0;
    };
    let cam = &scene.camera;
    let p = cam.to_view_space(s.position.as_vec3());
    let dist = p.distance(cam.eye()).max(1e-3);
    let r_px = s.radius as f32 * px_per_m_at_unit_distance(cam.fov_y, height_px) / dist;
    if r_px.is_finite() && r_px > 1e-6 {
        (0.5 * MIN_STONE_PX / r_px).max(1.0)
    } else {
        1.0
    }
}

/// A ring of 24 segments facing the eye around a stone drawn smaller than [`MIN_STONE_PX`] in
/// radius, or under the water's surface, so it is never lost from view.
fn halo(scene: &Scene, vp: Viewport, px: f32) -> Vec<Line> {
    let Some(s) = &scene.stone else {
        return Vec::new();
    };
    let cam = &scene.camera;
    let centre_v = cam.to_view_space(s.position.as_vec3());
    let dist = centre_v.distance(cam.eye()).max(1e-3);
    let ppm = px_per_m_at_unit_distance(cam.fov_y, vp.height / px) / dist;
    let r_px = s.radius as f32 * ppm;
    // Small on screen, or under the surface (sunk, or planing with its centre below z = 0).
    let hidden = s.position.z < 0.0;
    if !(r_px.is_finite() && (r_px < MIN_STONE_PX || hidden)) {
        return Vec::new();
    }
    // Built in view space (exaggerated), then mapped back to the world the shaders expect.
    let f = cam.forward();
    let right = f.cross(Vec3::Z).normalize_or(Vec3::X);
    let up = right.cross(f);
    let radius = (1.6 * MIN_STONE_PX).max(1.3 * r_px) / ppm;
    let n = 24;
    let pt = |k: usize| {
        let a = k as f32 / n as f32 * std::f32::consts::TAU;
        cam.from_view_space(centre_v + (right * a.cos() + up * a.sin()) * radius)
    };
    (0..n)
        .map(|k| Line {
            a: pt(k),
            b: pt(k + 1),
            width_px: 2.0,
            color: [1.0, 0.95, 0.6, 0.95],
        })
        .collect()
}

/// Decal instances: (flat ones on the water — markers, shadow, foam rings; solid ones — crowns).
fn decals_for(scene: &Scene, view_height_px: f32) -> (Vec<DecalInstance>, Vec<DecalInstance>) {
    let mut flat = Vec::new();
    // World size of one pixel at a distance: markers keep a legible size however far they are.
    let eye = scene.camera.eye();
    let px_per_m = px_per_m_at_unit_distance(scene.camera.fov_y, view_height_px);
    let pixel_at = |x: f32, y: f32| Vec3::new(x, y, 0.0).distance(eye) / px_per_m;
    let mut solid = Vec::new();
    let r = scene
        .stone
        .as_ref()
        .map_or(0.05, |s| s.radius as f32)
        .max(0.01);
    let lift = 0.003;
    if let Some(s) = &scene.stone {
        // Shadow: where the sun's ray through the centre of mass meets the water.
        let p = s.position.as_vec3();
        let sun = sun_direction();
        let h = p.z.max(0.0);
        let c = p - sun * (h / sun.z.max(0.1));
        let alpha = 0.5 * (-h / 0.8).exp();
        if alpha > 0.01 && p.z > -0.05 {
            flat.push(DecalInstance {
                center: [c.x, c.y, lift, 0.0],
                shape: [r * (1.15 + 0.3 * h), lift, lift, 0.0],
                fade: [1.0, 0.0, 0.0, 0.0],
                color: [0.0, 0.02, 0.03, alpha],
            });
        }
    }
    if scene.style.show_markers {
        for m in &scene.markers {
            let color = if m.open {
                [1.0, 1.0, 1.0, 0.9]
            } else if m.skip {
                [0.55, 1.0, 0.35, 0.85]
            } else {
                [1.0, 0.3, 0.2, 0.9]
            };
            let (x, y) = (m.x as f32, m.y as f32);
            let px = pixel_at(x, y);
            let inner = (r * 1.5).max(4.0 * px);
            let width = (0.012 + 0.15 * r).max(1.6 * px);
            flat.push(DecalInstance {
                center: [x, y, lift, inner],
                shape: [inner + width, lift, lift, 0.0],
                fade: [1.0, 1.0, 0.0, 0.0],
                color,
            });
        }
    }
    if scene.style.show_splashes {
        splash_decals(scene, r, lift, &mut flat, &mut solid);
    }
    (flat, solid)
}

fn splash_decals(
    scene: &Scene,
    r: f32,
    lift: f32,
    flat: &mut Vec<DecalInstance>,
    solid: &mut Vec<DecalInstance>,
) {
    for s in &scene.splashes {
        let age = s.age as f32;
        let life = (1.0 - age / SPLASH_DURATION as f32).clamp(0.0, 1.0);
        let (x, y) = (s.x as f32, s.y as f32);
        // Foam ring spreading from the touch point.
        let ring = r * (1.2 + 8.0 * age);
        flat.push(DecalInstance {
            center: [x, y, lift, ring],
            shape: [ring + r * (0.4 + 1.5 * age), lift, lift, 0.0],
            fade: [1.0, 0.0, 0.0, 0.0],
            color: [0.95, 0.98, 1.0, 0.8 * life * life],
        });
        // Crown of spray: rises and falls within 0.4 s.
        let phase = (age / 0.4).clamp(0.0, 1.0);
        let height =
            (0.012 * s.speed as f32).clamp(0.02, 0.2) * (std::f32::consts::PI * phase).sin();
        if height > 1e-3 {
            solid.push(DecalInstance {
                center: [x, y, 0.0, r * 0.9],
                shape: [r * (1.4 + 3.0 * age), 0.0, height, 0.0],
                fade: [0.75, 0.05, 0.0, 0.0],
                color: [0.88, 0.94, 1.0, life],
            });
        }
    }
}
