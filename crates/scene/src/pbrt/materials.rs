//! pbrt's materials and textures mapped onto kousen's materials (see the list in [`super`]).
//!
//! Roughness: pbrt's `roughness` is remapped to a GGX width α = √roughness unless
//! `remaproughness` is false (then α = roughness); kousen's surfaces take glTF's roughness,
//! √α. Anisotropic widths are read as their mean.

use std::path::Path;

use glam::{Vec2, Vec3};

use super::spectra;
use super::tokens::{Param, Params, Values};
use super::{Definition, MaterialRef, Reader};
use crate::media::Medium;
use crate::{
    AlphaMode, Clearcoat, DiffuseTransmission, Material, SceneError, Surface, TextureId,
    coated_surface, dispersion_from_abbe, glass_surface, metal_surface,
};

/// How many materials (`mix`) or textures (`scale`, `mix`) may refer one to another: enough
/// for any scene, and a bound on a cycle.
pub(super) const MAX_NESTING: u32 = 16;
/// pbrt's GGX widths below this are perfectly smooth.
const SMOOTH_ALPHA: f32 = 1e-3;

/// A material made for shapes: its builder id and the map of their texture coordinates.
#[derive(Clone, Copy, Debug)]
pub(super) struct Made {
    pub id: u32,
    uv_map: Option<UvMap>,
}

impl Made {
    /// kousen's texture coordinates of pbrt's (s, t): through the image map's scale and
    /// offset, then t turned over (pbrt looks images up at 1 − t; kousen's v = 0 is the top).
    pub fn uv(&self, st: Vec2) -> Vec2 {
        let st = match self.uv_map {
            Some(map) => st * map.scale + map.offset,
            None => st,
        };
        Vec2::new(st.x, 1.0 - st.y)
    }
}

/// An `imagemap`'s `uscale`, `vscale`, `udelta`, `vdelta`.
#[derive(Clone, Copy, Debug, PartialEq)]
struct UvMap {
    scale: Vec2,
    offset: Vec2,
}

/// A colour: a constant, or a texture times it.
#[derive(Clone, Copy, Debug)]
pub(super) struct Colour {
    value: Vec3,
    texture: Option<TextureId>,
    uv_map: Option<UvMap>,
}

impl Colour {
    fn constant(value: Vec3) -> Colour {
        Colour {
            value,
            texture: None,
            uv_map: None,
        }
    }

    /// This colour times `factor`.
    fn scaled(self, factor: Vec3) -> Colour {
        Colour {
            value: self.value * factor,
            ..self
        }
    }
}

/// A pbrt material read (`crate::mapped`: for a `mix`, the members of its blend), with its
/// textures' uv mapping.
type Mapped = crate::mapped::Mapped<UvMap>;

impl Reader {
    /// The material shapes of `state`'s material get, with the area light's emission (radiance
    /// and two-sidedness) and the shape's `alpha` cut-out; made once for each.
    pub(super) fn shape_material(
        &mut self,
        (material, interior): (&MaterialRef, Option<&str>),
        emission: Option<(Vec3, bool)>,
        shape: &Params,
        file: &Path,
    ) -> Result<Made, SceneError> {
        let fail = |message: String| SceneError::format(file, message);
        let alpha = shape.get("alpha").cloned();
        let emission_key =
            emission.map(|(r, two)| [r.x.to_bits(), r.y.to_bits(), r.z.to_bits(), two as u32]);
        let alpha_key = alpha.as_ref().map(|p| format!("{:?}", p.values));
        let interior_key = interior.map(str::to_string);
        let key = (material.clone(), emission_key, alpha_key, interior_key);
        if let Some(made) = self.made.get(&key) {
            return Ok(*made);
        }
        let mut mapped = match material {
            MaterialRef::Default => Mapped::plain(diffuse(Vec3::splat(0.5), "default"), None),
            MaterialRef::Anonymous(i) => {
                let definition = self.anonymous[*i].clone();
                self.material(&definition, "material", MAX_NESTING)?
            }
            MaterialRef::Named(name) => {
                let definition = self
                    .named_materials
                    .get(name)
                    .cloned()
                    .ok_or_else(|| fail(format!("no material is named \"{name}\"")))?;
                self.material(&definition, name, MAX_NESTING)?
            }
        };
        for m in mapped.members_mut() {
            if let Some((radiance, two_sided)) = emission {
                m.emission = radiance;
                m.double_sided = two_sided;
                m.name = format!("{} (emitter)", m.name);
            }
            if let Some(alpha) = &alpha {
                self.cut_out(m, alpha, file)?;
            }
        }
        if let Some(name) = interior
            && let Some(medium) = self.interior_medium(name, file)?
        {
            match mapped.fill(medium) {
                true => _ = self.media_filled.insert(name.to_string()),
                false => {
                    let message = format!(
                        "medium \"{name}\" is read inside solid glass or an interface only"
                    );
                    self.warn(file, message);
                }
            }
        }
        let (id, uv_map, simplified) = mapped.add_to(&mut self.builder);
        if let Some(why) = simplified {
            self.warn(file, why);
        }
        let made = Made { id, uv_map };
        self.made.insert(key, made);
        Ok(made)
    }

