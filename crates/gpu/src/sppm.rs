//! The GPU backend of the SPPM integrator: the kernels of `shaders/kernels/sppm/*.wgsl` on the
//! state of `render::buffers` in storage buffers. Each pass is one command buffer; the host
//! never reads anything back per pass, and keeps at most [`MAX_PASSES_IN_FLIGHT`] submitted
//! ahead so that progress and `--time` stay honest.

mod density;
mod naive;

use std::collections::VecDeque;

pub use naive::NAIVE_STORAGE_BUFFERS;

use render::backend::{Backend, BackendError, Setup, Snapshot, Statistics};
use render::buffers::{
    HASH_ENTRY_WORDS, Light, PIXEL_STATS_SURFACE_BYTES, PathSlot, Photon, PixelStats, SppmParams,
    VisiblePoint, counter, emitted_total,
};
use render::half_storage::{HalfPoint, Precision};
use wgpu::util::DeviceExt;

use crate::display::DisplaySource;
use crate::readback::{read_buffer, wait_idle};
use crate::scene_upload::{bind_buffers, fitting_storage, scene_layout, storage_entry};
use crate::shader::Module;
use crate::textures::GpuTextures;
use crate::traversal::{uniform_entry, workgroups};
use crate::{GpuContext, GpuError, GpuScene, check_buffer_fits};

/// Passes submitted but not known finished before the host waits.
const MAX_PASSES_IN_FLIGHT: usize = 2;
/// Storage buffers the SPPM kernels bind per stage: the scene's five, the state's eight
/// (the volume photons' τ apart from the rest of the pixel statistics), the sky map and the
/// mesh's tangents.
pub const SPPM_STORAGE_BUFFERS: u32 = 15;

/// The kernels' entry points; indices into `GpuBackend::pipelines`.
const KERNELS: [&str; 6] = [
    "eye_pass",
    "photon_pass",
    "hash_count",
    "hash_select",
    "gather",
    "finish_pass",
];
const EYE_PASS: usize = 0;
const PHOTON_PASS: usize = 1;
const HASH_COUNT: usize = 2;
const HASH_SELECT: usize = 3;
const GATHER: usize = 4;
const FINISH_PASS: usize = 5;

/// The render's state on the device.
struct State {
    params: SppmParams,
    precision: Precision,
    slots: wgpu::Buffer,
    photons: wgpu::Buffer,
    visible_points: wgpu::Buffer,
    /// The pixel statistics up to their volume τ (`PIXEL_STATS_SURFACE_BYTES` a pixel), and
    /// that τ, one `vec4` a pixel where the scene has murky glass (`SceneFeatures::
    /// murky_glass`), else one zero element: no volume photon is kept, τ stays 0.
    pixels: wgpu::Buffer,
    volume_tau: wgpu::Buffer,
    hash: wgpu::Buffer,
    counters: wgpu::Buffer,
    bind_group: wgpu::BindGroup,
    /// (kind, bytes) of every buffer.
    memory: Vec<(&'static str, u64)>,
}

pub struct GpuBackend {
    context: GpuContext,
    scene: GpuScene,
    scene_bytes: u64,
    /// The scene's textures, kept alive for their bind group (group 2).
    textures: GpuTextures,
    textures_bind_group: wgpu::BindGroup,
    /// The sky's environment map (`render::sky_map`), bound with each render's state.
    sky_map: wgpu::Buffer,
    /// The mesh's tangents in packed order (`render::normal_map::packed_tangents`), bound
    /// with each render's state.
    vertex_tangents: wgpu::Buffer,
    layout: wgpu::BindGroupLayout,
    pipelines: Vec<wgpu::ComputePipeline>,
    state: Option<State>,
    encoder: Option<wgpu::CommandEncoder>,
    in_flight: VecDeque<wgpu::SubmissionIndex>,
    /// The first device error met while encoding or submitting (reported at the next wait).
    error: Option<String>,
    /// The naive photon-tracing scheme, made on first use (`kousen bench photons`).
    naive: Option<naive::NaiveTracer>,
    /// The full hash's or the kd-tree's kernels (`kousen bench density`); None: the
    /// stochastic hash.
    density: Option<density::DensityKernels>,
    /// What the SPPM pipelines were compiled from.
    kernels: Kernels,
    /// What the scene uses, which every pipeline is compiled for.
    features: SceneFeatures,
}

/// The source of the SPPM pipelines.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Kernels {
    /// `Module::Sppm`, photons stored in this precision.
    Standard(Precision),
    /// A source given to [`GpuBackend::with_kernels`] (f32 storage).
    Custom,
}

