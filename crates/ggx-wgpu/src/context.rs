//! Headless wgpu instance, adapter and device for compute work.

use std::fmt;

/// How to choose the adapter. Every field left `None` is taken from wgpu's environment
/// variables, and from wgpu's defaults when those are unset too:
///
/// * `WGPU_BACKEND`: comma-separated backends (`vulkan`, `metal`, `dx12`, `gl`); default all.
/// * `WGPU_ADAPTER_NAME`: case-insensitive substring of the adapter name (e.g. `llvmpipe`).
/// * `WGPU_POWER_PREF`: `low` or `high`; default none.
#[derive(Clone, Debug, Default)]
pub struct GpuOptions {
    /// Backends to search.
    pub backends: Option<wgpu::Backends>,
    /// Substring of the adapter name to require.
    pub adapter_name: Option<String>,
    /// Power preference used when no name is given.
    pub power_preference: Option<wgpu::PowerPreference>,
}

/// Why no GPU context could be made or a GPU command failed.
#[derive(Debug, thiserror::Error)]
pub enum GpuError {
    /// No adapter at all (no driver installed, or none for the requested backends).
    #[error(
        "no GPU adapter found for backends {backends:?}: {reason}. Without a GPU, install a software \
         Vulkan driver (Mesa's lavapipe): `apt-get install -y mesa-vulkan-drivers libvulkan1` on Debian \
         or Ubuntu, `dnf install mesa-vulkan-drivers` on Fedora; wgpu then finds the `llvmpipe` adapter"
    )]
    NoAdapter {
        /// Backends that were searched.
        backends: wgpu::Backends,
        /// What wgpu reported.
        reason: String,
    },
    /// Adapters exist but none matches the requested name.
    #[error("no adapter name contains {name:?} (WGPU_ADAPTER_NAME); available: {available:?}")]
    AdapterNotFound {
        /// The requested substring.
        name: String,
        /// Names of the adapters that were found.
        available: Vec<String>,
    },
    /// The adapter cannot run compute shaders (a downlevel GL adapter, for instance).
    #[error("adapter {0} does not support compute shaders")]
    NoCompute(String),
    /// The device request was refused.
    #[error("requesting a device failed: {0}")]
    RequestDevice(#[from] wgpu::RequestDeviceError),
    /// wgpu reported a validation or out-of-memory error (shader compilation included).
    #[error("wgpu error: {0}")]
    Wgpu(String),
    /// Waiting for the GPU failed.
    #[error("waiting for the GPU failed: {0}")]
    Poll(#[from] wgpu::PollError),
    /// Mapping a buffer for reading failed.
    #[error("mapping a buffer failed: {0}")]
    Map(#[from] wgpu::BufferAsyncError),
    /// A scene table or the image is larger than one buffer of this device may be.
    #[error(
        "the {what} need {}, more than this adapter's largest storage buffer ({}): render on the CPU \
         (--backend cpu), or lower the resolution or the scene's size", ggx_scene::format_bytes(*.bytes), ggx_scene::format_bytes(*.limit)
    )]
    TooLarge {
        /// Which buffer.
        what: &'static str,
        /// Bytes it needs.
        bytes: u64,
        /// The device's limit.
        limit: u64,
    },
    /// The render's own buffers (the film) could not be allocated.
    #[error(transparent)]
    Render(#[from] ggx_render::RenderError),
}

impl GpuError {
    /// True when the machine has no usable adapter, the case in which a test may skip.
    pub fn is_no_adapter(&self) -> bool {
        match self {
            GpuError::NoAdapter { .. } => true,
            GpuError::AdapterNotFound { available, .. } => available.is_empty(),
            _ => false,
        }
    }
}

/// A wgpu device and queue on the chosen adapter, ready for compute.
pub struct GpuContext {
    adapter: wgpu::Adapter,
    device: wgpu::Device,
    queue: wgpu::Queue,
}

impl fmt::Debug for GpuContext {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("GpuContext").field("adapter", &self.describe()).finish()
    }
}

