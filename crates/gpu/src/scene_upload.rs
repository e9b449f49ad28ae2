//! The packed scene in storage buffers (bind group 0 of every kernel): BVH nodes (boxes shared
//! by all threadings), triangles (vertices as two vec4 each), the six MTBVH link sets followed
//! by the TBVH's, where each threading starts, and the materials. On request
//! ([`GpuScene::upload_compact`]) also the compact MTBVH, bind group 2 of its trace kernels,
//! and ([`GpuScene::upload_wide`]) the four-wide MTBVH, binding 2 of group 2 of its.

use wgpu::util::DeviceExt;

use bvh::{BvhNode, CompactMtbvh, CompactNode, Links, PackedBvh, PackedTriangle, WideMtbvh};
use scene::Material;

use crate::traversal::uniform_entry;
use crate::types::{GpuMaterial, SceneInfo};
use crate::{GpuContext, GpuError, check_buffer_fits};

/// Storage buffers bound at once by the busiest kernel (scene group + a ray batch).
pub const STORAGE_BUFFERS_PER_STAGE: u32 = 7;

/// Storage buffers bound by the trace kernels that bind group 2 (the compact and the four-wide
/// MTBVH's): the scene's five, the ray batch's two and their own one.
pub const COMPACT_STORAGE_BUFFERS_PER_STAGE: u32 = 8;

/// Whether the device lets a kernel bind group 2's storage buffer besides the others.
fn check_group_2_fits(limits: &wgpu::Limits) -> Result<(), GpuError> {
    if limits.max_storage_buffers_per_shader_stage < COMPACT_STORAGE_BUFFERS_PER_STAGE {
        return Err(GpuError::TooFewStorageBuffers {
            needed: COMPACT_STORAGE_BUFFERS_PER_STAGE,
            limit: limits.max_storage_buffers_per_shader_stage,
        });
    }
    Ok(())
}

/// The scene's buffers on the device.
#[derive(Debug)]
pub struct GpuScene {
    pub nodes: wgpu::Buffer,
    pub triangles: wgpu::Buffer,
    pub links: wgpu::Buffer,
    pub info_buffer: wgpu::Buffer,
    pub materials: wgpu::Buffer,
    /// Group 0 of every kernel, made with [`scene_layout`].
    pub bind_group: wgpu::BindGroup,
    pub info: SceneInfo,
    /// Bytes uploaded.
    pub bytes: u64,
    /// The compact MTBVH, once [`GpuScene::upload_compact`] has put it there.
    pub compact: Option<GpuCompact>,
    /// The four-wide MTBVH, once [`GpuScene::upload_wide`] has put it there.
    pub wide: Option<GpuWide>,
}

/// The four-wide MTBVH on the device (see `shaders/shared/traverse_wide.wgsl`).
#[derive(Debug)]
pub struct GpuWide {
    /// [`WideMtbvh::gpu_words`].
    pub words: wgpu::Buffer,
    /// Group 2 of the wide trace kernels, made with [`wide_layout`].
    pub bind_group: wgpu::BindGroup,
}

/// The binding of the four-wide MTBVH's words in group 2 (0 and 1 are the compact MTBVH's, in
/// the same module).
const WIDE_BINDING: u32 = 2;

/// The layout of bind group 2 of the four-wide MTBVH's trace kernels.
pub fn wide_layout(device: &wgpu::Device) -> wgpu::BindGroupLayout {
    device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some("wide mtbvh"),
        entries: &[storage_entry(WIDE_BINDING, true)],
    })
}

/// The compact MTBVH on the device (see `shaders/shared/traverse_compact.wgsl`).
#[derive(Debug)]
pub struct GpuCompact {
    /// Node records, then far records.
    pub records: wgpu::Buffer,
    /// The quantisation frame (a uniform).
    pub frame: wgpu::Buffer,
    /// Group 2 of the compact trace kernels, made with [`compact_layout`].
    pub bind_group: wgpu::BindGroup,
    /// Bytes uploaded.
    pub bytes: u64,
}

/// The layout of bind group 2 of the compact trace kernels.
pub fn compact_layout(device: &wgpu::Device) -> wgpu::BindGroupLayout {
    device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some("compact mtbvh"),
        entries: &[storage_entry(0, true), uniform_entry(1)],
    })
}

/// The links buffer's contents: the six MTBVH sets (direction-major), then the TBVH's.
fn all_links(bvh: &PackedBvh) -> Vec<Links> {
    let mut links = Vec::with_capacity(bvh.mtbvh_links.len() + bvh.tbvh_links.len());
    links.extend_from_slice(&bvh.mtbvh_links);
    links.extend_from_slice(&bvh.tbvh_links);
    links
}

