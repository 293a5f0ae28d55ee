//! The scene renderer's passes, one struct each, in the shape of wgpu's examples: `new` builds the
//! pipeline and its resources once, `prepare` uploads what the frame needs (only what changed),
//! `draw` records into a render pass. They share the per-frame uniform block ([`Globals`]), a
//! pipeline builder ([`Shared`]), and the target's formats, viewport, sun and water grid spacing
//! (the renderer, which drives them, re-exports these).

pub mod overlay;
pub mod sky;
pub mod stone;
pub mod upscale;
pub mod water;

use bytemuck::{Pod, Zeroable};

use glam::Vec3;

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

/// Pixels between neighbouring vertices of the projected water grid.
pub const GRID_SPACING: f32 = 16.0;

/// Vertices (across, down) of the projected grid for a `width` × `height` viewport, `spacing`
/// pixels apart.
pub fn projected_grid_size(width: f32, height: f32, spacing: f32) -> (u32, u32) {
    let n = |px: f32| ((px / spacing.max(1.0)).ceil() as u32).clamp(8, 800) + 1;
    (n(width), n(height))
}

/// The per-frame uniform block every shader sees (`shaders/common.wgsl`).
#[repr(C)]
#[derive(Debug, Clone, Copy, Pod, Zeroable)]
pub struct Globals {
    pub clip_from_world: [f32; 16],
    pub world_from_clip: [f32; 16],
    pub world_from_stone: [f32; 16],
    /// Eye (true world, m) and the simulated time (s).
    pub camera_pos: [f32; 4],
    pub sun_dir: [f32; 4],
    pub viewport: [f32; 4],
    pub water_rect: [f32; 4],
    pub water_mesh: [f32; 4],
    /// sRGB encoding on, fog distance, stone radius, horizon NDC y.
    pub options: [f32; 4],
}

/// What every pass's pipeline has in common: the device's formats and the globals' bind group.
pub struct Shared {
    pub color_format: wgpu::TextureFormat,
    pub sample_count: u32,
    pub globals: wgpu::Buffer,
    pub globals_layout: wgpu::BindGroupLayout,
    pub globals_bind: wgpu::BindGroup,
    /// Linear clamp-to-edge sampler (water texture, upscaling).
    pub sampler: wgpu::Sampler,
    /// One texture + one sampler, fragment and vertex visible (water surface, blits).
    pub texture_layout: wgpu::BindGroupLayout,
}

/// The parts of a render pipeline that differ between passes.
pub struct PipelineDesc<'a> {
    pub label: &'a str,
    pub layout: &'a wgpu::PipelineLayout,
    pub module: &'a wgpu::ShaderModule,
    pub vs: &'a str,
    pub fs: &'a str,
    pub buffers: &'a [Option<wgpu::VertexBufferLayout<'a>>],
    pub cull: Option<wgpu::Face>,
    pub depth: Option<wgpu::DepthStencilState>,
    pub targets: &'a [Option<wgpu::ColorTargetState>],
    pub samples: u32,
}

impl Shared {
    pub fn new(
        device: &wgpu::Device,
        color_format: wgpu::TextureFormat,
        sample_count: u32,
    ) -> Self {
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
        let sampler = device.create_sampler(&wgpu::SamplerDescriptor {
            label: Some("linear_clamp"),
            address_mode_u: wgpu::AddressMode::ClampToEdge,
            address_mode_v: wgpu::AddressMode::ClampToEdge,
            mag_filter: wgpu::FilterMode::Linear,
            min_filter: wgpu::FilterMode::Linear,
            ..Default::default()
        });
        let texture_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("texture_sampler"),
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
        Self {
            color_format,
            sample_count,
            globals,
            globals_layout,
            globals_bind,
            sampler,
            texture_layout,
        }
    }

    /// A pipeline layout of `groups`.
    pub fn layout(
        &self,
        device: &wgpu::Device,
        label: &str,
        groups: &[Option<&wgpu::BindGroupLayout>],
    ) -> wgpu::PipelineLayout {
        device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some(label),
            bind_group_layouts: groups,
            immediate_size: 0,
        })
    }

    /// A shader module: `shaders/common.wgsl` followed by `body`.
    pub fn shader(&self, device: &wgpu::Device, label: &str, body: &str) -> wgpu::ShaderModule {
        let source = format!("{}\n{}", include_str!("../../shaders/common.wgsl"), body);
        device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some(label),
            source: wgpu::ShaderSource::Wgsl(source.into()),
        })
    }

    /// The colour target of the scene: opaque or alpha-blended.
    pub fn color_target(&self, blend: bool) -> [Option<wgpu::ColorTargetState>; 1] {
        [Some(wgpu::ColorTargetState {
            format: self.color_format,
            blend: blend.then_some(wgpu::BlendState::ALPHA_BLENDING),
            write_mask: wgpu::ColorWrites::ALL,
        })]
    }

    /// Reversed depth (nearer is greater).
    pub fn depth(
        &self,
        write: bool,
        compare: wgpu::CompareFunction,
    ) -> Option<wgpu::DepthStencilState> {
        Some(wgpu::DepthStencilState {
            format: DEPTH_FORMAT,
            depth_write_enabled: Some(write),
            depth_compare: Some(compare),
            stencil: wgpu::StencilState::default(),
            bias: wgpu::DepthBiasState::default(),
        })
    }

    pub fn pipeline(&self, device: &wgpu::Device, d: PipelineDesc) -> wgpu::RenderPipeline {
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
            multisample: wgpu::MultisampleState {
                count: d.samples,
                mask: !0,
                alpha_to_coverage_enabled: false,
            },
            fragment: Some(wgpu::FragmentState {
                module: d.module,
                entry_point: Some(d.fs),
                compilation_options: Default::default(),
                targets: d.targets,
            }),
            multiview_mask: None,
            cache: None,
        })
    }

    /// A bind group of `view` and the shared sampler in [`Shared::texture_layout`].
    pub fn texture_bind(&self, device: &wgpu::Device, view: &wgpu::TextureView) -> wgpu::BindGroup {
        device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("texture_sampler"),
            layout: &self.texture_layout,
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: wgpu::BindingResource::TextureView(view),
                },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: wgpu::BindingResource::Sampler(&self.sampler),
                },
            ],
        })
    }
}

/// A growable vertex buffer of instances.
pub struct InstanceBuffer {
    pub buffer: wgpu::Buffer,
    capacity: u64,
    label: &'static str,
}

impl InstanceBuffer {
    pub fn new(device: &wgpu::Device, label: &'static str, capacity: u64) -> Self {
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

    pub fn write(&mut self, device: &wgpu::Device, queue: &wgpu::Queue, bytes: &[u8]) {
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
