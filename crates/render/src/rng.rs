//! The kernels' random numbers: one PCG stream per (slot or pixel, pass), made by hashing the
//! stream's key (Jarzynski & Olano 2020's `pcg` hash, the one ANCHORS.md's rays use) and
//! advanced by PCG's 32-bit LCG with the RXS-M-XS output. Both backends draw the same numbers.

use bvh::bench_rays::pcg_hash;

/// Salts that keep the kernels' streams apart for the same (index, pass).
pub const PHOTON_STREAM: u32 = 0x2f6b_17c9;
pub const EYE_STREAM: u32 = 0x8d3e_a541;
pub const HASH_STREAM: u32 = 0x51c4_9e0b;
pub const JITTER_STREAM: u32 = 0xc7a2_3d95;

/// The R2 sequence's steps (Roberts 2018: the 2D Kronecker sequence of the plastic number
/// φ₂ ≈ 1.3247, steps 1/φ₂ and 1/φ₂²) in 32-bit fixed point.
pub const R2_STEP: [u32; 2] = [3_242_174_889, 2_447_445_414];

/// Where in its pixel eye pass `eye_pass` aims pixel `index`'s camera ray, in [0, 1)²: the
/// eye_pass-th point of the R2 sequence shifted by a random offset per pixel (a
/// Cranley–Patterson rotation, so that neighbouring pixels do not share a pattern), in 32-bit
/// fixed point so that both backends get the same numbers. Any run of consecutive eye passes
/// covers the pixel evenly, so features smaller than a pixel (a light seen in glass) and edges
/// converge faster than under independent jitter.
pub fn pixel_jitter(seed: u32, index: u32, eye_pass: u32) -> [f32; 2] {
    [0, 1].map(|axis| {
        let shift = stream_key(seed, JITTER_STREAM, axis, index);
        let fixed = eye_pass
            .wrapping_mul(R2_STEP[axis as usize])
            .wrapping_add(shift);
        (fixed >> 8) as f32 * (1.0 / 16_777_216.0)
    })
}

/// The steps of the lens's Kronecker sequence, √7 and √15 (their fractions) in 32-bit fixed
/// point. Beside [`R2_STEP`]'s jitter and [`GOLDEN_STEP`]'s wavelength they keep the
/// sequence of (jitter, lens, wavelength) evenly spread in all five dimensions (1, 1/φ₂,
/// 1/φ₂², √5, √7 and √15 are linearly independent over the rationals); R2's or the golden
/// steps for the lens would tie each pixel's lens point to its jitter or its wavelength. Of
/// pairs of square roots of 2 to 17 this one spread (jitter, lens) most evenly over runs of
/// 32 to 4,096 passes.
pub const LENS_STEP: [u32; 2] = [2_773_480_762, 3_749_434_922];

/// Where on its lens (in [0, 1)², mapped to the disk by `crate::sampling::concentric_disk`)
/// eye pass `eye_pass` starts pixel `index`'s first camera path: [`pixel_jitter`]'s scheme with
/// [`LENS_STEP`], from its stream with axes 3 and 4.
pub fn pixel_lens(seed: u32, index: u32, eye_pass: u32) -> [f32; 2] {
    [0, 1].map(|axis| {
        let shift = stream_key(seed, JITTER_STREAM, 3 + axis, index);
        let fixed = eye_pass
            .wrapping_mul(LENS_STEP[axis as usize])
            .wrapping_add(shift);
        (fixed >> 8) as f32 * (1.0 / 16_777_216.0)
    })
}

/// 2³² / φ (the golden ratio), rounded: the step of the Kronecker sequence of 1/φ (the R1
/// sequence) in 32-bit fixed point.
pub const GOLDEN_STEP: u32 = 0x9e37_79b9;

/// The number camera path `path` (0: the first; then the extra paths of pixels showing glass,
/// `crate::buffers::SPECULAR_EXTRA_PATHS`) of eye pass `eye_pass` through pixel `index`
/// draws its wavelength with at dispersive glass (`crate::dispersion`), in [0, 1): the R1
/// sequence, 1/φ further each eye pass and each path, from a random offset per pixel. Any run
/// of consecutive eye passes spreads a pixel's numbers evenly over the spectrum (three take a
/// third each, roughly: blue, green, red), and a pass's paths take numbers far apart, while
/// each number alone is uniform: independent draws left dispersive glass in colour noise
/// until many eye passes had averaged it. In 32-bit fixed point as [`pixel_jitter`], from its
/// stream with axis 2.
pub fn pixel_wavelength(seed: u32, index: u32, eye_pass: u32, path: u32) -> f32 {
    let shift = stream_key(seed, JITTER_STREAM, 2, index);
    let step = eye_pass.wrapping_add(path);
    let fixed = step.wrapping_mul(GOLDEN_STEP).wrapping_add(shift);
    (fixed >> 8) as f32 * (1.0 / 16_777_216.0)
}

