//! glTF skins and morph targets, in the pose the file gives them: joints placed by their nodes,
//! targets blended by the node's or the mesh's weights; sparse accessors and accessors without
//! a buffer view.

use crate::gltf_support;

use glam::{Affine3A, Quat, Vec3};
use gltf_support::*;
use scene::Scene;
use serde_json::{Value, json};

const EPS: f32 = 1e-5;

/// One triangle facing +z.
const TRIANGLE: [[f32; 3]; 3] = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];

fn assert_close(a: Vec3, b: Vec3) {
    assert!(a.abs_diff_eq(b, EPS), "{a} != {b}");
}

fn floats(values: &[f32]) -> Vec<u8> {
    values.iter().flat_map(|x| x.to_le_bytes()).collect()
}

/// Column-major elements of `m`, as glTF stores a MAT4.
fn mat4(m: Affine3A) -> Vec<f32> {
    glam::Mat4::from(m).to_cols_array().to_vec()
}

/// How the skinned triangle's joints and weights are stored.
#[derive(Clone, Copy)]
enum Storage {
    /// JOINTS_0 of UNSIGNED_BYTE, WEIGHTS_0 of FLOAT.
    BytesAndFloats,
    /// JOINTS_0 of UNSIGNED_SHORT, WEIGHTS_0 of normalized UNSIGNED_BYTE (128 + 128 for the
    /// shared vertex: halves once normalised).
    ShortsAndNormalizedBytes,
}

/// The triangle skinned to two joints: vertex 0 to joint 0, vertex 1 to joint 1, vertex 2
/// half to each. Joint 0's node sits at (0, 0, 5); joint 1's, its child, 2 along x and turned
/// a quarter about x. Their inverse bind matrices undo the bind pose (joint 1 not turned), so
/// joint 0 leaves its vertices where they are and joint 1 turns its vertices a quarter about
/// the x-parallel line through its origin, (2, 0, 5). The skinned node's own translation (100
/// along x) must not apply. `joints` are the vertices' JOINTS_0 (four each, the first weighing
/// all but at the shared vertex); `edit` changes the document last.
fn skinned_triangle(storage: Storage, joints: [[u32; 4]; 3], edit: impl FnOnce(&mut Doc)) -> Doc {
    let mut doc = Doc::default();
    let position = doc.vec3s(&TRIANGLE);
    let normal = doc.vec3s(&[[0.0, 0.0, 1.0]; 3]);
    let (joints, weights) = match storage {
        Storage::BytesAndFloats => {
            let bytes: Vec<u8> = joints.iter().flatten().map(|&j| j as u8).collect();
            let weights = [1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.5, 0.5, 0.0, 0.0];
            let joints = doc.accessor(&bytes, UNSIGNED_BYTE, 3, "VEC4");
            (joints, doc.accessor(&floats(&weights), FLOAT, 3, "VEC4"))
        }
        Storage::ShortsAndNormalizedBytes => {
            let bytes: Vec<u8> = (joints.iter().flatten())
                .flat_map(|&j| (j as u16).to_le_bytes())
                .collect();
            let weights = [255, 0, 0, 0, 255, 0, 0, 0, 128, 128, 0, 0];
            let joints = doc.accessor(&bytes, UNSIGNED_SHORT, 3, "VEC4");
            let weights = doc.accessor(&weights, UNSIGNED_BYTE, 3, "VEC4");
            doc.json["accessors"][weights]["normalized"] = json!(true);
            (joints, weights)
        }
    };
    let primitive = json!({ "attributes": {
        "POSITION": position, "NORMAL": normal, "JOINTS_0": joints, "WEIGHTS_0": weights } });
    let mesh = doc.push("meshes", json!({ "primitives": [primitive] }));
    let skinned = doc.node(json!({ "mesh": mesh, "skin": 0, "translation": [100, 0, 0] }));
    let joint_0 = doc.node(json!({ "translation": [0, 0, 5], "children": [2] }));
    let quarter_turn_x = Quat::from_rotation_x(std::f32::consts::FRAC_PI_2);
    doc.node(json!({ "translation": [2, 0, 0], "rotation": quarter_turn_x.to_array() }));
    let bind_0 = Affine3A::from_translation(Vec3::new(0.0, 0.0, 5.0));
    let bind_1 = Affine3A::from_translation(Vec3::new(2.0, 0.0, 5.0));
    let inverse_binds = [mat4(bind_0.inverse()), mat4(bind_1.inverse())].concat();
    let inverse_binds = doc.accessor(&floats(&inverse_binds), FLOAT, 2, "MAT4");
    doc.push(
        "skins",
        json!({ "joints": [joint_0, joint_0 + 1], "inverseBindMatrices": inverse_binds }),
    );
    doc.add_root(skinned);
    doc.add_root(joint_0);
    edit(&mut doc);
    doc
}

