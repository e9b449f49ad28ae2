//! The SPPM pass schedule: an eye pass before every K-th photon pass, and every photon pass
//! followed by the hash build and the gather/update (DESIGN.md step 3). The backend does the
//! work; this decides what runs when, and assembles the image.

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering::Relaxed};
use std::time::{Duration, Instant};

use glam::Vec3;
use scene::{Camera, Scene};

use crate::backend::{Backend, BackendError, Setup};
use crate::buffers::SppmParams;
use crate::emission::light_table_with;
use crate::guides::Guides;
use crate::medium::MediumLocator;
use crate::settings::{Budget, INITIAL_RADIUS_FOOTPRINTS, Settings, SettingsError};
use crate::{Image, resolve};

/// How often the progress callback runs, at most.
const PROGRESS_INTERVAL: Duration = Duration::from_millis(250);

#[derive(Debug, thiserror::Error)]
pub enum RenderError {
    #[error(transparent)]
    Settings(#[from] SettingsError),
    #[error(
        "the scene has no light (no emissive surface and no glTF punctual light), so the image would be black"
    )]
    NoLights,

    #[error(transparent)]
    Backend(#[from] BackendError),
    /// A checkpoint does not fit this render, or could not be written (said in words).
    #[error("{0}")]
    Checkpoint(String),
    /// An image of the render so far could not be written (said in words).
    #[error("{0}")]
    Intermediate(String),
}

/// A render stopped between passes: enough to continue it exactly ([`Sppm::restore`]).
#[derive(Clone, Debug, PartialEq)]
pub struct Checkpoint {
    pub passes: u32,
    pub eye_passes: u32,
    pub state: crate::backend::Snapshot,
}

/// Where [`Sppm::run_with`] hands its checkpoints: every this long, to this function, with
/// this run's rendering time so far in seconds (an error in words stops the render). Like the
/// intermediate images, their reading and writing is left out of the render's clock.
pub type CheckpointSink<'a> = (
    Duration,
    &'a mut dyn FnMut(&Checkpoint, f64) -> Result<(), String>,
);

/// When [`Sppm::run_with`] hands over the image so far: once this many passes are done (a
/// restored render's included), or once this run has rendered this long.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum SaveAt {
    Passes(u32),
    Seconds(f64),
}

/// The image of a render so far, and how far it had come.
#[derive(Debug)]
pub struct Intermediate<'a> {
    pub at: SaveAt,
    pub image: &'a Image,
    pub passes: u32,
    pub eye_passes: u32,
    pub photon_paths: u64,
    /// This run's rendering time so far (images handed over before not counted).
    pub seconds: f64,
}

/// Where [`Sppm::run_with`] hands images of the render so far: at each of these moments, to
/// this function (an error in words stops the render). Their reading and writing is left out
/// of the render's clock, so that `--time` and the seconds reported count rendering only.
pub type IntermediateSink<'a> = (
    Vec<SaveAt>,
    &'a mut dyn FnMut(&Intermediate) -> Result<(), String>,
);

/// What [`Sppm::run_with`] does between passes besides rendering.
#[derive(Default)]
pub struct RunHooks<'a> {
    pub checkpoints: Option<CheckpointSink<'a>>,
    pub intermediates: Option<IntermediateSink<'a>>,
}

/// Where a render stands, for progress bars and logs.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Progress {
    pub passes: u32,
    pub eye_passes: u32,
    pub photon_paths: u64,
    pub elapsed: Duration,
    /// The pass count or time asked for.
    pub budget: Budget,
}

/// A finished render.
#[derive(Clone, Debug)]
pub struct Rendered {
    pub image: Image,
    pub passes: u32,
    pub eye_passes: u32,
    pub photon_paths: u64,
    pub seconds: f64,
}

