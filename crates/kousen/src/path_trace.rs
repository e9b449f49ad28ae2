//! An interim CPU path tracer, so that `kousen render` makes a correct image before the SPPM
//! integrator (issue 4) lands, and an independent reference for it later. Unidirectional paths
//! with next-event estimation on diffuse surfaces, combined with BSDF sampling by multiple
//! importance sampling (power heuristic); Russian roulette after a few bounces. It reads the scene through the same packed
//! MTBVH and CPU traversal the GPU kernels will use, so it also exercises them end to end.

use glam::{Vec2, Vec3};
use rayon::prelude::*;
use scene::{AlphaMode, Camera, Material, Scene, Surface};

use render::light_sampling::{LightSampler, power_heuristic};
use render::normal_map::mapped_normal;
use render::optics::{fresnel_dielectric, reflect, refract};
use render::plastic::{CoatEvent, coat_event, coat_transmittance, diffuse_scale};
use render::sampling::{Rng, cosine_hemisphere, orthonormal_basis};
use render::shadow_terminator::{is_lifted, shadow_origin};

/// What to render and how much.
pub struct RenderSettings {
    pub width: u32,
    pub height: u32,
    pub samples_per_pixel: u32,
    pub max_depth: u32,
    pub seed: u64,
}

/// A linear RGB image, rows top to bottom.
pub use render::Image;

/// Surfaces a ray passes through (alpha cut-outs) count against this, not against the depth.
const MAX_PASS_THROUGH: u32 = 64;
/// Bounces before Russian roulette may end a path.
const ROULETTE_AFTER: u32 = 3;

pub struct PathTracer<'a> {
    scene: &'a Scene,
    bvh: &'a bvh::PackedBvh,
    /// The same tree four-wide (faster on the CPU, same hits); `None` if its leaves are too
    /// large for it.
    wide: Option<bvh::WideMtbvh>,
    camera: Camera,
    lights: LightSampler,
    /// Whether any material has alpha cut-outs (shadow rays must then look through them).
    has_cut_outs: bool,
    /// Offset of a continuation ray's origin, relative to the scene's size.
    epsilon: f32,
}

/// What the tracer needs to know about a hit.
struct SurfacePoint {
    position: Vec3,
    /// Where shadow rays start: on the vertex normals' smooth surface
    /// (`render::shadow_terminator`) when the ray came from their side.
    shadow_origin: Vec3,
    /// Unit geometric normal, front face.
    geometric: Vec3,
    /// Unit interpolated normal (bent by a normal map), front face.
    shading: Vec3,
    uv: Vec2,
    material: u32,
    /// Index into the scene's triangles.
    triangle: u32,
}

/// How the path reached the current vertex, for weighting emission found there.
enum Arrival {
    /// From the camera or a specular bounce: light sampling could not have found this path.
    Unsampled,
    /// From a diffuse bounce at `from`, with this solid-angle density.
    Diffuse { from: Vec3, pdf: f32 },
}

