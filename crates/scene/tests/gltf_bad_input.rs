//! Malformed and hostile glTF files: each must end in a one-line `SceneError` saying what is
//! wrong where, never a panic, a stack overflow or a huge allocation.

use crate::gltf_support;

use gltf_support::*;
use scene::SceneError;
use serde_json::json;

/// The error message of [`quad_doc`] after `edit`.
fn error_after(edit: impl FnOnce(&mut Doc)) -> String {
    let mut doc = quad_doc(None);
    edit(&mut doc);
    error_of(doc.load())
}

/// The quad's document as a GLB.
fn quad_glb() -> Vec<u8> {
    let doc = quad_doc(Some(json!({ "emissiveFactor": [1, 1, 1] })));
    let json = serde_json::to_vec(&doc.json_for(Layout::Glb, "")).expect("JSON");
    glb(&json, &doc.bin)
}

#[test]
fn an_empty_file_is_refused() {
    assert_mentions(
        &error_of(load_bytes("empty.gltf", b"")),
        &["empty.gltf", "empty file"],
    );
}

#[test]
fn malformed_json_is_refused() {
    let message = error_of(load_bytes("broken.gltf", b"{ \"asset\": { \"version\": "));
    assert_mentions(&message, &["invalid glTF JSON"]);
    let message = error_of(load_bytes("array.gltf", b"[1, 2, 3]"));
    assert_mentions(&message, &["invalid glTF JSON"]);
}

#[test]
fn a_glb_header_claiming_more_than_the_file_is_refused_before_allocating() {
    let mut bytes = quad_glb();
    bytes[8..12].copy_from_slice(&u32::MAX.to_le_bytes());
    assert_mentions(
        &error_of(load_bytes("huge.glb", &bytes)),
        &["truncated GLB", "4294967295"],
    );
    let whole = quad_glb();
    let cut = &whole[..whole.len() - 10];
    assert_mentions(&error_of(load_bytes("cut.glb", cut)), &["truncated GLB"]);
    assert_mentions(
        &error_of(load_bytes("stub.glb", b"glTF\x02\0")),
        &["truncated GLB header"],
    );
}

#[test]
fn a_glb_chunk_claiming_more_than_remains_is_refused() {
    let mut bytes = quad_glb();
    bytes[12..16].copy_from_slice(&100_000u32.to_le_bytes());
    assert_mentions(
        &error_of(load_bytes("chunk.glb", &bytes)),
        &["first chunk claims 100000 bytes"],
    );
}

#[test]
fn every_truncation_and_byte_flip_of_a_glb_fails_cleanly_or_loads() {
    let whole = quad_glb();
    let dir = tempfile::tempdir().expect("tempdir");
    let path = dir.path().join("fuzz.glb");
    let attempt = |bytes: &[u8]| {
        std::fs::write(&path, bytes).expect("write");
        if let Err(e) = scene::gltf::load(&path) {
            assert!(!e.to_string().contains('\n'));
        }
    };
    for len in 0..whole.len() {
        attempt(&whole[..len]);
    }
    for i in 0..whole.len() {
        let mut bytes = whole.clone();
        bytes[i] ^= 0xA5;
        attempt(&bytes);
    }
}

#[test]
fn an_index_out_of_range_names_the_accessor_and_mesh() {
    let mut doc = Doc::default();
    let mesh = doc.mesh(&QUAD, &[0, 1, 2, 0, 2, 99], None);
    doc.instance(mesh);
    assert_mentions(
        &error_of(doc.load()),
        &["accessor 1 (indices of mesh 0 primitive 0): index 99 out of range for 4 vertices"],
    );
}

#[test]
fn nan_and_infinite_positions_are_refused() {
    for bad in [f32::NAN, f32::INFINITY, f32::NEG_INFINITY] {
        let mut doc = Doc::default();
        let mesh = doc.mesh(
            &[[0.0, 0.0, 0.0], [1.0, bad, 0.0], [0.0, 1.0, 0.0]],
            &[0, 1, 2],
            None,
        );
        doc.instance(mesh);
        let message = error_of(doc.load());
        assert_mentions(
            &message,
            &[
                "accessor 0 (POSITION of mesh 0 primitive 0)",
                "vertex 1",
                "non-finite",
            ],
        );
    }
}

#[test]
fn only_points_and_lines_is_a_scene_without_triangles() {
    let mut doc = quad_doc(None);
    doc.json["meshes"][0]["primitives"][0]["mode"] = json!(0);
    let result = doc.load();
    assert!(
        matches!(result, Err(SceneError::NoTriangles { .. })),
        "{result:?}"
    );
    assert_mentions(&error_of(result), &["no triangles", "point or line"]);
}

