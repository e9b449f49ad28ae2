//! The SPPM kernels with another random generator (issue 6, table 6): the kernels name only
//! `Rng`, `rng_start` and `next_f32`, so swapping `shared/random_pcg.wgsl` for another
//! `shared/random_<name>.wgsl` changes every stream. Each file is the twin of one
//! `render::random` generator; its constants are generated here from that generator's.

use std::sync::LazyLock;

use render::random::{self, FractSin, Pcg, StreamRng, TalkFloat, Tea};

use crate::shader::{Module, RANDOM_PCG};
use crate::{GpuContext, GpuError, prelude, readback};

const RANDOM_TALK: &str = include_str!("../shaders/shared/random_talk.wgsl");
const RANDOM_TEA: &str = include_str!("../shaders/shared/random_tea.wgsl");
const RANDOM_FRACT_SIN: &str = include_str!("../shaders/shared/random_fract_sin.wgsl");
/// The part of [`Module::Sppm`] that holds the generator.
const GENERATOR_PART: &str = "shared/random_pcg.wgsl";
/// The generators' constants ([`constants_wgsl`]), made once so modules can list them as a part.
static CONSTANTS: LazyLock<String> = LazyLock::new(constants_wgsl);
const CONSTANTS_PART: &str = "generated/random_constants.wgsl";

/// A generator the kernels can be compiled with.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Generator {
    /// `render::random::Pcg`, the renderer's own.
    Pcg,
    /// `render::random::TalkFloat`, the talk's float-only `GPURnd`.
    TalkFloat,
    /// `render::random::Tea`, TEA in 8 rounds.
    Tea,
    /// `render::random::FractSin`, the noise function (GPU draws differ from the CPU's).
    FractSin,
}

impl Generator {
    pub const ALL: [Generator; 4] = [
        Generator::Pcg,
        Generator::TalkFloat,
        Generator::Tea,
        Generator::FractSin,
    ];

    /// The name its CPU twin goes by (`StreamRng::NAME`).
    pub fn name(self) -> &'static str {
        match self {
            Generator::Pcg => Pcg::NAME,
            Generator::TalkFloat => TalkFloat::NAME,
            Generator::Tea => Tea::NAME,
            Generator::FractSin => FractSin::NAME,
        }
    }

    /// Parses [`Generator::name`].
    pub fn from_name(name: &str) -> Option<Generator> {
        Generator::ALL.into_iter().find(|g| g.name() == name)
    }

    /// Its WGSL file (name, text), defining `Rng`, `rng_start` and `next_f32`.
    pub fn part(self) -> (&'static str, &'static str) {
        match self {
            Generator::Pcg => (GENERATOR_PART, RANDOM_PCG),
            Generator::TalkFloat => ("shared/random_talk.wgsl", RANDOM_TALK),
            Generator::Tea => ("shared/random_tea.wgsl", RANDOM_TEA),
            Generator::FractSin => ("shared/random_fract_sin.wgsl", RANDOM_FRACT_SIN),
        }
    }

    /// The label of its SPPM module.
    pub fn label(self) -> &'static str {
        match self {
            Generator::Pcg => "sppm/*.wgsl",
            Generator::TalkFloat => "sppm/*.wgsl + random_talk.wgsl",
            Generator::Tea => "sppm/*.wgsl + random_tea.wgsl",
            Generator::FractSin => "sppm/*.wgsl + random_fract_sin.wgsl",
        }
    }

    /// Exactly the CPU twin's draws on any device (integer states; see `render::random`)?
    /// TalkFloat's states are exact but its output rounds a sum, so within a few ULP;
    /// FractSin's GPU `sin` is approximate.
    pub fn draws_bit_exact(self) -> bool {
        matches!(self, Generator::Pcg | Generator::Tea)
    }
}

fn vec4_f32(v: [f32; 4]) -> String {
    let v = v.map(|x| format!("{x:?}f"));
    format!("vec4<f32>({})", v.join(", "))
}

