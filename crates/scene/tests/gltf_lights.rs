//! glTF lights (`KHR_lights_punctual`): placement by their nodes, kinds, intensity, cones,
//! `range` ignored with a warning, and bad input refused with a one-line error.

use crate::gltf_support;

use std::f32::consts::{FRAC_1_SQRT_2, FRAC_PI_2, FRAC_PI_4};

use glam::Vec3;
use gltf_support::*;
use scene::{PunctualKind, PunctualLight, Scene};
use serde_json::{Value, json};

const EPS: f32 = 1e-5;

/// [`quad_doc`] with `lights` in the document's `KHR_lights_punctual` extension.
fn lights_doc(lights: Value) -> Doc {
    let mut doc = quad_doc(None);
    doc.json["extensionsUsed"] = json!(["KHR_lights_punctual"]);
    doc.json["extensions"] = json!({ "KHR_lights_punctual": { "lights": lights } });
    doc
}

/// A root node carrying light `light`, with the rest of the node's properties from `node`.
fn add_light_node(doc: &mut Doc, light: usize, mut node: Value) -> usize {
    node["extensions"] = json!({ "KHR_lights_punctual": { "light": light } });
    let index = doc.node(node);
    doc.add_root(index);
    index
}

/// The document of one light, `light`, on a node with the properties of `node`.
fn one_light(light: Value, node: Value) -> Doc {
    let mut doc = lights_doc(json!([light]));
    add_light_node(&mut doc, 0, node);
    doc
}

/// The scene's punctual lights as loaded.
fn lights_of(scene: &Scene) -> Vec<PunctualLight> {
    scene.lights.punctual.iter().map(|e| e.light).collect()
}

fn spot_cosines(light: &PunctualLight) -> (f32, f32) {
    match light.kind {
        PunctualKind::Spot {
            cos_inner,
            cos_outer,
            falloff,
        } => {
            assert_eq!(falloff, scene::SpotFalloff::Gltf, "glTF's falloff");
            (cos_inner, cos_outer)
        }
        other => panic!("not a spot light: {other:?}"),
    }
}

#[test]
fn a_point_light_sits_at_its_nodes_world_origin() {
    let light = json!({ "type": "point", "color": [1.0, 0.5, 0.25], "intensity": 8.0 });
    // The light's node is a child, so its position combines both translations.
    let mut doc = lights_doc(json!([light]));
    let child = doc.node(json!({
        "extensions": { "KHR_lights_punctual": { "light": 0 } }, "translation": [0, 0, 1],
    }));
    let parent = doc.node(json!({ "translation": [1, 2, 3], "children": [child] }));
    doc.add_root(parent);
    let scene = doc.load().expect("loads");
    assert_eq!(scene.lights.punctual.len(), 1);
    let l = lights_of(&scene)[0];
    assert_eq!(l.kind, PunctualKind::Point);
    assert!(
        l.position.abs_diff_eq(Vec3::new(1.0, 2.0, 4.0), EPS),
        "{}",
        l.position
    );
    assert!(
        l.intensity.abs_diff_eq(Vec3::new(8.0, 4.0, 2.0), EPS),
        "{}",
        l.intensity
    );
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
}

#[test]
fn colour_and_intensity_default_to_one() {
    let scene = one_light(json!({ "type": "point" }), json!({}))
        .load()
        .expect("loads");
    assert_eq!(lights_of(&scene)[0].intensity, Vec3::ONE);
}

#[test]
fn a_spot_light_shines_down_its_nodes_rotated_negative_z() {
    // A quarter turn about +x turns -z into +y.
    let light = json!({
        "type": "spot", "intensity": 2.0, "spot": { "innerConeAngle": 0.2, "outerConeAngle": 0.6 },
    });
    let node =
        json!({ "translation": [0, -3, 0], "rotation": [FRAC_1_SQRT_2, 0, 0, FRAC_1_SQRT_2] });
    let scene = one_light(light, node).load().expect("loads");
    let l = lights_of(&scene)[0];
    assert!(l.direction.abs_diff_eq(Vec3::Y, EPS), "{}", l.direction);
    assert!(l.position.abs_diff_eq(Vec3::new(0.0, -3.0, 0.0), EPS));
    assert_eq!(l.intensity, Vec3::splat(2.0));
    let (cos_inner, cos_outer) = spot_cosines(&l);
    assert!((cos_inner - 0.2f32.cos()).abs() < EPS, "{cos_inner}");
    assert!((cos_outer - 0.6f32.cos()).abs() < EPS, "{cos_outer}");
}

