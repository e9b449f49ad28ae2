//! A CPU path tracer: an independent reference for the SPPM integrator (`kousen render
//! --integrator path`). Unidirectional paths with next-event estimation at Lambertian lobes
//! (diffuse surfaces, plastic's base) and glossy ones (rough metal, a rough plastic coat),
//! each combined with the lobe's own sampling by multiple importance sampling (power
//! heuristic, one pair of techniques per lobe); Russian roulette after a few bounces. Light
//! samples come from the light table SPPM uses (`render::emission::light_table`: emissive
//! triangles, glTF punctual lights, the sky), so every kind of light reaches it. It reads the
//! scene through the same packed MTBVH and CPU traversal as the kernels, so it also exercises
//! them end to end.

use glam::{Vec2, Vec3};
use rayon::prelude::*;
use render::lens::camera_lens_ray;
use scene::{AlphaMode, Camera, Material, Scene, Surface};

use render::blend::{blend_member, mapped_material};
use render::buffers::{LIGHT_POINT, LIGHT_SPOT, LIGHT_TRIANGLE, Light, RAY_T_MAX};
use render::clearcoat::{
    ClearcoatEvent, clearcoat_at, clearcoat_event, clearcoat_numbers, clearcoat_transmittance,
};
use render::coats::Coats;
use render::conductor::Metal;
use render::dielectric_layer::{
    DielectricLayer, LayerReflectance, layered_reflectance, lobe_layer_weight,
    rough_dielectric_layer_weight,
};
use render::direct::{LightSample, sample_light, shadow_ray, sky_pdf, triangle_pdf};
use render::emission::{
    light_area_density, light_table_triangles, light_table_with, triangle_barycentrics,
};
use render::iridescence::Film;
use render::light_sampling::power_heuristic;
use render::medium::{MediumLocator, NO_MEDIUM, medium_after, segment_medium, transmittance};
use render::microfacet::{GlossyLobe, glossy_response, refraction_response, sheet_response};
use render::normal_map::{FrameSource, mapped_normal, tangent_at};
use render::optics::{eye_refraction_scale, fresnel_dielectric, reflect, refract};
use render::plastic::{Coat, CoatEvent, layered_coat_event};
use render::sampling::{Rng, cosine_hemisphere, orthonormal_basis};
use render::scattering::{
    SCATTERINGS_PER_STEP, Walk, henyey_greenstein, henyey_greenstein_phase, scattering_solid,
};
use render::shadow_terminator::{is_lifted, shadow_origin};
use render::sheen::{SheenAt, SheenEvent, SheenTable};
use render::sky_map::{sky_map_buffer, sky_radiance};

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
    /// The scene's materials, indices of refraction relative to the solids they lie in
    /// (`render::nesting`).
    materials: Vec<Material>,
    /// Per material, the solid around it (`render::nesting::Nesting::exterior`).
    exterior: Vec<u32>,
    bvh: &'a bvh::PackedBvh,
    /// The same tree four-wide (faster on the CPU, same hits); `None` if its leaves are too
    /// large for it.
    wide: Option<bvh::WideMtbvh>,
    camera: Camera,
    /// The light table SPPM samples, in its CDF order.
    lights: Vec<Light>,
    /// The sky's environment map (`render::sky_map`).
    sky_map: Vec<f32>,
    /// The scene triangle behind each triangle entry of `lights` (they come first).
    light_triangles: Vec<u32>,
    /// Per material, the area density with which light sampling lands on its triangles.
    light_area_density: Vec<f32>,
    /// Every material's plastic coat, over its texture's widths where one maps it.
    coats: Coats,
    /// Every material's sheen table (`render::sheen`).
    sheens: Vec<Option<SheenTable>>,
    /// Whether any material has alpha cut-outs (shadow rays must then look through them).
    has_cut_outs: bool,
    /// Offset of a continuation ray's origin, relative to the scene's size.
    epsilon: f32,
    /// The absorbing solid the camera is in (`render::medium`), where every path starts.
    camera_medium: u32,
}

/// What the tracer needs to know about a hit.
struct SurfacePoint {
    position: Vec3,
    /// Where shadow rays start: on the vertex normals' smooth surface
    /// (`render::shadow_terminator`) when the ray came from their side.
    shadow_origin: Vec3,
    /// Unit geometric normal, front face.
    geometric: Vec3,
    /// Unit interpolated normal (bent by the clear coat's own normal map, if any), front face.
    shading: Vec3,
    /// The same before the normal map, which a clear coat follows.
    interpolated: Vec3,
    uv: Vec2,
    material: u32,
    /// A brushed metal's brushing (`cpu::surface::brush_at`); zero elsewhere.
    brush: Vec3,
}

/// How the path reached the current vertex, for weighting emission found there.
enum Arrival {
    /// From the camera or a specular bounce: light sampling could not have found this path.
    Unsampled,
    /// From a bounce at `from` drawn from a lobe a light sample there also served, with this
    /// solid-angle density; `normal` is the one that light sample was drawn about (the sky's
    /// cosine).
    Sampled { from: Vec3, normal: Vec3, pdf: f32 },
}

impl Arrival {
    /// The MIS weight of emission met at `point` along `direction`, against light sampling
    /// at the vertex the path came from; `area_density` is the emitter's
    /// ([`light_area_density`]).
    fn emitter_weight(&self, area_density: f32, point: &SurfacePoint, direction: Vec3) -> f32 {
        let Arrival::Sampled { from, pdf, .. } = *self else {
            return 1.0;
        };
        let distance = (point.position - from).length();
        let light_pdf = triangle_pdf(area_density, distance, direction.dot(point.geometric));
        power_heuristic(pdf, light_pdf)
    }

    /// The same for the sky, met along `direction`.
    fn sky_weight(&self, lights: &[Light], sky_map: &[f32], direction: Vec3) -> f32 {
        let Arrival::Sampled { normal, pdf, .. } = *self else {
            return 1.0;
        };
        power_heuristic(pdf, sky_pdf(lights, sky_map, direction, normal))
    }
}

/// The lobes of a surface that one light sample there lights, without the path's throughput.
#[derive(Default)]
struct LitLobes<'a> {
    /// A Lambertian lobe's albedo (under a coat: times plastic's scale and the coat's
    /// `T(θo)`); zero where there is none.
    lambertian: Vec3,
    /// The probability that the tracer's own sampling takes the Lambertian lobe.
    lambertian_choice: f32,
    /// The plastic coat over the Lambertian lobe, which gets what it lets through.
    coat: Option<&'a Coat>,
    /// The layer on the coat at the point (glTF's specular layer and thin film), whose share
    /// of the coat's reflection and transmission depends on the light's direction.
    coat_layer: DielectricLayer,
    /// The glossy lobe's tint (a metal's colour; 1 for a coat); zero where there is none.
    glossy: Vec3,
    lobe: GlossyLobe,
    /// glTF's clear coat over both lobes, which the light passes on its way in, and the normal
    /// it follows (the shading one before the normal map, facing the path).
    clearcoat: Option<(scene::Clearcoat, Vec3)>,
    /// glTF's sheen over both lobes (beneath the clear coat), which the light passes too, and
    /// the normal it follows (the shading one, facing the path).
    sheen: Option<(SheenAt, Vec3)>,
    /// The metal of a rough-metal lobe (its Fresnel reflectance, under glTF's thin film where
    /// it has one, depends on the light's direction: `glossy` then leaves the colour out).
    metal: Option<Metal>,
    /// Frosted glass's thin film, whose share of the lobe's way depends on the light's
    /// direction (factor 0: none).
    dielectric_layer: DielectricLayer,
}

impl<'a> LitLobes<'a> {
    /// A material's lobes (`coat` its coat) at a point with unit `shading` normal, seen along
    /// `outgoing` (unit, away from the surface) from its `front` or back, `tint` its base
    /// colour there, a metal brushed along `brush` (zero: isotropic).
    fn of(
        material: &Material,
        coat: &'a Coat,
        tint: Vec3,
        (outgoing, shading, brush): (Vec3, Vec3, Vec3),
        front: bool,
    ) -> LitLobes<'a> {
        match material.surface {
            Surface::Diffuse => LitLobes {
                lambertian: tint,
                lambertian_choice: 1.0,
                ..LitLobes::default()
            },
            Surface::Plastic { ior, alpha } => {
                let leaving = coat.transmittance(outgoing.dot(shading));
                LitLobes {
                    lambertian: tint * (coat.diffuse_scale * leaving),
                    lambertian_choice: leaving,
                    coat: Some(coat),
                    coat_layer: DielectricLayer::default(),
                    glossy: if alpha > 0.0 { Vec3::ONE } else { Vec3::ZERO },
                    lobe: GlossyLobe::reflection(alpha, ior),
                    clearcoat: None,
                    sheen: None,
                    metal: None,
                    dielectric_layer: DielectricLayer::default(),
                }
            }
            Surface::RoughConductor { alpha } => LitLobes {
                glossy: tint,
                lobe: GlossyLobe::metal(alpha, brush),
                ..LitLobes::default()
            },
            // Solid frosted glass seen from outside reflects as a coat does; from inside, its
            // refraction out is the lobe (light refracted in gets no light sample).
            Surface::RoughDielectric {
                ior,
                thin_walled: false,
                alpha,
            } if front => LitLobes {
                glossy: tint,
                lobe: GlossyLobe::reflection(alpha, ior),
                ..LitLobes::default()
            },
            Surface::RoughDielectric {
                ior,
                thin_walled: false,
                alpha,
            } => LitLobes {
                glossy: tint,
                lobe: GlossyLobe::refraction(alpha, ior),
                ..LitLobes::default()
            },
            // A thin frosted sheet: its reflection, and its transmission of light beyond it.
            Surface::RoughDielectric {
                ior,
                thin_walled: true,
                alpha,
            } => LitLobes {
                glossy: tint,
                lobe: GlossyLobe::sheet(alpha, 1.0 / ior),
                ..LitLobes::default()
            },
            _ => LitLobes::default(),
        }
    }

    fn is_lit(&self) -> bool {
        self.lambertian.max_element() > 0.0
            || (self.lobe.is_some() && self.glossy.max_element() > 0.0)
    }

    /// BSDF · cos towards `outgoing` for light arriving along `incident`, each lobe's share
    /// weighed by the power heuristic against that lobe's own sampling, which draws `incident`
    /// only where `drawable` (not below the geometric surface).
    fn response(
        &self,
        normal: Vec3,
        outgoing: Vec3,
        incident: Vec3,
        light_pdf: f32,
        drawable: bool,
    ) -> Vec3 {
        let cosine = incident.dot(normal);
        let reach = if drawable { 1.0 } else { 0.0 };
        let mut response = Vec3::ZERO;
        if self.lambertian.max_element() > 0.0 {
            let entering = self.coat.map_or(Vec3::ONE, |coat| {
                let layer = self.coat_layer.transmission_share(coat.ior, cosine);
                coat.transmittance(cosine) * layer
            });
            let lobe = cosine * std::f32::consts::FRAC_1_PI;
            let pdf = reach * self.lambertian_choice * lobe;
            response += self.lambertian * entering * (lobe * power_heuristic(light_pdf, pdf));
        }
        if self.lobe.is_some() {
            let lobe = self.lobe.response(normal, outgoing, incident);
            if lobe.value > 0.0 {
                let weight = power_heuristic(light_pdf, reach * lobe.pdf);
                let mut tint = self
                    .metal
                    .map_or(Vec3::ONE, |metal| metal.tint(outgoing, incident));
                if !self.dielectric_layer.is_bare() {
                    let ways = (outgoing, incident);
                    tint *= lobe_layer_weight(&self.lobe, self.dielectric_layer, normal, ways);
                }
                // A rough coat's reflection under its layer.
                if let Some(coat) = self.coat {
                    tint *= self
                        .coat_layer
                        .reflection_share(coat.ior, (outgoing, incident));
                }
                response += self.glossy * tint * (lobe.value * weight);
            }
        }
        // In through the clear coat, if any.
        let through = |(c, normal): (scene::Clearcoat, Vec3)| {
            clearcoat_transmittance(&c, incident.dot(normal))
        };
        let sheen = |(s, normal): (SheenAt, Vec3)| s.transmittance(incident.dot(normal));
        response * (self.clearcoat.map_or(1.0, through) * self.sheen.map_or(1.0, sheen))
    }
}

