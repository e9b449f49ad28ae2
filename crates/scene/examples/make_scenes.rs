//! Writes the scenes shipped in `scenes/` (glTF 2.0, `.gltf` + `.bin`) from the fixtures in
//! `scene::testing`:
//!
//! ```text
//! cargo run -p scene --example make_scenes -- scenes/
//! ```
//!
//! The output is deterministic; `crates/scene/tests/obj_shipped_scenes.rs` regenerates the
//! files and fails if the committed ones differ.

#[path = "make_scenes/gltf_writer.rs"]
mod gltf_writer;

use std::path::PathBuf;
use std::process::ExitCode;

fn main() -> ExitCode {
    let dir = PathBuf::from(std::env::args().nth(1).unwrap_or_else(|| "scenes".into()));
    if let Err(e) = std::fs::create_dir_all(&dir) {
        eprintln!("error: {}: {e}", dir.display());
        return ExitCode::FAILURE;
    }
    for (stem, fixture) in gltf_writer::SHIPPED {
        let scene = fixture();
        if let Err(e) = gltf_writer::write(&scene, stem, &dir) {
            eprintln!("error: {}: {e}", dir.join(stem).display());
            return ExitCode::FAILURE;
        }
        println!(
            "{}: {} triangles, {} materials",
            dir.join(format!("{stem}.gltf")).display(),
            scene.triangles.len(),
            scene.materials.len()
        );
    }
    ExitCode::SUCCESS
}
