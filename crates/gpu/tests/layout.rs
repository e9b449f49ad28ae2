//! The WGSL structs mirror the Rust ones byte for byte: sizes, member names and offsets, array
//! strides, read through naga's reflection. Also validates every shader module, checks the
//! generated prelude's values and that no shader file is left out of a module.

use std::mem::{offset_of, size_of};
use std::path::{Path, PathBuf};

use bvh::{BvhNode, CompactFrame, CompactNode, PackedTriangle, PackedVertex, ThreadedNode};
use gpu::SceneStorage;
use gpu::prelude;
use gpu::shader::Module;
use gpu::types::{BenchCameraUniform, GpuHit, GpuMaterial, GpuRay, SceneInfo};
use naga::valid::{Capabilities, ValidationFlags, Validator};
use render::half_storage::Precision;

const BVH_TYPES: &str = include_str!("../shaders/shared/bvh_types.wgsl");

fn parse(source: &str, name: &str) -> naga::Module {
    naga::front::wgsl::parse_str(source)
        .unwrap_or_else(|e| panic!("{name}: {}", e.emit_to_string(source)))
}

/// The members (name, offset, type) and span of struct `name`.
fn wgsl_struct(module: &naga::Module, name: &str) -> (Vec<naga::StructMember>, u32) {
    let found = module.types.iter().find_map(|(_, ty)| match &ty.inner {
        naga::TypeInner::Struct { members, span } if ty.name.as_deref() == Some(name) => {
            Some((members.clone(), *span))
        }
        _ => None,
    });
    found.unwrap_or_else(|| panic!("no WGSL struct {name}"))
}

/// Asserts span == size and, member by member, the same names in the same order at the same
/// offsets. `fields` lists (name, offset_of!) in declaration order.
fn assert_layout(module: &naga::Module, name: &str, size: usize, fields: &[(&str, usize)]) {
    let (members, span) = wgsl_struct(module, name);
    assert_eq!(span as usize, size, "{name}: WGSL span vs Rust size_of");
    let wgsl: Vec<(&str, usize)> = members
        .iter()
        .map(|m| (m.name.as_deref().unwrap_or("?"), m.offset as usize))
        .collect();
    assert_eq!(
        wgsl, fields,
        "{name}: WGSL (member, offset) vs Rust offset_of!"
    );
}

#[test]
fn bvh_node_layout_matches_rust() {
    let module = parse(BVH_TYPES, "bvh_types.wgsl");
    assert_layout(
        &module,
        "BvhNode",
        size_of::<BvhNode>(),
        &[
            ("min", offset_of!(BvhNode, min)),
            ("first_or_right", offset_of!(BvhNode, first_or_right)),
            ("max", offset_of!(BvhNode, max)),
            ("triangle_count", offset_of!(BvhNode, triangle_count)),
        ],
    );
}

#[test]
fn threaded_node_layout_matches_rust() {
    let module = parse(BVH_TYPES, "bvh_types.wgsl");
    assert_layout(
        &module,
        "ThreadedNode",
        size_of::<ThreadedNode>(),
        &[
            ("min", offset_of!(ThreadedNode, min)),
            ("miss", offset_of!(ThreadedNode, miss)),
            ("max", offset_of!(ThreadedNode, max)),
            ("leaf", offset_of!(ThreadedNode, leaf)),
        ],
    );
}

#[test]
fn compact_node_layout_matches_rust() {
    let module = parse(BVH_TYPES, "bvh_types.wgsl");
    assert_layout(
        &module,
        "CompactNode",
        size_of::<CompactNode>(),
        &[
            ("bounds_and_meta", offset_of!(CompactNode, bounds_and_meta)),
            ("links", offset_of!(CompactNode, links)),
        ],
    );
}

#[test]
fn compact_frame_layout_matches_rust() {
    let module = parse(BVH_TYPES, "bvh_types.wgsl");
    assert_layout(
        &module,
        "CompactFrame",
        size_of::<CompactFrame>(),
        &[
            ("origin", offset_of!(CompactFrame, origin)),
            ("root", offset_of!(CompactFrame, root)),
            ("scale", offset_of!(CompactFrame, scale)),
            ("node_count", offset_of!(CompactFrame, node_count)),
        ],
    );
}

