//! Helpers for the command-line tests: run the binary, make small scene files.

#![allow(dead_code)]

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use base64::Engine;
use serde_json::{Value, json};

pub fn kousen(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_kousen"))
        .args(args)
        .env("RUST_LOG", "error")
        .output()
        .expect("the kousen binary runs")
}

/// Asserts the command succeeded, showing what it wrote where it did not; returns its output.
pub fn succeeded(output: Output) -> Output {
    assert_succeeded(&output);
    output
}

/// Asserts the command succeeded, showing what it wrote where it did not.
pub fn assert_succeeded(output: &Output) {
    assert!(
        output.status.success(),
        "{}\n{}",
        String::from_utf8_lossy(&output.stdout),
        String::from_utf8_lossy(&output.stderr)
    );
}

/// The path of a scene shipped in `scenes/`.
pub fn shipped(name: &str) -> String {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../scenes")
        .join(name)
        .to_string_lossy()
        .into_owned()
}

/// Runs kousen with a private runtime directory, so Mesa's window-system probing has nothing
/// to complain about on stderr.
pub fn kousen_quiet(args: &[&str]) -> Output {
    let runtime = tempfile::tempdir().expect("temporary directory");
    Command::new(env!("CARGO_BIN_EXE_kousen"))
        .args(args)
        .env("RUST_LOG", "error")
        .env("XDG_RUNTIME_DIR", runtime.path())
        .output()
        .expect("the kousen binary runs")
}

/// `kousen render SCENE -o OUT` at 16², 8 passes on the CPU, with `more` arguments.
pub fn render_small(
    scene: &std::path::Path,
    out: &std::path::Path,
    more: &[&str],
) -> std::process::Output {
    let mut args = vec![
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
    ];
    args.extend_from_slice(more);
    kousen_quiet(&args)
}

/// Asserts a clean failure: non-zero exit, one line on stderr that starts with "kousen: error:"
/// and mentions `needle`, no panic.
pub fn assert_clean_error(output: &Output, needle: &str) {
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(
        !output.status.success(),
        "expected failure, got success; stderr: {stderr}"
    );
    assert_ne!(
        output.status.code(),
        Some(101),
        "exit code 101 is a panic: {stderr}"
    );
    assert!(!stderr.contains("panicked"), "panicked: {stderr}");
    let lines: Vec<&str> = stderr.lines().collect();
    assert_eq!(lines.len(), 1, "expected one line on stderr, got: {stderr}");
    assert!(
        lines[0].starts_with("kousen: error:"),
        "unexpected stderr: {stderr}"
    );
    assert!(
        lines[0].to_lowercase().contains(&needle.to_lowercase()),
        "stderr does not mention {needle:?}: {stderr}"
    );
}

pub fn write(dir: &Path, name: &str, bytes: &[u8]) -> PathBuf {
    let path = dir.join(name);
    std::fs::write(&path, bytes).expect("write test file");
    path
}

pub fn data_uri(bytes: &[u8]) -> String {
    let encoded = base64::engine::general_purpose::STANDARD.encode(bytes);
    format!("data:application/octet-stream;base64,{encoded}")
}

/// A one-mesh glTF: `positions` as VEC3 floats, optional u32 indices, primitive `mode`
/// (4 = triangles), all in one data-URI buffer. `extra` is merged into the top-level object.
pub fn gltf(positions: &[[f32; 3]], indices: Option<&[u32]>, mode: u32, extra: Value) -> Vec<u8> {
    let mut bytes: Vec<u8> = positions
        .iter()
        .flatten()
        .flat_map(|f| f.to_le_bytes())
        .collect();
    let position_len = bytes.len();
    if let Some(indices) = indices {
        bytes.extend(indices.iter().flat_map(|i| i.to_le_bytes()));
    }
    let (min, max) = bounds(positions);
    let mut accessors = vec![json!({
        "bufferView": 0, "componentType": 5126, "count": positions.len(), "type": "VEC3",
        "min": min, "max": max
    })];
    let mut views = vec![json!({"buffer": 0, "byteOffset": 0, "byteLength": position_len})];
    let mut primitive = json!({"attributes": {"POSITION": 0}, "mode": mode});
    if let Some(indices) = indices {
        views.push(
            json!({"buffer": 0, "byteOffset": position_len, "byteLength": indices.len() * 4}),
        );
        accessors.push(json!({"bufferView": 1, "componentType": 5125, "count": indices.len(), "type": "SCALAR"}));
        primitive["indices"] = json!(1);
    }
    let mut document = json!({
        "asset": {"version": "2.0"},
        "scene": 0,
        "scenes": [{"nodes": [0]}],
        "nodes": [{"mesh": 0}],
        "meshes": [{"primitives": [primitive]}],
        "accessors": accessors,
        "bufferViews": views,
        "buffers": [{"byteLength": bytes.len(), "uri": data_uri(&bytes)}],
    });
    if let (Value::Object(target), Value::Object(extra)) = (&mut document, extra) {
        target.extend(extra);
    }
    serde_json::to_vec_pretty(&document).expect("serialise glTF")
}

fn bounds(positions: &[[f32; 3]]) -> (Vec<f32>, Vec<f32>) {
    let mut min = vec![f32::MAX; 3];
    let mut max = vec![f32::MIN; 3];
    for p in positions {
        for i in 0..3 {
            if p[i].is_finite() {
                min[i] = min[i].min(p[i]);
                max[i] = max[i].max(p[i]);
            }
        }
    }
    (min, max)
}

/// A unit quad in the XZ plane facing +Y, two triangles.
pub const QUAD: [[f32; 3]; 4] = [
    [0.0, 0.0, 0.0],
    [0.0, 0.0, 1.0],
    [1.0, 0.0, 1.0],
    [1.0, 0.0, 0.0],
];
pub const QUAD_INDICES: [u32; 6] = [0, 1, 2, 0, 2, 3];

/// A binary glTF container around a JSON document and one binary chunk.
pub fn glb(json: &[u8], bin: &[u8]) -> Vec<u8> {
    let pad = |mut v: Vec<u8>, with: u8| {
        while !v.len().is_multiple_of(4) {
            v.push(with);
        }
        v
    };
    let json = pad(json.to_vec(), b' ');
    let bin = pad(bin.to_vec(), 0);
    let total = 12 + 8 + json.len() + 8 + bin.len();
    let mut out = Vec::with_capacity(total);
    out.extend(b"glTF");
    out.extend(2u32.to_le_bytes());
    out.extend((total as u32).to_le_bytes());
    out.extend((json.len() as u32).to_le_bytes());
    out.extend(b"JSON");
    out.extend(&json);
    out.extend((bin.len() as u32).to_le_bytes());
    out.extend(b"BIN\0");
    out.extend(&bin);
    out
}
