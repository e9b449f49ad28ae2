//! The uber-material every loader maps onto (DESIGN.md, "Materials").

use glam::Vec3;

use crate::{Texture, TextureId};

/// How light leaves the surface.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Surface {
    /// Lambertian, albedo `base_color` (× texture).
    Diffuse,
    /// Perfect specular reflection of a metal of colour `base_color` (its reflectance at
    /// normal incidence; Fresnel's rise towards grazing by [`Material::metal_edge`]).
    Mirror,
    /// Smooth glass with Fresnel reflection and refraction. `thin_walled`: a sheet with no
    /// interior (light passes straight through, glTF transmission without a volume); otherwise
    /// a solid whose inside has index `ior`.
    Dielectric { ior: f32, thin_walled: bool },
    /// Rough metal: GGX microfacets of width `alpha` (glTF's roughness squared), each
    /// reflecting as the mirror does (`render::microfacet`, `render::conductor`).
    RoughConductor { alpha: f32 },
    /// Rough glass (frosted): GGX microfacets of width `alpha` (glTF's roughness squared) on
    /// the [`Surface::Dielectric`] of `ior` and `thin_walled` (`render::microfacet`).
    RoughDielectric {
        ior: f32,
        thin_walled: bool,
        alpha: f32,
    },
    /// Plastic: a Lambertian base of albedo `base_color` (× texture) under a clear coat of
    /// index `ior`, smooth where `alpha` is 0, else GGX of width `alpha` (`render::plastic`).
    Plastic { ior: f32, alpha: f32 },
}

/// Whether a surface can be seen through where its texture says so.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum AlphaMode {
    Opaque,
    /// Alpha cut-out: where `alpha × texture alpha < cutoff`, rays pass through.
    Mask {
        cutoff: f32,
    },
}

#[derive(Clone, Debug, PartialEq)]
pub struct Material {
    pub name: String,
    pub surface: Surface,
    /// Linear RGB reflectance (or transmittance tint for a dielectric).
    pub base_color: Vec3,
    /// Multiplies `base_color`; its alpha channel multiplies `alpha`.
    pub base_color_texture: Option<TextureId>,
    /// Emitted radiance (linear RGB): glTF's emissiveFactor × emissive strength, OBJ's Ke.
    pub emission: Vec3,
    /// Multiplies `emission`.
    pub emission_texture: Option<TextureId>,
    /// Constant opacity factor (glTF baseColorFactor.a, OBJ d).
    pub alpha: f32,
    pub alpha_mode: AlphaMode,
    /// Emits from both faces when true; from the front face only otherwise. (Rays hit both
    /// faces of every triangle whatever this says.)
    pub double_sided: bool,
    /// Beer–Lambert absorption inside a solid (a solid dielectric or a translucent solid:
    /// [`Material::bounds_volume`]), per unit of length and colour channel
    /// ([`absorption_from_attenuation`]): a path that crosses the solid over a length `d` keeps
    /// `exp(−absorption·d)` of its light. Zero: clear. Volumes are closed; the path knows the
    /// solid it is in (`render::medium`), and solids nest (`render::nesting`).
    pub absorption: Vec3,
    /// Scattering inside a translucent solid (a diffusely transmitting surface bounding a
    /// volume, [`DiffuseTransmission::volume`]) or a solid of glass (murky water, smoky
    /// glass), per unit of length and colour channel: light inside is turned aside at this
    /// rate, by the Henyey–Greenstein phase function of asymmetry `scatter_anisotropy` (0
    /// isotropic, towards 1 forward), and absorbed at `absorption`'s (`render::scattering`).
    /// Zero: none. Only those solids scatter ([`Material::interior_scattering`]).
    pub scattering: Vec3,
    pub scatter_anisotropy: f32,
    /// A tangent-space normal map (glTF's `normalTexture`, linear RGB: +X along increasing u,
    /// +Y towards the image's top, +Z out of the surface), bending the shading normal.
    pub normal_texture: Option<TextureId>,
    /// Scales the normal map's X and Y before renormalising (glTF's `normalTexture.scale`).
    pub normal_scale: f32,
    /// Where the material is a mixture of surfaces ([`Blend`]); `None` for one surface.
    pub blend: Option<Blend>,
    /// A solid dielectric's dispersion (smooth or frosted): its index at wavelength λ (nm) is
    /// `ior + dispersion · (523655 / λ² − 1.5168)`, the Cauchy form glTF's
    /// `KHR_materials_dispersion` gives, whose `dispersion` is 20 / V for Abbe number V, so this
    /// is (ior − 1) / V ([`dispersion_from_abbe`]). Zero: none.
    pub dispersion: f32,
    /// glTF's `metallicRoughnessTexture` on this member of the material: its surface follows
    /// the texture's roughness at each hit, and a metal root's blend weight its metalness.
    pub roughness_map: Option<RoughnessMap>,
    /// A clear coat over the whole material (glTF's `KHR_materials_clearcoat`; every member
    /// of a blend carries it, the kernels read the root's); `None` for none.
    pub clearcoat: Option<Clearcoat>,
    /// A sheen over the material beneath the clear coat (glTF's `KHR_materials_sheen`: velvet,
    /// cloth); `None` for none.
    pub sheen: Option<Sheen>,
    /// glTF's `transmissionTexture` (linear data): its red channel multiplies the weight of a
    /// blend's glass member (a dielectric surface) at each hit, the opaque member after it
    /// taking the rest (`render::blend::blend_member`). Every member of the blend carries it.
    pub transmission_texture: Option<TextureId>,
    /// Lambertian transmission through the material's diffuse lobe (glTF's
    /// `KHR_materials_diffuse_transmission`: leaves, paper, a lamp shade); `None` for none.
    pub diffuse_transmission: Option<DiffuseTransmission>,
    /// Brushing of the metal's GGX lobe (glTF's `KHR_materials_anisotropy`); `None` for an
    /// isotropic lobe. Every member of a blend carries it; only rough metal reads it.
    pub anisotropy: Option<Anisotropy>,
    /// A thin film on the surface (glTF's `KHR_materials_iridescence`: anodised or
    /// heat-tinted metal, a soap bubble); `None` for none. Every member of a blend carries it;
    /// metal (mirror or rough), glass (smooth or frosted) and plastic's coat read it,
    /// Lambertian surfaces not.
    pub iridescence: Option<Iridescence>,
    /// glTF's specular layer on the dielectric (`KHR_materials_specular`), which plastic's coat
    /// and glass (smooth or frosted) read; `None` where it changes nothing (no extension, or
    /// its defaults).
    pub specular: Option<SpecularLayer>,
    /// How far a metal's reflectance rises from its colour F0 towards white at grazing angles,
    /// per channel, along Schlick's curve (`render::conductor`): 1, glTF's conductor Fresnel
    /// (the default); 0, the colour at every angle (Mitsuba's `"none"` conductor). Only metal
    /// (mirror or rough) reads it.
    pub metal_edge: Vec3,
}

