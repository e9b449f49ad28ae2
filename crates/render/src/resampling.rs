//! Light samples chosen among several candidates (resampled importance sampling, Talbot et
//! al. 2005), for visible points whose only lobe is Lambertian.
//!
//! [`crate::direct::sample_light`] picks a light by its power alone, blind to where the
//! receiver is: a bulb inside a paper lantern is picked as often from the lantern's outside,
//! where the paper hides it, as from inside; half the triangles of a glowing sphere face away
//! from any point. Such samples bring nothing and the pixel's noise grows with their share.
//! Here `M` candidates are drawn that way, each is weighed by what it would bring unoccluded,
//! w = luminance(incident) · cos θ about the receiver's normal (`incident` being radiance ÷
//! density, w is the target p̂ ÷ the density p), and one is kept with probability w ÷ Σw. Its
//! radiance is scaled by (Σw / M) ÷ w, which keeps the estimate unbiased wherever the light
//! reaching the point has w > 0, as it has wherever a Lambertian lobe takes it. Only the
//! shadow ray of the kept sample is traced.
//!
//! The kept sample's density is no longer known, so glossy lobes, whose light samples are
//! weighed against their own sampling (MIS), keep one candidate
//! ([`crate::buffers::SppmParams::light_candidates`] applies to Lambertian-only points).

use glam::Vec3;

use crate::buffers::{LIGHT_TRIANGLE, Light};
use crate::direct::{LightSample, sample_light};

/// Candidates per light sample at a Lambertian-only visible point where the scene's lights
/// differ in place or facing (`kousen render --light-candidates auto`, [`auto_candidates`]);
/// docs/BENCHMARKS.md §3 (session 36) measures the choice.
pub const DEFAULT_LIGHT_CANDIDATES: u32 = 8;

/// The candidates `auto` takes for `scene`: one where its only light is one flat one-sided
/// emitter (a Cornell box's ceiling quad: every candidate faces every receiver alike, and
/// weighing points on it by distance and cosine gained nothing measurable in whole images
/// while the eye pass cost 8–15 % more; a lone punctual light or sky takes one anyway, see
/// [`resample_light`]), else [`DEFAULT_LIGHT_CANDIDATES`].
pub fn auto_candidates(scene: &scene::Scene) -> u32 {
    let lights = &scene.lights;
    if !lights.punctual.is_empty() || lights.sky.is_some() || lights.triangles.is_empty() {
        return DEFAULT_LIGHT_CANDIDATES;
    }
    let triangle = |index: u32| &scene.triangles[index as usize];
    let first = triangle(lights.triangles[0].triangle);
    let normal = first.geometric_normal_unnormalized().normalize_or_zero();
    let origin = first.vertices[0].position;
    let size = scene.bounds().extent().length().max(f32::MIN_POSITIVE);
    let flat_and_alike = lights.triangles.iter().all(|l| {
        let t = triangle(l.triangle);
        let facing = t.geometric_normal_unnormalized().normalize_or_zero();
        !scene.materials[t.material as usize].double_sided
            && facing.dot(normal) > 1.0 - 1e-5
            && (t.positions().iter()).all(|p| (*p - origin).dot(normal).abs() <= 1e-5 * size)
    });
    if flat_and_alike {
        1
    } else {
        DEFAULT_LIGHT_CANDIDATES
    }
}

/// Most candidates a light sample may draw.
pub const MAX_LIGHT_CANDIDATES: u32 = 64;

/// Rec. 709 luminance of linear RGB: how candidates are weighed.
pub fn luminance(rgb: Vec3) -> f32 {
    rgb.dot(Vec3::new(0.2126, 0.7152, 0.0722))
}

/// A candidate's weight seen from a receiver facing `normal` (unit): what it brings
/// unoccluded to a Lambertian lobe, per its density.
pub fn candidate_weight(sample: &LightSample, normal: Vec3) -> f32 {
    luminance(sample.incident) * sample.direction.dot(normal).max(0.0)
}

