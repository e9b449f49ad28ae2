//! Direct light by sampling the light table from a visible point (next-event estimation), the
//! alternative to letting the photons that land straight from a light carry it.
//!
//! With `DirectLight::Sampled` each eye pass picks one light for every visible point, by the
//! same power CDF the photons start from, and a point on it (or a direction to it), and adds
//! what arrives, unoccluded, to the pixel's direct sum; photons are then stored from their
//! second hit on only, so every path from a light to the visible point is counted once. The
//! photons still carry everything that bounced at least once, caustics included. Direct light
//! then has no gather blur (sharp shadows from small lights) and no photon noise.
//!
//! Every quantity comes from the light table's `flux` (power ÷ probability of picking the
//! light, see [`Light`]), so the GPU reads nothing new. Per kind, what arrives from the sample
//! divided by the sample's density, before the receiver's cosine:
//!
//! | kind | sample | incident radiance ÷ density |
//! |---|---|---|
//! | triangle | uniform point, distance d, light cosine θ | flux · cos θ / (π · faces · d²) |
//! | point | its position | flux / (4π · d²) |
//! | spot | its position | flux · falloff / (cone's solid angle · d²) |
//! | directional | against its direction, unbounded | flux / disk area |
//! | sky | a cosine-distributed direction about the receiver's normal, unbounded | flux / (4 · disk area · cos θ) |
//! | sky map | a direction by the map's importance ([`crate::sky_map`]) within the half the receiver faces, above the receiver | radiance / (pick · density) |
//!
//! (The sky's flux is its radiance × disk area × 4π; sampled by the receiver's cosine, a lit
//! open plane gets the same value from every sample.)

use std::f32::consts::{PI, TAU};

use glam::Vec3;
use scene::SpotFalloff;

use crate::buffers::{
    LIGHT_DIRECTIONAL, LIGHT_POINT, LIGHT_SKY, LIGHT_SPOT, Light, RAY_T_MAX, vec3,
};
use crate::emission::{pick_light, triangle_point};
use crate::sampling::{about_axis, cosine_hemisphere};
use crate::sky_map::{MapFrame, sample_sky_map, sky_map_lookup};

/// Where the direct light on a visible point comes from.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum DirectLight {
    /// Photons landing straight from the lights, as the talk's renderer does.
    #[default]
    Photons,
    /// One light sample and shadow ray per visible point and eye pass.
    Sampled,
}

impl DirectLight {
    pub fn name(self) -> &'static str {
        match self {
            DirectLight::Photons => "photons",
            DirectLight::Sampled => "sampled",
        }
    }

    /// Its bit of [`crate::buffers::SppmParams::sample_lights`].
    pub fn flag(self) -> u32 {
        if self == DirectLight::Sampled {
            crate::buffers::SAMPLE_AT_VISIBLE_POINTS
        } else {
            0
        }
    }
}

/// A light seen from a point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LightSample {
    /// Unit direction from the point towards the light.
    pub direction: Vec3,
    /// How far along `direction` the light lies ([`RAY_T_MAX`] for the sky and directional
    /// lights).
    pub distance: f32,
    /// The point sampled on the light (a point or spot light's position); the receiver for
    /// the sky and directional lights. Shadow rays aim at it.
    pub target: Vec3,
    /// Radiance arriving along `direction` divided by the sample's density (solid angle, light
    /// pick included), before the receiver's cosine.
    pub incident: Vec3,
    /// The sample's density per solid angle, the pick included: what a BSDF's own sampling is
    /// weighed against (multiple importance sampling). Infinite for point, spot and
    /// directional lights, which no BSDF sample can meet.
    pub pdf: f32,
    /// The light table's entry sampled (a textured emitter is read where the sample landed).
    pub index: usize,
}

/// How much shorter than the distance to the light a shadow ray stops, relative: the ray
/// must not meet the light's own triangle, whose hit distance carries rounding error.
pub const SHADOW_SHORTENING: f32 = 1e-4;

