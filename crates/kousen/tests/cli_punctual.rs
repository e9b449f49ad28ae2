//! Scenes lit by glTF `KHR_lights_punctual` lights, through the command line: a quad lit by a
//! point light alone renders (a scene needs a light, not an emissive surface), `kousen info`
//! counts the lights by kind, and the path integrator samples them too.

use crate::common;

use common::*;
use serde_json::{Value, json};

/// The unit quad seen from straight above by a camera 1 above its centre, with `lights`
/// (`KHR_lights_punctual` lights, placed by `light_nodes`) as its only lights.
fn quad_scene(
    dir: &std::path::Path,
    name: &str,
    lights: Vec<Value>,
    light_nodes: Vec<Value>,
) -> std::path::PathBuf {
    let mut extra = json!({
        "cameras": [{"type": "perspective", "perspective": {"yfov": 0.6, "znear": 0.01}}],
    });
    if !lights.is_empty() {
        extra["extensionsUsed"] = json!(["KHR_lights_punctual"]);
        extra["extensions"] = json!({"KHR_lights_punctual": {"lights": lights}});
    }
    let mut document: Value =
        serde_json::from_slice(&gltf(&QUAD, Some(&QUAD_INDICES), 4, extra)).unwrap();
    let nodes = document["nodes"].as_array_mut().unwrap();
    // The camera's −z is the world's −y.
    nodes.push(json!({
        "camera": 0,
        "translation": [0.5, 1.0, 0.5],
        "rotation": [-std::f32::consts::FRAC_1_SQRT_2, 0.0, 0.0, std::f32::consts::FRAC_1_SQRT_2],
    }));
    nodes.extend(light_nodes);
    let count = nodes.len();
    document["scenes"][0]["nodes"] = json!((0..count).collect::<Vec<_>>());
    write(dir, name, &serde_json::to_vec(&document).unwrap())
}

/// The quad with a point light of intensity 2 at 0.5 above its centre as its only light.
fn point_lit_quad(dir: &std::path::Path) -> std::path::PathBuf {
    quad_scene(
        dir,
        "point.gltf",
        vec![json!({"type": "point", "intensity": 2.0})],
        vec![json!({
            "translation": [0.5, 0.5, 0.5],
            "extensions": {"KHR_lights_punctual": {"light": 0}},
        })],
    )
}

#[test]
fn a_point_light_alone_lights_a_scene() {
    let dir = tempfile::tempdir().unwrap();
    let scene = point_lit_quad(dir.path());
    let out = dir.path().join("point.pfm");
    let output = render_small(&scene, &out, &[]);
    // The central 4×4 pixels see the quad within 0.08 of the point under the light: there
    // L = ρ/π · I·h/r³ with the default material's ρ = 0.8, I = 2, h = 0.5: 6.4/π ≈ 2.04 at
    // the centre, 1.90 at the block's corners. 8 passes: within 30%.
    let centre = block_radiance(&output, &out, 6..10);
    assert!(
        (1.4..2.6).contains(&centre),
        "centre radiance {centre}, expected about 2"
    );
}

/// After a successful render of a 16² PFM to `out`: the mean red of its `range`² block.
fn block_radiance(
    output: &std::process::Output,
    out: &std::path::Path,
    range: std::ops::Range<usize>,
) -> f32 {
    assert_succeeded(output);
    mean_red(&std::fs::read(out).unwrap(), 16, range)
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
    let output = succeeded(kousen(&["info", &scene, "--json"]));
    let info: Value = serde_json::from_slice(&output.stdout).expect("JSON");
    assert_eq!(
        info["punctual_lights"],
        json!({"point": 0, "spot": 1, "directional": 0})
    );
    assert_eq!(info["emissive_triangles"], json!(2));
}

/// The path integrator samples punctual lights as SPPM does: the point-lit quad of
/// [`a_point_light_alone_lights_a_scene`] through it. One light sample per pixel and pass is
/// the whole of that light (the quad is lit once, and a point light's sample is exact), so
/// the central block's mean lies within the closed form's range over it (see
/// [`a_point_light_alone_lights_a_scene`]): 2.04 at its centre, 1.90 at its corners.
#[test]
fn the_path_integrator_samples_punctual_lights() {
    let dir = tempfile::tempdir().unwrap();
    let scene = point_lit_quad(dir.path());
    let out = dir.path().join("point-path.pfm");
    let output = render_small(&scene, &out, &["--integrator", "path"]);
    let centre = block_radiance(&output, &out, 6..10);
    assert!(
        (1.89..2.05).contains(&centre),
        "centre radiance {centre}, expected 1.90-2.04"
    );
}

