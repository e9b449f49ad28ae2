//! Unit normals in one u32: octahedral mapping, two signed 16-bit normalised halves (WGSL's
//! `pack2x16snorm`, reproduced bit for bit).

use glam::{Vec2, Vec3};

pub fn pack_normal(n: Vec3) -> u32 {
    let o = octahedral(n);
    let snorm = |x: f32| ((x.clamp(-1.0, 1.0) * 32767.0).round() as i16) as u16 as u32;
    snorm(o.x) | (snorm(o.y) << 16)
}

/// A photon's packed normal with its class in the lowest bit (1: caustic), which moves the
/// normal by at most 1/32767 in its first octahedral coordinate. Caustic photons are those at
/// their first diffuse surface: light that came there straight or through specular surfaces
/// only (caustics, and direct light where photons carry it); the rest are indirect. The two
/// classes have their own gather radius and statistics per pixel.
pub fn photon_normal(n: Vec3, caustic: bool) -> u32 {
    (pack_normal(n) & !1) | caustic as u32
}

/// Whether a photon's packed normal ([`photon_normal`]) marks a caustic photon.
pub fn is_caustic(packed_normal: u32) -> bool {
    packed_normal & 1 != 0
}

pub fn unpack_normal(bits: u32) -> Vec3 {
    let snorm = |h: u32| ((h as u16 as i16) as f32 / 32767.0).max(-1.0);
    let o = Vec2::new(snorm(bits & 0xffff), snorm(bits >> 16));
    let z = 1.0 - o.x.abs() - o.y.abs();
    let (x, y) = if z < 0.0 {
        (fold(o.x, o.y), fold(o.y, o.x))
    } else {
        (o.x, o.y)
    };
    Vec3::new(x, y, z).normalize_or(Vec3::Z)
}

fn octahedral(n: Vec3) -> Vec2 {
    let p = Vec2::new(n.x, n.y) / (n.x.abs() + n.y.abs() + n.z.abs()).max(f32::MIN_POSITIVE);
    if n.z < 0.0 {
        Vec2::new(fold(p.x, p.y), fold(p.y, p.x))
    } else {
        p
    }
}

/// Reflects the lower hemisphere's octahedron faces outwards (and back).
fn fold(a: f32, b: f32) -> f32 {
    (1.0 - b.abs()) * if a >= 0.0 { 1.0 } else { -1.0 }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn normals_round_trip_closely() {
        let mut state = 1u32;
        for _ in 0..10_000 {
            let mut next = || {
                state = bvh::bench_rays::pcg_hash(state);
                state as f32 / u32::MAX as f32 * 2.0 - 1.0
            };
            let Some(n) = Vec3::new(next(), next(), next()).try_normalize() else {
                continue;
            };
            let back = unpack_normal(pack_normal(n));
            assert!(back.dot(n) > 0.9999, "{n} -> {back}");
        }
        for n in [Vec3::X, -Vec3::X, Vec3::Y, -Vec3::Y, Vec3::Z, -Vec3::Z] {
            assert!(unpack_normal(pack_normal(n)).dot(n) > 0.9999, "{n}");
        }
    }
}
