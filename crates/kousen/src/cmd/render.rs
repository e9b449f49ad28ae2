//! `kousen render`: a scene to an image with SPPM on the GPU or CPU backend (or, with
//! `--integrator path`, the CPU path tracer kept as an independent reference).

use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use anyhow::{Context, bail};
use glam::Vec3;
use render::{Backend, Budget, Progress, Rendered, RunHooks, Settings, Sppm};
use serde::Serialize;

use super::intermediates::Intermediates;
use crate::checkpoint_file::{self, Header, Recorded};
use crate::cli::{Backend as BackendChoice, CameraArgs, GlossyLightChoice, Integrator, RenderArgs};
use crate::image_io::Output;
use crate::progress::ProgressBar;

/// How often `--checkpoint` saves the render while it runs (and once more at the end).
const CHECKPOINT_INTERVAL: Duration = Duration::from_secs(60);

/// Photon passes when neither --passes nor --time is given.
const DEFAULT_PASSES: u32 = 256;
/// Photon slots per pass: with the stochastic hash one per pixel (glslppm's choice; it keeps
/// one photon per cell, so many more slots than pixels mostly trace photons it drops: at
/// 128², 2¹⁴ slots reached half the error of 2¹⁸ in the same time, docs/BENCHMARKS.md §3);
/// with full lists or a kd-tree, which use every photon, four per pixel (measured there to
/// reach a given error sooner than one). At least [`MIN_SLOTS`] and at most [`MAX_SLOTS`] on
/// every device: on CPU cores too, where a cap of 2¹⁸ (glslppm's 512²) had 20–27 % more error
/// at equal time at 512² and 960×540 (docs/BENCHMARKS.md §3, session 12).
const MIN_SLOTS: u32 = 1 << 12;
const MAX_SLOTS: u32 = 1 << 20;

fn default_slots(width: u32, height: u32, density: render::Density) -> u32 {
    let per_pixel = match density {
        render::Density::StochasticHash => 1,
        render::Density::FullHash | render::Density::KdTree => 4,
    };
    (width as u64 * height as u64 * per_pixel).clamp(MIN_SLOTS as u64, MAX_SLOTS as u64) as u32
}

#[derive(Serialize)]
struct Stats {
    passes: u32,
    eye_passes: u32,
    photon_paths: u64,
    seconds: f64,
    photon_paths_per_second: f64,
    backend: &'static str,
    adapter: String,
    host_cpu_seconds: f64,
    integrator: &'static str,
    width: u32,
    height: u32,
    photon_slots: u32,
    hash_entries: u32,
    alpha: f32,
    indirect_alpha: f32,
    /// The caustic photons' first radius as a share of the indirect ones' (`--caustic-radius`).
    caustic_radius: f32,
    eye_every: u32,
    density: &'static str,
    precision: &'static str,
    direct_light: &'static str,
    /// `sampled` or `lobe` (`--glossy-light`).
    glossy_light: &'static str,
    /// `--light-candidates`, `auto` resolved for the scene.
    light_candidates: u32,
    seed: u64,
    /// Passes already done in the checkpoint this render continued (0: a new render).
    resumed_passes: u32,
    mean_radiance: [f32; 3],
    /// Bytes allocated by the backend, by kind.
    memory_bytes: std::collections::BTreeMap<&'static str, u64>,
    /// --save-at's images, each with how far the render had come (absent without it).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    saved_images: Vec<super::intermediates::SavedImage>,
    /// The camera's thin lens (`--aperture-radius`, `--focus-distance` or where the image's
    /// centre focused it); null for a pinhole.
    lens: Option<LensStats>,
    /// The eye passes --denoise-guides averaged; null without it.
    denoise_guide_eye_passes: Option<u32>,
}

#[derive(Serialize)]
struct LensStats {
    aperture_radius: f32,
    focus_distance: f32,
    /// 0: round.
    aperture_blades: u32,
    aperture_rotation_degrees: f32,
}

