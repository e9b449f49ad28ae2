//! Picking a point on the scene's lights, proportional to power (a CDF over the emissive
//! triangles), for next-event estimation.

use glam::{Vec2, Vec3};
use scene::Scene;

pub struct LightSampler {
    /// Cumulative power, normalised so the last entry is 1.
    cdf: Vec<f32>,
    /// `selection[triangle]` = probability of picking that scene triangle (0 if not a light).
    selection: Vec<f32>,
}

/// A point sampled on a light.
pub struct LightSample {
    pub triangle: u32,
    pub position: Vec3,
    /// Unit geometric normal of the light's front face.
    pub normal: Vec3,
    pub uv: Vec2,
    /// Density with respect to area on the light.
    pub pdf_area: f32,
}

impl LightSampler {
    pub fn new(scene: &Scene) -> LightSampler {
        let lights = &scene.lights.triangles;
        let weight = |l: &scene::EmissiveTriangle| l.power.element_sum().max(0.0);
        let total: f32 = lights.iter().map(weight).sum();
        let mut selection = vec![0.0; scene.triangles.len()];
        let mut cdf = Vec::with_capacity(lights.len());
        let mut running = 0.0;
        for light in lights {
            let p = weight(light) / total;
            selection[light.triangle as usize] = p;
            running += p;
            cdf.push(running);
        }
        if let Some(last) = cdf.last_mut() {
            *last = 1.0;
        }
        LightSampler { cdf, selection }
    }

    /// Density (per area) with which [`LightSampler::sample`] returns a point on `triangle`.
    pub fn pdf_area(&self, scene: &Scene, triangle: u32) -> f32 {
        let p = self.selection[triangle as usize];
        if p == 0.0 {
            return 0.0;
        }
        p / scene.triangles[triangle as usize].area()
    }

    /// A light triangle by power, then a uniform point on it. `None` without lights.
    pub fn sample(&self, scene: &Scene, u: [f32; 3]) -> Option<LightSample> {
        let index = self
            .cdf
            .partition_point(|&c| c <= u[0])
            .min(self.cdf.len().checked_sub(1)?);
        let triangle = scene.lights.triangles[index].triangle;
        let t = &scene.triangles[triangle as usize];
        // Uniform barycentrics by folding the unit square.
        let (mut b1, mut b2) = (u[1], u[2]);
        if b1 + b2 > 1.0 {
            (b1, b2) = (1.0 - b1, 1.0 - b2);
        }
        let b0 = 1.0 - b1 - b2;
        let [a, b, c] = t.vertices;
        Some(LightSample {
            triangle,
            position: b0 * a.position + b1 * b.position + b2 * c.position,
            normal: t.geometric_normal_unnormalized().normalize(),
            uv: b0 * a.uv + b1 * b.uv + b2 * c.uv,
            pdf_area: self.pdf_area(scene, triangle),
        })
    }
}

/// The power heuristic (β = 2) weight of a strategy with density `a` against one with `b`.
/// Written as a ratio, so that an infinite `a` (a point light, which `b`'s strategy cannot
/// draw) weighs 1 and large densities do not overflow their squares.
pub fn power_heuristic(a: f32, b: f32) -> f32 {
    if a <= 0.0 {
        return 0.0;
    }
    let ratio = b / a;
    1.0 / (1.0 + ratio * ratio)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn selection_is_proportional_to_power_and_sums_to_one() {
        let scene = scene::testing::cornell_box();
        let sampler = LightSampler::new(&scene);
        let total: f32 = sampler.selection.iter().sum();
        assert!((total - 1.0).abs() < 1e-5);
        let power = scene.lights.total_power.element_sum();
        for light in &scene.lights.triangles {
            let expected = light.power.element_sum() / power;
            assert!((sampler.selection[light.triangle as usize] - expected).abs() < 1e-5);
        }
    }

    #[test]
    fn samples_lie_on_emissive_triangles() {
        let scene = scene::testing::cornell_box();
        let sampler = LightSampler::new(&scene);
        for i in 0..64 {
            let u = [
                i as f32 / 64.0,
                (i * 7 % 64) as f32 / 64.0,
                (i * 13 % 64) as f32 / 64.0,
            ];
            let s = sampler.sample(&scene, u).unwrap();
            let t = &scene.triangles[s.triangle as usize];
            assert!(scene.materials[t.material as usize].is_emissive());
            let [p0, _, _] = t.positions();
            assert!(
                (s.position - p0).dot(s.normal).abs() < 1e-2,
                "off the plane"
            );
            assert!(s.pdf_area > 0.0);
        }
    }
}
