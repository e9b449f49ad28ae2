//! What a benchmark records about the machine it ran on, and its statistics.

pub use cpu::cpu_model;
use gpu::{GpuContext, GpuError};
use serde::Serialize;

use crate::cli::BenchDevice;

/// The adapter a report names (JSON: name, backend, driver, device_type).
#[derive(Serialize)]
pub struct AdapterReport {
    name: String,
    backend: String,
    driver: String,
    device_type: String,
}

impl AdapterReport {
    pub fn of(context: &GpuContext) -> AdapterReport {
        let info = &context.info;
        AdapterReport {
            name: info.name.clone(),
            backend: info.backend.to_string(),
            driver: gpu::device::driver(info),
            device_type: format!("{:?}", info.device_type),
        }
    }
}

/// What a report says about where and how it was made; flattened into the benches' JSON
/// (keys adapter, cpu_model, cpu_threads, gpu_timing, command).
#[derive(Serialize)]
pub struct BenchHost {
    pub adapter: Option<AdapterReport>,
    pub cpu_model: String,
    pub cpu_threads: usize,
    /// How GPU work is timed; null without a GPU.
    pub gpu_timing: Option<&'static str>,
    pub command: String,
}

impl BenchHost {
    /// This process on this machine, with `gpu` (if any) timed as `gpu_timing` says.
    pub fn here(gpu: Option<&GpuContext>, gpu_timing: &'static str) -> BenchHost {
        BenchHost {
            adapter: gpu.map(AdapterReport::of),
            cpu_model: cpu_model(),
            cpu_threads: rayon::current_num_threads(),
            gpu_timing: gpu.map(|_| gpu_timing),
            command: std::env::args().collect::<Vec<_>>().join(" "),
        }
    }
}

/// The GPU when `devices` includes it; with no adapter at all and no `adapter` asked for, the
/// CPU backend runs alone (said on stderr).
pub fn open_gpu(
    devices: &[BenchDevice],
    adapter: Option<&str>,
) -> anyhow::Result<Option<GpuContext>> {
    if !devices.contains(&BenchDevice::Gpu) {
        return Ok(None);
    }
    match GpuContext::new(adapter) {
        Ok(context) => Ok(Some(context)),
        Err(error @ GpuError::NoAdapter { .. }) if adapter.is_none() => {
            eprintln!("kousen: {error}; measuring the CPU side only");
            Ok(None)
        }
        Err(error) => Err(error.into()),
    }
}

/// The median of `samples` (which must not be empty); the mean of the middle two when even.
pub fn median(samples: &[f64]) -> f64 {
    let mut sorted = samples.to_vec();
    sorted.sort_by(f64::total_cmp);
    let mid = sorted.len() / 2;
    if sorted.len() % 2 == 1 {
        sorted[mid]
    } else {
        (sorted[mid - 1] + sorted[mid]) / 2.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn median_of_odd_and_even_counts() {
        assert_eq!(median(&[3.0, 1.0, 2.0]), 2.0);
        assert_eq!(median(&[4.0, 1.0, 3.0, 2.0]), 2.5);
        assert_eq!(median(&[7.0]), 7.0);
    }

    #[test]
    fn cpu_model_is_one_non_empty_line() {
        let model = cpu_model();
        assert!(!model.is_empty() && !model.contains('\n'), "{model:?}");
    }
}