#[test]
fn packed_vertex_layout_matches_rust() {
    let module = parse(BVH_TYPES, "bvh_types.wgsl");
    assert_layout(
        &module,
        "PackedVertex",
        size_of::<PackedVertex>(),
        &[
            ("position", offset_of!(PackedVertex, position)),
            ("u", offset_of!(PackedVertex, u)),
            ("normal_xy", offset_of!(PackedVertex, normal_xy)),
            ("signed_material", offset_of!(PackedVertex, signed_material)),
            ("v", offset_of!(PackedVertex, v)),
        ],
    );
}

#[test]
fn packed_triangle_layout_and_vertex_stride_match_rust() {
    let module = parse(BVH_TYPES, "bvh_types.wgsl");
    assert_layout(
        &module,
        "PackedTriangle",
        size_of::<PackedTriangle>(),
        &[("vertices", offset_of!(PackedTriangle, vertices))],
    );
    let (members, _) = wgsl_struct(&module, "PackedTriangle");
    match module.types[members[0].ty].inner {
        naga::TypeInner::Array { stride, size, .. } => {
            assert_eq!(
                stride as usize,
                size_of::<PackedVertex>(),
                "vertices stride"
            );
            assert_eq!(
                size,
                naga::ArraySize::Constant(3.try_into().unwrap()),
                "vertices length"
            );
        }
        ref other => panic!("PackedTriangle.vertices is not an array: {other:?}"),
    }
}

fn wgsl_files(dir: &Path, out: &mut Vec<PathBuf>) {
    for entry in std::fs::read_dir(dir).unwrap_or_else(|e| panic!("{}: {e}", dir.display())) {
        let path = entry.expect("readable directory entry").path();
        if path.is_dir() {
            wgsl_files(&path, out);
        } else if path.extension().is_some_and(|e| e == "wgsl") {
            out.push(path);
        }
    }
}

fn validate(module: &naga::Module, source: &str, name: &str) {
    Validator::new(ValidationFlags::all(), Capabilities::all())
        .validate(module)
        .unwrap_or_else(|e| panic!("{name}: {}", e.emit_to_string(source)));
}

#[test]
fn every_shader_module_parses_and_validates() {
    for module in Module::ALL {
        for precision in [Precision::F32, Precision::F16] {
            for storage in [SceneStorage::Buffers, SceneStorage::Texels] {
                let buffers = module.source_with_precision(precision);
                let source = gpu::shader::with_scene_storage(buffers.clone(), storage);
                // Every module but the display's reads the scene, so texels change it.
                let binds_scene = module != Module::Display;
                assert_eq!(
                    source != buffers,
                    binds_scene && storage == SceneStorage::Texels,
                    "{}",
                    module.label()
                );
                let label = format!(
                    "{} ({}, {})",
                    module.label(),
                    precision.name(),
                    storage.name()
                );
                let parsed = parse(&source, &label);
                validate(&parsed, &source, &label);
            }
        }
    }
}

#[test]
fn every_shader_file_belongs_to_a_module() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("shaders");
    let mut files = Vec::new();
    wgsl_files(&root, &mut files);
    let mut used: Vec<&str> = Module::ALL
        .iter()
        .flat_map(|m| m.parts())
        .map(|(name, _)| name)
        .collect();
    used.extend(gpu::shader::STORAGE_PARTS);
    used.extend(gpu::shader::SCENE_PARTS);
    used.extend(gpu::kdtree::parts().into_iter().map(|(name, _)| name));
    for path in files {
        let relative = path.strip_prefix(&root).expect("under shaders/");
        let relative = relative.to_str().expect("UTF-8 path").replace('\\', "/");
        assert!(
            used.contains(&relative.as_str()),
            "{relative} is in no shader module"
        );
    }
}

#[test]
fn prelude_constants_evaluate_to_the_rust_values() {
    let source = prelude::wgsl();
    let module = parse(&source, "prelude");
    let constants = prelude::constants();
    assert_eq!(module.constants.len(), constants.len());
    for (name, value) in constants {
        let (_, constant) = module
            .constants
            .iter()
            .find(|(_, c)| c.name.as_deref() == Some(name))
            .unwrap_or_else(|| panic!("no constant {name} in the prelude"));
        let literal = match module.global_expressions[constant.init] {
            naga::Expression::Literal(literal) => literal,
            ref other => panic!("{name} = {other:?}"),
        };
        match (value, literal) {
            (prelude::Value::U32(want), naga::Literal::U32(got)) => assert_eq!(got, want, "{name}"),
            (prelude::Value::F32(want), naga::Literal::F32(got)) => {
                assert_eq!(got.to_bits(), want.to_bits(), "{name}: {got} vs {want}")
            }
            (want, got) => panic!("{name}: {got:?} for {want:?}"),
        }
    }
}

