//! `kousen render`: renders a scene to an image. Until the SPPM integrator lands (issue 4) the
//! only backend is the CPU path tracer of [`crate::path_trace`].

use std::time::Instant;

use anyhow::{Context, bail};
use glam::Vec3;
use serde::Serialize;

use crate::cli::{Backend, CameraArgs, RenderArgs};
use crate::image_io::Output;
use crate::path_trace::{Image, PathTracer, RenderSettings};

/// Bounces per path before it is cut off.
const MAX_DEPTH: u32 = 32;
/// Passes when neither --passes nor --time is given.
const DEFAULT_PASSES: u32 = 64;

#[derive(Serialize)]
struct Stats {
    passes: u32,
    eye_passes: u32,
    photon_paths: u64,
    seconds: f64,
    backend: &'static str,
    adapter: Option<String>,
    integrator: &'static str,
    width: u32,
    height: u32,
    mean_radiance: [f32; 3],
}

pub fn run(args: &RenderArgs) -> anyhow::Result<()> {
    if let Some(t) = args.time
        && !(t.is_finite() && t > 0.0)
    {
        bail!("--time must be a positive number of seconds, got {t}");
    }
    if args.backend == Backend::Gpu {
        bail!("the GPU backend is not built yet; use --backend cpu (or auto)");
    }
    // Fail on a bad output path before any work.
    let output = Output::create(&args.output)?;
    let scene = scene::load(&args.scene)?;
    if scene.lights.triangles.is_empty() {
        bail!(
            "{}: the scene has no emissive surface, so the image would be black",
            args.scene.display()
        );
    }
    let camera = choose_camera(&scene, &args.camera)?;
    let width = args.width;
    let height = args.height.unwrap_or_else(|| {
        let aspect = camera.aspect_ratio.unwrap_or(1.0);
        ((width as f32 / aspect).round() as u32).clamp(1, 16384)
    });
    if args.backend == Backend::Auto {
        log::info!("no GPU backend yet: rendering on the CPU");
    }
    super::info::check_bvh_limits(&scene)?;
    let bvh = bvh::PackedBvh::build(&scene.triangles, &super::info::build_options(args.bvh));
    let tracer = PathTracer::new(&scene, &bvh, camera);

    let started = Instant::now();
    let (image, passes) = render_passes(&tracer, args, width, height, started);
    let seconds = started.elapsed().as_secs_f64();
    output.commit(&image, args.exposure)?;
    log::info!("{passes} passes in {seconds:.2} s");

    if let Some(path) = &args.stats {
        let stats = Stats {
            passes,
            eye_passes: passes,
            photon_paths: 0,
            seconds,
            backend: "cpu",
            adapter: None,
            integrator: "path tracing (interim, until SPPM)",
            width,
            height,
            mean_radiance: crate::image_io::mean(&image).to_array(),
        };
        let json = serde_json::to_string_pretty(&stats)?;
        crate::output_file::write_atomically(path, json.as_bytes())?;
    }
    Ok(())
}

/// Renders one sample per pixel per pass until the pass count or the time is reached, and
/// averages the passes.
fn render_passes(
    tracer: &PathTracer,
    args: &RenderArgs,
    width: u32,
    height: u32,
    started: Instant,
) -> (Image, u32) {
    let target_passes = match (args.passes, args.time) {
        (Some(n), _) => n,
        (None, Some(_)) => u32::MAX,
        (None, None) => DEFAULT_PASSES,
    };
    let mut sum = vec![Vec3::ZERO; (width * height) as usize];
    let mut passes = 0;
    while passes < target_passes {
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
        if args
            .time
            .is_some_and(|t| started.elapsed().as_secs_f64() >= t)
        {
            break;
        }
    }
    let pixels = sum.into_iter().map(|s| s / passes as f32).collect();
    (
        Image {
            width,
            height,
            pixels,
        },
        passes,
    )
}

/// The camera from --eye/--target, --camera I, or the scene's default.
pub fn choose_camera(scene: &scene::Scene, args: &CameraArgs) -> anyhow::Result<scene::Camera> {
    if let (Some(eye), Some(target)) = (args.eye, args.target) {
        let camera = scene::Camera::look_at(
            Vec3::from(eye),
            Vec3::from(target),
            Vec3::from(args.up),
            args.fov.to_radians(),
        );
        return camera.context("--eye, --target, --up and --fov do not make a camera (eye equals target, up parallel to the view, or fov not in (0, 180))");
    }
    scene.camera(args.camera).with_context(|| {
        format!(
            "--camera {}: the scene has {} camera(s)",
            args.camera.unwrap_or(0),
            scene.cameras.len()
        )
    })
}
