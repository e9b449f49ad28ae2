//! The photon kd-tree's GPU query (`kdtree.wgsl`, kernel `kdtree_query`) against its CPU twin,
//! `render::kdtree::PhotonKdTree::query`:
//!
//! - `kdtree_structs_layout_matches_rust`: the module validates through naga, its structs have
//!   Rust's sizes and offsets (as `tests/layout.rs` checks the others; it checks the prelude's
//!   KD_ constants);
//! - `kdtree_query_matches_cpu_on_random_photons`: 50k uniform and clustered photons (a tenth
//!   of the slots empty), 10k queries: the same counts, flux to rounding;
//! - `kdtree_query_matches_cpu_on_a_photon_pass`: the photons of real passes over the shipped
//!   caustics scene (the CPU photon pass), queried around themselves.
//!
//! Runs on whatever adapter wgpu finds (lavapipe in CI).

use std::mem::{offset_of, size_of};
use std::path::PathBuf;

use bvh::{BuildOptions, PackedBvh};
use cpu::{SceneData, kernels};
use glam::Vec3;
use gpu::GpuContext;
use gpu::kdtree::{self, KdQuery, KdQueryParams, KdResult, KdTreeQuery};
use naga::valid::{Capabilities, ValidationFlags, Validator};
use render::Settings;
use render::buffers::{PathSlot, Photon};
use render::kdtree::{KdNode, PhotonKdTree};
use render::packing::{surface_normal, unpack_normal};

/// Flux, relative: both sum in the same order; this leaves room for a compiler's reordering.
const RELATIVE_TOLERANCE: f32 = 1e-5;

fn context() -> GpuContext {
    GpuContext::new(None).unwrap_or_else(|e| {
        panic!("no usable GPU adapter in the test environment (CI installs Mesa lavapipe): {e}")
    })
}

fn parse(source: &str) -> naga::Module {
    naga::front::wgsl::parse_str(source)
        .unwrap_or_else(|e| panic!("kdtree_query: {}", e.emit_to_string(source)))
}

/// Asserts WGSL struct `name` spans `size` bytes with `fields` (name, offset) in order.
fn assert_layout(module: &naga::Module, name: &str, size: usize, fields: &[(&str, usize)]) {
    let (members, span) = module
        .types
        .iter()
        .find_map(|(_, ty)| match &ty.inner {
            naga::TypeInner::Struct { members, span } if ty.name.as_deref() == Some(name) => {
                Some((members.clone(), *span))
            }
            _ => None,
        })
        .unwrap_or_else(|| panic!("no WGSL struct {name}"));
    assert_eq!(span as usize, size, "{name}: WGSL span vs Rust size_of");
    let wgsl: Vec<(&str, usize)> = members
        .iter()
        .map(|m| (m.name.as_deref().unwrap_or("?"), m.offset as usize))
        .collect();
    assert_eq!(wgsl, fields, "{name}: WGSL (member, offset) vs Rust");
}

#[test]
fn kdtree_structs_layout_matches_rust() {
    let source = kdtree::source();
    let module = parse(&source);
    Validator::new(ValidationFlags::all(), Capabilities::all())
        .validate(&module)
        .unwrap_or_else(|e| panic!("kdtree_query: {}", e.emit_to_string(&source)));
    assert_layout(
        &module,
        "KdNode",
        size_of::<KdNode>(),
        &[
            ("position", offset_of!(KdNode, position)),
            ("normal", offset_of!(KdNode, normal)),
            ("flux", offset_of!(KdNode, flux)),
            ("photon_axis", offset_of!(KdNode, photon_axis)),
        ],
    );
    assert_layout(
        &module,
        "KdQuery",
        size_of::<KdQuery>(),
        &[
            ("position", offset_of!(KdQuery, position)),
            ("radius", offset_of!(KdQuery, radius)),
            ("normal", offset_of!(KdQuery, normal)),
            ("pad", offset_of!(KdQuery, pad)),
        ],
    );
    assert_layout(
        &module,
        "KdResult",
        size_of::<KdResult>(),
        &[
            ("flux", offset_of!(KdResult, flux)),
            ("found", offset_of!(KdResult, found)),
        ],
    );
    assert_layout(
        &module,
        "KdQueryParams",
        size_of::<KdQueryParams>(),
        &[
            ("query_count", offset_of!(KdQueryParams, query_count)),
            ("node_count", offset_of!(KdQueryParams, node_count)),
            ("pad0", offset_of!(KdQueryParams, pad0)),
            ("pad1", offset_of!(KdQueryParams, pad1)),
        ],
    );
}

/// SplitMix64, for test photons and queries.
struct Random(u64);