/// Photon passes per eye pass where the render runs on CPU cores (the CPU backend, or a
/// CPU-type adapter such as lavapipe): 4 × pixels per photon slot, to the nearest power of
/// two, from 1 to 8. An eye pass (a camera ray, a shadow ray and a gather per pixel)
/// costs about what a photon pass of twice as many slots costs, and each brings a new jittered
/// position and light sample per pixel: worth every pass where pixels are few next to the
/// slots, and a share of the time that photons need more where they are many. Measured at
/// equal time (docs/BENCHMARKS.md §3, session 12), best K against pixels per slot:
/// cornell-caustics 128² (0.25) 1; 512² (1) 1–2, 4 within 9 %; Crytek Sponza in sunlight
/// 480×270 (0.49) 2–4, 960×540 (1.98) 8–16. Through lavapipe, cornell-caustics at 128² (the
/// rule's 1) had 4× less error than with every 8th pass, at 512² (the rule's 4) 7 % less.
fn eye_every_on_cpu_cores(pixels: u64, slots: u32) -> u32 {
    let share = 4.0 * pixels as f64 / f64::from(slots.max(1));
    let power = share.max(1.0).log2().round().min(3.0);
    power.exp2() as u32
}

pub fn run(args: &RenderArgs) -> anyhow::Result<()> {
    // Installed first, so that a Ctrl-C while the scene loads already counts.
    let stop = stop_on_ctrl_c();
    match args.frames {
        Some(frames) => super::frames::run(args, frames, stop),
        None => run_until(args, stop),
    }
}

