//! Thin-film iridescence (glTF's `KHR_materials_iridescence`). A film of real index n2 and
//! thickness d lies on a base of real index n3 (one per colour channel) under air (n1 = 1).
//! Light reflected off the film's top interferes with light reflected, once or many times,
//! off the base; the sum of all those reflections is Airy's formula (Born & Wolf, *Principles
//! of Optics*, §7.6.1) with each interface's amplitude coefficients from Fresnel's equations,
//! taken for the s and p polarisations and averaged. For a single lossless film this is exact,
//! unlike approximations built on Schlick's Fresnel. The reflectance is summed over
//! [`FILM_WAVELENGTHS`] wavelengths, even in wavenumber, weighted by the CIE observer in linear
//! sRGB ([`film_spectrum`]).
//!
//! glTF's model is Belcour & Barla 2017 ("A practical extension to microfacet theory for the
//! modeling of varying iridescence"): the surface's reflectance becomes a mix, by the film's
//! factor, of its own and the film's. A metal's base index is the real index whose
//! normal-incidence reflectance is the metal's colour ([`ior_from_f0`],
//! `crate::conductor::Metal`);
//! glass's is its own, the film on its outside ([`iridescent_dielectric`]). The base is treated
//! as a real index throughout: a metal's phase change on reflection (its complex index) is not
//! modelled, as glTF's reference model does not model it either. The outside is taken as air
//! (index 1) wherever the surface lies.
//!
//! Where it is used: `cpu::surface::bounce_tint` (a bounce off metal takes the film's mix at
//! its micro-normal: `crate::conductor`; smooth glass chooses reflection by the film's mean reflectance and
//! weighs each channel by its share; frosted glass keeps its bare choice and weighs each way by
//! the film's share over the bare one at its micro-normal), plastic's coat
//! (`crate::dielectric_layer::DielectricLayer`: the coat's reflection the film's mix, chosen by its mean,
//! and the rest through it), the eye paths' light samples at rough
//! metal, frosted glass and plastic (`cpu::kernels::LitLobes::metal`,
//! `dielectric_film`), their WGSL twins and the path tracer. Lambertian surfaces do not read
//! a film.

use std::f32::consts::PI;
use std::sync::LazyLock;

use glam::{DVec3, Vec3, Vec4};

/// A film as a hit sees it: glTF's factor (after its texture), the film's index and thickness (nm).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Film {
    pub factor: f32,
    pub ior: f32,
    pub thickness: f32,
}

impl Film {
    pub fn is_some(&self) -> bool {
        self.factor > 0.0
    }

    /// glTF's film where its factor texture reads `factor_texel` and its thickness texture
    /// `thickness_texel` (`None`: no texture; `scene::Iridescence::at`).
    pub fn of(
        iridescence: &scene::Iridescence,
        factor_texel: Option<Vec4>,
        thickness_texel: Option<Vec4>,
    ) -> Film {
        let (factor, thickness) = iridescence.at(factor_texel, thickness_texel);
        Film {
            factor,
            ior: iridescence.ior,
            thickness,
        }
    }
}

/// How many wavelengths the film's reflectance is summed over.
pub const FILM_WAVELENGTHS: usize = 32;

/// The spectrum's ends (nm).
const SHORTEST: f64 = 380.0;
const LONGEST: f64 = 780.0;
/// The wavelengths lie at the centres of equal bins in wavenumber (1/λ, per nm) between the
/// ends: the film's phase is linear in the wavenumber, so the cosines of the phases at all of
/// them follow from three by Chebyshev's recurrence ([`film_reflectance`]). The first
/// (longest wavelength) and the step.
pub const FILM_WAVENUMBER_FIRST: f32 = (1.0 / LONGEST + 0.5 * FILM_WAVENUMBER_STEP_F64) as f32;
pub const FILM_WAVENUMBER_STEP: f32 = FILM_WAVENUMBER_STEP_F64 as f32;
const FILM_WAVENUMBER_STEP_F64: f64 = (1.0 / SHORTEST - 1.0 / LONGEST) / FILM_WAVELENGTHS as f64;

/// The wavelengths (nm, longest first) and their linear-sRGB weights, each channel's weights
/// summing to 1, so that a reflectance constant over the spectrum gives that constant in every
/// channel. Even in wavenumber k, a wavelength's weight is its colour times λ² (dλ = λ² dk).
pub fn film_spectrum() -> &'static [(f32, Vec3); FILM_WAVELENGTHS] {
    static SPECTRUM: LazyLock<[(f32, Vec3); FILM_WAVELENGTHS]> = LazyLock::new(build_spectrum);
    &SPECTRUM
}