/// The initial gather radius from the scene's bounding box: [`INITIAL_RADIUS_FOOTPRINTS`] ×
/// its mean side / the image's larger side. The fallback of [`initial_radius_from_view`].
pub fn initial_radius(scene: &Scene, width: u32, height: u32) -> f32 {
    let mean_side = scene.bounds().extent().element_sum() / 3.0;
    INITIAL_RADIUS_FOOTPRINTS * mean_side / width.max(height) as f32
}

/// Camera rays cast to size the initial radius (a grid of this many per side).
const RADIUS_PROBES: u32 = 32;

/// The initial gather radius from what the camera sees, glslppm's rule: [`INITIAL_RADIUS_FOOTPRINTS`]
/// × the mean side of the bounding box of the first surfaces seen / the image's larger side.
/// On glslppm's Cornell scene at 512² this is its 0.038; a camera seeing a small part of a
/// large scene gets a radius fitted to that part. `None` if every probe ray misses.
pub fn initial_radius_from_view(
    bvh: &bvh::PackedBvh,
    camera: &Camera,
    width: u32,
    height: u32,
) -> Option<f32> {
    initial_radius_in_footprints(bvh, camera, width, height, INITIAL_RADIUS_FOOTPRINTS)
}

/// [`initial_radius_from_view`] with `footprints` pixel footprints instead of glslppm's 2.5.
pub fn initial_radius_in_footprints(
    bvh: &bvh::PackedBvh,
    camera: &Camera,
    width: u32,
    height: u32,
    footprints: f32,
) -> Option<f32> {
    let aspect = width as f32 / height as f32;
    let mut bounds = scene::Bounds::EMPTY;
    for j in 0..RADIUS_PROBES {
        for i in 0..RADIUS_PROBES {
            let sx = (i as f32 + 0.5) / RADIUS_PROBES as f32 * 2.0 - 1.0;
            let sy = 1.0 - (j as f32 + 0.5) / RADIUS_PROBES as f32 * 2.0;
            let (origin, direction) = camera.ray(sx, sy, aspect);
            let ray = bvh::Ray {
                origin,
                direction,
                t_max: f32::INFINITY,
            };
            if let Some(hit) = bvh::closest_hit_mtbvh(bvh, &ray) {
                bounds = bounds.grow(ray.origin + hit.t * ray.direction);
            }
        }
    }
    if bounds.is_empty() {
        return None;
    }
    let mean_side = bounds.extent().element_sum() / 3.0;
    let radius = footprints * mean_side / width.max(height) as f32;
    (radius > 0.0 && radius.is_finite()).then_some(radius)
}

/// The render-wide constants for a scene, camera and settings.
pub fn params(scene: &Scene, camera: &Camera, settings: &Settings, lights: u32) -> SppmParams {
    params_with(scene, camera, settings, lights, &MediumLocator::new(scene))
}

/// [`params`] with the scene's `locator` built already (one build serves a render).
pub fn params_with(
    scene: &Scene,
    camera: &Camera,
    settings: &Settings,
    lights: u32,
    locator: &MediumLocator,
) -> SppmParams {
    let aspect = settings.width as f32 / settings.height as f32;
    let (right, up) = camera.film_half_extents(aspect);
    SppmParams {
        eye: camera.eye.to_array(),
        width: settings.width,
        forward: camera.forward.to_array(),
        height: settings.height,
        right: right.to_array(),
        slot_count: settings.photons,
        up: up.to_array(),
        hash_size: settings.hash_size(),
        alpha: settings.alpha,
        max_depth: settings.max_depth,
        light_count: lights,
        seed: settings.seed,
        epsilon: 1e-5 * scene.bounds().extent().length().max(1e-3),
        storage_origin: scene.bounds().center().to_array(),
        storage_flux_scale: 1.0,
        sky: scene
            .lights
            .sky
            .as_ref()
            .map_or(Vec3::ZERO, |s| s.radiance)
            .to_array(),
        sample_lights: settings.direct.flag()
            | if settings.glossy_light_sampling {
                crate::buffers::SAMPLE_AT_GLOSSY
            } else {
                0
            },
        cut_outs: scene
            .materials
            .iter()
            .any(|m| m.alpha_mode != scene::AlphaMode::Opaque) as u32,
        eye_every: settings.eye_every,
        indirect_alpha: settings.indirect_alpha,
        // Eye paths start where the camera is: under water, say.
        camera_medium: locator.medium_at(camera.eye),
        photon_classes: crate::hash::classes_for(
            scene.materials.iter().any(|m| m.dispersion > 0.0),
            settings.density == crate::Density::StochasticHash,
            settings.photons,
        ),
        lens_radius: camera.lens.radius,
        focus_distance: camera.lens.focus_distance,
        scene_half_extent: (0.5 * 1.01 * scene.bounds().extent()).to_array(),
        aperture_blades: camera.lens.blades,
        aperture_rotation: camera.lens.rotation,
        light_candidates: settings.light_candidates_for(scene),
        orthographic: camera.is_orthographic() as u32,
        shrunk_tenths: match settings.density {
            crate::Density::StochasticHash => crate::radius_histogram::STOCHASTIC_SHRUNK_TENTHS,
            _ => 0,
        },
    }
}

