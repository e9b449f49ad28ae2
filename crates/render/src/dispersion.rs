//! Dispersion in smooth solid glass (`scene::Material::dispersion`, glTF's
//! `KHR_materials_dispersion`) in a renderer that carries RGB. A path that carries the whole
//! spectrum (every path leaves its light or camera so) and meets dispersive glass keeps one
//! wavelength from there on, drawn uniformly from [`WAVELENGTH_LEVELS`] wavelengths between
//! [`SHORTEST`] and [`LONGEST`] nm ([`levels`]), and its throughput takes that level's weight:
//! the wavelength's colour over the density the levels are placed by, normalised so that the
//! weights average to one in each channel. A one-sample estimate of the integral over the
//! spectrum, unbiased for every RGB colour of light (a white light stays white through
//! dispersive glass). It refracts with its wavelength's index there and at every dispersive
//! glass after, so a path remembers its wavelength (a photon slot in its state word,
//! `crate::medium::pack_slot_state`; an eye path for its length).
//!
//! The levels lie where the light is (a weight of at most about 4 in any channel; three
//! channels at 611, 549 and 464 nm, as kousen had before, weigh 3) and, half of them, evenly
//! in 1/λ², in which the Cauchy index is linear: a prism's band is a rainbow of 126 images
//! with no gap wider than 1/60 of the band (levels even in λ leave 1/30 in the violet).
//!
//! The colour of a wavelength is the CIE 1931 observer's (Wyman, Sloan and Shirley 2013's
//! multi-lobe fit of its colour-matching functions) in linear sRGB, clamped at zero: spectral
//! colours lie outside sRGB's gamut, so one channel at least is zero; the photon hash keeps
//! such photons apart by their brightest channel (`crate::hash::photon_class`).

use std::sync::LazyLock;

use glam::{DVec3, Vec3};

/// How many wavelengths a path may keep: each is drawn with probability 1 / 126. Seven bits
/// in a photon slot's state word hold one (`crate::medium::pack_slot_state`), and a third of
/// them (42) is a band an eye path's stratified number falls in
/// (`crate::rng::pixel_wavelength`): 390–444 nm, 444–531 and 531–700 in turn.
pub const WAVELENGTH_LEVELS: u32 = 126;

/// The spectrum's ends (nanometres): below 390 and above 700 the eye sees under 0.1 % of its
/// peak.
pub const SHORTEST: f32 = 390.0;
pub const LONGEST: f32 = 700.0;

/// A path that carries the whole spectrum (it has met no dispersive glass).
pub const WHOLE_SPECTRUM: u32 = u32::MAX;

/// The level a number `u` in [0, 1) draws.
pub fn level_of(u: f32) -> u32 {
    ((u * WAVELENGTH_LEVELS as f32) as u32).min(WAVELENGTH_LEVELS - 1)
}

/// The index of glass of `ior` and `dispersion` at `lambda` nm: the Cauchy form of
/// `scene::Material::dispersion`, `ior + dispersion · (523655 / λ² − 1.5168)`.
pub fn wavelength_ior(ior: f32, dispersion: f32, lambda: f32) -> f32 {
    ior + dispersion * (523_655.0 / (lambda * lambda) - 1.5168)
}

/// One of the [`WAVELENGTH_LEVELS`] a path may keep.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Level {
    /// Nanometres.
    pub wavelength: f32,
    /// The weight a path's throughput takes where it keeps this wavelength.
    pub weight: Vec3,
}

/// The levels, shortest wavelength first. The GPU gets them as a prelude table.
pub fn levels() -> &'static [Level] {
    static LEVELS: LazyLock<Vec<Level>> = LazyLock::new(place_levels);
    &LEVELS
}

/// The wavelength (nanometres) of `level`.
pub fn level_wavelength(level: u32) -> f32 {
    levels()[level as usize].wavelength
}

/// The weight a path's throughput takes where it keeps `level`'s wavelength.
pub fn level_weight(level: u32) -> Vec3 {
    levels()[level as usize].weight
}

