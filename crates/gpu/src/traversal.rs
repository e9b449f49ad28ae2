//! The traversal kernels (`trace.wgsl`, with `traverse_compact.wgsl` for the compact MTBVH and
//! `traverse_wide.wgsl` for the four-wide one) and
//! benchmark ray generation (`raygen.wgsl`): pipelines, ray batches, dispatch and timing.

use wgpu::util::DeviceExt;

use bvh::bench_rays::BenchCamera;
use bvh::traverse::{Query, TraversalCounters};
use bvh::{CompactMtbvh, Hit, PackedBvh, Ray, WideMtbvh};

use crate::prelude::WORKGROUP_SIZE;
use crate::readback::{read_buffer, wait_idle};
use crate::scene_upload::{
    GpuScene, SceneStorage, bind_buffers, compact_layout, scene_layout, storage_entry, wide_layout,
};
use crate::shader::Module;
use crate::types::{BenchCameraUniform, GpuHit, GpuRay};
use crate::{GpuContext, GpuError, check_buffer_fits};

/// The ways through the BVH, the same on the GPU and in `bvh::traverse` / `bvh::compact` /
/// `bvh::wide`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Variant {
    /// Fixed-array stack, nearer child first.
    Stack,
    /// Stackless, one left-first threading.
    Tbvh,
    /// Stackless, the threading of the ray's major direction.
    Mtbvh,
    /// The MTBVH in the compact layout (`bvh::compact`: 16-bit boxes and links, one 32-byte
    /// record per node); needs [`GpuScene::upload_compact`].
    MtbvhCompact,
    /// The MTBVH four-wide (`bvh::wide`: four boxes per node, a per-direction child order, a
    /// stackless trail); needs [`GpuScene::upload_wide`].
    Mtbvh4,
}

impl Variant {
    /// In discriminant order, so `variant as usize` indexes arrays built from it.
    pub const ALL: [Variant; 5] = [
        Variant::Stack,
        Variant::Tbvh,
        Variant::Mtbvh,
        Variant::MtbvhCompact,
        Variant::Mtbvh4,
    ];

    /// "stack", "tbvh", "mtbvh", "mtbvh16" or "mtbvh4" (the bench's JSON contract).
    pub fn name(self) -> &'static str {
        match self {
            Variant::Stack => "stack",
            Variant::Tbvh => "tbvh",
            Variant::Mtbvh => "mtbvh",
            Variant::MtbvhCompact => "mtbvh16",
            Variant::Mtbvh4 => "mtbvh4",
        }
    }

    fn entry_point(self, query: Query) -> &'static str {
        match (query, self) {
            (Query::Closest, Variant::Stack) => "closest_stack",
            (Query::Closest, Variant::Tbvh) => "closest_tbvh",
            (Query::Closest, Variant::Mtbvh) => "closest_mtbvh",
            (Query::Closest, Variant::MtbvhCompact) => "closest_mtbvh16",
            (Query::Closest, Variant::Mtbvh4) => "closest_mtbvh4",
            (Query::Any, Variant::Stack) => "any_stack",
            (Query::Any, Variant::Tbvh) => "any_tbvh",
            (Query::Any, Variant::Mtbvh) => "any_mtbvh",
            (Query::Any, Variant::MtbvhCompact) => "any_mtbvh16",
            (Query::Any, Variant::Mtbvh4) => "any_mtbvh4",
        }
    }

    /// The CPU twin on `bvh`, or for [`Variant::MtbvhCompact`] on `compact` (made from `bvh`)
    /// and `bvh`'s triangles, for [`Variant::Mtbvh4`] on `wide` (made from `bvh`); `counters`
    /// accumulate the work done.
    pub fn cpu_trace(
        self,
        bvh: &PackedBvh,
        compact: &CompactMtbvh,
        wide: &WideMtbvh,
        ray: &Ray,
        query: Query,
        counters: &mut TraversalCounters,
    ) -> Option<Hit> {
        match self {
            Variant::Stack => bvh::traverse::trace_stack(bvh, ray, query, counters),
            Variant::Tbvh => bvh::traverse::trace_tbvh(bvh, ray, query, counters),
            Variant::Mtbvh => bvh::traverse::trace_mtbvh(bvh, ray, query, counters),
            Variant::MtbvhCompact => {
                bvh::compact::trace_mtbvh_compact(bvh, compact, ray, query, counters)
            }
            Variant::Mtbvh4 => bvh::wide::trace_wide(wide, ray, query, counters),
        }
    }

    /// [`Variant::cpu_trace`]'s closest hit without counting work: the functions renders call,
    /// compiled in `bvh` (what timed runs measure).
    pub fn cpu_closest_hit(
        self,
        bvh: &PackedBvh,
        compact: &CompactMtbvh,
        wide: &WideMtbvh,
        ray: &Ray,
    ) -> Option<Hit> {
        match self {
            Variant::Stack => bvh::closest_hit_stack(bvh, ray),
            Variant::Tbvh => bvh::closest_hit_tbvh(bvh, ray),
            Variant::Mtbvh => bvh::closest_hit_mtbvh(bvh, ray),
            Variant::MtbvhCompact => bvh::compact::closest_hit_mtbvh_compact(bvh, compact, ray),
            Variant::Mtbvh4 => bvh::closest_hit_wide(wide, ray),
        }
    }
}

