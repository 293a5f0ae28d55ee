//! The upscaling pass: the scene drawn at a reduced resolution (the render-scale setting for
//! software rasterisers) is filtered bilinearly into the 3D view's rectangle; the same pipeline
//! copies a finished frame into a window's swapchain image (`shaders/blit.wgsl`).

use super::Viewport;
use super::{PipelineDesc, Shared};

pub struct UpscalePass {
    pipeline: wgpu::RenderPipeline,
}

impl UpscalePass {
    pub fn new(device: &wgpu::Device, shared: &Shared) -> Self {
        let layout = shared.layout(device, "blit", &[Some(&shared.texture_layout)]);
        let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("blit"),
            source: wgpu::ShaderSource::Wgsl(include_str!("../../shaders/blit.wgsl").into()),
        });
        let pipeline = shared.pipeline(
            device,
            PipelineDesc {
                label: "blit",
                layout: &layout,
                module: &module,
                vs: "vs_blit",
                fs: "fs_blit",
                buffers: &[],
                cull: None,
                depth: None,
                targets: &shared.color_target(false),
                samples: 1,
            },
        );
        Self { pipeline }
    }

    /// Draws `source` (bound by [`Shared::texture_bind`]) over `viewport` of `target`; `load`
    /// clears or keeps the rest of the target.
    pub fn draw(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        source: &wgpu::BindGroup,
        target: &wgpu::TextureView,
        viewport: Option<Viewport>,
        load: wgpu::LoadOp<wgpu::Color>,
    ) {
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("upscale"),
            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                view: target,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations {
                    load,
                    store: wgpu::StoreOp::Store,
                },
            })],
            depth_stencil_attachment: None,
            timestamp_writes: None,
            occlusion_query_set: None,
            multiview_mask: None,
        });
        if let Some(vp) = viewport {
            pass.set_viewport(vp.x, vp.y, vp.width, vp.height, 0.0, 1.0);
            pass.set_scissor_rect(vp.x as u32, vp.y as u32, vp.width as u32, vp.height as u32);
        }
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, source, &[]);
        pass.draw(0..3, 0..1);
    }
}