const JOINTS: [[u32; 4]; 3] = [[0, 0, 0, 0], [1, 0, 0, 0], [0, 1, 0, 0]];

#[test]
fn a_skinned_mesh_is_drawn_where_its_joints_hold_it() {
    for storage in [Storage::BytesAndFloats, Storage::ShortsAndNormalizedBytes] {
        let scene = skinned_triangle(storage, JOINTS, |_| {})
            .load()
            .expect("loads");
        let [v0, v1, v2] = scene.triangles[0].vertices;
        // Joint 0 is where it was bound: vertex 0 stays.
        assert_close(v0.position, Vec3::ZERO);
        assert_close(v0.normal, Vec3::Z);
        // Joint 1 turns (1, 0, 0) about its origin (2, 0, 5): (−1, 0, −5) from it turns to
        // (−1, 5, 0); and the normal +z to −y.
        assert_close(v1.position, Vec3::new(1.0, 5.0, 5.0));
        assert_close(v1.normal, -Vec3::Y);
        // Half of each: (0, 1, 0) and (0, 5, 6); the normal half-way between +z and −y.
        assert_close(v2.position, Vec3::new(0.0, 3.0, 3.0));
        assert_close(v2.normal, Vec3::new(0.0, -1.0, 1.0).normalize());
    }
}

#[test]
fn a_skin_without_inverse_bind_matrices_places_vertices_by_the_joints_alone() {
    let doc = skinned_triangle(Storage::BytesAndFloats, JOINTS, |doc| {
        let skin = doc.json["skins"][0].as_object_mut().expect("skin");
        skin.remove("inverseBindMatrices");
    });
    let scene = doc.load().expect("loads");
    // Joint 0's world transform moves vertex 0 up by 5.
    assert_close(
        scene.triangles[0].vertices[0].position,
        Vec3::new(0.0, 0.0, 5.0),
    );
}

/// The triangle with one morph target moving vertex 2 by (0, 0, 2), stored by `target`,
/// shown by two nodes: node 0 at the origin without weights (the mesh's 0.5 apply), node 1
/// at x = 10 with its own weight 1.
fn morphed_triangle(target: impl FnOnce(&mut Doc) -> usize) -> Scene {
    let mut doc = Doc::default();
    let position = doc.vec3s(&TRIANGLE);
    let displacement = target(&mut doc);
    let primitive = json!({ "attributes": { "POSITION": position },
        "targets": [{ "POSITION": displacement }] });
    let mesh = doc.push(
        "meshes",
        json!({ "primitives": [primitive], "weights": [0.5] }),
    );
    let plain = doc.node(json!({ "mesh": mesh }));
    let weighted = doc.node(json!({ "mesh": mesh, "translation": [10, 0, 0], "weights": [1.0] }));
    doc.add_root(plain);
    doc.add_root(weighted);
    doc.load().expect("loads")
}

fn assert_morphed(scene: &Scene) {
    assert_eq!(scene.triangles.len(), 2);
    let (plain, weighted) = (&scene.triangles[0], &scene.triangles[1]);
    assert_close(plain.vertices[2].position, Vec3::new(0.0, 1.0, 1.0));
    assert_close(weighted.vertices[2].position, Vec3::new(10.0, 1.0, 2.0));
    // The vertices the target does not move stay, and the tilted triangle's normals follow
    // its placed shape (none given: smoothed from the positions).
    assert_close(weighted.vertices[0].position, Vec3::new(10.0, 0.0, 0.0));
    assert_close(
        plain.vertices[0].normal,
        Vec3::new(0.0, -1.0, 1.0).normalize(),
    );
}

