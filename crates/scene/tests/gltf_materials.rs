//! glTF materials: the mapping onto kousen's surfaces, emission, alpha, textures, lights.

use crate::gltf_support;
// The writer of `make_scenes`, for round trips of what the loader reads.
#[allow(dead_code)]
use crate::gltf_writer;

use glam::{Vec2, Vec3};
use gltf_support::*;
use scene::{AlphaMode, Iridescence, Material, Scene, Surface, Texels};
use serde_json::{Value, json};

/// The material of the only quad of a document made with `material`.
fn material_of(material: Value) -> Material {
    let scene = quad_doc(Some(material)).load().expect("loads");
    scene.materials[scene.triangles[0].material as usize].clone()
}

fn pbr(metallic: f32, roughness: f32) -> Value {
    json!({ "pbrMetallicRoughness": { "metallicFactor": metallic, "roughnessFactor": roughness } })
}

#[test]
fn smooth_metal_is_a_mirror_rough_metal_a_conductor_and_rough_surfaces_diffuse() {
    let cases = [
        ((1.0, 0.0), Surface::Mirror),
        ((1.0, 0.005), Surface::Mirror),
        ((1.0, 0.2), Surface::RoughConductor { alpha: 0.2 * 0.2 }),
        ((1.0, 0.4), Surface::RoughConductor { alpha: 0.4 * 0.4 }),
        ((1.0, 0.5), Surface::Diffuse),
        ((0.0, 0.5), Surface::Diffuse),
        ((0.4, 1.0), Surface::Diffuse),
    ];
    for ((metallic, roughness), surface) in cases {
        let m = material_of(pbr(metallic, roughness));
        assert_eq!(
            m.surface, surface,
            "metallic {metallic}, roughness {roughness}"
        );
    }
}

/// glTF's non-metals wear a clear dielectric coat (the spec's specular layer, F0 = 4 % at the
/// default ior 1.5): kousen's plastic where the coat is smooth enough to show (roughness < 0.5),
/// with `KHR_materials_ior`'s index; `KHR_materials_specular` factor 0 takes the coat off, and
/// an ior of 1 leaves nothing to reflect.
#[test]
fn smooth_non_metals_are_plastic_under_their_ior() {
    let cases = [
        (
            (0.0, 0.0),
            Surface::Plastic {
                ior: 1.5,
                alpha: 0.0,
            },
        ),
        (
            (0.0, 0.005),
            Surface::Plastic {
                ior: 1.5,
                alpha: 0.0,
            },
        ),
        (
            (0.0, 0.3),
            Surface::Plastic {
                ior: 1.5,
                alpha: 0.3 * 0.3,
            },
        ),
        (
            (0.0, 0.49),
            Surface::Plastic {
                ior: 1.5,
                alpha: 0.49 * 0.49,
            },
        ),
    ];
    for ((metallic, roughness), surface) in cases {
        let m = material_of(pbr(metallic, roughness));
        assert_eq!(
            m.surface, surface,
            "metallic {metallic}, roughness {roughness}"
        );
    }
    let with = |extensions: Value| {
        let mut material = pbr(0.0, 0.2);
        material["extensions"] = extensions;
        material_of(material).surface
    };
    assert_eq!(
        with(json!({ "KHR_materials_ior": { "ior": 1.33 } })),
        Surface::Plastic {
            ior: 1.33,
            alpha: 0.2 * 0.2
        }
    );
    assert_eq!(
        with(json!({ "KHR_materials_ior": { "ior": 1.0 } })),
        Surface::Diffuse
    );
    assert_eq!(
        with(json!({ "KHR_materials_ior": { "ior": 0.0 } })),
        Surface::Mirror
    );
    assert_eq!(
        with(json!({ "KHR_materials_specular": { "specularFactor": 0.0 } })),
        Surface::Diffuse
    );
    assert!(matches!(
        with(json!({ "KHR_materials_specular": { "specularFactor": 0.5 } })),
        Surface::Plastic { alpha, .. } if alpha == 0.2 * 0.2
    ));
}

/// `KHR_materials_specular` leaves the opaque dielectric's coat its own index and gives it a
/// `SpecularLayer`: glTF's F0 of the index times the colour factor, the factor, the strength
/// texture (data) and the colour texture (sRGB), whose reflectance at a hit is
/// `min(F0 · colour, 1) · strength` head on and `strength` at grazing; the defaults make
/// none, and values out of range are refused.
#[test]
fn specular_factors_and_textures_make_a_specular_layer() {
    let load = |specular: Value| {
        let mut doc = doc_with_two_textures();
        let mut material = pbr(0.0, 0.2);
        material["extensions"] = json!({ "KHR_materials_specular": specular });
        let material = doc.material(material);
        let mesh = doc.mesh(&QUAD, &QUAD_INDICES, Some(material));
        doc.instance(mesh);
        doc.load()
    };
    let scene = load(json!({
        "specularFactor": 0.5,
        "specularTexture": { "index": 0 },
        "specularColorFactor": [2.0, 1.0, 0.0],
        "specularColorTexture": { "index": 1 },
    }))
    .expect("loads");
    let material = &scene.materials[0];
    let layer = material.specular.expect("a layer");
    let Surface::Plastic { ior, .. } = material.surface else {
        panic!("{:?}", material.surface);
    };
    assert_eq!(ior, 1.5, "the coat keeps its index");
    // F0 of index 1.5 is 4 %.
    assert!(
        layer
            .tinted_f0
            .abs_diff_eq(Vec3::new(0.08, 0.04, 0.0), 1e-6)
    );
    assert_eq!(layer.factor, 0.5);
    let (Some(strength), Some(colour)) = (layer.texture, layer.color_texture) else {
        panic!("both textures are read: {layer:?}");
    };
    assert!(matches!(
        scene.textures[strength as usize].texels,
        Texels::LinearF32(_)
    ));
    assert_ne!(strength, colour);
    // Untextured: (2, 1, 0) × 4 % × 0.5 head on, 0.5 at grazing; textures multiply colour
    // and strength (the strength texture's alpha), and a channel's F0 stops at 1.
    let (f0, f90) = layer.at(None, None);
    assert!(f0.abs_diff_eq(Vec3::new(0.04, 0.02, 0.0), 1e-6), "{f0}");
    assert_eq!(f90, 0.5);
    let texel = Some(glam::Vec4::new(9.0, 9.0, 9.0, 0.5));
    let colour_texel = Some(glam::Vec4::new(20.0, 1.0, 1.0, 1.0));
    let (f0, f90) = layer.at(texel, colour_texel);
    assert!(f0.abs_diff_eq(Vec3::new(0.25, 0.01, 0.0), 1e-6), "{f0}");
    assert_eq!(f90, 0.25);
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);

    // A texture of the layer with a transform of its own is read with the base colour's.
    let shifted = load(json!({
        "specularColorTexture": {
            "index": 1,
            "extensions": { "KHR_texture_transform": { "offset": [0.5, 0.0] } },
        },
    }))
    .expect("loads");
    assert!(shifted.materials[0].specular.is_some());
    assert_eq!(shifted.warnings.len(), 1, "{:?}", shifted.warnings);
    assert_mentions(
        &shifted.warnings[0],
        &["specularColorTexture", "KHR_texture_transform"],
    );

    // A factor or a colour alone makes one, the defaults none; a factor of 0 leaves the opaque
    // dielectric Lambertian.
    for some in [
        json!({ "specularColorFactor": [1.0, 0.5, 0.5] }),
        json!({ "specularColorFactor": [2.0, 2.0, 2.0] }),
        json!({ "specularFactor": 0.5 }),
    ] {
        let scene = load(some.clone()).expect("loads");
        assert!(scene.materials[0].specular.is_some(), "{some}");
    }
    let white = json!({ "specularFactor": 1, "specularColorFactor": [1, 1, 1] });
    assert_eq!(load(white).expect("loads").materials[0].specular, None);
    let off = load(json!({ "specularFactor": 0.0 })).expect("loads");
    assert_eq!(off.materials[0].surface, Surface::Diffuse);
    for bad in [
        json!({ "specularFactor": 1.5 }),
        json!({ "specularColorFactor": [-1.0, 1.0, 1.0] }),
    ] {
        let error = load(bad.clone()).expect_err("refused");
        assert!(error.to_string().contains("specular"), "{bad}: {error}");
    }
}

/// The surfaces a blend's first material `id` chains, each with its probability.
fn members(scene: &Scene, id: u32) -> Vec<(f32, Surface)> {
    let (mut id, mut left, mut out) = (id as usize, 1.0, Vec::new());
    loop {
        let m = &scene.materials[id];
        let Some(blend) = m.blend else {
            out.push((left, m.surface));
            return out;
        };
        out.push((left * blend.weight, m.surface));
        left *= 1.0 - blend.weight;
        assert!(blend.other as usize > id, "a blend chains back");
        id = blend.other as usize;
    }
}

/// glTF's `mix(dielectric, metal, metallic)` and the dielectric's `mix(opaque, glass,
/// transmission)` as a blend: every surface with its probability, the Lambertian one last,
/// the material's other properties on every member.
#[test]
fn partial_metallic_and_transmission_factors_blend_their_surfaces() {
    let mut material = pbr(0.25, 0.2);
    material["pbrMetallicRoughness"]["baseColorFactor"] = json!([0.5, 0.6, 0.7, 1.0]);
    material["extensions"] = json!({ "KHR_materials_transmission": { "transmissionFactor": 0.4 } });
    let scene = quad_doc(Some(material)).load().expect("loads");
    let root = scene.triangles[0].material;
    let found = members(&scene, root);
    let alpha = 0.2 * 0.2;
    let expected = [
        (0.25, Surface::RoughConductor { alpha }),
        (
            0.75 * 0.4,
            Surface::RoughDielectric {
                ior: 1.5,
                thin_walled: true,
                alpha,
            },
        ),
        (0.75 * 0.6, Surface::Plastic { ior: 1.5, alpha }),
    ];
    assert_eq!(found.len(), expected.len(), "{found:?}");
    for ((p, surface), (q, expected)) in found.iter().zip(expected) {
        assert_eq!(*surface, expected);
        assert!(
            (p - q).abs() < 1e-6,
            "{surface:?}: probability {p}, not {q}"
        );
    }
    for m in &scene.materials[root as usize..] {
        assert_eq!(m.base_color, Vec3::new(0.5, 0.6, 0.7));
        assert_eq!(m.name, scene.materials[root as usize].name);
    }

    // Rough metal and rough dielectric are both Lambertian: one surface, no blend.
    let m = material_of(pbr(0.4, 1.0));
    assert_eq!((m.surface, m.blend), (Surface::Diffuse, None));
    // Half metal over a smooth coat.
    let scene = quad_doc(Some(pbr(0.5, 0.0))).load().expect("loads");
    let found = members(&scene, scene.triangles[0].material);
    let plastic = Surface::Plastic {
        ior: 1.5,
        alpha: 0.0,
    };
    assert_eq!(found, vec![(0.5, Surface::Mirror), (0.5, plastic)]);
}