    /// The `MakeNamedMedium` called `name` as kousen's solids hold a medium: pbrt's
    /// `homogeneous` (`sigma_a` and `sigma_s` × `scale`, Henyey–Greenstein `g`); `None`,
    /// warned about, for other kinds (grids, clouds) and presets.
    pub(super) fn interior_medium(
        &mut self,
        name: &str,
        file: &Path,
    ) -> Result<Option<Medium>, SceneError> {
        if let Some(read) = self.media_read.get(name) {
            return Ok(*read);
        }
        let definition = (self.media.get(name).cloned())
            .ok_or_else(|| SceneError::format(file, format!("no medium is named \"{name}\"")))?;
        let file = definition.file.as_path();
        let p = &definition.params;
        let medium = if definition.class != "homogeneous" {
            let kind = &definition.class;
            self.warn(
                file,
                format!("medium \"{name}\" of type \"{kind}\" is not read"),
            );
            None
        } else if p.get("preset").is_some() {
            self.warn(file, format!("medium \"{name}\": presets are not read"));
            None
        } else {
            // pbrt's defaults (both versions): a thin, bluish scattering medium.
            let absorption =
                self.colour(p, &["sigma_a"], Vec3::new(0.0011, 0.0024, 0.014), file)?;
            let scattering = self.colour(p, &["sigma_s"], Vec3::new(2.55, 3.21, 7.7), file)?;
            let scale = self.scalar(p, "scale", 1.0, file)?;
            let g = self.scalar(p, "g", 0.0, file)?;
            if p.get("Le").is_some() {
                self.warn(
                    file,
                    format!("medium \"{name}\": its emission Le is not read"),
                );
            }
            p.get("Lescale");
            self.warn_unused(file, &format!("medium \"{name}\""), p);
            let (absorption, scattering) = (absorption.value * scale, scattering.value * scale);
            let valid = |v: Vec3| v.is_finite() && v.min_element() >= 0.0;
            if !(valid(absorption) && valid(scattering) && -1.0 < g && g < 1.0) {
                let message = format!(
                    "medium \"{name}\": sigma_a {absorption}, sigma_s {scattering} must be ≥ 0 and g {g} in (−1, 1)"
                );
                return Err(SceneError::format(file, message));
            }
            Some(Medium {
                absorption,
                scattering,
                anisotropy: g,
            })
        };
        self.media_read.insert(name.to_string(), medium);
        Ok(medium)
    }

    /// A shape's `alpha`: a float (0 cuts the shape out; between 0 and 1, pbrt's stochastic
    /// transparency, is warned about) or a float `imagemap` whose values below ½ cut it out.
    fn cut_out(
        &mut self,
        material: &mut Material,
        alpha: &Param,
        file: &Path,
    ) -> Result<(), SceneError> {
        let fail = |message: String| SceneError::format(file, message);
        match (&alpha.values, alpha.ty.as_str()) {
            (Values::Numbers(v), "float") if v.len() == 1 => {
                if v[0] <= 0.0 {
                    material.alpha = 0.0;
                    material.alpha_mode = AlphaMode::Mask { cutoff: 0.5 };
                } else if v[0] < 1.0 {
                    self.warn(
                        file,
                        format!(
                            "line {}: an alpha of {} is read as opaque",
                            alpha.line, v[0]
                        ),
                    );
                }
                Ok(())
            }
            (Values::Strings(names), "texture") if names.len() == 1 => {
                let mask = self.float_image(&names[0], file)?;
                let base = material
                    .base_color_texture
                    .map(|id| self.builder.texture(id));
                let cut = crate::textures::with_mask(base, self.builder.texture(mask));
                material.base_color_texture = Some(self.builder.add_texture(cut));
                material.alpha_mode = AlphaMode::Mask { cutoff: 0.5 };
                Ok(())
            }
            _ => Err(fail(format!(
                "line {}: \"alpha\" must be a float or a texture",
                alpha.line
            ))),
        }
    }

    /// The image of float texture `name` (an `imagemap`, decoded as data) for a cut-out.
    fn float_image(&mut self, name: &str, file: &Path) -> Result<TextureId, SceneError> {
        let fail = |message: String| SceneError::format(file, message);
        let (_, definition) = self.texture_definition(name, true, file)?;
        let image = (definition.class == "imagemap")
            .then(|| definition.params.string("filename"))
            .transpose()
            .map_err(fail)?
            .flatten()
            .ok_or_else(|| {
                fail(format!(
                    "alpha texture \"{name}\" is not an imagemap with a filename"
                ))
            })?;
        self.image(&image, false, &definition.file)
    }