#[test]
fn sun_lights_a_scene_without_lights() {
    let dir = tempfile::tempdir().unwrap();
    let scene = quad_scene(dir.path(), "dark.gltf", vec![], vec![]);
    let render = |out: &std::path::Path, sun: &[&str]| render_small(&scene, out, sun);
    let unlit = dir.path().join("unlit.pfm");
    assert_clean_error(&render(&unlit, &[]), "--sun");
    assert!(!unlit.exists());
    let zero = dir.path().join("zero.pfm");
    assert_clean_error(&render(&zero, &["--sun", "0,0,0"]), "--sun");
    assert!(!zero.exists());

    // Straight down with illuminance 2: L = ρ/π · E = 1.6/π ≈ 0.51 everywhere on the quad
    // (the default material's ρ = 0.8).
    let out = dir.path().join("sun.pfm");
    let output = render(&out, &["--sun", "0,-1,0", "--sun-illuminance", "2"]);
    let centre = block_radiance(&output, &out, 4..12);
    assert!(
        (0.45..0.57).contains(&centre),
        "radiance {centre}, expected about 0.51"
    );
}

#[test]
fn sky_lights_a_scene_without_lights() {
    let dir = tempfile::tempdir().unwrap();
    let scene = quad_scene(dir.path(), "dark.gltf", vec![], vec![]);
    let black = dir.path().join("black.pfm");
    assert_clean_error(&render_small(&scene, &black, &["--sky", "0,0,0"]), "--sky");
    assert!(!black.exists());
    // A white sky of radiance 1 over the quad (default material, ρ = 0.8): L = ρ·1 = 0.8.
    let out = dir.path().join("sky.pfm");
    let output = render_small(&scene, &out, &["--sky", "1,1,1"]);
    let centre = block_radiance(&output, &out, 4..12);
    assert!(
        (0.7..0.9).contains(&centre),
        "radiance {centre}, expected about 0.8"
    );
}

/// A `width` × `height` portable float map of one colour (rows bottom to top, little-endian).
fn uniform_pfm(colour: [f32; 3], width: usize, height: usize) -> Vec<u8> {
    let mut bytes = format!("PF\n{width} {height}\n-1.0\n").into_bytes();
    for _ in 0..width * height {
        for c in colour {
            bytes.extend_from_slice(&c.to_le_bytes());
        }
    }
    bytes
}

/// `--sky-map`: a uniform map of radiance 1 lights the quad as `--sky 1,1,1` does (L = ρ =
/// 0.8), read from .pfm or Radiance .hdr; `--sky` scales it; bad maps are one-line errors
/// that write nothing.
#[test]
fn a_sky_map_lights_a_scene_without_lights() {
    let dir = tempfile::tempdir().unwrap();
    let scene = quad_scene(dir.path(), "dark.gltf", vec![], vec![]);
    let pfm = write(dir.path(), "white.pfm", &uniform_pfm([1.0; 3], 16, 8));
    let mut hdr_bytes = Vec::new();
    image::codecs::hdr::HdrEncoder::new(&mut hdr_bytes)
        .encode(&vec![image::Rgb([1.0f32; 3]); 16 * 8], 16, 8)
        .unwrap();
    let hdr = write(dir.path(), "white.hdr", &hdr_bytes);
    for (map, scale, expected) in [
        (&pfm, "1,1,1", 0.8),
        (&hdr, "1,1,1", 0.8),
        (&pfm, "2,2,2", 1.6),
    ] {
        let out = dir.path().join("mapped.pfm");
        let map = map.to_str().unwrap();
        let output = render_small(
            &scene,
            &out,
            &["--sky-map", map, "--sky", scale, "--sky-rotate", "-30"],
        );
        let centre = block_radiance(&output, &out, 4..12);
        assert!(
            (0.875 * expected..1.125 * expected).contains(&centre),
            "{map} × {scale}: radiance {centre}, expected about {expected}"
        );
    }
    let black = write(dir.path(), "black.pfm", &uniform_pfm([0.0; 3], 4, 2));
    let negative = write(
        dir.path(),
        "negative.pfm",
        &uniform_pfm([1.0, -1.0, 1.0], 4, 2),
    );
    let text = write(dir.path(), "notes.txt", b"not an image");
    let truncated = write(dir.path(), "cut.pfm", &uniform_pfm([1.0; 3], 4, 2)[..30]);
    let missing = dir.path().join("missing.hdr");
    for (map, needle) in [
        (&black, "black"),
        (&negative, "finite and ≥ 0"),
        (&text, "unknown sky map extension"),
        (&truncated, "cut.pfm"),
        (&missing, "missing.hdr"),
    ] {
        let out = dir.path().join("never.pfm");
        let output = render_small(&scene, &out, &["--sky-map", map.to_str().unwrap()]);
        assert_clean_error(&output, needle);
        assert!(!out.exists(), "{needle}: an image was written");
    }
    // A blue map scaled by red only lights nothing.
    let blue = write(dir.path(), "blue.pfm", &uniform_pfm([0.0, 0.0, 1.0], 4, 2));
    let out = dir.path().join("never.pfm");
    let output = render_small(
        &scene,
        &out,
        &["--sky-map", blue.to_str().unwrap(), "--sky", "1,0,0"],
    );
    assert_clean_error(&output, "scales the sky map");
    assert!(!out.exists(), "a black-scaled map: an image was written");
}