#[test]
fn morph_targets_blend_by_the_node_s_weights_else_the_mesh_s() {
    assert_morphed(&morphed_triangle(|doc| {
        doc.vec3s(&[[0.0; 3], [0.0; 3], [0.0, 0.0, 2.0]])
    }));
}

/// A sparse VEC3 accessor of 3 elements without a buffer view (zeros), element 2 replaced by
/// (0, 0, 2): as Blender writes a morph target moving few vertices.
fn sparse_displacement(doc: &mut Doc, index: u8) -> Value {
    let indices = doc.view(&[index]);
    let values = doc.view(&floats(&[0.0, 0.0, 2.0]));
    json!({ "componentType": FLOAT, "count": 3, "type": "VEC3",
        "sparse": { "count": 1,
            "indices": { "bufferView": indices, "componentType": UNSIGNED_BYTE },
            "values": { "bufferView": values } } })
}

#[test]
fn sparse_accessors_replace_the_elements_they_name() {
    assert_morphed(&morphed_triangle(|doc| {
        let accessor = sparse_displacement(doc, 2);
        doc.push("accessors", accessor)
    }));
    // Over a buffer view: the base elements stay where the sparse part names none.
    let scene = morphed_triangle(|doc| {
        let base = doc.vec3s(&[[0.0, 0.0, 4.0], [0.0; 3], [9.0; 3]]);
        let accessor = sparse_displacement(doc, 2);
        doc.json["accessors"][base]["sparse"] = accessor["sparse"].clone();
        base
    });
    assert_close(
        scene.triangles[0].vertices[0].position,
        Vec3::new(0.0, 0.0, 2.0),
    );
    assert_close(
        scene.triangles[0].vertices[2].position,
        Vec3::new(0.0, 1.0, 1.0),
    );
}

#[test]
fn bad_skins_and_sparse_accessors_are_refused_in_one_line() {
    let mut joints = JOINTS;
    joints[1][0] = 5;
    let doc = skinned_triangle(Storage::BytesAndFloats, joints, |_| {});
    assert_mentions(
        &error_of(doc.load()),
        &["mesh 0 primitive 0 names joint 5 of skin 0, which has 2 joints"],
    );
    // A joint of zero weight may name anything.
    let mut joints = JOINTS;
    joints[0][3] = 200;
    let doc = skinned_triangle(Storage::BytesAndFloats, joints, |_| {});
    assert!(doc.load().is_ok());
    let doc = skinned_triangle(Storage::BytesAndFloats, JOINTS, |doc| {
        doc.json["skins"][0]["joints"] = json!([1, 2, 1]);
    });
    assert_mentions(
        &error_of(doc.load()),
        &["skin 0", "2 inverse bind matrices for 3 joints"],
    );
    let doc = skinned_triangle(Storage::BytesAndFloats, JOINTS, |doc| {
        doc.json["skins"][0]["joints"] = json!([1, 9]);
    });
    assert_mentions(
        &error_of(doc.load()),
        &["skin 0", "joint node 9 does not exist"],
    );
    let doc = skinned_triangle(Storage::BytesAndFloats, JOINTS, |doc| {
        doc.json["nodes"][0]["skin"] = json!(3);
    });
    assert_mentions(&error_of(doc.load()), &["node 0: skin 3 does not exist"]);
    let mut doc = Doc::default();
    let position = doc.vec3s(&TRIANGLE);
    let accessor = sparse_displacement(&mut doc, 7);
    let displacement = doc.push("accessors", accessor);
    let primitive = json!({ "attributes": { "POSITION": position },
        "targets": [{ "POSITION": displacement }] });
    let mesh = doc.push("meshes", json!({ "primitives": [primitive] }));
    doc.instance(mesh);
    assert_mentions(
        &error_of(doc.load()),
        &[
            "morph target 0 POSITION",
            "sparse index 7 out of range for 3",
        ],
    );
}
