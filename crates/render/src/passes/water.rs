//! The water pass: η goes up as an R32Float texture (one texel per column) whenever the grid has
//! stepped; a preparation pass turns it into slopes (`shaders/water_prep.wgsl`); the surface is a
//! *projected grid* (Johanson 2004) — a mesh fixed in screen space whose vertices the vertex shader
//! casts onto the water plane and displaces by η there (`shaders/water.wgsl`) — so it reaches the
//! horizon and spends its vertices where the camera looks.

use wgpu::util::DeviceExt;

use super::{projected_grid_size, Viewport, GRID_SPACING, PREP_FORMAT};
use super::{PipelineDesc, Shared};
use crate::mesh::grid_indices;
use crate::scene::WaterView;

/// GPU resources of one water grid size.
struct GridTextures {
    /// Grid columns (nx, ny) and the texel stride (1 unless the grid exceeds the texture limit).
    grid: (usize, usize),
    stride: usize,
    tex_size: (u32, u32),
    eta_tex: wgpu::Texture,
    prep_view: wgpu::TextureView,
    prep_input: wgpu::BindGroup,
    surface_bind: wgpu::BindGroup,
    revision: Option<u64>,
    rect: [f32; 4],
}

/// The projected grid's triangles (vertex positions come from the vertex index).
struct ProjectedGrid {
    size: (u32, u32),
    indices: wgpu::Buffer,
    count: u32,
}

pub struct WaterPass {
    prep: wgpu::RenderPipeline,
    surface: wgpu::RenderPipeline,
    eta_layout: wgpu::BindGroupLayout,
    /// A flat 1×1 prepared texture for scenes without a grid (the surface still binds one).
    flat_bind: wgpu::BindGroup,
    max_texture: u32,
    textures: Option<GridTextures>,
    grid: Option<ProjectedGrid>,
    grid_spacing: f32,
    scratch: Vec<f32>,
    /// The scene of the last `prepare` had a grid.
    has_grid: bool,
}

