//! OBJ/MTL material mapping onto the uber-material (obj module manual).

use std::path::{Path, PathBuf};

use glam::Vec3;
use scene::{AlphaMode, Scene, Surface, Texels};

/// A unit quad in the z = 0 plane facing +z, with texture coordinates, one per material named.
fn quads_obj(materials: &[&str]) -> String {
    let mut obj = String::from("mtllib scene.mtl\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n");
    for (i, name) in materials.iter().enumerate() {
        let x = 2.0 * i as f32;
        obj += &format!(
            "v {x} 0 0\nv {} 0 0\nv {} 1 0\nv {x} 1 0\nusemtl {name}\nf -4/1 -3/2 -2/3 -1/4\n",
            x + 1.0,
            x + 1.0
        );
    }
    obj
}

fn write_scene(dir: &Path, obj: &str, mtl: &str) -> PathBuf {
    std::fs::write(dir.join("scene.mtl"), mtl).unwrap();
    let path = dir.join("scene.obj");
    std::fs::write(&path, obj).unwrap();
    path
}

fn load(dir: &Path, materials: &[&str], mtl: &str) -> Scene {
    let path = write_scene(dir, &quads_obj(materials), mtl);
    scene::obj::load(&path).unwrap_or_else(|e| panic!("{e}"))
}

fn material<'a>(scene: &'a Scene, name: &str) -> &'a scene::Material {
    scene.materials.iter().find(|m| m.name == name).unwrap()
}

/// Writes RGBA texels in the format `path`'s extension names (PNG, or lossless WebP).
fn write_image(path: &Path, width: u32, height: u32, rgba: &[[u8; 4]]) {
    let raw = rgba.iter().flatten().copied().collect();
    image::RgbaImage::from_raw(width, height, raw)
        .unwrap()
        .save(path)
        .unwrap();
}

#[test]
fn kd_becomes_diffuse_albedo_and_ke_emission() {
    let dir = tempfile::tempdir().unwrap();
    let mtl = "newmtl wall\nKd 0.2 0.4 0.6\nnewmtl lamp\nKd 0 0 0\nKe 17 12 4\n";
    let scene = load(dir.path(), &["wall", "lamp"], mtl);
    let wall = material(&scene, "wall");
    assert_eq!(wall.surface, Surface::Diffuse);
    assert_eq!(wall.base_color, Vec3::new(0.2, 0.4, 0.6));
    assert_eq!(wall.emission, Vec3::ZERO);
    assert_eq!(
        material(&scene, "lamp").emission,
        Vec3::new(17.0, 12.0, 4.0)
    );
    assert_eq!(scene.lights.triangles.len(), 2);
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
}

/// Materials neither mirror nor glass map as glTF's would: roughness from `Pr`, else from `Ns`
/// as Blender writes it (1 − √(Ns / 1000)); a specular colour (or `Pr`) puts a coat of index
/// `Ni` (1.5 where not above 1) over the albedo, Lambertian from roughness 0.5; `Pm` makes
/// metal tinted by `Kd`, partly a blend; a material without `Ks` (or with a black one) or
/// without a shininess stays Lambertian, its `map_Kd` kept under a coat.
#[test]
fn specular_colour_and_shininess_make_plastic_and_pm_metal() {
    let dir = tempfile::tempdir().unwrap();
    let mtl = "newmtl gloss\nillum 2\nKd 0.5 0.1 0.1\nKs 0.5 0.5 0.5\nNs 640\nNi 1.45\n\
               newmtl satin\nillum 2\nKs 0.5 0.5 0.5\nNs 96\n\
               newmtl dull\nillum 2\nKs 0 0 0\nNs 900\n\
               newmtl plain\nKd 0.3 0.3 0.3\nKs 1 1 1\n\
               newmtl unit\nKs 0.2 0.2 0.2\nNs 1000\nNi 1\n\
               newmtl metal\nKd 0.9 0.7 0.3\nPr 0.3\nPm 1\n\
               newmtl half\nKd 0.9 0.7 0.3\nPr 0.3\nPm 0.25\n";
    let names = ["gloss", "satin", "dull", "plain", "unit", "metal", "half"];
    let scene = load(dir.path(), &names, mtl);
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
    let surface = |name| material(&scene, name).surface;
    let roughness = 1.0 - (640.0f32 / 1000.0).sqrt();
    assert_eq!(
        surface("gloss"),
        Surface::Plastic {
            ior: 1.45,
            alpha: roughness * roughness
        }
    );
    assert_eq!(
        material(&scene, "gloss").base_color,
        Vec3::new(0.5, 0.1, 0.1)
    );
    assert_eq!(surface("satin"), Surface::Diffuse, "Ns 96: roughness 0.69");
    assert_eq!(surface("dull"), Surface::Diffuse, "black Ks: no coat");
    assert_eq!(surface("plain"), Surface::Diffuse, "no shininess");
    assert_eq!(
        surface("unit"),
        Surface::Plastic {
            ior: 1.5,
            alpha: 0.0
        },
        "Ns 1000 is smooth; Ni 1 is no index"
    );
    let rough_metal = Surface::RoughConductor { alpha: 0.3 * 0.3 };
    assert_eq!(surface("metal"), rough_metal);
    assert_eq!(
        material(&scene, "metal").base_color,
        Vec3::new(0.9, 0.7, 0.3)
    );
    let half = material(&scene, "half");
    let blend = half.blend.expect("Pm 0.25 blends");
    assert_eq!((half.surface, blend.weight), (rough_metal, 0.25));
    assert_eq!(
        scene.materials[blend.other as usize].surface,
        Surface::Plastic {
            ior: 1.5,
            alpha: 0.3 * 0.3
        }
    );
}

