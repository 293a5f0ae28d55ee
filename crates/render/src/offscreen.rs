//! Offscreen rendering: draw a [`Scene`] into a texture and read it back as an 8-bit RGBA image
//! (rows padded to 256 bytes for the copy, unpadded on the way out). Works on software adapters.

use super::gpu::Gpu;
use super::renderer::{RendererConfig, SceneRenderer, Viewport};
use super::scene::Scene;
use super::RenderError;

/// Colour format of offscreen targets (the shaders encode sRGB themselves).
pub const OFFSCREEN_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8Unorm;
/// Largest offscreen picture side (pixels).
pub const MAX_SIDE: u32 = 8192;

/// A headless device with a scene renderer.
pub struct Offscreen {
    gpu: Gpu,
    renderer: SceneRenderer,
    target: Option<((u32, u32), wgpu::Texture)>,
}

impl Offscreen {
    /// Finds an adapter and builds the renderer (4× MSAA where the adapter offers it).
    pub fn new() -> Result<Self, RenderError> {
        Self::with_samples(4)
    }

    /// Like [`Offscreen::new`] with at most `max_samples` MSAA samples (1 turns it off).
    pub fn with_samples(max_samples: u32) -> Result<Self, RenderError> {
        let gpu = Gpu::headless()?;
        let flags = gpu
            .adapter
            .get_texture_format_features(OFFSCREEN_FORMAT)
            .flags;
        let depth_flags = gpu
            .adapter
            .get_texture_format_features(super::renderer::DEPTH_FORMAT)
            .flags;
        let samples = if max_samples >= 4
            && flags.sample_count_supported(4)
            && depth_flags.sample_count_supported(4)
        {
            4
        } else {
            1
        };
        let renderer = SceneRenderer::new(
            &gpu.device,
            &gpu.queue,
            RendererConfig {
                color_format: OFFSCREEN_FORMAT,
                sample_count: samples,
            },
        );
        Ok(Self {
            gpu,
            renderer,
            target: None,
        })
    }

    /// "llvmpipe (…) — Vulkan, Cpu".
    pub fn adapter(&self) -> String {
        self.gpu.describe()
    }

    pub fn gpu(&self) -> &Gpu {
        &self.gpu
    }

    /// The scene renderer (for its quality settings).
    pub fn renderer_mut(&mut self) -> &mut SceneRenderer {
        &mut self.renderer
    }

    /// Draws `scene` at `width` × `height` and returns the picture.
    pub fn render(
        &mut self,
        scene: &Scene,
        width: u32,
        height: u32,
    ) -> Result<image::RgbaImage, RenderError> {
        if width == 0 || height == 0 || width > MAX_SIDE || height > MAX_SIDE {
            return Err(RenderError::Size { width, height });
        }
        let size = (width, height);
        if self.target.as_ref().map(|(s, _)| *s) != Some(size) {
            let tex = self.gpu.device.create_texture(&wgpu::TextureDescriptor {
                label: Some("offscreen"),
                size: wgpu::Extent3d {
                    width,
                    height,
                    depth_or_array_layers: 1,
                },
                mip_level_count: 1,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D2,
                format: OFFSCREEN_FORMAT,
                usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
                view_formats: &[],
            });
            self.target = Some((size, tex));
        }
        let Some((_, tex)) = self.target.as_ref() else {
            return Err(RenderError::Readback("no target".to_owned()));
        };
        let view = tex.create_view(&wgpu::TextureViewDescriptor::default());
        let device = &self.gpu.device;
        let queue = &self.gpu.queue;
        let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
            label: Some("offscreen"),
        });
        self.renderer.render(
            device,
            queue,
            &mut encoder,
            &view,
            size,
            Viewport::full(width, height),
            scene,
            Some(wgpu::Color::BLACK),
        );
        queue.submit(Some(encoder.finish()));
        let pixels = read_rgba8(device, queue, tex, width, height)?;
        image::RgbaImage::from_raw(width, height, pixels)
            .ok_or_else(|| RenderError::Readback("pixel count does not match the size".to_owned()))
    }
}

/// Bytes per row of a texture-to-buffer copy: `width × 4` rounded up to 256.
pub fn padded_row_bytes(width: u32) -> u32 {
    let unpadded = width * 4;
    let align = wgpu::COPY_BYTES_PER_ROW_ALIGNMENT;
    unpadded.div_ceil(align) * align
}

/// Reads an RGBA8 texture back: copy into a buffer with 256-byte rows, map, strip the padding.
pub fn read_rgba8(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    texture: &wgpu::Texture,
    width: u32,
    height: u32,
) -> Result<Vec<u8>, RenderError> {
    let padded = padded_row_bytes(width);
    let buffer = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("readback"),
        size: padded as u64 * height as u64,
        usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
        mapped_at_creation: false,
    });
    let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
        label: Some("readback"),
    });
    encoder.copy_texture_to_buffer(
        wgpu::TexelCopyTextureInfo {
            texture,
            mip_level: 0,
            origin: wgpu::Origin3d::ZERO,
            aspect: wgpu::TextureAspect::All,
        },
        wgpu::TexelCopyBufferInfo {
            buffer: &buffer,
            layout: wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(padded),
                rows_per_image: Some(height),
            },
        },
        wgpu::Extent3d {
            width,
            height,
            depth_or_array_layers: 1,
        },
    );
    queue.submit(Some(encoder.finish()));
    let slice = buffer.slice(..);
    let (tx, rx) = std::sync::mpsc::channel();
    slice.map_async(wgpu::MapMode::Read, move |r| {
        let _ = tx.send(r);
    });
    device
        .poll(wgpu::PollType::wait_indefinitely())
        .map_err(|e| RenderError::Readback(e.to_string()))?;
    rx.recv()
        .map_err(|e| RenderError::Readback(e.to_string()))?
        .map_err(|e| RenderError::Readback(e.to_string()))?;
    let mut out = Vec::with_capacity((width * height * 4) as usize);
    {
        let view = slice
            .get_mapped_range()
            .map_err(|e| RenderError::Readback(e.to_string()))?;
        for row in view.chunks_exact(padded as usize) {
            out.extend_from_slice(&row[..(width * 4) as usize]);
        }
    }
    buffer.unmap();
    Ok(out)
}