/// Solid glass blended with metal: the first material carries the glass's absorption (a ray
/// that ran inside may leave through any member), the metal member none of its own.
#[test]
fn a_blend_with_solid_glass_absorbs_inside_through_its_first_material() {
    let mut material = pbr(0.5, 0.0);
    material["extensions"] = json!({
        "KHR_materials_transmission": { "transmissionFactor": 1.0 },
        "KHR_materials_volume": {
            "thicknessFactor": 1.0,
            "attenuationColor": [0.5, 1.0, 1.0],
            "attenuationDistance": 2.0
        }
    });
    let scene = quad_doc(Some(material)).load().expect("loads");
    let root = scene.triangles[0].material as usize;
    let found = members(&scene, root as u32);
    let glass = Surface::Dielectric {
        ior: 1.5,
        thin_walled: false,
    };
    assert_eq!(found, vec![(0.5, Surface::Mirror), (0.5, glass)]);
    let absorption = scene::absorption_from_attenuation(Vec3::new(0.5, 1.0, 1.0), 2.0);
    assert_eq!(scene.materials[root].interior_absorption(), absorption);
    assert_eq!(scene.materials[root + 1].interior_absorption(), absorption);
}

#[test]
fn base_color_factor_is_linear_and_alpha_kept() {
    let m = material_of(
        json!({ "pbrMetallicRoughness": { "baseColorFactor": [0.5, 0.25, 0.125, 0.75] } }),
    );
    assert_eq!(m.base_color, Vec3::new(0.5, 0.25, 0.125));
    assert_eq!(m.alpha, 0.75);
    assert_eq!(m.alpha_mode, AlphaMode::Opaque);
    assert_eq!(
        m.surface,
        Surface::Diffuse,
        "glTF's default metallic 1, roughness 1"
    );
}

#[test]
fn transmission_without_volume_is_a_thin_walled_dielectric() {
    let mut material = pbr(0.0, 0.0);
    material["extensions"] = json!({ "KHR_materials_transmission": { "transmissionFactor": 1.0 } });
    let m = material_of(material);
    assert_eq!(
        m.surface,
        Surface::Dielectric {
            ior: 1.5,
            thin_walled: true
        }
    );
}

/// Transmission with roughness from 0.01 is frosted glass, GGX of width roughness², solid or
/// a sheet as smooth glass is; glTF's default roughness (1) makes it very frosted.
#[test]
fn rough_transmission_is_a_rough_dielectric() {
    let cases = [
        (
            Some(0.005),
            false,
            Surface::Dielectric {
                ior: 1.5,
                thin_walled: false,
            },
        ),
        (
            Some(0.3),
            false,
            Surface::RoughDielectric {
                ior: 1.5,
                thin_walled: false,
                alpha: 0.3 * 0.3,
            },
        ),
        (
            Some(0.5),
            true,
            Surface::RoughDielectric {
                ior: 1.5,
                thin_walled: true,
                alpha: 0.5 * 0.5,
            },
        ),
        (
            None,
            true,
            Surface::RoughDielectric {
                ior: 1.5,
                thin_walled: true,
                alpha: 1.0,
            },
        ),
    ];
    for (roughness, thin, surface) in cases {
        let mut material = json!({ "pbrMetallicRoughness": { "metallicFactor": 0.0 } });
        if let Some(r) = roughness {
            material["pbrMetallicRoughness"]["roughnessFactor"] = json!(r);
        }
        material["extensions"] =
            json!({ "KHR_materials_transmission": { "transmissionFactor": 1.0 } });
        if !thin {
            material["extensions"]["KHR_materials_volume"] = json!({ "thicknessFactor": 0.1 });
        }
        assert_eq!(
            material_of(material).surface,
            surface,
            "roughness {roughness:?}"
        );
    }
}

/// A solid's `KHR_materials_volume` attenuation becomes Beer–Lambert absorption; thin sheets
/// have no volume to absorb in; a distance that is not above 0 is refused in words.
#[test]
fn volume_attenuation_is_absorption_in_solids() {
    let glass = |volume: Value| {
        let mut material = pbr(0.0, 0.0);
        material["extensions"] = json!({
            "KHR_materials_transmission": { "transmissionFactor": 1.0 },
            "KHR_materials_volume": volume,
        });
        material
    };
    let m = material_of(glass(json!({
        "thicknessFactor": 1.0, "attenuationColor": [0.5, 0.25, 1.0], "attenuationDistance": 2.0
    })));
    let want = Vec3::new(0.5f32.ln(), 0.25f32.ln(), 0.0) / -2.0;
    assert!(
        (m.absorption - want).abs().max_element() < 1e-6,
        "{}",
        m.absorption
    );
    let clear = material_of(glass(json!({ "thicknessFactor": 1.0 })));
    assert_eq!(
        clear.absorption,
        Vec3::ZERO,
        "no attenuation distance: clear"
    );
    let sheet = material_of(glass(json!({
        "thicknessFactor": 0.0, "attenuationColor": [0.5, 0.5, 0.5], "attenuationDistance": 2.0
    })));
    assert_eq!(sheet.absorption, Vec3::ZERO, "a thin sheet has no volume");
    let error = quad_doc(Some(glass(json!({
        "thicknessFactor": 1.0, "attenuationDistance": 0.0
    }))))
    .load()
    .expect_err("a zero distance is refused");
    assert!(
        error.to_string().contains("attenuationDistance 0"),
        "{error}"
    );
    let error = quad_doc(Some(glass(json!({
        "thicknessFactor": 1.0, "attenuationColor": [0.5, 1.5, 0.5], "attenuationDistance": 1.0
    }))))
    .load()
    .expect_err("a colour channel above 1 is refused");
    assert!(
        error.to_string().contains("attenuationColor's green"),
        "{error}"
    );
}

#[test]
fn transmission_with_volume_is_a_solid_dielectric_with_the_khr_ior() {
    let mut material = pbr(0.0, 0.0);
    material["extensions"] = json!({
        "KHR_materials_transmission": { "transmissionFactor": 0.9 },
        "KHR_materials_volume": { "thicknessFactor": 0.1 },
        "KHR_materials_ior": { "ior": 1.33 },
    });
    let m = material_of(material);
    assert_eq!(
        m.surface,
        Surface::Dielectric {
            ior: 1.33,
            thin_walled: false
        }
    );
}

#[test]
fn emissive_strength_multiplies_the_emissive_factor() {
    let m = material_of(json!({
        "emissiveFactor": [0.5, 1.0, 0.25],
        "extensions": { "KHR_materials_emissive_strength": { "emissiveStrength": 4.0 } },
    }));
    assert_eq!(m.emission, Vec3::new(2.0, 4.0, 1.0));
    assert_eq!(
        material_of(json!({ "emissiveFactor": [0.5, 1.0, 0.25] })).emission,
        Vec3::new(0.5, 1.0, 0.25)
    );
}

#[test]
fn primitives_without_material_share_one_default_material_that_does_not_emit() {
    let mut doc = quad_doc(None);
    let other = doc.mesh(&QUAD, &QUAD_INDICES, None);
    doc.instance(other);
    let scene = doc.load().expect("loads");
    assert_eq!(scene.triangles.len(), 4);
    assert_eq!(scene.materials.len(), 1);
    assert_eq!(scene.materials[0].emission, Vec3::ZERO);
    assert!(scene.lights.triangles.is_empty());
}

#[test]
fn alpha_mask_uses_the_cutoff_and_blend_becomes_a_mask_with_a_warning() {
    let masked =
        material_of(json!({ "alphaMode": "MASK", "alphaCutoff": 0.3, "doubleSided": true }));
    assert_eq!(masked.alpha_mode, AlphaMode::Mask { cutoff: 0.3 });
    assert!(masked.double_sided);
    let default_cutoff = material_of(json!({ "alphaMode": "MASK" }));
    assert_eq!(default_cutoff.alpha_mode, AlphaMode::Mask { cutoff: 0.5 });
    let scene = quad_doc(Some(json!({ "alphaMode": "BLEND" })))
        .load()
        .expect("loads");
    assert_eq!(
        scene.materials[0].alpha_mode,
        AlphaMode::Mask { cutoff: 0.5 }
    );
    assert!(
        scene.warnings.iter().any(|w| w.contains("BLEND")),
        "{:?}",
        scene.warnings
    );
}

fn tiny_png() -> Vec<u8> {
    let image =
        image::RgbaImage::from_raw(2, 1, vec![255, 0, 0, 255, 0, 128, 255, 64]).expect("2×1");
    let mut png = Vec::new();
    image
        .write_to(&mut std::io::Cursor::new(&mut png), image::ImageFormat::Png)
        .expect("encode PNG");
    png
}

/// A document whose image 0 is [`tiny_png`] in a buffer view.
/// [`doc_with_embedded_png`] with a second image and textures 0 and 1 of the two, so that two
/// slots decode to two textures.
fn doc_with_two_textures() -> Doc {
    let mut doc = doc_with_embedded_png();
    let view = doc.view(&tiny_png());
    doc.push(
        "images",
        json!({ "bufferView": view, "mimeType": "image/png" }),
    );
    doc.push("textures", json!({ "source": 0 }));
    doc.push("textures", json!({ "source": 1 }));
    doc
}

fn doc_with_embedded_png() -> Doc {
    let mut doc = Doc::default();
    let view = doc.view(&tiny_png());
    doc.push(
        "images",
        json!({ "bufferView": view, "mimeType": "image/png" }),
    );
    doc
}

/// A quad whose material uses image 0 for base colour and emission.
fn textured_quad(doc: &mut Doc) {
    doc.push("textures", json!({ "source": 0 }));
    let material = doc.material(json!({
        "pbrMetallicRoughness": { "baseColorTexture": { "index": 0 } },
        "emissiveTexture": { "index": 0 },
        "emissiveFactor": [1, 1, 1],
    }));
    let mesh = doc.mesh(&QUAD, &QUAD_INDICES, Some(material));
    doc.instance(mesh);
}

fn assert_tiny_png_decoded_once(scene: &Scene) {
    assert_eq!(
        scene.textures.len(),
        1,
        "decoded once, shared by both slots"
    );
    let texture = &scene.textures[0];
    assert_eq!((texture.width, texture.height), (2, 1));
    assert_eq!(
        texture.texels,
        Texels::Srgb8(vec![[255, 0, 0, 255], [0, 128, 255, 64]])
    );
    let m = &scene.materials[0];
    assert_eq!(
        (m.base_color_texture, m.emission_texture),
        (Some(0), Some(0))
    );
}

#[test]
fn an_embedded_png_in_a_buffer_view_is_decoded_once_as_srgb() {
    let mut doc = doc_with_embedded_png();
    textured_quad(&mut doc);
    for layout in [Layout::DataUri, Layout::Glb] {
        assert_tiny_png_decoded_once(&doc.load_as(layout).expect("loads"));
    }
}

