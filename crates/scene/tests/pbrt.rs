//! pbrt scene files (`scene::pbrt`): what the shipped one holds, pbrt's handedness, both
//! versions' spellings, shapes, materials, textures, lights, instancing and includes, and bad
//! files refused in one line naming where.

use std::path::Path;

use glam::{Vec2, Vec3};
use scene::{AlphaMode, PunctualKind, Scene, Surface};

use crate::files_support::{mangled, refusal, shipped};

/// Writes `text` to `scene.pbrt` in `dir` and loads it.
fn load_in(dir: &Path, text: &str) -> Result<Scene, scene::SceneError> {
    let path = dir.join("scene.pbrt");
    std::fs::write(&path, text).unwrap();
    scene::load(&path)
}

fn load(text: &str) -> Result<Scene, scene::SceneError> {
    load_in(tempfile::tempdir().unwrap().path(), text)
}

/// A camera looking down −z from z = 5, pbrt's way (so the scene is mirrored), then the world.
fn world(body: &str) -> String {
    format!("LookAt 0 0 5  0 0 0  0 1 0\nCamera \"perspective\"\nWorldBegin\n{body}\n")
}

/// An emitting triangle, so that a scene has a light.
const LAMP: &str = "AttributeBegin AreaLightSource \"diffuse\" \"rgb L\" [1 2 3]
    Shape \"trianglemesh\" \"point3 P\" [0 0 -9 1 0 -9 0 1 -9] AttributeEnd";

fn error(text: &str) -> String {
    refusal(load(text), text)
}

/// The geometric normal of triangle `i` (kousen's front: counter-clockwise).
fn front(scene: &Scene, i: usize) -> Vec3 {
    let [a, b, c] = scene.triangles[i].vertices.map(|v| v.position);
    (b - a).cross(c - a).normalize()
}

#[test]
fn the_shipped_cornell_box_loads_as_written() {
    let scene = scene::load(&shipped("pbrt/cornell-box.pbrt")).expect("loads");
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
    let surfaces: Vec<&Surface> = scene.materials.iter().map(|m| &m.surface).collect();
    assert!(surfaces.contains(&&Surface::Dielectric {
        ior: 1.5042,
        thin_walled: false
    }));
    // The metal's width 0.1 given directly, the plastic's from roughness 0.01.
    assert!(surfaces.contains(&&Surface::RoughConductor { alpha: 0.1 }));
    let plastic = scene
        .materials
        .iter()
        .find(|m| matches!(m.surface, Surface::Plastic { .. }))
        .expect("plastic");
    assert_eq!(plastic.base_color, Vec3::new(0.2, 0.3, 0.8));
    assert_eq!(
        plastic.surface,
        scene::coated_surface(1.5, 0.1f32.sqrt()),
        "GGX width 0.1"
    );
    // The light: 0.5 × 0.4 m of radiance (17, 12, 4), facing down.
    assert_eq!(scene.lights.triangles.len(), 2);
    for light in &scene.lights.triangles {
        let i = light.triangle as usize;
        assert!(front(&scene, i).abs_diff_eq(Vec3::NEG_Y, 1e-6));
        let material = &scene.materials[scene.triangles[i].material as usize];
        assert_eq!(material.emission, Vec3::new(17.0, 12.0, 4.0));
        assert!(!material.double_sided);
    }
    let area: f32 = scene.lights.triangles.iter().map(|t| t.area).sum();
    assert!((area - 0.2).abs() < 1e-5, "{area}");
    // The file mirrors its camera to Mitsuba's handedness: the scene is not mirrored.
    let camera = scene.camera(None).unwrap();
    assert!(camera.eye.abs_diff_eq(Vec3::new(0.0, 1.0, 3.8), 1e-5));
    assert!(camera.forward.abs_diff_eq(Vec3::NEG_Z, 1e-6));
    assert!(camera.up.abs_diff_eq(Vec3::Y, 1e-6));
    assert!(camera.right().abs_diff_eq(Vec3::X, 1e-6));
    assert!((camera.yfov.to_degrees() - 40.0).abs() < 1e-3);
    assert_eq!(camera.aspect_ratio, Some(1.0));
    let red = scene
        .materials
        .iter()
        .position(|m| m.name == "red")
        .unwrap() as u32;
    let red_wall = scene.triangles.iter().find(|t| t.material == red).unwrap();
    assert_eq!(red_wall.vertices[0].position.x, -1.0, "red on the left");
}

/// pbrt's camera with `LookAt` alone sees its +x on the image's left: kousen mirrors the whole
/// scene (x → −x), keeping each surface's front, so the image is pbrt's.
#[test]
fn an_unmirrored_camera_mirrors_the_scene_and_keeps_fronts() {
    let text = std::fs::read_to_string(shipped("pbrt/cornell-box.pbrt")).unwrap();
    let mirrored = load(&text.replace("\nScale -1 1 1\n", "\n")).expect("loads");
    let plain = scene::load(&shipped("pbrt/cornell-box.pbrt")).unwrap();
    assert_eq!(mirrored.triangles.len(), plain.triangles.len());
    let flip = |p: Vec3| Vec3::new(-p.x, p.y, p.z);
    for (i, (m, p)) in mirrored.triangles.iter().zip(&plain.triangles).enumerate() {
        // The same triangle, mirrored, wound to face the mirror of its front.
        let positions: Vec<Vec3> = m.vertices.iter().map(|v| v.position).collect();
        for v in &p.vertices {
            assert!(
                positions
                    .iter()
                    .any(|q| q.abs_diff_eq(flip(v.position), 1e-5))
            );
        }
        assert!(front(&mirrored, i).abs_diff_eq(flip(front(&plain, i)), 1e-4));
    }
    let camera = mirrored.camera(None).unwrap();
    assert!(camera.eye.abs_diff_eq(Vec3::new(0.0, 1.0, 3.8), 1e-5));
    // The red wall, at pbrt's x = −1, is at kousen's +1: on the image's right, as in pbrt.
    let red = mirrored
        .materials
        .iter()
        .position(|m| m.name == "red")
        .unwrap() as u32;
    let red_wall = mirrored
        .triangles
        .iter()
        .find(|t| t.material == red)
        .unwrap();
    assert_eq!(red_wall.vertices[0].position.x, 1.0);
}