/// √11's fraction in 32-bit fixed point: the step of [`pixel_side`]'s Kronecker sequence,
/// independent over the rationals of the jitter's, the lens's and the wavelength's steps.
pub const SIDE_STEP: u32 = 1_359_893_120;

/// The number with which eye pass `eye_pass`'s first camera path through pixel `index`
/// chooses the side of a translucent surface's Lambertian lobe (glTF's diffuse transmission:
/// the far side where the number lies below the share transmitted): [`pixel_jitter`]'s scheme
/// with [`SIDE_STEP`], from its stream with axis 5. Any run of consecutive eye passes takes
/// the far side in the share's proportion to within one pass; independent draws left the
/// proportion's binomial noise (7 % after 128 eye passes at a share of 0.6).
pub fn pixel_side(seed: u32, index: u32, eye_pass: u32) -> f32 {
    let shift = stream_key(seed, JITTER_STREAM, 5, index);
    let fixed = eye_pass.wrapping_mul(SIDE_STEP).wrapping_add(shift);
    (fixed >> 8) as f32 * (1.0 / 16_777_216.0)
}

/// A PCG stream.
#[derive(Clone, Copy, Debug)]
pub struct KernelRng {
    pub state: u32,
}

impl KernelRng {
    /// The stream of element `index` (a slot, pixel or photon) in pass `pass` of kernel `salt`.
    pub fn new(seed: u32, salt: u32, pass: u32, index: u32) -> KernelRng {
        KernelRng {
            state: stream_key(seed, salt, pass, index),
        }
    }

    pub fn next_u32(&mut self) -> u32 {
        let old = self.state;
        self.state = old.wrapping_mul(747_796_405).wrapping_add(2_891_336_453);
        pcg_hash(old)
    }

    /// Uniform in [0, 1): the top 24 bits, exact in f32, never 1.
    pub fn next_f32(&mut self) -> f32 {
        (self.next_u32() >> 8) as f32 * (1.0 / 16_777_216.0)
    }
}

