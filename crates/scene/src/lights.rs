//! The light list: every emissive triangle with its area and power.

use glam::Vec3;

use crate::{Material, Texture, Triangle};

/// One emissive triangle.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EmissiveTriangle {
    /// Index into [`crate::Scene::triangles`].
    pub triangle: u32,
    pub area: f32,
    /// Emitted flux per RGB channel: radiance × area × π (a Lambertian emitter), twice that
    /// when the material emits from both faces. A textured emitter uses the texture's mean.
    pub power: Vec3,
}

#[derive(Clone, Debug, Default, PartialEq)]
pub struct Lights {
    pub triangles: Vec<EmissiveTriangle>,
    pub total_power: Vec3,
}

impl Lights {
    /// Collects the emissive triangles of a scene.
    pub fn collect(triangles: &[Triangle], materials: &[Material], textures: &[Texture]) -> Lights {
        // Only emission textures need their mean, and computing one is not free.
        let mut texture_means: Vec<Option<Vec3>> = vec![None; textures.len()];
        let mut mean = |t: u32| {
            *texture_means[t as usize]
                .get_or_insert_with(|| textures[t as usize].mean_linear().truncate())
        };
        let mut lights = Lights::default();
        for (index, triangle) in triangles.iter().enumerate() {
            let material = &materials[triangle.material as usize];
            let mut radiance = material.emission;
            if let Some(t) = material.emission_texture {
                radiance *= mean(t);
            }
            if radiance.max_element() <= 0.0 {
                continue;
            }
            let area = triangle.area();
            let faces = if material.double_sided { 2.0 } else { 1.0 };
            let power = radiance * area * std::f32::consts::PI * faces;
            lights.total_power += power;
            lights.triangles.push(EmissiveTriangle {
                triangle: index as u32,
                area,
                power,
            });
        }
        lights
    }

    /// Total power as one number: the mean of the three channels.
    pub fn total_power_scalar(&self) -> f32 {
        self.total_power.element_sum() / 3.0
    }
}
