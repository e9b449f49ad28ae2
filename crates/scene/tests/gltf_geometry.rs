//! glTF geometry: transforms, winding, normals, index types, topologies, texture coordinates.

use crate::gltf_support;

use glam::{Vec2, Vec3, Vec4};
use gltf_support::*;
use scene::{Scene, Triangle};
use serde_json::json;

const EPS: f32 = 1e-5;

fn positions(scene: &Scene) -> Vec<Vec3> {
    scene.triangles.iter().flat_map(|t| t.positions()).collect()
}

fn assert_close(a: Vec3, b: Vec3) {
    assert!(a.abs_diff_eq(b, EPS), "{a} != {b}");
}

/// One triangle shown by a chain of nodes, outermost first; returns the loaded scene.
fn triangle_under(
    nodes: &[serde_json::Value],
    positions: &[[f32; 3]],
    normals: Option<&[[f32; 3]]>,
) -> Scene {
    let mut doc = Doc::default();
    let position = doc.vec3s(positions);
    let mut primitive = json!({ "attributes": { "POSITION": position } });
    if let Some(n) = normals {
        primitive["attributes"]["NORMAL"] = json!(doc.vec3s(n));
    }
    let mesh = doc.push("meshes", json!({ "primitives": [primitive] }));
    let count = nodes.len();
    for (i, node) in nodes.iter().enumerate() {
        let mut node = node.clone();
        if i + 1 < count {
            node["children"] = json!([i + 1]);
        } else {
            node["mesh"] = json!(mesh);
        }
        doc.node(node);
    }
    doc.add_root(0);
    doc.load().expect("loads")
}

const TRIANGLE: [[f32; 3]; 3] = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];

#[test]
fn node_matrix_places_positions() {
    // Column-major: scale 2 along x, translate (1, 2, 3).
    let matrix = json!([2, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 1, 2, 3, 1]);
    let scene = triangle_under(&[json!({ "matrix": matrix })], &TRIANGLE, None);
    let p = positions(&scene);
    assert_close(p[0], Vec3::new(1.0, 2.0, 3.0));
    assert_close(p[1], Vec3::new(3.0, 2.0, 3.0));
    assert_close(p[2], Vec3::new(1.0, 3.0, 3.0));
}

#[test]
fn nested_trs_nodes_compose_parent_first() {
    let quarter_turn_z = [
        0.0,
        0.0,
        std::f32::consts::FRAC_1_SQRT_2,
        std::f32::consts::FRAC_1_SQRT_2,
    ];
    let nodes = [
        json!({ "translation": [10, 0, 0] }),
        json!({ "rotation": quarter_turn_z }),
        json!({ "scale": [3, 3, 3] }),
    ];
    let scene = triangle_under(&nodes, &TRIANGLE, None);
    let p = positions(&scene);
    // x → 3x → rotated onto +y → shifted by 10 in x.
    assert_close(p[0], Vec3::new(10.0, 0.0, 0.0));
    assert_close(p[1], Vec3::new(10.0, 3.0, 0.0));
    assert_close(p[2], Vec3::new(7.0, 0.0, 0.0));
    assert_close(scene.triangles[0].vertices[0].normal, Vec3::Z);
}

#[test]
fn non_uniform_scale_transforms_normals_by_the_inverse_transpose() {
    let slanted = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    let n = 1.0 / 3f32.sqrt();
    let normals = [[n, n, n]; 3];
    let scene = triangle_under(&[json!({ "scale": [2, 1, 1] })], &slanted, Some(&normals));
    // The plane through (2,0,0), (0,1,0), (0,0,1) has normal ∝ (1/2, 1, 1).
    let expected = Vec3::new(1.0, 2.0, 2.0) / 3.0;
    for v in scene.triangles[0].vertices {
        assert_close(v.normal, expected);
    }
    let geometric = scene.triangles[0]
        .geometric_normal_unnormalized()
        .normalize();
    assert_close(geometric, expected);
}

#[test]
fn mirroring_scale_keeps_the_front_face() {
    let normals = [[0.0, 0.0, 1.0]; 3];
    let scene = triangle_under(&[json!({ "scale": [-1, 1, 1] })], &TRIANGLE, Some(&normals));
    let t = scene.triangles[0];
    let mut xs: Vec<f32> = t.positions().iter().map(|p| p.x).collect();
    xs.sort_by(f32::total_cmp);
    assert_eq!(xs, [-1.0, 0.0, 0.0]);
    // Front face still +z: the winding was flipped to match the normals.
    assert!(t.geometric_normal_unnormalized().z > 0.0);
    for v in t.vertices {
        assert_close(v.normal, Vec3::Z);
    }
}

