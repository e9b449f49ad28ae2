//! A minimal glTF 2.0 writer for the fixtures of `scene::testing`.
//!
//! One mesh with one primitive per material (vertices de-duplicated within a primitive,
//! u16 or u32 indices; texture coordinates where a primitive has any), one node per camera,
//! and the binary data in an external `.bin` beside the `.gltf`, textures in it as PNG images
//! (8 bits a channel: linear data as it is, sRGB colour as encoded). Materials follow DESIGN.md's mapping in reverse:
//! - diffuse → metallic 0, roughness 1; mirror → metallic 1, roughness 0; rough conductor →
//!   metallic 1, roughness √α;
//! - a blend (`scene::Blend`) → metallic the metal members' probability, transmission the glass
//!   member's share of the rest, the one roughness of its rough members;
//! - dielectric → `KHR_materials_transmission` 1 and `KHR_materials_ior`, with
//!   `KHR_materials_volume` (thickness: the material's smallest extent) when solid, and
//!   `KHR_materials_dispersion` where it disperses;
//! - a clear coat → `KHR_materials_clearcoat` (roughness √α);
//! - a sheen → `KHR_materials_sheen`;
//! - diffuse transmission → `KHR_materials_diffuse_transmission`, with `KHR_materials_volume`
//!   where it bounds a translucent solid;
//! - anisotropy → `KHR_materials_anisotropy` (strength and rotation);
//! - iridescence → `KHR_materials_iridescence` (factor, index, thickness range and its
//!   factor and thickness textures);
//! - emission → `emissiveFactor` scaled to a maximum of 1, times
//!   `KHR_materials_emissive_strength`.
//!
//! Punctual lights go into `KHR_lights_punctual`, one node each, the colour scaled to a
//! maximum of 1 times the intensity, the node rotated so that its −z is the light's direction.
//!
//! The output depends only on the scene: object keys are sorted and numbers are written as the
//! shortest text that reads back as the same f32.

use std::collections::HashMap;
use std::path::Path;

use glam::{Mat3, Quat, Vec2, Vec3};
use image::ExtendedColorType;
use image::ImageEncoder;
use image::codecs::png::PngEncoder;
use scene::{
    AlphaMode, Camera, Material, PunctualKind, PunctualLight, RoughnessMap, Scene, Surface, Texels,
    Texture, Triangle,
};
use serde_json::{Map, Value, json};

/// A function building a fixture scene.
pub type Fixture = fn() -> Scene;

/// The scenes shipped in `scenes/`, by file stem.
pub const SHIPPED: [(&str, Fixture); 22] = [
    ("cornell-box", scene::testing::cornell_box),
    ("cornell-caustics", scene::testing::cornell_caustics),
    ("cornell-rough", scene::testing::cornell_rough),
    ("cornell-plastic", scene::testing::cornell_plastic),
    ("cornell-spot", scene::testing::cornell_spot),
    ("cornell-frosted", scene::testing::cornell_frosted),
    ("cornell-tinted", scene::testing::cornell_tinted),
    ("cornell-bumpy", scene::testing::cornell_bumpy),
    ("cornell-blended", scene::testing::cornell_blended),
    ("cornell-pool", scene::testing::cornell_pool),
    ("cornell-marble", scene::testing::cornell_marble),
    ("cornell-dispersion", scene::testing::cornell_dispersion),
    (
        "cornell-metallic-roughness",
        scene::testing::cornell_metallic_roughness,
    ),
    ("prism", scene::testing::prism),
    ("cornell-clearcoat", scene::testing::cornell_clearcoat),
    ("cornell-sheen", scene::testing::cornell_sheen),
    ("cornell-translucent", scene::testing::cornell_translucent),
    (
        "cornell-translucent-solids",
        scene::testing::cornell_translucent_solids,
    ),
    ("cornell-brushed", scene::testing::cornell_brushed),
    ("cornell-iridescent", scene::testing::cornell_iridescent),
    ("cornell-murky", scene::testing::cornell_murky),
    ("spheres-on-a-floor", scene::testing::spheres_on_a_floor),
];

