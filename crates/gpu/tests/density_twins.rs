//! The density-estimation variants `kousen bench density` measures (issue 6, table 4) against
//! their CPU twins, each on the GPU's own input, pass after pass, on the caustics scene:
//!
//! - full spatial hash: the prefix sum over the GPU's counts equals `render::density::
//!   scan_counts` word for word; the scatter lists every stored photon exactly once, under the
//!   entry the CPU hashes it to, each list sorted by photon index; the gather over the GPU's
//!   lists (which reads the photons the sort copied into list order, stored in f32 or f16)
//!   equals `cpu::density::full_query`'s; two renders with the same seed give the same image,
//!   bit for bit;
//! - kd-tree: the gather over the tree uploaded from the GPU's photons equals the CPU's query
//!   of the same tree;
//! - the stochastic hash's gather, and both of those, in murky glass (`scene::testing::furnace_with_murky_glass`), where volume
//!   visible points gather the volume photons.
//!
//! Runs on whatever adapter wgpu finds (lavapipe in CI), so the sizes are small.

use std::sync::atomic::AtomicU32;

use bvh::{BuildOptions, PackedBvh};
use cpu::density::{full_query, photon_entry};
use cpu::kernels::{GatherQuery, GatherSum, gather_with, stochastic_query};
use gpu::GpuContext;
use gpu::sppm::GpuBackend;
use render::buffers::{HASH_ENTRY_WORDS, Photon, PixelStats, SppmParams, VisiblePoint};
use render::density::{SCAN_BLOCK, full_word, scan_counts};
use render::half_storage::Precision;
use render::integrator::Phase;
use render::kdtree::PhotonKdTree;
use render::{Backend, Density, Settings, Sppm};

/// Share of pixels whose statistics may differ beyond the tolerance (a photon a rounding from
/// the sphere's edge or a cell boundary).
const MAX_DIVERGED: f64 = 0.005;
/// Share of stored photons the GPU may list under another entry than the CPU hashes them to
/// (a position a rounding from a cell boundary).
const MAX_MOVED: f64 = 0.001;
const RELATIVE_TOLERANCE: f32 = 1e-4;

fn context() -> GpuContext {
    GpuContext::new(None).unwrap_or_else(|e| {
        panic!("no usable GPU adapter in the test environment (CI installs Mesa lavapipe): {e}")
    })
}

fn atomics(words: &[u32]) -> Vec<AtomicU32> {
    words.iter().map(|&w| AtomicU32::new(w)).collect()
}

/// What the GPU held when its hash (lists or tree) was built, before the gather.
#[derive(Default)]
struct BeforeGather {
    photons: Vec<Photon>,
    points: Vec<VisiblePoint>,
    stats: Vec<PixelStats>,
    counters: Vec<u32>,
    hash: Vec<u32>,
    lists: Option<(Vec<u32>, Vec<u32>)>,
}

fn render(density: Density) -> (Sppm<GpuBackend>, Settings) {
    render_in(density, Precision::F32)
}

fn render_in(density: Density, precision: Precision) -> (Sppm<GpuBackend>, Settings) {
    render_scene(scene::testing::cornell_caustics(), density, precision)
}

/// The murky glass furnace (`scene::testing::furnace_with_murky_glass`): most pixels see the
/// ball, whose eye paths end at volume visible points gathering volume photons.
fn murky_furnace() -> scene::Scene {
    scene::testing::furnace_with_murky_glass(glam::Vec3::new(4.0, 2.0, 1.0), 0.5, 1.33)
}

fn render_scene(
    scene: scene::Scene,
    density: Density,
    precision: Precision,
) -> (Sppm<GpuBackend>, Settings) {
    let bvh = PackedBvh::build(&scene.triangles, &BuildOptions::default());
    let camera = scene.camera(None).expect("a camera");
    let settings = Settings {
        seed: 3,
        eye_every: 2,
        density,
        precision,
        // 1,000 entries: four scan blocks, the last one partial.
        hash_ratio: 1000.0 / 4096.0,
        ..Settings::new(24, 24, 4096)
    };
    let backend = GpuBackend::new(context(), &scene, bvh).expect("gpu backend");
    let sppm = Sppm::new(backend, &scene, &camera, settings.clone()).expect("render started");
    (sppm, settings)
}

