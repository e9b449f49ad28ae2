//! An environment map for the sky: radiance from every direction in an equirectangular
//! (latitude-longitude) image, as HDR skies are published.
//!
//! Row 0 is straight up (+Y), the last row straight down; a row spans all longitudes. Column
//! u ∈ [0, 1) looks along azimuth φ = 2π(u − ½) measured from −Z towards +X (the image's centre
//! column faces −Z, its three-quarter column +X), before the map's rotation about +Y. Each
//! texel is constant over its patch of the sphere: what a renderer samples and what it looks up
//! are then the same function, with no filter between them.

use glam::Vec3;
use std::f32::consts::{PI, TAU};

/// Linear RGB radiance over the sphere of directions, `width` × `height` texels, rows top to
/// bottom. Every texel finite and ≥ 0, not all zero.
#[derive(Clone, PartialEq)]
pub struct SkyMap {
    width: u32,
    height: u32,
    texels: Vec<Vec3>,
}

impl SkyMap {
    /// The largest side accepted: a 16k map's texels and tables would pass a gigabyte.
    pub const MAX_SIDE: u32 = 16384;

    /// A map from `texels` (row-major, top row first), or why it cannot be one.
    pub fn new(width: u32, height: u32, texels: Vec<Vec3>) -> Result<SkyMap, String> {
        if width == 0 || height == 0 || width > Self::MAX_SIDE || height > Self::MAX_SIDE {
            return Err(format!(
                "the sky map is {width}x{height}; each side must be 1 to {}",
                Self::MAX_SIDE
            ));
        }
        if texels.len() != width as usize * height as usize {
            return Err(format!(
                "the sky map has {} texels for {width}x{height}",
                texels.len()
            ));
        }
        if let Some(i) = texels
            .iter()
            .position(|t| !t.is_finite() || t.min_element() < 0.0)
        {
            let (x, y) = (i as u32 % width, i as u32 / width);
            return Err(format!(
                "the sky map's texel ({x}, {y}) is {} (radiance must be finite and ≥ 0)",
                texels[i]
            ));
        }
        let map = SkyMap {
            width,
            height,
            texels,
        };
        if map.integral().max_element() <= 0.0 {
            return Err("the sky map is black: it would light nothing".into());
        }
        Ok(map)
    }

    pub fn width(&self) -> u32 {
        self.width
    }

    pub fn height(&self) -> u32 {
        self.height
    }

    /// The texels, row-major from the top row.
    pub fn texels(&self) -> &[Vec3] {
        &self.texels
    }

    pub fn texel(&self, x: u32, y: u32) -> Vec3 {
        self.texels[(y * self.width + x) as usize]
    }

    /// The solid angle of one texel of row `y`: 2π/width × (cos θ_top − cos θ_bottom).
    pub fn texel_solid_angle(&self, y: u32) -> f32 {
        let polar = |row: u32| PI * row as f32 / self.height as f32;
        TAU / self.width as f32 * (polar(y).cos() - polar(y + 1).cos())
    }

    /// ∫ radiance dω over the sphere, per channel (exact for texels constant over their
    /// patches): the sky's power is this × the area of the disk its photons cross.
    pub fn integral(&self) -> Vec3 {
        self.sum_by_row(|y| self.texel_solid_angle(y) as f64)
    }

    /// ∫ radiance · max(cos θ, 0) dω over the upper hemisphere (+Y), per channel, exact for
    /// texels constant over their patches: the irradiance of an open floor facing up, whose
    /// Lambertian radiance is then albedo/π times this. For analytic tests.
    pub fn floor_irradiance(&self) -> Vec3 {
        let polar = |row: u32| (PI as f64 * row as f64 / self.height as f64).min(PI as f64 / 2.0);
        // ∫ cos θ sin θ dθ over the row's band (above the horizon) × its texel's width.
        self.sum_by_row(|y| {
            let band = 0.5 * (polar(y + 1).sin().powi(2) - polar(y).sin().powi(2));
            band * std::f64::consts::TAU / self.width as f64
        })
    }

    /// Σ texel × `weight(row)` over the map, per channel, in f64.
    fn sum_by_row(&self, weight: impl Fn(u32) -> f64) -> Vec3 {
        let mut sum = [0.0f64; 3];
        for y in 0..self.height {
            let w = weight(y);
            let row = &self.texels[(y * self.width) as usize..][..self.width as usize];
            for texel in row {
                for (s, c) in sum.iter_mut().zip(texel.to_array()) {
                    *s += c as f64 * w;
                }
            }
        }
        Vec3::new(sum[0] as f32, sum[1] as f32, sum[2] as f32)
    }

    /// A digest of the texels (FNV-1a over their bits): what a checkpoint compares to know it
    /// resumes under the same sky without keeping the map.
    pub fn digest(&self) -> u64 {
        let mut hash = 0xcbf2_9ce4_8422_2325u64;
        let words = [self.width, self.height].into_iter().chain(
            self.texels
                .iter()
                .flat_map(|t| t.to_array().map(f32::to_bits)),
        );
        for word in words {
            for byte in word.to_le_bytes() {
                hash = (hash ^ byte as u64).wrapping_mul(0x0100_0000_01b3);
            }
        }
        hash
    }
}