/// One image of `args`, the render ending early once `stop` is set.
pub(super) fn run_until(args: &RenderArgs, stop: Arc<AtomicBool>) -> anyhow::Result<()> {
    let budget = budget(args)?;
    // Fail on a bad output or checkpoint path, or an unreadable checkpoint, before any work.
    let output = Output::create_with(&args.output, args.exr_precision)?;
    let components = args
        .components
        .then(|| component_outputs(&args.output, args.exr_precision))
        .transpose()?;
    if let Some(path) = &args.checkpoint {
        crate::output_file::PendingFile::create(path)?;
    }
    let resume = args
        .resume
        .as_ref()
        .map(|path| checkpoint_file::read(path).map(|loaded| (path.as_path(), loaded)))
        .transpose()?;
    if args.integrator == Integrator::Path && (args.checkpoint.is_some() || resume.is_some()) {
        bail!("--checkpoint and --resume are for SPPM renders, not --integrator path");
    }
    if args.integrator == Integrator::Path && args.components {
        bail!("--components is for SPPM renders, not --integrator path (its image has no parts)");
    }
    if args.integrator == Integrator::Path && args.denoise_guides {
        bail!("--denoise-guides is for SPPM renders, not --integrator path");
    }
    let guides = args
        .denoise_guides
        .then(|| guide_outputs(&args.output, args.exr_precision))
        .transpose()?;
    if args.integrator == Integrator::Path && !args.save_at.is_empty() {
        bail!("--save-at is for SPPM renders, not --integrator path");
    }
    let intermediates =
        Intermediates::create(&args.output, &args.save_at, args.exr_precision, budget)?;
    let output = Outputs {
        image: output,
        components,
        guides,
        intermediates,
    };
    let mut scene = scene::load_with(&args.scene, &args.load.options())?;
    args.added_lights.add_to(&mut scene, &args.scene)?;
    if scene.lights.is_empty() {
        bail!(
            "{}: the scene has no light (no emissive surface and no glTF punctual light), so the image would be black; --sun X,Y,Z, --sky R,G,B or --sky-map FILE adds one",
            args.scene.display()
        );
    }
    let requested = choose_camera(&scene, &args.camera)?;
    let width = args.width;
    let height = args.height.unwrap_or_else(|| {
        let aspect = requested
            .as_ref()
            .and_then(|c| c.aspect_ratio)
            .unwrap_or(1.0);
        ((width as f32 / aspect).round() as u32).clamp(1, 16384)
    });
    if args.photons == Some(0) {
        bail!("--photons must be at least 1");
    }
    super::info::check_bvh_limits(&scene)?;
    let started = Instant::now();
    let bvh = bvh::PackedBvh::build(&scene.triangles, &super::info::build_options(args.bvh));
    log::info!("BVH built in {:.2} s", started.elapsed().as_secs_f64());
    let camera = requested.unwrap_or_else(|| {
        let framed = render::framing::framed_view(&bvh, scene.bounds());
        log::info!("no camera in the scene: the view {}", framed.name);
        framed
    });
    let camera = with_lens(camera, &args.camera, &bvh, (width, height))?;
    let fingerprint = if args.checkpoint.is_some() || resume.is_some() {
        checkpoint_file::fingerprint(&bvh, &camera, &scene.lights)
    } else {
        String::new()
    };
    let continuation = Continuation {
        resume,
        fingerprint,
        stop,
    };

    if args.integrator == Integrator::Path {
        if args.backend == BackendChoice::Gpu {
            bail!("--integrator path runs on the CPU only; use --backend cpu or auto");
        }
        let frame = super::path_render::Frame {
            camera,
            width,
            height,
        };
        return super::path_render::run(
            args,
            &scene,
            &bvh,
            frame,
            budget,
            output.image,
            &continuation.stop,
        );
    }

    let footprints = args.gather.radius_footprints()?;
    let initial_radius =
        render::integrator::initial_radius_in_footprints(&bvh, &camera, width, height, footprints);
    let pixels = u64::from(width) * u64::from(height);
    let settings = |on_cpu_cores: bool, eye_every: fn(u64, u32) -> u32| {
        let density = args.estimator.density.density(on_cpu_cores);
        let photons = args
            .photons
            .unwrap_or(default_slots(width, height, density));
        Settings {
            initial_radius,
            caustic_radius_share: args
                .gather
                .caustic_radius_share(args.estimator.direct_light.direct()),
            alpha: args.gather.alpha,
            indirect_alpha: args.gather.indirect_alpha,
            eye_every: args.eye_every.unwrap_or(eye_every(pixels, photons)),
            hash_ratio: args.hash_ratio,
            max_depth: args.max_depth,
            density,
            precision: args.estimator.precision.precision(),
            direct: args.estimator.direct_light.direct(),
            glossy_light_sampling: args.estimator.glossy_light == GlossyLightChoice::Sampled,
            light_candidates: args.estimator.light_candidates.0,
            seed: fold_seed(args.seed),
            ..Settings::new(width, height, photons)
        }
    };
    let gpu_context = match args.backend {
        BackendChoice::Cpu => None,
        BackendChoice::Gpu => Some(gpu::GpuContext::new(args.adapter.as_deref())?),
        // A CPU-type adapter (lavapipe) runs the same kernels slower than the native CPU
        // backend on the same cores (docs/BENCHMARKS.md §3), so auto takes it only if named.
        BackendChoice::Auto => match gpu::GpuContext::new(args.adapter.as_deref()) {
            Ok(context) if context.is_cpu_device() && args.adapter.is_none() => {
                eprintln!(
                    "kousen: the only adapter is a CPU ({}); rendering on the CPU backend (use --backend gpu to render through it)",
                    context.info.name
                );
                None
            }
            Ok(context) => Some(context),
            Err(e) => {
                eprintln!("kousen: no GPU adapter ({e}); rendering on the CPU backend");
                None
            }
        },
    };
    let mut job = Job {
        budget,
        output,
        continuation,
    };
    let bvh = match gpu_context {
        None => bvh,
        Some(context) => {
            // Auto renders on the CPU backend where the render does not fit the adapter's
            // limits, with the scene as it was before the GPU's sky-map fitting.
            let fallback = (args.backend == BackendChoice::Auto).then(|| {
                (
                    bvh.clone(),
                    scene.lights.clone(),
                    job.continuation.fingerprint.clone(),
                )
            });
            if let Some(note) = gpu::limits::fit_sky_map(&mut scene.lights, &context.limits) {
                eprintln!("kousen: {note}");
                if !job.continuation.fingerprint.is_empty() {
                    job.continuation.fingerprint =
                        checkpoint_file::fingerprint(&bvh, &camera, &scene.lights);
                }
            }
            let cpu_device = context.is_cpu_device();
            let eye_every: fn(u64, u32) -> u32 = if cpu_device {
                eye_every_on_cpu_cores
            } else {
                |_, _| render::settings::DEFAULT_EYE_EVERY
            };
            let settings = settings(cpu_device, eye_every);
            let cpu_before = thread_cpu_seconds();
            let started = match gpu::sppm::GpuBackend::new(context, &scene, bvh) {
                Ok(backend) => Sppm::new(backend, &scene, &camera, settings.clone())
                    .map_err(|e| (does_not_fit(&e), anyhow::Error::from(e))),
                Err(e) => Err((e.is_limit(), e.into())),
            };
            match (started, fallback) {
                (Ok(sppm), fallback) => {
                    // The copies kept for the CPU (a BVH, a sky map) need not last the render.
                    drop(fallback);
                    let started = (sppm, cpu_before);
                    return finish(args, (&scene, &camera), started, job);
                }
                (Err((true, error)), Some((bvh, lights, fingerprint))) => {
                    eprintln!(
                        "kousen: the render does not fit the GPU adapter ({error:#}); rendering on the CPU backend"
                    );
                    scene.lights = lights;
                    job.continuation.fingerprint = fingerprint;
                    bvh
                }
                (Err((_, error)), _) => return Err(error),
            }
        }
    };
    let backend = cpu::CpuBackend::new(cpu::SceneData::new(&scene, bvh));
    let cpu_before = thread_cpu_seconds();
    let settings = settings(true, eye_every_on_cpu_cores);
    let sppm = Sppm::new(backend, &scene, &camera, settings)?;
    let started = (sppm, cpu_before);
    finish(args, (&scene, &camera), started, job)
}

