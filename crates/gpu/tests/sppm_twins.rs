//! The SPPM kernels (`sppm/*.wgsl`) against their CPU twins (`cpu::kernels`), which draw the
//! same random numbers, so the two agree element by element up to float rounding (GPU sin, cos,
//! sqrt and fused multiply-adds). Rounding may flip a branch (Russian roulette, Fresnel choice,
//! a hash cell) and send one path elsewhere, so a small share of elements may differ: the share
//! is stated per comparison ([`MAX_DIVERGED`], [`MAX_HASH_DIVERGED`]) and asserted, and every
//! other element must match within tight tolerances. Runs on whatever adapter wgpu finds
//! (lavapipe in CI), so the sizes are small.
//!
//! - `first_pass_matches_the_cpu_backend`: both backends from scratch, one pass then four;
//! - `every_kernel_matches_its_twin_on_the_gpu_state`: each kernel's twin run on the GPU's own
//!   input, pass after pass, so no divergence carries over;
//! - `resolved_images_match_after_eight_passes`: the images of both backends, same seed;
//! - `gpu_and_cpu_renders_differ_by_no_more_than_their_noise`: different seeds, the Cornell box.
//! - `a_scene_past_the_binding_limit_renders_from_texels`: the storage fallback of
//!   `gpu::scene_upload::fitting_storage`, end to end;
//! - `photon_walks_in_murky_glass_match_their_twin`: the photon pass on slots restored inside
//!   murky glass, where every walk keeps volume photons.

use std::fmt::Debug;
use std::sync::atomic::{AtomicU32, Ordering::Relaxed};

use bvh::{BuildOptions, PackedBvh};
use cpu::{CpuBackend, SceneData, kernels};
use gpu::GpuContext;
use gpu::sppm::GpuBackend;
use render::buffers::{
    HASH_ENTRY_WORDS, LIGHT_DIRECTIONAL, LIGHT_POINT, LIGHT_SKY, LIGHT_SPOT, LIGHT_TRIANGLE,
    PathSlot, Photon, PixelStats, SLOT_IDLE, SppmParams, VisiblePoint, counter, vec3,
};
use render::direct::DirectLight;
use render::packing::{is_volume, unpack_normal};
use render::volume_boundary::unpack_depths;
use render::{Backend, Image, Settings, Sppm, Statistics};
use scene::{Camera, Scene};

/// Share of elements (pixels, slots) allowed to differ beyond the tolerances: a branch flipped
/// by rounding.
const MAX_DIVERGED: f64 = 0.005;
/// Share of the filled hash entries allowed to differ between the two backends (a photon a
/// rounding apart lands in another cell). This holds only if no cell boundary lies on a plane
/// the scene's photons crowd onto: with boundaries at coordinate 0 (an unshifted grid) and the
/// Cornell floor at y = 0, a floor photon's y comes out 0 or −6e-5 by one rounding (the GPU
/// fuses `origin + t · direction`), and 40% of the filled entries differ.
const MAX_HASH_DIVERGED: f64 = 0.001;
/// Positions: absolute, × the scene's diagonal.
const POSITION_TOLERANCE: f32 = 1e-4;
/// Unit directions: absolute.
const DIRECTION_TOLERANCE: f32 = 1e-4;
/// Fluxes, weights and statistics: relative.
const RELATIVE_TOLERANCE: f32 = 1e-4;
/// The direct sums of pixels that see a sky map, relative: a bilinear lookup turns the
/// direction's map coordinates into radiance continuously, and Vulkan lets atan2 and acos err
/// by 4096 ulp (~2.4e-4 of the angle), which on the fixture's 32-wide map with 12 % between
/// neighbouring texels moves the radiance up to ~5e-4.
const SKY_MAP_DIRECT_TOLERANCE: f32 = 2e-3;
/// Packed normals that differ must still agree to this cosine.
const NORMAL_COSINE: f32 = 0.999;

fn context() -> GpuContext {
    GpuContext::new(None).unwrap_or_else(|e| {
        panic!("no usable GPU adapter in the test environment (CI installs Mesa lavapipe): {e}")
    })
}

struct Fixture {
    scene: Scene,
    bvh: PackedBvh,
    camera: Camera,
    /// The length of the scene's bounding-box diagonal: the scale of positions.
    diagonal: f32,
}

impl Fixture {
    fn new(scene: Scene) -> Fixture {
        let bvh = PackedBvh::build(&scene.triangles, &BuildOptions::default());
        let camera = scene.camera(None).expect("the test scene has a camera");
        let diagonal = scene.bounds().extent().length();
        Fixture {
            scene,
            bvh,
            camera,
            diagonal,
        }
    }

    fn gpu(&self, context: GpuContext, settings: &Settings) -> Sppm<GpuBackend> {
        let backend = GpuBackend::new(context, &self.scene, self.bvh.clone()).expect("gpu backend");
        Sppm::new(backend, &self.scene, &self.camera, settings.clone()).expect("gpu render")
    }

    fn cpu(&self, settings: &Settings) -> Sppm<CpuBackend> {
        let backend = CpuBackend::new(self.scene_data());
        Sppm::new(backend, &self.scene, &self.camera, settings.clone()).expect("cpu render")
    }

    fn scene_data(&self) -> SceneData {
        SceneData::new(&self.scene, self.bvh.clone())
    }

    fn params(&self, settings: &Settings) -> SppmParams {
        let lights = render::emission::light_table(&self.scene).len() as u32;
        render::integrator::params(&self.scene, &self.camera, settings, lights)
    }
}

// ---- element comparisons: each field's error as a multiple of its tolerance ----

/// 0 when equal, infinite otherwise.
fn exact<T: PartialEq>(a: T, b: T) -> f32 {
    if a == b { 0.0 } else { f32::INFINITY }
}

/// Largest absolute component difference / `tolerance`.
fn absolute(a: [f32; 3], b: [f32; 3], tolerance: f32) -> f32 {
    (vec3(a) - vec3(b)).abs().max_element() / tolerance
}

/// Largest component difference relative to the larger vector's largest component.
fn relative(a: [f32; 3], b: [f32; 3]) -> f32 {
    relative_within(a, b, RELATIVE_TOLERANCE)
}

fn relative_within(a: [f32; 3], b: [f32; 3], tolerance: f32) -> f32 {
    let scale = vec3(a).abs().max(vec3(b).abs()).max_element();
    if scale == 0.0 {
        return 0.0;
    }
    absolute(a, b, tolerance * scale)
}

fn relative_scalar(a: f32, b: f32) -> f32 {
    relative([a, 0.0, 0.0], [b, 0.0, 0.0])
}

/// Packed normals: equal bits, or unit normals whose cosine is at least [`NORMAL_COSINE`].
fn normal(a: u32, b: u32) -> f32 {
    if a == b {
        return 0.0;
    }
    let cosine = unpack_normal(a).dot(unpack_normal(b));
    (1.0 - cosine).max(0.0) / (1.0 - NORMAL_COSINE)
}

fn point_errors(g: &VisiblePoint, c: &VisiblePoint, diagonal: f32) -> Vec<(&'static str, f32)> {
    if !(g.is_valid() && c.is_valid()) {
        return vec![("valid", exact(g.is_valid(), c.is_valid()))];
    }
    vec![
        (
            "position",
            absolute(g.position, c.position, POSITION_TOLERANCE * diagonal),
        ),
        ("normal", normal(g.normal, c.normal)),
        ("weight", relative(g.weight, c.weight)),
        ("boundary depths", boundary_depths(g.pad, c.pad, diagonal)),
    ]
}

/// A volume visible point's depths below its medium's surfaces (`render::volume_boundary`):
/// both words without them, or each depth within the positions' tolerance and a bfloat16 step.
fn boundary_depths(g: u32, c: u32, diagonal: f32) -> f32 {
    match (unpack_depths(g), unpack_depths(c)) {
        (None, None) => 0.0,
        (Some((g_behind, g_ahead)), Some((c_behind, c_ahead))) => {
            [(g_behind, c_behind), (g_ahead, c_ahead)]
                .into_iter()
                .map(|(g, c)| (g - c).abs() / (POSITION_TOLERANCE * diagonal + g.max(c) / 64.0))
                .fold(0.0, f32::max)
        }
        _ => f32::INFINITY,
    }
}

fn photon_errors(g: &Photon, c: &Photon, diagonal: f32) -> Vec<(&'static str, f32)> {
    if !(g.is_stored() && c.is_stored()) {
        return vec![("stored", exact(g.is_stored(), c.is_stored()))];
    }
    vec![
        (
            "position",
            absolute(g.position, c.position, POSITION_TOLERANCE * diagonal),
        ),
        ("normal", normal(g.normal, c.normal)),
        ("flux", relative(g.flux, c.flux)),
    ]
}

fn slot_errors(g: &PathSlot, c: &PathSlot, diagonal: f32) -> Vec<(&'static str, f32)> {
    vec![
        ("depth", exact(g.depth, c.depth)),
        ("pass_throughs", exact(g.pass_throughs, c.pass_throughs)),
        ("state", exact(g.state, c.state)),
        (
            "origin",
            absolute(g.origin, c.origin, POSITION_TOLERANCE * diagonal),
        ),
        (
            "direction",
            absolute(g.direction, c.direction, DIRECTION_TOLERANCE),
        ),
        ("flux", relative(g.flux, c.flux)),
        ("walk_hero", exact(g.walk_hero, c.walk_hero)),
        (
            "walk_densities",
            relative(g.walk_densities, c.walk_densities),
        ),
    ]
}

fn stats_errors(g: &PixelStats, c: &PixelStats) -> Vec<(&'static str, f32)> {
    stats_errors_within(g, c, RELATIVE_TOLERANCE)
}

/// [`stats_errors`] with the direct sums compared within `direct_tolerance`.
fn stats_errors_within(
    g: &PixelStats,
    c: &PixelStats,
    direct_tolerance: f32,
) -> Vec<(&'static str, f32)> {
    vec![
        ("tau", relative(g.tau, c.tau)),
        (
            "photon_count",
            relative_scalar(g.photon_count, c.photon_count),
        ),
        (
            "direct",
            relative_within(g.direct, c.direct, direct_tolerance),
        ),
        ("radius", relative_scalar(g.radius, c.radius)),
        ("caustic_tau", relative(g.caustic_tau, c.caustic_tau)),
        (
            "caustic_count",
            relative_scalar(g.caustic_count, c.caustic_count),
        ),
        (
            "caustic_radius",
            relative_scalar(g.caustic_radius, c.caustic_radius),
        ),
        (
            "specular_seen",
            (g.specular_seen != c.specular_seen) as u32 as f32,
        ),
        ("volume_tau", relative(g.volume_tau, c.volume_tau)),
        (
            "volume_count",
            relative_scalar(g.volume_count, c.volume_count),
        ),
        (
            "volume_radius",
            relative_scalar(g.volume_radius, c.volume_radius),
        ),
    ]
}

/// (priority, count, winner) of every hash entry.
fn hash_entries(words: &[u32]) -> Vec<Entry> {
    words
        .chunks_exact(HASH_ENTRY_WORDS)
        .map(|e| e.try_into().expect("whole entries"))
        .collect()
}