/// The phases of an SPPM iteration, in the order they run.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Phase {
    Eye,
    Photons,
    Hash,
    Gather,
}

/// The integrator: a backend started on one scene, camera and settings.
pub struct Sppm<B: Backend> {
    backend: B,
    settings: Settings,
    passes: u32,
    eye_passes: u32,
    /// Set from outside (Ctrl-C) to end the run after the pass in flight.
    stop: Option<Arc<AtomicBool>>,
    /// Denoising guides gathered from the eye passes, where asked for ([`Sppm::collect_guides`]).
    guides: Option<Guides>,
}

impl<B: Backend> Sppm<B> {
    pub fn new(
        mut backend: B,
        scene: &Scene,
        camera: &Camera,
        settings: Settings,
    ) -> Result<Sppm<B>, RenderError> {
        settings.validate()?;
        let locator = MediumLocator::new(scene);
        let lights = light_table_with(scene, &locator);
        if lights.is_empty() {
            return Err(RenderError::NoLights);
        }
        let radius = settings
            .initial_radius
            .unwrap_or_else(|| initial_radius(scene, settings.width, settings.height));
        let setup = Setup {
            params: SppmParams {
                storage_flux_scale: crate::half_storage::flux_scale(&lights),
                ..params_with(scene, camera, &settings, lights.len() as u32, &locator)
            },
            lights,
            initial_radius: radius,
            initial_caustic_radius: radius * settings.caustic_radius_share,
            initial_volume_radius: crate::scattering::initial_volume_radius(scene, radius),
            density: settings.density,
            precision: settings.precision,
        };
        backend.start(&setup)?;
        Ok(Sppm {
            backend,
            settings,
            passes: 0,
            eye_passes: 0,
            stop: None,
            guides: None,
        })
    }

    /// Makes [`Sppm::run`] and [`Sppm::run_with`] gather the denoising guides (each pixel's
    /// albedo and normal, [`crate::guides`]) from the eye passes they run.
    pub fn collect_guides(&mut self) {
        let (width, height) = (self.settings.width, self.settings.height);
        self.guides = Some(Guides::new(width, height));
    }

    /// The denoising guides gathered so far, where [`Sppm::collect_guides`] asked for them.
    pub fn guides(&self) -> Option<&Guides> {
        self.guides.as_ref()
    }

    /// Adds the last eye pass's visible points to the guides, where they want more.
    fn add_to_guides(&mut self) -> Result<(), RenderError> {
        if let Some(guides) = self.guides.as_mut().filter(|g| g.wants_more()) {
            guides.add(&self.backend.read_visible_points()?);
        }
        Ok(())
    }

    /// Ends [`Sppm::run`] and [`Sppm::run_with`] after the pass in flight once
    /// `flag` is set (by a Ctrl-C handler), as if the budget were spent: the image and the
    /// last checkpoint are whole.
    pub fn stop_when_set(&mut self, flag: Arc<AtomicBool>) {
        self.stop = Some(flag);
    }