#[test]
fn gpu_types_layout_matches_rust() {
    let source = Module::Raygen.source();
    let module = parse(&source, "raygen");
    assert_layout(
        &module,
        "GpuRay",
        size_of::<GpuRay>(),
        &[
            ("origin", offset_of!(GpuRay, origin)),
            ("t_max", offset_of!(GpuRay, t_max)),
            ("direction", offset_of!(GpuRay, direction)),
            ("pad", offset_of!(GpuRay, pad)),
        ],
    );
    assert_layout(
        &module,
        "GpuHit",
        size_of::<GpuHit>(),
        &[
            ("t", offset_of!(GpuHit, t)),
            ("triangle", offset_of!(GpuHit, triangle)),
            ("u", offset_of!(GpuHit, u)),
            ("v", offset_of!(GpuHit, v)),
        ],
    );
    assert_layout(
        &module,
        "SceneInfo",
        size_of::<SceneInfo>(),
        &[
            ("node_count", offset_of!(SceneInfo, node_count)),
            ("triangle_count", offset_of!(SceneInfo, triangle_count)),
            ("tbvh_record_base", offset_of!(SceneInfo, tbvh_record_base)),
            ("pad", offset_of!(SceneInfo, pad)),
            ("spectrum", offset_of!(SceneInfo, spectrum)),
            ("film_spectrum", offset_of!(SceneInfo, film_spectrum)),
        ],
    );
    assert_layout(
        &module,
        "GpuMaterial",
        size_of::<GpuMaterial>(),
        &[
            ("base_color", offset_of!(GpuMaterial, base_color)),
            ("surface", offset_of!(GpuMaterial, surface)),
            ("emission", offset_of!(GpuMaterial, emission)),
            ("ior", offset_of!(GpuMaterial, ior)),
            (
                "base_color_texture",
                offset_of!(GpuMaterial, base_color_texture),
            ),
            (
                "emission_texture",
                offset_of!(GpuMaterial, emission_texture),
            ),
            ("alpha_cutoff", offset_of!(GpuMaterial, alpha_cutoff)),
            ("flags", offset_of!(GpuMaterial, flags)),
            ("absorption", offset_of!(GpuMaterial, absorption)),
            ("roughness_alpha", offset_of!(GpuMaterial, roughness_alpha)),
            ("normal_texture", offset_of!(GpuMaterial, normal_texture)),
            ("normal_scale", offset_of!(GpuMaterial, normal_scale)),
            (
                "light_area_density",
                offset_of!(GpuMaterial, light_area_density),
            ),
            (
                "coat_diffuse_scale",
                offset_of!(GpuMaterial, coat_diffuse_scale),
            ),
            (
                "coat_transmittance",
                offset_of!(GpuMaterial, coat_transmittance),
            ),
            ("blend_weight", offset_of!(GpuMaterial, blend_weight)),
            ("blend_other", offset_of!(GpuMaterial, blend_other)),
            (
                "blend_photon_member",
                offset_of!(GpuMaterial, blend_photon_member),
            ),
            ("exterior", offset_of!(GpuMaterial, exterior)),
            ("dispersion", offset_of!(GpuMaterial, dispersion)),
            (
                "roughness_texture",
                offset_of!(GpuMaterial, roughness_texture),
            ),
            (
                "roughness_factor",
                offset_of!(GpuMaterial, roughness_factor),
            ),
            ("roughness_lobe", offset_of!(GpuMaterial, roughness_lobe)),
            ("coat_grid_first", offset_of!(GpuMaterial, coat_grid_first)),
            ("coat_grid_nodes", offset_of!(GpuMaterial, coat_grid_nodes)),
            (
                "coat_grid_roughness",
                offset_of!(GpuMaterial, coat_grid_roughness),
            ),
            ("coat_grid_step", offset_of!(GpuMaterial, coat_grid_step)),
            ("clearcoat", offset_of!(GpuMaterial, clearcoat)),
            ("clearcoat_alpha", offset_of!(GpuMaterial, clearcoat_alpha)),
            (
                "clearcoat_texture",
                offset_of!(GpuMaterial, clearcoat_texture),
            ),
            (
                "clearcoat_roughness_texture",
                offset_of!(GpuMaterial, clearcoat_roughness_texture),
            ),
            ("sheen_color", offset_of!(GpuMaterial, sheen_color)),
            ("sheen_alpha", offset_of!(GpuMaterial, sheen_alpha)),
            ("sheen_albedo", offset_of!(GpuMaterial, sheen_albedo)),
            (
                "sheen_color_texture",
                offset_of!(GpuMaterial, sheen_color_texture),
            ),
            (
                "sheen_roughness_texture",
                offset_of!(GpuMaterial, sheen_roughness_texture),
            ),
            (
                "sheen_grid_first",
                offset_of!(GpuMaterial, sheen_grid_first),
            ),
            ("sheen_roughness", offset_of!(GpuMaterial, sheen_roughness)),
            (
                "clearcoat_normal_texture",
                offset_of!(GpuMaterial, clearcoat_normal_texture),
            ),
            (
                "clearcoat_normal_scale",
                offset_of!(GpuMaterial, clearcoat_normal_scale),
            ),
            (
                "transmission_texture",
                offset_of!(GpuMaterial, transmission_texture),
            ),
            (
                "diffuse_transmission_texture",
                offset_of!(GpuMaterial, diffuse_transmission_texture),
            ),
            (
                "diffuse_transmission_color",
                offset_of!(GpuMaterial, diffuse_transmission_color),
            ),
            (
                "diffuse_transmission",
                offset_of!(GpuMaterial, diffuse_transmission),
            ),
            (
                "diffuse_transmission_color_texture",
                offset_of!(GpuMaterial, diffuse_transmission_color_texture),
            ),
            (
                "anisotropy_texture",
                offset_of!(GpuMaterial, anisotropy_texture),
            ),
            ("anisotropy", offset_of!(GpuMaterial, anisotropy)),
            ("scattering", offset_of!(GpuMaterial, scattering)),
            (
                "scatter_anisotropy",
                offset_of!(GpuMaterial, scatter_anisotropy),
            ),
            ("iridescence", offset_of!(GpuMaterial, iridescence)),
            (
                "iridescence_texture",
                offset_of!(GpuMaterial, iridescence_texture),
            ),
            (
                "iridescence_thickness_texture",
                offset_of!(GpuMaterial, iridescence_thickness_texture),
            ),
            (
                "specular_texture",
                offset_of!(GpuMaterial, specular_texture),
            ),
            (
                "specular_color_texture",
                offset_of!(GpuMaterial, specular_color_texture),
            ),
            (
                "specular_tinted_f0",
                offset_of!(GpuMaterial, specular_tinted_f0),
            ),
            ("specular_factor", offset_of!(GpuMaterial, specular_factor)),
            ("metal_edge", offset_of!(GpuMaterial, metal_edge)),
            ("specular_layer", offset_of!(GpuMaterial, specular_layer)),
        ],
    );
    assert_layout(
        &module,
        "BenchCameraUniform",
        size_of::<BenchCameraUniform>(),
        &[
            ("eye", offset_of!(BenchCameraUniform, eye)),
            ("tan_half_fov", offset_of!(BenchCameraUniform, tan_half_fov)),
            ("forward", offset_of!(BenchCameraUniform, forward)),
            ("side", offset_of!(BenchCameraUniform, side)),
            ("right", offset_of!(BenchCameraUniform, right)),
            ("diagonal", offset_of!(BenchCameraUniform, diagonal)),
            ("up", offset_of!(BenchCameraUniform, up)),
            ("ray_count", offset_of!(BenchCameraUniform, ray_count)),
        ],
    );
}

