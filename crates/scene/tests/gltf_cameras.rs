//! glTF cameras: placement by their nodes, order, selection, perspective and orthographic.

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

fn orthographic(xmag: f32, ymag: f32) -> serde_json::Value {
    json!({ "type": "orthographic",
        "orthographic": { "xmag": xmag, "ymag": ymag, "znear": 0, "zfar": 10 } })
}

#[test]
fn an_orthographic_camera_keeps_its_film_size_and_its_nodes_frame() {
    let mut doc = quad_doc(None);
    let camera = doc.push("cameras", orthographic(3.0, 2.0));
    // Scaled and turned a quarter about +y: the view turns to −x, the film keeps its size.
    let s = std::f32::consts::FRAC_1_SQRT_2;
    let node = doc.node(json!({
        "camera": camera, "translation": [0, 1, 5], "rotation": [0, s, 0, s], "scale": [4, 4, 4],
    }));
    doc.add_root(node);
    let scene = doc.load().expect("loads");
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
    let c = scene.camera(None).expect("a camera");
    assert_eq!(
        c.projection,
        scene::Projection::Orthographic { half_height: 2.0 }
    );
    assert_eq!(c.aspect_ratio, Some(1.5));
    assert!(c.eye.abs_diff_eq(Vec3::new(0.0, 1.0, 5.0), EPS));
    assert!(c.forward.abs_diff_eq(Vec3::NEG_X, EPS));
    // Its rays leave the film, 2 above and 3 to the right of the eye at the corner, along
    // the view.
    let (origin, direction) = c.ray(1.0, 1.0, 1.5);
    assert!(direction.abs_diff_eq(Vec3::NEG_X, EPS));
    assert!(
        origin.abs_diff_eq(c.eye + 3.0 * c.right() + 2.0 * c.up, EPS),
        "{origin}"
    );
    for (xmag, ymag) in [(0.0, 1.0), (1.0, -2.0)] {
        let mut doc = quad_doc(None);
        let camera = doc.push("cameras", orthographic(xmag, ymag));
        let node = doc.node(json!({ "camera": camera }));
        doc.add_root(node);
        assert_mentions(
            &error_of(doc.load()),
            &["camera 0", "xmag", "must be finite and > 0"],
        );
    }
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
