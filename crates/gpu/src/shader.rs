//! Shader modules assembled from the generated prelude and the files under `shaders/`. WGSL has
//! no includes, so each kernel names the shared pieces it needs, in dependency order.

use std::borrow::Cow;

use crate::prelude;
use crate::random_variants::{self, Generator};
use crate::scene_upload::SceneStorage;

const DISPATCH: &str = include_str!("../shaders/shared/dispatch.wgsl");
const BVH_TYPES: &str = include_str!("../shaders/shared/bvh_types.wgsl");
const GPU_TYPES: &str = include_str!("../shaders/shared/gpu_types.wgsl");
const SCENE_BINDINGS: &str = include_str!("../shaders/shared/scene_bindings.wgsl");
const SCENE_TEXELS: &str = include_str!("../shaders/shared/scene_texels.wgsl");
const INTERSECT: &str = include_str!("../shaders/shared/intersect.wgsl");
const TRAVERSE: &str = include_str!("../shaders/shared/traverse.wgsl");
const TRAVERSE_COMPACT: &str = include_str!("../shaders/shared/traverse_compact.wgsl");
const TRAVERSE_WIDE: &str = include_str!("../shaders/shared/traverse_wide.wgsl");
const TRACE: &str = include_str!("../shaders/kernels/trace.wgsl");
const RAYGEN: &str = include_str!("../shaders/kernels/raygen.wgsl");
const RANDOM: &str = include_str!("../shaders/shared/random.wgsl");
/// The kernels' generator; `random_variants` swaps this part for another.
pub(crate) const RANDOM_PCG: &str = include_str!("../shaders/shared/random_pcg.wgsl");
const SPPM_TYPES: &str = include_str!("../shaders/shared/sppm_types.wgsl");
const STORAGE_F32: &str = include_str!("../shaders/shared/photon_storage_f32.wgsl");
const STORAGE_F16: &str = include_str!("../shaders/shared/photon_storage_f16.wgsl");
/// The part of the SPPM modules that declares how photons and visible points are stored.
const STORAGE_PART: &str = "shared/photon_storage_f32.wgsl";
/// The files that can stand in that part ([`Module::source_with_precision`]).
pub const STORAGE_PARTS: [&str; 2] = [STORAGE_PART, "shared/photon_storage_f16.wgsl"];
const TEXTURES: &str = include_str!("../shaders/shared/textures.wgsl");
/// A file under `shaders/` as a module's part: (its name there, its text).
macro_rules! part {
    ($name:literal) => {
        ($name, include_str!(concat!("../shaders/", $name)))
    };
}
/// What the SPPM kernels know about a hit and the arithmetic their paths share, a concern a
/// file (each names the `render`/`cpu` functions it twins).
const SHADING: [(&str, &str); 13] = [
    part!("shared/shading/optics.wgsl"),
    part!("shared/shading/packing.wgsl"),
    part!("shared/shading/normals.wgsl"),
    part!("shared/shading/surface.wgsl"),
    part!("shared/shading/materials.wgsl"),
    part!("shared/shading/media.wgsl"),
    part!("shared/shading/volume_boundary.wgsl"),
    part!("shared/shading/thin_film.wgsl"),
    part!("shared/shading/microfacet.wgsl"),
    part!("shared/shading/coats.wgsl"),
    part!("shared/shading/sheen.wgsl"),
    part!("shared/shading/bounces.wgsl"),
    part!("shared/shading/hash.wgsl"),
];
/// The SPPM kernels, twins of `cpu::kernels`: group 1's bindings, then a file per concern
/// (lights, direct light, the photon pass, the eye pass, the hash and gather).
const SPPM: [(&str, &str); 8] = [
    part!("kernels/sppm/bindings.wgsl"),
    part!("kernels/sppm/lights.wgsl"),
    part!("kernels/sppm/light_sampling.wgsl"),
    part!("kernels/sppm/direct_light.wgsl"),
    part!("kernels/sppm/photon_pass.wgsl"),
    part!("kernels/sppm/camera.wgsl"),
    part!("kernels/sppm/eye_pass.wgsl"),
    part!("kernels/sppm/gather.wgsl"),
];
const SKY_MAP: &str = include_str!("../shaders/shared/sky_map.wgsl");
const DENSITY_GRID: &str = include_str!("../shaders/shared/density_grid.wgsl");
const DENSITY_STOCHASTIC: &str = include_str!("../shaders/shared/density_stochastic.wgsl");
const DENSITY_FULL: &str = include_str!("../shaders/shared/density_full.wgsl");
const DENSITY_KDTREE: &str = include_str!("../shaders/shared/density_kdtree.wgsl");
const KDTREE: &str = include_str!("../shaders/shared/kdtree.wgsl");
const DISPLAY: &str = include_str!("../shaders/kernels/display.wgsl");
const PHOTON_TRACE_NAIVE: &str = include_str!("../shaders/kernels/photon_trace_naive.wgsl");