#[test]
fn sppm_types_layout_matches_render_buffers() {
    use render::buffers::{Light, PathSlot, Photon, SppmParams, VisiblePoint};
    let source = Module::Sppm.source();
    let module = parse(&source, "sppm");
    assert_layout(
        &module,
        "PathSlot",
        size_of::<PathSlot>(),
        &[
            ("origin", offset_of!(PathSlot, origin)),
            ("depth", offset_of!(PathSlot, depth)),
            ("direction", offset_of!(PathSlot, direction)),
            ("pass_throughs", offset_of!(PathSlot, pass_throughs)),
            ("flux", offset_of!(PathSlot, flux)),
            ("state", offset_of!(PathSlot, state)),
            ("walk_densities", offset_of!(PathSlot, walk_densities)),
            ("walk_hero", offset_of!(PathSlot, walk_hero)),
        ],
    );
    assert_layout(
        &module,
        "Photon",
        size_of::<Photon>(),
        &[
            ("position", offset_of!(Photon, position)),
            ("normal", offset_of!(Photon, normal)),
            ("flux", offset_of!(Photon, flux)),
            ("pad", offset_of!(Photon, pad)),
        ],
    );
    assert_layout(
        &module,
        "VisiblePoint",
        size_of::<VisiblePoint>(),
        &[
            ("position", offset_of!(VisiblePoint, position)),
            ("normal", offset_of!(VisiblePoint, normal)),
            ("weight", offset_of!(VisiblePoint, weight)),
            ("pad", offset_of!(VisiblePoint, pad)),
        ],
    );
    assert_pixel_stats_layout(&module);
    assert_layout(
        &module,
        "Light",
        size_of::<Light>(),
        &[
            ("v0", offset_of!(Light, v0)),
            ("cdf", offset_of!(Light, cdf)),
            ("edge1", offset_of!(Light, edge1)),
            ("double_sided", offset_of!(Light, double_sided)),
            ("edge2", offset_of!(Light, edge2)),
            ("kind", offset_of!(Light, kind)),
            ("flux", offset_of!(Light, flux)),
            ("medium", offset_of!(Light, medium)),
        ],
    );
    // Rust's `storage_origin: [f32; 3]` is WGSL's origin_x..origin_z (a vec3 would be 16-byte
    // aligned).
    let origin = offset_of!(SppmParams, storage_origin);
    assert_layout(
        &module,
        "SppmParams",
        size_of::<SppmParams>(),
        &[
            ("eye", offset_of!(SppmParams, eye)),
            ("width", offset_of!(SppmParams, width)),
            ("forward", offset_of!(SppmParams, forward)),
            ("height", offset_of!(SppmParams, height)),
            ("right", offset_of!(SppmParams, right)),
            ("slot_count", offset_of!(SppmParams, slot_count)),
            ("up", offset_of!(SppmParams, up)),
            ("hash_size", offset_of!(SppmParams, hash_size)),
            ("alpha", offset_of!(SppmParams, alpha)),
            ("max_depth", offset_of!(SppmParams, max_depth)),
            ("light_count", offset_of!(SppmParams, light_count)),
            ("seed", offset_of!(SppmParams, seed)),
            ("epsilon", offset_of!(SppmParams, epsilon)),
            ("origin_x", origin),
            ("origin_y", origin + 4),
            ("origin_z", origin + 8),
            ("flux_scale", offset_of!(SppmParams, storage_flux_scale)),
            ("sky_r", offset_of!(SppmParams, sky)),
            ("sky_g", offset_of!(SppmParams, sky) + 4),
            ("sky_b", offset_of!(SppmParams, sky) + 8),
            ("sample_lights", offset_of!(SppmParams, sample_lights)),
            ("cut_outs", offset_of!(SppmParams, cut_outs)),
            ("eye_every", offset_of!(SppmParams, eye_every)),
            ("indirect_alpha", offset_of!(SppmParams, indirect_alpha)),
            ("camera_medium", offset_of!(SppmParams, camera_medium)),
            ("photon_classes", offset_of!(SppmParams, photon_classes)),
            ("lens_radius", offset_of!(SppmParams, lens_radius)),
            ("focus_distance", offset_of!(SppmParams, focus_distance)),
            (
                "scene_half_extent",
                offset_of!(SppmParams, scene_half_extent),
            ),
            ("aperture_blades", offset_of!(SppmParams, aperture_blades)),
            (
                "aperture_rotation",
                offset_of!(SppmParams, aperture_rotation),
            ),
            ("light_candidates", offset_of!(SppmParams, light_candidates)),
            ("orthographic", offset_of!(SppmParams, orthographic)),
            ("shrunk_tenths", offset_of!(SppmParams, shrunk_tenths)),
        ],
    );
}