/// One pass on the GPU, keeping its state at the end of the hash phase; then the statistics.
fn pass(sppm: &mut Sppm<GpuBackend>, density: Density) -> (BeforeGather, Vec<PixelStats>) {
    let mut before = BeforeGather::default();
    sppm.pass_phases(|gpu, phase| {
        if phase == Phase::Hash {
            before = BeforeGather {
                photons: gpu.read_photons().expect("photons"),
                points: gpu.read_visible_points().expect("visible points"),
                stats: gpu.read_statistics().expect("statistics").pixels,
                counters: gpu.counters().expect("counters"),
                hash: gpu.read_hash().expect("hash"),
                lists: (density == Density::FullHash)
                    .then(|| gpu.read_full_hash_lists().expect("lists")),
            };
        }
    });
    let after = sppm.backend().read_statistics().expect("statistics").pixels;
    (before, after)
}

/// The CPU's gather of every pixel on the GPU's state `before`, its photons found by `query`.
fn twin_gather(
    before: &BeforeGather,
    params: &SppmParams,
    counters: &[AtomicU32],
    query: impl Fn(&GatherQuery) -> GatherSum,
) -> Vec<PixelStats> {
    (before.stats.iter())
        .zip(&before.points)
        .map(|(s, point)| gather_with(counters, params, point, *s, &query))
        .collect()
}

fn relative(a: f32, b: f32) -> f32 {
    (a - b).abs() / a.abs().max(b.abs()).max(1e-30)
}

/// Asserts that at most [`MAX_DIVERGED`] of the pixels differ beyond the tolerance, and that
/// the pass met photons at all; returns how many pixels' volume statistics met photons.
fn assert_gather_matches(label: &str, gpu: &[PixelStats], twin: &[PixelStats]) -> usize {
    let differing = gpu
        .iter()
        .zip(twin)
        .filter(|(g, c)| {
            let mut errors = vec![
                relative(g.photon_count, c.photon_count),
                relative(g.radius, c.radius),
                relative(g.caustic_count, c.caustic_count),
                relative(g.caustic_radius, c.caustic_radius),
                relative(g.volume_count, c.volume_count),
                relative(g.volume_radius, c.volume_radius),
            ];
            for (g, c) in [
                (g.tau, c.tau),
                (g.caustic_tau, c.caustic_tau),
                (g.volume_tau, c.volume_tau),
            ] {
                errors.extend((0..3).map(|k| relative(g[k], c[k])));
            }
            errors.iter().any(|&e| e > RELATIVE_TOLERANCE)
        })
        .count();
    let lit = twin
        .iter()
        .filter(|s| s.photon_count > 0.0 || s.caustic_count > 0.0 || s.volume_count > 0.0)
        .count();
    let volume_lit = twin.iter().filter(|s| s.volume_count > 0.0).count();
    println!(
        "{label}: {differing} of {} pixels differ; {lit} lit, {volume_lit} by volume photons",
        gpu.len()
    );
    assert!(
        lit > gpu.len() / 4,
        "{label}: only {lit} pixels met photons"
    );
    assert!(
        differing as f64 <= MAX_DIVERGED * gpu.len() as f64,
        "{label}: {differing} pixels differ"
    );
    volume_lit
}

#[test]
fn full_hash_matches_its_cpu_twin_on_the_gpu_state() {
    full_hash_matches_its_cpu_twin(scene::testing::cornell_caustics(), Precision::F32);
}

/// With f16 photons the sort copies packed records into list order, which the gather unpacks.
#[test]
fn full_hash_matches_its_cpu_twin_with_f16_photons() {
    full_hash_matches_its_cpu_twin(scene::testing::cornell_caustics(), Precision::F16);
}

