//! kousen's CPU backend: the SPPM kernels of [`kernels`] run over all cores with rayon, on the
//! same buffers the GPU backend keeps. It renders where no GPU adapter exists, and it is the
//! oracle the GPU kernels are tested against.

pub mod kernels;
pub mod surface;

use std::sync::atomic::{AtomicU32, Ordering::Relaxed};

use rayon::prelude::*;
use render::backend::{Backend, BackendError, PhotonTracing, Setup, Statistics};
use render::buffers::{
    HASH_ENTRY_WORDS, Light, PathSlot, Photon, PixelStats, SppmParams, VisiblePoint, counter,
    emitted_total, initial_counters,
};
use render::textures::{DEFAULT_MAX_SIDE, TextureArray};
use scene::{Material, Scene};

/// The scene as the CPU kernels read it: the packed BVH and triangles the GPU reads, the
/// materials, textures (in the array the GPU binds, at the side it would choose by default)
/// and light table.
pub struct SceneData {
    pub bvh: bvh::PackedBvh,
    pub materials: Vec<Material>,
    pub textures: TextureArray,
    pub lights: Vec<Light>,
}

impl SceneData {
    pub fn new(scene: &Scene, bvh: bvh::PackedBvh) -> SceneData {
        SceneData {
            bvh,
            materials: scene.materials.clone(),
            textures: TextureArray::build(&scene.textures, DEFAULT_MAX_SIDE),
            lights: render::emission::light_table(scene),
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
            pixels: vec![PixelStats::initial(setup.initial_radius); pixels],
            hash: atomics(std::iter::repeat_n(
                0,
                params.hash_size as usize * HASH_ENTRY_WORDS,
            )),
            counters: atomics(initial_counters(setup.initial_radius)),
            path_segments: Vec::new(),
        };
        Ok(())
    }

    fn eye_pass(&mut self) {
        let pass = self.pass_index();
        let (scene, state) = (&self.scene, &mut self.state);
        let params = state.params;
        state
            .visible_points
            .par_iter_mut()
            .zip(state.pixels.par_iter_mut())
            .enumerate()
            .for_each(|(index, (point, stats))| {
                let step = kernels::eye_pass(scene, &params, pass, index as u32);
                *point = step.visible_point;
                for (d, s) in stats.direct.iter_mut().zip(step.direct.to_array()) {
                    *d += s;
                }
            });
    }

    fn photon_pass(&mut self) {
        let pass = self.pass_index();
        let (scene, state) = (&self.scene, &mut self.state);
        let params = state.params;
        let counters = &state.counters;
        state
            .slots
            .par_iter_mut()
            .zip(state.photons.par_iter_mut())
            .enumerate()
            .for_each(|(index, (slot, photon))| {
                let step = kernels::photon_pass(scene, &params, pass, index as u32, *slot);
                *slot = step.slot;
                *photon = step.photon;
                if step.emitted {
                    counters[counter::EMITTED_PASS].fetch_add(1, Relaxed);
                }
            });
    }

    fn build_hash(&mut self) {
        let state = &self.state;
        state.hash.par_iter().for_each(|w| w.store(0, Relaxed));
        let each = |kernel: fn(&SppmParams, &[AtomicU32], &[AtomicU32], u32, &Photon)| {
            state.photons.par_iter().enumerate().for_each(|(i, p)| {
                kernel(&state.params, &state.counters, &state.hash, i as u32, p)
            });
        };
        each(kernels::hash_count);
        each(kernels::hash_select);
    }

    fn gather(&mut self) {
        let state = &mut self.state;
        let (params, counters, hash, photons) =
            (&state.params, &state.counters, &state.hash, &state.photons);
        state
            .pixels
            .par_iter_mut()
            .zip(state.visible_points.par_iter())
            .for_each(|(stats, point)| {
                *stats = kernels::gather(params, counters, hash, photons, point, *stats);
            });
        kernels::finish_pass(&state.counters);
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

    fn memory(&self) -> Vec<(&'static str, u64)> {
        let s = &self.state;
        let bytes = |n: usize, size: usize| (n * size) as u64;
        let bvh = self.scene.bvh.memory();
        vec![
            ("scene", bvh.triangle_bytes as u64),
            ("bvh", (bvh.node_bytes + 7 * bvh.link_set_bytes) as u64),
            ("textures", self.scene.textures.bytes()),
            (
                "photons",
                bytes(s.slots.len(), size_of::<PathSlot>())
                    + bytes(s.photons.len(), size_of::<Photon>()),
            ),
            ("hash", bytes(s.hash.len(), size_of::<u32>())),
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
        kernels::finish_pass(&self.state.counters);
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
