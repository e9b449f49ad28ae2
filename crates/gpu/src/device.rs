//! A headless device: the best adapter wgpu can see, opened with that adapter's own limits.
//!
//! SPPM's photon and hit-point arrays run to hundreds of MiB, so the WebGPU default limits
//! (128 MiB bindings, 256 MiB buffers) would refuse scenes the hardware can hold: we ask for
//! everything the adapter offers and check each buffer against it (see [`crate::limits`]).

use crate::GpuError;
use crate::scene_upload::SceneStorage;

/// Timestamp features we take when the adapter has them (per-kernel timings in `bench`).
const TIMESTAMP_FEATURES: wgpu::Features = wgpu::Features::TIMESTAMP_QUERY
    .union(wgpu::Features::TIMESTAMP_QUERY_INSIDE_ENCODERS)
    .union(wgpu::Features::TIMESTAMP_QUERY_INSIDE_PASSES);

/// Environment variable naming an adapter when the caller gives no filter (wgpu's own name).
const ADAPTER_NAME_ENV: &str = "WGPU_ADAPTER_NAME";

/// An open device and its queue, with what was learned about the adapter.
#[derive(Clone, Debug)]
pub struct GpuContext {
    /// The logical device, created with [`GpuContext::limits`] and [`GpuContext::features`].
    pub device: wgpu::Device,
    /// Its queue.
    pub queue: wgpu::Queue,
    /// The adapter the device was opened on.
    pub adapter: wgpu::Adapter,
    /// Name, backend, type and driver of the adapter.
    pub info: wgpu::AdapterInfo,
    /// The limits the device was created with (the adapter's own).
    pub limits: wgpu::Limits,
    /// The features enabled on the device.
    pub features: wgpu::Features,
    /// How scenes uploaded to it store nodes, triangles and threaded records, and so which kernels run
    /// ([`SceneStorage::preferred`] for the adapter unless changed before the upload).
    pub scene_storage: SceneStorage,
}

impl GpuContext {
    /// Opens the best adapter whose name contains `adapter_filter` (case-insensitive); with no
    /// filter, `WGPU_ADAPTER_NAME` if set, else any adapter. Prefers discrete, then integrated,
    /// virtual, CPU, other. Backends are Vulkan, Metal and DX12 unless `WGPU_BACKEND` names
    /// others; instance flags follow wgpu's environment variables (`WGPU_VALIDATION`, ...).
    pub fn new(adapter_filter: Option<&str>) -> Result<GpuContext, GpuError> {
        pollster::block_on(Self::new_async(adapter_filter))
    }

    async fn new_async(adapter_filter: Option<&str>) -> Result<GpuContext, GpuError> {
        let instance = wgpu::Instance::new(instance_descriptor(None));
        Self::open(&instance, adapter_filter, None).await
    }

    /// Opens the best adapter (as [`GpuContext::new`] chooses) among those of `instance` that
    /// can present to `surface`: the device the window of `kousen view` draws with.
    pub fn for_surface(
        instance: &wgpu::Instance,
        surface: &wgpu::Surface<'_>,
        adapter_filter: Option<&str>,
    ) -> Result<GpuContext, GpuError> {
        pollster::block_on(Self::open(instance, adapter_filter, Some(surface)))
    }

