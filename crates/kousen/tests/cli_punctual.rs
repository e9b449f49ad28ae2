//! Scenes lit by glTF `KHR_lights_punctual` lights, through the command line: a quad lit by a
//! point light alone renders (a scene needs a light, not an emissive surface), `kousen info`
//! counts the lights by kind, and the path integrator, which cannot sample them, says so.

mod common;

use common::*;
use serde_json::{Value, json};

/// The unit quad lit only by a point light 0.5 above its centre, seen from straight above.
fn point_lit_quad(dir: &std::path::Path) -> std::path::PathBuf {
    let lights = json!({
        "extensionsUsed": ["KHR_lights_punctual"],
        "extensions": {"KHR_lights_punctual": {"lights": [{"type": "point", "intensity": 2.0}]}},
    });
    let mut document: Value =
        serde_json::from_slice(&gltf(&QUAD, Some(&QUAD_INDICES), 4, lights)).unwrap();
    let nodes = document["nodes"].as_array_mut().unwrap();
    nodes.push(json!({
        "translation": [0.5, 0.5, 0.5],
        "extensions": {"KHR_lights_punctual": {"light": 0}},
    }));
    // A camera 1 above the centre looking down (−z of the node is −y of the world).
    nodes.push(json!({
        "camera": 0,
        "translation": [0.5, 1.0, 0.5],
        "rotation": [-std::f32::consts::FRAC_1_SQRT_2, 0.0, 0.0, std::f32::consts::FRAC_1_SQRT_2],
    }));
    document["scenes"][0]["nodes"] = json!([0, 1, 2]);
    document["cameras"] =
        json!([{"type": "perspective", "perspective": {"yfov": 0.6, "znear": 0.01}}]);
    write(dir, "point.gltf", &serde_json::to_vec(&document).unwrap())
}

#[test]
fn a_point_light_alone_lights_a_scene() {
    let dir = tempfile::tempdir().unwrap();
    let scene = point_lit_quad(dir.path());
    let out = dir.path().join("point.pfm");
    let output = kousen_quiet(&[
        "render",
        scene.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
        "--width",
        "16",
        "--passes",
        "8",
        "--backend",
        "cpu",
    ]);
    assert!(
        output.status.success(),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    // The central 4×4 pixels see the quad within 0.08 of the point under the light: there
    // L = ρ/π · I·h/r³ with the default material's ρ = 1, I = 2, h = 0.5: 8/π ≈ 2.55 at the
    // centre, 2.4 at the block's corners. 8 passes: within 30%.
    let centre = mean_red(&std::fs::read(&out).unwrap(), 16, 6..10);
    assert!(
        (1.7..3.3).contains(&centre),
        "centre radiance {centre}, expected about 2.5"
    );
}

/// Mean red channel of the `range` × `range` block of a `side`² PFM (little-endian floats).
fn mean_red(pfm: &[u8], side: usize, range: std::ops::Range<usize>) -> f32 {
    let header = format!("PF\n{side} {side}\n-1.0\n");
    assert!(pfm.starts_with(header.as_bytes()), "not a {side}² PFM");
    let floats: Vec<f32> = pfm[header.len()..]
        .chunks_exact(4)
        .map(|b| f32::from_le_bytes(b.try_into().unwrap()))
        .collect();
    assert_eq!(floats.len(), 3 * side * side);
    let mut sum = 0.0;
    for y in range.clone() {
        for x in range.clone() {
            sum += floats[3 * (y * side + x)];
        }
    }
    sum / (range.len() * range.len()) as f32
}

#[test]
fn info_counts_punctual_lights_by_kind() {
    let scene = shipped("cornell-spot.gltf");
    let output = kousen(&["info", &scene, "--json"]);
    assert!(output.status.success());
    let info: Value = serde_json::from_slice(&output.stdout).expect("JSON");
    assert_eq!(
        info["punctual_lights"],
        json!({"point": 0, "spot": 1, "directional": 0})
    );
    assert_eq!(info["emissive_triangles"], json!(2));
}

#[test]
fn the_path_integrator_refuses_punctual_lights() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("spot.png");
    let scene = shipped("cornell-spot.gltf");
    let output = kousen(&[
        "render",
        &scene,
        "-o",
        out.to_str().unwrap(),
        "--integrator",
        "path",
        "--backend",
        "cpu",
    ]);
    assert_clean_error(&output, "punctual");
    assert!(!out.exists(), "an image was written");
}