/// One image as base colour and as a normal map: decoded twice, as sRGB colour and as linear
/// data; the map's scale is kept, and a second coordinate set is warned about.
#[test]
fn a_normal_texture_is_decoded_as_linear_data_with_its_scale() {
    let mut doc = doc_with_embedded_png();
    doc.push("textures", json!({ "source": 0 }));
    let material = doc.material(json!({
        "pbrMetallicRoughness": { "baseColorTexture": { "index": 0 } },
        "normalTexture": { "index": 0, "scale": -0.5, "texCoord": 1 },
    }));
    let mesh = doc.mesh(&QUAD, &QUAD_INDICES, Some(material));
    doc.instance(mesh);
    let scene = doc.load().expect("loads");
    let m = &scene.materials[0];
    assert_eq!(m.normal_scale, -0.5);
    let (colour, normal) = (m.base_color_texture.unwrap(), m.normal_texture.unwrap());
    assert_ne!(colour, normal, "decoded once each way");
    assert!(matches!(
        scene.textures[colour as usize].texels,
        Texels::Srgb8(_)
    ));
    let Texels::LinearF32(texels) = &scene.textures[normal as usize].texels else {
        panic!("a normal map is linear data");
    };
    assert_eq!(texels[1], [0.0, 128.0 / 255.0, 1.0, 64.0 / 255.0]);
    assert!(
        scene
            .warnings
            .iter()
            .any(|w| w.contains("normalTexture uses TEXCOORD_1")),
        "{:?}",
        scene.warnings
    );
    // 1e39 reads as an infinite f32.
    let error = quad_doc(Some(
        json!({ "normalTexture": { "index": 0, "scale": 1e39 } }),
    ))
    .load()
    .expect_err("an infinite scale is refused");
    assert!(
        error.to_string().contains("normalTexture's scale inf"),
        "{error}"
    );
}

#[test]
fn images_load_from_data_uris_and_files_next_to_the_gltf() {
    use base64::Engine;
    let png = tiny_png();
    let mut doc = Doc::default();
    let data = base64::engine::general_purpose::STANDARD.encode(&png);
    doc.push(
        "images",
        json!({ "uri": format!("data:image/png;base64,{data}") }),
    );
    textured_quad(&mut doc);
    assert_tiny_png_decoded_once(&doc.load().expect("loads"));

    doc.json["images"][0]["uri"] = json!("tex%20dir/tiny.png");
    let dir = tempfile::tempdir().expect("tempdir");
    std::fs::create_dir(dir.path().join("tex dir")).expect("mkdir");
    std::fs::write(dir.path().join("tex dir/tiny.png"), &png).expect("write");
    let scene = scene::gltf::load(&doc.write(dir.path(), Layout::ExternalBin)).expect("loads");
    assert_tiny_png_decoded_once(&scene);
    assert_eq!(scene.textures[0].name, "tiny.png");
}

#[test]
fn an_emissive_quad_is_collected_as_a_light_with_its_area_and_power() {
    let mut doc = Doc::default();
    let material = doc.material(json!({ "emissiveFactor": [1.0, 0.5, 0.25] }));
    let mesh = doc.mesh(&QUAD, &QUAD_INDICES, Some(material));
    let node = doc.node(json!({ "mesh": mesh, "scale": [2, 3, 1] }));
    doc.add_root(node);
    let scene = doc.load().expect("loads");
    let lights = &scene.lights;
    assert_eq!(lights.triangles.len(), 2);
    let area: f32 = lights.triangles.iter().map(|l| l.area).sum();
    assert!((area - 6.0).abs() < 1e-5, "area {area}");
    let expected = Vec3::new(1.0, 0.5, 0.25) * 6.0 * std::f32::consts::PI;
    assert!(
        lights.total_power.abs_diff_eq(expected, 1e-4),
        "{}",
        lights.total_power
    );
}

#[test]
fn ignored_extensions_are_named_in_one_warning() {
    let mut doc = quad_doc(None);
    doc.json["extensionsUsed"] = json!([
        "KHR_draco_mesh_compression",
        "KHR_materials_ior",
        "KHR_materials_specular"
    ]);
    let scene = doc.load().expect("loads");
    let warnings: Vec<&String> = scene
        .warnings
        .iter()
        .filter(|w| w.contains("extension"))
        .collect();
    assert_eq!(warnings.len(), 1, "{warnings:?}");
    assert_mentions(warnings[0], &["ignoring", "KHR_draco_mesh_compression"]);
    for read in ["KHR_materials_specular", "KHR_materials_ior"] {
        assert!(!warnings[0].contains(read), "{read} is read: {warnings:?}");
    }
}

#[test]
fn supported_extensions_may_be_required() {
    let mut doc = quad_doc(None);
    let required = [
        "KHR_materials_volume",
        "KHR_materials_transmission",
        "KHR_materials_specular",
    ];
    doc.json["extensionsRequired"] = json!(required);
    doc.json["extensionsUsed"] = json!(required);
    let scene = doc.load().expect("loads");
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
}

/// A quad with texture coordinates (u, v) = (x, y) of its corners, whose material's base
/// colour texture carries `transform` (a `KHR_texture_transform` object) and, if given, whose
/// emissive texture carries `emissive_transform`.
fn transformed_quad(transform: Value, emissive_transform: Option<Value>) -> Scene {
    let mut doc = doc_with_embedded_png();
    doc.push("textures", json!({ "source": 0 }));
    let mut material = json!({
        "pbrMetallicRoughness": { "baseColorTexture": {
            "index": 0, "extensions": { "KHR_texture_transform": transform } } },
    });
    if let Some(e) = emissive_transform {
        material["emissiveTexture"] =
            json!({ "index": 0, "extensions": { "KHR_texture_transform": e } });
        material["emissiveFactor"] = json!([1, 1, 1]);
    }
    let material = doc.material(material);
    let position = doc.vec3s(&QUAD);
    let uv = doc.vec2s(&QUAD.map(|[x, y, _]| [x, y]));
    let indices = doc.indices(&QUAD_INDICES, 5123);
    let primitive = json!({
        "attributes": { "POSITION": position, "TEXCOORD_0": uv },
        "indices": indices, "material": material,
    });
    let mesh = doc.push("meshes", json!({ "primitives": [primitive] }));
    doc.instance(mesh);
    doc.load_as(Layout::Glb).expect("loads")
}

/// `KHR_texture_transform` moves the texture coordinates as the extension's
/// `translation * rotation * scale` does: a corner (1, 0) scaled by (2, 3), turned a quarter
/// counter-clockwise and offset by (0.5, 0.25) lands at (0.5, 2.25); the others follow.
#[test]
fn texture_transforms_move_the_texture_coordinates() {
    let scene = transformed_quad(
        json!({ "offset": [0.5, 0.25], "rotation": std::f32::consts::FRAC_PI_2, "scale": [2.0, 3.0] }),
        None,
    );
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
    let place = |[u, v]: [f32; 2]| {
        let (su, sv) = (2.0 * u, 3.0 * v);
        // Rotating (x, y) a quarter counter-clockwise gives (−y, x).
        Vec2::new(-sv + 0.5, su + 0.25)
    };
    let mut seen = 0;
    for triangle in &scene.triangles {
        for vertex in &triangle.vertices {
            let want = place([vertex.position.x, vertex.position.y]);
            assert!(
                (vertex.uv - want).abs().max_element() < 1e-5,
                "{} vs {want}",
                vertex.uv
            );
            seen += 1;
        }
    }
    assert_eq!(seen, 6);
    assert!(
        scene
            .triangles
            .iter()
            .flat_map(|t| t.vertices)
            .any(|v| (v.uv - Vec2::new(0.5, 2.25)).length() < 1e-5),
        "the corner (1, 0)"
    );
}

/// One transform a material: the base colour's wins, and a different emissive one is named.
#[test]
fn a_different_emissive_texture_transform_is_warned_about() {
    let scene = transformed_quad(
        json!({ "offset": [0.5, 0.0] }),
        Some(json!({ "scale": [2.0, 2.0] })),
    );
    assert!(
        scene
            .warnings
            .iter()
            .any(|w| w.contains("emissiveTexture's KHR_texture_transform differs")),
        "{:?}",
        scene.warnings
    );
    let uvs: Vec<Vec2> = scene
        .triangles
        .iter()
        .flat_map(|t| t.vertices.map(|v| v.uv))
        .collect();
    assert!(
        uvs.iter()
            .all(|uv| uv.x >= 0.5 && uv.x <= 1.5 && uv.y <= 1.0),
        "{uvs:?}"
    );
}

/// `KHR_materials_dispersion` on solid glass, smooth or frosted, alone or blended:
/// `Material::dispersion` = (ior − 1) / V with the Abbe number V = 20 / the extension's
/// `dispersion`; on a thin-walled sheet it is warned about and ignored, and a negative value
/// is refused.
#[test]
fn dispersion_is_read_on_solid_glass() {
    let glass_of = |roughness: f32, dispersion: f32, thickness: f32| {
        let mut material = pbr(0.0, roughness);
        material["extensions"] = json!({
            "KHR_materials_transmission": { "transmissionFactor": 1.0 },
            "KHR_materials_ior": { "ior": 1.75 },
            "KHR_materials_volume": { "thicknessFactor": thickness },
            "KHR_materials_dispersion": { "dispersion": dispersion },
        });
        quad_doc(Some(material)).load()
    };
    let glass = |roughness, dispersion| glass_of(roughness, dispersion, 1.0);
    let want = (1.75 - 1.0) / (20.0 / 0.8);
    for roughness in [0.0, 0.3] {
        let scene = glass(roughness, 0.8).expect("loads");
        let flint = &scene.materials[scene.triangles[0].material as usize];
        assert!(
            (flint.dispersion - want).abs() < 1e-7,
            "roughness {roughness}: {}",
            flint.dispersion
        );
        assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
    }
    // Half glass, half plastic: a blend whose glass member disperses (every member carries
    // the number; only glass surfaces use it).
    let mut material = pbr(0.0, 0.0);
    material["extensions"] = json!({
        "KHR_materials_transmission": { "transmissionFactor": 0.5 },
        "KHR_materials_ior": { "ior": 1.75 },
        "KHR_materials_volume": { "thicknessFactor": 1.0 },
        "KHR_materials_dispersion": { "dispersion": 0.8 },
    });
    let blended = quad_doc(Some(material)).load().expect("loads");
    let root = &blended.materials[blended.triangles[0].material as usize];
    assert!(root.blend.is_some(), "transmission 0.5 blends");
    assert!((root.dispersion - want).abs() < 1e-7, "{}", root.dispersion);
    assert!(blended.warnings.is_empty(), "{:?}", blended.warnings);
    let sheet = glass_of(0.0, 0.8, 0.0).expect("loads");
    let ignored = &sheet.materials[sheet.triangles[0].material as usize];
    assert_eq!(ignored.dispersion, 0.0);
    assert!(
        sheet
            .warnings
            .iter()
            .any(|w| w.contains("KHR_materials_dispersion")),
        "{:?}",
        sheet.warnings
    );
    let error = glass(0.0, -1.0).expect_err("a negative dispersion is refused");
    assert!(error.to_string().contains("dispersion"), "{error}");
}

