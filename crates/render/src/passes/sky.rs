//! The sky pass: one full-screen triangle coloured by the view ray (gradient, haze, sun), drawn
//! first at the far end of the depth range (`shaders/sky.wgsl`).

use super::{PipelineDesc, Shared};

pub struct SkyPass {
    pipeline: wgpu::RenderPipeline,
}

impl SkyPass {
    pub fn new(device: &wgpu::Device, shared: &Shared) -> Self {
        let layout = shared.layout(device, "sky", &[Some(&shared.globals_layout)]);
        let module = shared.shader(device, "sky", include_str!("../../shaders/sky.wgsl"));
        let pipeline = shared.pipeline(
            device,
            PipelineDesc {
                label: "sky",
                layout: &layout,
                module: &module,
                vs: "vs_sky",
                fs: "fs_sky",
                buffers: &[],
                cull: None,
                depth: shared.depth(false, wgpu::CompareFunction::Always),
                targets: &shared.color_target(false),
                samples: shared.sample_count,
            },
        );
        Self { pipeline }
    }

    /// Nothing to upload: the sky reads only the globals.
    pub fn draw(&self, pass: &mut wgpu::RenderPass<'_>) {
        pass.set_pipeline(&self.pipeline);
        pass.draw(0..3, 0..1);
    }
}