/// The PBR extension's coat and sheen, as Blender writes them: `Pc` and `Pcr` a clear coat of
/// that weight and roughness, `Ps` a white sheen of that strength and roughness 0.5; 0 is
/// none; a metal blend's members all carry them; mirrors and glass wear none.
#[test]
fn pc_pcr_and_ps_make_a_clear_coat_and_a_sheen() {
    let dir = tempfile::tempdir().unwrap();
    let mtl = "newmtl coated\nKd 0.8 0.1 0.1\nPr 0.6\nPc 0.7\nPcr 0.2\n\
               newmtl velvet\nKd 0.3 0.0 0.0\nPr 0.9\nPs 0.8\n\
               newmtl none\nKd 0.5 0.5 0.5\nPc 0\nPs 0\n\
               newmtl half\nKd 0.9 0.7 0.3\nPr 0.3\nPm 0.5\nPc 1\nPs 0.5\n\
               newmtl glass\nillum 7\nPc 1\nPs 1\n";
    let names = ["coated", "velvet", "none", "half", "glass"];
    let scene = load(dir.path(), &names, mtl);
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
    let coated = material(&scene, "coated");
    assert_eq!(coated.clearcoat, scene::Clearcoat::new(0.7, 0.2));
    assert_eq!(coated.sheen, None);
    let velvet = material(&scene, "velvet");
    assert_eq!(velvet.sheen, scene::Sheen::new(Vec3::splat(0.8), 0.5));
    assert_eq!(velvet.clearcoat, None);
    let none = material(&scene, "none");
    assert_eq!((none.clearcoat, none.sheen), (None, None));
    let half = material(&scene, "half");
    let other = &scene.materials[half.blend.expect("Pm 0.5 blends").other as usize];
    for member in [half, other] {
        assert_eq!(member.clearcoat, scene::Clearcoat::new(1.0, 0.0));
        assert_eq!(member.sheen, scene::Sheen::new(Vec3::splat(0.5), 0.5));
    }
    let glass = material(&scene, "glass");
    assert_eq!((glass.clearcoat, glass.sheen), (None, None));
}

/// Both are mirrors; 5 ("Fresnel on") rises to white at grazing angles, 3 does not.
#[test]
fn illum_3_and_5_are_mirrors_tinted_by_ks_else_kd() {
    let dir = tempfile::tempdir().unwrap();
    let mtl = "newmtl a\nillum 5\nKd 0 0 0\nKs 0.9 0.8 0.7\n\
               newmtl b\nillum 3\nKd 0.5 0.5 0.5\nKs 0 0 0\n";
    let scene = load(dir.path(), &["a", "b"], mtl);
    assert_eq!(material(&scene, "a").surface, Surface::Mirror);
    assert_eq!(material(&scene, "a").base_color, Vec3::new(0.9, 0.8, 0.7));
    assert_eq!(material(&scene, "b").surface, Surface::Mirror);
    assert_eq!(material(&scene, "b").base_color, Vec3::splat(0.5));
    assert_eq!(material(&scene, "a").metal_edge, Vec3::ONE);
    assert_eq!(material(&scene, "b").metal_edge, Vec3::ZERO);
}

#[test]
fn illum_7_is_solid_glass_with_ni_and_tf() {
    let dir = tempfile::tempdir().unwrap();
    let mtl = "newmtl glass\nillum 7\nNi 1.33\nKd 0 0 0\nTf 0.9 1 0.9\n\
               newmtl plain\nillum 4\nNi 0.5\n";
    let scene = load(dir.path(), &["glass", "plain"], mtl);
    let glass = material(&scene, "glass");
    let expected = Surface::Dielectric {
        ior: 1.33,
        thin_walled: false,
    };
    assert_eq!(glass.surface, expected);
    assert_eq!(glass.base_color, Vec3::new(0.9, 1.0, 0.9));
    // Ni below 1 falls back to 1.5 with a warning; no Tf means a clear tint.
    let plain = material(&scene, "plain");
    let fallback = Surface::Dielectric {
        ior: scene::obj::DEFAULT_IOR,
        thin_walled: false,
    };
    assert_eq!(plain.surface, fallback);
    assert_eq!(plain.base_color, Vec3::ONE);
    assert!(
        scene.warnings.iter().any(|w| w.contains("Ni 0.5")),
        "{:?}",
        scene.warnings
    );
}

