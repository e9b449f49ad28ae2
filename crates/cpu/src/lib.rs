//! kousen's CPU backend: the SPPM kernels of [`kernels`] run over all cores with rayon, on the
//! same buffers the GPU backend keeps. It renders where no GPU adapter exists, and it is the
//! oracle the GPU kernels are tested against.

pub mod density;
pub mod kernels;
pub mod surface;

use std::sync::atomic::{AtomicU32, Ordering::Relaxed};

use rayon::prelude::*;
use render::backend::{Backend, BackendError, PhotonTracing, Setup, Snapshot, Statistics};
use render::buffers::{
    HASH_ENTRY_WORDS, Light, PathSlot, Photon, PixelStats, SppmParams, VisiblePoint, counter,
    emitted_total, vec3,
};
use render::density::Density;
use render::half_storage::{Precision, round_photon, round_visible_point};
use render::kdtree::PhotonKdTree;
use render::textures::{DEFAULT_MAX_SIDE, TextureArray};
use render::volume_boundary::share_in_weight;
use scene::{Material, Scene};

/// The scene as the CPU kernels read it: the packed BVH and triangles the GPU reads, the
/// materials, textures (in the array the GPU binds, at the side it would choose by default)
/// and light table.
pub struct SceneData {
    pub bvh: bvh::PackedBvh,
    /// The same tree four-wide, which the CPU traverses faster (same hits); `None` where the
    /// tree has leaves too large for it, and the kernels trace through `bvh`.
    pub wide: Option<bvh::WideMtbvh>,
    /// The scene's materials, indices of refraction relative to the solids they lie in
    /// (`render::nesting::Nesting::materials`).
    pub materials: Vec<Material>,
    /// Per material, the solid around it (`render::nesting::Nesting::exterior`).
    pub exterior: Vec<u32>,
    pub textures: TextureArray,
    pub lights: Vec<Light>,
    /// The sky's environment map (`render::sky_map`; four zeros without one).
    pub sky_map: Vec<f32>,
    /// Per material, the density per area with which light sampling lands on it
    /// (`render::emission::light_area_density`).
    pub light_area_density: Vec<f32>,
    /// Every material's plastic coat, over its texture's widths where one maps it.
    pub coats: render::coats::Coats,
    /// Every material's sheen table (`render::sheen`; `None` without a sheen).
    pub sheens: Vec<Option<render::sheen::SheenTable>>,
    /// The mesh's tangents of each of `bvh`'s triangles (`render::normal_map::packed_tangents`;
    /// empty without any).
    pub tangents: Vec<[glam::Vec4; 3]>,
}

impl SceneData {
    pub fn new(scene: &Scene, bvh: bvh::PackedBvh) -> SceneData {
        // One medium locator serves the nesting and the lights (`render::medium`).
        let locator = render::medium::MediumLocator::new(scene);
        let nesting = render::nesting::Nesting::of_with(scene, &locator);
        SceneData {
            wide: bvh::WideMtbvh::new(&bvh).ok(),
            tangents: render::normal_map::packed_tangents(scene, &bvh.triangle_ids),
            bvh,
            coats: render::coats::Coats::of(&nesting.materials),
            sheens: render::sheen::sheen_tables(&nesting.materials),
            materials: nesting.materials,
            exterior: nesting.exterior,
            textures: TextureArray::build(&scene.textures, DEFAULT_MAX_SIDE),
            lights: render::emission::light_table_with(scene, &locator),
            sky_map: render::sky_map::sky_map_buffer(scene.lights.sky.as_ref()),
            light_area_density: render::emission::light_area_density(scene),
        }
    }
}

/// The render's state: what the GPU backend keeps in storage buffers.
#[derive(Default)]
struct State {
    params: SppmParams,
    slots: Vec<PathSlot>,
    photons: Vec<Photon>,
    visible_points: Vec<VisiblePoint>,
    pixels: Vec<PixelStats>,
    hash: Vec<AtomicU32>,
    counters: Vec<AtomicU32>,
    /// Per slot, the segments of its last naive path (empty until the naive scheme runs).
    path_segments: Vec<u32>,
    density: Density,
    precision: Precision,
    /// The full hash's photon indices in entry order and its scan blocks' offsets.
    photon_order: Vec<AtomicU32>,
    /// The photons themselves in that order, for the gather.
    listed_photons: Vec<Photon>,
    block_offsets: Vec<u32>,
    /// This pass's kd-tree (kd-tree density only).
    kd_tree: Option<PhotonKdTree>,
}

