//! Denoising guides: each pixel's albedo and normal, the auxiliary images that denoisers such
//! as Intel Open Image Denoise take beside a noisy render to keep edges and textures sharp.
//!
//! They are read off the visible points the eye passes store (`crate::buffers::VisiblePoint`),
//! so they show what the render's own pixels gather at: the first surface that is not a
//! mirror or glass, seen through such chains with their tint (a red wall in a mirror has the
//! wall's albedo times the mirror's colour, the floor under water the floor's through the
//! water), with the eye passes' jitter, so that edges are filtered as the image's are.
//! A surface point's weight is throughput × albedo / π, so its albedo is π × weight; a point
//! inside murky glass has no surface: its weight (throughput × the medium's scattering
//! albedo) is its albedo and its normal is zero. Pixels whose eye paths end on no such point
//! (a lamp, the sky) add zero to both, which denoisers read as "no surface here".
//!
//! Means over the first [`GUIDE_EYE_PASSES`] eye passes (each read back from the device and
//! added up here): guides converge far faster than the image, and a long render need not
//! pay for a read-back every eye pass.

use glam::Vec3;

use crate::Image;
use crate::buffers::VisiblePoint;
use crate::packing::{is_volume, unpack_normal};

/// The eye passes whose visible points the guides average: 64 jittered samples a pixel
/// filter its edges about as well as the image's own first minute does.
pub const GUIDE_EYE_PASSES: u32 = 64;

/// Running sums of every pixel's albedo and normal over the eye passes added so far.
#[derive(Clone, Debug)]
pub struct Guides {
    width: u32,
    height: u32,
    albedo: Vec<Vec3>,
    normal: Vec<Vec3>,
    eye_passes: u32,
}

impl Guides {
    pub fn new(width: u32, height: u32) -> Guides {
        let pixels = width as usize * height as usize;
        Guides {
            width,
            height,
            albedo: vec![Vec3::ZERO; pixels],
            normal: vec![Vec3::ZERO; pixels],
            eye_passes: 0,
        }
    }

    /// Whether another eye pass should be added ([`GUIDE_EYE_PASSES`]).
    pub fn wants_more(&self) -> bool {
        self.eye_passes < GUIDE_EYE_PASSES
    }

    /// The eye passes added so far.
    pub fn eye_passes(&self) -> u32 {
        self.eye_passes
    }

    /// Adds one eye pass's visible points, one a pixel in the image's order.
    pub fn add(&mut self, points: &[VisiblePoint]) {
        assert_eq!(points.len(), self.albedo.len(), "one visible point a pixel");
        let sums = self.albedo.iter_mut().zip(&mut self.normal);
        for ((albedo, normal), point) in sums.zip(points) {
            if !point.is_valid() {
                continue;
            }
            let weight = Vec3::from_array(point.weight);
            if is_volume(point.normal) {
                *albedo += weight;
            } else {
                *albedo += std::f32::consts::PI * weight;
                *normal += unpack_normal(point.normal);
            }
        }
        self.eye_passes += 1;
    }

    /// Each pixel's mean albedo, within [0, 1] in each channel as denoisers expect (a
    /// plastic base's weight carries the coat's scale, which may lift a pass above 1).
    pub fn albedo(&self) -> Image {
        let mean = self.means(&self.albedo);
        let clamped = mean.into_iter().map(|a| a.clamp(Vec3::ZERO, Vec3::ONE));
        Image::new(self.width, self.height, clamped.collect())
    }

    /// Each pixel's mean shading normal in world space, on the side its eye paths came from:
    /// of unit length where every pass saw one flat surface, shorter at edges and where some
    /// passes saw none.
    pub fn normal(&self) -> Image {
        Image::new(self.width, self.height, self.means(&self.normal))
    }

    fn means(&self, sums: &[Vec3]) -> Vec<Vec3> {
        let passes = self.eye_passes.max(1) as f32;
        sums.iter().map(|s| *s / passes).collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::packing::{surface_normal, volume_point_direction};

    fn surface(weight: Vec3, normal: Vec3) -> VisiblePoint {
        VisiblePoint {
            position: [0.0; 3],
            normal: surface_normal(normal),
            weight: weight.to_array(),
            pad: 0,
        }
    }

    #[test]
    fn guides_average_albedo_and_normal_over_eye_passes() {
        let up = Vec3::Y;
        let tilted = Vec3::new(0.6, 0.8, 0.0);
        let grey = Vec3::splat(0.5 / std::f32::consts::PI);
        let murky = VisiblePoint {
            normal: volume_point_direction(Vec3::X, 0.3),
            ..surface(Vec3::new(0.2, 0.4, 0.8), up)
        };
        let mut guides = Guides::new(4, 1);
        guides.add(&[
            surface(grey, up),
            surface(grey, up),
            murky,
            surface(Vec3::splat(0.4), up),
        ]);
        guides.add(&[
            surface(grey * 0.5, tilted),
            VisiblePoint::default(),
            murky,
            surface(Vec3::splat(0.4), up),
        ]);
        assert_eq!(guides.eye_passes(), 2);
        let albedo = guides.albedo().pixels;
        let normal = guides.normal().pixels;
        assert!(
            albedo[0].abs_diff_eq(Vec3::splat(0.375), 1e-6),
            "{}",
            albedo[0]
        );
        assert!(
            normal[0].abs_diff_eq((up + tilted) / 2.0, 1e-4),
            "{}",
            normal[0]
        );
        // Half the passes saw nothing: half the albedo, half the normal.
        assert!(albedo[1].abs_diff_eq(Vec3::splat(0.25), 1e-6));
        assert!(normal[1].abs_diff_eq(up / 2.0, 1e-4));
        // A point in a medium: its weight is its albedo, and it has no normal.
        assert!(albedo[2].abs_diff_eq(Vec3::new(0.2, 0.4, 0.8), 1e-6));
        assert_eq!(normal[2], Vec3::ZERO);
        // π × 0.4 > 1: clamped.
        assert_eq!(albedo[3], Vec3::ONE);
    }

    #[test]
    fn guides_stop_wanting_passes_after_their_share() {
        let mut guides = Guides::new(1, 1);
        for _ in 0..GUIDE_EYE_PASSES {
            assert!(guides.wants_more());
            guides.add(&[VisiblePoint::default()]);
        }
        assert!(!guides.wants_more());
        assert_eq!(guides.albedo().pixels, [Vec3::ZERO]);
    }
}
