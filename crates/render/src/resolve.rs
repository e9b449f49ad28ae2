//! From statistics to radiance: L = direct / E + τ / (π R² N_emitted) per pixel, the last term
//! once for the indirect and once for the caustic photons, and τ / (4/3 π R³ N_emitted) for the
//! volume photons (`render::scattering`).

use glam::Vec3;

use crate::Image;
use crate::buffers::{PixelStats, vec3};

pub fn resolve_pixel(stats: &PixelStats, eye_passes: u32, emitted_paths: u64) -> Vec3 {
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
    direct
        + density(stats.tau, area(stats.radius))
        + density(stats.caustic_tau, area(stats.caustic_radius))
        + density(stats.volume_tau, volume)
}

pub fn resolve(
    pixels: &[PixelStats],
    width: u32,
    height: u32,
    eye_passes: u32,
    emitted_paths: u64,
) -> Image {
    let pixels = pixels
        .iter()
        .map(|s| resolve_pixel(s, eye_passes, emitted_paths))
        .collect();
    Image::new(width, height, pixels)
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
            caustic_tau: [std::f32::consts::PI * 2.0; 3],
            caustic_count: 1.0,
            caustic_radius: 1.0,
            volume_tau: [std::f32::consts::PI * 48.0; 3],
            volume_count: 2.0,
            volume_radius: 3.0,
            ..PixelStats::default()
        };
        // τ / (π·4·2) = 1; caustic τ / (π·1·2) = 1; volume τ / (4/3·π·27·2) = 2/3;
        // direct / 3 = (1, 2, 3).
        let l = resolve_pixel(&stats, 3, 2);
        assert!(
            (l - Vec3::new(11.0, 14.0, 17.0) / 3.0).abs().max_element() < 1e-5,
            "{l}"
        );
        assert_eq!(
            resolve_pixel(&PixelStats::initial(1.0, 0.5, 2.0), 0, 0),
            Vec3::ZERO
        );
    }
}
