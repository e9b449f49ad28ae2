//! From statistics to radiance: L = direct / E + τ / (π R² N_emitted) per pixel, the last term
//! once for the indirect and once for the caustic photons, and τ / (4/3 π R³ N_emitted) for the
//! volume photons (`render::scattering`).

use glam::Vec3;

use crate::Image;
use crate::buffers::{PixelStats, vec3};

/// The parts of a pixel's radiance, in the order [`resolve_components`] gives them: what the
/// eye paths saw directly (emission through specular chains, light samples), the indirect
/// and caustic photons' estimates on surfaces, and the volume photons' in murky glass.
pub const COMPONENTS: [&str; 4] = ["direct", "indirect", "caustic", "volume"];

/// Which parts of the radiance ([`COMPONENTS`]) an image shows: bit k for part k (the
/// viewer's selector; the display shader reads the same bits).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Parts(u32);

impl Parts {
    pub const ALL: Parts = Parts((1 << COMPONENTS.len()) - 1);

    /// Whether part `part` (an index into [`COMPONENTS`]) is shown.
    pub fn shows(self, part: usize) -> bool {
        self.0 & (1 << part) != 0
    }

    /// These parts with part `part` shown or hidden.
    pub fn with(self, part: usize, shown: bool) -> Parts {
        if shown {
            Parts(self.0 | (1 << part))
        } else {
            Parts(self.0 & !(1 << part))
        }
    }

    /// The bits, as the display shader's uniform holds them.
    pub fn bits(self) -> u32 {
        self.0
    }

    /// The names of the parts shown, joined by `+` ("direct+caustic"), or "all".
    pub fn name(self) -> String {
        if self == Parts::ALL {
            return "all".to_owned();
        }
        let shown: Vec<&str> = (COMPONENTS.iter().enumerate())
            .filter(|&(k, _)| self.shows(k))
            .map(|(_, name)| *name)
            .collect();
        if shown.is_empty() {
            "none".to_owned()
        } else {
            shown.join("+")
        }
    }
}

impl Default for Parts {
    fn default() -> Parts {
        Parts::ALL
    }
}

/// A pixel's radiance: its [`resolve_components`] summed.
pub fn resolve_pixel(stats: &PixelStats, eye_passes: u32, emitted_paths: u64) -> Vec3 {
    resolve_parts(stats, eye_passes, emitted_paths, Parts::ALL)
}

/// A pixel's radiance in the parts `parts` shows, summed in [`COMPONENTS`]' order (a hidden
/// part adds 0, so all shown is [`resolve_pixel`] bit for bit).
pub fn resolve_parts(
    stats: &PixelStats,
    eye_passes: u32,
    emitted_paths: u64,
    parts: Parts,
) -> Vec3 {
    let components = resolve_components(stats, eye_passes, emitted_paths);
    let part = |k: usize| {
        if parts.shows(k) {
            components[k]
        } else {
            Vec3::ZERO
        }
    };
    part(0) + part(1) + part(2) + part(3)
}

/// A pixel's radiance by part, as [`COMPONENTS`] names them.
pub fn resolve_components(stats: &PixelStats, eye_passes: u32, emitted_paths: u64) -> [Vec3; 4] {
    let direct = if eye_passes > 0 {
        vec3(stats.direct) / eye_passes as f32
    } else {
        Vec3::ZERO
    };
    let density = |tau: [f32; 3], measure: f64| {
        if emitted_paths > 0 && measure > 0.0 {
            (vec3(tau).as_dvec3() / (measure * emitted_paths as f64)).as_vec3()
        } else {
            Vec3::ZERO
        }
    };
    let area = |radius: f32| std::f64::consts::PI * (radius as f64).powi(2);
    let volume = 4.0 / 3.0 * std::f64::consts::PI * (stats.volume_radius as f64).powi(3);
    [
        direct,
        density(stats.tau, area(stats.radius)),
        density(stats.caustic_tau, area(stats.caustic_radius)),
        density(stats.volume_tau, volume),
    ]
}

pub fn resolve(
    pixels: &[PixelStats],
    width: u32,
    height: u32,
    eye_passes: u32,
    emitted_paths: u64,
) -> Image {
    resolve_shown(
        pixels,
        (width, height),
        eye_passes,
        emitted_paths,
        Parts::ALL,
    )
}

/// The image of the parts `parts` shows ([`resolve_parts`] at every pixel).
pub fn resolve_shown(
    pixels: &[PixelStats],
    (width, height): (u32, u32),
    eye_passes: u32,
    emitted_paths: u64,
    parts: Parts,
) -> Image {
    let pixels = pixels
        .iter()
        .map(|s| resolve_parts(s, eye_passes, emitted_paths, parts))
        .collect();
    Image::new(width, height, pixels)
}

