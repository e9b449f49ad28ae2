//! pbrt's spectra read in kousen's linear sRGB: `rgb` values as they are, `blackbody`
//! temperatures, wavelength–value pairs and the named spectra kousen knows (metals' and
//! glasses'), through the CIE 1931 observer.

use glam::Vec3;

/// The glasses pbrt-v4 names (`glass-X`): index at the helium d line (587.6 nm) and Abbe
/// number, from Schott's catalogue (N-BK7, N-BAF10, N-FK51A, N-LASF9, SF5, SF10, SF11).
pub(super) const GLASSES: [(&str, f32, f32); 7] = [
    ("bk7", 1.5168, 64.17),
    ("baf10", 1.6700, 47.11),
    ("fk51a", 1.4866, 84.47),
    ("lasf9", 1.8503, 32.17),
    ("f5", 1.6727, 32.21),
    ("f10", 1.7283, 28.41),
    ("f11", 1.7847, 25.68),
];

/// Wavelengths (nm) the observer is integrated over, and the step.
const LAMBDA_MIN: f64 = 360.0;
const LAMBDA_MAX: f64 = 830.0;
const LAMBDA_STEP: f64 = 1.0;

/// The CIE 1931 2° colour matching functions at `lambda` (nm), by the multi-lobe Gaussian
/// fit of Wyman, Sloan and Shirley, "Simple Analytic Approximations to the CIE XYZ Color
/// Matching Functions" (JCGT 2013).
fn observer(lambda: f64) -> [f64; 3] {
    let g = |mu: f64, below: f64, above: f64| {
        let sigma = if lambda < mu { below } else { above };
        let t = (lambda - mu) / sigma;
        (-0.5 * t * t).exp()
    };
    [
        1.056 * g(599.8, 37.9, 31.0) + 0.362 * g(442.0, 16.0, 26.7) - 0.065 * g(501.1, 20.4, 26.2),
        0.821 * g(568.8, 46.9, 40.5) + 0.286 * g(530.9, 16.3, 31.1),
        1.217 * g(437.0, 11.8, 36.0) + 0.681 * g(459.0, 26.0, 13.8),
    ]
}

/// CIE XYZ of a spectrum (unnormalised: the sum over the observer).
fn xyz(spectrum: impl Fn(f64) -> f64) -> [f64; 3] {
    let mut sum = [0.0; 3];
    let steps = ((LAMBDA_MAX - LAMBDA_MIN) / LAMBDA_STEP) as usize;
    for i in 0..=steps {
        let lambda = LAMBDA_MIN + i as f64 * LAMBDA_STEP;
        let s = spectrum(lambda);
        for (sum, cmf) in sum.iter_mut().zip(observer(lambda)) {
            *sum += s * cmf;
        }
    }
    sum
}

/// Linear sRGB (D65) of CIE XYZ.
fn srgb([x, y, z]: [f64; 3]) -> Vec3 {
    Vec3::new(
        (3.2404542 * x - 1.5371385 * y - 0.4985314 * z) as f32,
        (-0.9692660 * x + 1.8760108 * y + 0.0415560 * z) as f32,
        (0.0556434 * x - 0.2040259 * y + 1.0572252 * z) as f32,
    )
}

/// The linear sRGB reflectance of a reflectance spectrum: its colour under light of equal
/// energy, each channel divided by the equal-energy white's, so that a flat spectrum of 1 is
/// white (1, 1, 1); clamped to [0, 1].
pub(super) fn albedo(spectrum: impl Fn(f64) -> f64) -> Vec3 {
    let white = srgb(xyz(|_| 1.0));
    (srgb(xyz(spectrum)) / white).clamp(Vec3::ZERO, Vec3::ONE)
}

/// The linear sRGB colour of an emission spectrum scaled to a luminance (Y) of 1, as pbrt-v4
/// scales a light's spectrum before its `scale` (negative channels of colours outside sRGB
/// clamped).
pub(super) fn unit_luminance(spectrum: impl Fn(f64) -> f64) -> Vec3 {
    let c = xyz(spectrum);
    let y = c[1].max(f64::MIN_POSITIVE);
    srgb(c.map(|v| v / y)).max(Vec3::ZERO)
}

