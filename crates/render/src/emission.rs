//! Where photon paths start: a table of the scene's lights with a CDF proportional to power.
//! - an emissive triangle: a uniform point on it, a cosine-distributed direction from its
//!   emitting face (either face, with even odds, for a double-sided emitter);
//! - a point light: its position, a uniform direction over the sphere;
//! - a spot light: its position, a uniform direction in its outer cone, the flux weighted by
//!   the falloff at that direction;
//! - a directional light: a uniform point across the scene upstream of it, travelling in the
//!   light's direction: on the bounding sphere's disk or, where smaller, on the rectangle
//!   bounding the shadow of the scene's box ([`parallel_start`]);
//! - the sky: a uniform direction over the sphere, then as a directional light that way.

use std::f32::consts::PI;

use glam::Vec3;
use scene::{PunctualEmitter, PunctualKind, Scene, SpotFalloff};

use crate::buffers::{
    LIGHT_DIRECTIONAL, LIGHT_POINT, LIGHT_SKY, LIGHT_SPOT, LIGHT_TRIANGLE, Light, vec3,
};
use crate::sampling::{
    about_axis, cosine_hemisphere, orthonormal_basis, uniform_cone, uniform_disk,
};
use crate::sky_map::{sample_sky_map, sky_photon_flux};

/// The light table of a scene, in CDF order: emissive triangles, punctual lights, the sky, each
/// with the solid its paths start in (`crate::medium`). Empty if nothing emits. A textured emitter is taken at its texture's mean (scene::Lights does the
/// same for power).
pub fn light_table(scene: &Scene) -> Vec<Light> {
    light_table_with(scene, &crate::medium::MediumLocator::new(scene))
}

/// [`light_table`] with the scene's `locator` built already (one build serves a render).
pub fn light_table_with(scene: &Scene, locator: &crate::medium::MediumLocator) -> Vec<Light> {
    let weight = pick_weight;
    let triangles = scene.lights.triangles.iter().map(|l| {
        let triangle = &scene.triangles[l.triangle as usize];
        let [p0, p1, p2] = triangle.positions();
        let material = &scene.materials[triangle.material as usize];
        let light = Light {
            v0: p0.to_array(),
            edge1: (p1 - p0).to_array(),
            double_sided: material.double_sided as u32,
            edge2: (p2 - p0).to_array(),
            kind: LIGHT_TRIANGLE,
            ..Light::default()
        };
        (light, l.power, l.power)
    });
    let punctual = scene.lights.punctual.iter().map(punctual_light);
    let sky = scene
        .lights
        .sky
        .iter()
        .map(|sky| (crate::sky_map::sky_light(sky), sky.power, sky.power));
    let lights: Vec<(Light, Vec3, Vec3)> = triangles
        .chain(punctual)
        .chain(sky)
        .filter(|(_, power, _)| weight(*power) > 0.0)
        .collect();
    let total: f64 = lights.iter().map(|(_, power, _)| weight(*power)).sum();
    let mut running = 0.0;
    let mut table: Vec<Light> = lights
        .into_iter()
        .map(|(light, power, flux_if_certain)| {
            let probability = weight(power) / total;
            running += probability;
            Light {
                cdf: running as f32,
                flux: (flux_if_certain / probability as f32).to_array(),
                ..light
            }
        })
        .collect();
    if let Some(last) = table.last_mut() {
        last.cdf = 1.0;
    }
    // Where each light's paths start: a lamp may be inside water or glass.
    locator.set_light_media(&mut table);
    table
}

/// The scene triangle behind each of [`light_table`]'s triangle entries, in table order (they
/// come first): a renderer that samples the table can then read a textured emitter's
/// radiance at the point it drew, where the table holds the texture's mean.
pub fn light_table_triangles(scene: &Scene) -> Vec<u32> {
    scene
        .lights
        .triangles
        .iter()
        .filter(|l| pick_weight(l.power) > 0.0)
        .map(|l| l.triangle)
        .collect()
}

/// A light's share of the table's CDF before normalising: the sum of its power's channels.
fn pick_weight(power: Vec3) -> f64 {
    power.element_sum().max(0.0) as f64
}

