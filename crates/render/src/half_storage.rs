//! Photons and visible points stored in 16 bytes of f16 instead of 32 bytes of f32 (issue 6,
//! table 7; the talk: "16 bits is often enough"). Positions are stored relative to the scene's
//! centre (`SppmParams::storage_origin`), which halves their magnitude and so doubles their
//! f16 precision; fluxes are stored × `SppmParams::storage_flux_scale`, which keeps them in
//! [0, 1]; normals keep their 32-bit octahedral packing. WGSL packs with
//! `pack2x16float`, whose rounding the spec leaves to the implementation (either neighbour),
//! so the GPU and the CPU twin may differ by one f16 step.

use bytemuck::{Pod, Zeroable};
use glam::Vec3;
use half::f16;

use crate::buffers::{Photon, VisiblePoint, vec3};

/// How photons and visible points are stored.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Precision {
    /// 32-byte structs of f32 (kousen's default).
    #[default]
    F32,
    /// 16-byte structs of f16 ([`HalfPoint`]).
    F16,
}

impl Precision {
    pub fn name(self) -> &'static str {
        match self {
            Precision::F32 => "f32",
            Precision::F16 => "f16",
        }
    }

    /// Bytes of one stored photon or visible point: 32 of f32, or 16 of f16.
    pub fn point_bytes(self) -> u64 {
        match self {
            Precision::F32 => size_of::<Photon>() as u64,
            Precision::F16 => size_of::<HalfPoint>() as u64,
        }
    }
}

/// [`crate::buffers::SppmParams::storage_flux_scale`] for a light table.
pub fn flux_scale(lights: &[crate::buffers::Light]) -> f32 {
    let largest = lights.iter().flat_map(|l| l.flux).fold(0.0f32, f32::max);
    if largest > 0.0 { 1.0 / largest } else { 1.0 }
}

/// A photon or a visible point in f16 (16 bytes): position relative to the storage origin,
/// its normal (octahedral, as [`Photon::normal`]), and its flux or weight.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct HalfPoint {
    /// x and y (pack2x16float: x in the low half).
    pub xy: u32,
    /// z and the red flux.
    pub z_r: u32,
    /// green and blue flux.
    pub g_b: u32,
    pub normal: u32,
}

fn pack2(a: f32, b: f32) -> u32 {
    u32::from(f16::from_f32(a).to_bits()) | (u32::from(f16::from_f32(b).to_bits()) << 16)
}

fn unpack2(bits: u32) -> (f32, f32) {
    (
        f16::from_bits(bits as u16).to_f32(),
        f16::from_bits((bits >> 16) as u16).to_f32(),
    )
}

impl HalfPoint {
    pub fn pack(position: Vec3, normal: u32, value: Vec3, origin: Vec3) -> HalfPoint {
        let p = position - origin;
        HalfPoint {
            xy: pack2(p.x, p.y),
            z_r: pack2(p.z, value.x),
            g_b: pack2(value.y, value.z),
            normal,
        }
    }

    /// (position, normal, flux or weight).
    pub fn unpack(&self, origin: Vec3) -> (Vec3, u32, Vec3) {
        let (x, y) = unpack2(self.xy);
        let (z, r) = unpack2(self.z_r);
        let (g, b) = unpack2(self.g_b);
        (Vec3::new(x, y, z) + origin, self.normal, Vec3::new(r, g, b))
    }

    /// The photon it stores, its flux stored × `flux_scale`.
    pub fn to_photon(&self, origin: Vec3, flux_scale: f32) -> Photon {
        let (position, normal, flux) = self.unpack(origin);
        Photon {
            position: position.to_array(),
            normal,
            flux: (flux / flux_scale).to_array(),
            pad: 0,
        }
    }

    /// The visible point it stores.
    pub fn to_visible_point(&self, origin: Vec3) -> VisiblePoint {
        let (position, normal, weight) = self.unpack(origin);
        VisiblePoint {
            position: position.to_array(),
            normal,
            weight: weight.to_array(),
            pad: 0,
        }
    }
}

/// A photon as the f16 storage gives it back, its flux stored × `flux_scale` (an unstored
/// photon stays unstored).
pub fn round_photon(photon: &Photon, origin: Vec3, flux_scale: f32) -> Photon {
    if !photon.is_stored() {
        return Photon::default();
    }
    let flux = vec3(photon.flux) * flux_scale;
    HalfPoint::pack(vec3(photon.position), photon.normal, flux, origin)
        .to_photon(origin, flux_scale)
}

/// A visible point as the f16 storage gives it back.
pub fn round_visible_point(point: &VisiblePoint, origin: Vec3) -> VisiblePoint {
    if !point.is_valid() {
        return VisiblePoint::default();
    }
    let packed = HalfPoint::pack(
        vec3(point.position),
        point.normal,
        vec3(point.weight),
        origin,
    );
    packed.to_visible_point(origin)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn round_trip_keeps_eleven_bits() {
        let origin = Vec3::new(100.0, -3.0, 0.5);
        let photon = Photon {
            position: [101.234, -2.0, 0.75],
            normal: 0x1234_5678,
            flux: [0.3, 12.5, 1000.25],
            pad: 0,
        };
        let back = round_photon(&photon, origin, 1.0 / 1024.0);
        assert_eq!(back.normal, photon.normal);
        for k in 0..3 {
            let relative = |a: f32, b: f32, scale: f32| (a - b).abs() / scale;
            let offset = photon.position[k] - origin[k];
            assert!(relative(back.position[k], photon.position[k], offset.abs()) <= 1.0 / 2048.0);
            assert!(relative(back.flux[k], photon.flux[k], photon.flux[k]) <= 1.0 / 2048.0);
        }
        // Exactly representable values come back exactly.
        let exact = Photon {
            position: [100.5, -2.0, 1.0],
            normal: 7,
            flux: [0.25, 2.0, 1024.0],
            pad: 0,
        };
        assert_eq!(round_photon(&exact, origin, 0.5), exact);
        assert_eq!(
            round_photon(&Photon::default(), origin, 1.0),
            Photon::default()
        );
        assert_eq!(size_of::<HalfPoint>() * 2, size_of::<Photon>());
    }
}
