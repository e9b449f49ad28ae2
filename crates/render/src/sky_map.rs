//! The sky's environment map as the kernels read it (`scene::SkyMap`): one flat buffer of f32
//! that the CPU kernels and the GPU's (`sky_map` in `kernels/sppm/`) read alike, and the
//! lookups and importance sampling both sides do on it.
//!
//! Radiance is bilinear between texel centres (`scene::SkyMap::radiance_at`), so the map is
//! sampled on the grid whose corners are those centres: each cell is one bilinear patch (the
//! first and last rows' cells, reaching to the poles, are half as tall and constant in v).
//! A cell is drawn in proportion to its mean radiance (channel sum) × its solid angle, by two
//! 1-D CDFs (rows of cells, then the cells of the row drawn); within it a point is drawn in
//! proportion to the bilinear radiance itself. The density over map coordinates is then the
//! radiance's channel sum × the sine at the cell row's centre ÷ the map's total, and a sun
//! in a dim sky gets nearly all light samples and photons, each carrying nearly the same
//! radiance ÷ density: as good as texel-by-texel sampling of a map constant over its texels.
//!
//! The rows are split at the horizon into two halves with a CDF each, so that a receiver can
//! weigh them by where it faces ([`MapFrame::upper_share_facing`]): a floor draws from the
//! upper half only, where a draw by the whole map's importance would waste the samples that
//! land below its horizon (the ground's share of the map's power). A draw first picks the half
//! (the upper with probability `upper`), then a row of it; photons, which face nowhere, pick
//! the halves by their power ([`MapFrame::map_upper_share`]), which is the whole map's
//! importance again.
//!
//! Layout, for a map of W × H = N texels (row 0 up), its cells in H + 1 rows of W:
//! | offset | what |
//! |---|---|
//! | 3i .. 3i + 2 | texel i's radiance (the sky's scale applied) |
//! | 3N + jW + x | cell row j's CDF at cell x (its last entry 1); cell x spans texel centres x and x + 1 |
//! | 3N + (H + 1)W + j | the CDF over the cell rows of j's half at row j (each half's last entry 1): the upper half rows 0 ..= H/2 (the row holding the horizon, or the last above it), the lower half the rest |
//! | 3N + (H + 1)(W + 1) + j | cell row j's density factor: the sine at its centre ÷ its half's total (Σ over its cells of mean × sine × area) |
//! | 3N + (H + 1)(W + 2) | the upper half's share of the map's total |
//! | 3N + (H + 1)(W + 2) + 1 + j(B + 1) + k | cell row j's guide: the cell its CDF search returns for u = k / B, k = 0 ..= B ([`GUIDE_BUCKETS`] B) |
//! | 3N + (H + 1)(W + B + 3) + 1 + h(B + 1) + k | the same for the CDF over the rows of half h (0: upper) |
//!
//! The guides only narrow the CPU's searches, to the cells between the guide's entries about
//! u; a search returns the same cell with or without them (the GPU searches the whole CDF).
//!
//! Without a map the buffer is four zeros (a binding cannot be empty). The map's size and
//! rotation travel in the sky's light-table entry ([`sky_light`]).

use std::f32::consts::PI;

use glam::Vec3;
use scene::sky_map::{bilinear_footprint, map_coordinates, map_direction};
use scene::{Sky, SkyMap};

use crate::buffers::{LIGHT_SKY, Light};

/// The buffer of a scene without a sky map.
pub const NO_SKY_MAP: [f32; 4] = [0.0; 4];

/// The length in floats of the buffer of a `width` × `height` map.
fn buffer_len(width: usize, height: usize) -> usize {
    3 * width * height + (width + 2) * (height + 1) + 1 + (height + 3) * (GUIDE_BUCKETS + 1)
}

/// Buckets of a CDF's guide (a power of two, so that `u · B` and `k / B` are exact in f32).
pub const GUIDE_BUCKETS: usize = 64;

/// The last cell row of the upper half of a map `height` texels tall.
fn last_upper_row(height: u32) -> u32 {
    height / 2
}

/// The bytes of the buffer [`sky_map_buffer`] makes for `map`.
pub fn sky_map_bytes(map: &SkyMap) -> u64 {
    (buffer_len(map.width() as usize, map.height() as usize) * size_of::<f32>()) as u64
}

