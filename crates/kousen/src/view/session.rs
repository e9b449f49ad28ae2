//! The render behind the window: one scene on the GPU backend, restarted whenever the camera,
//! the render size or a setting that shapes the state changes.

use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::{Context, bail};
use gpu::GpuContext;
use gpu::sppm::GpuBackend;
use render::{Backend, Settings, Sppm};

use crate::cli::{AddedLightArgs, BvhArgs};

/// A scene read and its BVH built: the part of opening a file that may run off the window's
/// thread.
pub struct LoadedScene {
    pub path: PathBuf,
    pub scene: scene::Scene,
    pub bvh: bvh::PackedBvh,
}

/// Reads a scene the viewer can render (with `added_lights` added, loaded with `options`: a
/// moment of its animation, a material variant): a known format with at least one light.
pub fn load_scene(
    path: &Path,
    bvh_args: BvhArgs,
    added_lights: &AddedLightArgs,
    options: &scene::LoadOptions,
) -> anyhow::Result<LoadedScene> {
    let mut scene = scene::load_with(path, options)?;
    added_lights.add_to(&mut scene, path)?;
    if scene.lights.is_empty() {
        bail!(
            "{}: the scene has no light (no emissive surface and no glTF punctual light), so the image would be black; --sun X,Y,Z, --sky R,G,B or --sky-map FILE adds one",
            path.display()
        );
    }
    crate::cmd::info::check_bvh_limits(&scene)?;
    let bvh = bvh::PackedBvh::build(&scene.triangles, &crate::cmd::info::build_options(bvh_args));
    Ok(LoadedScene {
        path: path.to_owned(),
        scene,
        bvh,
    })
}

/// What the overlay may change; any change but exposure restarts the render.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RenderControls {
    pub photons: u32,
    pub alpha: f32,
    pub eye_every: u32,
    /// Fixed for the window's life (`--indirect-alpha`, `--radius`, `--caustic-radius`,
    /// `--density`, `--precision`, `--direct-light`, `--glossy-light`).
    pub indirect_alpha: f32,
    pub radius_footprints: f32,
    pub caustic_radius_share: f32,
    pub density: crate::cli::DensityChoice,
    pub precision: render::half_storage::Precision,
    pub direct: render::direct::DirectLight,
    pub glossy_light_sampling: bool,
    /// Light candidates per Lambertian light sample (`--light-candidates`, then the
    /// overlay's slider); 0: auto ([`RenderControls::light_candidates`]).
    pub light_candidates: u32,
    /// The sky map's turn about +Y in degrees (`--sky-rotate`, then the overlay's slider);
    /// `None` when the sky has no map.
    pub sky_rotation: Option<f32>,
    /// The thin lens every view is rendered through (`--aperture-radius`, `--focus-distance`,
    /// then the overlay's sliders and Ctrl+click); a pinhole by default.
    pub lens: scene::Lens,
}

impl RenderControls {
    /// The settings' light candidates: `None` (auto) for the slider's 0.
    pub fn light_candidates(&self) -> Option<u32> {
        (self.light_candidates > 0).then_some(self.light_candidates)
    }
}

/// Figures for the overlay.
#[derive(Clone, Copy, Debug, Default)]
pub struct SessionStats {
    pub passes: u32,
    pub eye_passes: u32,
    pub photon_paths: u64,
    pub seconds: f64,
}

pub struct Session {
    pub scene: scene::Scene,
    pub path: PathBuf,
    /// A CPU copy of the BVH: each restart probes the view for the initial radius.
    bvh: bvh::PackedBvh,
    context: GpuContext,
    sppm: Option<Sppm<GpuBackend>>,
    /// The backend while no render runs (before the first start, after a failed one).
    idle_backend: Option<GpuBackend>,
    started: Instant,
    /// Paths emitted, read now and then (reading waits for the queued passes).
    photon_paths: u64,
}

impl Session {
    /// The scene's first camera, or, when it has none, the view kousen frames it with
    /// (`render::framing`).
    pub fn default_camera(&self) -> scene::Camera {
        self.scene
            .cameras
            .first()
            .cloned()
            .unwrap_or_else(|| render::framing::framed_view(&self.bvh, self.scene.bounds()))
    }

    /// Uploads the scene to `context`'s device and compiles the kernels.
    pub fn new(context: &GpuContext, mut loaded: LoadedScene) -> anyhow::Result<Session> {
        if let Some(note) = gpu::limits::fit_sky_map(&mut loaded.scene.lights, &context.limits) {
            eprintln!("kousen: {note}");
        }
        let backend = GpuBackend::new(context.clone(), &loaded.scene, loaded.bvh.clone())?;
        Ok(Session {
            scene: loaded.scene,
            path: loaded.path,
            bvh: loaded.bvh,
            context: context.clone(),
            sppm: None,
            idle_backend: Some(backend),
            started: Instant::now(),
            photon_paths: 0,
        })
    }