/// The benchmark's two kinds of rays (ANCHORS.md).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum RayKind {
    /// One per pixel from the camera: coherent.
    Primary,
    /// One cosine-distributed bounce from each primary hit: incoherent.
    Diffuse,
}

impl RayKind {
    pub const ALL: [RayKind; 2] = [RayKind::Primary, RayKind::Diffuse];

    /// "primary" or "diffuse" (the bench's JSON contract).
    pub fn name(self) -> &'static str {
        match self {
            RayKind::Primary => "primary",
            RayKind::Diffuse => "diffuse",
        }
    }
}

/// Rays and their hits on the device.
#[derive(Debug)]
pub struct RayBatch {
    pub rays: wgpu::Buffer,
    pub hits: wgpu::Buffer,
    count: u32,
    trace_group: wgpu::BindGroup,
}

/// Compiled traversal and ray-generation pipelines.
#[derive(Debug)]
pub struct TraversalKernels {
    /// Where the kernels read the scene from: a scene uploaded otherwise cannot be bound.
    storage: SceneStorage,
    trace_layout: wgpu::BindGroupLayout,
    raygen_layout: wgpu::BindGroupLayout,
    closest: [wgpu::ComputePipeline; Variant::ALL.len()],
    any: [wgpu::ComputePipeline; Variant::ALL.len()],
    primary: wgpu::ComputePipeline,
    diffuse: wgpu::ComputePipeline,
    timer: Option<Timer>,
}

/// Timestamp queries around one pass.
#[derive(Debug)]
struct Timer {
    queries: wgpu::QuerySet,
    resolved: wgpu::Buffer,
    period_ns: f64,
}

pub(crate) fn uniform_entry(binding: u32) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::COMPUTE,
        ty: wgpu::BindingType::Buffer {
            ty: wgpu::BufferBindingType::Uniform,
            has_dynamic_offset: false,
            min_binding_size: None,
        },
        count: None,
    }
}

fn pipeline(
    device: &wgpu::Device,
    layout: &wgpu::PipelineLayout,
    module: &wgpu::ShaderModule,
    entry_point: &str,
) -> wgpu::ComputePipeline {
    device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
        label: Some(entry_point),
        layout: Some(layout),
        module,
        entry_point: Some(entry_point),
        compilation_options: Default::default(),
        cache: None,
    })
}

/// Workgroups for `count` invocations, spread over y when x would pass the device's limit.
pub fn workgroups(count: u32, max_per_dimension: u32) -> (u32, u32) {
    let groups = count.div_ceil(WORKGROUP_SIZE).max(1);
    let x = groups.min(max_per_dimension);
    (x, groups.div_ceil(x))
}