impl GpuContext {
    /// Creates a headless instance, picks an adapter (see [`GpuOptions`]) and requests a device
    /// with WebGPU's downlevel limits, which cover the storage buffers compute work needs.
    pub fn new(options: GpuOptions) -> Result<GpuContext, GpuError> {
        pollster::block_on(Self::new_async(options))
    }

    async fn new_async(options: GpuOptions) -> Result<GpuContext, GpuError> {
        let mut desc = wgpu::InstanceDescriptor::new_without_display_handle_from_env();
        if let Some(backends) = options.backends {
            desc.backends = backends;
        }
        let backends = desc.backends;
        let instance = wgpu::Instance::new(desc);

        let name = options.adapter_name.or_else(|| std::env::var("WGPU_ADAPTER_NAME").ok());
        let adapter = match name {
            Some(name) => {
                let adapters = instance.enumerate_adapters(backends).await;
                let wanted = name.to_lowercase();
                let available: Vec<String> = adapters.iter().map(|a| a.get_info().name).collect();
                if available.is_empty() {
                    return Err(GpuError::NoAdapter { backends, reason: "no adapters enumerated".into() });
                }
                adapters
                    .into_iter()
                    .find(|a| a.get_info().name.to_lowercase().contains(&wanted))
                    .ok_or(GpuError::AdapterNotFound { name, available })?
            }
            None => {
                let power_preference =
                    options.power_preference.or_else(wgpu::PowerPreference::from_env).unwrap_or_default();
                let request = wgpu::RequestAdapterOptions { power_preference, ..Default::default() };
                instance
                    .request_adapter(&request)
                    .await
                    .map_err(|e| GpuError::NoAdapter { backends, reason: e.to_string() })?
            }
        };

        if !adapter.get_downlevel_capabilities().flags.contains(wgpu::DownlevelFlags::COMPUTE_SHADERS) {
            return Err(GpuError::NoCompute(adapter.get_info().name));
        }
        // The path tracer binds 8 storage buffers: WebGPU's default (8) where the adapter has it.
        let mut required_limits = wgpu::Limits::downlevel_defaults().using_alignment(adapter.limits());
        required_limits.max_storage_buffers_per_shader_stage = adapter
            .limits()
            .max_storage_buffers_per_shader_stage
            .min(wgpu::Limits::default().max_storage_buffers_per_shader_stage);
        // Large scenes and images: as large a buffer as the adapter allows.
        required_limits.max_storage_buffer_binding_size = adapter.limits().max_storage_buffer_binding_size;
        required_limits.max_buffer_size = adapter.limits().max_buffer_size;
        let (device, queue) = adapter
            .request_device(&wgpu::DeviceDescriptor {
                label: Some("ggx-wgpu"),
                required_features: wgpu::Features::empty(),
                required_limits,
                experimental_features: wgpu::ExperimentalFeatures::disabled(),
                memory_hints: wgpu::MemoryHints::Performance,
                trace: wgpu::Trace::Off,
            })
            .await?;
        Ok(GpuContext { adapter, device, queue })
    }

    /// Name, backend, device type and driver of the adapter.
    pub fn adapter_info(&self) -> wgpu::AdapterInfo {
        self.adapter.get_info()
    }

    /// One line for logs: `llvmpipe (LLVM 15.0.6, 256 bits) [Vulkan, Cpu, llvmpipe Mesa 22.3.6]`.
    pub fn describe(&self) -> String {
        let info = self.adapter_info();
        format!("{} [{:?}, {:?}, {} {}]", info.name, info.backend, info.device_type, info.driver, info.driver_info)
    }

    /// Whether the adapter renders in software on the CPU (Mesa's llvmpipe, WARP, SwiftShader).
    pub fn is_software(&self) -> bool {
        self.adapter_info().device_type == wgpu::DeviceType::Cpu
    }

    /// The adapter.
    pub fn adapter(&self) -> &wgpu::Adapter {
        &self.adapter
    }

    /// The device.
    pub fn device(&self) -> &wgpu::Device {
        &self.device
    }

    /// The queue.
    pub fn queue(&self) -> &wgpu::Queue {
        &self.queue
    }
}
