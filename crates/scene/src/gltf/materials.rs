//! glTF materials mapped onto kousen's uber-material (DESIGN.md, "Materials"):
//!
//! - glTF's BRDF, `mix(dielectric, metal, metallicFactor)` with the dielectric
//!   `mix(opaque, glass, transmissionFactor)` under its specular layer, as a blend of up to
//!   three surfaces chosen at random per hit with those probabilities (`scene::Blend`; factors
//!   of 0 or 1 leave one surface, and equal surfaces merge):
//! - the metal reflects the base colour: `roughnessFactor` < 0.01 → perfect mirror; below 0.5
//!   → rough conductor, GGX of width α = roughness²; from 0.5 → Lambertian diffuse: so broad a
//!   lobe sends light out nearly as a diffuse surface does, and SPPM gathers at diffuse points
//!   where it would otherwise trace eye paths on through the metal.
//! - the glass (`KHR_materials_transmission`) is a dielectric of `KHR_materials_ior` (default
//!   1.5); solid when `KHR_materials_volume` gives `thicknessFactor > 0`, thin-walled otherwise;
//!   smooth where `roughnessFactor` < 0.01, else rough (frosted) glass, GGX of width α =
//!   roughness² (glTF's default roughness is 1: transmission without a roughness is very
//!   frosted glass, as glTF viewers show it). An ior of 0 (the extension's "F0 = 1") reflects
//!   everything → mirror.
//! - the opaque dielectric with `roughnessFactor` < 0.5 is plastic (`render::plastic`): a
//!   Lambertian base of the base colour under glTF's clear dielectric coat of
//!   `KHR_materials_ior` (default 1.5), smooth below 0.01, else GGX of width α = roughness²;
//!   rougher coats spread their 4 % so widely that Lambertian alone stands for them, as for
//!   metal. `KHR_materials_specular` → [`SpecularLayer`]: the coat keeps its index, and its
//!   reflectance at a hit is glTF's layer's there, `min(F0 · c, 1) · s` at normal incidence
//!   for `specularColorFactor` c and `specularFactor` s (each times its texture), `s` at
//!   grazing, in between the shape of the coat's own Fresnel reflectance
//!   (`render::dielectric_layer`); s = 0 removes the coat (Lambertian). The glass member
//!   wears the same layer: smooth or frosted, its reflection and transmission share what the
//!   layer reflects (refracting by its own index; total internal reflection stays total), so
//!   s = 0 makes glass that reflects nothing but inside it. Over an index of 0 (glTF's
//!   "F0 = 1") or above 3 (converters write 1000 for it), where the layer's colour is its
//!   reflectance head on, the coat takes the index of the layer's mean reflectance (up to 3)
//!   and keeps its lobe however rough: `KHR_materials_pbrSpecularGlossiness` converts so
//!   (`super::spec_gloss`), a metal written as black diffuse under a coloured specular
//!   among them.
//! - the opaque dielectric otherwise → Lambertian diffuse with the base colour (×
//!   `baseColorTexture`).
//! - `KHR_materials_clearcoat` → [`Clearcoat`] over every member: `clearcoatFactor` its
//!   weight, `clearcoatRoughnessFactor` its GGX width (squared; smooth below 0.01), each
//!   multiplied per hit by its texture (`clearcoatTexture`'s red, `clearcoatRoughnessTexture`'s
//!   green, linear data); `clearcoatNormalTexture` (with its `scale`) bends the coat's own
//!   normal, which otherwise follows the interpolated one. A factor of 0 is no coat.
//! - `KHR_materials_sheen` → [`Sheen`] beneath the clear coat: `sheenColorFactor` (×
//!   `sheenColorTexture`, sRGB) its colour, `sheenRoughnessFactor` (× the alpha channel of
//!   `sheenRoughnessTexture`, linear data) its roughness, raised to 0.07. A black colour is no
//!   sheen.
//! - `KHR_materials_diffuse_transmission` → [`DiffuseTransmission`] of the Lambertian lobe
//!   (diffuse, or plastic's base): `diffuseTransmissionFactor` (× the alpha channel of
//!   `diffuseTransmissionTexture`, linear data) the share passing to the other side,
//!   `diffuseTransmissionColorFactor` (× `diffuseTransmissionColorTexture`, sRGB) its tint.
//!   With `KHR_materials_volume`'s `thicknessFactor` above 0 the surface bounds a translucent
//!   solid (wax, jade: [`DiffuseTransmission::volume`]) whose attenuation absorbs inside it,
//!   else it is a sheet. A factor of 0 is none.
//! - `KHR_materials_volume_scatter` (a Khronos draft) on a translucent solid or on solid glass
//!   that is not a blend (murky water, smoky glass): the attenuation is the extinction, of
//!   which the single-scattering albedo of `multiscatterColor` scatters (`Material::scattering`,
//!   Henyey–Greenstein of `scatterAnisotropy`) and the rest absorbs; ignored with a warning
//!   elsewhere.
//! - `KHR_materials_anisotropy` → [`Anisotropy`] on the metal (brushed metal):
//!   `anisotropyStrength` (× the blue of `anisotropyTexture`, linear data), the direction
//!   +u of the mesh's TANGENT frame, else of each triangle's texture frame (or the
//!   texture's red and green), turned by
//!   `anisotropyRotation`; a smooth metal so brushed becomes rough metal of width
//!   `MIN_BRUSHED_ALPHA`. The dielectric's coat and glass stay isotropic (warned).
//! - `KHR_materials_iridescence` → [`Iridescence`], a thin film on metal, glass and plastic's
//!   coat:
//!   `iridescenceFactor` (× the red of `iridescenceTexture`, linear data) its weight,
//!   `iridescenceIor` (default 1.3) its index, its thickness `iridescenceThicknessMaximum`
//!   (default 400 nm), or where `iridescenceThicknessTexture` (linear data) is given, from
//!   `iridescenceThicknessMinimum` (default 100 nm) to the maximum by its green. A factor of
//!   0 is no film. A filmed metal or opaque dielectric keeps its lobe however rough (rough
//!   metal, rough plastic of width roughness²) where it would otherwise be rendered
//!   Lambertian, which has no layer to colour; per-hit surfaces that a metallic-roughness
//!   texture picks keep their thresholds (the film is not read where a texel makes them
//!   Lambertian). On an opaque dielectric whose `specularFactor` is 0 the film is ignored
//!   (warned). A blend's members all carry it.
//! - emission = `emissiveFactor` × `KHR_materials_emissive_strength` (× `emissiveTexture`).
//! - `KHR_materials_unlit` → an emitter of the base colour (factor × texture) that reflects
//!   nothing: a backdrop or sky dome lights the scene with what it shows.
//! - `alphaMode` MASK → cut-out at `alphaCutoff` (default 0.5); BLEND → cut-out at 0.5, with a
//!   warning (kousen has no partial transparency).
//!
//! - a solid dielectric's or translucent solid's `KHR_materials_volume` attenuation (colour
//!   after distance) →
//!   Beer–Lambert absorption inside it, along every segment of a path that entered it
//!   (`render::medium`): what lies inside (a floor under water) is seen through it. Solids
//!   nest (`render::nesting` finds which lies in which), but touching solids (a liquid filling
//!   a glass exactly) have no interface of their own.
//! - `KHR_materials_dispersion` on solid glass, smooth or frosted (a blend's glass member
//!   too) → `Material::dispersion`,
//!   the Cauchy form the extension gives (`render::dispersion`); elsewhere warned about and
//!   ignored.
//!
//! - `KHR_texture_transform` on the base colour texture (else the emissive one) → applied to
//!   the texture coordinates of the material's primitives (one transform a material: kousen's
//!   vertices keep one set of coordinates; a different emissive transform is warned about).
//!
//! - `normalTexture` (with its `scale`) → a tangent-space normal map bending the shading normal,
//!   in the frame of each triangle's texture-coordinate gradients (`render::normal_map`).
//!
//! - `metallicRoughnessTexture` (linear data: roughness × `roughnessFactor` in green,
//!   metalness × `metallicFactor` in blue) → `scene::RoughnessMap` on the metal, the glass and
//!   the opaque dielectric, read at each hit: the metal's probability is the texel's metalness and
//!   its surface follows the texel's roughness as above (mirror, rough conductor of α =
//!   roughness², Lambertian); the opaque dielectric is plastic where the texel's roughness is
//!   below 0.5, its coat of the texel's own width (smooth below 0.01; the coat's tables over
//!   the texture's range of widths, `render::coats`), and Lambertian above; the glass is
//!   smooth below roughness 0.01 and frosted (α = roughness²) above, texel by texel. Each
//!   member is stored at the mean roughness of the texels where it shows, which what reads
//!   the material outside a hit sees (`kousen info`).
//!
//! - `transmissionTexture` (linear data: its red channel) multiplies the glass member's weight
//!   at each hit, the opaque dielectric taking the rest (`Material::transmission_texture`).
//!
//! Ignored: occlusion (a path tracer's light needs none), `KHR_materials_volume`'s thickness
//! texture, samplers (the renderer filters bilinearly and wraps with repeat). Colour textures
//! are decoded as sRGB, each image once however many materials use it.