/// Whether a render could not start because it does not fit the backend's device.
fn does_not_fit(error: &render::RenderError) -> bool {
    matches!(
        error,
        render::RenderError::Backend(render::BackendError::DoesNotFit(_))
    )
}

/// Where a render's image goes and, with --components, its parts (`render::resolve::COMPONENTS`),
/// and with --save-at the images on the way.
struct Outputs {
    image: Output,
    components: Option<Vec<Output>>,
    /// --denoise-guides's albedo and normal images.
    guides: Option<[Output; 2]>,
    /// --save-at's images of the render so far.
    intermediates: Intermediates,
}

/// The files of --components: `out.direct.exr` and so on beside `out.exr`.
fn component_outputs(
    output: &Path,
    precision: crate::image_io::ExrPrecision,
) -> anyhow::Result<Vec<Output>> {
    render::resolve::COMPONENTS
        .iter()
        .map(|name| Output::create_with(&component_path(output, name), precision))
        .collect()
}

/// The files of --denoise-guides, `out.albedo.exr` and `out.normal.exr` beside `out.exr`:
/// float images, as denoisers read them (a normal's components are signed).
fn guide_outputs(
    output: &Path,
    precision: crate::image_io::ExrPrecision,
) -> anyhow::Result<[Output; 2]> {
    if crate::image_io::Format::from_path(output)? == crate::image_io::Format::Png {
        bail!(
            "--denoise-guides writes float images beside the output, and {} is a PNG: render to an .exr or .pfm",
            output.display()
        );
    }
    let guide = |name| Output::create_with(&component_path(output, name), precision);
    Ok([guide("albedo")?, guide("normal")?])
}

/// `out.exr` with `name` before its extension: `out.NAME.exr`.
fn component_path(output: &Path, name: &str) -> PathBuf {
    beside(output, &format!(".{name}"))
}

/// `out.exr` with `suffix` after its stem (`out<suffix>.exr`), beside it.
pub(super) fn beside(output: &Path, suffix: &str) -> PathBuf {
    let stem = output.file_stem().unwrap_or_default().to_string_lossy();
    let file = match output.extension() {
        Some(extension) => format!("{stem}{suffix}.{}", extension.to_string_lossy()),
        None => format!("{stem}{suffix}"),
    };
    output.with_file_name(file)
}

/// The checkpoint a render continues, if any, the scene-and-view fingerprint its
/// checkpoints carry (empty when neither --checkpoint nor --resume is given), and when it
/// stops early.
struct Continuation<'a> {
    resume: Option<(&'a std::path::Path, checkpoint_file::Loaded)>,
    fingerprint: String,
    /// Set by the first Ctrl-C: stop after the pass in flight, writing everything.
    stop: Arc<AtomicBool>,
}

/// What a render is asked to do beyond its scene and settings: its budget, its outputs and how
/// it continues and stops.
struct Job<'a> {
    budget: Budget,
    output: Outputs,
    continuation: Continuation<'a>,
}

