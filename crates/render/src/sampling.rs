//! Random numbers (PCG32, for the CPU path tracer) and direction sampling.

use glam::Vec3;

/// PCG32 (O'Neill 2014): a 64-bit LCG state with a permuted 32-bit output. Each pixel gets
/// its own stream (the increment), so images do not depend on thread scheduling.
pub struct Rng {
    state: u64,
    increment: u64,
}

impl Rng {
    const MULTIPLIER: u64 = 6364136223846793005;

    pub fn new(seed: u64, stream: u64) -> Self {
        let mut rng = Rng {
            state: 0,
            increment: (stream << 1) | 1,
        };
        rng.next_u32();
        rng.state = rng.state.wrapping_add(seed);
        rng.next_u32();
        rng
    }

    pub fn next_u32(&mut self) -> u32 {
        let old = self.state;
        self.state = old
            .wrapping_mul(Self::MULTIPLIER)
            .wrapping_add(self.increment);
        let xorshifted = (((old >> 18) ^ old) >> 27) as u32;
        let rotation = (old >> 59) as u32;
        xorshifted.rotate_right(rotation)
    }

    /// Uniform in [0, 1): the top 24 bits, so the value is exact in f32 and never 1.
    pub fn next_f32(&mut self) -> f32 {
        (self.next_u32() >> 8) as f32 * (1.0 / (1u32 << 24) as f32)
    }
}

/// Cosine-weighted direction about +Z from two uniform numbers.
pub fn cosine_hemisphere(u1: f32, u2: f32) -> Vec3 {
    let r = u1.sqrt();
    let phi = std::f32::consts::TAU * u2;
    Vec3::new(r * phi.cos(), r * phi.sin(), (1.0 - u1).max(0.0).sqrt())
}

/// Uniform direction about +Z within the cone `z ≥ cos_max` from two uniform numbers
/// (`cos_max = −1`: the whole sphere).
pub fn uniform_cone(u1: f32, u2: f32, cos_max: f32) -> Vec3 {
    let z = 1.0 - u1 * (1.0 - cos_max);
    let r = (1.0 - z * z).max(0.0).sqrt();
    let phi = std::f32::consts::TAU * u2;
    Vec3::new(r * phi.cos(), r * phi.sin(), z)
}

/// Uniform point on the unit disk (as x, y) from two uniform numbers.
pub fn uniform_disk(u1: f32, u2: f32) -> glam::Vec2 {
    let r = u1.sqrt();
    let phi = std::f32::consts::TAU * u2;
    glam::Vec2::new(r * phi.cos(), r * phi.sin())
}

/// Uniform point on the unit disk (as x, y) from two uniform numbers by Shirley and Chiu's
/// concentric map (1997): squares about the centre go to rings, so evenly spread numbers
/// (a lens's low-discrepancy points, [`crate::rng::pixel_lens`]) stay evenly spread on the
/// disk, where the polar map crowds them at the centre.
pub fn concentric_disk(u1: f32, u2: f32) -> glam::Vec2 {
    let (a, b) = (2.0 * u1 - 1.0, 2.0 * u2 - 1.0);
    if a == 0.0 && b == 0.0 {
        return glam::Vec2::ZERO;
    }
    let quarter = std::f32::consts::FRAC_PI_4;
    let (r, phi) = if a.abs() > b.abs() {
        (a, quarter * (b / a))
    } else {
        (b, 2.0 * quarter - quarter * (a / b))
    };
    glam::Vec2::new(r * phi.cos(), r * phi.sin())
}

/// `local` (coordinates about +Z) turned to the frame of `n` (unit) built by
/// [`orthonormal_basis`].
pub fn about_axis(n: Vec3, local: Vec3) -> Vec3 {
    let (t, b) = orthonormal_basis(n);
    t * local.x + b * local.y + n * local.z
}

/// Two unit vectors completing `n` (unit) to an orthonormal basis, without branches on the
/// tangent's choice (Duff et al. 2017, "Building an orthonormal basis, revisited").
pub fn orthonormal_basis(n: Vec3) -> (Vec3, Vec3) {
    let sign = 1f32.copysign(n.z);
    let a = -1.0 / (sign + n.z);
    let b = n.x * n.y * a;
    (
        Vec3::new(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x),
        Vec3::new(b, sign + n.y * n.y * a, -n.y),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rng_is_uniform_in_unit_interval() {
        let mut rng = Rng::new(7, 3);
        let mut buckets = [0u32; 10];
        let n = 100_000;
        for _ in 0..n {
            let x = rng.next_f32();
            assert!((0.0..1.0).contains(&x));
            buckets[(x * 10.0) as usize] += 1;
        }
        // Chi-square with 9 degrees of freedom; 27.88 is the 0.999 quantile.
        let expected = n as f64 / 10.0;
        let chi2: f64 = buckets
            .iter()
            .map(|&c| (c as f64 - expected).powi(2) / expected)
            .sum();
        assert!(chi2 < 27.88, "chi2 = {chi2}");
    }

    #[test]
    fn neighbouring_streams_differ() {
        let a: Vec<u32> = (0..8)
            .map({
                let mut r = Rng::new(1, 0);
                move |_| r.next_u32()
            })
            .collect();
        let b: Vec<u32> = (0..8)
            .map({
                let mut r = Rng::new(1, 1);
                move |_| r.next_u32()
            })
            .collect();
        assert_ne!(a, b);
    }

    #[test]
    fn basis_is_orthonormal() {
        for n in [
            Vec3::Z,
            -Vec3::Z,
            Vec3::new(0.3, -0.5, 0.81).normalize(),
            Vec3::X,
        ] {
            let (t, b) = orthonormal_basis(n);
            for (x, y) in [(t, b), (t, n), (b, n)] {
                assert!(x.dot(y).abs() < 1e-5);
            }
            assert!((t.length() - 1.0).abs() < 1e-5 && (b.length() - 1.0).abs() < 1e-5);
        }
    }
}