const ARRAY_BUFFER: u32 = 34962;
const ELEMENT_ARRAY_BUFFER: u32 = 34963;
const FLOAT: u32 = 5126;
const UNSIGNED_SHORT: u32 = 5123;
const UNSIGNED_INT: u32 = 5125;
const TRIANGLES: u32 = 4;

/// A scene as glTF: the JSON text and the `.bin` it refers to as `<stem>.bin`.
pub struct Encoded {
    pub json: Vec<u8>,
    pub bin: Vec<u8>,
}

/// Writes `<dir>/<stem>.gltf` and `<dir>/<stem>.bin`.
pub fn write(scene: &Scene, stem: &str, dir: &Path) -> std::io::Result<()> {
    let encoded = encode(scene, stem);
    std::fs::write(dir.join(format!("{stem}.bin")), &encoded.bin)?;
    std::fs::write(dir.join(format!("{stem}.gltf")), &encoded.json)
}

pub fn encode(scene: &Scene, stem: &str) -> Encoded {
    let mut doc = Document::default();
    let images: Vec<Value> = scene.textures.iter().map(|t| doc.image(t)).collect();
    // A blend's later members are part of its first material's glTF material, not their own.
    let members: Vec<u32> = scene
        .materials
        .iter()
        .filter_map(|m| m.blend)
        .map(|b| b.other)
        .collect();
    let written: Vec<u32> = (0..scene.materials.len() as u32)
        .filter(|m| !members.contains(m))
        .collect();
    let primitives: Vec<Value> = written
        .iter()
        .enumerate()
        .filter_map(|(index, &m)| {
            let triangles: Vec<&Triangle> =
                scene.triangles.iter().filter(|t| t.material == m).collect();
            (!triangles.is_empty()).then(|| doc.primitive(&triangles, index))
        })
        .collect();
    let materials: Vec<Value> = written
        .iter()
        .map(|&m| {
            let chain = blend_members(&scene.materials, m);
            let map = roughness_map(&scene.materials, m);
            doc.material(
                &scene.materials[m as usize],
                &chain,
                map,
                thickness(scene, m),
            )
        })
        .collect();
    let mut nodes = vec![json!({ "name": stem, "mesh": 0 })];
    let near = znear(scene);
    let cameras: Vec<Value> = scene
        .cameras
        .iter()
        .map(|c| camera_object(c, near))
        .collect();
    nodes.extend(
        scene
            .cameras
            .iter()
            .enumerate()
            .map(|(i, c)| camera_node(c, i)),
    );
    let lights: Vec<Value> = scene
        .lights
        .punctual
        .iter()
        .map(|e| punctual(&e.light))
        .collect();
    nodes.extend(
        scene
            .lights
            .punctual
            .iter()
            .enumerate()
            .map(|(i, e)| light_node(&e.light, i)),
    );
    if !lights.is_empty() {
        doc.extensions.push("KHR_lights_punctual");
    }
    let mut extensions: Vec<&str> = doc.extensions.clone();
    extensions.sort_unstable();
    extensions.dedup();
    let mut root = json!({
        "asset": {
            "version": "2.0",
            "generator": "kousen make_scenes (crates/scene/examples/make_scenes.rs)",
        },
        "scene": 0,
        "scenes": [{ "name": stem, "nodes": (0..nodes.len()).collect::<Vec<_>>() }],
        "nodes": nodes,
        "meshes": [{ "name": stem, "primitives": primitives }],
        "materials": materials,
        "accessors": doc.accessors,
        "bufferViews": doc.views,
        "buffers": [{ "uri": format!("{stem}.bin"), "byteLength": doc.bin.len() }],
    });
    if !cameras.is_empty() {
        root["cameras"] = Value::Array(cameras);
    }
    if !images.is_empty() {
        let textures: Vec<Value> = (0..images.len()).map(|i| json!({ "source": i })).collect();
        root["images"] = Value::Array(images);
        root["textures"] = Value::Array(textures);
    }
    if !extensions.is_empty() {
        root["extensionsUsed"] = json!(extensions);
    }
    if !lights.is_empty() {
        root["extensions"] = json!({ "KHR_lights_punctual": { "lights": lights } });
    }
    let mut json = serde_json::to_vec_pretty(&sorted(root)).expect("JSON values serialise");
    json.push(b'\n');
    Encoded { json, bin: doc.bin }
}