/// One sample of the light table as seen from `position` on a surface facing `normal` (unit),
/// from three uniform numbers; `None` where the picked light sends nothing that way (a
/// one-sided emitter seen from behind, a spot seen from outside its cone, a sky map's
/// direction below the surface). `sky_map` is the sky's map ([`crate::sky_map`]). `lights`
/// must not be empty.
pub fn sample_light(
    lights: &[Light],
    sky_map: &[f32],
    u: [f32; 3],
    position: Vec3,
    normal: Vec3,
) -> Option<LightSample> {
    let index = pick_light(lights, u[0]);
    let light = &lights[index];
    let pick = pick_probability(lights, index);
    let flux = vec3(light.flux);
    let towards = |target: Vec3| {
        let offset = target - position;
        let distance_squared = offset.length_squared();
        (distance_squared > 0.0).then(|| {
            let distance = distance_squared.sqrt();
            (offset / distance, distance, distance_squared, target)
        })
    };
    let sample = match light.kind {
        LIGHT_POINT => {
            let (direction, distance, d2, target) = towards(vec3(light.v0))?;
            LightSample {
                index,
                direction,
                distance,
                target,
                incident: flux / (4.0 * PI * d2),
                pdf: f32::INFINITY,
            }
        }
        LIGHT_SPOT => {
            let (direction, distance, d2, target) = towards(vec3(light.v0))?;
            let [cos_inner, cos_outer, shape] = light.edge2;
            let cos_angle = -direction.dot(vec3(light.edge1));
            let shape = SpotFalloff::from_code(shape);
            let falloff = scene::lights::spot_falloff(cos_angle, cos_inner, cos_outer, shape);
            let cone = TAU * (1.0 - cos_outer);
            LightSample {
                index,
                direction,
                distance,
                target,
                incident: flux * falloff / (cone * d2),
                pdf: f32::INFINITY,
            }
        }
        LIGHT_DIRECTIONAL => {
            let radius = light.edge2[0];
            LightSample {
                index,
                direction: -vec3(light.edge1),
                distance: RAY_T_MAX,
                target: position,
                incident: flux / (PI * radius * radius),
                pdf: f32::INFINITY,
            }
        }
        LIGHT_SKY => {
            // A map's direction by its importance, from the half of the map the surface faces
            // (none below it), else a cosine one.
            let (direction, incident, pdf) = match MapFrame::of(light) {
                Some(frame) => {
                    let upper = frame.upper_share_facing(sky_map, normal);
                    let s = sample_sky_map(&frame, sky_map, u[1], u[2], upper)?;
                    if s.direction.dot(normal) <= 0.0 {
                        return None;
                    }
                    (s.direction, s.radiance / (pick * s.pdf), pick * s.pdf)
                }
                None => {
                    let local = cosine_hemisphere(u[1], u[2]);
                    let radius = light.edge2[0];
                    (
                        about_axis(normal, local).normalize(),
                        flux / (4.0 * PI * radius * radius * local.z),
                        pick * local.z / PI,
                    )
                }
            };
            LightSample {
                index,
                direction,
                distance: RAY_T_MAX,
                target: position,
                incident,
                pdf,
            }
        }
        _ => {
            let (direction, distance, d2, target) = towards(triangle_point(light, u[1], u[2]))?;
            let cross = vec3(light.edge1).cross(vec3(light.edge2));
            let normal = cross.normalize();
            let cos_light = -direction.dot(normal);
            let (cos_light, faces) = if light.double_sided != 0 {
                (cos_light.abs(), 2.0)
            } else {
                (cos_light, 1.0)
            };
            LightSample {
                index,
                direction,
                distance,
                target,
                incident: flux * cos_light / (PI * faces * d2),
                pdf: pick * d2 / (0.5 * cross.length() * cos_light),
            }
        }
    };
    (sample.incident.max_element() > 0.0).then_some(sample)
}

/// The probability of picking light `index` of the table (its share of the CDF).
pub fn pick_probability(lights: &[Light], index: usize) -> f32 {
    let before = if index == 0 {
        0.0
    } else {
        lights[index - 1].cdf
    };
    lights[index].cdf - before
}

/// The solid-angle density with which [`sample_light`], from a receiver facing `normal`,
/// draws the sky along `direction`: 0 without a sky (the table's last light when there is one).
pub fn sky_pdf(lights: &[Light], sky_map: &[f32], direction: Vec3, normal: Vec3) -> f32 {
    let Some(last) = lights.last().filter(|l| l.kind == LIGHT_SKY) else {
        return 0.0;
    };
    let pick = pick_probability(lights, lights.len() - 1);
    let cos = direction.dot(normal);
    match MapFrame::of(last) {
        Some(frame) if cos > 0.0 => {
            let upper = frame.upper_share_facing(sky_map, normal);
            pick * sky_map_lookup(&frame, sky_map, direction, upper).1
        }
        Some(_) => 0.0,
        None => pick * cos.max(0.0) / PI,
    }
}