    /// This scene under `map` (scaled by `scale`, turned `rotation` radians) instead of its
    /// sky, uploaded anew (the map's buffer, and kernels compiled with the map's lookups); the
    /// camera's view stays the caller's.
    pub fn with_sky_map(
        &self,
        map: scene::SkyMap,
        scale: glam::Vec3,
        rotation: f32,
    ) -> anyhow::Result<Session> {
        let mut scene = self.scene.clone();
        let sky = scene::Sky::with_map(std::sync::Arc::new(map), scale, rotation, scene.bounds());
        scene.lights.replace_sky(sky);
        let loaded = LoadedScene {
            path: self.path.clone(),
            scene,
            bvh: self.bvh.clone(),
        };
        Session::new(&self.context, loaded)
    }

    /// File name for titles and saved images.
    pub fn name(&self) -> String {
        self.path
            .file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_else(|| "scene".into())
    }

    /// Starts accumulating anew from `camera` at `size`.
    pub fn restart(
        &mut self,
        camera: &scene::Camera,
        size: (u32, u32),
        controls: RenderControls,
    ) -> anyhow::Result<()> {
        let (width, height) = size;
        let settings = Settings {
            alpha: controls.alpha,
            indirect_alpha: controls.indirect_alpha,
            caustic_radius_share: controls.caustic_radius_share,
            eye_every: controls.eye_every,
            density: controls.density.for_view(),
            precision: controls.precision,
            direct: controls.direct,
            glossy_light_sampling: controls.glossy_light_sampling,
            light_candidates: controls.light_candidates(),
            initial_radius: render::integrator::initial_radius_in_footprints(
                &self.bvh,
                camera,
                width,
                height,
                controls.radius_footprints,
            ),
            ..Settings::new(width, height, controls.photons)
        };
        settings.validate()?;
        // The sky's turn travels in the light table that each start builds (the map's buffer
        // does not depend on it), so turning the sky needs no upload.
        if let (Some(degrees), Some(sky)) = (controls.sky_rotation, &mut self.scene.lights.sky) {
            sky.rotation = degrees.to_radians();
        }
        let camera = &camera.clone().with_lens(controls.lens);
        let backend = match (self.sppm.take(), self.idle_backend.take()) {
            (Some(sppm), _) => sppm.into_backend(),
            (None, Some(backend)) => backend,
            // A failed start consumed it: upload the scene again.
            (None, None) => GpuBackend::new(self.context.clone(), &self.scene, self.bvh.clone())?,
        };
        self.sppm = Some(
            Sppm::new(backend, &self.scene, camera, settings).context("cannot start the render")?,
        );
        self.started = Instant::now();
        self.photon_paths = 0;
        Ok(())
    }

    /// How far ahead along the view `camera` sees a surface through film point (sx, sy) of an
    /// image of aspect ratio `aspect` (the distance a lens focused there needs).
    pub fn depth_at(&self, camera: &scene::Camera, film: (f32, f32), aspect: f32) -> Option<f32> {
        render::lens::depth_along_view(&self.bvh, camera, film, aspect)
    }

    /// The lens to start `camera`'s view with: its own, a pinhole focused (should its aperture
    /// be opened) on what the image's centre shows, or half the scene's size ahead.
    pub fn starting_lens(&self, camera: &scene::Camera) -> scene::Lens {
        if !camera.lens.is_pinhole() {
            return camera.lens;
        }
        let focus_distance = render::lens::autofocus(&self.bvh, camera)
            .filter(|d| *d > 0.0)
            .unwrap_or(0.5 * self.scene_size().max(f32::MIN_POSITIVE));
        scene::Lens {
            focus_distance,
            ..scene::Lens::PINHOLE
        }
    }

    /// The length of the scene's bounding-box diagonal: the scale of the lens's sliders.
    pub fn scene_size(&self) -> f32 {
        self.scene.bounds().extent().length()
    }

    pub fn is_running(&self) -> bool {
        self.sppm.is_some()
    }

    /// Queues `passes` SPPM passes and waits for them: the caller times the work.
    pub fn run_passes(&mut self, passes: u32) -> anyhow::Result<()> {
        let Some(sppm) = &mut self.sppm else {
            return Ok(());
        };
        for _ in 0..passes {
            sppm.pass();
        }
        sppm.backend().synchronize()?;
        Ok(())
    }

    /// Reads the emitted-path total (a few words; waits for queued work).
    pub fn refresh_photon_paths(&mut self) -> anyhow::Result<()> {
        if let Some(sppm) = &mut self.sppm {
            self.photon_paths = sppm.backend().emitted_paths()?;
        }
        Ok(())
    }

    pub fn stats(&self) -> SessionStats {
        let Some(sppm) = &self.sppm else {
            return SessionStats::default();
        };
        SessionStats {
            passes: sppm.passes(),
            eye_passes: sppm.eye_passes(),
            photon_paths: self.photon_paths,
            seconds: self.started.elapsed().as_secs_f64(),
        }
    }

    /// The mean gather radius over the pixels that have met photons (reads every pixel's
    /// statistics back: call it rarely).
    pub fn mean_radius(&mut self) -> anyhow::Result<Option<f32>> {
        let Some(sppm) = &mut self.sppm else {
            return Ok(None);
        };
        let stats = sppm.backend().read_statistics()?;
        let lit: Vec<f32> = stats
            .pixels
            .iter()
            .filter(|p| p.photon_count > 0.0)
            .map(|p| p.radius)
            .collect();
        Ok((!lit.is_empty()).then(|| lit.iter().sum::<f32>() / lit.len() as f32))
    }

