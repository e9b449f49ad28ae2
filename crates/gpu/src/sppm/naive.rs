//! Photon tracing alone on the GPU backend's state (`render::PhotonTracing`, for `kousen bench
//! photons`): the photon pass closed without a hash or gather, and the naive scheme of
//! `shaders/kernels/photon_trace_naive.wgsl`, whose pipeline and segment buffer are made on
//! first use so that renders never compile it.

use render::backend::{BackendError, PhotonTracing};

use super::{
    FINISH_PASS, GpuBackend, SPPM_STORAGE_BUFFERS, compile_pipelines, device_error, pass_encoder,
};
use crate::GpuError;
use crate::readback::read_buffer;
use crate::scene_upload::storage_entry;
use crate::shader::Module;
use crate::traversal::workgroups;

/// Storage buffers the naive kernel binds per stage: the SPPM kernels' and its segment counts.
pub const NAIVE_STORAGE_BUFFERS: u32 = SPPM_STORAGE_BUFFERS + 1;

/// The naive kernel's entry point, pipeline label and pass label.
const ENTRY_POINT: &str = "photon_trace_naive";

/// The naive kernel: its pipeline, its own bind group's layout (group 3), and the per-slot
/// segment counts it writes.
pub(super) struct NaiveTracer {
    pipeline: wgpu::ComputePipeline,
    layout: wgpu::BindGroupLayout,
    segments: Option<Segments>,
}

/// Segment counts for `slots` slots, bound at group 3.
struct Segments {
    buffer: wgpu::Buffer,
    bind_group: wgpu::BindGroup,
    slots: u32,
}

impl NaiveTracer {
    fn new(backend: &GpuBackend) -> NaiveTracer {
        let device = &backend.context.device;
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("path segments"),
            entries: &[storage_entry(0, false)],
        });
        let pipeline = compile_pipelines(
            &backend.context,
            &backend.layout,
            Some(&layout),
            backend.features,
            Module::PhotonTraceNaive.label(),
            Module::PhotonTraceNaive.source(),
            &[ENTRY_POINT],
        )
        .pop()
        .expect("one entry point, one pipeline");
        NaiveTracer {
            pipeline,
            layout,
            segments: None,
        }
    }

    /// The bind group of the segment counts for `slots` slots: the ones there are, or new ones
    /// when the render was started again with another slot count.
    fn segments(&mut self, device: &wgpu::Device, slots: u32) -> wgpu::BindGroup {
        if let Some(segments) = self.segments.as_ref().filter(|s| s.slots == slots) {
            return segments.bind_group.clone();
        }
        let buffer = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("path_segments"),
            size: u64::from(slots.max(1)) * size_of::<u32>() as u64,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("path segments"),
            layout: &self.layout,
            entries: &[wgpu::BindGroupEntry {
                binding: 0,
                resource: buffer.as_entire_binding(),
            }],
        });
        self.segments = Some(Segments {
            buffer,
            bind_group: bind_group.clone(),
            slots,
        });
        bind_group
    }
}

impl PhotonTracing for GpuBackend {
    fn finish_pass(&mut self) {
        self.dispatch(FINISH_PASS, 1);
        self.submit();
    }

    fn photon_trace_naive(&mut self) {
        let Some(state) = &self.state else {
            return;
        };
        let limit = self.context.limits.max_storage_buffers_per_shader_stage;
        if limit < NAIVE_STORAGE_BUFFERS {
            let error = GpuError::TooFewStorageBuffers {
                needed: NAIVE_STORAGE_BUFFERS,
                limit,
            };
            self.error.get_or_insert(error.to_string());
            return;
        }
        let slots = state.params.slot_count;
        let mut naive = self.naive.take().unwrap_or_else(|| NaiveTracer::new(self));
        let segments = naive.segments(&self.context.device, slots);
        let (x, y) = workgroups(
            slots,
            self.context.limits.max_compute_workgroups_per_dimension,
        );
        let encoder = pass_encoder(&mut self.encoder, &self.context);
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some(ENTRY_POINT),
            timestamp_writes: None,
        });
        pass.set_pipeline(&naive.pipeline);
        pass.set_bind_group(0, &self.scene.bind_group, &[]);
        pass.set_bind_group(1, &state.bind_group, &[]);
        pass.set_bind_group(2, &self.textures_bind_group, &[]);
        pass.set_bind_group(3, &segments, &[]);
        pass.dispatch_workgroups(x, y, 1);
        drop(pass);
        self.naive = Some(naive);
    }

    fn read_path_segments(&mut self) -> Result<Vec<u32>, BackendError> {
        use render::Backend;
        self.synchronize()?;
        let segments = self
            .naive
            .as_ref()
            .and_then(|n| n.segments.as_ref())
            .ok_or_else(|| BackendError::Device("the naive scheme has not run".into()))?;
        read_buffer(&self.context, &segments.buffer, segments.slots as usize).map_err(device_error)
    }
}
