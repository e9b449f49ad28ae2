//! The sky's environment map as the kernels read it (`scene::SkyMap`): one flat buffer of f32
//! that the CPU kernels and the GPU's (`sky_map` in sppm.wgsl) read alike, and the
//! lookups and importance sampling both sides do on it.
//!
//! Directions are drawn in proportion to each texel's radiance (its channels' sum) times its
//! solid angle, two 1-D CDFs over the map (rows, then the texels of the row drawn): a bright
//! sun in a dim sky gets nearly all light samples and photons, as it gets nearly all the power.
//!
//! Layout, for a map of W × H = N texels (row 0 up):
//! | offset | what |
//! |---|---|
//! | 4i .. 4i + 3 | texel i's radiance (the sky's scale applied), then its density over the unit square of map coordinates |
//! | 4N + yW + x | row y's CDF at texel x (its last entry 1) |
//! | 5N + y | the CDF over rows at row y (its last entry 1) |
//!
//! Without a map the buffer is four zeros (a binding cannot be empty). The map's size and
//! rotation travel in the sky's light-table entry ([`sky_light_fields`]).

use std::f32::consts::PI;

use glam::Vec3;
use scene::Sky;
use scene::sky_map::{map_coordinates, map_direction};

use crate::buffers::{LIGHT_SKY, Light};

/// The buffer of a scene without a sky map.
pub const NO_SKY_MAP: [f32; 4] = [0.0; 4];

/// The buffer of `sky`'s map ([`NO_SKY_MAP`] without one).
pub fn sky_map_buffer(sky: Option<&Sky>) -> Vec<f32> {
    let Some((map, scale)) = sky.and_then(|s| s.map.as_ref().map(|m| (m, s.radiance))) else {
        return NO_SKY_MAP.to_vec();
    };
    let (width, height) = (map.width() as usize, map.height() as usize);
    let count = width * height;
    let mut buffer = vec![0.0f32; 5 * count + height];
    // Each texel's share: its radiance's channel sum × the sine at its row's centre (its
    // solid angle over the map's, up to a constant).
    let weights: Vec<f64> = (0..count)
        .map(|i| {
            let sine = (PI as f64 * ((i / width) as f64 + 0.5) / height as f64).sin();
            (scale * map.texels()[i]).element_sum().max(0.0) as f64 * sine
        })
        .collect();
    let total: f64 = weights.iter().sum();
    let mut row_sums = vec![0.0f64; height];
    for y in 0..height {
        let row = &weights[y * width..][..width];
        let sum: f64 = row.iter().sum();
        row_sums[y] = sum;
        let cdf = &mut buffer[4 * count + y * width..][..width];
        cumulative(row, sum, cdf);
    }
    cumulative(&row_sums, total, &mut buffer[5 * count..]);
    for (i, texel) in map.texels().iter().enumerate() {
        let radiance = scale * *texel;
        let density = if total > 0.0 {
            (weights[i] / total * count as f64) as f32
        } else {
            0.0
        };
        buffer[4 * i..4 * i + 4].copy_from_slice(&[radiance.x, radiance.y, radiance.z, density]);
    }
    buffer
}

/// Writes the normalised running sum of `weights` (summing to `sum`) into `cdf`, its last
/// entry exactly 1; uniform where the weights are all zero.
fn cumulative(weights: &[f64], sum: f64, cdf: &mut [f32]) {
    let n = weights.len();
    let mut running = 0.0f64;
    for (i, (w, c)) in weights.iter().zip(cdf.iter_mut()).enumerate() {
        running += w;
        *c = if sum > 0.0 {
            (running / sum) as f32
        } else {
            (i + 1) as f32 / n as f32
        };
    }
    cdf[n - 1] = 1.0;
}

