//! glTF cameras: placement by their nodes, order, selection, orthographic ones skipped.

use crate::gltf_support;

use glam::Vec3;
use gltf_support::*;
use serde_json::json;

const EPS: f32 = 1e-5;

fn perspective(yfov: f32) -> serde_json::Value {
    json!({ "type": "perspective", "perspective": { "yfov": yfov, "aspectRatio": 1.5, "znear": 0.1 } })
}

#[test]
fn a_perspective_camera_takes_its_nodes_position_and_orientation() {
    let mut doc = quad_doc(None);
    let camera = doc.push("cameras", perspective(0.8));
    // A quarter turn about +y turns the camera's -z view direction to -x.
    let s = std::f32::consts::FRAC_1_SQRT_2;
    let node = doc.node(json!({
        "camera": camera, "translation": [0, 1, 5], "rotation": [0, s, 0, s], "name": "eye",
    }));
    doc.add_root(node);
    let scene = doc.load().expect("loads");
    let c = scene.camera(None).expect("a camera");
    assert!(
        c.eye.abs_diff_eq(Vec3::new(0.0, 1.0, 5.0), EPS),
        "{}",
        c.eye
    );
    assert!(c.forward.abs_diff_eq(Vec3::NEG_X, EPS), "{}", c.forward);
    assert!(c.up.abs_diff_eq(Vec3::Y, EPS), "{}", c.up);
    assert_eq!((c.yfov, c.aspect_ratio), (0.8, Some(1.5)));
    assert_eq!(c.name, "eye");
}

#[test]
fn cameras_come_in_node_traversal_order_and_are_selectable() {
    let mut doc = quad_doc(None);
    let wide = doc.push("cameras", perspective(1.2));
    let narrow = doc.push("cameras", perspective(0.3));
    // Root (narrow camera) → child (wide camera, offset by its parent): pre-order.
    let child = doc.node(json!({ "camera": wide, "translation": [0, 0, 1] }));
    let parent =
        doc.node(json!({ "camera": narrow, "translation": [0, 0, 10], "children": [child] }));
    doc.add_root(parent);
    let scene = doc.load().expect("loads");
    assert_eq!(scene.cameras.len(), 2);
    let first = scene.camera(Some(0)).expect("camera 0");
    let second = scene.camera(Some(1)).expect("camera 1");
    assert_eq!((first.yfov, second.yfov), (0.3, 1.2));
    assert!(second.eye.abs_diff_eq(Vec3::new(0.0, 0.0, 11.0), EPS));
    assert!(scene.camera(Some(2)).is_none());
}

#[test]
fn a_scaled_parent_leaves_a_unit_camera_frame() {
    let mut doc = quad_doc(None);
    let camera = doc.push("cameras", perspective(0.5));
    let child = doc.node(json!({ "camera": camera }));
    let parent = doc.node(json!({ "scale": [3, 0.5, 2], "children": [child] }));
    doc.add_root(parent);
    let c = doc.load().expect("loads").camera(None).expect("a camera");
    assert!((c.forward.length() - 1.0).abs() < EPS && (c.up.length() - 1.0).abs() < EPS);
    assert!(c.forward.abs_diff_eq(Vec3::NEG_Z, EPS));
}

#[test]
fn orthographic_cameras_are_skipped_with_a_warning() {
    let mut doc = quad_doc(None);
    let ortho = json!({ "type": "orthographic", "orthographic": { "xmag": 1, "ymag": 1, "znear": 0, "zfar": 10 } });
    let camera = doc.push("cameras", ortho);
    let node = doc.node(json!({ "camera": camera }));
    doc.add_root(node);
    let scene = doc.load().expect("loads");
    assert!(scene.cameras.is_empty());
    assert!(
        scene.warnings.iter().any(|w| w.contains("orthographic")),
        "{:?}",
        scene.warnings
    );
}

#[test]
fn a_field_of_view_out_of_range_is_an_error() {
    for yfov in [0.0, -1.0, 3.2] {
        let mut doc = quad_doc(None);
        let camera = doc.push("cameras", perspective(yfov));
        let node = doc.node(json!({ "camera": camera }));
        doc.add_root(node);
        assert_mentions(&error_of(doc.load()), &["camera 0", "yfov"]);
    }
}