/// pbrt's rules for a surface's front: a mesh without normals by its winding (turned by
/// `ReverseOrientation` and by a mirroring transform), with normals by them (turned by
/// `ReverseOrientation` only), a quadric by its outward normal (turned by both).
#[test]
fn fronts_follow_pbrt_rules() {
    let lit = |transform: &str, shape: &str| {
        let scene = load(&world(&format!(
            "AttributeBegin {transform} AreaLightSource \"diffuse\" Shape {shape} AttributeEnd"
        )))
        .expect("loads");
        // In kousen's world (x mirrored), the mean front of the emitting triangles.
        (scene.lights.triangles.iter())
            .map(|t| front(&scene, t.triangle as usize))
            .sum::<Vec3>()
            .normalize()
    };
    let triangle = "\"trianglemesh\" \"point3 P\" [0 0 0 1 0 0 0 1 0]";
    let with_normals =
        "\"trianglemesh\" \"point3 P\" [0 0 0 1 0 0 0 1 0] \"normal N\" [0 0 -1 0 0 -1 0 0 -1]";
    let disk = "\"disk\"";
    for (transform, shape, expected) in [
        ("", triangle, Vec3::Z),
        ("ReverseOrientation", triangle, Vec3::NEG_Z),
        ("Scale 1 1 -1", triangle, Vec3::NEG_Z),
        ("Scale 1 1 -1 ReverseOrientation", triangle, Vec3::Z),
        ("", with_normals, Vec3::NEG_Z),
        ("Scale -1 1 1", with_normals, Vec3::NEG_Z),
        ("ReverseOrientation", with_normals, Vec3::Z),
        ("", disk, Vec3::Z),
        ("ReverseOrientation", disk, Vec3::NEG_Z),
        ("Scale 1 1 -1", disk, Vec3::Z),
    ] {
        let seen = lit(transform, shape);
        assert!(
            seen.abs_diff_eq(expected, 1e-4),
            "{transform} {shape}: {seen} against {expected}"
        );
    }
}

/// pbrt-v3's spellings: `matte`, `plastic`, `metal`, `mirror`, `glass`, `uber`, `color`,
/// `float uv`, quoted bools, `point` and `normal`, `WorldEnd`, a two-number black body.
#[test]
fn pbrt_v3_spellings_are_read() {
    let scene = load(&world(
        "MakeNamedMaterial \"a\" \"string type\" \"matte\" \"color Kd\" [0.1 0.2 0.3]
        MakeNamedMaterial \"b\" \"string type\" \"plastic\" \"color Kd\" [0.4 0.5 0.6] \"float roughness\" 0.04
        MakeNamedMaterial \"c\" \"string type\" \"metal\" \"spectrum eta\" \"metal-Au-eta\" \"spectrum k\" \"metal-Au-k\" \"float roughness\" 0
        MakeNamedMaterial \"d\" \"string type\" \"mirror\" \"color Kr\" [0.5 0.5 0.5]
        MakeNamedMaterial \"e\" \"string type\" \"glass\" \"float index\" 1.33 \"color Kt\" [0.9 0.9 1]
        MakeNamedMaterial \"f\" \"string type\" \"uber\" \"color Kd\" [0.7 0.7 0.7] \"bool remaproughness\" \"false\" \"float roughness\" 0.01
        NamedMaterial \"a\" Shape \"trianglemesh\" \"point P\" [0 0 0 1 0 0 0 1 0] \"integer indices\" [0 1 2] \"float uv\" [0 0 1 0 0 1]
        NamedMaterial \"b\" Shape \"sphere\"
        NamedMaterial \"c\" Shape \"sphere\"
        NamedMaterial \"d\" Shape \"sphere\"
        NamedMaterial \"e\" Shape \"sphere\"
        NamedMaterial \"f\" Shape \"sphere\"
        AttributeBegin AreaLightSource \"diffuse\" \"blackbody L\" [6500 2] Shape \"disk\" AttributeEnd
        WorldEnd",
    ))
    .expect("loads");
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
    let material = |name: &str| scene.materials.iter().find(|m| m.name == name).unwrap();
    assert_eq!(material("a").surface, Surface::Diffuse);
    assert_eq!(material("a").base_color, Vec3::new(0.1, 0.2, 0.3));
    // v3's plastic remaps its roughness: α = √0.04 = 0.2, kousen's roughness √α.
    assert_eq!(
        material("b").surface,
        scene::coated_surface(1.5, 0.2f32.sqrt())
    );
    assert_eq!(material("c").surface, Surface::Mirror);
    assert_eq!(material("c").base_color, Vec3::new(1.0, 0.782, 0.344));
    // v3's metal rises to white at grazing angles (Fresnel); its mirror reflects Kr at every
    // angle.
    assert_eq!(material("c").metal_edge, Vec3::ONE);
    assert_eq!(material("d").surface, Surface::Mirror);
    assert_eq!(material("d").metal_edge, Vec3::ZERO);
    assert_eq!(material("e").base_color, Vec3::new(0.9, 0.9, 1.0));
    assert!(matches!(material("e").surface, Surface::Dielectric { ior, .. } if ior == 1.33));
    assert_eq!(material("f").surface, scene::coated_surface(1.5, 0.1));
    // The first triangle's texture coordinates, t turned over.
    let uvs = scene.triangles[0].vertices.map(|v| v.uv);
    assert!(uvs.contains(&Vec2::new(0.0, 1.0)) && uvs.contains(&Vec2::new(0.0, 0.0)));
    // A black body scaled by its peak (v3), times 2: warm white under 2.
    let light = &scene.materials
        [scene.triangles[scene.lights.triangles[0].triangle as usize].material as usize];
    let luminance = light.emission.dot(Vec3::new(0.2126, 0.7152, 0.0722));
    assert!(luminance > 1.0 && luminance < 2.0, "{}", light.emission);
}

