//! Shapes loaders share: indexed meshes, how a shape's triangles are placed in the world,
//! and the disk and sphere tessellated (Mitsuba's and pbrt's quadrics).

use std::f32::consts::{PI, TAU};

use glam::{Mat3, Mat4, Vec2, Vec3};

use crate::Vertex;

/// A shape's triangles in its own space.
pub(crate) type Mesh = Vec<[Vertex; 3]>;

/// Facets of a tessellated sphere: around its axis, and from pole to pole.
const SPHERE_SEGMENTS: usize = 128;
const SPHERE_RINGS: usize = 64;
/// Facets of a tessellated disk, cylinder or surface of revolution around its axis.
const DISK_SEGMENTS: usize = 128;

/// How a shape's triangles are placed: its transform (normals by the inverse transpose, a
/// mirroring one swapping two vertices so that the front face stays the front), turned over
/// by `flip_normals`, and with `face_normals` the triangles' own normals.
pub(crate) struct Placement {
    to_world: Mat4,
    normals: Mat3,
    swap: bool,
    flip: bool,
    face_normals: bool,
}

impl Placement {
    pub fn new(to_world: Mat4, flip: bool, face_normals: bool) -> Placement {
        let linear = Mat3::from_mat4(to_world);
        Placement {
            to_world,
            normals: linear.inverse().transpose(),
            swap: (linear.determinant() < 0.0) != flip,
            flip,
            face_normals,
        }
    }

    pub fn place(&self, mut vertices: [Vertex; 3]) -> [Vertex; 3] {
        for v in &mut vertices {
            v.position = self.to_world.transform_point3(v.position);
            v.normal = match self.face_normals {
                // The builder gives a triangle without normals its geometric one.
                true => Vec3::ZERO,
                false => (self.normals * v.normal).normalize_or_zero(),
            };
            if self.flip {
                v.normal = -v.normal;
            }
        }
        if self.swap {
            vertices.swap(1, 2);
        }
        vertices
    }
}

/// A mesh as files index it: vertices, and triangles of indices in range.
pub(crate) struct IndexedMesh {
    pub vertices: Vec<Vertex>,
    pub triangles: Vec<[u32; 3]>,
    /// Whether the file gave normals (zero in `vertices` otherwise).
    pub with_normals: bool,
}

impl IndexedMesh {
    /// The triangles, with smooth normals (area-weighted) where the file gave none, as
    /// Mitsuba shades a mesh without normals.
    pub fn smooth(mut self) -> Mesh {
        if !self.with_normals {
            let positions: Vec<Vec3> = self.vertices.iter().map(|v| v.position).collect();
            let normals = crate::mesh::smooth_normals(&positions, &self.triangles);
            for (v, n) in self.vertices.iter_mut().zip(normals) {
                v.normal = n;
            }
        }
        self.flat()
    }

    /// The triangles as the file gives them: without normals in the file, flat (each
    /// triangle's own normal, which the builder gives a zero normal), as pbrt shades them.
    pub fn flat(self) -> Mesh {
        let vertices = &self.vertices;
        (self.triangles.iter())
            .map(|t| t.map(|i| vertices[i as usize]))
            .collect()
    }
}

pub(crate) fn vertex(position: Vec3, normal: Vec3, uv: Vec2) -> Vertex {
    Vertex {
        position,
        normal,
        uv,
        ..Vertex::default()
    }
}

/// Two triangles (0, 1, 2) and (0, 2, 3) of a quad whose corners run counter-clockwise seen
/// from the side its normals face.
pub(crate) fn quad(corners: [Vertex; 4]) -> [[Vertex; 3]; 2] {
    let [a, b, c, d] = corners;
    [[a, b, c], [a, c, d]]
}

/// The unit disk in the plane z = 0, facing +z (texture coordinates: radius
/// and turn).
pub(crate) fn disk() -> Mesh {
    let rim = |i: usize| {
        let turn = i as f32 / DISK_SEGMENTS as f32;
        let (sin, cos) = (turn * TAU).sin_cos();
        vertex(Vec3::new(cos, sin, 0.0), Vec3::Z, Vec2::new(1.0, turn))
    };
    let centre = vertex(Vec3::ZERO, Vec3::Z, Vec2::ZERO);
    (0..DISK_SEGMENTS)
        .map(|i| [centre, rim(i), rim(i + 1)])
        .collect()
}