/// Per material, the density per unit area with which light sampling ([`light_table`]'s CDF,
/// then a uniform point) lands on its triangles; 0 for materials that do not emit. The same
/// for every triangle of a material, since a triangle's pick is in proportion to its area:
/// what a path that meets an emitter by a BSDF's sampling weighs itself against (multiple
/// importance sampling), without a per-triangle table.
pub fn light_area_density(scene: &Scene) -> Vec<f32> {
    let lights = &scene.lights;
    let total: f64 = lights
        .triangles
        .iter()
        .map(|l| pick_weight(l.power))
        .sum::<f64>()
        + lights
            .punctual
            .iter()
            .map(|p| pick_weight(p.power))
            .sum::<f64>()
        + lights.sky.iter().map(|s| pick_weight(s.power)).sum::<f64>();
    let mut density = vec![0.0; scene.materials.len()];
    for light in &lights.triangles {
        let material = scene.triangles[light.triangle as usize].material as usize;
        if light.area > 0.0 && total > 0.0 {
            density[material] = (pick_weight(light.power) / (total * light.area as f64)) as f32;
        }
    }
    density
}

/// A punctual light's table entry (cdf and flux still to be set), its power, and the flux its
/// photons carry were it the only light: its power, except for a spot, whose photons are
/// spread uniformly over the whole outer cone and weighted by the falloff.
fn punctual_light(emitter: &PunctualEmitter) -> (Light, Vec3, Vec3) {
    let light = &emitter.light;
    let (kind, edge1, edge2, flux_if_certain) = match light.kind {
        PunctualKind::Point => (LIGHT_POINT, Vec3::ZERO, Vec3::ZERO, emitter.power),
        PunctualKind::Spot {
            cos_inner,
            cos_outer,
            falloff,
        } => {
            let cone = std::f32::consts::TAU * (1.0 - cos_outer);
            let edge2 = Vec3::new(cos_inner, cos_outer, falloff.code());
            (LIGHT_SPOT, light.direction, edge2, light.intensity * cone)
        }
        PunctualKind::Directional => (
            LIGHT_DIRECTIONAL,
            light.direction,
            Vec3::new(emitter.radius, 0.0, 0.0),
            emitter.power,
        ),
    };
    let entry = Light {
        v0: emitter.origin.to_array(),
        edge1: edge1.to_array(),
        edge2: edge2.to_array(),
        kind,
        ..Light::default()
    };
    (entry, emitter.power, flux_if_certain)
}

/// The start of a light path.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Emission {
    pub origin: Vec3,
    /// Unit normal of the emitting face; a punctual light's photon direction.
    pub normal: Vec3,
    pub direction: Vec3,
    pub flux: Vec3,
    /// The solid the path starts in (`Light::medium`).
    pub medium: u32,
}

/// Index of the light whose CDF interval holds `u` (a binary search, as the kernel does it).
pub fn pick_light(lights: &[Light], u: f32) -> usize {
    let (mut lo, mut hi) = (0usize, lights.len() - 1);
    while lo < hi {
        let mid = (lo + hi) / 2;
        if u < lights[mid].cdf {
            hi = mid;
        } else {
            lo = mid + 1;
        }
    }
    lo
}