#[test]
fn one_number_colours_are_grey_and_reflectances_are_clamped() {
    let dir = tempfile::tempdir().unwrap();
    let mtl = "newmtl a\nKd 0.5 # grey\nnewmtl b\nKd 2 0.5 -1\n";
    let scene = load(dir.path(), &["a", "b"], mtl);
    assert_eq!(material(&scene, "a").base_color, Vec3::splat(0.5));
    assert_eq!(material(&scene, "b").base_color, Vec3::new(1.0, 0.5, 0.0));
    assert!(scene.warnings.iter().any(|w| w.contains("clamped")));
}

#[test]
fn map_kd_is_an_srgb_texture_that_replaces_kd() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::create_dir(dir.path().join("tex")).unwrap();
    let texels = [
        [255, 0, 0, 255],
        [0, 255, 0, 255],
        [0, 0, 255, 255],
        [128, 128, 128, 255],
    ];
    write_image(&dir.path().join("tex/check.png"), 2, 2, &texels);
    let mtl = "newmtl a\nKd 0.588 0.588 0.588\nmap_Kd tex\\check.png\n\
               newmtl b\nmap_Kd -bm 0.5 tex/check.png\n";
    let scene = load(dir.path(), &["a", "b"], mtl);
    assert_eq!(scene.textures.len(), 1, "one file, decoded once");
    let texture = &scene.textures[0];
    assert_eq!((texture.width, texture.height), (2, 2));
    assert_eq!(texture.texels, Texels::Srgb8(texels.to_vec()));
    for name in ["a", "b"] {
        assert_eq!(material(&scene, name).base_color_texture, Some(0));
        assert_eq!(material(&scene, name).base_color, Vec3::ONE);
    }
    assert!(scene.warnings.iter().any(|w| w.contains("-bm 0.5")));
    // vt (0, 0) is the image's bottom-left corner: the scene's v = 1.
    let uvs: Vec<_> = scene.triangles[0].vertices.iter().map(|v| v.uv).collect();
    assert_eq!(uvs[0], glam::Vec2::new(0.0, 1.0));
    assert_eq!(uvs[2], glam::Vec2::new(1.0, 0.0));
}

/// Also from a (lossless) WebP image, which maps may name as they name PNG and JPEG.
#[test]
fn map_d_naming_the_base_image_uses_its_alpha() {
    for image in ["leaf.png", "leaf.webp"] {
        let dir = tempfile::tempdir().unwrap();
        let texels = [[10, 20, 30, 0], [40, 50, 60, 255]];
        write_image(&dir.path().join(image), 2, 1, &texels);
        let mtl = format!("newmtl leaf\nmap_Kd {image}\nmap_d {image}\n");
        let scene = load(dir.path(), &["leaf"], &mtl);
        let leaf = material(&scene, "leaf");
        assert_eq!(leaf.alpha_mode, AlphaMode::Mask { cutoff: 0.5 });
        assert_eq!(leaf.base_color_texture, Some(0));
        assert_eq!(scene.textures.len(), 1);
        assert_eq!(scene.textures[0].texels, Texels::Srgb8(texels.to_vec()));
    }
}

#[test]
fn separate_grey_map_d_becomes_the_base_textures_alpha() {
    let dir = tempfile::tempdir().unwrap();
    // A 4×2 colour image and a 2×1 grey mask: each mask texel covers 2×2 colour texels.
    let colour: Vec<[u8; 4]> = (0..8).map(|i| [i * 10, 0, 0, 255]).collect();
    write_image(&dir.path().join("colour.png"), 4, 2, &colour);
    image::GrayImage::from_raw(2, 1, vec![0, 200])
        .unwrap()
        .save(dir.path().join("mask.png"))
        .unwrap();
    let mtl = "newmtl chain\nmap_Kd colour.png\nmap_d mask.png\n\
               newmtl bare\nKd 0.3 0.3 0.3\nmap_d mask.png\n";
    let scene = load(dir.path(), &["chain", "bare"], mtl);
    let chain = material(&scene, "chain");
    assert_eq!(chain.alpha_mode, AlphaMode::Mask { cutoff: 0.5 });
    let merged = &scene.textures[chain.base_color_texture.unwrap() as usize];
    let Texels::Srgb8(texels) = &merged.texels else {
        panic!("sRGB expected");
    };
    let alphas: Vec<u8> = texels.iter().map(|t| t[3]).collect();
    assert_eq!(alphas, [0, 0, 200, 200, 0, 0, 200, 200]);
    assert_eq!(texels[5][0], 50, "colour kept");
    // Without map_Kd: a white image carries the mask, and Kd stays the colour.
    let bare = material(&scene, "bare");
    assert_eq!(bare.base_color, Vec3::splat(0.3));
    let white = &scene.textures[bare.base_color_texture.unwrap() as usize];
    assert_eq!(
        white.texels,
        Texels::Srgb8(vec![[255, 255, 255, 0], [255, 255, 255, 200]])
    );
}