/// The buffer of `sky`'s map ([`NO_SKY_MAP`] without one).
pub fn sky_map_buffer(sky: Option<&Sky>) -> Vec<f32> {
    let Some((map, scale)) = sky.and_then(|s| s.map.as_ref().map(|m| (m, s.radiance))) else {
        return NO_SKY_MAP.to_vec();
    };
    let (width, height) = (map.width() as usize, map.height() as usize);
    let count = width * height;
    let cells = width * (height + 1);
    let mut buffer = vec![0.0f32; buffer_len(width, height)];
    for (i, texel) in map.texels().iter().enumerate() {
        buffer[3 * i..3 * i + 3].copy_from_slice(&(scale * *texel).to_array());
    }
    let sums: Vec<f64> = map
        .texels()
        .iter()
        .map(|t| (scale * *t).element_sum().max(0.0) as f64)
        .collect();
    // A cell's weight within its row: the mean of its four corners' sums (the bilinear
    // patch's mean); its row's weight: the row's sum × its sine × its height.
    let mut row_weights = vec![0.0f64; height + 1];
    for (j, row_weight) in row_weights.iter_mut().enumerate() {
        let (upper, lower) = (j.saturating_sub(1), j.min(height - 1));
        let means: Vec<f64> = (0..width)
            .map(|x| {
                let next = (x + 1) % width;
                let corners = [(x, upper), (next, upper), (x, lower), (next, lower)];
                corners
                    .iter()
                    .map(|&(x, y)| sums[y * width + x])
                    .sum::<f64>()
                    / 4.0
            })
            .collect();
        let sum: f64 = means.iter().sum();
        let (top, bottom) = cell_row_span(j as u32, height as u32);
        *row_weight = sum * cell_row_sine(j as u32, height as u32) as f64 * (bottom - top) as f64
            / width as f64;
        cumulative(&means, sum, &mut buffer[3 * count + j * width..][..width]);
    }
    let split = last_upper_row(height as u32) as usize + 1;
    let halves = [0..split, split..height + 1];
    let totals = halves
        .clone()
        .map(|rows| row_weights[rows].iter().sum::<f64>());
    for (rows, total) in halves.into_iter().zip(totals) {
        let marginal = &mut buffer[3 * count + cells + rows.start..][..rows.len()];
        cumulative(&row_weights[rows.clone()], total, marginal);
        for j in rows {
            let sine = cell_row_sine(j as u32, height as u32) as f64;
            buffer[3 * count + cells + height + 1 + j] = if total > 0.0 {
                (sine / total) as f32
            } else {
                0.0
            };
        }
    }
    // A map scaled to black has no power to share (and is not in the light table).
    let sum = totals[0] + totals[1];
    buffer[3 * count + cells + 2 * (height + 1)] = if sum > 0.0 {
        (totals[0] / sum) as f32
    } else {
        0.5
    };
    // The guides, cell rows' then halves'.
    let guides = 3 * count + cells + 2 * (height + 1) + 1;
    for j in 0..height + 1 {
        let cdf = buffer[3 * count + j * width..][..width].to_vec();
        write_guide(&cdf, &mut buffer[guides + j * (GUIDE_BUCKETS + 1)..]);
    }
    for (h, rows) in [0..split, split..height + 1].into_iter().enumerate() {
        let cdf = buffer[3 * count + cells + rows.start..][..rows.len()].to_vec();
        let at = guides + (height + 1 + h) * (GUIDE_BUCKETS + 1);
        write_guide(&cdf, &mut buffer[at..]);
    }
    buffer
}

/// Writes `cdf`'s guide into the first [`GUIDE_BUCKETS`] + 1 entries of `guide`: entry k the
/// index [`search`] returns for u = k / B.
fn write_guide(cdf: &[f32], guide: &mut [f32]) {
    for (k, entry) in guide[..=GUIDE_BUCKETS].iter_mut().enumerate() {
        let u = k as f32 / GUIDE_BUCKETS as f32;
        *entry = search(cdf, u).0 as f32;
    }
}

/// Where cell row `j` of a map `height` texels tall spans in v: between the centres of texel
/// rows j − 1 and j, the first from the pole to row 0's centre, the last from row H − 1's
/// centre to the other pole.
fn cell_row_span(j: u32, height: u32) -> (f32, f32) {
    let h = height as f32;
    ((j as f32 - 0.5).max(0.0) / h, (j as f32 + 0.5).min(h) / h)
}