/// The files that can stand as a module's scene bindings ([`with_scene_storage`]).
pub const SCENE_PARTS: [&str; 2] = ["shared/scene_bindings.wgsl", "shared/scene_texels.wgsl"];

/// `source` (a module's, as [`Module::source`] and its kin make it, which read the scene from
/// storage buffers) reading the scene from `storage`: with texels, `scene_texels.wgsl` stands
/// in for `scene_bindings.wgsl`, which defines the same load functions. Sources without the
/// scene's bindings (the display's) are returned as they are.
pub fn with_scene_storage(source: String, storage: SceneStorage) -> String {
    match storage {
        SceneStorage::Buffers => source,
        SceneStorage::Texels => source.replacen(SCENE_BINDINGS, SCENE_TEXELS, 1),
    }
}

/// The sky map's functions (`sky_map.wgsl`) after the prelude, for a test kernel that calls
/// them: it declares the `sky_map` buffer they read.
pub fn sky_map_source() -> String {
    format!("{}\n{SKY_MAP}", prelude::wgsl())
}

/// A shader module of kousen's.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Module {
    /// Closest- and any-hit traversal kernels (`trace.wgsl`); the compact MTBVH's bind group 2
    /// (`traverse_compact.wgsl`) is theirs alone.
    Trace,
    /// Benchmark ray generation (`raygen.wgsl`).
    Raygen,
    /// The SPPM kernels (`kernels/sppm/*.wgsl`, over `shared/shading/*.wgsl`).
    Sppm,
    /// The progressive image on screen: vertex and fragment shaders over the SPPM statistics
    /// (`display.wgsl`, used by [`crate::display`]); no scene bindings.
    Display,
    /// The SPPM kernels and the naive photon-tracing scheme (`photon_trace_naive.wgsl`), for
    /// `kousen bench photons` only: its extra storage buffer keeps it out of [`Module::Sppm`].
    PhotonTraceNaive,
    /// The SPPM kernels with the full spatial hash's build kernels and gather
    /// (`density_full.wgsl`, bind group 3), for `kousen bench density`.
    SppmFullHash,
    /// The SPPM kernels gathering from a kd-tree built on the CPU (`density_kdtree.wgsl`,
    /// bind group 3), for `kousen bench density`.
    SppmKdTree,
    /// The SPPM kernels drawing from another random generator (`random_variants`), for
    /// `kousen bench rng`.
    SppmRandom(Generator),
}

impl Module {
    pub const ALL: [Module; 10] = [
        Module::Trace,
        Module::Raygen,
        Module::Sppm,
        Module::Display,
        Module::PhotonTraceNaive,
        Module::SppmFullHash,
        Module::SppmKdTree,
        Module::SppmRandom(Generator::TalkFloat),
        Module::SppmRandom(Generator::Tea),
        Module::SppmRandom(Generator::FractSin),
    ];

