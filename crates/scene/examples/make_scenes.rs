//! Writes the scenes shipped in `scenes/` (glTF 2.0, `.gltf` + `.bin`) and the sky maps in
//! `scenes/skies/` (.hdr) from the fixtures in `scene::testing`:
//!
//! ```text
//! cargo run -p scene --example make_scenes -- scenes/
//! ```
//!
//! The output is deterministic; `crates/scene/tests/obj_shipped_scenes.rs` regenerates the
//! files and fails if the committed ones differ.

#[path = "make_scenes/gltf_writer.rs"]
mod gltf_writer;
#[path = "make_scenes/sky_writer.rs"]
mod sky_writer;

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
    for (stem, fixture) in sky_writer::SKIES {
        let map = fixture();
        if let Err(e) = sky_writer::write(&map, stem, &dir) {
            eprintln!("error: {}: {e}", dir.join("skies").join(stem).display());
            return ExitCode::FAILURE;
        }
        println!(
            "{}: {}x{} sky map",
            dir.join("skies").join(format!("{stem}.hdr")).display(),
            map.width(),
            map.height()
        );
    }
    ExitCode::SUCCESS
}
