//! glTF's metallic-roughness texture (`scene::RoughnessMap`) against the factors it stands
//! for: where the texture reads the same everywhere, a render must be the render of the
//! untextured blend glTF's factors would make, bit for bit (the same random numbers are drawn
//! and the same surfaces met), the factors being the texel as the texture array keeps it. The
//! texel picks each lobe's surface: mirror or rough metal, plastic or Lambertian coat, clear or
//! frosted glass. The same holds for glTF's transmission texture
//! (`scene::Material::transmission_texture`), which weighs a blend's glass member by its red.

use glam::Vec2;
use render::textures::{DEFAULT_MAX_SIDE, TextureArray};
use render::{Budget, Image, Settings, Sppm};
use scene::{Scene, Texels, metal_surface, testing};

fn render(scene: &Scene) -> Image {
    let bvh = bvh::PackedBvh::build(&scene.triangles, &bvh::BuildOptions::default());
    let camera = scene.camera(None).unwrap();
    let backend = cpu::CpuBackend::new(cpu::SceneData::new(scene, bvh));
    let settings = Settings {
        seed: 3,
        eye_every: 2,
        ..Settings::new(24, 24, 4096)
    };
    let mut sppm = Sppm::new(backend, scene, &camera, settings).unwrap();
    sppm.run(Budget::Passes(6), &mut |_| {}).unwrap().image
}

/// `testing::cornell_metallic_roughness` whose texture reads (`green`, `blue`) everywhere,
/// and the id of its tiled material (the metal, first of its blend).
fn uniform(green: u8, blue: u8) -> (Scene, usize) {
    let mut scene = testing::cornell_metallic_roughness();
    let Texels::LinearF32(texels) = &mut scene.textures[0].texels else {
        panic!("the tiles are linear data");
    };
    for texel in texels.iter_mut() {
        *texel = [0.0, f32::from(green) / 255.0, f32::from(blue) / 255.0, 1.0];
    }
    // The roughness range the loader would find (as the texture array keeps the texel).
    let roughness = stored_texel(&scene).y;
    for material in &mut scene.materials {
        if let Some(map) = &mut material.roughness_map {
            map.roughness_range = [roughness; 2];
        }
    }
    let tiled = (scene.materials.iter())
        .position(|m| m.roughness_map.is_some())
        .expect("a mapped material");
    (scene, tiled)
}

/// The uniform texture's texel as the renderers' texture array stores it (8 bits in sRGB's
/// encoding).
fn stored_texel(scene: &Scene) -> glam::Vec4 {
    TextureArray::build(&scene.textures, DEFAULT_MAX_SIDE).sample(0, Vec2::splat(0.3))
}

/// [`uniform`] with the texture gone: the metal's weight is the metalness, its surface glTF's
/// metal at that roughness, the coat plastic at that roughness (smooth below 0.01, Lambertian
/// from 0.5), the glass smooth below roughness 0.01 and frosted above (the texel as the
/// renderers' texture array stores it).
fn factored(green: u8, blue: u8) -> Scene {
    let (mut scene, metal) = uniform(green, blue);
    let texel = stored_texel(&scene);
    let roughness = texel.y;
    let blend = scene.materials[metal].blend.as_mut().unwrap();
    blend.weight = texel.z;
    let coat = blend.other as usize;
    scene.materials[metal].surface = metal_surface(roughness);
    scene.materials[coat].surface = scene::coated_surface(1.5, roughness);
    let glass = (scene.materials.iter())
        .position(|m| m.name == "tiled glass")
        .expect("the mapped glass sphere");
    scene.materials[glass].surface = scene::glass_surface(1.5, false, roughness);
    for id in [metal, coat, glass] {
        scene.materials[id].roughness_map = None;
    }
    scene
}

#[test]
fn a_uniform_texture_renders_as_the_factors_it_reads() {
    // Brushed metal over glossy plastic, frosted glass; a polished mirror over a smooth coat,
    // clear glass; rough metal over a matte (Lambertian) coat, very frosted glass.
    for (green, blue) in [(64, 153), (0, 102), (200, 51)] {
        let (textured, _) = uniform(green, blue);
        let image = render(&textured);
        assert!(image.pixels.iter().any(|p| p.max_element() > 0.0));
        assert_eq!(
            image,
            render(&factored(green, blue)),
            "texel ({green}, {blue}) renders otherwise than its factors"
        );
        // And the texel matters: another one gives another image.
        let (other, _) = uniform(blue, green);
        assert_ne!(image, render(&other), "texel ({green}, {blue}) swapped");
    }
}

