//! `KHR_materials_pbrSpecularGlossiness` (archived by Khronos, still in many older assets) as
//! the metallic-roughness material `KHR_materials_specular` documents as its equivalent: a
//! non-metal whose base colour is the diffuse colour, whose specular layer's colour is the
//! specular colour over an index of 0 (so its reflectance head on is that colour, rising to 1
//! at grazing), and whose roughness is one minus the glossiness. The material is rewritten
//! here and then read as any other; the glossiness texture (the alpha channel of
//! `specularGlossinessTexture`) becomes a roughness texture in [`super::materials`].

use ::gltf::json;
use serde_json::{Value, json};

/// The extension's name.
pub const EXTENSION: &str = "KHR_materials_pbrSpecularGlossiness";

/// `m` rewritten as its metallic-roughness equivalent, where it is a specular-glossiness
/// material; `None` otherwise. Its other extensions (emissive strength, clear coat, ...) stay.
pub fn as_metal_rough(m: &json::Material) -> Result<Option<json::Material>, serde_json::Error> {
    let Some(spec_gloss) = (m.extensions.as_ref()).and_then(|e| e.pbr_specular_glossiness.as_ref())
    else {
        return Ok(None);
    };
    let mut value = serde_json::to_value(m)?;
    let [diffuse @ .., alpha] = spec_gloss.diffuse_factor.0;
    let glossiness = spec_gloss.glossiness_factor.0;
    let mut pbr = json!({
        "baseColorFactor": [diffuse[0], diffuse[1], diffuse[2], alpha],
        "metallicFactor": 0.0,
        // With a glossiness texture the factor is baked into the roughness texture made from
        // it (roughness 1 − factor × alpha is no product of a factor and a texel).
        "roughnessFactor": if spec_gloss.specular_glossiness_texture.is_some() {
            1.0
        } else {
            1.0 - glossiness
        },
    });
    if let Some(info) = &spec_gloss.diffuse_texture {
        pbr["baseColorTexture"] = serde_json::to_value(info)?;
    }
    let mut specular = json!({
        "specularFactor": 1.0,
        "specularColorFactor": spec_gloss.specular_factor.0,
    });
    if let Some(info) = &spec_gloss.specular_glossiness_texture {
        let info = serde_json::to_value(info)?;
        specular["specularColorTexture"] = info.clone();
        pbr["metallicRoughnessTexture"] = info;
    }
    value["pbrMetallicRoughness"] = pbr;
    let mut extensions = value["extensions"].take();
    if let Value::Object(map) = &mut extensions {
        map.remove(EXTENSION);
        map.insert("KHR_materials_specular".into(), specular);
        map.insert("KHR_materials_ior".into(), json!({ "ior": 0.0 }));
    }
    value["extensions"] = extensions;
    serde_json::from_value(value).map(Some)
}

/// The glossiness factor of `m` where its glossiness comes from a texture (whose alpha,
/// times this, gives one minus the roughness); `None` otherwise.
pub fn textured_glossiness(m: &json::Material) -> Option<f32> {
    let spec_gloss = m.extensions.as_ref()?.pbr_specular_glossiness.as_ref()?;
    spec_gloss
        .specular_glossiness_texture
        .as_ref()
        .map(|_| spec_gloss.glossiness_factor.0)
}