/// `KHR_materials_clearcoat`'s factors as `Material::clearcoat` (GGX width the roughness
/// squared, smooth below 0.01), carried by every member of a blend; a factor of 0 is no coat;
/// its weight, roughness and normal textures are read (the last with its scale); a factor
/// outside [0, 1] is refused; the extension may be required.
#[test]
fn clearcoat_factors_are_read() {
    let coated = |metallic: f32, coat: Value| {
        let mut material = pbr(metallic, 0.4);
        material["extensions"] = json!({ "KHR_materials_clearcoat": coat });
        quad_doc(Some(material)).load()
    };
    let scene = coated(
        1.0,
        json!({ "clearcoatFactor": 0.8, "clearcoatRoughnessFactor": 0.3 }),
    )
    .expect("loads");
    let root = &scene.materials[scene.triangles[0].material as usize];
    let coat = root.clearcoat.expect("a coat");
    assert_eq!(coat.weight, 0.8);
    assert!((coat.alpha - 0.09).abs() < 1e-7, "{}", coat.alpha);
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
    let smooth = coated(0.0, json!({ "clearcoatFactor": 1.0 })).expect("loads");
    let plastic = &smooth.materials[smooth.triangles[0].material as usize];
    assert_eq!(plastic.clearcoat, scene::Clearcoat::new(1.0, 0.0));
    assert_eq!(plastic.clearcoat.unwrap().alpha, 0.0);
    // Half metal: both members carry the coat.
    let half = coated(0.5, json!({ "clearcoatFactor": 0.6 })).expect("loads");
    let id = half.triangles[0].material as usize;
    let other = half.materials[id].blend.expect("a blend").other as usize;
    for member in [id, other] {
        assert_eq!(
            half.materials[member].clearcoat.map(|c| c.weight),
            Some(0.6)
        );
    }
    let none = coated(0.0, json!({ "clearcoatRoughnessFactor": 0.5 })).expect("loads");
    assert_eq!(
        none.materials[0].clearcoat, None,
        "factor 0 (the default): no coat"
    );
    // Its weight and roughness textures, decoded as data (one image, both slots); its normal
    // texture is warned about.
    let mut doc = doc_with_embedded_png();
    doc.push("textures", json!({ "source": 0 }));
    let mut material = pbr(0.0, 0.4);
    material["extensions"] = json!({ "KHR_materials_clearcoat": {
        "clearcoatFactor": 1.0,
        "clearcoatTexture": { "index": 0 },
        "clearcoatRoughnessTexture": { "index": 0 },
        "clearcoatNormalTexture": { "index": 0, "scale": 0.5 },
    } });
    let material = doc.material(material);
    let mesh = doc.mesh(&QUAD, &QUAD_INDICES, Some(material));
    doc.instance(mesh);
    let textured = doc.load().expect("loads");
    let coat = textured.materials[0].clearcoat.expect("a coat");
    assert_eq!(
        (
            coat.weight_texture,
            coat.roughness_texture,
            coat.normal_texture
        ),
        (Some(0), Some(0), Some(0))
    );
    assert_eq!(coat.normal_scale, 0.5);
    assert!(
        matches!(textured.textures[0].texels, Texels::LinearF32(_)),
        "coat textures are data"
    );
    assert!(textured.warnings.is_empty(), "{:?}", textured.warnings);
    let bad = coated(
        0.0,
        json!({ "clearcoatFactor": 1.0, "clearcoatTexture": { "index": 7 } }),
    );
    assert!(
        bad.is_err(),
        "a coat texture that does not exist is an error"
    );
    let error = coated(0.0, json!({ "clearcoatFactor": 1.5 })).expect_err("out of range");
    assert!(error.to_string().contains("clearcoatFactor"), "{error}");
    let mut doc = quad_doc(None);
    doc.json["extensionsRequired"] = json!(["KHR_materials_clearcoat"]);
    doc.json["extensionsUsed"] = json!(["KHR_materials_clearcoat"]);
    assert!(
        doc.load().is_ok(),
        "KHR_materials_clearcoat may be required"
    );
}

/// `KHR_materials_unlit`: the base colour becomes emission (factor and texture) and the
/// surface reflects nothing, whatever its metallic or transmission factors; the quad is a
/// light; the extension may be required.
#[test]
fn unlit_materials_emit_their_base_colour() {
    let mut doc = doc_with_embedded_png();
    doc.push("textures", json!({ "source": 0 }));
    let material = doc.material(json!({
        "pbrMetallicRoughness": {
            "baseColorFactor": [0.2, 0.4, 0.6, 1.0],
            "baseColorTexture": { "index": 0 },
            "metallicFactor": 0.5,
        },
        "extensions": {
            "KHR_materials_unlit": {},
            "KHR_materials_transmission": { "transmissionFactor": 1.0 },
        },
    }));
    let mesh = doc.mesh(&QUAD, &QUAD_INDICES, Some(material));
    doc.instance(mesh);
    doc.json["extensionsUsed"] = json!(["KHR_materials_unlit", "KHR_materials_transmission"]);
    doc.json["extensionsRequired"] = json!(["KHR_materials_unlit"]);
    let scene = doc.load().expect("loads");
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
    let unlit = &scene.materials[scene.triangles[0].material as usize];
    assert_eq!(unlit.surface, Surface::Diffuse);
    assert_eq!(unlit.blend, None);
    assert_eq!(unlit.base_color, Vec3::ZERO);
    assert_eq!(unlit.emission, Vec3::new(0.2, 0.4, 0.6));
    assert_eq!(unlit.emission_texture, Some(0));
    assert_eq!(scene.lights.triangles.len(), 2);
}

/// A quad whose material is `material` with image 0 ([`tiny_png`]) as its
/// metallic-roughness texture: texel 0 reads roughness 0 and metalness 0, texel 1 roughness
/// 128/255 and metalness 1.
fn metallic_roughness_quad(mut material: Value) -> Scene {
    let mut doc = doc_with_embedded_png();
    doc.push("textures", json!({ "source": 0 }));
    material["pbrMetallicRoughness"]["metallicRoughnessTexture"] = json!({ "index": 0 });
    let material = doc.material(material);
    let mesh = doc.mesh(&QUAD, &QUAD_INDICES, Some(material));
    doc.instance(mesh);
    doc.load().expect("loads")
}

/// glTF's metallic-roughness texture: decoded as linear data; the metal comes first, its
/// weight the metallic factor (1 included: the texel's metalness scales it per hit), its
/// surface following the texel's roughness (`RoughnessMap`, which keeps the texture's range of
/// roughness); the opaque dielectric is plastic, stored at the mean roughness of the texels
/// where it shows and is not Lambertian (weighted by 1 − metalness), following the texel's
/// roughness per hit; the glass follows the texel's roughness too (stored at the mean
/// roughness where it shows); without a metallic factor there is no metal.
#[test]
fn a_metallic_roughness_texture_maps_the_metal_and_the_coat() {
    use scene::{RoughnessMap, TexturedLobe};
    let roughness_factor = 0.8;
    // The texels' roughness: 0 and 0.8 × 128/255, both below 0.5.
    let mean = 0.5 * roughness_factor * 128.0 / 255.0;
    let close = |a: f32, b: f32| (a - b).abs() < 1e-6;
    let scene = metallic_roughness_quad(pbr(1.0, roughness_factor));
    let root = scene.triangles[0].material;
    let metal = &scene.materials[root as usize];
    let map = |lobe| RoughnessMap {
        texture: 0,
        roughness_factor,
        roughness_range: [0.0, roughness_factor * (128.0 / 255.0)],
        lobe,
        keeps_lobe: false,
    };
    assert_eq!(metal.roughness_map, Some(map(TexturedLobe::Metal)));
    assert!(
        matches!(metal.surface, Surface::RoughConductor { alpha } if close(alpha, mean * mean))
    );
    let blend = metal.blend.expect("a metal factor of 1 still blends");
    assert_eq!(blend.weight, 1.0);
    let coat = &scene.materials[blend.other as usize];
    assert_eq!(coat.roughness_map, Some(map(TexturedLobe::Coated)));
    // The coat shows only on texel 0, of roughness 0: smooth.
    let smooth = Surface::Plastic {
        ior: 1.5,
        alpha: 0.0,
    };
    assert_eq!(coat.surface, smooth);
    assert_eq!(coat.blend, None);
    let Texels::LinearF32(texels) = &scene.textures[0].texels else {
        panic!("a metallic-roughness texture is linear data");
    };
    assert_eq!(texels[1], [0.0, 128.0 / 255.0, 1.0, 64.0 / 255.0]);
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);

    // Half transmissive and not metallic: no metal; glass mapped by the texture, stored as
    // frosted glass of the mean roughness.
    let mut material = pbr(0.0, roughness_factor);
    material["extensions"] = json!({ "KHR_materials_transmission": { "transmissionFactor": 0.5 } });
    let scene = metallic_roughness_quad(material);
    let root = scene.triangles[0].material as usize;
    let glass = &scene.materials[root];
    assert!(
        matches!(glass.surface, Surface::RoughDielectric { alpha, .. } if close(alpha, mean * mean)),
        "{:?}",
        glass.surface
    );
    assert_eq!(glass.roughness_map, Some(map(TexturedLobe::Glass)));
    assert_eq!(glass.blend.map(|b| b.weight), Some(0.5));
    let coat = &scene.materials[root + 1];
    assert_eq!(coat.roughness_map, Some(map(TexturedLobe::Coated)));
    assert!(
        matches!(coat.surface, Surface::Plastic { ior: 1.5, alpha } if close(alpha, mean * mean)),
        "{:?}",
        coat.surface
    );
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);

    // Without a specular layer the opaque dielectric is Lambertian whatever the texel says.
    let mut material = pbr(0.5, roughness_factor);
    material["extensions"] = json!({ "KHR_materials_specular": { "specularFactor": 0.0 } });
    let scene = metallic_roughness_quad(material);
    let root = scene.triangles[0].material as usize;
    assert_eq!(scene.materials[root].blend.map(|b| b.weight), Some(0.5));
    let opaque = &scene.materials[root + 1];
    assert_eq!(
        (opaque.surface, opaque.roughness_map),
        (Surface::Diffuse, None)
    );
}

/// `KHR_materials_sheen`'s factors as `Material::sheen` (roughness raised to its least), on
/// every member of a blend; a black colour is no sheen; its colour texture is read as sRGB,
/// its roughness texture as data; bad factors are refused; it may be required.
#[test]
fn sheen_factors_are_read() {
    let sheened = |metallic: f32, sheen: Value| {
        let mut material = pbr(metallic, 0.4);
        material["extensions"] = json!({ "KHR_materials_sheen": sheen });
        quad_doc(Some(material)).load()
    };
    let scene = sheened(
        0.0,
        json!({ "sheenColorFactor": [0.9, 0.5, 0.2], "sheenRoughnessFactor": 0.4 }),
    )
    .expect("loads");
    let sheen = scene.materials[0].sheen.expect("a sheen");
    assert_eq!(sheen.color, Vec3::new(0.9, 0.5, 0.2));
    assert_eq!(sheen.roughness, 0.4);
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
    let smooth = sheened(0.0, json!({ "sheenColorFactor": [1, 1, 1] })).expect("loads");
    assert_eq!(
        smooth.materials[0].sheen.map(|s| s.roughness),
        Some(scene::Sheen::MIN_ROUGHNESS),
        "roughness 0 (the default) is raised"
    );
    let none = sheened(0.0, json!({ "sheenRoughnessFactor": 0.5 })).expect("loads");
    assert_eq!(none.materials[0].sheen, None, "a black colour: no sheen");
    let half = sheened(0.5, json!({ "sheenColorFactor": [1, 1, 1] })).expect("loads");
    let id = half.triangles[0].material as usize;
    let other = half.materials[id].blend.expect("a blend").other as usize;
    for member in [id, other] {
        assert!(half.materials[member].sheen.is_some(), "member {member}");
    }
    let mut doc = doc_with_embedded_png();
    doc.push("textures", json!({ "source": 0 }));
    let mut material = pbr(0.0, 0.8);
    material["extensions"] = json!({ "KHR_materials_sheen": {
        "sheenColorFactor": [1, 1, 1],
        "sheenColorTexture": { "index": 0 },
        "sheenRoughnessTexture": { "index": 0 },
    } });
    let material = doc.material(material);
    let mesh = doc.mesh(&QUAD, &QUAD_INDICES, Some(material));
    doc.instance(mesh);
    let textured = doc.load().expect("loads");
    let sheen = textured.materials[0].sheen.unwrap();
    assert_eq!(
        (sheen.color_texture, sheen.roughness_texture),
        (Some(0), Some(1))
    );
    assert!(
        !matches!(textured.textures[0].texels, Texels::LinearF32(_)),
        "the sheen colour is sRGB"
    );
    assert!(
        matches!(textured.textures[1].texels, Texels::LinearF32(_)),
        "the sheen roughness is data"
    );
    assert!(textured.warnings.is_empty(), "{:?}", textured.warnings);
    for bad in [
        json!({ "sheenColorFactor": [1.5, 1, 1] }),
        json!({ "sheenColorFactor": [1, 1] }),
        json!({ "sheenColorFactor": [1, 1, 1], "sheenRoughnessFactor": "rough" }),
        json!({ "sheenColorFactor": [1, 1, 1], "sheenColorTexture": { "index": 7 } }),
    ] {
        let error = sheened(0.0, bad.clone()).expect_err("refused");
        assert!(error.to_string().contains("sheen"), "{bad}: {error}");
    }
    let mut doc = quad_doc(None);
    doc.json["extensionsRequired"] = json!(["KHR_materials_sheen"]);
    doc.json["extensionsUsed"] = json!(["KHR_materials_sheen"]);
    assert!(doc.load().is_ok(), "KHR_materials_sheen may be required");
}

