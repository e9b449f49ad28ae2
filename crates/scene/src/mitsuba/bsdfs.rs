//! Mitsuba BSDFs mapped onto kousen's materials (see the table in [`super`]).

use glam::{Mat4, Vec3};
use roxmltree::Node;

use super::Reader;
use super::properties::property;
use crate::{
    AlphaMode, Material, SceneError, Surface, TextureId, coated_surface, glass_surface,
    metal_surface,
};

/// Mitsuba's exterior index by default: air.
const AIR_IOR: f32 = 1.000277;
/// Defaults of Mitsuba's `dielectric` and `plastic` interior indices (BK7 and polypropylene).
const DIELECTRIC_IOR: f32 = 1.5046;
const PLASTIC_IOR: f32 = 1.49;
/// How many BSDFs (`twosided`, `mask`, ...) may wrap one another: enough for any scene, and a
/// bound on a reference cycle.
const MAX_NESTING: u32 = 16;
/// Mitsuba's default GGX width of its rough BSDFs.
const ROUGH_ALPHA: f32 = 0.1;

/// Named indices of refraction Mitsuba accepts (at 589 nm), lower case.
const NAMED_IORS: [(&str, f32); 23] = [
    ("vacuum", 1.0),
    ("helium", 1.00004),
    ("hydrogen", 1.00013),
    ("air", 1.000277),
    ("carbon dioxide", 1.00045),
    ("water", 1.333),
    ("acetone", 1.36),
    ("ethanol", 1.361),
    ("carbon tetrachloride", 1.461),
    ("glycerol", 1.4729),
    ("benzene", 1.501),
    ("silicone oil", 1.52045),
    ("bromine", 1.661),
    ("water ice", 1.31),
    ("fused quartz", 1.458),
    ("pyrex", 1.47),
    ("acrylic glass", 1.49),
    ("polypropylene", 1.49),
    ("bk7", 1.5046),
    ("sodium chloride", 1.544),
    ("amber", 1.55),
    ("pet", 1.575),
    ("diamond", 2.419),
];

/// A BSDF mapped onto kousen (`crate::mapped`), its base colour texture's `to_uv` the mapping
/// the shape's texture coordinates go through.
pub(super) type Mapped = crate::mapped::Mapped<Mat4>;

/// A colour or a texture of it, as a reflectance property gives it.
struct Reflectance {
    colour: Vec3,
    texture: Option<TextureId>,
    /// A bitmap's `to_uv`: the map from a surface's texture coordinates to the image's.
    to_uv: Option<Mat4>,
}

impl<'a> Reader<'a> {
    /// The material Mitsuba BSDF `node` (a `<bsdf>` element) maps to, without emission.
    pub(super) fn material(&mut self, node: Node<'a, 'a>) -> Result<Mapped, SceneError> {
        self.material_within(node, MAX_NESTING)
    }

