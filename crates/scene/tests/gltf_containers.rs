//! glTF containers: data URIs, external `.bin`, `.glb`, and the shipped Cornell box.

use crate::gltf_support;

use gltf_support::*;
use scene::{Scene, Surface};
use serde_json::json;

fn sample_doc() -> Doc {
    let mut doc = quad_doc(Some(json!({ "emissiveFactor": [1, 1, 1] })));
    let camera = doc.push(
        "cameras",
        json!({ "type": "perspective", "perspective": { "yfov": 0.7, "znear": 0.1 } }),
    );
    let node = doc.node(json!({ "camera": camera, "translation": [0, 0, 3] }));
    doc.add_root(node);
    doc
}

fn summary(scene: &Scene) -> (Vec<scene::Triangle>, usize, usize, usize) {
    (
        scene.triangles.clone(),
        scene.materials.len(),
        scene.cameras.len(),
        scene.lights.triangles.len(),
    )
}

#[test]
fn gltf_with_data_uri_with_bin_and_glb_load_the_same_scene() {
    let doc = sample_doc();
    let reference = summary(&doc.load_as(Layout::DataUri).expect("data URI"));
    assert_eq!(reference.0.len(), 2);
    for layout in [Layout::ExternalBin, Layout::Glb] {
        assert_eq!(
            summary(&doc.load_as(layout).expect("loads")),
            reference,
            "{layout:?}"
        );
    }
}

#[test]
fn both_buffer_media_types_are_accepted() {
    use base64::Engine;
    let doc = sample_doc();
    let data = base64::engine::general_purpose::STANDARD.encode(&doc.bin);
    for media_type in ["application/octet-stream", "application/gltf-buffer"] {
        let mut doc = sample_doc();
        doc.json["buffers"] = json!([{ "byteLength": doc.bin.len(), "uri": format!("data:{media_type};base64,{data}") }]);
        assert_eq!(
            doc.load().expect("loads").triangles.len(),
            2,
            "{media_type}"
        );
    }
}

#[test]
fn a_gltf_file_that_is_really_a_glb_is_read_as_one() {
    let doc = sample_doc();
    let json = serde_json::to_vec(&doc.json_for(Layout::Glb, "")).expect("JSON");
    let scene = load_bytes("misnamed.gltf", &glb(&json, &doc.bin)).expect("loads");
    assert_eq!(scene.triangles.len(), 2);
}

#[test]
fn a_glb_json_chunk_padded_with_zeros_is_accepted() {
    let doc = sample_doc();
    let mut json = serde_json::to_vec(&doc.json_for(Layout::Glb, "")).expect("JSON");
    json.extend_from_slice(&[0; 7]);
    let scene = load_bytes("zeros.glb", &glb(&json, &doc.bin)).expect("loads");
    assert_eq!(scene.triangles.len(), 2);
}

#[test]
fn extras_objects_and_unknown_properties_are_ignored() {
    let mut doc = sample_doc();
    let extras = json!({ "blender": { "custom": [1, { "deep": [[[]]] }] } });
    for object in [
        "asset",
        "/nodes/0",
        "/meshes/0",
        "/materials/0",
        "/accessors/0",
    ] {
        let target = match object {
            "asset" => &mut doc.json["asset"],
            pointer => doc.json.pointer_mut(pointer).expect("object exists"),
        };
        target["extras"] = extras.clone();
        target["someFutureProperty"] = json!([1, 2, 3]);
    }
    assert_eq!(doc.load().expect("loads").triangles.len(), 2);
}

#[test]
fn an_unused_buffer_is_never_opened() {
    let mut doc = sample_doc();
    let dir = tempfile::tempdir().expect("tempdir");
    let mut json = doc.json_for(Layout::ExternalBin, "scene.bin");
    json["buffers"]
        .as_array_mut()
        .expect("buffers")
        .push(json!({ "byteLength": 64, "uri": "animations.bin" }));
    doc.json = json;
    let scene = scene::gltf::load(&doc.write(dir.path(), Layout::ExternalBin)).expect("loads");
    assert_eq!(scene.triangles.len(), 2);
}

#[test]
fn the_cornell_metal_scene_loads_with_its_light_camera_and_mirrors() {
    // A benchmark scene of the shared folder, absent from a clean clone.
    let Some(path) = scene::testing::shared_scene("cornell-metal/cornell-metal.gltf") else {
        return;
    };
    let scene = scene::load(&path).expect("cornell-metal loads");
    assert_eq!(scene.triangles.len(), 36);
    assert_eq!(scene.cameras.len(), 1);
    assert!(!scene.lights.triangles.is_empty(), "has an emissive light");
    assert!(scene.lights.total_power_scalar() > 0.0);
    assert!(scene.materials.iter().any(|m| m.surface == Surface::Mirror));
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
}
