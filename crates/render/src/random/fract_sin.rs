//! The "noise function" the talk warns about: `fract(sin(dot(co, k)) · 43758.5453)`, a
//! hash of coordinates widely copied into shaders, here driven by (element index, pass, draw
//! counter). In f32 the product keeps only the 24 − 16 = 8 bits of the fraction that survive
//! the multiplication by 43758 when |sin| > 0.75, and `sin` of large arguments is where GPUs
//! approximate most, so its output is coarse and patterned.
//!
//! GPU `sin` is not correctly rounded (WGSL leaves its accuracy to the device), so this
//! generator's GPU draws are compared with these in distribution only, not draw by draw.

use super::{ONE_BELOW, StreamRng};

/// The noise function's constants, as it circulates.
pub const K: [f32; 3] = [12.9898, 78.233, 37.719];
/// Written as it circulates; f32 holds it as 43758.547.
#[allow(clippy::excessive_precision)]
pub const SCALE: f32 = 43758.5453;
/// Draw counters per pass: pass p's draws use coordinates [64p, 64p + 64).
pub const DRAWS_PER_PASS: u32 = 64;

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FractSin {
    /// (index, pass · 64 + counter, seed ^ salt reduced to 16 bits) as coordinates.
    pub index: u32,
    pub row: u32,
    pub key: u32,
}

impl StreamRng for FractSin {
    const NAME: &'static str = "fract_sin";

    fn start(seed: u32, salt: u32, pass: u32, index: u32) -> Self {
        FractSin {
            index,
            row: pass.wrapping_mul(DRAWS_PER_PASS),
            key: (seed ^ salt) & 0xffff,
        }
    }

    fn next_f32(&mut self) -> f32 {
        let d = self.index as f32 * K[0] + self.row as f32 * K[1] + self.key as f32 * K[2];
        self.row = self.row.wrapping_add(1);
        let x = d.sin() * SCALE;
        (x - x.floor()).min(ONE_BELOW)
    }
}
