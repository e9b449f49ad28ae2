//! Unit normals in one u32: octahedral mapping, two signed 16-bit normalised halves (WGSL's
//! `pack2x16snorm`, reproduced bit for bit).

use glam::{Vec2, Vec3};

pub fn pack_normal(n: Vec3) -> u32 {
    let o = octahedral(n);
    // WGSL's floor(0.5 + 32767·x), not Rust's round (away from zero at halves).
    let snorm = |x: f32| ((x.clamp(-1.0, 1.0) * 32767.0 + 0.5).floor() as i16) as u16 as u32;
    snorm(o.x) | (snorm(o.y) << 16)
}

/// A photon's packed normal with its class in the lowest bit (1: caustic), which moves the
/// normal by at most 1/32767 in its first octahedral coordinate, and [`VOLUME_BIT`] clear.
/// Caustic photons are those at their first diffuse surface: light that came there straight
/// or through specular surfaces only (caustics, and direct light where photons carry it); the
/// rest are indirect. The two classes have their own gather radius and statistics per pixel.
pub fn photon_normal(n: Vec3, caustic: bool) -> u32 {
    (surface_normal(n) & !1) | caustic as u32
}

/// Whether a photon's packed normal ([`photon_normal`]) marks a caustic photon.
pub fn is_caustic(packed_normal: u32) -> bool {
    packed_normal & 1 != 0
}

/// Set in the packed normal of a photon or visible point inside a scattering medium (the
/// second octahedral coordinate's lowest bit): its word holds a direction instead
/// ([`volume_photon_direction`], [`volume_point_direction`]). Clear on surfaces.
pub const VOLUME_BIT: u32 = 1 << 16;

/// A surface's normal packed with [`VOLUME_BIT`] clear (a visible point's, or a photon's
/// before its class).
pub fn surface_normal(n: Vec3) -> u32 {
    pack_normal(n) & !VOLUME_BIT
}

/// Whether a packed normal marks a volume photon or visible point ([`VOLUME_BIT`]).
pub fn is_volume(packed_normal: u32) -> bool {
    packed_normal & VOLUME_BIT != 0
}

/// A volume photon's word: the way it travelled when it scattered, with [`VOLUME_BIT`] set
/// (and no caustic class).
pub fn volume_photon_direction(direction: Vec3) -> u32 {
    (pack_normal(direction) & !1) | VOLUME_BIT
}

/// The bits of a volume visible point's word that hold its medium's phase asymmetry: the
/// five lowest of each octahedral coordinate but [`VOLUME_BIT`] (nine bits).
const ANISOTROPY_BITS: u32 = 0x001e_001f;

/// A volume visible point's word: the way its eye path travelled, each octahedral coordinate
/// to 11 bits (at most 0.2° off), and its medium's Henyey–Greenstein asymmetry `g` in
/// (−1, 1) to 9 bits (steps of 2/511), which the gather needs for the phase function and a
/// visible point has no other room for (16-byte f16 storage included).
pub fn volume_point_direction(direction: Vec3, g: f32) -> u32 {
    let level = (((g.clamp(-1.0, 1.0) + 1.0) * 0.5 * 511.0).round()) as u32;
    let bits = (level & 0x1f) | ((level >> 5) << 17);
    (pack_normal(direction) & !(ANISOTROPY_BITS | VOLUME_BIT)) | bits | VOLUME_BIT
}

/// A volume visible point's direction and asymmetry ([`volume_point_direction`]).
pub fn unpack_volume_point(word: u32) -> (Vec3, f32) {
    let level = (word & 0x1f) | (((word >> 17) & 0xf) << 5);
    let g = level as f32 / 511.0 * 2.0 - 1.0;
    (unpack_normal(word & !(ANISOTROPY_BITS | VOLUME_BIT)), g)
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
            let g = next() * 0.99;
            let word = volume_point_direction(n, g);
            assert!(is_volume(word) && !is_volume(surface_normal(n)));
            let (back, g_back) = unpack_volume_point(word);
            assert!(back.dot(n) > 0.99999, "{n} -> {back}");
            assert!((g - g_back).abs() <= 1.0 / 511.0 + 1e-6, "{g} -> {g_back}");
            let photon = volume_photon_direction(n);
            assert!(is_volume(photon) && !is_caustic(photon));
            assert!(unpack_normal(photon).dot(n) > 0.9999);
            assert!(!is_volume(photon_normal(n, true)) && is_caustic(photon_normal(n, true)));
        }
        for n in [Vec3::X, -Vec3::X, Vec3::Y, -Vec3::Y, Vec3::Z, -Vec3::Z] {
            assert!(unpack_normal(pack_normal(n)).dot(n) > 0.9999, "{n}");
        }
    }
}
