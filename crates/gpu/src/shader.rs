//! Shader modules assembled from the generated prelude and the files under `shaders/`. WGSL has
//! no includes, so each kernel names the shared pieces it needs, in dependency order.

use std::borrow::Cow;

use crate::prelude;

const DISPATCH: &str = include_str!("../shaders/shared/dispatch.wgsl");
const BVH_TYPES: &str = include_str!("../shaders/shared/bvh_types.wgsl");
const GPU_TYPES: &str = include_str!("../shaders/shared/gpu_types.wgsl");
const SCENE_BINDINGS: &str = include_str!("../shaders/shared/scene_bindings.wgsl");
const INTERSECT: &str = include_str!("../shaders/shared/intersect.wgsl");
const TRAVERSE: &str = include_str!("../shaders/shared/traverse.wgsl");
const TRAVERSE_COMPACT: &str = include_str!("../shaders/shared/traverse_compact.wgsl");
const TRACE: &str = include_str!("../shaders/kernels/trace.wgsl");
const RAYGEN: &str = include_str!("../shaders/kernels/raygen.wgsl");
const RANDOM: &str = include_str!("../shaders/shared/random.wgsl");
const SPPM_TYPES: &str = include_str!("../shaders/shared/sppm_types.wgsl");
const TEXTURES: &str = include_str!("../shaders/shared/textures.wgsl");
const SHADING: &str = include_str!("../shaders/shared/shading.wgsl");
const SPPM: &str = include_str!("../shaders/kernels/sppm.wgsl");
const DISPLAY: &str = include_str!("../shaders/kernels/display.wgsl");
const PHOTON_TRACE_NAIVE: &str = include_str!("../shaders/kernels/photon_trace_naive.wgsl");

/// A shader module of kousen's.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Module {
    /// Closest- and any-hit traversal kernels (`trace.wgsl`); the compact MTBVH's bind group 2
    /// (`traverse_compact.wgsl`) is theirs alone.
    Trace,
    /// Benchmark ray generation (`raygen.wgsl`).
    Raygen,
    /// The SPPM kernels (`sppm.wgsl`).
    Sppm,
    /// The progressive image on screen: vertex and fragment shaders over the SPPM statistics
    /// (`display.wgsl`, used by [`crate::display`]); no scene bindings.
    Display,
    /// The SPPM kernels and the naive photon-tracing scheme (`photon_trace_naive.wgsl`), for
    /// `kousen bench photons` only: its extra storage buffer keeps it out of [`Module::Sppm`].
    PhotonTraceNaive,
}

impl Module {
    pub const ALL: [Module; 5] = [
        Module::Trace,
        Module::Raygen,
        Module::Sppm,
        Module::Display,
        Module::PhotonTraceNaive,
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
                ("kernels/trace.wgsl", TRACE),
            ],
            Module::Raygen => &[
                ("shared/random.wgsl", RANDOM),
                ("kernels/raygen.wgsl", RAYGEN),
            ],
            Module::Sppm => &[
                ("shared/intersect.wgsl", INTERSECT),
                ("shared/traverse.wgsl", TRAVERSE),
                ("shared/random.wgsl", RANDOM),
                ("shared/sppm_types.wgsl", SPPM_TYPES),
                ("shared/textures.wgsl", TEXTURES),
                ("shared/shading.wgsl", SHADING),
                ("kernels/sppm.wgsl", SPPM),
            ],
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

    /// The whole WGSL source.
    pub fn source(self) -> String {
        let mut text = prelude::wgsl();
        for (name, part) in self.parts() {
            text.push_str(&format!("\n// ---- {name} ----\n"));
            text.push_str(part);
        }
        text
    }

    /// Compiles it on `device`.
    pub fn create(self, device: &wgpu::Device) -> wgpu::ShaderModule {
        device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some(self.label()),
            source: wgpu::ShaderSource::Wgsl(Cow::Owned(self.source())),
        })
    }

    pub fn label(self) -> &'static str {
        match self {
            Module::Trace => "trace.wgsl",
            Module::Raygen => "raygen.wgsl",
            Module::Sppm => "sppm.wgsl",
            Module::Display => "display.wgsl",
            Module::PhotonTraceNaive => "photon_trace_naive.wgsl",
        }
    }
}
