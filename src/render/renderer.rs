//! The scene renderer: draws a [`Scene`] into any colour target (the window's surface or an
//! offscreen texture) with wgpu — sky, water (height field from an R32Float texture of η, normals
//! on the GPU), far water plane, stone, trail, contact markers, shadow and splash cues.
//!
//! Per frame the CPU writes a few hundred bytes of uniforms and instance data, and copies η into
//! its texture only when the water has stepped; everything O(grid) beyond that copy runs on the GPU.

use bytemuck::{Pod, Zeroable};
use glam::{Mat4, Vec3};
use wgpu::util::DeviceExt;

use super::mesh::{far_plane, grid_indices, mesh_key, stone_vertices, water_mesh_size, StoneVertex};
use super::scene::{Scene, SPLASH_DURATION};

/// Depth buffer format (reversed: cleared to 0, nearer is greater).
pub const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;
/// Format of the prepared water texture: (∂η/∂x, ∂η/∂y, η, 1), filterable everywhere.
pub const PREP_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;
/// Direction towards the sun: 25° above the horizon, ahead of the default camera and a little to
/// its left, so the glitter of the ripples lies in the default view.
pub const SUN_AZIMUTH_DEG: f32 = 18.0;
pub const SUN_ELEVATION_DEG: f32 = 24.0;
/// Haze distance (m).
pub const FOG_DISTANCE: f32 = 450.0;

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
    mesh: (u32, u32),
    indices: wgpu::Buffer,
    index_count: u32,
    revision: Option<u64>,
    rect: [f32; 4],
}

struct StoneGpu {
    key: u64,
    vertices: wgpu::Buffer,
    count: u32,
}

struct FarGpu {
    rect: [f32; 4],
    vertices: wgpu::Buffer,
    indices: wgpu::Buffer,
    count: u32,
}

struct Targets {
    size: (u32, u32),
    depth: wgpu::TextureView,
    msaa: Option<wgpu::TextureView>,
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
    water_grid: wgpu::RenderPipeline,
    water_far: wgpu::RenderPipeline,
    stone_pipe: wgpu::RenderPipeline,
    trail_pipe: wgpu::RenderPipeline,
    decal_flat: wgpu::RenderPipeline,
    decal_solid: wgpu::RenderPipeline,
    flat_water_bind: wgpu::BindGroup,
    water: Option<WaterGpu>,
    stone: Option<StoneGpu>,
    far: Option<FarGpu>,
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
    pub fn new(device: &wgpu::Device, config: RendererConfig) -> Self {
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
        let prep_sh = shader(device, "water_prep", include_str!("../../shaders/water_prep.wgsl"));
        let water_sh = shader(device, "water", include_str!("../../shaders/water.wgsl"));
        let stone_sh = shader(device, "stone", include_str!("../../shaders/stone.wgsl"));
        let overlay_sh = shader(device, "overlay", include_str!("../../shaders/overlay.wgsl"));

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
            buffers: &'a [wgpu::VertexBufferLayout<'a>],
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
        let water_grid = make(Desc {
            label: "water_grid",
            layout: &water_pl,
            module: &water_sh,
            vs: "vs_grid",
            fs: "fs_water",
            buffers: &[],
            cull: None,
            depth: depth(true, C::GreaterEqual),
            targets: &opaque,
            ms,
        });
        let far_buffers = [wgpu::VertexBufferLayout {
            array_stride: 12,
            step_mode: wgpu::VertexStepMode::Vertex,
            attributes: &wgpu::vertex_attr_array![0 => Float32x3],
        }];
        let water_far = make(Desc {
            label: "water_far",
            layout: &water_pl,
            module: &water_sh,
            vs: "vs_far",
            fs: "fs_water",
            buffers: &far_buffers,
            cull: None,
            depth: depth(true, C::GreaterEqual),
            targets: &opaque,
            ms,
        });
        let stone_buffers = [wgpu::VertexBufferLayout {
            array_stride: std::mem::size_of::<StoneVertex>() as u64,
            step_mode: wgpu::VertexStepMode::Vertex,
            attributes: &wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32x3],
        }];
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
        let trail_buffers = [wgpu::VertexBufferLayout {
            array_stride: std::mem::size_of::<TrailInstance>() as u64,
            step_mode: wgpu::VertexStepMode::Instance,
            attributes: &wgpu::vertex_attr_array![0 => Float32x4, 1 => Float32x4, 2 => Float32x4],
        }];
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
        let decal_buffers = [wgpu::VertexBufferLayout {
            array_stride: std::mem::size_of::<DecalInstance>() as u64,
            step_mode: wgpu::VertexStepMode::Instance,
            attributes: &wgpu::vertex_attr_array![0 => Float32x4, 1 => Float32x4, 2 => Float32x4, 3 => Float32x4],
        }];
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
        // A flat 1×1 prepared texture for scenes without a grid (the far plane still binds one).
        let flat_prep = device.create_texture_with_data(
            &queue_less_init(),
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
        let _ = flat_prep;
        unreachable!()
    }
}