/// One image per part of the radiance ([`COMPONENTS`]); they sum to [`resolve`]'s.
pub fn resolve_component_images(
    pixels: &[PixelStats],
    width: u32,
    height: u32,
    eye_passes: u32,
    emitted_paths: u64,
) -> [Image; 4] {
    let parts: Vec<[Vec3; 4]> = pixels
        .iter()
        .map(|s| resolve_components(s, eye_passes, emitted_paths))
        .collect();
    std::array::from_fn(|k| Image::new(width, height, parts.iter().map(|p| p[k]).collect()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn resolve_combines_direct_and_density() {
        let stats = PixelStats {
            tau: [std::f32::consts::PI * 8.0; 3],
            photon_count: 10.0,
            direct: [3.0, 6.0, 9.0],
            radius: 2.0,
            caustic_tau: [std::f32::consts::PI * 4.0; 3],
            caustic_count: 1.0,
            caustic_radius: 1.0,
            volume_tau: [std::f32::consts::PI * 48.0; 3],
            volume_count: 2.0,
            volume_radius: 3.0,
            ..PixelStats::default()
        };
        // τ / (π·4·2) = 1; caustic τ / (π·1·2) = 2; volume τ / (4/3·π·27·2) = 2/3;
        // direct / 3 = (1, 2, 3).
        let l = resolve_pixel(&stats, 3, 2);
        assert!(
            (l - Vec3::new(14.0, 17.0, 20.0) / 3.0).abs().max_element() < 1e-5,
            "{l}"
        );
        let parts = resolve_components(&stats, 3, 2);
        let expected = [
            Vec3::new(1.0, 2.0, 3.0),
            Vec3::ONE,
            Vec3::splat(2.0),
            Vec3::splat(2.0 / 3.0),
        ];
        for (name, (part, expected)) in COMPONENTS.iter().zip(parts.iter().zip(expected)) {
            assert!(
                (*part - expected).abs().max_element() < 1e-5,
                "{name}: {part}"
            );
        }
        // The images by part sum to the image, bit for bit (the same additions in order).
        let pixels = [stats, PixelStats::initial(1.0, 0.5, 2.0)];
        let image = resolve(&pixels, 2, 1, 3, 2);
        let [a, b, c, d] = resolve_component_images(&pixels, 2, 1, 3, 2);
        for i in 0..2 {
            let sum = a.pixels[i] + b.pixels[i] + c.pixels[i] + d.pixels[i];
            assert_eq!(sum, image.pixels[i]);
        }
        assert_eq!(
            resolve_pixel(&PixelStats::initial(1.0, 0.5, 2.0), 0, 0),
            Vec3::ZERO
        );
    }

    /// Each part alone is that part; the parts a selection shows add up; none shows black.
    #[test]
    fn a_selection_of_parts_resolves_what_it_shows() {
        let stats = PixelStats {
            tau: [2.0, 3.0, 4.0],
            photon_count: 3.0,
            direct: [1.0, 0.5, 0.25],
            radius: 0.1,
            caustic_tau: [0.5; 3],
            caustic_radius: 0.05,
            volume_tau: [0.1, 0.2, 0.3],
            volume_radius: 0.2,
            ..PixelStats::default()
        };
        let components = resolve_components(&stats, 4, 1000);
        let none = (0..4).fold(Parts::ALL, |parts, k| parts.with(k, false));
        assert_eq!(resolve_parts(&stats, 4, 1000, none), Vec3::ZERO);
        assert_eq!(none.name(), "none");
        for (k, component) in components.iter().enumerate() {
            let alone = none.with(k, true);
            assert_eq!(resolve_parts(&stats, 4, 1000, alone), *component);
            assert_eq!(alone.name(), COMPONENTS[k]);
            assert!(component.max_element() > 0.0, "{}", COMPONENTS[k]);
        }
        let direct_and_caustic = none.with(0, true).with(2, true);
        assert_eq!(direct_and_caustic.name(), "direct+caustic");
        assert_eq!(
            resolve_parts(&stats, 4, 1000, direct_and_caustic),
            components[0] + components[2]
        );
        assert_eq!(Parts::ALL.name(), "all");
        assert_eq!(Parts::default(), Parts::ALL);
        let all = resolve_shown(&[stats], (1, 1), 4, 1000, Parts::ALL);
        assert_eq!(all.pixels[0], resolve_pixel(&stats, 4, 1000));
    }
}