/// Planck's spectral radiance at `lambda` nm of a black body at `kelvin` (unnormalised).
pub(super) fn planck(lambda: f64, kelvin: f64) -> f64 {
    const C: f64 = 299_792_458.0;
    const H: f64 = 6.626_070_15e-34;
    const KB: f64 = 1.380_649e-23;
    let l = lambda * 1e-9;
    2.0 * H * C * C / (l.powi(5) * ((H * C / (l * KB * kelvin)).exp() - 1.0))
}

/// A black body's linear sRGB colour at a luminance of 1.
pub(super) fn blackbody(kelvin: f64) -> Vec3 {
    unit_luminance(|lambda| planck(lambda, kelvin))
}

/// pbrt-v3's black body of `kelvin` scaled to a peak of 1, as v3 normalised it: its luminance
/// is the mean of that over the observer's Y.
pub(super) fn blackbody_v3(kelvin: f64) -> Vec3 {
    // Wien's displacement law: the peak's wavelength.
    let peak = planck(2.897_771_955e6 / kelvin, kelvin);
    let c = xyz(|lambda| planck(lambda, kelvin) / peak);
    let y_of_white = xyz(|_| 1.0)[1];
    srgb(c.map(|v| v / y_of_white)).max(Vec3::ZERO)
}

/// A spectrum given as wavelength–value pairs (ascending), piecewise linear between them and
/// zero outside, as pbrt reads them.
pub(super) struct Piecewise(Vec<f64>);

impl Piecewise {
    /// `None` unless `pairs` are two pairs at least, of ascending wavelengths.
    pub fn new(pairs: Vec<f64>) -> Option<Piecewise> {
        if pairs.len() < 4 || !pairs.len().is_multiple_of(2) {
            return None;
        }
        let mut wavelengths = pairs.iter().step_by(2);
        let mut last = *wavelengths.next()?;
        for &lambda in wavelengths {
            if lambda <= last {
                return None;
            }
            last = lambda;
        }
        Some(Piecewise(pairs))
    }

    /// The value at `lambda` nm.
    pub fn at(&self, lambda: f64) -> f64 {
        let pairs = &self.0;
        let n = pairs.len() / 2;
        let point = |i: usize| (pairs[2 * i], pairs[2 * i + 1]);
        if lambda < point(0).0 || lambda > point(n - 1).0 {
            return 0.0;
        }
        let i = (1..n).find(|&i| point(i).0 >= lambda).unwrap_or(n - 1);
        let ((l0, v0), (l1, v1)) = (point(i - 1), point(i));
        v0 + (v1 - v0) * (lambda - l0) / (l1 - l0)
    }
}

/// A named metal's reflectance at normal incidence, from `metal-X-eta` or `metal-X-k`.
pub(super) fn named_metal(name: &str) -> Option<Vec3> {
    let lower = name.to_ascii_lowercase();
    let metal = lower.strip_prefix("metal-")?;
    let metal = metal
        .strip_suffix("-eta")
        .or_else(|| metal.strip_suffix("-k"))?;
    crate::material::metal_f0(metal)
}

/// A named glass's index and Abbe number, from `glass-X`.
pub(super) fn named_glass(name: &str) -> Option<(f32, f32)> {
    let lower = name.to_ascii_lowercase();
    let glass = lower.strip_prefix("glass-")?;
    let (_, ior, abbe) = GLASSES.iter().find(|(n, ..)| *n == glass)?;
    Some((*ior, *abbe))
}