/// pbrt-v4's materials: roughness remapped or not, named and sampled spectra, mixtures,
/// coats, diffuse transmission, the invisible interface.
#[test]
fn pbrt_v4_materials_map_onto_kousen() {
    let scene = load(&world(&format!(
        "MakeNamedMaterial \"glass\" \"string type\" \"dielectric\" \"spectrum eta\" \"glass-BAF10\"
        MakeNamedMaterial \"water\" \"string type\" \"dielectric\" \"spectrum eta\" [400 1.34 500 1.336 600 1.333 700 1.331] \"float roughness\" 1e-7
        MakeNamedMaterial \"thin\" \"string type\" \"thindielectric\" \"float eta\" 1.4
        MakeNamedMaterial \"copper\" \"string type\" \"conductor\" \"float roughness\" 0.01
        MakeNamedMaterial \"rgb\" \"string type\" \"conductor\" \"rgb eta\" [0.2 0.9 1.1] \"rgb k\" [3.9 2.4 2.2] \"float roughness\" 0.0016
        MakeNamedMaterial \"coated\" \"string type\" \"coatedconductor\" \"spectrum conductor.eta\" \"metal-Ag-eta\" \"spectrum conductor.k\" \"metal-Ag-k\" \"float interface.roughness\" 0.01
        MakeNamedMaterial \"leaf\" \"string type\" \"diffusetransmission\" \"rgb reflectance\" [0.2 0.4 0.1] \"rgb transmittance\" [0.2 0.4 0.1]
        MakeNamedMaterial \"mix\" \"string type\" \"mix\" \"string materials\" [\"glass\" \"leaf\"] \"float amount\" 0.25
        MakeNamedMaterial \"black\" \"string type\" \"diffuse\" \"rgb reflectance\" [0 0 0]
        MakeNamedMaterial \"leather\" \"string type\" \"mix\" \"string materials\" [\"black\" \"coated\"] \"float amount\" 0.2
        MakeNamedMaterial \"white\" \"string type\" \"coateddiffuse\" \"rgb reflectance\" [1 1 1]
        MakeNamedMaterial \"grey\" \"string type\" \"mix\" \"string materials\" [\"black\" \"white\"] \"float amount\" 0.2
        MakeNamedMaterial \"none\" \"string type\" \"interface\"
        NamedMaterial \"glass\" Shape \"sphere\"
        NamedMaterial \"water\" Shape \"sphere\"
        NamedMaterial \"thin\" Shape \"sphere\"
        NamedMaterial \"copper\" Shape \"sphere\"
        NamedMaterial \"rgb\" Shape \"sphere\"
        NamedMaterial \"coated\" Shape \"sphere\"
        NamedMaterial \"mix\" Shape \"sphere\"
        NamedMaterial \"none\" Shape \"sphere\"
        NamedMaterial \"leather\" Shape \"sphere\"
        NamedMaterial \"grey\" Shape \"sphere\"
        {LAMP}"
    )))
    .expect("loads");
    assert_eq!(
        scene.warnings,
        ["a mix of diffuse materials is read as one, of their mean colour"]
    );
    let last_shape = |k: usize| {
        let sphere = 128 * 63 * 2;
        &scene.materials[scene.triangles[sphere * k].material as usize]
    };
    // Black diffuse 0.8 and a coated silver mirror 0.2: a blend, the mirror first.
    let leather = last_shape(8);
    assert!(leather.clearcoat.is_some() && leather.surface == Surface::Mirror);
    assert!((leather.blend.expect("a blend").weight - 0.2).abs() < 1e-6);
    // Black diffuse 0.8 and white plastic 0.2, both Lambertian: one diffuse of 0.2.
    let grey = last_shape(9);
    assert_eq!((grey.surface, grey.blend), (Surface::Diffuse, None));
    assert!(grey.base_color.abs_diff_eq(Vec3::splat(0.2), 1e-6));
    let material = |name: &str| scene.materials.iter().find(|m| m.name == name).unwrap();
    // Schott's N-BAF10: n_d 1.670, Abbe 47.11: dispersion (n − 1)/V.
    let glass = material("glass");
    assert!(matches!(glass.surface, Surface::Dielectric { ior, .. } if ior == 1.67));
    assert!((glass.dispersion - 0.67 / 47.11).abs() < 1e-6);
    let water = material("water");
    assert!(
        matches!(water.surface, Surface::Dielectric { ior, .. } if (ior - 1.3331).abs() < 1e-3)
    );
    assert!(water.dispersion > 0.0);
    assert!(matches!(
        material("thin").surface,
        Surface::Dielectric {
            thin_walled: true,
            ..
        }
    ));
    // pbrt's default conductor is copper; roughness 0.01 remaps to α = 0.1.
    let copper = material("copper");
    assert_eq!(copper.base_color, Vec3::new(0.955, 0.638, 0.538));
    let alpha = |m: &scene::Material| match m.surface {
        Surface::RoughConductor { alpha } => alpha,
        other => panic!("{other:?}"),
    };
    assert!((alpha(copper) - 0.1).abs() < 1e-6);
    // Fresnel at normal incidence of η + ik; α = √0.0016 = 0.04.
    let rgb = material("rgb");
    let f0 = |n: f32, k: f32| ((n - 1.0).powi(2) + k * k) / ((n + 1.0).powi(2) + k * k);
    assert!(
        rgb.base_color
            .abs_diff_eq(Vec3::new(f0(0.2, 3.9), f0(0.9, 2.4), f0(1.1, 2.2)), 1e-6)
    );
    assert!((alpha(rgb) - 0.04).abs() < 1e-6);
    let coated = material("coated");
    assert!(coated.clearcoat.is_some());
    assert_eq!(coated.base_color, Vec3::new(0.972, 0.960, 0.915));
    let leaf = material("leaf");
    let transmission = leaf.diffuse_transmission.expect("transmits");
    assert!((transmission.factor - 0.5).abs() < 1e-6);
    assert!(leaf.base_color.abs_diff_eq(Vec3::new(0.4, 0.8, 0.2), 1e-6));
    // The mix: glass drawn with probability 0.75, the leaf (Lambertian, last) with 0.25.
    let mixed = scene
        .materials
        .iter()
        .position(|m| m.blend.is_some())
        .expect("a blend");
    let blend = scene.materials[mixed].blend.unwrap();
    assert!(matches!(
        scene.materials[mixed].surface,
        Surface::Dielectric { .. }
    ));
    assert!((blend.weight - 0.75).abs() < 1e-6);
    assert!(
        scene.materials[blend.other as usize]
            .diffuse_transmission
            .is_some()
    );
    let none = material("none");
    assert_eq!(none.alpha, 0.0);
    assert!(matches!(none.alpha_mode, AlphaMode::Mask { .. }));
}