/// `KHR_materials_anisotropy` as `Material::anisotropy` (strength, rotation, texture read as
/// data); a smooth metal brushed becomes rough metal of the least brushed width; a strength
/// of 0 is none; a material that is not wholly metal is warned about (only the metal's lobe
/// is brushed); bad values are refused; it may be required.
#[test]
fn anisotropy_is_read() {
    const ANISOTROPY: &str = "KHR_materials_anisotropy";
    let brushed = |metallic: f32, roughness: f32, anisotropy: Value| {
        let mut material = pbr(metallic, roughness);
        material["extensions"] = json!({ ANISOTROPY: anisotropy });
        quad_doc(Some(material)).load()
    };
    let scene = brushed(
        1.0,
        0.3,
        json!({ "anisotropyStrength": 0.6, "anisotropyRotation": 1.2 }),
    )
    .expect("loads");
    let anisotropy = scene.materials[0].anisotropy.expect("brushed");
    assert_eq!((anisotropy.strength, anisotropy.rotation), (0.6, 1.2));
    assert_eq!(
        scene.materials[0].surface,
        Surface::RoughConductor { alpha: 0.3 * 0.3 }
    );
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
    let smooth = brushed(1.0, 0.0, json!({ "anisotropyStrength": 1.0 })).expect("loads");
    assert_eq!(
        smooth.materials[0].surface,
        Surface::RoughConductor {
            alpha: scene::MIN_BRUSHED_ALPHA
        }
    );
    let none = brushed(1.0, 0.0, json!({ "anisotropyRotation": 1.0 })).expect("loads");
    assert_eq!(none.materials[0].anisotropy, None);
    assert_eq!(none.materials[0].surface, Surface::Mirror);
    let half = brushed(0.5, 0.3, json!({ "anisotropyStrength": 0.5 })).expect("loads");
    assert!(
        half.warnings
            .iter()
            .any(|w| w.contains("metal's lobe only")),
        "{:?}",
        half.warnings
    );
    let mut doc = doc_with_embedded_png();
    doc.push("textures", json!({ "source": 0 }));
    let mut material = pbr(1.0, 0.2);
    material["extensions"] = json!({ ANISOTROPY: {
        "anisotropyStrength": 1.0,
        "anisotropyTexture": { "index": 0 },
    } });
    let material = doc.material(material);
    let mesh = doc.mesh(&QUAD, &QUAD_INDICES, Some(material));
    doc.instance(mesh);
    let textured = doc.load().expect("loads");
    let texture = textured.materials[0].anisotropy.unwrap().texture.unwrap();
    assert!(
        matches!(
            textured.textures[texture as usize].texels,
            Texels::LinearF32(_)
        ),
        "the direction is data"
    );
    for bad in [
        json!({ "anisotropyStrength": 1.5 }),
        json!({ "anisotropyStrength": 0.5, "anisotropyRotation": "a quarter" }),
        json!({ "anisotropyStrength": 0.5, "anisotropyTexture": { "index": 7 } }),
    ] {
        let error = brushed(1.0, 0.3, bad.clone()).expect_err("refused");
        assert!(error.to_string().contains("anisotropy"), "{bad}: {error}");
    }
    let mut doc = quad_doc(None);
    doc.json["extensionsRequired"] = json!([ANISOTROPY]);
    doc.json["extensionsUsed"] = json!([ANISOTROPY]);
    assert!(doc.load().is_ok(), "{ANISOTROPY} may be required");
}

const IRIDESCENCE: &str = "KHR_materials_iridescence";

/// A quad of metalness `metallic` and roughness 0.3 under `KHR_materials_iridescence`
/// `iridescence`.
fn iridescent(metallic: f32, iridescence: Value) -> Result<Scene, scene::SceneError> {
    let mut material = pbr(metallic, 0.3);
    material["extensions"] = json!({ IRIDESCENCE: iridescence });
    quad_doc(Some(material)).load()
}

/// `KHR_materials_iridescence` with its factor alone takes the spec's defaults: index 1.3,
/// thickness from 100 to 400 nm, no textures; a metal keeps it without a warning, and the
/// extension may be required.
#[test]
fn iridescence_defaults_are_read() {
    let scene = iridescent(1.0, json!({ "iridescenceFactor": 0.6 })).expect("loads");
    assert_eq!(
        scene.materials[0].iridescence,
        Some(Iridescence {
            factor: 0.6,
            texture: None,
            ior: 1.3,
            thickness_min: 100.0,
            thickness_max: 400.0,
            thickness_texture: None,
        })
    );
    assert_eq!(
        scene.materials[0].surface,
        Surface::RoughConductor { alpha: 0.3 * 0.3 },
        "the film leaves the metal's lobe as it is"
    );
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
    let mut doc = quad_doc(None);
    doc.json["extensionsRequired"] = json!([IRIDESCENCE]);
    doc.json["extensionsUsed"] = json!([IRIDESCENCE]);
    let required = doc.load().expect("loads");
    assert!(required.warnings.is_empty(), "{:?}", required.warnings);
}

/// Every field of `KHR_materials_iridescence` is read as given (a maximum thickness below the
/// minimum too, which the spec allows); its factor and thickness textures are decoded as
/// linear data, each to a texture of the scene; a texture transform of their own that
/// differs from the base colour's is warned about, naming the slot.
#[test]
fn iridescence_fields_and_textures_are_read() {
    let load = |offset: [f32; 2]| {
        let mut doc = doc_with_two_textures();
        let mut material = pbr(1.0, 0.0);
        material["pbrMetallicRoughness"]["baseColorTexture"] = json!({ "index": 0 });
        material["extensions"] = json!({ IRIDESCENCE: {
            "iridescenceFactor": 0.8,
            "iridescenceTexture": { "index": 0 },
            "iridescenceIor": 1.8,
            "iridescenceThicknessMinimum": 600,
            "iridescenceThicknessMaximum": 250.5,
            "iridescenceThicknessTexture": {
                "index": 1,
                "extensions": { "KHR_texture_transform": { "offset": offset } },
            },
        } });
        let material = doc.material(material);
        let mesh = doc.mesh(&QUAD, &QUAD_INDICES, Some(material));
        doc.instance(mesh);
        doc.load().expect("loads")
    };
    let scene = load([0.0, 0.0]);
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
    let film = scene.materials[0].iridescence.expect("a film");
    assert_eq!(
        (
            film.factor,
            film.ior,
            film.thickness_min,
            film.thickness_max
        ),
        (0.8, 1.8, 600.0, 250.5)
    );
    assert_eq!(
        scene.materials[0].surface,
        Surface::Mirror,
        "a smooth metal stays a mirror"
    );
    let (Some(factor), Some(thickness)) = (film.texture, film.thickness_texture) else {
        panic!("both textures are read: {film:?}");
    };
    assert_ne!(factor, thickness, "two images, two textures");
    for id in [factor, thickness] {
        let texture = scene.textures.get(id as usize).expect("the id resolves");
        assert_eq!((texture.width, texture.height), (2, 1));
        assert!(
            matches!(texture.texels, Texels::LinearF32(_)),
            "texture {id} is data"
        );
    }
    assert_ne!(
        scene.materials[0].base_color_texture,
        Some(factor),
        "the base colour is decoded apart, as sRGB"
    );
    let shifted = load([0.5, 0.0]);
    assert!(
        (shifted.warnings.iter())
            .any(|w| w.contains("iridescenceThicknessTexture")
                && w.contains("KHR_texture_transform")),
        "{:?}",
        shifted.warnings
    );
    assert!(
        !shifted
            .warnings
            .iter()
            .any(|w| w.contains("iridescenceTexture'")),
        "{:?}",
        shifted.warnings
    );
}

/// A factor of 0 (the default) is no film, whatever else the extension says (its texture can
/// only lower the factor), and its textures are not read.
#[test]
fn iridescence_of_factor_0_is_none() {
    for film in [
        json!({}),
        json!({ "iridescenceFactor": 0.0, "iridescenceIor": 2.0 }),
        json!({ "iridescenceFactor": 0, "iridescenceTexture": { "index": 0 } }),
    ] {
        let mut doc = doc_with_embedded_png();
        doc.push("textures", json!({ "source": 0 }));
        let mut material = pbr(1.0, 0.3);
        material["extensions"] = json!({ IRIDESCENCE: film.clone() });
        let material = doc.material(material);
        let mesh = doc.mesh(&QUAD, &QUAD_INDICES, Some(material));
        doc.instance(mesh);
        let scene = doc.load().expect("loads");
        assert_eq!(scene.materials[0].iridescence, None, "{film}");
        assert!(scene.textures.is_empty(), "{film}: no texture read");
        assert!(scene.warnings.is_empty(), "{film}: {:?}", scene.warnings);
    }
}

/// Values outside the spec's ranges are refused in one line naming the field: a factor
/// outside [0, 1], an index below 1 or beyond f32, a negative or infinite thickness, a
/// number that is not one, a texture that does not exist.
#[test]
fn bad_iridescence_values_are_refused() {
    for (film, field) in [
        (json!({ "iridescenceFactor": 1.5 }), "iridescenceFactor"),
        (json!({ "iridescenceFactor": -0.25 }), "iridescenceFactor"),
        (json!({ "iridescenceFactor": "full" }), "iridescenceFactor"),
        (
            json!({ "iridescenceFactor": 1, "iridescenceIor": 0.9 }),
            "iridescenceIor",
        ),
        (
            json!({ "iridescenceFactor": 1, "iridescenceIor": 1e39 }),
            "iridescenceIor",
        ),
        (
            json!({ "iridescenceFactor": 1, "iridescenceThicknessMinimum": -1 }),
            "iridescenceThicknessMinimum",
        ),
        (
            json!({ "iridescenceFactor": 1, "iridescenceThicknessMaximum": -400 }),
            "iridescenceThicknessMaximum",
        ),
        (
            json!({ "iridescenceFactor": 1, "iridescenceThicknessMaximum": 1e39 }),
            "iridescenceThicknessMaximum",
        ),
        (
            json!({ "iridescenceFactor": 1, "iridescenceTexture": { "index": 7 } }),
            "iridescenceTexture",
        ),
        (
            json!({ "iridescenceFactor": 1, "iridescenceThicknessTexture": { "index": 7 } }),
            "iridescenceThicknessTexture",
        ),
    ] {
        let error = iridescent(1.0, film.clone())
            .expect_err("refused")
            .to_string();
        assert_mentions(&error, &["material 0", field]);
        assert!(!error.contains('\n'), "one line: {error}");
    }
    // Refused on a dielectric too, where the film is then ignored.
    let error = iridescent(
        0.0,
        json!({ "iridescenceFactor": 1, "iridescenceIor": 0.5 }),
    )
    .expect_err("refused");
    assert_mentions(&error.to_string(), &["iridescenceIor"]);
}