    /// [`Reader::material`] of a BSDF that may wrap at most `depth` more inside it.
    fn material_within(&mut self, node: Node<'a, 'a>, depth: u32) -> Result<Mapped, SceneError> {
        let kind = self.context.required(node, "type")?;
        let name = node.attribute("id").unwrap_or(&kind).to_string();
        let base = |surface, base_color| Material {
            name: name.clone(),
            surface,
            base_color,
            ..Material::default()
        };
        let alpha = |r: &mut Self| r.float(node, "alpha", ROUGH_ALPHA);
        let mut to_uv = None;
        let material = match kind.as_str() {
            "blendbsdf" => return self.blend(node, depth),
            "twosided" | "mask" | "bumpmap" | "normalmap" => {
                if !matches!(kind.as_str(), "twosided" | "mask") {
                    self.warn(node, format!("{kind} is read as the BSDF inside it alone"));
                }
                let inner = node
                    .children()
                    .find(|c| c.has_tag_name("bsdf") || c.has_tag_name("ref"))
                    .ok_or_else(|| self.context.error(node, "holds no BSDF"))?;
                let inner = self.resolve_bsdf(inner)?;
                let depth = depth.checked_sub(1).ok_or_else(|| {
                    self.context
                        .error(node, "BSDFs wrapped too deep (a reference cycle?)")
                })?;
                let mut mapped = self.material_within(inner, depth)?;
                if kind == "mask" {
                    for member in mapped.members_mut() {
                        *member = self.masked(node, member.clone())?;
                    }
                }
                return Ok(mapped);
            }
            "diffuse" => {
                let reflectance = self.reflectance(node, "reflectance", Vec3::splat(0.5))?;
                to_uv = reflectance.to_uv;
                Material {
                    base_color_texture: reflectance.texture,
                    ..base(Surface::Diffuse, reflectance.colour)
                }
            }
            "dielectric" | "thindielectric" | "roughdielectric" => {
                let ior = self.ior(node, "int_ior", DIELECTRIC_IOR)?
                    / self.ior(node, "ext_ior", AIR_IOR)?;
                let roughness = match kind.as_str() {
                    "roughdielectric" => alpha(self)?.sqrt(),
                    _ => 0.0,
                };
                let tint = self.colour(node, "specular_transmittance", Vec3::ONE)?;
                let thin = kind == "thindielectric";
                base(glass_surface(ior, thin, roughness), tint)
            }
            "conductor" | "roughconductor" => {
                let roughness = match kind.as_str() {
                    "roughconductor" => alpha(self)?.sqrt(),
                    _ => 0.0,
                };
                let tint = self.colour(node, "specular_reflectance", Vec3::ONE)?;
                let (colour, metal_edge) = match self.metal_reflectance(node)? {
                    Some(f0) => (tint * f0, crate::material::metal_edge_to(tint * f0, tint)),
                    // A perfect mirror times the tint at every angle.
                    None => (tint, Vec3::ZERO),
                };
                Material {
                    metal_edge,
                    ..base(metal_surface(roughness), colour)
                }
            }
            "plastic" | "roughplastic" => {
                let ior =
                    self.ior(node, "int_ior", PLASTIC_IOR)? / self.ior(node, "ext_ior", AIR_IOR)?;
                let roughness = match kind.as_str() {
                    "roughplastic" => alpha(self)?.sqrt(),
                    _ => 0.0,
                };
                let reflectance =
                    self.reflectance(node, "diffuse_reflectance", Vec3::splat(0.5))?;
                to_uv = reflectance.to_uv;
                Material {
                    base_color_texture: reflectance.texture,
                    ..base(coated_surface(ior, roughness), reflectance.colour)
                }
            }
            "principled" => return self.principled(node, &name),
            "null" => Material {
                // Invisible: cut out everywhere.
                alpha: 0.0,
                alpha_mode: AlphaMode::Mask { cutoff: 0.5 },
                ..base(Surface::Diffuse, Vec3::ZERO)
            },
            other => {
                self.warn(
                    node,
                    format!("BSDF \"{other}\" is not read: grey diffuse instead"),
                );
                base(Surface::Diffuse, Vec3::splat(0.5))
            }
        };
        Ok(Mapped::plain(material, to_uv))
    }

    /// `blendbsdf`: its first BSDF with probability 1 − `weight`, its second with `weight` (a
    /// weight texture read as its mean), each member's own mixture or blend spread out.
    fn blend(&mut self, node: Node<'a, 'a>, depth: u32) -> Result<Mapped, SceneError> {
        let weight = match property(node, "weight") {
            Some(p) if p.has_tag_name("float") => self.context.number(p, "value")?,
            Some(_) => self.colour(node, "weight", Vec3::splat(0.5))?.x,
            None => 0.5,
        }
        .clamp(0.0, 1.0);
        let inner: Vec<Node> = (node.children())
            .filter(|c| c.has_tag_name("bsdf") || c.has_tag_name("ref"))
            .collect();
        let [first, second] = inner[..] else {
            return Err(self.context.error(node, "a blendbsdf holds two BSDFs"));
        };
        let depth = depth.checked_sub(1).ok_or_else(|| {
            self.context
                .error(node, "BSDFs wrapped too deep (a reference cycle?)")
        })?;
        let mut mixture = Vec::new();
        let mut to_uv = None;
        for (probability, inner) in [(1.0 - weight, first), (weight, second)] {
            let inner = self.resolve_bsdf(inner)?;
            let mapped = self.material_within(inner, depth)?;
            to_uv = to_uv.or(mapped.spread_into(probability, &mut mixture));
        }
        Ok(Mapped::mixed(mixture, to_uv))
    }