#[test]
fn sppm_module_is_validated_and_binds_the_buffers_the_backend_counts() {
    assert!(
        Module::ALL.contains(&Module::Sppm),
        "Module::ALL lacks Sppm"
    );
    let used: Vec<&str> = Module::Sppm.parts().iter().map(|(name, _)| *name).collect();
    assert!(
        used.contains(&"shared/sppm_types.wgsl"),
        "Module::Sppm lacks shared/sppm_types.wgsl"
    );
    // Every piece of the shading and of the kernels, each file of their folders.
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("shaders");
    for folder in ["shared/shading", "kernels/sppm"] {
        let mut files = Vec::new();
        wgsl_files(&root.join(folder), &mut files);
        assert!(!files.is_empty(), "no pieces in shaders/{folder}");
        for path in files {
            let relative = path.strip_prefix(&root).expect("under shaders/");
            let part = relative.to_str().expect("UTF-8 path").replace('\\', "/");
            assert!(used.contains(&part.as_str()), "Module::Sppm lacks {part}");
        }
    }
    let source = Module::Sppm.source();
    let module = parse(&source, "sppm");
    validate(&module, &source, "sppm");
    let storage = module
        .global_variables
        .iter()
        .filter(|(_, v)| matches!(v.space, naga::AddressSpace::Storage { .. }))
        .count();
    assert_eq!(
        storage as u32,
        gpu::sppm::SPPM_STORAGE_BUFFERS,
        "storage buffers bound by Module::Sppm vs gpu::sppm::SPPM_STORAGE_BUFFERS"
    );
}