/// The film is rendered on metal, glass and plastic's coat: an opaque dielectric (plastic)
/// keeps it, also where a metallic-roughness texture maps it, and so do a dielectric and a
/// metal rough enough to be rendered Lambertian without it, which keep their lobes (rough
/// plastic and rough metal of width roughness²); without a specular layer it is warned about
/// once and dropped; glass, smooth or frosted, keeps it; a partly metal material keeps it on
/// every member of its blend, and so does a metal whose metalness a texture maps.
#[test]
fn iridescence_keeps_its_layer_and_is_ignored_only_without_one() {
    let scene = iridescent(0.0, json!({ "iridescenceFactor": 1.0 })).expect("loads");
    assert!(matches!(
        scene.materials[0].surface,
        Surface::Plastic { .. }
    ));
    assert!(scene.materials[0].iridescence.is_some());
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
    let film = json!({ IRIDESCENCE: { "iridescenceFactor": 1.0 } });
    let mut material = pbr(0.0, 0.3);
    material["extensions"] = film.clone();
    let mapped = metallic_roughness_quad(material);
    let plastic = &mapped.materials[mapped.triangles[0].material as usize];
    assert!(plastic.roughness_map.is_some() && plastic.iridescence.is_some());
    assert!(mapped.warnings.is_empty(), "{:?}", mapped.warnings);

    // A rough dielectric and a rough metal keep their lobes under the film.
    for (metallic, lobe) in [
        (
            0.0,
            Surface::Plastic {
                ior: 1.5,
                alpha: 0.7 * 0.7,
            },
        ),
        (1.0, Surface::RoughConductor { alpha: 0.7 * 0.7 }),
    ] {
        let mut matte = pbr(metallic, 0.7);
        matte["extensions"] = film.clone();
        let scene = quad_doc(Some(matte)).load().expect("loads");
        assert_eq!(scene.materials[0].surface, lobe);
        assert!(scene.materials[0].iridescence.is_some());
        assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
    }
    // One whose specular layer is taken away, or whose index matches the air's.
    for layerless in [
        json!({ "KHR_materials_specular": { "specularFactor": 0.0 } }),
        json!({ "KHR_materials_ior": { "ior": 1.0 } }),
    ] {
        let mut bare = pbr(0.0, 0.3);
        bare["extensions"] = layerless.clone();
        bare["extensions"][IRIDESCENCE] = json!({ "iridescenceFactor": 1.0 });
        let scene = quad_doc(Some(bare)).load().expect("loads");
        assert_eq!(scene.materials[0].surface, Surface::Diffuse, "{layerless}");
        assert!(scene.materials.iter().all(|m| m.iridescence.is_none()));
        assert_eq!(
            scene.warnings,
            vec![
                "material 0: KHR_materials_iridescence on an opaque dielectric without a \
                 specular layer (specularFactor 0 or ior 1, rendered Lambertian) is not \
                 modelled: its film is ignored"
                    .to_string()
            ],
            "{layerless}"
        );
    }

    // Glass keeps it, smooth or frosted.
    for roughness in [0.0, 0.3] {
        let mut glass = pbr(0.0, roughness);
        glass["extensions"] = json!({
            IRIDESCENCE: { "iridescenceFactor": 1.0 },
            "KHR_materials_transmission": { "transmissionFactor": 1.0 },
        });
        let scene = quad_doc(Some(glass)).load().expect("loads");
        let material = &scene.materials[scene.triangles[0].material as usize];
        assert!(material.iridescence.is_some(), "roughness {roughness}");
        assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
    }

    let half = iridescent(0.5, json!({ "iridescenceFactor": 1.0 })).expect("loads");
    let id = half.triangles[0].material as usize;
    let other = half.materials[id].blend.expect("a blend").other as usize;
    for member in [id, other] {
        assert!(
            half.materials[member].iridescence.is_some(),
            "member {member}"
        );
    }
    assert!(half.warnings.is_empty(), "{:?}", half.warnings);
    let mut material = pbr(1.0, 0.3);
    material["extensions"] = film;
    let mapped = metallic_roughness_quad(material);
    let metal = &mapped.materials[mapped.triangles[0].material as usize];
    assert!(metal.roughness_map.is_some() && metal.iridescence.is_some());
    assert!(mapped.warnings.is_empty(), "{:?}", mapped.warnings);
}

/// `make_scenes`' writer writes a film as `KHR_materials_iridescence` (listed in
/// `extensionsUsed`), which loads back as it was.
#[test]
fn iridescence_round_trips_through_the_writer() {
    let mut fixture = scene::testing::cornell_brushed();
    let film = Iridescence {
        factor: 0.7,
        texture: None,
        ior: 1.45,
        thickness_min: 210.5,
        thickness_max: 180.0,
        thickness_texture: None,
    };
    let mut filmed = 0;
    for m in &mut fixture.materials {
        if matches!(m.surface, Surface::Mirror | Surface::RoughConductor { .. }) {
            m.iridescence = Some(film);
            filmed += 1;
        }
    }
    assert!(filmed > 0, "the fixture has metal");
    let dir = tempfile::tempdir().expect("tempdir");
    gltf_writer::write(&fixture, "iridescent", dir.path()).expect("written");
    let path = dir.path().join("iridescent.gltf");
    let json: Value = serde_json::from_slice(&std::fs::read(&path).expect("read")).expect("JSON");
    let used = json["extensionsUsed"].as_array().expect("extensionsUsed");
    assert!(used.contains(&json!(IRIDESCENCE)), "{used:?}");
    let loaded = scene::load(&path).expect("loads");
    assert!(loaded.warnings.is_empty(), "{:?}", loaded.warnings);
    assert_eq!(loaded.materials.len(), fixture.materials.len());
    for (x, y) in loaded.materials.iter().zip(&fixture.materials) {
        assert_eq!(x.iridescence, y.iridescence, "{}", y.name);
    }
}

/// `KHR_materials_diffuse_transmission`'s factors as `Material::diffuse_transmission` (the
/// colour white by default), on every member of a blend; a factor of 0 is none; its strength
/// texture is read as data, its colour texture as sRGB; bad factors are refused; a volume is
/// warned about (the surface is thin); it may be required.
#[test]
fn diffuse_transmission_is_read() {
    const DIFFUSE: &str = "KHR_materials_diffuse_transmission";
    let translucent = |metallic: f32, transmission: Value| {
        let mut material = pbr(metallic, 0.3);
        material["extensions"] = json!({ DIFFUSE: transmission });
        quad_doc(Some(material)).load()
    };
    let scene = translucent(
        0.0,
        json!({ "diffuseTransmissionFactor": 0.4, "diffuseTransmissionColorFactor": [0.9, 0.5, 0.2] }),
    )
    .expect("loads");
    let transmission = scene.materials[0]
        .diffuse_transmission
        .expect("transmission");
    assert_eq!(
        (transmission.factor, transmission.color),
        (0.4, Vec3::new(0.9, 0.5, 0.2))
    );
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
    let white = translucent(0.0, json!({ "diffuseTransmissionFactor": 1.0 })).expect("loads");
    assert_eq!(
        white.materials[0].diffuse_transmission.map(|t| t.color),
        Some(Vec3::ONE),
        "the colour is white by default"
    );
    let none =
        translucent(0.0, json!({ "diffuseTransmissionColorFactor": [1, 0, 0] })).expect("loads");
    assert_eq!(
        none.materials[0].diffuse_transmission, None,
        "factor 0: none"
    );
    let half = translucent(0.5, json!({ "diffuseTransmissionFactor": 0.5 })).expect("loads");
    let id = half.triangles[0].material as usize;
    let other = half.materials[id].blend.expect("a blend").other as usize;
    for member in [id, other] {
        let transmission = half.materials[member].diffuse_transmission;
        assert!(transmission.is_some(), "member {member}");
    }
    let mut doc = doc_with_embedded_png();
    doc.push("textures", json!({ "source": 0 }));
    let mut material = pbr(0.0, 0.8);
    material["extensions"] = json!({ DIFFUSE: {
        "diffuseTransmissionFactor": 1.0,
        "diffuseTransmissionTexture": { "index": 0 },
        "diffuseTransmissionColorTexture": { "index": 0 },
    } });
    let material = doc.material(material);
    let mesh = doc.mesh(&QUAD, &QUAD_INDICES, Some(material));
    doc.instance(mesh);
    let textured = doc.load().expect("loads");
    let transmission = textured.materials[0].diffuse_transmission.unwrap();
    let (strength, color) = (
        transmission.texture.unwrap(),
        transmission.color_texture.unwrap(),
    );
    assert!(
        matches!(
            textured.textures[strength as usize].texels,
            Texels::LinearF32(_)
        ),
        "the strength is data"
    );
    assert!(
        !matches!(
            textured.textures[color as usize].texels,
            Texels::LinearF32(_)
        ),
        "the colour is sRGB"
    );
    assert!(textured.warnings.is_empty(), "{:?}", textured.warnings);
    for bad in [
        json!({ "diffuseTransmissionFactor": 1.5 }),
        json!({ "diffuseTransmissionFactor": "half" }),
        json!({ "diffuseTransmissionFactor": 1, "diffuseTransmissionColorFactor": [1, 1] }),
        json!({ "diffuseTransmissionFactor": 1, "diffuseTransmissionTexture": { "index": 7 } }),
    ] {
        let error = translucent(0.0, bad.clone()).expect_err("refused");
        assert!(
            error.to_string().contains("diffuseTransmission"),
            "{bad}: {error}"
        );
    }
    // With a volume's thickness the surface bounds a translucent solid, which absorbs inside
    // by the volume's attenuation; without one it is a sheet, whatever the attenuation.
    let with_volume = |volume: Value| {
        let mut material = pbr(0.0, 0.3);
        material["extensions"] = json!({
            DIFFUSE: { "diffuseTransmissionFactor": 0.5 },
            "KHR_materials_volume": volume,
        });
        quad_doc(Some(material)).load()
    };
    let attenuation = json!({ "attenuationColor": [0.5, 0.25, 1.0], "attenuationDistance": 2.0 });
    let mut thick_volume = attenuation.clone();
    thick_volume["thicknessFactor"] = json!(1.0);
    let thick = with_volume(thick_volume).expect("loads");
    let solid = &thick.materials[0];
    assert!(solid.diffuse_transmission.is_some_and(|t| t.volume));
    assert!(solid.bounds_volume());
    let expected = scene::absorption_from_attenuation(Vec3::new(0.5, 0.25, 1.0), 2.0);
    assert_eq!(solid.interior_absorption(), expected);
    assert!(thick.warnings.is_empty(), "{:?}", thick.warnings);
    let thin = with_volume(attenuation).expect("loads");
    assert!(!thin.materials[0].bounds_volume());
    assert_eq!(thin.materials[0].interior_absorption(), Vec3::ZERO);
    let error = with_volume(json!({ "thicknessFactor": -1.0 })).expect_err("refused");
    assert!(error.to_string().contains("thicknessFactor"), "{error}");

    let mut doc = quad_doc(None);
    doc.json["extensionsRequired"] = json!([DIFFUSE]);
    doc.json["extensionsUsed"] = json!([DIFFUSE]);
    assert!(doc.load().is_ok(), "{DIFFUSE} may be required");
}

