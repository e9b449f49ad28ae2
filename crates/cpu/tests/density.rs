//! The density-estimation methods `kousen bench density` compares (issue 6, table 4), on the
//! CPU backend: the full spatial hash's counting sort lists every stored photon once under its
//! entry; the full hash and the kd-tree find exactly the photons in the gather sphere; and the
//! three methods render the same picture (the full hash and the kd-tree to rounding, the
//! stochastic hash within its noise).

use std::sync::atomic::{AtomicU32, Ordering::Relaxed};

use cpu::density::{full_count, full_query, full_scan, full_scatter, photon_entry};
use cpu::kernels::GatherQuery;
use glam::Vec3;
use render::buffers::{HASH_ENTRY_WORDS, Photon, SppmParams, counter};
use render::density::full_word;
use render::kdtree::PhotonKdTree;
use render::packing::surface_normal;
use render::{Budget, Density, Image, Settings, Sppm};

fn atomics(n: usize) -> Vec<AtomicU32> {
    (0..n).map(|_| AtomicU32::new(0)).collect()
}

/// Deterministic test inputs (SplitMix64), apart from the kernels' streams.
struct SplitMix(u64);

impl SplitMix {
    fn next_f32(&mut self) -> f32 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        ((z ^ (z >> 31)) >> 40) as f32 / (1u64 << 24) as f32
    }

    fn vec3(&mut self) -> Vec3 {
        Vec3::new(self.next_f32(), self.next_f32(), self.next_f32())
    }
}

/// 5,000 photon slots in a unit box, clustered around a few points (as caustics crowd), one in
/// seven storing nothing, normals mostly up.
fn photons() -> Vec<Photon> {
    let mut rng = SplitMix(9);
    let centres: Vec<Vec3> = (0..6).map(|_| rng.vec3()).collect();
    (0..5000)
        .map(|i| {
            if i % 7 == 3 {
                return Photon::default();
            }
            let position = if i % 2 == 0 {
                centres[i % 6] + (rng.vec3() - 0.5) * 0.05
            } else {
                rng.vec3()
            };
            let normal = (Vec3::Y + (rng.vec3() - 0.5) * 2.5).normalize();
            Photon {
                position: position.to_array(),
                normal: surface_normal(normal),
                flux: (Vec3::new(0.1, 0.2, 0.3) + rng.vec3()).to_array(),
                pad: 0,
            }
        })
        .collect()
}

/// A full hash of `photons` over 1,000 entries (four scan blocks), cells for radius 0.04.
struct FullHash {
    params: SppmParams,
    counters: Vec<AtomicU32>,
    hash: Vec<AtomicU32>,
    offsets: Vec<u32>,
    order: Vec<AtomicU32>,
    cell_size: f32,
}

impl FullHash {
    fn build(photons: &[Photon]) -> FullHash {
        let params = SppmParams {
            hash_size: 1000,
            slot_count: photons.len() as u32,
            ..SppmParams::default()
        };
        let cell_size = render::hash::cell_size(0.04);
        let counters = atomics(counter::COUNT);
        counters[counter::CELL_SIZE].store(cell_size.to_bits(), Relaxed);
        let hash = atomics(params.hash_size as usize * HASH_ENTRY_WORDS);
        for photon in photons {
            full_count(&params, &counters, &hash, photon);
        }
        let offsets = full_scan(&hash);
        let order = atomics(photons.len());
        // Scattered last to first: the lists' order must not matter.
        for (i, photon) in photons.iter().enumerate().rev() {
            full_scatter(
                &params, &counters, &hash, &offsets, &order, i as u32, photon,
            );
        }
        FullHash {
            params,
            counters,
            hash,
            offsets,
            order,
            cell_size,
        }
    }
}

#[test]
fn full_hash_lists_every_stored_photon_once_under_its_entry() {
    let photons = photons();
    let full = FullHash::build(&photons);
    let stored = photons.iter().filter(|p| p.is_stored()).count();
    let mut seen = vec![false; photons.len()];
    let mut listed = 0;
    for entry in 0..full.params.hash_size as usize {
        let word = entry * HASH_ENTRY_WORDS;
        let start = full.offsets[entry / 256] + full.hash[word + full_word::START].load(Relaxed);
        let count = full.hash[word + full_word::COUNT].load(Relaxed);
        assert_eq!(full.hash[word + full_word::FILL].load(Relaxed), count);
        for place in start..start + count {
            let index = full.order[place as usize].load(Relaxed) as usize;
            assert!(!seen[index], "photon {index} listed twice");
            seen[index] = true;
            let home = photon_entry(&full.params, &full.counters, &photons[index]);
            assert_eq!(home, Some(word), "photon {index} under another entry");
        }
        listed += count as usize;
    }
    assert_eq!(listed, stored);
    for (photon, seen) in photons.iter().zip(seen) {
        assert_eq!(photon.is_stored(), seen);
    }
}

