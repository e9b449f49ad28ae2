//! glTF's clear coat (`KHR_materials_clearcoat`, `scene::Clearcoat`): a thin clear layer of
//! index 1.5 over a whole material. It reflects `weight · F(θ)` of the light meeting it (F:
//! unpolarised Fresnel at the surface's cosine) and lets the rest through to the material
//! beneath, untinted and unrefracted, as glTF's model has it: the material beneath is dimmed
//! by `1 − weight · F` on the way in and again on the way out.
//!
//! The kernels (CPU, WGSL twins in `shading/coats.wgsl`, the path tracer) meet the coat first at a
//! hit ([`clearcoat_event`]): reflected with that probability, weight 1 (a rough coat reflects
//! about a visible GGX micro-normal, weight `G1` of the reflection, as rough metal does: the
//! choice keeps the surface's Fresnel rather than the micro-normal's, whose ratio to it would
//! weigh tilted micro-normals up to 25×), or through to the material beneath, weight 1, whose
//! light samples carry the coat's [`clearcoat_transmittance`] for the light's direction.
//! Photons reflected by the coat are not kept on the surface beneath: those kept carry its
//! dimming by the choice. The coat's own reflection gets no light sample (emission met after
//! it counts whole, as after a mirror).

use glam::Vec3;
use scene::Clearcoat;

use crate::microfacet::rough_reflection;
use crate::optics::{fresnel_dielectric, reflect};

/// What the coat does with a ray.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ClearcoatEvent {
    /// The coat reflects it into a direction with a weight, or ends it (`None`) where a rough
    /// coat's micro-normal sends it below the surface.
    Reflected(Option<(Vec3, f32)>),
    /// It passes to the material beneath, weight 1.
    Through,
}

/// The coat at a hit whose textures read `texel(id)` (linear RGBA): `scene::Clearcoat::at`
/// of its weight texture's red and its roughness texture's green.
pub fn clearcoat_at(coat: &Clearcoat, texel: impl Fn(scene::TextureId) -> glam::Vec4) -> Clearcoat {
    let weight = coat.weight_texture.map_or(1.0, |id| texel(id).x);
    let roughness = coat.roughness_texture.map_or(1.0, |id| texel(id).y);
    coat.at(weight, roughness)
}

/// The share of light meeting the coat at cosine `cos` (its sign ignored) that it reflects.
pub fn clearcoat_reflectance(coat: &Clearcoat, cos: f32) -> f32 {
    coat.weight * fresnel_dielectric(cos.abs(), 1.0 / Clearcoat::IOR)
}

/// The share it lets through to the material beneath.
pub fn clearcoat_transmittance(coat: &Clearcoat, cos: f32) -> f32 {
    1.0 - clearcoat_reflectance(coat, cos)
}

/// The numbers [`clearcoat_event`] takes, drawn from `next`: one for the choice, and two more
/// for a rough coat's micro-normal (0 for a smooth one, which draws none).
pub fn clearcoat_numbers(coat: &Clearcoat, mut next: impl FnMut() -> f32) -> [f32; 3] {
    let choice = next();
    if coat.alpha > 0.0 {
        [choice, next(), next()]
    } else {
        [choice, 0.0, 0.0]
    }
}

/// The coat's choice for a ray along `incoming` at a surface with unit `normal` (facing the
/// ray): `u[0]` chooses, `u[1]` and `u[2]` draw a rough coat's micro-normal.
pub fn clearcoat_event(
    incoming: Vec3,
    normal: Vec3,
    coat: &Clearcoat,
    u: [f32; 3],
) -> ClearcoatEvent {
    if u[0] >= clearcoat_reflectance(coat, -incoming.dot(normal)) {
        return ClearcoatEvent::Through;
    }
    if coat.alpha == 0.0 {
        return ClearcoatEvent::Reflected(Some((reflect(incoming, normal), 1.0)));
    }
    ClearcoatEvent::Reflected(rough_reflection(incoming, normal, coat.alpha, u[1], u[2]))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Head-on a full coat reflects 4 % (index 1.5), half a coat 2 %; at grazing a full coat
    /// reflects everything; the choice follows the reflectance, a smooth coat mirroring.
    #[test]
    fn the_coat_reflects_its_weight_of_fresnel() {
        let full = Clearcoat::new(1.0, 0.0).unwrap();
        let half = Clearcoat::new(0.5, 0.0).unwrap();
        assert!((clearcoat_reflectance(&full, 1.0) - 0.04).abs() < 1e-6);
        assert!((clearcoat_reflectance(&half, -1.0) - 0.02).abs() < 1e-6);
        assert!((clearcoat_transmittance(&full, 0.0)).abs() < 1e-6);
        let incoming = Vec3::new(0.6, -0.8, 0.0);
        let f = clearcoat_reflectance(&full, 0.8);
        assert_eq!(
            clearcoat_event(incoming, Vec3::Y, &full, [f * 0.99, 0.5, 0.5]),
            ClearcoatEvent::Reflected(Some((Vec3::new(0.6, 0.8, 0.0), 1.0)))
        );
        assert_eq!(
            clearcoat_event(incoming, Vec3::Y, &full, [f * 1.01, 0.5, 0.5]),
            ClearcoatEvent::Through
        );
        assert!(Clearcoat::new(0.0, 0.3).is_none());
    }

    /// A rough coat reflects about a micro-normal: above the surface, near the mirror
    /// direction for a narrow lobe, weight G1 ≤ 1.
    #[test]
    fn a_rough_coat_reflects_about_a_micro_normal() {
        let coat = Clearcoat::new(1.0, 0.2).unwrap();
        let mut drawn = 0;
        clearcoat_numbers(&coat, || {
            drawn += 1;
            0.5
        });
        assert_eq!(drawn, 3, "a rough coat draws its micro-normal");
        let incoming = Vec3::new(0.6, -0.8, 0.0);
        let ClearcoatEvent::Reflected(Some((direction, weight))) =
            clearcoat_event(incoming, Vec3::Y, &coat, [0.0, 0.3, 0.7])
        else {
            panic!("a choice of 0 reflects");
        };
        assert!(direction.y > 0.0 && direction.dot(Vec3::new(0.6, 0.8, 0.0)) > 0.9);
        assert!(weight > 0.0 && weight <= 1.0);
    }
}
