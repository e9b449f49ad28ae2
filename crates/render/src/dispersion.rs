//! Dispersion in smooth solid glass (`scene::Material::dispersion`, glTF's
//! `KHR_materials_dispersion`) in a renderer that carries RGB. Each colour channel stands for
//! one wavelength ([`CHANNEL_WAVELENGTHS`]) and refracts with its own index. Where a path that
//! carries more than one channel meets dispersive glass, it keeps one channel, chosen
//! uniformly, weighted by 3: a one-sample estimate of the three refracted paths, unbiased. A
//! path that carries one channel only refracts with that channel's index and draws nothing, so
//! a path needs no memory of its choice: its throughput says which channel it is.
//!
//! Three wavelengths, not a spectrum: a prism's band is three overlapping images, one per
//! channel, rather than a continuous rainbow.

use glam::Vec3;

/// The wavelength (nanometres) each RGB channel stands for: the dominant wavelengths of the
/// sRGB primaries.
pub const CHANNEL_WAVELENGTHS: [f32; 3] = [611.3, 549.1, 464.3];

/// The index of glass of `ior` and `dispersion` for `channel`: the Cauchy form of
/// `scene::Material::dispersion`, `ior + dispersion · (523655 / λ² − 1.5168)`.
pub fn channel_ior(ior: f32, dispersion: f32, channel: usize) -> f32 {
    let lambda = CHANNEL_WAVELENGTHS[channel];
    ior + dispersion * (523_655.0 / (lambda * lambda) - 1.5168)
}

/// The channel a path of `throughput` refracts with at glass of `dispersion` and the weight
/// its throughput takes, with `u` drawn where [`draws_channel`] says so (else unused):
/// `None` where the glass does not disperse.
pub fn dispersed_channel(dispersion: f32, throughput: Vec3, u: f32) -> Option<(usize, Vec3)> {
    if dispersion <= 0.0 {
        return None;
    }
    if let Some(channel) = single_channel(throughput) {
        return Some((channel, Vec3::ONE));
    }
    let channel = ((u * 3.0) as usize).min(2);
    let mut weight = Vec3::ZERO;
    weight[channel] = 3.0;
    Some((channel, weight))
}

/// Whether a path of `throughput` meeting glass of `dispersion` draws a number to choose its
/// channel: it disperses and the path carries more than one channel (or none).
pub fn draws_channel(dispersion: f32, throughput: Vec3) -> bool {
    dispersion > 0.0 && single_channel(throughput).is_none()
}

/// The one channel `throughput` carries, where the other two are zero.
pub fn single_channel(throughput: Vec3) -> Option<usize> {
    let carried = throughput.cmpgt(Vec3::ZERO).bitmask();
    match carried {
        0b001 => Some(0),
        0b010 => Some(1),
        0b100 => Some(2),
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Dense flint (n_d 1.717, V 29.5): blue bends more than green, green more than red, by
    /// the amounts the Cauchy form gives (n_F − n_C = (n_d − 1) / V between 486 and 656 nm).
    #[test]
    fn blue_refracts_more_than_red() {
        let (ior, abbe) = (1.717, 29.5);
        let dispersion = scene::dispersion_from_abbe(ior, abbe);
        let [r, g, b] = [0, 1, 2].map(|c| channel_ior(ior, dispersion, c));
        assert!(b > g && g > r, "{r} {g} {b}");
        let at = |lambda: f32| ior + dispersion * (523_655.0 / (lambda * lambda) - 1.5168);
        let spread = at(486.13) - at(656.27);
        assert!((spread - (ior - 1.0) / abbe).abs() < 1e-4, "{spread}");
        assert!((at(587.56) - ior).abs() < 1e-4, "n_d at the d line");
        assert_eq!(channel_ior(ior, 0.0, 2), ior);
    }

    /// The channel's weight averages to one in every channel: the choice is unbiased; a path
    /// of one channel keeps it and draws nothing; clear glass chooses nothing.
    #[test]
    fn the_choice_is_unbiased_and_a_single_channel_stays() {
        let white = Vec3::new(0.5, 0.7, 0.2);
        assert!(draws_channel(0.02, white));
        let n = 3000;
        let mean = (0..n)
            .map(|i| {
                dispersed_channel(0.02, white, (i as f32 + 0.5) / n as f32)
                    .unwrap()
                    .1
            })
            .sum::<Vec3>()
            / n as f32;
        assert!((mean - Vec3::ONE).abs().max_element() < 1e-3, "{mean}");
        let green = Vec3::new(0.0, 1.2, 0.0);
        assert!(!draws_channel(0.02, green));
        assert_eq!(dispersed_channel(0.02, green, 0.9), Some((1, Vec3::ONE)));
        assert_eq!(dispersed_channel(0.0, white, 0.5), None);
        assert!(!draws_channel(0.0, white));
    }
}