#[test]
fn degenerate_or_missing_geometry_is_a_scene_without_triangles() {
    let mut doc = Doc::default();
    let mesh = doc.mesh(
        &[[0.0; 3], [1.0, 0.0, 0.0], [2.0, 0.0, 0.0]],
        &[0, 1, 2],
        None,
    );
    doc.instance(mesh);
    assert!(matches!(doc.load(), Err(SceneError::NoTriangles { .. })));
    let empty = load_bytes("empty-scene.gltf", br#"{"asset":{"version":"2.0"}}"#);
    assert!(
        matches!(empty, Err(SceneError::NoTriangles { .. })),
        "{empty:?}"
    );
}

#[test]
fn an_unknown_required_extension_is_unsupported_and_named() {
    let result = {
        let mut doc = quad_doc(None);
        doc.json["extensionsRequired"] = json!(["KHR_draco_mesh_compression"]);
        doc.load()
    };
    assert!(
        matches!(result, Err(SceneError::Unsupported { .. })),
        "{result:?}"
    );
    assert_mentions(&error_of(result), &["KHR_draco_mesh_compression"]);
}

#[test]
fn a_gltf_1_file_is_unsupported() {
    assert_mentions(
        &error_after(|d| d.json["asset"]["version"] = json!("1.0")),
        &["version", "1.0"],
    );
    assert_mentions(
        &error_after(|d| d.json["asset"]["minVersion"] = json!("2.1")),
        &["2.1"],
    );
}

#[test]
fn accessors_views_and_buffers_past_their_containers_are_refused() {
    let accessor = error_after(|d| d.json["accessors"][0]["count"] = json!(1000));
    assert_mentions(
        &accessor,
        &[
            "accessor 0 (POSITION of mesh 0 primitive 0)",
            "overrun bufferView 0",
        ],
    );
    let huge = error_after(|d| d.json["accessors"][1]["count"] = json!(1u64 << 40));
    assert_mentions(&huge, &["accessor 1 (indices", "overrun"]);
    let view = error_after(|d| d.json["bufferViews"][0]["byteLength"] = json!(100_000));
    assert_mentions(&view, &["bufferView 0", "overruns buffer 0"]);
    let buffer = error_after(|d| {
        let declared = d.bin.len() + 1000;
        let mut json = d.json_for(Layout::DataUri, "");
        json["buffers"][0]["byteLength"] = json!(declared);
        d.json = json;
    });
    assert_mentions(&buffer, &["buffer 0", "byteLength"]);
}

#[test]
fn wrong_accessor_types_are_refused() {
    let float_indices = error_after(|d| d.json["accessors"][1]["componentType"] = json!(FLOAT));
    assert_mentions(
        &float_indices,
        &["accessor 1 (indices", "expected SCALAR", "FLOAT"],
    );
    let vec2_positions = error_after(|d| d.json["accessors"][0]["type"] = json!("VEC2"));
    assert_mentions(&vec2_positions, &["expected VEC3 of FLOAT, found VEC2"]);
    let bad_stride = error_after(|d| d.json["bufferViews"][0]["byteStride"] = json!(2));
    assert_mentions(&bad_stride, &["byteStride 2"]);
    // Sparse indices are unsigned integers, and their views hold `count` of them.
    let sparse = |indices_type: u32, count: usize| {
        error_after(|d| {
            d.json["accessors"][0]["sparse"] = json!({ "count": count,
                "indices": { "bufferView": 1, "componentType": indices_type },
                "values": { "bufferView": 0 } });
        })
    };
    assert_mentions(
        &sparse(FLOAT, 1),
        &["accessor 0 (POSITION", "sparse indices", "componentType"],
    );
    assert_mentions(
        &sparse(UNSIGNED_SHORT, 1000),
        &[
            "sparse indices: 1000 elements of 2 bytes",
            "overrun bufferView 1",
        ],
    );
    // TANGENT must be VEC4 of FLOAT, one per vertex (read where NORMAL is given).
    let with_tangent = |d: &mut Doc, ty: &str, count: usize| {
        let normal = d.vec3s(&[[0.0, 0.0, 1.0]; 4]);
        let tangent = d.accessor(&[0u8; 64], FLOAT, count, ty);
        let attributes = &mut d.json["meshes"][0]["primitives"][0]["attributes"];
        attributes["NORMAL"] = json!(normal);
        attributes["TANGENT"] = json!(tangent);
    };
    let vec3_tangents = error_after(|d| with_tangent(d, "VEC3", 4));
    assert_mentions(
        &vec3_tangents,
        &["TANGENT", "expected VEC4 of FLOAT, found VEC3"],
    );
    let few_tangents = error_after(|d| with_tangent(d, "VEC4", 3));
    assert_mentions(
        &few_tangents,
        &["TANGENT has 3 elements but POSITION has 4"],
    );
}

#[test]
fn dangling_references_are_refused() {
    type Edit = fn(&mut Doc);
    let cases: [(&str, Edit); 6] = [
        ("accessor 7", |d| {
            d.json["meshes"][0]["primitives"][0]["attributes"]["POSITION"] = json!(7)
        }),
        ("bufferView 9", |d| {
            d.json["accessors"][0]["bufferView"] = json!(9)
        }),
        ("mesh 4", |d| d.json["nodes"][0]["mesh"] = json!(4)),
        ("material 3", |d| {
            d.json["meshes"][0]["primitives"][0]["material"] = json!(3)
        }),
        ("scene 5", |d| d.json["scene"] = json!(5)),
        ("node 8", |d| d.json["scenes"][0]["nodes"] = json!([8])),
    ];
    for (what, edit) in cases {
        assert_mentions(&error_after(edit), &[what, "does not exist"]);
    }
    assert_mentions(
        &error_after(|d| d.json["meshes"][0]["primitives"][0]["mode"] = json!(9)),
        &["invalid mode"],
    );
}

#[test]
fn bad_buffer_uris_are_refused() {
    let cases = [
        (
            "data:application/octet-stream;base64,@@@@",
            "malformed base64",
        ),
        ("data:application/octet-stream", "malformed data URI"),
        ("data:text/plain,hello", "not base64"),
        ("https://example.com/scene.bin", "not supported"),
        ("/etc/scene.bin", "not a relative path"),
        ("scene%zz.bin", "percent escape"),
    ];
    for (uri, expected) in cases {
        let message = error_after(|d| {
            let mut json = d.json_for(Layout::DataUri, "");
            json["buffers"][0]["uri"] = json!(uri);
            d.json = json;
        });
        assert_mentions(&message, &["buffer 0", expected]);
    }
}

#[test]
fn a_missing_bin_names_the_file() {
    let doc = quad_doc(None);
    let dir = tempfile::tempdir().expect("tempdir");
    let path = doc.write(dir.path(), Layout::ExternalBin);
    std::fs::remove_file(dir.path().join("scene.bin")).expect("remove .bin");
    let result = scene::gltf::load(&path);
    assert!(matches!(result, Err(SceneError::Io { .. })), "{result:?}");
    assert_mentions(&error_of(result), &["scene.bin", "buffer 0"]);
}

#[test]
fn buffers_and_images_must_be_regular_files() {
    // Enough `..` to reach / from any temporary directory; /dev/zero would never end.
    let dev_zero = format!("{}dev/zero", "../".repeat(16));
    let buffer = error_after(|d| {
        let mut json = d.json_for(Layout::DataUri, "");
        json["buffers"][0]["uri"] = json!(dev_zero);
        d.json = json;
    });
    assert_mentions(&buffer, &["not a regular file", "buffer 0"]);
    let directory = error_after(|d| {
        let mut json = d.json_for(Layout::DataUri, "");
        json["buffers"][0]["uri"] = json!(".");
        d.json = json;
    });
    assert_mentions(&directory, &["not a regular file"]);
    let material = json!({ "pbrMetallicRoughness": { "baseColorTexture": { "index": 0 } } });
    let mut doc = quad_doc(Some(material));
    doc.push("images", json!({ "uri": dev_zero }));
    doc.push("textures", json!({ "source": 0 }));
    assert_mentions(&error_of(doc.load()), &["not a regular file", "image 0"]);
}

#[test]
fn node_cycles_and_shared_children_are_refused() {
    let cycle = error_after(|d| {
        d.json["nodes"] = json!([{ "mesh": 0 }, { "children": [2] }, { "children": [1] }]);
    });
    assert_mentions(&cycle, &["cycle through node"]);
    let own_child = error_after(|d| d.json["nodes"][0]["children"] = json!([0]));
    assert_mentions(&own_child, &["node 0: is its own child"]);
    let shared = error_after(|d| {
        d.json["nodes"] = json!([{ "mesh": 0, "children": [1] }, {}, { "children": [1] }]);
    });
    assert_mentions(&shared, &["node 2: child 1 already has parent node 0"]);
}

/// A chain of `depth` nodes, each translated by 0.001 along x, with the quad at the bottom;
/// `close_loop` makes the last node the parent of the first, closing a cycle.
fn chain(depth: usize, close_loop: bool) -> Doc {
    let mut doc = Doc::default();
    let mesh = doc.mesh(&QUAD, &QUAD_INDICES, None);
    let nodes: Vec<_> = (0..depth)
        .map(|i| match i + 1 {
            next if next < depth => json!({ "children": [next], "translation": [0.001, 0, 0] }),
            _ if close_loop => json!({ "children": [0] }),
            _ => json!({ "mesh": mesh }),
        })
        .collect();
    doc.json["nodes"] = json!(nodes);
    doc.add_root(0);
    doc
}

#[test]
fn a_hierarchy_100k_nodes_deep_loads_without_recursion() {
    const DEPTH: usize = 100_000;
    let scene = chain(DEPTH, false).load().expect("deep hierarchy loads");
    let x = scene.triangles[0].vertices[0].position.x;
    assert!((x - 0.001 * (DEPTH - 1) as f32).abs() < 0.5, "x = {x}");
    assert_mentions(
        &error_of(chain(DEPTH, true).load()),
        &["cycle through node"],
    );
}

#[test]
fn out_of_range_material_values_are_refused() {
    let cases = [
        (
            json!({ "pbrMetallicRoughness": { "baseColorFactor": [2, 0, 0, 1] } }),
            "baseColorFactor",
        ),
        (
            json!({ "pbrMetallicRoughness": { "metallicFactor": -0.5 } }),
            "metallicFactor",
        ),
        (
            json!({ "extensions": { "KHR_materials_ior": { "ior": 0.5 } } }),
            "ior 0.5",
        ),
        (
            json!({ "extensions": { "KHR_materials_emissive_strength": { "emissiveStrength": -1 } } }),
            "emissiveStrength",
        ),
        (
            json!({ "alphaMode": "MASK", "alphaCutoff": -0.5 }),
            "alphaCutoff",
        ),
        (json!({ "alphaMode": "SOMETIMES" }), "invalid alphaMode"),
    ];
    for (material, expected) in cases {
        let message = error_of(quad_doc(Some(material)).load());
        assert_mentions(&message, &[expected]);
    }
}

#[test]
fn an_undecodable_image_names_the_image() {
    let mut doc = quad_doc(Some(
        json!({ "pbrMetallicRoughness": { "baseColorTexture": { "index": 0 } } }),
    ));
    let view = doc.view(b"definitely not a PNG");
    doc.push(
        "images",
        json!({ "bufferView": view, "mimeType": "image/png" }),
    );
    doc.push("textures", json!({ "source": 0 }));
    assert_mentions(&error_of(doc.load()), &["image 0"]);
    doc.json["textures"][0] = json!({});
    assert_mentions(&error_of(doc.load()), &["texture 0", "image source"]);
}

#[test]
fn instancing_beyond_the_triangle_budget_is_refused_before_building() {
    // A strip of 65,534 triangles (one byte each) placed by 1,100 nodes: 72 million triangles.
    let mut doc = Doc::default();
    let position = doc.vec3s(&QUAD);
    let strip: Vec<u32> = (0..65_536).map(|i| [0, 1, 3, 2][i % 4]).collect();
    let indices = doc.indices(&strip, UNSIGNED_BYTE);
    let primitive =
        json!({ "attributes": { "POSITION": position }, "indices": indices, "mode": 5 });
    let mesh = doc.push("meshes", json!({ "primitives": [primitive] }));
    for _ in 0..1_100 {
        doc.instance(mesh);
    }
    let result = doc.load();
    assert!(
        matches!(result, Err(SceneError::Unsupported { .. })),
        "{:?}",
        result.map(|s| s.triangles.len())
    );
    assert_mentions(&error_of(result), &["would place 72087400 triangles"]);
}

#[test]
fn instancing_many_vertices_beyond_the_budget_is_refused_before_building() {
    // One triangle over 200,000 vertices, placed by 1,100 nodes: 220 million transforms.
    let mut doc = Doc::default();
    let position = doc.vec3s(&vec![[0.0, 0.0, 1.0]; 200_000]);
    let indices = doc.indices(&[0, 1, 2], UNSIGNED_BYTE);
    let primitive = json!({ "attributes": { "POSITION": position }, "indices": indices });
    let mesh = doc.push("meshes", json!({ "primitives": [primitive] }));
    for _ in 0..1_100 {
        doc.instance(mesh);
    }
    assert_mentions(&error_of(doc.load()), &["would place 220000000 vertices"]);
}
