//! An environment map for the sky: radiance from every direction in an equirectangular
//! (latitude-longitude) image, as HDR skies are published.
//!
//! Row 0 is straight up (+Y), the last row straight down; a row spans all longitudes. Column
//! u ∈ [0, 1) looks along azimuth φ = 2π(u − ½) measured from −Z towards +X (the image's centre
//! column faces −Z, its three-quarter column +X), before the map's rotation about +Y. Between
//! texel centres the radiance is bilinear ([`SkyMap::radiance_at`]), wrapping around in
//! longitude and held constant from the first and last rows' centres to the poles, so a map
//! shows no texel edges; [`SkyMap::integral`] and [`SkyMap::floor_irradiance`] integrate that
//! function exactly, and `render::sky_map` samples it exactly.

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

    /// The map at half the resolution (each side rounded up): each texel the mean of the 2 × 2
    /// (or fewer, at an odd edge) it covers, rows weighed by their solid angle so that the
    /// map's power is kept. For a map larger than a device can hold.
    pub fn halved(&self) -> SkyMap {
        let (width, height) = (self.width.div_ceil(2), self.height.div_ceil(2));
        let row_weight = |y: u32| (PI * (y as f32 + 0.5) / self.height as f32).sin();
        let texels = (0..height)
            .flat_map(|y| (0..width).map(move |x| (x, y)))
            .map(|(x, y)| {
                let (mut sum, mut weight) = (Vec3::ZERO, 0.0);
                for source_y in (2 * y..2 * y + 2).filter(|&r| r < self.height) {
                    for source_x in (2 * x..2 * x + 2).filter(|&c| c < self.width) {
                        let w = row_weight(source_y);
                        sum += w * self.texel(source_x, source_y);
                        weight += w;
                    }
                }
                sum / weight
            })
            .collect();
        SkyMap {
            width,
            height,
            texels,
        }
    }

    /// The radiance at map coordinates (u, v) ∈ [0, 1]²: bilinear between the four nearest
    /// texel centres (texel (x, y)'s centre at ((x + ½)/width, (y + ½)/height)), wrapping in u
    /// and clamped to the top and bottom rows' centres in v.
    pub fn radiance_at(&self, u: f32, v: f32) -> Vec3 {
        let [(x0, x1, a), (y0, y1, b)] = bilinear_footprint(self.width, self.height, u, v);
        let row = |y: u32| self.texel(x0, y).lerp(self.texel(x1, y), a);
        row(y0).lerp(row(y1), b)
    }

    /// ∫ radiance dω over the sphere, per channel, exact for [`SkyMap::radiance_at`]: the
    /// sky's power is this × the area of the disk its photons cross.
    pub fn integral(&self) -> Vec3 {
        // ∫ sin θ dθ with θ = πv: the kernel sin(πv) · π.
        self.sum_by_row(|y| self.row_integral(y, 1.0, std::f64::consts::PI))
    }

    /// ∫ radiance · max(cos θ, 0) dω over the upper hemisphere (+Y), per channel, exact for
    /// [`SkyMap::radiance_at`]: the irradiance of an open floor facing up, whose Lambertian
    /// radiance is then albedo/π times this. For analytic tests.
    pub fn floor_irradiance(&self) -> Vec3 {
        // cos θ sin θ = ½ sin 2θ, over v ∈ [0, ½].
        self.sum_by_row(|y| self.row_integral(y, 2.0, std::f64::consts::FRAC_PI_2))
    }

    /// `factor` × ∫ weight_y(v) · sin(kπv) dv over v ∈ [0, 1/k], times 2π/width, where
    /// weight_y is row y's share of the bilinear function at v (a tent between the
    /// neighbouring rows' centres, flat to the pole for the first and last rows). Each texel's
    /// tent across its row integrates to 1/width of the row's 2π, so the rows' sums times this
    /// are the integral.
    fn row_integral(&self, y: u32, k: f64, factor: f64) -> f64 {
        let h = self.height as f64;
        let (y, last) = (y as f64, self.height - 1);
        // weight = p + q·v on each of the tent's two sides (v from the texel centres' grid).
        let rising = if y == 0.0 {
            (0.0, 0.5 / h, 1.0, 0.0)
        } else {
            ((y - 0.5) / h, (y + 0.5) / h, 0.5 - y, h)
        };
        let falling = if y as u32 == last {
            ((y + 0.5) / h, 1.0, 1.0, 0.0)
        } else {
            ((y + 0.5) / h, (y + 1.5) / h, y + 1.5, -h)
        };
        let omega = k * std::f64::consts::PI;
        // An antiderivative of (p + q·v) · sin(ωv).
        let primitive = |p: f64, q: f64, v: f64| {
            -(p + q * v) * (omega * v).cos() / omega + q * (omega * v).sin() / (omega * omega)
        };
        let limit = 1.0 / k;
        let side = |(start, stop, p, q): (f64, f64, f64, f64)| {
            let stop = f64::min(stop, limit);
            if stop <= start {
                0.0
            } else {
                primitive(p, q, stop) - primitive(p, q, start)
            }
        };
        (side(rising) + side(falling)) * factor * std::f64::consts::TAU / self.width as f64
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

/// The two texels either side of (u, v) along each axis and the second's weight, for
/// [`SkyMap::radiance_at`]: `[(x0, x1, a), (y0, y1, b)]`. Columns wrap; rows clamp, so above
/// the first row's centres and below the last's both rows are the same.
pub fn bilinear_footprint(width: u32, height: u32, u: f32, v: f32) -> [(u32, u32, f32); 2] {
    let s = u * width as f32 - 0.5;
    let t = v * height as f32 - 0.5;
    let (left, top) = (s.floor(), t.floor());
    let x0 = (left as i64).rem_euclid(width as i64) as u32;
    let row = |y: f32| (y.max(0.0) as u32).min(height - 1);
    [
        (x0, (x0 + 1) % width, s - left),
        (row(top), row(top + 1.0), t - top),
    ]
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

    /// Midpoint quadrature of `radiance_at` × `kernel(θ)` sin θ dθ dφ over a fine grid, in f64.
    fn quadrature(map: &SkyMap, kernel: impl Fn(f64) -> f64) -> Vec3 {
        let (columns, rows) = (1024, 2048);
        let mut sum = [0.0f64; 3];
        for j in 0..rows {
            let v = (j as f64 + 0.5) / rows as f64;
            let theta = std::f64::consts::PI * v;
            let weight = kernel(theta) * theta.sin();
            for i in 0..columns {
                let u = (i as f64 + 0.5) / columns as f64;
                let l = map.radiance_at(u as f32, v as f32);
                for (s, c) in sum.iter_mut().zip(l.to_array()) {
                    *s += c as f64 * weight;
                }
            }
        }
        let cell = std::f64::consts::TAU * std::f64::consts::PI / (columns * rows) as f64;
        Vec3::new(sum[0] as f32, sum[1] as f32, sum[2] as f32) * cell as f32
    }

    /// The closed forms against quadrature of the bilinear function, on maps of uneven texels
    /// and on the degenerate sizes (one row, one or two columns).
    #[test]
    fn the_integrals_are_those_of_the_bilinear_radiance() {
        for (w, h) in [(5, 4), (3, 7), (1, 3), (2, 1), (6, 2)] {
            let map = sky(w, h, |x, y| {
                let n = (x * 7 + y * 13) % 5;
                Vec3::new(n as f32, 1.0 + y as f32, (x == 0) as u32 as f32 * 3.0)
            });
            let exact = [map.integral(), map.floor_irradiance()];
            let numeric = [
                quadrature(&map, |_| 1.0),
                quadrature(&map, |theta| theta.cos().max(0.0)),
            ];
            for (e, n) in exact.into_iter().zip(numeric) {
                let error = (e - n).abs().max_element() / n.max_element();
                assert!(error < 1e-4, "{w}x{h}: exact {e}, quadrature {n}");
            }
        }
    }

    #[test]
    fn radiance_is_bilinear_between_texel_centres() {
        let map = sky(4, 3, |x, y| Vec3::new(x as f32, y as f32, 1.0));
        // At a centre, the texel; halfway between centres, the mean.
        assert_eq!(map.radiance_at(0.375, 0.5), Vec3::new(1.0, 1.0, 1.0));
        assert_eq!(map.radiance_at(0.5, 0.5), Vec3::new(1.5, 1.0, 1.0));
        assert_eq!(map.radiance_at(0.375, 1.0 / 3.0), Vec3::new(1.0, 0.5, 1.0));
        // Columns wrap: between the last centre and the first, either side of u = 0.
        assert_eq!(map.radiance_at(0.0, 0.5), Vec3::new(1.5, 1.0, 1.0));
        assert!((map.radiance_at(0.999_999, 0.5).x - 1.5).abs() < 1e-4);
        // Rows clamp towards the poles.
        assert_eq!(map.radiance_at(0.375, 0.0), Vec3::new(1.0, 0.0, 1.0));
        assert_eq!(map.radiance_at(0.375, 1.0), Vec3::new(1.0, 2.0, 1.0));
    }

    #[test]
    fn the_floor_sees_only_the_upper_rows() {
        // Six rows: the horizon (v = ½) lies between rows 2 and 3's centres, so rows 4 and 5
        // never reach the upper hemisphere and row 3 does, interpolated with row 2.
        let rows = |l: [f32; 6]| sky(4, 6, move |_, y| Vec3::splat(l[y as usize]));
        let base = rows([1.0, 1.0, 1.0, 1.0, 0.0, 0.0]);
        assert!(
            (base.floor_irradiance() - Vec3::splat(PI))
                .abs()
                .max_element()
                < 1e-4
        );
        let below = rows([1.0, 1.0, 1.0, 1.0, 9.0, 5.0]);
        assert_eq!(below.floor_irradiance(), base.floor_irradiance());
        let horizon = rows([1.0, 1.0, 1.0, 0.0, 0.0, 0.0]);
        assert!(horizon.floor_irradiance().x < PI - 1e-3);
        let lower = rows([0.0, 0.0, 0.0, 0.0, 1.0, 1.0]);
        assert_eq!(lower.floor_irradiance(), Vec3::ZERO);
    }

    #[test]
    fn halving_keeps_the_power() {
        let map = sky(9, 6, |x, y| {
            Vec3::new(1.0 + (x as f32 * 0.8).sin().abs(), 0.5 + y as f32, 2.0)
        });
        let half = map.halved();
        assert_eq!((half.width(), half.height()), (5, 3));
        // The odd last column averages only its own texels.
        assert_eq!(half.texel(4, 0).z, 2.0);
        let (before, after) = (map.integral(), half.integral());
        let error = ((after - before) / before).abs().max_element();
        assert!(error < 0.03, "{before} -> {after}");
        // Down to a single texel, still a valid map.
        let mut small = map;
        while small.width() > 1 || small.height() > 1 {
            small = small.halved();
        }
        assert!(small.integral().min_element() > 0.0);
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