use std::borrow::Cow;
use std::collections::HashMap;

use glam::{Affine2, Vec2, Vec3};

use ::gltf::json;
use json::material::AlphaMode as GltfAlphaMode;
use json::validation::Checked;

use super::buffers::{read_regular, resolve_uri};
use super::spec_gloss;
use super::uri::Resolved;
use super::{Context, Input, quoted};
use crate::{
    AlphaMode, Anisotropy, Clearcoat, DIFFUSE_MIN_ROUGHNESS, DiffuseTransmission, Iridescence,
    Material, RoughnessMap, SceneBuilder, SceneError, Sheen, SpecularLayer, Surface, Texels,
    Texture, TextureId, TextureRoughness, TexturedLobe,
    absorption_from_attenuation as scene_absorption, brushed_metal_surface, coated_surface,
    glass_surface, metal_surface,
};

/// `KHR_materials_ior`'s default, also the core spec's dielectric ior.
pub const DEFAULT_IOR: f32 = 1.5;
/// glTF's default `alphaCutoff`, also used for BLEND.
pub const DEFAULT_ALPHA_CUTOFF: f32 = 0.5;

/// What the `gltf` crate reads a texture without `source` as.
const NO_SOURCE: usize = u32::MAX as usize;

/// Converts glTF materials on first use and remembers the builder's ids.
pub(super) struct Materials {
    /// Builder id of each glTF material converted so far.
    ids: Vec<Option<u32>>,
    /// Builder id of the default material, once a primitive without material asked for it.
    default_id: Option<u32>,
    /// Builder texture id of each glTF image decoded so far as colour (sRGB).
    images: Vec<Option<TextureId>>,
    /// The same for images decoded as data (normal maps).
    linear_images: Vec<Option<TextureId>>,
    /// Each glTF material's `KHR_texture_transform` (of its base colour texture, else its
    /// emissive one), once converted: applied to the texture coordinates of the primitives
    /// that use it, since kousen's materials keep no transform of their own.
    uv_transforms: Vec<Option<Affine2>>,
    /// Each glTF material's texture-coordinate set ([`material_uv_set`]): the TEXCOORD_n its
    /// primitives' vertices take, since kousen keeps one set a vertex.
    uv_sets: Vec<usize>,
    /// The set of the material being converted, for [`Materials::texture`]'s warning.
    converting_uv_set: usize,
    /// Roughness textures made from specular-glossiness textures (`spec_gloss`), by image and
    /// glossiness factor.
    gloss_images: HashMap<(usize, u32), TextureId>,
}

impl Materials {
    pub fn new(root: &json::Root) -> Self {
        Materials {
            ids: vec![None; root.materials.len()],
            default_id: None,
            images: vec![None; root.images.len()],
            linear_images: vec![None; root.images.len()],
            uv_transforms: vec![None; root.materials.len()],
            uv_sets: vec![0; root.materials.len()],
            converting_uv_set: 0,
            gloss_images: HashMap::new(),
        }
    }

    /// The texture-coordinate set of glTF material `index` (after [`Materials::id`] converted
    /// it): TEXCOORD_0 for none or the default material.
    pub fn uv_set(&self, index: Option<usize>) -> usize {
        index.map_or(0, |i| self.uv_sets[i])
    }

    /// The texture-coordinate transform of glTF material `index` (after [`Materials::id`]
    /// converted it); `None` for none or the default material.
    pub fn uv_transform(&self, index: Option<usize>) -> Option<Affine2> {
        index.and_then(|i| self.uv_transforms[i])
    }

    /// The builder's id for glTF material `index` (which must exist), or for the default
    /// material when `index` is `None`: Lambertian grey 0.8, kousen's default everywhere
    /// (glTF's default is white, which absorbs nothing and never lets photon paths end).
    pub fn id(
        &mut self,
        input: &Input,
        builder: &mut SceneBuilder,
        index: Option<usize>,
    ) -> Result<u32, SceneError> {
        let Some(index) = index else {
            return Ok(*self.default_id.get_or_insert_with(|| {
                builder.add_material(Material {
                    name: "default".to_string(),
                    ..Material::default()
                })
            }));
        };
        if let Some(id) = self.ids[index] {
            return Ok(id);
        }
        let (material, members) = self.convert(input, builder, index)?;
        let id = match members.textured_metal {
            Some((metallic, surface, map)) => builder.add_textured_metal_blend(
                material,
                metallic,
                (surface, map),
                &members.dielectric,
            ),
            None => builder.add_mapped_blend(material, &members.dielectric),
        };
        self.ids[index] = Some(id);
        Ok(id)
    }

