//! A linear RGB image: what the integrator resolves to and what the writers take.

use glam::Vec3;

/// Linear RGB radiance, rows top to bottom.
#[derive(Clone, Debug, PartialEq)]
pub struct Image {
    pub width: u32,
    pub height: u32,
    pub pixels: Vec<Vec3>,
}

impl Image {
    pub fn new(width: u32, height: u32, pixels: Vec<Vec3>) -> Image {
        assert_eq!(pixels.len(), width as usize * height as usize);
        Image {
            width,
            height,
            pixels,
        }
    }

    /// Mean of every pixel (per channel).
    pub fn mean(&self) -> Vec3 {
        let sum: glam::DVec3 = self.pixels.iter().map(|p| p.as_dvec3()).sum();
        (sum / self.pixels.len().max(1) as f64).as_vec3()
    }
}