impl<'a> PathTracer<'a> {
    pub fn new(scene: &'a Scene, bvh: &'a bvh::PackedBvh, camera: Camera) -> Self {
        let epsilon = 1e-5 * scene.bounds().extent().length().max(1e-3);
        let has_cut_outs = scene
            .materials
            .iter()
            .any(|m| matches!(m.alpha_mode, AlphaMode::Mask { .. }));
        PathTracer {
            scene,
            wide: bvh::WideMtbvh::new(bvh).ok(),
            bvh,
            camera,
            lights: LightSampler::new(scene),
            has_cut_outs,
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
        let mut arrival = Arrival::Unsampled;
        let (mut depth, mut passes) = (0, 0);
        while depth < max_depth {
            let Some(point) = self.intersect(origin, direction) else {
                // Out of the scene: the sky, at full weight (next-event estimation samples
                // emissive triangles only).
                if let Some(sky) = &self.scene.lights.sky {
                    radiance += throughput * sky.radiance;
                }
                break;
            };
            let material = &self.scene.materials[point.material as usize];
            let front = direction.dot(point.geometric) < 0.0;
            if self.cut_out(material, point.uv) && passes < MAX_PASS_THROUGH {
                passes += 1;
                origin = point.position + direction * self.epsilon;
                continue;
            }
            if !front {
                // The segment ran inside a solid dielectric: Beer–Lambert over its length.
                let length = (point.position - origin).length();
                throughput *= (-material.interior_absorption() * length).exp();
            }
            if front || material.double_sided {
                let weight = self.emission_weight(&arrival, &point, direction);
                radiance += throughput * weight * self.emission(material, point.uv);
            }
            let facing = if front { 1.0 } else { -1.0 };
            // Next-event estimation on the Lambertian lobe: a diffuse surface's, or plastic's
            // base, which the coat lets light into and out of (`render::plastic`).
            let tint = self.tint(material, point.uv);
            let lambertian = match material.surface {
                Surface::Diffuse => Some((tint, None)),
                Surface::Plastic { ior, .. } => {
                    let (_, shading) = facing_normals(&point, front);
                    let leaving = coat_transmittance(direction.dot(shading), ior);
                    let coat = Coat {
                        ior,
                        base_probability: leaving,
                    };
                    Some((tint * (diffuse_scale(ior) * leaving), Some(coat)))
                }
                _ => None,
            };
            if let Some((albedo, coat)) = lambertian {
                radiance += throughput * albedo * self.direct_light(&point, facing, coat, rng);
            }
            let Some((next, weight, lobe)) = self.scatter(material, &point, direction, front, rng)
            else {
                break;
            };
            arrival = match lobe {
                Lobe::Lambertian { pdf } => Arrival::Diffuse {
                    from: point.position,
                    pdf,
                },
                Lobe::Specular => Arrival::Unsampled,
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

    /// The MIS weight of emission found by BSDF sampling, against light sampling.
    fn emission_weight(&self, arrival: &Arrival, point: &SurfacePoint, direction: Vec3) -> f32 {
        let Arrival::Diffuse { from, pdf } = *arrival else {
            return 1.0;
        };
        let cos_light = direction.dot(point.geometric).abs();
        if cos_light == 0.0 {
            return 0.0;
        }
        let distance_sq = (point.position - from).length_squared();
        let pdf_light = self.lights.pdf_area(self.scene, point.triangle) * distance_sq / cos_light;
        power_heuristic(pdf, pdf_light)
    }

    /// Next-event estimation at a diffuse point, divided by its albedo: one light sample,
    /// (1/π)·Le·cos / pdf, weighted against BSDF sampling. `facing` turns the point's
    /// normals to the side the path arrived from. Under a plastic `coat`, the light the coat
    /// lets in, weighted against the base's share of BSDF sampling.
    fn direct_light(
        &self,
        point: &SurfacePoint,
        facing: f32,
        coat: Option<Coat>,
        rng: &mut Rng,
    ) -> Vec3 {
        let u = [rng.next_f32(), rng.next_f32(), rng.next_f32()];
        let Some(light) = self.lights.sample(self.scene, u) else {
            return Vec3::ZERO;
        };
        let to_light = light.position - point.position;
        let distance_sq = to_light.length_squared();
        let wi = to_light / distance_sq.sqrt();
        let cos_surface = wi.dot(facing * point.shading);
        if cos_surface <= 0.0 {
            return Vec3::ZERO;
        }
        // A facet turned from the light whose smooth surface faces it (a coarse mesh's
        // terminator): the shadow ray from the smooth surface decides. BSDF sampling never
        // goes below the facet, so there the light sample counts alone.
        let above_facet = wi.dot(facing * point.geometric) > 0.0;
        let geometric = facing * point.geometric;
        if !above_facet && !is_lifted(point.position, point.shadow_origin, geometric, self.epsilon)
        {
            return Vec3::ZERO;
        }
        let light_triangle = &self.scene.triangles[light.triangle as usize];
        let light_material = &self.scene.materials[light_triangle.material as usize];
        let mut cos_light = -wi.dot(light.normal);
        if light_material.double_sided {
            cos_light = cos_light.abs();
        }
        if cos_light <= 0.0 || light.pdf_area <= 0.0 {
            return Vec3::ZERO;
        }
        let origin = point.shadow_origin + facing * self.epsilon * point.geometric;
        if !self.visible(origin, light.position) {
            return Vec3::ZERO;
        }
        let pdf_light = light.pdf_area * distance_sq / cos_light;
        let base_probability = coat.map_or(1.0, |c| c.base_probability);
        let pdf_bsdf = if above_facet {
            base_probability * cos_surface * std::f32::consts::FRAC_1_PI
        } else {
            0.0
        };
        let weight = power_heuristic(pdf_light, pdf_bsdf);
        let entering = coat.map_or(1.0, |c| coat_transmittance(cos_surface, c.ior));
        self.emission(light_material, light.uv)
            * (entering * cos_surface * std::f32::consts::FRAC_1_PI)
            * (weight / pdf_light)
    }

    /// Whether nothing opaque lies between `from` and `to` (cut-out surfaces let light by).
    fn visible(&self, mut from: Vec3, to: Vec3) -> bool {
        // Stop just short of the light's own surface.
        const SHORT_OF_TARGET: f32 = 1.0 - 1e-4;
        if !self.has_cut_outs {
            let ray = bvh::Ray {
                origin: from,
                direction: to - from,
                t_max: SHORT_OF_TARGET,
            };
            return !bvh::any_hit_cpu(self.bvh, self.wide.as_ref(), &ray);
        }
        for _ in 0..MAX_PASS_THROUGH {
            let Some(point) = self.intersect_segment(from, to - from, SHORT_OF_TARGET) else {
                return true;
            };
            let material = &self.scene.materials[point.material as usize];
            if !self.cut_out(material, point.uv) {
                return false;
            }
            from = point.position + (to - from).normalize() * self.epsilon;
        }
        false
    }

    fn intersect(&self, origin: Vec3, direction: Vec3) -> Option<SurfacePoint> {
        self.intersect_segment(origin, direction, f32::INFINITY)
    }

    fn intersect_segment(&self, origin: Vec3, direction: Vec3, t_max: f32) -> Option<SurfacePoint> {
        let ray = bvh::Ray {
            origin,
            direction,
            t_max,
        };
        let hit = bvh::closest_hit_cpu(self.bvh, self.wide.as_ref(), &ray)?;
        let id = self.bvh.triangle_ids[hit.triangle as usize];
        let triangle = &self.scene.triangles[id as usize];
        let [a, b, c] = triangle.vertices;
        let w = 1.0 - hit.u - hit.v;
        let geometric = triangle.geometric_normal_unnormalized().normalize();
        let position = origin + hit.t * direction;
        let positions = [a.position, b.position, c.position];
        let normals = [a.normal, b.normal, c.normal];
        let interpolated = w * a.normal + hit.u * b.normal + hit.v * c.normal;
        let barycentric = [w, hit.u, hit.v];
        let shadow_origin = shadow_origin(
            position,
            direction,
            interpolated,
            positions,
            normals,
            barycentric,
        );
        let mut shading = interpolated.try_normalize().unwrap_or(geometric);
        let uv = w * a.uv + hit.u * b.uv + hit.v * c.uv;
        let material = &self.scene.materials[triangle.material as usize];
        if let Some(map) = material.normal_texture {
            let texel = self.texture(Some(map), uv).truncate();
            let uvs = [a.uv, b.uv, c.uv];
            shading = mapped_normal(shading, positions, uvs, texel, material.normal_scale);
        }
        Some(SurfacePoint {
            position,
            shadow_origin,
            geometric,
            shading,
            uv,
            material: triangle.material,
            triangle: id,
        })
    }

    fn texture(&self, id: Option<u32>, uv: Vec2) -> glam::Vec4 {
        id.map_or(glam::Vec4::ONE, |t| {
            self.scene.textures[t as usize].sample_bilinear(uv.x, uv.y)
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

    /// Base colour × texture.
    fn tint(&self, material: &Material, uv: Vec2) -> Vec3 {
        material.base_color * self.texture(material.base_color_texture, uv).truncate()
    }

    /// Samples the next direction; returns it with the throughput weight (BSDF·cos/pdf) and
    /// the lobe that drew it.
    fn scatter(
        &self,
        material: &Material,
        point: &SurfacePoint,
        incoming: Vec3,
        front: bool,
        rng: &mut Rng,
    ) -> Option<(Vec3, Vec3, Lobe)> {
        let tint = self.tint(material, point.uv);
        let (geometric, shading) = facing_normals(point, front);
        // A cosine-distributed bounce, `None` below the geometric surface (it would leak).
        let lambertian = |rng: &mut Rng| {
            let (t, b) = orthonormal_basis(shading);
            let local = cosine_hemisphere(rng.next_f32(), rng.next_f32());
            let next = t * local.x + b * local.y + shading * local.z;
            (next.dot(geometric) > 0.0).then_some((next, local.z * std::f32::consts::FRAC_1_PI))
        };
        let direction = match material.surface {
            Surface::RoughConductor { alpha } => {
                let (u1, u2) = (rng.next_f32(), rng.next_f32());
                let (next, weight) =
                    render::microfacet::rough_reflection(incoming, shading, alpha, u1, u2)?;
                // Bent below the geometric surface by the shading normal: it would leak.
                return (next.dot(geometric) > 0.0).then_some((
                    next,
                    tint * weight,
                    Lobe::Specular,
                ));
            }
            Surface::RoughDielectric {
                ior,
                thin_walled,
                alpha,
            } => {
                let eta = render::optics::relative_eta(ior, front, thin_walled);
                let u = [rng.next_f32(), rng.next_f32(), rng.next_f32()];
                let (next, weight) = render::microfacet::rough_dielectric(
                    incoming,
                    shading,
                    eta,
                    thin_walled,
                    alpha,
                    u,
                )?;
                // Sent across the geometric surface by the shading normal: it would leak.
                let same_side = (next.dot(shading) > 0.0) == (next.dot(geometric) > 0.0);
                return same_side.then_some((next, tint * weight, Lobe::Specular));
            }
            Surface::Plastic { ior, alpha } => {
                let u = [rng.next_f32(), rng.next_f32(), rng.next_f32()];
                return match coat_event(incoming, shading, ior, alpha, u) {
                    CoatEvent::Base { weight } => {
                        // The base: ρ · scale · (1 − F(θo)) (1 − F(θi)) / π over the choice
                        // and the cosine density. MIS takes the smooth coat's 1 − F(θo) as the
                        // base's probability (any value, used alike by both techniques, keeps
                        // the weights summing to 1).
                        let (next, pdf) = lambertian(rng)?;
                        let leaving = coat_transmittance(next.dot(shading), ior);
                        let weight = tint * (diffuse_scale(ior) * leaving * weight);
                        let pdf = coat_transmittance(-incoming.dot(shading), ior) * pdf;
                        Some((next, weight, Lobe::Lambertian { pdf }))
                    }
                    CoatEvent::Reflected { direction, weight } => (weight > 0.0
                        && direction.dot(geometric) > 0.0)
                        .then_some((direction, Vec3::splat(weight), Lobe::Specular)),
                };
            }
            Surface::Diffuse => {
                let (next, pdf) = lambertian(rng)?;
                return Some((next, tint, Lobe::Lambertian { pdf }));
            }
            Surface::Mirror => reflect(incoming, shading),
            Surface::Dielectric { ior, thin_walled } => {
                let eta = render::optics::relative_eta(ior, front, thin_walled);
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
        Some((direction, tint, Lobe::Specular))
    }
}

/// The point's geometric and shading normals turned to the side a ray arrived from (`front`),
/// the shading one replaced by the geometric where it would lie below the surface.
fn facing_normals(point: &SurfacePoint, front: bool) -> (Vec3, Vec3) {
    let facing = if front { 1.0 } else { -1.0 };
    let geometric = facing * point.geometric;
    let shading = facing * point.shading;
    if shading.dot(geometric) <= 0.0 {
        (geometric, geometric)
    } else {
        (geometric, shading)
    }
}

/// The lobe a scattered direction was drawn from.
enum Lobe {
    /// The Lambertian lobe, at this solid-angle density (the lobe's choice included), which
    /// light sampling also covers: emission found along it is weighted by MIS.
    Lambertian { pdf: f32 },
    /// A mirror, glass, metal or coat reflection: emission found along it counts whole.
    Specular,
}

/// A plastic coat over the Lambertian lobe a light sample serves.
#[derive(Clone, Copy)]
struct Coat {
    ior: f32,
    /// The probability that BSDF sampling chose the base, `1 − F(θo)`.
    base_probability: f32,
}

#[cfg(test)]
mod tests {
    use super::*;
    use scene::testing;

    fn tracer_for(scene: &Scene) -> (bvh::PackedBvh, Camera) {
        let bvh = bvh::PackedBvh::build(&scene.triangles, &bvh::BuildOptions::default());
        (bvh, scene.camera(None).unwrap())
    }

    /// Inside a closed emitting, reflecting sphere every pixel sees L = Le / (1 − ρ) = 1.
    #[test]
    fn furnace_sphere_converges_to_analytic_radiance() {
        let scene = testing::furnace_sphere();
        let (bvh, camera) = tracer_for(&scene);
        let settings = RenderSettings {
            width: 8,
            height: 8,
            samples_per_pixel: 256,
            max_depth: 64,
            seed: 1,
        };
        let image = PathTracer::new(&scene, &bvh, camera).render(&settings);
        let mean = image.mean();
        // 16,384 paths; the per-path standard deviation is below 1, so 2% is > 5 sigma.
        let expected = testing::FURNACE_RADIANCE;
        assert!(
            (mean - Vec3::splat(expected)).abs().max_element() < 0.02 * expected,
            "{mean}"
        );
    }

    /// A diffuse plane under a large parallel light: radiance ρE/π from the closed-form form
    /// factor, checked at several points by rays shot straight down.
    #[test]
    fn lit_plane_matches_analytic_irradiance() {
        let scene = testing::lit_plane();
        let (bvh, camera) = tracer_for(&scene);
        let tracer = PathTracer::new(&scene, &bvh, camera);
        let mut rng = Rng::new(3, 0);
        for (x, z) in [(0.0, 0.0), (0.3, -0.2), (-0.45, 0.45)] {
            let origin = Vec3::new(x, 0.5, z);
            let samples = 4096;
            let sum: Vec3 = (0..samples)
                .map(|_| tracer.radiance(origin, Vec3::NEG_Y, 8, &mut rng))
                .sum();
            let measured = sum / samples as f32;
            let expected = testing::lit_plane_radiance(x, z);
            let error = (measured - Vec3::splat(expected)).abs().max_element();
            assert!(
                error < 0.01 * expected,
                "at ({x}, {z}): {measured} against {expected}"
            );
        }
    }

    /// A smooth plastic plane under the sky L, seen straight down and at 60°: L·(F(θ) +
    /// ρ·s·(1 − F(θ))·T), T = 2∫(1 − F(μ))μ dμ by the midpoint rule (as the SPPM test in
    /// `crates/cpu/tests/analytic.rs`); the coat's reflection and the base's light samples
    /// and bounces through the tracer's MIS.
    #[test]
    fn plastic_plane_under_the_sky_returns_coat_and_base() {
        use render::plastic::{coat_reflectance, diffuse_scale};
        let (sky, ior) = (2.0f32, 1.5f32);
        let mut scene = testing::punctual_plane(&[]);
        let bounds = scene.bounds();
        scene.lights.set_sky(Vec3::splat(sky), bounds);
        for material in &mut scene.materials {
            material.surface = Surface::Plastic { ior, alpha: 0.0 };
        }
        let (bvh, camera) = tracer_for(&scene);
        let tracer = PathTracer::new(&scene, &bvh, camera);
        let steps = 100_000;
        let transmittance: f64 = (0..steps)
            .map(|i| {
                let mu = (i as f64 + 0.5) / steps as f64;
                2.0 * mu * (1.0 - coat_reflectance(mu as f32, ior) as f64) / steps as f64
            })
            .sum();
        let mut rng = Rng::new(5, 0);
        for cos in [1.0f32, 0.5] {
            let direction = Vec3::new((1.0 - cos * cos).sqrt(), -cos, 0.0);
            // Towards the plane's centre from 0.4 away.
            let origin = -0.4 * direction;
            let samples = 20_000;
            let sum: Vec3 = (0..samples)
                .map(|_| tracer.radiance(origin, direction, 8, &mut rng))
                .sum();
            let measured = (sum / samples as f32).x as f64;
            let f = coat_reflectance(cos, ior) as f64;
            let albedo = testing::LIT_PLANE_ALBEDO as f64;
            let expected =
                sky as f64 * (f + albedo * diffuse_scale(ior) as f64 * (1.0 - f) * transmittance);
            assert!(
                (measured / expected - 1.0).abs() < 0.01,
                "at cos {cos}: {measured} against {expected}"
            );
        }
    }
}