impl WaterPass {
    pub fn new(device: &wgpu::Device, queue: &wgpu::Queue, shared: &Shared) -> Self {
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
        let prep_layout = shared.layout(
            device,
            "prep",
            &[Some(&shared.globals_layout), Some(&eta_layout)],
        );
        let surface_layout = shared.layout(
            device,
            "water",
            &[Some(&shared.globals_layout), Some(&shared.texture_layout)],
        );
        let prep_sh = shared.shader(
            device,
            "water_prep",
            include_str!("../../shaders/water_prep.wgsl"),
        );
        let water_sh = shared.shader(device, "water", include_str!("../../shaders/water.wgsl"));
        let prep_targets = [Some(wgpu::ColorTargetState {
            format: PREP_FORMAT,
            blend: None,
            write_mask: wgpu::ColorWrites::ALL,
        })];
        let prep = shared.pipeline(
            device,
            PipelineDesc {
                label: "water_prep",
                layout: &prep_layout,
                module: &prep_sh,
                vs: "vs_prep",
                fs: "fs_prep",
                buffers: &[],
                cull: None,
                depth: None,
                targets: &prep_targets,
                samples: 1,
            },
        );
        let surface = shared.pipeline(
            device,
            PipelineDesc {
                label: "water",
                layout: &surface_layout,
                module: &water_sh,
                vs: "vs_water",
                fs: "fs_water",
                buffers: &[],
                cull: None,
                depth: shared.depth(true, wgpu::CompareFunction::GreaterEqual),
                targets: &shared.color_target(false),
                samples: shared.sample_count,
            },
        );
        let flat = device.create_texture_with_data(
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
        let flat_view = flat.create_view(&wgpu::TextureViewDescriptor::default());
        Self {
            prep,
            surface,
            eta_layout,
            flat_bind: shared.texture_bind(device, &flat_view),
            max_texture: device.limits().max_texture_dimension_2d.max(1),
            textures: None,
            grid: None,
            grid_spacing: GRID_SPACING,
            scratch: Vec::new(),
            has_grid: false,
        }
    }

    /// Pixels between the projected grid's vertices (smaller shows finer displacement).
    pub fn set_grid_spacing(&mut self, pixels: f32) {
        if pixels.is_finite() {
            self.grid_spacing = pixels.clamp(2.0, 200.0);
        }
    }

    /// The projected grid's size (vertices across, down) for the last viewport.
    pub fn grid_size(&self) -> (u32, u32) {
        self.grid.as_ref().map_or((2, 2), |g| g.size)
    }

    /// The grid's rectangle (x0, y0, width, height in m), when the scene has one.
    pub fn rect(&self) -> Option<[f32; 4]> {
        self.textures
            .as_ref()
            .filter(|_| self.has_grid)
            .map(|t| t.rect)
    }

    /// Sizes the projected grid for `vp` and (re)creates the water textures for the grid's size.
    /// Call [`WaterPass::upload`] after the globals are written.
    pub fn prepare(
        &mut self,
        device: &wgpu::Device,
        shared: &Shared,
        water: Option<&WaterView>,
        vp: Viewport,
    ) {
        self.ensure_grid(device, vp);
        self.has_grid = false;
        let Some(wv) = water else {
            return;
        };
        if wv.nx < 2 || wv.ny < 2 || wv.heights.len() != wv.nx * wv.ny {
            return;
        }
        if self
            .textures
            .as_ref()
            .is_none_or(|w| w.grid != (wv.nx, wv.ny))
        {
            self.textures = Some(self.make_textures(device, shared, wv.nx, wv.ny));
        }
        if let Some(t) = self.textures.as_mut() {
            t.rect = [
                wv.origin[0] as f32,
                wv.origin[1] as f32,
                (wv.nx as f64 * wv.cell) as f32,
                (wv.ny as f64 * wv.cell) as f32,
            ];
            self.has_grid = true;
        }
    }

    /// Uploads η when it changed and records the preparation pass (slopes on the GPU).
    pub fn upload(
        &mut self,
        queue: &wgpu::Queue,
        encoder: &mut wgpu::CommandEncoder,
        shared: &Shared,
        water: Option<&WaterView>,
    ) {
        let (Some(wv), true) = (water, self.has_grid) else {
            return;
        };
        let Some(w) = self.textures.as_mut() else {
            return;
        };
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
        pass.set_bind_group(0, &shared.globals_bind, &[]);
        pass.set_bind_group(1, &w.prep_input, &[]);
        pass.draw(0..3, 0..1);
    }

    /// Draws the surface unless the horizon lies below the view (`horizon_ndc_y` ≤ −1.5).
    pub fn draw(&self, pass: &mut wgpu::RenderPass<'_>, horizon_ndc_y: f32) {
        let Some(grid) = &self.grid else {
            return;
        };
        if horizon_ndc_y <= -1.5 {
            return;
        }
        let bind = match &self.textures {
            Some(t) if self.has_grid => &t.surface_bind,
            _ => &self.flat_bind,
        };
        pass.set_pipeline(&self.surface);
        pass.set_bind_group(1, bind, &[]);
        pass.set_index_buffer(grid.indices.slice(..), wgpu::IndexFormat::Uint32);
        pass.draw_indexed(0..grid.count, 0, 0..1);
    }

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

    fn make_textures(
        &self,
        device: &wgpu::Device,
        shared: &Shared,
        nx: usize,
        ny: usize,
    ) -> GridTextures {
        let max = self.max_texture as usize;
        let stride = nx.max(ny).div_ceil(max).max(1);
        let tw = nx.div_ceil(stride) as u32;
        let th = ny.div_ceil(stride) as u32;
        let texture = |label: &str, format, usage| {
            device.create_texture(&wgpu::TextureDescriptor {
                label: Some(label),
                size: wgpu::Extent3d {
                    width: tw,
                    height: th,
                    depth_or_array_layers: 1,
                },
                mip_level_count: 1,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D2,
                format,
                usage,
                view_formats: &[],
            })
        };
        let eta_tex = texture(
            "eta",
            wgpu::TextureFormat::R32Float,
            wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
        );
        let prep_tex = texture(
            "water_prep",
            PREP_FORMAT,
            wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::RENDER_ATTACHMENT,
        );
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
        GridTextures {
            grid: (nx, ny),
            stride,
            tex_size: (tw, th),
            eta_tex,
            surface_bind: shared.texture_bind(device, &prep_view),
            prep_view,
            prep_input,
            revision: None,
            rect: [0.0; 4],
        }
    }
}