/// Image textures: the colour image's scale and uv mapping, t turned over, an alpha cut-out
/// from a float texture, a normal map; a texture by reference in a `scale`.
#[test]
fn textures_map_images_as_pbrt_does() {
    let dir = tempfile::tempdir().unwrap();
    let image = image::RgbaImage::from_fn(4, 2, |x, _| image::Rgba([x as u8 * 60, 100, 200, 255]));
    image.save(dir.path().join("colour.png")).unwrap();
    let mask = image::GrayImage::from_fn(4, 2, |x, _| image::Luma([if x < 2 { 0 } else { 255 }]));
    mask.save(dir.path().join("mask.png")).unwrap();
    let scene = load_in(
        dir.path(),
        &world(&format!(
            "Texture \"c\" \"spectrum\" \"imagemap\" \"string filename\" \"colour.png\" \"float uscale\" 2 \"float vdelta\" 0.5
            Texture \"half\" \"spectrum\" \"scale\" \"texture tex\" \"c\" \"float scale\" 0.5
            Texture \"m\" \"float\" \"imagemap\" \"string filename\" \"mask.png\"
            Material \"diffuse\" \"texture reflectance\" \"half\" \"string normalmap\" \"colour.png\"
            Shape \"trianglemesh\" \"point3 P\" [0 0 0 1 0 0 0 1 0] \"point2 uv\" [0 0 1 0 0 1] \"texture alpha\" \"m\"
            {LAMP}"
        )),
    )
    .expect("loads");
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
    let triangle = scene
        .triangles
        .iter()
        .find(|t| scene.materials[t.material as usize].emission == Vec3::ZERO)
        .unwrap();
    let material = &scene.materials[triangle.material as usize];
    assert_eq!(material.base_color, Vec3::splat(0.5));
    assert!(matches!(material.alpha_mode, AlphaMode::Mask { .. }));
    assert!(material.normal_texture.is_some());
    let texture = &scene.textures[material.base_color_texture.unwrap() as usize];
    // The colour image with the mask's alpha (nearest texel).
    assert_eq!(texture.texel_linear(0, 0).w, 0.0);
    assert_eq!(texture.texel_linear(3, 0).w, 1.0);
    // (s, t) → (2s, t + ½) → (2s, 1 − t − ½).
    let uvs = triangle.vertices.map(|v| v.uv);
    for expected in [
        Vec2::new(0.0, 0.5),
        Vec2::new(2.0, 0.5),
        Vec2::new(0.0, -0.5),
    ] {
        assert!(uvs.contains(&expected), "{uvs:?} lacks {expected}");
    }
}

#[test]
fn lights_are_placed_and_scaled_as_pbrt_places_them() {
    let scene = load(&world(&format!(
        "AttributeBegin Translate 1 2 3
            LightSource \"point\" \"rgb I\" [1 2 3] \"point3 from\" [1 0 0] \"float scale\" 2
        AttributeEnd
        LightSource \"spot\" \"blackbody I\" 3000 \"point3 from\" [0 5 0] \"point3 to\" [0 0 0] \"float coneangle\" 20 \"float conedeltaangle\" 5 \"float power\" 100
        LightSource \"distant\" \"rgb L\" [1 1 1] \"point3 from\" [1 1 0] \"point3 to\" [0 0 0] \"float illuminance\" 3
        LightSource \"infinite\" \"rgb L\" [0.1 0.2 0.3]
        AttributeBegin AreaLightSource \"diffuse\" \"float power\" 10 \"bool twosided\" true
            Shape \"trianglemesh\" \"point3 P\" [0 0 0 2 0 0 0 2 0] AttributeEnd
        {LAMP}"
    )))
    .expect("loads");
    assert!(
        scene.warnings.iter().all(|w| w.contains("smoothstep")),
        "{:?}",
        scene.warnings
    );
    let lights: Vec<_> = scene.lights.punctual.iter().map(|p| p.light).collect();
    // Mirrored: pbrt's (2, 2, 3) is kousen's (−2, 2, 3).
    assert_eq!(lights[0].kind, PunctualKind::Point);
    assert!(
        lights[0]
            .position
            .abs_diff_eq(Vec3::new(-2.0, 2.0, 3.0), 1e-6)
    );
    assert_eq!(lights[0].intensity, Vec3::new(2.0, 4.0, 6.0));
    let PunctualKind::Spot {
        cos_inner,
        cos_outer,
        falloff,
    } = lights[1].kind
    else {
        panic!("{:?}", lights[1].kind)
    };
    // pbrt's spot falls off by smoothstep in the cosine.
    assert_eq!(falloff, scene::SpotFalloff::Smoothstep);
    assert!((cos_outer - 20f32.to_radians().cos()).abs() < 1e-6);
    assert!((cos_inner - 15f32.to_radians().cos()).abs() < 1e-6);
    assert!(lights[1].direction.abs_diff_eq(Vec3::NEG_Y, 1e-6));
    // Power 100 over pbrt's cone: 2π((1 − cos 15°) + (cos 15° − cos 20°)/2) sr at luminance 1.
    let solid = std::f32::consts::TAU * ((1.0 - cos_inner) + (cos_inner - cos_outer) / 2.0);
    let luminance = lights[1].intensity.dot(Vec3::new(0.2126, 0.7152, 0.0722));
    assert!(
        (luminance * solid / 100.0 - 1.0).abs() < 0.02,
        "{luminance}"
    );
    assert!(lights[1].intensity.x > lights[1].intensity.z, "a warm spot");
    // Light travels from `from` to `to`, mirrored.
    assert_eq!(lights[2].kind, PunctualKind::Directional);
    assert!(
        lights[2]
            .direction
            .abs_diff_eq(Vec3::new(1.0, -1.0, 0.0).normalize(), 1e-6)
    );
    assert_eq!(lights[2].intensity, Vec3::splat(3.0));
    let sky = scene.lights.sky.as_ref().expect("a sky");
    assert_eq!(sky.radiance, Vec3::new(0.1, 0.2, 0.3));
    // 10 W over a two-sided triangle of area 2: radiance 10 / (π · 2 · 2).
    let lamp = scene
        .lights
        .triangles
        .iter()
        .find(|t| (t.area - 2.0).abs() < 1e-5)
        .unwrap();
    let material = &scene.materials[scene.triangles[lamp.triangle as usize].material as usize];
    assert!(material.double_sided);
    let expected = 10.0 / (std::f32::consts::PI * 4.0);
    assert!(
        material.emission.abs_diff_eq(Vec3::splat(expected), 1e-6),
        "{}",
        material.emission
    );
}

