//! Plastic: a Lambertian base under a smooth or GGX-rough clear coat of index `ior` (glTF's
//! non-metal, whose specular layer is a dielectric of `KHR_materials_ior`, default 1.5).
//!
//! The model is Mitsuba 3's `plastic` (linear variant), so its renders can serve as an
//! independent reference. The coat reflects `F(θ)` (unpolarised Fresnel, [`coat_reflectance`])
//! untinted; the light it lets through scatters in the base and leaves through the coat again,
//! which the diffuse lobe
//!
//! ```text
//! f_base(ωi, ωo) = ρ/π · (1 − F(θi)) (1 − F(θo)) · diffuse_scale(ior)
//! ```
//!
//! stands for, with `diffuse_scale = 1 / (ior² · (1 − F_dr))` accounting for the light the coat
//! reflects back into the base (`F_dr`, [`internal_diffuse_reflectance`]) and the squeezed solid
//! angle inside it. The lobe is symmetric in its two directions, so photons, eye paths and the
//! path tracer all use it as it is.
//!
//! How the kernels sample it ([`coat_event`]): a smooth coat reflects with probability `F(θo)`,
//! weight 1; a rough one first draws a visible GGX micro-normal `m` and reflects about it with
//! probability `F(ωo·m)`, weight `G1` of the reflection (so a highlight costs no Fresnel ratio).
//! Otherwise the path meets the base, whose estimate carries `ρ · diffuse_scale` and, per light
//! sample or photon, the factor `1 − F(θi)` of the direction the light came from; under a rough
//! coat also `(1 − F(θo)) / (1 − F(ωo·m))`, whose mean over `m` is 1, so the base keeps the
//! smooth coat's transmittance (Mitsuba's `roughplastic` tabulates a rough one instead).

use glam::Vec3;

use crate::microfacet::{Frame, sample_visible_normal, smith_g1};
use crate::optics::{fresnel_dielectric, reflect};

/// What a plastic coat does with a ray.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum CoatEvent {
    /// The coat reflects it (untinted) into `direction` with `weight`; weight 0 where a rough
    /// coat's micro-normal sends it below the surface (the path ends).
    Reflected { direction: Vec3, weight: f32 },
    /// It passes the coat to the base, whose estimate it multiplies by `weight`.
    Base { weight: f32 },
}

/// The coat's choice for a ray along `incoming` at a surface with unit `normal` (facing the
/// ray), GGX width `alpha` (0: smooth), from three uniform numbers: `u[0]` chooses, `u[1]` and
/// `u[2]` draw a rough coat's micro-normal.
pub fn coat_event(incoming: Vec3, normal: Vec3, ior: f32, alpha: f32, u: [f32; 3]) -> CoatEvent {
    let cos_view = -incoming.dot(normal);
    if alpha == 0.0 {
        return if u[0] < coat_reflectance(cos_view, ior) {
            CoatEvent::Reflected {
                direction: reflect(incoming, normal),
                weight: 1.0,
            }
        } else {
            CoatEvent::Base { weight: 1.0 }
        };
    }
    let frame = Frame::about(normal);
    let view = frame.to_local(-incoming);
    if view.z <= 0.0 {
        return CoatEvent::Base { weight: 1.0 };
    }
    let micro = sample_visible_normal(view, alpha, u[1], u[2]);
    let micro_reflectance = coat_reflectance(view.dot(micro), ior);
    if u[0] < micro_reflectance {
        let out = reflect(-view, micro);
        return CoatEvent::Reflected {
            direction: frame.to_world(out),
            weight: smith_g1(out, alpha),
        };
    }
    CoatEvent::Base {
        weight: coat_transmittance(cos_view, ior) / (1.0 - micro_reflectance),
    }
}

/// The coat's Fresnel reflectance for light arriving from outside at cosine `cos` (its sign
/// is ignored: both faces of a plastic surface wear the coat).
pub fn coat_reflectance(cos: f32, ior: f32) -> f32 {
    fresnel_dielectric(cos.abs(), 1.0 / ior)
}

/// The share of light passing the coat from outside at cosine `cos`: `1 − F`.
pub fn coat_transmittance(cos: f32, ior: f32) -> f32 {
    1.0 - coat_reflectance(cos, ior)
}

/// The hemispherical (cosine-weighted) reflectance of the coat for diffuse light inside the
/// base (index `ior`) meeting it: Egan and Hilgeman's fit (1973), as Mitsuba 3 evaluates it;
/// within 0.6 % of the exact integral for 1 < ior ≤ 2 (`fit_matches_the_integral` below).
pub fn internal_diffuse_reflectance(ior: f32) -> f32 {
    let eta = 1.0 / ior;
    -1.4399 * eta * eta + 0.7099 * eta + 0.6681 + 0.0636 / eta
}