    /// Material `definition` (named `name`) mapped onto kousen's; `depth` more `mix`es may
    /// nest inside it.
    fn material(
        &mut self,
        definition: &Definition,
        name: &str,
        depth: u32,
    ) -> Result<Mapped, SceneError> {
        let file = definition.file.clone();
        let file = file.as_path();
        let fail = |message: String| SceneError::format(file, message);
        let p = &definition.params;
        p.get("type");
        let named = |surface, base_color| Material {
            name: name.to_string(),
            surface,
            base_color,
            ..Material::default()
        };
        let class = definition.class.as_str();
        let mut uv_map = None;
        let mut textured = |colour: Colour, surface: Surface| {
            uv_map = uv_map.or(colour.uv_map);
            Material {
                base_color_texture: colour.texture,
                ..named(surface, colour.value)
            }
        };
        let material = match class {
            "diffuse" | "matte" => {
                let reflectance = self.colour(p, &["reflectance", "Kd"], Vec3::splat(0.5), file)?;
                if p.float("sigma", 0.0).map_err(fail)? > 0.0 {
                    self.warn(file, "a rough diffuse's sigma is not read: Lambertian");
                }
                textured(reflectance, Surface::Diffuse)
            }
            "coateddiffuse" | "plastic" | "substrate" | "uber" => {
                let default = match class {
                    "coateddiffuse" | "substrate" => 0.5,
                    _ => 0.25,
                };
                let reflectance =
                    self.colour(p, &["reflectance", "Kd"], Vec3::splat(default), file)?;
                let default_roughness = match class {
                    "coateddiffuse" => 0.0,
                    _ => 0.1,
                };
                let roughness = self.roughness(p, "", default_roughness, file)?;
                let (ior, _) = self.index(p, &["eta"], 1.5, file)?;
                for ignored in [
                    "thickness",
                    "g",
                    "maxdepth",
                    "nsamples",
                    "Ks",
                    "Kr",
                    "Kt",
                    "opacity",
                ] {
                    p.get(ignored);
                }
                if p.get("albedo").is_some() {
                    self.warn(file, "a coat's albedo is not read: a clear coat");
                }
                textured(reflectance, coated_surface(ior, roughness))
            }
            "conductor" | "metal" => {
                let default = if class == "metal" { 0.01 } else { 0.0 };
                let roughness = self.roughness(p, "", default, file)?;
                let f0 = self.conductor(p, "", file)?;
                textured(f0, metal_surface(roughness))
            }
            "mirror" => {
                // pbrt-v3's mirror reflects `Kr` at every angle (no Fresnel).
                let reflectance = self.colour(p, &["Kr"], Vec3::splat(0.9), file)?;
                Material {
                    metal_edge: Vec3::ZERO,
                    ..textured(reflectance, Surface::Mirror)
                }
            }
            "coatedconductor" => {
                let f0 = self.conductor(p, "conductor.", file)?;
                let roughness = self.roughness(p, "conductor.", 0.0, file)?;
                let coat = self.roughness(p, "interface.", 0.0, file)?;
                self.index(p, &["interface.eta"], 1.5, file)?;
                for ignored in ["thickness", "g", "maxdepth", "nsamples"] {
                    p.get(ignored);
                }
                if p.get("albedo").is_some() {
                    self.warn(file, "a coat's albedo is not read: a clear coat");
                }
                Material {
                    clearcoat: Clearcoat::new(1.0, coat),
                    ..textured(f0, metal_surface(roughness))
                }
            }
            "dielectric" | "glass" | "thindielectric" => {
                let (ior, abbe) = self.index(p, &["eta", "index"], 1.5, file)?;
                let roughness = match class {
                    "thindielectric" => 0.0,
                    _ => self.roughness(p, "", 0.0, file)?,
                };
                let tint = self.colour(p, &["Kt", "tint"], Vec3::ONE, file)?.value;
                p.get("Kr");
                let thin = class == "thindielectric";
                Material {
                    dispersion: match thin {
                        true => 0.0,
                        false => dispersion_from_abbe(ior, abbe),
                    },
                    ..named(glass_surface(ior, thin, roughness), tint)
                }
            }
            "diffusetransmission" | "translucent" => {
                let (r, t) = match class {
                    "translucent" => {
                        let kd = self.colour(p, &["Kd"], Vec3::splat(0.25), file)?;
                        p.get("Ks");
                        p.get("roughness");
                        let reflect = self.colour(p, &["reflect"], Vec3::splat(0.5), file)?.value;
                        let transmit = self.colour(p, &["transmit"], Vec3::splat(0.5), file)?.value;
                        (kd.scaled(reflect), kd.scaled(transmit))
                    }
                    _ => {
                        let scale = Vec3::splat(p.float("scale", 1.0).map_err(fail)?);
                        let r = self.colour(p, &["reflectance"], Vec3::splat(0.25), file)?;
                        let t = self.colour(p, &["transmittance"], Vec3::splat(0.25), file)?;
                        (r.scaled(scale), t.scaled(scale))
                    }
                };
                if r.texture.is_some() && t.texture.is_some() && r.texture != t.texture {
                    self.warn(
                        file,
                        "a diffuse transmission's two images: the reflectance's is read",
                    );
                }
                uv_map = uv_map.or(r.uv_map).or(t.uv_map);
                Material {
                    base_color_texture: r.texture.or(t.texture),
                    ..diffuse_transmission(name, r.value, t.value)
                }
            }
            "mix" => return self.mix(definition, name, depth),
            // A boundary between media, invisible; filled with a medium, glass of index 1.
            "interface" | "none" | "" => Material {
                alpha: 0.0,
                alpha_mode: AlphaMode::Mask { cutoff: 0.5 },
                ..named(Surface::Diffuse, Vec3::ZERO)
            },
            "disney" => {
                let colour = self.colour(p, &["color"], Vec3::splat(0.5), file)?;
                let metallic = p.float("metallic", 0.0).map_err(fail)?.clamp(0.0, 1.0);
                let transmission = p.float("spectrans", 0.0).map_err(fail)?.clamp(0.0, 1.0);
                let roughness = p.float("roughness", 0.5).map_err(fail)?.clamp(0.0, 1.0);
                let ior = p.float("eta", 1.5).map_err(fail)?;
                let base = textured(colour, Surface::Diffuse);
                let mixture = crate::material::principled_mixture(
                    base,
                    metallic,
                    transmission,
                    roughness,
                    ior,
                );
                self.warn_unused(file, &format!("material \"{name}\""), p);
                return Ok(Mapped::mixed(mixture, uv_map));
            }
            "subsurface" | "kdsubsurface" | "measured" | "hair" | "fourier" => {
                let reflectance =
                    self.colour(p, &["reflectance", "Kd", "color"], Vec3::splat(0.5), file)?;
                self.warn(file, format!("material \"{class}\" is read as diffuse"));
                let material = textured(reflectance, Surface::Diffuse);
                return Ok(Mapped::plain(material, uv_map));
            }
            other => {
                self.warn(
                    file,
                    format!("material \"{other}\" is not read: grey diffuse instead"),
                );
                return Ok(Mapped::plain(diffuse(Vec3::splat(0.5), name), None));
            }
        };
        let mut material = material;
        if let Some(map) = p.string("normalmap").map_err(fail)? {
            material.normal_texture = Some(self.image(&map, false, file)?);
            material.normal_scale = 1.0;
        }
        for unread in ["displacement", "bumpmap"] {
            if p.get(unread).is_some() {
                self.warn(file, format!("a material's {unread} is not read"));
            }
        }
        self.warn_unused(file, &format!("material \"{name}\""), p);
        Ok(Mapped::plain(material, uv_map))
    }