/// glTF's index of a non-metal's specular layer where `KHR_materials_ior` is absent.
const DEFAULT_COAT_IOR: f32 = 1.5;

#[derive(Default)]
struct Document {
    bin: Vec<u8>,
    views: Vec<Value>,
    accessors: Vec<Value>,
    extensions: Vec<&'static str>,
}

impl Document {
    /// Appends `bytes` as a buffer view (of vertex or index data when `target` is given) and
    /// returns its index.
    fn view(&mut self, bytes: &[u8], target: Option<u32>) -> usize {
        while !self.bin.len().is_multiple_of(4) {
            self.bin.push(0);
        }
        let mut view = json!({
            "buffer": 0,
            "byteOffset": self.bin.len(),
            "byteLength": bytes.len(),
        });
        if let Some(target) = target {
            view["target"] = json!(target);
        }
        self.views.push(view);
        self.bin.extend_from_slice(bytes);
        self.views.len() - 1
    }

    fn accessor(&mut self, mut accessor: Value, bytes: &[u8], target: u32) -> usize {
        accessor["bufferView"] = json!(self.view(bytes, Some(target)));
        self.accessors.push(accessor);
        self.accessors.len() - 1
    }

    fn vec3_accessor(&mut self, values: &[Vec3], with_bounds: bool) -> usize {
        let bytes: Vec<u8> = values
            .iter()
            .flat_map(|v| v.to_array())
            .flat_map(f32::to_le_bytes)
            .collect();
        let mut accessor = json!({ "componentType": FLOAT, "count": values.len(), "type": "VEC3" });
        if with_bounds {
            let (min, max) = values
                .iter()
                .fold((Vec3::INFINITY, Vec3::NEG_INFINITY), |(lo, hi), &v| {
                    (lo.min(v), hi.max(v))
                });
            accessor["min"] = numbers(&min.to_array());
            accessor["max"] = numbers(&max.to_array());
        }
        self.accessor(accessor, &bytes, ARRAY_BUFFER)
    }

    /// A texture as a PNG image in the binary buffer.
    fn image(&mut self, texture: &Texture) -> Value {
        let bytes: Vec<u8> = match &texture.texels {
            Texels::Srgb8(texels) => texels.iter().flatten().copied().collect(),
            Texels::LinearF32(texels) => texels
                .iter()
                .flatten()
                .map(|&c| (c.clamp(0.0, 1.0) * 255.0).round() as u8)
                .collect(),
        };
        let mut png = Vec::new();
        PngEncoder::new(&mut png)
            .write_image(
                &bytes,
                texture.width,
                texture.height,
                ExtendedColorType::Rgba8,
            )
            .expect("fixture textures encode");
        let view = self.view(&png, None);
        json!({ "name": texture.name, "bufferView": view, "mimeType": "image/png" })
    }