/// An equal-area sky image (pbrt-v4's) and a latitude–longitude one (pbrt-v3's) resampled
/// into kousen's sky: each direction sees what pbrt's lookup gives, through the light's
/// transform and the scene's mirror.
#[test]
fn sky_images_face_as_pbrt_turns_them() {
    let dir = tempfile::tempdir().unwrap();
    // Texels coloured by their quadrant: u < ½ red, else green; v < ½ no blue, else blue.
    let colour = |u: f32, v: f32| {
        Vec3::new(
            (u < 0.5) as u8 as f32,
            (u >= 0.5) as u8 as f32,
            (v >= 0.5) as u8 as f32,
        )
    };
    let write = |name: &str, w: u32, h: u32| {
        let pixels = image::Rgb32FImage::from_fn(w, h, |x, y| {
            let c = colour((x as f32 + 0.5) / w as f32, (y as f32 + 0.5) / h as f32);
            image::Rgb(c.to_array())
        });
        image::DynamicImage::ImageRgb32F(pixels)
            .save(dir.path().join(name))
            .unwrap();
    };
    write("square.exr", 64, 64);
    write("wide.exr", 128, 64);
    let sees = |file: &str, transform: &str, direction: Vec3| {
        let scene = load_in(
            dir.path(),
            &world(&format!(
                "AttributeBegin {transform} LightSource \"infinite\" \"string filename\" \"{file}\" AttributeEnd {LAMP}"
            )),
        )
        .expect("loads");
        let map = scene.lights.sky.as_ref().unwrap().map.clone().unwrap();
        let (u, v) = scene::sky_map::map_coordinates(direction.normalize());
        map.radiance_at(u, v)
    };
    // pbrt's +x (kousen's −x) at the middle of the equal-area square's right edge: green;
    // its +y at the bottom edge's middle: blue; −x red, −y not blue.
    let near = |a: Vec3, b: Vec3| a.abs_diff_eq(b, 1e-3);
    let green_x = sees("square.exr", "", Vec3::new(-1.0, 0.1, 0.3));
    assert!(near(green_x, Vec3::new(0.0, 1.0, 1.0)), "{green_x}");
    let red_x = sees("square.exr", "", Vec3::new(1.0, -0.1, 0.3));
    assert!(near(red_x, Vec3::new(1.0, 0.0, 0.0)), "{red_x}");
    // Turned 90° about z: pbrt's +y sees what +x saw.
    let turned = sees("square.exr", "Rotate 90 0 0 1", Vec3::new(0.1, 1.0, 0.3));
    assert!(near(turned, Vec3::new(0.0, 1.0, 1.0)), "{turned}");
    // Latitude–longitude: u from +x about +z, v from +z down. pbrt's (0, 1, 0.3) has u = ¼
    // (red), v < ½; (0, −1, −0.3) u = ¾ (green), v > ½.
    let up = sees("wide.exr", "", Vec3::new(0.0, 1.0, 0.3));
    assert!(near(up, Vec3::new(1.0, 0.0, 0.0)), "{up}");
    let down = sees("wide.exr", "", Vec3::new(0.0, -1.0, -0.3));
    assert!(near(down, Vec3::new(0.0, 1.0, 1.0)), "{down}");

    // A white map scaled by `illuminance` π lights a surface facing the light's +z with π:
    // radiance 1 (the resampling's quadrature within 1 %), turned to kousen's +y or not.
    let pixels = image::Rgb32FImage::from_pixel(32, 32, image::Rgb([2.0, 2.0, 2.0]));
    image::DynamicImage::ImageRgb32F(pixels)
        .save(dir.path().join("white.exr"))
        .unwrap();
    for turn in ["", "Rotate -90 1 0 0"] {
        let scene = load_in(
            dir.path(),
            &world(&format!(
                "AttributeBegin {turn} LightSource \"infinite\" \"string filename\" \"white.exr\" \"float illuminance\" 3.14159265 AttributeEnd {LAMP}"
            )),
        )
        .expect("loads");
        let map = scene.lights.sky.as_ref().unwrap().map.clone().unwrap();
        let seen = map.radiance_at(0.3, 0.6);
        assert!(
            (seen - Vec3::ONE).abs().max_element() < 0.01,
            "{turn}: {seen}"
        );
    }
}

/// Object instances placed twice; included files read in place, relative to the main file;
/// `Import` keeps its state changes to itself; `CoordSysTransform "camera"`.
#[test]
fn instances_and_includes_are_read() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::create_dir(dir.path().join("parts")).unwrap();
    std::fs::write(
        dir.path().join("parts/object.pbrt"),
        "ObjectBegin \"tri\" Translate 0 0 1 Shape \"trianglemesh\" \"point3 P\" [0 0 0 1 0 0 0 1 0] ObjectEnd",
    )
    .unwrap();
    std::fs::write(
        dir.path().join("parts/state.pbrt"),
        "Material \"conductor\"",
    )
    .unwrap();
    let scene = load_in(
        dir.path(),
        &world(&format!(
            "Include \"parts/object.pbrt\"
            Import \"parts/state.pbrt\"
            AttributeBegin Translate 10 0 0 ObjectInstance \"tri\" AttributeEnd
            AttributeBegin Translate 20 0 0 ObjectInstance \"tri\" AttributeEnd
            AttributeBegin CoordSysTransform \"camera\" LightSource \"point\" AttributeEnd
            {LAMP}"
        )),
    )
    .expect("loads");
    let placed: Vec<Vec3> = scene.triangles[..2]
        .iter()
        .map(|t| t.vertices[0].position)
        .collect();
    // pbrt's (10, 0, 1) and (20, 0, 1), mirrored; diffuse (the Import's material stays there).
    assert!(
        placed.contains(&Vec3::new(-10.0, 0.0, 1.0))
            && placed.contains(&Vec3::new(-20.0, 0.0, 1.0)),
        "{placed:?}"
    );
    assert_eq!(
        scene.materials[scene.triangles[0].material as usize].surface,
        Surface::Diffuse
    );
    // The camera's coordinate system: the point light sits at the eye.
    let light = scene.lights.punctual[0].light;
    assert!(
        light.position.abs_diff_eq(Vec3::new(0.0, 0.0, 5.0), 1e-5),
        "{}",
        light.position
    );
}