/// The SPPM kernels' pipelines, in [`KERNELS`] order, compiled from `source`.
fn compile_kernels(
    context: &GpuContext,
    state_layout: &wgpu::BindGroupLayout,
    features: SceneFeatures,
    label: &str,
    source: String,
) -> Vec<wgpu::ComputePipeline> {
    compile_pipelines(
        context,
        state_layout,
        None,
        features,
        label,
        source,
        &KERNELS,
    )
}

/// What a scene uses that the kernels can be compiled without (WGSL `override` constants).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct SceneFeatures {
    /// Some material, or its clear coat, has a normal map (`NORMAL_MAPS` in
    /// `shading/surface.wgsl`).
    pub normal_maps: bool,
    /// Some material is rough plastic, or plastic a metallic-roughness texture may roughen
    /// (`ROUGH_COATS`).
    pub rough_coats: bool,
    /// Some material is frosted glass, solid or a thin sheet, or glass a metallic-roughness
    /// texture may frost (`FROSTED_GLASS`).
    pub frosted_glass: bool,
    /// Some material is a blend (`BLENDS`).
    pub blends: bool,
    /// Some material wears a clear coat (`CLEARCOATS`).
    pub clearcoats: bool,
    /// Some material wears a sheen (`SHEENS`).
    pub sheens: bool,
    /// Some material transmits diffusely (`DIFFUSE_TRANSMISSION`).
    pub diffuse_transmission: bool,
    /// Some material is brushed (`ANISOTROPY`).
    pub anisotropy: bool,
    /// Some material wears a thin film (`IRIDESCENCE`).
    pub iridescence: bool,
    /// Some material wears glTF's specular layer (`SPECULAR_LAYERS`).
    pub specular_layers: bool,
    /// Some blend's glass member is weighed by a transmission texture (`TRANSMISSION_MAPS`).
    pub transmission_maps: bool,
    /// Some solid absorbs inside (`MEDIA`).
    pub media: bool,
    /// Some solid scatters inside, a translucent solid or murky glass (`SCATTERING`).
    pub scattering: bool,
    /// Some of them is murky glass (`MURKY_GLASS`): volume photons and visible points.
    pub murky_glass: bool,
    /// Some glass disperses (`DISPERSION`).
    pub dispersion: bool,
    /// Some member's surface follows a metallic-roughness texture (`ROUGHNESS_MAPS`).
    pub roughness_maps: bool,
    /// The sky has an environment map (`SKY_MAP`).
    pub sky_map: bool,
    /// Some vertex carries the mesh's own tangent and some material reads a frame (a normal
    /// map or brushing): hits interpolate the tangents (`TANGENTS`).
    pub vertex_tangents: bool,
}

impl SceneFeatures {
    pub(crate) fn of(scene: &scene::Scene) -> SceneFeatures {
        let any = |f: fn(&scene::Material) -> bool| scene.materials.iter().any(f);
        SceneFeatures {
            normal_maps: any(|m| {
                m.normal_texture.is_some()
                    || m.clearcoat.is_some_and(|c| c.normal_texture.is_some())
            }),
            rough_coats: any(|m| {
                matches!(m.surface, scene::Surface::Plastic { alpha, .. } if alpha > 0.0)
                    || m.roughness_map
                        .is_some_and(|map| map.lobe == scene::TexturedLobe::Coated)
            }),
            frosted_glass: any(|m| {
                matches!(m.surface, scene::Surface::RoughDielectric { .. })
                    || m.roughness_map
                        .is_some_and(|map| map.lobe == scene::TexturedLobe::Glass)
            }),
            blends: any(|m| m.blend.is_some()),
            clearcoats: any(|m| m.clearcoat.is_some()),
            sheens: any(|m| m.sheen.is_some()),
            transmission_maps: any(|m| m.transmission_texture.is_some()),
            diffuse_transmission: any(|m| m.diffuse_transmission.is_some()),
            anisotropy: any(|m| m.anisotropy.is_some()),
            iridescence: any(|m| m.iridescence.is_some()),
            specular_layers: any(|m| m.specular.is_some()),
            media: any(|m| m.interior_extinction().max_element() > 0.0),
            scattering: any(|m| m.interior_scattering().max_element() > 0.0),
            murky_glass: any(|m| m.has_murky_glass()),
            dispersion: any(|m| m.dispersion > 0.0),
            roughness_maps: any(|m| m.roughness_map.is_some()),
            sky_map: scene.lights.sky.as_ref().is_some_and(|s| s.map.is_some()),
            vertex_tangents: scene.has_vertex_tangents() && any(|m| m.reads_tangent_frame()),
        }
    }