    fn convert(
        &mut self,
        input: &Input,
        builder: &mut SceneBuilder,
        index: usize,
    ) -> Result<(Material, Members), SceneError> {
        let original = &input.root.materials[index];
        let label = match &original.name {
            Some(name) => format!("material {index} ({})", quoted(name)),
            None => format!("material {index}"),
        };
        let check = Check {
            input,
            label: &label,
        };
        // A specular-glossiness material is read as its metallic-roughness equivalent.
        let rewritten = spec_gloss::as_metal_rough(original)
            .map_err(|e| check.error(format!("{}: {e}", spec_gloss::EXTENSION)))?;
        let glossiness = spec_gloss::textured_glossiness(original);
        let m = rewritten.as_ref().unwrap_or(original);
        let uv_set = material_uv_set(m);
        self.uv_sets[index] = uv_set;
        self.converting_uv_set = uv_set;
        if uv_set >= super::meshes::MAX_UV_SETS {
            builder.warn(format!(
                "{label}: its textures use TEXCOORD_{uv_set}; only TEXCOORD_0 to TEXCOORD_{} are \
                 read, so they read (0, 0)",
                super::meshes::MAX_UV_SETS - 1
            ));
        }
        let pbr = &m.pbr_metallic_roughness;
        let base = pbr.base_color_factor.0;
        for (c, name) in base.iter().zip(["red", "green", "blue", "alpha"]) {
            check.unit(*c, &format!("baseColorFactor's {name}"))?;
        }
        let metallic = check.unit(pbr.metallic_factor.0, "metallicFactor")?;
        let roughness = check.unit(pbr.roughness_factor.0, "roughnessFactor")?;
        let transmission_info = (m.extensions.as_ref())
            .and_then(|e| e.transmission.as_ref())
            .and_then(|t| t.transmission_texture.as_ref());
        let transmission_texture = match transmission_info {
            Some(info) if transmission(&check, m)? > 0.0 => {
                let slot = TextureSlot::data(info, "transmissionTexture");
                Some(self.texture(input, builder, slot, &label)?)
            }
            _ => None,
        };
        // A texture needs the opaque member even at factor 1 (the builder keeps members of
        // some probability, and its blend weights stop short of 1 anyway).
        let transmission = match transmission_texture {
            Some(_) => transmission(&check, m)?.min(1.0 - TEXTURED_TRANSMISSION_GAP),
            None => transmission(&check, m)?,
        };
        let mapped = match &pbr.metallic_roughness_texture {
            Some(info) => {
                let texture = match glossiness {
                    Some(factor) => self.gloss_texture(input, builder, info, factor, &label)?,
                    None => {
                        let slot = TextureSlot::data(info, "metallicRoughnessTexture");
                        self.texture(input, builder, slot, &label)?
                    }
                };
                Some((texture, info))
            }
            None => None,
        };
        let members = match mapped {
            None => Members::plain(surface_members(
                &check,
                m,
                metallic,
                transmission,
                roughness,
            )?),
            Some((texture, _)) => {
                let texels = TextureRoughness::of(builder.texture(texture), roughness, metallic);
                // A film, or a specular layer that is the whole reflectance, would be lost on
                // texels rendered Lambertian.
                let filmed = iridescence(&check, m)?.is_some();
                let layered = layered_coat_ior(&check, m, ior_of(m))?.is_some();
                let map = |lobe| RoughnessMap {
                    texture,
                    roughness_factor: roughness,
                    roughness_range: texels.range,
                    lobe,
                    keeps_lobe: match lobe {
                        TexturedLobe::Metal => filmed,
                        TexturedLobe::Coated => filmed || layered,
                        TexturedLobe::Glass => false,
                    },
                };
                mapped_members(&check, m, metallic, transmission, &texels, map)?
            }
        };
        let surfaces = members.surfaces();
        if transmission_texture.is_some() && !surfaces.iter().any(|(_, s)| s.is_glass()) {
            builder.warn(format!(
                "{label}: transmissionTexture not read (ior 0 makes the glass a mirror)"
            ));
        }
        let dispersion = dispersion(&check, m, &surfaces, builder)?;
        let diffuse_transmission = self.diffuse_transmission(input, builder, &check, m)?;
        let translucent_volume = diffuse_transmission.is_some_and(|t| t.volume);
        let extinction = absorption(&check, m, &surfaces, translucent_volume)?;
        // Solid glass of one surface (not a blend) scatters too: murky water, smoky glass.
        let glass_volume = matches!(surfaces.as_slice(), [(_, s)] if s.is_solid_dielectric());
        let scattering_volume = translucent_volume || glass_volume;
        let scatter = volume_scatter(&check, m, scattering_volume, extinction, builder)?;
        let emission = emission(&check, m)?;
        let alpha_mode = alpha_mode(&check, m, builder)?;
        let mut texture = |info: &Option<json::texture::Info>, slot: &'static str| {
            info.as_ref()
                .map(|info| {
                    let slot = TextureSlot::colour(info, slot);
                    self.texture(input, builder, slot, &label)
                })
                .transpose()
        };
        let base_color_texture = texture(&pbr.base_color_texture, "baseColorTexture")?;
        let emission_texture = texture(&m.emissive_texture, "emissiveTexture")?;
        let transform = uv_transform(
            pbr.base_color_texture.as_ref(),
            m.emissive_texture.as_ref(),
            &label,
            builder,
        );
        let normal_texture = match &m.normal_texture {
            Some(normal) => {
                if !normal.scale.is_finite() {
                    let scale = normal.scale;
                    return Err(check.error(format!("normalTexture's scale {scale} is not finite")));
                }
                let slot = TextureSlot::normal(normal);
                let id = self.texture(input, builder, slot, &label)?;
                let own = normal
                    .extensions
                    .as_ref()
                    .and_then(|e| e.others.get("KHR_texture_transform"))
                    .and_then(|v| serde_json::from_value(v.clone()).ok())
                    .map(|t| transform_of(&t));
                warn_own_transform("normalTexture", own, transform, &label, builder);
                Some(id)
            }
            None => None,
        };
        if let Some((_, info)) = mapped {
            let own = slot_transform(info);
            warn_own_transform("metallicRoughnessTexture", own, transform, &label, builder);
        }
        warn_layer_transforms(m, transform, &label, builder);
        self.uv_transforms[index] = transform;
        let material = Material {
            name: m.name.clone().unwrap_or_else(|| label.clone()),
            surface: surfaces[0].1,
            base_color: Vec3::new(base[0], base[1], base[2]),
            base_color_texture,
            emission,
            emission_texture,
            alpha: base[3],
            alpha_mode,
            double_sided: m.double_sided,
            absorption: scatter.absorption,
            scattering: scatter.scattering,
            scatter_anisotropy: scatter.anisotropy,
            normal_texture,
            normal_scale: m.normal_texture.as_ref().map_or(1.0, |n| n.scale),
            blend: None,
            dispersion,
            roughness_map: None,
            clearcoat: self.clearcoat(input, builder, &check, m)?,
            sheen: self.sheen(input, builder, &check, m)?,
            transmission_texture,
            diffuse_transmission,
            anisotropy: self.anisotropy(input, builder, &check, m)?,
            iridescence: self.iridescence(input, builder, &check, m)?,
            specular: self.specular_layer(input, builder, &check, m)?,
            metal_edge: Vec3::ONE,
        };
        if is_unlit(m) {
            return Ok((
                unlit(material),
                Members::plain(vec![(1.0, Surface::Diffuse)]),
            ));
        }
        Ok((material, members))
    }

    /// `KHR_materials_clearcoat` as a [`Clearcoat`] ([`clearcoat`]'s factors) with its
    /// weight, roughness and normal textures, decoded as linear data.
    fn clearcoat(
        &mut self,
        input: &Input,
        builder: &mut SceneBuilder,
        check: &Check,
        m: &json::Material,
    ) -> Result<Option<Clearcoat>, SceneError> {
        let Some(mut coat) = clearcoat(check, m)? else {
            return Ok(None);
        };
        const COAT: &str = "KHR_materials_clearcoat";
        let mut data = |name| self.layer_texture(input, builder, check, (m, COAT, name), DATA);
        coat.weight_texture = data("clearcoatTexture")?;
        coat.roughness_texture = data("clearcoatRoughnessTexture")?;
        let name = "clearcoatNormalTexture";
        if let Some(normal) =
            layer_slot::<json::material::NormalTexture>(check, m, COAT, name, "normal texture")?
        {
            if !normal.scale.is_finite() {
                return Err(check.error(format!("{name}'s scale {} is not finite", normal.scale)));
            }
            let slot = TextureSlot {
                name,
                ..TextureSlot::normal(&normal)
            };
            coat.normal_texture = Some(self.texture(input, builder, slot, check.label)?);
            coat.normal_scale = normal.scale;
        }
        Ok(Some(coat))
    }

    /// `KHR_materials_sheen` as a [`Sheen`] ([`sheen`]'s factors) with its colour texture,
    /// decoded as sRGB, and its roughness texture, as linear data.
    fn sheen(
        &mut self,
        input: &Input,
        builder: &mut SceneBuilder,
        check: &Check,
        m: &json::Material,
    ) -> Result<Option<Sheen>, SceneError> {
        let Some(mut sheen) = sheen(check, m)? else {
            return Ok(None);
        };
        let mut texture =
            |name, srgb| self.layer_texture(input, builder, check, (m, SHEEN, name), srgb);
        sheen.color_texture = texture("sheenColorTexture", COLOUR)?;
        sheen.roughness_texture = texture("sheenRoughnessTexture", DATA)?;
        Ok(Some(sheen))
    }

    /// `KHR_materials_diffuse_transmission` as a [`DiffuseTransmission`]
    /// ([`diffuse_transmission`]'s factors) with its strength texture, as linear data, and its
    /// colour texture, as sRGB.
    fn diffuse_transmission(
        &mut self,
        input: &Input,
        builder: &mut SceneBuilder,
        check: &Check,
        m: &json::Material,
    ) -> Result<Option<DiffuseTransmission>, SceneError> {
        let Some(mut transmission) = diffuse_transmission(check, m)? else {
            return Ok(None);
        };
        // A thickness makes the surface bound a translucent solid (KHR_materials_volume);
        // without one it is a sheet.
        let volume = (m.extensions.as_ref()).and_then(|e| e.volume.as_ref());
        let thickness = volume.map_or(0.0, |v| v.thickness_factor.0);
        transmission.volume = check.non_negative(thickness, "thicknessFactor")? > 0.0;
        let mut texture =
            |name, srgb| self.layer_texture(input, builder, check, (m, DIFFUSE, name), srgb);
        transmission.texture = texture("diffuseTransmissionTexture", DATA)?;
        transmission.color_texture = texture("diffuseTransmissionColorTexture", COLOUR)?;
        Ok(Some(transmission))
    }

    /// `KHR_materials_anisotropy` as an [`Anisotropy`] ([`anisotropy`]'s factors) with its
    /// texture, decoded as linear data.
    fn anisotropy(
        &mut self,
        input: &Input,
        builder: &mut SceneBuilder,
        check: &Check,
        m: &json::Material,
    ) -> Result<Option<Anisotropy>, SceneError> {
        let Some(mut anisotropy) = anisotropy(check, m)? else {
            return Ok(None);
        };
        let slot = (m, ANISOTROPY, "anisotropyTexture");
        anisotropy.texture = self.layer_texture(input, builder, check, slot, DATA)?;
        if m.pbr_metallic_roughness.metallic_factor.0 < 1.0 {
            builder.warn(format!(
                "{}: {ANISOTROPY} brushes the metal's lobe only (the dielectric's coat and \
                 glass stay isotropic)",
                check.label
            ));
        }
        Ok(Some(anisotropy))
    }

    /// `KHR_materials_iridescence` as an [`Iridescence`] ([`iridescence`]'s factors) with its
    /// factor and thickness textures, decoded as linear data. The film is rendered on metal,
    /// glass and plastic's coat, which keep their lobes under it however rough (`lobes`); an
    /// opaque dielectric whose specular layer `KHR_materials_specular` removes gets none, with
    /// a warning.
    fn iridescence(
        &mut self,
        input: &Input,
        builder: &mut SceneBuilder,
        check: &Check,
        m: &json::Material,
    ) -> Result<Option<Iridescence>, SceneError> {
        let Some(mut film) = iridescence(check, m)? else {
            return Ok(None);
        };
        // The film colours metal, glass and plastic's coat, which keep their lobes however
        // rough under it (`lobes`); an opaque dielectric without a specular layer has none to
        // wear it.
        let pbr = &m.pbr_metallic_roughness;
        let metal = pbr.metallic_factor.0 > 0.0;
        let glass = transmission(check, m)? > 0.0;
        let ior = ior_of(m);
        if !metal && !glass && (specular_factor(check, m)? == 0.0 || ior == 1.0) {
            builder.warn(format!(
                "{}: {IRIDESCENCE} on an opaque dielectric without a specular layer \
                 (specularFactor 0 or ior 1, rendered Lambertian) is not modelled: its film is \
                 ignored",
                check.label
            ));
            return Ok(None);
        }
        let mut data =
            |name| self.layer_texture(input, builder, check, (m, IRIDESCENCE, name), DATA);
        film.texture = data("iridescenceTexture")?;
        film.thickness_texture = data("iridescenceThicknessTexture")?;
        Ok(Some(film))
    }

    /// `KHR_materials_specular` as a [`SpecularLayer`]; `None` where it changes nothing (its
    /// defaults) or has no Fresnel reflectance to shape (an index of 1: see [`lobes`]). Over an
    /// index of 0 (glTF's "F0 = 1") its colour is its reflectance head on.
    fn specular_layer(
        &mut self,
        input: &Input,
        builder: &mut SceneBuilder,
        check: &Check,
        m: &json::Material,
    ) -> Result<Option<SpecularLayer>, SceneError> {
        let Some(extension) = m.extensions.as_ref().and_then(|e| e.specular.as_ref()) else {
            return Ok(None);
        };
        let factor = specular_factor(check, m)?;
        let ior = ior_of(m);
        let colour = Vec3::from_array(extension.specular_color_factor.0);
        let textured =
            extension.specular_texture.is_some() || extension.specular_color_texture.is_some();
        if !(textured || colour != Vec3::ONE || factor != 1.0) || ior == 1.0 {
            return Ok(None);
        }
        let mut texture = |info: &Option<json::texture::Info>, name, srgb| match info {
            Some(info) => {
                let slot = if srgb {
                    TextureSlot::colour(info, name)
                } else {
                    TextureSlot::data(info, name)
                };
                self.texture(input, builder, slot, check.label).map(Some)
            }
            None => Ok(None),
        };
        Ok(Some(SpecularLayer {
            texture: texture(&extension.specular_texture, "specularTexture", DATA)?,
            color_texture: texture(
                &extension.specular_color_texture,
                "specularColorTexture",
                COLOUR,
            )?,
            ..SpecularLayer::new(ior, colour, factor)
        }))
    }

    /// The texture an extension of material `m` names in its field `name` (the `slot`:
    /// material, extension, field), decoded as sRGB colour (`srgb`, [`COLOUR`]) or linear data
    /// ([`DATA`]); `None` where the field is absent.
    fn layer_texture(
        &mut self,
        input: &Input,
        builder: &mut SceneBuilder,
        check: &Check,
        (m, extension, name): (&json::Material, &str, &'static str),
        srgb: bool,
    ) -> Result<Option<TextureId>, SceneError> {
        let Some(info) = layer_slot::<json::texture::Info>(check, m, extension, name, "texture")?
        else {
            return Ok(None);
        };
        let slot = if srgb {
            TextureSlot::colour(&info, name)
        } else {
            TextureSlot::data(&info, name)
        };
        self.texture(input, builder, slot, check.label).map(Some)
    }

    /// The builder's id for the image behind a texture slot, decoding it on first use (colour
    /// as sRGB, a normal map as linear data: one image read both ways is decoded twice).
    fn texture(
        &mut self,
        input: &Input,
        builder: &mut SceneBuilder,
        slot: TextureSlot,
        label: &str,
    ) -> Result<TextureId, SceneError> {
        let TextureSlot {
            name: slot,
            texture: t,
            tex_coord,
            srgb,
        } = slot;
        let material_set = self.converting_uv_set;
        if tex_coord != material_set {
            builder.warn(format!(
                "{label}: {slot} uses TEXCOORD_{tex_coord} where the material's other textures \
                 use TEXCOORD_{material_set}; it reads those (kousen keeps one set a vertex)"
            ));
        }
        let image = image_of(input, (slot, t), label)?;
        let cache = if srgb {
            &mut self.images
        } else {
            &mut self.linear_images
        };
        let cached = &mut cache[image];
        if let Some(id) = cached {
            return Ok(*id);
        }
        let id = builder.add_texture(decode_image(input, image, srgb)?);
        *cached = Some(id);
        Ok(id)
    }

    /// A roughness texture (metallic-roughness layout: roughness in green, metalness 0 in blue)
    /// made from a specular-glossiness texture `info`: roughness `1 − factor × alpha`, the
    /// glossiness in its alpha channel (linear) times the material's glossiness factor.
    fn gloss_texture(
        &mut self,
        input: &Input,
        builder: &mut SceneBuilder,
        info: &json::texture::Info,
        factor: f32,
        label: &str,
    ) -> Result<TextureId, SceneError> {
        let slot = TextureSlot::data(info, "specularGlossinessTexture");
        let image = image_of(input, (slot.name, slot.texture), label)?;
        if let Some(id) = self.gloss_images.get(&(image, factor.to_bits())) {
            return Ok(*id);
        }
        let glossy = decode_image(input, image, DATA)?;
        let roughness = |alpha: f32| [0.0, 1.0 - factor * alpha, 0.0, 1.0];
        let texels = match &glossy.texels {
            Texels::LinearF32(texels) => texels.iter().map(|t| roughness(t[3])).collect(),
            Texels::Srgb8(texels) => (texels.iter())
                .map(|t| roughness(f32::from(t[3]) / 255.0))
                .collect(),
        };
        let id = builder.add_texture(Texture {
            name: format!("{} (roughness from glossiness)", glossy.name),
            texels: Texels::LinearF32(texels),
            ..glossy
        });
        self.gloss_images.insert((image, factor.to_bits()), id);
        Ok(id)
    }
}