    /// The image so far, in linear radiance (reads the statistics back).
    /// The image so far in the parts of its radiance `parts` shows.
    pub fn image_of(&mut self, parts: render::resolve::Parts) -> anyhow::Result<render::Image> {
        let sppm = self.sppm.as_mut().context("no render is running")?;
        Ok(sppm.image_of(parts)?)
    }

    /// The backend's accumulation buffers for the display pass, and the eye passes so far.
    pub fn display_source(&self) -> Option<(gpu::display::DisplaySource, u32)> {
        let sppm = self.sppm.as_ref()?;
        Some((sppm.backend_ref().display_source()?, sppm.eye_passes()))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn loaded(scene: scene::Scene) -> LoadedScene {
        let bvh = bvh::PackedBvh::build(&scene.triangles, &bvh::BuildOptions::default());
        LoadedScene {
            path: PathBuf::from("spheres-under-sky-map"),
            scene,
            bvh,
        }
    }

    fn controls(sky_rotation: Option<f32>) -> RenderControls {
        RenderControls {
            photons: 1 << 12,
            alpha: 2.0 / 3.0,
            eye_every: 1,
            indirect_alpha: render::settings::MEASURED_INDIRECT_ALPHA,
            radius_footprints: render::settings::INITIAL_RADIUS_FOOTPRINTS,
            caustic_radius_share: render::settings::MEASURED_CAUSTIC_RADIUS_SHARE,
            density: crate::cli::DensityChoice::Auto,
            precision: render::half_storage::Precision::F32,
            direct: render::direct::DirectLight::Sampled,
            glossy_light_sampling: true,
            light_candidates: 0,
            sky_rotation,
            lens: scene::Lens::PINHOLE,
        }
    }

    /// Three passes from a restart with `controls`, the image's pixels.
    fn render(session: &mut Session, controls: RenderControls) -> Vec<glam::Vec3> {
        let camera = session.default_camera();
        session.restart(&camera, (32, 24), controls).unwrap();
        session.run_passes(3).unwrap();
        session
            .image_of(render::resolve::Parts::ALL)
            .unwrap()
            .pixels
    }

    /// The overlay's sky turn restarts the render under the turned map exactly as a sky turned
    /// when the scene was made (same kernels, seed and light table), and differs from the turn
    /// the scene came with.
    #[test]
    fn turning_the_sky_renders_as_a_sky_turned_at_load() {
        let context = GpuContext::new(None).unwrap_or_else(|e| {
            panic!("no usable GPU adapter in the test environment (CI installs Mesa lavapipe): {e}")
        });
        let scene = scene::testing::spheres_under_sky_map();
        let loaded_turn = scene.lights.sky.as_ref().unwrap().rotation.to_degrees();
        let mut session = Session::new(&context, loaded(scene.clone())).unwrap();
        let as_loaded = render(&mut session, controls(Some(loaded_turn)));
        let turned = render(&mut session, controls(Some(-100.0)));

        let mut made_turned = scene;
        made_turned.lights.sky.as_mut().unwrap().rotation = (-100.0f32).to_radians();
        let mut reference = Session::new(&context, loaded(made_turned)).unwrap();
        assert_eq!(turned, render(&mut reference, controls(None)));
        let changed = turned
            .iter()
            .zip(&as_loaded)
            .filter(|(a, b)| a != b)
            .count();
        assert!(changed > turned.len() / 2, "{changed} pixels changed");
    }

    /// A sky map dropped on the window (`Session::with_sky_map`) renders as the scene loaded
    /// with that map (`--sky-map`), and replaces the sky the scene had.
    #[test]
    fn a_dropped_sky_map_renders_as_one_given_at_load() {
        let context = GpuContext::new(None).unwrap_or_else(|e| {
            panic!("no usable GPU adapter in the test environment (CI installs Mesa lavapipe): {e}")
        });
        let mut uniform = scene::testing::spheres_on_a_floor();
        let bounds = uniform.bounds();
        uniform.lights.set_sky(glam::Vec3::splat(0.7), bounds);
        let session = Session::new(&context, loaded(uniform.clone())).unwrap();
        let map = scene::testing::sunset_sky_map();
        let scale = glam::Vec3::new(1.0, 0.9, 1.1);
        let mut dropped = session.with_sky_map(map.clone(), scale, 0.4).unwrap();
        let with_map = render(&mut dropped, controls(Some(0.4f32.to_degrees())));

        let mut given = uniform;
        let sky = scene::Sky::with_map(std::sync::Arc::new(map), scale, 0.4, bounds);
        given.lights.replace_sky(sky);
        let mut reference = Session::new(&context, loaded(given.clone())).unwrap();
        assert_eq!(with_map, render(&mut reference, controls(None)));
        assert_eq!(dropped.scene.lights, given.lights);
    }
}
