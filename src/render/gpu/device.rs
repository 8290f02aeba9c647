//! The adapter and the device: made once per [`Gpu`], on the backend the user chose.

use super::pipelines::create_pipelines;
use super::{Backend, Gpu, RenderError, State};
use std::sync::{Arc, Mutex};

/// The adapter `backend` offers (lavapipe on this project's machines), and the backend's name
/// for errors: what [`Gpu::new`] builds its device on.
fn request_adapter(backend: Backend) -> Result<(wgpu::Adapter, &'static str), RenderError> {
    let (backends, name) = match backend {
        Backend::Vulkan => (wgpu::Backends::VULKAN, "Vulkan"),
        Backend::Gl => (wgpu::Backends::GL, "GL"),
    };
    let mut desc = wgpu::InstanceDescriptor::new_without_display_handle();
    desc.backends = backends;
    desc.flags = wgpu::InstanceFlags::empty();
    let instance = wgpu::Instance::new(desc);
    let adapter = pollster::block_on(instance.request_adapter(&wgpu::RequestAdapterOptions {
        power_preference: wgpu::PowerPreference::HighPerformance,
        force_fallback_adapter: false,
        ..Default::default()
    }))
    .map_err(|e| RenderError::NoAdapter {
        backend: name,
        detail: e.to_string(),
    })?;
    Ok((adapter, name))
}

/// "name (backend, device type, driver)" of an adapter.
fn describe(info: &wgpu::AdapterInfo) -> String {
    format!(
        "{} ({:?}, {:?}, driver {} {})",
        info.name, info.backend, info.device_type, info.driver, info.driver_info
    )
}

/// [`Gpu::adapter_info`] of the adapter `backend` offers, without creating a device (tens of
/// milliseconds instead of a device and its pipelines): for benchmark tables of stages that
/// do not render, which still name the rasterizer of the machine they ran on (docs/benchmarks.md
/// "Benchmarks").
pub fn adapter_summary(backend: Backend) -> Result<String, RenderError> {
    request_adapter(backend).map(|(adapter, _)| describe(&adapter.get_info()))
}

impl Gpu {
    /// Creates instance, adapter, device and pipelines on `backend`.
    pub fn new(backend: Backend) -> Result<Gpu, RenderError> {
        let (adapter, name) = request_adapter(backend)?;
        let info = adapter.get_info();
        let limits = adapter.limits();
        let (device, queue) = pollster::block_on(adapter.request_device(&wgpu::DeviceDescriptor {
            label: Some("blockworld"),
            required_features: wgpu::Features::empty(),
            required_limits: wgpu::Limits::downlevel_webgl2_defaults().using_resolution(limits),
            experimental_features: wgpu::ExperimentalFeatures::disabled(),
            memory_hints: wgpu::MemoryHints::Performance,
            trace: wgpu::Trace::Off,
        }))
        .map_err(|e| RenderError::Gpu(format!("cannot create a {name} device: {e}")))?;
        let uncaptured = Arc::new(Mutex::new(Vec::new()));
        let sink = Arc::clone(&uncaptured);
        device.on_uncaptured_error(Arc::new(move |e: wgpu::Error| {
            tracing::error!("wgpu: {e}");
            if let Ok(mut v) = sink.lock() {
                v.push(e.to_string());
            }
        }));
        let scope = device.push_error_scope(wgpu::ErrorFilter::Validation);
        let (pipelines, uniforms, bind_group) = create_pipelines(&device);
        if let Some(e) = pollster::block_on(scope.pop()) {
            return Err(RenderError::Gpu(format!("creating pipelines: {e}")));
        }
        Ok(Gpu {
            max_texture_px: device.limits().max_texture_dimension_2d,
            max_buffer_bytes: device.limits().max_buffer_size,
            device,
            queue,
            info,
            pipelines,
            uniforms,
            bind_group,
            uncaptured,
            state: Mutex::new(State::default()),
        })
    }

    /// "name (backend, device type, driver)", for logs and benchmark tables.
    pub fn adapter_info(&self) -> String {
        describe(&self.info)
    }
}
