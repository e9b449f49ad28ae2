//! The light list: every emissive triangle with its area and power, and the lights without
//! area that glTF files place on nodes (`KHR_lights_punctual`).

use glam::Vec3;

use crate::{Bounds, Material, SkyMap, Texture, Triangle};

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

/// What kind of light without area, with what it needs beyond position and direction.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum PunctualKind {
    /// Emits the same intensity in every direction.
    Point,
    /// Emits around its direction: full intensity within the inner cone, none beyond the
    /// outer one, and in between the falloff of [`spot_falloff`] of the given shape. Cosines
    /// of the half-angles, `cos_outer < cos_inner`.
    Spot {
        cos_inner: f32,
        cos_outer: f32,
        falloff: SpotFalloff,
    },
    /// Parallel light from infinitely far away (the sun).
    Directional,
}

/// A light without area, as glTF's `KHR_lights_punctual` defines it. Camera rays never see
/// one; it lights the scene through the photons it emits.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PunctualLight {
    pub kind: PunctualKind,
    /// Where the light is (point, spot); unused for a directional light.
    pub position: Vec3,
    /// Unit direction the light travels in (spot, directional: its node's −Z); unused for a
    /// point light.
    pub direction: Vec3,
    /// Linear RGB colour × intensity: luminous intensity in candela for point and spot
    /// lights (radiance units × m²), illuminance in lux for directional ones (radiance units
    /// × sr), so that they sit with emissive surfaces' radiance as glTF means them to.
    pub intensity: Vec3,
}

/// A punctual light with what emitting its photons needs.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PunctualEmitter {
    pub light: PunctualLight,
    /// Point and spot: the light's position. Directional: the centre of the disk the photons
    /// leave from, outside the scene's bounding sphere on the side the light comes from.
    pub origin: Vec3,
    /// Directional: the disk's radius, the scene's bounding-sphere radius (0 otherwise).
    pub radius: f32,
    /// Emitted flux per RGB channel (see [`PunctualLight::power`]).
    pub power: Vec3,
}

/// How a spot's intensity falls from its inner cone (1) to its outer one (0): each scene
/// format has its own curve between the two, and renders its spots with it.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum SpotFalloff {
    /// glTF's recommended one: the square of the linear ramp in the cosine of the angle from
    /// the spot's axis.
    #[default]
    Gltf,
    /// pbrt-v4's: smoothstep in the cosine.
    Smoothstep,
    /// Mitsuba 3's: linear in the angle itself.
    LinearAngle,
}

impl SpotFalloff {
    /// The shape as the light table stores it (`render::buffers::Light`'s `edge2.z`).
    pub fn code(self) -> f32 {
        match self {
            SpotFalloff::Gltf => 0.0,
            SpotFalloff::Smoothstep => 1.0,
            SpotFalloff::LinearAngle => 2.0,
        }
    }

    /// The shape whose [`SpotFalloff::code`] is `code` (anything else: glTF's).
    pub fn from_code(code: f32) -> SpotFalloff {
        if code == 1.0 {
            SpotFalloff::Smoothstep
        } else if code == 2.0 {
            SpotFalloff::LinearAngle
        } else {
            SpotFalloff::Gltf
        }
    }

    /// ∫ falloff dω over the band between the cones, over 2π.
    fn band_integral(self, cos_inner: f32, cos_outer: f32) -> f32 {
        match self {
            // ∫ ramp² dc = (ci − co)/3; ∫ smoothstep dc = (ci − co)/2.
            SpotFalloff::Gltf => (cos_inner - cos_outer) / 3.0,
            SpotFalloff::Smoothstep => (cos_inner - cos_outer) / 2.0,
            // ∫ (θo − θ)/(θo − θi) sin θ dθ from θi to θo = cos θi − (sin θo − sin θi)/(θo − θi).
            SpotFalloff::LinearAngle => {
                let (inner, outer) = (cos_inner.acos(), cos_outer.acos());
                let width = (outer - inner).max(f32::MIN_POSITIVE);
                cos_inner - (outer.sin() - inner.sin()) / width
            }
        }
    }
}