/// The entries filled in either table (most of a table is empty, and empty entries agree).
type Entry = [u32; HASH_ENTRY_WORDS];
fn filled_entries(a: &[Entry], b: &[Entry]) -> (Vec<Entry>, Vec<Entry>) {
    a.iter()
        .zip(b)
        .filter(|(a, b)| a[1] > 0 || b[1] > 0)
        .map(|(a, b)| (*a, *b))
        .unzip()
}

/// Element-by-element comparison of a GPU array with its twin.
struct Comparison {
    what: String,
    elements: usize,
    diverged: usize,
    /// The first few elements that differ, described.
    examples: Vec<String>,
    /// Per field, the largest error (× tolerance) among the elements that match.
    worst: Vec<(&'static str, f32)>,
}

impl Comparison {
    fn new<T: Debug>(
        what: impl Into<String>,
        gpu: &[T],
        cpu: &[T],
        errors: impl Fn(&T, &T) -> Vec<(&'static str, f32)>,
    ) -> Comparison {
        let what = what.into();
        assert_eq!(gpu.len(), cpu.len(), "{what}: lengths");
        let mut comparison = Comparison {
            what,
            elements: gpu.len(),
            diverged: 0,
            examples: Vec::new(),
            worst: Vec::new(),
        };
        for (i, (g, c)) in gpu.iter().zip(cpu).enumerate() {
            let errors = errors(g, c);
            let bad: Vec<&str> = errors
                .iter()
                .filter(|(_, e)| e.is_nan() || *e > 1.0)
                .map(|(f, _)| *f)
                .collect();
            if bad.is_empty() {
                for (field, e) in errors {
                    match comparison.worst.iter_mut().find(|(f, _)| *f == field) {
                        Some((_, w)) => *w = w.max(e),
                        None => comparison.worst.push((field, e)),
                    }
                }
            } else {
                comparison.diverged += 1;
                if comparison.examples.len() < 3 {
                    comparison
                        .examples
                        .push(format!("[{i}] {bad:?}: gpu {g:?}, cpu {c:?}"));
                }
            }
        }
        eprintln!("{}", comparison.summary());
        comparison
    }

    fn fraction(&self) -> f64 {
        self.diverged as f64 / self.elements.max(1) as f64
    }

    fn summary(&self) -> String {
        let worst: Vec<String> = self
            .worst
            .iter()
            .map(|(f, w)| format!("{f} {w:.3}"))
            .collect();
        format!(
            "{}: {} of {} differ ({:.3}%); worst matching error × tolerance: {}{}",
            self.what,
            self.diverged,
            self.elements,
            100.0 * self.fraction(),
            worst.join(", "),
            if self.examples.is_empty() {
                String::new()
            } else {
                format!("; first: {}", self.examples.join("; "))
            }
        )
    }

    fn assert_at_most(&self, fraction: f64) {
        assert!(
            self.fraction() <= fraction,
            "more than {:.2}% differ: {}",
            100.0 * fraction,
            self.summary()
        );
    }
}

fn atomics(words: &[u32]) -> Vec<AtomicU32> {
    words.iter().map(|&w| AtomicU32::new(w)).collect()
}

fn loads(words: &[AtomicU32]) -> Vec<u32> {
    words.iter().map(|w| w.load(Relaxed)).collect()
}

fn emitted(counters: &[u32]) -> u64 {
    ((counters[counter::EMITTED_HI] as u64) << 32) | counters[counter::EMITTED_LO] as u64
}

/// relMSE = mean((a − b)² / (b² + 0.01)) over pixels and channels, b the reference (as
/// `kousen diff`).
fn rel_mse(a: &Image, b: &Image) -> f64 {
    assert_eq!((a.width, a.height), (b.width, b.height));
    let sum: f64 = a
        .pixels
        .iter()
        .zip(&b.pixels)
        .flat_map(|(a, b)| a.to_array().into_iter().zip(b.to_array()))
        .map(|(a, b)| (a as f64 - b as f64).powi(2) / ((b as f64).powi(2) + 0.01))
        .sum();
    sum / (3 * a.pixels.len()) as f64
}

/// mean(a) / mean(b) over all channels.
fn mean_ratio(a: &Image, b: &Image) -> f64 {
    let sum = |i: &Image| i.mean().as_dvec3().element_sum();
    sum(a) / sum(b)
}

/// After both backends' first pass from idle slots: the GPU's photons and slots against the
/// CPU backend's, and the CPU backend's against its kernel run on idle slots.
fn assert_first_photon_pass_matches(
    fixture: &Fixture,
    settings: &Settings,
    g: &mut Sppm<GpuBackend>,
    c: &mut Sppm<CpuBackend>,
) {
    let d = fixture.diagonal;
    let gpu_photons = g.backend().read_photons().expect("photons");
    let cpu_photons = c.backend().photons().to_vec();
    let stored = cpu_photons.iter().filter(|p| p.is_stored()).count();
    assert!(stored > cpu_photons.len() / 4, "{stored} photons stored");
    Comparison::new("photon_pass photons", &gpu_photons, &cpu_photons, |g, c| {
        photon_errors(g, c, d)
    })
    .assert_at_most(MAX_DIVERGED);

    // The CPU backend has no slot accessor: its slots are its kernel's on idle slots.
    let data = fixture.scene_data();
    let params = fixture.params(settings);
    let twin: Vec<_> = (0..params.slot_count)
        .map(|i| kernels::photon_pass(&data, &params, 0, i, PathSlot::IDLE))
        .collect();
    assert!(
        twin.iter().zip(&cpu_photons).all(|(t, p)| t.photon == *p),
        "the CPU backend's photons are not its kernel's"
    );
    let cpu_slots: Vec<PathSlot> = twin.iter().map(|t| t.slot).collect();
    let continuing = cpu_slots.iter().filter(|s| s.depth != SLOT_IDLE).count();
    assert!(continuing > cpu_slots.len() / 4, "{continuing} paths go on");
    let gpu_slots = g.backend().read_slots().expect("slots");
    Comparison::new("photon_pass slots", &gpu_slots, &cpu_slots, |g, c| {
        slot_errors(g, c, d)
    })
    .assert_at_most(MAX_DIVERGED);
}

/// Both backends' pixel statistics, compared; returned for further checks.
fn assert_statistics_match(
    what: &str,
    g: &mut Sppm<GpuBackend>,
    c: &mut Sppm<CpuBackend>,
) -> (Statistics, Statistics) {
    let gpu_stats = g.backend().read_statistics().expect("statistics");
    let cpu_stats = c.backend().read_statistics().expect("statistics");
    Comparison::new(what, &gpu_stats.pixels, &cpu_stats.pixels, stats_errors)
        .assert_at_most(MAX_DIVERGED);
    (gpu_stats, cpu_stats)
}

fn caustics_settings() -> Settings {
    Settings {
        seed: 3,
        ..Settings::new(32, 32, 4096)
    }
}

#[test]
fn first_pass_matches_the_cpu_backend() {
    let fixture = Fixture::new(scene::testing::cornell_caustics());
    let settings = caustics_settings();
    let mut g = fixture.gpu(context(), &settings);
    let mut c = fixture.cpu(&settings);
    g.pass();
    c.pass();
    let d = fixture.diagonal;

    let gpu_points = g.backend().read_visible_points().expect("visible points");
    let cpu_points = c.backend().visible_points().to_vec();
    let valid = cpu_points.iter().filter(|p| p.is_valid()).count();
    assert!(valid > cpu_points.len() / 2, "{valid} visible points");
    Comparison::new(
        "eye_pass visible points",
        &gpu_points,
        &cpu_points,
        |g, c| point_errors(g, c, d),
    )
    .assert_at_most(MAX_DIVERGED);

    assert_first_photon_pass_matches(&fixture, &settings, &mut g, &mut c);

    let gpu_counters = g.backend().counters().expect("counters");
    let cpu_counters = c.backend().counters();
    assert_eq!(gpu_counters, cpu_counters, "counters after the first pass");
    assert_eq!(gpu_counters[counter::PASS], 1);
    assert_eq!(emitted(&gpu_counters), settings.photons as u64);

    let gpu_hash = hash_entries(&g.backend().read_hash().expect("hash"));
    let cpu_hash = hash_entries(&c.backend().hash_words());
    let (gpu_hash, cpu_hash) = filled_entries(&gpu_hash, &cpu_hash);
    assert!(
        cpu_hash.len() > 100,
        "{} hash entries filled",
        cpu_hash.len()
    );
    Comparison::new("hash entries filled", &gpu_hash, &cpu_hash, |g, c| {
        vec![("entry", exact(g, c))]
    })
    .assert_at_most(MAX_HASH_DIVERGED);

    assert_statistics_match("pixel statistics after 1 pass", &mut g, &mut c);

    // A few passes more: paths continue from the slots past specular bounces, radii shrink.
    for _ in 0..3 {
        g.pass();
        c.pass();
    }
    let (gpu_stats, cpu_stats) =
        assert_statistics_match("pixel statistics after 4 passes", &mut g, &mut c);
    assert_eq!(
        gpu_stats.emitted_paths, cpu_stats.emitted_paths,
        "paths emitted in 4 passes"
    );
    let gpu_counters = g.backend().counters().expect("counters");
    assert_eq!(gpu_counters[counter::PASS], 4);
    assert_eq!(
        gpu_counters[counter::CELL_SIZE],
        c.backend().counters()[counter::CELL_SIZE],
        "cell size after 4 passes"
    );
}

/// `--caustic-radius`: both backends start every pixel's caustic radius at its share of the
/// indirect one, and the statistics stay twins while the two radii shrink apart.
#[test]
fn caustic_radii_start_at_their_share_on_both_backends() {
    let fixture = Fixture::new(scene::testing::cornell_caustics());
    let settings = Settings {
        caustic_radius_share: 0.5,
        direct: DirectLight::Sampled,
        ..caustics_settings()
    };
    let mut g = fixture.gpu(context(), &settings);
    let mut c = fixture.cpu(&settings);
    let (gpu_start, cpu_start) = assert_statistics_match("statistics at the start", &mut g, &mut c);
    assert_eq!(gpu_start.pixels, cpu_start.pixels);
    for stats in &gpu_start.pixels {
        assert!(stats.radius > 0.0);
        assert_eq!(stats.caustic_radius, 0.5 * stats.radius);
    }
    for _ in 0..4 {
        g.pass();
        c.pass();
    }
    let (_, cpu_stats) = assert_statistics_match("statistics after 4 passes", &mut g, &mut c);
    let caustic_pixels = cpu_stats
        .pixels
        .iter()
        .filter(|s| s.caustic_count > 0.0)
        .count();
    assert!(
        caustic_pixels > 10,
        "{caustic_pixels} pixels met caustic photons"
    );
}

/// Point, spot and directional lights (glTF `KHR_lights_punctual`) and a sky besides the
/// Cornell box's own, and two spots more with pbrt's and Mitsuba's falloffs
/// (`scene::SpotFalloff`): the first pass's emission (and first bounce) on the GPU against
/// the CPU twin, and the pixels' statistics (the sky seen past the box's edges in the direct
/// term).
#[test]
fn punctual_lights_emit_like_their_cpu_twin() {
    let mut scene = scene::testing::cornell_box_punctual();
    let bounds = scene.bounds();
    for (falloff, x) in [
        (scene::SpotFalloff::Smoothstep, 150.0),
        (scene::SpotFalloff::LinearAngle, 300.0),
    ] {
        let spot = scene::PunctualLight {
            kind: scene::PunctualKind::Spot {
                cos_inner: 15f32.to_radians().cos(),
                cos_outer: 40f32.to_radians().cos(),
                falloff,
            },
            position: glam::Vec3::new(x, 520.0, 250.0),
            direction: glam::Vec3::new(0.1, -1.0, 0.1).normalize(),
            intensity: glam::Vec3::splat(40_000.0),
        };
        scene.lights.add_punctual(spot, bounds);
    }
    let fixture = Fixture::new(scene);
    let lights = render::emission::light_table(&fixture.scene);
    let kinds: Vec<u32> = lights.iter().map(|l| l.kind).collect();
    for kind in [
        LIGHT_TRIANGLE,
        LIGHT_POINT,
        LIGHT_SPOT,
        LIGHT_DIRECTIONAL,
        LIGHT_SKY,
    ] {
        assert!(kinds.contains(&kind), "no light of kind {kind}: {kinds:?}");
    }
    // With sampled direct light the eye pass also samples every kind of light.
    for direct in [DirectLight::Photons, DirectLight::Sampled] {
        let settings = Settings {
            direct,
            ..caustics_settings()
        };
        let mut g = fixture.gpu(context(), &settings);
        let mut c = fixture.cpu(&settings);
        g.pass();
        c.pass();
        match direct {
            DirectLight::Photons => {
                assert_first_photon_pass_matches(&fixture, &settings, &mut g, &mut c)
            }
            // First hits store nothing: that light is sampled. The second pass stores.
            DirectLight::Sampled => {
                let photons = g.backend().read_photons().expect("photons");
                assert!(photons.iter().all(|p| !p.is_stored()), "a first hit stored");
                g.pass();
                c.pass();
            }
        }
        assert_statistics_match(
            &format!("pixel statistics, {} direct light", direct.name()),
            &mut g,
            &mut c,
        );
    }
}

/// Each kernel's twin run on the GPU's own state before the pass, pass after pass: the photon
/// pass on the GPU's slots, the hash on the GPU's photons, the gather on the GPU's hash,
/// photons and visible points, `finish_pass` on the counters. Divergences cannot carry over
/// from one pass or kernel to the next, so these agree more tightly than two whole renders.
#[test]
fn every_kernel_matches_its_twin_on_the_gpu_state() {
    every_kernel_matches_its_twin(scene::testing::cornell_caustics(), DirectLight::Photons);
}

/// The same with light sampled at the visible points: the eye pass's light samples and shadow
/// rays in the direct sums, and photons stored from their second hit on.
#[test]
fn every_kernel_matches_its_twin_with_sampled_direct_light() {
    every_kernel_matches_its_twin(scene::testing::cornell_caustics(), DirectLight::Sampled);
}

/// The same with the scene in storage buffers, as on GPUs (on a CPU-type adapter, the CI's
/// lavapipe, the other tests read it from texels).
#[test]
fn every_kernel_matches_its_twin_with_the_scene_in_buffers() {
    let mut context = context();
    context.scene_storage = gpu::SceneStorage::Buffers;
    every_kernel_matches_its_twin_on(
        context,
        scene::testing::cornell_caustics(),
        DirectLight::Sampled,
    );
}

/// A scene whose threaded records are past the adapter's storage binding (224 bytes a node in
/// one binding; simulated by lowering the limit) renders from texels instead of failing, and
/// gives the image the texels give when chosen outright (the two storages render alike).
#[test]
fn a_scene_past_the_binding_limit_renders_from_texels() {
    let fixture = Fixture::new(scene::testing::cornell_caustics());
    let settings = Settings {
        seed: 5,
        ..Settings::new(4, 4, 64)
    };
    let records = fixture.bvh.nodes.len() as u64 * (bvh::DIRECTION_COUNT as u64 + 1) * 32;
    let mut cramped = context();
    cramped.scene_storage = gpu::SceneStorage::Buffers;
    cramped.limits.max_storage_buffer_binding_size = records - 1;
    let materials = fixture.scene.materials.len();
    let refused = gpu::scene_upload::check_scene_fits(
        &fixture.bvh,
        materials,
        &cramped.limits,
        cramped.scene_storage,
    );
    assert!(
        refused.is_err(),
        "the lowered limit must refuse the records in buffers"
    );
    let mut fallen_back = fixture.gpu(cramped, &settings);
    let mut chosen = context();
    chosen.scene_storage = gpu::SceneStorage::Texels;
    let mut texels = fixture.gpu(chosen, &settings);
    for _ in 0..3 {
        fallen_back.pass();
        texels.pass();
    }
    let a = fallen_back.image().expect("image");
    let b = texels.image().expect("image");
    assert!(
        a.pixels.iter().any(|p| p.max_element() > 0.0),
        "a lit image"
    );
    assert_eq!(a.pixels, b.pixels);
}

/// Tangents past the adapter's binding limit are dropped (warned about), not refused: the
/// kernels then take the triangles' texture frames, as for the same scene without tangents.
#[test]
fn tangents_past_the_binding_limit_fall_back_to_texture_frames() {
    let with_tangents = Fixture::new(scene::testing::cornell_bumpy());
    let mut stripped = scene::testing::cornell_bumpy();
    for v in stripped.triangles.iter_mut().flat_map(|t| &mut t.vertices) {
        v.tangent = glam::Vec4::ZERO;
    }
    let without = Fixture::new(stripped);
    let settings = Settings {
        seed: 3,
        ..Settings::new(8, 8, 256)
    };
    let tangent_bytes = with_tangents.bvh.triangles.len() as u64 * 3 * 16;
    let cramped = || {
        let mut context = context();
        context.scene_storage = gpu::SceneStorage::Texels;
        context.limits.max_storage_buffer_binding_size = tangent_bytes - 1;
        context
    };
    let mut dropped = with_tangents.gpu(cramped(), &settings);
    let mut plain = without.gpu(cramped(), &settings);
    for _ in 0..3 {
        dropped.pass();
        plain.pass();
    }
    let a = dropped.image().expect("image");
    assert!(
        a.pixels.iter().any(|p| p.max_element() > 0.0),
        "a lit image"
    );
    assert_eq!(a.pixels, plain.image().expect("image").pixels);
}

/// The same through rough metal: eye and photon paths draw GGX micro-normals
/// (`render::microfacet` and its WGSL twin), carry their shadowing weights and take the
/// metal's Fresnel reflectance at each micro-normal (`render::conductor`), one sphere's
/// rising to white at grazing angles, the other's by a different share in each channel.
#[test]
fn every_kernel_matches_its_twin_through_rough_metal() {
    let mut scene = scene::testing::cornell_rough();
    let silver = (scene.materials.iter_mut()).find(|m| m.name.contains("silver"));
    silver.expect("a silver sphere").metal_edge = glam::Vec3::new(0.0, 0.5, 1.0);
    every_kernel_matches_its_twin(scene, DirectLight::Sampled);
}

/// The same through frosted glass (`render::microfacet::rough_dielectric`): micro-normals,
/// then reflection or refraction by their Fresnel reflectance with a third number; one
/// sphere made a thin-walled sheet, so both kinds are compared.
#[test]
fn every_kernel_matches_its_twin_through_frosted_glass() {
    let mut scene = scene::testing::cornell_frosted();
    let sheets = scene
        .materials
        .iter_mut()
        .filter_map(|m| match &mut m.surface {
            scene::Surface::RoughDielectric {
                thin_walled, alpha, ..
            } if *alpha > 0.2 => {
                *thin_walled = true;
                Some(())
            }
            _ => None,
        })
        .count();
    assert_eq!(sheets, 1, "the milky sphere made a sheet");
    every_kernel_matches_its_twin(scene, DirectLight::Sampled);
}

/// The same through tinted glass: Beer–Lambert absorption over the segments that run inside
/// the solid spheres (`cpu::surface::transmittance_to` and its WGSL twin), smooth and rough.
#[test]
fn every_kernel_matches_its_twin_through_absorbing_glass() {
    every_kernel_matches_its_twin(scene::testing::cornell_tinted(), DirectLight::Sampled);
}

/// The same under tinted water (`scene::testing::cornell_pool`): the medium a path is in
/// (`render::medium`) absorbs over segments that end at the floor, the walls and the sphere
/// under the surface, photon slots carry it from pass to pass in their state word, and eye
/// paths' light samples and glass probes take theirs.
#[test]
fn every_kernel_matches_its_twin_under_tinted_water() {
    every_kernel_matches_its_twin(scene::testing::cornell_pool(), DirectLight::Sampled);
}

/// The same with the lamp and the camera inside the water (`scene::testing::underwater_lamp`):
/// photon slots start in the light's medium (`Light::medium`), eye paths in the camera's
/// (`SppmParams::camera_medium`), which sees the plane and, above, the water's surface from
/// beneath. Photons carry the lamp's direct light here, so that the plane stores some.
#[test]
fn every_kernel_matches_its_twin_with_the_lamp_and_camera_under_water() {
    let scene = scene::testing::underwater_lamp();
    let lights = render::emission::light_table(&scene);
    assert!(
        lights.iter().all(|l| l.medium == 1),
        "the lamp is in the water"
    );
    every_kernel_matches_its_twin(scene, DirectLight::Photons);
}

/// The same through a thin lens (`scene::Lens`, `render::lens::camera_ray`), round and
/// hexagonal (`render::sampling::aperture_point`): eye paths start across the aperture, the
/// first of each pixel from `pixel_lens`, the extra paths of pixels showing glass (the second
/// eye pass here) from the pixel's stream.
#[test]
fn every_kernel_matches_its_twin_through_a_thin_lens() {
    for blades in [0, 6] {
        let mut scene = scene::testing::cornell_caustics();
        let diagonal = scene.bounds().extent().length();
        let camera = scene.cameras[0].clone();
        let focus = camera.eye.distance(scene.bounds().center());
        let lens = scene::Lens::new(0.03 * diagonal, focus)
            .and_then(|l| l.with_blades(blades, 0.4))
            .expect("a lens");
        scene.cameras[0] = camera.with_lens(lens);
        every_kernel_matches_its_twin(scene, DirectLight::Sampled);
    }
}

/// The same seen by an orthographic camera (`scene::Projection`, `render::lens::camera_ray`):
/// every eye path leaves its own film point, along the view.
#[test]
fn every_kernel_matches_its_twin_through_an_orthographic_camera() {
    let mut scene = scene::testing::cornell_caustics();
    let half_height = 0.45 * scene.bounds().extent().y;
    let camera = scene.cameras[0].clone().orthographic(half_height);
    scene.cameras[0] = camera.expect("an orthographic camera");
    every_kernel_matches_its_twin(scene, DirectLight::Sampled);
}

/// The same with a glass marble under the tinted water (`scene::testing::cornell_marble`):
/// indices relative to the water (`render::nesting`, uploaded as the CPU backend holds them),
/// and paths leaving the marble in the water again (`GpuMaterial::exterior`).
#[test]
fn every_kernel_matches_its_twin_with_a_marble_under_water() {
    every_kernel_matches_its_twin(scene::testing::cornell_marble(), DirectLight::Sampled);
}

/// The same with the underwater lamp shining through an invisible marble
/// (`scene::testing::underwater_lamp_with_marble`), photons carrying its direct light.
#[test]
fn every_kernel_matches_its_twin_through_a_marble_around_the_lamp() {
    every_kernel_matches_its_twin(
        scene::testing::underwater_lamp_with_marble(),
        DirectLight::Photons,
    );
}

/// The same through dispersive glass (`scene::testing::cornell_dispersion`: the spot light's
/// caustic through flint): paths carrying the whole spectrum keep one wavelength at the glass,
/// drawn with one more number, and refract with its index there and after
/// (`render::dispersion`, WGSL `dispersed_material`); photons and eye paths alike.
#[test]
fn every_kernel_matches_its_twin_through_dispersive_glass() {
    every_kernel_matches_its_twin(scene::testing::cornell_dispersion(), DirectLight::Sampled);
}

/// The same with the flint frosted (GGX α 0.2): each wavelength's index serves the
/// micro-normals' refraction and, in eye paths, the frosted lobe's light samples.
#[test]
fn every_kernel_matches_its_twin_through_frosted_dispersive_glass() {
    let mut scene = scene::testing::cornell_dispersion();
    for material in scene.materials.iter_mut().filter(|m| m.dispersion > 0.0) {
        let scene::Surface::Dielectric { ior, thin_walled } = material.surface else {
            panic!("cornell_dispersion's flint is smooth glass");
        };
        material.surface = scene::Surface::RoughDielectric {
            ior,
            thin_walled,
            alpha: 0.2,
        };
    }
    every_kernel_matches_its_twin(scene, DirectLight::Sampled);
}

/// The same through a dispersive blend: cornell-blended's sphere of 60 % glass and 40 %
/// plastic made of flint's dispersion (every member carries it; only the glass member
/// disperses, and only there is a wavelength drawn).
#[test]
fn every_kernel_matches_its_twin_through_a_dispersive_blend() {
    let mut scene = scene::testing::cornell_blended();
    let glass = (scene.materials.iter())
        .position(|m| matches!(m.surface, scene::Surface::Dielectric { .. }))
        .expect("cornell_blended has a glass member");
    let dispersion = scene::dispersion_from_abbe(1.5, 25.0);
    let mut root = (0..scene.materials.len())
        .find(|&id| {
            scene.materials[id]
                .blend
                .is_some_and(|b| b.other as usize == glass)
        })
        .unwrap_or(glass);
    loop {
        scene.materials[root].dispersion = dispersion;
        match scene.materials[root].blend {
            Some(blend) => root = blend.other as usize,
            None => break,
        }
    }
    assert!(scene.materials[glass].dispersion > 0.0);
    every_kernel_matches_its_twin(scene, DirectLight::Sampled);
}

/// The same inside a mixture of whole materials of their own colours (pbrt's `mix`, Mitsuba's
/// `blendbsdf`: `scene::testing::furnace_sphere_mixed`, a mirror of one tint and a diffuse
/// surface of another): each kernel reads the member it draws, colour and all.
#[test]
fn every_kernel_matches_its_twin_in_a_mixture_of_whole_materials() {
    let scene = scene::testing::furnace_sphere_mixed();
    let colours: Vec<_> = scene.materials.iter().map(|m| m.base_color).collect();
    assert!(colours.windows(2).any(|c| c[0] != c[1]), "{colours:?}");
    every_kernel_matches_its_twin(scene, DirectLight::Sampled);
}

/// The same with normal maps (`render::normal_map` and its WGSL twin) on the tiled floor and
/// back wall, a diffuse sphere and a mirror one: bent shading normals in every kernel, and
/// the photons' shading-normal weights where they land and bounce.
#[test]
fn every_kernel_matches_its_twin_with_normal_maps() {
    every_kernel_matches_its_twin(scene::testing::cornell_bumpy(), DirectLight::Sampled);
}

/// The same where Veach's correction would pass its bound for many photons
/// (`render::normal_map::MAX_SHADING_CORRECTION` and its WGSL twin): every vertex normal of
/// the normal-mapped box leaned 40° from its triangle, each its own way, so that photons
/// arriving at a low geometric cosine meet a steep shading one wherever they land or bounce.
/// Direct light by photons: it is the photons this checks, and light samples at visible
/// points this steep flip at the shading horizon by a rounding (as eye paths do at 48°).
/// With the bound left out of the WGSL bounce, 0.61 % of the slots differ here (the limit is
/// 0.5 %) where the other twins all pass; left out where photons land, it is not caught:
/// too few photons land with an arrival factor above 4 (the next test's do: 48.5 % of its
/// photons differ without it, and 16.4 % of its slots without the bound at the bounce).
#[test]
fn every_kernel_matches_its_twin_with_steep_vertex_normals() {
    let mut scene = scene::testing::cornell_bumpy();
    for (t, triangle) in scene.triangles.iter_mut().enumerate() {
        let normal = triangle.geometric_normal_unnormalized().normalize();
        let (u, v) = normal.any_orthonormal_pair();
        for (k, vertex) in triangle.vertices.iter_mut().enumerate() {
            let angle = (3 * t + k) as f32 * 2.4;
            let lean = u * angle.cos() + v * angle.sin();
            vertex.normal = (normal + 40f32.to_radians().tan() * lean).normalize();
        }
    }
    every_kernel_matches_its_twin(scene, DirectLight::Photons);
}

/// The same where every photon lands past the bound: a diffuse square lit only by a
/// directional light 5° above its horizon, its vertex normals leaned 40° towards the light,
/// so that each photon arrives at a geometric cosine of 0.087 and a shading one of 0.71
/// (Veach's arrival factor 8.1, bounded at 4 where it lands, and with the departure's at
/// its bounce: `render::normal_map::MAX_SHADING_CORRECTION`). The bound left out where
/// photons land in the WGSL is what [`every_kernel_matches_its_twin_with_steep_vertex_normals`]
/// cannot see; here every stored photon landing first differs without it (48.5 % of the
/// slots' photons), and 16.4 % of the slots without the bound at the bounce.
#[test]
fn every_kernel_matches_its_twin_where_photons_land_past_the_shading_bound() {
    let elevation = 5f32.to_radians();
    let mut scene = scene::testing::punctual_plane(&[scene::PunctualLight {
        kind: scene::PunctualKind::Directional,
        position: glam::Vec3::ZERO,
        direction: glam::Vec3::new(-elevation.cos(), -elevation.sin(), 0.0),
        intensity: glam::Vec3::splat(3.0),
    }]);
    let leaned = glam::Vec3::new(40f32.to_radians().tan(), 1.0, 0.0).normalize();
    for triangle in &mut scene.triangles {
        for vertex in &mut triangle.vertices {
            vertex.normal = leaned;
        }
    }
    let arriving = glam::Vec3::new(elevation.cos(), elevation.sin(), 0.0);
    let factor = arriving.dot(leaned) / arriving.y;
    assert!(
        factor > 2.0 * render::normal_map::MAX_SHADING_CORRECTION,
        "{factor}"
    );
    every_kernel_matches_its_twin(scene, DirectLight::Photons);
}

/// The same through plastic (`render::plastic` and its WGSL twin): a smooth coat on the floor
/// and one sphere, a rough one on the other; Fresnel chooses coat or base, photons land with
/// the coat's transmittance, light samples pass it, a rough coat's base carries its weight.
#[test]
fn every_kernel_matches_its_twin_through_plastic() {
    every_kernel_matches_its_twin(scene::testing::cornell_plastic(), DirectLight::Sampled);
}

/// The same under clear coats (`render::clearcoat` and its WGSL twin): a smooth coat over
/// a Lambertian floor, a rough one over rough metal, a smooth one over a blend; the coat
/// reflects or lets through, photons it reflects are not kept, light samples and bounces pass
/// it.
#[test]
fn every_kernel_matches_its_twin_under_clear_coats() {
    every_kernel_matches_its_twin(scene::testing::cornell_clearcoat(), DirectLight::Sampled);
}

/// The same with the floor's coat textured (`render::clearcoat::clearcoat_at`): a checker of
/// weight 0.2 or 1 (red) and roughness 0.3 or 1 times a factor of 0.4 (green), so that hits
/// meet a smooth or a rough coat of either weight; the floor beneath is normal-mapped (dimples),
/// which the coat does not follow (`SurfaceHit::interpolated`).
#[test]
fn every_kernel_matches_its_twin_under_textured_clear_coats() {
    let mut scene = scene::testing::cornell_clearcoat();
    let texture = push_checker(&mut scene, "coat checker", |x, y| {
        let weight = if (x + y) % 2 == 0 { 0.2 } else { 1.0 };
        let roughness = if y < CHECKER_SIDE / 2 { 0.3 } else { 1.0 };
        [weight, roughness, 0.0, 1.0]
    });
    let floor = (scene.materials.iter())
        .position(|m| m.name == "coated white")
        .expect("the coated floor") as u32;
    let coat = scene.materials[floor as usize].clearcoat.as_mut().unwrap();
    *coat = scene::Clearcoat {
        weight_texture: Some(texture),
        roughness_texture: Some(texture),
        ..scene::Clearcoat::new(1.0, 0.4).unwrap()
    };
    let dimples = scene.textures.len() as u32;
    scene.textures.push(scene::testing::dimple_normal_map(32));
    scene.materials[floor as usize].normal_texture = Some(dimples);
    for triangle in scene.triangles.iter_mut().filter(|t| t.material == floor) {
        for v in &mut triangle.vertices {
            v.uv = glam::Vec2::new(v.position.x, v.position.z) / 140.0;
        }
    }
    every_kernel_matches_its_twin(scene, DirectLight::Sampled);
}

/// The same with the floor's coat following a normal map of its own (dimples,
/// `scene::Clearcoat::normal_texture`) over the plain Lambertian floor: the coat's choice, its
/// reflection and its transmittance for light samples and bounces take the bent normal.
#[test]
fn every_kernel_matches_its_twin_under_a_normal_mapped_clear_coat() {
    let mut scene = scene::testing::cornell_clearcoat();
    let floor = (scene.materials.iter())
        .position(|m| m.name == "coated white")
        .expect("the coated floor") as u32;
    let dimples = scene.textures.len() as u32;
    scene.textures.push(scene::testing::dimple_normal_map(32));
    let coat = scene.materials[floor as usize].clearcoat.as_mut().unwrap();
    coat.normal_texture = Some(dimples);
    coat.normal_scale = 0.8;
    for triangle in scene.triangles.iter_mut().filter(|t| t.material == floor) {
        for v in &mut triangle.vertices {
            v.uv = glam::Vec2::new(v.position.x, v.position.z) / 140.0;
        }
    }
    every_kernel_matches_its_twin(scene, DirectLight::Sampled);
}

/// The same under sheens (`render::sheen` and its WGSL twin): velvet over a Lambertian base,
/// and a sheen over rough plastic under half a clear coat; the sheen reflects or lets through,
/// photons it reflects are not kept, its reflection takes a light sample for its own lobe, and
/// light samples and bounces beneath pass it.
#[test]
fn every_kernel_matches_its_twin_under_sheens() {
    every_kernel_matches_its_twin(scene::testing::cornell_sheen(), DirectLight::Sampled);
}

/// The same with the velvet's sheen colour and roughness textured (`render::sheen::SheenAt::
/// new`): a checker of white and dark blue, its alpha (the roughness) 1 or 0.4 in bands across
/// it, so that hits meet sheens of different colour, strength and width (the grid's tables);
/// the white room wears the same textured sheen.
#[test]
fn every_kernel_matches_its_twin_under_textured_sheens() {
    let mut scene = scene::testing::cornell_sheen();
    let texture = push_checker(&mut scene, "sheen checker", |x, y| {
        let roughness = if y % 4 < 2 { 1.0 } else { 0.15 };
        match (x + y) % 2 {
            0 => [1.0, 1.0, 1.0, roughness],
            _ => [0.1, 0.2, 0.6, roughness],
        }
    });
    let velvet = (scene.materials.iter())
        .position(|m| m.name == "red velvet")
        .expect("the velvet") as usize;
    let sheen = scene.materials[velvet].sheen.as_mut().unwrap();
    sheen.color_texture = Some(texture);
    sheen.roughness_texture = Some(texture);
    // The white room too, so that most photons and eye paths meet a textured sheen.
    let white = (scene.materials.iter())
        .position(|m| m.name == "white")
        .expect("the white walls");
    scene.materials[white].sheen = Some(scene::Sheen {
        color_texture: Some(texture),
        roughness_texture: Some(texture),
        ..scene::Sheen::new(glam::Vec3::splat(0.6), 1.0).unwrap()
    });
    planar_uv(&mut scene, &[velvet, white]);
    every_kernel_matches_its_twin(scene, DirectLight::Sampled);
}

/// The same with a white sheen on `cornell-caustics`'s solid glass sphere: the sheen meets
/// paths arriving from outside and not those inside the glass (`cpu::surface::sheen_faces`).
#[test]
fn every_kernel_matches_its_twin_with_a_sheen_on_glass() {
    let mut scene = scene::testing::cornell_caustics();
    let glass = (scene.materials.iter())
        .position(|m| m.surface.is_solid_dielectric())
        .expect("the glass sphere");
    scene.materials[glass].sheen = scene::Sheen::new(glam::Vec3::ONE, 0.3);
    every_kernel_matches_its_twin(scene, DirectLight::Sampled);
}

/// The same with glTF's diffuse transmission (`scene::DiffuseTransmission`, `cpu::surface::
/// lambertian_side` and its WGSL twin) on `cornell_sheen`'s spheres: the velvet's Lambertian
/// base lets 60 % through tinted orange; the layered plastic's base a share and tint read from
/// a checker (strength in its alpha), beneath its sheen and clear coat. Photons and eye paths
/// pass to the spheres' insides and back, the visible points' side follows each pixel's
/// number, and light samples are taken on the far side.
#[test]
fn every_kernel_matches_its_twin_through_diffuse_transmission() {
    let mut scene = scene::testing::cornell_sheen();
    let texture = push_checker(&mut scene, "transmission checker", |x, y| {
        match (x + y) % 2 {
            0 => [1.0, 1.0, 1.0, 0.9],
            _ => [0.2, 0.9, 0.4, if y % 4 < 2 { 0.0 } else { 0.5 }],
        }
    });
    let named = |name: &str| (scene.materials.iter()).position(|m| m.name.contains(name));
    let (velvet, layered) = (named("velvet").unwrap(), named("plastic").unwrap());
    scene.materials[velvet].diffuse_transmission =
        scene::DiffuseTransmission::new(0.6, glam::Vec3::new(1.0, 0.6, 0.2));
    scene.materials[layered].diffuse_transmission = Some(scene::DiffuseTransmission {
        texture: Some(texture),
        color_texture: Some(texture),
        ..scene::DiffuseTransmission::new(1.0, glam::Vec3::splat(0.9)).unwrap()
    });
    planar_uv(&mut scene, &[layered]);
    every_kernel_matches_its_twin(scene, DirectLight::Sampled);
}

/// The same in translucent solids (`scene::testing::cornell_translucent_solids`: diffuse
/// transmission bounding absorbing volumes, `scene::DiffuseTransmission::volume`): photons and
/// eye paths passing a surface go inside and absorb there until they pass out, the lamp's
/// photons start inside the wax (its medium found by `render::medium::MediumLocator`), and
/// light samples from a surface's inside run through the solid.
#[test]
fn every_kernel_matches_its_twin_in_translucent_solids() {
    let scene = scene::testing::cornell_translucent_solids();
    every_kernel_matches_its_twin(scene, DirectLight::Sampled);
}

/// The same in murky glass (`scene::testing::furnace_with_murky_glass`: a smooth ball of
/// index 1.33 scattering σs = (4, 2, 1) inside, g = 0.5, in the furnace; `render::scattering`):
/// photon walks keep one volume photon a step by one more number at each scattering event,
/// the slot idles where the walk's roulette ends it, eye paths entering the ball draw a walk
/// and a flight and end where they scatter, at volume visible points carrying their medium's
/// asymmetry in their word, which gather the volume photons in a sphere weighed by the phase
/// function, shrinking their radius by the cube root. With a diffuse core inside the ball,
/// walks that reach it land a surface photon too, and the slot keeps one of the two by one
/// more number; eye paths inside end there or where they scatter.
#[test]
fn every_kernel_matches_its_twin_in_murky_glass() {
    let furnace =
        || scene::testing::furnace_with_murky_glass(glam::Vec3::new(4.0, 2.0, 1.0), 0.5, 1.33);
    for (scene, direct) in [
        (furnace(), DirectLight::Photons),
        (with_diffuse_core(furnace()), DirectLight::Sampled),
    ] {
        let seen = every_kernel_matches_its_twin(scene, direct);
        assert!(seen.volume_points > 100, "{seen:?}");
        assert!(seen.volume_photons > 300, "{seen:?}");
        assert!(seen.volume_lit_pixels > 100, "{seen:?}");
    }
}

/// The same in a Mitsuba file's murky medium (`scenes/mitsuba/cornell-murky.xml`, read by
/// `scene::media`), inside its BK7 ball and, as a `null` boundary makes it, inside glass of
/// index 1 that light crosses unbent (fog).
#[test]
fn every_kernel_matches_its_twin_in_a_mitsuba_file_s_medium() {
    let scene = shipped("mitsuba/cornell-murky.xml");
    let mut fog = scene.clone();
    for material in fog.materials.iter_mut().filter(|m| m.has_murky_glass()) {
        material.surface = scene::Surface::Dielectric {
            ior: 1.0,
            thin_walled: false,
        };
    }
    for scene in [scene, fog] {
        let seen = every_kernel_matches_its_twin(scene, DirectLight::Sampled);
        assert!(seen.volume_points > 20, "{seen:?}");
    }
}

/// The same in an atmosphere (`scenes/mitsuba/cornell-fog.xml`: the sensor's medium, no shape
/// bounding it, fills all space outside the solids): eye paths start in it, photons of the
/// panel and the spot start in it, walks go on where a ray leaves the room through its open
/// front (a flight on an endless segment: it scatters on the way or leaves, keeping its volume
/// photon), the ball's inside is clear glass and its outside the fog again. The fog thinned
/// to a quarter, so that enough of the twins' 32² pixels see the ball through it.
#[test]
fn every_kernel_matches_its_twin_in_an_atmosphere() {
    let mut scene = shipped("mitsuba/cornell-fog.xml");
    let air = &mut scene.materials[scene.atmosphere.expect("an atmosphere") as usize];
    air.absorption *= 0.25;
    air.scattering *= 0.25;
    let seen = every_kernel_matches_its_twin(scene, DirectLight::Sampled);
    assert!(seen.volume_points > 100, "{seen:?}");
    assert!(seen.volume_photons > 100, "{seen:?}");
    assert!(seen.volume_lit_pixels > 50, "{seen:?}");
}

/// The same in `scene::testing::cornell_murky`: milky quartz and murky water that absorb as
/// they scatter, under the ceiling light, their volume visible points among the room's.
#[test]
fn every_kernel_matches_its_twin_in_the_murky_cornell_box() {
    let seen = every_kernel_matches_its_twin(scene::testing::cornell_murky(), DirectLight::Sampled);
    assert!(seen.volume_points > 20, "{seen:?}");
    assert!(seen.volume_photons > 100, "{seen:?}");
    assert!(seen.volume_lit_pixels > 20, "{seen:?}");
}

/// The photon pass on slots that all walk in murky glass: [`with_diffuse_core`]'s ball, each
/// slot restored into the GPU's state halfway between the core and the glass, going some way,
/// so that walks keep volume photons at every step, their roulette ends many, and many reach
/// the core, where the slot keeps the volume photon or the landed one by one more number. The
/// twin in the furnace meets these too rarely to notice a wrong draw (dropping that number
/// left it passing); here each such slot would differ. Two slots in three carry a walk from
/// earlier steps (a hero and skewed densities), which goes on without a new hero.
#[test]
fn photon_walks_in_murky_glass_match_their_twin() {
    let scene = scene::testing::furnace_with_murky_glass(glam::Vec3::new(4.0, 2.0, 1.0), 0.5, 1.33);
    let fixture = Fixture::new(with_diffuse_core(scene));
    let glass = (fixture.scene.materials.iter())
        .position(|m| m.has_murky_glass())
        .expect("murky glass");
    let ball = (fixture.scene.triangles.iter())
        .filter(|t| t.material as usize == glass)
        .flat_map(|t| t.positions())
        .fold(scene::Bounds::EMPTY, |b, p| b.grow(p));
    let (centre, radius) = (ball.center(), 0.5 * ball.extent().x);
    let settings = caustics_settings();
    let params = fixture.params(&settings);
    let mut g = fixture.gpu(context(), &settings);
    let direction = |i: u32, k: u32| {
        let z = 2.0 * unit(i, k) - 1.0;
        let phi = std::f32::consts::TAU * unit(i, k + 1);
        let r = (1.0 - z * z).max(0.0).sqrt();
        glam::Vec3::new(r * phi.cos(), r * phi.sin(), z)
    };
    let slots: Vec<PathSlot> = (0..params.slot_count)
        .map(|i| PathSlot {
            origin: (centre + 0.8 * radius * direction(i, 0)).to_array(),
            depth: 1,
            direction: direction(i, 2).to_array(),
            pass_throughs: 0,
            flux: [1.0, 0.8, 0.6],
            state: render::medium::pack_slot_state(
                i % 2 == 0,
                glass as u32,
                render::dispersion::WHOLE_SPECTRUM,
            ),
            walk_densities: [1.6, 0.9, 0.5],
            walk_hero: if i % 3 == 2 {
                render::scattering::NO_WALK
            } else {
                i % 3
            },
        })
        .collect();
    let mut snapshot = g.backend().snapshot().expect("snapshot");
    snapshot.slots = bytemuck::cast_slice(&slots).to_vec();
    g.backend().restore(&snapshot).expect("restore");
    g.pass();
    let data = fixture.scene_data();
    let twin: Vec<_> = (0..params.slot_count)
        .map(|i| kernels::photon_pass(&data, &params, 0, i, slots[i as usize]))
        .collect();
    let d = fixture.diagonal;
    let twin_slots: Vec<PathSlot> = twin.iter().map(|t| t.slot).collect();
    let twin_photons: Vec<Photon> = twin.iter().map(|t| t.photon).collect();
    let gpu = g.backend();
    let (gpu_slots, gpu_photons) = (gpu.read_slots().unwrap(), gpu.read_photons().unwrap());
    Comparison::new("murky walks' slots", &gpu_slots, &twin_slots, |g, c| {
        slot_errors(g, c, d)
    })
    .assert_at_most(MAX_DIVERGED);
    Comparison::new(
        "murky walks' photons",
        &gpu_photons,
        &twin_photons,
        |g, c| photon_errors(g, c, d),
    )
    .assert_at_most(MAX_DIVERGED);
    let count = |keep: &dyn Fn(&Photon) -> bool| twin_photons.iter().filter(|p| keep(p)).count();
    let volume = count(&|p| p.is_stored() && is_volume(p.normal));
    let landed = count(&|p| p.is_stored() && !is_volume(p.normal));
    let ended = twin_slots.iter().filter(|s| s.depth == SLOT_IDLE).count();
    eprintln!("{volume} volume photons, {landed} landed, {ended} slots ended");
    assert!(volume > 1000 && landed > 100 && ended > 40);
}

/// A number in [0, 1) for test input `i`, dimension `k`.
fn unit(i: u32, k: u32) -> f32 {
    (render::rng::stream_key(17, k, 0, i) >> 8) as f32 / (1u32 << 24) as f32
}

/// `scene` with a diffuse ball (white, 0.6 of the radius) inside its murky glass ball: a copy
/// of the glass's triangles shrunk about their centre.
fn with_diffuse_core(mut scene: scene::Scene) -> scene::Scene {
    let glass = (scene.materials.iter())
        .position(|m| m.has_murky_glass())
        .expect("a murky glass ball") as u32;
    let core = scene.materials.len() as u32;
    scene.materials.push(scene::Material {
        name: "diffuse core".into(),
        base_color: glam::Vec3::splat(0.8),
        ..scene::Material::default()
    });
    let ball: Vec<scene::Triangle> = (scene.triangles.iter())
        .filter(|t| t.material == glass)
        .cloned()
        .collect();
    let centre = (ball.iter())
        .flat_map(|t| &t.vertices)
        .fold(scene::Bounds::EMPTY, |b, v| b.grow(v.position))
        .center();
    for mut triangle in ball {
        triangle.material = core;
        for v in &mut triangle.vertices {
            v.position = centre + 0.6 * (v.position - centre);
        }
        scene.triangles.push(triangle);
    }
    scene
}

/// The same with glTF's anisotropy (`scene::Anisotropy`, `render::microfacet::
/// brushed_reflection` and its WGSL twin) on `cornell_rough`'s metal spheres: the gold brushed
/// at strength 0.8 turned 0.5 rad from +u, the silver along a checker of directions (red and
/// green) and strengths (blue); bounces, light samples and the MIS of emission met after them
/// follow the brushing of each hit's texture frame.
#[test]
fn every_kernel_matches_its_twin_on_brushed_metal() {
    let mut scene = scene::testing::cornell_rough();
    let texture = push_checker(&mut scene, "brushing checker", |x, y| match (x + y) % 2 {
        0 => [1.0, 0.5, 0.9, 1.0],
        _ => [0.5, 1.0, if y % 4 < 2 { 0.3 } else { 1.0 }, 1.0],
    });
    let named = |name: &str| (scene.materials.iter()).position(|m| m.name.contains(name));
    let (gold, silver) = (named("gold").unwrap(), named("silver").unwrap());
    scene.materials[gold].anisotropy = Some(scene::Anisotropy {
        strength: 0.8,
        rotation: 0.5,
        texture: None,
    });
    scene.materials[silver].anisotropy = Some(scene::Anisotropy {
        strength: 1.0,
        rotation: -0.3,
        texture: Some(texture),
    });
    planar_uv(&mut scene, &[gold, silver]);
    every_kernel_matches_its_twin(scene, DirectLight::Sampled);
}

/// The same on `cornell_iridescent` (glTF's iridescence: `render::iridescence` and its WGSL
/// twin): the titanium mirror's film thickness from a checker's green (between 100 and
/// 300 nm) and the rough steel's factor from its red: photon and eye bounces off both take the
/// film's colour at their micro-normal, and the steel's light samples its colour at the
/// light's direction.
#[test]
fn every_kernel_matches_its_twin_on_iridescent_metal() {
    let mut scene = scene::testing::cornell_iridescent();
    let texture = push_checker(&mut scene, "film checker", |x, y| match (x + y) % 2 {
        0 => [0.3, 0.1, 0.0, 1.0],
        _ => [1.0, 0.8, 0.0, 1.0],
    });
    let named = |name: &str| (scene.materials.iter()).position(|m| m.name.contains(name));
    let (titanium, steel) = (named("titanium").unwrap(), named("steel").unwrap());
    for (id, thickness) in [(titanium, true), (steel, false)] {
        let film = scene.materials[id].iridescence.as_mut().unwrap();
        if thickness {
            film.thickness_texture = Some(texture);
        } else {
            film.texture = Some(texture);
        }
    }
    planar_uv(&mut scene, &[titanium, steel]);
    every_kernel_matches_its_twin(scene, DirectLight::Sampled);
}

/// The same on `cornell_caustics` with its glass sphere under a thin film (index 1.33,
/// 500 nm, its thickness from a checker's green): photons and eye paths meeting the glass
/// from outside and inside (where the film is seen at the angle outside, or reflects all)
/// take the film's share of the way they go.
#[test]
fn every_kernel_matches_its_twin_on_iridescent_glass() {
    let mut scene = scene::testing::cornell_caustics();
    glass_under_textured_film(&mut scene);
    every_kernel_matches_its_twin(scene, DirectLight::Sampled);
}

/// The same on `cornell_plastic` with its plastic under thin films (glTF's iridescence on an
/// opaque dielectric): the smooth red sphere's film 1.8 of index and 380 nm thick, the glossy
/// blue one's and the floor's of index 1.33 with their thickness from a checker's green:
/// photons landing on the base and leaving it take the film's share of the coat's
/// transmittance both ways, the coat's reflections its share at their micro-normal, and the
/// light samples both (`render::iridescence::coat_film_transmission`).
#[test]
fn every_kernel_matches_its_twin_on_iridescent_plastic() {
    let mut scene = scene::testing::cornell_plastic();
    let texture = push_checker(&mut scene, "film checker", |x, y| match (x + y) % 2 {
        0 => [0.0, 0.2, 0.0, 1.0],
        _ => [0.0, 0.9, 0.0, 1.0],
    });
    let named = |name: &str| (scene.materials.iter()).position(|m| m.name.contains(name));
    let (floor, red, blue) = (
        named("white plastic").unwrap(),
        named("red").unwrap(),
        named("blue").unwrap(),
    );
    scene.materials[red].iridescence = Some(scene::testing::film(1.8, 380.0));
    for id in [floor, blue] {
        scene.materials[id].iridescence = Some(scene::Iridescence {
            thickness_texture: Some(texture),
            ..scene::testing::film(1.33, 500.0)
        });
    }
    planar_uv(&mut scene, &[floor, blue]);
    every_kernel_matches_its_twin(scene, DirectLight::Sampled);
}

/// The same on `cornell_plastic` under glTF's specular layer (`scene::SpecularLayer`): the
/// floor's strength and colour from two checkers (alpha 0.2 or 1; colour (1, 0.5, 0.2) or
/// white), the glossy blue sphere's a tinted colour without textures (F0 × (0.3, 1, 2)) at
/// strength 0.6:
/// photons landing on the base and leaving it, the coat's reflections and the light samples
/// take the layer's share per channel (`render::dielectric_layer::DielectricLayer`).
#[test]
fn every_kernel_matches_its_twin_on_a_specular_layer() {
    let mut scene = scene::testing::cornell_plastic();
    let strength = push_checker(&mut scene, "strength checker", |x, y| match (x + y) % 2 {
        0 => [1.0, 1.0, 1.0, 0.2],
        _ => [1.0, 1.0, 1.0, 1.0],
    });
    let colour = push_checker(&mut scene, "colour checker", |x, y| match (x / 2 + y) % 2 {
        0 => [1.0, 0.5, 0.2, 1.0],
        _ => [1.0, 1.0, 1.0, 1.0],
    });
    let named = |name: &str| (scene.materials.iter()).position(|m| m.name.contains(name));
    let (floor, blue) = (named("white plastic").unwrap(), named("blue").unwrap());
    scene.materials[floor].specular = Some(scene::SpecularLayer {
        texture: Some(strength),
        color_texture: Some(colour),
        ..scene::SpecularLayer::new(1.5, glam::Vec3::ONE, 1.0)
    });
    scene.materials[blue].specular = Some(scene::SpecularLayer::new(
        1.5,
        glam::Vec3::new(0.3, 1.0, 2.0),
        0.6,
    ));
    planar_uv(&mut scene, &[floor]);
    every_kernel_matches_its_twin(scene, DirectLight::Sampled);
}

/// The same on `cornell_frosted` with its frosted spheres under a thin film (index 1.33,
/// 500 nm, its thickness from a checker's green), and with its spheres made thin frosted
/// sheets (bubbles of frosted glass) under the film: bounces take the film's share of their way at their micro-normal, and the
/// light samples of the three frosted lobes (reflection from outside, refraction out, the
/// sheet's two ways) take it at the light's.
#[test]
fn every_kernel_matches_its_twin_on_iridescent_frosted_glass() {
    let mut frosted = scene::testing::cornell_frosted();
    let mut sheet = frosted_sheets();
    for scene in [&mut frosted, &mut sheet] {
        glass_under_textured_film(scene);
    }
    every_kernel_matches_its_twin(frosted, DirectLight::Sampled);
    every_kernel_matches_its_twin(sheet, DirectLight::Sampled);
}

/// The same on `cornell_caustics` and `cornell_frosted` (also as thin frosted sheets) with their
/// glass under glTF's specular layer (`render::dielectric_layer`: its reflectance head on
/// and at grazing set by the layer, a colour texture varying it): smooth glass chooses its
/// way by the layer's mean reflectance and weighs each channel by its share, from inside too
/// (total internal reflection kept), frosted glass keeps its own choice and weighs each way,
/// and its light samples, by the layer's share at the micro-normal.
#[test]
fn every_kernel_matches_its_twin_on_glass_under_a_specular_layer() {
    let mut smooth = scene::testing::cornell_caustics();
    let mut frosted = scene::testing::cornell_frosted();
    let mut sheet = frosted_sheets();
    for scene in [&mut smooth, &mut frosted, &mut sheet] {
        glass_under_textured_specular_layer(scene);
    }
    every_kernel_matches_its_twin(smooth, DirectLight::Sampled);
    every_kernel_matches_its_twin(frosted, DirectLight::Sampled);
    every_kernel_matches_its_twin(sheet, DirectLight::Sampled);
}

/// The same with the mesh's own tangents (glTF TANGENT, `render::normal_map::tangent_frame`
/// and its WGSL twin) on `cornell_bumpy`'s normal-mapped surfaces, its hammered mirror made
/// brushed rough metal: every vertex's tangent turned from its normal's basis by an angle of
/// its position, of handedness alternating triangle by triangle, so normal maps and the
/// brushing follow them (ignoring the handedness in the WGSL, or the tangents, fails it: 8.4 %
/// and 21 % of the first eye pass's points differ).
#[test]
fn every_kernel_matches_its_twin_with_mesh_tangents() {
    let mut scene = scene::testing::cornell_bumpy();
    let mirror = (scene.materials.iter()).position(|m| m.name.contains("mirror"));
    let hammered = &mut scene.materials[mirror.expect("a hammered mirror")];
    hammered.surface = scene::Surface::RoughConductor { alpha: 0.1 };
    hammered.anisotropy = Some(scene::Anisotropy {
        strength: 0.8,
        rotation: 0.2,
        texture: None,
    });
    for (index, triangle) in scene.triangles.iter_mut().enumerate() {
        let handedness = if index % 2 == 0 { 1.0 } else { -1.0 };
        for v in &mut triangle.vertices {
            let (a, b) = render::sampling::orthonormal_basis(v.normal);
            let angle = 3.0 * (v.position.x + v.position.y);
            v.tangent = (a * angle.cos() + b * angle.sin()).extend(handedness);
        }
    }
    assert!(scene.has_vertex_tangents());
    every_kernel_matches_its_twin(scene, DirectLight::Sampled);
}

/// The same on `cornell_metallic_roughness` with its brass brushed (strength 0.7): the
/// texture's polished tiles, mirrors before, are rough metal of the least brushed width
/// (`scene::brushed_metal_surface`), widened along the brushing, on both backends.
#[test]
fn every_kernel_matches_its_twin_on_brushed_textured_metal() {
    let mut scene = scene::testing::cornell_metallic_roughness();
    for material in (scene.materials.iter_mut()).filter(|m| m.name.contains("brass")) {
        material.anisotropy = Some(scene::Anisotropy {
            strength: 0.7,
            rotation: 0.4,
            texture: None,
        });
    }
    assert!(scene.materials.iter().any(|m| m.anisotropy.is_some()));
    every_kernel_matches_its_twin(scene, DirectLight::Sampled);
}

/// The same without light samples at glossy lobes (`--glossy-light off`): rough plastic's
/// Lambertian base keeps its light sample, through the rough coat's own transmittance table.
#[test]
fn every_kernel_matches_its_twin_without_glossy_light_samples() {
    let settings = Settings {
        eye_every: 2,
        direct: DirectLight::Sampled,
        glossy_light_sampling: false,
        ..caustics_settings()
    };
    every_kernel_matches_its_twin_with(context(), scene::testing::cornell_plastic(), settings);
}

/// The same through blends (`scene::Blend`, `render::blend` and its WGSL twin): each hit on
/// the floor and spheres draws its member (mirror or plastic, rough metal or rough plastic,
/// solid glass or diffuse), and photons are kept for the Lambertian member whichever member
/// the photon path takes.
#[test]
fn every_kernel_matches_its_twin_through_blends() {
    every_kernel_matches_its_twin(scene::testing::cornell_blended(), DirectLight::Sampled);
}

/// The same with the glass-and-plastic sphere's glass weighed by a transmission texture
/// (`render::blend::transmission_weight`): a checker of 1 and 0.2, so that hits draw glass or
/// plastic with the texel's share of the factor.
#[test]
fn every_kernel_matches_its_twin_through_a_transmission_texture() {
    let mut scene = scene::testing::cornell_blended();
    let texture = push_checker(&mut scene, "transmission checker", |x, y| {
        let red = if (x + y) % 2 == 0 { 1.0 } else { 0.2 };
        [red, 0.0, 0.0, 1.0]
    });
    let milky: Vec<u32> = (0..scene.materials.len() as u32)
        .filter(|&id| scene.materials[id as usize].name == "glass and plastic")
        .collect();
    for &id in &milky {
        scene.materials[id as usize].transmission_texture = Some(texture);
    }
    for triangle in (scene.triangles.iter_mut()).filter(|t| milky.contains(&t.material)) {
        for v in &mut triangle.vertices {
            v.uv = glam::Vec2::new(v.position.x, v.position.y) / 40.0;
        }
    }
    every_kernel_matches_its_twin(scene, DirectLight::Sampled);
}

/// The same with glTF's metallic-roughness texture (`scene::RoughnessMap`,
/// `render::blend::mapped_material` and its WGSL twin): on the tiled floor and sphere each hit
/// reads its texel, which weighs the metal's share and picks the metal's surface (mirror or
/// rough) and the coat's (plastic or Lambertian); photons are kept by the member's surface
/// there.
#[test]
fn every_kernel_matches_its_twin_through_metallic_roughness_tiles() {
    every_kernel_matches_its_twin(
        scene::testing::cornell_metallic_roughness(),
        DirectLight::Sampled,
    );
}

/// The same with every mapped metal and coat keeping its lobe however rough
/// (`scene::RoughnessMap::keeps_lobe`, as a filmed or specular-glossiness material's does):
/// the tiles that were Lambertian are rough metal and rough plastic up to roughness 1, the
/// coat's grid spanning it.
#[test]
fn every_kernel_matches_its_twin_through_tiles_that_keep_their_lobes() {
    let mut scene = scene::testing::cornell_metallic_roughness();
    for material in &mut scene.materials {
        if let Some(map) = &mut material.roughness_map {
            map.keeps_lobe = true;
        }
    }
    every_kernel_matches_its_twin(scene, DirectLight::Sampled);
}

/// The same under a sky map (`render::sky_map` and its WGSL twin): photons start in the map's
/// directions by its importance, light samples draw them, glossy bounces weigh the map's
/// density, and camera rays past the plane, through the glass or off the gold see its texels.
#[test]
fn every_kernel_matches_its_twin_under_a_sky_map() {
    let scene = scene::testing::spheres_under_sky_map();
    let lights = render::emission::light_table(&scene);
    assert!(render::sky_map::MapFrame::of(lights.last().unwrap()).is_some());
    every_kernel_matches_its_twin(scene.clone(), DirectLight::Sampled);
    every_kernel_matches_its_twin(scene, DirectLight::Photons);
}

/// Texels a side of the textures [`push_checker`] makes.
const CHECKER_SIDE: u32 = 8;

/// Adds a [`CHECKER_SIDE`]² texture of linear data whose texel at column `x`, row `y` is
/// `texel(x, y)`, and returns its id.
fn push_checker(scene: &mut scene::Scene, name: &str, texel: impl Fn(u32, u32) -> [f32; 4]) -> u32 {
    let side = CHECKER_SIDE;
    let texels = (0..side * side)
        .map(|i| texel(i % side, i / side))
        .collect();
    scene.textures.push(scene::Texture {
        name: name.into(),
        width: side,
        height: side,
        texels: scene::Texels::LinearF32(texels),
    });
    scene.textures.len() as u32 - 1
}

/// Texture coordinates on the triangles of `materials` from their positions (a planar map,
/// 40 units a repeat), so that textures on them vary over the surface.
fn planar_uv(scene: &mut scene::Scene, materials: &[usize]) {
    let of_them = |t: &&mut scene::Triangle| materials.contains(&(t.material as usize));
    for triangle in scene.triangles.iter_mut().filter(of_them) {
        for v in &mut triangle.vertices {
            v.uv = glam::Vec2::new(v.position.x + v.position.z, v.position.y) / 40.0;
        }
    }
}

/// Every glass of `scene` under a thin film (index 1.33, 500 nm) whose thickness a checker's
/// green gives (0.2 and 0.9 of it), mapped over the glass by [`planar_uv`].
/// `cornell_frosted` with its spheres made thin frosted sheets (bubbles of frosted glass, index
/// 1.5, GGX α 0.09).
fn frosted_sheets() -> scene::Scene {
    let mut sheet = scene::testing::cornell_frosted();
    for material in &mut sheet.materials {
        if let scene::Surface::RoughDielectric {
            ior,
            alpha,
            thin_walled,
        } = &mut material.surface
        {
            (*ior, *alpha, *thin_walled) = (1.5, 0.09, true);
        }
    }
    sheet
}

/// The glass materials of `scene` (at least one).
fn glass_ids(scene: &scene::Scene) -> Vec<usize> {
    let glass: Vec<usize> = (0..scene.materials.len())
        .filter(|&i| scene.materials[i].surface.is_glass())
        .collect();
    assert!(!glass.is_empty(), "the fixture has glass");
    glass
}

/// Every glass of `scene` under glTF's specular layer: strength 0.5, colour (2, 1, 0.3), and
/// a colour texture's checker (white or (0.4, 1, 1)).
fn glass_under_textured_specular_layer(scene: &mut scene::Scene) {
    let checker = |x: u32, y: u32| match (x + y) % 2 {
        0 => [0.4, 1.0, 1.0, 1.0],
        _ => [1.0, 1.0, 1.0, 1.0],
    };
    dress_glass(
        scene,
        ("specular colour checker", checker),
        |material, texture| {
            material.specular = Some(scene::SpecularLayer {
                color_texture: Some(texture),
                ..scene::SpecularLayer::new(1.5, glam::Vec3::new(2.0, 1.0, 0.3), 0.5)
            });
        },
    );
}

fn glass_under_textured_film(scene: &mut scene::Scene) {
    let checker = |x: u32, y: u32| match (x + y) % 2 {
        0 => [0.0, 0.2, 0.0, 1.0],
        _ => [0.0, 0.9, 0.0, 1.0],
    };
    dress_glass(scene, ("film checker", checker), |material, texture| {
        material.iridescence = Some(scene::Iridescence {
            thickness_texture: Some(texture),
            ..scene::testing::film(1.33, 500.0)
        });
    });
}

/// Pushes a checker texture (`name`, `texel`) and lets `dress` give every glass of `scene`
/// what reads it, on planar texture coordinates.
fn dress_glass(
    scene: &mut scene::Scene,
    (name, texel): (&str, impl Fn(u32, u32) -> [f32; 4]),
    dress: impl Fn(&mut scene::Material, u32),
) {
    let texture = push_checker(scene, name, texel);
    let glass = glass_ids(scene);
    for &id in &glass {
        dress(&mut scene.materials[id], texture);
    }
    planar_uv(scene, &glass);
}

/// The scene file `name` shipped in `scenes/`.
fn shipped(name: &str) -> scene::Scene {
    let path = format!("{}/../../scenes/{name}", env!("CARGO_MANIFEST_DIR"));
    scene::load(std::path::Path::new(&path)).expect("the shipped file loads")
}

fn every_kernel_matches_its_twin(scene: scene::Scene, direct: DirectLight) -> Seen {
    every_kernel_matches_its_twin_on(context(), scene, direct)
}

/// What the GPU's passes held, summed over a twin run: murky glass's volume visible points and
/// photons (`render::packing::is_volume`), and pixels whose volume statistics met photons.
#[derive(Debug, Default)]
struct Seen {
    volume_points: usize,
    volume_photons: usize,
    volume_lit_pixels: usize,
}

fn every_kernel_matches_its_twin_on(
    context: GpuContext,
    scene: scene::Scene,
    direct: DirectLight,
) -> Seen {
    let settings = Settings {
        eye_every: 2,
        direct,
        // Resampled light samples even where `auto` would take one candidate (one ceiling
        // quad), so that every twin covers them.
        light_candidates: Some(render::resampling::DEFAULT_LIGHT_CANDIDATES),
        ..caustics_settings()
    };
    every_kernel_matches_its_twin_with(context, scene, settings)
}

fn every_kernel_matches_its_twin_with(
    context: GpuContext,
    scene: scene::Scene,
    settings: Settings,
) -> Seen {
    // Mirrors, glass and metal seen first send pixels extra eye paths; plastic coats do not.
    let flags_pixels = scene.materials.iter().any(|m| {
        !matches!(
            m.surface,
            scene::Surface::Diffuse | scene::Surface::Plastic { .. }
        )
    });
    let sky_map = render::emission::light_table(&scene)
        .last()
        .and_then(render::sky_map::MapFrame::of)
        .is_some();
    let direct_tolerance = if sky_map {
        SKY_MAP_DIRECT_TOLERANCE
    } else {
        RELATIVE_TOLERANCE
    };
    let fixture = Fixture::new(scene);
    let data = fixture.scene_data();
    let params = fixture.params(&settings);
    let d = fixture.diagonal;
    let mut g = fixture.gpu(context, &settings);
    let mut specular_slots = 0;
    let mut flagged = 0;
    let mut seen = Seen::default();
    for pass in 0..4u32 {
        let gpu = g.backend();
        let slots_before = gpu.read_slots().expect("slots");
        let points_before = gpu.read_visible_points().expect("visible points");
        let stats_before = gpu.read_statistics().expect("statistics").pixels;
        let counters_before = gpu.counters().expect("counters");
        assert_eq!(counters_before[counter::PASS], pass);
        g.pass();
        let gpu = g.backend();
        let slots = gpu.read_slots().expect("slots");
        let photons = gpu.read_photons().expect("photons");
        let points = gpu.read_visible_points().expect("visible points");
        let hash = gpu.read_hash().expect("hash");
        let stats = gpu.read_statistics().expect("statistics").pixels;
        let counters = gpu.counters().expect("counters");

        // Eye pass (when due): new visible points and the direct emission added.
        let mut twin_points = points_before;
        let mut twin_stats = stats_before;
        if pass.is_multiple_of(settings.eye_every) {
            for (i, (point, s)) in twin_points.iter_mut().zip(&mut twin_stats).enumerate() {
                *point = kernels::eye_pass_pixel(&data, &params, pass, i as u32, s);
            }
        }
        Comparison::new(
            format!("pass {pass} eye_pass"),
            &points,
            &twin_points,
            |g, c| point_errors(g, c, d),
        )
        .assert_at_most(MAX_DIVERGED);

        // Photon pass on the GPU's slots.
        let twin: Vec<_> = slots_before
            .iter()
            .enumerate()
            .map(|(i, &slot)| kernels::photon_pass(&data, &params, pass, i as u32, slot))
            .collect();
        specular_slots += slots_before
            .iter()
            .filter(|s| s.depth != SLOT_IDLE && s.depth > 0)
            .count();
        let twin_slots: Vec<PathSlot> = twin.iter().map(|t| t.slot).collect();
        let twin_photons: Vec<Photon> = twin.iter().map(|t| t.photon).collect();
        Comparison::new(
            format!("pass {pass} photon_pass slots"),
            &slots,
            &twin_slots,
            |g, c| slot_errors(g, c, d),
        )
        .assert_at_most(MAX_DIVERGED);
        Comparison::new(
            format!("pass {pass} photon_pass photons"),
            &photons,
            &twin_photons,
            |g, c| photon_errors(g, c, d),
        )
        .assert_at_most(MAX_DIVERGED);
        let emitted_now = twin.iter().filter(|t| t.emitted).count() as u32;

        // Hash build on the GPU's photons.
        let twin_counters = atomics(&counters_before);
        twin_counters[counter::EMITTED_PASS].store(emitted_now, Relaxed);
        let twin_hash = atomics(&vec![0; hash.len()]);
        for kernel in [kernels::hash_count, kernels::hash_select] {
            for (i, photon) in photons.iter().enumerate() {
                kernel(&params, &twin_counters, &twin_hash, i as u32, photon);
            }
        }
        let (gpu_entries, twin_entries) =
            filled_entries(&hash_entries(&hash), &hash_entries(&loads(&twin_hash)));
        Comparison::new(
            format!("pass {pass} hash_count + hash_select (filled entries)"),
            &gpu_entries,
            &twin_entries,
            |g, c| vec![("entry", exact(g, c))],
        )
        .assert_at_most(MAX_HASH_DIVERGED);

        // Gather on the GPU's hash, photons and visible points, then the pass closed.
        let gpu_hash = atomics(&hash);
        let twin_stats: Vec<PixelStats> = twin_stats
            .iter()
            .zip(&points)
            .map(|(s, point)| {
                kernels::gather(&params, &twin_counters, &gpu_hash, &photons, point, *s)
            })
            .collect();
        Comparison::new(
            format!("pass {pass} gather"),
            &stats,
            &twin_stats,
            |g, c| stats_errors_within(g, c, direct_tolerance),
        )
        .assert_at_most(MAX_DIVERGED);
        kernels::finish_pass(&params, &twin_counters);
        assert_eq!(
            counters,
            loads(&twin_counters),
            "pass {pass}: counters after finish_pass"
        );
        if pass == 0 {
            flagged = stats.iter().filter(|s| s.specular_seen != 0).count();
        }
        seen.volume_points += (points.iter())
            .filter(|p| p.is_valid() && is_volume(p.normal))
            .count();
        seen.volume_photons += (photons.iter())
            .filter(|p| p.is_stored() && is_volume(p.normal))
            .count();
        seen.volume_lit_pixels = stats.iter().filter(|s| s.volume_count > 0.0).count();
    }
    // The later passes continued paths past specular and diffuse bounces.
    assert!(specular_slots > 1000, "{specular_slots} continued paths");
    // The second eye pass traced extra paths in the pixels showing the spheres.
    assert!(
        flagged > 20 || !flags_pixels,
        "{flagged} pixels flagged after the first eye pass"
    );
    assert!(flags_pixels || flagged == 0, "{flagged} pixels flagged");
    eprintln!("{seen:?}");
    seen
}

#[test]
fn resolved_images_match_after_eight_passes() {
    let fixture = Fixture::new(scene::testing::cornell_caustics());
    for eye_every in [8, 2] {
        let settings = Settings {
            eye_every,
            ..caustics_settings()
        };
        let mut g = fixture.gpu(context(), &settings);
        let mut c = fixture.cpu(&settings);
        for _ in 0..8 {
            g.pass();
            c.pass();
        }
        let gpu = g.image().expect("gpu image");
        let cpu = c.image().expect("cpu image");
        let error = rel_mse(&gpu, &cpu);
        let ratio = mean_ratio(&gpu, &cpu);
        eprintln!("eye_every {eye_every}: relMSE {error:.3e}, mean ratio {ratio:.6}");
        assert!(cpu.mean().min_element() > 0.0, "black image");
        assert!(error < 1e-3, "eye_every {eye_every}: relMSE {error:e}");
        assert!(
            (ratio - 1.0).abs() < 1e-3,
            "eye_every {eye_every}: mean ratio {ratio}"
        );
    }
}

/// The eye pass at glass on both backends: through the glass pane each pixel's emission after
/// one pass is what both of the sheet's ways see, weighted by Fresnel (the analytic value of
/// cpu's `glass_pane_shows_both_ways_in_every_eye_pass`), on the GPU as on the CPU; behind
/// three sheets, where only the first splits the path and the others choose, the GPU's
/// emission equals the CPU's pixel for pixel; and so under a thin film (glTF's iridescence:
/// each way weighed by the film's share in each channel, cpu's
/// `an_iridescent_glass_pane_shows_both_ways_in_every_channel`), one sheet and three.
#[test]
fn eye_paths_at_glass_count_both_ways_like_the_cpu_twin() {
    let settings = Settings {
        eye_every: 1,
        ..Settings::new(8, 8, 256)
    };
    let direct_with = |sheets: u32, film: bool| {
        let mut scene = scene::testing::glass_panes(sheets);
        if film {
            for material in &mut scene.materials {
                if material.surface.is_glass() {
                    material.iridescence = Some(scene::testing::film(1.33, 500.0));
                }
            }
        }
        let fixture = Fixture::new(scene);
        let mut g = fixture.gpu(context(), &settings);
        let mut c = fixture.cpu(&settings);
        g.pass();
        c.pass();
        let gpu = g.backend().read_statistics().expect("statistics").pixels;
        let cpu = c.backend().read_statistics().expect("statistics").pixels;
        for (i, (g, c)) in gpu.iter().zip(&cpu).enumerate() {
            for k in 0..3 {
                let (g, c) = (g.direct[k], c.direct[k]);
                assert!(
                    (g - c).abs() <= 1e-5 * c.abs(),
                    "{sheets} sheets, pixel {i}: GPU {g}, CPU {c}"
                );
            }
        }
        gpu.iter().map(|s| s.direct[0]).collect::<Vec<f32>>()
    };
    for sheets in [1, 3] {
        direct_with(sheets, true);
    }
    let direct = |sheets: u32| direct_with(sheets, false);
    let expected = scene::testing::glass_pane_radiance(1.0, render::optics::fresnel_dielectric);
    for (i, g) in direct(1).iter().enumerate() {
        assert!(
            (g / expected - 1.0).abs() < 1e-4,
            "pixel {i}: GPU {g} against {expected}"
        );
    }
    assert!(
        direct(3).iter().any(|g| (g / expected - 1.0).abs() > 0.01),
        "three sheets look like one"
    );
}

/// The check: GPU and CPU renders of the Cornell box at the same budget differ by no
/// more than their own noise, estimated from two seeds of the CPU backend.
#[test]
fn gpu_and_cpu_renders_differ_by_no_more_than_their_noise() {
    let fixture = Fixture::new(scene::testing::cornell_box());
    let passes = 16;
    let settings = |seed| Settings {
        seed,
        ..Settings::new(32, 32, 16384)
    };
    let render_cpu = |seed| {
        let mut c = fixture.cpu(&settings(seed));
        for _ in 0..passes {
            c.pass();
        }
        c.image().expect("cpu image")
    };
    let (cpu1, cpu2) = (render_cpu(1), render_cpu(2));
    let mut g = fixture.gpu(context(), &settings(3));
    for _ in 0..passes {
        g.pass();
    }
    let gpu = g.image().expect("gpu image");
    let noise = rel_mse(&cpu2, &cpu1);
    let error = rel_mse(&gpu, &cpu1);
    let (gpu_ratio, cpu_ratio) = (mean_ratio(&gpu, &cpu1), mean_ratio(&cpu2, &cpu1));
    eprintln!(
        "relMSE(gpu seed 3, cpu seed 1) {error:.4e}, relMSE(cpu seed 2, cpu seed 1) {noise:.4e} \
         (ratio {:.3}); mean ratio gpu/cpu1 {gpu_ratio:.4}, cpu2/cpu1 {cpu_ratio:.4}",
        error / noise
    );
    assert!(noise > 0.0, "two seeds gave the same image");
    assert!(
        error <= 1.5 * noise + 1e-4,
        "relMSE(gpu, cpu) {error:e} > 1.5 × relMSE(cpu seed 2, cpu seed 1) {noise:e}"
    );
    assert!(
        (gpu_ratio - 1.0).abs() < 0.02,
        "mean(gpu) / mean(cpu) = {gpu_ratio}"
    );
}