/// glTF's specular layer (`KHR_materials_specular`) on a dielectric of index n: at a hit its
/// reflectance is `min(F0(n) · colour, 1) · strength` at normal incidence in each channel and
/// `strength` at grazing, the colour and strength being the factors times the textures read
/// there ([`SpecularLayer::at`]); in between it follows the shape of the dielectric's own
/// Fresnel reflectance (`render::dielectric_layer`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SpecularLayer {
    /// The dielectric's F0 from its index times `specularColorFactor`, per channel.
    pub tinted_f0: Vec3,
    /// `specularFactor`.
    pub factor: f32,
    /// `specularTexture` (linear data): its alpha channel multiplies `factor`.
    pub texture: Option<TextureId>,
    /// `specularColorTexture` (sRGB): multiplies the colour.
    pub color_texture: Option<TextureId>,
}

impl SpecularLayer {
    /// glTF's layer of `specularColorFactor` `colour` and `specularFactor` `factor` on a
    /// dielectric of index `ior` (> 1), without textures.
    pub fn new(ior: f32, colour: Vec3, factor: f32) -> SpecularLayer {
        let r = (ior - 1.0) / (ior + 1.0);
        SpecularLayer {
            tinted_f0: r * r * colour,
            factor,
            texture: None,
            color_texture: None,
        }
    }

    /// The layer's reflectance at normal incidence (each channel) and at grazing (glTF's
    /// `dielectric_f0` and `dielectric_f90`) where the strength texture reads `texel` and the
    /// colour texture `color_texel` (`None`: no texture).
    pub fn at(&self, texel: Option<glam::Vec4>, color_texel: Option<glam::Vec4>) -> (Vec3, f32) {
        let colour = color_texel.map_or(Vec3::ONE, |t| t.truncate());
        let strength = self.factor * texel.map_or(1.0, |t| t.w);
        (
            (self.tinted_f0 * colour).min(Vec3::ONE) * strength,
            strength,
        )
    }
}

/// glTF's iridescence: a thin film of index `ior` and a thickness in nanometres on the surface,
/// whose reflections interfere (`render::iridescence`). The surface's reflectance becomes a mix
/// of its own and the film's by the factor.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Iridescence {
    /// glTF's `iridescenceFactor`, in (0, 1].
    pub factor: f32,
    /// glTF's `iridescenceTexture` (linear data): its red channel multiplies `factor`.
    pub texture: Option<TextureId>,
    /// glTF's `iridescenceIor`, the film's index (default 1.3).
    pub ior: f32,
    /// glTF's `iridescenceThicknessMinimum` in nm (default 100).
    pub thickness_min: f32,
    /// glTF's `iridescenceThicknessMaximum` in nm (default 400): the thickness where there is
    /// no thickness texture.
    pub thickness_max: f32,
    /// glTF's `iridescenceThicknessTexture` (linear data): its green channel places the
    /// thickness between the minimum (0) and the maximum (1).
    pub thickness_texture: Option<TextureId>,
}

impl Iridescence {
    /// The film's factor and thickness (nm) where the factor texture reads `factor_texel`
    /// and the thickness texture `thickness_texel` (`None`: no texture).
    pub fn at(
        &self,
        factor_texel: Option<glam::Vec4>,
        thickness_texel: Option<glam::Vec4>,
    ) -> (f32, f32) {
        let factor = self.factor * factor_texel.map_or(1.0, |t| t.x);
        let thickness = match thickness_texel {
            Some(t) => self.thickness_min + (self.thickness_max - self.thickness_min) * t.y,
            None => self.thickness_max,
        };
        (factor, thickness)
    }
}

/// glTF's anisotropy of a metal's lobe (brushed metal): along a direction in the surface the
/// GGX width grows from α to `α + (1 − α)·s²`, across it stays α
/// (`render::microfacet::brushed_widths`). The direction is the texture frame's +u turned by
/// `rotation` (counter-clockwise towards +v), or the texture's own direction turned so.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Anisotropy {
    /// glTF's `anisotropyStrength`, in [0, 1].
    pub strength: f32,
    /// glTF's `anisotropyRotation`, radians.
    pub rotation: f32,
    /// glTF's `anisotropyTexture` (linear data): red and green the direction in the texture
    /// frame (each mapped from [0, 1] to [−1, 1]), blue multiplying the strength.
    pub texture: Option<TextureId>,
}

impl Anisotropy {
    /// The brushing without a texture, in the texture frame (+u, +v): +u turned by the
    /// rotation, times the strength (what the GPU's material record holds).
    pub fn base(&self) -> glam::Vec2 {
        let (sin, cos) = self.rotation.sin_cos();
        glam::Vec2::new(cos, sin) * self.strength
    }

    /// The brushing in the texture frame where the texture reads `texel` (`None`: no
    /// texture): its direction turned by the rotation, times the strength and its blue.
    pub fn at(&self, texel: Option<glam::Vec4>) -> glam::Vec2 {
        let base = self.base();
        let Some(texel) = texel else {
            return base;
        };
        let d = (glam::Vec2::new(texel.x, texel.y) * 2.0 - glam::Vec2::ONE)
            .try_normalize()
            .unwrap_or(glam::Vec2::X);
        glam::Vec2::new(d.x * base.x - d.y * base.y, d.x * base.y + d.y * base.x) * texel.z
    }
}

