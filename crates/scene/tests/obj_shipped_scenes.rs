//! The glTF scenes shipped in `scenes/` are what `make_scenes` writes from `scene::testing`,
//! valid glTF 2.0, and load back as their fixtures.
//!
//! (The file is named `obj_*` only because of how the crate's test files are divided among
//! its authors; it tests the shipped glTF scenes.)

use crate::gltf_writer;
use crate::sky_writer;

use std::path::{Path, PathBuf};

use glam::{Vec3, Vec4};
use scene::{Material, PunctualKind, Scene, Triangle};

fn shipped_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes")
}

/// The file `name` written fresh into `dir` is the one in `scenes/`, byte for byte.
fn assert_as_shipped(dir: &Path, name: &str) {
    let fresh = std::fs::read(dir.join(name)).unwrap();
    let shipped =
        std::fs::read(shipped_dir().join(name)).unwrap_or_else(|e| panic!("scenes/{name}: {e}"));
    assert!(
        fresh == shipped,
        "scenes/{name} differs from what make_scenes writes; regenerate it with \
         `cargo run -p scene --example make_scenes -- scenes/`"
    );
}

#[test]
fn shipped_scenes_match_a_fresh_regeneration() {
    let dir = tempfile::tempdir().unwrap();
    for (stem, fixture) in gltf_writer::SHIPPED {
        gltf_writer::write(&fixture(), stem, dir.path()).unwrap();
        for extension in ["gltf", "bin"] {
            assert_as_shipped(dir.path(), &format!("{stem}.{extension}"));
        }
    }
}

#[test]
fn shipped_skies_match_a_fresh_regeneration() {
    let dir = tempfile::tempdir().unwrap();
    for (stem, fixture) in sky_writer::SKIES {
        sky_writer::write(&fixture(), stem, dir.path()).unwrap();
        assert_as_shipped(dir.path(), &format!("skies/{stem}.hdr"));
    }
}

#[test]
fn encoding_is_deterministic() {
    for (stem, fixture) in gltf_writer::SHIPPED {
        let (a, b) = (
            gltf_writer::encode(&fixture(), stem),
            gltf_writer::encode(&fixture(), stem),
        );
        assert!(a.json == b.json && a.bin == b.bin, "{stem}");
    }
}

#[test]
fn shipped_scenes_are_valid_gltf() {
    for (stem, _) in gltf_writer::SHIPPED {
        let json = std::fs::read(shipped_dir().join(format!("{stem}.gltf"))).unwrap();
        let bin = std::fs::read(shipped_dir().join(format!("{stem}.bin"))).unwrap();
        // `from_slice` runs the gltf crate's validation (indices, required fields, enums).
        let document = gltf::Gltf::from_slice(&json).unwrap_or_else(|e| panic!("{stem}: {e}"));
        let buffer = document.buffers().next().unwrap();
        assert_eq!(buffer.length(), bin.len(), "{stem}: byteLength");
        for view in document.views() {
            assert_eq!(view.offset() % 4, 0);
            assert!(view.offset() + view.length() <= bin.len());
        }
        for accessor in document.accessors() {
            let view = accessor.view().unwrap();
            assert_eq!(
                accessor.count() * accessor.size(),
                view.length(),
                "{stem}: tightly packed"
            );
        }
        let used: Vec<&str> = document.extensions_used().collect();
        for extension in gltf_writer_extensions(&document) {
            assert!(
                used.contains(&extension.as_str()),
                "{stem}: {extension} not in extensionsUsed"
            );
        }
        let camera = document.cameras().next().unwrap();
        assert!(matches!(
            camera.projection(),
            gltf::camera::Projection::Perspective(_)
        ));
    }
}