#[test]
fn ply_meshes_and_quadrics_are_shapes() {
    use std::io::Write;
    let dir = tempfile::tempdir().unwrap();
    let ply = "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\n\
        property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n\
        0 0 0\n1 0 0\n1 1 0\n0 1 0\n4 0 1 2 3\n";
    let mut gz = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::default());
    gz.write_all(ply.as_bytes()).unwrap();
    std::fs::write(dir.path().join("quad.ply.gz"), gz.finish().unwrap()).unwrap();
    let scene = load_in(
        dir.path(),
        &world(&format!(
            "Shape \"plymesh\" \"string filename\" \"quad.ply.gz\"
            Shape \"bilinearmesh\" \"point3 P\" [0 0 0 1 0 0 0 1 0 1 1 0]
            Shape \"cylinder\" \"float radius\" 0.5
            Shape \"disk\" \"float innerradius\" 0.5 \"float height\" 2
            {LAMP}"
        )),
    )
    .expect("loads");
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
    let area = |range: std::ops::Range<usize>| -> f32 {
        scene.triangles[range]
            .iter()
            .map(|t| {
                let [a, b, c] = t.vertices.map(|v| v.position);
                (b - a).cross(c - a).length() / 2.0
            })
            .sum()
    };
    assert!((area(0..2) - 1.0).abs() < 1e-6, "the PLY quad");
    assert!((area(2..4) - 1.0).abs() < 1e-6, "the bilinear patch");
    let pi = std::f32::consts::PI;
    assert!(
        (area(4..260) / (2.0 * pi) - 1.0).abs() < 1e-3,
        "the cylinder: 2π r h"
    );
    assert!(
        (area(260..516) / (0.75 * pi) - 1.0).abs() < 1e-3,
        "the annulus"
    );
    assert!(
        scene.triangles[300]
            .vertices
            .iter()
            .all(|v| v.position.z == 2.0)
    );
}

/// `loopsubdiv` subdivides its control mesh (an octahedron here) by Loop's rules, `levels`
/// times, with smooth normals facing as the control mesh's winding does.
#[test]
fn loop_subdivision_surfaces_are_subdivided() {
    let scene = load(&world(&format!(
        "Shape \"loopsubdiv\" \"integer levels\" 2
            \"point3 P\" [1 0 0 -1 0 0 0 1 0 0 -1 0 0 0 1 0 0 -1]
            \"integer indices\" [0 2 4 2 1 4 1 3 4 3 0 4 2 0 5 1 2 5 3 1 5 0 3 5]
        {LAMP}"
    )))
    .expect("loads");
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
    let surface = &scene.triangles[..scene.triangles.len() - 1];
    assert_eq!(surface.len(), 8 * 16);
    for v in surface.iter().flat_map(|t| t.vertices) {
        assert!(v.position.length() < 1.0 && v.position.length() > 0.35);
        assert!(v.normal.dot(v.position) > 0.0, "faces out");
    }
}

/// Unread parameters, materials and shapes are warned about, as pbrt warns.
#[test]
fn what_is_not_read_is_warned_about() {
    let scene = load(&world(&format!(
        "Material \"diffuse\" \"float glow\" 3 Shape \"sphere\"
        Material \"hair\" Shape \"sphere\"
        Shape \"curve\" \"point3 P\" [0 0 0 1 1 1 2 2 2 3 3 3]
        MakeNamedMedium \"fog\" \"string type\" \"homogeneous\"
        {LAMP}"
    )))
    .expect("loads");
    let all = scene.warnings.join("\n");
    for expected in [
        "\"float glow\"",
        "\"hair\" is read as diffuse",
        "shape \"curve\"",
        "medium \"fog\" fills no shape",
    ] {
        assert!(all.contains(expected), "{expected}: {all}");
    }
}

/// Homogeneous media named by `MediumInterface` fill the shapes made after it: glass keeps its
/// surface and takes the medium's absorption and scattering (`sigma_a` and `sigma_s` ×
/// `scale`) and its `g`; an `interface` becomes glass of index 1. Media of other kinds, of
/// other surfaces and outside shapes are warned about.
#[test]
fn interior_media_fill_solids() {
    let scene = load(&world(&format!(
        "MakeNamedMedium \"milk\" \"string type\" \"homogeneous\" \"rgb sigma_a\" [0.5 1 2]
            \"rgb sigma_s\" [4 5 6] \"float scale\" 2 \"float g\" 0.5
        MakeNamedMedium \"smoke\" \"string type\" \"homogeneous\" \"float sigma_a\" 0.25 \"float sigma_s\" 1
        MakeNamedMedium \"cloud\" \"string type\" \"cloud\"
        AttributeBegin MediumInterface \"milk\" \"\" Material \"dielectric\" Shape \"sphere\" AttributeEnd
        AttributeBegin MediumInterface \"smoke\" \"\" Material \"interface\"
            Shape \"trianglemesh\" \"point3 P\" [0 0 0 1 0 0 0 1 0] \"integer indices\" [0 1 2]
        AttributeEnd
        AttributeBegin MediumInterface \"smoke\" \"\" Material \"diffuse\" Shape \"disk\" AttributeEnd
        AttributeBegin MediumInterface \"cloud\" \"\" Material \"dielectric\" Shape \"disk\" AttributeEnd
        {LAMP}"
    )))
    .expect("loads");
    let milk = &scene.materials[scene.triangles[0].material as usize];
    assert!(matches!(
        milk.surface,
        Surface::Dielectric {
            thin_walled: false,
            ..
        }
    ));
    assert_eq!(milk.absorption, Vec3::new(1.0, 2.0, 4.0));
    assert_eq!(milk.scattering, Vec3::new(8.0, 10.0, 12.0));
    assert_eq!(milk.scatter_anisotropy, 0.5);
    let fog: Vec<_> = (scene.materials.iter())
        .filter(|m| {
            m.surface
                == Surface::Dielectric {
                    ior: 1.0,
                    thin_walled: false,
                }
        })
        .collect();
    assert_eq!(fog.len(), 1, "{:?}", scene.materials);
    assert_eq!(
        (fog[0].absorption, fog[0].scattering),
        (Vec3::splat(0.25), Vec3::ONE)
    );
    assert_eq!((fog[0].alpha, fog[0].base_color), (1.0, Vec3::ONE));
    let all = scene.warnings.join("\n");
    for expected in [
        "medium \"smoke\" is read inside solid glass or an interface only",
        "medium \"cloud\" of type \"cloud\" is not read",
    ] {
        assert!(all.contains(expected), "{expected}: {all}");
    }
    assert_eq!(scene.warnings.len(), 2, "{all}");
    // One name is both sides: the shapes bound nothing, and the medium is the air's.
    let immersed = load(&world(&format!(
        "MakeNamedMedium \"fog\" \"string type\" \"homogeneous\"
        MediumInterface \"fog\" Material \"dielectric\" Shape \"sphere\" {LAMP}"
    )))
    .expect("loads");
    assert!(
        immersed
            .materials
            .iter()
            .all(|m| m.scattering == Vec3::ZERO)
    );
    let all = immersed.warnings.join("\n");
    assert!(all.contains("medium \"fog\" fills no shape"), "{all}");
    assert_eq!(immersed.atmosphere, None);
    assert!(
        error(&world("MediumInterface \"nowhere\" \"\" Shape \"sphere\""))
            .contains("no medium is named")
    );
}

