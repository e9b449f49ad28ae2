//! pbrt's lights: area lights on shapes, point, spot and distant lights, and the infinite
//! light (a colour, or an image resampled into kousen's latitude–longitude sky map).

use std::f32::consts::PI;
use std::path::Path;

use glam::{Mat3, Vec2, Vec3};

use super::tokens::Params;
use super::{AreaLight, Reader};
use crate::{PunctualKind, PunctualLight, SceneError, SkyMap, SpotFalloff};

/// The widest sky map kept (its height is half): an equal-area square of side N becomes
/// 2N × N, up to this.
const MAX_SKY_WIDTH: u32 = 4096;

impl Reader {
    /// `AreaLightSource`: the radiance (and `power`) shapes after it emit, and on which faces.
    pub(super) fn area_light(
        &mut self,
        kind: &str,
        params: &Params,
        file: &Path,
    ) -> Result<Option<AreaLight>, SceneError> {
        let fail = |message: String| SceneError::format(file, message);
        if kind != "diffuse" && kind != "area" {
            self.warn(file, format!("area light \"{kind}\" is not read"));
            return Ok(None);
        }
        let radiance = self.emission(params, "L", file)?;
        let scale = params.float("scale", 1.0).map_err(fail)?;
        let two_sided = params.boolean("twosided", false).map_err(fail)?;
        let power = params.float("power", -1.0).map_err(fail)?;
        if params.get("filename").is_some() {
            self.warn(file, "an area light's image is not read: its L is emitted");
        }
        Ok(Some(AreaLight {
            radiance: radiance * scale,
            two_sided,
            power: (power > 0.0).then_some(power),
        }))
    }

    /// `LightSource`: a punctual light, or the sky.
    pub(super) fn light(
        &mut self,
        kind: &str,
        params: &Params,
        file: &Path,
    ) -> Result<(), SceneError> {
        let fail = |message: String| SceneError::format(file, message);
        let scale = params.float("scale", 1.0).map_err(fail)?;
        let power = params.float("power", -1.0).map_err(fail)?;
        let from = params.point("from", Vec3::ZERO).map_err(fail)?;
        let to = params.point("to", Vec3::Z).map_err(fail)?;
        let ctm = self.state.ctm;
        let world = self.mirror * ctm;
        let position = world.transform_point3(from);
        let direction = world.transform_vector3(to - from);
        let light = match kind {
            "point" => {
                let mut intensity = self.emission(params, "I", file)? * scale;
                if power > 0.0 {
                    intensity *= power / (4.0 * PI);
                }
                PunctualLight {
                    kind: PunctualKind::Point,
                    position,
                    direction: Vec3::NEG_Y,
                    intensity,
                }
            }
            "spot" => {
                let cone = params.float("coneangle", 30.0).map_err(fail)?;
                let delta = params.float("conedeltaangle", 5.0).map_err(fail)?;
                if !(cone > 0.0 && cone <= 90.0 && delta >= 0.0) {
                    let message = format!("coneangle {cone}° or conedeltaangle {delta}°");
                    return Err(fail(format!("spot light: {message} out of range")));
                }
                let cos_outer = cone.to_radians().cos();
                // kousen's cones must differ: a hard edge keeps a thousandth of the angle.
                let inner = (cone - delta).clamp(0.0, cone * 0.999);
                let cos_inner = inner.to_radians().cos();
                let mut intensity = self.emission(params, "I", file)? * scale;
                if power > 0.0 {
                    let solid = 2.0 * PI * ((1.0 - cos_inner) + (cos_inner - cos_outer) / 2.0);
                    intensity *= power / solid;
                }
                PunctualLight {
                    kind: PunctualKind::Spot {
                        cos_inner,
                        cos_outer,
                        falloff: SpotFalloff::Smoothstep,
                    },
                    position,
                    direction,
                    intensity,
                }
            }
            "distant" => {
                let mut irradiance = self.emission(params, "L", file)? * scale;
                let illuminance = params.float("illuminance", -1.0).map_err(fail)?;
                if illuminance > 0.0 {
                    irradiance *= illuminance;
                }
                PunctualLight {
                    kind: PunctualKind::Directional,
                    position,
                    direction,
                    intensity: irradiance,
                }
            }
            "infinite" => return self.infinite(params, scale, file),
            other => {
                self.warn(file, format!("light \"{other}\" is not read"));
                return Ok(());
            }
        };
        self.builder.add_punctual_light(light).map_err(|e| match e {
            SceneError::Format { message, .. } => fail(message),
            e => e,
        })
    }

