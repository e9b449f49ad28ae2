//! From statistics to radiance: L = direct / E + τ / (π R² N_emitted) per pixel, the last term
//! once for the indirect and once for the caustic photons.

use glam::Vec3;

use crate::Image;
use crate::buffers::{PixelStats, vec3};

pub fn resolve_pixel(stats: &PixelStats, eye_passes: u32, emitted_paths: u64) -> Vec3 {
    let direct = if eye_passes > 0 {
        vec3(stats.direct) / eye_passes as f32
    } else {
        Vec3::ZERO
    };
    let density = |tau: [f32; 3], radius: f32| {
        let area = std::f64::consts::PI * (radius as f64).powi(2);
        if emitted_paths > 0 && area > 0.0 {
            (vec3(tau).as_dvec3() / (area * emitted_paths as f64)).as_vec3()
        } else {
            Vec3::ZERO
        }
    };
    direct + density(stats.tau, stats.radius) + density(stats.caustic_tau, stats.caustic_radius)
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
            ..PixelStats::default()
        };
        // τ / (π·4·2) = 1; caustic τ / (π·1·2) = 1; direct / 3 = (1, 2, 3).
        let l = resolve_pixel(&stats, 3, 2);
        assert!(
            (l - Vec3::new(3.0, 4.0, 5.0)).abs().max_element() < 1e-5,
            "{l}"
        );
        assert_eq!(
            resolve_pixel(&PixelStats::initial(1.0, 0.5), 0, 0),
            Vec3::ZERO
        );
    }
}