/// What multiplies the base's `ρ/π · (1 − F(θi)) (1 − F(θo))`: `1 / (ior² (1 − F_dr))`.
pub fn diffuse_scale(ior: f32) -> f32 {
    1.0 / (ior * ior * (1.0 - internal_diffuse_reflectance(ior)))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// 2∫₀¹ F_inside(μ) μ dμ by the midpoint rule: total internal reflection below the
    /// critical cosine, Fresnel above it.
    fn internal_reflectance_integral(ior: f32) -> f64 {
        let steps = 200_000;
        (0..steps)
            .map(|i| {
                let mu = (i as f64 + 0.5) / steps as f64;
                2.0 * mu * fresnel_dielectric(mu as f32, ior) as f64 / steps as f64
            })
            .sum()
    }

    #[test]
    fn fit_matches_the_integral() {
        for ior in [1.1, 1.33, 1.5, 1.7, 2.0] {
            let exact = internal_reflectance_integral(ior);
            let fit = internal_diffuse_reflectance(ior) as f64;
            assert!(
                ((fit - exact) / exact).abs() < 0.006,
                "ior {ior}: fit {fit}, integral {exact}"
            );
        }
        // At least the share totally reflected, 1 − 1/ior².
        let ior = 1.5f32;
        assert!(internal_diffuse_reflectance(ior) > 1.0 - 1.0 / (ior * ior));
    }

    #[test]
    fn coat_reflects_four_percent_head_on_and_all_at_grazing() {
        assert!((coat_reflectance(1.0, 1.5) - 0.04).abs() < 1e-6);
        assert!((coat_reflectance(-1.0, 1.5) - 0.04).abs() < 1e-6);
        assert!(coat_reflectance(1e-4, 1.5) > 0.99);
        assert!((coat_transmittance(1.0, 1.5) - 0.96).abs() < 1e-6);
    }

    /// Over many draws, the base's share times its weight is the smooth coat's transmittance
    /// `1 − F(θo)`, rough or smooth; the smooth coat reflects `F(θo)` of the rays.
    #[test]
    fn coat_events_give_the_base_its_transmittance() {
        let normal = Vec3::Y;
        let mut rng = crate::sampling::Rng::new(7, 0);
        for (cos_view, alpha) in [
            (1.0f32, 0.0),
            (0.3, 0.0),
            (1.0, 0.09),
            (0.3, 0.09),
            (0.1, 0.25),
        ] {
            let sin = (1.0 - cos_view * cos_view).sqrt();
            let incoming = Vec3::new(sin, -cos_view, 0.0);
            let draws = 400_000;
            let (mut base, mut reflected) = (0.0f64, 0.0f64);
            for _ in 0..draws {
                let u = [rng.next_f32(), rng.next_f32(), rng.next_f32()];
                match coat_event(incoming, normal, 1.5, alpha, u) {
                    CoatEvent::Base { weight } => base += weight as f64,
                    CoatEvent::Reflected { direction, weight } => {
                        assert!(direction.y > 0.0 || weight == 0.0);
                        reflected += 1.0;
                    }
                }
            }
            let expected = coat_transmittance(cos_view, 1.5) as f64;
            let base = base / draws as f64;
            assert!(
                (base - expected).abs() < 3e-3,
                "cos {cos_view}, α {alpha}: base {base}, expected {expected}"
            );
            if alpha == 0.0 {
                let share = reflected / draws as f64;
                assert!((share - (1.0 - expected)).abs() < 3e-3, "{share}");
            }
        }
    }

    /// A white base under the coat, lit uniformly, returns all the light: the coat's outside and
    /// inside diffuse transmittances differ by exactly ior² (1 − F_dr,out = ior² (1 − F_dr,in)),
    /// so `diffuse_scale` undoes the outside one and the base gives back what the coat let in.
    /// Only the fit's error remains.
    #[test]
    fn white_plastic_returns_nearly_all_light() {
        let ior = 1.5;
        let steps = 20_000;
        let external: f64 = (0..steps)
            .map(|i| {
                let mu = (i as f64 + 0.5) / steps as f64;
                2.0 * mu * coat_transmittance(mu as f32, ior) as f64 / steps as f64
            })
            .sum();
        for cos_view in [1.0f32, 0.5, 0.1] {
            let f = coat_reflectance(cos_view, ior) as f64;
            let base = diffuse_scale(ior) as f64 * (1.0 - f) * external;
            let albedo = f + base;
            assert!((0.995..=1.005).contains(&albedo), "at {cos_view}: {albedo}");
        }
    }
}