/// `KHR_materials_volume_scatter` (a draft) on a translucent solid splits the volume's
/// attenuation (the extinction) by the single-scattering albedo of `multiscatterColor`
/// (`scene::single_scatter_albedo`: 0 → 0 (6e-6 in f32), 1 → 1, rising between) and reads
/// `scatterAnisotropy`; so on solid glass (murky water); on a blend of glass and plastic it
/// is warned about and ignored; an anisotropy outside (−1, 1) is refused in words.
#[test]
fn volume_scatter_splits_a_translucent_solid_s_extinction() {
    const TRANSLUCENT: &str = "KHR_materials_diffuse_transmission";
    const HALF_GLASS: &str = "half glass";
    let scattering = |volume: Value, scatter: Value, transmission: &str| {
        let mut material = pbr(0.0, 0.3);
        let mut extensions = json!({
            "KHR_materials_volume": volume,
            "KHR_materials_volume_scatter": scatter,
        });
        match transmission {
            TRANSLUCENT => extensions[TRANSLUCENT] = json!({ "diffuseTransmissionFactor": 1.0 }),
            HALF_GLASS => {
                extensions["KHR_materials_transmission"] = json!({ "transmissionFactor": 0.5 })
            }
            _ => extensions[transmission] = json!({ "transmissionFactor": 1.0 }),
        };
        material["extensions"] = extensions;
        quad_doc(Some(material)).load()
    };
    let volume = json!({
        "thicknessFactor": 1.0, "attenuationColor": [0.5, 0.25, 0.8], "attenuationDistance": 2.0
    });
    let scatter = json!({ "multiscatterColor": [0.0, 0.5, 1.0], "scatterAnisotropy": 0.4 });
    let scene = scattering(volume.clone(), scatter.clone(), TRANSLUCENT).expect("loads");
    let m = &scene.materials[0];
    let extinction = scene::absorption_from_attenuation(Vec3::new(0.5, 0.25, 0.8), 2.0);
    let albedo = scene::single_scatter_albedo(Vec3::new(0.0, 0.5, 1.0));
    assert!(albedo.x < 1e-4 && albedo.z == 1.0, "{albedo}");
    assert!(albedo.y > 0.5 && albedo.y < 1.0, "{albedo}");
    assert!((m.interior_extinction() - extinction).abs().max_element() < 1e-6);
    assert!(
        (m.interior_scattering() - extinction * albedo)
            .abs()
            .max_element()
            < 1e-6
    );
    assert_eq!(m.scatter_anisotropy, 0.4);
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
    let glass = scattering(
        volume.clone(),
        scatter.clone(),
        "KHR_materials_transmission",
    )
    .expect("loads");
    let murky = &glass.materials[0];
    assert!(murky.has_murky_glass());
    assert!(
        (murky.interior_extinction() - extinction)
            .abs()
            .max_element()
            < 1e-6
    );
    assert!(
        (murky.interior_scattering() - extinction * albedo)
            .abs()
            .max_element()
            < 1e-6
    );
    assert!(glass.warnings.is_empty(), "{:?}", glass.warnings);
    let blend = scattering(volume.clone(), scatter, HALF_GLASS).expect("loads");
    assert!(blend.materials[0].blend.is_some());
    assert_eq!(blend.materials[0].interior_scattering(), Vec3::ZERO);
    assert_eq!(blend.materials[0].interior_absorption(), extinction);
    assert!(
        blend
            .warnings
            .iter()
            .any(|w| w.contains("only translucent solids")),
        "{:?}",
        blend.warnings
    );
    let error =
        scattering(volume, json!({ "scatterAnisotropy": 1.0 }), TRANSLUCENT).expect_err("refused");
    assert!(error.to_string().contains("scatterAnisotropy"), "{error}");
}

/// `KHR_materials_transmission`'s texture (`Material::transmission_texture`, linear data) on
/// every member of the blend it makes; at factor 1 the opaque member stays, with what the
/// texel leaves (the glass's weight just short of 1); with factor 0 there is no glass and the
/// texture is not read.
#[test]
fn transmission_textures_weigh_the_glass() {
    let textured = |factor: f32| {
        let mut doc = doc_with_embedded_png();
        doc.push("textures", json!({ "source": 0 }));
        let mut material = pbr(0.0, 0.0);
        material["extensions"] = json!({ "KHR_materials_transmission": {
            "transmissionFactor": factor,
            "transmissionTexture": { "index": 0 },
        } });
        let material = doc.material(material);
        let mesh = doc.mesh(&QUAD, &QUAD_INDICES, Some(material));
        doc.instance(mesh);
        doc.load().expect("loads")
    };
    let full = textured(1.0);
    let first = full.triangles[0].material as usize;
    let glass = &full.materials[first];
    assert!(glass.surface.is_glass(), "{:?}", glass.surface);
    let blend = glass.blend.expect("glass and the opaque member");
    assert!(
        blend.weight > 0.999 && blend.weight < 1.0,
        "{}",
        blend.weight
    );
    let opaque = &full.materials[blend.other as usize];
    assert!(matches!(opaque.surface, Surface::Plastic { .. }));
    assert_eq!(glass.transmission_texture, Some(0));
    assert_eq!(opaque.transmission_texture, Some(0));
    assert!(matches!(full.textures[0].texels, Texels::LinearF32(_)));
    let half = textured(0.5);
    let first = half.triangles[0].material as usize;
    assert_eq!(half.materials[first].blend.map(|b| b.weight), Some(0.5));
    let none = textured(0.0);
    assert!(
        none.materials
            .iter()
            .all(|m| m.transmission_texture.is_none())
    );
    assert!(
        none.textures.is_empty(),
        "factor 0: the texture is not read"
    );
}

/// The layers' textures read the material's one set of coordinates: a transform of their own
/// that differs from the base colour's is warned about, naming the slot; the same one is not.
#[test]
fn layer_textures_with_their_own_transform_are_warned_about() {
    let load = |offset: [f32; 2]| {
        let mut doc = doc_with_embedded_png();
        doc.push("textures", json!({ "source": 0 }));
        let shifted = json!({ "index": 0, "extensions": {
            "KHR_texture_transform": { "offset": offset } } });
        let mut material = pbr(0.0, 0.4);
        material["pbrMetallicRoughness"]["baseColorTexture"] = json!({ "index": 0 });
        material["extensions"] = json!({
            "KHR_materials_sheen": { "sheenColorFactor": [1, 1, 1], "sheenColorTexture": shifted },
            "KHR_materials_transmission": {
                "transmissionFactor": 0.5,
                "transmissionTexture": shifted,
            },
            "KHR_materials_diffuse_transmission": {
                "diffuseTransmissionFactor": 0.5,
                "diffuseTransmissionTexture": shifted,
            },
        });
        let material = doc.material(material);
        let mesh = doc.mesh(&QUAD, &QUAD_INDICES, Some(material));
        doc.instance(mesh);
        doc.load().expect("loads")
    };
    let shifted = load([0.5, 0.0]);
    for slot in [
        "sheenColorTexture",
        "transmissionTexture",
        "diffuseTransmissionTexture",
    ] {
        assert!(
            (shifted.warnings.iter())
                .any(|w| w.contains(slot) && w.contains("KHR_texture_transform")),
            "{slot}: {:?}",
            shifted.warnings
        );
    }
    let identity = load([0.0, 0.0]);
    assert!(identity.warnings.is_empty(), "{:?}", identity.warnings);
}

