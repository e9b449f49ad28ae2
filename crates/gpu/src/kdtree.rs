//! The photon kd-tree's query on the GPU (`shaders/shared/kdtree.wgsl`, twin of
//! [`render::kdtree::PhotonKdTree::query`]), as a standalone kernel, `kdtree_query`
//! (`shaders/kernels/kdtree_query.wgsl`): one gather per query, for tests and the density
//! benchmark. The SPPM gather variant includes `kdtree.wgsl` itself.
//!
//! The module is the whole SPPM module (for `add_if_near`, whose file needs the rest), then
//! the kd-tree's files. Its pipeline layout holds only what the kernel binds: its own buffers,
//! group 1 bindings 16 to 19, past the SPPM kernels' (group 0, the scene, is left out).

use std::borrow::Cow;

use bytemuck::{Pod, Zeroable};
use render::kdtree::PhotonKdTree;
use wgpu::util::DeviceExt;

use crate::prelude;
use crate::readback::read_buffer;
use crate::scene_upload::storage_entry;
use crate::shader::Module;
use crate::traversal::{uniform_entry, workgroups};
use crate::{GpuContext, GpuError, check_buffer_fits};

const KDTREE: &str = include_str!("../shaders/shared/kdtree.wgsl");
const KDTREE_QUERY: &str = include_str!("../shaders/kernels/kdtree_query.wgsl");

/// The kernel's buffers in group 1: nodes, queries, results, uniform.
const FIRST_BINDING: u32 = 16;

/// Entry point, pipeline label and kernel file name.
pub const LABEL: &str = "kdtree_query";

/// One query (32 bytes): gather around `position` within `radius`, facing `normal` (unit).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct KdQuery {
    pub position: [f32; 3],
    pub radius: f32,
    pub normal: [f32; 3],
    pub pad: u32,
}

/// One query's answer (16 bytes): the summed flux and the number of photons counted.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct KdResult {
    pub flux: [f32; 3],
    pub found: u32,
}

/// The kernel's uniform (16 bytes).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct KdQueryParams {
    pub query_count: u32,
    pub node_count: u32,
    pub pad0: u32,
    pub pad1: u32,
}

/// The files of the `kdtree_query` module after the prelude, as (name, text).
pub fn parts() -> Vec<(&'static str, &'static str)> {
    let mut parts = Module::Sppm.parts();
    parts.push(("shared/kdtree.wgsl", KDTREE));
    parts.push(("kernels/kdtree_query.wgsl", KDTREE_QUERY));
    parts
}

/// The whole WGSL source of the `kdtree_query` module.
pub fn source() -> String {
    let mut text = prelude::wgsl();
    for (name, part) in parts() {
        text.push_str(&format!("\n// ---- {name} ----\n"));
        text.push_str(part);
    }
    text
}

/// The compiled `kdtree_query` kernel.
#[derive(Debug)]
pub struct KdTreeQuery {
    context: GpuContext,
    layout: wgpu::BindGroupLayout,
    pipeline: wgpu::ComputePipeline,
}

impl KdTreeQuery {
    pub fn new(context: &GpuContext) -> KdTreeQuery {
        let device = &context.device;
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some(LABEL),
            entries: &[
                storage_entry(FIRST_BINDING, true),
                storage_entry(FIRST_BINDING + 1, true),
                storage_entry(FIRST_BINDING + 2, false),
                uniform_entry(FIRST_BINDING + 3),
            ],
        });
        let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some(LABEL),
            bind_group_layouts: &[None, Some(&layout)],
            immediate_size: 0,
        });
        let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("kdtree_query.wgsl"),
            source: wgpu::ShaderSource::Wgsl(Cow::Owned(source())),
        });
        let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some(LABEL),
            layout: Some(&pipeline_layout),
            module: &module,
            entry_point: Some(LABEL),
            compilation_options: Default::default(),
            cache: None,
        });
        KdTreeQuery {
            context: context.clone(),
            layout,
            pipeline,
        }
    }

    /// Runs every query against `tree` and reads the results back.
    pub fn run(&self, tree: &PhotonKdTree, queries: &[KdQuery]) -> Result<Vec<KdResult>, GpuError> {
        if queries.is_empty() {
            return Ok(Vec::new());
        }
        let context = &self.context;
        let device = &context.device;
        let none = wgpu::BufferUsages::empty();
        let nodes = storage(context, "kd_nodes", tree.nodes(), none)?;
        let results = vec![KdResult::default(); queries.len()];
        let results = storage(
            context,
            "kd_results",
            &results,
            wgpu::BufferUsages::COPY_SRC,
        )?;
        let query_count = queries.len();
        let queries = storage(context, "kd_queries", queries, none)?;
        // Within the binding limit, so far below 2^32 queries and 2^27 nodes.
        let params = KdQueryParams {
            query_count: query_count as u32,
            node_count: tree.len() as u32,
            ..KdQueryParams::default()
        };
        let uniform = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("kd_params"),
            contents: bytemuck::bytes_of(&params),
            usage: wgpu::BufferUsages::UNIFORM,
        });
        let buffers = [
            (FIRST_BINDING, &nodes),
            (FIRST_BINDING + 1, &queries),
            (FIRST_BINDING + 2, &results),
            (FIRST_BINDING + 3, &uniform),
        ];
        let entries = buffers.map(|(binding, buffer)| wgpu::BindGroupEntry {
            binding,
            resource: buffer.as_entire_binding(),
        });
        let group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some(LABEL),
            layout: &self.layout,
            entries: &entries,
        });
        let mut encoder =
            device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some(LABEL) });
        {
            let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some(LABEL),
                timestamp_writes: None,
            });
            pass.set_pipeline(&self.pipeline);
            pass.set_bind_group(1, &group, &[]);
            let (x, y) = workgroups(
                params.query_count,
                context.limits.max_compute_workgroups_per_dimension,
            );
            pass.dispatch_workgroups(x, y, 1);
        }
        context.queue.submit([encoder.finish()]);
        read_buffer(context, &results, query_count)
    }
}

/// A storage buffer holding `items` (one zeroed element when empty: bindings cannot be empty),
/// checked against the device's limits first.
fn storage<T: Pod>(
    context: &GpuContext,
    label: &str,
    items: &[T],
    usage: wgpu::BufferUsages,
) -> Result<wgpu::Buffer, GpuError> {
    let placeholder = [T::zeroed()];
    let items = if items.is_empty() {
        &placeholder[..]
    } else {
        items
    };
    check_buffer_fits(label, size_of_val(items) as u64, &context.limits)?;
    Ok(context
        .device
        .create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some(label),
            contents: bytemuck::cast_slice(items),
            usage: wgpu::BufferUsages::STORAGE | usage,
        }))
}
