//! Finding a GPU: the wgpu instance, adapter, device and queue, with one clear message naming what
//! was tried and how to fix it when there is no adapter (never a panic).
//!
//! Backends follow `WGPU_BACKEND` (`vulkan`, `gl`, …) when it is set; otherwise every backend wgpu
//! was built with. Without a GPU, Mesa's software rasterisers work: llvmpipe through GL/EGL, and
//! lavapipe through Vulkan once `mesa-vulkan-drivers` is installed.

use super::RenderError;

/// An adapter with its device and queue.
pub struct Gpu {
    pub instance: wgpu::Instance,
    pub adapter: wgpu::Adapter,
    pub device: wgpu::Device,
    pub queue: wgpu::Queue,
}

impl Gpu {
    /// A device without a window (offscreen rendering).
    pub fn headless() -> Result<Self, RenderError> {
        let instance =
            wgpu::Instance::new(wgpu::InstanceDescriptor::new_without_display_handle_from_env());
        let adapter = request_adapter(&instance, None)?;
        let (device, queue) = request_device(&adapter)?;
        Ok(Self {
            instance,
            adapter,
            device,
            queue,
        })
    }

    /// One line naming the adapter: name, backend, device type.
    pub fn describe(&self) -> String {
        describe_adapter(&self.adapter)
    }
}

/// "llvmpipe (LLVM 15.0.6, 256 bits) — Vulkan, Cpu".
pub fn describe_adapter(adapter: &wgpu::Adapter) -> String {
    let info = adapter.get_info();
    format!("{} — {:?}, {:?}", info.name, info.backend, info.device_type)
}

/// The backends this process will try (from `WGPU_BACKEND`, or all).
pub fn backends_tried() -> wgpu::Backends {
    wgpu::Backends::from_env().unwrap_or(wgpu::Backends::all())
}

fn backend_names(b: wgpu::Backends) -> String {
    let mut names = Vec::new();
    for (flag, name) in [
        (wgpu::Backends::VULKAN, "Vulkan"),
        (wgpu::Backends::GL, "GL/EGL"),
        (wgpu::Backends::METAL, "Metal"),
        (wgpu::Backends::DX12, "DirectX 12"),
        (wgpu::Backends::BROWSER_WEBGPU, "WebGPU"),
    ] {
        if b.contains(flag) {
            names.push(name);
        }
    }
    if names.is_empty() {
        "no backend at all (WGPU_BACKEND is set but names none)".to_owned()
    } else {
        names.join(", ")
    }
}

/// The error for "no adapter": what was tried, and how to fix it.
pub fn no_adapter_error(detail: &str) -> RenderError {
    let tried = backend_names(backends_tried());
    RenderError::NoAdapter {
        tried: format!("{tried}; {detail}"),
    }
}

/// Requests an adapter (compatible with `surface` when given): the preferred one first, then the
/// fallback (software) adapter.
pub fn request_adapter(
    instance: &wgpu::Instance,
    surface: Option<&wgpu::Surface<'_>>,
) -> Result<wgpu::Adapter, RenderError> {
    let mut last = String::from("no adapter found");
    for fallback in [false, true] {
        let options = wgpu::RequestAdapterOptions {
            power_preference: wgpu::PowerPreference::from_env()
                .unwrap_or(wgpu::PowerPreference::HighPerformance),
            force_fallback_adapter: fallback,
            compatible_surface: surface,
            apply_limit_buckets: false,
        };
        match pollster::block_on(instance.request_adapter(&options)) {
            Ok(adapter) => return Ok(adapter),
            Err(e) => last = e.to_string(),
        }
    }
    Err(no_adapter_error(&format!(
        "asked for a high-performance adapter, then the fallback one; wgpu said: {last}"
    )))
}

/// Requests a device with the adapter's texture size limits (large water grids) and otherwise
/// downlevel defaults, so GL-only software adapters qualify.
pub fn request_device(adapter: &wgpu::Adapter) -> Result<(wgpu::Device, wgpu::Queue), RenderError> {
    let limits = wgpu::Limits::downlevel_defaults().using_resolution(adapter.limits());
    let desc = wgpu::DeviceDescriptor {
        label: Some("stoneskip"),
        required_features: wgpu::Features::empty(),
        required_limits: limits,
        experimental_features: wgpu::ExperimentalFeatures::disabled(),
        memory_hints: wgpu::MemoryHints::Performance,
        trace: wgpu::Trace::Off,
    };
    pollster::block_on(adapter.request_device(&desc)).map_err(|e| RenderError::Device {
        adapter: describe_adapter(adapter),
        message: e.to_string(),
    })
}