/// glTF's diffuse transmission: of what reaches the Lambertian lobe (a diffuse surface, or
/// plastic's base under its coat), the share `factor` leaves from the other side of the
/// surface, cosine-distributed and tinted by `color`, and the rest is reflected with the base
/// colour as before. What passes it is on the other side at once; where `volume` says so, that
/// side is the inside of a translucent solid, whose absorption ([`Material::absorption`]) acts
/// on light until it passes the surface again (`render::medium`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DiffuseTransmission {
    /// glTF's `diffuseTransmissionFactor`, in (0, 1].
    pub factor: f32,
    /// glTF's `diffuseTransmissionColorFactor` (linear RGB, each channel in [0, 1]).
    pub color: Vec3,
    /// glTF's `diffuseTransmissionTexture` (linear data): its alpha channel multiplies
    /// `factor`.
    pub texture: Option<TextureId>,
    /// glTF's `diffuseTransmissionColorTexture` (sRGB): multiplies `color`.
    pub color_texture: Option<TextureId>,
    /// The surface bounds a volume (glTF's `KHR_materials_volume` with a thickness above 0):
    /// a closed translucent solid, wax or jade, rather than a sheet of paper.
    pub volume: bool,
}

impl DiffuseTransmission {
    /// The transmission of glTF's `diffuseTransmissionFactor` `factor` and colour `color`;
    /// `None` where the factor is 0.
    pub fn new(factor: f32, color: Vec3) -> Option<DiffuseTransmission> {
        (factor > 0.0).then_some(DiffuseTransmission {
            factor,
            color,
            texture: None,
            color_texture: None,
            volume: false,
        })
    }
}

/// glTF's sheen (`KHR_materials_sheen`): a retro-reflective fibre layer of the Charlie
/// distribution over the material, reflecting its colour most at grazing angles and dimming
/// what lies beneath by the share it reflects (`render::sheen`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sheen {
    /// glTF's `sheenColorFactor` (linear RGB, each channel in [0, 1]; not all zero).
    pub color: Vec3,
    /// glTF's `sheenRoughnessFactor`, raised to [`Sheen::MIN_ROUGHNESS`].
    pub roughness: f32,
    /// glTF's `sheenColorTexture` (sRGB): multiplies `color`.
    pub color_texture: Option<TextureId>,
    /// glTF's `sheenRoughnessTexture` (linear data): its alpha channel multiplies `roughness`
    /// (the product raised to [`Sheen::MIN_ROUGHNESS`] again).
    pub roughness_texture: Option<TextureId>,
}

impl Sheen {
    /// The least roughness kept: the Charlie distribution's peak grows as 1 / roughness², and
    /// below this the lobe's weights (and its albedo table) would be dominated by a sliver of
    /// grazing directions.
    pub const MIN_ROUGHNESS: f32 = 0.07;

    /// The sheen of glTF's `sheenColorFactor` and `sheenRoughnessFactor`; `None` where the
    /// colour is black (glTF's default: no sheen).
    pub fn new(color: Vec3, roughness: f32) -> Option<Sheen> {
        (color.max_element() > 0.0).then_some(Sheen {
            color,
            roughness: roughness.clamp(Sheen::MIN_ROUGHNESS, 1.0),
            color_texture: None,
            roughness_texture: None,
        })
    }
}

/// A thin clear layer of index [`Clearcoat::IOR`] over a material, reflecting `weight` times
/// its Fresnel reflectance and letting the rest through to the surface beneath
/// (`render::clearcoat`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Clearcoat {
    /// glTF's `clearcoatFactor`, in (0, 1].
    pub weight: f32,
    /// GGX width: glTF's `clearcoatRoughnessFactor` squared; 0 (smooth) below
    /// [`MIRROR_MAX_ROUGHNESS`].
    pub alpha: f32,
    /// glTF's `clearcoatTexture` (linear data): its red channel multiplies `weight`.
    pub weight_texture: Option<TextureId>,
    /// glTF's `clearcoatRoughnessTexture` (linear data): its green channel multiplies the
    /// roughness.
    pub roughness_texture: Option<TextureId>,
    /// glTF's `clearcoatNormalTexture`: a tangent-space normal map (as
    /// [`Material::normal_texture`]) bending the coat's own normal, which otherwise follows the
    /// interpolated normal, not the material's map beneath.
    pub normal_texture: Option<TextureId>,
    /// Its `scale`.
    pub normal_scale: f32,
}

impl Clearcoat {
    /// glTF's clear coat's index (the extension fixes it).
    pub const IOR: f32 = 1.5;

    /// The coat of glTF's `clearcoatFactor` `weight` and `clearcoatRoughnessFactor`
    /// `roughness`; `None` where the weight is 0.
    pub fn new(weight: f32, roughness: f32) -> Option<Clearcoat> {
        (weight > 0.0).then_some(Clearcoat {
            weight,
            alpha: coat_alpha(roughness),
            weight_texture: None,
            roughness_texture: None,
            normal_texture: None,
            normal_scale: 1.0,
        })
    }

    /// The coat where its textures read `weight_texel` (red of `weight_texture`) and
    /// `roughness_texel` (green of `roughness_texture`; 1 where there is none): weight and
    /// roughness multiplied by them (clamped to [0, 1]), so α by the roughness texel squared,
    /// smooth below [`MIRROR_MAX_ROUGHNESS`]; at texels of 1, the coat's own factors.
    pub fn at(&self, weight_texel: f32, roughness_texel: f32) -> Clearcoat {
        let roughness_scale = roughness_texel.clamp(0.0, 1.0);
        let alpha = self.alpha * (roughness_scale * roughness_scale);
        Clearcoat {
            weight: self.weight * weight_texel.clamp(0.0, 1.0),
            alpha: if alpha < MIRROR_MAX_ROUGHNESS * MIRROR_MAX_ROUGHNESS {
                0.0
            } else {
                alpha
            },
            weight_texture: None,
            roughness_texture: None,
            normal_texture: self.normal_texture,
            normal_scale: self.normal_scale,
        }
    }
}