#[test]
fn spot_cone_angles_take_the_specs_defaults() {
    let scene = one_light(json!({ "type": "spot", "spot": {} }), json!({}))
        .load()
        .expect("loads");
    let (cos_inner, cos_outer) = spot_cosines(&lights_of(&scene)[0]);
    assert_eq!(cos_inner, 1.0);
    assert!((cos_outer - FRAC_PI_4.cos()).abs() < EPS, "{cos_outer}");
}

#[test]
fn a_spot_may_open_to_a_half_space() {
    let light = json!({ "type": "spot", "spot": { "outerConeAngle": FRAC_PI_2 } });
    let scene = one_light(light, json!({})).load().expect("loads");
    let (cos_inner, cos_outer) = spot_cosines(&lights_of(&scene)[0]);
    assert_eq!((cos_inner, cos_outer), (1.0, 0.0));
}

#[test]
fn a_needle_thin_spot_still_loads() {
    // Both cosines round to 1 in f32; the cone keeps outer < inner all the same.
    let light = json!({ "type": "spot", "spot": { "outerConeAngle": 1e-4 } });
    let scene = one_light(light, json!({})).load().expect("loads");
    let (cos_inner, cos_outer) = spot_cosines(&lights_of(&scene)[0]);
    assert!(
        cos_outer < cos_inner && cos_inner == 1.0,
        "{cos_inner} {cos_outer}"
    );
}

#[test]
fn a_directional_light_keeps_its_direction_and_lux() {
    // A quarter turn about +y turns -z into -x; the scale does not change the direction.
    let light = json!({ "type": "directional", "color": [0.5, 1.0, 1.0], "intensity": 3.0 });
    let node = json!({ "rotation": [0, FRAC_1_SQRT_2, 0, FRAC_1_SQRT_2], "scale": [4, 4, 4] });
    let scene = one_light(light, node).load().expect("loads");
    let l = lights_of(&scene)[0];
    assert_eq!(l.kind, PunctualKind::Directional);
    assert!(l.direction.abs_diff_eq(Vec3::NEG_X, EPS), "{}", l.direction);
    assert!(l.intensity.abs_diff_eq(Vec3::new(1.5, 3.0, 3.0), EPS));
    let emitter = &scene.lights.punctual[0];
    assert!(emitter.radius > 0.0 && emitter.power.max_element() > 0.0);
}

#[test]
fn lights_may_be_shared_by_nodes_and_come_in_traversal_order() {
    let mut doc = lights_doc(json!([
        { "type": "point", "intensity": 1.0 },
        { "type": "directional", "intensity": 2.0 },
    ]));
    add_light_node(&mut doc, 1, json!({}));
    add_light_node(&mut doc, 0, json!({ "translation": [0, 0, 1] }));
    add_light_node(&mut doc, 0, json!({ "translation": [0, 0, 2] }));
    let scene = doc.load().expect("loads");
    let lights = lights_of(&scene);
    let kinds: Vec<PunctualKind> = lights.iter().map(|l| l.kind).collect();
    assert_eq!(
        kinds,
        [
            PunctualKind::Directional,
            PunctualKind::Point,
            PunctualKind::Point
        ]
    );
    assert_eq!(lights[2].position, Vec3::new(0.0, 0.0, 2.0));
}

#[test]
fn lights_of_zero_intensity_are_dropped() {
    let scene = one_light(json!({ "type": "point", "intensity": 0.0 }), json!({}))
        .load()
        .expect("loads");
    assert!(scene.lights.punctual.is_empty());
}

#[test]
fn the_extension_may_be_required() {
    let mut doc = one_light(json!({ "type": "point" }), json!({}));
    doc.json["extensionsRequired"] = json!(["KHR_lights_punctual"]);
    let scene = doc.load().expect("loads");
    assert_eq!(scene.lights.punctual.len(), 1);
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
}

#[test]
fn lights_load_from_every_container() {
    for layout in [Layout::DataUri, Layout::ExternalBin, Layout::Glb] {
        let scene = one_light(
            json!({ "type": "point" }),
            json!({ "translation": [0, 1, 0] }),
        )
        .load_as(layout)
        .expect("loads");
        assert_eq!(scene.lights.punctual.len(), 1, "{layout:?}");
    }
}

