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

/// Uniform point (as x, y) of a lens aperture of unit radius: the disk ([`concentric_disk`])
/// for `blades` 0, else the regular polygon of `blades` sides inscribed in the unit circle
/// with a vertex at angle `rotation`. `u1` picks the polygon's triangle about the centre
/// (equal areas) and, rescaled, the distance from the centre (its square root: uniform in
/// area), `u2` the point across it, so evenly spread numbers stay evenly spread.
pub fn aperture_point(u1: f32, u2: f32, blades: u32, rotation: f32) -> glam::Vec2 {
    if blades == 0 {
        return concentric_disk(u1, u2);
    }
    let scaled = u1 * blades as f32;
    let side = (scaled as u32).min(blades - 1);
    let along = (scaled - side as f32).clamp(0.0, 1.0);
    let step = std::f32::consts::TAU / blades as f32;
    let corner = |k: u32| {
        let angle = rotation + step * k as f32;
        glam::Vec2::new(angle.cos(), angle.sin())
    };
    let (a, b) = (corner(side), corner(side + 1));
    along.sqrt() * a.lerp(b, u2)
}

/// The mean of `f(u1, u2)` over the unit square by the midpoint rule on an `n`×`n` grid:
/// the quadrature the tables integrate their lobes with, over the numbers that draw them.
pub fn midpoint_grid_mean(n: u32, f: impl Fn(f32, f32) -> f64) -> f64 {
    let mut sum = 0.0f64;
    for i in 0..n {
        for j in 0..n {
            sum += f((i as f32 + 0.5) / n as f32, (j as f32 + 0.5) / n as f32);
        }
    }
    sum / (n * n) as f64
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

    /// A polygonal aperture's points fill the polygon evenly: all inside it, each of its
    /// triangles about the centre equally often, and the second moments of a uniform regular
    /// polygon of unit circumradius ((1 + 2cos²(π/N))/12 per axis, none across); the disk's
    /// (1/4) for 0 blades. The first vertex sits at the rotation.
    #[test]
    fn aperture_points_fill_their_shape() {
        // A grid of numbers whose rows split evenly among 3, 5, 6 and 9 triangles.
        let n = 360;
        for (blades, rotation) in [(0, 0.0), (3, 0.3), (5, -1.0), (6, 0.0), (9, 2.0)] {
            let want = if blades == 0 {
                0.25
            } else {
                let cos = (std::f64::consts::PI / blades as f64).cos();
                (1.0 + 2.0 * cos * cos) / 12.0
            };
            let (mut xx, mut yy, mut xy, mut farthest) = (0.0f64, 0.0f64, 0.0f64, glam::Vec2::ZERO);
            for i in 0..n {
                for j in 0..n {
                    let u = [(i as f32 + 0.5) / n as f32, (j as f32 + 0.5) / n as f32];
                    let p = aperture_point(u[0], u[1], blades, rotation);
                    assert!(p.length() <= 1.0 + 1e-6);
                    if blades > 0 {
                        // Inside every edge: no farther along an edge's normal than its apothem.
                        let step = std::f32::consts::TAU / blades as f32;
                        let apothem = (0.5 * step).cos();
                        for k in 0..blades {
                            let normal = rotation + step * (k as f32 + 0.5);
                            let along = p.dot(glam::Vec2::new(normal.cos(), normal.sin()));
                            assert!(
                                along <= apothem + 1e-5,
                                "{blades} blades: {p} past edge {k}"
                            );
                        }
                    }
                    xx += (p.x * p.x) as f64;
                    yy += (p.y * p.y) as f64;
                    xy += (p.x * p.y) as f64;
                    if p.length() > farthest.length() {
                        farthest = p;
                    }
                }
            }
            let count = (n * n) as f64;
            let (xx, yy, xy) = (xx / count, yy / count, xy / count);
            assert!(
                (xx / want - 1.0).abs() < 0.01 && (yy / want - 1.0).abs() < 0.01,
                "{blades}: {xx} {yy} against {want}"
            );
            assert!(xy.abs() < 0.002, "{blades}: {xy}");
            if blades > 0 {
                // The outermost point is (nearly) a vertex.
                let step = std::f32::consts::TAU / blades as f32;
                let angle = (farthest.y.atan2(farthest.x) - rotation).rem_euclid(step);
                assert!(angle.min(step - angle) < 0.05, "{blades}: {farthest}");
            }
        }
    }
}