/// The ids of `testing::cornell_blended`'s sphere of 60 % glass and 40 % plastic: its glass
/// member (first) and its plastic one.
fn milky_members(scene: &Scene) -> [usize; 2] {
    let glass = (scene.materials.iter())
        .position(|m| m.name == "glass and plastic" && m.surface.is_glass())
        .expect("the milky sphere's glass");
    let plastic = scene.materials[glass].blend.expect("a blend").other as usize;
    [glass, plastic]
}

/// `testing::cornell_blended` whose milky sphere's members carry a transmission texture
/// reading `red` everywhere.
fn uniform_transmission(red: u8) -> Scene {
    let mut scene = testing::cornell_blended();
    let texture = scene.textures.len() as u32;
    scene.textures.push(scene::Texture {
        name: "transmission".into(),
        width: 1,
        height: 1,
        texels: Texels::LinearF32(vec![[f32::from(red) / 255.0, 0.0, 0.0, 1.0]]),
    });
    for id in milky_members(&scene) {
        scene.materials[id].transmission_texture = Some(texture);
    }
    scene
}

/// [`uniform_transmission`] with the texture gone: the glass member's weight is the factor times the texel
/// as the renderers' texture array stores it.
fn factored_transmission(red: u8) -> Scene {
    let mut scene = uniform_transmission(red);
    let texel = TextureArray::build(&scene.textures, DEFAULT_MAX_SIDE)
        .sample(scene.textures.len() as u32 - 1, Vec2::splat(0.3));
    let [glass, plastic] = milky_members(&scene);
    let blend = scene.materials[glass].blend.as_mut().unwrap();
    blend.weight *= texel.x;
    for id in [glass, plastic] {
        scene.materials[id].transmission_texture = None;
    }
    scene
}

#[test]
fn a_uniform_transmission_texture_renders_as_the_factor_it_reads() {
    for red in [0, 90, 255] {
        let image = render(&uniform_transmission(red));
        assert!(image.pixels.iter().any(|p| p.max_element() > 0.0));
        assert_eq!(
            image,
            render(&factored_transmission(red)),
            "texel {red} renders otherwise than its factor"
        );
    }
    // And the texel matters: another one gives another image.
    assert_ne!(
        render(&uniform_transmission(90)),
        render(&uniform_transmission(200))
    );
}

/// The same where the maps keep their lobes however rough (`scene::RoughnessMap::keeps_lobe`:
/// a film or a specular-glossiness layer lies on them): a rough texel (roughness 0.78) renders
/// as rough metal over rough plastic of α = roughness², not as Lambertian members, bit for bit.
#[test]
fn a_uniform_rough_texture_that_keeps_its_lobes_renders_as_its_rough_factors() {
    let (green, blue) = (200, 51);
    let keep = |scene: &mut Scene| {
        for material in &mut scene.materials {
            if let Some(map) = &mut material.roughness_map {
                map.keeps_lobe = true;
            }
        }
    };
    let (mut textured, metal) = uniform(green, blue);
    keep(&mut textured);
    let mut factors = factored(green, blue);
    let roughness = stored_texel(&factors).y;
    assert!(roughness > scene::DIFFUSE_MIN_ROUGHNESS, "{roughness}");
    let alpha = roughness * roughness;
    factors.materials[metal].surface = scene::Surface::RoughConductor { alpha };
    let coat = factors.materials[metal].blend.unwrap().other as usize;
    factors.materials[coat].surface = scene::Surface::Plastic { ior: 1.5, alpha };
    let image = render(&textured);
    assert_eq!(
        image,
        render(&factors),
        "kept lobes render otherwise than their factors"
    );
    let (lambertian, _) = uniform(green, blue);
    assert_ne!(
        image,
        render(&lambertian),
        "keeping the lobes changes nothing"
    );
}