    /// `mix`: pbrt-v4's `materials` (the second drawn with probability `amount`) or pbrt-v3's
    /// `namedmaterial1` (drawn with probability `amount`) and `namedmaterial2`.
    fn mix(
        &mut self,
        definition: &Definition,
        name: &str,
        depth: u32,
    ) -> Result<Mapped, SceneError> {
        let file = definition.file.as_path();
        let fail = |message: String| SceneError::format(file, message);
        let p = &definition.params;
        let amount = self.scalar(p, "amount", 0.5, file)?.clamp(0.0, 1.0);
        let names = match p.strings("materials").map_err(fail)? {
            Some(names) if names.len() == 2 => {
                [(1.0 - amount, names[0].clone()), (amount, names[1].clone())]
            }
            Some(names) => {
                return Err(fail(format!(
                    "mix \"{name}\": {} materials, not 2",
                    names.len()
                )));
            }
            None => {
                let one = p.string("namedmaterial1").map_err(fail)?;
                let two = p.string("namedmaterial2").map_err(fail)?;
                match (one, two) {
                    (Some(one), Some(two)) => [(amount, one), (1.0 - amount, two)],
                    _ => return Err(fail(format!("mix \"{name}\" names no two materials"))),
                }
            }
        };
        let depth = depth.checked_sub(1).ok_or_else(|| {
            fail(format!(
                "mix \"{name}\": materials nested too deep (a cycle?)"
            ))
        })?;
        let mut mixture = Vec::new();
        let mut uv_map = None;
        for (probability, member) in names {
            let definition = (self.named_materials.get(&member).cloned()).ok_or_else(|| {
                fail(format!("mix \"{name}\": no material is named \"{member}\""))
            })?;
            let mapped = self.material(&definition, &member, depth)?;
            uv_map = uv_map.or(mapped.spread_into(probability, &mut mixture));
        }
        Ok(Mapped::mixed(mixture, uv_map))
    }