    /// One primitive: the triangles' distinct (position, normal, uv, tangent) corners and their
    /// indices.
    fn primitive(&mut self, triangles: &[&Triangle], material: usize) -> Value {
        let corners = || triangles.iter().flat_map(|t| t.vertices);
        let textured = corners().any(|v| v.uv != Vec2::ZERO);
        let tangential = corners().all(|v| v.tangent.w != 0.0);
        let mut slots: HashMap<[u32; 12], u32> = HashMap::new();
        let (mut positions, mut normals, mut uvs, mut tangents, mut indices) =
            (Vec::new(), Vec::new(), Vec::new(), Vec::new(), Vec::new());
        for v in corners() {
            let key = [
                &v.position.to_array()[..],
                &v.normal.to_array(),
                &v.uv.to_array(),
                &v.tangent.to_array(),
            ]
            .concat();
            let key: [u32; 12] = std::array::from_fn(|i| key[i].to_bits());
            let index = *slots.entry(key).or_insert_with(|| {
                positions.push(v.position);
                normals.push(v.normal);
                uvs.push(v.uv);
                tangents.push(v.tangent);
                positions.len() as u32 - 1
            });
            indices.push(index);
        }
        let position = self.vec3_accessor(&positions, true);
        let normal = self.vec3_accessor(&normals, false);
        let mut attributes = json!({ "POSITION": position, "NORMAL": normal });
        if textured {
            let bytes: Vec<u8> = (uvs.iter().flat_map(|v| v.to_array()))
                .flat_map(f32::to_le_bytes)
                .collect();
            let accessor = json!({ "componentType": FLOAT, "count": uvs.len(), "type": "VEC2" });
            attributes["TEXCOORD_0"] = json!(self.accessor(accessor, &bytes, ARRAY_BUFFER));
        }
        if tangential {
            let bytes: Vec<u8> = (tangents.iter().flat_map(|t| t.to_array()))
                .flat_map(f32::to_le_bytes)
                .collect();
            let accessor =
                json!({ "componentType": FLOAT, "count": tangents.len(), "type": "VEC4" });
            attributes["TANGENT"] = json!(self.accessor(accessor, &bytes, ARRAY_BUFFER));
        }
        let (component, bytes): (u32, Vec<u8>) = if positions.len() <= u16::MAX as usize {
            (
                UNSIGNED_SHORT,
                indices
                    .iter()
                    .flat_map(|&i| (i as u16).to_le_bytes())
                    .collect(),
            )
        } else {
            (
                UNSIGNED_INT,
                indices.iter().flat_map(|&i| i.to_le_bytes()).collect(),
            )
        };
        let accessor =
            json!({ "componentType": component, "count": indices.len(), "type": "SCALAR" });
        let indices = self.accessor(accessor, &bytes, ELEMENT_ARRAY_BUFFER);
        json!({
            "attributes": attributes,
            "indices": indices,
            "material": material,
            "mode": TRIANGLES,
        })
    }

