//! An interim CPU path tracer, so that `kousen render` makes a correct image before the SPPM
//! integrator (issue 4) lands. It is deliberately plain: unidirectional paths, no light
//! sampling, Russian roulette after a few bounces. It reads the scene through the same packed
//! MTBVH and CPU traversal the GPU kernels will use, so it also exercises them end to end.

use glam::{Vec2, Vec3};
use rayon::prelude::*;
use scene::{AlphaMode, Camera, Material, Scene, Surface};

use crate::sampling::{Rng, cosine_hemisphere, orthonormal_basis};

/// What to render and how much.
pub struct RenderSettings {
    pub width: u32,
    pub height: u32,
    pub samples_per_pixel: u32,
    pub max_depth: u32,
    pub seed: u64,
}

/// A linear RGB image, rows top to bottom.
pub struct Image {
    pub width: u32,
    pub height: u32,
    pub pixels: Vec<Vec3>,
}

/// Surfaces a ray passes through (alpha cut-outs) count against this, not against the depth.
const MAX_PASS_THROUGH: u32 = 64;
/// Bounces before Russian roulette may end a path.
const ROULETTE_AFTER: u32 = 3;

pub struct PathTracer<'a> {
    scene: &'a Scene,
    bvh: &'a bvh::PackedBvh,
    camera: Camera,
    /// Offset of a continuation ray's origin, relative to the scene's size.
    epsilon: f32,
}

/// What the tracer needs to know about a hit.
struct SurfacePoint {
    position: Vec3,
    /// Unit geometric normal, front face.
    geometric: Vec3,
    /// Unit interpolated normal, front face.
    shading: Vec3,
    uv: Vec2,
    material: u32,
}

impl<'a> PathTracer<'a> {
    pub fn new(scene: &'a Scene, bvh: &'a bvh::PackedBvh, camera: Camera) -> Self {
        let epsilon = 1e-5 * scene.bounds().extent().length().max(1e-3);
        PathTracer {
            scene,
            bvh,
            camera,
            epsilon,
        }
    }

    /// Renders every pixel in parallel; the image depends only on the settings and the seed.
    pub fn render(&self, settings: &RenderSettings) -> Image {
        let (w, h) = (settings.width, settings.height);
        let pixels = (0..w * h)
            .into_par_iter()
            .map(|index| self.pixel(index % w, index / w, settings))
            .collect();
        Image {
            width: w,
            height: h,
            pixels,
        }
    }

    /// The box-filtered pixel: uniformly jittered sub-pixel positions, averaged.
    fn pixel(&self, x: u32, y: u32, settings: &RenderSettings) -> Vec3 {
        let pixel_index = (y as u64) * settings.width as u64 + x as u64;
        let mut rng = Rng::new(settings.seed, pixel_index);
        let aspect = settings.width as f32 / settings.height as f32;
        let mut sum = Vec3::ZERO;
        for _ in 0..settings.samples_per_pixel {
            let sx = ((x as f32 + rng.next_f32()) / settings.width as f32) * 2.0 - 1.0;
            let sy = 1.0 - ((y as f32 + rng.next_f32()) / settings.height as f32) * 2.0;
            let direction = self.camera.direction(sx, sy, aspect);
            sum += self.radiance(self.camera.eye, direction, settings.max_depth, &mut rng);
        }
        sum / settings.samples_per_pixel as f32
    }

    fn radiance(
        &self,
        mut origin: Vec3,
        mut direction: Vec3,
        max_depth: u32,
        rng: &mut Rng,
    ) -> Vec3 {
        let mut radiance = Vec3::ZERO;
        let mut throughput = Vec3::ONE;
        let (mut depth, mut passes) = (0, 0);
        while depth < max_depth {
            let Some(point) = self.intersect(origin, direction) else {
                break;
            };
            let material = &self.scene.materials[point.material as usize];
            let front = direction.dot(point.geometric) < 0.0;
            if self.cut_out(material, point.uv) && passes < MAX_PASS_THROUGH {
                passes += 1;
                origin = point.position + direction * self.epsilon;
                continue;
            }
            if front || material.double_sided {
                radiance += throughput * self.emission(material, point.uv);
            }
            let Some((next, weight)) = self.scatter(material, &point, direction, front, rng) else {
                break;
            };
            throughput *= weight;
            depth += 1;
            if depth > ROULETTE_AFTER {
                let survive = throughput.max_element().min(0.95);
                if rng.next_f32() >= survive {
                    break;
                }
                throughput /= survive;
            }
            // Leave the surface on the side the new direction goes.
            let side = if next.dot(point.geometric) > 0.0 {
                1.0
            } else {
                -1.0
            };
            origin = point.position + side * self.epsilon * point.geometric;
            direction = next;
        }
        radiance
    }

    fn intersect(&self, origin: Vec3, direction: Vec3) -> Option<SurfacePoint> {
        let ray = bvh::Ray {
            origin,
            direction,
            t_max: f32::INFINITY,
        };
        let hit = bvh::closest_hit_mtbvh(self.bvh, &ray)?;
        let id = self.bvh.triangle_ids[hit.triangle as usize];
        let triangle = &self.scene.triangles[id as usize];
        let [a, b, c] = triangle.vertices;
        let w = 1.0 - hit.u - hit.v;
        let shading = (w * a.normal + hit.u * b.normal + hit.v * c.normal)
            .try_normalize()
            .unwrap_or(Vec3::Y);
        Some(SurfacePoint {
            position: origin + hit.t * direction,
            geometric: triangle.geometric_normal_unnormalized().normalize(),
            shading,
            uv: w * a.uv + hit.u * b.uv + hit.v * c.uv,
            material: triangle.material,
        })
    }