#[test]
fn display_params_layout_matches_rust() {
    use gpu::display::DisplayParams;
    let source = Module::Display.source();
    let module = parse(&source, "display");
    assert_layout(
        &module,
        "DisplayParams",
        size_of::<DisplayParams>(),
        &[
            ("render_width", offset_of!(DisplayParams, render_width)),
            ("render_height", offset_of!(DisplayParams, render_height)),
            ("target_width", offset_of!(DisplayParams, target_width)),
            ("target_height", offset_of!(DisplayParams, target_height)),
            ("eye_passes", offset_of!(DisplayParams, eye_passes)),
            ("exposure", offset_of!(DisplayParams, exposure)),
            ("encode_srgb", offset_of!(DisplayParams, encode_srgb)),
            ("tone_map", offset_of!(DisplayParams, tone_map)),
            ("parts", offset_of!(DisplayParams, parts)),
            ("pad0", offset_of!(DisplayParams, pad0)),
            ("pad1", offset_of!(DisplayParams, pad1)),
            ("pad2", offset_of!(DisplayParams, pad2)),
        ],
    );
    // The statistics it reads are the SPPM kernels' struct.
    assert_pixel_stats_layout(&module);
}

/// `PixelStats` (`sppm_types.wgsl`) against `render::buffers::PixelStats` up to its volume τ,
/// which the GPU keeps in a buffer of its own (a `vec4` a pixel: τ and the padding).
fn assert_pixel_stats_layout(module: &naga::Module) {
    use render::buffers::{PIXEL_STATS_SURFACE_BYTES, PixelStats};
    assert_eq!(
        offset_of!(PixelStats, volume_tau),
        PIXEL_STATS_SURFACE_BYTES
    );
    assert_eq!(size_of::<PixelStats>(), PIXEL_STATS_SURFACE_BYTES + 16);
    assert_eq!(offset_of!(PixelStats, pad), PIXEL_STATS_SURFACE_BYTES + 12);
    assert_layout(
        module,
        "PixelStats",
        PIXEL_STATS_SURFACE_BYTES,
        &[
            ("tau", offset_of!(PixelStats, tau)),
            ("photon_count", offset_of!(PixelStats, photon_count)),
            ("direct", offset_of!(PixelStats, direct)),
            ("radius", offset_of!(PixelStats, radius)),
            ("caustic_tau", offset_of!(PixelStats, caustic_tau)),
            ("caustic_count", offset_of!(PixelStats, caustic_count)),
            ("caustic_radius", offset_of!(PixelStats, caustic_radius)),
            ("specular_seen", offset_of!(PixelStats, specular_seen)),
            ("volume_count", offset_of!(PixelStats, volume_count)),
            ("volume_radius", offset_of!(PixelStats, volume_radius)),
        ],
    );
}