/// Every extension the materials use.
fn gltf_writer_extensions(document: &gltf::Gltf) -> Vec<String> {
    let mut names = Vec::new();
    for material in document.materials() {
        if material.emissive_strength().is_some() {
            names.push("KHR_materials_emissive_strength".to_string());
        }
        if material.transmission().is_some() {
            names.push("KHR_materials_transmission".to_string());
        }
        if material.ior().is_some() {
            names.push("KHR_materials_ior".to_string());
        }
        if material.volume().is_some() {
            names.push("KHR_materials_volume".to_string());
        }
        if material
            .extension_value("KHR_materials_dispersion")
            .is_some()
        {
            names.push("KHR_materials_dispersion".to_string());
        }
    }
    names
}

fn sort_key(t: &Triangle) -> (u32, [u32; 9]) {
    let p = t.positions();
    let coords: Vec<f32> = p.iter().flat_map(|v| v.to_array()).collect();
    (t.material, std::array::from_fn(|i| coords[i].to_bits()))
}

fn close(a: Vec3, b: Vec3, tolerance: f32) -> bool {
    (a - b).abs().max_element() <= tolerance * a.abs().max_element().max(1.0)
}

/// Same triangles (as a set, with their normals and materials), materials and cameras.
fn assert_same_scene(loaded: &Scene, fixture: &Scene, stem: &str) {
    assert_eq!(
        loaded.triangles.len(),
        fixture.triangles.len(),
        "{stem}: triangles"
    );
    assert_eq!(loaded.degenerate_dropped, 0, "{stem}");
    assert!(loaded.warnings.is_empty(), "{stem}: {:?}", loaded.warnings);
    let mut a: Vec<&Triangle> = loaded.triangles.iter().collect();
    let mut b: Vec<&Triangle> = fixture.triangles.iter().collect();
    a.sort_by_key(|t| sort_key(t));
    b.sort_by_key(|t| sort_key(t));
    for (x, y) in a.iter().zip(&b) {
        assert_eq!(x.material, y.material, "{stem}");
        for (u, v) in x.vertices.iter().zip(&y.vertices) {
            assert_eq!(
                u.position, v.position,
                "{stem}: positions are written exactly"
            );
            assert!(
                close(u.normal, v.normal, 1e-6),
                "{stem}: normal {} vs {}",
                u.normal,
                v.normal
            );
            assert_eq!(u.uv, v.uv);
        }
    }
    assert_eq!(loaded.materials.len(), fixture.materials.len());
    for (x, y) in loaded.materials.iter().zip(&fixture.materials) {
        assert_eq!(
            (&x.name, x.surface, x.base_color),
            (&y.name, y.surface, y.base_color),
            "{stem}"
        );
        assert!(
            close(x.emission, y.emission, 1e-6),
            "{stem}: {} vs {}",
            x.emission,
            y.emission
        );
        assert_eq!(
            (x.alpha, x.alpha_mode, x.double_sided),
            (y.alpha, y.alpha_mode, y.double_sided)
        );
        assert!(
            close(x.absorption, y.absorption, 1e-5),
            "{stem}: absorption {} vs {}",
            x.absorption,
            y.absorption
        );
        assert!(
            close(x.scattering, y.scattering, 1e-5),
            "{stem}: scattering {} vs {}",
            x.scattering,
            y.scattering
        );
        assert!(
            (x.scatter_anisotropy - y.scatter_anisotropy).abs() < 1e-6,
            "{stem}: scattering's anisotropy"
        );
        assert_eq!(x.normal_scale, y.normal_scale, "{stem}: normal scale");
        assert!(
            (x.dispersion - y.dispersion).abs() <= 1e-6 * y.dispersion,
            "{stem}: dispersion {} vs {}",
            x.dispersion,
            y.dispersion
        );
        assert_eq!(x.clearcoat, y.clearcoat, "{stem}: clear coat");
        assert_eq!(x.sheen, y.sheen, "{stem}: sheen");
        assert_eq!(x.anisotropy, y.anisotropy, "{stem}: anisotropy");
        assert_eq!(
            x.diffuse_transmission, y.diffuse_transmission,
            "{stem}: diffuse transmission"
        );
        match (x.blend, y.blend) {
            (Some(a), Some(b)) => assert!(
                a.other == b.other && (a.weight - b.weight).abs() < 1e-6,
                "{stem}: {}'s blend {a:?} vs {b:?}",
                x.name
            ),
            (a, b) => assert_eq!(a, b, "{stem}: {}'s blend", x.name),
        }
        assert_eq!(
            normal_map_texels(loaded, x),
            normal_map_texels(fixture, y),
            "{stem}: {}'s normal map",
            x.name
        );
        assert_eq!(
            film_texels(loaded, x),
            film_texels(fixture, y),
            "{stem}: {}'s film",
            x.name
        );
    }
    assert_eq!(loaded.cameras.len(), fixture.cameras.len());
    for (x, y) in loaded.cameras.iter().zip(&fixture.cameras) {
        // An oblique camera's frame goes through the file as an f32 quaternion: its forward
        // and up come back within a few 1e-6 (measured 3e-6 for cornell-pool's under water).
        assert!(
            close(x.eye, y.eye, 1e-6) && close(x.forward, y.forward, 1e-5),
            "{stem}: {x:?} vs {y:?}"
        );
        assert!(close(x.up, y.up, 1e-5), "{stem}");
        assert_eq!((x.yfov, x.aspect_ratio), (y.yfov, y.aspect_ratio), "{stem}");
    }
    assert!(
        close(loaded.lights.total_power, fixture.lights.total_power, 1e-5),
        "{stem}"
    );
    assert_eq!(
        loaded.lights.punctual.len(),
        fixture.lights.punctual.len(),
        "{stem}: punctual lights"
    );
    for (x, y) in loaded.lights.punctual.iter().zip(&fixture.lights.punctual) {
        let (x, y) = (&x.light, &y.light);
        assert!(
            close(x.position, y.position, 1e-6)
                && close(x.direction, y.direction, 1e-6)
                && close(x.intensity, y.intensity, 1e-6),
            "{stem}: {x:?} vs {y:?}"
        );
        match (x.kind, y.kind) {
            (
                PunctualKind::Spot {
                    cos_inner: a,
                    cos_outer: b,
                    falloff: e,
                },
                PunctualKind::Spot {
                    cos_inner: c,
                    cos_outer: d,
                    falloff: f,
                },
            ) => assert!(
                (a - c).abs() < 1e-6 && (b - d).abs() < 1e-6 && e == f,
                "{stem}"
            ),
            (a, b) => assert_eq!(a, b, "{stem}"),
        }
    }
}

