//! Choosing a graphics adapter and opening a device, without a window.
//!
//! Backends come from `WGPU_BACKEND` (e.g. `vulkan`, `gl`; wgpu's own parsing); without it
//! Vulkan is tried first, then GL through EGL. `WGPU_ADAPTER_NAME` picks an adapter by a part of
//! its name. When no adapter is found, a software ("fallback") adapter is asked for; when there
//! is none either, [`RenderError::NoAdapter`] says what to install.

use super::error::RenderError;

/// A device ready to render, and what it runs on.
pub struct GpuContext {
    /// The device.
    pub device: wgpu::Device,
    /// Its queue.
    pub queue: wgpu::Queue,
    /// The adapter behind it.
    pub info: wgpu::AdapterInfo,
    /// Largest 2D texture side it allows.
    pub max_texture_side: u32,
}

/// One line about an adapter: name, backend, type and driver.
pub fn describe_adapter(info: &wgpu::AdapterInfo) -> String {
    let driver = [info.driver.as_str(), info.driver_info.as_str()]
        .iter()
        .filter(|s| !s.is_empty())
        .copied()
        .collect::<Vec<_>>()
        .join(" ");
    format!(
        "{} ({:?}, {:?}{})",
        info.name,
        info.backend,
        info.device_type,
        if driver.is_empty() {
            String::new()
        } else {
            format!(", {driver}")
        }
    )
}

impl GpuContext {
    /// Opens a device on the best available adapter (see the module documentation).
    pub fn new_headless() -> Result<Self, RenderError> {
        pollster::block_on(Self::open())
    }

    async fn open() -> Result<Self, RenderError> {
        // Without WGPU_BACKEND: Vulkan first (lavapipe on machines without a GPU), then GL
        // (llvmpipe through EGL), so that a working Vulkan never wakes EGL's display probing.
        let attempts = match wgpu::Backends::from_env() {
            Some(b) => vec![b],
            None => vec![wgpu::Backends::VULKAN, wgpu::Backends::GL],
        };
        let mut tried = Vec::new();
        let mut last = None;
        let mut found = None;
        for backends in attempts {
            let mut desc = wgpu::InstanceDescriptor::new_without_display_handle();
            desc.backends = backends;
            let instance = wgpu::Instance::new(desc);
            tried.push(format!("{backends:?}"));
            match Self::pick(&instance, backends).await {
                Ok(a) => {
                    found = Some(a);
                    break;
                }
                Err(e) => last = Some(e),
            }
        }
        let adapter = match (found, last) {
            (Some(a), _) => a,
            (None, Some(RenderError::NoAdapter { hint, .. })) => {
                return Err(RenderError::NoAdapter {
                    backends: tried.join(", then "),
                    hint,
                })
            }
            (None, Some(e)) => return Err(e),
            (None, None) => unreachable!("at least one attempt"),
        };
        let info = adapter.get_info();
        let limits = wgpu::Limits::downlevel_defaults().using_resolution(adapter.limits());
        let (device, queue) = adapter
            .request_device(&wgpu::DeviceDescriptor {
                label: Some("prehensile renderer"),
                required_features: wgpu::Features::empty(),
                required_limits: limits.clone(),
                ..Default::default()
            })
            .await
            .map_err(|cause| RenderError::Device {
                adapter: info.name.clone(),
                cause,
            })?;
        Ok(Self {
            device,
            queue,
            info,
            max_texture_side: limits.max_texture_dimension_2d,
        })
    }

    async fn pick(
        instance: &wgpu::Instance,
        backends: wgpu::Backends,
    ) -> Result<wgpu::Adapter, RenderError> {
        if let Ok(wanted) = std::env::var("WGPU_ADAPTER_NAME") {
            let wanted = wanted.to_lowercase();
            let adapters = instance.enumerate_adapters(backends).await;
            let names: Vec<String> = adapters.iter().map(|a| a.get_info().name).collect();
            return adapters
                .into_iter()
                .find(|a| a.get_info().name.to_lowercase().contains(&wanted))
                .ok_or_else(|| RenderError::NoAdapter {
                    backends: format!("{backends:?}"),
                    hint: format!(
                        "WGPU_ADAPTER_NAME=\"{wanted}\" matches none of [{}]",
                        names.join(", ")
                    ),
                });
        }
        let mut last_error = String::new();
        for force_fallback_adapter in [false, true] {
            match instance
                .request_adapter(&wgpu::RequestAdapterOptions {
                    power_preference: wgpu::PowerPreference::from_env().unwrap_or_default(),
                    force_fallback_adapter,
                    compatible_surface: None,
                    ..Default::default()
                })
                .await
            {
                Ok(adapter) => return Ok(adapter),
                Err(e) => last_error = e.to_string(),
            }
        }
        Err(RenderError::NoAdapter {
            backends: format!("{backends:?}"),
            hint: last_error,
        })
    }
}