    fn constants(self) -> [(&'static str, f64); 18] {
        let flag = |on: bool| f64::from(u8::from(on));
        [
            ("NORMAL_MAPS", flag(self.normal_maps)),
            ("ROUGH_COATS", flag(self.rough_coats)),
            ("FROSTED_GLASS", flag(self.frosted_glass)),
            ("BLENDS", flag(self.blends)),
            ("CLEARCOATS", flag(self.clearcoats)),
            ("SHEENS", flag(self.sheens)),
            ("TRANSMISSION_MAPS", flag(self.transmission_maps)),
            ("DIFFUSE_TRANSMISSION", flag(self.diffuse_transmission)),
            ("ANISOTROPY", flag(self.anisotropy)),
            ("IRIDESCENCE", flag(self.iridescence)),
            ("SPECULAR_LAYERS", flag(self.specular_layers)),
            ("MEDIA", flag(self.media)),
            ("SCATTERING", flag(self.scattering)),
            ("MURKY_GLASS", flag(self.murky_glass)),
            ("DISPERSION", flag(self.dispersion)),
            ("ROUGHNESS_MAPS", flag(self.roughness_maps)),
            ("SKY_MAP", flag(self.sky_map)),
            ("TANGENTS", flag(self.vertex_tangents)),
        ]
    }
}

/// Pipelines for `entry_points` of `source`, laid out as every SPPM kernel is (group 0 the
/// scene, stored as `context.scene_storage` says; 1 the render's state, 2 the textures) and,
/// given `extra`, with it as group 3.
pub(crate) fn compile_pipelines(
    context: &GpuContext,
    state_layout: &wgpu::BindGroupLayout,
    extra: Option<&wgpu::BindGroupLayout>,
    features: SceneFeatures,
    label: &str,
    source: String,
    entry_points: &[&str],
) -> Vec<wgpu::ComputePipeline> {
    let constants = features.constants();
    let device = &context.device;
    let storage = context.scene_storage;
    let source = crate::shader::with_scene_storage(source, storage);
    let scene = scene_layout(device, storage);
    let textures = textures_layout(device);
    let mut groups = vec![Some(&scene), Some(state_layout), Some(&textures)];
    groups.extend(extra.map(Some));
    let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
        label: Some(label),
        bind_group_layouts: &groups,
        immediate_size: 0,
    });
    let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some(label),
        source: wgpu::ShaderSource::Wgsl(source.into()),
    });
    entry_points
        .iter()
        .map(|entry| {
            device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                label: Some(entry),
                layout: Some(&pipeline_layout),
                module: &module,
                entry_point: Some(entry),
                compilation_options: wgpu::PipelineCompilationOptions {
                    constants: &constants,
                    ..Default::default()
                },
                cache: None,
            })
        })
        .collect()
}

/// Group 2: the scene's texture array (`textures.wgsl`).
fn textures_layout(device: &wgpu::Device) -> wgpu::BindGroupLayout {
    device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some("scene textures"),
        entries: &[crate::textures::layout_entry(0)],
    })
}

fn state_layout(device: &wgpu::Device) -> wgpu::BindGroupLayout {
    let mut entries = vec![uniform_entry(0), storage_entry(1, true)];
    entries.extend((2..8).map(|b| storage_entry(b, false)));
    entries.push(storage_entry(8, true));
    entries.push(storage_entry(9, true));
    entries.push(storage_entry(10, false));
    device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some("sppm state"),
        entries: &entries,
    })
}

impl GpuBackend {
    /// Uploads the scene (its textures as one array, see [`crate::textures`]) and compiles
    /// the kernels.
    pub fn new(
        context: GpuContext,
        scene: &scene::Scene,
        bvh: bvh::PackedBvh,
    ) -> Result<GpuBackend, GpuError> {
        let source = Module::Sppm.source();
        let mut backend =
            GpuBackend::with_kernels(context, scene, bvh, Module::Sppm.label(), source)?;
        backend.kernels = Kernels::Standard(Precision::F32);
        Ok(backend)
    }

