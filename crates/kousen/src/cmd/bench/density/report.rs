//! What `kousen bench density` reports: the JSON rows, the equal-time error, the GPU/CPU
//! ratios and the printed table.

use serde::Serialize;

use render::Image;

use crate::cmd::bench::host::BenchHost;

use crate::image_metrics::rel_mse;

/// The JSON report (a contract for scripts: adapter, cpu_model, command, results[...] with
/// scene, device, method, passes, hash_build_ms, gather_ms, iteration_ms, rel_mse_equal_passes,
/// rel_mse_equal_time; the other keys are extras).
#[derive(Serialize)]
pub(super) struct Report {
    #[serde(flatten)]
    pub(super) host: BenchHost,
    pub(super) width: u32,
    pub(super) height: u32,
    pub(super) photon_slots: u32,
    pub(super) passes: u32,
    pub(super) eye_every: u32,
    pub(super) seed: u32,
    pub(super) references: Vec<ReferenceReport>,
    pub(super) results: Vec<Row>,
    /// Table 5: the CPU backend's times over the GPU's, per scene and method.
    pub(super) gpu_over_cpu: Vec<Speedup>,
}

#[derive(Serialize)]
pub(super) struct ReferenceReport {
    pub(super) scene: String,
    /// The file given, or how it was rendered.
    pub(super) source: String,
}

#[derive(Serialize)]
pub(super) struct Row {
    pub(super) scene: String,
    pub(super) device: &'static str,
    pub(super) method: &'static str,
    /// How photons and visible points were stored: "f32" or "f16".
    pub(super) precision: &'static str,
    /// Table entries per photon slot (hash methods).
    pub(super) table_ratio: Option<f32>,
    pub(super) passes: u32,
    /// Medians over the passes (ms).
    pub(super) hash_build_ms: f64,
    pub(super) gather_ms: f64,
    pub(super) photon_pass_ms: f64,
    /// Median of the eye passes (one every `eye_every` passes).
    pub(super) eye_pass_ms: f64,
    /// Mean time of a whole iteration (eye passes spread over their passes) and total.
    pub(super) iteration_ms: f64,
    pub(super) seconds: f64,
    /// Bytes of the hash, lists or tree on the device.
    pub(super) density_bytes: u64,
    /// Bytes of the photon slots, photons and visible points on the device (the CPU backend
    /// keeps f32 structs and rounds them for f16).
    pub(super) point_bytes: u64,
    pub(super) rel_mse_equal_passes: f64,
    /// Mean brightness over the reference's at equal passes (1: unbiased).
    pub(super) mean_ratio: f64,
    /// At the fastest method's total time on this device; None when this method's first
    /// checkpoint came later.
    pub(super) rel_mse_equal_time: Option<f64>,
    pub(super) equal_time_seconds: f64,
    pub(super) checkpoints: Vec<Checkpoint>,
}

#[derive(Clone, Copy, Serialize)]
pub(super) struct Checkpoint {
    pub(super) passes: u32,
    /// Timed seconds up to this pass.
    pub(super) seconds: f64,
    pub(super) rel_mse: f64,
}

#[derive(Serialize)]
pub(super) struct Speedup {
    pub(super) scene: String,
    /// The method, with "-f16" for f16 storage.
    pub(super) method: String,
    /// CPU backend time over GPU time: the hash build alone and a whole iteration.
    pub(super) hash_build: f64,
    pub(super) iteration: f64,
}

impl Row {
    /// The method, with the storage precision when it is not f32 ("stochastic-1-f16").
    pub(super) fn label(&self) -> String {
        match self.precision {
            "f32" => self.method.to_owned(),
            precision => format!("{}-{precision}", self.method),
        }
    }
}

/// Mean grey the images are scaled to before the relMSE, so that its 0.01 in the denominator
/// means the same on dark and bright scenes.
const ERROR_MEAN: f32 = 0.18;

/// relMSE after scaling `image` and `reference` by one factor that brings the reference's mean
/// to [`ERROR_MEAN`].
pub(super) fn scaled_rel_mse(image: &Image, reference: &Image) -> f64 {
    let mean = reference.mean().element_sum() / 3.0;
    let k = if mean > 0.0 { ERROR_MEAN / mean } else { 1.0 };
    let scaled = |i: &Image| Image {
        pixels: i.pixels.iter().map(|p| *p * k).collect(),
        ..*i
    };
    rel_mse(&scaled(image), &scaled(reference))
}

/// Each row's error at the time the fastest method on its device took.
pub(super) fn equal_time(mut rows: Vec<Row>) -> Vec<Row> {
    let budget = rows.iter().map(|r| r.seconds).fold(f64::INFINITY, f64::min);
    for row in &mut rows {
        row.equal_time_seconds = budget;
        row.rel_mse_equal_time = error_at(&row.checkpoints, budget);
    }
    println!("at equal time ({budget:.3} s each):");
    for row in &rows {
        println!(
            "  {:<18} {:<4} relMSE {}",
            row.label(),
            row.device,
            row.rel_mse_equal_time.map_or_else(
                || "- (first checkpoint later)".to_owned(),
                |e| format!("{e:.5}")
            )
        );
    }
    rows
}