    /// An `infinite` light: uniform radiance `L`, or an image map turned by the transform.
    fn infinite(&mut self, params: &Params, scale: f32, file: &Path) -> Result<(), SceneError> {
        let fail = |message: String| SceneError::format(file, message);
        if params.get("portal").is_some() {
            self.warn(
                file,
                "an infinite light's portal is not read (it only guides sampling)",
            );
        }
        let illuminance = params.float("illuminance", -1.0).map_err(fail)?;
        let Some(name) = params.string("filename").map_err(fail)? else {
            let mut radiance = self.emission(params, "L", file)? * scale;
            if illuminance > 0.0 {
                // A uniform sky of radiance L lights an open floor with π·L.
                radiance *= illuminance / PI;
            }
            self.sky = Some(self.sky.unwrap_or(Vec3::ZERO) + radiance);
            return Ok(());
        };
        let path = self.resolve(&name);
        let image = crate::Texture::read_file(&path, &name, true, fail)?;
        let light_from_world = Mat3::from_mat4(self.state.ctm).inverse();
        let mirror = Mat3::from_mat4(self.mirror);
        let equal_area = image.width == image.height;
        let height = image.height.clamp(2, MAX_SKY_WIDTH / 2);
        let width = 2 * height;
        let mut texels = Vec::with_capacity((width * height) as usize);
        // The illuminance the map gives a surface facing the light's +z (pbrt's up for it).
        let mut up_irradiance = Vec3::ZERO;
        let texel_angle = (2.0 * PI / width as f32) * (PI / height as f32);
        for y in 0..height {
            for x in 0..width {
                let u = (x as f32 + 0.5) / width as f32;
                let v = (y as f32 + 0.5) / height as f32;
                let direction = light_from_world * (mirror * crate::sky_map::map_direction(u, v));
                let direction = direction.normalize_or_zero();
                let at = match equal_area {
                    true => equal_area_square(direction),
                    false => latitude_longitude(direction),
                };
                let radiance = image.sample_bilinear(at.x, at.y).truncate();
                let solid_angle = texel_angle * (PI * v).sin();
                up_irradiance += radiance * direction.z.max(0.0) * solid_angle;
                texels.push(radiance);
            }
        }
        // `illuminance` scales the map to light a surface facing up with that much (its
        // luminance), as pbrt-v4 scales it.
        let luminance = up_irradiance.dot(Vec3::new(0.2126, 0.7152, 0.0722));
        let factor = match illuminance > 0.0 && luminance > 0.0 {
            true => scale * illuminance / luminance,
            false => scale,
        };
        for texel in &mut texels {
            *texel *= factor;
        }
        let map = SkyMap::new(width, height, texels).map_err(fail)?;
        if self.sky_map.is_some() {
            self.warn(file, "a second image sky: kousen has one sky, the last");
        }
        self.sky_map = Some(map);
        Ok(())
    }
}

/// pbrt-v4's equal-area octahedral square coordinates (Clarberg's mapping) of a unit
/// direction in the light's space: +z at the centre, −z at the corners, +x at the middle of
/// the right edge, +y at the middle of the bottom edge (row 0 at the top).
pub(super) fn equal_area_square(d: Vec3) -> Vec2 {
    let (x, y, z) = (d.x.abs(), d.y.abs(), d.z.abs());
    let r = (1.0 - z).max(0.0).sqrt();
    let (small, large) = (x.min(y), x.max(y));
    let mut phi = match large > 0.0 {
        true => (small / large).atan() * 2.0 / PI,
        false => 0.0,
    };
    if x < y {
        phi = 1.0 - phi;
    }
    let mut v = phi * r;
    let mut u = r - v;
    if d.z < 0.0 {
        (u, v) = (1.0 - v, 1.0 - u);
    }
    let u = u.copysign(d.x);
    let v = v.copysign(d.y);
    Vec2::new((u + 1.0) / 2.0, (v + 1.0) / 2.0)
}

/// pbrt-v3's latitude–longitude coordinates of a unit direction in the light's space: u the
/// angle about +z from +x over 2π, v the angle from +z over π (row 0 at +z).
pub(super) fn latitude_longitude(d: Vec3) -> Vec2 {
    let phi = d.y.atan2(d.x);
    let phi = if phi < 0.0 { phi + 2.0 * PI } else { phi };
    Vec2::new(phi / (2.0 * PI), d.z.clamp(-1.0, 1.0).acos() / PI)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_equal_area_square_puts_the_axes_where_pbrt_does() {
        let close = |a: Vec2, b: Vec2| (a - b).abs().max_element() < 1e-5;
        assert!(close(equal_area_square(Vec3::Z), Vec2::splat(0.5)));
        assert!(close(equal_area_square(Vec3::X), Vec2::new(1.0, 0.5)));
        assert!(close(equal_area_square(Vec3::NEG_X), Vec2::new(0.0, 0.5)));
        assert!(close(equal_area_square(Vec3::Y), Vec2::new(0.5, 1.0)));
        let corner = equal_area_square(Vec3::NEG_Z);
        assert!(
            close(corner, Vec2::ONE) || close(corner, Vec2::ZERO),
            "{corner}"
        );
    }

    /// Equal areas of the sphere take equal areas of the square: directions uniform on the
    /// sphere fall uniformly into the square's cells.
    #[test]
    fn the_equal_area_square_keeps_areas() {
        let cells = 4;
        let mut counts = vec![0u32; cells * cells];
        let n = 64_000;
        for i in 0..n {
            // A Fibonacci sphere: near-uniform directions.
            let z = 1.0 - (2.0 * i as f32 + 1.0) / n as f32;
            let r = (1.0 - z * z).sqrt();
            let phi = i as f32 * 2.399_963;
            let at = equal_area_square(Vec3::new(r * phi.cos(), r * phi.sin(), z));
            let cell = |c: f32| ((c * cells as f32) as usize).min(cells - 1);
            counts[cell(at.y) * cells + cell(at.x)] += 1;
        }
        let expected = n as f32 / (cells * cells) as f32;
        for c in counts {
            assert!(
                (c as f32 / expected - 1.0).abs() < 0.02,
                "{c} against {expected}"
            );
        }
    }

    #[test]
    fn latitude_longitude_starts_at_plus_z_and_plus_x() {
        assert_eq!(latitude_longitude(Vec3::Z).y, 0.0);
        let x = latitude_longitude(Vec3::X);
        assert!(x.x.abs() < 1e-6 && (x.y - 0.5).abs() < 1e-6);
        let y = latitude_longitude(Vec3::Y);
        assert!((y.x - 0.25).abs() < 1e-6);
    }
}