/// The image that texture `t` (named in `slot` of material `label`) shows, checked to exist.
fn image_of(input: &Input, (slot, t): (&str, usize), label: &str) -> Result<usize, SceneError> {
    let root = input.root;
    let Some(texture) = root.textures.get(t) else {
        return Err(input.error(format!(
            "{label}: {slot} refers to texture {t}, which does not exist ({} textures)",
            root.textures.len()
        )));
    };
    let others = texture.extensions.as_ref().map(|e| &e.others);
    let webp = others.and_then(|o| o.get(WEBP_SOURCE));
    let image = match webp {
        Some(webp) => webp_source(webp).ok_or_else(|| {
            input.error(format!(
                "texture {t}: {WEBP_SOURCE} has no valid source (a non-negative image index)"
            ))
        })?,
        None => texture.source.value(),
    };
    if image >= root.images.len() {
        return Err(input.error(match image {
            NO_SOURCE => {
                let undecodable: Vec<&str> = others
                    .map(|o| o.keys().map(String::as_str).collect())
                    .unwrap_or_default();
                format!(
                    "texture {t} has no image source kousen can decode (its extension sources: \
                     {}; kousen reads {WEBP_SOURCE} besides PNG and JPEG)",
                    match undecodable.is_empty() {
                        true => "none".to_string(),
                        false => undecodable.join(", "),
                    }
                )
            }
            _ => format!(
                "texture {t}: its image source {image} does not exist ({} images)",
                root.images.len()
            ),
        }));
    }
    Ok(image)
}

/// The extension giving a texture a WebP image, preferred to its core `source` (then a PNG
/// or JPEG fallback, or absent) as the extension asks of readers that support it.
const WEBP_SOURCE: &str = "EXT_texture_webp";