    /// [`GpuBackend::new`] with the SPPM kernels compiled from `source` (WGSL holding the
    /// entry points of `kernels/sppm/*.wgsl`, e.g. with another random generator): for
    /// benchmarks that compare variants of one kernel.
    pub fn with_kernels(
        mut context: GpuContext,
        scene: &scene::Scene,
        bvh: bvh::PackedBvh,
        label: &str,
        source: String,
    ) -> Result<GpuBackend, GpuError> {
        if context.limits.max_storage_buffers_per_shader_stage < SPPM_STORAGE_BUFFERS {
            return Err(GpuError::TooFewStorageBuffers {
                needed: SPPM_STORAGE_BUFFERS,
                limit: context.limits.max_storage_buffers_per_shader_stage,
            });
        }
        let array = render::textures::TextureArray::build(
            &scene.textures,
            crate::textures::max_side(&context.limits),
        );
        let textures = GpuTextures::upload(&context, &array)?;
        drop(array);
        let storage = fitting_storage(
            &bvh,
            scene.materials.len(),
            &context.limits,
            context.scene_storage,
        )?;
        if storage != context.scene_storage {
            log::warn!(
                "gpu: the scene does not fit this adapter's {} (see its limits); reading it from {} instead",
                context.scene_storage.name(),
                storage.name()
            );
            context.scene_storage = storage;
        }
        let light_area_density = render::emission::light_area_density(scene);
        // Indices of refraction relative to the solids materials lie in (`render::nesting`).
        let nesting = render::nesting::Nesting::of(scene);
        let gpu_scene = GpuScene::upload_lit(
            &context,
            &bvh,
            &nesting.materials,
            &light_area_density,
            &nesting.exterior,
        )?;
        let device = &context.device;
        let layout = state_layout(device);
        let texture_layout = textures_layout(device);
        let textures_bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("scene textures"),
            layout: &texture_layout,
            entries: &[wgpu::BindGroupEntry {
                binding: 0,
                resource: wgpu::BindingResource::TextureView(&textures.view),
            }],
        });
        let sky_map = render::sky_map::sky_map_buffer(scene.lights.sky.as_ref());
        let sky_map_bytes = (sky_map.len() * size_of::<f32>()) as u64;
        check_buffer_fits("sky_map", sky_map_bytes, &context.limits)?;
        let sky_map = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("sky_map"),
            contents: bytemuck::cast_slice(&sky_map),
            usage: wgpu::BufferUsages::STORAGE,
        });
        let mut features = SceneFeatures::of(scene);
        // The mesh's tangents, three a packed triangle (one zero where no kernel reads them).
        let mut tangents: Vec<[f32; 4]> = Vec::new();
        if features.vertex_tangents {
            let packed = render::normal_map::packed_tangents(scene, &bvh.triangle_ids);
            tangents = packed.iter().flatten().map(|t| t.to_array()).collect();
            let bytes = std::mem::size_of_val(tangents.as_slice()) as u64;
            if let Err(e) = check_buffer_fits("vertex_tangents", bytes, &context.limits) {
                log::warn!("gpu: {e}; normal maps and brushing take each triangle's texture frame");
                features.vertex_tangents = false;
                tangents.clear();
            }
        }
        if tangents.is_empty() {
            tangents.push([0.0; 4]);
        }
        let tangent_bytes = std::mem::size_of_val(tangents.as_slice()) as u64;
        let vertex_tangents = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("vertex_tangents"),
            contents: bytemuck::cast_slice(&tangents),
            usage: wgpu::BufferUsages::STORAGE,
        });
        let pipelines = compile_kernels(&context, &layout, features, label, source);
        Ok(GpuBackend {
            sky_map,
            vertex_tangents,
            features,
            scene_bytes: gpu_scene.bytes + sky_map_bytes + tangent_bytes,
            context,
            scene: gpu_scene,
            textures,
            textures_bind_group,
            layout,
            pipelines,
            state: None,
            encoder: None,
            in_flight: VecDeque::new(),
            error: None,
            naive: None,
            density: None,
            kernels: Kernels::Custom,
        })
    }

    /// Compiles the standard kernels again when the render stores photons in another
    /// precision than they were compiled for.
    fn compile_for(&mut self, precision: Precision) -> Result<(), BackendError> {
        match self.kernels {
            Kernels::Standard(compiled) if compiled == precision => Ok(()),
            Kernels::Standard(_) => {
                let source = Module::Sppm.source_with_precision(precision);
                self.pipelines = compile_kernels(
                    &self.context,
                    &self.layout,
                    self.features,
                    Module::Sppm.label(),
                    source,
                );
                self.kernels = Kernels::Standard(precision);
                Ok(())
            }
            Kernels::Custom if precision == Precision::F32 => Ok(()),
            Kernels::Custom => Err(BackendError::Device(
                "kernels compiled from a given source store photons in f32 only".into(),
            )),
        }
    }

    pub fn context(&self) -> &GpuContext {
        &self.context
    }

    fn allocate(&self, setup: &Setup) -> Result<State, GpuError> {
        let params = setup.params;
        let device = &self.context.device;
        let limits = &self.context.limits;
        let pixels = params.pixel_count() as u64;
        let slots = params.slot_count as u64;
        let point_bytes = setup.precision.point_bytes();
        let volume_pixels = self.features.murky_glass;
        let volume_taus = if volume_pixels { pixels } else { 1 };
        let sizes: [(&'static str, &'static str, u64); 7] = [
            (
                "photon_slots",
                "photons",
                slots * size_of::<PathSlot>() as u64,
            ),
            ("photons", "photons", slots * point_bytes),
            ("visible_points", "visible_points", pixels * point_bytes),
            (
                "pixel_stats",
                "statistics",
                pixels * PIXEL_STATS_SURFACE_BYTES as u64,
            ),
            (
                "pixel_volume_tau",
                "statistics",
                volume_taus * VOLUME_TAU_BYTES as u64,
            ),
            (
                "hash_table",
                "hash",
                params.hash_entries() as u64 * HASH_ENTRY_WORDS as u64 * 4,
            ),
            (
                "lights",
                "scene",
                (setup.lights.len() * size_of::<Light>()) as u64,
            ),
        ];
        for (label, kind, bytes) in sizes {
            check_buffer_fits(label, bytes, limits).map_err(|error| {
                let remedy = match kind {
                    "photons" | "hash" => {
                        "fewer photon slots, --photons, would make it fit, or --backend cpu"
                    }
                    "scene" => "fewer lights would make it fit, or --backend cpu",
                    _ => "a smaller image would make it fit, or --backend cpu",
                };
                GpuError::RenderBufferTooLarge {
                    error: Box::new(error),
                    remedy,
                }
            })?;
        }
        let usage = wgpu::BufferUsages::STORAGE
            | wgpu::BufferUsages::COPY_SRC
            | wgpu::BufferUsages::COPY_DST;
        let init = |label: &str, contents: &[u8]| {
            device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some(label),
                contents,
                usage,
            })
        };
        let zeroed = |label: &str, size: u64| {
            device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size,
                usage,
                mapped_at_creation: false,
            })
        };
        let params_buffer = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("sppm_params"),
            contents: bytemuck::bytes_of(&params),
            usage: wgpu::BufferUsages::UNIFORM,
        });
        let lights = init("lights", bytemuck::cast_slice(&setup.lights));
        let slots = init(
            "photon_slots",
            bytemuck::cast_slice(&vec![PathSlot::IDLE; params.slot_count as usize]),
        );
        let photons = zeroed("photons", sizes[1].2);
        let visible_points = zeroed("visible_points", sizes[2].2);
        let initial = vec![setup.initial_stats(); params.pixel_count() as usize];
        let (surface_words, volume_words) = split_stats(&initial, volume_pixels);
        let pixels = init("pixel_stats", bytemuck::cast_slice(&surface_words));
        let volume_tau = init("pixel_volume_tau", bytemuck::cast_slice(&volume_words));
        let hash = zeroed("hash_table", sizes[5].2);
        let counters = init("counters", bytemuck::cast_slice(&setup.initial_counters()));
        let bind_group = bind_buffers(
            device,
            "sppm state",
            &self.layout,
            &[
                &params_buffer,
                &lights,
                &slots,
                &photons,
                &visible_points,
                &pixels,
                &hash,
                &counters,
                &self.sky_map,
                &self.vertex_tangents,
                &volume_tau,
            ],
        );
        let mut memory: Vec<(&'static str, u64)> = vec![
            ("scene", self.scene_bytes - self.scene.bvh_bytes),
            ("bvh", self.scene.bvh_bytes),
            ("textures", self.textures.bytes),
        ];
        for (_, kind, bytes) in sizes {
            match memory.iter_mut().find(|(k, _)| *k == kind) {
                Some((_, total)) => *total += bytes,
                None => memory.push((kind, bytes)),
            }
        }
        Ok(State {
            params,
            precision: setup.precision,
            slots,
            photons,
            visible_points,
            pixels,
            volume_tau,
            hash,
            counters,
            bind_group,
            memory,
        })
    }

    /// Records `kernel` over `count` invocations into this pass's command buffer.
    fn dispatch(&mut self, kernel: usize, count: u32) {
        let Some(state) = &self.state else {
            return;
        };
        let encoder = pass_encoder(&mut self.encoder, &self.context);
        let (x, y) = workgroups(
            count,
            self.context.limits.max_compute_workgroups_per_dimension,
        );
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some(KERNELS[kernel]),
            timestamp_writes: None,
        });
        pass.set_pipeline(&self.pipelines[kernel]);
        pass.set_bind_group(0, &self.scene.bind_group, &[]);
        pass.set_bind_group(1, &state.bind_group, &[]);
        pass.set_bind_group(2, &self.textures_bind_group, &[]);
        pass.dispatch_workgroups(x, y, 1);
    }

    /// Submits what was recorded; waits for the oldest pass when too many are in flight.
    fn submit(&mut self) {
        if let Some(encoder) = self.encoder.take() {
            let index = self.context.queue.submit([encoder.finish()]);
            self.in_flight.push_back(index);
        }
        while self.in_flight.len() > MAX_PASSES_IN_FLIGHT {
            let index = self.in_flight.pop_front().expect("non-empty");
            let waited = self.context.device.poll(wgpu::PollType::Wait {
                submission_index: Some(index),
                timeout: None,
            });
            if let Err(e) = waited {
                self.error.get_or_insert(e.to_string());
            }
        }
    }

    fn state(&self) -> Result<&State, BackendError> {
        self.state
            .as_ref()
            .ok_or_else(|| BackendError::Device("the render was not started".into()))
    }

    /// Waits for the queued work, then reads `count` elements of the state buffer `pick` names.
    fn read_state<T: bytemuck::Pod>(
        &mut self,
        pick: impl Fn(&State) -> (&wgpu::Buffer, usize),
    ) -> Result<Vec<T>, BackendError> {
        self.synchronize()?;
        let (buffer, count) = pick(self.state()?);
        read_buffer(&self.context, buffer, count).map_err(device_error)
    }

    fn read_counters(&mut self) -> Result<Vec<u32>, BackendError> {
        self.read_state(|s| (&s.counters, counter::COUNT))
    }

    /// The pixel statistics, their two buffers joined as `render::buffers::PixelStats`.
    fn read_pixel_stats(&mut self) -> Result<Vec<PixelStats>, BackendError> {
        let count = self.state()?.params.pixel_count() as usize;
        let volume_pixels = self.features.murky_glass;
        let surface: Vec<u32> = self.read_state(|s| (&s.pixels, count * SURFACE_WORDS))?;
        let volume: Vec<u32> = if volume_pixels {
            self.read_state(|s| (&s.volume_tau, count * VOLUME_TAU_WORDS))?
        } else {
            Vec::new()
        };
        Ok(join_stats(&surface, &volume, count))
    }

    /// This pass's photons (for tests, and the kd-tree built on the CPU), as f32 whatever
    /// the storage.
    pub fn read_photons(&mut self) -> Result<Vec<Photon>, BackendError> {
        let count = |s: &State| s.params.slot_count as usize;
        if self.state()?.precision == Precision::F32 {
            return self.read_state(|s| (&s.photons, count(s)));
        }
        let params = self.state()?.params;
        let (origin, scale) = (
            render::buffers::vec3(params.storage_origin),
            params.storage_flux_scale,
        );
        let packed: Vec<HalfPoint> = self.read_state(|s| (&s.photons, count(s)))?;
        Ok(packed.iter().map(|h| h.to_photon(origin, scale)).collect())
    }

    pub fn read_slots(&mut self) -> Result<Vec<PathSlot>, BackendError> {
        self.read_state(|s| (&s.slots, s.params.slot_count as usize))
    }

    /// The hash table's words (entry-major: priority, count, winner).
    pub fn read_hash(&mut self) -> Result<Vec<u32>, BackendError> {
        self.read_state(|s| (&s.hash, s.params.hash_entries() * HASH_ENTRY_WORDS))
    }

    pub fn counters(&mut self) -> Result<Vec<u32>, BackendError> {
        self.read_counters()
    }

    /// The statistics and counters buffers for [`crate::display::DisplayPass`] (handles to the
    /// same buffers, read in place on the device); None before `start`. A new `start`
    /// allocates new buffers, so take a new source after it.
    pub fn display_source(&self) -> Option<DisplaySource> {
        self.state.as_ref().map(|s| DisplaySource {
            pixels: s.pixels.clone(),
            volume_tau: s.volume_tau.clone(),
            counters: s.counters.clone(),
            width: s.params.width,
            height: s.params.height,
        })
    }
}