    /// `material` cut out where a `mask`'s `opacity` is below ½: an opacity texture becomes
    /// the alpha of the material's base colour texture (a white one where it has none);
    /// a constant opacity below 1 (blending, which kousen does not do) is warned about.
    fn masked(&mut self, node: Node<'a, 'a>, material: Material) -> Result<Material, SceneError> {
        let Some(mut opacity) = property(node, "opacity") else {
            return Ok(material);
        };
        if opacity.has_tag_name("ref") {
            opacity = self.referenced(opacity, "texture")?;
        }
        if !opacity.has_tag_name("texture") {
            let value = self.context.colour(opacity, &mut self.warnings)?;
            if value.min_element() < 1.0 {
                self.warn(node, "a constant opacity below 1 is not read: opaque");
            }
            return Ok(material);
        }
        let kind = self.context.required(opacity, "type")?;
        let file = property(opacity, "filename").filter(|_| kind == "bitmap");
        let file =
            file.ok_or_else(|| self.context.error(opacity, "an opacity must be a bitmap"))?;
        let file = self.context.required(file, "value")?;
        let mask = self.bitmap(opacity, &file, false)?;
        let base = material
            .base_color_texture
            .map(|id| self.builder.texture(id));
        let cut_out = crate::textures::with_mask(base, self.builder.texture(mask));
        Ok(Material {
            base_color_texture: Some(self.builder.add_texture(cut_out)),
            alpha_mode: AlphaMode::Mask { cutoff: 0.5 },
            ..material
        })
    }

    /// Mitsuba 3's principled BSDF, read as glTF's metallic-roughness material: metal with
    /// probability `metallic`, else glass with probability `spec_trans`, else plastic, all of
    /// `roughness` and the base colour (a blend where more than one has a share).
    fn principled(&mut self, node: Node<'a, 'a>, name: &str) -> Result<Mapped, SceneError> {
        let reflectance = self.reflectance(node, "base_color", Vec3::splat(0.5))?;
        let metallic = self.float(node, "metallic", 0.0)?.clamp(0.0, 1.0);
        let transmission = self.float(node, "spec_trans", 0.0)?.clamp(0.0, 1.0);
        let roughness = self.float(node, "roughness", 0.5)?.clamp(0.0, 1.0);
        let ior = self.float(node, "eta", 1.5)?;
        let base = Material {
            name: name.to_string(),
            base_color: reflectance.colour,
            base_color_texture: reflectance.texture,
            ..Material::default()
        };
        let mixture =
            crate::material::principled_mixture(base, metallic, transmission, roughness, ior);
        Ok(Mapped::mixed(mixture, reflectance.to_uv))
    }

    /// A float property of `node` (`<float>` or `<integer>`), `default` where absent.
    pub(super) fn float(
        &mut self,
        node: Node<'a, 'a>,
        name: &str,
        default: f32,
    ) -> Result<f32, SceneError> {
        match property(node, name) {
            Some(p) if p.has_tag_name("float") || p.has_tag_name("integer") => {
                self.context.number(p, "value")
            }
            Some(p) => Err(self.context.error(p, format!("{name} must be a float"))),
            None => Ok(default),
        }
    }

    /// A colour property: `<rgb>`, `<spectrum>` or `<float>`; a texture is read as its mean
    /// colour (where only a colour can be used, as for a tint).
    pub(super) fn colour(
        &mut self,
        node: Node<'a, 'a>,
        name: &str,
        default: Vec3,
    ) -> Result<Vec3, SceneError> {
        let reflectance = self.reflectance(node, name, default)?;
        Ok(match reflectance.texture {
            Some(texture) => {
                self.warn(node, format!("{name}'s texture is read as its mean colour"));
                self.builder.texture(texture).mean_linear().truncate()
            }
            None => reflectance.colour,
        })
    }

