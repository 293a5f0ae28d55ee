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
//! Per frame the CPU writes a few hundred bytes of uniforms and instance data, and copies η only
//! when the water has stepped; everything O(grid) beyond that copy runs on the GPU.

use bytemuck::{Pod, Zeroable};
use glam::{Mat4, Vec3};
use wgpu::util::DeviceExt;

use super::mesh::{grid_indices, mesh_key, stone_vertices, StoneVertex};
use super::scene::{Scene, SPLASH_DURATION};

/// Depth buffer format (reversed: cleared to 0, nearer is greater).
pub const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;
/// Format of the prepared water texture: (∂η/∂x, ∂η/∂y, η, 1), filterable everywhere.
pub const PREP_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;
/// Direction towards the sun: 25° above the horizon, ahead of the default camera and a little to
/// its left, so the glitter of the ripples lies in the default view.
pub const SUN_AZIMUTH_DEG: f32 = 32.0;
pub const SUN_ELEVATION_DEG: f32 = 24.0;
/// Haze distance (m).
pub const FOG_DISTANCE: f32 = 700.0;

/// A rectangle of the target in pixels (the 3D view's part of the window).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Viewport {
    pub x: f32,
    pub y: f32,
    pub width: f32,
    pub height: f32,
}

impl Viewport {
    pub fn full(width: u32, height: u32) -> Self {
        Self {
            x: 0.0,
            y: 0.0,
            width: width as f32,
            height: height as f32,
        }
    }

    pub fn aspect(&self) -> f32 {
        self.width / self.height.max(1.0)
    }
}

/// Unit vector towards the sun.
pub fn sun_direction() -> Vec3 {
    let (az, el) = (SUN_AZIMUTH_DEG.to_radians(), SUN_ELEVATION_DEG.to_radians());
    Vec3::new(el.cos() * az.cos(), el.cos() * az.sin(), el.sin())
}

#[repr(C)]
#[derive(Debug, Clone, Copy, Pod, Zeroable)]
struct Globals {
    clip_from_world: [f32; 16],
    world_from_clip: [f32; 16],
    world_from_stone: [f32; 16],
    camera_pos: [f32; 4],
    sun_dir: [f32; 4],
    viewport: [f32; 4],
    water_rect: [f32; 4],
    water_mesh: [f32; 4],
    options: [f32; 4],
}

#[repr(C)]
#[derive(Debug, Clone, Copy, Pod, Zeroable)]
struct TrailInstance {
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

/// GPU resources of one water grid size.
struct WaterGpu {
    /// Grid columns (nx, ny) and the texel stride (1 unless the grid exceeds the texture limit).
    grid: (usize, usize),
    stride: usize,
    tex_size: (u32, u32),
    eta_tex: wgpu::Texture,
    prep_view: wgpu::TextureView,
    prep_input: wgpu::BindGroup,
    water_bind: wgpu::BindGroup,
    revision: Option<u64>,
    rect: [f32; 4],
}

struct StoneGpu {
    key: u64,
    vertices: wgpu::Buffer,
    count: u32,
}

/// The projected grid's triangles (vertex positions come from the vertex index).
struct ProjectedGrid {
    size: (u32, u32),
    indices: wgpu::Buffer,
    count: u32,
}

struct Targets {
    size: (u32, u32),
    depth: wgpu::TextureView,
    msaa: Option<wgpu::TextureView>,
    /// The reduced-resolution colour target and its blit bind group (render scale < 1).
    low: Option<(wgpu::TextureView, wgpu::BindGroup)>,
}

/// A growable vertex buffer of instances.
struct InstanceBuffer {
    buffer: wgpu::Buffer,
    capacity: u64,
    label: &'static str,
}

impl InstanceBuffer {
    fn new(device: &wgpu::Device, label: &'static str, capacity: u64) -> Self {
        let buffer = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some(label),
            size: capacity.max(256),
            usage: wgpu::BufferUsages::VERTEX | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        Self {
            buffer,
            capacity: capacity.max(256),
            label,
        }
    }