    pub fn backend(&mut self) -> &mut B {
        &mut self.backend
    }

    pub fn backend_ref(&self) -> &B {
        &self.backend
    }

    /// The backend back, to start another render on the same scene (a new camera, say).
    pub fn into_backend(self) -> B {
        self.backend
    }

    pub fn settings(&self) -> &Settings {
        &self.settings
    }

    /// One SPPM iteration: the eye pass when due, a photon pass, the hash, the gather.
    pub fn pass(&mut self) {
        self.pass_phases(|_, _| {});
    }

    /// [`Sppm::pass`], calling `after` with the backend once each phase has been asked for
    /// (benchmarks synchronise there to time each kernel).
    pub fn pass_phases(&mut self, mut after: impl FnMut(&mut B, Phase)) {
        if self.passes.is_multiple_of(self.settings.eye_every) {
            self.backend.eye_pass();
            self.eye_passes += 1;
            after(&mut self.backend, Phase::Eye);
        }
        self.backend.photon_pass();
        after(&mut self.backend, Phase::Photons);
        self.backend.build_hash();
        after(&mut self.backend, Phase::Hash);
        self.backend.gather();
        after(&mut self.backend, Phase::Gather);
        self.passes += 1;
    }

    /// Runs passes until the budget is spent (a pass budget counts the passes of a restored
    /// render too), calling `progress` now and then.
    pub fn run(
        &mut self,
        budget: Budget,
        progress: &mut dyn FnMut(&Progress),
    ) -> Result<Rendered, RenderError> {
        self.run_with(budget, progress, RunHooks::default())
    }

    /// [`Sppm::run`], handing a [`Checkpoint`] to `hooks.checkpoints` every interval of
    /// rendering and the image so far to `hooks.intermediates` at each of its moments (both
    /// between passes); an error from either stops the render.
    pub fn run_with(
        &mut self,
        budget: Budget,
        progress: &mut dyn FnMut(&Progress),
        hooks: RunHooks,
    ) -> Result<Rendered, RenderError> {
        let RunHooks {
            mut checkpoints,
            mut intermediates,
        } = hooks;
        let started = Instant::now();
        // Time spent handing over intermediate images and checkpoints, left out of the
        // render's clock.
        let mut handing_over = Duration::ZERO;
        let rendering = |handing_over: Duration| started.elapsed().saturating_sub(handing_over);
        let mut last_report = started;
        let mut last_checkpoint = started;
        loop {
            let done = match budget {
                Budget::Passes(n) => self.passes >= n,
                Budget::Time(t) => rendering(handing_over) >= t,
            };
            let stopped = self.stop.as_ref().is_some_and(|flag| flag.load(Relaxed));
            if done || stopped {
                break;
            }
            let eye_passes = self.eye_passes;
            self.pass();
            if self.eye_passes > eye_passes {
                self.add_to_guides()?;
            }
            if let Some((moments, save)) = intermediates.as_mut() {
                let since = Instant::now();
                let seconds = rendering(handing_over).as_secs_f64();
                self.hand_over_due(moments, &mut **save, seconds)?;
                handing_over += since.elapsed();
            }
            if let Some((interval, save)) = checkpoints.as_mut()
                && last_checkpoint.elapsed() >= *interval
            {
                let since = Instant::now();
                last_checkpoint = since;
                let seconds = rendering(handing_over).as_secs_f64();
                save(&self.checkpoint()?, seconds).map_err(RenderError::Checkpoint)?;
                handing_over += since.elapsed();
            }
            if last_report.elapsed() >= PROGRESS_INTERVAL {
                last_report = Instant::now();
                progress(&Progress {
                    passes: self.passes,
                    eye_passes: self.eye_passes,
                    photon_paths: self.backend.emitted_paths()?,
                    elapsed: rendering(handing_over),
                    budget,
                });
            }
        }
        self.backend.synchronize()?;
        let seconds = rendering(handing_over).as_secs_f64();
        let image = self.image()?;
        let photon_paths = self.backend.emitted_paths()?;
        progress(&Progress {
            passes: self.passes,
            eye_passes: self.eye_passes,
            photon_paths,
            elapsed: rendering(handing_over),
            budget,
        });
        Ok(Rendered {
            image,
            passes: self.passes,
            eye_passes: self.eye_passes,
            photon_paths,
            seconds,
        })
    }