/// What real scenes (pbrt-v4-scenes) do: name a material before the file defines it, give a
/// conductor's η and k as spectrum files, texture a diffuse transmission, hide an area light's
/// sphere with an alpha of 0, use one texture name for a float and a spectrum texture.
#[test]
fn what_real_scenes_do_is_read() {
    let dir = tempfile::tempdir().unwrap();
    // Silver-like η and k at three wavelengths (flat: F0 = ((η−1)² + k²)/((η+1)² + k²)).
    std::fs::write(
        dir.path().join("eta.spd"),
        "# eta\n400 0.15\n550 0.15\n700 0.15\n",
    )
    .unwrap();
    std::fs::write(dir.path().join("k.spd"), "400 3.5 550 3.5 700 3.5").unwrap();
    image::RgbImage::from_pixel(2, 2, image::Rgb([200, 100, 50]))
        .save(dir.path().join("leaf.png"))
        .unwrap();
    let scene = load_in(
        dir.path(),
        &world(&format!(
            "NamedMaterial \"later\" Shape \"sphere\"
            MakeNamedMaterial \"later\" \"string type\" \"conductor\" \"spectrum eta\" \"eta.spd\" \"spectrum k\" \"k.spd\"
            Texture \"leaf\" \"spectrum\" \"imagemap\" \"string filename\" \"leaf.png\"
            Texture \"leaf\" \"float\" \"constant\" \"float value\" 0.04
            Material \"diffusetransmission\" \"texture reflectance\" \"leaf\" \"texture transmittance\" \"leaf\"
            Shape \"trianglemesh\" \"point3 P\" [0 0 0 1 0 0 0 1 0]
            Material \"conductor\" \"rgb reflectance\" [1 1 1] \"texture roughness\" \"leaf\" \"bool remaproughness\" false
            Shape \"sphere\"
            AttributeBegin AreaLightSource \"diffuse\" Shape \"sphere\" \"float alpha\" 0 AttributeEnd
            {LAMP}"
        )),
    )
    .expect("loads");
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
    let material = |i: usize| &scene.materials[scene.triangles[i].material as usize];
    // The sphere made once its material was read (after the rest of the file).
    let metal = scene
        .materials
        .iter()
        .find(|m| m.name == "later")
        .expect("made");
    let f0 = (0.85f32 * 0.85 + 12.25) / (1.15 * 1.15 + 12.25);
    assert!(
        metal.base_color.abs_diff_eq(Vec3::splat(f0), 1e-3),
        "{}",
        metal.base_color
    );
    let leaf = material(0);
    assert!(leaf.base_color_texture.is_some() && leaf.diffuse_transmission.is_some());
    // Reflectance and transmittance of one image: half each of an albedo of the image (their
    // sum, 2 × the image, is more than a surface can return: clamped to 1 × it).
    assert_eq!(leaf.base_color, Vec3::ONE);
    assert_eq!(leaf.diffuse_transmission.unwrap().factor, 0.5);
    // The float "leaf" (0.04) is the roughness; the spectrum "leaf" the colour.
    let rough = scene
        .materials
        .iter()
        .find(|m| matches!(m.surface, Surface::RoughConductor { .. }));
    let Surface::RoughConductor { alpha } = rough.expect("rough metal").surface else {
        unreachable!()
    };
    assert!((alpha - 0.04).abs() < 1e-6, "{alpha}");
    // The hidden sphere emits nothing: the lamp's triangle is the only light.
    assert_eq!(scene.lights.triangles.len(), 1);

    let message = refusal(
        load(&world("NamedMaterial \"never\"\nShape \"sphere\"")),
        "never",
    );
    assert!(
        message.contains("line 5: Shape: no material is named \"never\""),
        "{message}"
    );
}

/// Procedural textures read as their means take pbrt's defaults: a mix of nothing given
/// is 0 and 1 mixed by its amount, a checkerboard's squares 1 and 0.
#[test]
fn procedural_textures_are_read_as_their_means() {
    let scene = load(&world(&format!(
        "Texture \"m\" \"spectrum\" \"mix\" \"float amount\" 0.25
        Texture \"c\" \"spectrum\" \"checkerboard\" \"rgb tex2\" [0.2 0.4 0.6]
        Material \"diffuse\" \"texture reflectance\" \"m\" Shape \"trianglemesh\" \"point3 P\" [0 0 0 1 0 0 0 1 0]
        Material \"diffuse\" \"texture reflectance\" \"c\" Shape \"trianglemesh\" \"point3 P\" [0 0 0 1 0 0 0 1 0]
        {LAMP}"
    )))
    .expect("loads");
    let colour = |i: usize| scene.materials[scene.triangles[i].material as usize].base_color;
    assert!(
        colour(0).abs_diff_eq(Vec3::splat(0.25), 1e-6),
        "{}",
        colour(0)
    );
    assert!(
        colour(1).abs_diff_eq(Vec3::new(0.6, 0.7, 0.8), 1e-6),
        "{}",
        colour(1)
    );
    assert_eq!(scene.warnings.len(), 2, "{:?}", scene.warnings);
}