    /// A conductor's reflectance at normal incidence: its `reflectance`, else from `eta` and
    /// `k` (named metals from kousen's table; colours or sampled spectra by Fresnel's
    /// ((η − 1)² + k²) / ((η + 1)² + k²)); copper, pbrt's default, where none is given.
    fn conductor(&mut self, p: &Params, prefix: &str, file: &Path) -> Result<Colour, SceneError> {
        let fail = |message: String| SceneError::format(file, message);
        if p.get("reflectance").is_some() {
            return self.colour(p, &["reflectance"], Vec3::ONE, file);
        }
        let eta = p.get(&format!("{prefix}eta")).cloned();
        let k = p.get(&format!("{prefix}k")).cloned();
        let copper = spectra::named_metal("metal-Cu-eta").unwrap_or(Vec3::ONE);
        let f0 = match (&eta, &k) {
            (None, None) => copper,
            (Some(eta), Some(k)) => match (&eta.values, &k.values) {
                (Values::Strings(name), _) | (_, Values::Strings(name)) if name.len() == 1 => {
                    let files = [eta, k].map(|p| match &p.values {
                        Values::Strings(s) => spectra::named_metal(&s[0]).is_none(),
                        _ => false,
                    });
                    match spectra::named_metal(&name[0]) {
                        Some(f0) => f0,
                        // Both given as spectrum files (`.spd`): Fresnel at each wavelength.
                        None if files == [true, true] => {
                            let (n, kn) = (self.sampled(eta, file)?, self.sampled(k, file)?);
                            spectra::albedo(|l| conductor_f0(n.at(l), kn.at(l)))
                        }
                        None => {
                            let message =
                                format!("metal \"{}\" is not in kousen's table: copper", name[0]);
                            self.warn(file, message);
                            copper
                        }
                    }
                }
                (Values::Numbers(n), Values::Numbers(kn)) if n.len() == 3 && kn.len() == 3 => {
                    let (n, kn) = (super::vec3(n), super::vec3(kn));
                    let f0 = |i: usize| conductor_f0(n[i] as f64, kn[i] as f64) as f32;
                    Vec3::new(f0(0), f0(1), f0(2)).clamp(Vec3::ZERO, Vec3::ONE)
                }
                (Values::Numbers(n), Values::Numbers(kn)) if n.len() > 3 && kn.len() > 3 => {
                    let (n, kn) = (self.sampled(eta, file)?, self.sampled(k, file)?);
                    spectra::albedo(|l| conductor_f0(n.at(l), kn.at(l)))
                }
                _ => {
                    return Err(fail(format!(
                        "line {}: eta and k must be alike (names, rgb or spectra)",
                        eta.line
                    )));
                }
            },
            (Some(only), None) | (None, Some(only)) => {
                return Err(fail(format!(
                    "line {}: a conductor needs both eta and k",
                    only.line
                )));
            }
        };
        Ok(Colour::constant(f0))
    }

    /// kousen's roughness (glTF's, √α) of pbrt's `{prefix}roughness` (or the mean width of
    /// `uroughness` and `vroughness`), remapped unless `remaproughness` is false.
    fn roughness(
        &mut self,
        p: &Params,
        prefix: &str,
        default: f32,
        file: &Path,
    ) -> Result<f32, SceneError> {
        let fail = |message: String| SceneError::format(file, message);
        let r = self.scalar(p, &format!("{prefix}roughness"), default, file)?;
        let u = self.scalar(p, &format!("{prefix}uroughness"), r, file)?;
        let v = self.scalar(p, &format!("{prefix}vroughness"), r, file)?;
        let remap = p.boolean("remaproughness", true).map_err(fail)?;
        let alpha = |r: f32| match remap {
            true => r.max(0.0).sqrt(),
            false => r.max(0.0),
        };
        let (au, av) = (alpha(u), alpha(v));
        if (au - av).abs() > 1e-3 * au.max(av) {
            self.warn(file, "anisotropic roughness is read as its mean width");
        }
        let alpha = (au + av) / 2.0;
        Ok(if alpha < SMOOTH_ALPHA {
            0.0
        } else {
            alpha.sqrt().min(1.0)
        })
    }

    /// An index of refraction (the first of `names` given): a number, a named glass, or an
    /// index spectrum; with its Abbe number (infinite: no dispersion).
    fn index(
        &mut self,
        p: &Params,
        names: &[&str],
        default: f32,
        file: &Path,
    ) -> Result<(f32, f32), SceneError> {
        let fail = |message: String| SceneError::format(file, message);
        let Some(param) = names.iter().find_map(|n| p.get(n)) else {
            return Ok((default, f32::INFINITY));
        };
        let (ior, abbe) = match (&param.values, param.ty.as_str()) {
            (Values::Numbers(v), "float") if v.len() == 1 => (v[0] as f32, f32::INFINITY),
            (Values::Strings(s), "spectrum") if s.len() == 1 => match spectra::named_glass(&s[0]) {
                Some(glass) => glass,
                None => {
                    let index = self.sampled(param, file)?;
                    spectra::index_and_abbe(|l| index.at(l))
                }
            },
            (Values::Numbers(_), "spectrum") => {
                let index = self.sampled(param, file)?;
                spectra::index_and_abbe(|l| index.at(l))
            }
            _ => {
                return Err(fail(format!(
                    "line {}: an index must be a float or a spectrum",
                    param.line
                )));
            }
        };
        match ior > 0.0 && ior.is_finite() {
            true => Ok((ior, abbe)),
            false => Err(fail(format!(
                "line {}: index {ior} is not positive",
                param.line
            ))),
        }
    }