/// In murky glass: volume visible points gather the listed volume photons in their spheres,
/// weighed by the phase function, and surface ones pass them by.
#[test]
fn full_hash_matches_its_cpu_twin_in_murky_glass() {
    let volume_lit = full_hash_matches_its_cpu_twin(murky_furnace(), Precision::F32);
    assert!(volume_lit > 100, "{volume_lit} pixels met volume photons");
}

/// The stochastic hash's gather in murky glass on the GPU's own state: volume visible points
/// read the volume photons' finer grid cell by cell (`render::hash::volume_query_cells`)
/// through a table of 1,000 entries, where the cells they read share entries, each cell
/// counting only the kept photon lying in it.
#[test]
fn stochastic_gather_matches_its_cpu_twin_in_murky_glass() {
    let scene = murky_furnace();
    let (mut sppm, settings) = render_scene(scene.clone(), Density::StochasticHash, Precision::F32);
    let params = params_of(&scene, &settings);
    // One kept photon a cell finds fewer than the lists: a pass first, so that a quarter of
    // the pixels have met photons when the comparison starts.
    pass(&mut sppm, Density::StochasticHash);
    for p in 1..4 {
        let (before, after) = pass(&mut sppm, Density::StochasticHash);
        let counters = atomics(&before.counters);
        let hash = atomics(&before.hash);
        let twin = twin_gather(&before, &params, &counters, |q| {
            stochastic_query(&params, &hash, &before.photons, q)
        });
        let volume_lit = assert_gather_matches(&format!("stochastic hash pass {p}"), &after, &twin);
        assert!(
            volume_lit > 100,
            "pass {p}: {volume_lit} pixels met volume photons"
        );
    }
}

/// The kernels' parameters for `scene` under `settings`, as the backends are given them.
fn params_of(scene: &scene::Scene, settings: &Settings) -> SppmParams {
    let camera = scene.camera(None).unwrap();
    let lights = render::emission::light_table(scene).len() as u32;
    render::integrator::params(scene, &camera, settings, lights)
}

/// Three passes of the full hash on the GPU against their CPU twins; the pixels whose volume
/// statistics met photons in the last.
fn full_hash_matches_its_cpu_twin(scene: scene::Scene, precision: Precision) -> usize {
    let (mut sppm, settings) = render_scene(scene.clone(), Density::FullHash, precision);
    let params = params_of(&scene, &settings);
    let mut volume_lit = 0;
    for p in 0..3 {
        let (mut before, after) = pass(&mut sppm, Density::FullHash);
        let (order, offsets) = before.lists.take().expect("full hash lists");
        let words = &before.hash;
        // The prefix sum, word for word, over the GPU's own counts.
        let counts: Vec<u32> = words
            .chunks(HASH_ENTRY_WORDS)
            .map(|e| e[full_word::COUNT])
            .collect();
        let mut starts = vec![0; counts.len()];
        assert_eq!(
            scan_counts(&counts, &mut starts),
            offsets,
            "pass {p}: block offsets"
        );
        for (entry, start) in words.chunks(HASH_ENTRY_WORDS).zip(&starts) {
            assert_eq!(entry[full_word::START], *start, "pass {p}: list start");
            assert_eq!(
                entry[full_word::FILL],
                entry[full_word::COUNT],
                "pass {p}: fill"
            );
        }
        // The scatter: every stored photon listed once, under the entry the CPU hashes it to.
        let counters = atomics(&before.counters);
        let mut listed = vec![false; before.photons.len()];
        let mut moved = 0;
        for (entry, words) in words.chunks(HASH_ENTRY_WORDS).enumerate() {
            let start = offsets[entry / SCAN_BLOCK as usize] + words[full_word::START];
            let list = &order[start as usize..(start + words[full_word::COUNT]) as usize];
            assert!(
                list.windows(2).all(|w| w[0] < w[1]),
                "pass {p}: entry {entry}'s list is not in photon order: {list:?}"
            );
            for &index in list {
                assert!(
                    !listed[index as usize],
                    "pass {p}: photon {index} listed twice"
                );
                listed[index as usize] = true;
                let home = photon_entry(&params, &counters, &before.photons[index as usize]);
                moved += usize::from(home != Some(entry * HASH_ENTRY_WORDS));
            }
        }
        let stored = before.photons.iter().filter(|ph| ph.is_stored()).count();
        for (photon, listed) in before.photons.iter().zip(&listed) {
            assert_eq!(
                photon.is_stored(),
                *listed,
                "pass {p}: stored photons listed"
            );
        }
        assert!(stored > 1000, "pass {p}: {stored} photons stored");
        assert!(
            moved as f64 <= MAX_MOVED * stored as f64,
            "pass {p}: {moved} moved"
        );
        // The gather over the GPU's lists.
        let hash = atomics(words);
        let order = atomics(&order);
        let twin = twin_gather(&before, &params, &counters, |q| {
            full_query(&params, &hash, &offsets, &order, &before.photons, q)
        });
        volume_lit = assert_gather_matches(&format!("full hash pass {p}"), &after, &twin);
    }
    volume_lit
}

