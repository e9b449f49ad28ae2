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

use crate::iridescence::{Film, film_mix, film_share};
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

/// A smooth dielectric of index `ior` (relative to outside) under `layer`: its own Fresnel
/// reflectance `fresnel` for light meeting it at `cos_incident` as the layer makes it
/// ([`DielectricLayer::reflectance`]). The layer lies on the outside: light from inside
/// meets it at the angle Snell's law gives outside (reflectance is the same from both sides of
/// a lossless interface), and where none is (total internal reflection) everything reflects.
pub fn layered_dielectric(
    fresnel: f32,
    layer: DielectricLayer,
    cos_incident: f32,
    ior: f32,
    from_outside: bool,
) -> Vec3 {
    if layer.is_bare() {
        return Vec3::splat(fresnel);
    }
    let cos_incident = cos_incident.clamp(0.0, 1.0);
    let cos_outside = if from_outside {
        cos_incident
    } else {
        let sin2_outside = ior * ior * (1.0 - cos_incident * cos_incident);
        if sin2_outside >= 1.0 {
            return Vec3::ONE;
        }
        (1.0 - sin2_outside).sqrt()
    };
    layer.reflectance(fresnel, cos_outside, ior)
}

/// A smooth dielectric's reflectance at `cos_incident`, bare (`fresnel`, its own Fresnel
/// reflectance there) and under `layer` ([`layered_dielectric`]), and for a `thin_walled`
/// sheet, whose light bounces between its two faces, the total 2R / (1 + R) of each.
pub fn layered_reflectance(
    fresnel: f32,
    layer: DielectricLayer,
    (cos_incident, ior, from_outside): (f32, f32, bool),
    thin_walled: bool,
) -> (f32, Vec3) {
    let layered = layered_dielectric(fresnel, layer, cos_incident, ior, from_outside);
    let sheet = |r: f32| 2.0 * r / (1.0 + r);
    if thin_walled {
        (sheet(fresnel), layered.map(sheet))
    } else {
        (fresnel, layered)
    }
}

/// The weight a layer gives a rough dielectric's way from `view` into `out` (unit, both away
/// from the surface; `normal` the shading normal on the view's side; `eta` = n on the view's
/// side / n beyond; `thin_walled` a sheet, whose transmission is its reflection mirrored
/// across the surface): at the micro-normal that takes one into the other, the layer's share
/// of that way over the bare surface's, by which `crate::microfacet::rough_dielectric` chose
/// it (so its sampling and its lobes' densities stay as they were). 1 when bare.
pub fn rough_dielectric_layer_weight(
    layer: DielectricLayer,
    (view, out): (Vec3, Vec3),
    normal: Vec3,
    eta: f32,
    thin_walled: bool,
) -> Vec3 {
    if layer.is_bare() {
        return Vec3::ONE;
    }
    let reflected = out.dot(normal) > 0.0;
    let micro = if reflected {
        view + out
    } else if thin_walled {
        view + out - 2.0 * out.dot(normal) * normal
    } else {
        -(eta * view + out)
    };
    let Some(mut micro) = micro.try_normalize() else {
        return Vec3::ONE;
    };
    if micro.dot(normal) < 0.0 {
        micro = -micro;
    }
    let cos_view = view.dot(micro).clamp(0.0, 1.0);
    // Seen from outside where the view's side is the less dense (a sheet is air on both).
    let (ior, from_outside) = if thin_walled || eta <= 1.0 {
        (1.0 / eta, true)
    } else {
        (eta, false)
    };
    let fresnel = crate::optics::fresnel_dielectric(cos_view, eta);
    let seen = (cos_view, ior, from_outside);
    let (bare, layered) = layered_reflectance(fresnel, layer, seen, thin_walled);
    film_share(bare, layered, reflected)
}