    /// A float parameter that may be a texture (read as its mean, with a warning).
    fn scalar(
        &mut self,
        p: &Params,
        name: &str,
        default: f32,
        file: &Path,
    ) -> Result<f32, SceneError> {
        let fail = |message: String| SceneError::format(file, message);
        match p.get(name).map(|param| (param.ty.as_str(), &param.values)) {
            Some(("texture", Values::Strings(names))) if names.len() == 1 => {
                let colour = self.texture(&names[0], true, file, MAX_NESTING)?;
                if colour.texture.is_some() {
                    self.warn(file, format!("\"{name}\"'s texture is read as its mean"));
                }
                Ok(self.mean(colour).x)
            }
            Some(_) => p.float(name, default).map_err(fail),
            None => Ok(default),
        }
    }

    /// A colour parameter (the first of `names` given): `rgb`, `spectrum`, `float`, or a
    /// `texture`.
    fn colour(
        &mut self,
        p: &Params,
        names: &[&str],
        default: Vec3,
        file: &Path,
    ) -> Result<Colour, SceneError> {
        let fail = |message: String| SceneError::format(file, message);
        let Some(param) = names.iter().find_map(|n| p.get(n)).cloned() else {
            return Ok(Colour::constant(default));
        };
        let line = param.line;
        let value = match (param.ty.as_str(), &param.values) {
            ("texture", Values::Strings(names)) if names.len() == 1 => {
                return self.texture(&names[0], false, file, MAX_NESTING);
            }
            ("rgb" | "color", Values::Numbers(v)) if v.len() == 3 => super::vec3(v),
            ("float", Values::Numbers(v)) if v.len() == 1 => Vec3::splat(v[0] as f32),
            ("spectrum", _) => {
                let s = self.sampled(&param, file)?;
                spectra::albedo(|l| s.at(l))
            }
            (ty, _) => {
                return Err(fail(format!(
                    "line {line}: \"{ty} {}\" is not a colour kousen reads",
                    param.name
                )));
            }
        };
        if !value.is_finite() || value.min_element() < 0.0 {
            return Err(fail(format!(
                "line {line}: colour {value} is not finite and ≥ 0"
            )));
        }
        Ok(Colour::constant(value))
    }

    /// A light's colour parameter `name`: `rgb` as it is, a `blackbody` or spectrum scaled to
    /// a luminance of 1 (pbrt-v3's two-number black body by its peak, times its scale);
    /// white where absent.
    pub(super) fn emission(
        &mut self,
        p: &Params,
        name: &str,
        file: &Path,
    ) -> Result<Vec3, SceneError> {
        let fail = |message: String| SceneError::format(file, message);
        let Some(param) = p.get(name).cloned() else {
            return Ok(Vec3::ONE);
        };
        let line = param.line;
        let value = match (param.ty.as_str(), &param.values) {
            ("rgb" | "color", Values::Numbers(v)) if v.len() == 3 => super::vec3(v),
            ("float", Values::Numbers(v)) if v.len() == 1 => Vec3::splat(v[0] as f32),
            ("blackbody", Values::Numbers(v)) if v.len() == 1 && v[0] > 0.0 => {
                spectra::blackbody(v[0])
            }
            ("blackbody", Values::Numbers(v)) if v.len() == 2 && v[0] > 0.0 => {
                spectra::blackbody_v3(v[0]) * v[1] as f32
            }
            ("spectrum", Values::Numbers(_)) => {
                let s = self.sampled(&param, file)?;
                spectra::unit_luminance(|l| s.at(l))
            }
            ("spectrum", Values::Strings(s)) if s.len() == 1 => match s[0].as_str() {
                "stdillum-D65" | "stdillum-E" => Vec3::ONE,
                "stdillum-A" => spectra::blackbody(2856.0),
                named if named.starts_with("stdillum-") || named.starts_with("illum-") => {
                    self.warn(
                        file,
                        format!("line {line}: illuminant \"{named}\" is read as white"),
                    );
                    Vec3::ONE
                }
                _ => {
                    let s = self.sampled(&param, file)?;
                    spectra::unit_luminance(|l| s.at(l))
                }
            },
            (ty, _) => {
                return Err(fail(format!(
                    "line {line}: \"{ty} {name}\" is not a light's colour"
                )));
            }
        };
        if !value.is_finite() || value.min_element() < 0.0 {
            return Err(fail(format!(
                "line {line}: colour {value} is not finite and ≥ 0"
            )));
        }
        Ok(value)
    }