/// The solid-angle density with which [`sample_light`] draws a point on an emissive triangle
/// whose area density is `area_density` ([`crate::emission::light_area_density`]), met at
/// `distance` where the ray makes cosine `cos_light` with its normal.
pub fn triangle_pdf(area_density: f32, distance: f32, cos_light: f32) -> f32 {
    let cos = cos_light.abs();
    if cos > 0.0 {
        area_density * distance * distance / cos
    } else {
        0.0
    }
}

/// The shadow ray towards a light sample from `origin` (the receiver, already offset off its
/// surface): its direction and length. A finite light's ray aims from the offset origin at the
/// sampled point and stops [`SHADOW_SHORTENING`] short of it (aiming the sample's own
/// direction from the offset origin would pass the light's plane before the point on grazing
/// directions, and meet the light).
pub fn shadow_ray(light: &LightSample, origin: Vec3) -> (Vec3, f32) {
    if light.distance >= RAY_T_MAX {
        return (light.direction, RAY_T_MAX);
    }
    let offset = light.target - origin;
    let distance = offset.length();
    if distance <= 0.0 {
        return (light.direction, 0.0);
    }
    (offset / distance, distance * (1.0 - SHADOW_SHORTENING))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::emission::{light_table, sample_emission};
    use crate::rng::stream_key;
    use crate::sky_map::NO_SKY_MAP;

    fn uniform(seed: u32, index: u32) -> f32 {
        (stream_key(seed, 0, 0, index) >> 8) as f32 / (1u32 << 24) as f32
    }

    /// The mean irradiance over a disk of radius `r` from `lights` (occlusion ignored) two
    /// ways: light samples from uniform points on the disk, and the flux of photons from the
    /// same table crossing the disk ÷ its area. They must agree within the photons' noise.
    fn estimates_agree(lights: &[Light], sky_map: &[f32], centre: Vec3, normal: Vec3, r: f32) {
        let (tangent, bitangent) = crate::sampling::orthonormal_basis(normal);
        let n = 1 << 18;
        let mut sampled = 0.0f64;
        for i in 0..n {
            let disk = r * crate::sampling::uniform_disk(uniform(8, i), uniform(9, i));
            let point = centre + disk.x * tangent + disk.y * bitangent;
            let u = [(i as f32 + 0.5) / n as f32, uniform(1, i), uniform(2, i)];
            if let Some(s) = sample_light(lights, sky_map, u, point, normal) {
                sampled += (s.incident * s.direction.dot(normal).max(0.0)).element_sum() as f64;
            }
        }
        let sampled = sampled / n as f64;
        let (m, area) = (1u32 << 22, (PI * r * r) as f64);
        let (mut sum, mut sum_squares) = (0.0f64, 0.0f64);
        for i in 0..m {
            let e = sample_emission(
                lights,
                sky_map,
                Vec3::ZERO,
                [3, 4, 5, 6, 7].map(|seed| uniform(seed, i)),
            );
            let towards = e.direction.dot(normal);
            if towards >= 0.0 {
                continue;
            }
            let t = (centre - e.origin).dot(normal) / towards;
            if t > 0.0 && (e.origin + t * e.direction - centre).length() < r {
                let x = e.flux.element_sum() as f64 / area;
                sum += x;
                sum_squares += x * x;
            }
        }
        let counted = sum / m as f64;
        let sigma = ((sum_squares / m as f64 - counted * counted) / m as f64).sqrt();
        assert!(
            counted > 0.0 && sigma < 0.02 * counted,
            "too few photons: {counted} ± {sigma}"
        );
        assert!(
            (sampled - counted).abs() < 4.0 * sigma + 0.01 * counted,
            "kind {}: sampled {sampled}, photons {counted} ± {sigma}",
            lights[0].kind
        );
    }

    /// The entries of `table` of one kind, as the table of a scene with only those lights.
    fn only_kind(table: &[Light], kind: u32) -> Vec<Light> {
        let mut previous = 0.0;
        let chosen: Vec<(Light, f32)> = table
            .iter()
            .map(|light| {
                let probability = light.cdf - previous;
                previous = light.cdf;
                (*light, probability)
            })
            .filter(|(light, _)| light.kind == kind)
            .collect();
        let total: f32 = chosen.iter().map(|(_, p)| p).sum();
        let mut running = 0.0;
        let mut lights: Vec<Light> = chosen
            .into_iter()
            .map(|(light, p)| {
                running += p / total;
                Light {
                    cdf: running,
                    flux: (vec3(light.flux) * p / total).to_array(),
                    ..light
                }
            })
            .collect();
        lights.last_mut().expect("a light of that kind").cdf = 1.0;
        lights
    }

    /// Each kind of light alone (the Cornell box's area light, and the point, spot,
    /// directional and sky lights added to it), on a floor patch the spot's inner cone covers.
    #[test]
    fn sampled_irradiance_matches_the_photons_for_every_light_kind() {
        let table = light_table(&scene::testing::cornell_box_punctual());
        for kind in [
            crate::buffers::LIGHT_TRIANGLE,
            LIGHT_POINT,
            LIGHT_SPOT,
            LIGHT_DIRECTIONAL,
            LIGHT_SKY,
        ] {
            estimates_agree(
                &only_kind(&table, kind),
                &NO_SKY_MAP,
                Vec3::new(250.0, 1.0, 400.0),
                Vec3::Y,
                40.0,
            );
        }
    }

    /// The same under a sky map (`crate::sky_map`): light samples drawn by the map's
    /// importance and photons started the same way must give one irradiance, on a patch facing
    /// up and on one tilted 70° (which sees the map's warm ground too). A point light shares
    /// the table, so that the sky's pick counts.
    #[test]
    fn sampled_irradiance_matches_the_photons_under_a_sky_map() {
        let mut scene = scene::testing::plane_under_sky_map(Vec3::new(1.0, 0.8, 1.2), 0.6);
        let lamp = scene::PunctualLight {
            kind: scene::PunctualKind::Point,
            position: Vec3::new(0.5, 1.5, 0.5),
            direction: Vec3::NEG_Y,
            intensity: Vec3::splat(2.0),
        };
        let bounds = scene.bounds();
        scene.lights.add_punctual(lamp, bounds);
        let table = light_table(&scene);
        assert_eq!(table.len(), 2);
        let sky_map = crate::sky_map::sky_map_buffer(scene.lights.sky.as_ref());
        let tilted = Vec3::new(70f32.to_radians().sin(), 70f32.to_radians().cos(), 0.3);
        for normal in [Vec3::Y, tilted.normalize()] {
            estimates_agree(&table, &sky_map, Vec3::new(0.1, 0.2, 0.0), normal, 0.5);
        }
    }

    #[test]
    fn one_sided_emitters_send_nothing_backwards() {
        let scene = scene::testing::cornell_box();
        let lights = light_table(&scene);
        let above_the_light = Vec3::new(278.0, 600.0, 280.0);
        for i in 0..64 {
            let u = [uniform(1, i), uniform(2, i), uniform(3, i)];
            assert_eq!(
                sample_light(&lights, &NO_SKY_MAP, u, above_the_light, Vec3::Y),
                None
            );
        }
    }

    /// A sample's density, times what it claims arrives divided by that density, is the
    /// light's own radiance; and the densities a BSDF-sampled path computes for the same point
    /// (`sky_pdf`, `triangle_pdf`) are the sampler's.
    #[test]
    fn sample_densities_are_the_samplers() {
        let scene = scene::testing::cornell_box_punctual();
        let table = light_table(&scene);
        let area_density = crate::emission::light_area_density(&scene);
        let emitter = scene
            .materials
            .iter()
            .position(|m| m.emission.max_element() > 0.0)
            .expect("an emissive material");
        let sky = scene.lights.sky.as_ref().expect("a sky").radiance;
        let (position, normal) = (Vec3::new(250.0, 1.0, 400.0), Vec3::Y);
        let close = |a: Vec3, b: Vec3| (a - b).abs().max_element() <= 1e-3 * b.max_element();
        let (mut triangles, mut skies) = (0, 0);
        for i in 0..4096 {
            let u = [uniform(4, i), uniform(5, i), uniform(6, i)];
            let Some(s) = sample_light(&table, &NO_SKY_MAP, u, position, normal) else {
                continue;
            };
            if s.pdf.is_infinite() {
                continue;
            }
            if s.distance >= RAY_T_MAX {
                skies += 1;
                assert!(close(s.incident * s.pdf, sky), "{:?}", s.incident * s.pdf);
                let again = sky_pdf(&table, &NO_SKY_MAP, s.direction, normal);
                assert!((again - s.pdf).abs() <= 1e-4 * s.pdf);
            } else {
                triangles += 1;
                let radiance = scene.materials[emitter].emission;
                assert!(
                    close(s.incident * s.pdf, radiance),
                    "{:?}",
                    s.incident * s.pdf
                );
                // The Cornell box's light faces down.
                let again = triangle_pdf(area_density[emitter], s.distance, s.direction.y);
                assert!(
                    (again - s.pdf).abs() <= 1e-3 * s.pdf,
                    "{again} against {}",
                    s.pdf
                );
            }
        }
        assert!(triangles > 100 && skies > 100, "{triangles} and {skies}");
    }
}