/// The error at `seconds`, interpolated log–log between the checkpoints around it; the last
/// checkpoint's when `seconds` is at or past it; None before the first.
pub(super) fn error_at(checkpoints: &[Checkpoint], seconds: f64) -> Option<f64> {
    let last = checkpoints.last()?;
    if seconds >= last.seconds {
        return Some(last.rel_mse);
    }
    let after = checkpoints.iter().position(|c| c.seconds >= seconds)?;
    if after == 0 {
        return (checkpoints[0].seconds == seconds).then_some(checkpoints[0].rel_mse);
    }
    let (a, b) = (checkpoints[after - 1], checkpoints[after]);
    let t = (seconds.ln() - a.seconds.ln()) / (b.seconds.ln() - a.seconds.ln());
    Some((a.rel_mse.ln() + t * (b.rel_mse.ln() - a.rel_mse.ln())).exp())
}

/// Table 5: for each method measured on both devices, the CPU's times over the GPU's.
pub(super) fn speedups(rows: &[Row]) -> Vec<Speedup> {
    rows.iter()
        .filter(|r| r.device == "gpu")
        .filter_map(|g| {
            let c = rows
                .iter()
                .find(|c| c.device == "cpu" && c.label() == g.label())?;
            Some(Speedup {
                scene: g.scene.clone(),
                method: g.label(),
                hash_build: c.hash_build_ms / g.hash_build_ms,
                iteration: c.iteration_ms / g.iteration_ms,
            })
        })
        .collect()
}

pub(super) fn print_speedups(speedups: &[Speedup]) {
    if speedups.is_empty() {
        return;
    }
    println!("CPU backend time / GPU time:");
    for s in speedups {
        println!(
            "  {:<18} {:<18} hash build ×{:.2}, whole iteration ×{:.2}",
            s.scene, s.method, s.hash_build, s.iteration
        );
    }
}

pub(super) fn print_header() {
    println!(
        "{:<18} {:<4} {:<18} {:>6} {:>9} {:>9} {:>9} {:>9} {:>9} {:>10} {:>11} {:>7}",
        "scene",
        "dev",
        "method",
        "passes",
        "build ms",
        "gather ms",
        "photon ms",
        "eye ms",
        "iter ms",
        "MiB",
        "relMSE(=P)",
        "mean"
    );
}

pub(super) fn print_row(row: &Row) {
    println!(
        "{:<18} {:<4} {:<18} {:>6} {:>9.3} {:>9.3} {:>9.3} {:>9.3} {:>9.3} {:>10.2} {:>11.5} {:>7.3}",
        row.scene,
        row.device,
        row.label(),
        row.passes,
        row.hash_build_ms,
        row.gather_ms,
        row.photon_pass_ms,
        row.eye_pass_ms,
        row.iteration_ms,
        row.density_bytes as f64 / (1 << 20) as f64,
        row.rel_mse_equal_passes,
        row.mean_ratio
    );
}

#[cfg(test)]
mod tests {
    use super::*;

    fn at(passes: u32, seconds: f64, rel_mse: f64) -> Checkpoint {
        Checkpoint {
            passes,
            seconds,
            rel_mse,
        }
    }

    #[test]
    fn scaled_error_does_not_depend_on_brightness() {
        let image = |scale: f32, shift: f32| Image {
            width: 2,
            height: 2,
            pixels: (0..4)
                .map(|i| glam::Vec3::splat(scale * (i as f32 + shift)))
                .collect(),
        };
        let bright = scaled_rel_mse(&image(1.0, 0.5), &image(1.0, 1.0));
        let dark = scaled_rel_mse(&image(1e-4, 0.5), &image(1e-4, 1.0));
        assert!(bright > 0.01);
        assert!(
            (bright - dark).abs() < 1e-6 * bright,
            "{bright} against {dark}"
        );
    }

    #[test]
    fn error_at_interpolates_log_log_between_checkpoints() {
        let checkpoints = [at(1, 1.0, 1.0), at(2, 4.0, 0.25), at(4, 16.0, 0.0625)];
        // Error ∝ 1/t here, so log–log interpolation is exact.
        assert!((error_at(&checkpoints, 2.0).unwrap() - 0.5).abs() < 1e-12);
        assert!((error_at(&checkpoints, 8.0).unwrap() - 0.125).abs() < 1e-12);
        assert_eq!(error_at(&checkpoints, 16.0), Some(0.0625));
        assert_eq!(error_at(&checkpoints, 40.0), Some(0.0625));
        assert_eq!(error_at(&checkpoints, 1.0), Some(1.0));
        assert_eq!(error_at(&checkpoints, 0.5), None);
        assert_eq!(error_at(&[], 1.0), None);
    }
}