#[test]
fn missing_normals_become_area_weighted_smooth_normals() {
    // Two triangles sharing the edge (0,0,0)-(1,0,0): one facing +z (area 1/2), one facing
    // +y (area 1), so the shared corners get (0, 2, 1)/√5.
    let mut doc = Doc::default();
    let corners = [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, 0.0, 2.0],
    ];
    let mesh = doc.mesh(&corners, &[0, 1, 2, 0, 3, 1], None);
    doc.instance(mesh);
    let scene = doc.load().expect("loads");
    let shared = Vec3::new(0.0, 2.0, 1.0) / 5f32.sqrt();
    let [a, b, c] = scene.triangles[0].vertices;
    assert_close(a.normal, shared);
    assert_close(b.normal, shared);
    assert_close(c.normal, Vec3::Z);
    assert_close(scene.triangles[1].vertices[1].normal, Vec3::Y);
}

fn quad_with_indices(component_type: Option<u32>) -> Scene {
    let mut doc = Doc::default();
    let (position, indices) = match component_type {
        Some(ct) => (doc.vec3s(&QUAD), Some(doc.indices(&QUAD_INDICES, ct))),
        None => (doc.vec3s(&QUAD_INDICES.map(|i| QUAD[i as usize])), None),
    };
    let mut primitive = json!({ "attributes": { "POSITION": position } });
    if let Some(i) = indices {
        primitive["indices"] = json!(i);
    }
    let mesh = doc.push("meshes", json!({ "primitives": [primitive] }));
    doc.instance(mesh);
    doc.load().expect("loads")
}

#[test]
fn u8_u16_u32_and_no_indices_give_the_same_triangles() {
    let reference = positions(&quad_with_indices(None));
    assert_eq!(reference.len(), 6);
    for ct in [UNSIGNED_BYTE, UNSIGNED_SHORT, UNSIGNED_INT] {
        assert_eq!(
            positions(&quad_with_indices(Some(ct))),
            reference,
            "componentType {ct}"
        );
    }
}

fn quad_with_mode(mode: u32, indices: &[u32]) -> Vec<Triangle> {
    let mut doc = Doc::default();
    let position = doc.vec3s(&QUAD);
    let indices = doc.indices(indices, UNSIGNED_BYTE);
    let primitive =
        json!({ "attributes": { "POSITION": position }, "indices": indices, "mode": mode });
    let mesh = doc.push("meshes", json!({ "primitives": [primitive] }));
    doc.instance(mesh);
    doc.load().expect("loads").triangles
}

#[test]
fn strips_and_fans_become_front_facing_triangles() {
    const STRIP: u32 = 5;
    const FAN: u32 = 6;
    for (mode, indices) in [(STRIP, [0, 1, 3, 2]), (FAN, [0, 1, 2, 3])] {
        let triangles = quad_with_mode(mode, &indices);
        assert_eq!(triangles.len(), 2, "mode {mode}");
        let area: f32 = triangles.iter().map(Triangle::area).sum();
        assert!((area - 1.0).abs() < EPS, "mode {mode}: area {area}");
        for t in &triangles {
            assert!(t.geometric_normal_unnormalized().z > 0.0, "mode {mode}");
        }
    }
}

#[test]
fn texcoords_read_float_and_normalized_integers() {
    let mut doc = Doc::default();
    let position = doc.vec3s(&TRIANGLE);
    let floats = doc.vec2s(&[[0.25, 0.5], [1.0, 0.0], [0.0, 1.0]]);
    let bytes = doc.accessor(&[255, 0, 51, 255, 0, 0], UNSIGNED_BYTE, 3, "VEC2");
    let shorts: Vec<u8> = [65535u16, 0, 0, 65535, 0, 0]
        .iter()
        .flat_map(|s| s.to_le_bytes())
        .collect();
    let shorts = doc.accessor(&shorts, UNSIGNED_SHORT, 3, "VEC2");
    for accessor in [bytes, shorts] {
        doc.json["accessors"][accessor]["normalized"] = json!(true);
    }
    for uv in [floats, bytes, shorts] {
        let primitive = json!({ "attributes": { "POSITION": position, "TEXCOORD_0": uv } });
        let mesh = doc.push("meshes", json!({ "primitives": [primitive] }));
        doc.instance(mesh);
    }
    let scene = doc.load().expect("loads");
    let first_uvs: Vec<Vec2> = scene.triangles.iter().map(|t| t.vertices[0].uv).collect();
    assert!(first_uvs[0].abs_diff_eq(Vec2::new(0.25, 0.5), EPS));
    assert!(first_uvs[1].abs_diff_eq(Vec2::new(1.0, 0.0), EPS));
    assert!(first_uvs[2].abs_diff_eq(Vec2::new(1.0, 0.0), EPS));
    assert!(
        scene.triangles[1].vertices[1]
            .uv
            .abs_diff_eq(Vec2::new(0.2, 1.0), EPS)
    );
}