/// A strip folded along x = 1: a flat quad (x 0–1) and one rising at 45° (x 1–2), smooth
/// normals, u running along the strip and v along +y, under `material`, without TANGENT.
fn folded_strip(doc: &mut Doc, material: usize) {
    let s = std::f32::consts::FRAC_1_SQRT_2;
    let positions = [
        [0.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [1.0, 0.0, 0.0],
        [1.0, 1.0, 0.0],
        [1.0 + s, 0.0, s],
        [1.0 + s, 1.0, s],
    ];
    // At the fold, the normal halfway between the two faces'.
    let fold = (Vec3::Z + Vec3::new(-s, 0.0, s)).normalize().to_array();
    let up_slope = [-s, 0.0, s];
    let normals = [
        [0.0, 0.0, 1.0],
        [0.0, 0.0, 1.0],
        fold,
        fold,
        up_slope,
        up_slope,
    ];
    let uvs = [
        [0.0, 0.0],
        [0.0, 1.0],
        [1.0, 0.0],
        [1.0, 1.0],
        [2.0, 0.0],
        [2.0, 1.0],
    ];
    two_quad_strip(doc, &positions, &normals, &uvs, material);
}

/// Two quads sharing the edge of vertices 2 and 3 (0–1–3–2 and 2–3–5–4), with these
/// attributes and no TANGENT, shown under `material`.
fn two_quad_strip(
    doc: &mut Doc,
    positions: &[[f32; 3]; 6],
    normals: &[[f32; 3]; 6],
    uvs: &[[f32; 2]; 6],
    material: usize,
) {
    let (position, normal, uv) = (doc.vec3s(positions), doc.vec3s(normals), doc.vec2s(uvs));
    let indices = doc.indices(&[0, 2, 3, 0, 3, 1, 2, 4, 5, 2, 5, 3], UNSIGNED_SHORT);
    let primitive = json!({
        "attributes": { "POSITION": position, "NORMAL": normal, "TEXCOORD_0": uv },
        "indices": indices,
        "material": material,
    });
    let mesh = doc.push("meshes", json!({ "primitives": [primitive] }));
    doc.instance(mesh);
}

/// Where a file gives no TANGENT, a normal-mapped primitive's tangents are made from its
/// texture coordinates: unit, perpendicular to each vertex normal, along increasing u (the
/// fold's between its two faces' directions), the bitangent w · n × t towards the image's top
/// (decreasing v, −y here); a material that reads no frame gets none.
#[test]
fn tangents_are_made_for_normal_maps_where_the_file_has_none() {
    let mut doc = doc_with_embedded_png();
    doc.push("textures", json!({ "source": 0 }));
    let mapped = doc.material(json!({ "normalTexture": { "index": 0 } }));
    folded_strip(&mut doc, mapped);
    let scene = doc.load().expect("loads");
    assert!(scene.has_vertex_tangents());
    let slope = Vec3::new(1.0, 0.0, 1.0).normalize();
    for v in scene.triangles.iter().flat_map(|t| t.vertices) {
        let t = v.tangent.truncate();
        assert!((t.length() - 1.0).abs() < 1e-5, "{t}");
        assert!(t.dot(v.normal).abs() < 1e-5, "{t} against {}", v.normal);
        let bitangent = v.normal.cross(t) * v.tangent.w;
        assert!(bitangent.dot(-Vec3::Y) > 0.99, "{bitangent}");
        if v.position.x == 0.0 {
            assert!((t - Vec3::X).length() < 1e-5, "{t}");
        } else if v.position.x == 1.0 {
            assert!(t.dot(Vec3::X) > 0.8 && t.dot(slope) > 0.8, "{t}");
        } else {
            assert!((t - slope).length() < 1e-5, "{t}");
        }
    }
    let mut plain = Doc::default();
    let material = plain.material(json!({}));
    folded_strip(&mut plain, material);
    assert!(!plain.load().expect("loads").has_vertex_tangents());
}

/// A mirror seam through shared vertices: the strip's second quad takes its texture mirrored
/// (u running back), so the vertices on the fold serve triangles of both handednesses: they
/// are split as MikkTSpace splits them, each triangle there taking its own side's tangent,
/// so neither side's frame is bent towards the other's.
#[test]
fn tangents_are_split_at_a_mirror_seam() {
    let mut doc = doc_with_embedded_png();
    doc.push("textures", json!({ "source": 0 }));
    let mapped = doc.material(json!({ "normalTexture": { "index": 0 } }));
    let positions = [
        [0.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [1.0, 0.0, 0.0],
        [1.0, 1.0, 0.0],
        [2.0, 0.0, 0.0],
        [2.0, 1.0, 0.0],
    ];
    let uvs = [
        [0.0, 0.0],
        [0.0, 1.0],
        [1.0, 0.0],
        [1.0, 1.0],
        [0.0, 0.0],
        [0.0, 1.0],
    ];
    two_quad_strip(&mut doc, &positions, &[[0.0, 0.0, 1.0]; 6], &uvs, mapped);
    let scene = doc.load().expect("loads");
    for triangle in &scene.triangles {
        let centre_x = triangle.vertices.iter().map(|v| v.position.x).sum::<f32>() / 3.0;
        // v grows along +y, so the image's top is −y: w · (+z × +x) = −y.
        let expected = if centre_x < 1.0 {
            glam::Vec4::new(1.0, 0.0, 0.0, -1.0)
        } else {
            glam::Vec4::new(-1.0, 0.0, 0.0, 1.0)
        };
        for v in triangle.vertices {
            assert!(
                (v.tangent - expected).length() < 1e-5,
                "{} at {} of a triangle centred at x = {centre_x}",
                v.tangent,
                v.position
            );
        }
    }
}

/// A quad whose TEXCOORD_0 is (x, y) and TEXCOORD_1 (1 − y, x) of each corner (absent where
/// `second_set` is false), under `material`.
fn quad_with_two_uv_sets(material: Value, second_set: bool) -> Scene {
    let mut doc = doc_with_embedded_png();
    doc.push("textures", json!({ "source": 0 }));
    let material = doc.material(material);
    let position = doc.vec3s(&QUAD);
    let uv0 = doc.vec2s(&QUAD.map(|[x, y, _]| [x, y]));
    let uv1 = doc.vec2s(&QUAD.map(|[x, y, _]| [1.0 - y, x]));
    let indices = doc.indices(&QUAD_INDICES, 5123);
    let mut attributes = json!({ "POSITION": position, "TEXCOORD_0": uv0 });
    if second_set {
        attributes["TEXCOORD_1"] = json!(uv1);
    }
    let primitive = json!({ "attributes": attributes, "indices": indices, "material": material });
    let mesh = doc.push("meshes", json!({ "primitives": [primitive] }));
    doc.instance(mesh);
    doc.load_as(Layout::Glb).expect("loads")
}

/// Whether every vertex's coordinates are `uv` of its position.
fn uvs_are(scene: &Scene, uv: impl Fn(Vec3) -> Vec2) -> bool {
    let vertices = scene.triangles.iter().flat_map(|t| t.vertices);
    vertices.clone().count() == 6
        && vertices
            .into_iter()
            .all(|v| (v.uv - uv(v.position)).length() < 1e-6)
}

/// A material whose textures use TEXCOORD_1 (by `texCoord`, or by its texture transform's,
/// which overrides it) gives its primitives' vertices that set; its other textures asking
/// for TEXCOORD_0 read the same (kousen keeps one set a vertex), with a warning; a primitive
/// without the set its material uses reads (0, 0), with a warning.
#[test]
fn a_material_s_textures_read_the_coordinate_set_they_name() {
    let first = |p: Vec3| Vec2::new(p.x, p.y);
    let second = |p: Vec3| Vec2::new(1.0 - p.y, p.x);
    let base_on = |set: u32| json!({ "pbrMetallicRoughness": { "baseColorTexture": { "index": 0, "texCoord": set } } });
    let scene = quad_with_two_uv_sets(base_on(1), true);
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
    assert!(uvs_are(&scene, second));
    let scene = quad_with_two_uv_sets(base_on(0), true);
    assert!(uvs_are(&scene, first));

    let overridden = json!({ "pbrMetallicRoughness": { "baseColorTexture": { "index": 0,
        "extensions": { "KHR_texture_transform": { "texCoord": 1 } } } } });
    let scene = quad_with_two_uv_sets(overridden, true);
    assert!(
        uvs_are(&scene, second),
        "the transform's texCoord overrides the slot's"
    );

    // Between the emissive texture and the normal map the emissive one decides; the normal
    // map, on the other set, is warned about.
    let mixed = json!({
        "normalTexture": { "index": 0, "texCoord": 1 },
        "emissiveTexture": { "index": 0, "texCoord": 0 },
        "emissiveFactor": [1, 1, 1],
    });
    let scene = quad_with_two_uv_sets(mixed, true);
    assert!(
        uvs_are(&scene, first),
        "the emissive texture comes first: set 0"
    );
    assert_warned(&scene, &["normalTexture uses TEXCOORD_1"]);
    let mixed = json!({
        "pbrMetallicRoughness": { "metallicRoughnessTexture": { "index": 0, "texCoord": 0 } },
        "normalTexture": { "index": 0, "texCoord": 1 },
    });
    let scene = quad_with_two_uv_sets(mixed, true);
    assert!(
        uvs_are(&scene, second),
        "the normal map comes before the metallic-roughness one"
    );
    assert_warned(
        &scene,
        &["metallicRoughnessTexture uses TEXCOORD_0", "use TEXCOORD_1"],
    );

    let scene = quad_with_two_uv_sets(base_on(1), false);
    assert!(uvs_are(&scene, |_| Vec2::ZERO));
    assert_warned(&scene, &["has no TEXCOORD_1"]);
    let scene = quad_with_two_uv_sets(base_on(9), true);
    assert!(uvs_are(&scene, |_| Vec2::ZERO));
    assert_warned(&scene, &["only TEXCOORD_0 to TEXCOORD_7"]);
}

/// Asserts one of the scene's warnings mentions every one of `parts`.
fn assert_warned(scene: &Scene, parts: &[&str]) {
    assert!(
        (scene.warnings.iter()).any(|w| parts.iter().all(|p| w.contains(p))),
        "no warning mentions {parts:?}: {:?}",
        scene.warnings
    );
}

/// `KHR_materials_pbrSpecularGlossiness` is read as the metallic-roughness material that
/// `KHR_materials_specular` gives as its equivalent: the diffuse colour and texture as the base
/// colour, the specular colour (and the texture's colour) as a specular layer over an index of
/// 0, so its reflectance head on is that colour, and one minus the glossiness as the roughness.
/// The coat takes the index whose reflectance head on is the layer's mean (a dielectric's 4 %:
/// 1.5; a metal's colour: capped at 3), and keeps its lobe however rough; the glossiness in
/// the texture's alpha becomes a roughness texture, 1 − factor × alpha.
#[test]
fn specular_glossiness_materials_read_as_their_metallic_roughness_equivalent() {
    let load = |spec_gloss: Value| {
        let mut doc = doc_with_two_textures();
        doc.json["extensionsUsed"] = json!(["KHR_materials_pbrSpecularGlossiness"]);
        let material = doc.material(json!({
            "extensions": { "KHR_materials_pbrSpecularGlossiness": spec_gloss },
        }));
        let mesh = doc.mesh(&QUAD, &QUAD_INDICES, Some(material));
        doc.instance(mesh);
        doc.load().expect("loads")
    };
    let plastic = load(json!({
        "diffuseFactor": [0.8, 0.2, 0.1, 1.0],
        "specularFactor": [0.04, 0.04, 0.04],
        "glossinessFactor": 0.8,
    }));
    assert!(plastic.warnings.is_empty(), "{:?}", plastic.warnings);
    let material = &plastic.materials[0];
    assert_eq!(material.base_color, Vec3::new(0.8, 0.2, 0.1));
    let Surface::Plastic { ior, alpha } = material.surface else {
        panic!("{:?}", material.surface);
    };
    assert!((ior - 1.5).abs() < 1e-4, "coat index {ior}");
    assert!((alpha - 0.2 * 0.2).abs() < 1e-6, "α {alpha}");
    let (f0, f90) = material.specular.expect("a layer").at(None, None);
    assert!(f0.abs_diff_eq(Vec3::splat(0.04), 1e-6), "{f0}");
    assert_eq!(f90, 1.0);

    // A metal as specular-glossiness writes it: black diffuse, coloured specular; rough, it
    // keeps its coat (as Lambertian it would be black).
    let gold = Vec3::new(1.0, 0.78, 0.34);
    for (glossiness, expected_alpha) in [(1.0f32, 0.0f32), (0.3, 0.49)] {
        let metal = load(json!({
            "diffuseFactor": [0.0, 0.0, 0.0, 1.0],
            "specularFactor": gold.to_array(),
            "glossinessFactor": glossiness,
        }));
        let material = &metal.materials[0];
        let Surface::Plastic { ior, alpha } = material.surface else {
            panic!("{:?}", material.surface);
        };
        assert_eq!(ior, 3.0, "capped");
        assert!((alpha - expected_alpha).abs() < 1e-5, "α {alpha}");
        let (f0, _) = material.specular.expect("a layer").at(None, None);
        assert!(f0.abs_diff_eq(gold, 1e-6), "{f0}");
    }

    // Textures: the diffuse one is the base colour's, the specular-glossiness one the layer's
    // colour and, by its alpha, the roughness (texels of alpha 1 and 64/255).
    let textured = load(json!({
        "diffuseTexture": { "index": 0 },
        "specularGlossinessTexture": { "index": 1 },
        "glossinessFactor": 0.8,
    }));
    assert!(textured.warnings.is_empty(), "{:?}", textured.warnings);
    let material = &textured.materials[0];
    assert!(material.base_color_texture.is_some());
    let layer = material.specular.expect("a layer");
    assert!(layer.color_texture.is_some());
    let map = material.roughness_map.expect("a roughness map");
    assert_eq!(map.roughness_factor, 1.0, "the factor is in the texels");
    assert!(map.keeps_lobe, "rough texels keep the coloured coat");
    let Texels::LinearF32(texels) = &textured.textures[map.texture as usize].texels else {
        panic!("linear roughness");
    };
    let roughness: Vec<f32> = texels.iter().map(|t| t[1]).collect();
    let expected = [1.0 - 0.8, 1.0 - 0.8 * 64.0 / 255.0];
    for (r, e) in roughness.iter().zip(expected) {
        assert!((r - e).abs() < 1e-5, "{roughness:?} against {expected:?}");
    }
    assert!(texels.iter().all(|t| t[2] == 0.0), "no metalness");
}
