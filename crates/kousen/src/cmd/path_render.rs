//! `kousen render --integrator path`: the CPU path tracer of [`crate::path_trace`], one sample
//! per pixel per pass, averaged. An independent reference for the SPPM integrator.

use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Instant;

use glam::Vec3;
use render::{Budget, Image};

use crate::cli::RenderArgs;
use crate::image_io::Output;
use crate::path_trace::{PathTracer, RenderSettings};

/// Bounces per path before it is cut off.
const MAX_DEPTH: u32 = 32;

/// The view rendered.
pub struct Frame {
    pub camera: scene::Camera,
    pub width: u32,
    pub height: u32,
}

/// Renders until `budget` is spent or `stop` is set (Ctrl-C: after the pass in flight, with the
/// image and statistics written, then [`super::Interrupted`]).
pub fn run(
    args: &RenderArgs,
    scene: &scene::Scene,
    bvh: &bvh::PackedBvh,
    frame: Frame,
    budget: Budget,
    output: Output,
    stop: &AtomicBool,
) -> anyhow::Result<()> {
    let Frame {
        camera,
        width,
        height,
    } = frame;
    let tracer = PathTracer::new(scene, bvh, camera);
    let started = Instant::now();
    let mut sum = vec![Vec3::ZERO; (width * height) as usize];
    let mut passes = 0u32;
    loop {
        let done = match budget {
            Budget::Passes(n) => passes >= n,
            Budget::Time(t) => passes > 0 && started.elapsed() >= t,
        } || (passes > 0 && stop.load(Ordering::Relaxed));
        if done {
            break;
        }
        let settings = RenderSettings {
            width,
            height,
            samples_per_pixel: 1,
            max_depth: MAX_DEPTH,
            seed: args
                .seed
                .wrapping_mul(0x9E37_79B9_7F4A_7C15)
                .wrapping_add(passes as u64),
        };
        let pass = tracer.render(&settings);
        for (s, p) in sum.iter_mut().zip(&pass.pixels) {
            *s += *p;
        }
        passes += 1;
    }
    let seconds = started.elapsed().as_secs_f64();
    let image = Image::new(
        width,
        height,
        sum.into_iter().map(|s| s / passes as f32).collect(),
    );
    output.commit(&image, args.look())?;
    log::info!("{passes} path-traced passes in {seconds:.2} s");
    if let Some(path) = &args.stats {
        let stats = serde_json::json!({
            "passes": passes,
            "eye_passes": passes,
            "photon_paths": 0,
            "seconds": seconds,
            "backend": "cpu",
            "adapter": cpu::processor_name(),
            "integrator": "path",
            "width": width,
            "height": height,
            "mean_radiance": image.mean().to_array(),
        });
        let json = serde_json::to_string_pretty(&stats)?;
        crate::output_file::write_atomically(path, json.as_bytes())?;
    }
    if stop.load(Ordering::Relaxed) {
        return Err(super::Interrupted { passes }.into());
    }
    Ok(())
}