#[test]
fn a_mesh_used_by_two_nodes_is_placed_twice() {
    let mut doc = Doc::default();
    let mesh = doc.mesh(&TRIANGLE, &[0, 1, 2], None);
    doc.instance(mesh);
    let moved = doc.node(json!({ "mesh": mesh, "translation": [0, 0, 5] }));
    doc.add_root(moved);
    let scene = doc.load().expect("loads");
    assert_eq!(scene.triangles.len(), 2);
    assert_close(
        scene.triangles[1].vertices[0].position,
        Vec3::new(0.0, 0.0, 5.0),
    );
    assert_eq!(scene.materials.len(), 1, "one default material");
}

#[test]
fn the_scene_property_chooses_which_scene_is_drawn() {
    let mut doc = Doc::default();
    let small = doc.mesh(&TRIANGLE, &[0, 1, 2], None);
    let big = doc.mesh(&QUAD, &QUAD_INDICES, None);
    let a = doc.node(json!({ "mesh": small }));
    let b = doc.node(json!({ "mesh": big }));
    doc.json["scenes"] = json!([{ "nodes": [a] }, { "nodes": [b] }]);
    assert_eq!(
        doc.load().expect("loads").triangles.len(),
        1,
        "first scene by default"
    );
    doc.json["scene"] = json!(1);
    assert_eq!(doc.load().expect("loads").triangles.len(), 2);
    doc.json.as_object_mut().expect("object").remove("scenes");
    doc.json.as_object_mut().expect("object").remove("scene");
    assert_eq!(
        doc.load().expect("loads").triangles.len(),
        3,
        "no scenes: every root"
    );
}

#[test]
fn points_and_lines_are_skipped_with_a_warning() {
    let mut doc = quad_doc(None);
    let position = doc.vec3s(&TRIANGLE);
    let lines = json!({ "attributes": { "POSITION": position }, "mode": 1 });
    let mesh = doc.push("meshes", json!({ "primitives": [lines] }));
    doc.instance(mesh);
    let scene = doc.load().expect("loads");
    assert_eq!(scene.triangles.len(), 2);
    assert!(
        scene.warnings.iter().any(|w| w.contains("point or line")),
        "{:?}",
        scene.warnings
    );
}

/// A quantized triangle (`KHR_mesh_quantization`): positions as SHORT integers, scaled back by
/// the node (as gltfpack writes them), normals as normalized BYTE (−127 is −1), texture
/// coordinates as normalized UNSIGNED_SHORT; padded to 4-byte strides. It loads as the float
/// triangle; without the extension declared, the integer positions are an error naming what
/// is allowed.
#[test]
fn quantized_attributes_load_as_their_floats() {
    const BYTE: u32 = 5120;
    const SHORT: u32 = 5122;
    let quantized = |declared: bool| {
        let mut doc = Doc::default();
        // (0, 0, 0), (1, 0, 0), (0, 1, 0) at 1/1000 a step, each element 8 bytes apart.
        let positions: Vec<u8> = [[0i16, 0, 0], [1000, 0, 0], [0, 1000, 0]]
            .iter()
            .flat_map(|p| p.iter().flat_map(|c| c.to_le_bytes()).chain([0, 0]))
            .collect();
        let view = doc.view(&positions);
        doc.json["bufferViews"][view]["byteStride"] = json!(8);
        let position = doc.push(
            "accessors",
            json!({ "bufferView": view, "componentType": SHORT, "count": 3, "type": "VEC3",
                    "min": [0, 0, 0], "max": [1000, 1000, 0] }),
        );
        // Normal (0, 0, −1): bytes (0, 0, −127) and one of padding each.
        let normals: Vec<u8> = (0..3).flat_map(|_| [0u8, 0, (-127i8) as u8, 0]).collect();
        let view = doc.view(&normals);
        doc.json["bufferViews"][view]["byteStride"] = json!(4);
        let normal = doc.push(
            "accessors",
            json!({ "bufferView": view, "componentType": BYTE, "normalized": true,
                    "count": 3, "type": "VEC3" }),
        );
        let uvs: Vec<u8> = [[0u16, 0], [65535, 0], [0, 32768]]
            .iter()
            .flat_map(|uv| uv.iter().flat_map(|c| c.to_le_bytes()))
            .collect();
        let view = doc.view(&uvs);
        let uv = doc.push(
            "accessors",
            json!({ "bufferView": view, "componentType": UNSIGNED_SHORT,
                    "normalized": true, "count": 3, "type": "VEC2" }),
        );
        let primitive =
            json!({ "attributes": { "POSITION": position, "NORMAL": normal, "TEXCOORD_0": uv } });
        let mesh = doc.push("meshes", json!({ "primitives": [primitive] }));
        let node = doc.node(json!({ "mesh": mesh, "scale": [0.001, 0.001, 0.001] }));
        doc.add_root(node);
        if declared {
            doc.json["extensionsUsed"] = json!(["KHR_mesh_quantization"]);
            doc.json["extensionsRequired"] = json!(["KHR_mesh_quantization"]);
        }
        doc.load()
    };
    let scene = quantized(true).expect("loads");
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
    let triangle = &scene.triangles[0];
    for (v, p) in triangle.vertices.iter().zip(TRIANGLE) {
        assert_close(v.position, Vec3::from(p));
        assert_close(v.normal, Vec3::NEG_Z);
    }
    let uvs: Vec<Vec2> = triangle.vertices.iter().map(|v| v.uv).collect();
    assert!(uvs[1].abs_diff_eq(Vec2::new(1.0, 0.0), EPS), "{uvs:?}");
    assert!(
        uvs[2].abs_diff_eq(Vec2::new(0.0, 32768.0 / 65535.0), EPS),
        "{uvs:?}"
    );
    let message = error_of(quantized(false));
    assert_mentions(&message, &["POSITION", "VEC3 of FLOAT", "SHORT"]);
}