fn build_spectrum() -> [(f32, Vec3); FILM_WAVELENGTHS] {
    let mut lambdas = [0.0f64; FILM_WAVELENGTHS];
    let mut colours = [DVec3::ZERO; FILM_WAVELENGTHS];
    let mut total = DVec3::ZERO;
    for i in 0..FILM_WAVELENGTHS {
        let wavenumber = 1.0 / LONGEST + (i as f64 + 0.5) * FILM_WAVENUMBER_STEP_F64;
        lambdas[i] = 1.0 / wavenumber;
        colours[i] = crate::dispersion::spectral_rgb(lambdas[i]) * lambdas[i] * lambdas[i];
        total += colours[i];
    }
    let mut spectrum = [(0.0f32, Vec3::ZERO); FILM_WAVELENGTHS];
    for i in 0..FILM_WAVELENGTHS {
        spectrum[i] = (lambdas[i] as f32, (colours[i] / total).as_vec3());
    }
    spectrum
}

/// The real index whose normal-incidence Fresnel reflectance from air is `f0` (each channel;
/// f0 clamped to [0, 0.9999] first): n = (1 + √f0) / (1 − √f0).
pub fn ior_from_f0(f0: Vec3) -> Vec3 {
    let s = f0.clamp(Vec3::ZERO, Vec3::splat(0.9999)).sqrt();
    (Vec3::ONE + s) / (Vec3::ONE - s)
}

/// Airy's reflectance of one polarisation from the two interfaces' amplitude coefficients and
/// the cosine of the phase difference: (r12² + r23² + 2 r12 r23 cos δ) / (1 + r12² r23² +
/// 2 r12 r23 cos δ). The numerator is written (r12 + r23)² − 2 r12 r23 (1 − cos δ), exactly
/// the Fresnel reflectance r13² of the bare base where δ = 0, and the denominator as the
/// numerator plus (1 − r12²)(1 − r23²) (what the film transmits), so that rounding cannot take
/// the result out of [0, 1].
fn airy(r12: f32, r23: f32, cos_delta: f32) -> f32 {
    let sum = r12 + r23;
    let reflected = (sum * sum - 2.0 * r12 * r23 * (1.0 - cos_delta)).max(0.0);
    let transmitted = (1.0 - r12 * r12) * (1.0 - r23 * r23);
    reflected / (reflected + transmitted)
}

/// The film's reflectance at one wavelength `lambda` (nm) for unpolarised light: the Airy sum
/// of the film's multiple reflections, each polarisation's amplitude coefficients from Fresnel's
/// equations at the two interfaces, the two polarisations' reflectances averaged. `cos_outside`
/// in (0, 1]. Where light cannot enter the film or the base (total internal reflection), 1.
pub fn film_reflectance_at(
    lambda: f32,
    cos_outside: f32,
    film_ior: f32,
    thickness: f32,
    base_ior: f32,
) -> f32 {
    let cos1 = cos_outside;
    let sin2_1 = 1.0 - cos1 * cos1;
    let cos2_film = 1.0 - sin2_1 / (film_ior * film_ior);
    let cos2_base = 1.0 - sin2_1 / (base_ior * base_ior);
    // At the critical angle itself the transmitted wave runs along the interface and the
    // reflectance is 1 too (and Airy's formula would be 0 / 0 there).
    if cos2_film <= 0.0 || cos2_base <= 0.0 {
        return 1.0;
    }
    let cos2 = cos2_film.sqrt();
    let cos3 = cos2_base.sqrt();
    let (n2, n3) = (film_ior, base_ior);
    let r12_s = (cos1 - n2 * cos2) / (cos1 + n2 * cos2);
    let r12_p = (n2 * cos1 - cos2) / (n2 * cos1 + cos2);
    let r23_s = (n2 * cos2 - n3 * cos3) / (n2 * cos2 + n3 * cos3);
    let r23_p = (n3 * cos2 - n2 * cos3) / (n3 * cos2 + n2 * cos3);
    let cos_delta = (4.0 * PI * n2 * thickness * cos2 / lambda).cos();
    0.5 * (airy(r12_s, r23_s, cos_delta) + airy(r12_p, r23_p, cos_delta))
}