/// This pass's command encoder, made on first use.
fn pass_encoder<'a>(
    encoder: &'a mut Option<wgpu::CommandEncoder>,
    context: &GpuContext,
) -> &'a mut wgpu::CommandEncoder {
    encoder.get_or_insert_with(|| {
        context
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("sppm pass"),
            })
    })
}

fn device_error(e: GpuError) -> BackendError {
    if e.is_limit() {
        BackendError::DoesNotFit(e.to_string())
    } else {
        BackendError::Device(e.to_string())
    }
}

/// Words of a pixel's statistics in the `pixel_stats` buffer, and of its volume τ in
/// `pixel_volume_tau` (a `vec4`: τ and the struct's padding).
const SURFACE_WORDS: usize = PIXEL_STATS_SURFACE_BYTES / 4;
const VOLUME_TAU_WORDS: usize = VOLUME_TAU_BYTES / 4;
const VOLUME_TAU_BYTES: usize = size_of::<PixelStats>() - PIXEL_STATS_SURFACE_BYTES;
const _: () = assert!(VOLUME_TAU_BYTES == 16);

/// `stats` as the words of the two statistics buffers: each pixel's first
/// `PIXEL_STATS_SURFACE_BYTES`, and its volume τ where `volume_pixels`, else one zero `vec4`.
fn split_stats(stats: &[PixelStats], volume_pixels: bool) -> (Vec<u32>, Vec<u32>) {
    let words: &[u32] = bytemuck::cast_slice(stats);
    let record = SURFACE_WORDS + VOLUME_TAU_WORDS;
    let part = |range: std::ops::Range<usize>| {
        (words.chunks_exact(record))
            .flat_map(|pixel| pixel[range.clone()].iter().copied())
            .collect::<Vec<u32>>()
    };
    let volume = if volume_pixels {
        part(SURFACE_WORDS..record)
    } else {
        vec![0; VOLUME_TAU_WORDS]
    };
    (part(0..SURFACE_WORDS), volume)
}

