//! Where photon paths start: a table of the emissive triangles with a CDF proportional to
//! power, a uniform point on the picked triangle, a cosine-distributed direction from its
//! emitting face (either face, with even odds, for a double-sided emitter).

use glam::Vec3;
use scene::Scene;

use crate::buffers::{Light, vec3};
use crate::sampling::{cosine_hemisphere, orthonormal_basis};

/// The light table of a scene, in CDF order. Empty if nothing emits. A textured emitter is
/// taken at its texture's mean (scene::Lights does the same for power).
pub fn light_table(scene: &Scene) -> Vec<Light> {
    let lights = &scene.lights.triangles;
    let weight = |l: &scene::EmissiveTriangle| l.power.element_sum().max(0.0) as f64;
    let total: f64 = lights.iter().map(weight).sum();
    if total <= 0.0 {
        return Vec::new();
    }
    let mut running = 0.0;
    let mut table: Vec<Light> = lights
        .iter()
        .filter(|l| weight(l) > 0.0)
        .map(|l| {
            let probability = weight(l) / total;
            running += probability;
            let triangle = &scene.triangles[l.triangle as usize];
            let [p0, p1, p2] = triangle.positions();
            let material = &scene.materials[triangle.material as usize];
            Light {
                v0: p0.to_array(),
                cdf: running as f32,
                edge1: (p1 - p0).to_array(),
                double_sided: material.double_sided as u32,
                edge2: (p2 - p0).to_array(),
                pad0: 0,
                flux: (l.power / probability as f32).to_array(),
                pad1: 0,
            }
        })
        .collect();
    if let Some(last) = table.last_mut() {
        last.cdf = 1.0;
    }
    table
}

/// The start of a light path.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Emission {
    pub origin: Vec3,
    /// Unit normal of the emitting face.
    pub normal: Vec3,
    pub direction: Vec3,
    pub flux: Vec3,
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

/// A light path's start from five uniform numbers. `lights` must not be empty.
pub fn sample_emission(lights: &[Light], u: [f32; 5]) -> Emission {
    let light = &lights[pick_light(lights, u[0])];
    let (mut b1, mut b2) = (u[1], u[2]);
    if b1 + b2 > 1.0 {
        (b1, b2) = (1.0 - b1, 1.0 - b2);
    }
    let (edge1, edge2) = (vec3(light.edge1), vec3(light.edge2));
    let origin = vec3(light.v0) + b1 * edge1 + b2 * edge2;
    let mut normal = edge1.cross(edge2).normalize();
    // A double-sided light picks its face with the lowest bit of the direction's first number.
    let mut u3 = u[3];
    if light.double_sided != 0 {
        u3 *= 2.0;
        if u3 >= 1.0 {
            u3 -= 1.0;
            normal = -normal;
        }
    }
    let (t, b) = orthonormal_basis(normal);
    let local = cosine_hemisphere(u3, u[4]);
    Emission {
        origin,
        normal,
        direction: (t * local.x + b * local.y + normal * local.z).normalize(),
        flux: vec3(light.flux),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

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

    #[test]
    fn emission_leaves_the_front_face() {
        let scene = scene::testing::cornell_box();
        let table = light_table(&scene);
        for i in 0..200 {
            let f = |k: u32| ((i * 7919 + k * 104_729) % 1000) as f32 / 1000.0;
            let e = sample_emission(&table, [f(0), f(1), f(2), f(3), f(4)]);
            assert!(e.direction.dot(e.normal) >= 0.0);
            assert!((e.direction.length() - 1.0).abs() < 1e-5);
        }
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