/// The film's reflectance in linear sRGB: `film_reflectance_at` summed over `film_spectrum()`,
/// channel c using base index `base_ior[c]`; clamped to [0, 1].
///
/// Written to port line by line to WGSL: everything but the phase is the same at every
/// wavelength and is computed once, the base's coefficients for the three channels at once;
/// each wavelength takes one cosine.
pub fn film_reflectance(cos_outside: f32, film_ior: f32, thickness: f32, base_ior: Vec3) -> Vec3 {
    let cos1 = cos_outside.clamp(0.0, 1.0);
    let sin2_1 = 1.0 - cos1 * cos1;
    let cos2_film = 1.0 - sin2_1 / (film_ior * film_ior);
    if cos2_film <= 0.0 {
        return Vec3::ONE;
    }
    let cos2_base = Vec3::ONE - sin2_1 / (base_ior * base_ior);
    let base_blocked = cos2_base.cmple(Vec3::ZERO);
    let n2 = film_ior;
    let n3 = base_ior;
    let cos2 = cos2_film.sqrt();
    let cos3 = cos2_base.max(Vec3::ZERO).sqrt();

    // The top interface: the same for every channel.
    let r12_s = (cos1 - n2 * cos2) / (cos1 + n2 * cos2);
    let r12_p = (n2 * cos1 - cos2) / (n2 * cos1 + cos2);
    let t12_s = 1.0 - r12_s * r12_s;
    let t12_p = 1.0 - r12_p * r12_p;
    // The base: one per channel. A blocked channel's coefficients are 1 (its result is
    // replaced below); the small floor keeps 0 / 0 out of it.
    let film_s = Vec3::splat(n2 * cos2);
    let base_s = n3 * cos3;
    let r23_s = (film_s - base_s) / (film_s + base_s).max(Vec3::splat(1e-30));
    let film_p = n3 * cos2;
    let base_p = n2 * cos3;
    let r23_p = (film_p - base_p) / (film_p + base_p).max(Vec3::splat(1e-30));
    // Airy's formula as in `airy`, its parts independent of the phase taken out of the loop.
    let sum_s = r12_s + r23_s;
    let sum_p = r12_p + r23_p;
    let bare_s = sum_s * sum_s;
    let bare_p = sum_p * sum_p;
    let cross_s = 2.0 * r12_s * r23_s;
    let cross_p = 2.0 * r12_p * r23_p;
    let through_s = t12_s * (Vec3::ONE - r23_s * r23_s);
    let through_p = t12_p * (Vec3::ONE - r23_p * r23_p);

    // The phase at wavenumber k is phase·k; along the even steps of k its cosines follow
    // Chebyshev's recurrence cos(x + s) = 2 cos s · cos x − cos(x − s): three cosines, not 32.
    let phase = 4.0 * PI * n2 * thickness * cos2;
    let first = phase * FILM_WAVENUMBER_FIRST;
    let step = phase * FILM_WAVENUMBER_STEP;
    let twice_cos_step = 2.0 * step.cos();
    let mut before = (first - step).cos();
    let mut cos_delta = first.cos();
    let mut total = Vec3::ZERO;
    for &(_, weight) in film_spectrum() {
        let one_minus_cos = 1.0 - cos_delta;
        (before, cos_delta) = (cos_delta, twice_cos_step * cos_delta - before);
        let reflected_s = (bare_s - cross_s * one_minus_cos).max(Vec3::ZERO);
        let reflected_p = (bare_p - cross_p * one_minus_cos).max(Vec3::ZERO);
        let r_s = reflected_s / (reflected_s + through_s);
        let r_p = reflected_p / (reflected_p + through_p);
        total += weight * (0.5 * (r_s + r_p));
    }
    Vec3::select(base_blocked, Vec3::ONE, total).clamp(Vec3::ZERO, Vec3::ONE)
}

/// glTF's mix by `film.factor` of a dielectric's own reflectance `bare` (each channel) with
/// the film's on a base of index `ior`, seen at `cos_outside` (in [0, 1]) outside it.
pub fn film_mix(bare: Vec3, film: Film, cos_outside: f32, ior: f32) -> Vec3 {
    let film_colour = film_reflectance(cos_outside, film.ior, film.thickness, Vec3::splat(ior));
    bare.lerp(film_colour, film.factor.min(1.0))
}