/// `EXT_texture_webp`'s `source` image index, if it is one.
fn webp_source(extension: &json::Value) -> Option<usize> {
    let source = extension.get("source")?.as_u64()?;
    usize::try_from(source).ok().filter(|&i| i != NO_SOURCE)
}

/// [`Materials::layer_texture`]'s decoding: sRGB colour, or linear data.
const COLOUR: bool = true;
const DATA: bool = false;

/// What [`Materials::texture`] needs of a material's texture reference.
struct TextureSlot {
    /// The slot's name in the glTF file, for messages.
    name: &'static str,
    texture: usize,
    /// The texture-coordinate set it reads (`info_uv_set`).
    tex_coord: usize,
    /// Colour (decoded from sRGB) or data (linear).
    srgb: bool,
}

impl TextureSlot {
    fn colour(info: &json::texture::Info, name: &'static str) -> TextureSlot {
        TextureSlot {
            name,
            texture: info.index.value(),
            tex_coord: info_uv_set(info),
            srgb: true,
        }
    }

    /// A slot of linear data (not colour).
    fn data(info: &json::texture::Info, name: &'static str) -> TextureSlot {
        TextureSlot {
            name,
            texture: info.index.value(),
            tex_coord: info_uv_set(info),
            srgb: false,
        }
    }

    fn normal(normal: &json::material::NormalTexture) -> TextureSlot {
        TextureSlot {
            name: "normalTexture",
            texture: normal.index.value(),
            tex_coord: normal.tex_coord as usize,
            srgb: false,
        }
    }
}

/// Warns where a data texture's own `KHR_texture_transform` (`own`) differs from the
/// transform the material's coordinates were given (kousen keeps one set of coordinates a
/// vertex).
fn warn_own_transform(
    slot: &str,
    own: Option<Affine2>,
    transform: Option<Affine2>,
    label: &str,
    builder: &mut SceneBuilder,
) {
    if own.unwrap_or(Affine2::IDENTITY) != transform.unwrap_or(Affine2::IDENTITY) {
        builder.warn(format!(
            "{label}: {slot}'s KHR_texture_transform differs from the base colour's; \
             the base colour's is used for both"
        ));
    }
}

/// [`warn_own_transform`] for the textures of the clear coat, the sheen, the diffuse
/// transmission, the anisotropy, the iridescence, the transmission and the specular layer,
/// which read the material's one set of coordinates too.
fn warn_layer_transforms(
    m: &json::Material,
    transform: Option<Affine2>,
    label: &str,
    builder: &mut SceneBuilder,
) {
    let Some(extensions) = m.extensions.as_ref() else {
        return;
    };
    let layers = [
        (
            "KHR_materials_clearcoat",
            &[
                "clearcoatTexture",
                "clearcoatRoughnessTexture",
                "clearcoatNormalTexture",
            ][..],
        ),
        (
            "KHR_materials_sheen",
            &["sheenColorTexture", "sheenRoughnessTexture"][..],
        ),
        (
            DIFFUSE,
            &[
                "diffuseTransmissionTexture",
                "diffuseTransmissionColorTexture",
            ][..],
        ),
        (ANISOTROPY, &["anisotropyTexture"][..]),
        (
            IRIDESCENCE,
            &["iridescenceTexture", "iridescenceThicknessTexture"][..],
        ),
    ];
    for (extension, slots) in layers {
        for &slot in slots {
            let own = (extensions.others.get(extension))
                .and_then(|e| e.get(slot))
                .and_then(|info| info.get("extensions"))
                .and_then(|e| e.get("KHR_texture_transform"))
                .and_then(|t| serde_json::from_value(t.clone()).ok())
                .map(|t| transform_of(&t));
            if own.is_some() {
                warn_own_transform(slot, own, transform, label, builder);
            }
        }
    }
    let specular = extensions.specular.as_ref();
    let typed = [
        (
            "transmissionTexture",
            (extensions.transmission.as_ref()).and_then(|t| t.transmission_texture.as_ref()),
        ),
        (
            "specularTexture",
            specular.and_then(|s| s.specular_texture.as_ref()),
        ),
        (
            "specularColorTexture",
            specular.and_then(|s| s.specular_color_texture.as_ref()),
        ),
    ];
    for (slot, info) in typed {
        let own = info.and_then(slot_transform);
        if own.is_some() {
            warn_own_transform(slot, own, transform, label, builder);
        }
    }
}

/// A texture slot's `KHR_texture_transform` as an affine map of texture coordinates: scale,
/// then a counter-clockwise rotation about the origin, then the offset (the extension's
/// `translation * rotation * scale`).
fn slot_transform(info: &json::texture::Info) -> Option<Affine2> {
    let t = info.extensions.as_ref()?.texture_transform.as_ref()?;
    Some(transform_of(t))
}

/// `KHR_texture_transform`'s `translation * rotation * scale`.
fn transform_of(t: &json::extensions::texture::TextureTransform) -> Affine2 {
    Affine2::from_scale_angle_translation(
        Vec2::from_array(t.scale.0),
        t.rotation.0,
        Vec2::from_array(t.offset.0),
    )
}

/// The texture-coordinate set a texture reference reads: its `texCoord`, or its
/// `KHR_texture_transform`'s where that names one (the extension's overrides).
fn info_uv_set(info: &json::texture::Info) -> usize {
    let transform = (info.extensions.as_ref()).and_then(|e| e.texture_transform.as_ref());
    transform
        .and_then(|t| t.tex_coord)
        .unwrap_or(info.tex_coord) as usize
}

/// A material's one texture-coordinate set (kousen keeps one a vertex): that of its base
/// colour texture, else of its emissive texture, normal map or metallic-roughness texture,
/// in that order; TEXCOORD_0 where it has none of them. Its other textures read the same set
/// (with a warning where they ask for another).
fn material_uv_set(m: &json::Material) -> usize {
    let pbr = &m.pbr_metallic_roughness;
    let normal = (m.normal_texture.as_ref()).map(|n| n.tex_coord as usize);
    (pbr.base_color_texture.as_ref().map(info_uv_set))
        .or(m.emissive_texture.as_ref().map(info_uv_set))
        .or(normal)
        .or(pbr.metallic_roughness_texture.as_ref().map(info_uv_set))
        .unwrap_or(0)
}

/// The material's one texture-coordinate transform: the base colour texture's, else the
/// emissive texture's; a warning where the two differ (kousen keeps one set of coordinates a
/// vertex).
fn uv_transform(
    base: Option<&json::texture::Info>,
    emissive: Option<&json::texture::Info>,
    label: &str,
    builder: &mut SceneBuilder,
) -> Option<Affine2> {
    let (base, emissive) = (
        base.and_then(slot_transform),
        emissive.and_then(slot_transform),
    );
    if let (Some(b), Some(e)) = (base, emissive)
        && b != e
    {
        builder.warn(format!(
            "{label}: emissiveTexture's KHR_texture_transform differs from baseColorTexture's; \
             the base colour's is used for both"
        ));
    }
    base.or(emissive)
}

/// Checks of a material's values against the ranges the spec sets.
struct Check<'a> {
    input: &'a Input<'a>,
    label: &'a str,
}

impl Check<'_> {
    fn error(&self, message: String) -> SceneError {
        self.input.error(format!("{}: {message}", self.label))
    }

    /// A factor in [0, 1].
    fn unit(&self, value: f32, name: &str) -> Result<f32, SceneError> {
        if (0.0..=1.0).contains(&value) {
            Ok(value)
        } else {
            Err(self.error(format!("{name} {value} is outside [0, 1]")))
        }
    }

    /// A finite value ≥ 0.
    fn non_negative(&self, value: f32, name: &str) -> Result<f32, SceneError> {
        if value.is_finite() && value >= 0.0 {
            Ok(value)
        } else {
            Err(self.error(format!("{name} {value} is not a finite number ≥ 0")))
        }
    }
}

/// glTF's lobes as kousen's surfaces at one roughness.
struct Lobes {
    metal: Surface,
    glass: Surface,
    /// The opaque dielectric under its specular layer.
    opaque: Surface,
}

/// What a textured transmission's factor stays below, so that the opaque member is kept.
const TEXTURED_TRANSMISSION_GAP: f32 = 1.0 / (1 << 20) as f32;

/// `KHR_materials_transmission`'s factor (0 without it).
fn transmission(check: &Check, m: &json::Material) -> Result<f32, SceneError> {
    let transmission = (m.extensions.as_ref())
        .and_then(|e| e.transmission.as_ref())
        .map_or(0.0, |t| t.transmission_factor.0);
    check.unit(transmission, "transmissionFactor")
}

