//! The packed scene on the device (bind group 0 of every kernel): BVH nodes (boxes and
//! contents, read by the stack traversal and for leaves' triangles), triangles (vertices as
//! two vec4 each), the threaded records of the six MTBVH threadings followed by the TBVH's
//! (each node's box and miss link in that threading's pre-order, [`bvh::threaded`]), the
//! scene's sizes, and the materials. Nodes, triangles and threaded records are in storage
//! buffers or, the same bytes, in integer textures ([`SceneStorage`]). On request
//! ([`GpuScene::upload_compact`]) also the compact MTBVH, bind group 2 of its trace kernels,
//! and ([`GpuScene::upload_wide`]) the four-wide MTBVH, binding 2 of group 2 of its.

use wgpu::util::DeviceExt;

use bvh::{
    BvhNode, CompactMtbvh, CompactNode, PackedBvh, PackedTriangle, ThreadedNode, WideMtbvh,
    threaded_nodes,
};
use scene::Material;

use crate::limits::check_texels_fit;
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

/// Where the kernels read nodes, triangles and threaded records from (`shaders/shared/scene_bindings.wgsl`
/// or `scene_texels.wgsl`; the kernels are the same otherwise).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SceneStorage {
    /// Storage buffers.
    Buffers,
    /// rgba32uint textures of [`TEXEL_ROW`] texels a row, 16 bytes a texel: on CPU-type adapters
    /// (lavapipe) a texel fetch is a gather, where a storage-buffer load with a different
    /// index per lane is a loop over the lanes (docs/BENCHMARKS.md §2, session 15).
    Texels,
}

impl SceneStorage {
    /// Texels on a CPU-type adapter, where they were measured faster; buffers on GPUs, where
    /// they have not been compared.
    pub fn preferred(device_type: wgpu::DeviceType) -> SceneStorage {
        match device_type {
            wgpu::DeviceType::Cpu => SceneStorage::Texels,
            _ => SceneStorage::Buffers,
        }
    }

    /// The storage that is not this one.
    pub fn other(self) -> SceneStorage {
        match self {
            SceneStorage::Buffers => SceneStorage::Texels,
            SceneStorage::Texels => SceneStorage::Buffers,
        }
    }

    pub fn name(self) -> &'static str {
        match self {
            SceneStorage::Buffers => "buffers",
            SceneStorage::Texels => "texels",
        }
    }
}

/// Where nodes, triangles and threaded records live, by [`SceneStorage`].
#[derive(Debug)]
enum SceneRecords {
    Buffers([wgpu::Buffer; 3]),
    Texels([wgpu::TextureView; 3]),
}

