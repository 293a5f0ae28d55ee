//! The stone pass: the stone's mesh (body frame) placed by `world_from_stone` in the globals, lit by
//! the sun (`shaders/stone.wgsl`). The vertex buffer is rebuilt only when the mesh changes.

use wgpu::util::DeviceExt;

use super::{PipelineDesc, Shared};
use crate::mesh::{mesh_key, stone_vertices, StoneVertex};
use crate::scene::Scene;

struct StoneMesh {
    key: u64,
    vertices: wgpu::Buffer,
    count: u32,
}

pub struct StonePass {
    pipeline: wgpu::RenderPipeline,
    mesh: Option<StoneMesh>,
}

impl StonePass {
    pub fn new(device: &wgpu::Device, shared: &Shared) -> Self {
        let layout = shared.layout(device, "stone", &[Some(&shared.globals_layout)]);
        let module = shared.shader(device, "stone", include_str!("../../shaders/stone.wgsl"));
        let buffers = [Some(wgpu::VertexBufferLayout {
            array_stride: std::mem::size_of::<StoneVertex>() as u64,
            step_mode: wgpu::VertexStepMode::Vertex,
            attributes: &wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32x3],
        })];
        let pipeline = shared.pipeline(
            device,
            PipelineDesc {
                label: "stone",
                layout: &layout,
                module: &module,
                vs: "vs_stone",
                fs: "fs_stone",
                buffers: &buffers,
                cull: Some(wgpu::Face::Back),
                depth: shared.depth(true, wgpu::CompareFunction::GreaterEqual),
                targets: &shared.color_target(false),
                samples: shared.sample_count,
            },
        );
        Self {
            pipeline,
            mesh: None,
        }
    }

    /// Uploads the stone's mesh if it changed.
    pub fn prepare(&mut self, device: &wgpu::Device, scene: &Scene) {
        let Some(s) = &scene.stone else {
            return;
        };
        let key = mesh_key(s.mesh);
        if self.mesh.as_ref().is_some_and(|g| g.key == key) {
            return;
        }
        let verts = stone_vertices(s.mesh);
        if verts.is_empty() {
            self.mesh = None;
            return;
        }
        let vertices = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("stone"),
            contents: bytemuck::cast_slice(&verts),
            usage: wgpu::BufferUsages::VERTEX,
        });
        self.mesh = Some(StoneMesh {
            key,
            vertices,
            count: verts.len() as u32,
        });
    }

    pub fn draw(&self, pass: &mut wgpu::RenderPass<'_>, scene: &Scene) {
        if let (Some(m), true) = (&self.mesh, scene.stone.is_some()) {
            pass.set_pipeline(&self.pipeline);
            pass.set_vertex_buffer(0, m.vertices.slice(..));
            pass.draw(0..m.count, 0..1);
        }
    }
}