/// Runs a started render (`started`: it, and the driving thread's CPU time before it was
/// set up) and writes what it made.
fn finish<B: Backend>(
    args: &RenderArgs,
    (scene, camera): (&scene::Scene, &scene::Camera),
    (mut sppm, cpu_before): (Sppm<B>, f64),
    job: Job,
) -> anyhow::Result<()> {
    let Job {
        budget,
        mut output,
        continuation,
    } = job;
    let settings = sppm.settings().clone();
    let backend_name = sppm.backend().name();
    let adapter = sppm.backend().adapter();
    log::info!(
        "SPPM on the {backend_name} backend ({adapter}): {}×{}, {} photon slots",
        settings.width,
        settings.height,
        settings.photons
    );
    let recorded = Recorded::new(backend_name, &settings);
    let (mut seconds_before, mut resumed_passes, mut resumed_paths) = (0.0, 0, 0);
    if let Some((path, loaded)) = &continuation.resume {
        checkpoint_file::check_fits(path, &loaded.header, &recorded, &continuation.fingerprint)?;
        sppm.restore(&loaded.checkpoint)?;
        (seconds_before, resumed_passes) = (loaded.header.seconds, loaded.checkpoint.passes);
        resumed_paths = sppm.backend().emitted_paths()?;
        log::info!("continuing {} from pass {resumed_passes}", path.display());
        output.intermediates.skip_passed(resumed_passes);
    }
    let header = |seconds: f64| Header {
        scene: args.scene.display().to_string(),
        fingerprint: continuation.fingerprint.clone(),
        settings: recorded.clone(),
        adapter: adapter.clone(),
        passes: 0,
        eye_passes: 0,
        seconds,
        words: [0; 4],
    };
    sppm.stop_when_set(continuation.stop.clone());
    if output.guides.is_some() {
        sppm.collect_guides();
    }
    let mut bar = ProgressBar::new(budget);
    let mut save_checkpoint = args.checkpoint.as_deref().map(|path| {
        move |checkpoint: &render::Checkpoint, seconds: f64| {
            let header = header(seconds_before + seconds);
            checkpoint_file::write(path, header, checkpoint).map_err(|e| format!("{e:#}"))
        }
    });
    let moments = output.intermediates.moments();
    let intermediates = &mut output.intermediates;
    let mut save_image = |image: &render::Intermediate| intermediates.save(image, args.look());
    let hooks = RunHooks {
        checkpoints: (save_checkpoint.as_mut()).map(|save| (CHECKPOINT_INTERVAL, save as _)),
        intermediates: (!moments.is_empty()).then_some((moments, &mut save_image as _)),
    };
    let rendered: Rendered = sppm.run_with(budget, &mut |p: &Progress| bar.update(p), hooks)?;
    output.intermediates.warn_unreached();
    bar.finish();
    if let Some(path) = &args.checkpoint {
        let seconds = seconds_before + rendered.seconds;
        checkpoint_file::write(path, header(seconds), &sppm.checkpoint()?)?;
    }
    let host_cpu_seconds = thread_cpu_seconds() - cpu_before;
    output.image.commit(&rendered.image, args.look())?;
    if let Some(components) = output.components {
        for (file, image) in components.into_iter().zip(sppm.component_images()?) {
            file.commit(&image, args.look())?;
        }
    }
    if let (Some([albedo, normal]), Some(guides)) = (output.guides, sppm.guides()) {
        albedo.commit(&guides.albedo(), args.look())?;
        normal.commit(&guides.normal(), args.look())?;
        log::info!("denoising guides from {} eye passes", guides.eye_passes());
    }
    log::info!(
        "{} passes, {} photon paths in {:.2} s",
        rendered.passes,
        rendered.photon_paths,
        rendered.seconds
    );
    if let Some(path) = &args.stats {
        let stats = Stats {
            passes: rendered.passes,
            eye_passes: rendered.eye_passes,
            photon_paths: rendered.photon_paths,
            seconds: rendered.seconds,
            // This run's paths over this run's time (a resumed render's total counts both).
            photon_paths_per_second: (rendered.photon_paths - resumed_paths) as f64
                / rendered.seconds.max(1e-9),
            backend: backend_name,
            adapter,
            host_cpu_seconds,
            integrator: "sppm",
            width: settings.width,
            height: settings.height,
            photon_slots: settings.photons,
            hash_entries: settings.hash_size(),
            alpha: settings.alpha,
            indirect_alpha: settings.indirect_alpha,
            caustic_radius: settings.caustic_radius_share,
            eye_every: settings.eye_every,
            density: settings.density.name(),
            precision: settings.precision.name(),
            direct_light: settings.direct.name(),
            glossy_light: if settings.glossy_light_sampling {
                "sampled"
            } else {
                "lobe"
            },
            light_candidates: settings.light_candidates_for(scene),
            seed: args.seed,
            resumed_passes,
            mean_radiance: rendered.image.mean().to_array(),
            memory_bytes: sppm.backend().memory().into_iter().collect(),
            saved_images: std::mem::take(&mut output.intermediates.saved),
            lens: (!camera.lens.is_pinhole()).then_some(LensStats {
                aperture_radius: camera.lens.radius,
                focus_distance: camera.lens.focus_distance,
                aperture_blades: camera.lens.blades,
                aperture_rotation_degrees: camera.lens.rotation.to_degrees(),
            }),
            denoise_guide_eye_passes: sppm.guides().map(|g| g.eye_passes()),
        };
        let json = serde_json::to_string_pretty(&stats)?;
        crate::output_file::write_atomically(path, json.as_bytes())?;
    }
    if continuation.stop.load(Ordering::Relaxed) {
        return Err(super::Interrupted {
            passes: rendered.passes,
        }
        .into());
    }
    Ok(())
}