    /// Material `m`, whose surfaces (its blend's, or its own) are `members` with their
    /// probabilities, and which a metallic-roughness texture may map.
    fn material(
        &mut self,
        m: &Material,
        members: &[(f32, Surface)],
        map: Option<RoughnessMap>,
        thickness: f32,
    ) -> Value {
        let metallic: f32 = members
            .iter()
            .filter(|(_, s)| matches!(s, Surface::Mirror | Surface::RoughConductor { .. }))
            .map(|(p, _)| p)
            .sum();
        let glass = members.iter().find(|(_, s)| {
            matches!(
                s,
                Surface::Dielectric { .. } | Surface::RoughDielectric { .. }
            )
        });
        // One roughness serves every member: a rough one's, else 1 for a Lambertian one
        // (diffuse is the rough end of glTF's lobes), else smooth.
        let alpha = members.iter().find_map(|(_, s)| match *s {
            Surface::RoughConductor { alpha }
            | Surface::RoughDielectric { alpha, .. }
            | Surface::Plastic { alpha, .. }
                if alpha > 0.0 =>
            {
                Some(alpha)
            }
            _ => None,
        });
        let lambertian = members.iter().any(|(_, s)| *s == Surface::Diffuse);
        let roughness = alpha.map_or(if lambertian { 1.0 } else { 0.0 }, f32::sqrt);
        let [r, g, b] = m.base_color.to_array();
        let mut value = json!({
            "name": m.name,
            "pbrMetallicRoughness": {
                "baseColorFactor": numbers(&[r, g, b, m.alpha]),
                "metallicFactor": number(metallic),
                "roughnessFactor": number(roughness),
            },
        });
        let mut extensions = Map::new();
        if let Some(&(
            probability,
            Surface::Dielectric { ior, thin_walled }
            | Surface::RoughDielectric {
                ior, thin_walled, ..
            },
        )) = glass
        {
            let transmission = probability / (1.0 - metallic);
            let factor = if transmission == 1.0 {
                json!(1)
            } else {
                number(transmission)
            };
            extensions.insert(
                "KHR_materials_transmission".into(),
                json!({ "transmissionFactor": factor }),
            );
            extensions.insert("KHR_materials_ior".into(), json!({ "ior": number(ior) }));
            if !thin_walled {
                extensions.insert("KHR_materials_volume".into(), volume(m, thickness));
                if m.has_murky_glass() {
                    extensions.insert("KHR_materials_volume_scatter".into(), volume_scatter(m));
                }
                if m.dispersion > 0.0 {
                    // The extension's 20 / V, V the Abbe number (ior − 1) / dispersion.
                    let strength = 20.0 * m.dispersion / (ior - 1.0);
                    extensions.insert(
                        "KHR_materials_dispersion".into(),
                        json!({ "dispersion": number(strength) }),
                    );
                }
            }
        }
        let coat_ior = members.iter().find_map(|(_, s)| match s {
            Surface::Plastic { ior, .. } => Some(*ior),
            _ => None,
        });
        if let Some(ior) = coat_ior
            && ior != DEFAULT_COAT_IOR
            && glass.is_none()
        {
            extensions.insert("KHR_materials_ior".into(), json!({ "ior": number(ior) }));
        }
        if let Some(coat) = m.clearcoat {
            extensions.insert(
                "KHR_materials_clearcoat".into(),
                json!({
                    "clearcoatFactor": number(coat.weight),
                    "clearcoatRoughnessFactor": number(coat.alpha.sqrt()),
                }),
            );
        }
        if let Some(anisotropy) = m.anisotropy {
            extensions.insert(
                "KHR_materials_anisotropy".into(),
                json!({
                    "anisotropyStrength": number(anisotropy.strength),
                    "anisotropyRotation": number(anisotropy.rotation),
                }),
            );
        }
        if let Some(film) = m.iridescence {
            let mut value = json!({
                "iridescenceFactor": number(film.factor),
                "iridescenceIor": number(film.ior),
                "iridescenceThicknessMinimum": number(film.thickness_min),
                "iridescenceThicknessMaximum": number(film.thickness_max),
            });
            if let Some(texture) = film.texture {
                value["iridescenceTexture"] = json!({ "index": texture });
            }
            if let Some(texture) = film.thickness_texture {
                value["iridescenceThicknessTexture"] = json!({ "index": texture });
            }
            extensions.insert("KHR_materials_iridescence".into(), value);
        }
        if let Some(transmission) = m.diffuse_transmission {
            extensions.insert(
                "KHR_materials_diffuse_transmission".into(),
                json!({
                    "diffuseTransmissionFactor": number(transmission.factor),
                    "diffuseTransmissionColorFactor": numbers(&transmission.color.to_array()),
                }),
            );
            if transmission.volume {
                extensions.insert("KHR_materials_volume".into(), volume(m, thickness));
                if m.scattering.max_element() > 0.0 {
                    extensions.insert("KHR_materials_volume_scatter".into(), volume_scatter(m));
                }
            }
        }
        if let Some(sheen) = m.sheen {
            extensions.insert(
                "KHR_materials_sheen".into(),
                json!({
                    "sheenColorFactor": numbers(&sheen.color.to_array()),
                    "sheenRoughnessFactor": number(sheen.roughness),
                }),
            );
        }
        let strength = m.emission.max_element();
        if strength > 0.0 {
            let factor = if strength > 1.0 {
                m.emission / strength
            } else {
                m.emission
            };
            value["emissiveFactor"] = numbers(&factor.to_array());
            if strength > 1.0 {
                extensions.insert(
                    "KHR_materials_emissive_strength".into(),
                    json!({ "emissiveStrength": number(strength) }),
                );
            }
        }
        if let AlphaMode::Mask { cutoff } = m.alpha_mode {
            value["alphaMode"] = json!("MASK");
            value["alphaCutoff"] = number(cutoff);
        }
        if m.double_sided {
            value["doubleSided"] = json!(true);
        }
        if let Some(texture) = m.base_color_texture {
            value["pbrMetallicRoughness"]["baseColorTexture"] = json!({ "index": texture });
        }
        if let Some(texture) = m.emission_texture {
            value["emissiveTexture"] = json!({ "index": texture });
        }
        if let Some(map) = map {
            // The metal's weight is the metallic factor already; the members' surfaces are
            // the loader's summaries of the texture, which it makes again from it.
            let pbr = &mut value["pbrMetallicRoughness"];
            pbr["roughnessFactor"] = number(map.roughness_factor);
            pbr["metallicRoughnessTexture"] = json!({ "index": map.texture });
        }
        if let Some(texture) = m.normal_texture {
            value["normalTexture"] = json!({ "index": texture });
            if m.normal_scale != 1.0 {
                value["normalTexture"]["scale"] = number(m.normal_scale);
            }
        }
        if !extensions.is_empty() {
            self.extensions
                .extend(extensions.keys().map(|k| known_extension(k)));
            value["extensions"] = Value::Object(extensions);
        }
        value
    }
}