    /// Hands the image so far to `save` for each of `moments` reached, after `seconds` of
    /// rendering, and drops them from the list (one image serves all reached at once).
    fn hand_over_due(
        &mut self,
        moments: &mut Vec<SaveAt>,
        save: &mut dyn FnMut(&Intermediate) -> Result<(), String>,
        seconds: f64,
    ) -> Result<(), RenderError> {
        let reached = |at: &SaveAt| match *at {
            SaveAt::Passes(n) => self.passes >= n,
            SaveAt::Seconds(s) => seconds >= s,
        };
        let due: Vec<SaveAt> = moments.iter().copied().filter(reached).collect();
        if due.is_empty() {
            return Ok(());
        }
        moments.retain(|at| !reached(at));
        let image = self.image()?;
        let photon_paths = self.backend.emitted_paths()?;
        for at in due {
            save(&Intermediate {
                at,
                image: &image,
                passes: self.passes,
                eye_passes: self.eye_passes,
                photon_paths,
                seconds,
            })
            .map_err(RenderError::Intermediate)?;
        }
        Ok(())
    }

    /// The image so far: every pixel's radiance.
    pub fn image(&mut self) -> Result<Image, RenderError> {
        self.image_of(resolve::Parts::ALL)
    }

    /// The image so far in the parts of its radiance `parts` shows.
    pub fn image_of(&mut self, parts: resolve::Parts) -> Result<Image, RenderError> {
        let stats = self.backend.read_statistics()?;
        Ok(resolve::resolve_shown(
            &stats.pixels,
            (self.settings.width, self.settings.height),
            self.eye_passes,
            stats.emitted_paths,
            parts,
        ))
    }

    /// The image so far by part of its radiance ([`resolve::COMPONENTS`]: direct, indirect,
    /// caustic, volume), which sum to [`Sppm::image`]'s pixels.
    pub fn component_images(&mut self) -> Result<[Image; 4], RenderError> {
        let stats = self.backend.read_statistics()?;
        Ok(resolve::resolve_component_images(
            &stats.pixels,
            self.settings.width,
            self.settings.height,
            self.eye_passes,
            stats.emitted_paths,
        ))
    }

    pub fn passes(&self) -> u32 {
        self.passes
    }

    /// The render so far, to continue later (waits for the work queued).
    pub fn checkpoint(&mut self) -> Result<Checkpoint, RenderError> {
        Ok(Checkpoint {
            passes: self.passes,
            eye_passes: self.eye_passes,
            state: self.backend.snapshot()?,
        })
    }

    /// Continues from `checkpoint`, taken of a render with the same scene, camera and
    /// settings: the passes that follow are those the interrupted render would have run.
    pub fn restore(&mut self, checkpoint: &Checkpoint) -> Result<(), RenderError> {
        self.backend.restore(&checkpoint.state)?;
        self.passes = checkpoint.passes;
        self.eye_passes = checkpoint.eye_passes;
        Ok(())
    }

    pub fn eye_passes(&self) -> u32 {
        self.eye_passes
    }
}

/// Camera ray direction through film point (sx, sy) ∈ [−1, 1]², +y up, as the eye kernels
/// make it (a perspective camera's; an orthographic one's rays all go along the view,
/// `crate::lens::camera_ray`).
pub fn camera_direction(params: &SppmParams, sx: f32, sy: f32) -> Vec3 {
    (Vec3::from_array(params.forward)
        + sx * Vec3::from_array(params.right)
        + sy * Vec3::from_array(params.up))
    .normalize()
}