/// A sphere of `radius` around `centre`, its poles on ±z, with smooth normals (texture
/// coordinates: turn about z, and pole to pole).
pub(crate) fn sphere(centre: Vec3, radius: f32) -> Mesh {
    let point = |i: usize, j: usize| {
        let (u, v) = (
            i as f32 / SPHERE_SEGMENTS as f32,
            j as f32 / SPHERE_RINGS as f32,
        );
        let (sin_phi, cos_phi) = (u * TAU).sin_cos();
        let (sin_theta, cos_theta) = (v * PI).sin_cos();
        let normal = Vec3::new(sin_theta * cos_phi, sin_theta * sin_phi, cos_theta);
        vertex(centre + radius * normal, normal, Vec2::new(u, v))
    };
    let mut mesh = Mesh::new();
    for j in 0..SPHERE_RINGS {
        for i in 0..SPHERE_SEGMENTS {
            // Counter-clockwise seen from outside: down the ring, then around.
            let corners = [
                point(i, j),
                point(i, j + 1),
                point(i + 1, j + 1),
                point(i + 1, j),
            ];
            let [first, second] = quad(corners);
            // At each pole one triangle of each quad has no area: the second at the north
            // pole (its first and last corners meet), the first at the south.
            if j + 1 < SPHERE_RINGS {
                mesh.push(first);
            }
            if j > 0 {
                mesh.push(second);
            }
        }
    }
    mesh
}

/// A surface of revolution about +z through a profile from `(r, z, normal)` to the next
/// (`normal` given at turn 0, in the xz-plane), `DISK_SEGMENTS` facets round, counter-clockwise
/// seen from the side its normals face. Texture coordinates: turn, and along the profile.
pub(crate) fn revolve(profile: [(f32, f32, Vec3); 2]) -> Mesh {
    let point = |i: usize, j: usize| {
        let turn = i as f32 / DISK_SEGMENTS as f32;
        let (sin, cos) = (turn * TAU).sin_cos();
        let (r, z, n) = profile[j];
        let position = Vec3::new(r * cos, r * sin, z);
        let normal = Vec3::new(n.x * cos, n.x * sin, n.z);
        vertex(position, normal, Vec2::new(turn, j as f32))
    };
    let mut mesh = Mesh::new();
    for i in 0..DISK_SEGMENTS {
        let corners = [point(i, 0), point(i + 1, 0), point(i + 1, 1), point(i, 1)];
        for mut t in [
            [corners[0], corners[1], corners[2]],
            [corners[0], corners[2], corners[3]],
        ] {
            let [a, b, c] = t.map(|v| v.position);
            let facing = (b - a).cross(c - a);
            if facing.length_squared() == 0.0 {
                continue;
            }
            if facing.dot(t[0].normal + t[1].normal + t[2].normal) < 0.0 {
                t.swap(1, 2);
            }
            mesh.push(t);
        }
    }
    mesh
}

#[cfg(test)]
mod tests {
    use super::*;

    fn facing(t: &[Vertex; 3]) -> Vec3 {
        let [a, b, c] = t.map(|v| v.position);
        (b - a).cross(c - a)
    }

    #[test]
    fn tessellated_shapes_face_their_normals() {
        for (name, mesh) in [("disk", disk()), ("sphere", sphere(Vec3::ONE, 2.0))] {
            for t in &mesh {
                let n = facing(t);
                assert!(n.length() > 0.0, "{name}: a degenerate triangle");
                for v in t {
                    assert!(
                        n.dot(v.normal) > 0.0,
                        "{name}: a triangle faces away from its normals"
                    );
                }
            }
        }
    }

    #[test]
    fn the_sphere_is_closed_and_round() {
        let mesh = sphere(Vec3::new(1.0, 2.0, 3.0), 0.5);
        let area: f32 = mesh.iter().map(|t| facing(t).length() / 2.0).sum();
        let exact = 4.0 * PI * 0.25;
        assert!(
            (area / exact - 1.0).abs() < 1e-3,
            "area {area} against {exact}"
        );
        for v in mesh.iter().flatten() {
            let r = (v.position - Vec3::new(1.0, 2.0, 3.0)).length();
            assert!((r - 0.5).abs() < 1e-5);
        }
    }

    #[test]
    fn mirroring_and_flipping_keep_fronts_and_normals_together() {
        let mirror = Mat4::from_scale(Vec3::new(-1.0, 2.0, 1.0));
        for (to_world, flip) in [(Mat4::IDENTITY, true), (mirror, false), (mirror, true)] {
            let placement = Placement::new(to_world, flip, false);
            for t in disk() {
                let placed = placement.place(t);
                let n = facing(&placed);
                assert!(placed.iter().all(|v| n.dot(v.normal) > 0.0));
                assert_eq!(placed[0].normal.z < 0.0, flip, "flipped: {flip}");
            }
        }
    }

    #[test]
    fn revolved_shapes_face_their_normals_and_close() {
        let disk = revolve([(2.0, 0.5, Vec3::Z), (0.0, 0.5, Vec3::Z)]);
        let tube = revolve([(1.0, -1.0, Vec3::X), (1.0, 1.0, Vec3::X)]);
        for (mesh, area) in [(disk, std::f32::consts::PI * 4.0), (tube, TAU * 2.0)] {
            let mut sum = 0.0;
            for t in &mesh {
                let [a, b, c] = t.map(|v| v.position);
                let n = (b - a).cross(c - a);
                sum += n.length() / 2.0;
                assert!(t.iter().all(|v| n.dot(v.normal) > 0.0));
            }
            assert!((sum / area - 1.0).abs() < 1e-3, "area {sum} against {area}");
        }
    }
}