#[test]
fn full_hash_and_kd_tree_find_exactly_the_photons_in_the_sphere() {
    let photons = photons();
    let full = FullHash::build(&photons);
    let tree = PhotonKdTree::build(&photons);
    let mut rng = SplitMix(31);
    let mut nonempty = 0;
    for i in 0..2000 {
        // Half the queries sit near a photon, among the clusters.
        let near = Vec3::from(photons[(i * 37) % photons.len()].position);
        let position = if i % 2 == 0 {
            near + (rng.vec3() - 0.5) * 0.02
        } else {
            rng.vec3()
        };
        let normal = (Vec3::Y + (rng.vec3() - 0.5)).normalize();
        let radius = 0.04 * rng.next_f32();
        // Caustic photons within a smaller radius: each class is found within its own.
        let caustic_radius = 0.6 * radius;
        let radii = [caustic_radius, radius];
        let [(caustic_found, caustic_flux), (found, flux)] =
            render::kdtree::gather_brute_force_classes(&photons, position, radii, normal);
        let query = GatherQuery {
            volume: None,
            position,
            normal,
            radius,
            caustic_radius,
            cell_size: full.cell_size,
            caustic_cell_size: full.cell_size,
        };
        let listed = full_query(
            &full.params,
            &full.hash,
            &full.offsets,
            &full.order,
            &photons,
            &query,
        );
        let [tree_caustic, (tree_found, tree_flux)] = tree.query_classes(position, radii, normal);
        assert_eq!((listed.found, tree_found), (found, found));
        assert_eq!(
            (listed.caustic_found, tree_caustic.0),
            (caustic_found, caustic_found)
        );
        let scale = flux.max_element().max(caustic_flux.max_element()).max(1e-6);
        assert!((listed.flux - flux).abs().max_element() / scale < 1e-5);
        assert!((tree_flux - flux).abs().max_element() / scale < 1e-5);
        assert!((listed.caustic_flux - caustic_flux).abs().max_element() / scale < 1e-5);
        assert!((tree_caustic.1 - caustic_flux).abs().max_element() / scale < 1e-5);
        nonempty += usize::from(found > 0 && caustic_found > 0);
    }
    assert!(
        nonempty > 500,
        "too few queries met photons of both classes: {nonempty}"
    );
}

fn render(density: Density, seed: u32) -> Image {
    render_with(
        Settings {
            seed,
            density,
            ..render_settings()
        },
        24,
    )
}

/// The renders' settings: 32², 8,192 photon slots, an eye pass every 2 passes.
fn render_settings() -> Settings {
    Settings {
        eye_every: 2,
        ..Settings::new(32, 32, 8192)
    }
}

/// cornell-caustics on the CPU backend for `passes` passes.
fn render_with(settings: Settings, passes: u32) -> Image {
    let scene = scene::testing::cornell_caustics();
    let bvh = bvh::PackedBvh::build(&scene.triangles, &bvh::BuildOptions::default());
    let camera = scene.camera(None).unwrap();
    let backend = cpu::CpuBackend::new(cpu::SceneData::new(&scene, bvh));
    let mut sppm = Sppm::new(backend, &scene, &camera, settings).unwrap();
    sppm.run(Budget::Passes(passes), &mut |_| {}).unwrap().image
}

fn rel_mse(a: &Image, b: &Image) -> f64 {
    let pairs = a.pixels.iter().zip(&b.pixels);
    let sum: f64 = pairs
        .map(|(p, q)| {
            let (p, q) = (p.as_dvec3(), q.as_dvec3());
            ((p - q) * (p - q) / (q * q + 1e-2)).element_sum() / 3.0
        })
        .sum();
    sum / a.pixels.len() as f64
}

fn mean(image: &Image) -> f64 {
    image.mean().as_dvec3().element_sum()
}

/// The full hash and the kd-tree count the same photons, so their renders differ only by the
/// order flux is summed in; the stochastic hash's render differs by its added noise, no more
/// than another seed's render differs.
#[test]
fn the_methods_render_the_same_picture() {
    let full = render(Density::FullHash, 4);
    let tree = render(Density::KdTree, 4);
    let stochastic = render(Density::StochasticHash, 4);
    let other_seed = render(Density::FullHash, 5);
    assert!(mean(&full) > 0.0);
    let exact = rel_mse(&tree, &full);
    assert!(exact < 1e-8, "kd-tree against full hash: relMSE {exact}");
    let noise = rel_mse(&other_seed, &full);
    let added = rel_mse(&stochastic, &full);
    println!("relMSE to the full hash: stochastic {added:.4}, full with another seed {noise:.4}");
    assert!(
        added < 2.0 * noise,
        "stochastic {added} against seed noise {noise}"
    );
    let ratio = mean(&stochastic) / mean(&full);
    assert!((ratio - 1.0).abs() < 0.05, "mean ratio {ratio}");
}

/// f16 storage of photons and visible points (`render::half_storage`) on the CPU backend:
/// the same seed's picture to well within another seed's noise.
#[test]
fn f16_storage_renders_the_f32_picture() {
    let render = |precision, seed| {
        let settings = Settings {
            seed,
            precision,
            ..render_settings()
        };
        render_with(settings, 8)
    };
    use render::half_storage::Precision;
    let full = render(Precision::F32, 4);
    let half = render(Precision::F16, 4);
    let (rounding, noise) = (
        rel_mse(&half, &full),
        rel_mse(&render(Precision::F32, 5), &full),
    );
    assert!(rounding > 0.0, "f16 storage changed nothing");
    assert!(
        rounding < 0.05 * noise,
        "f16 {rounding} against seed noise {noise}"
    );
}
