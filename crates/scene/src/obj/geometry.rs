//! `tobj` models to triangles: normals from `vn` or smoothed, texture coordinates flipped to
//! the scene's convention (v = 0 is the image's top row; OBJ's v = 0 is its bottom row).

use std::collections::HashMap;

use glam::{Vec2, Vec3};

use crate::mesh::smooth_normals;
use crate::{SceneBuilder, SceneError, Triangle, Vertex};

/// Adds a model's triangles with material `material`.
pub(super) fn add_model(
    builder: &mut SceneBuilder,
    model: &tobj::Model,
    material: u32,
) -> Result<(), SceneError> {
    let mesh = &model.mesh;
    let positions: Vec<Vec3> = mesh
        .positions
        .chunks_exact(3)
        .map(|p| Vec3::new(p[0], p[1], p[2]))
        .collect();
    let count = positions.len();
    let normals = if mesh.normals.len() == 3 * count {
        mesh.normals
            .chunks_exact(3)
            .map(|n| Vec3::new(n[0], n[1], n[2]))
            .collect()
    } else {
        if !mesh.normals.is_empty() {
            builder.warn(format!(
                "object '{}': only some faces have normals; smooth normals computed",
                model.name
            ));
        }
        welded_smooth_normals(&positions, &mesh.indices)
    };
    let uvs: Vec<Vec2> = if mesh.texcoords.len() == 2 * count {
        mesh.texcoords
            .chunks_exact(2)
            .map(|t| Vec2::new(t[0], 1.0 - t[1]))
            .collect()
    } else {
        if !mesh.texcoords.is_empty() {
            builder.warn(format!(
                "object '{}': only some faces have texture coordinates; all set to zero",
                model.name
            ));
        }
        vec![Vec2::ZERO; count]
    };
    for corners in mesh.indices.chunks_exact(3) {
        let mut vertices = [Vertex::default(); 3];
        for (vertex, &index) in vertices.iter_mut().zip(corners) {
            let i = index as usize;
            if i >= count {
                return Err(SceneError::format(
                    builder.path(),
                    format!("object '{}': vertex index {i} out of range", model.name),
                ));
            }
            *vertex = Vertex {
                position: positions[i],
                normal: normals[i],
                uv: uvs[i],
                ..Vertex::default()
            };
        }
        builder.add_triangle(Triangle { vertices, material })?;
    }
    Ok(())
}

/// Area-weighted smooth normals over the model's distinct positions: `tobj` splits a vertex
/// where its texture coordinates differ, and a seam must not show in the shading.
fn welded_smooth_normals(positions: &[Vec3], indices: &[u32]) -> Vec<Vec3> {
    let mut welded: Vec<Vec3> = Vec::with_capacity(positions.len());
    let mut slots: HashMap<[u32; 3], u32> = HashMap::with_capacity(positions.len());
    let remap: Vec<u32> = positions
        .iter()
        .map(|&p| {
            // Adding zero turns -0.0 into 0.0, so both weld.
            let key = (p + Vec3::ZERO).to_array().map(f32::to_bits);
            *slots.entry(key).or_insert_with(|| {
                welded.push(p);
                (welded.len() - 1) as u32
            })
        })
        .collect();
    let triangles: Vec<[u32; 3]> = indices
        .chunks_exact(3)
        .filter(|c| c.iter().all(|&i| (i as usize) < remap.len()))
        .map(|c| [0, 1, 2].map(|k| remap[c[k] as usize]))
        .collect();
    let normals = smooth_normals(&welded, &triangles);
    remap.iter().map(|&w| normals[w as usize]).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn welded_normals_ignore_uv_seams() {
        // A tent of two triangles whose shared edge is split (as a UV seam would split it).
        let positions = [
            Vec3::new(-1.0, 0.0, 0.0),
            Vec3::new(0.0, 1.0, 0.0),
            Vec3::new(0.0, 1.0, 1.0),
            Vec3::new(0.0, 1.0, 0.0),
            Vec3::new(0.0, 1.0, 1.0),
            Vec3::new(1.0, 0.0, 1.0),
        ];
        let normals = welded_smooth_normals(&positions, &[0, 2, 1, 3, 4, 5]);
        assert!((normals[1] - Vec3::Y).length() < 1e-6, "{normals:?}");
        assert_eq!(normals[1], normals[3]);
    }
}