/// (label, bytes) of each scene buffer.
fn buffer_sizes(bvh: &PackedBvh, material_count: usize) -> [(&'static str, u64); 4] {
    let bytes = |count: usize, size: usize| (count * size) as u64;
    [
        ("bvh_nodes", bytes(bvh.nodes.len(), size_of::<BvhNode>())),
        (
            "bvh_triangles",
            bytes(bvh.triangles.len(), size_of::<PackedTriangle>()),
        ),
        (
            "bvh_links",
            bytes(
                bvh.mtbvh_links.len() + bvh.tbvh_links.len(),
                size_of::<Links>(),
            ),
        ),
        (
            "materials",
            bytes(material_count.max(1), size_of::<GpuMaterial>()),
        ),
    ]
}

/// Checks, before anything is allocated, that a scene fits a device with `limits`: every
/// buffer within the binding and buffer sizes, enough storage buffers per shader stage.
pub fn check_scene_fits(
    bvh: &PackedBvh,
    material_count: usize,
    limits: &wgpu::Limits,
) -> Result<(), GpuError> {
    if limits.max_storage_buffers_per_shader_stage < STORAGE_BUFFERS_PER_STAGE {
        return Err(GpuError::TooFewStorageBuffers {
            needed: STORAGE_BUFFERS_PER_STAGE,
            limit: limits.max_storage_buffers_per_shader_stage,
        });
    }
    for (label, bytes) in buffer_sizes(bvh, material_count) {
        check_buffer_fits(label, bytes, limits)?;
    }
    Ok(())
}

/// The layout of bind group 0 (see `shaders/shared/scene_bindings.wgsl`).
pub fn scene_layout(device: &wgpu::Device) -> wgpu::BindGroupLayout {
    let entries: Vec<_> = (0..5).map(|binding| storage_entry(binding, true)).collect();
    device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some("scene"),
        entries: &entries,
    })
}

/// A compute-stage storage buffer binding.
pub fn storage_entry(binding: u32, read_only: bool) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::COMPUTE,
        ty: wgpu::BindingType::Buffer {
            ty: wgpu::BufferBindingType::Storage { read_only },
            has_dynamic_offset: false,
            min_binding_size: None,
        },
        count: None,
    }
}

/// A bind group of whole buffers at bindings 0, 1, 2, ...
pub fn bind_buffers(
    device: &wgpu::Device,
    label: &str,
    layout: &wgpu::BindGroupLayout,
    buffers: &[&wgpu::Buffer],
) -> wgpu::BindGroup {
    let entries: Vec<_> = buffers
        .iter()
        .enumerate()
        .map(|(binding, buffer)| wgpu::BindGroupEntry {
            binding: binding as u32,
            resource: buffer.as_entire_binding(),
        })
        .collect();
    device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some(label),
        layout,
        entries: &entries,
    })
}