impl std::fmt::Debug for SkyMap {
    /// Its size and digest: the texels would fill a terminal.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "SkyMap {}x{} #{:016x}",
            self.width,
            self.height,
            self.digest()
        )
    }
}

/// The unit direction at map coordinates (u, v) ∈ [0, 1]², before the map's rotation.
pub fn map_direction(u: f32, v: f32) -> Vec3 {
    let (sin_theta, cos_theta) = (PI * v).sin_cos();
    let (sin_phi, cos_phi) = (TAU * (u - 0.5)).sin_cos();
    Vec3::new(sin_theta * sin_phi, cos_theta, -sin_theta * cos_phi)
}

/// The map coordinates (u, v) of unit `direction` (before the map's rotation):
/// [`map_direction`]'s inverse, u in [0, 1).
pub fn map_coordinates(direction: Vec3) -> (f32, f32) {
    let u = 0.5 + direction.x.atan2(-direction.z) / TAU;
    let v = direction.y.clamp(-1.0, 1.0).acos() / PI;
    (if u >= 1.0 { u - 1.0 } else { u }, v)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sky(width: u32, height: u32, f: impl Fn(u32, u32) -> Vec3) -> SkyMap {
        let texels = (0..height)
            .flat_map(|y| (0..width).map(move |x| (x, y)))
            .map(|(x, y)| f(x, y))
            .collect();
        SkyMap::new(width, height, texels).unwrap()
    }

    #[test]
    fn a_constant_map_integrates_to_its_radiance_times_the_sphere() {
        let map = sky(7, 5, |_, _| Vec3::new(1.0, 2.0, 0.5));
        let expected = Vec3::new(1.0, 2.0, 0.5) * 4.0 * PI;
        assert!((map.integral() - expected).abs().max_element() < 1e-4 * expected.max_element());
        // An open floor under a uniform sky L receives π·L.
        let floor = map.floor_irradiance();
        let expected = Vec3::new(1.0, 2.0, 0.5) * PI;
        assert!((floor - expected).abs().max_element() < 1e-4, "{floor}");
    }

    #[test]
    fn the_floor_sees_only_the_upper_rows() {
        // The lower half black: the floor's irradiance is unchanged; the upper half black: 0.
        let upper = sky(4, 6, |_, y| if y < 3 { Vec3::ONE } else { Vec3::ZERO });
        assert!(
            (upper.floor_irradiance() - Vec3::splat(PI))
                .abs()
                .max_element()
                < 1e-4
        );
        let lower = sky(4, 6, |_, y| if y < 3 { Vec3::ZERO } else { Vec3::ONE });
        assert!(lower.floor_irradiance().max_element() < 1e-6);
        assert!((lower.integral() - Vec3::splat(TAU)).abs().max_element() < 1e-4);
    }

    #[test]
    fn coordinates_and_directions_are_inverse() {
        for (u, v) in [
            (0.1, 0.2),
            (0.5, 0.5),
            (0.75, 0.9),
            (0.99, 0.01),
            (0.3, 0.6),
        ] {
            let d = map_direction(u, v);
            assert!((d.length() - 1.0).abs() < 1e-5);
            let (u2, v2) = map_coordinates(d);
            assert!(
                (u - u2).abs() < 1e-5 && (v - v2).abs() < 1e-5,
                "{u},{v} -> {u2},{v2}"
            );
        }
        // The documented axes: the centre column faces −Z, three quarters +X, row 0 up.
        assert!((map_direction(0.5, 0.5) - Vec3::NEG_Z).length() < 1e-6);
        assert!((map_direction(0.75, 0.5) - Vec3::X).length() < 1e-6);
        assert!((map_direction(0.3, 0.0) - Vec3::Y).length() < 1e-6);
    }

    #[test]
    fn bad_maps_say_why() {
        let err = |w, h, t: Vec<Vec3>| SkyMap::new(w, h, t).unwrap_err();
        assert!(err(0, 1, vec![]).contains("each side"));
        assert!(err(2, 1, vec![Vec3::ONE]).contains("1 texels for 2x1"));
        assert!(err(1, 1, vec![Vec3::new(1.0, -1.0, 0.0)]).contains("finite and ≥ 0"));
        assert!(err(1, 1, vec![Vec3::splat(f32::NAN)]).contains("(0, 0)"));
        assert!(err(2, 1, vec![Vec3::ZERO; 2]).contains("black"));
    }

    #[test]
    fn the_digest_follows_the_texels() {
        let a = sky(3, 2, |x, _| Vec3::splat(x as f32 + 1.0));
        let b = sky(3, 2, |x, y| {
            Vec3::splat(x as f32 + 1.0 + (y == 1 && x == 2) as u32 as f32)
        });
        assert_ne!(a.digest(), b.digest());
        assert_eq!(a.digest(), a.clone().digest());
        assert!(format!("{a:?}").starts_with("SkyMap 3x2 #"));
    }
}