pub struct CpuBackend {
    scene: SceneData,
    state: State,
}

impl CpuBackend {
    pub fn new(scene: SceneData) -> CpuBackend {
        CpuBackend {
            scene,
            state: State::default(),
        }
    }

    fn pass_index(&self) -> u32 {
        self.state.counters[counter::PASS].load(Relaxed)
    }

    /// This pass's photons (for tests and benchmarks).
    pub fn photons(&self) -> &[Photon] {
        &self.state.photons
    }

    pub fn visible_points(&self) -> &[VisiblePoint] {
        &self.state.visible_points
    }

    /// The hash table's words (entry-major: priority, count, winner).
    pub fn hash_words(&self) -> Vec<u32> {
        self.state.hash.iter().map(|w| w.load(Relaxed)).collect()
    }

    pub fn counters(&self) -> Vec<u32> {
        self.state
            .counters
            .iter()
            .map(|w| w.load(Relaxed))
            .collect()
    }
}

/// The CPU's model name ("Intel(R) Xeon(R) Processor @ 2.50GHz"), from /proc/cpuinfo where
/// there is one, else the architecture.
pub fn cpu_model() -> String {
    std::fs::read_to_string("/proc/cpuinfo")
        .ok()
        .and_then(|text| {
            text.lines()
                .find(|line| line.starts_with("model name"))
                .and_then(|line| line.split_once(':'))
                .map(|(_, name)| name.trim().to_owned())
        })
        .unwrap_or_else(|| std::env::consts::ARCH.to_owned())
}

/// The processor doing the CPU backend's work: its model and rayon's thread count.
pub fn processor_name() -> String {
    format!("{} ({} threads)", cpu_model(), rayon::current_num_threads())
}

fn clear(words: &[AtomicU32]) {
    words.par_iter().for_each(|w| w.store(0, Relaxed));
}

fn atomics(values: impl IntoIterator<Item = u32>) -> Vec<AtomicU32> {
    values.into_iter().map(AtomicU32::new).collect()
}

