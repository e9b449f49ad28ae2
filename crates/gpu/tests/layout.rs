//! The WGSL structs mirror the Rust ones byte for byte: sizes, member names and offsets, array
//! strides, read through naga's reflection. Also validates every shader file.

use std::mem::{offset_of, size_of};
use std::path::{Path, PathBuf};

use bvh::{BvhNode, Links, PackedTriangle, PackedVertex};
use naga::valid::{Capabilities, ValidationFlags, Validator};

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
fn links_layout_matches_rust() {
    let module = parse(BVH_TYPES, "bvh_types.wgsl");
    assert_layout(
        &module,
        "Links",
        size_of::<Links>(),
        &[
            ("hit", offset_of!(Links, hit)),
            ("miss", offset_of!(Links, miss)),
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

#[test]
fn every_shader_file_parses_and_validates() {
    let mut files = Vec::new();
    wgsl_files(
        &Path::new(env!("CARGO_MANIFEST_DIR")).join("shaders"),
        &mut files,
    );
    assert!(!files.is_empty(), "no .wgsl files under shaders/");
    for path in files {
        let name = path.display().to_string();
        let source = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{name}: {e}"));
        let module = parse(&source, &name);
        Validator::new(ValidationFlags::all(), Capabilities::all())
            .validate(&module)
            .unwrap_or_else(|e| panic!("{name}: {}", e.emit_to_string(&source)));
    }
}