    fn write(&mut self, device: &wgpu::Device, queue: &wgpu::Queue, bytes: &[u8]) {
        if bytes.is_empty() {
            return;
        }
        let need = bytes.len() as u64;
        if need > self.capacity {
            *self = Self::new(device, self.label, need.next_power_of_two());
        }
        queue.write_buffer(&self.buffer, 0, bytes);
    }
}

/// Settings fixed when the renderer is made.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RendererConfig {
    /// Format of the colour targets it will draw into.
    pub color_format: wgpu::TextureFormat,
    /// MSAA samples (1 or 4).
    pub sample_count: u32,
}

/// Draws scenes. One per device; reusable across frames and target sizes.
pub struct SceneRenderer {
    config: RendererConfig,
    encode_srgb: bool,
    max_texture: u32,
    globals: wgpu::Buffer,
    globals_bind: wgpu::BindGroup,
    eta_layout: wgpu::BindGroupLayout,
    water_layout: wgpu::BindGroupLayout,
    sampler: wgpu::Sampler,
    sky: wgpu::RenderPipeline,
    prep: wgpu::RenderPipeline,
    water_pipe: wgpu::RenderPipeline,
    stone_pipe: wgpu::RenderPipeline,
    trail_pipe: wgpu::RenderPipeline,
    decal_flat: wgpu::RenderPipeline,
    decal_solid: wgpu::RenderPipeline,
    flat_water_bind: wgpu::BindGroup,
    water: Option<WaterGpu>,
    stone: Option<StoneGpu>,
    grid: Option<ProjectedGrid>,
    grid_spacing: f32,
    render_scale: f32,
    blit: wgpu::RenderPipeline,
    blit_layout: wgpu::BindGroupLayout,
    targets: Option<Targets>,
    trail_buf: InstanceBuffer,
    trail_key: Option<(usize, [u32; 3])>,
    trail_count: u32,
    decal_buf: InstanceBuffer,
    scratch: Vec<f32>,
}

fn shader(device: &wgpu::Device, label: &str, body: &str) -> wgpu::ShaderModule {
    let source = format!("{}\n{}", include_str!("../../shaders/common.wgsl"), body);
    device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some(label),
        source: wgpu::ShaderSource::Wgsl(source.into()),
    })
}