/// The weight of a way chosen by the bare reflectance `bare` (reflected or not) where each
/// channel's share of it is the film's (`filmed`): that share over the choice's probability.
pub fn film_share(bare: f32, filmed: Vec3, reflected: bool) -> Vec3 {
    if reflected {
        if bare > 0.0 {
            filmed / bare
        } else {
            Vec3::ZERO
        }
    } else if bare < 1.0 {
        (Vec3::ONE - filmed) / (1.0 - bare)
    } else {
        Vec3::ZERO
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::optics::fresnel_dielectric;

    /// Normal-incidence reflectance between air and `n`.
    fn f0_of(n: f32) -> f32 {
        let r = (n - 1.0) / (n + 1.0);
        r * r
    }

    const COSINES: [f32; 7] = [1.0, 0.95, 0.8, 0.6, 0.4, 0.2, 0.05];

    #[test]
    fn zero_thickness_is_the_bare_base_fresnel() {
        for lambda in [400.0, 550.0, 700.0] {
            for cos in COSINES {
                let film = film_reflectance_at(lambda, cos, 1.3, 0.0, 1.5);
                // `fresnel_dielectric` takes eta = n_incident / n_transmitted: air into 1.5.
                let bare = fresnel_dielectric(cos, 1.0 / 1.5);
                assert!(
                    (film - bare).abs() < 1e-5,
                    "λ {lambda} cos {cos}: film {film} bare {bare}"
                );
            }
        }
        // And the spectral sum too, per channel.
        let film = film_reflectance(0.7, 1.8, 0.0, Vec3::new(1.2, 1.5, 2.4));
        for (c, n3) in [1.2f32, 1.5, 2.4].into_iter().enumerate() {
            let bare = fresnel_dielectric(0.7, 1.0 / n3);
            assert!(
                (film[c] - bare).abs() < 1e-5,
                "channel {c}: {film} vs {bare}"
            );
        }
    }

    #[test]
    fn quarter_wave_film_cancels_reflection() {
        let lambda = 550.0;
        for n3 in [1.5f32, 2.25, 3.0] {
            let n2 = n3.sqrt();
            let quarter = lambda / (4.0 * n2);
            let r = film_reflectance_at(lambda, 1.0, n2, quarter, n3);
            assert!(r < 1e-6, "base {n3}: quarter-wave reflectance {r}");
            // Off the design wavelength it reflects again.
            assert!(film_reflectance_at(400.0, 1.0, n2, quarter, n3) > 1e-4);
            // A half-wave film is absent at its wavelength.
            let half = film_reflectance_at(lambda, 1.0, n2, 2.0 * quarter, n3);
            assert!(
                (half - f0_of(n3)).abs() < 1e-5,
                "base {n3}: half-wave {half} vs bare {}",
                f0_of(n3)
            );
        }
    }

    #[test]
    fn reflectance_stays_within_energy_bounds() {
        let films = [1.0f32, 1.2, 1.33, 1.5, 1.8, 2.1, 2.5];
        let bases = [1.0f32, 1.1, 1.5, 2.0, 3.0, 4.0];
        let cosines = [1.0f32, 0.9, 0.7, 0.5, 0.3, 0.1, 0.01, 1e-4];
        for &n2 in &films {
            for &n3 in &bases {
                for &cos in &cosines {
                    for step in 0..=48 {
                        let d = step as f32 * 25.0;
                        for lambda in [380.0f32, 455.0, 550.0, 640.0, 780.0] {
                            let r = film_reflectance_at(lambda, cos, n2, d, n3);
                            assert!(
                                (0.0..=1.0).contains(&r),
                                "n2 {n2} n3 {n3} cos {cos} d {d} λ {lambda}: {r}"
                            );
                        }
                        let rgb = film_reflectance(cos, n2, d, Vec3::splat(n3));
                        assert!(rgb.cmpge(Vec3::ZERO).all() && rgb.cmple(Vec3::ONE).all());
                    }
                }
            }
        }
        // Grazing light is reflected whole, whatever the film (a base of index 1 would be no
        // interface at all, so the bases here are denser than air).
        for &n2 in &films {
            for n3 in [1.33f32, 1.5, 2.0, 3.0, 4.0] {
                for step in 0..=48 {
                    let d = step as f32 * 25.0;
                    let r = film_reflectance(1e-4, n2, d, Vec3::splat(n3));
                    assert!(r.min_element() > 0.99, "n2 {n2} n3 {n3} d {d}: {r}");
                }
            }
        }
    }

    #[test]
    fn spectrum_weights_are_normalised() {
        let spectrum = film_spectrum();
        let mut total = Vec3::ZERO;
        let mut previous = f32::INFINITY;
        for &(lambda, weight) in spectrum {
            assert!(weight.cmpge(Vec3::ZERO).all(), "{lambda}: {weight}");
            assert!((380.0..=780.0).contains(&lambda) && lambda < previous);
            previous = lambda;
            total += weight;
        }
        assert!((total - Vec3::ONE).abs().max_element() < 1e-6, "{total}");
        // Even in wavenumber, longest first: the first and last bins' centres.
        let step = (1.0 / 380.0 - 1.0 / 780.0) / FILM_WAVELENGTHS as f64;
        let first = 1.0 / (1.0 / 780.0 + step / 2.0);
        let last = 1.0 / (1.0 / 380.0 - step / 2.0);
        assert!(
            (spectrum[0].0 as f64 - first).abs() < 1e-3,
            "{}",
            spectrum[0].0
        );
        assert!((spectrum[FILM_WAVELENGTHS - 1].0 as f64 - last).abs() < 1e-3);
        for (i, &(lambda, _)) in spectrum.iter().enumerate() {
            let wavenumber = FILM_WAVENUMBER_FIRST + i as f32 * FILM_WAVENUMBER_STEP;
            assert!((lambda * wavenumber - 1.0).abs() < 1e-5, "{i}: {lambda}");
        }
    }

    #[test]
    fn ior_from_f0_inverts_normal_incidence_fresnel() {
        for n in [1.0f32, 1.2, 1.5, 2.0, 3.0, 5.0, 10.0] {
            let f0 = f0_of(n);
            let back = ior_from_f0(Vec3::new(f0, f0, f0));
            assert!(((back - n) / n).abs().max_element() < 1e-5, "{n}: {back}");
            assert!((f0_of(back.x) - f0).abs() < 1e-5);
        }
        // Clamped: a perfect mirror gives a finite index.
        assert!(ior_from_f0(Vec3::ONE).is_finite());
    }

    #[test]
    fn film_reflectance_is_the_weighted_sum_of_wavelengths() {
        let base = Vec3::new(1.4, 2.2, 0.8);
        for (cos, n2, d) in [(1.0, 1.3, 300.0), (0.5, 1.8, 520.0), (0.9, 1.1, 90.0)] {
            let rgb = film_reflectance(cos, n2, d, base);
            let mut sum = Vec3::ZERO;
            for &(lambda, weight) in film_spectrum() {
                let at = Vec3::new(
                    film_reflectance_at(lambda, cos, n2, d, base.x),
                    film_reflectance_at(lambda, cos, n2, d, base.y),
                    film_reflectance_at(lambda, cos, n2, d, base.z),
                );
                sum += weight * at;
            }
            assert!((rgb - sum).abs().max_element() < 1e-5, "{rgb} vs {sum}");
        }
        // A base of index 0.8 reflects everything past its critical angle (and only that
        // channel does).
        let rgb = film_reflectance(0.3, 1.3, 300.0, base);
        assert_eq!(rgb.z, 1.0);
        assert!(rgb.x < 0.5 && rgb.y < 0.5, "{rgb}");
    }

    #[test]
    fn a_thin_film_is_coloured_unless_index_matched() {
        // 1.3 on 1.5 reflects between (r12 − r23)² ≈ 0.0034 and (r12 + r23)² ≈ 0.040 at any
        // one wavelength, so the colour is measured against its own brightness. The two
        // reflections are out of phase where 2 n d = 780 nm is 1.5 wavelengths (520 nm) and
        // in phase at 780 and 390 nm: a magenta, green the darkest.
        let rgb = film_reflectance(1.0, 1.3, 300.0, Vec3::splat(1.5));
        let spread = rgb.max_element() - rgb.min_element();
        assert!(
            spread > 0.01 && spread > 0.5 * rgb.max_element(),
            "300 nm of 1.3 on 1.5 looks grey: {rgb}"
        );
        assert!(rgb.y < rgb.x && rgb.y < rgb.z, "not magenta: {rgb}");

        for cos in COSINES {
            let rgb = film_reflectance(cos, 1.5, 300.0, Vec3::splat(1.5));
            let bare = fresnel_dielectric(cos, 1.0 / 1.5);
            assert!(
                (rgb - Vec3::splat(bare)).abs().max_element() < 1e-5,
                "cos {cos}: {rgb} vs {bare}"
            );
        }
    }
}
