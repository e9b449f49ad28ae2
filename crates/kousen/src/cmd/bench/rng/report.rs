//! `kousen bench rng`'s report: the JSON rows and the tables printed.

use serde::Serialize;

use gpu::random_variants::Generator;
use render::random::{StreamRng, battery};

use super::draws::DrawRow;
use super::images::ImageRow;
use super::{Run, median};
use crate::cli::RngArgs;
use crate::cmd::bench::host::BenchHost;

/// The JSON report (a contract for scripts: adapter, cpu_model, command, battery[...] with
/// generator, test, statistic, limit, passed; results[...] with scene, device, generator,
/// photon_paths, seconds, photon_paths_per_s; images[...]).
#[derive(Serialize)]
pub(super) struct Report {
    #[serde(flatten)]
    pub(super) host: BenchHost,
    pub(super) photon_slots: u32,
    pub(super) passes: u32,
    pub(super) runs: u32,
    pub(super) battery_draws: u32,
    pub(super) significance: f64,
    pub(super) battery: Vec<BatteryRow>,
    /// The generators alone: draws per second (`sum_draws`).
    pub(super) draw_rates: Vec<DrawRow>,
    pub(super) results: Vec<Row>,
    pub(super) images: Vec<ImageRow>,
}

#[derive(Serialize)]
pub(super) struct BatteryRow {
    pub(super) generator: &'static str,
    pub(super) test: &'static str,
    /// "chi2" or "max_abs_z".
    pub(super) kind: &'static str,
    pub(super) statistic: f64,
    /// Critical value at `significance`; the test passes below it.
    pub(super) limit: f64,
    pub(super) passed: bool,
}

#[derive(Serialize)]
pub(super) struct Row {
    pub(super) scene: String,
    pub(super) path: String,
    pub(super) device: &'static str,
    pub(super) generator: &'static str,
    pub(super) photon_slots: u32,
    pub(super) passes: u32,
    /// Paths emitted per run (median).
    pub(super) photon_paths: u64,
    /// Seconds per run (median).
    pub(super) seconds: f64,
    /// Median over the runs of paths / seconds.
    pub(super) photon_paths_per_s: f64,
    pub(super) photon_paths_per_min: f64,
    /// This row's paths/s over PCG's on the same device and scene.
    pub(super) over_pcg: f64,
    /// GPU rows: slots of the checked pass that differ from the CPU twin (null: not checked).
    pub(super) diverged: Option<usize>,
}

pub(super) fn battery_rows<G: StreamRng>(draws: u32) -> Vec<BatteryRow> {
    battery::run::<G>(draws)
        .into_iter()
        .map(|o| BatteryRow {
            generator: G::NAME,
            test: o.test,
            kind: o.kind,
            statistic: o.statistic,
            limit: o.limit,
            passed: o.passed,
        })
        .collect()
}

pub(super) fn print_battery(rows: &[BatteryRow], draws: u32) {
    println!(
        "battery: {draws} draws per test, significance {}; statistic (limit) pass/FAIL",
        battery::SIGNIFICANCE
    );
    for generator in Generator::ALL {
        let cells: Vec<String> = rows
            .iter()
            .filter(|r| r.generator == generator.name())
            .map(|r| {
                let verdict = if r.passed { "pass" } else { "FAIL" };
                format!("{} {:.1} ({:.1}) {verdict}", r.test, r.statistic, r.limit)
            })
            .collect();
        println!("  {:<10} {}", generator.name(), cells.join(" | "));
    }
}

pub(super) fn print_speed_header() {
    println!(
        "{:<18} {:<4} {:<10} {:>6} {:>10} {:>8} {:>9} {:>10} {:>6} {:>8}",
        "scene",
        "dev",
        "generator",
        "passes",
        "paths/run",
        "seconds",
        "Mpaths/s",
        "Mpaths/min",
        "×pcg",
        "diverged"
    );
}

pub(super) fn print_row(row: &Row) {
    println!(
        "{:<18} {:<4} {:<10} {:>6} {:>10} {:>8.3} {:>9.3} {:>10.1} {:>6.2} {:>8}",
        row.scene,
        row.device,
        row.generator,
        row.passes,
        row.photon_paths,
        row.seconds,
        row.photon_paths_per_s / 1e6,
        row.photon_paths_per_min / 1e6,
        row.over_pcg,
        row.diverged
            .map_or_else(|| "-".to_owned(), |d| d.to_string()),
    );
}

pub(super) fn row(
    args: &RngArgs,
    device: &'static str,
    generator: Generator,
    runs: &[Run],
    diverged: Option<usize>,
) -> Row {
    let rates: Vec<f64> = runs
        .iter()
        .map(|r| r.paths as f64 / r.seconds.max(1e-9))
        .collect();
    let per_s = median(&rates);
    let paths: Vec<f64> = runs.iter().map(|r| r.paths as f64).collect();
    let seconds: Vec<f64> = runs.iter().map(|r| r.seconds).collect();
    Row {
        scene: String::new(),
        path: String::new(),
        device,
        generator: generator.name(),
        photon_slots: args.photons,
        passes: args.passes,
        photon_paths: median(&paths) as u64,
        seconds: median(&seconds),
        photon_paths_per_s: per_s,
        photon_paths_per_min: 60.0 * per_s,
        over_pcg: 1.0,
        diverged,
    }
}