/// The generators' WGSL constants, from their Rust values.
pub fn constants_wgsl() -> String {
    use random::{fract_sin as fs, talk, tea};
    let k = fs::K.map(|x| format!("{x:?}f")).join(", ");
    let key = tea::KEY.map(|x| format!("{x}u")).join(", ");
    [
        "// Generated from render::random by gpu::random_variants; do not edit.".to_owned(),
        format!("const ONE_BELOW: f32 = {:?}f;", random::ONE_BELOW),
        format!("const TALK_Q: vec4<f32> = {};", vec4_f32(talk::Q)),
        format!("const TALK_R: vec4<f32> = {};", vec4_f32(talk::R)),
        format!("const TALK_A: vec4<f32> = {};", vec4_f32(talk::A)),
        format!("const TALK_M: vec4<f32> = {};", vec4_f32(talk::M)),
        format!("const TALK_INV_M: vec4<f32> = {};", vec4_f32(talk::INV_M)),
        format!("const TEA_KEY: vec4<u32> = vec4<u32>({key});"),
        format!("const TEA_DELTA: u32 = {}u;", tea::DELTA),
        format!("const TEA_ROUNDS: u32 = {}u;", tea::ROUNDS),
        format!("const FRACT_SIN_K: vec3<f32> = vec3<f32>({k});"),
        format!("const FRACT_SIN_SCALE: f32 = {:?}f;", fs::SCALE),
        format!(
            "const FRACT_SIN_DRAWS_PER_PASS: u32 = {}u;",
            fs::DRAWS_PER_PASS
        ),
    ]
    .join("\n")
        + "\n"
}

/// [`Module::Sppm`]'s parts with the generator part swapped for `generator`'s, after the
/// generators' constants ([`Module::SppmRandom`]).
pub(crate) fn sppm_parts(generator: Generator) -> Vec<(&'static str, &'static str)> {
    let mut parts = Vec::new();
    for (name, part) in Module::Sppm.parts() {
        if name == GENERATOR_PART {
            parts.push((CONSTANTS_PART, CONSTANTS.as_str()));
            parts.push(generator.part());
        } else {
            parts.push((name, part));
        }
    }
    parts
}

/// The SPPM kernels drawing from `generator`, for `GpuBackend::with_kernels`; with
/// [`Generator::Pcg`] exactly the renderer's own ([`Module::Sppm`]).
pub fn sppm_source_with(generator: Generator) -> String {
    match generator {
        Generator::Pcg => Module::Sppm.source(),
        other => Module::SppmRandom(other).source(),
    }
}

/// The random parts alone (prelude, constants, `random.wgsl` and `generator`'s file), for a
/// test kernel that writes draws.
pub fn generator_source(generator: Generator) -> String {
    let mut text = prelude::wgsl();
    for (name, part) in sppm_parts(generator) {
        if name.starts_with("shared/random") || name == CONSTANTS_PART {
            text.push_str(&format!("\n// ---- {name} ----\n"));
            text.push_str(part);
        }
    }
    text
}

/// Draws per invocation of the draw-rate kernel ([`DrawRate`]).
pub const DRAWS_PER_INVOCATION: u32 = 256;

/// The generator alone: each invocation sums the first draws of its stream (stream `i` of
/// pass 0), so the rate counts drawing, not memory traffic. Not part of a renderer.
const SUM_DRAWS: &str = r#"
@group(0) @binding(0) var<storage, read_write> sums: array<f32>;

@compute @workgroup_size(WORKGROUP_SIZE)
fn sum_draws(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if i >= arrayLength(&sums) {
        return;
    }
    var rng = rng_start(1u, PHOTON_STREAM, 0u, i);
    var sum = 0.0;
    for (var k = 0u; k < DRAWS_PER_INVOCATION; k++) {
        sum += next_f32(&rng);
    }
    sums[i] = sum;
}
"#;

