//! The benchmark scenes of the shared folder (see `scene::testing::shared_scene`) load with their published counts.
//!
//! Those files are not in the repository (CI runs on a clean clone), so each test checks that
//! its file exists and otherwise prints a note and passes. Load times are printed; run
//! `cargo test --release -p scene --test integration obj_shared_scenes -- --nocapture` to see them.

use std::path::{Path, PathBuf};
use std::time::Instant;

use scene::{AlphaMode, Scene, Surface};

fn shared(relative: &str) -> Option<PathBuf> {
    scene::testing::shared_scene(relative)
}

fn load_timed(path: &Path) -> Scene {
    let start = Instant::now();
    let scene = scene::obj::load(path).unwrap_or_else(|e| panic!("{e}"));
    println!(
        "{}: {} triangles, {} dropped, {} materials, {} textures, {} warnings in {:.3} s",
        path.display(),
        scene.triangles.len(),
        scene.degenerate_dropped,
        scene.materials.len(),
        scene.textures.len(),
        scene.warnings.len(),
        start.elapsed().as_secs_f64()
    );
    for warning in &scene.warnings {
        println!("  warning: {warning}");
    }
    // The builder's `finish` runs this; timed alone to show its share of the load.
    let start = Instant::now();
    scene::Lights::collect(&scene.triangles, &scene.materials, &scene.textures, &[]);
    println!(
        "  of which Lights::collect: {:.3} s",
        start.elapsed().as_secs_f64()
    );
    scene
}

#[test]
fn cornell_box_original_loads_36_triangles_with_its_light() {
    let Some(path) = shared("cornell/CornellBox-Original.obj") else {
        return;
    };
    let scene = load_timed(&path);
    assert_eq!(scene.triangles.len(), 36);
    assert_eq!(scene.degenerate_dropped, 0);
    assert_eq!(scene.materials.len(), 8);
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
    assert_eq!(scene.lights.triangles.len(), 2);
    let light = &scene.triangles[scene.lights.triangles[0].triangle as usize];
    let normal = light.geometric_normal_unnormalized().normalize();
    assert!(
        normal.y < -0.99,
        "the light faces down into the box: {normal}"
    );
    let left_wall = scene
        .materials
        .iter()
        .find(|m| m.name == "leftWall")
        .unwrap();
    assert_eq!(left_wall.base_color, glam::Vec3::new(0.63, 0.065, 0.05));
}

#[test]
fn cornell_metal_obj_loads_36_triangles() {
    let Some(path) = shared("cornell-metal/cornell_metal.obj") else {
        return;
    };
    let scene = load_timed(&path);
    assert_eq!(scene.triangles.len(), 36);
    // Its MTL marks the light with Ka and the mirrors with Ks/Ns (glslppm's own rules), not
    // with Ke and illum: as plain MTL everything is diffuse and nothing emits.
    assert!(scene.lights.triangles.is_empty());
    assert!(
        scene
            .materials
            .iter()
            .all(|m| m.surface == Surface::Diffuse)
    );
}

#[test]
fn bunny_loads_69451_triangles_with_smooth_normals() {
    let Some(path) = shared("bunny/bunny.obj") else {
        return;
    };
    let scene = load_timed(&path);
    assert_eq!(scene.triangles.len() + scene.degenerate_dropped, 69_451);
    assert_eq!(scene.materials.len(), 1);
    // Smooth normals differ from the face normal somewhere.
    let smooth = scene.triangles.iter().any(|t| {
        let face = t.geometric_normal_unnormalized().normalize();
        t.vertices.iter().any(|v| v.normal.dot(face) < 0.999)
    });
    assert!(smooth);
}

#[test]
fn dabrovic_sponza_loads_66454_triangles() {
    let Some(path) = shared("sponza-dabrovic/sponza.obj") else {
        return;
    };
    let scene = load_timed(&path);
    assert_eq!(scene.triangles.len() + scene.degenerate_dropped, 66_454);
}

#[test]
fn crytek_sponza_loads_262267_triangles_and_20_textures() {
    let Some(path) = shared("crytek-sponza/sponza.obj") else {
        return;
    };
    let scene = load_timed(&path);
    assert_eq!(scene.triangles.len() + scene.degenerate_dropped, 262_267);
    assert_eq!(scene.degenerate_dropped, 425);
    assert_eq!(scene.materials.len(), 25);
    assert_eq!(scene.textures.len(), 20);
    for name in ["chain", "leaf"] {
        let m = scene.materials.iter().find(|m| m.name == name).unwrap();
        assert_eq!(m.alpha_mode, AlphaMode::Mask { cutoff: 0.5 }, "{name}");
        assert!(m.base_color_texture.is_some(), "{name}");
    }
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
    // The snapshot lacks four maps; its MTL leaves those materials with only a Kd colour.
    let curtain = scene
        .materials
        .iter()
        .find(|m| m.name == "fabric_c")
        .unwrap();
    assert_eq!(curtain.base_color_texture, None);
}