    /// The spectrum of a `spectrum` parameter: wavelength–value pairs given inline, or in the
    /// file it names.
    fn sampled(&mut self, param: &Param, file: &Path) -> Result<spectra::Piecewise, SceneError> {
        let pairs = match &param.values {
            Values::Numbers(v) => v.clone(),
            Values::Strings(s) if s.len() == 1 => self.spectrum_file(&s[0], param.line, file)?,
            _ => Vec::new(),
        };
        spectra::Piecewise::new(pairs).ok_or_else(|| {
            let message = format!(
                "line {}: \"{}\" is not a spectrum of ascending wavelength–value pairs",
                param.line, param.name
            );
            SceneError::format(file, message)
        })
    }

    /// The wavelength–value pairs of a spectrum file (`.spd`: numbers, `#` comments).
    fn spectrum_file(
        &mut self,
        name: &str,
        line: u32,
        file: &Path,
    ) -> Result<Vec<f64>, SceneError> {
        let fail = |message: String| SceneError::format(file, message);
        let path = self.resolve(name);
        if !path.is_file() {
            return Err(fail(format!(
                "line {line}: \"{name}\" is neither a spectrum kousen knows nor a file"
            )));
        }
        let (bytes, _) = crate::files::read_regular_file(&path, 16 << 20)
            .map_err(|e| SceneError::io(&path, e))?;
        let text = String::from_utf8_lossy(&bytes);
        let numbers = text
            .lines()
            .map(|l| l.split('#').next().unwrap_or(""))
            .flat_map(str::split_whitespace)
            .map(|w| {
                w.parse::<f64>()
                    .map_err(|_| SceneError::format(&path, format!("\"{w}\" is not a number")))
            });
        numbers.collect()
    }

    /// The definition of texture `name`, a float one if `float` (else a spectrum one) or,
    /// where there is none of that kind, the other; with its key.
    fn texture_definition(
        &self,
        name: &str,
        float: bool,
        file: &Path,
    ) -> Result<((bool, String), Definition), SceneError> {
        [float, !float]
            .into_iter()
            .map(|kind| (kind, name.to_string()))
            .find_map(|key| self.textures.get(&key).map(|d| (key, d.clone())))
            .ok_or_else(|| SceneError::format(file, format!("no texture is named \"{name}\"")))
    }

    /// Named texture `name` (a float one if `float`, see [`Reader::texture_definition`]) as a
    /// colour; `depth` more textures may nest inside it.
    fn texture(
        &mut self,
        name: &str,
        float: bool,
        file: &Path,
        depth: u32,
    ) -> Result<Colour, SceneError> {
        let fail = |message: String| SceneError::format(file, message);
        let (key, definition) = self.texture_definition(name, float, file)?;
        if let Some(colour) = self.texture_colours.get(&key) {
            return Ok(*colour);
        }
        let depth = depth.checked_sub(1).ok_or_else(|| {
            fail(format!(
                "texture \"{name}\": textures nested too deep (a cycle?)"
            ))
        })?;
        let file = definition.file.as_path();
        let fail = |message: String| SceneError::format(file, message);
        let p = &definition.params;
        let float = key.0;
        let colour = match definition.class.as_str() {
            "imagemap" => {
                let image = (p.string("filename").map_err(fail)?)
                    .ok_or_else(|| fail(format!("imagemap \"{name}\" needs a filename")))?;
                let encoding = p.string("encoding").map_err(fail)?;
                let png = image.to_ascii_lowercase().ends_with(".png");
                let srgb = match encoding.as_deref() {
                    Some("sRGB") => true,
                    Some("linear") => false,
                    Some(other) => {
                        self.warn(file, format!("encoding \"{other}\" is read as sRGB"));
                        true
                    }
                    // v3's gamma flag, else pbrt-v4's default: sRGB for PNG, linear otherwise.
                    None => p.boolean("gamma", png).map_err(fail)?,
                };
                let scale = p.float("scale", 1.0).map_err(fail)?;
                if p.boolean("invert", false).map_err(fail)? {
                    self.warn(file, format!("imagemap \"{name}\": invert is not read"));
                }
                let mapping = p
                    .string("mapping")
                    .map_err(fail)?
                    .unwrap_or_else(|| "uv".into());
                if mapping != "uv" {
                    self.warn(
                        file,
                        format!("imagemap \"{name}\": {mapping} mapping is read as uv"),
                    );
                }
                for ignored in ["filter", "wrap", "maxanisotropy", "trilinear"] {
                    p.get(ignored);
                }
                let map = UvMap {
                    scale: Vec2::new(
                        p.float("uscale", 1.0).map_err(fail)?,
                        p.float("vscale", 1.0).map_err(fail)?,
                    ),
                    offset: Vec2::new(
                        p.float("udelta", 0.0).map_err(fail)?,
                        p.float("vdelta", 0.0).map_err(fail)?,
                    ),
                };
                let texture = self.image(&image, srgb && !float, file)?;
                Colour {
                    value: Vec3::splat(scale),
                    texture: Some(texture),
                    uv_map: (map.scale != Vec2::ONE || map.offset != Vec2::ZERO).then_some(map),
                }
            }
            "constant" => self.texture_value(p, "value", float, file, depth)?,
            "scale" => {
                let a = self.texture_value(p, "tex", float, file, depth)?;
                let b = self.texture_value(p, "scale", true, file, depth)?;
                if a.texture.is_some() && b.texture.is_some() {
                    self.warn(
                        file,
                        format!("texture \"{name}\": a scale of two images keeps the first's"),
                    );
                }
                Colour {
                    value: a.value * b.value,
                    texture: a.texture.or(b.texture),
                    uv_map: a.uv_map.or(b.uv_map),
                }
            }
            "checkerboard" | "mix" => {
                // pbrt's defaults: a checkerboard's 1 and 0, a mix's 0 and 1.
                let mix = definition.class == "mix";
                let mut ends = [("tex1", !mix), ("tex2", mix)].map(|(name, one)| {
                    let default = Colour::constant(Vec3::splat(one as u8 as f32));
                    (name, default)
                });
                for (name, value) in &mut ends {
                    if p.get(name).is_some() {
                        *value = self.texture_value(p, name, float, file, depth)?;
                    }
                }
                let [(_, one), (_, two)] = ends;
                let amount = match definition.class.as_str() {
                    "mix" if p.get("amount").is_some() => {
                        self.texture_value(p, "amount", true, file, depth)?
                    }
                    _ => Colour::constant(Vec3::splat(0.5)),
                };
                for ignored in [
                    "uscale",
                    "vscale",
                    "udelta",
                    "vdelta",
                    "mapping",
                    "dimension",
                ] {
                    p.get(ignored);
                }
                self.warn(
                    file,
                    format!(
                        "texture \"{name}\" ({}) is read as its mean",
                        definition.class
                    ),
                );
                let (one, two, amount) = (self.mean(one), self.mean(two), self.mean(amount));
                Colour::constant(one.lerp(two, amount.x))
            }
            other => {
                self.warn(
                    file,
                    format!("texture \"{other}\" is not read: grey instead"),
                );
                Colour::constant(Vec3::splat(0.5))
            }
        };
        self.warn_unused(file, &format!("texture \"{name}\""), p);
        self.texture_colours.insert(key, colour);
        Ok(colour)
    }