/// `KHR_materials_ior`'s index (glTF's default 1.5 without it), unchecked ([`lobes`] checks it).
fn ior_of(m: &json::Material) -> f32 {
    (m.extensions.as_ref())
        .and_then(|e| e.ior.as_ref())
        .map_or(DEFAULT_IOR, |i| i.ior.0)
}

/// The surfaces glTF's metal, glass and opaque dielectric make at `roughness`.
fn lobes(check: &Check, m: &json::Material, roughness: f32) -> Result<Lobes, SceneError> {
    let extensions = m.extensions.as_ref();
    let ior = ior_of(m);
    if !(ior.is_finite() && (ior >= 1.0 || ior == 0.0)) {
        return Err(check.error(format!("ior {ior} is neither ≥ 1 nor 0")));
    }
    let thickness = extensions
        .and_then(|e| e.volume.as_ref())
        .map_or(0.0, |v| v.thickness_factor.0);
    let thickness = check.non_negative(thickness, "thicknessFactor")?;
    let glass = if ior == 0.0 {
        // The extension's "F0 = 1": the specular layer reflects everything.
        Surface::Mirror
    } else {
        glass_surface(ior, thickness == 0.0, roughness)
    };
    // A thin film needs a layer to colour: a filmed metal or coat keeps its lobe however
    // rough (rendered Lambertian it would lose the film).
    let filmed = iridescence(check, m)?.is_some();
    let keep_lobe = |surface: Surface, lobe: Surface| match surface {
        Surface::Diffuse if filmed && roughness >= DIFFUSE_MIN_ROUGHNESS => lobe,
        other => other,
    };
    let rough = roughness * roughness;
    let metal = keep_lobe(
        metal_lobe(check, m, roughness)?,
        Surface::RoughConductor { alpha: rough },
    );
    let opaque = if specular_factor(check, m)? == 0.0 || ior == 1.0 {
        Surface::Diffuse
    } else if let Some(coat_ior) = layered_coat_ior(check, m, ior)? {
        // Its colour is the specular layer's: rendered Lambertian, it would be lost.
        Surface::Plastic {
            ior: coat_ior,
            alpha: rough,
        }
    } else if ior == 0.0 && roughness < DIFFUSE_MIN_ROUGHNESS {
        Surface::Mirror
    } else if ior == 0.0 {
        Surface::Diffuse
    } else {
        let lobe = Surface::Plastic { ior, alpha: rough };
        keep_lobe(coated_surface(ior, roughness), lobe)
    };
    Ok(Lobes {
        metal,
        glass,
        opaque,
    })
}

/// glTF's BRDF as kousen's surfaces, each with its probability: `mix(dielectric, metal,
/// metallic)`, the dielectric being `mix(opaque, glass, transmission)` under its specular
/// layer. Factors of 0 or 1 leave one surface; others make a blend (`SceneBuilder::add_blend`),
/// whose equal surfaces merge (rough metal and rough plastic are both Lambertian).
fn surface_members(
    check: &Check,
    m: &json::Material,
    metallic: f32,
    transmission: f32,
    roughness: f32,
) -> Result<Vec<(f32, Surface)>, SceneError> {
    let lobes = lobes(check, m, roughness)?;
    let dielectric = 1.0 - metallic;
    Ok(vec![
        (metallic, lobes.metal),
        (dielectric * transmission, lobes.glass),
        (dielectric * (1.0 - transmission), lobes.opaque),
    ]
    .into_iter()
    .filter(|(probability, _)| *probability > 0.0)
    .collect())
}

/// A material's members as the builder takes them: a textured metal first where its
/// metalness comes from a texture, then the others (`SceneBuilder::add_mapped_blend`).
struct Members {
    /// The metal's probability (glTF's `metallicFactor`), its surface at the texture's mean
    /// roughness and its map.
    textured_metal: Option<(f32, Surface, RoughnessMap)>,
    dielectric: Vec<(f32, Surface, Option<RoughnessMap>)>,
}

impl Members {
    fn plain(members: Vec<(f32, Surface)>) -> Members {
        Members {
            textured_metal: None,
            dielectric: members.into_iter().map(|(p, s)| (p, s, None)).collect(),
        }
    }

    /// Every member's surface with its probability (the dielectric's relative to the rest).
    fn surfaces(&self) -> Vec<(f32, Surface)> {
        let metal = self.textured_metal.map(|(p, s, _)| (p, s));
        let rest = self.dielectric.iter().map(|&(p, s, _)| (p, s));
        metal.into_iter().chain(rest).collect()
    }
}

/// [`Members`] of a material with a metallic-roughness texture: the metal (where
/// `metallicFactor` > 0) follows the texel's metalness and roughness; the opaque dielectric
/// is plastic of the texel's roughness or Lambertian (stored at the coat texels' mean); the
/// glass smooth or frosted by the texel's roughness (stored at the mean's).
fn mapped_members(
    check: &Check,
    m: &json::Material,
    metallic: f32,
    transmission: f32,
    texels: &TextureRoughness,
    map: impl Fn(TexturedLobe) -> RoughnessMap,
) -> Result<Members, SceneError> {
    let mean = lobes(check, m, texels.mean)?;
    let metal = metal_lobe(check, m, texels.metal_mean)?;
    let coat = lobes(check, m, texels.coat.unwrap_or(0.0))?.opaque;
    let coat_map = matches!(coat, Surface::Plastic { .. }).then(|| map(TexturedLobe::Coated));
    let glass_map = matches!(
        mean.glass,
        Surface::Dielectric { .. } | Surface::RoughDielectric { .. }
    )
    .then(|| map(TexturedLobe::Glass));
    let dielectric = [
        (transmission, mean.glass, glass_map),
        (1.0 - transmission, coat, coat_map),
    ]
    .into_iter()
    .filter(|(probability, ..)| *probability > 0.0)
    .collect();
    Ok(Members {
        textured_metal: (metallic > 0.0).then(|| (metallic, metal, map(TexturedLobe::Metal))),
        dielectric,
    })
}

/// The largest index a plastic coat is given for a specular layer over an index that is no real
/// coat's: 0 (glTF's "F0 = 1", as specular-glossiness materials convert) or above this
/// (converters also write 1000 for it). F0 = 25 %.
const MAX_LAYERED_COAT_IOR: f32 = 3.0;

/// The plastic coat's index where `KHR_materials_specular` lies over an `ior` of 0 or above
/// [`MAX_LAYERED_COAT_IOR`]: the index whose reflectance head on is the layer's mean there
/// (`min(F0 · colour, 1) · factor`, F0 = 1 for an index of 0; between 1.1 and
/// [`MAX_LAYERED_COAT_IOR`]), giving the Fresnel curve's shape, while the layer sets each
/// channel's ends (`render::dielectric_layer`). `None` for other materials.
fn layered_coat_ior(
    check: &Check,
    m: &json::Material,
    ior: f32,
) -> Result<Option<f32>, SceneError> {
    let Some(extension) = m.extensions.as_ref().and_then(|e| e.specular.as_ref()) else {
        return Ok(None);
    };
    if !(ior == 0.0 || ior > MAX_LAYERED_COAT_IOR) {
        return Ok(None);
    }
    let factor = specular_factor(check, m)?;
    let colour = Vec3::from_array(extension.specular_color_factor.0);
    let tinted_f0 = SpecularLayer::new(ior, colour, factor).tinted_f0;
    let f0 = tinted_f0.min(Vec3::ONE).element_sum() / 3.0 * factor;
    let root = f0.sqrt();
    let index = (1.0 + root) / (1.0 - root).max(f32::MIN_POSITIVE);
    Ok(Some(index.clamp(1.1, MAX_LAYERED_COAT_IOR)))
}

/// `KHR_materials_specular`'s `specularFactor` (1 without the extension), its colour factor
/// checked too. A factor of 0 leaves the opaque dielectric no specular reflection at all
/// (Lambertian, [`lobes`]).
fn specular_factor(check: &Check, m: &json::Material) -> Result<f32, SceneError> {
    let Some(specular) = m.extensions.as_ref().and_then(|e| e.specular.as_ref()) else {
        return Ok(1.0);
    };
    for (c, name) in specular
        .specular_color_factor
        .0
        .iter()
        .zip(["red", "green", "blue"])
    {
        check.non_negative(*c, &format!("specularColorFactor's {name}"))?;
    }
    check.unit(specular.specular_factor.0, "specularFactor")
}

/// Whether the material is `KHR_materials_unlit`.
fn is_unlit(m: &json::Material) -> bool {
    (m.extensions.as_ref()).is_some_and(|e| e.others.contains_key("KHR_materials_unlit"))
}