/// The sine of the polar angle at cell row `j`'s centre: its cells' solid angle per unit of
/// map area ÷ 2π², the factor the density carries for the row.
fn cell_row_sine(j: u32, height: u32) -> f32 {
    let (top, bottom) = cell_row_span(j, height);
    (PI * 0.5 * (top + bottom)).sin()
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

/// The sky's entry in the light table, before its pick probability: the bounding sphere's
/// centre in `v0`; in `edge1` the rotation's cosine and sine, in `edge2` the bounding radius
/// and the map's width and height (zero without a map).
pub fn sky_light(sky: &Sky) -> Light {
    let (edge1, edge2) = match &sky.map {
        Some(map) => {
            let (sin, cos) = sky.rotation.sin_cos();
            (
                [cos, sin, 0.0],
                [sky.radius, map.width() as f32, map.height() as f32],
            )
        }
        None => ([0.0; 3], [sky.radius, 0.0, 0.0]),
    };
    Light {
        v0: sky.centre.to_array(),
        edge1,
        edge2,
        kind: LIGHT_SKY,
        ..Light::default()
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

    /// The map coordinates (u, v) of world `direction` (unit).
    pub fn coordinates(&self, direction: Vec3) -> (f32, f32) {
        map_coordinates(self.turned_to_map(direction))
    }

    fn texel(&self, buffer: &[f32], x: u32, y: u32) -> Vec3 {
        let i = 3 * (y * self.width + x) as usize;
        Vec3::new(buffer[i], buffer[i + 1], buffer[i + 2])
    }

    /// The bilinear radiance at map coordinates (u, v) (`scene::SkyMap::radiance_at`, the
    /// sky's scale applied) read from `buffer`.
    pub fn radiance_at(&self, buffer: &[f32], (u, v): (f32, f32)) -> Vec3 {
        let [(x0, x1, a), (y0, y1, b)] = bilinear_footprint(self.width, self.height, u, v);
        let row = |y: u32| self.texel(buffer, x0, y).lerp(self.texel(buffer, x1, y), a);
        row(y0).lerp(row(y1), b)
    }

    /// Where the rows' CDFs over cells begin in the buffer, then those over rows, the rows'
    /// density factors, the upper half's share, and the guides (cell rows', then halves').
    fn offsets(&self) -> [usize; 5] {
        let count = (self.width * self.height) as usize;
        let rows = self.height as usize + 1;
        let cells = 3 * count;
        let marginal = cells + rows * self.width as usize;
        let share = marginal + 2 * rows;
        [cells, marginal, marginal + rows, share, share + 1]
    }

    /// The upper half's share of the map's power: the probability of drawing from it that
    /// makes a draw follow the whole map's importance (photons').
    pub fn map_upper_share(&self, buffer: &[f32]) -> f32 {
        buffer[self.offsets()[3]]
    }

    /// The probability of drawing from the upper half for a receiver facing `normal` (world,
    /// unit): 1 facing straight up, 0 straight down, the map's own share facing sideways,
    /// linear in the normal's height between; never a half with no power.
    pub fn upper_share_facing(&self, buffer: &[f32], normal: Vec3) -> f32 {
        let share = self.map_upper_share(buffer);
        if share <= 0.0 || share >= 1.0 {
            return share.clamp(0.0, 1.0);
        }
        if normal.y >= 0.0 {
            share + normal.y * (1.0 - share)
        } else {
            share * (1.0 + normal.y)
        }
    }

    /// The density over map coordinates with which [`sample_sky_map`], drawing from the upper
    /// half with probability `upper`, draws a point of cell row `j` where the map holds
    /// `radiance`.
    fn density(&self, buffer: &[f32], j: u32, radiance: Vec3, upper: f32) -> f32 {
        let half = if j <= last_upper_row(self.height) {
            upper
        } else {
            1.0 - upper
        };
        radiance.element_sum() * buffer[self.offsets()[2] + j as usize] * half
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

/// The density per solid angle of a direction whose density over map coordinates is
/// `density` and whose polar angle has sine `sine` (map area → solid angle: 2π² sin θ).
fn solid_angle_density(density: f32, sine: f32) -> f32 {
    if sine > 0.0 {
        density / (2.0 * PI * PI * sine)
    } else {
        0.0
    }
}

/// The radiance along world `direction` (unit) and the solid-angle density with which
/// [`sample_sky_map`], drawing from the upper half with probability `upper`, draws it.
pub fn sky_map_lookup(
    frame: &MapFrame,
    buffer: &[f32],
    direction: Vec3,
    upper: f32,
) -> (Vec3, f32) {
    let (u, v) = frame.coordinates(direction);
    let radiance = frame.radiance_at(buffer, (u, v));
    // The cell row holding v: row j spans texel centres j − 1 and j.
    let j = ((v * frame.height as f32 + 0.5) as u32).min(frame.height);
    let sine = (1.0 - direction.y * direction.y).max(0.0).sqrt();
    let density = frame.density(buffer, j, radiance, upper);
    (radiance, solid_angle_density(density, sine))
}

/// A direction drawn from two uniform numbers in proportion to the map's bilinear radiance ×
/// its cell's solid angle, from the upper half with probability `upper` (`u1` chooses the
/// half, then the row); `None` on the measure-zero poles, where the density is undefined.
pub fn sample_sky_map(
    frame: &MapFrame,
    buffer: &[f32],
    u1: f32,
    u2: f32,
    upper: f32,
) -> Option<SkyDirection> {
    let (width, height) = (frame.width, frame.height);
    let [cells, marginal, _, _, guides] = frame.offsets();
    let split = last_upper_row(height) + 1;
    let (first, rows, u1, half) = if u1 < upper {
        (0, split, u1 / upper, 0)
    } else {
        (split, height + 1 - split, (u1 - upper) / (1.0 - upper), 1)
    };
    let guide = |i: u32| &buffer[guides + i as usize * (GUIDE_BUCKETS + 1)..][..=GUIDE_BUCKETS];
    let half_cdf = &buffer[marginal + first as usize..][..rows as usize];
    let (row, row_fraction) =
        guided_search(half_cdf, guide(height + 1 + half), u1.min(0.999_999_94));
    let j = first + row as u32;
    let row_cdf = &buffer[cells + (j * width) as usize..][..width as usize];
    let (x, column_fraction) = guided_search(row_cdf, guide(j), u2);
    let x = x as u32;
    // The cell's corners, then a point by the bilinear patch their radiance sums span: v by
    // its marginal (linear between the upper and lower edges' means), u given v.
    let (top_row, bottom_row) = (j.saturating_sub(1), j.min(height - 1));
    let next = (x + 1) % width;
    let [t00, t10] = [
        frame.texel(buffer, x, top_row),
        frame.texel(buffer, next, top_row),
    ];
    let [t01, t11] = [
        frame.texel(buffer, x, bottom_row),
        frame.texel(buffer, next, bottom_row),
    ];
    let [c00, c10, c01, c11] = [t00, t10, t01, t11].map(Vec3::element_sum);
    let b = sample_linear(row_fraction, c00 + c10, c01 + c11);
    let a = sample_linear(
        column_fraction,
        c00 + (c01 - c00) * b,
        c10 + (c11 - c10) * b,
    );
    // MapFrame::radiance_at's interpolation, on the corners at hand.
    let radiance = t00.lerp(t10, a).lerp(t01.lerp(t11, a), b);
    let mut u = (x as f32 + 0.5 + a) / width as f32;
    if u >= 1.0 {
        u -= 1.0;
    }
    let (top, bottom) = cell_row_span(j, height);
    let v = top + (bottom - top) * b;
    let sine = (PI * v).sin();
    if sine <= 0.0 {
        return None;
    }
    Some(SkyDirection {
        direction: frame.turned_to_world(map_direction(u, v)),
        radiance,
        pdf: solid_angle_density(frame.density(buffer, j, radiance, upper), sine),
    })
}

/// A point of [0, 1) drawn from uniform `u` with density proportional to the line from `p0`
/// at 0 to `p1` at 1 (both ≥ 0; uniform when they are equal or both zero), the root of its
/// CDF in the form that stays exact as either end goes to zero.
fn sample_linear(u: f32, p0: f32, p1: f32) -> f32 {
    if p0 == p1 {
        return u;
    }
    let x = u * (p0 + p1) / (p0 + (p0 * p0 + (p1 * p1 - p0 * p0) * u).max(0.0).sqrt());
    x.clamp(0.0, 0.999_999_94)
}

/// The first entry of `cdf` above `u` (a binary search) and where `u` lies within its
/// interval, in [0, 1).
fn search(cdf: &[f32], u: f32) -> (usize, f32) {
    search_between(cdf, u, 0, cdf.len() - 1)
}

/// [`search`] narrowed by `cdf`'s guide to the entries between those of u's bucket: the same
/// result, as the search's answer grows with u and the guide holds it at the buckets' edges.
fn guided_search(cdf: &[f32], guide: &[f32], u: f32) -> (usize, f32) {
    let bucket = ((u * GUIDE_BUCKETS as f32) as usize).min(GUIDE_BUCKETS - 1);
    let (lo, hi) = (guide[bucket] as usize, guide[bucket + 1] as usize);
    search_between(cdf, u, lo, hi)
}

/// [`search`] among entries `lo ..= hi`, which hold its answer.
fn search_between(cdf: &[f32], u: f32, lo: usize, hi: usize) -> (usize, f32) {
    let (mut lo, mut hi) = (lo, hi);
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
        Some(frame) => frame.radiance_at(buffer, frame.coordinates(direction)),
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

    /// The share of draws from the upper half that follows the whole map (photons').
    fn whole(frame: &MapFrame, buffer: &[f32]) -> f32 {
        frame.map_upper_share(buffer)
    }

    /// Sample `i` of the whole map (photons' draw).
    fn draw(frame: &MapFrame, buffer: &[f32], i: u32) -> SkyDirection {
        sample_sky_map(
            frame,
            buffer,
            uniform(i, 0),
            uniform(i, 1),
            whole(frame, buffer),
        )
        .unwrap()
    }

    fn frame_of(sky: &Sky) -> MapFrame {
        MapFrame::of(&sky_light(sky)).unwrap()
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

    /// The guides change no search: for CDFs flat, peaked, with empty stretches and of one
    /// entry, and every cell row and half of a sun's map, the guided search returns what the
    /// whole search does, at the buckets' edges, just below them and between.
    #[test]
    fn guided_searches_return_what_whole_searches_do() {
        let mut cdfs: Vec<Vec<f32>> = vec![
            (1..=37).map(|i| i as f32 / 37.0).collect(),
            vec![0.0, 0.0, 0.001, 0.001, 0.999, 1.0, 1.0],
            vec![1.0],
            (0..300)
                .map(|i| {
                    if i < 290 {
                        0.0
                    } else {
                        (i - 289) as f32 / 10.0
                    }
                })
                .collect(),
        ];
        let sky = sun_sky(0.4);
        let frame = frame_of(&sky);
        let buffer = sky_map_buffer(Some(&sky));
        let [cells, marginal, _, _, _] = frame.offsets();
        let (w, h) = (frame.width as usize, frame.height as usize);
        cdfs.extend((0..=h).map(|j| buffer[cells + j * w..][..w].to_vec()));
        let split = last_upper_row(frame.height) as usize + 1;
        cdfs.push(buffer[marginal..][..split].to_vec());
        cdfs.push(buffer[marginal + split..][..h + 1 - split].to_vec());
        let mut us: Vec<f32> = (0..=4096).map(|i| i as f32 / 4096.0).collect();
        us.extend((1..=GUIDE_BUCKETS).map(|k| k as f32 / GUIDE_BUCKETS as f32 - 6e-8));
        us.push(0.999_999_94);
        for cdf in &cdfs {
            let mut guide = vec![0.0; GUIDE_BUCKETS + 1];
            write_guide(cdf, &mut guide);
            for &u in us.iter().filter(|&&u| u < 1.0) {
                assert_eq!(
                    guided_search(cdf, &guide, u),
                    search(cdf, u),
                    "u {u}, {cdf:?}"
                );
            }
        }
        // The buffer's own guides are those.
        let guides = frame.offsets()[4];
        let mut guide = vec![0.0; GUIDE_BUCKETS + 1];
        write_guide(&buffer[cells + 3 * w..][..w], &mut guide);
        assert_eq!(
            &buffer[guides + 3 * (GUIDE_BUCKETS + 1)..][..=GUIDE_BUCKETS],
            &guide[..]
        );
        assert_eq!(buffer.len(), buffer_len(w, h));
    }

    #[test]
    fn samples_carry_the_density_the_lookup_gives() {
        for rotation in [0.0, 1.1] {
            let sky = sun_sky(rotation);
            let (frame, buffer) = (frame_of(&sky), sky_map_buffer(Some(&sky)));
            // Directions on a texel's border may round to its neighbour: a few in 2000.
            let differ = (0..2000)
                .filter(|&i| {
                    let s = draw(&frame, &buffer, i);
                    let (radiance, pdf) =
                        sky_map_lookup(&frame, &buffer, s.direction, whole(&frame, &buffer));
                    let off = (radiance - s.radiance).abs().max_element();
                    (pdf - s.pdf).abs() > 1e-4 * s.pdf || off > 1e-3 * s.radiance.max_element()
                })
                .count();
            assert!(
                differ <= 4,
                "{differ} of 2000 samples differ from their lookup"
            );
        }
    }

    /// Monte Carlo over the sampler: E[L/pdf] is the map's integral (the sky's power ÷ the
    /// disk's area, exact for the bilinear radiance), within 1 % at 2^16 samples, and E[1/pdf]
    /// the sphere's 4π, within 3 % (the dim texels' rare samples weigh much: measured +1.3 %).
    #[test]
    fn importance_sampling_integrates_the_map() {
        let sky = sun_sky(0.7);
        let (frame, buffer) = (frame_of(&sky), sky_map_buffer(Some(&sky)));
        let n = 1 << 16;
        let (mut radiance, mut sphere) = (Vec3::ZERO, 0.0f64);
        for i in 0..n {
            let s = draw(&frame, &buffer, i);
            radiance += s.radiance / s.pdf;
            sphere += 1.0 / s.pdf as f64;
        }
        let expected = sky.radiance * sky.map.as_ref().unwrap().integral();
        let relative = (radiance / n as f32 - expected).abs() / expected;
        assert!(relative.max_element() < 0.01, "{relative}");
        let sphere = sphere / n as f64;
        assert!((sphere / (4.0 * PI as f64) - 1.0).abs() < 0.03, "{sphere}");
    }

    /// A lone sun on black: the bilinear radiance spreads into the sun's eight neighbours,
    /// which must be drawn too (a density of zero where there is light would lose it): no
    /// lit direction has zero density, and the sampler still integrates the map (within 1 %).
    #[test]
    fn every_lit_direction_can_be_drawn() {
        let sky = mapped_sky(16, 8, 0.3, |x, y| {
            Vec3::splat(if (x, y) == (0, 3) { 50.0 } else { 0.0 })
        });
        let (frame, buffer) = (frame_of(&sky), sky_map_buffer(Some(&sky)));
        let lit_without_density = (0..20000)
            .map(|i| map_direction(uniform(i, 2), uniform(i, 3)))
            .filter(|&d| {
                let (radiance, pdf) = sky_map_lookup(
                    &frame,
                    &buffer,
                    frame.turned_to_world(d),
                    whole(&frame, &buffer),
                );
                radiance.max_element() > 0.0 && pdf <= 0.0
            })
            .count();
        assert_eq!(lit_without_density, 0);
        let n = 1 << 16;
        let integral = (0..n)
            .map(|i| draw(&frame, &buffer, i))
            .fold(Vec3::ZERO, |sum, s| sum + s.radiance / s.pdf)
            / n as f32;
        let expected = sky.radiance * sky.map.as_ref().unwrap().integral();
        let relative = (integral - expected).abs() / expected;
        assert!(relative.max_element() < 0.01, "{integral} vs {expected}");
    }

    /// The buffer's bilinear lookup is the scene's `SkyMap::radiance_at`, scaled.
    #[test]
    fn the_buffer_interpolates_as_the_map() {
        let sky = sun_sky(0.0);
        let (frame, buffer) = (frame_of(&sky), sky_map_buffer(Some(&sky)));
        let map = sky.map.as_ref().unwrap();
        for i in 0..500 {
            let (u, v) = (uniform(i, 4), uniform(i, 5));
            let expected = sky.radiance * map.radiance_at(u, v);
            let found = frame.radiance_at(&buffer, (u, v));
            assert!(
                (found - expected).abs().max_element() <= 1e-5 * expected.max_element(),
                "({u}, {v}): {found} vs {expected}"
            );
        }
    }

    /// The samples land where the lookup's density says, within cells as well as between
    /// them, and between the halves as `upper` shares them: 2^16 samples of the sun sky binned
    /// 4 × 4 per texel, Pearson's χ² against the lookup's density integrated over each bin
    /// (bins expecting fewer than 5 samples pooled into one), for the whole map's share, a
    /// floor's (1), a ceiling's (0) and one between. A correct sampler gives χ² ≈ the bins'
    /// count (±√(2·bins)); measured χ²/bins 1.01 (whole map), and 82 with points drawn
    /// uniformly within their cell.
    #[test]
    fn samples_follow_the_density_within_cells() {
        let sky = sun_sky(0.0);
        let (frame, buffer) = (frame_of(&sky), sky_map_buffer(Some(&sky)));
        for upper in [whole(&frame, &buffer), 1.0, 0.0, 0.3] {
            follow_the_density(&frame, &buffer, upper);
        }
    }

    fn follow_the_density(frame: &MapFrame, buffer: &[f32], upper: f32) {
        let (frame, buffer) = (*frame, buffer);
        let (columns, rows) = (4 * frame.width as usize, 4 * frame.height as usize);
        let n = 1u32 << 16;
        let mut observed = vec![0.0f64; columns * rows];
        for i in 0..n {
            let s = sample_sky_map(&frame, buffer, uniform(i, 0), uniform(i, 1), upper).unwrap();
            let (u, v) = frame.coordinates(s.direction);
            let bin = |c: f32, count: usize| ((c * count as f32) as usize).min(count - 1);
            observed[bin(v, rows) * columns + bin(u, columns)] += 1.0;
        }
        // The density over map coordinates, by 4 × 4 midpoints a bin.
        let expected: Vec<f64> = (0..columns * rows)
            .map(|bin| {
                let (column, row) = (bin % columns, bin / columns);
                let mut sum = 0.0f64;
                for k in 0..16 {
                    let u = (column as f32 + (k % 4) as f32 / 4.0 + 0.125) / columns as f32;
                    let v = (row as f32 + (k / 4) as f32 / 4.0 + 0.125) / rows as f32;
                    let (_, pdf) = sky_map_lookup(&frame, buffer, map_direction(u, v), upper);
                    sum += (pdf * 2.0 * PI * PI * (PI * v).sin()) as f64;
                }
                sum / 16.0 / (columns * rows) as f64 * n as f64
            })
            .collect();
        let total: f64 = expected.iter().sum();
        assert!((total / n as f64 - 1.0).abs() < 1e-3, "{total}");
        let (mut chi2, mut bins, mut pooled) = (0.0, 0usize, (0.0, 0.0));
        for (o, e) in observed.iter().zip(&expected) {
            if *e >= 5.0 {
                chi2 += (o - e).powi(2) / e;
                bins += 1;
            } else {
                pooled = (pooled.0 + o, pooled.1 + e);
            }
        }
        chi2 += (pooled.0 - pooled.1).powi(2) / pooled.1.max(1.0);
        let bound = bins as f64 + 6.0 * (2.0 * bins as f64).sqrt();
        assert!(
            chi2 < bound,
            "upper {upper}: χ² {chi2} over {bins} bins (bound {bound})"
        );
    }

    #[test]
    fn receivers_draw_from_the_half_they_face() {
        let sky = sun_sky(0.0);
        let (frame, buffer) = (frame_of(&sky), sky_map_buffer(Some(&sky)));
        let share = whole(&frame, &buffer);
        assert!(share > 0.5 && share < 1.0, "{share}");
        let facing = |normal: Vec3| frame.upper_share_facing(&buffer, normal.normalize());
        assert_eq!(facing(Vec3::Y), 1.0);
        assert_eq!(facing(Vec3::NEG_Y), 0.0);
        assert_eq!(facing(Vec3::X), share);
        let tilted = facing(Vec3::new(1.0, 1.0, 0.0));
        assert!(tilted > share && tilted < 1.0, "{tilted}");
        // A map black below the horizon: everyone draws from the upper half.
        let dark_ground = mapped_sky(8, 4, 0.0, |_, y| Vec3::splat((y < 2) as u32 as f32));
        let (frame, buffer) = (frame_of(&dark_ground), sky_map_buffer(Some(&dark_ground)));
        assert_eq!(frame.upper_share_facing(&buffer, Vec3::NEG_Y), 1.0);
    }

    /// A floor's irradiance by light samples, E[L cos⁺ θ / pdf] = `SkyMap::floor_irradiance`,
    /// under a map whose ground is bright: unbiased whether drawn by the whole map's
    /// importance or from the upper half only (the floor's share), within 1 % at 2^15
    /// samples; and drawn from the upper half, no sample is wasted below the horizon, so its
    /// variance is lower (measured: relative standard deviation 0.64 against 1.22).
    #[test]
    fn a_floor_drawing_from_the_upper_half_wastes_nothing() {
        let sky = mapped_sky(32, 16, 0.4, |x, y| {
            if (x, y) == (5, 4) {
                Vec3::new(40.0, 30.0, 20.0)
            } else if y < 8 {
                Vec3::new(0.3, 0.5, 1.0)
            } else {
                Vec3::splat(0.8)
            }
        });
        let (frame, buffer) = (frame_of(&sky), sky_map_buffer(Some(&sky)));
        let expected = (sky.radiance * sky.map.as_ref().unwrap().floor_irradiance()).element_sum();
        let n = 1 << 15;
        let spread = |upper: f32| {
            let estimates: Vec<f64> = (0..n)
                .map(|i| {
                    let Some(s) =
                        sample_sky_map(&frame, &buffer, uniform(i, 0), uniform(i, 1), upper)
                    else {
                        return 0.0;
                    };
                    (s.radiance.element_sum() * s.direction.y.max(0.0) / s.pdf) as f64
                })
                .collect();
            let mean = estimates.iter().sum::<f64>() / n as f64;
            let variance = estimates.iter().map(|e| (e - mean).powi(2)).sum::<f64>() / n as f64;
            assert!(
                (mean / expected as f64 - 1.0).abs() < 0.01,
                "upper {upper}: {mean} against {expected}"
            );
            variance.sqrt() / mean
        };
        let (by_map, by_floor) = (spread(whole(&frame, &buffer)), spread(1.0));
        assert!(by_floor < 0.8 * by_map, "{by_floor} against {by_map}");
    }

    #[test]
    fn the_rotation_turns_the_map_about_up() {
        // A map bright only in the two columns either side of its centre (−Z before the turn),
        // so that the bilinear radiance peaks at −Z and fades out a quarter turn away.
        let sky = mapped_sky(8, 2, std::f32::consts::FRAC_PI_2, |x, _| {
            Vec3::splat(if x == 3 || x == 4 { 1.0 } else { 0.0 })
        });
        let (frame, buffer) = (frame_of(&sky), sky_map_buffer(Some(&sky)));
        let seen = |d: Vec3| sky_map_lookup(&frame, &buffer, d.normalize(), 0.5).0.x;
        // Turned a quarter counter-clockwise from above: −Z's columns now face −X.
        assert_eq!(seen(Vec3::new(-1.0, 0.1, 0.0)), 1.0);
        assert_eq!(seen(Vec3::new(0.05, 0.1, -1.0)), 0.0);
        let lights = [sky_light(&sky)];
        let direction = Vec3::new(-1.0, 0.0, 0.0);
        let through = sky_radiance(&lights, &buffer, Vec3::ZERO, direction);
        assert_eq!(through, sky.radiance);
    }

    #[test]
    fn the_buffer_has_the_size_announced() {
        let sky = sun_sky(0.0);
        let map = sky.map.as_ref().unwrap();
        let bytes = sky_map_buffer(Some(&sky)).len() * size_of::<f32>();
        assert_eq!(bytes as u64, sky_map_bytes(map));
    }

    #[test]
    fn a_uniform_sky_has_no_map() {
        let bounds = Bounds::EMPTY.grow(Vec3::ZERO).grow(Vec3::ONE);
        let sky = Sky::new(Vec3::ONE, bounds);
        assert_eq!(sky_map_buffer(Some(&sky)), vec![0.0; 4]);
        let light = sky_light(&sky);
        assert_eq!(MapFrame::of(&light), None);
        let seen = sky_radiance(&[light], &[0.0; 4], Vec3::splat(3.0), Vec3::Y);
        assert_eq!(seen, Vec3::splat(3.0));
    }
}