    /// A texture's parameter that is a value or another texture (a float one if `float`);
    /// 1 where absent (pbrt's default for `tex`, `tex1`, `scale` and `value`).
    fn texture_value(
        &mut self,
        p: &Params,
        name: &str,
        float: bool,
        file: &Path,
        depth: u32,
    ) -> Result<Colour, SceneError> {
        match p.get(name) {
            Some(param) if param.ty == "texture" => {
                let Values::Strings(names) = &param.values else {
                    unreachable!("texture parameters are strings")
                };
                self.texture(&names[0], float, file, depth)
            }
            _ => self.colour(p, &[name], Vec3::ONE, file),
        }
    }

    /// A colour's mean: its texture's mean times its value.
    fn mean(&self, colour: Colour) -> Vec3 {
        match colour.texture {
            Some(t) => self.builder.texture(t).mean_linear().truncate() * colour.value,
            None => colour.value,
        }
    }

    /// The texture of image file `name` (relative to the main file), decoded once as sRGB
    /// colour or linear data.
    fn image(&mut self, name: &str, srgb: bool, file: &Path) -> Result<TextureId, SceneError> {
        let path = self.resolve(name);
        if let Some(id) = self.images.get(&(path.clone(), srgb)) {
            return Ok(*id);
        }
        let texture =
            crate::Texture::read_file(&path, name, srgb, |e| SceneError::format(file, e))?;
        let id = self.builder.add_texture(texture);
        self.images.insert((path, srgb), id);
        Ok(id)
    }
}

/// A conductor's reflectance at normal incidence: ((η − 1)² + k²) / ((η + 1)² + k²).
fn conductor_f0(eta: f64, k: f64) -> f64 {
    ((eta - 1.0) * (eta - 1.0) + k * k) / ((eta + 1.0) * (eta + 1.0) + k * k)
}

fn diffuse(colour: Vec3, name: &str) -> Material {
    Material {
        name: name.to_string(),
        surface: Surface::Diffuse,
        base_color: colour,
        ..Material::default()
    }
}

/// Lambertian reflection `r` and transmission `t`: a diffuse surface of albedo r + t passing
/// the transmitted share on (glTF's diffuse transmission).
fn diffuse_transmission(name: &str, r: Vec3, t: Vec3) -> Material {
    let albedo = (r + t).min(Vec3::ONE);
    let total = albedo.element_sum();
    let factor = if total > 0.0 {
        t.element_sum() / (r + t).element_sum()
    } else {
        0.0
    };
    let colour = (t / (albedo * factor).max(Vec3::splat(1e-6))).min(Vec3::ONE);
    Material {
        diffuse_transmission: DiffuseTransmission::new(factor, colour),
        ..diffuse(albedo, name)
    }
}
