//! Random-number generators for the kernels' streams, behind one trait so the photon kernel
//! can be run with each (issue 6, table 6), and a statistical [`battery`] to judge them.
//!
//! - [`Pcg`]: the renderer's generator (`render::rng::KernelRng`), PCG hashed stream starts;
//! - [`TalkFloat`]: the float-only generator of Hachisuka's talk (*Implementing a practical
//!   rendering system using GLSL*, 2015, slide "Random number generator", `GPURnd`);
//! - [`Tea`]: a crypto-hash generator, TEA reduced to 8 rounds (Zafar, Olano & Curtis 2010,
//!   *GPU random numbers via the tiny encryption algorithm*);
//! - [`FractSin`]: the `fract(sin(dot(...)) * 43758.5453)` noise function the talk warns
//!   against.
//!
//! Each has a WGSL twin in `crates/gpu/shaders/shared/random_<name>.wgsl` defining `Rng`,
//! `rng_start` and `next_f32` the same way.

pub mod battery;
pub mod fract_sin;
pub mod talk;
pub mod tea;

pub use crate::rng::KernelRng as Pcg;
pub use fract_sin::FractSin;
pub use talk::TalkFloat;
pub use tea::Tea;

/// One random stream per (seed, kernel salt, pass, element index), as the kernels use them.
pub trait StreamRng: Sized {
    /// Short name used in tables and file names.
    const NAME: &'static str;
    /// The stream of element `index` in pass `pass` of kernel `salt`.
    fn start(seed: u32, salt: u32, pass: u32, index: u32) -> Self;
    /// The next draw, uniform in [0, 1).
    fn next_f32(&mut self) -> f32;
}

/// The largest f32 below 1: where a float generator's `fract` rounds up to 1.0 it is clamped
/// here, so every generator stays in [0, 1).
pub const ONE_BELOW: f32 = 1.0 - 1.0 / 16_777_216.0;

impl StreamRng for Pcg {
    const NAME: &'static str = "pcg";

    fn start(seed: u32, salt: u32, pass: u32, index: u32) -> Self {
        Pcg::new(seed, salt, pass, index)
    }

    fn next_f32(&mut self) -> f32 {
        Pcg::next_f32(self)
    }
}