impl TraversalKernels {
    pub fn new(context: &GpuContext) -> TraversalKernels {
        let device = &context.device;
        let scene = scene_layout(device, context.scene_storage);
        let trace_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("trace batch"),
            entries: &[
                storage_entry(0, true),
                storage_entry(1, false),
                uniform_entry(2),
            ],
        });
        let raygen_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("raygen batch"),
            entries: &[
                storage_entry(0, false),
                storage_entry(1, true),
                uniform_entry(2),
            ],
        });
        let compact = compact_layout(device);
        let wide = wide_layout(device);
        let layout = |groups: &[Option<&wgpu::BindGroupLayout>]| {
            device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: None,
                bind_group_layouts: groups,
                immediate_size: 0,
            })
        };
        let trace_pipeline_layout = layout(&[Some(&scene), Some(&trace_layout)]);
        let raygen_pipeline_layout = layout(&[Some(&scene), Some(&raygen_layout)]);
        // Only the compact kernels bind group 2, so the others keep their two groups.
        let compact_pipeline_layout = layout(&[Some(&scene), Some(&trace_layout), Some(&compact)]);
        let wide_pipeline_layout = layout(&[Some(&scene), Some(&trace_layout), Some(&wide)]);
        let trace = Module::Trace.create(device, context.scene_storage);
        let raygen = Module::Raygen.create(device, context.scene_storage);
        let kernels = |query| {
            Variant::ALL.map(|v| {
                let layout = match v {
                    Variant::MtbvhCompact => &compact_pipeline_layout,
                    Variant::Mtbvh4 => &wide_pipeline_layout,
                    _ => &trace_pipeline_layout,
                };
                pipeline(device, layout, &trace, v.entry_point(query))
            })
        };
        let timer = context
            .features
            .contains(wgpu::Features::TIMESTAMP_QUERY)
            .then(|| Timer {
                queries: device.create_query_set(&wgpu::QuerySetDescriptor {
                    label: Some("pass time"),
                    ty: wgpu::QueryType::Timestamp,
                    count: 2,
                }),
                resolved: device.create_buffer(&wgpu::BufferDescriptor {
                    label: Some("pass time"),
                    size: 16,
                    usage: wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC,
                    mapped_at_creation: false,
                }),
                period_ns: f64::from(context.queue.get_timestamp_period()),
            });
        TraversalKernels {
            storage: context.scene_storage,
            closest: kernels(Query::Closest),
            any: kernels(Query::Any),
            primary: pipeline(device, &raygen_pipeline_layout, &raygen, "primary_rays"),
            diffuse: pipeline(device, &raygen_pipeline_layout, &raygen, "diffuse_rays"),
            trace_layout,
            raygen_layout,
            timer,
        }
    }

    /// Whether [`TraversalKernels::trace`] times with timestamp queries (else wall time).
    pub fn has_timestamps(&self) -> bool {
        self.timer.is_some()
    }

    /// A batch for `count` rays, its contents zero.
    pub fn batch(&self, context: &GpuContext, count: u32) -> Result<RayBatch, GpuError> {
        self.batch_with(context, count, None)
    }

    /// A batch holding `rays`.
    pub fn upload_rays(&self, context: &GpuContext, rays: &[GpuRay]) -> Result<RayBatch, GpuError> {
        let count = u32::try_from(rays.len()).map_err(|_| GpuError::TooManyRays(rays.len()))?;
        self.batch_with(context, count, Some(rays))
    }

    fn batch_with(
        &self,
        context: &GpuContext,
        count: u32,
        rays: Option<&[GpuRay]>,
    ) -> Result<RayBatch, GpuError> {
        let device = &context.device;
        let slots = u64::from(count.max(1));
        let ray_bytes = slots * size_of::<GpuRay>() as u64;
        let hit_bytes = slots * size_of::<GpuHit>() as u64;
        check_buffer_fits("rays", ray_bytes, &context.limits)?;
        check_buffer_fits("hits", hit_bytes, &context.limits)?;
        let usage = wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC;
        let rays = match rays {
            Some(rays) if !rays.is_empty() => {
                device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                    label: Some("rays"),
                    contents: bytemuck::cast_slice(rays),
                    usage,
                })
            }
            _ => device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("rays"),
                size: ray_bytes,
                usage,
                mapped_at_creation: false,
            }),
        };
        let hits = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("hits"),
            size: hit_bytes,
            usage,
            mapped_at_creation: false,
        });
        let params = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("trace batch"),
            contents: bytemuck::cast_slice(&[count, 0, 0, 0]),
            usage: wgpu::BufferUsages::UNIFORM,
        });
        let trace_group = bind_buffers(
            device,
            "trace batch",
            &self.trace_layout,
            &[&rays, &hits, &params],
        );
        Ok(RayBatch {
            rays,
            hits,
            count,
            trace_group,
        })
    }

    /// Generates `kind` rays into `batch` (sized `camera.ray_count()`): primary rays of the
    /// camera, or, replacing each ray by the diffuse ray leaving its hit (`batch.hits` from a
    /// closest-hit trace), diffuse rays; rays that hit nothing become unused slots.
    pub fn generate(
        &self,
        context: &GpuContext,
        scene: &GpuScene,
        batch: &RayBatch,
        kind: RayKind,
        camera: &BenchCamera,
        diagonal: f32,
    ) -> Result<(), GpuError> {
        self.check_storage(scene)?;
        let pipeline = match kind {
            RayKind::Primary => &self.primary,
            RayKind::Diffuse => &self.diffuse,
        };
        let device = &context.device;
        let uniform = BenchCameraUniform::new(camera, diagonal);
        if uniform.ray_count != batch.count {
            return Err(GpuError::Device(format!(
                "ray generation for {} rays into a batch of {}",
                uniform.ray_count, batch.count
            )));
        }
        let camera_buffer = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("bench camera"),
            contents: bytemuck::bytes_of(&uniform),
            usage: wgpu::BufferUsages::UNIFORM,
        });
        let group = bind_buffers(
            device,
            "raygen batch",
            &self.raygen_layout,
            &[&batch.rays, &batch.hits, &camera_buffer],
        );
        self.run(
            context,
            pipeline,
            &[&scene.bind_group, &group],
            batch.count,
            false,
        )
        .map(drop)
    }

    /// Traces every ray of `batch` into `batch.hits` and returns the seconds the pass took: GPU
    /// time from timestamp queries where the device has them, else the wall time of a
    /// submit-and-wait. [`Variant::MtbvhCompact`] needs [`GpuScene::upload_compact`] first,
    /// [`Variant::Mtbvh4`] [`GpuScene::upload_wide`].
    pub fn trace(
        &self,
        context: &GpuContext,
        scene: &GpuScene,
        batch: &RayBatch,
        variant: Variant,
        query: Query,
    ) -> Result<f64, GpuError> {
        self.check_storage(scene)?;
        let pipelines = match query {
            Query::Closest => &self.closest,
            Query::Any => &self.any,
        };
        let pipeline = &pipelines[variant as usize];
        let not_uploaded = |what: &str, upload: &str| {
            GpuError::Device(format!(
                "the {what} is not on the device (GpuScene::{upload})"
            ))
        };
        // The compact and four-wide kernels also bind their tree as group 2.
        let group_2 = match variant {
            Variant::MtbvhCompact => Some(
                scene
                    .compact
                    .as_ref()
                    .map(|c| &c.bind_group)
                    .ok_or_else(|| not_uploaded("compact MTBVH", "upload_compact"))?,
            ),
            Variant::Mtbvh4 => Some(
                scene
                    .wide
                    .as_ref()
                    .map(|w| &w.bind_group)
                    .ok_or_else(|| not_uploaded("four-wide MTBVH", "upload_wide"))?,
            ),
            _ => None,
        };
        let mut groups = vec![&scene.bind_group, &batch.trace_group];
        groups.extend(group_2);
        self.run(context, pipeline, &groups, batch.count, true)
    }

    /// An error in words unless `scene` is stored as these kernels read it (both follow the
    /// context's `scene_storage` when they are made).
    fn check_storage(&self, scene: &GpuScene) -> Result<(), GpuError> {
        if scene.storage == self.storage {
            return Ok(());
        }
        Err(GpuError::Device(format!(
            "the scene was uploaded in {} but the traversal kernels read it from {}",
            scene.storage.name(),
            self.storage.name()
        )))
    }

    /// One pass of `pipeline` over `count` invocations with `groups` bound at 0, 1, ...; its
    /// duration in seconds.
    fn run(
        &self,
        context: &GpuContext,
        pipeline: &wgpu::ComputePipeline,
        groups: &[&wgpu::BindGroup],
        count: u32,
        timed: bool,
    ) -> Result<f64, GpuError> {
        let timer = self.timer.as_ref().filter(|_| timed);
        let mut encoder = context
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor::default());
        {
            let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some("kousen kernel"),
                timestamp_writes: timer.map(|t| wgpu::ComputePassTimestampWrites {
                    query_set: &t.queries,
                    beginning_of_pass_write_index: Some(0),
                    end_of_pass_write_index: Some(1),
                }),
            });
            pass.set_pipeline(pipeline);
            for (index, group) in groups.iter().enumerate() {
                pass.set_bind_group(index as u32, *group, &[]);
            }
            let (x, y) = workgroups(count, context.limits.max_compute_workgroups_per_dimension);
            pass.dispatch_workgroups(x, y, 1);
        }
        if let Some(t) = timer {
            encoder.resolve_query_set(&t.queries, 0..2, &t.resolved, 0);
        }
        let start = std::time::Instant::now();
        context.queue.submit([encoder.finish()]);
        wait_idle(context)?;
        let wall = start.elapsed().as_secs_f64();
        match timer {
            None => Ok(wall),
            Some(t) => {
                let stamps: Vec<u64> = read_buffer(context, &t.resolved, 2)?;
                Ok(stamps[1].saturating_sub(stamps[0]) as f64 * t.period_ns * 1e-9)
            }
        }
    }
}

impl RayBatch {
    /// Number of rays.
    pub fn len(&self) -> usize {
        self.count as usize
    }

    pub fn is_empty(&self) -> bool {
        self.count == 0
    }

    pub fn read_rays(&self, context: &GpuContext) -> Result<Vec<GpuRay>, GpuError> {
        read_buffer(context, &self.rays, self.len())
    }

    pub fn read_hits(&self, context: &GpuContext) -> Result<Vec<GpuHit>, GpuError> {
        read_buffer(context, &self.hits, self.len())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn workgroups_cover_the_rays_within_the_dimension_limit() {
        assert_eq!(workgroups(0, 65535), (1, 1));
        assert_eq!(workgroups(64, 65535), (1, 1));
        assert_eq!(workgroups(65, 65535), (2, 1));
        let (x, y) = workgroups(1 << 24, 65535);
        assert!(
            x <= 65535 && u64::from(x) * u64::from(y) * 64 >= 1 << 24,
            "{x} {y}"
        );
        let (x, y) = workgroups(1000 * 64, 100);
        assert_eq!((x, y), (100, 10));
    }
}