/// GGX width of glTF's `roughness`: its square, 0 (smooth) below [`MIRROR_MAX_ROUGHNESS`].
fn coat_alpha(roughness: f32) -> f32 {
    if roughness < MIRROR_MAX_ROUGHNESS {
        0.0
    } else {
        roughness * roughness
    }
}

/// Metal smoother than this (glTF roughness) is a mirror, glass smoother than this smooth.
pub const MIRROR_MAX_ROUGHNESS: f32 = 0.01;
/// Metal, and a dielectric's specular coat, at least this rough is Lambertian: so broad a lobe
/// sends light out nearly as a diffuse surface does, and SPPM gathers at diffuse points where
/// it would otherwise trace eye paths on through it.
pub const DIFFUSE_MIN_ROUGHNESS: f32 = 0.5;

/// glTF's metal of roughness `roughness`: a mirror, a rough conductor of GGX width
/// roughness², or Lambertian ([`MIRROR_MAX_ROUGHNESS`], [`DIFFUSE_MIN_ROUGHNESS`]).
pub fn metal_surface(roughness: f32) -> Surface {
    if roughness < MIRROR_MAX_ROUGHNESS {
        Surface::Mirror
    } else if roughness < DIFFUSE_MIN_ROUGHNESS {
        Surface::RoughConductor {
            alpha: roughness * roughness,
        }
    } else {
        Surface::Diffuse
    }
}

/// The least GGX width across a brushed metal's brushing: glTF's smooth metal brushed (its
/// roughness 0) stays a lobe the kernels can sample.
pub const MIN_BRUSHED_ALPHA: f32 = 1e-3;

/// [`metal_surface`] for a metal brushed with some strength (`Anisotropy`): a mirror becomes
/// rough metal of width [`MIN_BRUSHED_ALPHA`], which the brushing widens along its direction.
pub fn brushed_metal_surface(roughness: f32) -> Surface {
    match metal_surface(roughness) {
        Surface::Mirror => Surface::RoughConductor {
            alpha: (roughness * roughness).max(MIN_BRUSHED_ALPHA),
        },
        other => other,
    }
}

/// glTF's glass of index `ior` at `roughness`: smooth below [`MIRROR_MAX_ROUGHNESS`], frosted
/// (GGX α = roughness²) from there.
pub fn glass_surface(ior: f32, thin_walled: bool, roughness: f32) -> Surface {
    if roughness < MIRROR_MAX_ROUGHNESS {
        Surface::Dielectric { ior, thin_walled }
    } else {
        Surface::RoughDielectric {
            ior,
            thin_walled,
            alpha: roughness * roughness,
        }
    }
}

/// glTF's opaque dielectric of index `ior` under its specular coat at `roughness`: plastic,
/// smooth below [`MIRROR_MAX_ROUGHNESS`] and GGX-rough (α = roughness²) from there, and
/// Lambertian from [`DIFFUSE_MIN_ROUGHNESS`].
pub fn coated_surface(ior: f32, roughness: f32) -> Surface {
    if roughness >= DIFFUSE_MIN_ROUGHNESS {
        Surface::Diffuse
    } else {
        Surface::Plastic {
            ior,
            alpha: coat_alpha(roughness),
        }
    }
}

/// Reflectance at normal incidence (linear sRGB) of the metals the Mitsuba and pbrt loaders
/// know by name, lower case: Hoffman's table ("Physics and Math of Shading", SIGGRAPH 2015
/// course) for silver, aluminium, gold, chromium, copper, brass (CuZn) and nickel; MgO and
/// TiO₂ (pbrt's names) from their indices, 1.74 and 2.6, without absorption. kousen's metals
/// rise from it to white at grazing angles along Schlick's curve (`render::conductor`).
const METAL_F0: [(&str, [f32; 3]); 9] = [
    ("ag", [0.972, 0.960, 0.915]),
    ("al", [0.913, 0.922, 0.924]),
    ("au", [1.000, 0.782, 0.344]),
    ("cr", [0.549, 0.556, 0.554]),
    ("cu", [0.955, 0.638, 0.538]),
    ("cuzn", [0.910, 0.778, 0.423]),
    ("mgo", [0.073, 0.073, 0.073]),
    ("ni_palik", [0.660, 0.609, 0.526]),
    ("tio2", [0.198, 0.198, 0.198]),
];

/// The reflectance at normal incidence of the metal `name`s (any case), if kousen knows it.
pub fn metal_f0(name: &str) -> Option<Vec3> {
    let found = METAL_F0.iter().find(|(n, _)| n.eq_ignore_ascii_case(name));
    found.map(|(_, f0)| Vec3::from_array(*f0))
}

/// The [`Material::metal_edge`] whose grazing reflectance is `f90` for a metal of colour `f0`
/// (each channel, clamped to [0, 1]; 0 where `f0` is already white): a conductor's Fresnel
/// scaled by a tint (Mitsuba's `specular_reflectance`) rises to the tint, not to white.
pub fn metal_edge_to(f0: Vec3, f90: Vec3) -> Vec3 {
    let rise = Vec3::ONE - f0;
    let edge = (f90 - f0) / rise.max(Vec3::splat(1e-6));
    Vec3::select(rise.cmpgt(Vec3::ZERO), edge, Vec3::ZERO).clamp(Vec3::ZERO, Vec3::ONE)
}

