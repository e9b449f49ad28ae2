//! What lies on a dielectric's surface (plastic's coat, glass) and changes its reflectance:
//! glTF's specular layer (`KHR_materials_specular`) and thin film (`KHR_materials_iridescence`,
//! `crate::iridescence`), [`DielectricLayer`].
//!
//! glTF scales the dielectric's Fresnel term: in each channel it is `f0 = min(F0 · colour, 1) ·
//! strength` head on and `f90 = strength` at grazing (`scene::SpecularLayer::at`), and glTF's
//! sample renderer draws the curve between them with Schlick's approximation. kousen's
//! dielectrics reflect by the exact Fresnel reflectance `F(θ)` of their index, so the layer
//! keeps that curve's shape and moves its ends: `R = f0 + (f90 − f0) · (F(θ) − F0) / (1 − F0)`,
//! an affine map of `F` taking the index's own `F0` to `f0` and 1 to `f90`. Without a layer (or
//! with glTF's defaults, `f0 = F0` and `f90 = 1`) it is `F` itself.

use glam::Vec3;

use crate::iridescence::{Film, film_mix};
use crate::optics::fresnel_dielectric;

/// The specular layer's ends at a hit: its reflectance head on, per channel, and at grazing.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LayerReflectance {
    pub f0: Vec3,
    pub f90: f32,
}

impl LayerReflectance {
    /// The layer where `layer`'s textures read `texel` and `color_texel`.
    pub fn of(
        layer: &scene::SpecularLayer,
        texel: Option<glam::Vec4>,
        color_texel: Option<glam::Vec4>,
    ) -> LayerReflectance {
        let (f0, f90) = layer.at(texel, color_texel);
        LayerReflectance { f0, f90 }
    }

    /// The layer's reflectance in each channel where the dielectric of relative index `ior`
    /// (> 1) reflects `bare` by Fresnel's law.
    pub fn remap(&self, bare: f32, ior: f32) -> Vec3 {
        let bare_f0 = fresnel_dielectric(1.0, 1.0 / ior);
        let towards_grazing = ((bare - bare_f0) / (1.0 - bare_f0)).clamp(0.0, 1.0);
        self.f0 + (Vec3::splat(self.f90) - self.f0) * towards_grazing
    }
}

/// What lies on a dielectric's surface at a hit (plastic's coat, glass) and changes its
/// reflectance there: glTF's specular layer ([`LayerReflectance`]; `None` for none) and a thin
/// film (glTF's iridescence; factor 0 for none).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct DielectricLayer {
    pub specular: Option<LayerReflectance>,
    pub film: Film,
}

impl DielectricLayer {
    /// Whether the surface reflects as its index says (no specular layer, no film).
    pub fn is_bare(&self) -> bool {
        self.specular.is_none() && !self.film.is_some()
    }

    /// The surface's reflectance in each channel for light meeting it from outside at cosine
    /// `cos` (its sign ignored), where its bare Fresnel reflectance is `bare`: the specular
    /// layer's there ([`LayerReflectance::remap`]), then mixed by the film's factor with the
    /// film's reflectance on a base of the surface's index (`crate::iridescence::film_mix`).
    pub fn reflectance(&self, bare: f32, cos: f32, ior: f32) -> Vec3 {
        let scaled = match self.specular {
            Some(layer) => layer.remap(bare, ior),
            None => Vec3::splat(bare),
        };
        if !self.film.is_some() {
            return scaled;
        }
        film_mix(scaled, self.film, cos.abs().min(1.0), ior)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The map's ends are the layer's, exactly, at any index; glTF's defaults leave Fresnel's
    /// reflectance as it is; and in between it stays near glTF's own Schlick curve for the
    /// same ends (index 1.5, strength 0.5, a red tint): at most 0.0184 apart, at cosine 0.09,
    /// where Schlick's curve leaves Fresnel's (tolerance 0.02).
    #[test]
    fn the_layer_moves_the_ends_of_fresnel_s_curve() {
        for ior in [1.2f32, 1.5, 2.4] {
            let f0 = fresnel_dielectric(1.0, 1.0 / ior);
            let layer = LayerReflectance {
                f0: Vec3::new(0.3, 0.02, 0.0),
                f90: 0.6,
            };
            assert!(layer.remap(f0, ior).abs_diff_eq(layer.f0, 1e-6));
            assert!(layer.remap(1.0, ior).abs_diff_eq(Vec3::splat(0.6), 1e-6));
            let defaults = LayerReflectance {
                f0: Vec3::splat(f0),
                f90: 1.0,
            };
            for cos in [1.0f32, 0.7, 0.3, 0.05] {
                let bare = fresnel_dielectric(cos, 1.0 / ior);
                let mapped = defaults.remap(bare, ior);
                assert!(
                    mapped.abs_diff_eq(Vec3::splat(bare), 1e-6),
                    "{mapped} {bare}"
                );
            }
        }
        let layer = LayerReflectance {
            f0: Vec3::new(0.04, 0.02, 0.01) * 0.5,
            f90: 0.5,
        };
        for cos in [1.0f32, 0.8, 0.5, 0.3, 0.09, 0.02] {
            let ours = layer.remap(fresnel_dielectric(cos, 1.0 / 1.5), 1.5);
            let schlick = layer.f0 + (Vec3::splat(layer.f90) - layer.f0) * (1.0 - cos).powi(5);
            assert!(
                ours.abs_diff_eq(schlick, 0.02),
                "cos {cos}: {ours} against Schlick's {schlick}"
            );
        }
    }
}
