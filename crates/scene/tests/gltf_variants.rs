//! glTF material variants (`KHR_materials_variants`): a primitive wears the material its
//! mapping gives the chosen variant, else its own.

use crate::gltf_support;

use gltf_support::*;
use scene::{LoadOptions, Scene, SceneError};
use serde_json::json;

/// The quad in material 0 ("plain"), mapped to material 1 ("red") in variants 0 and 2 and to
/// material 2 ("blue") in variant 1, of variants "red", "blue" and "crimson"; variant 3
/// ("bare") maps nothing.
fn dressed_quad() -> Doc {
    let mut doc = quad_doc(None);
    for (name, colour) in [
        ("plain", [1.0, 1.0, 1.0]),
        ("red", [1.0, 0.0, 0.0]),
        ("blue", [0.0, 0.0, 1.0]),
    ] {
        doc.material(json!({ "name": name,
            "pbrMetallicRoughness": { "baseColorFactor": [colour[0], colour[1], colour[2], 1.0] } }));
    }
    doc.json["meshes"][0]["primitives"][0]["material"] = json!(0);
    doc.json["meshes"][0]["primitives"][0]["extensions"] = json!({ "KHR_materials_variants": {
        "mappings": [{ "material": 1, "variants": [0, 2] }, { "material": 2, "variants": [1] }] } });
    doc.json["extensionsUsed"] = json!(["KHR_materials_variants"]);
    doc.json["extensions"] = json!({ "KHR_materials_variants": { "variants": [
        { "name": "red" }, { "name": "blue" }, { "name": "crimson" }, { "name": "bare" }] } });
    doc
}

fn load_variant(doc: &Doc, variant: Option<&str>) -> Result<Scene, SceneError> {
    let dir = tempfile::tempdir().expect("tempdir");
    let options = LoadOptions {
        variant: variant.map(str::to_owned),
        ..LoadOptions::default()
    };
    scene::gltf::load_with(&doc.write(dir.path(), Layout::DataUri), &options)
}

/// The name of the material the quad's first triangle wears.
fn worn(scene: &Scene) -> &str {
    &scene.materials[scene.triangles[0].material as usize].name
}

#[test]
fn a_primitive_wears_what_the_chosen_variant_maps_it_to() {
    let doc = dressed_quad();
    let plain = load_variant(&doc, None).unwrap();
    assert_eq!(worn(&plain), "plain");
    assert_eq!(plain.variants, ["red", "blue", "crimson", "bare"]);
    assert!(plain.warnings.is_empty(), "{:?}", plain.warnings);
    assert_eq!(worn(&load_variant(&doc, Some("blue")).unwrap()), "blue");
    assert_eq!(worn(&load_variant(&doc, Some("2")).unwrap()), "red");
    assert_eq!(worn(&load_variant(&doc, Some("bare")).unwrap()), "plain");
    let dressed_in = |variant: &str| LoadOptions {
        variant: Some(variant.to_owned()),
        ..LoadOptions::default()
    };
    assert_eq!(dressed_in("crimson").variant_index(&plain), Some(2));
    assert_eq!(dressed_in("3").variant_index(&plain), Some(3));
    assert_eq!(dressed_in("green").variant_index(&plain), None);
    assert_eq!(LoadOptions::default().variant_index(&plain), None);
    assert_mentions(
        &error_of(load_variant(&doc, Some("green"))),
        &["no material variant \"green\" (the file has 0 \"red\", 1 \"blue\""],
    );
    assert_mentions(
        &error_of(load_variant(&quad_doc(None), Some("red"))),
        &["no material variant \"red\": the file has none"],
    );
    let mut broken = dressed_quad();
    broken.json["meshes"][0]["primitives"][0]["extensions"]["KHR_materials_variants"]["mappings"]
        [1]["material"] = json!(9);
    assert_mentions(
        &error_of(load_variant(&broken, Some("blue"))),
        &["material 9 does not exist"],
    );
}