/// A principled material (Mitsuba 3's `principled`, pbrt-v3's `disney`) read as glTF's
/// metallic-roughness one: `base` as metal with probability `metallic`, else as glass with
/// probability `transmission`, else as plastic, all of `roughness` and index `ior`; those of
/// probability 0 left out (one at least remains), for `SceneBuilder::add_mixture`.
pub fn principled_mixture(
    base: Material,
    metallic: f32,
    transmission: f32,
    roughness: f32,
    ior: f32,
) -> Vec<(f32, Material)> {
    let members = [
        (metallic, metal_surface(roughness)),
        (
            (1.0 - metallic) * transmission,
            glass_surface(ior, false, roughness),
        ),
        (
            (1.0 - metallic) * (1.0 - transmission),
            coated_surface(ior, roughness),
        ),
    ];
    (members.into_iter())
        .filter(|(p, _)| *p > 0.0)
        .map(|(p, surface)| {
            let member = Material {
                surface,
                ..base.clone()
            };
            (p, member)
        })
        .collect()
}

/// A member of a material whose glTF roughness (and, for the metal, metalness) comes from a
/// texture, per hit: linear data, roughness in green and metalness in blue, each multiplied
/// by its factor (glTF's `metallicRoughnessTexture`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RoughnessMap {
    pub texture: TextureId,
    /// glTF's `roughnessFactor`.
    pub roughness_factor: f32,
    /// The least and greatest roughness the texture's texels give (`roughness_factor` ×
    /// green, clamped to [0, 1]; [`TextureRoughness::range`]): every hit reads one between
    /// them, filtering included. A mapped coat's tables span it (`render::plastic`).
    pub roughness_range: [f32; 2],
    pub lobe: TexturedLobe,
    /// The metal or coat keeps its lobe however rough the texel (rough metal, rough plastic)
    /// where as Lambertian it would lose what lies on it: a thin film, or a specular layer
    /// whose colour is the whole reflectance (a specular-glossiness metal). Glass ignores it.
    pub keeps_lobe: bool,
}

/// Which of glTF's lobes a [`RoughnessMap`] member is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TexturedLobe {
    /// The metal ([`metal_surface`] of the texel's roughness). As a blend's first member its
    /// weight (`metallicFactor`) is multiplied by the texel's metalness.
    Metal,
    /// The opaque dielectric under its specular coat: [`coated_surface`] of the member's
    /// index at the texel's roughness (plastic, smooth or rough, or Lambertian).
    Coated,
    /// The glass (glTF's transmission): [`glass_surface`] of the member's index and walls at
    /// the texel's roughness, smooth or frosted.
    Glass,
}

impl RoughnessMap {
    /// The surface of `member` (whose map this is) where the texture reads `texel` (linear
    /// RGBA); a `brushed` metal (one with an [`Anisotropy`]) is rough metal where the texel
    /// would make it a mirror ([`brushed_metal_surface`]).
    pub fn surface(&self, member: Surface, texel: glam::Vec4, brushed: bool) -> Surface {
        let roughness = (self.roughness_factor * texel.y).clamp(0.0, 1.0);
        let kept = |surface: Surface, lobe: Surface| match surface {
            Surface::Diffuse if self.keeps_lobe => lobe,
            other => other,
        };
        match self.lobe {
            TexturedLobe::Metal => {
                let surface = if brushed {
                    brushed_metal_surface(roughness)
                } else {
                    metal_surface(roughness)
                };
                let alpha = roughness * roughness;
                kept(surface, Surface::RoughConductor { alpha })
            }
            TexturedLobe::Coated => match member {
                Surface::Plastic { ior, .. } => {
                    let alpha = coat_alpha(roughness);
                    kept(
                        coated_surface(ior, roughness),
                        Surface::Plastic { ior, alpha },
                    )
                }
                other => other,
            },
            TexturedLobe::Glass => match member {
                Surface::Dielectric { ior, thin_walled }
                | Surface::RoughDielectric {
                    ior, thin_walled, ..
                } => glass_surface(ior, thin_walled, roughness),
                other => other,
            },
        }
    }

    /// A blend's weight where this map is its first member's and the texture reads `texel`:
    /// a metal's `weight` (glTF's `metallicFactor`) times the texel's metalness; other
    /// members' weights are not textured.
    pub fn blend_weight(&self, weight: f32, texel: glam::Vec4) -> f32 {
        match self.lobe {
            TexturedLobe::Metal => weight * texel.z.clamp(0.0, 1.0),
            TexturedLobe::Coated | TexturedLobe::Glass => weight,
        }
    }
}

/// The roughness a metallic-roughness texture gives (green × `roughnessFactor`), summed up
/// for the lobes that cannot follow it texel by texel, over the texels where the dielectric
/// shows (weighted by 1 − metalness, blue × `metallicFactor`).
pub struct TextureRoughness {
    /// Where the dielectric shows: the glass's roughness.
    pub mean: f32,
    /// Over all texels: the roughness of the metal's stored surface, which what reads the
    /// material outside a hit sees (`kousen info`).
    pub metal_mean: f32,
    /// Over the texels where the coat is not Lambertian (below [`DIFFUSE_MIN_ROUGHNESS`]): the
    /// roughness of the coated member's stored surface, which what reads the material outside
    /// a hit sees; `None` where there are none.
    pub coat: Option<f32>,
    /// The least and greatest roughness over all texels ([`RoughnessMap::roughness_range`]).
    pub range: [f32; 2],
}

impl TextureRoughness {
    /// The summaries of `texture` under glTF's `roughnessFactor` and `metallicFactor`.
    pub fn of(texture: &Texture, roughness_factor: f32, metallic_factor: f32) -> TextureRoughness {
        let mut all = MeanOf::default();
        let mut dielectric = MeanOf::default();
        let mut coat = MeanOf::default();
        let mut range = [f32::INFINITY, f32::NEG_INFINITY];
        for y in 0..texture.height {
            for x in 0..texture.width {
                let texel = texture
                    .texel_linear(x, y)
                    .clamp(glam::Vec4::ZERO, glam::Vec4::ONE);
                let roughness = (roughness_factor * texel.y).clamp(0.0, 1.0);
                range = [range[0].min(roughness), range[1].max(roughness)];
                let shows = 1.0 - metallic_factor * texel.z;
                all.add(roughness, 1.0);
                dielectric.add(roughness, shows);
                if roughness < DIFFUSE_MIN_ROUGHNESS {
                    coat.add(roughness, shows);
                }
            }
        }
        TextureRoughness {
            mean: dielectric.mean().or(all.mean()).unwrap_or(0.0),
            metal_mean: all.mean().unwrap_or(0.0),
            coat: coat.mean(),
            range: if range[0] <= range[1] {
                range
            } else {
                [0.0; 2]
            },
        }
    }
}