/// The CPU twin of `sum_draws`: the same draws added in the same order.
pub fn sum_draws<G: StreamRng>(index: u32) -> f32 {
    let mut rng = G::start(1, render::rng::PHOTON_STREAM, 0, index);
    (0..DRAWS_PER_INVOCATION).fold(0.0, |sum, _| sum + rng.next_f32())
}

/// `sum_draws` compiled with one generator over `invocations` streams.
pub struct DrawRate {
    pipeline: wgpu::ComputePipeline,
    bind_group: wgpu::BindGroup,
    sums: wgpu::Buffer,
    invocations: u32,
}

impl DrawRate {
    /// `invocations` ≤ 65,535 workgroups of [`prelude::WORKGROUP_SIZE`].
    pub fn new(context: &GpuContext, generator: Generator, invocations: u32) -> DrawRate {
        let source = format!(
            "{}\nconst DRAWS_PER_INVOCATION: u32 = {DRAWS_PER_INVOCATION}u;\n{SUM_DRAWS}",
            generator_source(generator)
        );
        let device = &context.device;
        let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("sum_draws"),
            source: wgpu::ShaderSource::Wgsl(source.into()),
        });
        let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some("sum_draws"),
            layout: None,
            module: &module,
            entry_point: Some("sum_draws"),
            compilation_options: Default::default(),
            cache: None,
        });
        let sums = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("sum_draws"),
            size: u64::from(invocations) * size_of::<f32>() as u64,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("sum_draws"),
            layout: &pipeline.get_bind_group_layout(0),
            entries: &[wgpu::BindGroupEntry {
                binding: 0,
                resource: sums.as_entire_binding(),
            }],
        });
        DrawRate {
            pipeline,
            bind_group,
            sums,
            invocations,
        }
    }

    /// One dispatch, submitted and waited for: its wall-clock seconds.
    pub fn run(&self, context: &GpuContext) -> Result<f64, GpuError> {
        let mut encoder = context
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor::default());
        {
            let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some("sum_draws"),
                timestamp_writes: None,
            });
            pass.set_pipeline(&self.pipeline);
            pass.set_bind_group(0, &self.bind_group, &[]);
            pass.dispatch_workgroups(self.invocations.div_ceil(prelude::WORKGROUP_SIZE), 1, 1);
        }
        let started = std::time::Instant::now();
        context.queue.submit([encoder.finish()]);
        readback::wait_idle(context)?;
        Ok(started.elapsed().as_secs_f64())
    }

    /// The sums of the last run.
    pub fn sums(&self, context: &GpuContext) -> Result<Vec<f32>, GpuError> {
        readback::read_buffer(context, &self.sums, self.invocations as usize)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_variant_validates() {
        for generator in Generator::ALL {
            let source = sppm_source_with(generator);
            let module = naga::front::wgsl::parse_str(&source)
                .unwrap_or_else(|e| panic!("{}: {}", generator.name(), e.emit_to_string(&source)));
            naga::valid::Validator::new(
                naga::valid::ValidationFlags::all(),
                naga::valid::Capabilities::all(),
            )
            .validate(&module)
            .unwrap_or_else(|e| panic!("{}: {e:?}", generator.name()));
            assert_eq!(Generator::from_name(generator.name()), Some(generator));
        }
    }

    /// The variants differ from the renderer's kernels in the generator part alone.
    #[test]
    fn variants_swap_only_the_generator() {
        let default = Module::Sppm.parts();
        for generator in Generator::ALL {
            let parts = sppm_parts(generator);
            assert_eq!(parts.len(), default.len() + 1);
            let others = |p: Vec<(&'static str, &'static str)>| -> Vec<&'static str> {
                p.into_iter()
                    .map(|(n, _)| n)
                    .filter(|n| !n.starts_with("shared/random_") && *n != CONSTANTS_PART)
                    .collect()
            };
            assert!(parts.contains(&generator.part()));
            assert_eq!(
                others(parts),
                others(default.clone()),
                "{}",
                generator.name()
            );
        }
        assert_eq!(sppm_source_with(Generator::Pcg), Module::Sppm.source());
    }
}