/// The starting state of a stream: the key hashed in three rounds so that neighbouring
/// indices and passes land far apart.
pub fn stream_key(seed: u32, salt: u32, pass: u32, index: u32) -> u32 {
    pcg_hash(index ^ pcg_hash(pass ^ pcg_hash(seed ^ salt)))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Any run of eye passes spreads a pixel's jitter evenly: 256 consecutive points over a
    /// 4 × 4 grid give a chi-square of 1.9–4.9 (16 points per cell expected; independent
    /// points: 15 on average, below 7.5 one time in twenty), for pixels whose shifts differ.
    #[test]
    fn pixel_jitter_covers_the_pixel_evenly() {
        let mut shifts = Vec::new();
        for index in [0, 1, 777, 65_535] {
            for start in [0, 1000] {
                let mut cells = [0u32; 16];
                for k in start..start + 256 {
                    let [x, y] = pixel_jitter(9, index, k);
                    assert!((0.0..1.0).contains(&x) && (0.0..1.0).contains(&y));
                    cells[(x * 4.0) as usize + 4 * (y * 4.0) as usize] += 1;
                }
                let chi_square: f64 = cells
                    .iter()
                    .map(|&c| (c as f64 - 16.0).powi(2) / 16.0)
                    .sum();
                assert!(chi_square < 7.5, "{cells:?}: chi-square {chi_square}");
            }
            shifts.push(pixel_jitter(9, index, 0));
        }
        shifts.dedup();
        assert_eq!(shifts.len(), 4, "pixels share a shift: {shifts:?}");
    }

    /// A pixel's lens points fill the (jitter, lens) space evenly, pass after pass: 4,096
    /// consecutive passes over 4⁴ cells (16 points each expected) give a chi-square of 96–101,
    /// where independent points average 255 ± 23 (150 is 4.6 standard deviations below). Lens points
    /// made with R2's own steps would trace a plane through that space (19,000 here).
    #[test]
    fn pixel_lens_fills_jitter_and_lens_together() {
        let chi_square = |lens: &dyn Fn(u32, u32) -> [f32; 2], index: u32, start: u32| {
            let mut cells = [0u32; 256];
            for k in start..start + 4096 {
                let [x, y] = pixel_jitter(9, index, k);
                let [u, v] = lens(index, k);
                assert!((0.0..1.0).contains(&u) && (0.0..1.0).contains(&v));
                let cell = |t: f32| (t * 4.0) as usize;
                cells[cell(x) + 4 * cell(y) + 16 * cell(u) + 64 * cell(v)] += 1;
            }
            cells
                .iter()
                .map(|&c| (c as f64 - 16.0).powi(2) / 16.0)
                .sum::<f64>()
        };
        for index in [0, 1, 777, 65_535] {
            for start in [0, 5000] {
                let lens = |i, k| pixel_lens(9, i, k);
                let chi = chi_square(&lens, index, start);
                assert!(chi < 150.0, "pixel {index} from {start}: chi-square {chi}");
            }
        }
        let tied = |i, k| {
            let [x, y] = pixel_jitter(9, i, k);
            [(x + 0.3) % 1.0, (y + 0.6) % 1.0]
        };
        assert!(chi_square(&tied, 1, 0) > 1000.0);
    }

    /// A pixel's side numbers take the far side of a translucent surface in the share's
    /// proportion to within a pass or two over any run of eye passes (independent draws: ±8
    /// passes, one standard deviation, over 256 at a share of 0.6), and are independent of its
    /// jitter: over 4,096 passes the (jitter x, side) pairs fill 8 × 8 cells evenly (chi-square
    /// 5.6–7.4 measured; independent points average 63 ± 11).
    #[test]
    fn pixel_side_takes_each_side_in_proportion() {
        for index in [0, 1, 777, 65_535] {
            for start in [0, 3000] {
                for share in [0.1, 0.6, 0.95] {
                    let far = (start..start + 256)
                        .filter(|&k| pixel_side(9, index, k) < share)
                        .count() as f32;
                    let off = (far - 256.0 * share).abs();
                    assert!(
                        off <= 2.0,
                        "pixel {index} from {start}, share {share}: {far}"
                    );
                }
                let mut cells = [0u32; 64];
                for k in start..start + 4096 {
                    let side = pixel_side(9, index, k);
                    assert!((0.0..1.0).contains(&side));
                    let x = pixel_jitter(9, index, k)[0];
                    cells[(x * 8.0) as usize + 8 * (side * 8.0) as usize] += 1;
                }
                let chi_square: f64 = (cells.iter())
                    .map(|&c| (c as f64 - 64.0).powi(2) / 64.0)
                    .sum();
                assert!(chi_square < 100.0, "pixel {index}: chi-square {chi_square}");
            }
        }
    }

    /// Chi-square over 64 bins of many streams' first draws and of one stream's sequence.
    #[test]
    fn draws_are_uniform() {
        const BINS: usize = 64;
        let n = 200_000;
        let chi_square = |values: &mut dyn Iterator<Item = f32>| {
            let mut counts = [0u32; BINS];
            for v in values.take(n) {
                assert!((0.0..1.0).contains(&v));
                counts[(v * BINS as f32) as usize] += 1;
            }
            let expected = n as f64 / BINS as f64;
            counts
                .iter()
                .map(|&c| (c as f64 - expected).powi(2) / expected)
                .sum::<f64>()
        };
        // 63 degrees of freedom: the 0.999 quantile is 103.4.
        let mut across = (0..n as u32).map(|i| KernelRng::new(7, PHOTON_STREAM, 3, i).next_f32());
        let across = chi_square(&mut across);
        assert!(across < 103.4, "across streams: {across}");
        let mut rng = KernelRng::new(7, EYE_STREAM, 0, 0);
        let mut along = std::iter::from_fn(|| Some(rng.next_f32()));
        let along = chi_square(&mut along);
        assert!(along < 103.4, "along one stream: {along}");
    }

    /// Neighbouring streams (index i and i + 1, and pass p and p + 1) are uncorrelated: the
    /// sample correlation of their k-th draws stays within 4 standard errors of 0.
    #[test]
    fn neighbouring_streams_are_independent() {
        let n = 100_000u32;
        let correlation = |a: &dyn Fn(u32) -> KernelRng, b: &dyn Fn(u32) -> KernelRng| {
            let mut worst: f64 = 0.0;
            for draw in 0..4 {
                let (mut sxy, mut sx, mut sy, mut sxx, mut syy) = (0.0, 0.0, 0.0, 0.0, 0.0);
                for i in 0..n {
                    let (mut ra, mut rb) = (a(i), b(i));
                    for _ in 0..draw {
                        ra.next_u32();
                        rb.next_u32();
                    }
                    let (x, y) = (ra.next_f32() as f64, rb.next_f32() as f64);
                    sxy += x * y;
                    sx += x;
                    sy += y;
                    sxx += x * x;
                    syy += y * y;
                }
                let n = n as f64;
                let cov = sxy / n - sx / n * sy / n;
                let r = cov / ((sxx / n - (sx / n).powi(2)) * (syy / n - (sy / n).powi(2))).sqrt();
                worst = worst.max(r.abs());
            }
            worst
        };
        let limit = 4.0 / (n as f64).sqrt();
        let by_index = correlation(&|i| KernelRng::new(1, PHOTON_STREAM, 5, i), &|i| {
            KernelRng::new(1, PHOTON_STREAM, 5, i + 1)
        });
        assert!(by_index < limit, "index neighbours: r = {by_index}");
        let by_pass = correlation(&|i| KernelRng::new(1, EYE_STREAM, i, 9), &|i| {
            KernelRng::new(1, EYE_STREAM, i + 1, 9)
        });
        assert!(by_pass < limit, "pass neighbours: r = {by_pass}");
        let by_kernel = correlation(&|i| KernelRng::new(1, PHOTON_STREAM, 2, i), &|i| {
            KernelRng::new(1, EYE_STREAM, 2, i)
        });
        assert!(by_kernel < limit, "kernel salts: r = {by_kernel}");
    }
}
