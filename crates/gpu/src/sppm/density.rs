//! The density-estimation methods besides the stochastic hash (`kousen render --density`,
//! `kousen bench density`), on the GPU backend's state: the full spatial hash built by a
//! counting sort on the GPU, its lists then sorted by photon index so images are reproducible
//! and the photons copied into list order for the gather (`shaders/shared/density_full.wgsl`),
//! and a kd-tree built on the CPU from the pass's photons read back, queried on the GPU
//! (`density_kdtree.wgsl`). Their extra buffers are bind group 3;
//! renders with the stochastic hash never make any of this.

use render::Density;
use render::buffers::{Photon, SppmParams};
use render::density::scan_blocks;
use render::half_storage::Precision;
use render::kdtree::{KdNode, PhotonKdTree};

use super::{GpuBackend, SPPM_STORAGE_BUFFERS, compile_pipelines, pass_encoder};
use crate::readback::read_buffer;
use crate::scene_upload::{bind_buffers, storage_entry};
use crate::shader::Module;
use crate::traversal::workgroups;
use crate::{GpuError, check_buffer_fits};

/// The full hash's entry points, in the order a pass runs them.
const FULL_KERNELS: [&str; 6] = [
    "full_count",
    "full_scan_blocks",
    "full_scan_totals",
    "full_scatter",
    "full_sort_lists",
    "gather",
];

/// A density method's kernels and its bind group 3.
pub(super) struct DensityKernels {
    method: Density,
    precision: Precision,
    /// Group 3's layout, kept with the pipelines made for it.
    layout: wgpu::BindGroupLayout,
    /// The method's pipelines by entry point (the full hash's six, or the kd-tree's gather).
    pipelines: Vec<wgpu::ComputePipeline>,
    bind_group: wgpu::BindGroup,
    /// Group 3's buffers: the full hash's photon order, scan-block sums and photons in list
    /// order, or the kd-tree's nodes and node count.
    buffers: Vec<wgpu::Buffer>,
    /// Bytes of group 3's buffers.
    pub(super) bytes: u64,
}

fn storage_buffer(device: &wgpu::Device, label: &str, bytes: u64) -> wgpu::Buffer {
    device.create_buffer(&wgpu::BufferDescriptor {
        label: Some(label),
        size: bytes.max(4),
        usage: wgpu::BufferUsages::STORAGE
            | wgpu::BufferUsages::COPY_SRC
            | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    })
}

impl DensityKernels {
    /// The kernels and buffers of `method` for a render with `params`; `None` for the
    /// stochastic hash, which the SPPM kernels hold. The pipelines of `previous` are reused
    /// when it is the same method and precision (compiling them takes seconds on a CPU-type
    /// adapter, and the viewer restarts the render at every camera move).
    pub(super) fn new(
        backend: &GpuBackend,
        method: Density,
        precision: Precision,
        params: &SppmParams,
        previous: Option<DensityKernels>,
    ) -> Result<Option<DensityKernels>, GpuError> {
        let context = &backend.context;
        let limit = context.limits.max_storage_buffers_per_shader_stage;
        let (module, entry_points, buffers): (Module, &[&str], Vec<(&str, u64)>) = match method {
            Density::StochasticHash => return Ok(None),
            Density::FullHash => (
                Module::SppmFullHash,
                &FULL_KERNELS,
                vec![
                    ("photon_order", u64::from(params.slot_count) * 4),
                    (
                        "scan_block_sums",
                        u64::from(scan_blocks(params.hash_size)) * 4,
                    ),
                    (
                        "listed_photons",
                        u64::from(params.slot_count) * precision.point_bytes(),
                    ),
                ],
            ),
            Density::KdTree => (
                Module::SppmKdTree,
                &["gather"],
                vec![
                    (
                        "kd_nodes",
                        u64::from(params.slot_count) * size_of::<KdNode>() as u64,
                    ),
                    ("kd_node_count", 4),
                ],
            ),
        };
        let needed = SPPM_STORAGE_BUFFERS + buffers.len() as u32;
        if limit < needed {
            return Err(GpuError::TooFewStorageBuffers { needed, limit });
        }
        for &(label, bytes) in &buffers {
            check_buffer_fits(label, bytes, &context.limits)?;
        }
        let device = &context.device;
        let (layout, pipelines) = match previous {
            Some(p) if p.method == method && p.precision == precision => (p.layout, p.pipelines),
            _ => compile(
                backend,
                module,
                entry_points,
                buffers.len(),
                method,
                precision,
            ),
        };
        let made: Vec<_> = buffers
            .iter()
            .map(|&(label, bytes)| storage_buffer(device, label, bytes))
            .collect();
        let bind_group = bind_buffers(device, "density", &layout, &made.iter().collect::<Vec<_>>());
        let bytes = buffers.iter().map(|(_, b)| b).sum();
        Ok(Some(DensityKernels {
            method,
            precision,
            layout,
            pipelines,
            bind_group,
            buffers: made,
            bytes,
        }))
    }
}