/// The index at the d line and the Abbe number of an index spectrum (wavelength–index
/// pairs): (n_d − 1) / (n_F − n_C) at 587.6, 486.1 and 656.3 nm; no dispersion (Abbe
/// infinite) where the index does not fall with wavelength.
pub(super) fn index_and_abbe(index: impl Fn(f64) -> f64) -> (f32, f32) {
    let (d, f, c) = (index(587.6), index(486.1), index(656.3));
    let abbe = match f > c {
        true => (d - 1.0) / (f - c),
        false => f64::INFINITY,
    };
    (d as f32, abbe as f32)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn flat_spectra_are_white_and_grey() {
        let white = albedo(|_| 1.0);
        assert!((white - Vec3::ONE).abs().max_element() < 1e-5, "{white}");
        let grey = albedo(|_| 0.5);
        assert!(
            (grey - Vec3::splat(0.5)).abs().max_element() < 1e-5,
            "{grey}"
        );
        // A reflectance of long wavelengths only is red.
        let red = albedo(|l| if l > 600.0 { 1.0 } else { 0.0 });
        assert!(red.x > 0.5 && red.y < 0.2 && red.z < 0.05, "{red}");
    }

    #[test]
    fn the_observer_sees_light_as_the_cie_tables_say() {
        // The tables' ȳ peaks at 555 nm with 1.0; x̄ at 600 nm is 1.062, z̄ at 445 nm 1.78.
        let [_, y, _] = observer(555.0);
        assert!((y - 1.0).abs() < 0.03, "ȳ(555) = {y}");
        let [x, _, _] = observer(600.0);
        assert!((x - 1.062).abs() < 0.05, "x̄(600) = {x}");
        let [_, _, z] = observer(445.0);
        assert!((z - 1.78).abs() < 0.1, "z̄(445) = {z}");
    }

    #[test]
    fn black_bodies_warm_and_cool_with_temperature() {
        let warm = blackbody(2700.0);
        let daylight = blackbody(6504.0);
        let cool = blackbody(12000.0);
        assert!(warm.x > warm.z * 2.0, "{warm}");
        assert!(cool.z > cool.x, "{cool}");
        // Near D65's temperature a black body is nearly white.
        assert!(
            (daylight / daylight.max_element()).min_element() > 0.85,
            "{daylight}"
        );
        // Scaled to a luminance of 1 (sRGB's Y weights).
        for c in [warm, daylight, cool] {
            let y = 0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z;
            assert!((y - 1.0).abs() < 0.02, "luminance {y} of {c}");
        }
        let v3 = blackbody_v3(6504.0);
        assert!(v3.y < 1.0 && v3.y > 0.5, "{v3}");
    }

    #[test]
    fn piecewise_spectra_interpolate_and_stop_at_their_ends() {
        let s = Piecewise::new(vec![400.0, 0.0, 500.0, 1.0, 600.0, 0.5]).unwrap();
        assert_eq!(s.at(450.0), 0.5);
        assert_eq!(s.at(550.0), 0.75);
        assert_eq!(s.at(399.0), 0.0);
        assert_eq!(s.at(601.0), 0.0);
        assert!(Piecewise::new(vec![500.0, 1.0, 400.0, 1.0]).is_none());
        assert!(Piecewise::new(vec![500.0, 1.0, 400.0]).is_none());
    }

    #[test]
    fn names_and_index_spectra() {
        assert_eq!(
            named_metal("metal-Au-eta"),
            Some(Vec3::new(1.0, 0.782, 0.344))
        );
        assert_eq!(named_metal("metal-CuZn-k").map(|c| c.x), Some(0.910));
        assert_eq!(named_metal("metal-Xx-eta"), None);
        assert_eq!(named_glass("glass-BK7"), Some((1.5168, 64.17)));
        // Cauchy's n = 1.5 + 4000/λ² has n_d ≈ 1.5116, Abbe ≈ (0.5116)/(0.01693 − 0.00929).
        let (n, abbe) = index_and_abbe(|l| 1.5 + 4000.0 / (l * l));
        assert!((n - 1.51159).abs() < 1e-4, "{n}");
        assert!((abbe - 66.9).abs() < 0.5, "{abbe}");
        assert_eq!(index_and_abbe(|_| 1.33).1, f32::INFINITY);
    }
}