impl GpuScene {
    /// Uploads `bvh` and `materials`, after [`check_scene_fits`].
    pub fn upload(
        context: &GpuContext,
        bvh: &PackedBvh,
        materials: &[Material],
    ) -> Result<GpuScene, GpuError> {
        check_scene_fits(bvh, materials.len(), &context.limits)?;
        let device = &context.device;
        let storage = |label: &str, contents: &[u8]| {
            device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some(label),
                contents,
                usage: wgpu::BufferUsages::STORAGE,
            })
        };
        let mut gpu_materials: Vec<GpuMaterial> = materials.iter().map(GpuMaterial::new).collect();
        if gpu_materials.is_empty() {
            // A binding cannot be empty; no triangle refers to this one.
            gpu_materials.push(GpuMaterial::new(&Material::default()));
        }
        let info = SceneInfo::new(bvh);
        let nodes = storage("bvh_nodes", bytemuck::cast_slice(&bvh.nodes));
        let triangles = storage("bvh_triangles", bytemuck::cast_slice(&bvh.triangles));
        let links = storage("bvh_links", bytemuck::cast_slice(&all_links(bvh)));
        let info_buffer = storage("scene_info", bytemuck::bytes_of(&info));
        let materials = storage("materials", bytemuck::cast_slice(&gpu_materials));
        let buffers = [&nodes, &triangles, &links, &info_buffer, &materials];
        let bind_group = bind_buffers(device, "scene", &scene_layout(device), &buffers);
        let bytes = buffers.iter().map(|b| b.size()).sum();
        Ok(GpuScene {
            nodes,
            triangles,
            links,
            info_buffer,
            materials,
            bind_group,
            info,
            bytes,
            compact: None,
            wide: None,
        })
    }

    /// Uploads `compact` (made from the uploaded BVH) for the `mtbvh16` trace kernels,
    /// after checking it fits the device.
    pub fn upload_compact(
        &mut self,
        context: &GpuContext,
        compact: &CompactMtbvh,
    ) -> Result<(), GpuError> {
        let limits = &context.limits;
        check_group_2_fits(limits)?;
        let record_bytes = (compact.records.len().max(1) * size_of::<CompactNode>()) as u64;
        check_buffer_fits("compact_nodes", record_bytes, limits)?;
        let device = &context.device;
        // A binding cannot be empty; an empty tree's root is LINK_END, so nothing reads it.
        let mut records = compact.records.clone();
        if records.is_empty() {
            records.push(CompactNode::default());
        }
        let records = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("compact_nodes"),
            contents: bytemuck::cast_slice(&records),
            usage: wgpu::BufferUsages::STORAGE,
        });
        let frame = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("compact_frame"),
            contents: bytemuck::bytes_of(&compact.frame),
            usage: wgpu::BufferUsages::UNIFORM,
        });
        let bind_group = bind_buffers(
            device,
            "compact mtbvh",
            &compact_layout(device),
            &[&records, &frame],
        );
        let bytes = records.size() + frame.size();
        self.compact = Some(GpuCompact {
            records,
            frame,
            bind_group,
            bytes,
        });
        Ok(())
    }

    /// Uploads `wide` (made from the uploaded BVH) for the `mtbvh4` trace kernels, after
    /// checking it fits the device.
    pub fn upload_wide(&mut self, context: &GpuContext, wide: &WideMtbvh) -> Result<(), GpuError> {
        let limits = &context.limits;
        check_group_2_fits(limits)?;
        let words = wide.gpu_words();
        check_buffer_fits("wide_words", size_of_val(words.as_slice()) as u64, limits)?;
        let device = &context.device;
        let words = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("wide_words"),
            contents: bytemuck::cast_slice(&words),
            usage: wgpu::BufferUsages::STORAGE,
        });
        let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("wide mtbvh"),
            layout: &wide_layout(device),
            entries: &[wgpu::BindGroupEntry {
                binding: WIDE_BINDING,
                resource: words.as_entire_binding(),
            }],
        });
        self.wide = Some(GpuWide { words, bind_group });
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn small_bvh() -> PackedBvh {
        let triangles = scene::testing::cornell_box().triangles;
        PackedBvh::build(&triangles, &bvh::BuildOptions::default())
    }

    #[test]
    fn links_hold_six_mtbvh_sets_then_the_tbvh() {
        let bvh = small_bvh();
        let links = all_links(&bvh);
        let n = bvh.nodes.len();
        assert_eq!(links.len(), 7 * n);
        assert_eq!(&links[..6 * n], &bvh.mtbvh_links[..]);
        assert_eq!(&links[6 * n..], &bvh.tbvh_links[..]);
        assert_eq!(SceneInfo::new(&bvh).tbvh_link_base as usize, 6 * n);
    }

    #[test]
    fn oversize_scene_names_the_buffer_and_the_limit() {
        let bvh = small_bvh();
        let triangle_bytes = (bvh.triangles.len() * size_of::<PackedTriangle>()) as u64;
        let limits = wgpu::Limits {
            max_storage_buffer_binding_size: triangle_bytes - 1,
            ..wgpu::Limits::default()
        };
        let message = check_scene_fits(&bvh, 1, &limits).unwrap_err().to_string();
        assert!(message.contains("bvh_triangles"), "{message}");
        assert!(
            message.contains("max_storage_buffer_binding_size"),
            "{message}"
        );
        assert!(!message.contains('\n'));
        assert!(check_scene_fits(&bvh, 1, &wgpu::Limits::default()).is_ok());
    }

    #[test]
    fn too_few_storage_buffers_is_an_error_in_words() {
        let limits = wgpu::Limits {
            max_storage_buffers_per_shader_stage: 4,
            ..wgpu::Limits::default()
        };
        let message = check_scene_fits(&small_bvh(), 1, &limits)
            .unwrap_err()
            .to_string();
        assert!(
            message.contains("max_storage_buffers_per_shader_stage"),
            "{message}"
        );
    }
}