/// [`split_stats`] undone for `count` pixels: `volume` empty where the scene keeps no volume
/// τ (it is 0).
fn join_stats(surface: &[u32], volume: &[u32], count: usize) -> Vec<PixelStats> {
    (0..count)
        .map(|i| {
            let mut words = [0u32; SURFACE_WORDS + VOLUME_TAU_WORDS];
            words[..SURFACE_WORDS].copy_from_slice(&surface[i * SURFACE_WORDS..][..SURFACE_WORDS]);
            if !volume.is_empty() {
                let tau = &volume[i * VOLUME_TAU_WORDS..][..VOLUME_TAU_WORDS];
                words[SURFACE_WORDS..].copy_from_slice(tau);
            }
            bytemuck::cast(words)
        })
        .collect()
}

/// Words of the counters, slots, visible points (as stored: f32 or f16) and statistics
/// buffers, in [`Snapshot::parts`] order (the statistics joined as `PixelStats`).
fn snapshot_words(state: &State) -> [usize; 4] {
    let pixels = state.params.pixel_count() as usize;
    let point = match state.precision {
        Precision::F32 => size_of::<VisiblePoint>(),
        Precision::F16 => size_of::<HalfPoint>(),
    };
    [
        counter::COUNT,
        state.params.slot_count as usize * size_of::<PathSlot>() / 4,
        pixels * point / 4,
        pixels * size_of::<render::buffers::PixelStats>() / 4,
    ]
}