/// An unlit material (`KHR_materials_unlit`: its base colour is the colour it shows) as an
/// emitter of that radiance which reflects nothing: the base colour factor and texture become
/// its emission (which lights the scene, as a backdrop or a sky dome would), its albedo black;
/// alpha cut-outs keep reading the base colour texture's alpha. Other lobes are dropped.
fn unlit(material: Material) -> Material {
    Material {
        surface: Surface::Diffuse,
        emission: material.base_color,
        emission_texture: material.base_color_texture,
        base_color: Vec3::ZERO,
        clearcoat: None,
        sheen: None,
        transmission_texture: None,
        diffuse_transmission: None,
        anisotropy: None,
        iridescence: None,
        roughness_map: None,
        normal_texture: None,
        absorption: Vec3::ZERO,
        dispersion: 0.0,
        ..material
    }
}

/// The slot `name` of `m`'s extension `extension` (read as a `what`), `None` where either is
/// missing; one that does not read as one is an error.
fn layer_slot<T: serde::de::DeserializeOwned>(
    check: &Check,
    m: &json::Material,
    extension: &str,
    name: &str,
    what: &str,
) -> Result<Option<T>, SceneError> {
    let Some(value) = (m.extensions.as_ref())
        .and_then(|e| e.others.get(extension))
        .and_then(|e| e.get(name))
    else {
        return Ok(None);
    };
    serde_json::from_value(value.clone())
        .map(Some)
        .map_err(|e| check.error(format!("{extension}'s {name} is not a {what}: {e}")))
}

/// `KHR_materials_clearcoat`'s factors as a [`Clearcoat`] (none for a factor of 0).
fn clearcoat(check: &Check, m: &json::Material) -> Result<Option<Clearcoat>, SceneError> {
    const COAT: &str = "KHR_materials_clearcoat";
    let Some(value) = extension(m, COAT) else {
        return Ok(None);
    };
    let weight = unit_factor(check, value, COAT, "clearcoatFactor", 0.0)?;
    let roughness = unit_factor(check, value, COAT, "clearcoatRoughnessFactor", 0.0)?;
    Ok(Clearcoat::new(weight, roughness))
}

/// `KHR_materials_sheen`'s factors as a [`Sheen`] (none for a black colour).
fn sheen(check: &Check, m: &json::Material) -> Result<Option<Sheen>, SceneError> {
    let Some(value) = extension(m, SHEEN) else {
        return Ok(None);
    };
    let color = unit_color(check, value, SHEEN, "sheenColorFactor", Vec3::ZERO)?;
    let roughness = unit_factor(check, value, SHEEN, "sheenRoughnessFactor", 0.0)?;
    Ok(Sheen::new(color, roughness))
}

const SHEEN: &str = "KHR_materials_sheen";
const ANISOTROPY: &str = "KHR_materials_anisotropy";

/// glTF's metal at `roughness`: brushed where `KHR_materials_anisotropy` brushes it (a
/// mirror then becomes rough metal, which the brushing widens).
fn metal_lobe(check: &Check, m: &json::Material, roughness: f32) -> Result<Surface, SceneError> {
    Ok(if anisotropy(check, m)?.is_some() {
        brushed_metal_surface(roughness)
    } else {
        metal_surface(roughness)
    })
}

/// `KHR_materials_anisotropy`'s factors as an [`Anisotropy`] (none for a strength of 0
/// without a texture, which can only lower it).
fn anisotropy(check: &Check, m: &json::Material) -> Result<Option<Anisotropy>, SceneError> {
    let Some(value) = extension(m, ANISOTROPY) else {
        return Ok(None);
    };
    let strength = unit_factor(check, value, ANISOTROPY, "anisotropyStrength", 0.0)?;
    let rotation = match value.get("anisotropyRotation") {
        None => 0.0,
        Some(v) => match v.as_f64() {
            Some(x) if x.is_finite() => x as f32,
            _ => {
                return Err(check.error(format!(
                    "{ANISOTROPY}'s anisotropyRotation is not a finite number"
                )));
            }
        },
    };
    Ok((strength > 0.0).then_some(Anisotropy {
        strength,
        rotation,
        texture: None,
    }))
}

const IRIDESCENCE: &str = "KHR_materials_iridescence";

/// `KHR_materials_iridescence`'s defaults: the film's index and its thickness range (nm).
const DEFAULT_IRIDESCENCE_IOR: f32 = 1.3;
const DEFAULT_THICKNESS_MIN: f32 = 100.0;
const DEFAULT_THICKNESS_MAX: f32 = 400.0;

/// `KHR_materials_iridescence`'s factors as an [`Iridescence`] (none for a factor of 0,
/// which its texture can only lower): the factor in [0, 1], the index finite and ≥ 1, the
/// thicknesses finite and ≥ 0. A maximum below the minimum is kept as given (the thickness
/// texture then runs from the minimum down to the maximum, as the spec allows).
fn iridescence(check: &Check, m: &json::Material) -> Result<Option<Iridescence>, SceneError> {
    let Some(value) = extension(m, IRIDESCENCE) else {
        return Ok(None);
    };
    let factor = unit_factor(check, value, IRIDESCENCE, "iridescenceFactor", 0.0)?;
    let name = "iridescenceIor";
    let ior = extension_number(check, value, IRIDESCENCE, name, DEFAULT_IRIDESCENCE_IOR)?;
    if !(ior.is_finite() && ior >= 1.0) {
        return Err(check.error(format!(
            "{IRIDESCENCE}'s {name} {ior} is not a finite number ≥ 1"
        )));
    }
    let thickness = |name: &str, default| {
        let nm = extension_number(check, value, IRIDESCENCE, name, default)?;
        check.non_negative(nm, &format!("{IRIDESCENCE}'s {name}"))
    };
    let thickness_min = thickness("iridescenceThicknessMinimum", DEFAULT_THICKNESS_MIN)?;
    let thickness_max = thickness("iridescenceThicknessMaximum", DEFAULT_THICKNESS_MAX)?;
    Ok((factor > 0.0).then_some(Iridescence {
        factor,
        texture: None,
        ior,
        thickness_min,
        thickness_max,
        thickness_texture: None,
    }))
}

const DIFFUSE: &str = "KHR_materials_diffuse_transmission";

/// `KHR_materials_diffuse_transmission`'s factors as a [`DiffuseTransmission`] (none for a
/// factor of 0).
fn diffuse_transmission(
    check: &Check,
    m: &json::Material,
) -> Result<Option<DiffuseTransmission>, SceneError> {
    let Some(value) = extension(m, DIFFUSE) else {
        return Ok(None);
    };
    let factor = unit_factor(check, value, DIFFUSE, "diffuseTransmissionFactor", 0.0)?;
    let color = unit_color(
        check,
        value,
        DIFFUSE,
        "diffuseTransmissionColorFactor",
        Vec3::ONE,
    )?;
    Ok(DiffuseTransmission::new(factor, color))
}

const VOLUME_SCATTER: &str = "KHR_materials_volume_scatter";

/// A volume's absorption and scattering (`Material::absorption`, `scattering`,
/// `scatter_anisotropy`).
struct VolumeScatter {
    absorption: Vec3,
    scattering: Vec3,
    anisotropy: f32,
}

/// `KHR_materials_volume_scatter` (a Khronos draft) on a `scattering_volume` (a translucent
/// solid, or solid glass that is not a blend): the volume's
/// attenuation is then its `extinction` (absorption and scattering together), of which the
/// single-scattering albedo of `multiscatterColor` (default black:
/// [`crate::single_scatter_albedo`]) scatters and the rest absorbs; `scatterAnisotropy` in
/// (−1, 1) the phase function's asymmetry. Elsewhere warned about and ignored (only
/// translucent solids scatter); without it everything is absorption.
fn volume_scatter(
    check: &Check,
    m: &json::Material,
    scattering_volume: bool,
    extinction: Vec3,
    builder: &mut SceneBuilder,
) -> Result<VolumeScatter, SceneError> {
    let absorbing = VolumeScatter {
        absorption: extinction,
        scattering: Vec3::ZERO,
        anisotropy: 0.0,
    };
    let Some(value) = extension(m, VOLUME_SCATTER) else {
        return Ok(absorbing);
    };
    if !scattering_volume {
        builder.warn(format!(
            "{}: {VOLUME_SCATTER} ignored: only translucent solids (diffuse transmission with \
             a volume) and solid glass that is not a blend scatter",
            check.label
        ));
        return Ok(absorbing);
    }
    let multiscatter = unit_color(
        check,
        value,
        VOLUME_SCATTER,
        "multiscatterColor",
        Vec3::ZERO,
    )?;
    let anisotropy = match value.get("scatterAnisotropy") {
        None => 0.0,
        Some(v) => v
            .as_f64()
            .map(|g| g as f32)
            .filter(|g| g.abs() < 1.0)
            .ok_or_else(|| {
                check.error(format!(
                    "{VOLUME_SCATTER}'s scatterAnisotropy {v} is not a number in (-1, 1)"
                ))
            })?,
    };
    let scattering = extinction * crate::single_scatter_albedo(multiscatter);
    Ok(VolumeScatter {
        absorption: extinction - scattering,
        scattering,
        anisotropy,
    })
}

