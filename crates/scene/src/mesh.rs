//! Helpers loaders share for indexed meshes.

use glam::Vec3;

/// Smooth vertex normals of an indexed mesh: each vertex gets the area-weighted sum of its
/// triangles' geometric normals, normalised. A vertex no non-degenerate triangle touches gets
/// zero (the builder then falls back to the geometric normal). Indices must be in range.
pub fn smooth_normals(positions: &[Vec3], triangles: &[[u32; 3]]) -> Vec<Vec3> {
    let mut normals = vec![Vec3::ZERO; positions.len()];
    for &[a, b, c] in triangles {
        let [pa, pb, pc] = [a, b, c].map(|i| positions[i as usize]);
        // The cross product's length is twice the area: this weights by area.
        let n = (pb - pa).cross(pc - pa);
        if !n.is_finite() {
            continue;
        }
        for i in [a, b, c] {
            normals[i as usize] += n;
        }
    }
    normals
        .into_iter()
        .map(|n| n.try_normalize().unwrap_or(Vec3::ZERO))
        .collect()
}