#[test]
fn range_is_ignored_with_one_warning() {
    let mut doc = lights_doc(json!([
        { "type": "point", "range": 5.0 },
        { "type": "spot", "range": 2.0, "spot": {} },
    ]));
    add_light_node(&mut doc, 0, json!({}));
    add_light_node(&mut doc, 1, json!({}));
    add_light_node(&mut doc, 0, json!({}));
    let scene = doc.load().expect("loads");
    assert_eq!(scene.lights.punctual.len(), 3);
    let warnings: Vec<&String> = scene
        .warnings
        .iter()
        .filter(|w| w.contains("range"))
        .collect();
    assert_eq!(warnings.len(), 1, "{:?}", scene.warnings);
}

#[test]
fn a_zero_scale_skips_directed_lights_with_a_warning() {
    let mut doc = lights_doc(json!([
        { "type": "spot", "spot": {} },
        { "type": "directional" },
        { "type": "point" },
    ]));
    for light in 0..3 {
        add_light_node(&mut doc, light, json!({ "scale": [0, 0, 0] }));
    }
    let scene = doc.load().expect("loads");
    // The point light needs no direction.
    let kinds: Vec<PunctualKind> = lights_of(&scene).iter().map(|l| l.kind).collect();
    assert_eq!(kinds, [PunctualKind::Point]);
    let skipped = scene.warnings.iter().filter(|w| w.contains("skipped"));
    assert_eq!(skipped.count(), 2, "{:?}", scene.warnings);
}

/// Loading a document of one light, `light`, fails with a message mentioning `parts`.
fn assert_refused(light: Value, parts: &[&str]) {
    let message = error_of(one_light(light.clone(), json!({})).load());
    assert_mentions(&message, parts);
    assert_mentions(&message, &["light 0", "node 1"]);
}

#[test]
fn a_negative_or_non_finite_intensity_is_an_error() {
    assert_refused(
        json!({ "type": "point", "intensity": -1.0 }),
        &["intensity", "-1"],
    );
    // 1e39 overflows f32 to infinity.
    assert_refused(
        json!({ "type": "directional", "intensity": 1e39 }),
        &["intensity", "inf"],
    );
}

#[test]
fn a_colour_outside_zero_to_one_is_an_error() {
    assert_refused(
        json!({ "type": "point", "color": [1.0, 1.5, 0.0] }),
        &["color", "green", "1.5"],
    );
    assert_refused(
        json!({ "type": "point", "color": [-0.1, 0.0, 0.0] }),
        &["color", "red"],
    );
}

#[test]
fn spot_cone_angles_out_of_order_or_range_are_errors() {
    for (inner, outer) in [(0.5, 0.5), (0.6, 0.5), (-0.1, 0.5), (0.1, 1.6)] {
        let light = json!({
            "type": "spot", "spot": { "innerConeAngle": inner, "outerConeAngle": outer },
        });
        assert_refused(light, &["cone angles", "inner", "outer"]);
    }
    // The default outer angle, π/4, is below a given inner one.
    assert_refused(
        json!({ "type": "spot", "spot": { "innerConeAngle": 1.0 } }),
        &["cone angles"],
    );
}

#[test]
fn a_spot_light_without_spot_properties_is_an_error() {
    assert_refused(json!({ "type": "spot" }), &["spot properties"]);
}

#[test]
fn an_unknown_light_type_is_an_error() {
    assert_refused(json!({ "type": "area" }), &["invalid type"]);
}

#[test]
fn a_missing_light_is_an_error() {
    let mut doc = lights_doc(json!([{ "type": "point" }]));
    add_light_node(&mut doc, 3, json!({}));
    assert_mentions(
        &error_of(doc.load()),
        &["node 1", "light 3 does not exist", "1 lights"],
    );
    // A node referring to a light in a document without the extension's lights.
    let mut doc = quad_doc(None);
    add_light_node(&mut doc, 0, json!({}));
    assert_mentions(
        &error_of(doc.load()),
        &["node 1", "light 0 does not exist", "0 lights"],
    );
}

#[test]
fn a_light_pushed_to_infinity_is_an_error() {
    // Each scale is finite, their product is not.
    let mut doc = lights_doc(json!([{ "type": "point" }]));
    let child = doc.node(json!({
        "extensions": { "KHR_lights_punctual": { "light": 0 } }, "translation": [0, 0, 1e30],
    }));
    let parent = doc.node(json!({ "scale": [1e30, 1e30, 1e30], "children": [child] }));
    doc.add_root(parent);
    assert_mentions(&error_of(doc.load()), &["light 0 (node 1)", "position"]);
}