#[test]
fn full_hash_renders_are_reproducible() {
    let image = || {
        let (mut sppm, _) = render(Density::FullHash);
        sppm.run(render::Budget::Passes(4), &mut |_| {})
            .expect("render")
            .image
    };
    let first = image();
    assert!(first.pixels.iter().any(|p| p.max_element() > 0.0));
    assert_eq!(first, image());
}

/// A backend restarted with the same method reuses its compiled kernels (as the viewer does
/// at every camera move) and renders what a new backend renders.
#[test]
fn restarted_full_hash_render_equals_a_new_one() {
    let (mut first, settings) = render(Density::FullHash);
    first
        .run(render::Budget::Passes(2), &mut |_| {})
        .expect("render");
    let scene = scene::testing::cornell_caustics();
    let camera = scene.camera(None).unwrap();
    let mut again = Sppm::new(first.into_backend(), &scene, &camera, settings).expect("restart");
    let (mut fresh, _) = render(Density::FullHash);
    let image = |sppm: &mut Sppm<GpuBackend>| {
        sppm.run(render::Budget::Passes(3), &mut |_| {})
            .expect("render")
            .image
    };
    assert_eq!(image(&mut again), image(&mut fresh));
}

#[test]
fn kd_tree_gather_matches_its_cpu_twin_on_the_gpu_state() {
    kd_tree_gather_matches_its_cpu_twin(scene::testing::cornell_caustics());
}

/// In murky glass: volume visible points gather the volume photons the tree visits in their
/// spheres, and surface ones pass them by.
#[test]
fn kd_tree_gather_matches_its_cpu_twin_in_murky_glass() {
    let volume_lit = kd_tree_gather_matches_its_cpu_twin(murky_furnace());
    assert!(volume_lit > 100, "{volume_lit} pixels met volume photons");
}

/// Three passes of the kd-tree gather on the GPU against the CPU backend's (every node the
/// search visits through `GatherSum::add_if_near`) on the tree of the GPU's photons; the
/// pixels whose volume statistics met photons in the last.
fn kd_tree_gather_matches_its_cpu_twin(scene: scene::Scene) -> usize {
    let (mut sppm, settings) = render_scene(scene.clone(), Density::KdTree, Precision::F32);
    let params = params_of(&scene, &settings);
    let mut volume_lit = 0;
    for p in 0..3 {
        let (before, after) = pass(&mut sppm, Density::KdTree);
        let tree = PhotonKdTree::build(&before.photons);
        let counters = atomics(&before.counters);
        let twin = twin_gather(&before, &params, &counters, |q| {
            let mut sum = GatherSum::default();
            tree.visit(q.position, q.reach(), |node| {
                let photon = Photon {
                    position: node.position,
                    normal: node.normal,
                    flux: node.flux,
                    pad: 0,
                };
                sum.add_if_near(q, &photon, 1);
            });
            sum
        });
        volume_lit = assert_gather_matches(&format!("kd-tree pass {p}"), &after, &twin);
    }
    volume_lit
}