/// One light sample at `position` facing `normal` from `candidates` (at least 1) drawn by
/// [`sample_light`]: the one kept, its `incident` scaled as the module says; `None` where no
/// candidate brings anything. `next` gives uniform numbers: three per candidate, and one more
/// for each candidate after the first (whether to keep it), drawn for every candidate so the
/// count is fixed. With one candidate, or a table of one light that is not a triangle, this is
/// [`sample_light`] itself.
pub fn resample_light(
    lights: &[Light],
    sky_map: &[f32],
    candidates: u32,
    position: Vec3,
    normal: Vec3,
    mut next: impl FnMut() -> f32,
) -> Option<LightSample> {
    let draw = |next: &mut dyn FnMut() -> f32| [next(), next(), next()];
    if candidates <= 1 || is_lone_non_triangle(lights) {
        return sample_light(lights, sky_map, draw(&mut next), position, normal);
    }
    let mut kept: Option<(LightSample, f32)> = None;
    let mut total = 0.0f32;
    for i in 0..candidates {
        let sample = sample_light(lights, sky_map, draw(&mut next), position, normal);
        let u_keep = if i == 0 { 0.0 } else { next() };
        let Some(sample) = sample else {
            continue;
        };
        let weight = candidate_weight(&sample, normal);
        if !(weight > 0.0 && weight <= f32::MAX) {
            continue;
        }
        total += weight;
        // Kept with probability weight / total (the first with weight, always).
        if u_keep * total < weight {
            kept = Some((sample, weight));
        }
    }
    let (mut sample, weight) = kept?;
    sample.incident *= total / (candidates as f32 * weight);
    Some(sample)
}

/// Whether the table is one point, spot or directional light or the sky alone: its candidates
/// would be the same light (a sky's directions are drawn by its own importance already), so
/// resampling would cost and bring nothing (measured: a sky map alone, +34 % time, the same
/// noise; docs/BENCHMARKS.md §3, session 36).
fn is_lone_non_triangle(lights: &[Light]) -> bool {
    matches!(lights, [light] if light.kind != LIGHT_TRIANGLE)
}

#[cfg(test)]
mod tests {
    use std::f32::consts::PI;

    use super::*;
    use crate::buffers::{LIGHT_POINT, vec3};
    use crate::rng::stream_key;
    use crate::sky_map::NO_SKY_MAP;

    fn uniform(seed: u32, index: u32, draw: u32) -> f32 {
        (stream_key(seed, 0, index, draw) >> 8) as f32 / (1u32 << 24) as f32
    }

    /// A one-sided square emitter of side 1 centred at `centre`, emitting along `normal`
    /// (`normal` along an axis), as two triangles of the light table, radiance `radiance`.
    fn square(centre: Vec3, normal: Vec3, radiance: f32) -> [Light; 2] {
        let (mut a, mut b) = crate::sampling::orthonormal_basis(normal);
        // Emitting along edge1 × edge2, as the light table's triangles do.
        if a.cross(b).dot(normal) < 0.0 {
            std::mem::swap(&mut a, &mut b);
        }
        let corner = |s: f32, t: f32| centre + (s - 0.5) * a + (t - 0.5) * b;
        let flux = radiance * PI * 0.5;
        let triangle = |p: Vec3, q: Vec3, r: Vec3| Light {
            kind: LIGHT_TRIANGLE,
            v0: p.to_array(),
            edge1: (q - p).to_array(),
            edge2: (r - p).to_array(),
            flux: [flux; 3],
            ..Light::default()
        };
        [
            triangle(corner(0.0, 0.0), corner(1.0, 0.0), corner(1.0, 1.0)),
            triangle(corner(0.0, 0.0), corner(1.0, 1.0), corner(0.0, 1.0)),
        ]
    }

    /// A table of lights with power-proportional picks (`flux` ÷ pick, as the table keeps).
    fn table(lights: &[Light]) -> Vec<Light> {
        let total: f32 = lights.iter().map(|l| l.flux[0]).sum();
        let mut cdf = 0.0;
        lights
            .iter()
            .map(|l| {
                let pick = l.flux[0] / total;
                cdf += pick;
                Light {
                    flux: vec3(l.flux).map(|f| f / pick).to_array(),
                    cdf,
                    ..*l
                }
            })
            .collect()
    }

    /// Mean and standard error of the irradiance at the origin (normal +z) estimated with
    /// `candidates`, over `n` samples of seed `seed`.
    fn irradiance(lights: &[Light], candidates: u32, n: u32, seed: u32) -> (f64, f64) {
        let (mut sum, mut sum_squares) = (0.0f64, 0.0f64);
        for i in 0..n {
            let mut draw = 0;
            let next = || {
                draw += 1;
                uniform(seed, i, draw)
            };
            let value = resample_light(lights, &NO_SKY_MAP, candidates, Vec3::ZERO, Vec3::Z, next)
                .map_or(0.0, |s| (s.incident.x * s.direction.z.max(0.0)) as f64);
            sum += value;
            sum_squares += value * value;
        }
        let mean = sum / n as f64;
        let variance = (sum_squares / n as f64 - mean * mean).max(0.0);
        (mean, (variance / n as f64).sqrt())
    }