    fn texture(&self, id: Option<u32>, uv: Vec2) -> glam::Vec4 {
        id.map_or(glam::Vec4::ONE, |t| {
            self.scene.textures[t as usize].sample_nearest(uv.x, uv.y)
        })
    }

    fn cut_out(&self, material: &Material, uv: Vec2) -> bool {
        match material.alpha_mode {
            AlphaMode::Opaque => false,
            AlphaMode::Mask { cutoff } => {
                material.alpha * self.texture(material.base_color_texture, uv).w < cutoff
            }
        }
    }

    fn emission(&self, material: &Material, uv: Vec2) -> Vec3 {
        if !material.is_emissive() {
            return Vec3::ZERO;
        }
        material.emission * self.texture(material.emission_texture, uv).truncate()
    }

    /// Samples the next direction; returns it with the throughput weight (BSDF·cos/pdf).
    fn scatter(
        &self,
        material: &Material,
        point: &SurfacePoint,
        incoming: Vec3,
        front: bool,
        rng: &mut Rng,
    ) -> Option<(Vec3, Vec3)> {
        let tint = material.base_color
            * self
                .texture(material.base_color_texture, point.uv)
                .truncate();
        // Normals facing the side the ray came from.
        let facing = if front { 1.0 } else { -1.0 };
        let geometric = facing * point.geometric;
        let mut shading = facing * point.shading;
        if shading.dot(geometric) <= 0.0 {
            shading = geometric;
        }
        let direction = match material.surface {
            Surface::Diffuse => {
                let (t, b) = orthonormal_basis(shading);
                let local = cosine_hemisphere(rng.next_f32(), rng.next_f32());
                t * local.x + b * local.y + shading * local.z
            }
            Surface::Mirror => reflect(incoming, shading),
            Surface::Dielectric { ior, thin_walled } => {
                let eta = if front || thin_walled { 1.0 / ior } else { ior };
                let cos_i = -incoming.dot(shading);
                let reflectance = fresnel_dielectric(cos_i, eta);
                let reflectance = if thin_walled {
                    // A sheet: light bounces between its two faces; the total reflectance.
                    2.0 * reflectance / (1.0 + reflectance)
                } else {
                    reflectance
                };
                if rng.next_f32() < reflectance {
                    reflect(incoming, shading)
                } else if thin_walled {
                    incoming
                } else {
                    refract(incoming, shading, eta)?
                }
            }
        };
        // A diffuse bounce below the geometric surface would leak light through it.
        if matches!(material.surface, Surface::Diffuse) && direction.dot(geometric) <= 0.0 {
            return None;
        }
        Some((direction, tint))
    }
}

fn reflect(incoming: Vec3, normal: Vec3) -> Vec3 {
    incoming - 2.0 * incoming.dot(normal) * normal
}

/// Snell refraction of `incoming` through a surface with `normal` facing it; `eta` = n_i / n_t.
/// `None` on total internal reflection.
fn refract(incoming: Vec3, normal: Vec3, eta: f32) -> Option<Vec3> {
    let cos_i = -incoming.dot(normal);
    let sin2_t = eta * eta * (1.0 - cos_i * cos_i).max(0.0);
    if sin2_t >= 1.0 {
        return None;
    }
    let cos_t = (1.0 - sin2_t).sqrt();
    Some((eta * incoming + (eta * cos_i - cos_t) * normal).normalize())
}

/// Unpolarised Fresnel reflectance of a smooth dielectric; 1 under total internal reflection.
fn fresnel_dielectric(cos_i: f32, eta: f32) -> f32 {
    let cos_i = cos_i.clamp(0.0, 1.0);
    let sin2_t = eta * eta * (1.0 - cos_i * cos_i);
    if sin2_t >= 1.0 {
        return 1.0;
    }
    let cos_t = (1.0 - sin2_t).sqrt();
    let r_parallel = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
    let r_perpendicular = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
    0.5 * (r_parallel * r_parallel + r_perpendicular * r_perpendicular)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fresnel_matches_normal_incidence_formula() {
        // ((n1 - n2) / (n1 + n2))² = 0.04 for air to glass at 1.5.
        assert!((fresnel_dielectric(1.0, 1.0 / 1.5) - 0.04).abs() < 1e-6);
        assert_eq!(
            fresnel_dielectric(0.1, 1.5),
            1.0,
            "total internal reflection"
        );
    }

    #[test]
    fn refraction_obeys_snell() {
        let normal = Vec3::Y;
        let incoming = Vec3::new(0.6, -0.8, 0.0);
        let out = refract(incoming, normal, 1.0 / 1.5).unwrap();
        let sin_t = out.x;
        assert!((sin_t - 0.6 / 1.5).abs() < 1e-6);
        assert!(out.y < 0.0);
    }
}