/// A material's normal map as (width, height, linear texels), if it has one.
fn normal_map_texels(scene: &Scene, material: &Material) -> Option<(u32, u32, Vec<Vec4>)> {
    texels(scene, material.normal_texture)
}

/// A material's thin film with its textures' ids left out, and those textures' texels.
type FilmTexels = Option<(f32, f32, f32, f32, [Option<TexelGrid>; 2])>;
type TexelGrid = (u32, u32, Vec<Vec4>);

fn film_texels(scene: &Scene, material: &Material) -> FilmTexels {
    let film = material.iridescence?;
    Some((
        film.factor,
        film.ior,
        film.thickness_min,
        film.thickness_max,
        [film.texture, film.thickness_texture].map(|id| texels(scene, id)),
    ))
}

/// Texture `id` as (width, height, linear texels), `None` for none.
fn texels(scene: &Scene, id: Option<u32>) -> Option<TexelGrid> {
    let texture = &scene.textures[id? as usize];
    let texels = (0..texture.height)
        .flat_map(|y| (0..texture.width).map(move |x| texture.texel_linear(x, y)))
        .collect();
    Some((texture.width, texture.height, texels))
}

#[test]
fn shipped_scenes_load_as_their_fixtures() {
    for (stem, fixture) in gltf_writer::SHIPPED {
        let path = shipped_dir().join(format!("{stem}.gltf"));
        let loaded = scene::load(&path).unwrap_or_else(|e| panic!("{e}"));
        assert_same_scene(&loaded, &fixture(), stem);
    }
}