#[test]
fn dissolve_without_map_is_opaque_with_a_warning() {
    let dir = tempfile::tempdir().unwrap();
    let scene = load(dir.path(), &["a"], "newmtl a\nd 0.4\n");
    let a = material(&scene, "a");
    assert_eq!(a.alpha_mode, AlphaMode::Opaque);
    assert_eq!(a.alpha, 0.4);
    assert!(scene.warnings.iter().any(|w| w.contains("blend opacity")));
}

#[test]
fn missing_texture_is_a_warning_naming_the_file_and_keeps_kd() {
    let dir = tempfile::tempdir().unwrap();
    let mtl = "newmtl a\nKd 0.1 0.2 0.3\nmap_Kd nowhere.png\nmap_d nomask.png\n";
    let scene = load(dir.path(), &["a"], mtl);
    let a = material(&scene, "a");
    assert_eq!(a.base_color, Vec3::new(0.1, 0.2, 0.3));
    assert_eq!(a.base_color_texture, None);
    assert_eq!(a.alpha_mode, AlphaMode::Opaque);
    assert!(scene.textures.is_empty());
    assert!(
        scene.warnings.iter().any(|w| w.contains("nowhere.png")),
        "{:?}",
        scene.warnings
    );
    assert!(scene.warnings.iter().any(|w| w.contains("nomask.png")));
}

#[test]
fn corrupt_texture_is_a_warning() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("bad.png"), b"\x89PNG not really").unwrap();
    let scene = load(dir.path(), &["a"], "newmtl a\nmap_Kd bad.png\n");
    assert!(scene.textures.is_empty());
    assert!(scene.warnings.iter().any(|w| w.contains("bad.png")));
}

#[test]
fn missing_mtl_is_a_warning_and_faces_get_the_default_material() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("scene.obj");
    std::fs::write(&path, quads_obj(&["a"])).unwrap();
    let scene = scene::obj::load(&path).unwrap();
    assert_eq!(scene.materials.len(), 1);
    assert_eq!(scene.materials[0].name, "default");
    assert_eq!(scene.materials[0].base_color, Vec3::splat(0.8));
    assert!(
        scene.warnings.iter().any(|w| w.contains("scene.mtl")),
        "{:?}",
        scene.warnings
    );
    assert!(scene.warnings.iter().any(|w| w.contains("usemtl a")));
}

#[test]
fn unknown_material_name_is_a_warning() {
    let dir = tempfile::tempdir().unwrap();
    let scene = load(dir.path(), &["a", "ghost"], "newmtl a\nKd 1 0 0\n");
    assert_eq!(scene.triangles.len(), 4);
    assert!(scene.warnings.iter().any(|w| w.contains("usemtl ghost")));
    let ghost_face = &scene.triangles[2];
    assert_eq!(
        scene.materials[ghost_face.material as usize].name,
        "default"
    );
}

#[test]
fn mtl_with_unreadable_lines_keeps_the_rest() {
    let dir = tempfile::tempdir().unwrap();
    let mtl = "newmtl a\nKd spectral x.rfl\nillum two\nNs\nKe 1 1 1\n";
    let scene = load(dir.path(), &["a"], mtl);
    assert_eq!(material(&scene, "a").emission, Vec3::ONE);
    assert_eq!(scene.warnings.len(), 3, "{:?}", scene.warnings);
}

#[test]
fn missing_mask_keeps_the_base_texture_and_is_opaque() {
    let dir = tempfile::tempdir().unwrap();
    write_image(&dir.path().join("c.png"), 1, 1, &[[9, 8, 7, 255]]);
    let scene = load(
        dir.path(),
        &["a"],
        "newmtl a\nmap_Kd c.png\nmap_d gone.png\n",
    );
    let a = material(&scene, "a");
    assert_eq!(a.alpha_mode, AlphaMode::Opaque);
    assert_eq!(a.base_color_texture, Some(0));
    assert!(scene.warnings.iter().any(|w| w.contains("gone.png")));
}