/// A spot's falloff of `shape` at `cos_angle` from its axis: 0 at the outer cone, 1 at the
/// inner one, and in between the shape's curve.
pub fn spot_falloff(cos_angle: f32, cos_inner: f32, cos_outer: f32, shape: SpotFalloff) -> f32 {
    if cos_angle >= cos_inner {
        return 1.0;
    }
    if cos_angle <= cos_outer {
        return 0.0;
    }
    // The builder keeps cos_outer < cos_inner; the guard only keeps a bad call finite.
    let ramp = (cos_angle - cos_outer) / (cos_inner - cos_outer).max(f32::MIN_POSITIVE);
    match shape {
        SpotFalloff::Gltf => ramp * ramp,
        SpotFalloff::Smoothstep => ramp * ramp * (3.0 - 2.0 * ramp),
        SpotFalloff::LinearAngle => {
            let (inner, outer) = (cos_inner.acos(), cos_outer.acos());
            let width = (outer - inner).max(f32::MIN_POSITIVE);
            ((outer - cos_angle.acos()) / width).clamp(0.0, 1.0)
        }
    }
}

impl PunctualLight {
    /// Flux the light emits; a directional light's through a disk of `radius`.
    ///
    /// Point: 4π·I. Spot: I · ∫ falloff dω = I · 2π ∫ falloff(c) dc over the cosine c: 2π·I·(1 −
    /// cos_inner) for the full-intensity cap plus the band's share (glTF's squared ramp:
    /// 2π·I·(cos_inner − cos_outer)/3). Directional: E·π·radius².
    pub fn power(&self, radius: f32) -> Vec3 {
        use std::f32::consts::PI;
        let solid_angle_weight = match self.kind {
            PunctualKind::Point => 4.0 * PI,
            PunctualKind::Spot {
                cos_inner,
                cos_outer,
                falloff,
            } => {
                2.0 * PI * (1.0 - cos_inner)
                    + 2.0 * PI * falloff.band_integral(cos_inner, cos_outer)
            }
            PunctualKind::Directional => PI * radius * radius,
        };
        self.intensity * solid_angle_weight
    }
}

/// Radiance from every direction, infinitely far away (kousen's `--sky` and `--sky-map`):
/// uniform, or an environment map's. Camera rays that leave the scene see it, and its photons
/// come from every direction through a disk across the scene's bounding sphere.
#[derive(Clone, Debug, PartialEq)]
pub struct Sky {
    /// The uniform sky's radiance; with a map, the factor its texels are scaled by.
    pub radiance: Vec3,
    /// The environment map, if any ([`SkyMap`]), and its rotation about +Y in radians
    /// (counter-clockwise seen from above: a positive angle turns the map's −Z column towards
    /// −X).
    pub map: Option<std::sync::Arc<SkyMap>>,
    pub rotation: f32,
    /// The scene's bounding sphere (slightly enlarged), which the photons' disk covers.
    pub centre: Vec3,
    pub radius: f32,
    /// Flux into the bounding sphere: radiance × the disk's area π·radius² × 4π steradians of
    /// directions (each direction's light crosses the disk perpendicular to it).
    pub power: Vec3,
}

/// The sphere the photons of a directional light or the sky must cover: the one around
/// `bounds` (not empty), 1 % larger so that every photon starts outside the scene. (centre,
/// radius).
pub fn bounding_sphere(bounds: Bounds) -> (Vec3, f32) {
    (bounds.center(), 0.5 * bounds.extent().length() * 1.01)
}

impl Sky {
    /// A sky of `radiance` around a scene within `bounds` (not empty).
    pub fn new(radiance: Vec3, bounds: Bounds) -> Sky {
        use std::f32::consts::PI;
        let (centre, radius) = bounding_sphere(bounds);
        Sky {
            radiance,
            centre,
            radius,
            power: radiance * PI * radius * radius * 4.0 * PI,
            map: None,
            rotation: 0.0,
        }
    }

    /// A sky whose radiance is `map` × `scale`, turned `rotation` radians about +Y, around a
    /// scene within `bounds` (not empty). Its power is the map's integral × the disk's area.
    pub fn with_map(
        map: std::sync::Arc<SkyMap>,
        scale: Vec3,
        rotation: f32,
        bounds: Bounds,
    ) -> Sky {
        let (centre, radius) = bounding_sphere(bounds);
        Sky {
            radiance: scale,
            centre,
            radius,
            power: Vec3::ZERO,
            map: None,
            rotation,
        }
        .with_map_replaced(map)
    }