    async fn open(
        instance: &wgpu::Instance,
        adapter_filter: Option<&str>,
        surface: Option<&wgpu::Surface<'_>>,
    ) -> Result<GpuContext, GpuError> {
        let env_filter = std::env::var(ADAPTER_NAME_ENV).ok();
        let filter = adapter_filter.or(env_filter.as_deref());

        let adapters = instance.enumerate_adapters(backends()).await;
        let seen: Vec<String> = adapters.iter().map(|a| a.get_info().name).collect();
        let adapter = adapters
            .into_iter()
            .filter(|a| filter.is_none_or(|f| name_matches(&a.get_info().name, f)))
            .filter(|a| surface.is_none_or(|s| a.is_surface_supported(s)))
            .min_by_key(|a| type_rank(a.get_info().device_type))
            .ok_or_else(|| GpuError::NoAdapter {
                filter: filter.map(str::to_owned),
                seen: seen.join(", "),
            })?;

        let info = adapter.get_info();
        let limits = adapter.limits();
        let features = adapter.features() & TIMESTAMP_FEATURES;
        let (device, queue) = adapter
            .request_device(&wgpu::DeviceDescriptor {
                label: Some("kousen"),
                required_features: features,
                required_limits: limits.clone(),
                ..Default::default()
            })
            .await
            .map_err(|e| GpuError::RequestDevice {
                adapter: info.name.clone(),
                reason: e.to_string(),
            })?;
        let scene_storage = SceneStorage::preferred(info.device_type);
        let context = GpuContext {
            device,
            queue,
            adapter,
            info,
            limits,
            features,
            scene_storage,
        };
        log::info!("gpu: {}", context.description());
        Ok(context)
    }

    /// One line: "name (backend, type, driver)".
    /// Whether the adapter is a CPU (such as lavapipe): work sizes are then kept small.
    pub fn is_cpu_device(&self) -> bool {
        self.info.device_type == wgpu::DeviceType::Cpu
    }

    pub fn description(&self) -> String {
        describe(&self.info)
    }
}

/// The backends kousen uses: Vulkan, Metal, DX12 (and WebGPU) unless `WGPU_BACKEND` says
/// otherwise. The GL backend lacks the storage-buffer compute we need on many drivers, and
/// probing it where there is no display only prints EGL errors.
pub fn backends() -> wgpu::Backends {
    wgpu::Backends::PRIMARY.with_env()
}

/// An instance over [`backends`], flags from wgpu's environment variables; a window's display
/// handle where one will present (GL needs it; the others ignore it).
pub fn instance_descriptor(
    display: Option<Box<dyn wgpu::wgt::WgpuHasDisplayHandle>>,
) -> wgpu::InstanceDescriptor {
    let mut desc = match display {
        Some(display) => wgpu::InstanceDescriptor::new_with_display_handle_from_env(display),
        None => wgpu::InstanceDescriptor::new_without_display_handle_from_env(),
    };
    desc.backends = backends();
    desc
}

/// "name (backend, type, driver driver_info)", driver parts left out when the backend is silent.
pub fn describe(info: &wgpu::AdapterInfo) -> String {
    let driver = driver(info);
    let driver = if driver.is_empty() {
        "unknown driver".to_owned()
    } else {
        driver
    };
    format!(
        "{} ({}, {:?}, {driver})",
        info.name, info.backend, info.device_type
    )
}

/// "driver driver_info", the parts the backend leaves empty left out ("" if both are).
pub fn driver(info: &wgpu::AdapterInfo) -> String {
    [info.driver.trim(), info.driver_info.trim()]
        .into_iter()
        .filter(|s| !s.is_empty())
        .collect::<Vec<_>>()
        .join(" ")
}

/// Lower is better: discrete, integrated, virtual, CPU, other.
fn type_rank(device_type: wgpu::DeviceType) -> u8 {
    match device_type {
        wgpu::DeviceType::DiscreteGpu => 0,
        wgpu::DeviceType::IntegratedGpu => 1,
        wgpu::DeviceType::VirtualGpu => 2,
        wgpu::DeviceType::Cpu => 3,
        wgpu::DeviceType::Other => 4,
    }
}

fn name_matches(name: &str, filter: &str) -> bool {
    name.to_lowercase().contains(&filter.to_lowercase())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn type_rank_prefers_discrete_then_integrated_virtual_cpu_other() {
        use wgpu::DeviceType::*;
        let ranks = [DiscreteGpu, IntegratedGpu, VirtualGpu, Cpu, Other].map(type_rank);
        assert!(ranks.is_sorted_by(|a, b| a < b), "{ranks:?}");
    }

    #[test]
    fn name_matches_ignores_case() {
        assert!(name_matches("llvmpipe (LLVM 15.0.6, 256 bits)", "LLVMPIPE"));
        assert!(!name_matches("llvmpipe", "nvidia"));
    }
}