/// The surfaces of the blend starting at material `id` with their probabilities (its own
/// surface alone, probability 1, where it is no blend).
fn blend_members(materials: &[Material], id: u32) -> Vec<(f32, Surface)> {
    let (mut id, mut left, mut members) = (id as usize, 1.0, Vec::new());
    while let Some(blend) = materials[id].blend {
        members.push((left * blend.weight, materials[id].surface));
        left *= 1.0 - blend.weight;
        id = blend.other as usize;
    }
    members.push((left, materials[id].surface));
    members
}

/// The metallic-roughness texture mapping a member of the blend starting at material `id`.
fn roughness_map(materials: &[Material], id: u32) -> Option<RoughnessMap> {
    let mut id = Some(id as usize);
    std::iter::from_fn(|| {
        let material = &materials[id?];
        id = material.blend.map(|b| b.other as usize);
        Some(material.roughness_map)
    })
    .flatten()
    .next()
}

fn known_extension(name: &str) -> &'static str {
    [
        "KHR_materials_anisotropy",
        "KHR_materials_clearcoat",
        "KHR_materials_diffuse_transmission",
        "KHR_materials_dispersion",
        "KHR_materials_emissive_strength",
        "KHR_materials_ior",
        "KHR_materials_iridescence",
        "KHR_materials_sheen",
        "KHR_materials_transmission",
        "KHR_materials_volume",
        "KHR_materials_volume_scatter",
    ]
    .into_iter()
    .find(|&k| k == name)
    .expect("only these extensions are written")
}

/// `KHR_materials_volume` of a solid `m` (glass, or a translucent solid) of `thickness`:
/// its attenuation the extinction, absorption and scattering together.
fn volume(m: &Material, thickness: f32) -> Value {
    let mut volume = json!({ "thicknessFactor": number(thickness) });
    let extinction = m.absorption + m.scattering;
    let strongest = extinction.max_element();
    if strongest > 0.0 {
        // The distance over which the most attenuated channel falls to 1/e, and the colours
        // there: numbers of a size that read back close.
        let distance = 1.0 / strongest;
        let color = (-extinction * distance).exp();
        volume["attenuationDistance"] = number(distance);
        volume["attenuationColor"] = numbers(&color.to_array());
    }
    volume
}

/// `KHR_materials_volume_scatter` of a scattering solid `m` (translucent, or murky glass): the
/// multiple-scatter
/// colour whose single-scattering albedo (`scene::single_scatter_albedo`, rising in it) is
/// σs / σt, found by bisection.
fn volume_scatter(m: &Material) -> Value {
    let albedo = m.scattering / (m.absorption + m.scattering);
    let multiscatter = albedo.to_array().map(|target| {
        let (mut low, mut high) = (0.0f32, 1.0f32);
        for _ in 0..40 {
            let middle = 0.5 * (low + high);
            if scene::single_scatter_albedo(Vec3::splat(middle)).x < target {
                low = middle;
            } else {
                high = middle;
            }
        }
        0.5 * (low + high)
    });
    json!({
        "multiscatterColor": numbers(&multiscatter),
        "scatterAnisotropy": number(m.scatter_anisotropy),
    })
}

/// A solid's volume thickness: the smallest side of its triangles' bounding box.
fn thickness(scene: &Scene, material: u32) -> f32 {
    let bounds = scene
        .triangles
        .iter()
        .filter(|t| t.material == material)
        .fold(scene::Bounds::EMPTY, |b, t| b.union(t.bounds()));
    if bounds.is_empty() {
        0.0
    } else {
        bounds.extent().min_element()
    }
}