    /// This sky with its map replaced by `map` (a resampled one), its power recomputed.
    pub fn with_map_replaced(&self, map: std::sync::Arc<SkyMap>) -> Sky {
        use std::f32::consts::PI;
        Sky {
            power: self.radiance * map.integral() * PI * self.radius * self.radius,
            map: Some(map),
            ..self.clone()
        }
    }
}

#[derive(Clone, Debug, Default, PartialEq)]
pub struct Lights {
    pub triangles: Vec<EmissiveTriangle>,
    pub punctual: Vec<PunctualEmitter>,
    pub sky: Option<Sky>,
    pub total_power: Vec3,
}

impl Lights {
    /// Collects the emissive triangles of a scene and prepares its punctual lights (those of
    /// zero intensity dropped); directional lights cover the triangles' bounding sphere.
    pub fn collect(
        triangles: &[Triangle],
        materials: &[Material],
        textures: &[Texture],
        punctual: &[PunctualLight],
    ) -> Lights {
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
        let bounds = triangles
            .iter()
            .fold(Bounds::EMPTY, |b, t| b.union(t.bounds()));
        for light in punctual.iter().filter(|l| l.intensity.max_element() > 0.0) {
            lights.add_punctual(*light, bounds);
        }
        lights
    }

    /// Adds a punctual light to a scene whose triangles lie within `bounds` (the renderer's
    /// `--sun`); `light` must be valid as [`crate::SceneBuilder::add_punctual_light`] checks.
    pub fn add_punctual(&mut self, light: PunctualLight, bounds: Bounds) {
        let emitter = PunctualEmitter::new(light, bounds);
        self.total_power += emitter.power;
        self.punctual.push(emitter);
    }

    /// Sets the sky around a scene within `bounds` (kousen's `--sky`), replacing any.
    pub fn set_sky(&mut self, radiance: Vec3, bounds: Bounds) {
        self.replace_sky(Sky::new(radiance, bounds));
    }

    /// Sets `sky` (uniform or mapped), replacing any.
    pub fn replace_sky(&mut self, sky: Sky) {
        if let Some(old) = self.sky.take() {
            self.total_power -= old.power;
        }
        self.total_power += sky.power;
        self.sky = Some(sky);
    }

    /// Scales the light that comes from infinitely far away, the sky and directional lights,
    /// by `mask` per channel (`crate::Scene::far_light_mask`); whether any of it dims.
    pub fn dim_far_lights(&mut self, mask: Vec3) -> bool {
        let mut dimmed = false;
        let mut dim = |power: &mut Vec3| {
            let kept = *power * mask;
            dimmed |= kept != *power;
            *power = kept;
        };
        if let Some(sky) = &mut self.sky {
            dim(&mut sky.power);
            sky.radiance *= mask;
        }
        for emitter in &mut self.punctual {
            if emitter.light.kind == PunctualKind::Directional {
                dim(&mut emitter.power);
                emitter.light.intensity *= mask;
            }
        }
        let punctual = self.punctual.iter().map(|p| p.power);
        let triangles = self.triangles.iter().map(|t| t.power);
        let sky = self.sky.iter().map(|s| s.power);
        self.total_power = triangles.chain(punctual).chain(sky).sum();
        dimmed
    }

    /// Whether anything emits.
    pub fn is_empty(&self) -> bool {
        self.triangles.is_empty() && self.punctual.is_empty() && self.sky.is_none()
    }

    /// Total power as one number: the mean of the three channels.
    pub fn total_power_scalar(&self) -> f32 {
        self.total_power.element_sum() / 3.0
    }
}