/// A light path's start from five uniform numbers; `sky_map` is the sky's map
/// ([`crate::sky_map`]), `scene_half_extent` [`crate::buffers::SppmParams::scene_half_extent`].
/// `lights` must not be empty.
pub fn sample_emission(
    lights: &[Light],
    sky_map: &[f32],
    scene_half_extent: Vec3,
    u: [f32; 5],
) -> Emission {
    let index = pick_light(lights, u[0]);
    let light = &lights[index];
    let emission = match light.kind {
        LIGHT_POINT => {
            let direction = uniform_cone(u[3], u[4], -1.0);
            emission_along(vec3(light.v0), direction, vec3(light.flux))
        }
        LIGHT_SPOT => {
            let axis = vec3(light.edge1);
            let [cos_inner, cos_outer, shape] = light.edge2;
            let local = uniform_cone(u[3], u[4], cos_outer);
            let direction = about_axis(axis, local).normalize();
            let shape = SpotFalloff::from_code(shape);
            let falloff = scene::lights::spot_falloff(local.z, cos_inner, cos_outer, shape);
            emission_along(vec3(light.v0), direction, falloff * vec3(light.flux))
        }
        LIGHT_DIRECTIONAL => {
            let direction = vec3(light.edge1);
            let radius = light.edge2[0];
            let (origin, share) = parallel_start(
                vec3(light.v0),
                radius,
                scene_half_extent,
                direction,
                u[1],
                u[2],
            );
            emission_along(origin, direction, vec3(light.flux) * share)
        }
        LIGHT_SKY => {
            // A map's direction by its importance, else a uniform one; photons travel
            // against the direction the sky is seen along.
            let (direction, flux) = match crate::sky_map::MapFrame::of(light) {
                Some(frame) => match sample_sky_map(
                    &frame,
                    sky_map,
                    u[3],
                    u[4],
                    frame.map_upper_share(sky_map),
                ) {
                    Some(s) => {
                        let pick = crate::direct::pick_probability(lights, index);
                        (-s.direction, sky_photon_flux(light, &s, pick))
                    }
                    None => (Vec3::Y, Vec3::ZERO),
                },
                None => (uniform_cone(u[3], u[4], -1.0), vec3(light.flux)),
            };
            let radius = light.edge2[0];
            // Two radii upstream of the sphere's centre, outside it.
            let centre = vec3(light.v0) - 2.0 * radius * direction;
            let (origin, share) =
                parallel_start(centre, radius, scene_half_extent, direction, u[1], u[2]);
            emission_along(origin, direction, flux * share)
        }
        _ => triangle_emission(light, u),
    };
    Emission {
        medium: light.medium,
        ..emission
    }
}

/// Where a photon of parallel light (a directional light's, or the sky's along one direction)
/// starts, from two uniform numbers: a uniform point of the region across `direction` about
/// `centre` that its flux was counted over, the bounding sphere's disk of `radius`, or, where
/// smaller, the rectangle bounding the shadow of the scene's box (`half_extent` about the
/// sphere's centre; zero: none). Both cover every surface the light can reach, so either is
/// unbiased; the rectangle wastes fewer photons past a flat or long scene (an open floor under
/// a low sun: a third of the disk). Returns the point and the region's area over the disk's,
/// the factor the flux (counted over the disk) takes.
pub fn parallel_start(
    centre: Vec3,
    radius: f32,
    half_extent: Vec3,
    direction: Vec3,
    u1: f32,
    u2: f32,
) -> (Vec3, f32) {
    let (t, b) = orthonormal_basis(direction);
    let reach = |axis: Vec3| axis.abs().dot(half_extent);
    let (across_t, across_b) = (reach(t), reach(b));
    let share = 4.0 * across_t * across_b / (PI * radius * radius);
    if half_extent == Vec3::ZERO || share.is_nan() || share >= 1.0 {
        return (disk_point(centre, radius, direction, u1, u2), 1.0);
    }
    let point = centre + t * ((2.0 * u1 - 1.0) * across_t) + b * ((2.0 * u2 - 1.0) * across_b);
    (point, share)
}

/// A uniform point on the disk of `radius` about `centre` perpendicular to `direction`.
fn disk_point(centre: Vec3, radius: f32, direction: Vec3, u1: f32, u2: f32) -> Vec3 {
    let (t, b) = orthonormal_basis(direction);
    let disk = radius * uniform_disk(u1, u2);
    centre + t * disk.x + b * disk.y
}

fn emission_along(origin: Vec3, direction: Vec3, flux: Vec3) -> Emission {
    Emission {
        origin,
        normal: direction,
        direction,
        flux,
        // sample_emission sets the light's own.
        medium: crate::medium::NO_MEDIUM,
    }
}

/// A uniform point on a triangle light from two uniform numbers (the unit square folded onto
/// the triangle's barycentrics).
pub fn triangle_point(light: &Light, u1: f32, u2: f32) -> Vec3 {
    let (b1, b2) = triangle_barycentrics(u1, u2);
    vec3(light.v0) + b1 * vec3(light.edge1) + b2 * vec3(light.edge2)
}

/// The barycentrics of the second and third vertex of [`triangle_point`]'s point: the unit
/// square folded onto the triangle.
pub fn triangle_barycentrics(u1: f32, u2: f32) -> (f32, f32) {
    if u1 + u2 > 1.0 {
        (1.0 - u1, 1.0 - u2)
    } else {
        (u1, u2)
    }
}

