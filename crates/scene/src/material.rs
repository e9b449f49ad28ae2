//! The uber-material every loader maps onto (DESIGN.md, "Materials").

use glam::Vec3;

use crate::TextureId;

/// How light leaves the surface.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Surface {
    /// Lambertian, albedo `base_color` (× texture).
    Diffuse,
    /// Perfect specular reflection tinted by `base_color`.
    Mirror,
    /// Smooth glass with Fresnel reflection and refraction. `thin_walled`: a sheet with no
    /// interior (light passes straight through, glTF transmission without a volume); otherwise
    /// a solid whose inside has index `ior`.
    Dielectric { ior: f32, thin_walled: bool },
    /// Rough metal: GGX microfacets of width `alpha` (glTF's roughness squared) reflecting
    /// `base_color` at every angle, as the mirror does (`render::microfacet`).
    RoughConductor { alpha: f32 },
    /// Rough glass (frosted): GGX microfacets of width `alpha` (glTF's roughness squared) on
    /// the [`Surface::Dielectric`] of `ior` and `thin_walled` (`render::microfacet`).
    RoughDielectric {
        ior: f32,
        thin_walled: bool,
        alpha: f32,
    },
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
}

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
        }
    }
}

impl Material {
    pub fn is_emissive(&self) -> bool {
        self.emission.max_element() > 0.0
    }

    /// Whether paths go on through it (everything but Lambertian, where SPPM gathers).
    pub fn is_specular(&self) -> bool {
        !matches!(self.surface, Surface::Diffuse)
    }
}