impl PunctualEmitter {
    /// Places `light` for a scene within `bounds` (not empty).
    pub fn new(light: PunctualLight, bounds: Bounds) -> PunctualEmitter {
        let (origin, radius) = match light.kind {
            PunctualKind::Directional => {
                let (centre, radius) = bounding_sphere(bounds);
                (centre - light.direction * 2.0 * radius, radius)
            }
            _ => (light.position, 0.0),
        };
        PunctualEmitter {
            light,
            origin,
            radius,
            power: light.power(radius),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const SHAPES: [SpotFalloff; 3] = [
        SpotFalloff::Gltf,
        SpotFalloff::Smoothstep,
        SpotFalloff::LinearAngle,
    ];

    /// Flux by numerical integration of intensity × falloff over the sphere.
    fn integrated_spot_power(cos_inner: f32, cos_outer: f32, shape: SpotFalloff) -> f64 {
        let steps = 200_000;
        let mut sum = 0.0f64;
        for i in 0..steps {
            let c = -1.0 + 2.0 * (i as f64 + 0.5) / steps as f64;
            sum += spot_falloff(c as f32, cos_inner, cos_outer, shape) as f64;
        }
        2.0 * std::f64::consts::PI * sum * 2.0 / steps as f64
    }

    #[test]
    fn spot_power_is_the_integral_of_its_falloff() {
        for shape in SHAPES {
            for (inner, outer) in [(0.1f32, 0.5f32), (0.0, 0.3), (0.7, 0.75), (0.2, 1.5)] {
                let light = PunctualLight {
                    kind: PunctualKind::Spot {
                        cos_inner: inner.cos(),
                        cos_outer: outer.cos(),
                        falloff: shape,
                    },
                    position: Vec3::ZERO,
                    direction: Vec3::NEG_Z,
                    intensity: Vec3::ONE,
                };
                let expected = integrated_spot_power(inner.cos(), outer.cos(), shape);
                let power = light.power(0.0).x as f64;
                assert!(
                    (power - expected).abs() < 1e-3 * expected,
                    "{shape:?} {inner} {outer}: {power} vs {expected}"
                );
            }
        }
    }

    #[test]
    fn falloff_is_one_inside_and_zero_outside() {
        let (inner, outer) = (0.9f32, 0.8f32);
        for shape in SHAPES {
            assert_eq!(spot_falloff(0.95, inner, outer, shape), 1.0);
            assert_eq!(spot_falloff(0.79, inner, outer, shape), 0.0);
            assert_eq!(SpotFalloff::from_code(shape.code()), shape);
        }
        // Halfway up the cosine ramp: glTF's square of it, smoothstep's half.
        let gltf = spot_falloff(0.85, inner, outer, SpotFalloff::Gltf);
        assert!((gltf - 0.25).abs() < 1e-5);
        let smooth = spot_falloff(0.85, inner, outer, SpotFalloff::Smoothstep);
        assert!((smooth - 0.5).abs() < 1e-5);
        // Mitsuba's: halfway in angle, half.
        let half_angle = 0.5 * (inner.acos() + outer.acos());
        let linear = spot_falloff(half_angle.cos(), inner, outer, SpotFalloff::LinearAngle);
        assert!((linear - 0.5).abs() < 1e-4, "{linear}");
        // Every shape rises from the outer cone to the inner one.
        for shape in SHAPES {
            let mut last = 0.0;
            for i in 1..20 {
                let c = outer + (inner - outer) * i as f32 / 20.0;
                let f = spot_falloff(c, inner, outer, shape);
                assert!(f > last, "{shape:?} at {c}: {f} after {last}");
                last = f;
            }
        }
    }

    #[test]
    fn directional_light_covers_the_scene_from_outside() {
        let bounds = Bounds {
            min: Vec3::splat(-1.0),
            max: Vec3::splat(1.0),
        };
        let light = PunctualLight {
            kind: PunctualKind::Directional,
            position: Vec3::ZERO,
            direction: Vec3::new(0.0, -1.0, 0.0),
            intensity: Vec3::splat(2.0),
        };
        let e = PunctualEmitter::new(light, bounds);
        let sphere = 3f32.sqrt();
        assert!(e.radius >= sphere);
        assert!(e.origin.y >= sphere && e.origin.x == 0.0 && e.origin.z == 0.0);
        let expected = 2.0 * std::f32::consts::PI * e.radius * e.radius;
        assert!((e.power.x - expected).abs() < 1e-4 * expected);
    }
}