impl Backend for GpuBackend {
    fn name(&self) -> &'static str {
        "gpu"
    }

    fn adapter(&self) -> String {
        self.context.description()
    }

    fn start(&mut self, setup: &Setup) -> Result<(), BackendError> {
        let previous = self.density.take();
        self.compile_for(setup.precision)?;
        self.state = Some(self.allocate(setup).map_err(device_error)?);
        self.density = density::DensityKernels::new(
            self,
            setup.density,
            setup.precision,
            &setup.params,
            previous,
        )
        .map_err(device_error)?;
        Ok(())
    }

    fn eye_pass(&mut self) {
        let pixels = self.state.as_ref().map_or(0, |s| s.params.pixel_count());
        self.dispatch(EYE_PASS, pixels);
    }

    fn photon_pass(&mut self) {
        let slots = self.state.as_ref().map_or(0, |s| s.params.slot_count);
        self.dispatch(PHOTON_PASS, slots);
    }

    fn build_hash(&mut self) {
        if self.build_density() {
            return;
        }
        let Some(state) = &self.state else {
            return;
        };
        let slots = state.params.slot_count;
        pass_encoder(&mut self.encoder, &self.context).clear_buffer(&state.hash, 0, None);
        self.dispatch(HASH_COUNT, slots);
        self.dispatch(HASH_SELECT, slots);
    }

    fn gather(&mut self) {
        if !self.gather_density() {
            let pixels = self.state.as_ref().map_or(0, |s| s.params.pixel_count());
            self.dispatch(GATHER, pixels);
        }
        self.dispatch(FINISH_PASS, 1);
        self.submit();
    }

    fn synchronize(&mut self) -> Result<(), BackendError> {
        self.submit();
        wait_idle(&self.context).map_err(device_error)?;
        self.in_flight.clear();
        match self.error.take() {
            Some(e) => Err(BackendError::Device(e)),
            None => Ok(()),
        }
    }

    fn emitted_paths(&mut self) -> Result<u64, BackendError> {
        let c = self.read_counters()?;
        Ok(emitted_total(
            c[counter::EMITTED_LO],
            c[counter::EMITTED_HI],
        ))
    }

    fn snapshot(&mut self) -> Result<Snapshot, BackendError> {
        let sizes = snapshot_words(self.state()?);
        Ok(Snapshot {
            counters: self.read_state(|s| (&s.counters, sizes[0]))?,
            slots: self.read_state(|s| (&s.slots, sizes[1]))?,
            visible_points: self.read_state(|s| (&s.visible_points, sizes[2]))?,
            pixels: bytemuck::cast_slice(&self.read_pixel_stats()?).to_vec(),
        })
    }

    fn restore(&mut self, snapshot: &Snapshot) -> Result<(), BackendError> {
        self.synchronize()?;
        let state = self.state()?;
        snapshot.check_sizes(snapshot_words(state))?;
        let stats: &[PixelStats] = bytemuck::cast_slice(&snapshot.pixels);
        let (surface, volume) = split_stats(stats, self.features.murky_glass);
        let writes = [
            (&state.counters, &snapshot.counters),
            (&state.slots, &snapshot.slots),
            (&state.visible_points, &snapshot.visible_points),
            (&state.pixels, &surface),
            (&state.volume_tau, &volume),
        ];
        for (buffer, words) in writes {
            self.context
                .queue
                .write_buffer(buffer, 0, bytemuck::cast_slice(words));
        }
        Ok(())
    }

    fn read_statistics(&mut self) -> Result<Statistics, BackendError> {
        let emitted_paths = self.emitted_paths()?;
        let pixels = self.read_pixel_stats()?;
        Ok(Statistics {
            pixels,
            emitted_paths,
        })
    }

    fn read_visible_points(&mut self) -> Result<Vec<VisiblePoint>, BackendError> {
        let count = |s: &State| s.params.pixel_count() as usize;
        if self.state()?.precision == Precision::F32 {
            return self.read_state(|s| (&s.visible_points, count(s)));
        }
        let origin = render::buffers::vec3(self.state()?.params.storage_origin);
        let packed: Vec<HalfPoint> = self.read_state(|s| (&s.visible_points, count(s)))?;
        Ok(packed.iter().map(|h| h.to_visible_point(origin)).collect())
    }

    fn memory(&self) -> Vec<(&'static str, u64)> {
        let mut memory = self
            .state
            .as_ref()
            .map_or_else(Vec::new, |s| s.memory.clone());
        if let (Some(density), Some((_, bytes))) = (
            &self.density,
            memory.iter_mut().find(|(kind, _)| *kind == "hash"),
        ) {
            *bytes += density.bytes;
        }
        memory
    }
}