impl SceneRenderer {
    /// Builds the pipelines for targets of `config.color_format`.
    pub fn new(device: &wgpu::Device, queue: &wgpu::Queue, config: RendererConfig) -> Self {
        let encode_srgb = !config.color_format.is_srgb();
        let sample_count = if config.sample_count >= 4 { 4 } else { 1 };
        let config = RendererConfig {
            sample_count,
            ..config
        };
        let globals = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("globals"),
            size: std::mem::size_of::<Globals>() as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let globals_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("globals"),
            entries: &[wgpu::BindGroupLayoutEntry {
                binding: 0,
                visibility: wgpu::ShaderStages::VERTEX_FRAGMENT,
                ty: wgpu::BindingType::Buffer {
                    ty: wgpu::BufferBindingType::Uniform,
                    has_dynamic_offset: false,
                    min_binding_size: None,
                },
                count: None,
            }],
        });
        let globals_bind = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("globals"),
            layout: &globals_layout,
            entries: &[wgpu::BindGroupEntry {
                binding: 0,
                resource: globals.as_entire_binding(),
            }],
        });
        let eta_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("eta"),
            entries: &[wgpu::BindGroupLayoutEntry {
                binding: 0,
                visibility: wgpu::ShaderStages::FRAGMENT,
                ty: wgpu::BindingType::Texture {
                    sample_type: wgpu::TextureSampleType::Float { filterable: false },
                    view_dimension: wgpu::TextureViewDimension::D2,
                    multisampled: false,
                },
                count: None,
            }],
        });
        let water_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("water"),
            entries: &[
                wgpu::BindGroupLayoutEntry {
                    binding: 0,
                    visibility: wgpu::ShaderStages::VERTEX_FRAGMENT,
                    ty: wgpu::BindingType::Texture {
                        sample_type: wgpu::TextureSampleType::Float { filterable: true },
                        view_dimension: wgpu::TextureViewDimension::D2,
                        multisampled: false,
                    },
                    count: None,
                },
                wgpu::BindGroupLayoutEntry {
                    binding: 1,
                    visibility: wgpu::ShaderStages::VERTEX_FRAGMENT,
                    ty: wgpu::BindingType::Sampler(wgpu::SamplerBindingType::Filtering),
                    count: None,
                },
            ],
        });
        let sampler = device.create_sampler(&wgpu::SamplerDescriptor {
            label: Some("water"),
            address_mode_u: wgpu::AddressMode::ClampToEdge,
            address_mode_v: wgpu::AddressMode::ClampToEdge,
            mag_filter: wgpu::FilterMode::Linear,
            min_filter: wgpu::FilterMode::Linear,
            ..Default::default()
        });
        let layout = |label: &str, groups: &[Option<&wgpu::BindGroupLayout>]| {
            device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: Some(label),
                bind_group_layouts: groups,
                immediate_size: 0,
            })
        };
        let scene_layout = layout("scene", &[Some(&globals_layout)]);
        let water_pl = layout("water", &[Some(&globals_layout), Some(&water_layout)]);
        let prep_pl = layout("prep", &[Some(&globals_layout), Some(&eta_layout)]);

        let sky_sh = shader(device, "sky", include_str!("../../shaders/sky.wgsl"));
        let prep_sh = shader(
            device,
            "water_prep",
            include_str!("../../shaders/water_prep.wgsl"),
        );
        let water_sh = shader(device, "water", include_str!("../../shaders/water.wgsl"));
        let stone_sh = shader(device, "stone", include_str!("../../shaders/stone.wgsl"));
        let overlay_sh = shader(
            device,
            "overlay",
            include_str!("../../shaders/overlay.wgsl"),
        );

        let ms = wgpu::MultisampleState {
            count: sample_count,
            mask: !0,
            alpha_to_coverage_enabled: false,
        };
        let depth = |write: bool, compare: wgpu::CompareFunction| {
            Some(wgpu::DepthStencilState {
                format: DEPTH_FORMAT,
                depth_write_enabled: Some(write),
                depth_compare: Some(compare),
                stencil: wgpu::StencilState::default(),
                bias: wgpu::DepthBiasState::default(),
            })
        };
        let opaque = [Some(wgpu::ColorTargetState {
            format: config.color_format,
            blend: None,
            write_mask: wgpu::ColorWrites::ALL,
        })];
        let blended = [Some(wgpu::ColorTargetState {
            format: config.color_format,
            blend: Some(wgpu::BlendState::ALPHA_BLENDING),
            write_mask: wgpu::ColorWrites::ALL,
        })];
        struct Desc<'a> {
            label: &'a str,
            layout: &'a wgpu::PipelineLayout,
            module: &'a wgpu::ShaderModule,
            vs: &'a str,
            fs: &'a str,
            buffers: &'a [Option<wgpu::VertexBufferLayout<'a>>],
            cull: Option<wgpu::Face>,
            depth: Option<wgpu::DepthStencilState>,
            targets: &'a [Option<wgpu::ColorTargetState>],
            ms: wgpu::MultisampleState,
        }
        let make = |d: Desc| {
            device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                label: Some(d.label),
                layout: Some(d.layout),
                vertex: wgpu::VertexState {
                    module: d.module,
                    entry_point: Some(d.vs),
                    compilation_options: Default::default(),
                    buffers: d.buffers,
                },
                primitive: wgpu::PrimitiveState {
                    topology: wgpu::PrimitiveTopology::TriangleList,
                    front_face: wgpu::FrontFace::Ccw,
                    cull_mode: d.cull,
                    ..Default::default()
                },
                depth_stencil: d.depth,
                multisample: d.ms,
                fragment: Some(wgpu::FragmentState {
                    module: d.module,
                    entry_point: Some(d.fs),
                    compilation_options: Default::default(),
                    targets: d.targets,
                }),
                multiview_mask: None,
                cache: None,
            })
        };
        use wgpu::CompareFunction as C;
        let sky = make(Desc {
            label: "sky",
            layout: &scene_layout,
            module: &sky_sh,
            vs: "vs_sky",
            fs: "fs_sky",
            buffers: &[],
            cull: None,
            depth: depth(false, C::Always),
            targets: &opaque,
            ms,
        });
        let prep_targets = [Some(wgpu::ColorTargetState {
            format: PREP_FORMAT,
            blend: None,
            write_mask: wgpu::ColorWrites::ALL,
        })];
        let prep = make(Desc {
            label: "water_prep",
            layout: &prep_pl,
            module: &prep_sh,
            vs: "vs_prep",
            fs: "fs_prep",
            buffers: &[],
            cull: None,
            depth: None,
            targets: &prep_targets,
            ms: wgpu::MultisampleState::default(),
        });
        let water_pipe = make(Desc {
            label: "water",
            layout: &water_pl,
            module: &water_sh,
            vs: "vs_water",
            fs: "fs_water",
            buffers: &[],
            cull: None,
            depth: depth(true, C::GreaterEqual),
            targets: &opaque,
            ms,
        });
        let stone_buffers = [Some(wgpu::VertexBufferLayout {
            array_stride: std::mem::size_of::<StoneVertex>() as u64,
            step_mode: wgpu::VertexStepMode::Vertex,
            attributes: &wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32x3],
        })];
        let stone_pipe = make(Desc {
            label: "stone",
            layout: &scene_layout,
            module: &stone_sh,
            vs: "vs_stone",
            fs: "fs_stone",
            buffers: &stone_buffers,
            cull: Some(wgpu::Face::Back),
            depth: depth(true, C::GreaterEqual),
            targets: &opaque,
            ms,
        });
        let trail_buffers = [Some(wgpu::VertexBufferLayout {
            array_stride: std::mem::size_of::<TrailInstance>() as u64,
            step_mode: wgpu::VertexStepMode::Instance,
            attributes: &wgpu::vertex_attr_array![0 => Float32x4, 1 => Float32x4, 2 => Float32x4],
        })];
        let trail_pipe = make(Desc {
            label: "trail",
            layout: &scene_layout,
            module: &overlay_sh,
            vs: "vs_trail",
            fs: "fs_color",
            buffers: &trail_buffers,
            cull: None,
            depth: depth(false, C::GreaterEqual),
            targets: &blended,
            ms,
        });
        let decal_buffers = [Some(wgpu::VertexBufferLayout {
            array_stride: std::mem::size_of::<DecalInstance>() as u64,
            step_mode: wgpu::VertexStepMode::Instance,
            attributes: &wgpu::vertex_attr_array![0 => Float32x4, 1 => Float32x4, 2 => Float32x4, 3 => Float32x4],
        })];
        let decal_flat = make(Desc {
            label: "decal_flat",
            layout: &scene_layout,
            module: &overlay_sh,
            vs: "vs_decal",
            fs: "fs_color",
            buffers: &decal_buffers,
            cull: None,
            depth: depth(false, C::Always),
            targets: &blended,
            ms,
        });
        let decal_solid = make(Desc {
            label: "decal_solid",
            layout: &scene_layout,
            module: &overlay_sh,
            vs: "vs_decal",
            fs: "fs_color",
            buffers: &decal_buffers,
            cull: None,
            depth: depth(false, C::GreaterEqual),
            targets: &blended,
            ms,
        });
        let blit_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("blit"),
            entries: &[
                wgpu::BindGroupLayoutEntry {
                    binding: 0,
                    visibility: wgpu::ShaderStages::FRAGMENT,
                    ty: wgpu::BindingType::Texture {
                        sample_type: wgpu::TextureSampleType::Float { filterable: true },
                        view_dimension: wgpu::TextureViewDimension::D2,
                        multisampled: false,
                    },
                    count: None,
                },
                wgpu::BindGroupLayoutEntry {
                    binding: 1,
                    visibility: wgpu::ShaderStages::FRAGMENT,
                    ty: wgpu::BindingType::Sampler(wgpu::SamplerBindingType::Filtering),
                    count: None,
                },
            ],
        });
        let blit_pl = layout("blit", &[Some(&blit_layout)]);
        let blit_sh = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("blit"),
            source: wgpu::ShaderSource::Wgsl(include_str!("../../shaders/blit.wgsl").into()),
        });
        let blit = make(Desc {
            label: "blit",
            layout: &blit_pl,
            module: &blit_sh,
            vs: "vs_blit",
            fs: "fs_blit",
            buffers: &[],
            cull: None,
            depth: None,
            targets: &opaque,
            ms: wgpu::MultisampleState::default(),
        });
        // A flat 1×1 prepared texture for scenes without a grid (the water still binds one).
        let flat_prep = device.create_texture_with_data(
            queue,
            &wgpu::TextureDescriptor {
                label: Some("flat_prep"),
                size: wgpu::Extent3d {
                    width: 1,
                    height: 1,
                    depth_or_array_layers: 1,
                },
                mip_level_count: 1,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D2,
                format: PREP_FORMAT,
                usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
                view_formats: &[],
            },
            wgpu::util::TextureDataOrder::LayerMajor,
            &[0u8; 8],
        );
        let flat_view = flat_prep.create_view(&wgpu::TextureViewDescriptor::default());
        let flat_water_bind = water_bind_group(device, &water_layout, &flat_view, &sampler);
        Self {
            config,
            encode_srgb,
            max_texture: device.limits().max_texture_dimension_2d.max(1),
            globals,
            globals_bind,
            eta_layout,
            water_layout,
            sampler,
            sky,
            prep,
            water_pipe,
            stone_pipe,
            trail_pipe,
            decal_flat,
            decal_solid,
            flat_water_bind,
            water: None,
            stone: None,
            grid: None,
            grid_spacing: GRID_SPACING,
            render_scale: 1.0,
            blit,
            blit_layout,
            targets: None,
            trail_buf: InstanceBuffer::new(device, "trail", 64 * 1024),
            trail_key: None,
            trail_count: 0,
            decal_buf: InstanceBuffer::new(device, "decals", 16 * 1024),
            scratch: Vec::new(),
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
        self.upload_water(device, queue, encoder, scene);
        self.upload_stone(device, scene);
        self.ensure_grid(device, scene_vp);
        let globals = self.globals_for(scene, scene_vp);
        queue.write_buffer(&self.globals, 0, bytemuck::bytes_of(&globals));
        self.upload_trail(device, queue, scene, scene_vp);
        let (flat_decals, solid_decals) = decals_for(scene, scene_vp.height);
        let n_flat = flat_decals.len() as u32;
        let n_solid = solid_decals.len() as u32;
        let mut all = flat_decals;
        all.extend(solid_decals);
        self.decal_buf
            .write(device, queue, bytemuck::cast_slice(&all));

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
        pass.set_bind_group(0, &self.globals_bind, &[]);

        pass.set_pipeline(&self.sky);
        pass.draw(0..3, 0..1);

        let water_bind = match &self.water {
            Some(w) if scene.water.is_some() => &w.water_bind,
            _ => &self.flat_water_bind,
        };
        // The horizon below the view: no water to draw.
        if let (Some(grid), true) = (&self.grid, globals.options[3] > -1.5) {
            pass.set_pipeline(&self.water_pipe);
            pass.set_bind_group(1, water_bind, &[]);
            pass.set_index_buffer(grid.indices.slice(..), wgpu::IndexFormat::Uint32);
            pass.draw_indexed(0..grid.count, 0, 0..1);
        }
        let decal_size = std::mem::size_of::<DecalInstance>() as u64;
        if n_flat > 0 {
            pass.set_pipeline(&self.decal_flat);
            pass.set_vertex_buffer(0, self.decal_buf.buffer.slice(..n_flat as u64 * decal_size));
            pass.draw(0..DECAL_VERTICES, 0..n_flat);
        }
        if let (Some(st), true) = (&self.stone, scene.stone.is_some()) {
            pass.set_pipeline(&self.stone_pipe);
            pass.set_vertex_buffer(0, st.vertices.slice(..));
            pass.draw(0..st.count, 0..1);
        }
        if self.trail_count > 0 && scene.style.show_trail {
            let size = std::mem::size_of::<TrailInstance>() as u64;
            pass.set_pipeline(&self.trail_pipe);
            pass.set_vertex_buffer(
                0,
                self.trail_buf
                    .buffer
                    .slice(..self.trail_count as u64 * size),
            );
            pass.draw(0..6, 0..self.trail_count);
        }
        if n_solid > 0 {
            pass.set_pipeline(&self.decal_solid);
            pass.set_vertex_buffer(
                0,
                self.decal_buf
                    .buffer
                    .slice(n_flat as u64 * decal_size..(n_flat + n_solid) as u64 * decal_size),
            );
            pass.draw(0..DECAL_VERTICES, 0..n_solid);
        }
        drop(pass);
        if let Some((_, bind)) = &targets.low {
            // Upscale into the view's rectangle.
            let mut blit = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("upscale"),
                color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                    view: target,
                    depth_slice: None,
                    resolve_target: None,
                    ops: wgpu::Operations {
                        load: outer_load,
                        store: wgpu::StoreOp::Store,
                    },
                })],
                depth_stencil_attachment: None,
                timestamp_writes: None,
                occlusion_query_set: None,
                multiview_mask: None,
            });
            blit.set_viewport(vp.x, vp.y, vp.width, vp.height, 0.0, 1.0);
            blit.set_scissor_rect(vp.x as u32, vp.y as u32, vp.width as u32, vp.height as u32);
            blit.set_pipeline(&self.blit);
            blit.set_bind_group(0, bind, &[]);
            blit.draw(0..3, 0..1);
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
        let bind = water_bind_group(device, &self.blit_layout, source, &self.sampler);
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("blit"),
            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                view: target,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Clear(wgpu::Color::BLACK),
                    store: wgpu::StoreOp::Store,
                },
            })],
            depth_stencil_attachment: None,
            timestamp_writes: None,
            occlusion_query_set: None,
            multiview_mask: None,
        });
        pass.set_pipeline(&self.blit);
        pass.set_bind_group(0, &bind, &[]);
        pass.draw(0..3, 0..1);
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

    fn ensure_targets(&mut self, device: &wgpu::Device, size: (u32, u32), low_res: bool) {
        if self
            .targets
            .as_ref()
            .is_some_and(|t| t.size == size && t.low.is_some() == low_res)
        {
            return;
        }
        let extent = wgpu::Extent3d {
            width: size.0,
            height: size.1,
            depth_or_array_layers: 1,
        };
        let samples = self.config.sample_count;
        let depth = device.create_texture(&wgpu::TextureDescriptor {
            label: Some("depth"),
            size: extent,
            mip_level_count: 1,
            sample_count: samples,
            dimension: wgpu::TextureDimension::D2,
            format: DEPTH_FORMAT,
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT,
            view_formats: &[],
        });
        let msaa = (samples > 1).then(|| {
            device
                .create_texture(&wgpu::TextureDescriptor {
                    label: Some("msaa"),
                    size: extent,
                    mip_level_count: 1,
                    sample_count: samples,
                    dimension: wgpu::TextureDimension::D2,
                    format: self.config.color_format,
                    usage: wgpu::TextureUsages::RENDER_ATTACHMENT,
                    view_formats: &[],
                })
                .create_view(&wgpu::TextureViewDescriptor::default())
        });
        let low = low_res.then(|| {
            let view = device
                .create_texture(&wgpu::TextureDescriptor {
                    label: Some("scene_low_res"),
                    size: extent,
                    mip_level_count: 1,
                    sample_count: 1,
                    dimension: wgpu::TextureDimension::D2,
                    format: self.config.color_format,
                    usage: wgpu::TextureUsages::RENDER_ATTACHMENT
                        | wgpu::TextureUsages::TEXTURE_BINDING,
                    view_formats: &[],
                })
                .create_view(&wgpu::TextureViewDescriptor::default());
            let bind = water_bind_group(device, &self.blit_layout, &view, &self.sampler);
            (view, bind)
        });
        self.targets = Some(Targets {
            size,
            depth: depth.create_view(&wgpu::TextureViewDescriptor::default()),
            msaa,
            low,
        });
    }

    fn globals_for(&self, scene: &Scene, viewport: Viewport) -> Globals {
        let cam = &scene.camera;
        let clip_from_world = cam.clip_from_world(viewport.aspect());
        let world_from_clip = clip_from_world.inverse();
        let (world_from_stone, radius) = match &scene.stone {
            Some(s) => (
                Mat4::from_rotation_translation(s.orientation.as_quat(), s.position.as_vec3()),
                s.radius as f32,
            ),
            None => (Mat4::IDENTITY, 0.05),
        };
        let eye = cam.eye();
        let sun = sun_direction();
        let (rect, has_grid) = match (&self.water, &scene.water) {
            (Some(w), Some(_)) => (w.rect, 1.0),
            _ => ([0.0; 4], 0.0),
        };
        let (gx, gy) = self.grid.as_ref().map_or((2, 2), |g| g.size);
        let mesh = [gx as f32, gy as f32, scene.style.ripple_gain, has_grid];
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
            water_mesh: mesh,
            options: [
                if self.encode_srgb { 1.0 } else { 0.0 },
                FOG_DISTANCE,
                radius,
                horizon,
            ],
        }
    }

    /// (Re)creates the water textures for the grid's size and uploads η when it changed, then
    /// records the preparation pass (gradients on the GPU).
    fn upload_water(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        encoder: &mut wgpu::CommandEncoder,
        scene: &Scene,
    ) {
        let Some(wv) = &scene.water else {
            return;
        };
        if wv.nx < 2 || wv.ny < 2 || wv.heights.len() != wv.nx * wv.ny {
            return;
        }
        let rect = [
            wv.origin[0] as f32,
            wv.origin[1] as f32,
            (wv.nx as f64 * wv.cell) as f32,
            (wv.ny as f64 * wv.cell) as f32,
        ];
        let rebuild = self.water.as_ref().is_none_or(|w| w.grid != (wv.nx, wv.ny));
        if rebuild {
            self.water = Some(self.make_water(device, wv.nx, wv.ny));
        }
        let Some(w) = self.water.as_mut() else {
            return;
        };
        w.rect = rect;
        if w.revision == Some(wv.revision) {
            return;
        }
        w.revision = Some(wv.revision);
        let (tw, th) = w.tex_size;
        let data: &[f32] = if w.stride == 1 {
            wv.heights
        } else {
            // A grid larger than the texture limit: every stride-th column (rare; huge lakes).
            self.scratch.clear();
            for ty in 0..th as usize {
                let iy = (ty * w.stride).min(wv.ny - 1);
                for tx in 0..tw as usize {
                    let ix = (tx * w.stride).min(wv.nx - 1);
                    self.scratch.push(wv.heights[iy * wv.nx + ix]);
                }
            }
            &self.scratch
        };
        queue.write_texture(
            wgpu::TexelCopyTextureInfo {
                texture: &w.eta_tex,
                mip_level: 0,
                origin: wgpu::Origin3d::ZERO,
                aspect: wgpu::TextureAspect::All,
            },
            bytemuck::cast_slice(data),
            wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(4 * tw),
                rows_per_image: Some(th),
            },
            wgpu::Extent3d {
                width: tw,
                height: th,
                depth_or_array_layers: 1,
            },
        );
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("water_prep"),
            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                view: &w.prep_view,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT),
                    store: wgpu::StoreOp::Store,
                },
            })],
            depth_stencil_attachment: None,
            timestamp_writes: None,
            occlusion_query_set: None,
            multiview_mask: None,
        });
        pass.set_pipeline(&self.prep);
        pass.set_bind_group(0, &self.globals_bind, &[]);
        pass.set_bind_group(1, &w.prep_input, &[]);
        pass.draw(0..3, 0..1);
    }

    fn make_water(&self, device: &wgpu::Device, nx: usize, ny: usize) -> WaterGpu {
        let max = self.max_texture as usize;
        let stride = nx.max(ny).div_ceil(max).max(1);
        let tw = nx.div_ceil(stride) as u32;
        let th = ny.div_ceil(stride) as u32;
        let extent = wgpu::Extent3d {
            width: tw,
            height: th,
            depth_or_array_layers: 1,
        };
        let eta_tex = device.create_texture(&wgpu::TextureDescriptor {
            label: Some("eta"),
            size: extent,
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: wgpu::TextureFormat::R32Float,
            usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
            view_formats: &[],
        });
        let prep_tex = device.create_texture(&wgpu::TextureDescriptor {
            label: Some("water_prep"),
            size: extent,
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: PREP_FORMAT,
            usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::RENDER_ATTACHMENT,
            view_formats: &[],
        });
        let eta_view = eta_tex.create_view(&wgpu::TextureViewDescriptor::default());
        let prep_view = prep_tex.create_view(&wgpu::TextureViewDescriptor::default());
        let prep_input = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("eta"),
            layout: &self.eta_layout,
            entries: &[wgpu::BindGroupEntry {
                binding: 0,
                resource: wgpu::BindingResource::TextureView(&eta_view),
            }],
        });
        let water_bind = water_bind_group(device, &self.water_layout, &prep_view, &self.sampler);
        WaterGpu {
            grid: (nx, ny),
            stride,
            tex_size: (tw, th),
            eta_tex,
            prep_view,
            prep_input,
            water_bind,
            revision: None,
            rect: [0.0; 4],
        }
    }

    fn upload_stone(&mut self, device: &wgpu::Device, scene: &Scene) {
        let Some(s) = &scene.stone else {
            return;
        };
        let key = mesh_key(s.mesh);
        if self.stone.as_ref().is_some_and(|g| g.key == key) {
            return;
        }
        let verts = stone_vertices(s.mesh);
        if verts.is_empty() {
            self.stone = None;
            return;
        }
        let vertices = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("stone"),
            contents: bytemuck::cast_slice(&verts),
            usage: wgpu::BufferUsages::VERTEX,
        });
        self.stone = Some(StoneGpu {
            key,
            vertices,
            count: verts.len() as u32,
        });
    }

    /// Pixels between the projected water grid's vertices (default [`GRID_SPACING`]; smaller shows
    /// finer displacement, costs more triangles).
    pub fn set_grid_spacing(&mut self, pixels: f32) {
        if pixels.is_finite() {
            self.grid_spacing = pixels.clamp(2.0, 200.0);
        }
    }

    /// The projected grid for a viewport: about one vertex every `grid_spacing` pixels.
    fn ensure_grid(&mut self, device: &wgpu::Device, vp: Viewport) {
        let size = projected_grid_size(vp.width, vp.height, self.grid_spacing);
        if self.grid.as_ref().is_some_and(|g| g.size == size) {
            return;
        }
        let idx = grid_indices(size.0, size.1);
        let indices = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("projected_grid"),
            contents: bytemuck::cast_slice(&idx),
            usage: wgpu::BufferUsages::INDEX,
        });
        self.grid = Some(ProjectedGrid {
            size,
            indices,
            count: idx.len() as u32,
        });
    }

    fn upload_trail(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        scene: &Scene,
        vp: Viewport,
    ) {
        let pts = scene.trail;
        // 1.5–3 pixels of the view, never below one pixel of a reduced-resolution scene.
        let width =
            ((vp.height / self.render_scale.max(0.25)) / 400.0).clamp(1.5, 3.0) * self.render_scale;
        let width = width.max(1.0);
        let last = pts.last().map_or([0; 3], |p| {
            [
                p.x.to_bits(),
                p.y.to_bits(),
                p.z.to_bits() ^ width.to_bits(),
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
            let alpha = 0.9 - 0.35 * age;
            inst.push(TrailInstance {
                a: [a.x, a.y, a.z, width],
                b: [b.x, b.y, b.z, width],
                color: [1.0, 0.78, 0.25, alpha],
            });
        }
        self.trail_count = inst.len() as u32;
        self.trail_buf
            .write(device, queue, bytemuck::cast_slice(&inst));
    }
}

fn water_bind_group(
    device: &wgpu::Device,
    layout: &wgpu::BindGroupLayout,
    view: &wgpu::TextureView,
    sampler: &wgpu::Sampler,
) -> wgpu::BindGroup {
    device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("water"),
        layout,
        entries: &[
            wgpu::BindGroupEntry {
                binding: 0,
                resource: wgpu::BindingResource::TextureView(view),
            },
            wgpu::BindGroupEntry {
                binding: 1,
                resource: wgpu::BindingResource::Sampler(sampler),
            },
        ],
    })
}

/// Pixels between neighbouring vertices of the projected water grid.
pub const GRID_SPACING: f32 = 16.0;

/// Vertices (across, down) of the projected grid for a `width` × `height` viewport, `spacing`
/// pixels apart.
pub fn projected_grid_size(width: f32, height: f32, spacing: f32) -> (u32, u32) {
    let n = |px: f32| ((px / spacing.max(1.0)).ceil() as u32).clamp(8, 800) + 1;
    (n(width), n(height))
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

/// Decal instances: (flat ones on the water — markers, shadow, foam rings; solid ones — crowns).
fn decals_for(scene: &Scene, view_height_px: f32) -> (Vec<DecalInstance>, Vec<DecalInstance>) {
    let mut flat = Vec::new();
    // World size of one pixel at a distance: markers keep a legible size however far they are.
    let eye = scene.camera.eye();
    let px_per_m = view_height_px.max(1.0) / (2.0 * (0.5 * scene.camera.fov_y).tan());
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
    (flat, solid)
}