fn triangle_emission(light: &Light, u: [f32; 5]) -> Emission {
    let origin = triangle_point(light, u[1], u[2]);
    let mut normal = vec3(light.edge1).cross(vec3(light.edge2)).normalize();
    // A double-sided light picks its face with the lowest bit of the direction's first number.
    let mut u3 = u[3];
    if light.double_sided != 0 {
        u3 *= 2.0;
        if u3 >= 1.0 {
            u3 -= 1.0;
            normal = -normal;
        }
    }
    Emission {
        origin,
        normal,
        direction: about_axis(normal, cosine_hemisphere(u3, u[4])).normalize(),
        flux: vec3(light.flux),
        medium: light.medium,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every emissive triangle's pick probability over its area is its material's density,
    /// with a sky in the table too.
    #[test]
    fn area_density_is_each_triangles_pick_over_its_area() {
        let mut scene = scene::testing::cornell_box();
        let bounds = scene.bounds();
        scene.lights.set_sky(Vec3::splat(0.3), bounds);
        let table = light_table(&scene);
        let density = light_area_density(&scene);
        let mut checked = 0;
        for (index, light) in scene.lights.triangles.iter().enumerate() {
            let pick = crate::direct::pick_probability(&table, index);
            let material = scene.triangles[light.triangle as usize].material as usize;
            let expected = pick / light.area;
            assert!(
                (density[material] - expected).abs() < 1e-4 * expected,
                "{} against {expected}",
                density[material]
            );
            checked += 1;
        }
        assert!(checked > 0);
        let emissive = |m: &scene::Material| m.emission.max_element() > 0.0;
        for (material, d) in scene.materials.iter().zip(&density) {
            assert_eq!(*d > 0.0, emissive(material));
        }
    }

    /// The scene triangle named for each triangle entry is the one the entry was made from,
    /// and a point drawn on the entry has the barycentrics `triangle_barycentrics` gives.
    #[test]
    fn table_triangles_name_each_entry_s_triangle() {
        let scene = scene::testing::cornell_box_punctual();
        let table = light_table(&scene);
        let triangles = light_table_triangles(&scene);
        let entries = table.iter().filter(|l| l.kind == LIGHT_TRIANGLE).count();
        assert!(entries > 0 && entries < table.len());
        assert_eq!(triangles.len(), entries);
        for (light, &id) in table.iter().zip(&triangles) {
            assert_eq!(light.kind, LIGHT_TRIANGLE);
            let [p0, p1, p2] = scene.triangles[id as usize].positions();
            assert_eq!(vec3(light.v0), p0);
            for (u1, u2) in [(0.2, 0.3), (0.9, 0.7)] {
                let (b1, b2) = triangle_barycentrics(u1, u2);
                let expected = (1.0 - b1 - b2) * p0 + b1 * p1 + b2 * p2;
                let drawn = triangle_point(light, u1, u2);
                assert!(
                    (drawn - expected).length() < 1e-3,
                    "{drawn} against {expected}"
                );
            }
        }
    }

    #[test]
    fn table_flux_times_probability_is_power() {
        let scene = scene::testing::cornell_box();
        let table = light_table(&scene);
        assert!(!table.is_empty());
        assert_eq!(table.last().unwrap().cdf, 1.0);
        let mut previous = 0.0;
        let mut total = Vec3::ZERO;
        for light in &table {
            let probability = light.cdf - previous;
            previous = light.cdf;
            total += vec3(light.flux) * probability;
        }
        let expected = scene.lights.total_power;
        assert!((total - expected).abs().max_element() < 1e-3 * expected.max_element());
    }

    /// The rectangle covers the shadow of every corner of the box across any direction (so
    /// no surface goes unlit), its points fill it uniformly, and over a flat box lit from low
    /// it is a fraction of the bounding disk; over a cube the disk is kept where smaller.
    #[test]
    fn parallel_light_starts_over_the_scene_boxs_shadow() {
        let half = Vec3::new(2.0, 0.3, 2.0);
        let radius = half.length() * 1.01;
        let centre = Vec3::new(1.0, 0.3, -2.0);
        for i in 0..200 {
            let f = |k: u32| ((i * 7919 + k * 104_729) % 1000) as f32 / 1000.0;
            let direction = uniform_cone(f(0), f(1), -1.0);
            let (t, b) = orthonormal_basis(direction);
            let (_, share) = parallel_start(centre, radius, half, direction, 0.5, 0.5);
            assert!(share > 0.0 && share <= 1.0, "{share}");
            // The rectangle's corners, against each box corner's offset across `direction`.
            let (low, _) = parallel_start(centre, radius, half, direction, 0.0, 0.0);
            let (high, _) = parallel_start(centre, radius, half, direction, 1.0, 1.0);
            for corner in 0..8 {
                let sign = |bit: u32| if corner & bit == 0 { -1.0 } else { 1.0 };
                let offset = Vec3::new(sign(1) * half.x, sign(2) * half.y, sign(4) * half.z);
                if share < 1.0 {
                    for axis in [t, b] {
                        let (lo, hi) = ((low - centre).dot(axis), (high - centre).dot(axis));
                        let at = offset.dot(axis);
                        assert!(
                            lo <= at + 1e-4 && at <= hi + 1e-4,
                            "{direction}: {at} outside {lo}..{hi}"
                        );
                    }
                }
            }
        }
        // Low over the flat box: the rectangle, about a third of the disk.
        let low_sun = Vec3::new(0.0, -0.34, 0.94).normalize();
        let (_, share) = parallel_start(centre, radius, half, low_sun, 0.3, 0.6);
        assert!(share > 0.2 && share < 0.45, "{share}");
        // A cube seen along its diagonal: the disk is no larger, and is kept.
        let cube = Vec3::ONE;
        let diagonal = Vec3::ONE.normalize();
        let (_, share) = parallel_start(centre, cube.length(), cube, diagonal, 0.3, 0.6);
        assert_eq!(share, 1.0);
        // No box known: the disk.
        assert_eq!(
            parallel_start(centre, radius, Vec3::ZERO, low_sun, 0.3, 0.6).1,
            1.0
        );
    }

    #[test]
    fn emission_leaves_the_front_face() {
        let scene = scene::testing::cornell_box();
        let table = light_table(&scene);
        for i in 0..200 {
            let f = |k: u32| ((i * 7919 + k * 104_729) % 1000) as f32 / 1000.0;
            let e = sample_emission(
                &table,
                &crate::sky_map::NO_SKY_MAP,
                Vec3::ZERO,
                [f(0), f(1), f(2), f(3), f(4)],
            );
            assert!(e.direction.dot(e.normal) >= 0.0);
            assert!((e.direction.length() - 1.0).abs() < 1e-5);
        }
    }

    /// `light` alone over the punctual plane: its scene and `count` emissions drawn with a
    /// xorshift generator.
    fn emissions(light: scene::PunctualLight, count: u32) -> (Scene, Vec<Emission>) {
        let scene = scene::testing::punctual_plane(&[light]);
        let table = light_table(&scene);
        assert_eq!(table.len(), 1, "one light");
        let mut state = 0x9e37_79b9u32;
        let mut next = || {
            state ^= state << 13;
            state ^= state >> 17;
            state ^= state << 5;
            (state >> 8) as f32 / (1u32 << 24) as f32
        };
        let samples = (0..count)
            .map(|_| {
                sample_emission(
                    &table,
                    &crate::sky_map::NO_SKY_MAP,
                    Vec3::ZERO,
                    [(); 5].map(|_| next()),
                )
            })
            .collect();
        (scene, samples)
    }

    fn mean_flux(samples: &[Emission]) -> Vec3 {
        let sum: glam::DVec3 = samples.iter().map(|e| e.flux.as_dvec3()).sum();
        (sum / samples.len() as f64).as_vec3()
    }

    #[test]
    fn point_light_emits_its_power_uniformly() {
        let light = scene::PunctualLight {
            kind: PunctualKind::Point,
            position: Vec3::new(0.0, 1.0, 0.0),
            direction: Vec3::ZERO,
            intensity: Vec3::new(1.0, 2.0, 3.0),
        };
        let (scene, samples) = emissions(light, 100_000);
        let power = scene.lights.total_power;
        let off = |e: &Emission| (e.flux - power).abs().max_element() / power.max_element();
        assert!(
            samples.iter().all(|e| off(e) < 1e-6),
            "every photon carries the power"
        );
        let mean_direction = samples.iter().map(|e| e.direction).sum::<Vec3>() / 1e5;
        assert!(mean_direction.length() < 0.01, "{mean_direction}");
        assert!(samples.iter().all(|e| e.origin == light.position));
        assert!(
            samples
                .iter()
                .all(|e| (e.direction.length() - 1.0).abs() < 1e-5)
        );
    }

    /// For each format's falloff between the cones (`scene::SpotFalloff`).
    #[test]
    fn spot_light_emits_its_power_inside_its_outer_cone() {
        let (cos_inner, cos_outer) = (0.9, 0.7);
        let axis = Vec3::new(0.3, -1.0, 0.1).normalize();
        let shapes = [
            SpotFalloff::Gltf,
            SpotFalloff::Smoothstep,
            SpotFalloff::LinearAngle,
        ];
        for falloff in shapes {
            let light = scene::PunctualLight {
                kind: PunctualKind::Spot {
                    cos_inner,
                    cos_outer,
                    falloff,
                },
                position: Vec3::new(0.0, 1.0, 0.0),
                direction: axis,
                intensity: Vec3::splat(5.0),
            };
            let (scene, samples) = emissions(light, 200_000);
            // The falloff's weights average out to the power (Monte Carlo: about 0.2% noise).
            let power = scene.lights.total_power;
            let mean = mean_flux(&samples);
            assert!(
                (mean.x / power.x - 1.0).abs() < 0.01,
                "{falloff:?}: {mean} against {power}"
            );
            let cosines = samples.iter().map(|e| e.direction.dot(axis));
            assert!(cosines.clone().all(|c| c >= cos_outer - 1e-5));
            // Inside the inner cone a photon carries the full intensity × the outer cone's
            // solid angle.
            let full = 5.0 * std::f32::consts::TAU * (1.0 - cos_outer);
            for (e, c) in samples.iter().zip(cosines) {
                if c > cos_inner + 1e-4 {
                    assert!((e.flux.x / full - 1.0).abs() < 1e-5);
                }
            }
        }
    }

    #[test]
    fn directional_light_crosses_the_scene_from_upstream() {
        let direction = Vec3::new(0.6, -0.8, 0.0);
        let light = scene::PunctualLight {
            kind: PunctualKind::Directional,
            position: Vec3::ZERO,
            direction,
            intensity: Vec3::splat(1.5),
        };
        let (scene, samples) = emissions(light, 50_000);
        let bounds = scene.bounds();
        let (centre, radius) = (bounds.center(), 0.5 * bounds.extent().length());
        let power = scene.lights.total_power;
        let off = |e: &Emission| (e.flux - power).abs().max_element() / power.max_element();
        assert!(
            samples.iter().all(|e| off(e) < 1e-6),
            "every photon carries the power"
        );
        for e in &samples {
            assert_eq!(e.direction, direction);
            let offset = e.origin - centre;
            // Upstream of the bounding sphere, and within the disk that covers it.
            assert!(offset.dot(direction) <= -radius);
            let lateral = offset - offset.dot(direction) * direction;
            assert!(lateral.length() <= 1.02 * radius);
        }
        // The disk is covered uniformly: a quarter of the photons within half its radius.
        let disk_radius = scene.lights.punctual[0].radius;
        let inner = samples
            .iter()
            .filter(|e| {
                let o = e.origin - scene.lights.punctual[0].origin;
                o.length() < 0.5 * disk_radius
            })
            .count() as f64
            / samples.len() as f64;
        assert!((inner - 0.25).abs() < 0.01, "{inner}");
    }

    #[test]
    fn pick_follows_the_cdf() {
        let light = |cdf| Light {
            cdf,
            ..Light::default()
        };
        let table = [light(0.25), light(0.5), light(1.0)];
        assert_eq!(pick_light(&table, 0.0), 0);
        assert_eq!(pick_light(&table, 0.25), 1);
        assert_eq!(pick_light(&table, 0.49), 1);
        assert_eq!(pick_light(&table, 0.999), 2);
    }
}