/// Places the levels at the quantiles of a density over wavelength that is half the light's
/// (the colours' sum, each channel's colour over the channel's integral: a weight of at most
/// 3 in any channel, as three channels would give) and half even in 1/λ² (where the Cauchy
/// index is linear, so that gaps between neighbouring levels stay narrow where the light is
/// faint). Each level's weight is its colour over the density, normalised so that the
/// levels' weights average to exactly one in each channel. In f64, on a 0.01 nm grid.
fn place_levels() -> Vec<Level> {
    let steps = 31_000;
    let (short, long) = (SHORTEST as f64, LONGEST as f64);
    let grid: Vec<f64> = (0..=steps)
        .map(|i| short + (long - short) * i as f64 / steps as f64)
        .collect();
    let step = (long - short) / steps as f64;
    let colours: Vec<DVec3> = grid.iter().map(|&l| spectral_rgb(l)).collect();
    let integral = |f: &dyn Fn(usize) -> f64| {
        (0..steps)
            .map(|i| 0.5 * (f(i) + f(i + 1)) * step)
            .sum::<f64>()
    };
    let channel_integrals = DVec3::from_array([0, 1, 2].map(|c| integral(&|i| colours[i][c])));
    let index_span = 1.0 / (short * short) - 1.0 / (long * long);
    let density = |lambda: f64, colour: DVec3| {
        let light = (colour / channel_integrals).element_sum() / 3.0;
        let even_in_index = 2.0 / (lambda * lambda * lambda) / index_span;
        0.5 * light + 0.5 * even_in_index
    };
    let densities: Vec<f64> = (0..=steps).map(|i| density(grid[i], colours[i])).collect();
    let mut cdf = vec![0.0; steps + 1];
    for i in 0..steps {
        cdf[i + 1] = cdf[i] + 0.5 * (densities[i] + densities[i + 1]) * step;
    }
    let total = cdf[steps];
    let wavelengths: Vec<f64> = (0..WAVELENGTH_LEVELS)
        .map(|level| {
            let target = (level as f64 + 0.5) / WAVELENGTH_LEVELS as f64 * total;
            let i = cdf.partition_point(|&c| c < target).clamp(1, steps);
            let t = (target - cdf[i - 1]) / (cdf[i] - cdf[i - 1]);
            grid[i - 1] + t * step
        })
        .collect();
    let raw: Vec<DVec3> = wavelengths
        .iter()
        .map(|&l| {
            let colour = spectral_rgb(l);
            colour / density(l, colour)
        })
        .collect();
    let mean = raw.iter().sum::<DVec3>() / WAVELENGTH_LEVELS as f64;
    wavelengths
        .iter()
        .zip(&raw)
        .map(|(&lambda, &weight)| Level {
            wavelength: lambda as f32,
            weight: (weight / mean).as_vec3(),
        })
        .collect()
}

/// One lobe of the colour-matching functions' fit: a Gaussian of mean `mean`, of width
/// `below` on its short side and `above` on its long side.
fn lobe(lambda: f64, mean: f64, below: f64, above: f64) -> f64 {
    let x = (lambda - mean) / if lambda < mean { below } else { above };
    (-0.5 * x * x).exp()
}

/// The colour of light of one wavelength, `lambda` nm: the CIE 1931 colour-matching functions
/// (Wyman, Sloan and Shirley 2013, their multi-lobe fit) in linear sRGB (D65), clamped at zero.
pub fn spectral_rgb(lambda: f64) -> DVec3 {
    let x = 1.056 * lobe(lambda, 599.8, 37.9, 31.0) + 0.362 * lobe(lambda, 442.0, 16.0, 26.7)
        - 0.065 * lobe(lambda, 501.1, 20.4, 26.2);
    let y = 0.821 * lobe(lambda, 568.8, 46.9, 40.5) + 0.286 * lobe(lambda, 530.9, 16.3, 31.1);
    let z = 1.217 * lobe(lambda, 437.0, 11.8, 36.0) + 0.681 * lobe(lambda, 459.0, 26.0, 13.8);
    let r = 3.240_454 * x - 1.537_139 * y - 0.498_531 * z;
    let g = -0.969_266 * x + 1.876_011 * y + 0.041_556 * z;
    let b = 0.055_643 * x - 0.204_026 * y + 1.057_225 * z;
    DVec3::new(r, g, b).max(DVec3::ZERO)
}

