//! `kousen bench rng`: the generators alone, draws per second on the GPU adapter and the CPU.

use std::time::Instant;

use anyhow::bail;
use rayon::prelude::*;
use serde::Serialize;

use gpu::GpuContext;
use gpu::random_variants::{DRAWS_PER_INVOCATION, DrawRate, Generator, sum_draws};
use render::BackendError;
use render::random::{FractSin, Pcg, TalkFloat, Tea};

use super::super::host::median;
use super::measure;
use crate::cli::{BenchDevice, RngArgs};

#[derive(Serialize)]
pub(super) struct DrawRow {
    device: &'static str,
    generator: &'static str,
    /// Draws per run.
    draws: u64,
    /// Seconds per run (median).
    seconds: f64,
    /// Median over the runs of draws / seconds.
    draws_per_s: f64,
    over_pcg: f64,
    /// GPU rows: the largest |GPU sum − CPU twin's sum| over the streams.
    max_difference: Option<f32>,
}

/// Streams of the draw-rate runs (1,024 workgroups of 64), 256 draws each.
const DRAW_STREAMS: u32 = 1 << 16;
/// Largest |GPU − CPU| sum of 256 draws accepted for the talk's generator (its outputs differ
/// in the last bits; an error in the state would differ by whole draws).
const TALK_SUM_TOLERANCE: f32 = 1e-3;

type SumDraws = fn(u32) -> f32;

fn cpu_sum(generator: Generator) -> SumDraws {
    match generator {
        Generator::Pcg => sum_draws::<Pcg>,
        Generator::TalkFloat => sum_draws::<TalkFloat>,
        Generator::Tea => sum_draws::<Tea>,
        Generator::FractSin => sum_draws::<FractSin>,
    }
}

/// Draws per second of each generator alone, GPU and CPU: a warm-up, then `--runs` runs,
/// generators alternating. The GPU's sums are checked against the CPU twin's first.
pub(super) fn draw_rates(args: &RngArgs, gpu: Option<&GpuContext>) -> anyhow::Result<Vec<DrawRow>> {
    let draws = u64::from(DRAW_STREAMS) * u64::from(DRAWS_PER_INVOCATION);
    let twins: Vec<Vec<f32>> = Generator::ALL
        .iter()
        .map(|&g| (0..DRAW_STREAMS).into_par_iter().map(cpu_sum(g)).collect())
        .collect();
    let mut rows = Vec::new();
    let mut push = |device, runs: &[Vec<f64>], differences: Vec<Option<f32>>| {
        let rate = |seconds: &[f64]| {
            median(
                &seconds
                    .iter()
                    .map(|s| draws as f64 / s.max(1e-9))
                    .collect::<Vec<_>>(),
            )
        };
        let pcg = rate(&runs[0]);
        for ((g, seconds), max_difference) in Generator::ALL.iter().zip(runs).zip(differences) {
            rows.push(DrawRow {
                device,
                generator: g.name(),
                draws,
                seconds: median(seconds),
                draws_per_s: rate(seconds),
                over_pcg: rate(seconds) / pcg,
                max_difference,
            });
        }
    };
    if let Some(context) = gpu {
        let kernels: Vec<DrawRate> = Generator::ALL
            .iter()
            .map(|&g| DrawRate::new(context, g, DRAW_STREAMS))
            .collect();
        let runs = measure(&mut kernels.iter().collect::<Vec<_>>(), args, |k, _| {
            k.run(context)
                .map_err(|e| BackendError::Device(e.to_string()))
        })?;
        let mut differences = Vec::new();
        for ((g, kernel), twin) in Generator::ALL.iter().zip(&kernels).zip(&twins) {
            let sums = kernel.sums(context)?;
            let worst = sums
                .iter()
                .zip(twin)
                .map(|(a, b)| (a - b).abs())
                .fold(0.0f32, f32::max);
            let limit = match g {
                Generator::Pcg | Generator::Tea => 0.0,
                Generator::TalkFloat => TALK_SUM_TOLERANCE,
                Generator::FractSin => f32::INFINITY,
            };
            if worst > limit {
                bail!(
                    "{}: GPU draws differ from the CPU twin's by {worst}: a bug",
                    g.name()
                );
            }
            differences.push(Some(worst));
        }
        push("gpu", &runs, differences);
    }
    if args.devices.contains(&BenchDevice::Cpu) {
        let mut sums: Vec<SumDraws> = Generator::ALL.iter().map(|&g| cpu_sum(g)).collect();
        let runs = measure(&mut sums, args, |sum, _| {
            let started = Instant::now();
            let total: f32 = (0..DRAW_STREAMS).into_par_iter().map(*sum).sum();
            std::hint::black_box(total);
            Ok(started.elapsed().as_secs_f64())
        })?;
        push("cpu", &runs, vec![None; Generator::ALL.len()]);
    }
    println!(
        "generators alone: {draws} draws per run ({DRAW_STREAMS} streams × {DRAWS_PER_INVOCATION}); \
         median of {} runs",
        args.runs
    );
    for row in &rows {
        println!(
            "  {:<4} {:<10} {:>9.1} Mdraws/s {:>6.2} ×pcg{}",
            row.device,
            row.generator,
            row.draws_per_s / 1e6,
            row.over_pcg,
            row.max_difference
                .map_or_else(String::new, |d| format!("  (GPU − CPU sums ≤ {d:.2e})"))
        );
    }
    Ok(rows)
}