impl<'a> PathTracer<'a> {
    pub fn new(scene: &'a Scene, bvh: &'a bvh::PackedBvh, camera: Camera) -> Self {
        let epsilon = 1e-5 * scene.bounds().extent().length().max(1e-3);
        let has_cut_outs = scene
            .materials
            .iter()
            .any(|m| matches!(m.alpha_mode, AlphaMode::Mask { .. }));
        // One medium locator serves the nesting, the lights and the camera.
        let locator = MediumLocator::new(scene);
        let nesting = render::nesting::Nesting::of_with(scene, &locator);
        PathTracer {
            camera_medium: locator.medium_at(camera.eye),
            scene,
            wide: bvh::WideMtbvh::new(bvh).ok(),
            bvh,
            camera,
            lights: light_table_with(scene, &locator),
            sky_map: sky_map_buffer(scene.lights.sky.as_ref()),
            light_triangles: light_table_triangles(scene),
            light_area_density: light_area_density(scene),
            coats: Coats::of(&nesting.materials),
            sheens: render::sheen::sheen_tables(&nesting.materials),
            materials: nesting.materials,
            exterior: nesting.exterior,
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
            // A pinhole draws no lens point, so its images keep their numbers.
            let lens = if self.camera.lens.is_pinhole() {
                [0.5; 2]
            } else {
                [rng.next_f32(), rng.next_f32()]
            };
            let (origin, direction) = camera_lens_ray(&self.camera, (sx, sy), aspect, lens);
            sum += self.radiance(origin, direction, settings.max_depth, &mut rng);
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
        // The solid the path is inside (`render::medium`): the camera's, to begin with.
        let mut medium = self.camera_medium;
        // The wavelength the path keeps since its first dispersive glass.
        let mut wavelength = render::dispersion::WHOLE_SPECTRUM;
        // The path's walk through scattering solids, one over all of them (its hero drawn at
        // the first), and the scatterings of its current step (`render::scattering`).
        let (mut walk, mut scatterings): (Option<Walk>, u32) = (None, 0);
        while depth < max_depth {
            let found = self.intersect(origin, direction);
            // A ray out of the scene runs on forever (and scatters on the way in an atmosphere).
            let distance = (found.as_ref()).map_or(RAY_T_MAX, |p| (p.position - origin).length());
            let solid = scattering_solid(&self.materials, medium);
            if let Some(solid) = solid {
                // Inside a scattering solid the path walks: the punctual lights' light
                // scattered once along the segment is sampled (`segment_light`); scattered on
                // the way, the path goes on from there in a direction the phase function draws.
                // Every `SCATTERINGS_PER_STEP` scatterings the step is counted as a bounce, as
                // the photon pass's are, its weight handed to the throughput.
                let inside = walk.get_or_insert_with(|| Walk::start(rng.next_f32()));
                let segment = (origin, direction, distance);
                let light = self.segment_light(segment, solid, medium, rng);
                radiance += throughput * inside.weight() * light;
                let (extinction, scattering) =
                    (solid.interior_extinction(), solid.interior_scattering());
                if let Some(t) = inside.flight(extinction, scattering, distance, rng.next_f32()) {
                    scatterings += 1;
                    if !inside.survives(rng.next_f32()) {
                        break;
                    }
                    origin += t * direction;
                    let u = [rng.next_f32(), rng.next_f32()];
                    direction = henyey_greenstein(direction, solid.scatter_anisotropy, u);
                    arrival = Arrival::Unsampled;
                    if scatterings == SCATTERINGS_PER_STEP {
                        throughput *= inside.take_weight();
                        scatterings = 0;
                        depth += 1;
                    }
                    continue;
                }
                throughput *= inside.take_weight();
                scatterings = 0;
            }
            let Some(mut point) = found else {
                // Out of the scene: the sky, weighed against the light sample that could
                // have drawn it (and absorbed by water around the path; a walk's weight holds
                // that already).
                if let Some(sky) = &self.scene.lights.sky {
                    let weight = arrival.sky_weight(&self.lights, &self.sky_map, direction);
                    let kept = match solid {
                        Some(_) => Vec3::ONE,
                        None => self.transmittance(medium, RAY_T_MAX),
                    };
                    let seen = sky_radiance(&self.lights, &self.sky_map, sky.radiance, direction);
                    radiance += throughput * seen * weight * kept;
                }
                break;
            };
            let material = &self.materials[point.material as usize];
            let front = direction.dot(point.geometric) < 0.0;
            if solid.is_none() {
                // Beer–Lambert over the segment in the medium it ran through.
                let absorbs_inside = material.interior_extinction().max_element() > 0.0;
                let segment = segment_medium(medium, point.material, absorbs_inside, front);
                throughput *= self.transmittance(segment, distance);
            }
            if self.cut_out(material, point.uv) && passes < MAX_PASS_THROUGH {
                passes += 1;
                origin = point.position + direction * self.epsilon;
                continue;
            }
            if front || material.double_sided {
                let area_density = self.light_area_density[point.material as usize];
                let weight = arrival.emitter_weight(area_density, &point, direction);
                radiance += throughput * weight * self.emission(material, point.uv);
            }
            // glTF's clear coat over the material meets the path first (`render::clearcoat`):
            // its reflection goes on as a mirror's (or rough metal's).
            let through_coat = (material.clearcoat)
                .map(|c| clearcoat_at(&c, |id| self.texture(Some(id), point.uv)));
            if let Some(coat) = through_coat {
                let u = clearcoat_numbers(&coat, || rng.next_f32());
                let (geometric, coat_normal) = facing_interpolated_normals(&point, front);
                if let ClearcoatEvent::Reflected(reflected) =
                    clearcoat_event(direction, coat_normal, &coat, u)
                {
                    let kept = |next: &Vec3| coat.alpha == 0.0 || next.dot(geometric) > 0.0;
                    let Some((next, weight)) = reflected.filter(|(next, _)| kept(next)) else {
                        break;
                    };
                    arrival = Arrival::Unsampled;
                    throughput *= weight;
                    depth += 1;
                    origin = self.leaving(&point, next);
                    direction = next;
                    continue;
                }
            }
            let root = point.material;
            let coat_normal = facing_interpolated_normals(&point, front).1;
            // glTF's sheen beneath the coat meets it next (`render::sheen`): its reflection
            // takes a light sample for the sheen's lobe and goes on from it.
            let through_sheen = (material.sheen)
                .zip(self.sheens[root as usize])
                .filter(|_| cpu::surface::sheen_faces(material.surface, front))
                .map(|(s, t)| SheenAt::new(&s, t, |id| self.texture(Some(id), point.uv)));
            if let Some(sheen) = through_sheen {
                let (geometric, shading) = facing_normals(&point, front);
                let u = [rng.next_f32(), rng.next_f32(), rng.next_f32()];
                if let SheenEvent::Reflected(next, weight) = sheen.event(direction, shading, u) {
                    if next.dot(geometric) <= 0.0 || weight.max_element() <= 0.0 {
                        break;
                    }
                    let lit = LitLobes {
                        glossy: sheen.lobe_scale(direction.dot(shading)),
                        lobe: GlossyLobe::sheen(sheen.table.alpha),
                        clearcoat: through_coat.map(|c| (c, coat_normal)),
                        ..LitLobes::default()
                    };
                    if !self.lights.is_empty() {
                        let light = self.direct_light(&point, front, -direction, &lit, medium, rng);
                        radiance += throughput * light;
                    }
                    arrival = Arrival::Sampled {
                        from: point.position,
                        normal: shading,
                        pdf: lit.lobe.response(shading, -direction, next).pdf,
                    };
                    let coat = through_coat
                        .map_or(1.0, |c| clearcoat_transmittance(&c, next.dot(coat_normal)));
                    throughput *= weight * coat;
                    depth += 1;
                    origin = self.leaving(&point, next);
                    direction = next;
                    continue;
                }
            }
            // A blend's member for this path (`render::blend`), drawn only at blends.
            let texel = |texture| self.texture(Some(texture), point.uv);
            if material.blend.is_some() {
                point.material = blend_member(&self.materials, root, rng.next_f32(), texel);
            }
            // Where a metallic-roughness texture maps the member, its surface here.
            let member = mapped_material(&self.materials[point.material as usize], texel);
            let material: &Material = &member;
            let (_, shading) = facing_normals(&point, front);
            // Next-event estimation on the lobes light sampling serves: Lambertian ones (a
            // diffuse surface, plastic's base, which the coat lets light into and out of:
            // `render::plastic`) and glossy ones (rough metal, a rough coat).
            let tint = self.tint(material, point.uv);
            let coat = self.coats.at(point.material, material.surface);
            // Dispersive glass keeps one wavelength (`render::dispersion`): the lobes below,
            // the light sample's among them, are that wavelength's.
            let (surface, kept, weight) =
                cpu::surface::dispersed_surface(material, wavelength, || rng.next_f32());
            wavelength = kept;
            throughput *= weight;
            // A copy only where dispersion changed the surface.
            let dispersed;
            let lobes_of = if surface == material.surface {
                material
            } else {
                dispersed = Material {
                    name: String::new(),
                    surface,
                    ..*material
                };
                &dispersed
            };
            // glTF's diffuse transmission: this time the Lambertian lobe lies on the far side
            // (chosen with the share's probability, before its light sample and its bounce, so
            // that both are that side's), tinted by the transmission.
            let transmitted = self
                .diffuse_transmission(material, point.uv)
                .filter(|_| surface.has_diffuse_lobe())
                .and_then(|(share, tint)| (rng.next_f32() < share).then_some(tint));
            let lambertian_tint = transmitted.unwrap_or(tint);
            let mut lit = LitLobes {
                clearcoat: through_coat.map(|c| (c, coat_normal)),
                sheen: through_sheen.map(|s| (s, shading)),
                ..LitLobes::of(
                    lobes_of,
                    &coat,
                    lambertian_tint,
                    (-direction, shading, point.brush),
                    front,
                )
            };
            if matches!(lobes_of.surface, Surface::RoughConductor { .. }) {
                lit.metal = Some(Metal {
                    f0: lit.glossy,
                    edge: lobes_of.metal_edge,
                    film: self.film(lobes_of, point.uv),
                });
                lit.glossy = Vec3::ONE;
            }
            if matches!(lobes_of.surface, Surface::Plastic { .. }) {
                // The layer's share of the coat's transmittance along the view, and of the
                // base's scale.
                let layer = self.dielectric_layer(lobes_of, point.uv);
                lit.lambertian *= layer.transmission_share(coat.ior, direction.dot(shading))
                    * layer.diffuse_share(coat.diffuse_scale, coat.ior);
                lit.coat_layer = layer;
            }
            if matches!(lobes_of.surface, Surface::RoughDielectric { .. }) {
                lit.dielectric_layer = self.dielectric_layer(lobes_of, point.uv);
            }
            if !self.lights.is_empty() {
                if transmitted.is_some() {
                    // The far side's light sample for the Lambertian lobe, through that
                    // side's coats, from the point itself (its lift is the near side's).
                    let far_lit = LitLobes {
                        lambertian: lit.lambertian,
                        lambertian_choice: lit.lambertian_choice,
                        coat: lit.coat,
                        clearcoat: through_coat.map(|c| (c, -coat_normal)),
                        sheen: through_sheen.map(|s| (s, -shading)),
                        ..LitLobes::default()
                    };
                    let far_point = SurfacePoint {
                        shadow_origin: point.position,
                        ..point
                    };
                    // Inside a translucent solid where the surface bounds one.
                    let exterior = self.exterior[root as usize];
                    let solid = material.bounds_volume();
                    let far_medium = medium_after(medium, root, exterior, solid, front, true);
                    let light = self
                        .direct_light(&far_point, !front, -direction, &far_lit, far_medium, rng);
                    radiance += throughput * light;
                    lit.lambertian = Vec3::ZERO;
                }
                if lit.is_lit() {
                    let light = self.direct_light(&point, front, -direction, &lit, medium, rng);
                    radiance += throughput * light;
                }
            }
            let facing = Facing { front, transmitted };
            let scattered = self.scatter(material, surface, &point, direction, facing, rng);
            let Some((next, weight, lobe)) = scattered else {
                break;
            };
            // Out through the sheen and the clear coat, if any (the coat about the normal
            // before the map; the far side's where the path passed through).
            let crossed = (next.dot(point.geometric) < 0.0) == front;
            let exit = if transmitted.is_some() && crossed {
                -1.0
            } else {
                1.0
            };
            let weight = weight
                * through_coat.map_or(1.0, |c| {
                    clearcoat_transmittance(&c, next.dot(exit * coat_normal))
                })
                * through_sheen.map_or(1.0, |s| s.transmittance(next.dot(exit * shading)));
            arrival = match lobe {
                // Light samples (the sky's hemisphere) were drawn about the lobe's facing side.
                Lobe::LightSampled { pdf } => Arrival::Sampled {
                    from: point.position,
                    normal: lit.lobe.facing(exit * shading),
                    pdf,
                },
                Lobe::Specular => Arrival::Unsampled,
            };
            throughput *= weight;
            let crosses = (next.dot(point.geometric) < 0.0) == front;
            let solid = material.bounds_volume();
            let exterior = self.exterior[root as usize];
            medium = medium_after(medium, root, exterior, solid, front, crosses);
            depth += 1;
            if depth > ROULETTE_AFTER {
                let survive = throughput.max_element().min(0.95);
                if rng.next_f32() >= survive {
                    break;
                }
                throughput /= survive;
            }
            origin = self.leaving(&point, next);
            direction = next;
        }
        radiance
    }

    /// Where a path leaving `point` along `next` starts: off the surface on the side it goes.
    fn leaving(&self, point: &SurfacePoint, next: Vec3) -> Vec3 {
        let side = if next.dot(point.geometric) > 0.0 {
            1.0
        } else {
            -1.0
        };
        point.position + side * self.epsilon * point.geometric
    }

    /// What a path in `medium` keeps of its light over `distance` (from [`RAY_T_MAX`]: it
    /// left the scene).
    fn transmittance(&self, medium: u32, distance: f32) -> Vec3 {
        if medium == NO_MEDIUM {
            return Vec3::ONE;
        }
        let absorption = self.materials[medium as usize].interior_extinction();
        transmittance(absorption, distance)
    }

    /// The light of a point or spot light scattered once towards the path along its segment
    /// from `origin` along `direction`, `length` long, inside `solid` (its `medium`):
    /// ∫ T(t)·σs·phase·L(t) dt, one point drawn by equiangular sampling about the light (Kulla
    /// and Fajardo 2012: density ∝ 1/r², so the light's own 1/r² cancels and the estimate is
    /// bounded however near the segment passes the lamp), one shadow ray. A lamp inside wax
    /// lights the wax around it this way; the path's walk, which never meets a punctual
    /// light, brings the light scattered more than once. Other lights give nothing here:
    /// emitters and the sky, which a walk can meet, count when it does, and a directional
    /// light cannot shine into a closed solid (its surface stops light samples).
    fn segment_light(
        &self,
        (origin, direction, length): (Vec3, Vec3, f32),
        solid: &Material,
        medium: u32,
        rng: &mut Rng,
    ) -> Vec3 {
        let u = [rng.next_f32(), rng.next_f32(), rng.next_f32()];
        let u_along = rng.next_f32();
        let index = render::emission::pick_light(&self.lights, u[0]);
        if !matches!(self.lights[index].kind, LIGHT_POINT | LIGHT_SPOT) {
            return Vec3::ZERO;
        }
        let lamp = Vec3::from_array(self.lights[index].v0);
        // The segment's nearest point to the lamp, `along` from the origin, `apart` from it
        // (not less than a tenth of the ray offset: the segment may be endless, `RAY_T_MAX`).
        let along = (lamp - origin).dot(direction);
        let apart = (origin + along * direction - lamp)
            .length()
            .max(0.1 * self.epsilon);
        let first = (-along / apart).atan();
        let last = ((length - along) / apart).atan();
        let angle = first + (last - first) * u_along;
        let t = along + apart * angle.tan();
        let density = apart / ((last - first) * (apart * apart + (t - along) * (t - along)));
        if !(t > 0.0 && t < length && density > 0.0) {
            return Vec3::ZERO;
        }
        let position = origin + t * direction;
        let Some(light) = sample_light(&self.lights, &self.sky_map, u, position, direction) else {
            return Vec3::ZERO;
        };
        let (towards, distance) = shadow_ray(&light, position);
        if !self.visible(position, towards, distance) {
            return Vec3::ZERO;
        }
        let phase = henyey_greenstein_phase(solid.scatter_anisotropy, direction.dot(towards));
        let kept = self.transmittance(medium, t) * self.transmittance(medium, distance);
        light.incident * kept * solid.interior_scattering() * (phase / density)
    }

    /// One light sample from the table at `point` (reached from its `front` or back), seen
    /// along `outgoing` by a path in `medium`: what arrives unoccluded through the lobes `lit`
    /// names, each weighed against its own sampling (the path's throughput aside).
    fn direct_light(
        &self,
        point: &SurfacePoint,
        front: bool,
        outgoing: Vec3,
        lit: &LitLobes,
        medium: u32,
        rng: &mut Rng,
    ) -> Vec3 {
        let u = [rng.next_f32(), rng.next_f32(), rng.next_f32()];
        let (geometric, shading) = facing_normals(point, front);
        let facing = lit.lobe.facing(shading);
        let Some(light) = sample_light(&self.lights, &self.sky_map, u, point.position, facing)
        else {
            return Vec3::ZERO;
        };
        if light.direction.dot(shading) < 0.0 {
            // Beyond the surface: only a refraction out or a sheet's transmission sees it.
            if lit.lobe.refraction_eta <= 0.0 && !lit.lobe.is_two_sided() {
                return Vec3::ZERO;
            }
            return self.direct_light_through(
                point,
                (geometric, shading),
                outgoing,
                (lit, medium),
                &light,
                u,
            );
        }
        if light.direction.dot(shading) == 0.0 || lit.lobe.refraction_eta > 0.0 {
            return Vec3::ZERO;
        }
        // A facet turned from the light whose smooth surface faces it (a coarse mesh's
        // terminator): the shadow ray from the smooth surface decides. The lobes' own
        // sampling never goes below the facet, so there the light sample counts alone.
        let above_facet = light.direction.dot(geometric) > 0.0;
        if !above_facet && !is_lifted(point.position, point.shadow_origin, geometric, self.epsilon)
        {
            return Vec3::ZERO;
        }
        let response = lit.response(shading, outgoing, light.direction, light.pdf, above_facet);
        if response.max_element() <= 0.0 {
            return Vec3::ZERO;
        }
        let origin = point.shadow_origin + self.epsilon * geometric;
        let (direction, distance) = shadow_ray(&light, origin);
        if !self.visible(origin, direction, distance) {
            return Vec3::ZERO;
        }
        self.incident(&light, u) * response * self.transmittance(medium, distance)
    }

    /// [`Self::direct_light`] of a `light` beyond the surface (sampled with `u`), through a
    /// refraction out (solid frosted glass from inside, which leaves the path's `medium`) or a
    /// sheet's transmission: only beyond the geometric surface too.
    fn direct_light_through(
        &self,
        point: &SurfacePoint,
        (geometric, shading): (Vec3, Vec3),
        outgoing: Vec3,
        (lit, medium): (&LitLobes, u32),
        light: &LightSample,
        u: [f32; 3],
    ) -> Vec3 {
        if light.direction.dot(geometric) >= 0.0 {
            return Vec3::ZERO;
        }
        let response = lit.response(shading, outgoing, light.direction, light.pdf, true);
        if response.max_element() <= 0.0 {
            return Vec3::ZERO;
        }
        let origin = point.position - self.epsilon * geometric;
        let (direction, distance) = shadow_ray(light, origin);
        if !self.visible(origin, direction, distance) {
            return Vec3::ZERO;
        }
        let medium = if lit.lobe.refraction_eta > 0.0 {
            self.exterior[point.material as usize]
        } else {
            medium
        };
        self.incident(light, u) * response * self.transmittance(medium, distance)
    }

    /// Radiance arriving from a light sample drawn with `u`, divided by its density: the
    /// table's, except on a textured emitter, read at the point drawn (the table holds the
    /// texture's mean).
    fn incident(&self, light: &LightSample, u: [f32; 3]) -> Vec3 {
        let index = light.index;
        if self.lights[index].kind != LIGHT_TRIANGLE {
            return light.incident;
        }
        let triangle = &self.scene.triangles[self.light_triangles[index] as usize];
        let material = &self.materials[triangle.material as usize];
        if material.emission_texture.is_none() {
            return light.incident;
        }
        let (b1, b2) = triangle_barycentrics(u[1], u[2]);
        let [a, b, c] = &triangle.vertices;
        let uv = (1.0 - b1 - b2) * a.uv + b1 * b.uv + b2 * c.uv;
        self.emission(material, uv) / light.pdf
    }

    /// Whether nothing opaque lies within `distance` of `from` along unit `direction`
    /// (cut-out surfaces let light by).
    fn visible(&self, mut from: Vec3, direction: Vec3, distance: f32) -> bool {
        if !self.has_cut_outs {
            let ray = bvh::Ray {
                origin: from,
                direction,
                t_max: distance,
            };
            return !bvh::any_hit_cpu(self.bvh, self.wide.as_ref(), &ray);
        }
        let mut remaining = distance;
        for _ in 0..MAX_PASS_THROUGH {
            let Some(point) = self.intersect_segment(from, direction, remaining) else {
                return true;
            };
            let material = &self.materials[point.material as usize];
            if !self.cut_out(material, point.uv) {
                return false;
            }
            let next = point.position + direction * self.epsilon;
            remaining -= (next - from).dot(direction);
            if remaining <= 0.0 {
                return true;
            }
            from = next;
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
        let unit_interpolated = interpolated.try_normalize().unwrap_or(geometric);
        let mut shading = unit_interpolated;
        let uv = w * a.uv + hit.u * b.uv + hit.v * c.uv;
        let material = &self.materials[triangle.material as usize];
        let source = FrameSource {
            positions,
            uvs: [a.uv, b.uv, c.uv],
            tangent: tangent_at([a.tangent, b.tangent, c.tangent], barycentric),
        };
        if let Some(map) = material.normal_texture {
            let texel = self.texture(Some(map), uv).truncate();
            shading = mapped_normal(shading, &source, texel, material.normal_scale);
        }
        // A clear coat with a normal map of its own follows it.
        let mut coat_normal = unit_interpolated;
        if let Some(coat) = material.clearcoat
            && let Some(map) = coat.normal_texture
        {
            let texel = self.texture(Some(map), uv).truncate();
            coat_normal = mapped_normal(coat_normal, &source, texel, coat.normal_scale);
        }
        let texel = |t| self.texture(Some(t), uv);
        let brush = cpu::surface::brush_at(material, texel, unit_interpolated, &source);
        Some(SurfacePoint {
            position,
            shadow_origin,
            geometric,
            shading,
            interpolated: coat_normal,
            uv,
            material: triangle.material,
            brush,
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

    /// What lies on plastic's coat at `uv` (`cpu::surface::hit_dielectric_layer`).
    fn dielectric_layer(&self, material: &Material, uv: Vec2) -> DielectricLayer {
        let texel = |id: Option<u32>| id.map(|_| self.texture(id, uv));
        DielectricLayer {
            specular: (material.specular.as_ref())
                .map(|s| LayerReflectance::of(s, texel(s.texture), texel(s.color_texture))),
            film: self.film(material, uv),
        }
    }

    /// The thin film on `material` at `uv` (glTF's iridescence; factor 0 for none).
    fn film(&self, material: &Material, uv: Vec2) -> Film {
        let Some(film) = material.iridescence else {
            return Film::default();
        };
        let texel = |id: Option<u32>| id.map(|_| self.texture(id, uv));
        Film::of(&film, texel(film.texture), texel(film.thickness_texture))
    }

    /// A metal of colour `tint` reflecting from `incoming` into `next`: its Fresnel reflectance
    /// (under its thin film, if any) at the angle to the reflection's micro-normal.
    fn metal_reflection_tint(
        &self,
        material: &Material,
        uv: Vec2,
        tint: Vec3,
        (incoming, next): (Vec3, Vec3),
    ) -> Vec3 {
        let metal = Metal {
            f0: tint,
            edge: material.metal_edge,
            film: self.film(material, uv),
        };
        metal.tint(-incoming, next)
    }

    /// glTF's diffuse transmission at `uv` (`cpu::surface::diffuse_transmission_of`): the
    /// share through and its tint, `None` for none.
    fn diffuse_transmission(&self, material: &Material, uv: Vec2) -> Option<(f32, Vec3)> {
        cpu::surface::diffuse_transmission_of(material, |id| self.texture(id, uv))
    }

    /// Samples the next direction; returns it with the throughput weight (BSDF·cos/pdf) and
    /// the lobe that drew it.
    /// `surface` is `material`'s own, or for dispersive glass one wavelength's
    /// (`cpu::surface::dispersed_surface`).
    fn scatter(
        &self,
        material: &Material,
        surface: Surface,
        point: &SurfacePoint,
        incoming: Vec3,
        Facing { front, transmitted }: Facing,
        rng: &mut Rng,
    ) -> Option<(Vec3, Vec3, Lobe)> {
        let tint = self.tint(material, point.uv);
        let (geometric, shading) = facing_normals(point, front);
        // The Lambertian lobe's side: the far one where the light passes through, and its
        // tint there.
        let (lobe_normals, lobe_tint) = match transmitted {
            Some(far_tint) => ((-geometric, -shading), far_tint),
            None => ((geometric, shading), tint),
        };
        // A cosine-distributed bounce, `None` below the geometric surface (it would leak).
        let lambertian = |rng: &mut Rng| {
            let (geometric, shading) = lobe_normals;
            let (t, b) = orthonormal_basis(shading);
            let local = cosine_hemisphere(rng.next_f32(), rng.next_f32());
            let next = t * local.x + b * local.y + shading * local.z;
            (next.dot(geometric) > 0.0).then_some((next, local.z * std::f32::consts::FRAC_1_PI))
        };
        match surface {
            Surface::RoughConductor { alpha } => {
                let (u1, u2) = (rng.next_f32(), rng.next_f32());
                let brush = point.brush;
                let (next, weight) = if brush == Vec3::ZERO {
                    render::microfacet::rough_reflection(incoming, shading, alpha, u1, u2)?
                } else {
                    render::microfacet::brushed_reflection(
                        incoming,
                        shading,
                        brush,
                        alpha,
                        [u1, u2],
                    )?
                };
                // Bent below the geometric surface by the shading normal: it would leak.
                let pdf = GlossyLobe::metal(alpha, brush)
                    .response(shading, -incoming, next)
                    .pdf;
                let tint = self.metal_reflection_tint(material, point.uv, tint, (incoming, next));
                (next.dot(geometric) > 0.0).then_some((
                    next,
                    tint * weight,
                    Lobe::LightSampled { pdf },
                ))
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
                // Under a layer (thin film, specular layer) each channel takes its share of the
                // way chosen.
                let layer = self.dielectric_layer(material, point.uv);
                let ways = (-incoming, next);
                let tint =
                    tint * rough_dielectric_layer_weight(layer, ways, shading, eta, thin_walled);
                // Sent across the geometric surface by the shading normal: it would leak.
                let same_side = (next.dot(shading) > 0.0) == (next.dot(geometric) > 0.0);
                // Solid glass's reflection from outside, and its refraction out from inside,
                // are lobes light samples serve too.
                let reflected = next.dot(shading) > 0.0;
                let lobe = if thin_walled {
                    let pdf = sheet_response(-incoming, next, shading, alpha, eta).pdf;
                    Lobe::LightSampled { pdf }
                } else if front && reflected {
                    let pdf = glossy_response(-incoming, next, shading, alpha, ior).pdf;
                    Lobe::LightSampled { pdf }
                } else if !front && !reflected {
                    let pdf = refraction_response(-incoming, next, shading, alpha, ior).pdf;
                    Lobe::LightSampled { pdf }
                } else {
                    Lobe::Specular
                };
                // Radiance through a solid's surface (`eye_refraction_scale`).
                let crossing = if !thin_walled && next.dot(geometric) < 0.0 {
                    eye_refraction_scale(eta)
                } else {
                    1.0
                };
                same_side.then_some((next, tint * (weight * crossing), lobe))
            }
            Surface::Plastic { ior, alpha } => {
                let u = [rng.next_f32(), rng.next_f32(), rng.next_f32()];
                let coat = self.coats.at(point.material, surface);
                // The layer on the coat weighs each way by its share (as
                // `cpu::surface::plastic_bounce`).
                let layer = self.dielectric_layer(material, point.uv);
                let through =
                    |cos: f32| coat.transmittance(cos) * layer.transmission_share(coat.ior, cos);
                let (event, film_tint) = layered_coat_event(incoming, shading, (&coat, layer), u);
                match event {
                    CoatEvent::Base { weight } => {
                        // The base: ρ · scale · T(θo) T(θi) / π over the choice and the cosine
                        // density. MIS takes the coat's T(θo) as the base's probability (any
                        // value, used alike by both techniques, keeps the weights summing
                        // to 1).
                        let (next, pdf) = lambertian(rng)?;
                        let leaving = through(next.dot(lobe_normals.1));
                        let scale =
                            coat.diffuse_scale * layer.diffuse_share(coat.diffuse_scale, coat.ior);
                        let weight = lobe_tint * leaving * film_tint * scale * weight;
                        let pdf = coat.transmittance(-incoming.dot(shading)) * pdf;
                        Some((next, weight, Lobe::LightSampled { pdf }))
                    }
                    CoatEvent::Reflected { direction, weight } => {
                        // A rough coat's reflection is a glossy lobe light samples serve too.
                        let lobe = if alpha > 0.0 {
                            let pdf =
                                glossy_response(-incoming, direction, shading, alpha, ior).pdf;
                            Lobe::LightSampled { pdf }
                        } else {
                            Lobe::Specular
                        };
                        (weight > 0.0 && direction.dot(geometric) > 0.0).then_some((
                            direction,
                            film_tint * weight,
                            lobe,
                        ))
                    }
                }
            }
            Surface::Diffuse => {
                let (next, pdf) = lambertian(rng)?;
                Some((next, lobe_tint, Lobe::LightSampled { pdf }))
            }
            Surface::Mirror => {
                let next = reflect(incoming, shading);
                let tint = self.metal_reflection_tint(material, point.uv, tint, (incoming, next));
                Some((next, tint, Lobe::Specular))
            }
            Surface::Dielectric { ior, thin_walled } => {
                let eta = render::optics::relative_eta(ior, front, thin_walled);
                let cos_i = -incoming.dot(shading);
                // Under a layer (glTF's thin film, specular layer) each channel reflects the
                // layer's share, and the way is chosen by their mean; a sheet's light bounces
                // between its two faces (`layered_reflectance`).
                let layer = self.dielectric_layer(material, point.uv);
                let seen = (cos_i, ior, front || thin_walled);
                let fresnel = fresnel_dielectric(cos_i, eta);
                let (mut reflectance, layered) =
                    layered_reflectance(fresnel, layer, seen, thin_walled);
                if !layer.is_bare() {
                    reflectance = layered.element_sum() / 3.0;
                }
                if rng.next_f32() < reflectance {
                    let tint = tint * layered / reflectance;
                    return Some((reflect(incoming, shading), tint, Lobe::Specular));
                }
                let tint = tint * (Vec3::ONE - layered) / (1.0 - reflectance);
                if thin_walled {
                    return Some((incoming, tint, Lobe::Specular));
                }
                // Radiance through a solid's surface (`eye_refraction_scale`).
                let next = refract(incoming, shading, eta)?;
                Some((next, tint * eye_refraction_scale(eta), Lobe::Specular))
            }
        }
    }
}

/// The side of a hit a path arrived on (`front`: the triangle's front face), and where glTF's
/// diffuse transmission takes the Lambertian lobe to the far side this time, the lobe's tint
/// there.
#[derive(Clone, Copy)]
struct Facing {
    front: bool,
    transmitted: Option<Vec3>,
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

/// The geometric normal and the shading normal before the normal map, facing the path as
/// [`facing_normals`] turns them.
fn facing_interpolated_normals(point: &SurfacePoint, front: bool) -> (Vec3, Vec3) {
    let unmapped = SurfacePoint {
        shading: point.interpolated,
        ..*point
    };
    facing_normals(&unmapped, front)
}

/// The lobe a scattered direction was drawn from.
enum Lobe {
    /// A lobe light sampling also serves (Lambertian, or the GGX reflection of rough metal or
    /// a rough coat), at this solid-angle density, the lobe's choice included: emission met
    /// along it is weighed by MIS.
    LightSampled { pdf: f32 },
    /// A mirror, glass, smooth coat or rough glass bounce: emission met along it counts whole.
    Specular,
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
        assert_furnace_radiance(&testing::furnace_sphere());
    }

    /// The furnace in a blend of mirror and diffuse (`testing::furnace_sphere_blended`): the
    /// mixture reflects 0.5, so L = 1 again (members swapped: 1.67).
    #[test]
    fn blended_furnace_converges_to_the_mixture_s_radiance() {
        assert_furnace_radiance(&testing::furnace_sphere_blended());
    }

    /// The furnace with a ball of dispersive flint glass in view
    /// (`testing::furnace_with_dispersive_glass`): each wavelength refracts its own way
    /// through the lossless ball, which stays invisible, L = 1 in every channel.
    /// 65,536 paths: the wavelength's choice adds colour noise (seed 1: 0.996, 1.007, 0.990;
    /// three channels at 16,384 paths: 1.022, 0.987, 0.977), so each channel is held within 4 % and their average within 2 %.
    #[test]
    fn dispersive_glass_in_the_furnace_is_invisible() {
        let mean = furnace_mean(&testing::furnace_with_dispersive_glass(), 1024);
        let expected = testing::FURNACE_RADIANCE;
        let average = mean.element_sum() / 3.0;
        println!("dispersive furnace: {mean}");
        assert!((average - expected).abs() < 0.02 * expected, "{mean}");
        assert!(
            (mean - Vec3::splat(expected)).abs().max_element() < 0.04 * expected,
            "{mean}"
        );
    }

    /// The furnace with a ball of clear glass under a tinted, weak specular layer in view
    /// (`testing::furnace_with_layered_glass`): each channel reflects its layer's share and
    /// lets the rest through (total internal reflection kept inside), so the ball is lossless
    /// and invisible, L = 1 in every channel. 65,536 paths; measured, seed 1: 1.0009, 1.0007,
    /// 1.0006. Tolerance: each channel within 1.5 %.
    #[test]
    fn glass_under_a_specular_layer_in_the_furnace_is_invisible() {
        let mean = furnace_mean(&testing::furnace_with_layered_glass(), 1024);
        println!("layered glass furnace: {mean}");
        let expected = testing::FURNACE_RADIANCE;
        assert!(
            (mean - Vec3::splat(expected)).abs().max_element() < 0.015 * expected,
            "{mean}"
        );
    }

    /// The furnace with a lossless scattering solid in view
    /// (`testing::furnace_with_scattering_solid`, σs = (20, 8, 3), g = 0.5): paths passing
    /// its surface walk through it (`render::scattering::Walk`) and out, none lost, so it
    /// stays invisible, L = 1 in every channel. 65,536 paths, seeds 1–3: channels 0.990–1.003
    /// (16,384 paths: 0.966–1.022 over seeds 1–4). Tolerance: each channel within 3 %.
    #[test]
    fn a_scattering_solid_in_the_furnace_is_invisible() {
        let scene = testing::furnace_with_scattering_solid(Vec3::new(20.0, 8.0, 3.0), 0.5);
        assert_furnace_within("scattering furnace", &scene, 1024, 0.03);
    }

    /// The furnace with lossless murky glass in view (`testing::furnace_with_murky_glass`: a
    /// smooth glass ball of index 1.33 scattering σs = (20, 8, 3) inside, g = 0.5): paths
    /// refracted into it walk through it and out through its glass, none lost, so it stays
    /// invisible. 524,288 paths, seeds 1–2: channels 0.979–1.002 (65,536: red 0.958, the
    /// walks in it long and the glass's Fresnel choices on top). Tolerance: each channel
    /// within 3 %, as for the translucent solid.
    #[test]
    fn murky_glass_in_the_furnace_is_invisible() {
        let scene = testing::furnace_with_murky_glass(Vec3::new(20.0, 8.0, 3.0), 0.5, 1.33);
        assert_furnace_within("murky furnace", &scene, 8192, 0.03);
    }

    /// The furnace filled with a lossless atmosphere (`testing::furnace_in_an_atmosphere`,
    /// σs = (2, 1, 0.5), g = 0.3): paths start in the fog and walk through it to the walls
    /// and back, none lost, so it stays invisible. 65,536 paths, seed 1: channels 1.000,
    /// 1.000, 0.997. Tolerance: each channel within 3 %.
    #[test]
    fn an_atmosphere_in_the_furnace_is_invisible() {
        let scene = testing::furnace_in_an_atmosphere(Vec3::new(2.0, 1.0, 0.5), 0.3);
        assert_furnace_within("atmosphere furnace", &scene, 1024, 0.03);
    }

    /// A lamp inside a lossless scattering solid (`testing::lamp_in_scattering_cube`): a
    /// sixth of its light leaves through the top face, whose radiance averages I / (6h²).
    /// Paths looking straight down at points spread evenly over the face (a 512 × 512 grid)
    /// pass its surface and walk inside, each segment sampling the lamp's light scattered
    /// once along it (`PathTracer::segment_light`, equiangular) and the face's inside the
    /// light reaching it unscattered. Seeds 1–3, each channel: −4.4 % to +1.1 % (red, the
    /// most scattering, the widest: a segment passing at D from the lamp still weighs ~1/D,
    /// whose variance diverges slowly; light samples at the scatterings instead, 1/d²:
    /// −21 % to +9 % at 16,384 paths). Tolerance: 6 %.
    #[test]
    fn a_lamp_inside_a_scattering_solid_sends_a_sixth_through_each_face() {
        let scene = testing::lamp_in_scattering_cube(Vec3::new(2.0, 1.0, 0.5), 0.3);
        let (bvh, camera) = tracer_for(&scene);
        let tracer = PathTracer::new(&scene, &bvh, camera);
        let h = testing::SCATTERING_CUBE_HALF_SIDE;
        let expected = testing::TRANSLUCENT_CUBE_LAMP_INTENSITY / (6.0 * h * h);
        let mut rng = Rng::new(1, 0);
        let side = 512;
        let sum: Vec3 = (0..side * side)
            .map(|i| {
                let at = |k: u32| ((k as f32 + 0.5) / side as f32 * 2.0 - 1.0) * h;
                let origin = Vec3::new(at(i % side), 0.5, at(i / side));
                tracer.radiance(origin, Vec3::NEG_Y, 32, &mut rng)
            })
            .sum();
        let mean = sum / (side * side) as f32;
        println!("lamp in a scattering cube: {mean} against {expected}");
        assert!(
            (mean / expected - Vec3::ONE).abs().max_element() < 0.06,
            "{mean} against {expected}"
        );
    }

    /// The mean of an 8 × 8 image of furnace `scene` from seed 1, `samples_per_pixel` paths a
    /// pixel, up to 64 bounces.
    fn furnace_mean(scene: &Scene, samples_per_pixel: u32) -> Vec3 {
        let (bvh, camera) = tracer_for(scene);
        let settings = RenderSettings {
            width: 8,
            height: 8,
            samples_per_pixel,
            max_depth: 64,
            seed: 1,
        };
        PathTracer::new(scene, &bvh, camera)
            .render(&settings)
            .mean()
    }

    /// The image of a furnace `scene` has mean radiance `testing::FURNACE_RADIANCE`: 16,384
    /// paths, each with a standard deviation below 1, so 2 % is > 5 sigma.
    fn assert_furnace_radiance(scene: &Scene) {
        let mean = furnace_mean(scene, 256);
        let expected = testing::FURNACE_RADIANCE;
        assert!(
            (mean - Vec3::splat(expected)).abs().max_element() < 0.02 * expected,
            "{mean}"
        );
    }

    /// Each channel of a furnace `scene`'s image mean (`label` in the printout) within
    /// `tolerance` (a share) of `testing::FURNACE_RADIANCE`, over `samples_per_pixel` paths a
    /// pixel of [`furnace_mean`]'s 8 × 8.
    fn assert_furnace_within(label: &str, scene: &Scene, samples_per_pixel: u32, tolerance: f32) {
        let mean = furnace_mean(scene, samples_per_pixel);
        println!("{label}: {mean}");
        let expected = testing::FURNACE_RADIANCE;
        assert!(
            (mean - Vec3::splat(expected)).abs().max_element() < tolerance * expected,
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

    /// The lit plane tiled by a metallic-roughness texture (`testing::lit_plane_metallic_tiles`)
    /// seen straight down at the centre of a tile of each kind: a mirror (the light overhead,
    /// 0.5), Lambertian, half of each, and metal of roughness 1 (Lambertian): the texel's
    /// metalness weighs the blend and its roughness picks the metal's surface. 16,384 paths a
    /// point: measured over seeds 1–4 within 0.93 % (the mirror exact); tolerance 2 % (the
    /// metalness ignored: +39 % on the Lambertian tile).
    #[test]
    fn a_metallic_roughness_texture_tiles_the_lit_plane() {
        let scene = testing::lit_plane_metallic_tiles();
        let (bvh, camera) = tracer_for(&scene);
        let tracer = PathTracer::new(&scene, &bvh, camera);
        let mut rng = Rng::new(3, 0);
        for x in [-0.375, -0.125, 0.125, 0.375] {
            let z = -0.375;
            let origin = Vec3::new(x, 0.5, z);
            let samples = 16384;
            let sum: Vec3 = (0..samples)
                .map(|_| tracer.radiance(origin, Vec3::NEG_Y, 8, &mut rng))
                .sum();
            let measured = sum / samples as f32;
            let expected = testing::lit_plane_metallic_tile_radiance(x, z, 0.0).unwrap();
            let error = (measured - Vec3::splat(expected)).abs().max_element();
            assert!(
                error < 0.02 * expected,
                "at ({x}, {z}): {measured} against {expected}"
            );
        }
    }

    /// The sky over the diffuse plane under index-matched absorbing water
    /// (`testing::plane_under_water`), seen straight down: ρ·L·2E₃(τ)·exp(−τ) per channel
    /// (`testing::plane_under_water_radiance`). The camera ray's segment under the layer ends
    /// at the plane's front face, absorbed only by a path that knows it is in the water
    /// (`render::medium`); light samples are blocked by the layer, so the sky comes by the
    /// bounces, each cosine-drawn way up absorbed over depth/μ. 16,384 paths: the mean's
    /// standard error is under 0.5 %; tolerance 2 %.
    #[test]
    fn sky_through_absorbing_water_follows_beer_lambert() {
        let (sky, depth) = (2.0f32, 0.02f32);
        let absorption = Vec3::new(25.0, 12.5, 5.0);
        let mut scene = testing::plane_under_water(depth, absorption);
        let bounds = scene.bounds();
        scene.lights.set_sky(Vec3::splat(sky), bounds);
        let measured = mean_looking_down(&scene, Vec3::new(0.1, 0.5, -0.1), 16_384, 5);
        for channel in 0..3 {
            let expected =
                testing::plane_under_water_radiance(depth, absorption[channel], sky, 1.0);
            let error = (measured[channel] / expected - 1.0).abs();
            assert!(
                error < 0.02,
                "channel {channel}: {} against {expected}",
                measured[channel]
            );
        }
    }

    /// The mean radiance of `samples` paths from `origin` straight down into `scene`.
    fn mean_looking_down(scene: &Scene, origin: Vec3, samples: u32, seed: u64) -> Vec3 {
        let (bvh, camera) = tracer_for(scene);
        let tracer = PathTracer::new(scene, &bvh, camera);
        let mut rng = Rng::new(seed, 0);
        let sum: Vec3 = (0..samples)
            .map(|_| tracer.radiance(origin, Vec3::NEG_Y, 8, &mut rng))
            .sum();
        sum / samples as f32
    }

    /// The plane under a sky map (`testing::plane_under_sky_map`): its radiance is
    /// ρ/π · ∫ L cos θ dω over the map's upper hemisphere (`SkyMap::floor_irradiance`). Light samples
    /// drawn by the map and cosine bounces that escape to it are weighed against each other
    /// (`sky_pdf`): a wrong weight or density shows in the sum. 16,384 paths: the mean's
    /// standard error is under 0.5 %; tolerance 2 %.
    #[test]
    fn a_sky_map_lights_the_plane_to_its_cosine_weighted_integral() {
        let scale = Vec3::new(1.0, 0.7, 1.3);
        let scene = testing::plane_under_sky_map(scale, 0.6);
        let measured = mean_looking_down(&scene, Vec3::new(0.1, 0.5, -0.1), 16_384, 9);
        let irradiance = testing::sunset_sky_map().floor_irradiance() * scale;
        let expected = testing::LIT_PLANE_ALBEDO / std::f32::consts::PI * irradiance;
        let error = (measured / expected - Vec3::ONE).abs();
        assert!(error.max_element() < 0.02, "{measured} against {expected}");
    }

    /// An underwater lamp (`testing::underwater_lamp`): the point light and the camera in
    /// index-matched water of absorption σ. A path from the camera's medium straight down to
    /// the plane below the lamp sees ρ/π · I/h² · exp(−σ(h + d)), d the way down from the
    /// origin; the light sample is the only way the lamp arrives and it is exact but for the
    /// shadow ray's absorption, taken over a ray that stops just short of the light (1e-4
    /// relative, measured): tolerance 5e-4. Without the camera's medium it came out 3.3× too
    /// bright in red (measured: nothing absorbed).
    #[test]
    fn an_underwater_lamp_is_seen_through_the_water() {
        let scene = testing::underwater_lamp();
        let (bvh, camera) = tracer_for(&scene);
        let tracer = PathTracer::new(&scene, &bvh, camera);
        let mut rng = Rng::new(9, 0);
        let (h, d) = (testing::UNDERWATER_LAMP_HEIGHT, 0.5);
        let intensity = testing::UNDERWATER_LAMP_INTENSITY;
        let measured = tracer.radiance(Vec3::new(0.0, d, 0.0), Vec3::NEG_Y, 8, &mut rng);
        let sigma = testing::UNDERWATER_ABSORPTION;
        let expected = testing::LIT_PLANE_ALBEDO / std::f32::consts::PI * intensity / (h * h)
            * (-sigma * (h + d)).exp();
        assert!(
            ((measured - expected) / expected).abs().max_element() < 5e-4,
            "{measured} against {expected}"
        );
    }

    /// The underwater lamp with an invisible marble (`testing::underwater_lamp_with_marble`:
    /// the water's own index and absorption), a path looking down through the marble's edge at
    /// a point of the plane whose light sample passes beside it: the water absorbs all the way,
    /// the marble's share included and the water's below it, where the path is in the water
    /// again (`render::nesting`): ρ/π · I·h/r³ · exp(−σ(r + d)). Tolerance as without the
    /// marble (5e-4).
    #[test]
    fn a_path_leaving_a_marble_in_water_is_in_the_water_again() {
        let scene = testing::underwater_lamp_with_marble();
        let (bvh, camera) = tracer_for(&scene);
        let tracer = PathTracer::new(&scene, &bvh, camera);
        let mut rng = Rng::new(9, 0);
        let (origin, target) = (Vec3::new(-0.05, 0.5, 0.0), Vec3::new(0.3, 0.0, 0.0));
        let direction = (target - origin).normalize();
        // The way down crosses the marble.
        let centre = testing::UNDERWATER_MARBLE_CENTRE;
        let closest = (centre - origin).dot(direction);
        let miss = (origin + closest * direction - centre).length();
        assert!(miss < 0.8 * testing::UNDERWATER_MARBLE_RADIUS, "{miss}");
        let measured = tracer.radiance(origin, direction, 8, &mut rng);
        let h = testing::UNDERWATER_LAMP_HEIGHT;
        let r = (target.x * target.x + h * h).sqrt();
        let d = (target - origin).length();
        let sigma = testing::UNDERWATER_ABSORPTION;
        let expected = testing::LIT_PLANE_ALBEDO / std::f32::consts::PI
            * testing::UNDERWATER_LAMP_INTENSITY
            * h
            / (r * r * r)
            * (-sigma * (r + d)).exp();
        assert!(
            ((measured - expected) / expected).abs().max_element() < 5e-4,
            "{measured} against {expected}"
        );
    }

    /// A lamp inside a translucent solid (`testing::lamp_in_translucent_cube`: its surface
    /// passes all light diffusely, σ absorbed inside): a path looking down at the top's centre
    /// passes it, and the far side's light sample, from inside, runs through the cube: the
    /// top shows I·h·exp(−σh)/(π·h³). The path then goes on inside, and every face it meets
    /// sends it out to nothing: the light sample is all, exact but for the shadow ray's
    /// absorption (tolerance 5e-4). Without the far side's medium it came out e^σh too bright.
    #[test]
    fn a_lamp_inside_a_translucent_solid_is_seen_through_it() {
        let absorption = Vec3::new(2.0, 1.0, 0.5);
        let scene = testing::lamp_in_translucent_cube(absorption);
        let (bvh, camera) = tracer_for(&scene);
        let tracer = PathTracer::new(&scene, &bvh, camera);
        let mut rng = Rng::new(9, 0);
        let measured = tracer.radiance(Vec3::new(0.0, 0.5, 0.0), Vec3::NEG_Y, 8, &mut rng);
        let h = testing::TRANSLUCENT_CUBE_HALF_SIDE;
        let expected = testing::TRANSLUCENT_CUBE_LAMP_INTENSITY * (-absorption * h).exp()
            / (std::f32::consts::PI * h * h);
        assert!(
            ((measured - expected) / expected).abs().max_element() < 5e-4,
            "{measured} against {expected}"
        );
    }

    /// A point light and a directional one over the diffuse plane: ρ/π · I·h/r³ and
    /// ρ/π · E·cos θ. The one light sample per hit is the only way light arrives (the plane
    /// is open, bounces leave it), and it is exact: tolerance 1e-4 (f32 arithmetic).
    #[test]
    fn punctual_lights_light_the_plane_exactly() {
        use scene::{PunctualKind, PunctualLight};
        let (h, intensity, illuminance) = (1.0f32, 2.0f32, 1.5f32);
        let albedo_over_pi = testing::LIT_PLANE_ALBEDO / std::f32::consts::PI;
        let point = PunctualLight {
            kind: PunctualKind::Point,
            position: Vec3::new(0.0, h, 0.0),
            direction: Vec3::ZERO,
            intensity: Vec3::splat(intensity),
        };
        let sun = PunctualLight {
            kind: PunctualKind::Directional,
            position: Vec3::ZERO,
            direction: Vec3::new(0.6, -0.8, 0.0),
            intensity: Vec3::splat(illuminance),
        };
        let lit_by_point = |x: f32, z: f32| {
            let r = (x * x + z * z + h * h).sqrt();
            albedo_over_pi * intensity * h / (r * r * r)
        };
        let lit_by_sun = |_: f32, _: f32| albedo_over_pi * illuminance * 0.8;
        type Radiance<'a> = &'a dyn Fn(f32, f32) -> f32;
        let cases: [(PunctualLight, Radiance); 2] = [(point, &lit_by_point), (sun, &lit_by_sun)];
        for (light, expected) in cases {
            let scene = testing::punctual_plane(&[light]);
            let (bvh, camera) = tracer_for(&scene);
            let tracer = PathTracer::new(&scene, &bvh, camera);
            let mut rng = Rng::new(9, 0);
            for (x, z) in [(0.0, 0.0), (0.5, -0.3), (-0.8, 0.7)] {
                let origin = Vec3::new(x, 0.5, z);
                let measured = tracer.radiance(origin, Vec3::NEG_Y, 8, &mut rng);
                let expected = expected(x, z);
                assert!(
                    (measured - Vec3::splat(expected)).abs().max_element() < 1e-4 * expected,
                    "{:?} at ({x}, {z}): {measured} against {expected}",
                    light.kind
                );
            }
        }
    }

    /// A square light whose emission texture is black but for one white quarter, over the
    /// diffuse plane, seen straight down under that quarter, where the texture's mean would be
    /// wrong: light
    /// samples read the texture where they land, and the tracer's radiance matches plain
    /// cosine sampling of the light (in the test, through the same hits) within four standard
    /// errors of the difference.
    #[test]
    fn light_samples_read_a_textured_emitter_where_they_land() {
        use scene::{Texels, Texture};
        let half = testing::LIT_PLANE_HALF_SIZE;
        let mut scene = testing::lit_plane_under(half);
        // 8² texels, the quarter at u, v > 0.5 white (bilinear filtering blurs only its edges).
        let texels = (0..64)
            .map(|i| {
                let white = i % 8 >= 4 && i / 8 >= 4;
                let level = if white { 1.0 } else { 0.0 };
                [level, level, level, 1.0]
            })
            .collect();
        scene.textures.push(Texture {
            name: "checker".into(),
            width: 8,
            height: 8,
            texels: Texels::LinearF32(texels),
        });
        let checker = (scene.textures.len() - 1) as u32;
        let light = scene
            .materials
            .iter()
            .position(|m| m.is_emissive())
            .expect("a light");
        scene.materials[light].emission_texture = Some(checker);
        for triangle in &mut scene.triangles {
            if triangle.material as usize == light {
                for vertex in &mut triangle.vertices {
                    let p = vertex.position / half;
                    vertex.uv = Vec2::new(0.5 * (p.x + 1.0), 0.5 * (p.z + 1.0));
                }
            }
        }
        let (bvh, camera) = tracer_for(&scene);
        let tracer = PathTracer::new(&scene, &bvh, camera);
        // Under the middle of the white quarter.
        let (x, z) = (0.25, 0.25);
        let mut rng = Rng::new(13, 0);
        let traced = mean_and_error(40_000, || {
            let origin = Vec3::new(x, 0.5, z);
            tracer.radiance(origin, Vec3::NEG_Y, 8, &mut rng).x as f64
        });
        let mut rng = Rng::new(14, 0);
        let albedo = testing::LIT_PLANE_ALBEDO;
        let sampled = mean_and_error(400_000, || {
            let local = cosine_hemisphere(rng.next_f32(), rng.next_f32());
            let direction = Vec3::new(local.x, local.z, local.y);
            let seen = tracer
                .intersect(Vec3::new(x, 1e-4, z), direction)
                .map_or(Vec3::ZERO, |hit| {
                    tracer.emission(&tracer.materials[hit.material as usize], hit.uv)
                });
            (albedo * seen.x) as f64
        });
        let error = (traced.1 * traced.1 + sampled.1 * sampled.1).sqrt();
        assert!(
            (traced.0 - sampled.0).abs() < 4.0 * error,
            "traced {traced:?}, sampled {sampled:?}"
        );
        let uniform = testing::square_light_radiance(x, z, half) as f64;
        assert!(
            sampled.0 > 0.3 * uniform,
            "the texture does not matter here: {sampled:?} against {uniform}"
        );
    }

    /// The punctual plane made of `surface`, under a sky of radiance `sky` and no other light.
    fn plane_under_sky(surface: Surface, sky: f32) -> Scene {
        let mut scene = testing::punctual_plane(&[]);
        let bounds = scene.bounds();
        scene.lights.set_sky(Vec3::splat(sky), bounds);
        for material in &mut scene.materials {
            material.surface = surface;
        }
        scene
    }

    /// Mean and standard error of `samples` draws of `draw`.
    fn mean_and_error(samples: u32, mut draw: impl FnMut() -> f64) -> (f64, f64) {
        let (mut sum, mut sum_squares) = (0.0, 0.0);
        for _ in 0..samples {
            let x = draw();
            sum += x;
            sum_squares += x * x;
        }
        let n = samples as f64;
        let mean = sum / n;
        (mean, ((sum_squares / n - mean * mean).max(0.0) / n).sqrt())
    }

    /// Rough metal, a rough plastic coat, solid frosted glass and a thin frosted sheet under
    /// the sky, seen at 60°: the tracer, which samples the sky at the hit and weighs it
    /// against the GGX lobe's own sampling (and the coat's base against its cosine sampling),
    /// against the lobes' sampling alone, drawn here straight from the samplers
    /// (`rough_reflection` weighed by the metal's Fresnel reflectance at its micro-normal,
    /// `coat_event`, a cosine bounce out through the coat, `rough_dielectric`) with every
    /// escaping ray seeing the sky. They must agree within four
    /// standard errors of the difference (the sheet's reflections weighed as if the sky were
    /// sampled on their side too: 0.75 against 0.82).
    #[test]
    fn glossy_light_samples_keep_the_sky_s_expectation() {
        use render::microfacet::rough_reflection;
        use render::plastic::coat_event;
        let sky = 2.0f32;
        let alpha = 0.3;
        let direction = Vec3::new(0.75f32.sqrt(), -0.5, 0.0);
        let cases = [
            Surface::RoughConductor { alpha },
            Surface::Plastic { ior: 1.5, alpha },
            Surface::RoughDielectric {
                ior: 1.5,
                thin_walled: false,
                alpha,
            },
            Surface::RoughDielectric {
                ior: 1.5,
                thin_walled: true,
                alpha,
            },
        ];
        for surface in cases {
            let scene = plane_under_sky(surface, sky);
            let albedo = scene.materials[0].base_color.x;
            let (bvh, camera) = tracer_for(&scene);
            let tracer = PathTracer::new(&scene, &bvh, camera);
            let mut rng = Rng::new(11, 0);
            let origin = -0.4 * direction;
            let traced = mean_and_error(40_000, || {
                tracer.radiance(origin, direction, 8, &mut rng).x as f64
            });
            let mut rng = Rng::new(12, 0);
            let normal = Vec3::Y;
            let coat = Coat::of(&surface);
            let sampled = mean_and_error(400_000, || {
                let u = [rng.next_f32(), rng.next_f32(), rng.next_f32()];
                let seen = match surface {
                    Surface::RoughConductor { alpha } => {
                        rough_reflection(direction, normal, alpha, u[0], u[1]).map_or(
                            0.0,
                            |(next, weight)| {
                                // The metal's Fresnel reflectance at the micro-normal.
                                let metal = Metal {
                                    f0: Vec3::splat(albedo),
                                    edge: Vec3::ONE,
                                    film: Film::default(),
                                };
                                let tint = metal.tint(-direction, next).x;
                                tint * weight * f32::from(next.y > 0.0)
                            },
                        )
                    }
                    Surface::Plastic { .. } => match coat_event(direction, normal, &coat, u) {
                        CoatEvent::Reflected { direction, weight } => {
                            weight * f32::from(direction.y > 0.0)
                        }
                        CoatEvent::Base { weight } => {
                            let out = cosine_hemisphere(rng.next_f32(), rng.next_f32());
                            albedo * coat.diffuse_scale * weight * coat.transmittance(out.z)
                        }
                    },
                    // Reflected or refracted, the ray leaves the open plane and sees the sky;
                    // refracted, it crossed into the glass (`eye_refraction_scale`), through a
                    // sheet it did not.
                    Surface::RoughDielectric {
                        ior, thin_walled, ..
                    } => render::microfacet::rough_dielectric(
                        direction,
                        normal,
                        1.0 / ior,
                        thin_walled,
                        alpha,
                        u,
                    )
                    .map_or(0.0, |(next, weight)| {
                        let crossing = if next.y < 0.0 && !thin_walled {
                            eye_refraction_scale(1.0 / ior)
                        } else {
                            1.0
                        };
                        albedo * weight * crossing
                    }),
                    _ => unreachable!(),
                };
                (sky * seen) as f64
            });
            let error = (traced.1 * traced.1 + sampled.1 * sampled.1).sqrt();
            assert!(
                (traced.0 - sampled.0).abs() < 4.0 * error,
                "{surface:?}: traced {traced:?}, sampled {sampled:?}"
            );
            assert!(traced.0 > 0.1 * sky as f64, "{surface:?}: {traced:?}");
        }
    }

    /// Frosted glass under a thin film (index 1.33, 420 nm) under the sky, solid and a thin
    /// sheet, seen at 60°: the tracer, whose light samples at the frosted lobe take the film's
    /// share at the light's direction and whose bounces take it at theirs, against
    /// `rough_dielectric`'s sampling alone weighed by the film's share
    /// (`render::iridescence::rough_dielectric_film_weight`), every channel within four
    /// standard errors of the difference. The light samples' share left out moves the
    /// reflection's MIS part (measured: fails).
    #[test]
    fn frosted_glass_under_a_film_keeps_the_sky_s_expectation() {
        let (sky, alpha) = (2.0f32, 0.3f32);
        let direction = Vec3::new(0.75f32.sqrt(), -0.5, 0.0);
        let film = Film {
            factor: 1.0,
            ior: 1.33,
            thickness: 420.0,
        };
        for thin_walled in [false, true] {
            let surface = Surface::RoughDielectric {
                ior: 1.5,
                thin_walled,
                alpha,
            };
            let mut scene = plane_under_sky(surface, sky);
            for material in &mut scene.materials {
                material.iridescence = Some(testing::film(1.33, 420.0));
            }
            let albedo = scene.materials[0].base_color;
            let (bvh, camera) = tracer_for(&scene);
            let tracer = PathTracer::new(&scene, &bvh, camera);
            let origin = -0.4 * direction;
            let eta = 1.0 / 1.5;
            for channel in 0..3 {
                let mut rng = Rng::new(11, 0);
                let traced = mean_and_error(40_000, || {
                    tracer.radiance(origin, direction, 8, &mut rng)[channel] as f64
                });
                let mut rng = Rng::new(12, 0);
                let sampled = mean_and_error(400_000, || {
                    let u = [rng.next_f32(), rng.next_f32(), rng.next_f32()];
                    render::microfacet::rough_dielectric(
                        direction,
                        Vec3::Y,
                        eta,
                        thin_walled,
                        alpha,
                        u,
                    )
                    .map_or(0.0, |(next, weight)| {
                        let ways = (-direction, next);
                        let share = rough_dielectric_layer_weight(
                            DielectricLayer {
                                film,
                                specular: None,
                            },
                            ways,
                            Vec3::Y,
                            eta,
                            thin_walled,
                        );
                        let crossing = if next.y < 0.0 && !thin_walled {
                            eye_refraction_scale(eta)
                        } else {
                            1.0
                        };
                        (sky * albedo[channel] * weight * crossing * share[channel]) as f64
                    })
                });
                let error = (traced.1 * traced.1 + sampled.1 * sampled.1).sqrt();
                assert!(
                    (traced.0 - sampled.0).abs() < 4.0 * error,
                    "thin {thin_walled}, channel {channel}: traced {traced:?}, sampled {sampled:?}"
                );
            }
        }
    }

    /// The frosted plane under the sky met from inside (from below, the quad's back): light
    /// samples through its refraction out, weighed against the refraction's own sampling,
    /// against `rough_dielectric` alone (every way out sees the sky), within four standard
    /// errors of the difference.
    #[test]
    fn frosted_glass_from_inside_keeps_the_sky_s_expectation() {
        let (sky, ior, alpha) = (2.0f32, 1.5f32, 0.3f32);
        let surface = Surface::RoughDielectric {
            ior,
            thin_walled: false,
            alpha,
        };
        let scene = plane_under_sky(surface, sky);
        let albedo = scene.materials[0].base_color.x;
        let (bvh, camera) = tracer_for(&scene);
        let tracer = PathTracer::new(&scene, &bvh, camera);
        let direction = Vec3::new(0.5, 0.75f32.sqrt(), 0.0);
        let origin = -0.4 * direction;
        let mut rng = Rng::new(15, 0);
        let traced = mean_and_error(40_000, || {
            tracer.radiance(origin, direction, 8, &mut rng).x as f64
        });
        let mut rng = Rng::new(16, 0);
        let sampled = mean_and_error(400_000, || {
            let u = [rng.next_f32(), rng.next_f32(), rng.next_f32()];
            // Refracted out, the ray crossed out of the glass (`eye_refraction_scale`).
            render::microfacet::rough_dielectric(direction, Vec3::NEG_Y, ior, false, alpha, u)
                .map_or(0.0, |(next, weight)| {
                    let crossing = if next.y > 0.0 {
                        eye_refraction_scale(ior)
                    } else {
                        1.0
                    };
                    (sky * albedo * weight * crossing) as f64
                })
        });
        let error = (traced.1 * traced.1 + sampled.1 * sampled.1).sqrt();
        assert!(
            (traced.0 - sampled.0).abs() < 4.0 * error,
            "traced {traced:?}, sampled {sampled:?}"
        );
        assert!(traced.0 > 0.1 * sky as f64, "{traced:?}");
    }

    /// A smooth plastic plane under the sky L, seen straight down and at 60°: L·(R(θ) +
    /// ρ·s·(1 − R(θ))·T), T = 2∫(1 − R(μ))μ dμ by the midpoint rule (as the SPPM tests in
    /// `crates/cpu/tests/analytic.rs`); the coat's reflection and the base's light samples
    /// and bounces through the tracer's MIS. Bare, R is the coat's Fresnel reflectance F
    /// (within 1 %); under a thin film (index 1.8, 420 nm, factor 0.8) glTF's mix of F and the
    /// film's, and under a specular layer of strength 0.7 tinted (1.5, 1, 0.5) glTF's
    /// reflectance, 0.7·F0·tint head on and 0.7 at grazing (`render::dielectric_layer`), with the
    /// base scaled by 1 / T instead of s (`DielectricLayer::diffuse_share`: a white base returns all
    /// the light), each channel within 1.5 %.
    #[test]
    fn plastic_plane_under_the_sky_returns_coat_and_base() {
        use render::dielectric_layer::DielectricLayer;
        use render::plastic::{coat_reflectance, diffuse_scale};
        let (sky, ior) = (2.0f32, 1.5f32);
        let film = scene::Iridescence {
            factor: 0.8,
            ..testing::film(1.8, 420.0)
        };
        let tint = Vec3::new(1.5, 1.0, 0.5);
        let specular = scene::SpecularLayer::new(ior, tint, 0.7);
        for (iridescence, layer, tolerance) in [
            (None, None, 0.01),
            (Some(film), None, 0.015),
            (None, Some(specular), 0.015),
        ] {
            let mut scene = plane_under_sky(Surface::Plastic { ior, alpha: 0.0 }, sky);
            for material in &mut scene.materials {
                material.iridescence = iridescence;
                material.specular = layer;
            }
            let at = DielectricLayer {
                specular: layer.map(|s| LayerReflectance::of(&s, None, None)),
                film: iridescence.map_or(Film::default(), |f| Film::of(&f, None, None)),
            };
            let (bvh, camera) = tracer_for(&scene);
            let tracer = PathTracer::new(&scene, &bvh, camera);
            let reflectance = |cos: f32| at.reflectance(coat_reflectance(cos, ior), cos, ior);
            let steps = 100_000;
            let transmittance = (0..steps)
                .map(|i| {
                    let mu = (i as f64 + 0.5) / steps as f64;
                    (Vec3::ONE - reflectance(mu as f32)).as_dvec3() * (2.0 * mu / steps as f64)
                })
                .sum::<glam::DVec3>();
            let mut rng = Rng::new(5, 0);
            for cos in [1.0f32, 0.5] {
                let direction = Vec3::new((1.0 - cos * cos).sqrt(), -cos, 0.0);
                // Towards the plane's centre from 0.4 away.
                let origin = -0.4 * direction;
                let samples = 20_000;
                let sum: Vec3 = (0..samples)
                    .map(|_| tracer.radiance(origin, direction, 8, &mut rng))
                    .sum();
                let measured = (sum / samples as f32).as_dvec3();
                let r = reflectance(cos).as_dvec3();
                let scale = match layer {
                    Some(_) => glam::DVec3::ONE / transmittance,
                    None => glam::DVec3::splat(diffuse_scale(ior) as f64),
                };
                let albedo = testing::LIT_PLANE_ALBEDO as f64 * scale;
                let expected = sky as f64 * (r + albedo * (glam::DVec3::ONE - r) * transmittance);
                let error = (measured / expected - glam::DVec3::ONE).abs().max_element();
                assert!(
                    error < tolerance,
                    "{at:?}, at cos {cos}: {measured} against {expected}"
                );
            }
        }
    }

    /// A Lambertian plane under glTF's sheen of colour (0.5, 0.9, 0.3) and roughness 0.5
    /// under the sky L, seen straight down and at 60° (`render::sheen::sky_plane_radiance`,
    /// as the SPPM test in `crates/cpu/tests/analytic.rs`): the sheen's reflection with its
    /// light sample under MIS, and the plane's light samples and bounces through it, within
    /// 1.5 % in the red channel, whose sheen is weaker than the green one that sets the choice.
    #[test]
    fn sheened_plane_under_the_sky_returns_sheen_and_plane() {
        let sky = 2.0f32;
        let color = Vec3::new(0.5, 0.9, 0.3);
        let mut scene = plane_under_sky(Surface::Diffuse, sky);
        for material in &mut scene.materials {
            material.sheen = scene::Sheen::new(color, 0.5);
        }
        let (bvh, camera) = tracer_for(&scene);
        let tracer = PathTracer::new(&scene, &bvh, camera);
        let radiance =
            render::sheen::sky_plane_radiance(sky, testing::LIT_PLANE_ALBEDO, color, 0.5, 0);
        assert_sky_plane(&tracer, radiance, 40_000, 0.015);
    }

    /// A Lambertian plane under glTF's smooth clear coat of weight 0.7 under the sky L, seen
    /// straight down and at 60°: L·(w·F(θ) + (1 − w·F(θ))·ρ·(1 − w·F̄)), F̄ = 2∫F(μ)μ dμ (as
    /// the SPPM test in `crates/cpu/tests/analytic.rs`); the coat's reflection, and the
    /// plane's light samples and bounces through the coat, within 1 %.
    #[test]
    fn clear_coated_plane_under_the_sky_returns_coat_and_plane() {
        use render::optics::fresnel_dielectric;
        let (sky, weight) = (2.0f32, 0.7f32);
        let mut scene = plane_under_sky(Surface::Diffuse, sky);
        for material in &mut scene.materials {
            material.clearcoat = scene::Clearcoat::new(weight, 0.0);
        }
        let (bvh, camera) = tracer_for(&scene);
        let tracer = PathTracer::new(&scene, &bvh, camera);
        let radiance = testing::clear_coated_sky_plane(
            sky,
            testing::LIT_PLANE_ALBEDO,
            weight,
            fresnel_dielectric,
        );
        assert_sky_plane(&tracer, radiance, 20_000, 0.01);
    }

    /// glTF's diffuse transmission (share t = 0.7, tint c) on the sky's plane, whose faces
    /// both see the sky L: L·((1 − t)·ρ + t·c) seen from above, and as plastic (a smooth coat
    /// of ior 1.5 on both faces) L·(F(θ) + (1 − F(θ))·s·T·((1 − t)·ρ + t·c)), as the SPPM test
    /// in `crates/cpu/tests/analytic.rs`: the far side's light samples and bounces through
    /// the tracer's MIS, within 1 % (red channel).
    #[test]
    fn translucent_plane_under_the_sky_returns_both_faces_light() {
        use render::plastic::{coat_reflectance, diffuse_scale};
        let (sky, share, tint) = (2.0f32, 0.7f32, Vec3::new(0.9, 0.3, 0.6));
        let albedo = ((1.0 - share) * testing::LIT_PLANE_ALBEDO + share * tint.x) as f64;
        let ior = 1.5f32;
        for surface in [Surface::Diffuse, Surface::Plastic { ior, alpha: 0.0 }] {
            let mut scene = plane_under_sky(surface, sky);
            for material in &mut scene.materials {
                material.diffuse_transmission = scene::DiffuseTransmission::new(share, tint);
            }
            let (bvh, camera) = tracer_for(&scene);
            let tracer = PathTracer::new(&scene, &bvh, camera);
            let transmittance =
                testing::cosine_weighted_mean(|mu| 1.0 - coat_reflectance(mu, ior) as f64);
            let radiance = |cos: f32| match surface {
                Surface::Diffuse => sky as f64 * albedo,
                _ => {
                    let f = coat_reflectance(cos, ior) as f64;
                    let base = albedo * diffuse_scale(ior) as f64 * (1.0 - f) * transmittance;
                    sky as f64 * (f + base)
                }
            };
            assert_sky_plane(&tracer, radiance, 20_000, 0.01);
        }
    }

    /// The punctual plane with diffuse transmission (share 0.6, tint c) lit only from below
    /// by a directional light of illuminance E at cos θ = 0.8: its top shows t·c·E·0.8/π, all
    /// of it from the far side's light sample (red channel, within 1.5 %: the side is drawn
    /// per path, so 40,000 paths leave a binomial 0.4 % of noise).
    #[test]
    fn translucent_plane_passes_light_from_below() {
        let (illuminance, share, tint) = (1.5f32, 0.6f32, Vec3::new(0.9, 0.4, 0.2));
        let mut scene = testing::punctual_plane(&[scene::PunctualLight {
            kind: scene::PunctualKind::Directional,
            position: Vec3::ZERO,
            direction: Vec3::new(0.6, 0.8, 0.0),
            intensity: Vec3::splat(illuminance),
        }]);
        for material in &mut scene.materials {
            material.diffuse_transmission = scene::DiffuseTransmission::new(share, tint);
        }
        let (bvh, camera) = tracer_for(&scene);
        let tracer = PathTracer::new(&scene, &bvh, camera);
        let radiance = share * tint.x * std::f32::consts::FRAC_1_PI * 0.8 * illuminance;
        assert_sky_plane(&tracer, |_| radiance as f64, 40_000, 0.015);
    }

    /// A brushed white-ish metal plane (GGX α 0.1, glTF anisotropy 0.8 turned 0.3 rad) under
    /// the sky L: seen straight down and at 60°, it returns L·E(view), E the brushed lobe's
    /// directional albedo with the metal's Fresnel reflectance from ρ by quadrature over the
    /// hemisphere (`render::microfacet::
    /// brushed_response`, about the brushing the hit computes: the plane has no texture
    /// coordinates, so any frame about its normal), within 0.5 % over 200,000 paths (20,000
    /// left 1 % of noise): the tracer's brushed bounces and light samples under MIS. The same plane brushed at right angles returns a different
    /// light at 60° (the check can tell the brushing's direction).
    #[test]
    fn brushed_metal_plane_under_the_sky_returns_its_albedo() {
        let (sky, alpha) = (2.0f32, 0.1f32);
        // The lobe's albedo with the metal's Fresnel reflectance from ρ at each micro-normal.
        let albedo_of = |brush: Vec3, view: Vec3, rho: f32| {
            let metal = Metal {
                f0: Vec3::splat(rho),
                edge: Vec3::ONE,
                film: Film::default(),
            };
            let n = 600;
            let mut sum = 0.0f64;
            for i in 0..n {
                let x = (i as f64 + 0.5) / n as f64;
                let cos_theta = 1.0 - x * x;
                let d_cos = 2.0 * x / n as f64;
                let sin_theta = (1.0 - cos_theta * cos_theta).max(0.0).sqrt();
                for j in 0..n {
                    let phi = (j as f64 + 0.5) / n as f64 * std::f64::consts::TAU;
                    // About +Y, the plane's normal.
                    let l = Vec3::new(
                        (sin_theta * phi.cos()) as f32,
                        cos_theta as f32,
                        (sin_theta * phi.sin()) as f32,
                    );
                    let value =
                        render::microfacet::brushed_response(view, l, Vec3::Y, brush, alpha);
                    let tint = metal.tint(view, l).x as f64;
                    sum += tint * value.value as f64 * d_cos * std::f64::consts::TAU / n as f64;
                }
            }
            sum
        };
        let mut radiances = Vec::new();
        for rotation in [0.3f32, 0.3 + std::f32::consts::FRAC_PI_2] {
            let mut scene = plane_under_sky(Surface::RoughConductor { alpha }, sky);
            let anisotropy = scene::Anisotropy {
                strength: 0.8,
                rotation,
                texture: None,
            };
            for material in &mut scene.materials {
                material.anisotropy = Some(anisotropy);
            }
            let rho = scene.materials[0].base_color.x;
            let no_frame = render::normal_map::FrameSource {
                positions: [Vec3::ZERO, Vec3::X, Vec3::Z],
                uvs: [Vec2::ZERO; 3],
                tangent: glam::Vec4::ZERO,
            };
            let brush = render::normal_map::brushing(Vec3::Y, &no_frame, anisotropy.base());
            let (bvh, camera) = tracer_for(&scene);
            let tracer = PathTracer::new(&scene, &bvh, camera);
            let radiance = |cos: f32| {
                let view = Vec3::new(-(1.0 - cos * cos).sqrt(), cos, 0.0);
                sky as f64 * albedo_of(brush, view, rho)
            };
            radiances.push(radiance(0.5));
            assert_sky_plane(&tracer, radiance, 200_000, 0.005);
        }
        assert!(
            (radiances[0] / radiances[1] - 1.0).abs() > 0.02,
            "{radiances:?}"
        );
    }

    /// Metal of colour ρ under a thin film (glTF's iridescence, index 1.8, 420 nm:
    /// `render::iridescence`) under the sky: polished, the plane returns L·F(θ), the film's
    /// mix at the view's angle; rough (α 0.09), L·∫F(h·v)·f(v, l)·cos dω by quadrature, the
    /// film's colour read at each micro-normal of the tracer's bounces and of its light
    /// samples (left out of the light samples: +3 % at normal incidence). The red channel,
    /// whose film colour is not ρ's, within 0.5 % (the mirror with 1,000 paths, the rough
    /// metal with 200,000).
    #[test]
    fn iridescent_metal_plane_under_the_sky_returns_the_film_s_colour() {
        let sky = 2.0f32;
        let base = Vec3::new(0.9, 0.6, 0.3);
        let iridescence = testing::film(1.8, 420.0);
        let film = Film {
            factor: 1.0,
            ior: 1.8,
            thickness: 420.0,
        };
        let with_film = |surface| {
            let mut scene = plane_under_sky(surface, sky);
            for material in &mut scene.materials {
                material.base_color = base;
                material.iridescence = Some(iridescence);
            }
            scene
        };
        let scene = with_film(Surface::Mirror);
        let (bvh, camera) = tracer_for(&scene);
        let tracer = PathTracer::new(&scene, &bvh, camera);
        let metal = Metal {
            f0: base,
            edge: Vec3::ONE,
            film,
        };
        let mirror = |cos: f32| (sky * metal.reflectance(cos)).x as f64;
        assert!((mirror(1.0) / (sky * base.x) as f64 - 1.0).abs() > 0.05);
        assert_sky_plane(&tracer, mirror, 1000, 0.005);

        let alpha = 0.09f32;
        let rough = |cos: f32| {
            let view = Vec3::new(-(1.0 - cos * cos).sqrt(), cos, 0.0);
            let n = 400;
            let mut sum = 0.0f64;
            for i in 0..n {
                let x = (i as f64 + 0.5) / n as f64;
                let cos_l = 1.0 - x * x;
                let d_omega = 2.0 * x / n as f64 * std::f64::consts::TAU / n as f64;
                let sin_l = (1.0 - cos_l * cos_l).max(0.0).sqrt();
                for j in 0..n {
                    let phi = (j as f64 + 0.5) / n as f64 * std::f64::consts::TAU;
                    let l = Vec3::new(
                        (sin_l * phi.cos()) as f32,
                        cos_l as f32,
                        (sin_l * phi.sin()) as f32,
                    );
                    let lobe = glossy_response(view, l, Vec3::Y, alpha, 0.0);
                    if lobe.value > 0.0 {
                        let tint = metal.tint(view, l).x as f64;
                        sum += tint * lobe.value as f64 * d_omega;
                    }
                }
            }
            sky as f64 * sum
        };
        let scene = with_film(Surface::RoughConductor { alpha });
        let (bvh, camera) = tracer_for(&scene);
        let tracer = PathTracer::new(&scene, &bvh, camera);
        assert_sky_plane(&tracer, rough, 200_000, 0.005);
    }

    /// The glass pane under a thin film (index 1.33, 500 nm), a soap film (the same film on a
    /// sheet of index 1, which bare would reflect nothing), and the pane under glTF's specular
    /// layer (strength 0.5, colour (2, 1, 0.25): each face reflects min(F0·colour, 1)·0.5 head
    /// on). A path from the camera chooses reflection or transmission by the layer's mean
    /// reflectance and takes the layer's share of its way over that probability, so the mean
    /// over 100,000 paths is R'·3 + (1 − R')·1 in each channel, R' the layered sheet's
    /// (`render::dielectric_layer::layered_dielectric`); within 1 % (the mean's standard error
    /// ~0.2 %).
    #[test]
    fn iridescent_glass_pane_reflects_the_film_s_share() {
        use render::dielectric_layer::layered_dielectric;
        let film = DielectricLayer {
            film: Film {
                factor: 1.0,
                ior: 1.33,
                thickness: 500.0,
            },
            specular: None,
        };
        let pane_f0 = fresnel_dielectric(1.0, 1.0 / testing::GLASS_PANE_IOR);
        let colour = Vec3::new(2.0, 1.0, 0.25);
        let specular = scene::SpecularLayer::new(testing::GLASS_PANE_IOR, colour, 0.5);
        for (ior, specular) in [
            (testing::GLASS_PANE_IOR, None),
            (1.0, None),
            (testing::GLASS_PANE_IOR, Some(specular)),
        ] {
            let mut scene = testing::glass_pane();
            for material in &mut scene.materials {
                if material.surface.is_glass() {
                    material.surface = Surface::Dielectric {
                        ior,
                        thin_walled: true,
                    };
                    material.iridescence = specular.is_none().then(|| testing::film(1.33, 500.0));
                    material.specular = specular;
                }
            }
            let bare = fresnel_dielectric(1.0, 1.0 / ior);
            let single = match specular {
                Some(_) => (pane_f0 * colour).min(Vec3::ONE) * 0.5,
                None => layered_dielectric(bare, film, 1.0, ior, true),
            };
            let sheet = single.map(|r| 2.0 * r / (1.0 + r));
            let expected = sheet * testing::GLASS_PANE_BACK_EMISSION
                + (Vec3::ONE - sheet) * testing::GLASS_PANE_FRONT_EMISSION;
            let (bvh, camera) = tracer_for(&scene);
            let tracer = PathTracer::new(&scene, &bvh, camera);
            let mut rng = Rng::new(3, 0);
            let samples = 100_000;
            let sum: Vec3 = (0..samples)
                .map(|_| tracer.radiance(Vec3::ZERO, Vec3::Z, 8, &mut rng))
                .sum();
            let measured = sum / samples as f32;
            assert!(
                (measured / expected - Vec3::ONE).abs().max_element() < 0.01,
                "ior {ior}: {measured} against {expected}"
            );
            let bare_sheet = 2.0 * bare / (1.0 + bare);
            assert!(
                (sheet - Vec3::splat(bare_sheet)).abs().max_element() > 0.01,
                "ior {ior}: the layer matters: {sheet} against {bare_sheet}"
            );
        }
    }

    /// The red channel of `samples` paths at the origin's plane seen straight down and at 60°
    /// is `radiance(cos)` within `tolerance` (relative).
    fn assert_sky_plane(
        tracer: &PathTracer,
        radiance: impl Fn(f32) -> f64,
        samples: u32,
        tolerance: f64,
    ) {
        let mut rng = Rng::new(5, 0);
        for cos in [1.0f32, 0.5] {
            let direction = Vec3::new((1.0 - cos * cos).sqrt(), -cos, 0.0);
            let origin = -0.4 * direction;
            let sum: Vec3 = (0..samples)
                .map(|_| tracer.radiance(origin, direction, 8, &mut rng))
                .sum();
            let measured = (sum / samples as f32).x as f64;
            let expected = radiance(cos);
            assert!(
                (measured / expected - 1.0).abs() < tolerance,
                "at cos {cos}: {measured} against {expected}"
            );
        }
    }
}
