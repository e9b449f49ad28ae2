//! A throwaway Wavefront OBJ reader for the examples: `v` and `f` lines only, polygons
//! fan-triangulated `(v0, vi, vi+1)` in file order, as ANCHORS.md's rays assume. The real
//! loader lives in the scene crate.

use std::path::Path;

use glam::Vec3;
use scene::{Triangle, Vertex};

/// The file's triangles (geometric normals, material 0), or a message.
pub fn read_triangles(path: &Path) -> Result<Vec<Triangle>, String> {
    let text = std::fs::read_to_string(path).map_err(|e| format!("{}: {e}", path.display()))?;
    let mut positions: Vec<Vec3> = Vec::new();
    let mut triangles = Vec::new();
    for (number, line) in text.lines().enumerate() {
        let mut words = line.split_whitespace();
        match words.next() {
            Some("v") => {
                let xyz: Vec<f32> = words.take(3).filter_map(|w| w.parse().ok()).collect();
                let [x, y, z] = xyz[..] else {
                    return Err(format!("line {}: bad vertex", number + 1));
                };
                positions.push(Vec3::new(x, y, z));
            }
            Some("f") => {
                let corners = words
                    .map(|w| corner(w, positions.len()))
                    .collect::<Option<Vec<usize>>>()
                    .ok_or_else(|| format!("line {}: bad face", number + 1))?;
                for i in 1..corners.len().saturating_sub(1) {
                    let p = [corners[0], corners[i], corners[i + 1]].map(|k| positions[k]);
                    triangles.push(triangle(p));
                }
            }
            _ => {}
        }
    }
    Ok(triangles)
}

/// Zero-based position index of a face corner `v`, `v/vt`, `v//vn` or `v/vt/vn`.
fn corner(word: &str, count: usize) -> Option<usize> {
    let index: i64 = word.split('/').next()?.parse().ok()?;
    let zero_based = if index < 0 {
        count as i64 + index
    } else {
        index - 1
    };
    (0..count as i64)
        .contains(&zero_based)
        .then_some(zero_based as usize)
}

fn triangle(p: [Vec3; 3]) -> Triangle {
    let normal = (p[1] - p[0])
        .cross(p[2] - p[0])
        .try_normalize()
        .unwrap_or(Vec3::Z);
    Triangle {
        vertices: p.map(|position| Vertex {
            position,
            normal,
            ..Vertex::default()
        }),
        material: 0,
    }
}