/// --passes, --time or the default, checked.
fn budget(args: &RenderArgs) -> anyhow::Result<Budget> {
    Ok(match (args.passes, args.time) {
        (Some(n), _) => Budget::Passes(n),
        (None, Some(t)) => {
            if !(t.is_finite() && t > 0.0 && t < 1e9) {
                bail!("--time must be a positive number of seconds, got {t}");
            }
            Budget::Time(Duration::from_secs_f64(t))
        }
        (None, None) => Budget::Passes(DEFAULT_PASSES),
    })
}

/// The kernels take a 32-bit seed: the 64-bit one folded.
fn fold_seed(seed: u64) -> u32 {
    (seed ^ (seed >> 32)) as u32
}

/// CPU time of the calling thread, in seconds (0 where the platform cannot say).
pub fn thread_cpu_seconds() -> f64 {
    #[cfg(unix)]
    {
        let mut t = libc::timespec {
            tv_sec: 0,
            tv_nsec: 0,
        };
        // SAFETY: clock_gettime writes one timespec through the valid pointer given.
        if unsafe { libc::clock_gettime(libc::CLOCK_THREAD_CPUTIME_ID, &mut t) } == 0 {
            return t.tv_sec as f64 + t.tv_nsec as f64 * 1e-9;
        }
    }
    0.0
}

/// The camera from --eye/--target, --camera I, or the scene's first; `None` when the scene
/// has none and none was asked for: kousen frames the scene itself
/// ([`render::framing::framed_view`], once the BVH is built).
pub fn choose_camera(
    scene: &scene::Scene,
    args: &CameraArgs,
) -> anyhow::Result<Option<scene::Camera>> {
    if let (Some(eye), Some(target)) = (args.eye, args.target) {
        let camera = scene::Camera::look_at(
            Vec3::from(eye),
            Vec3::from(target),
            Vec3::from(args.up),
            args.fov.to_radians(),
        );
        return camera
            .map(Some)
            .context("--eye, --target, --up and --fov do not make a camera (eye equals target, up parallel to the view, or fov not in (0, 180))");
    }
    if scene.cameras.is_empty() && args.camera.is_none() {
        return Ok(None);
    }
    scene.camera(args.camera).map(Some).with_context(|| {
        format!(
            "--camera {}: the scene has {} camera(s)",
            args.camera.unwrap_or(0),
            scene.cameras.len()
        )
    })
}