/// A weighted mean, summed in f64.
#[derive(Default)]
struct MeanOf {
    sum: f64,
    weight: f64,
}

impl MeanOf {
    fn add(&mut self, value: f32, weight: f32) {
        self.sum += f64::from(value) * f64::from(weight);
        self.weight += f64::from(weight);
    }

    fn mean(&self) -> Option<f32> {
        (self.weight > 0.0).then(|| (self.sum / self.weight) as f32)
    }
}

/// [`Material::dispersion`] of glass of index `ior` and Abbe number `abbe` (infinite: none).
pub fn dispersion_from_abbe(ior: f32, abbe: f32) -> f32 {
    if abbe.is_finite() && abbe > 0.0 {
        (ior - 1.0) / abbe
    } else {
        0.0
    }
}

/// A material that is one of several surfaces, chosen at random at each hit (glTF's
/// `metallicFactor` and `transmissionFactor` between 0 and 1 mix the metal, glass and
/// dielectric lobes this way): this material's own surface with probability `weight`, else
/// material `other`'s, which may blend on. A one-sample estimate of the mixture's BSDF, so
/// each lobe keeps its own sampling and light samples. Made by [`crate::SceneBuilder::add_blend`],
/// which keeps the chain short ([`MAX_BLEND_MEMBERS`]), its ids increasing, and the one member
/// with a Lambertian lobe (if any) last: photons landing on the mixture are kept for it
/// whichever member the photon's own path then takes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Blend {
    /// Probability of this material's own surface, in (0, 1); in (0, 1] where a metal's
    /// [`RoughnessMap`] multiplies it by the texel's metalness.
    pub weight: f32,
    /// The material taken otherwise: a later id.
    pub other: u32,
}

/// The most materials one blend chains (metal, glass and dielectric for glTF).
pub const MAX_BLEND_MEMBERS: usize = 3;

/// The materials of the blend starting at `id` (itself alone for none), in chain order.
pub fn blend_members(materials: &[Material], id: u32) -> impl Iterator<Item = u32> + '_ {
    let mut next = Some(id);
    std::iter::from_fn(move || {
        let id = next?;
        next = materials[id as usize].blend.map(|b| b.other);
        Some(id)
    })
    .take(MAX_BLEND_MEMBERS)
}

/// The single-scattering albedo (σs / σt) of a medium whose multiple scattering, seen from
/// outside, reflects `multiscatter` (glTF `KHR_materials_volume_scatter`'s
/// `multiscatterColor`, each channel in [0, 1]): the fit of Chiang, Kutz and Burley 2016
/// ("Practical and controllable subsurface scattering for production path tracing"),
/// 1 − (4.09712 + 4.20863·a − √(9.59217 + 41.6808·a + 17.7126·a²))², which maps 0 to 0 and 1 to
/// 1 and rises steeply near 1 (a white look needs nearly lossless scattering).
pub fn single_scatter_albedo(multiscatter: Vec3) -> Vec3 {
    multiscatter.map(|a| {
        let a = a.clamp(0.0, 1.0);
        let root = (9.59217 + 41.6808 * a + 17.7126 * a * a).sqrt();
        let k = (4.09712 + 4.20863 * a - root).clamp(0.0, 1.0);
        1.0 - k * k
    })
}

/// glTF's `KHR_materials_volume` attenuation as an absorption coefficient: white light turns
/// `color` after `distance` (> 0; infinite: no absorption), so `−ln(color) / distance`. A
/// channel of 0 absorbs all but a trace (e⁻²⁰ over the distance) rather than being infinite.
pub fn absorption_from_attenuation(color: Vec3, distance: f32) -> Vec3 {
    if distance.is_infinite() {
        return Vec3::ZERO;
    }
    let color = color.max(Vec3::splat(MIN_ATTENUATION_COLOR));
    -Vec3::from_array(color.to_array().map(f32::ln)) / distance
}

/// The least attenuation colour [`absorption_from_attenuation`] reads: e⁻²⁰.
pub const MIN_ATTENUATION_COLOR: f32 = 2.061_153_6e-9;

impl Default for Material {
    fn default() -> Self {
        Material {
            name: String::new(),
            surface: Surface::Diffuse,
            base_color: Vec3::splat(0.8),
            base_color_texture: None,
            emission: Vec3::ZERO,
            emission_texture: None,
            alpha: 1.0,
            alpha_mode: AlphaMode::Opaque,
            double_sided: false,
            absorption: Vec3::ZERO,
            scattering: Vec3::ZERO,
            scatter_anisotropy: 0.0,
            normal_texture: None,
            normal_scale: 1.0,
            blend: None,
            dispersion: 0.0,
            roughness_map: None,
            clearcoat: None,
            sheen: None,
            transmission_texture: None,
            diffuse_transmission: None,
            anisotropy: None,
            iridescence: None,
            specular: None,
            metal_edge: Vec3::ONE,
        }
    }
}

impl Surface {
    /// Whether it is glass, smooth or frosted (a blend's member that glTF's
    /// `transmissionTexture` weighs).
    pub fn is_glass(self) -> bool {
        matches!(
            self,
            Surface::Dielectric { .. } | Surface::RoughDielectric { .. }
        )
    }

    /// Whether it has a Lambertian lobe (diffuse, or plastic's base), where photons are kept
    /// and eye paths end.
    pub fn has_diffuse_lobe(self) -> bool {
        matches!(self, Surface::Diffuse | Surface::Plastic { .. })
    }