/// [`rough_dielectric_layer_weight`] for the frosted glass lobe a light sample serves
/// (`crate::microfacet::GlossyLobe`: solid glass's reflection from outside, its refraction out
/// from inside, or a thin sheet's two ways), seen along `outgoing` and lit along `incident`.
pub fn lobe_layer_weight(
    lobe: &crate::microfacet::GlossyLobe,
    layer: DielectricLayer,
    normal: Vec3,
    (outgoing, incident): (Vec3, Vec3),
) -> Vec3 {
    let (eta, thin_walled) = if lobe.sheet_eta > 0.0 {
        (lobe.sheet_eta, true)
    } else if lobe.refraction_eta > 0.0 {
        (lobe.refraction_eta, false)
    } else {
        (1.0 / lobe.fresnel_ior, false)
    };
    rough_dielectric_layer_weight(layer, (outgoing, incident), normal, eta, thin_walled)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A layer of `film` alone.
    fn filmed(film: Film) -> DielectricLayer {
        DielectricLayer {
            film,
            specular: None,
        }
    }
    /// Glass under a specular layer reflects the layer's map of its Fresnel reflectance from
    /// either side: from inside at cosine μ the same as from outside at Snell's angle (where
    /// the bare reflectances agree), and everything past the critical angle, whatever the
    /// layer; a sheet's two faces total 2R / (1 + R) of it.
    #[test]
    fn glass_under_a_specular_layer_reflects_its_map_from_either_side() {
        let ior = 1.5f32;
        let layer = DielectricLayer {
            specular: Some(LayerReflectance {
                f0: Vec3::new(0.05, 0.02, 0.004),
                f90: 0.4,
            }),
            film: Film::default(),
        };
        for cos_inside in [1.0f32, 0.9, 0.8, 0.76] {
            let sin2_outside = ior * ior * (1.0 - cos_inside * cos_inside);
            let cos_outside = (1.0 - sin2_outside).sqrt();
            let inside = fresnel_dielectric(cos_inside, ior);
            let outside = fresnel_dielectric(cos_outside, 1.0 / ior);
            assert!(
                (inside - outside).abs() < 1e-5,
                "reciprocity at {cos_inside}"
            );
            let from_inside = layered_dielectric(inside, layer, cos_inside, ior, false);
            let from_outside = layered_dielectric(outside, layer, cos_outside, ior, true);
            let mapped = layer.specular.unwrap().remap(outside, ior);
            assert!(
                from_inside.abs_diff_eq(mapped, 1e-5),
                "{from_inside} {mapped}"
            );
            assert!(
                from_outside.abs_diff_eq(mapped, 1e-6),
                "{from_outside} {mapped}"
            );
        }
        assert_eq!(layered_dielectric(1.0, layer, 0.7, ior, false), Vec3::ONE);
        let (bare, layered) = layered_reflectance(0.04, layer, (1.0, ior, true), true);
        assert!((bare - 0.08 / 1.04).abs() < 1e-6);
        let f0 = layer.specular.unwrap().f0;
        assert!(
            layered.abs_diff_eq(2.0 * f0 / (Vec3::ONE + f0), 1e-6),
            "{layered}"
        );
    }

    /// On glass a film of zero thickness is the bare glass from either side: from inside at
    /// cosine μ it is seen outside at Snell's angle, and the reflectance there is the
    /// inside's Fresnel (reciprocity); past the critical angle everything reflects; without a
    /// film the glass's own Fresnel comes back exactly.
    #[test]
    fn a_film_on_glass_of_zero_thickness_is_the_bare_glass_from_either_side() {
        let ior = 1.5;
        let bare = Film {
            factor: 1.0,
            ior: 1.3,
            thickness: 0.0,
        };
        for cos in [1.0f32, 0.9, 0.8, 0.77] {
            let inside = fresnel_dielectric(cos, ior);
            let seen = layered_dielectric(inside, filmed(bare), cos, ior, false);
            assert!(
                (seen - Vec3::splat(inside)).abs().max_element() < 2e-5,
                "inside at cos {cos}: {seen} vs {inside}"
            );
            let outside = fresnel_dielectric(cos, 1.0 / ior);
            let seen = layered_dielectric(outside, filmed(bare), cos, ior, true);
            assert!(
                (seen - Vec3::splat(outside)).abs().max_element() < 2e-5,
                "outside at cos {cos}: {seen} vs {outside}"
            );
        }
        // The critical angle from inside is at cos √(1 − 1/1.5²) ≈ 0.745.
        let seen = layered_dielectric(1.0, filmed(bare), 0.7, ior, false);
        assert_eq!(seen, Vec3::ONE);
        let none = Film::default();
        assert_eq!(
            layered_dielectric(0.123, filmed(none), 0.5, ior, true),
            Vec3::splat(0.123)
        );
    }

    /// A rough dielectric's way rebuilt from its two directions finds the micro-normal that
    /// made it: reflected, refracted out of and into glass, and through a sheet (the
    /// reflection mirrored), the weight is the film's share over the bare one at that
    /// micro-normal; at zero thickness it is 1.
    #[test]
    fn a_rough_dielectric_s_film_weight_finds_its_micro_normal() {
        use crate::optics::{reflect, refract};
        let film = Film {
            factor: 1.0,
            ior: 1.33,
            thickness: 420.0,
        };
        let normal = Vec3::Z;
        let micro = Vec3::new(0.3, -0.2, 1.0).normalize();
        let view = Vec3::new(-0.5, 0.1, 0.8).normalize();
        let share = |eta: f32, reflected: bool, thin: bool| {
            let cos = view.dot(micro);
            let (ior, outside) = if thin || eta <= 1.0 {
                (1.0 / eta, true)
            } else {
                (eta, false)
            };
            let bare = fresnel_dielectric(cos, eta);
            let filmed = layered_dielectric(bare, filmed(film), cos, ior, outside);
            let sheet = |r: f32| 2.0 * r / (1.0 + r);
            let (bare, filmed) = if thin {
                (sheet(bare), filmed.map(sheet))
            } else {
                (bare, filmed)
            };
            if reflected {
                filmed / bare
            } else {
                (Vec3::ONE - filmed) / (1.0 - bare)
            }
        };
        let reflected = reflect(-view, micro);
        for (eta, thin) in [(1.0 / 1.5, false), (1.5, false), (1.0 / 1.5, true)] {
            let weight =
                rough_dielectric_layer_weight(filmed(film), (view, reflected), normal, eta, thin);
            let expected = share(eta, true, thin);
            assert!(
                (weight - expected).abs().max_element() < 1e-4,
                "{weight} vs {expected}"
            );
        }
        for eta in [1.0 / 1.5, 1.2] {
            let out = refract(-view, micro, eta).expect("refracts");
            let weight =
                rough_dielectric_layer_weight(filmed(film), (view, out), normal, eta, false);
            let expected = share(eta, false, false);
            assert!(
                (weight - expected).abs().max_element() < 1e-4,
                "eta {eta}: {weight} vs {expected}"
            );
        }
        let through = reflected - 2.0 * reflected.z * Vec3::Z;
        let weight =
            rough_dielectric_layer_weight(filmed(film), (view, through), normal, 1.0 / 1.5, true);
        let expected = share(1.0 / 1.5, false, true);
        assert!(
            (weight - expected).abs().max_element() < 1e-4,
            "{weight} vs {expected}"
        );
        assert!(
            (expected - Vec3::ONE).abs().max_element() > 0.01,
            "the film matters"
        );
        let bare = Film {
            thickness: 0.0,
            ..film
        };
        let weight = rough_dielectric_layer_weight(
            filmed(bare),
            (view, reflected),
            normal,
            1.0 / 1.5,
            false,
        );
        assert!((weight - Vec3::ONE).abs().max_element() < 1e-4, "{weight}");
    }

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