/// Group 3's layout (`buffer_count` storage buffers) and the method's pipelines, one per entry
/// point.
fn compile(
    backend: &GpuBackend,
    module: Module,
    entry_points: &[&str],
    buffer_count: usize,
    method: Density,
    precision: Precision,
) -> (wgpu::BindGroupLayout, Vec<wgpu::ComputePipeline>) {
    let device = &backend.context.device;
    let read_only = method == Density::KdTree;
    let entries: Vec<_> = (0..buffer_count as u32)
        .map(|binding| storage_entry(binding, read_only))
        .collect();
    let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some("density"),
        entries: &entries,
    });
    let pipelines = compile_pipelines(
        &backend.context,
        &backend.layout,
        Some(&layout),
        backend.features,
        module.label(),
        module.source_with_precision(precision),
        entry_points,
    );
    (layout, pipelines)
}

impl GpuBackend {
    /// Records `pipeline` over `groups` workgroups with the density method's group 3.
    fn dispatch_density(&mut self, pipeline: usize, groups: (u32, u32)) {
        let (Some(state), Some(density)) = (&self.state, &self.density) else {
            return;
        };
        let encoder = pass_encoder(&mut self.encoder, &self.context);
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("density"),
            timestamp_writes: None,
        });
        pass.set_pipeline(&density.pipelines[pipeline]);
        pass.set_bind_group(0, &self.scene.bind_group, &[]);
        pass.set_bind_group(1, &state.bind_group, &[]);
        pass.set_bind_group(2, &self.textures_bind_group, &[]);
        pass.set_bind_group(3, &density.bind_group, &[]);
        pass.dispatch_workgroups(groups.0, groups.1, 1);
    }

    /// The method's hash build; false for the stochastic hash (the caller builds it).
    pub(super) fn build_density(&mut self) -> bool {
        let (Some(state), Some(density)) = (&self.state, &self.density) else {
            return false;
        };
        let params = state.params;
        let max = self.context.limits.max_compute_workgroups_per_dimension;
        let per_photon = workgroups(params.slot_count, max);
        match density.method {
            Density::FullHash => {
                let hash = state.hash.clone();
                pass_encoder(&mut self.encoder, &self.context).clear_buffer(&hash, 0, None);
                let blocks = scan_blocks(params.hash_size);
                let x = blocks.min(max);
                self.dispatch_density(0, per_photon);
                self.dispatch_density(1, (x, blocks.div_ceil(x)));
                self.dispatch_density(2, (1, 1));
                self.dispatch_density(3, per_photon);
                self.dispatch_density(4, workgroups(params.hash_size, max));
            }
            Density::KdTree => {
                if let Err(e) = self.upload_kd_tree() {
                    self.error.get_or_insert(e.to_string());
                }
            }
            Density::StochasticHash => return false,
        }
        true
    }

    /// The kd-tree of this pass's photons, read back, built on the CPU and written to group 3.
    fn upload_kd_tree(&mut self) -> Result<(), render::BackendError> {
        let photons: Vec<Photon> = self.read_photons()?;
        let tree = PhotonKdTree::build(&photons);
        let Some([nodes, count]) = self.density.as_ref().map(|d| d.buffers.as_slice()) else {
            return Ok(());
        };
        let queue = &self.context.queue;
        queue.write_buffer(nodes, 0, bytemuck::cast_slice(tree.nodes()));
        queue.write_buffer(count, 0, bytemuck::bytes_of(&(tree.nodes().len() as u32)));
        Ok(())
    }

    /// The method's gather; false for the stochastic hash (the caller gathers).
    pub(super) fn gather_density(&mut self) -> bool {
        let (Some(state), Some(density)) = (&self.state, &self.density) else {
            return false;
        };
        let gather = density.pipelines.len() - 1;
        let pixels = workgroups(
            state.params.pixel_count(),
            self.context.limits.max_compute_workgroups_per_dimension,
        );
        self.dispatch_density(gather, pixels);
        true
    }
}

impl GpuBackend {
    /// The full hash's photon order and scan-block offsets (for tests); waits for the work
    /// queued. An error if the render does not use the full hash.
    pub fn read_full_hash_lists(&mut self) -> Result<(Vec<u32>, Vec<u32>), render::BackendError> {
        use render::Backend;
        self.synchronize()?;
        let (Some(state), Some(density)) = (&self.state, &self.density) else {
            return Err(render::BackendError::Device(
                "no full hash in this render".into(),
            ));
        };
        if density.method != Density::FullHash {
            return Err(render::BackendError::Device(
                "no full hash in this render".into(),
            ));
        }
        let order = read_buffer(
            &self.context,
            &density.buffers[0],
            state.params.slot_count as usize,
        );
        let blocks = scan_blocks(state.params.hash_size) as usize;
        let offsets = read_buffer(&self.context, &density.buffers[1], blocks);
        Ok((
            order.map_err(super::device_error)?,
            offsets.map_err(super::device_error)?,
        ))
    }
}