/// The sky entry's `edge1` and `edge2` in the light table: the rotation's cosine and sine,
/// then the bounding radius and the map's width and height (zero without a map).
pub fn sky_light_fields(sky: &Sky) -> ([f32; 3], [f32; 3]) {
    match &sky.map {
        Some(map) => {
            let (sin, cos) = sky.rotation.sin_cos();
            (
                [cos, sin, 0.0],
                [sky.radius, map.width() as f32, map.height() as f32],
            )
        }
        None => ([0.0; 3], [sky.radius, 0.0, 0.0]),
    }
}

/// The map's size and rotation, read from the sky's table entry: `None` for a uniform sky.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MapFrame {
    pub width: u32,
    pub height: u32,
    pub cos: f32,
    pub sin: f32,
}

impl MapFrame {
    pub fn of(light: &Light) -> Option<MapFrame> {
        (light.kind == LIGHT_SKY && light.edge2[1] > 0.0).then(|| MapFrame {
            width: light.edge2[1] as u32,
            height: light.edge2[2] as u32,
            cos: light.edge1[0],
            sin: light.edge1[1],
        })
    }

    /// The world direction of a direction in the map's frame (a turn about +Y).
    fn turned_to_world(self, d: Vec3) -> Vec3 {
        Vec3::new(
            self.cos * d.x + self.sin * d.z,
            d.y,
            -self.sin * d.x + self.cos * d.z,
        )
    }

    /// [`MapFrame::turned_to_world`]'s inverse.
    fn turned_to_map(self, d: Vec3) -> Vec3 {
        Vec3::new(
            self.cos * d.x - self.sin * d.z,
            d.y,
            self.sin * d.x + self.cos * d.z,
        )
    }

    /// The index of the texel seen along world `direction` (unit).
    pub fn texel_index(&self, direction: Vec3) -> usize {
        let (u, v) = map_coordinates(self.turned_to_map(direction));
        let x = ((u * self.width as f32) as u32).min(self.width - 1);
        let y = ((v * self.height as f32) as u32).min(self.height - 1);
        (y * self.width + x) as usize
    }
}

/// A direction towards the sky and what the map holds there.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SkyDirection {
    /// Unit, from the scene towards the sky.
    pub direction: Vec3,
    pub radiance: Vec3,
    /// The density per solid angle with which [`sample_sky_map`] draws it.
    pub pdf: f32,
}

/// The radiance along world `direction` (unit) and the solid-angle density with which
/// [`sample_sky_map`] draws it.
pub fn sky_map_lookup(frame: &MapFrame, buffer: &[f32], direction: Vec3) -> (Vec3, f32) {
    let i = frame.texel_index(direction);
    let sine = (1.0 - direction.y * direction.y).max(0.0).sqrt();
    let texel = &buffer[4 * i..4 * i + 4];
    let pdf = if sine > 0.0 {
        texel[3] / (2.0 * PI * PI * sine)
    } else {
        0.0
    };
    (Vec3::new(texel[0], texel[1], texel[2]), pdf)
}

/// A direction drawn from two uniform numbers in proportion to the map's radiance × solid
/// angle; `None` on the measure-zero poles, where the density is undefined.
pub fn sample_sky_map(frame: &MapFrame, buffer: &[f32], u1: f32, u2: f32) -> Option<SkyDirection> {
    let (width, height) = (frame.width as usize, frame.height as usize);
    let count = width * height;
    let (y, row_fraction) = search(&buffer[5 * count..][..height], u1);
    let (x, column_fraction) = search(&buffer[4 * count + y * width..][..width], u2);
    let u = (x as f32 + column_fraction) / width as f32;
    let v = (y as f32 + row_fraction) / height as f32;
    let sine = (PI * v).sin();
    if sine <= 0.0 {
        return None;
    }
    let texel = &buffer[4 * (y * width + x)..][..4];
    Some(SkyDirection {
        direction: frame.turned_to_world(map_direction(u, v)),
        radiance: Vec3::new(texel[0], texel[1], texel[2]),
        pdf: texel[3] / (2.0 * PI * PI * sine),
    })
}