    /// Whether it is a solid (not thin-walled) dielectric, with an inside that absorbs.
    pub fn is_solid_dielectric(self) -> bool {
        self.solid_ior().is_some()
    }

    /// A solid (not thin-walled) dielectric's index of refraction, smooth or rough.
    pub fn solid_ior(self) -> Option<f32> {
        match self {
            Surface::Dielectric {
                ior,
                thin_walled: false,
            }
            | Surface::RoughDielectric {
                ior,
                thin_walled: false,
                ..
            } => Some(ior),
            _ => None,
        }
    }
}

impl Material {
    /// Whether hits on it read a tangent frame: a normal map (its own or its clear coat's) or
    /// a brushing.
    pub fn reads_tangent_frame(&self) -> bool {
        self.normal_texture.is_some()
            || self.clearcoat.is_some_and(|c| c.normal_texture.is_some())
            || self.anisotropy.is_some()
    }

    pub fn is_emissive(&self) -> bool {
        self.emission.max_element() > 0.0
    }

    /// Whether a path crossing its surface goes inside a volume: a solid dielectric, or a
    /// Lambertian lobe whose diffuse transmission bounds one ([`DiffuseTransmission::volume`]).
    pub fn bounds_volume(&self) -> bool {
        self.surface.is_solid_dielectric() || self.is_translucent_solid()
    }

    /// The absorption a path inside this material suffers: [`Material::absorption`] where it
    /// bounds a volume ([`Material::bounds_volume`]) and for a blend's first material (which
    /// carries its glass member's, as the ray that ran inside may leave through any member),
    /// zero for every other surface (none of them has an inside).
    pub fn interior_absorption(&self) -> Vec3 {
        if self.bounds_volume() || self.blend.is_some() {
            self.absorption
        } else {
            Vec3::ZERO
        }
    }

    /// Whether it is a solid of glass, smooth or frosted, and not a blend: where eye paths
    /// pass inside, so that what scatters there is seen through its surface.
    pub fn is_solid_glass(&self) -> bool {
        self.surface.is_solid_dielectric() && self.blend.is_none()
    }

    /// Whether light scatters inside solid glass ([`Material::is_solid_glass`]): murky water,
    /// smoky glass. There eye paths end at a scattering event too, and photons are kept where
    /// they scatter, to be gathered there (volume photons, `render::scattering`).
    pub fn has_murky_glass(&self) -> bool {
        self.is_solid_glass() && self.scattering.max_element() > 0.0
    }

    /// Whether it is a translucent solid: a Lambertian lobe whose diffuse transmission bounds
    /// a volume.
    pub fn is_translucent_solid(&self) -> bool {
        self.surface.has_diffuse_lobe() && self.diffuse_transmission.is_some_and(|t| t.volume)
    }

    /// The scattering a path inside this material meets: [`Material::scattering`] for a
    /// translucent solid and for solid glass that is not a blend ([`Material::has_murky_glass`]),
    /// zero for every other surface.
    pub fn interior_scattering(&self) -> Vec3 {
        if self.is_translucent_solid() || self.is_solid_glass() {
            self.scattering
        } else {
            Vec3::ZERO
        }
    }