/// `EXT_mesh_gpu_instancing`: a node draws its mesh once per instance, each instance's T·R·S
/// applied in the node's space before the node's own transform; missing attributes are the
/// identity's; attributes of different lengths are an error; the extension may be required.
#[test]
fn gpu_instances_place_copies_of_the_mesh() {
    let instanced = |translations: &[[f32; 3]], with_rotation_and_scale: bool| {
        let mut doc = Doc::default();
        let position = doc.vec3s(&TRIANGLE);
        let mesh = doc.push(
            "meshes",
            json!({ "primitives": [{ "attributes": { "POSITION": position } }] }),
        );
        let translation = doc.vec3s(translations);
        let mut attributes = json!({ "TRANSLATION": translation });
        if with_rotation_and_scale {
            // Instance 2 turned 90° about z, instance 1 scaled by 2.
            let h = std::f32::consts::FRAC_1_SQRT_2;
            let rotations: Vec<u8> = [[0.0, 0.0, 0.0, 1.0], [0.0, 0.0, 0.0, 1.0], [0.0, 0.0, h, h]]
                .iter()
                .flatten()
                .flat_map(|x: &f32| x.to_le_bytes())
                .collect();
            attributes["ROTATION"] = json!(doc.accessor(&rotations, FLOAT, 3, "VEC4"));
            attributes["SCALE"] = json!(doc.vec3s(&[[1.0; 3], [2.0; 3], [1.0; 3]]));
        }
        let node = doc.node(json!({
            "mesh": mesh,
            "translation": [10.0, 0.0, 0.0],
            "extensions": { "EXT_mesh_gpu_instancing": { "attributes": attributes } },
        }));
        doc.add_root(node);
        doc.json["extensionsUsed"] = json!(["EXT_mesh_gpu_instancing"]);
        doc.json["extensionsRequired"] = json!(["EXT_mesh_gpu_instancing"]);
        doc.load()
    };
    let scene = instanced(&[[0.0; 3], [2.0, 0.0, 0.0], [0.0, 0.0, 5.0]], true).expect("loads");
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
    assert_eq!(scene.triangles.len(), 3);
    let mut placed = positions(&scene);
    placed.sort_by(|a, b| a.to_array().partial_cmp(&b.to_array()).unwrap());
    let mut expected: Vec<Vec3> = [
        // Instance 0: the triangle moved by the node.
        [[10.0, 0.0, 0.0], [11.0, 0.0, 0.0], [10.0, 1.0, 0.0]],
        // Instance 1: scaled by 2, moved by 2, then by the node.
        [[12.0, 0.0, 0.0], [14.0, 0.0, 0.0], [12.0, 2.0, 0.0]],
        // Instance 2: turned 90° about z (x → y, y → −x), moved by 5 in z, then by the node.
        [[10.0, 0.0, 5.0], [10.0, 1.0, 5.0], [9.0, 0.0, 5.0]],
    ]
    .iter()
    .flatten()
    .map(|p| Vec3::from(*p))
    .collect();
    expected.sort_by(|a, b| a.to_array().partial_cmp(&b.to_array()).unwrap());
    for (a, b) in placed.iter().zip(&expected) {
        assert_close(*a, *b);
    }
    let translated_only = instanced(&[[0.0; 3], [0.0, 3.0, 0.0]], false).expect("loads");
    assert_eq!(translated_only.triangles.len(), 2);
    // Two translations against three rotations and scales.
    let message = error_of(instanced(&[[0.0; 3], [1.0, 0.0, 0.0]], true));
    assert_mentions(&message, &["EXT_mesh_gpu_instancing", "2", "3"]);
}