/// `m`'s extension `name`, if it has it.
fn extension<'a>(m: &'a json::Material, name: &str) -> Option<&'a serde_json::Value> {
    m.extensions.as_ref().and_then(|e| e.others.get(name))
}

/// The number `name` of extension `extension` (`value`), in [0, 1]; `default` where missing.
fn unit_factor(
    check: &Check,
    value: &serde_json::Value,
    extension: &str,
    name: &str,
    default: f32,
) -> Result<f32, SceneError> {
    let x = extension_number(check, value, extension, name, default)?;
    check.unit(x, &format!("{extension}'s {name}"))
}

/// The number `name` of extension `extension` (`value`) as an `f32` (unchecked: one too
/// large for it becomes infinite); `default` where missing.
fn extension_number(
    check: &Check,
    value: &serde_json::Value,
    extension: &str,
    name: &str,
    default: f32,
) -> Result<f32, SceneError> {
    match value.get(name) {
        None => Ok(default),
        Some(v) => (v.as_f64())
            .map(|x| x as f32)
            .ok_or_else(|| check.error(format!("{extension}'s {name} is not a number"))),
    }
}

/// The colour `name` of extension `extension` (`value`): three numbers, each in [0, 1];
/// `default` where missing.
fn unit_color(
    check: &Check,
    value: &serde_json::Value,
    extension: &str,
    name: &str,
    default: Vec3,
) -> Result<Vec3, SceneError> {
    let Some(v) = value.get(name) else {
        return Ok(default);
    };
    let channels: Vec<f32> = (v.as_array())
        .filter(|a| a.len() == 3)
        .and_then(|a| a.iter().map(|x| x.as_f64().map(|x| x as f32)).collect())
        .ok_or_else(|| check.error(format!("{extension}'s {name} is not three numbers")))?;
    for &c in &channels {
        check.unit(c, &format!("{extension}'s {name}"))?;
    }
    Ok(Vec3::from_slice(&channels))
}

/// `KHR_materials_dispersion` as [`Material::dispersion`]: (ior − 1) / V with the Abbe
/// number V = 20 / the extension's `dispersion`, on smooth solid glass of one surface (a
/// warning and none elsewhere).
fn dispersion(
    check: &Check,
    m: &json::Material,
    members: &[(f32, Surface)],
    builder: &mut SceneBuilder,
) -> Result<f32, SceneError> {
    let Some(value) = m
        .extensions
        .as_ref()
        .and_then(|e| e.others.get("KHR_materials_dispersion"))
    else {
        return Ok(0.0);
    };
    let strength = value
        .get("dispersion")
        .and_then(|d| d.as_f64())
        .unwrap_or(0.0) as f32;
    if !strength.is_finite() || strength < 0.0 {
        return Err(check.error(format!(
            "KHR_materials_dispersion's dispersion {strength} is not a finite number from 0"
        )));
    }
    if strength == 0.0 {
        return Ok(0.0);
    }
    // The solid glass member (a blend's too: only glass surfaces disperse).
    let solid_glass = members.iter().find_map(|(_, surface)| surface.solid_ior());
    match solid_glass {
        Some(ior) => Ok(crate::dispersion_from_abbe(ior, 20.0 / strength)),
        None => {
            builder.warn(format!(
                "{}: KHR_materials_dispersion is rendered on solid glass only (not on \
                 thin-walled glass or opaque surfaces); ignored",
                check.label
            ));
            Ok(0.0)
        }
    }
}

/// A solid dielectric's or a `translucent_volume`'s absorption from `KHR_materials_volume`'s
/// attenuation colour (each in [0, 1]) and distance (> 0, infinite by default); zero for every
/// other surface (the extension describes a volume, which thin-walled and opaque surfaces do
/// not have).
fn absorption(
    check: &Check,
    m: &json::Material,
    members: &[(f32, Surface)],
    translucent_volume: bool,
) -> Result<Vec3, SceneError> {
    let solid = translucent_volume || members.iter().any(|(_, s)| s.is_solid_dielectric());
    let Some(volume) = m.extensions.as_ref().and_then(|e| e.volume.as_ref()) else {
        return Ok(Vec3::ZERO);
    };
    if !solid {
        return Ok(Vec3::ZERO);
    }
    let color = volume.attenuation_color.0;
    for (c, name) in color.iter().zip(["red", "green", "blue"]) {
        check.unit(*c, &format!("attenuationColor's {name}"))?;
    }
    let distance = volume.attenuation_distance.0;
    if distance.is_nan() || distance <= 0.0 {
        return Err(check.error(format!("attenuationDistance {distance} is not above 0")));
    }
    Ok(scene_absorption(Vec3::from_array(color), distance))
}

/// Emitted radiance: emissiveFactor (finite, ≥ 0) × emissive strength (finite, ≥ 0).
fn emission(check: &Check, m: &json::Material) -> Result<Vec3, SceneError> {
    let factor = m.emissive_factor.0;
    for (c, name) in factor.iter().zip(["red", "green", "blue"]) {
        check.non_negative(*c, &format!("emissiveFactor's {name}"))?;
    }
    let strength = m
        .extensions
        .as_ref()
        .and_then(|e| e.emissive_strength.as_ref())
        .map_or(1.0, |s| s.emissive_strength.0);
    let strength = check.non_negative(strength, "emissiveStrength")?;
    let emission = Vec3::from_array(factor) * strength;
    if !emission.is_finite() {
        return Err(check.error("emission overflows 32-bit floats".to_string()));
    }
    Ok(emission)
}

fn alpha_mode(
    check: &Check,
    m: &json::Material,
    builder: &mut SceneBuilder,
) -> Result<AlphaMode, SceneError> {
    let cutoff = m.alpha_cutoff.map_or(DEFAULT_ALPHA_CUTOFF, |c| c.0);
    match m.alpha_mode {
        Checked::Valid(GltfAlphaMode::Opaque) => Ok(AlphaMode::Opaque),
        Checked::Valid(GltfAlphaMode::Mask) => Ok(AlphaMode::Mask {
            cutoff: check.non_negative(cutoff, "alphaCutoff")?,
        }),
        Checked::Valid(GltfAlphaMode::Blend) => {
            builder.warn(format!(
                "{}: alphaMode BLEND is rendered as MASK with cutoff {DEFAULT_ALPHA_CUTOFF}",
                check.label
            ));
            Ok(AlphaMode::Mask {
                cutoff: DEFAULT_ALPHA_CUTOFF,
            })
        }
        Checked::Invalid => Err(check.error("invalid alphaMode".to_string())),
    }
}

/// Decodes image `index` (which must exist) as sRGB colour.
fn decode_image(input: &Input, index: usize, srgb: bool) -> Result<Texture, SceneError> {
    let image = &input.root.images[index];
    let context = || format!("image {index}");
    let fallback_name = image.name.clone().unwrap_or_else(context);
    let (name, bytes) = match (&image.uri, image.buffer_view) {
        (Some(uri), _) => match resolve_uri(input.path, uri).context(context)? {
            Resolved::Data(bytes) => (fallback_name, Cow::Owned(bytes)),
            Resolved::File(file) => {
                let name = file.file_name().map(|n| n.to_string_lossy().into_owned());
                let bytes = read_regular(&file, None).context(context)?;
                (name.unwrap_or(fallback_name), Cow::Owned(bytes))
            }
        },
        (None, Some(view)) => {
            let view = input.buffers.view(view.value()).context(context)?;
            (fallback_name, Cow::Borrowed(view.bytes))
        }
        (None, None) => {
            return Err(input.error(format!("{}: has neither a uri nor a bufferView", context())));
        }
    };
    Texture::decode(&name, &bytes, srgb).map_err(|e| input.error(format!("{}: {e}", context())))
}