    /// One lamp above the receiver facing it, an equally bright one below it facing it (behind
    /// the receiver) and a brighter one above turned away: the estimate's mean stays that of
    /// one candidate (unbiased) while its error falls by about √M, since candidates that bring
    /// nothing are never kept.
    #[test]
    fn resampling_keeps_the_mean_and_drops_hidden_lights() {
        let lights = table(
            &[
                square(Vec3::new(0.0, 0.0, 1.0), -Vec3::Z, 1.0),
                square(Vec3::new(0.3, 0.0, -1.0), Vec3::Z, 1.0),
                square(Vec3::new(0.0, 0.2, 2.0), Vec3::Z, 3.0),
            ]
            .concat(),
        );
        let n = 1 << 17;
        let (plain, plain_error) = irradiance(&lights, 1, n, 1);
        let (resampled, resampled_error) = irradiance(&lights, 8, n, 2);
        let difference = (plain - resampled).abs();
        let error = (plain_error * plain_error + resampled_error * resampled_error).sqrt();
        assert!(
            difference < 4.0 * error,
            "plain {plain} ± {plain_error}, resampled {resampled} ± {resampled_error}"
        );
        assert!(
            resampled_error < 0.4 * plain_error,
            "{resampled_error} vs {plain_error}"
        );
    }

    #[test]
    fn one_candidate_is_the_plain_sample() {
        let lights = table(&square(Vec3::new(0.2, 0.1, 1.0), -Vec3::Z, 2.0));
        for i in 0..64 {
            let u = [1, 2, 3].map(|d| uniform(5, i, d));
            let mut draw = 0;
            let resampled = resample_light(&lights, &NO_SKY_MAP, 1, Vec3::ZERO, Vec3::Z, || {
                draw += 1;
                uniform(5, i, draw)
            });
            assert_eq!(
                resampled,
                sample_light(&lights, &NO_SKY_MAP, u, Vec3::ZERO, Vec3::Z)
            );
            assert_eq!(draw, 3);
        }
    }

    #[test]
    fn auto_takes_one_candidate_for_a_lone_flat_emitter_only() {
        use scene::testing;
        assert_eq!(auto_candidates(&testing::cornell_box()), 1);
        assert_eq!(auto_candidates(&testing::cornell_caustics()), 1);
        // A bulb besides the ceiling quad; a spot light besides it.
        let several = DEFAULT_LIGHT_CANDIDATES;
        assert_eq!(auto_candidates(&testing::cornell_translucent()), several);
        assert_eq!(auto_candidates(&testing::cornell_spot()), several);
        // The quad emitting from both faces: receivers above it see it too.
        let mut both_faces = testing::cornell_box();
        for material in &mut both_faces.materials {
            material.double_sided |= material.is_emissive();
        }
        assert_eq!(auto_candidates(&both_faces), several);
    }

    #[test]
    fn a_lone_punctual_light_is_sampled_once() {
        let point = Light {
            kind: LIGHT_POINT,
            v0: [0.0, 1.0, 0.0],
            flux: [1.0; 3],
            cdf: 1.0,
            ..Light::default()
        };
        let mut draw = 0;
        let kept = resample_light(&[point], &NO_SKY_MAP, 8, Vec3::ZERO, Vec3::Y, || {
            draw += 1;
            0.5
        });
        assert!(kept.is_some());
        assert_eq!(draw, 3);
    }

    #[test]
    fn a_fixed_count_of_numbers_is_drawn() {
        // Every candidate behind the receiver: nothing kept, all 4M − 1 numbers drawn.
        let lights = table(&square(Vec3::new(0.0, 0.0, -1.0), -Vec3::Z, 1.0));
        let mut draw = 0;
        let kept = resample_light(&lights, &NO_SKY_MAP, 5, Vec3::ZERO, Vec3::Z, || {
            draw += 1;
            0.5
        });
        assert!(kept.is_none());
        assert_eq!(draw, 4 * 5 - 1);
    }
}