    /// The files it is made of, as (name, text), after the prelude.
    pub fn parts(self) -> Vec<(&'static str, &'static str)> {
        let scene = [
            ("shared/dispatch.wgsl", DISPATCH),
            ("shared/bvh_types.wgsl", BVH_TYPES),
            ("shared/gpu_types.wgsl", GPU_TYPES),
            ("shared/scene_bindings.wgsl", SCENE_BINDINGS),
        ];
        let own: &[(&str, &str)] = match self {
            Module::Trace => &[
                ("shared/intersect.wgsl", INTERSECT),
                ("shared/traverse.wgsl", TRAVERSE),
                ("shared/traverse_compact.wgsl", TRAVERSE_COMPACT),
                ("shared/traverse_wide.wgsl", TRAVERSE_WIDE),
                ("kernels/trace.wgsl", TRACE),
            ],
            Module::Raygen => &[
                ("shared/random.wgsl", RANDOM),
                ("kernels/raygen.wgsl", RAYGEN),
            ],
            Module::Sppm => {
                let mut parts = scene.to_vec();
                parts.extend_from_slice(&[
                    ("shared/intersect.wgsl", INTERSECT),
                    ("shared/traverse.wgsl", TRAVERSE),
                    ("shared/random.wgsl", RANDOM),
                    ("shared/random_pcg.wgsl", RANDOM_PCG),
                    ("shared/sppm_types.wgsl", SPPM_TYPES),
                    (STORAGE_PART, STORAGE_F32),
                    ("shared/textures.wgsl", TEXTURES),
                ]);
                parts.extend_from_slice(&SHADING);
                parts.push(("shared/sky_map.wgsl", SKY_MAP));
                parts.extend_from_slice(&SPPM);
                parts.push(("shared/density_grid.wgsl", DENSITY_GRID));
                parts.push(("shared/density_stochastic.wgsl", DENSITY_STOCHASTIC));
                return parts;
            }
            Module::SppmFullHash => {
                return Module::Sppm.with_density(&[
                    ("shared/density_grid.wgsl", DENSITY_GRID),
                    ("shared/density_full.wgsl", DENSITY_FULL),
                ]);
            }
            Module::SppmKdTree => {
                return Module::Sppm.with_density(&[
                    ("shared/kdtree.wgsl", KDTREE),
                    ("shared/density_kdtree.wgsl", DENSITY_KDTREE),
                ]);
            }
            Module::SppmRandom(generator) => return random_variants::sppm_parts(generator),
            Module::PhotonTraceNaive => {
                let mut parts = Module::Sppm.parts();
                parts.push(("kernels/photon_trace_naive.wgsl", PHOTON_TRACE_NAIVE));
                return parts;
            }
            // The statistics' struct only: the display binds no scene.
            Module::Display => {
                return vec![
                    ("shared/sppm_types.wgsl", SPPM_TYPES),
                    ("kernels/display.wgsl", DISPLAY),
                ];
            }
        };
        scene.iter().chain(own).copied().collect()
    }

    /// These parts with the stochastic hash's query (the grid's loops and its entries)
    /// replaced by `density` (files defining `density_query`).
    fn with_density(
        self,
        density: &[(&'static str, &'static str)],
    ) -> Vec<(&'static str, &'static str)> {
        let mut parts: Vec<_> = self
            .parts()
            .into_iter()
            .filter(|&(name, _)| {
                !matches!(
                    name,
                    "shared/density_grid.wgsl" | "shared/density_stochastic.wgsl"
                )
            })
            .collect();
        parts.extend_from_slice(density);
        parts
    }

    /// The whole WGSL source with photons and visible points stored in `precision` (modules
    /// that store none are unchanged).
    pub fn source_with_precision(self, precision: render::half_storage::Precision) -> String {
        let storage = match precision {
            render::half_storage::Precision::F32 => STORAGE_F32,
            render::half_storage::Precision::F16 => STORAGE_F16,
        };
        let mut text = prelude::wgsl();
        for (name, part) in self.parts() {
            let part = if name == STORAGE_PART { storage } else { part };
            text.push_str(&format!("\n// ---- {name} ----\n"));
            text.push_str(part);
        }
        text
    }

    /// The whole WGSL source.
    pub fn source(self) -> String {
        self.source_with_precision(render::half_storage::Precision::F32)
    }

    /// Compiles it on `device`, reading the scene from `storage`.
    pub fn create(self, device: &wgpu::Device, storage: SceneStorage) -> wgpu::ShaderModule {
        device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some(self.label()),
            source: wgpu::ShaderSource::Wgsl(Cow::Owned(with_scene_storage(
                self.source(),
                storage,
            ))),
        })
    }

    pub fn label(self) -> &'static str {
        match self {
            Module::Trace => "trace.wgsl",
            Module::Raygen => "raygen.wgsl",
            Module::Sppm => "sppm/*.wgsl",
            Module::Display => "display.wgsl",
            Module::PhotonTraceNaive => "photon_trace_naive.wgsl",
            Module::SppmFullHash => "sppm/*.wgsl + density_full.wgsl",
            Module::SppmKdTree => "sppm/*.wgsl + density_kdtree.wgsl",
            Module::SppmRandom(generator) => generator.label(),
        }
    }
}