/// What changes pbrt's image but not the scene is warned about: the film's ISO (with the
/// exposure that matches it), media.
#[test]
fn film_and_media_settings_are_warned_about() {
    let scene = load(&format!(
        "Film \"rgb\" \"float iso\" 400 \"float maxcomponentvalue\" 10 \"string filename\" \"x.exr\"
        Camera \"perspective\"
        WorldBegin MediumInterface \"\" \"fog\" {LAMP}"
    ))
    .expect("loads");
    let all = scene.warnings.join("\n");
    for expected in [
        "4× the radiance",
        "--exposure 2.00",
        "\"float maxcomponentvalue\"",
    ] {
        assert!(all.contains(expected), "{expected}: {all}");
    }
}

/// The camera's medium (the outside one where `Camera` is declared), where no shape is filled
/// with it, fills all space outside the solids: the scene's atmosphere, which keeps the
/// infinite light from the scene (warned). Where a shape is filled with it, the camera's place
/// decides (no atmosphere).
#[test]
fn the_camera_s_medium_no_shape_bounds_is_the_atmosphere() {
    let fog =
        "MakeNamedMedium \"fog\" \"string type\" \"homogeneous\" \"rgb sigma_a\" [0.1 0.1 0.1]
        \"rgb sigma_s\" [0.3 0.3 0.3] \"float g\" 0.2
        MediumInterface \"\" \"fog\"
        LookAt 0 0 5  0 0 0  0 1 0 Camera \"perspective\"
        WorldBegin";
    let scene = load(&format!(
        "{fog}
        MediumInterface \"\" \"fog\" Material \"dielectric\" Shape \"sphere\"
        LightSource \"infinite\" \"rgb L\" [0.1 0.2 0.3]
        {LAMP}"
    ))
    .expect("loads");
    let atmosphere = scene.atmosphere.expect("an atmosphere");
    let air = &scene.materials[atmosphere as usize];
    assert!(air.has_murky_glass());
    assert!(air.absorption.abs_diff_eq(Vec3::splat(0.1), 1e-6));
    assert!(air.scattering.abs_diff_eq(Vec3::splat(0.3), 1e-6));
    assert_eq!(air.scatter_anisotropy, 0.2);
    assert!(scene.triangles.iter().all(|t| t.material != atmosphere));
    let sky = scene.lights.sky.as_ref().expect("a sky");
    assert_eq!((sky.radiance, sky.power), (Vec3::ZERO, Vec3::ZERO));
    let all = scene.warnings.join("\n");
    assert!(all.contains("hides the sky"), "{all}");
    assert_eq!(scene.warnings.len(), 1, "{all}");

    let bounded = load(&format!(
        "{fog}
        MediumInterface \"fog\" \"\" Material \"interface\" Shape \"sphere\" \"float radius\" 9
        {LAMP}"
    ))
    .expect("loads");
    assert_eq!(bounded.atmosphere, None);
    assert!(bounded.warnings.is_empty(), "{:?}", bounded.warnings);
}

#[test]
fn bad_files_are_refused_in_one_line_naming_the_line() {
    for (text, why) in [
        (
            "WorldBegin\nFrobnicate",
            "line 2: unknown directive \"Frobnicate\"",
        ),
        (
            "WorldBegin\nShape \"sphere\" \"float radius\" [1",
            "a [ is not closed",
        ),
        (
            "WorldBegin\n\nShape \"sphere\" \"float radius\" -1",
            "line 3: Shape: \"radius\" -1 is not positive",
        ),
        (
            "WorldBegin NamedMaterial \"x\" Shape \"sphere\"",
            "no material is named \"x\"",
        ),
        ("WorldBegin Include \"missing.pbrt\"", "missing.pbrt"),
        ("WorldBegin AttributeEnd", "without a matching begin"),
        ("WorldBegin ObjectInstance \"x\"", "no object \"x\""),
        ("Rotate 90 0 0 0", "the axis has no length"),
        ("Shape \"sphere\"", "Shape: before WorldBegin"),
        (
            "WorldBegin Camera \"perspective\"",
            "Camera: after WorldBegin",
        ),
        ("LookAt 0 0 0 0 0 0 0 1 0", "leave no view"),
        (
            "WorldBegin Shape \"trianglemesh\" \"point3 P\" [0 0 0 1 0 0]",
            "needs \"integer indices\"",
        ),
        (
            "WorldBegin MakeNamedMaterial \"m\" \"string type\" \"mix\" \"string materials\" [\"m\" \"m\"] NamedMaterial \"m\" Shape \"sphere\"",
            "nested too deep",
        ),
        (
            "WorldBegin Shape \"plymesh\"",
            "needs a \"string filename\"",
        ),
        ("\"float fov\" 3", "expected a directive"),
        ("WorldBegin", "no triangles"),
    ] {
        let message = error(text);
        assert!(message.contains(why), "{why}: {message}");
        assert!(
            message.contains("scene.pbrt") || message.contains("missing.pbrt"),
            "{message}"
        );
    }
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("loop.pbrt"), "Include \"loop.pbrt\"").unwrap();
    let message = load_in(dir.path(), "WorldBegin Include \"loop.pbrt\"")
        .err()
        .unwrap()
        .to_string();
    assert!(
        message.contains("loop.pbrt: line 1: Include: files included too deep"),
        "{message}"
    );
}

/// The shipped box cut short and with bytes changed at random: every copy loads or is
/// refused in one line, none panics.
#[test]
fn mangled_files_never_panic() {
    let original = std::fs::read(shipped("pbrt/cornell-box.pbrt")).unwrap();
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("scene.pbrt");
    for bytes in mangled(&original, 200, b"[]\"#-0.e9x \n") {
        std::fs::write(&path, &bytes).unwrap();
        if let Err(e) = scene::load(&path) {
            assert!(!e.to_string().contains('\n'), "{e}");
        }
    }
}