/// Dispersive glass as a path meets it: the index it refracts with, the wavelength it carries
/// from there on, and the weight its throughput takes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Dispersed {
    pub ior: f32,
    pub wavelength: u32,
    pub weight: Vec3,
}

/// Glass of `ior` and `dispersion` met by a path carrying `wavelength` (a level or
/// [`WHOLE_SPECTRUM`]), with `u` drawn where [`draws_wavelength`] says so (else unused):
/// `None` where the glass does not disperse. A path that carries one wavelength keeps it and
/// its weight stays.
pub fn disperse(ior: f32, dispersion: f32, wavelength: u32, u: f32) -> Option<Dispersed> {
    if dispersion <= 0.0 {
        return None;
    }
    let (wavelength, weight) = if wavelength == WHOLE_SPECTRUM {
        let level = level_of(u);
        (level, level_weight(level))
    } else {
        (wavelength, Vec3::ONE)
    };
    Some(Dispersed {
        ior: wavelength_ior(ior, dispersion, level_wavelength(wavelength)),
        wavelength,
        weight,
    })
}

/// Whether a path carrying `wavelength` that meets glass of `dispersion` draws a number to
/// choose its wavelength: the glass disperses and the path carries the whole spectrum.
pub fn draws_wavelength(dispersion: f32, wavelength: u32) -> bool {
    dispersion > 0.0 && wavelength == WHOLE_SPECTRUM
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Dense flint (n_d 1.717, V 29.5): the index falls with the wavelength by the amounts
    /// the Cauchy form gives (n_F − n_C = (n_d − 1) / V between 486 and 656 nm).
    #[test]
    fn blue_refracts_more_than_red() {
        let (ior, abbe) = (1.717, 29.5);
        let dispersion = scene::dispersion_from_abbe(ior, abbe);
        let at = |lambda: f32| wavelength_ior(ior, dispersion, lambda);
        let spread = at(486.13) - at(656.27);
        assert!((spread - (ior - 1.0) / abbe).abs() < 1e-4, "{spread}");
        assert!((at(587.56) - ior).abs() < 1e-4, "n_d at the d line");
        let indices: Vec<f32> = (0..WAVELENGTH_LEVELS)
            .map(|level| at(level_wavelength(level)))
            .collect();
        assert!(
            indices.windows(2).all(|w| w[1] < w[0]),
            "falls level by level"
        );
        assert_eq!(wavelength_ior(ior, 0.0, 450.0), ior);
    }

    /// The levels cover the spectrum, and a prism's band is continuous: neighbouring levels
    /// refract a ray through a 60° flint prism near minimum deviation less than 1/60 of the
    /// whole band apart where the light is (both levels over a quarter of the brightest's
    /// brightness), and less than 1/30 in the faint violet, where the deviation grows fastest
    /// with the index (levels even in λ: 1/54 and 1/30).
    #[test]
    fn the_band_is_continuous() {
        assert_eq!(level_of(0.0), 0);
        assert_eq!(level_of(0.999_999_9), WAVELENGTH_LEVELS - 1);
        assert_eq!(level_of(1.0 / 3.0), WAVELENGTH_LEVELS / 3);
        let (first, last) = (level_wavelength(0), level_wavelength(WAVELENGTH_LEVELS - 1));
        assert!(SHORTEST < first && first < SHORTEST + 2.0, "{first}");
        assert!(LONGEST - 8.0 < last && last < LONGEST, "{last}");
        let dispersion = scene::dispersion_from_abbe(1.717, 29.5);
        // A ray entering a 60° prism at 50° (about minimum deviation): deviation by level.
        let deviation = |level: u32| {
            let n = wavelength_ior(1.717, dispersion, level_wavelength(level)) as f64;
            let apex = 60f64.to_radians();
            let incidence = 50f64.to_radians();
            let inside = (incidence.sin() / n).asin();
            let exit = (n * (apex - inside).sin()).asin();
            incidence + exit - apex
        };
        let angles: Vec<f64> = (0..WAVELENGTH_LEVELS).map(deviation).collect();
        let band = angles[0] - angles[WAVELENGTH_LEVELS as usize - 1];
        assert!(band.to_degrees() > 2.0, "flint spreads the band {band}");
        // Each gap, and how bright the fainter of its two levels is (1: the brightest level).
        let brightness: Vec<f64> = (0..WAVELENGTH_LEVELS)
            .map(|level| spectral_rgb(level_wavelength(level) as f64).element_sum())
            .collect();
        let brightest = brightness.iter().copied().fold(0.0, f64::max);
        let gaps: Vec<(f64, f64)> = (1..WAVELENGTH_LEVELS as usize)
            .map(|i| {
                let gap = angles[i - 1] - angles[i];
                (gap, brightness[i - 1].min(brightness[i]) / brightest)
            })
            .collect();
        assert!(gaps.iter().all(|&(gap, _)| gap > 0.0));
        let widest = gaps.iter().map(|g| g.0).fold(0.0, f64::max);
        let widest_lit = gaps
            .iter()
            .filter(|g| g.1 > 0.25)
            .map(|g| g.0)
            .fold(0.0, f64::max);
        assert!(widest < band / 30.0, "{widest} of {band}");
        assert!(widest_lit < band / 60.0, "{widest_lit} of {band}");
    }

    /// The colours are the spectrum's: blue at 450 nm, green at 530, red at 640, yellow (red
    /// and green, no blue) at 570; every one has a zero channel; and the weights average to
    /// one in every channel, so white light stays white.
    #[test]
    fn the_weights_average_to_white() {
        let hue = |lambda: f64| {
            let c = spectral_rgb(lambda);
            c / c.max_element()
        };
        assert!(hue(450.0).z == 1.0 && hue(450.0).x < 0.2, "{}", hue(450.0));
        assert!(hue(530.0).y == 1.0 && hue(530.0).z < 0.2, "{}", hue(530.0));
        assert!(hue(640.0).x == 1.0 && hue(640.0).y < 0.2, "{}", hue(640.0));
        assert!(
            hue(570.0).z == 0.0 && hue(570.0).min_element() == 0.0 && hue(570.0).y > 0.9,
            "{}",
            hue(570.0)
        );
        let mean =
            (0..WAVELENGTH_LEVELS).map(level_weight).sum::<Vec3>() / WAVELENGTH_LEVELS as f32;
        assert!((mean - Vec3::ONE).abs().max_element() < 1e-5, "{mean}");
        for level in 0..WAVELENGTH_LEVELS {
            let weight = level_weight(level);
            assert_eq!(weight.min_element(), 0.0, "level {level}: {weight}");
            assert!(weight.max_element() < 4.5, "level {level}: {weight}");
        }
    }

    /// A path carrying the whole spectrum draws a wavelength; one carrying a wavelength keeps
    /// it, weight one; clear glass chooses nothing.
    #[test]
    fn a_wavelength_once_drawn_stays() {
        let dispersion = 0.02;
        assert!(draws_wavelength(dispersion, WHOLE_SPECTRUM));
        let drawn = disperse(1.5, dispersion, WHOLE_SPECTRUM, 0.9).unwrap();
        assert_eq!(drawn.wavelength, level_of(0.9));
        assert_eq!(drawn.weight, level_weight(level_of(0.9)));
        assert!(!draws_wavelength(dispersion, drawn.wavelength));
        let again = disperse(1.5, dispersion, drawn.wavelength, 0.1).unwrap();
        assert_eq!(
            (again.wavelength, again.weight),
            (drawn.wavelength, Vec3::ONE)
        );
        assert_eq!(again.ior, drawn.ior);
        assert_eq!(disperse(1.5, 0.0, WHOLE_SPECTRUM, 0.5), None);
        assert!(!draws_wavelength(0.0, WHOLE_SPECTRUM));
    }
}
