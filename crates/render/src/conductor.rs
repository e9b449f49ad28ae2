//! What a metal reflects: glTF's conductor Fresnel. A metal reflects its colour F0 (glTF's base
//! colour) at normal incidence and more towards grazing angles, along Schlick's curve
//! F = F0 + (F90 − F0)(1 − cos θ)⁵ with θ the angle to the micro-normal that reflects the
//! light (glTF's `conductor_fresnel`: F90 = 1). It stands in for a real metal's Fresnel curve
//! (from its complex index, which the Mitsuba and pbrt loaders read as F0:
//! `scene::material::metal_f0`), close to it for common metals.
//!
//! Each material says how far its edge rises towards white (`scene::Material::metal_edge`,
//! per channel): F90 = F0 + edge·(1 − F0). glTF's metals rise all the way (1); Mitsuba's
//! conductors tinted by `specular_reflectance` s rise to s, and its `"none"` conductor, a
//! perfect mirror times s, not at all (0).
//!
//! Under glTF's thin film (`crate::iridescence`) the reflectance is that curve mixed with the
//! film's by the film's factor. Used by `cpu::surface::bounce_tint` (a photon's or eye path's
//! bounce off metal takes the reflectance at its micro-normal), the eye paths' light samples
//! at rough metal (`cpu::kernels::LitLobes::metal`), their WGSL twins
//! (`shaders/shared/shading/thin_film.wgsl`) and the path tracer.

use glam::Vec3;

use crate::iridescence::{Film, film_reflectance, ior_from_f0};

/// Schlick's conductor Fresnel: `f0` at normal incidence rising by `edge` of the way to white
/// at grazing angles, at `cos_incident` (clamped to [0, 1]) to the micro-normal.
pub fn conductor_fresnel(f0: Vec3, edge: Vec3, cos_incident: f32) -> Vec3 {
    let grazing = (1.0 - cos_incident.clamp(0.0, 1.0)).powi(5);
    f0 + edge * (Vec3::ONE - f0) * grazing
}

/// A metal as a hit sees it: its colour (F0, after textures), how far its edge rises towards
/// white, and the thin film on it (factor 0: none).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Metal {
    pub f0: Vec3,
    pub edge: Vec3,
    pub film: Film,
}

impl Metal {
    /// The reflectance at `cos_incident` to the micro-normal: Schlick's curve, mixed by the
    /// film's factor with the film's reflectance on a base of index `ior_from_f0(f0)`.
    pub fn reflectance(&self, cos_incident: f32) -> Vec3 {
        let bare = conductor_fresnel(self.f0, self.edge, cos_incident);
        if !self.film.is_some() {
            return bare;
        }
        let film = self.film;
        let cos = cos_incident.clamp(0.0, 1.0);
        let film_colour = film_reflectance(cos, film.ior, film.thickness, ior_from_f0(self.f0));
        bare.lerp(film_colour, film.factor.min(1.0))
    }

    /// The reflectance of a reflection between `outgoing` and `incident` (unit, both away from
    /// the surface): at the angle to their half-way vector, the micro-normal that reflects one
    /// into the other. Reflectance is reciprocal, so eye and light paths see the same colour.
    pub fn tint(&self, outgoing: Vec3, incident: Vec3) -> Vec3 {
        let sum = outgoing + incident;
        let length = sum.length();
        let cos_incident = if length > 0.0 {
            outgoing.dot(sum / length)
        } else {
            0.0
        };
        self.reflectance(cos_incident)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const COLOURS: [Vec3; 3] = [
        Vec3::new(0.95, 0.64, 0.54),
        Vec3::new(0.56, 0.57, 0.58),
        Vec3::new(0.04, 0.3, 0.9),
    ];

    fn bare(f0: Vec3, edge: Vec3) -> Metal {
        Metal {
            f0,
            edge,
            film: Film::default(),
        }
    }

    #[test]
    fn schlick_s_curve_runs_from_f0_to_the_edge() {
        for f0 in COLOURS {
            let metal = bare(f0, Vec3::ONE);
            assert_eq!(metal.reflectance(1.0), f0);
            assert!((metal.reflectance(0.0) - Vec3::ONE).abs().max_element() < 1e-6);
            // Halfway in (1 − cos)⁵: cos = 1 − 0.5^(1/5).
            let half = metal.reflectance(1.0 - 0.5f32.powf(0.2));
            assert!((half - 0.5 * (f0 + Vec3::ONE)).abs().max_element() < 1e-5);
            // Rising, every channel, as the angle grows.
            let mut last = f0;
            for cos in [0.9, 0.7, 0.5, 0.3, 0.1, 0.0] {
                let now = metal.reflectance(cos);
                assert!(now.cmpge(last).all() && now.cmple(Vec3::ONE).all(), "{now}");
                last = now;
            }
            // No edge: the colour at every angle; half an edge, half the rise.
            for cos in [1.0, 0.6, 0.1, 0.0] {
                assert_eq!(bare(f0, Vec3::ZERO).reflectance(cos), f0);
                let rise = |e: f32| bare(f0, Vec3::splat(e)).reflectance(cos) - f0;
                assert!((rise(0.5) - 0.5 * rise(1.0)).abs().max_element() < 1e-6);
            }
        }
    }

    #[test]
    fn the_tint_is_read_at_the_half_way_vector() {
        let metal = bare(COLOURS[0], Vec3::ONE);
        let normal = Vec3::Y;
        let outgoing = Vec3::new(0.8, 0.6, 0.0);
        // The mirror direction: the half-way vector is the normal.
        let mirrored = Vec3::new(-0.8, 0.6, 0.0);
        assert_eq!(metal.tint(outgoing, mirrored), metal.reflectance(0.6));
        // Any other pair: the cosine to their half-way vector, the same both ways.
        let incident = Vec3::new(-0.2, 0.9, 0.3).normalize();
        let half = (outgoing + incident).normalize();
        let expected = metal.reflectance(outgoing.dot(half));
        assert!(
            (metal.tint(outgoing, incident) - expected)
                .abs()
                .max_element()
                < 1e-6
        );
        assert_eq!(
            metal.tint(outgoing, incident),
            metal.tint(incident, outgoing)
        );
        assert!(normal.dot(half) > 0.0);
    }

    /// A metal of colour `f0` rising to white under a film of index 1.3.
    fn filmed(f0: Vec3, factor: f32, thickness: f32) -> Metal {
        let film = Film {
            factor,
            ior: 1.3,
            thickness,
        };
        Metal {
            film,
            ..bare(f0, Vec3::ONE)
        }
    }

    #[test]
    fn a_film_mixes_with_schlick_s_curve() {
        for f0 in COLOURS {
            // A film of no thickness at normal incidence is the bare metal.
            let metal = filmed(f0, 1.0, 0.0);
            assert!((metal.reflectance(1.0) - f0).abs().max_element() < 1e-4);
        }
        // Half a film is halfway between the bare curve and the film's colour.
        let f0 = COLOURS[0];
        let metal = filmed(f0, 0.5, 400.0);
        let full = film_reflectance(0.3, 1.3, 400.0, ior_from_f0(f0));
        let curve = conductor_fresnel(f0, Vec3::ONE, 0.3);
        let half = metal.reflectance(0.3);
        assert!((half - 0.5 * (curve + full)).abs().max_element() < 1e-6);
    }
}