#[cfg(test)]
mod tests {
    use super::{PixelStats, SceneFeatures, join_stats, split_stats};

    /// The two statistics buffers' words join back into the statistics they were split from;
    /// without the volume buffer's pixels (no murky glass) the volume τ joins as 0.
    #[test]
    fn statistics_split_and_join_back() {
        let stats: Vec<PixelStats> = (0..5)
            .map(|i| PixelStats {
                tau: [i as f32, 1.0, 2.0],
                photon_count: 3.0,
                direct: [4.0, 5.0, 6.0],
                radius: 0.5,
                caustic_tau: [7.0, 8.0, 9.0],
                caustic_count: 10.0,
                caustic_radius: 0.25,
                specular_seen: i % 2,
                volume_count: 11.0,
                volume_radius: 0.75,
                volume_tau: [12.0, 13.0, i as f32],
                pad: 0,
            })
            .collect();
        let (surface, volume) = split_stats(&stats, true);
        assert_eq!((surface.len(), volume.len()), (5 * 16, 5 * 4));
        assert_eq!(join_stats(&surface, &volume, 5), stats);
        let (surface, volume) = split_stats(&stats, false);
        assert_eq!(volume, vec![0; 4]);
        let joined = join_stats(&surface, &[], 5);
        let without_tau: Vec<PixelStats> = (stats.iter())
            .map(|s| PixelStats {
                volume_tau: [0.0; 3],
                ..*s
            })
            .collect();
        assert_eq!(joined, without_tau);
    }
    use scene::testing;

    /// Each override is on exactly where the scene has what it compiles in.
    #[test]
    fn features_name_what_each_scene_has() {
        let features = |scene: &scene::Scene| {
            let f = SceneFeatures::of(scene);
            (f.normal_maps, f.rough_coats, f.frosted_glass, f.blends)
        };
        let none = (false, false, false, false);
        assert_eq!(features(&testing::cornell_box()), none);
        assert_eq!(
            features(&testing::cornell_plastic()),
            (false, true, false, false)
        );
        assert_eq!(
            features(&testing::cornell_frosted()),
            (false, false, true, false)
        );
        assert_eq!(
            features(&testing::cornell_bumpy()),
            (true, false, false, false)
        );
        assert_eq!(
            features(&testing::cornell_blended()),
            (false, true, false, true)
        );
        let sheens = |scene: &scene::Scene| SceneFeatures::of(scene).sheens;
        assert!(sheens(&testing::cornell_sheen()) && !sheens(&testing::cornell_clearcoat()));
        // Murky glass scatters; a translucent solid scatters without being murky glass.
        let scattering = |scene: &scene::Scene| {
            let f = SceneFeatures::of(scene);
            (f.scattering, f.murky_glass)
        };
        assert_eq!(scattering(&testing::cornell_murky()), (true, true));
        assert_eq!(
            scattering(&testing::cornell_translucent_solids()),
            (true, false)
        );
        assert_eq!(scattering(&testing::cornell_box()), (false, false));
    }
}