/// [`TRIANGLE`] with these TANGENTs (and NORMAL +z where `with_normals`) under `node`.
fn tangent_triangle(
    mut node: serde_json::Value,
    with_normals: bool,
    tangents: &[[f32; 4]],
) -> Scene {
    let mut doc = Doc::default();
    let position = doc.vec3s(&TRIANGLE);
    let bytes: Vec<u8> = tangents
        .iter()
        .flatten()
        .flat_map(|x| x.to_le_bytes())
        .collect();
    let tangent = doc.accessor(&bytes, FLOAT, tangents.len(), "VEC4");
    let mut primitive = json!({ "attributes": { "POSITION": position, "TANGENT": tangent } });
    if with_normals {
        primitive["attributes"]["NORMAL"] = json!(doc.vec3s(&[[0.0, 0.0, 1.0]; 3]));
    }
    node["mesh"] = json!(doc.push("meshes", json!({ "primitives": [primitive] })));
    doc.node(node);
    doc.add_root(0);
    doc.load().expect("loads")
}

/// The tangent of the vertex at `position`.
fn tangent_at(scene: &Scene, position: Vec3) -> Vec4 {
    let vertex = scene.triangles[0]
        .vertices
        .into_iter()
        .find(|v| (v.position - position).length() < 1e-6)
        .expect("a vertex there");
    vertex.tangent
}

fn assert_close4(a: Vec4, b: Vec4) {
    assert!((a - b).length() < 1e-5, "{a} vs {b}");
}

#[test]
fn tangents_follow_the_node_and_a_mirror_turns_their_handedness() {
    let tangents = [
        [2.0, 0.0, 0.0, 1.0],
        [0.0, 1.0, 0.0, -1.0],
        [1.0, 1.0, 0.0, 1.0],
    ];
    let diagonal = std::f32::consts::FRAC_1_SQRT_2;
    // A quarter turn about +z: +x to +y, +y to −x; unit, handedness kept.
    let s = diagonal;
    let turned = tangent_triangle(json!({ "rotation": [0.0, 0.0, s, s] }), true, &tangents);
    assert_close4(
        tangent_at(&turned, Vec3::ZERO),
        Vec4::new(0.0, 1.0, 0.0, 1.0),
    );
    assert_close4(
        tangent_at(&turned, Vec3::Y),
        Vec4::new(-1.0, 0.0, 0.0, -1.0),
    );
    let third = Vec4::new(-diagonal, diagonal, 0.0, 1.0);
    assert_close4(tangent_at(&turned, -Vec3::X), third);
    // Mirrored in x: directions mirrored, handedness turned, so that w · normal × tangent is
    // still the mirror image of the file's bitangent.
    let mirrored = tangent_triangle(json!({ "scale": [-1, 1, 1] }), true, &tangents);
    let first = tangent_at(&mirrored, Vec3::ZERO);
    assert_close4(first, Vec4::new(-1.0, 0.0, 0.0, -1.0));
    let normal = mirrored.triangles[0].vertices[0].normal;
    let bitangent = normal.cross(first.truncate()) * first.w;
    // The file's bitangent at that vertex: +z × +x = +y, which the mirror keeps.
    assert!((bitangent - Vec3::Y).length() < 1e-5, "{bitangent}");
    assert_close4(
        tangent_at(&mirrored, -Vec3::X),
        Vec4::new(0.0, 1.0, 0.0, 1.0),
    );
    // Without NORMAL glTF says to ignore them.
    let ignored = tangent_triangle(json!({}), false, &tangents);
    assert!(
        ignored.triangles[0]
            .vertices
            .iter()
            .all(|v| v.tangent == Vec4::ZERO)
    );
    assert!(!ignored.has_vertex_tangents() && turned.has_vertex_tangents());
}