    /// A reflectance property: a colour, or a `bitmap` texture (inline or by reference).
    fn reflectance(
        &mut self,
        node: Node<'a, 'a>,
        name: &str,
        default: Vec3,
    ) -> Result<Reflectance, SceneError> {
        let Some(mut p) = property(node, name) else {
            return Ok(Reflectance {
                colour: default,
                texture: None,
                to_uv: None,
            });
        };
        if p.has_tag_name("ref") {
            p = self.referenced(p, "texture")?;
        }
        if p.has_tag_name("texture") {
            return self.texture(p);
        }
        let colour = self.context.colour(p, &mut self.warnings)?;
        Ok(Reflectance {
            colour,
            texture: None,
            to_uv: None,
        })
    }

    /// A `<texture>`: a `bitmap` decoded (sRGB unless `raw`), a checkerboard as the mean of
    /// its colours.
    fn texture(&mut self, node: Node<'a, 'a>) -> Result<Reflectance, SceneError> {
        let kind = self.context.required(node, "type")?;
        match kind.as_str() {
            "bitmap" => {
                let file = property(node, "filename")
                    .ok_or_else(|| self.context.error(node, "a bitmap needs a filename"))?;
                let file = self.context.required(file, "value")?;
                let raw = property(node, "raw")
                    .and_then(|p| self.context.attribute(p, "value"))
                    .is_some_and(|v| v == "true");
                let texture = self.bitmap(node, &file, !raw)?;
                let to_uv = match property(node, "to_uv") {
                    Some(t) => Some(self.context.transform(t)?),
                    None => None,
                };
                Ok(Reflectance {
                    colour: Vec3::ONE,
                    texture: Some(texture),
                    to_uv,
                })
            }
            "checkerboard" => {
                let a = self.colour(node, "color0", Vec3::splat(0.4))?;
                let b = self.colour(node, "color1", Vec3::splat(0.2))?;
                self.warn(node, "a checkerboard is read as the mean of its colours");
                Ok(Reflectance {
                    colour: (a + b) / 2.0,
                    texture: None,
                    to_uv: None,
                })
            }
            other => {
                self.warn(
                    node,
                    format!("texture \"{other}\" is not read: grey instead"),
                );
                Ok(Reflectance {
                    colour: Vec3::splat(0.5),
                    texture: None,
                    to_uv: None,
                })
            }
        }
    }

    /// An index of refraction: a number or one of Mitsuba's named materials.
    fn ior(&mut self, node: Node<'a, 'a>, name: &str, default: f32) -> Result<f32, SceneError> {
        let Some(p) = property(node, name) else {
            return Ok(default);
        };
        let ior = if p.has_tag_name("string") {
            let named = self.context.required(p, "value")?.to_ascii_lowercase();
            NAMED_IORS
                .iter()
                .find(|(n, _)| *n == named)
                .map(|(_, ior)| *ior)
                .ok_or_else(|| self.context.error(p, format!("unknown index \"{named}\"")))?
        } else {
            self.context.number(p, "value")?
        };
        match ior > 0.0 {
            true => Ok(ior),
            false => Err(self
                .context
                .error(p, format!("{name} {ior} is not positive"))),
        }
    }

    /// A conductor's reflectance at normal incidence: from its `eta` and `k` where given
    /// (((η − 1)² + k²) / ((η + 1)² + k²) per channel, η relative to `ext_eta`), else its named
    /// `material` ([`crate::material::metal_f0`]); `None` for "none", Mitsuba's default, a
    /// perfect mirror without Fresnel's rise.
    fn metal_reflectance(&mut self, node: Node<'a, 'a>) -> Result<Option<Vec3>, SceneError> {
        if property(node, "eta").is_some() {
            let eta = self.colour(node, "eta", Vec3::ONE)? / self.float(node, "ext_eta", 1.0)?;
            let k = self.colour(node, "k", Vec3::ZERO)?;
            let f0 = ((eta - 1.0) * (eta - 1.0) + k * k) / ((eta + 1.0) * (eta + 1.0) + k * k);
            return Ok(Some(f0.clamp(Vec3::ZERO, Vec3::ONE)));
        }
        let Some(p) = property(node, "material") else {
            return Ok(None);
        };
        let named = self.context.required(p, "value")?;
        if named == "none" {
            return Ok(None);
        }
        Ok(Some(match crate::material::metal_f0(&named) {
            Some(f0) => f0,
            None => {
                self.warn(
                    p,
                    format!("conductor \"{named}\" is not in kousen's table: grey metal"),
                );
                Vec3::splat(0.8)
            }
        }))
    }
}