/// The first entry of `cdf` above `u` (a binary search) and where `u` lies within its
/// interval, in [0, 1).
fn search(cdf: &[f32], u: f32) -> (usize, f32) {
    let (mut lo, mut hi) = (0usize, cdf.len() - 1);
    while lo < hi {
        let mid = (lo + hi) / 2;
        if u < cdf[mid] {
            hi = mid;
        } else {
            lo = mid + 1;
        }
    }
    let before = if lo == 0 { 0.0 } else { cdf[lo - 1] };
    let width = cdf[lo] - before;
    let fraction = if width > 0.0 {
        ((u - before) / width).clamp(0.0, 0.999_999_94)
    } else {
        0.5
    };
    (lo, fraction)
}

/// What a camera path that leaves the scene along `direction` sees: the map's radiance there,
/// or `uniform` (the uniform sky's, zero without a sky) when the sky has no map.
pub fn sky_radiance(lights: &[Light], buffer: &[f32], uniform: Vec3, direction: Vec3) -> Vec3 {
    match lights.last().and_then(MapFrame::of) {
        Some(frame) => sky_map_lookup(&frame, buffer, direction).0,
        None => uniform,
    }
}

/// Photons' flux for a sky direction: radiance × the disk's area ÷ (density × pick).
pub fn sky_photon_flux(light: &Light, sample: &SkyDirection, pick: f32) -> Vec3 {
    let radius = light.edge2[0];
    sample.radiance * (PI * radius * radius / (sample.pdf * pick))
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use scene::{Bounds, SkyMap};
    use std::sync::Arc;

    /// A sky of `f(x, y)` over a unit scene, turned `rotation`.
    pub(crate) fn mapped_sky(
        width: u32,
        height: u32,
        rotation: f32,
        f: impl Fn(u32, u32) -> Vec3,
    ) -> Sky {
        let texels = (0..height)
            .flat_map(|y| (0..width).map(move |x| (x, y)))
            .map(|(x, y)| f(x, y))
            .collect();
        let map = SkyMap::new(width, height, texels).unwrap();
        let bounds = Bounds::EMPTY.grow(Vec3::ZERO).grow(Vec3::ONE);
        Sky::with_map(Arc::new(map), Vec3::new(1.0, 0.5, 2.0), rotation, bounds)
    }

    fn frame_of(sky: &Sky) -> MapFrame {
        let (edge1, edge2) = sky_light_fields(sky);
        MapFrame::of(&Light {
            kind: LIGHT_SKY,
            edge1,
            edge2,
            ..Light::default()
        })
        .unwrap()
    }

    fn uniform(i: u32, dimension: u32) -> f32 {
        (crate::rng::stream_key(17, dimension, 0, i) >> 8) as f32 / (1u32 << 24) as f32
    }

    /// A sun patch in a dim gradient, off-centre so that the rotation matters.
    fn sun_sky(rotation: f32) -> Sky {
        mapped_sky(16, 8, rotation, |x, y| {
            if (x, y) == (11, 2) {
                Vec3::new(400.0, 300.0, 200.0)
            } else {
                Vec3::splat(0.2 + 0.1 * y as f32)
            }
        })
    }

    #[test]
    fn samples_carry_the_density_the_lookup_gives() {
        for rotation in [0.0, 1.1] {
            let sky = sun_sky(rotation);
            let (frame, buffer) = (frame_of(&sky), sky_map_buffer(Some(&sky)));
            // Directions on a texel's border may round to its neighbour: a few in 2000.
            let differ = (0..2000)
                .filter(|&i| {
                    let s = sample_sky_map(&frame, &buffer, uniform(i, 0), uniform(i, 1)).unwrap();
                    let (radiance, pdf) = sky_map_lookup(&frame, &buffer, s.direction);
                    (pdf - s.pdf).abs() > 1e-4 * s.pdf || radiance != s.radiance
                })
                .count();
            assert!(
                differ <= 4,
                "{differ} of 2000 samples differ from their lookup"
            );
        }
    }

    /// Monte Carlo over the sampler: E[L/pdf] is the map's integral (the sky's power ÷ the
    /// disk's area), within 1 % at 2^16 samples, and E[1/pdf] the sphere's 4π, within 3 %
    /// (the dim texels' rare samples weigh much: measured +1.3 %).
    #[test]
    fn importance_sampling_integrates_the_map() {
        let sky = sun_sky(0.7);
        let (frame, buffer) = (frame_of(&sky), sky_map_buffer(Some(&sky)));
        let n = 1 << 16;
        let (mut radiance, mut sphere) = (Vec3::ZERO, 0.0f64);
        for i in 0..n {
            let s = sample_sky_map(&frame, &buffer, uniform(i, 0), uniform(i, 1)).unwrap();
            radiance += s.radiance / s.pdf;
            sphere += 1.0 / s.pdf as f64;
        }
        let expected = sky.radiance * sky.map.as_ref().unwrap().integral();
        let relative = (radiance / n as f32 - expected).abs() / expected;
        assert!(relative.max_element() < 0.01, "{relative}");
        let sphere = sphere / n as f64;
        assert!((sphere / (4.0 * PI as f64) - 1.0).abs() < 0.03, "{sphere}");
    }

    /// The sampled directions' texels follow their weights: the sun's texel, most of the
    /// power, gets its share of 2^14 samples within 2 %.
    #[test]
    fn the_sun_gets_its_share_of_samples() {
        let sky = sun_sky(0.0);
        let (frame, buffer) = (frame_of(&sky), sky_map_buffer(Some(&sky)));
        let sun = 2 * 16 + 11;
        let share = buffer[4 * sun + 3] / 128.0;
        let n = 1 << 14;
        let hits = (0..n)
            .filter(|&i| {
                let s = sample_sky_map(&frame, &buffer, uniform(i, 0), uniform(i, 1)).unwrap();
                frame.texel_index(s.direction) == sun
            })
            .count();
        let measured = hits as f32 / n as f32;
        assert!(
            (measured / share - 1.0).abs() < 0.02,
            "{measured} vs {share}"
        );
        assert!(share > 0.5, "{share}");
    }

    #[test]
    fn the_rotation_turns_the_map_about_up() {
        // A map bright only in its centre column (−Z before the turn).
        let sky = mapped_sky(4, 2, std::f32::consts::FRAC_PI_2, |x, _| {
            Vec3::splat(if x == 2 { 1.0 } else { 0.0 })
        });
        let (frame, buffer) = (frame_of(&sky), sky_map_buffer(Some(&sky)));
        let seen = |d: Vec3| sky_map_lookup(&frame, &buffer, d.normalize()).0.x;
        // Turned a quarter counter-clockwise from above: −Z's column now faces −X.
        assert!(seen(Vec3::new(-1.0, 0.1, -0.3)) > 0.0);
        assert_eq!(seen(Vec3::new(0.05, 0.1, -1.0)), 0.0);
        let lights = [Light {
            kind: LIGHT_SKY,
            edge1: sky_light_fields(&sky).0,
            edge2: sky_light_fields(&sky).1,
            ..Light::default()
        }];
        let direction = Vec3::new(-1.0, 0.0, -0.3).normalize();
        let through = sky_radiance(&lights, &buffer, Vec3::ZERO, direction);
        assert_eq!(through, sky.radiance);
    }

    #[test]
    fn a_uniform_sky_has_no_map() {
        let bounds = Bounds::EMPTY.grow(Vec3::ZERO).grow(Vec3::ONE);
        let sky = Sky::new(Vec3::ONE, bounds);
        assert_eq!(sky_map_buffer(Some(&sky)), vec![0.0; 4]);
        let (edge1, edge2) = sky_light_fields(&sky);
        let light = Light {
            kind: LIGHT_SKY,
            edge1,
            edge2,
            ..Light::default()
        };
        assert_eq!(MapFrame::of(&light), None);
        let seen = sky_radiance(&[light], &[0.0; 4], Vec3::splat(3.0), Vec3::Y);
        assert_eq!(seen, Vec3::splat(3.0));
    }
}
