//! The share of a volume gather's sphere that lies inside its medium (`render::scattering`).
//! A volume visible point near the surface of its murky glass gathers in a sphere part of
//! which lies outside, where no volume photon can be: dividing what it finds by the whole
//! sphere's volume darkens the medium near its surfaces, most where the light there is
//! brightest (thick media, lit and seen through the same surface: a pixel's light comes from
//! within a mean free path of it). The estimate divides instead by the volume inside, the
//! boundary treated as the two planes the eye ray met last and meets next: the surface it
//! left (or none, from a camera inside) and the surface its flight would have reached, each at
//! the point's depth below it. A curved or cornered boundary is flatter here than it is, so
//! the correction is partial at edges; the planes' caps are simply added (they overlap only
//! where the sphere reaches past both, in a sliver thinner than its radius).
//!
//! The depths ride in the visible point's spare word (`buffers::VisiblePoint::pad`) as two
//! bfloat16 (an f32's upper half, truncated alike on both backends: 2⁻⁷ relative, plenty for a
//! share), the upper one's sign bit set to say they are there. The 16-byte f16 storage
//! (`half_storage`) has no such word: there the eye pass divides a volume point's weight by
//! the share at its pixel's radius as it stands then ([`share_in_weight`]).

use crate::buffers::VisiblePoint;

/// The smallest share a gather is divided by: where both planes cut deep (a sheet of murky
/// glass much thinner than the sphere) the estimate would otherwise multiply a few photons
/// many times.
pub const MIN_SHARE: f32 = 0.125;

/// The depth given for "no surface that way" (a camera inside the medium): far past any
/// radius. WGSL has no infinity literal, so both twins use the largest f32.
pub const NO_SURFACE: f32 = f32::MAX;

/// Marks a word that holds depths (a zero word holds none: surface points, f16 storage).
const DEPTHS_PRESENT: u32 = 0x8000_0000;

/// The visible point's word for depths `behind` and `ahead` (non-negative) below the planes
/// of the surface its eye ray left and of the one it would reach.
pub fn depths_word(behind: f32, ahead: f32) -> u32 {
    let bfloat = |depth: f32| depth.max(0.0).to_bits() >> 16;
    DEPTHS_PRESENT | (bfloat(behind) << 16) | bfloat(ahead)
}

/// The depths of [`depths_word`], or `None` for a word without them.
pub fn unpack_depths(word: u32) -> Option<(f32, f32)> {
    if word & DEPTHS_PRESENT == 0 {
        return None;
    }
    let behind = f32::from_bits((word & !DEPTHS_PRESENT) & 0xffff_0000);
    let ahead = f32::from_bits(word << 16);
    Some((behind, ahead))
}

/// The share of a sphere of `radius` on the inside of a plane its centre lies `depth` below
/// is 1 less this: the cap beyond the plane, h²(3R − h)/(4R³) with h = R − depth.
fn cap_share(depth: f32, radius: f32) -> f32 {
    let beyond = 1.0 - (depth / radius).min(1.0);
    beyond * beyond * (3.0 - beyond) * 0.25
}

/// The share of a sphere of `radius` around the visible point whose spare word is `word` that
/// lies inside its medium (1 where the word holds no depths), at least [`MIN_SHARE`].
pub fn share_inside(word: u32, radius: f32) -> f32 {
    match unpack_depths(word) {
        Some((behind, ahead)) if radius > 0.0 => {
            let outside = cap_share(behind, radius) + cap_share(ahead, radius);
            (1.0 - outside).max(MIN_SHARE)
        }
        _ => 1.0,
    }
}

/// `point` as the 16-byte f16 storage keeps it, which has no spare word for the depths: a
/// volume point's weight divided by the share inside at its pixel's volume radius `radius` as
/// the eye pass finds it, the depths dropped. The gathers until the next eye pass use radii a
/// little smaller (most in a render's first passes), whose shares are a little larger: the
/// f32 storage's division at each gather is exact.
pub fn share_in_weight(point: &VisiblePoint, radius: f32) -> VisiblePoint {
    let share = share_inside(point.pad, radius);
    VisiblePoint {
        weight: (crate::buffers::vec3(point.weight) / share).to_array(),
        pad: 0,
        ..*point
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn depths_survive_the_word_to_a_bfloat_step() {
        for (behind, ahead) in [(0.0, 0.0), (1.0, 2.5), (0.013, 700.0), (NO_SURFACE, 3.0)] {
            let (b, a) = unpack_depths(depths_word(behind, ahead)).expect("depths");
            assert!(
                b <= behind && b >= behind * (1.0 - 1.0 / 128.0),
                "{b} for {behind}"
            );
            assert!(
                a <= ahead && a >= ahead * (1.0 - 1.0 / 128.0),
                "{a} for {ahead}"
            );
        }
        assert_eq!(unpack_depths(0), None);
        assert_eq!(share_inside(0, 1.0), 1.0);
    }

    #[test]
    fn shares_are_the_sphere_volumes_inside_the_planes() {
        let share = |behind, ahead| share_inside(depths_word(behind, ahead), 2.0);
        // Deep inside: the whole sphere; centred on one plane: half of it.
        assert_eq!(share(NO_SURFACE, 2.0), 1.0);
        assert!((share(0.0, 5.0) - 0.5).abs() < 1e-6);
        // A slab two radii thick, the centre in its middle, is inside whole.
        assert_eq!(share(2.0, 2.0), 1.0);
        // The cap's volume against a Monte Carlo count over the ball (a plane at depth 0.5 R).
        let depth = 1.0;
        let mut inside = 0;
        let mut all = 0;
        let n = 60;
        for i in 0..n {
            for j in 0..n {
                for k in 0..n {
                    let p = |c: i32| (c as f32 + 0.5) / n as f32 * 4.0 - 2.0;
                    let (x, y, z) = (p(i), p(j), p(k));
                    if x * x + y * y + z * z < 4.0 {
                        all += 1;
                        inside += (z > -depth) as i32;
                    }
                }
            }
        }
        let counted = inside as f32 / all as f32;
        assert!(
            (share(depth, NO_SURFACE) - counted).abs() < 2e-3,
            "{counted}"
        );
        // Two planes cutting deep: held at the floor.
        assert_eq!(share(0.0, 0.0), MIN_SHARE);
    }
}