    /// What takes light out of a ray inside this material, absorption and scattering
    /// together (σt = σa + σs): the transmittance of what is not scattered, which light
    /// samples and eye paths see.
    pub fn interior_extinction(&self) -> Vec3 {
        self.interior_absorption() + self.interior_scattering()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A coat's textures scale its weight (red) and roughness (green), clamped; a texel
    /// making it smoother than `MIRROR_MAX_ROUGHNESS` makes it smooth.
    #[test]
    fn a_clear_coat_follows_its_texels() {
        let coat = Clearcoat::new(0.8, 0.4).unwrap();
        let half = coat.at(0.5, 0.5);
        assert_eq!(half.weight, 0.4);
        assert!((half.alpha - 0.04).abs() < 1e-7, "{}", half.alpha);
        assert_eq!(coat.at(1.0, 1.0).alpha, coat.alpha);
        assert_eq!(coat.at(1.0, 0.02).alpha, 0.0, "roughness 0.008: smooth");
        assert_eq!(
            coat.at(2.0, -1.0),
            Clearcoat::new(0.8, 0.0).unwrap(),
            "clamped"
        );
    }

    /// A mapped metal is a mirror, a rough conductor of α = roughness² or Lambertian by its
    /// texel's roughness (green × factor), and its blend weight scales with the texel's
    /// metalness (blue); a mapped coat is plastic of its index at the texel's roughness below
    /// 0.5, Lambertian from there; mapped glass keeps its index and walls, smooth or frosted.
    #[test]
    fn a_roughness_map_follows_the_texel() {
        let map = |lobe| RoughnessMap {
            texture: 0,
            roughness_factor: 0.5,
            roughness_range: [0.0, 0.5],
            lobe,
            keeps_lobe: false,
        };
        let texel = |green: f32, blue: f32| glam::Vec4::new(0.9, green, blue, 1.0);
        let metal = map(TexturedLobe::Metal);
        let member = Surface::RoughConductor { alpha: 0.3 };
        assert_eq!(
            metal.surface(member, texel(0.01, 1.0), false),
            Surface::Mirror
        );
        assert_eq!(
            metal.surface(member, texel(0.6, 1.0), false),
            Surface::RoughConductor { alpha: 0.09 }
        );
        assert_eq!(
            metal.surface(member, texel(1.0, 1.0), false),
            Surface::Diffuse
        );
        assert_eq!(
            metal.surface(member, texel(0.0, 1.0), true),
            Surface::RoughConductor {
                alpha: MIN_BRUSHED_ALPHA
            },
            "a brushed metal is not a mirror"
        );
        assert_eq!(metal.blend_weight(0.8, texel(0.6, 0.25)), 0.2);
        assert_eq!(metal.blend_weight(0.8, texel(0.6, 1.5)), 0.8, "clamped");
        let coat = map(TexturedLobe::Coated);
        let plastic = Surface::Plastic {
            ior: 1.5,
            alpha: 0.04,
        };
        assert_eq!(
            coat.surface(plastic, texel(0.6, 0.0), false),
            Surface::Plastic {
                ior: 1.5,
                alpha: 0.09
            },
            "the texel's own width"
        );
        assert_eq!(
            coat.surface(plastic, texel(0.01, 0.0), false),
            Surface::Plastic {
                ior: 1.5,
                alpha: 0.0
            }
        );
        assert_eq!(
            coat.surface(plastic, texel(1.0, 0.0), false),
            Surface::Diffuse
        );
        assert_eq!(coat.blend_weight(0.8, texel(0.6, 0.25)), 0.8);
        let glass = map(TexturedLobe::Glass);
        let frosted = Surface::RoughDielectric {
            ior: 1.4,
            thin_walled: true,
            alpha: 0.2,
        };
        let smooth = Surface::Dielectric {
            ior: 1.4,
            thin_walled: true,
        };
        assert_eq!(glass.surface(frosted, texel(0.01, 1.0), false), smooth);
        assert_eq!(
            glass.surface(smooth, texel(1.0, 0.0), false),
            Surface::RoughDielectric {
                ior: 1.4,
                thin_walled: true,
                alpha: 0.25
            },
            "never Lambertian"
        );
        assert_eq!(glass.blend_weight(0.8, texel(0.6, 0.25)), 0.8);
    }

    /// A map that keeps its lobe (a film, or a specular layer that is the whole reflectance,
    /// lies on it) never turns Lambertian: rough metal and rough plastic of α = roughness² on
    /// texels of roughness 0.5 and above; below, it follows the texel as any map does.
    #[test]
    fn a_map_that_keeps_its_lobe_is_never_lambertian() {
        let kept = |lobe| RoughnessMap {
            texture: 0,
            roughness_factor: 1.0,
            roughness_range: [0.0, 1.0],
            lobe,
            keeps_lobe: true,
        };
        let rough = glam::Vec4::new(0.0, 0.75, 0.0, 1.0);
        let coat = Surface::Plastic {
            ior: 1.5,
            alpha: 0.01,
        };
        let metal = Surface::RoughConductor { alpha: 0.01 };
        for brushed in [false, true] {
            assert_eq!(
                kept(TexturedLobe::Metal).surface(metal, rough, brushed),
                Surface::RoughConductor { alpha: 0.5625 }
            );
        }
        let expected = Surface::Plastic {
            ior: 1.5,
            alpha: 0.5625,
        };
        assert_eq!(
            kept(TexturedLobe::Coated).surface(coat, rough, false),
            expected
        );
        let lambertian = RoughnessMap {
            keeps_lobe: false,
            ..kept(TexturedLobe::Coated)
        };
        assert_eq!(lambertian.surface(coat, rough, false), Surface::Diffuse);
        let smooth = glam::Vec4::new(0.0, 0.005, 0.0, 1.0);
        assert_eq!(
            kept(TexturedLobe::Metal).surface(metal, smooth, false),
            Surface::Mirror
        );
    }

    /// Light crossing the attenuation distance keeps the attenuation colour; twice as far, its
    /// square; an infinite distance absorbs nothing and a black channel nearly everything.
    #[test]
    fn absorption_turns_white_into_the_attenuation_colour_at_its_distance() {
        let color = Vec3::new(0.35, 0.75, 0.95);
        let sigma = absorption_from_attenuation(color, 100.0);
        let kept = |d: f32| (-sigma * d).exp();
        assert!(
            (kept(100.0) - color).abs().max_element() < 1e-6,
            "{}",
            kept(100.0)
        );
        assert!((kept(200.0) - color * color).abs().max_element() < 1e-6);
        assert_eq!(
            absorption_from_attenuation(color, f32::INFINITY),
            Vec3::ZERO
        );
        let black = absorption_from_attenuation(Vec3::new(0.0, 1.0, 1.0), 2.0);
        assert!((black.x - 10.0).abs() < 1e-4 && black.y == 0.0 && black.z == 0.0);
    }

    /// Only solid glass and translucent solids have an inside to absorb in.
    #[test]
    fn only_solid_dielectrics_and_translucent_volumes_absorb() {
        let absorbing = |surface| Material {
            surface,
            absorption: Vec3::splat(0.5),
            ..Material::default()
        };
        let solid = Surface::Dielectric {
            ior: 1.5,
            thin_walled: false,
        };
        let rough = Surface::RoughDielectric {
            ior: 1.5,
            thin_walled: false,
            alpha: 0.1,
        };
        assert_eq!(absorbing(solid).interior_absorption(), Vec3::splat(0.5));
        assert_eq!(absorbing(rough).interior_absorption(), Vec3::splat(0.5));
        for other in [
            Surface::Dielectric {
                ior: 1.5,
                thin_walled: true,
            },
            Surface::Diffuse,
            Surface::Mirror,
            Surface::RoughConductor { alpha: 0.1 },
        ] {
            assert_eq!(
                absorbing(other).interior_absorption(),
                Vec3::ZERO,
                "{other:?}"
            );
        }
        // Diffuse transmission bounds a volume only where it says so, and only on a surface
        // with a Lambertian lobe.
        let translucent = |surface, volume| Material {
            diffuse_transmission: DiffuseTransmission::new(0.5, Vec3::ONE)
                .map(|t| DiffuseTransmission { volume, ..t }),
            ..absorbing(surface)
        };
        let plastic = Surface::Plastic {
            ior: 1.5,
            alpha: 0.0,
        };
        for (surface, volume, inside) in [
            (Surface::Diffuse, true, true),
            (plastic, true, true),
            (Surface::Diffuse, false, false),
            (Surface::Mirror, true, false),
        ] {
            let material = translucent(surface, volume);
            assert_eq!(material.bounds_volume(), inside, "{surface:?} {volume}");
            let expected = if inside { Vec3::splat(0.5) } else { Vec3::ZERO };
            assert_eq!(material.interior_absorption(), expected, "{surface:?}");
        }
    }
}
