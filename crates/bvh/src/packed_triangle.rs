//! Triangles as the talk packs them: two vec4 per vertex, the material folded into the
//! normal's z sign.
//!
//! ```text
//! vec4 0: position.x  position.y  position.z                     u
//! vec4 1: normal.x    normal.y    sign(normal.z)·(material + 1)  v
//! ```
//! The normal is unit length, so `|normal.z| = sqrt(max(0, 1 − x² − y²))`; its sign rides on
//! the material (shifted by one so that material 0 keeps a sign). Positions and texture
//! coordinates come back exactly; the rebuilt z loses precision where it is near 0 (about
//! `sqrt(f32::EPSILON)` ≈ 3.5e-4 absolute in the worst case).

use std::mem::size_of;

use bytemuck::{Pod, Zeroable};
use glam::{Vec2, Vec3};
use scene::{Triangle, Vertex};

/// One vertex, two 16-byte rows (32 bytes).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct PackedVertex {
    /// World-space position.
    pub position: [f32; 3],
    /// Texture coordinate u.
    pub u: f32,
    /// x and y of the unit shading normal.
    pub normal_xy: [f32; 2],
    /// `sign(normal.z) · (material + 1)`, the sign positive when `normal.z ≥ 0` (+0 and −0
    /// both). Material indices below 2²⁴ − 1 are exact in an f32.
    pub signed_material: f32,
    /// Texture coordinate v.
    pub v: f32,
}

const _: () = assert!(size_of::<PackedVertex>() == 32);

/// A triangle's three vertices (96 bytes); the material is stored in each of them, as in the talk.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct PackedTriangle {
    /// The vertices in the scene's (counter-clockwise front face) order.
    pub vertices: [PackedVertex; 3],
}

const _: () = assert!(size_of::<PackedTriangle>() == 96);

impl PackedTriangle {
    /// First material index that does not fit (`material + 1` must be an exact f32 integer).
    pub const MAX_MATERIAL: u32 = (1 << 24) - 1;

    /// Packs a triangle.
    ///
    /// # Panics
    /// If `triangle.material ≥` [`PackedTriangle::MAX_MATERIAL`].
    pub fn pack(triangle: &Triangle) -> PackedTriangle {
        let material = triangle.material;
        assert!(
            material < Self::MAX_MATERIAL,
            "material index {material} does not fit a packed triangle"
        );
        let magnitude = (material + 1) as f32;
        PackedTriangle {
            vertices: triangle.vertices.map(|v| PackedVertex {
                position: v.position.to_array(),
                u: v.uv.x,
                normal_xy: [v.normal.x, v.normal.y],
                signed_material: if v.normal.z < 0.0 {
                    -magnitude
                } else {
                    magnitude
                },
                v: v.uv.y,
            }),
        }
    }

    /// The three positions.
    #[inline]
    pub fn positions(&self) -> [Vec3; 3] {
        self.vertices.map(|v| Vec3::from_array(v.position))
    }

    /// The material index.
    pub fn material(&self) -> u32 {
        self.vertices[0].signed_material.abs() as u32 - 1
    }

    /// Positions, normals (z rebuilt), texture coordinates and material (no tangents: they
    /// are not packed).
    pub fn unpack(&self) -> Triangle {
        Triangle {
            vertices: self.vertices.map(|v| {
                let [x, y] = v.normal_xy;
                let z = (1.0 - x * x - y * y).max(0.0).sqrt();
                Vertex {
                    position: Vec3::from_array(v.position),
                    normal: Vec3::new(x, y, z.copysign(v.signed_material)),
                    uv: Vec2::new(v.u, v.v),
                    ..Vertex::default()
                }
            }),
            material: self.material(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pack_roundtrips_positions_uvs_material_and_normals() {
        for (k, triangle) in crate::testing::random_soup(11, 500).iter().enumerate() {
            let mut triangle = *triangle;
            triangle.material = [0, 1, 7, 65_535, PackedTriangle::MAX_MATERIAL - 1][k % 5];
            let back = PackedTriangle::pack(&triangle).unpack();
            assert_eq!(back.material, triangle.material);
            for (a, b) in back.vertices.iter().zip(&triangle.vertices) {
                assert_eq!(a.position, b.position);
                assert_eq!(a.uv, b.uv);
                assert!(
                    a.normal.distance(b.normal) < 1e-3,
                    "{} vs {}",
                    a.normal,
                    b.normal
                );
                assert_eq!(a.normal.z < 0.0, b.normal.z < 0.0);
            }
        }
    }

    #[test]
    fn horizontal_normals_keep_their_sign() {
        let mut triangle = crate::testing::random_soup(1, 1)[0];
        triangle.vertices[0].normal = Vec3::new(1.0, 0.0, 0.0);
        triangle.vertices[1].normal = Vec3::new(0.0, 0.6, -0.8);
        triangle.vertices[2].normal = Vec3::new(0.0, 0.0, -1.0);
        let back = PackedTriangle::pack(&triangle).unpack();
        assert_eq!(back.vertices[0].normal, Vec3::new(1.0, 0.0, 0.0));
        assert!(back.vertices[1].normal.distance(Vec3::new(0.0, 0.6, -0.8)) < 1e-6);
        assert_eq!(back.vertices[2].normal, Vec3::new(0.0, 0.0, -1.0));
    }

    #[test]
    fn layout_sizes_match_the_talk() {
        // 8 floats per vertex, 24 per triangle.
        assert_eq!(size_of::<PackedTriangle>(), 24 * size_of::<f32>());
        assert_eq!(std::mem::align_of::<PackedTriangle>(), 4);
    }
}