/// A near plane a thousandth of the scene's size, rounded down to a power of ten.
fn znear(scene: &Scene) -> f32 {
    let diagonal = scene.bounds().extent().length() as f64;
    10f64.powf((diagonal * 1e-3).log10().floor()) as f32
}

/// A glTF camera: perspective, or orthographic (its film's half extents as `xmag`/`ymag`, the
/// far plane a million near planes away, which glTF asks for).
fn camera_object(camera: &Camera, znear: f32) -> Value {
    if let scene::Projection::Orthographic { half_height } = camera.projection {
        let xmag = half_height * camera.aspect_ratio.unwrap_or(1.0);
        let orthographic = json!({ "xmag": number(xmag), "ymag": number(half_height),
            "znear": number(znear), "zfar": number(znear * 1e6) });
        return json!({ "name": camera.name, "type": "orthographic", "orthographic": orthographic });
    }
    let mut perspective = json!({ "yfov": number(camera.yfov), "znear": number(znear) });
    if let Some(aspect) = camera.aspect_ratio {
        perspective["aspectRatio"] = number(aspect);
    }
    json!({ "name": camera.name, "type": "perspective", "perspective": perspective })
}

/// A glTF camera looks down its local −z with +y up: the node's rotation takes (x, y, −z) to
/// (right, up, forward).
fn camera_node(camera: &Camera, index: usize) -> Value {
    let frame = Mat3::from_cols(camera.right(), camera.up, -camera.forward);
    let mut rotation = Quat::from_mat3(&frame).normalize();
    if rotation.w < 0.0 {
        rotation = -rotation;
    }
    json!({
        "name": camera.name,
        "camera": index,
        "translation": numbers(&camera.eye.to_array()),
        "rotation": numbers(&rotation.to_array()),
    })
}

/// A `KHR_lights_punctual` light: colour (largest channel 1) × intensity.
fn punctual(light: &PunctualLight) -> Value {
    let intensity = light.intensity.max_element();
    let colour = if intensity > 0.0 {
        light.intensity / intensity
    } else {
        Vec3::ONE
    };
    let mut value = json!({ "color": numbers(&colour.to_array()), "intensity": number(intensity) });
    match light.kind {
        PunctualKind::Point => value["type"] = json!("point"),
        PunctualKind::Directional => value["type"] = json!("directional"),
        PunctualKind::Spot {
            cos_inner,
            cos_outer,
            ..
        } => {
            value["type"] = json!("spot");
            value["spot"] = json!({
                "innerConeAngle": number(cos_inner.acos()),
                "outerConeAngle": number(cos_outer.acos()),
            });
        }
    }
    value
}

/// A light's node: at its position, rotated so that its −z is the light's direction.
fn light_node(light: &PunctualLight, index: usize) -> Value {
    let mut node = json!({
        "extensions": { "KHR_lights_punctual": { "light": index } },
        "translation": numbers(&light.position.to_array()),
    });
    if light.kind != PunctualKind::Point {
        let rotation = Quat::from_rotation_arc(Vec3::NEG_Z, light.direction).normalize();
        node["rotation"] = numbers(&rotation.to_array());
    }
    node
}

/// An f32 as the shortest decimal that reads back as the same f32 (−0 written as 0).
fn number(x: f32) -> Value {
    let x = if x == 0.0 { 0.0 } else { x };
    let shortest: f64 = x.to_string().parse().expect("f32 text parses as f64");
    serde_json::Number::from_f64(shortest).map_or(Value::Null, Value::Number)
}

fn numbers(xs: &[f32]) -> Value {
    Value::Array(xs.iter().map(|&x| number(x)).collect())
}

/// The value with every object's keys in sorted order, whatever map serde_json uses.
fn sorted(value: Value) -> Value {
    match value {
        Value::Object(map) => {
            let mut entries: Vec<(String, Value)> = map.into_iter().collect();
            entries.sort_by(|a, b| a.0.cmp(&b.0));
            Value::Object(entries.into_iter().map(|(k, v)| (k, sorted(v))).collect())
        }
        Value::Array(items) => Value::Array(items.into_iter().map(sorted).collect()),
        other => other,
    }
}