/// `bytes` as rgba32uint texels, [`TEXEL_ROW`] a row, the last row padded with zeros.
fn texels(context: &GpuContext, label: &str, bytes: &[u8]) -> wgpu::Texture {
    let row = TEXEL_ROW as usize;
    let rows = bytes.len().div_ceil(16).div_ceil(row).max(1);
    let mut padded = bytes.to_vec();
    padded.resize(rows * row * 16, 0);
    context.device.create_texture_with_data(
        &context.queue,
        &wgpu::TextureDescriptor {
            label: Some(label),
            size: wgpu::Extent3d {
                width: TEXEL_ROW,
                height: rows as u32,
                depth_or_array_layers: 1,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: wgpu::TextureFormat::Rgba32Uint,
            usage: wgpu::TextureUsages::TEXTURE_BINDING,
            view_formats: &[],
        },
        wgpu::util::TextureDataOrder::LayerMajor,
        &padded,
    )
}

/// Texels a row of the scene's textures (a power of two; `TEXEL_ROW` in the WGSL prelude).
pub const TEXEL_ROW: u32 = 4096;

/// The scene on the device.
#[derive(Debug)]
pub struct GpuScene {
    /// How nodes, triangles and threaded records are stored.
    pub storage: SceneStorage,
    /// Bytes of the nodes and threaded records (the BVH).
    pub bvh_bytes: u64,
    pub info_buffer: wgpu::Buffer,
    pub materials: wgpu::Buffer,
    /// Group 0 of every kernel, made with [`scene_layout`].
    pub bind_group: wgpu::BindGroup,
    pub info: SceneInfo,
    /// Bytes uploaded.
    pub bytes: u64,
    /// Nodes, triangles and threaded records, kept alive for the bind group.
    _records: SceneRecords,
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

/// The threaded records' contents ([`bvh::threaded`]): the six MTBVH threadings
/// (direction-major), then the TBVH's, each in its own pre-order.
fn all_threaded(bvh: &PackedBvh) -> Vec<ThreadedNode> {
    let mut records = Vec::with_capacity(bvh::threaded::record_count(bvh.nodes.len()));
    for d in 0..bvh::DIRECTION_COUNT {
        records.extend(threaded_nodes(
            &bvh.nodes,
            bvh.direction_links(d),
            bvh.mtbvh_roots[d],
        ));
    }
    records.extend(threaded_nodes(&bvh.nodes, &bvh.tbvh_links, bvh.tbvh_root));
    records
}

/// (label, bytes) of the nodes, triangles and threaded records: buffers or textures, by [`SceneStorage`].
fn record_sizes(bvh: &PackedBvh) -> [(&'static str, u64); 3] {
    let bytes = |count: usize, size: usize| (count * size) as u64;
    [
        ("bvh_nodes", bytes(bvh.nodes.len(), size_of::<BvhNode>())),
        (
            "bvh_triangles",
            bytes(bvh.triangles.len(), size_of::<PackedTriangle>()),
        ),
        (
            "bvh_threaded",
            bytes(
                bvh::threaded::record_count(bvh.nodes.len()),
                size_of::<ThreadedNode>(),
            ),
        ),
    ]
}

/// The materials buffer's records: each material (its light-sampling density per area and
/// the solid around it where given; missing entries: 0 and none), then the tables of every
/// mapped coat's grid (`render::coats::CoatGrid`: its smooth coat, then its rough nodes), which
/// the material's `coat_grid_*` fields point at, then the sheen grid's tables where a texture
/// gives some sheen's roughness (`GpuMaterial::sheen_grid_first`). One record where there are no materials: a
/// binding cannot be empty (no triangle refers to it).
pub fn gpu_materials(
    materials: &[Material],
    light_area_density: &[f32],
    exterior: &[u32],
) -> Vec<GpuMaterial> {
    let coats = render::coats::Coats::of(materials);
    let mut records: Vec<GpuMaterial> = (0..materials.len() as u32)
        .map(|id| GpuMaterial::new(&materials[id as usize], coats.own(id)))
        .collect();
    for (gpu, &density) in records.iter_mut().zip(light_area_density) {
        gpu.light_area_density = density;
    }
    for (gpu, &around) in records.iter_mut().zip(exterior) {
        gpu.exterior = around;
    }
    let sheens = render::sheen::sheen_tables(materials);
    for (gpu, table) in records.iter_mut().zip(&sheens) {
        if let Some(table) = table {
            gpu.set_sheen_table(table);
        }
    }
    for id in 0..materials.len() as u32 {
        let gpu = &mut records[id as usize];
        gpu.blend_photon_member = render::blend::blend_photon_member(materials, id);
        if let Some(texture) = render::blend::roughness_texture(materials, id) {
            gpu.roughness_texture = texture;
        }
    }
    for id in 0..materials.len() {
        let Some(grid) = coats.grid(id as u32) else {
            continue;
        };
        let first = records.len() as u32;
        records.push(GpuMaterial::coat_record(&grid.smooth));
        records.extend(grid.nodes.iter().map(GpuMaterial::coat_record));
        let gpu = &mut records[id];
        gpu.coat_grid_first = first;
        gpu.coat_grid_nodes = grid.nodes.len() as u32;
        gpu.coat_grid_roughness = grid.first_roughness;
        gpu.coat_grid_step = grid.roughness_step;
    }
    // The sheen grid's tables, once, where some sheen's roughness follows a texture.
    let textured_sheen = |m: &Material| m.sheen.is_some_and(|s| s.roughness_texture.is_some());
    if materials.iter().any(textured_sheen) {
        let first = records.len() as u32;
        records.extend(
            render::sheen::sheen_grid()
                .iter()
                .map(GpuMaterial::sheen_record),
        );
        for (gpu, material) in records.iter_mut().zip(materials) {
            if textured_sheen(material) {
                gpu.sheen_grid_first = first;
            }
        }
    }
    if records.is_empty() {
        records.push(GpuMaterial::new(&Material::default(), &Default::default()));
    }
    records
}

/// Checks, before anything is allocated, that a scene fits a device with `limits`: every
/// buffer within the binding and buffer sizes (every texture within the texture side, with
/// [`SceneStorage::Texels`]), enough storage buffers per shader stage.
pub fn check_scene_fits(
    bvh: &PackedBvh,
    material_count: usize,
    limits: &wgpu::Limits,
    storage: SceneStorage,
) -> Result<(), GpuError> {
    if limits.max_storage_buffers_per_shader_stage < STORAGE_BUFFERS_PER_STAGE {
        return Err(GpuError::TooFewStorageBuffers {
            needed: STORAGE_BUFFERS_PER_STAGE,
            limit: limits.max_storage_buffers_per_shader_stage,
        });
    }
    for (label, bytes) in record_sizes(bvh) {
        match storage {
            SceneStorage::Buffers => check_buffer_fits(label, bytes, limits)?,
            SceneStorage::Texels => check_texels_fit(label, bytes, TEXEL_ROW, limits)?,
        }
    }
    let material_bytes = (material_count.max(1) * size_of::<GpuMaterial>()) as u64;
    check_buffer_fits("materials", material_bytes, limits)
}

/// The storage to upload `bvh` in: `preferred` where the scene fits it, else the other one
/// where it fits that (the threaded records take 224 bytes a node in one binding, more than
/// some adapters' 128 MiB bindings hold for scenes of ~450 k triangles, where textures of
/// [`TEXEL_ROW`] texels a row still take them). The error is `preferred`'s when neither fits.
pub fn fitting_storage(
    bvh: &PackedBvh,
    material_count: usize,
    limits: &wgpu::Limits,
    preferred: SceneStorage,
) -> Result<SceneStorage, GpuError> {
    let error = match check_scene_fits(bvh, material_count, limits, preferred) {
        Ok(()) => return Ok(preferred),
        Err(error) => error,
    };
    let other = preferred.other();
    match check_scene_fits(bvh, material_count, limits, other) {
        Ok(()) => Ok(other),
        Err(_) => Err(error),
    }
}

/// The layout of bind group 0 (see `shaders/shared/scene_bindings.wgsl` and
/// `scene_texels.wgsl`): nodes, triangles and threaded records at 0–2, the scene's info and materials at
/// 3 and 4.
pub fn scene_layout(device: &wgpu::Device, storage: SceneStorage) -> wgpu::BindGroupLayout {
    let entries: Vec<_> = (0..5)
        .map(|binding| match storage {
            SceneStorage::Texels if binding < 3 => wgpu::BindGroupLayoutEntry {
                binding,
                visibility: wgpu::ShaderStages::COMPUTE,
                ty: wgpu::BindingType::Texture {
                    sample_type: wgpu::TextureSampleType::Uint,
                    view_dimension: wgpu::TextureViewDimension::D2,
                    multisampled: false,
                },
                count: None,
            },
            _ => storage_entry(binding, true),
        })
        .collect();
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
    /// Uploads `bvh` and `materials` stored as the context prefers
    /// ([`GpuContext::scene_storage`]), after [`check_scene_fits`].
    pub fn upload(
        context: &GpuContext,
        bvh: &PackedBvh,
        materials: &[Material],
    ) -> Result<GpuScene, GpuError> {
        GpuScene::upload_lit(context, bvh, materials, &[], &[])
    }

    /// [`GpuScene::upload`] with each material's light-sampling density per area
    /// (`render::emission::light_area_density`; missing entries are 0), which the SPPM eye
    /// pass weighs emitters met after glossy reflections by, and the solid around it
    /// (`render::nesting::Nesting::exterior`; missing entries: none).
    pub fn upload_lit(
        context: &GpuContext,
        bvh: &PackedBvh,
        materials: &[Material],
        light_area_density: &[f32],
        exterior: &[u32],
    ) -> Result<GpuScene, GpuError> {
        let storage = context.scene_storage;
        let gpu_materials = gpu_materials(materials, light_area_density, exterior);
        check_scene_fits(bvh, gpu_materials.len(), &context.limits, storage)?;
        let device = &context.device;
        let storage_buffer = |label: &str, contents: &[u8]| {
            device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some(label),
                contents,
                usage: wgpu::BufferUsages::STORAGE,
            })
        };
        let info = SceneInfo::new(bvh);
        let threaded = all_threaded(bvh);
        let records: [(&str, &[u8]); 3] = [
            ("bvh_nodes", bytemuck::cast_slice(&bvh.nodes)),
            ("bvh_triangles", bytemuck::cast_slice(&bvh.triangles)),
            ("bvh_threaded", bytemuck::cast_slice(&threaded)),
        ];
        let info_buffer = storage_buffer("scene_info", bytemuck::bytes_of(&info));
        let materials = storage_buffer("materials", bytemuck::cast_slice(&gpu_materials));
        let (records, sizes) = match storage {
            SceneStorage::Buffers => {
                let buffers = records.map(|(label, contents)| storage_buffer(label, contents));
                let sizes = buffers.each_ref().map(|b| b.size());
                (SceneRecords::Buffers(buffers), sizes)
            }
            SceneStorage::Texels => {
                let textures = records.map(|(label, contents)| texels(context, label, contents));
                let sizes = textures
                    .each_ref()
                    .map(|t| u64::from(t.width()) * u64::from(t.height()) * 16);
                // A view keeps its texture alive.
                let views = textures.map(|t| t.create_view(&Default::default()));
                (SceneRecords::Texels(views), sizes)
            }
        };
        let record_resources: Vec<_> = match &records {
            SceneRecords::Buffers(buffers) => {
                buffers.iter().map(|b| b.as_entire_binding()).collect()
            }
            SceneRecords::Texels(views) => views
                .iter()
                .map(wgpu::BindingResource::TextureView)
                .collect(),
        };
        let entries: Vec<_> = record_resources
            .into_iter()
            .chain([
                info_buffer.as_entire_binding(),
                materials.as_entire_binding(),
            ])
            .enumerate()
            .map(|(binding, resource)| wgpu::BindGroupEntry {
                binding: binding as u32,
                resource,
            })
            .collect();
        let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("scene"),
            layout: &scene_layout(device, storage),
            entries: &entries,
        });
        Ok(GpuScene {
            storage,
            bvh_bytes: sizes[0] + sizes[2],
            bytes: sizes.iter().sum::<u64>() + info_buffer.size() + materials.size(),
            _records: records,
            info_buffer,
            materials,
            bind_group,
            info,
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
    fn fitting_storage_falls_back_to_the_other_storage_only_when_needed() {
        let bvh = small_bvh();
        let roomy = wgpu::Limits::default();
        for preferred in [SceneStorage::Buffers, SceneStorage::Texels] {
            assert_eq!(
                fitting_storage(&bvh, 1, &roomy, preferred).unwrap(),
                preferred
            );
        }
        // Bindings too small for the threaded records (but holding the one material, which stays
        // in a storage buffer), textures large enough.
        let small_bindings = wgpu::Limits {
            max_storage_buffer_binding_size: size_of::<GpuMaterial>() as u64,
            ..wgpu::Limits::default()
        };
        assert_eq!(
            fitting_storage(&bvh, 1, &small_bindings, SceneStorage::Buffers).unwrap(),
            SceneStorage::Texels
        );
        // Neither fits: the preferred storage's error, naming its limit.
        let neither = wgpu::Limits {
            max_storage_buffer_binding_size: size_of::<GpuMaterial>() as u64,
            max_texture_dimension_2d: 0,
            ..wgpu::Limits::default()
        };
        let message = fitting_storage(&bvh, 1, &neither, SceneStorage::Buffers)
            .unwrap_err()
            .to_string();
        assert!(
            message.contains("max_storage_buffer_binding_size"),
            "{message}"
        );
    }

    #[test]
    fn threaded_records_hold_six_mtbvh_sets_then_the_tbvh() {
        let bvh = small_bvh();
        let records = all_threaded(&bvh);
        let n = bvh.nodes.len();
        assert_eq!(records.len(), 7 * n);
        for d in 0..bvh::DIRECTION_COUNT {
            let set = threaded_nodes(&bvh.nodes, bvh.direction_links(d), bvh.mtbvh_roots[d]);
            assert_eq!(&records[d * n..][..n], &set[..]);
        }
        // The TBVH's pre-order is the stored node order.
        for (record, node) in records[6 * n..].iter().zip(&bvh.nodes) {
            assert_eq!((record.min, record.max), (node.min, node.max));
        }
        assert_eq!(SceneInfo::new(&bvh).tbvh_record_base as usize, 6 * n);
    }

    #[test]
    fn oversize_scene_names_the_buffer_and_the_limit() {
        let bvh = small_bvh();
        let triangle_bytes = (bvh.triangles.len() * size_of::<PackedTriangle>()) as u64;
        let limits = wgpu::Limits {
            max_storage_buffer_binding_size: triangle_bytes - 1,
            ..wgpu::Limits::default()
        };
        let message = check_scene_fits(&bvh, 1, &limits, SceneStorage::Buffers)
            .unwrap_err()
            .to_string();
        assert!(message.contains("bvh_triangles"), "{message}");
        assert!(
            message.contains("max_storage_buffer_binding_size"),
            "{message}"
        );
        assert!(!message.contains('\n'));
        assert!(check_scene_fits(&bvh, 1, &wgpu::Limits::default(), SceneStorage::Buffers).is_ok());
    }

    #[test]
    fn oversize_texels_name_the_texture_and_the_limit() {
        let bvh = small_bvh();
        let triangle_rows = (bvh.triangles.len() * size_of::<PackedTriangle>())
            .div_ceil(16 * TEXEL_ROW as usize) as u32;
        let limits = wgpu::Limits {
            max_texture_dimension_2d: TEXEL_ROW,
            ..wgpu::Limits::default()
        };
        assert!(check_scene_fits(&bvh, 1, &limits, SceneStorage::Texels).is_ok());
        // Buffers are not held to the texture side.
        let limits = wgpu::Limits {
            max_texture_dimension_2d: triangle_rows.max(1) - 1,
            ..wgpu::Limits::default()
        };
        assert!(check_scene_fits(&bvh, 1, &limits, SceneStorage::Buffers).is_ok());
        let message = check_scene_fits(&bvh, 1, &limits, SceneStorage::Texels)
            .unwrap_err()
            .to_string();
        assert!(message.contains("max_texture_dimension_2d"), "{message}");
        assert!(!message.contains('\n'));
    }

    #[test]
    fn too_few_storage_buffers_is_an_error_in_words() {
        let limits = wgpu::Limits {
            max_storage_buffers_per_shader_stage: 4,
            ..wgpu::Limits::default()
        };
        let message = check_scene_fits(&small_bvh(), 1, &limits, SceneStorage::Texels)
            .unwrap_err()
            .to_string();
        assert!(
            message.contains("max_storage_buffers_per_shader_stage"),
            "{message}"
        );
    }
}