impl Backend for CpuBackend {
    fn name(&self) -> &'static str {
        "cpu"
    }

    fn adapter(&self) -> String {
        processor_name()
    }

    fn start(&mut self, setup: &Setup) -> Result<(), BackendError> {
        let params = setup.params;
        let pixels = params.pixel_count() as usize;
        self.scene.lights = setup.lights.clone();
        self.state = State {
            params,
            slots: vec![PathSlot::IDLE; params.slot_count as usize],
            photons: vec![Photon::default(); params.slot_count as usize],
            visible_points: vec![VisiblePoint::default(); pixels],
            pixels: vec![setup.initial_stats(); pixels],
            hash: atomics(std::iter::repeat_n(
                0,
                params.hash_entries() * HASH_ENTRY_WORDS,
            )),
            counters: atomics(setup.initial_counters()),
            path_segments: Vec::new(),
            density: setup.density,
            precision: setup.precision,
            photon_order: match setup.density {
                Density::FullHash => atomics(std::iter::repeat_n(0, params.slot_count as usize)),
                _ => Vec::new(),
            },
            block_offsets: Vec::new(),
            listed_photons: Vec::new(),
            kd_tree: None,
        };
        Ok(())
    }

    fn eye_pass(&mut self) {
        let pass = self.pass_index();
        let (scene, state) = (&self.scene, &mut self.state);
        let params = state.params;
        let (precision, origin) = (state.precision, vec3(params.storage_origin));
        state
            .visible_points
            .par_iter_mut()
            .zip(state.pixels.par_iter_mut())
            .enumerate()
            .for_each(|(index, (point, stats))| {
                let visible_point =
                    kernels::eye_pass_pixel(scene, &params, pass, index as u32, stats);
                *point = match precision {
                    Precision::F32 => visible_point,
                    Precision::F16 => {
                        let kept = share_in_weight(&visible_point, stats.volume_radius);
                        round_visible_point(&kept, origin)
                    }
                };
            });
    }

    fn photon_pass(&mut self) {
        let pass = self.pass_index();
        let (scene, state) = (&self.scene, &mut self.state);
        let params = state.params;
        let (precision, origin) = (state.precision, vec3(params.storage_origin));
        // Counted per thread and added once: one shared atomic per emitted path would bounce
        // its cache line between the cores.
        let emitted: u32 = state
            .slots
            .par_iter_mut()
            .zip(state.photons.par_iter_mut())
            .enumerate()
            .map(|(index, (slot, photon))| {
                let step = kernels::photon_pass(scene, &params, pass, index as u32, *slot);
                *slot = step.slot;
                *photon = match precision {
                    Precision::F32 => step.photon,
                    Precision::F16 => round_photon(&step.photon, origin, params.storage_flux_scale),
                };
                u32::from(step.emitted)
            })
            .sum();
        state.counters[counter::EMITTED_PASS].fetch_add(emitted, Relaxed);
    }

    fn build_hash(&mut self) {
        let state = &mut self.state;
        match state.density {
            Density::StochasticHash => {
                clear(&state.hash);
                let each = |kernel: fn(&SppmParams, &[AtomicU32], &[AtomicU32], u32, &Photon)| {
                    state.photons.par_iter().enumerate().for_each(|(i, p)| {
                        kernel(&state.params, &state.counters, &state.hash, i as u32, p)
                    });
                };
                each(kernels::hash_count);
                each(kernels::hash_select);
            }
            Density::FullHash => {
                clear(&state.hash);
                let (params, counters, hash) = (&state.params, &state.counters, &state.hash);
                state
                    .photons
                    .par_iter()
                    .for_each(|p| density::full_count(params, counters, hash, p));
                state.block_offsets = density::full_scan(hash);
                let (offsets, order) = (&state.block_offsets, &state.photon_order);
                state.photons.par_iter().enumerate().for_each(|(i, p)| {
                    density::full_scatter(params, counters, hash, offsets, order, i as u32, p)
                });
                // The GPU's lists stay in arrival order; the CPU's are sorted, so that its
                // images are reproducible.
                density::sort_lists(hash, offsets, order);
                density::list_photons(order, &state.photons, &mut state.listed_photons);
            }
            Density::KdTree => state.kd_tree = Some(PhotonKdTree::build(&state.photons)),
        }
    }

    fn gather(&mut self) {
        let state = &mut self.state;
        let (params, counters, hash, photons) =
            (&state.params, &state.counters, &state.hash, &state.photons);
        let (offsets, listed, tree) = (
            &state.block_offsets,
            &state.listed_photons,
            state.kd_tree.as_ref(),
        );
        let density = state.density;
        let query = |query: &kernels::GatherQuery| match (density, tree) {
            (Density::FullHash, _) => {
                density::full_query_listed(params, hash, offsets, listed, query)
            }
            // No tree: no hash was built this pass, so no photon is found.
            (Density::KdTree, tree) => tree.map_or_else(Default::default, |tree| {
                let mut sum = kernels::GatherSum::default();
                tree.visit(query.position, query.reach(), |node| {
                    let photon = render::buffers::Photon {
                        position: node.position,
                        normal: node.normal,
                        flux: node.flux,
                        pad: 0,
                    };
                    sum.add_if_near(query, &photon, 1);
                });
                sum
            }),
            (Density::StochasticHash, _) => kernels::stochastic_query(params, hash, photons, query),
        };
        // The pass's lit radii, summed per thread and offered once (as with the emitted
        // paths: no shared atomic per pixel).
        let served = kernels::served_largest(counters);
        state
            .pixels
            .par_iter_mut()
            .zip(state.visible_points.par_iter())
            .fold(kernels::LitSummary::default, |summary, (stats, point)| {
                let (next, lit) = kernels::gather_update(counters, params, point, *stats, query);
                *stats = next;
                summary.add(lit, served)
            })
            .reduce(kernels::LitSummary::default, kernels::LitSummary::merge)
            .offer(counters);
        kernels::finish_pass(params, counters);
    }

    fn synchronize(&mut self) -> Result<(), BackendError> {
        Ok(())
    }

    fn emitted_paths(&mut self) -> Result<u64, BackendError> {
        let c = &self.state.counters;
        Ok(emitted_total(
            c[counter::EMITTED_LO].load(Relaxed),
            c[counter::EMITTED_HI].load(Relaxed),
        ))
    }

    fn read_statistics(&mut self) -> Result<Statistics, BackendError> {
        Ok(Statistics {
            pixels: self.state.pixels.clone(),
            emitted_paths: self.emitted_paths()?,
        })
    }

    fn read_visible_points(&mut self) -> Result<Vec<VisiblePoint>, BackendError> {
        Ok(self.state.visible_points.clone())
    }

    fn snapshot(&mut self) -> Result<Snapshot, BackendError> {
        let s = &self.state;
        Ok(Snapshot {
            counters: s.counters.iter().map(|c| c.load(Relaxed)).collect(),
            slots: bytemuck::cast_slice(&s.slots).to_vec(),
            // f32 points whatever the precision (f16 ones are kept rounded, in f32).
            visible_points: bytemuck::cast_slice(&s.visible_points).to_vec(),
            pixels: bytemuck::cast_slice(&s.pixels).to_vec(),
        })
    }

    fn restore(&mut self, snapshot: &Snapshot) -> Result<(), BackendError> {
        let s = &mut self.state;
        let words = |n: usize, size: usize| n * size / 4;
        snapshot.check_sizes([
            s.counters.len(),
            words(s.slots.len(), size_of::<PathSlot>()),
            words(s.visible_points.len(), size_of::<VisiblePoint>()),
            words(s.pixels.len(), size_of::<PixelStats>()),
        ])?;
        for (counter, &word) in s.counters.iter().zip(&snapshot.counters) {
            counter.store(word, Relaxed);
        }
        s.slots = bytemuck::cast_slice(&snapshot.slots).to_vec();
        s.visible_points = bytemuck::cast_slice(&snapshot.visible_points).to_vec();
        s.pixels = bytemuck::cast_slice(&snapshot.pixels).to_vec();
        Ok(())
    }

    fn memory(&self) -> Vec<(&'static str, u64)> {
        let s = &self.state;
        let bytes = |n: usize, size: usize| (n * size) as u64;
        let bvh = self.scene.bvh.memory();
        vec![
            ("scene", bvh.triangle_bytes as u64),
            (
                "bvh",
                (bvh.node_bytes + 7 * bvh.link_set_bytes) as u64
                    + self.scene.wide.as_ref().map_or(0, |w| w.bytes() as u64),
            ),
            ("textures", self.scene.textures.bytes()),
            (
                "photons",
                bytes(s.slots.len(), size_of::<PathSlot>())
                    + bytes(s.photons.len(), size_of::<Photon>()),
            ),
            (
                "hash",
                bytes(s.hash.len() + s.photon_order.len(), size_of::<u32>())
                    + bytes(s.listed_photons.capacity(), size_of::<Photon>())
                    + s.kd_tree
                        .as_ref()
                        .map_or(0, |t| size_of_val(t.nodes()) as u64),
            ),
            (
                "visible_points",
                bytes(s.visible_points.len(), size_of::<VisiblePoint>()),
            ),
            ("statistics", bytes(s.pixels.len(), size_of::<PixelStats>())),
        ]
    }
}

impl PhotonTracing for CpuBackend {
    fn finish_pass(&mut self) {
        kernels::finish_pass(&self.state.params, &self.state.counters);
    }

    fn photon_trace_naive(&mut self) {
        let pass = self.pass_index();
        let (scene, state) = (&self.scene, &mut self.state);
        let params = state.params;
        let counters = &state.counters;
        state.path_segments.resize(params.slot_count as usize, 0);
        state
            .path_segments
            .par_iter_mut()
            .zip(state.photons.par_iter_mut())
            .enumerate()
            .for_each(|(index, (segments, photon))| {
                let path = kernels::photon_trace_naive(scene, &params, pass, index as u32);
                *segments = path.segments;
                *photon = path.photon;
                counters[counter::EMITTED_PASS].fetch_add(1, Relaxed);
            });
    }

    fn read_path_segments(&mut self) -> Result<Vec<u32>, BackendError> {
        Ok(self.state.path_segments.clone())
    }
}