impl Random {
    fn unit(&mut self) -> f32 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        ((z ^ (z >> 31)) >> 40) as f32 / (1u64 << 24) as f32
    }

    fn vec3(&mut self, lo: f32, hi: f32) -> Vec3 {
        Vec3::new(self.unit(), self.unit(), self.unit()) * (hi - lo) + Vec3::splat(lo)
    }

    fn direction(&mut self) -> Vec3 {
        loop {
            let v = self.vec3(-1.0, 1.0);
            if (1e-4..=1.0).contains(&v.length_squared()) {
                return v.normalize();
            }
        }
    }
}

/// Half uniform in a cube, half in tight clumps; every tenth slot empty.
fn random_photons(random: &mut Random, count: usize) -> Vec<Photon> {
    let clumps: Vec<Vec3> = (0..16).map(|_| random.vec3(-1.0, 1.0)).collect();
    (0..count)
        .map(|i| {
            let position = if i % 2 == 0 {
                random.vec3(-1.0, 1.0)
            } else {
                clumps[i % clumps.len()] + random.vec3(-0.02, 0.02)
            };
            let flux = if i % 10 == 3 {
                Vec3::ZERO
            } else {
                random.vec3(0.01, 1.0)
            };
            Photon {
                position: position.to_array(),
                normal: surface_normal(random.direction()),
                flux: flux.to_array(),
                pad: 0,
            }
        })
        .collect()
}

/// Runs `queries` on the GPU and the CPU and asserts they agree; returns the photons found.
fn assert_gpu_matches_cpu(photons: &[Photon], queries: &[KdQuery]) -> u64 {
    let tree = PhotonKdTree::build(photons);
    let gpu = KdTreeQuery::new(&context())
        .run(&tree, queries)
        .expect("kdtree_query ran");
    assert_eq!(gpu.len(), queries.len());
    let mut total = 0u64;
    for (i, (query, result)) in queries.iter().zip(&gpu).enumerate() {
        let (found, flux) = tree.query(
            Vec3::from(query.position),
            query.radius,
            Vec3::from(query.normal),
        );
        assert_eq!(result.found, found, "query {i}: {query:?}");
        let difference = (Vec3::from(result.flux) - flux).abs().max_element();
        assert!(
            difference <= RELATIVE_TOLERANCE * flux.abs().max_element(),
            "query {i}: GPU flux {:?} vs CPU {flux}",
            result.flux
        );
        total += u64::from(found);
    }
    total
}

#[test]
fn kdtree_query_matches_cpu_on_random_photons() {
    let mut random = Random(17);
    let photons = random_photons(&mut random, 50_000);
    let queries: Vec<KdQuery> = (0..10_000)
        .map(|i| {
            // A third on photons (distance 0, ties with split planes), the rest anywhere.
            let position = if i % 3 == 0 {
                Vec3::from(photons[(random.unit() * 50_000.0) as usize].position)
            } else {
                random.vec3(-1.1, 1.1)
            };
            KdQuery {
                position: position.to_array(),
                radius: 0.2 * random.unit().powi(2),
                normal: random.direction().to_array(),
                pad: 0,
            }
        })
        .collect();
    let found = assert_gpu_matches_cpu(&photons, &queries);
    assert!(found > 10_000, "the queries should find photons: {found}");
}

#[test]
fn kdtree_query_matches_cpu_on_a_photon_pass() {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../scenes/cornell-caustics.gltf");
    let scene = scene::load(&path).expect("the shipped caustics scene loads");
    let bvh = PackedBvh::build(&scene.triangles, &BuildOptions::default());
    let data = SceneData::new(&scene, bvh);
    let camera = scene.camera(None).expect("a camera");
    let settings = Settings {
        seed: 5,
        ..Settings::new(16, 16, 16_384)
    };
    let lights = render::emission::light_table(&scene).len() as u32;
    let params = render::integrator::params(&scene, &camera, &settings, lights);
    // Three passes: later passes hold paths past their first bounce, and empty slots.
    let mut slots = vec![PathSlot::IDLE; settings.photons as usize];
    let mut photons = Vec::new();
    for pass in 0..3 {
        photons.clear();
        for (index, slot) in slots.iter_mut().enumerate() {
            let step = kernels::photon_pass(&data, &params, pass, index as u32, *slot);
            *slot = step.slot;
            photons.push(step.photon);
        }
    }
    let stored: Vec<&Photon> = photons.iter().filter(|p| p.is_stored()).collect();
    assert!(stored.len() > 1000, "{} photons stored", stored.len());
    let radius = 0.01 * scene.bounds().extent().length();
    let queries: Vec<KdQuery> = stored
        .iter()
        .step_by(2)
        .map(|photon| KdQuery {
            position: photon.position,
            radius,
            normal: unpack_normal(photon.normal).to_array(),
            pad: 0,
        })
        .collect();
    let found = assert_gpu_matches_cpu(&photons, &queries);
    assert!(
        found >= queries.len() as u64,
        "each query finds at least its own photon"
    );
}