/// `camera` with the lens of --aperture-radius and --focus-distance (a pinhole without them),
/// focused by default on what the image's centre shows, or with --focus-pixel on what that
/// pixel of an image of `size` shows.
pub fn with_lens(
    camera: scene::Camera,
    args: &CameraArgs,
    bvh: &bvh::PackedBvh,
    size: (u32, u32),
) -> anyhow::Result<scene::Camera> {
    if let Some(radius) = args.aperture_radius
        && !(radius.is_finite() && radius >= 0.0)
    {
        bail!("--aperture-radius {radius}: a lens's radius is a finite number ≥ 0 in scene units");
    }
    if let Some(distance) = args.focus_distance
        && !(distance.is_finite() && distance > 0.0)
    {
        bail!("--focus-distance {distance}: the plane in focus lies a finite distance > 0 ahead");
    }
    if args.focus_distance.is_some() && args.focus_pixel.is_some() {
        bail!("--focus-distance and --focus-pixel both place the plane in focus: give one");
    }
    let Some(radius) = args.aperture_radius.filter(|&r| r > 0.0) else {
        if args.focus_distance.is_some() && args.aperture_radius.is_none() {
            bail!("--focus-distance needs a lens: give --aperture-radius too");
        }
        if args.aperture_blades != 0 && args.aperture_radius.is_none() {
            bail!("--aperture-blades shapes a lens: give --aperture-radius too");
        }
        if args.focus_pixel.is_some() && args.aperture_radius.is_none() {
            bail!("--focus-pixel focuses a lens: give --aperture-radius too");
        }
        return Ok(camera);
    };
    if camera.is_orthographic() {
        bail!(
            "--aperture-radius: camera \"{}\" is orthographic and has no lens (depth of field needs a perspective camera)",
            camera.name
        );
    }
    let focus_distance = match (args.focus_distance, &args.focus_pixel) {
        (Some(distance), _) => distance,
        (None, Some(pixel)) => {
            let (x, y) = parse_pixel(pixel, size)?;
            let (width, height) = (size.0 as f32, size.1 as f32);
            let film = (
                (x as f32 + 0.5) / width * 2.0 - 1.0,
                1.0 - (y as f32 + 0.5) / height * 2.0,
            );
            let distance = render::lens::depth_along_view(bvh, &camera, film, width / height)
                .with_context(|| {
                    format!("--focus-pixel {pixel}: that pixel shows no surface to focus on")
                })?;
            log::info!("lens focused on pixel {x},{y}, {distance:.4} ahead");
            distance
        }
        (None, None) => {
            let distance = render::lens::autofocus(bvh, &camera).context(
                "--aperture-radius: the image's centre shows no surface to focus on; give --focus-distance",
            )?;
            log::info!("lens focused on the image's centre, {distance:.4} ahead");
            distance
        }
    };
    let lens = scene::Lens::new(radius, focus_distance)
        .context("--aperture-radius and --focus-distance do not make a lens")?
        .with_blades(args.aperture_blades, args.aperture_rotation.to_radians())
        .with_context(|| {
            format!(
                "--aperture-blades {} --aperture-rotation {}: an aperture is round (0) or has 3 to {} blades, turned by a finite angle",
                args.aperture_blades,
                args.aperture_rotation,
                scene::Lens::MAX_BLADES
            )
        })?;
    Ok(camera.with_lens(lens))
}

/// --focus-pixel's "x,y", inside an image of `size`.
fn parse_pixel(text: &str, (width, height): (u32, u32)) -> anyhow::Result<(u32, u32)> {
    let values: Result<Vec<u32>, _> = text.split(',').map(|p| p.trim().parse::<u32>()).collect();
    match values {
        Ok(v) if v.len() == 2 && v[0] < width && v[1] < height => Ok((v[0], v[1])),
        _ => bail!(
            "--focus-pixel {text}: expected \"x,y\", whole numbers inside the {width}x{height} image"
        ),
    }
}

/// A flag that the first Ctrl-C sets, so that the render stops after the pass in flight and
/// still writes its image, statistics and checkpoint; a second Ctrl-C exits at once.
fn stop_on_ctrl_c() -> Arc<AtomicBool> {
    let flag = Arc::new(AtomicBool::new(false));
    let set = flag.clone();
    let installed = ctrlc::set_handler(move || {
        if set.swap(true, Ordering::Relaxed) {
            std::process::exit(130);
        }
        eprintln!("kousen: stopping after this pass (Ctrl-C again to quit at once)");
    });
    if let Err(error) = installed {
        log::warn!("Ctrl-C will end the render without saving it: {error}");
    }
    flag
}

#[cfg(test)]
mod tests {
    use super::eye_every_on_cpu_cores;

    #[test]
    fn cpu_eye_passes_thin_out_as_pixels_outnumber_slots() {
        // The measured cases (pixels, default slots) and their best K.
        assert_eq!(eye_every_on_cpu_cores(128 * 128, 65_536), 1);
        assert_eq!(eye_every_on_cpu_cores(512 * 512, 262_144), 4);
        assert_eq!(eye_every_on_cpu_cores(480 * 270, 262_144), 2);
        assert_eq!(eye_every_on_cpu_cores(960 * 540, 262_144), 8);
        // Never beyond every 8th, never less than every pass.
        assert_eq!(eye_every_on_cpu_cores(3840 * 2160, 262_144), 8);
        assert_eq!(eye_every_on_cpu_cores(1, 262_144), 1);
        assert_eq!(eye_every_on_cpu_cores(1000, 0), 8);
    }
}
