//! Mitsuba shapes as triangles: meshes from OBJ and PLY files, and Mitsuba's rectangle, cube,
//! disk and sphere tessellated, each placed by its `to_world` and given its material.

use std::f32::consts::{PI, TAU};

use glam::{Mat3, Mat4, Vec2, Vec3};
use roxmltree::Node;

use super::Reader;
use crate::{Material, SceneError, Surface, Triangle, Vertex};

/// A shape's triangles in its own space.
pub(super) type Mesh = Vec<[Vertex; 3]>;

/// Facets of a tessellated sphere: around its axis, and from pole to pole.
const SPHERE_SEGMENTS: usize = 128;
const SPHERE_RINGS: usize = 64;
/// Facets of a tessellated disk.
const DISK_SEGMENTS: usize = 128;

impl<'a> Reader<'a> {
    pub(super) fn shape(&mut self, node: Node<'a, 'a>) -> Result<(), SceneError> {
        self.shape_within(node, Mat4::IDENTITY)
    }

    /// A shape placed by its own `to_world` and then by `outer` (an instance's); a
    /// `shapegroup` is only read through the `instance`s that place it.
    fn shape_within(&mut self, node: Node<'a, 'a>, outer: Mat4) -> Result<(), SceneError> {
        let kind = self.context.required(node, "type")?;
        let mesh = match kind.as_str() {
            "shapegroup" => return Ok(()),
            "instance" => return self.instance(node, outer),
            "obj" | "ply" | "serialized" => {
                let file = self.string(node, "filename")?.ok_or_else(|| {
                    self.context
                        .error(node, format!("a {kind} shape needs a filename"))
                })?;
                let path = self.file(&file);
                match kind.as_str() {
                    "obj" => self.obj_mesh(&path)?,
                    "ply" => super::ply::read(&path)?,
                    _ => {
                        let index = self.float(node, "shape_index", 0.0)?;
                        if index < 0.0 || index.fract() != 0.0 {
                            let message = format!("shape_index {index} is not a mesh's number");
                            return Err(self.context.error(node, message));
                        }
                        super::serialized::read(&path, index as usize)?
                    }
                }
            }
            "rectangle" => rectangle(),
            "cube" => cube(),
            "disk" => disk(),
            "sphere" => {
                let centre = self.vector(node, "center")?.unwrap_or(Vec3::ZERO);
                let radius = self.float(node, "radius", 1.0)?;
                if radius <= 0.0 {
                    return Err(self
                        .context
                        .error(node, format!("radius {radius} is not positive")));
                }
                sphere(centre, radius)
            }
            other => {
                self.warn(node, format!("shape \"{other}\" is not read"));
                return Ok(());
            }
        };
        let (material, to_uv) = self.shape_material(node)?;
        let to_world = outer * self.to_world(node)?;
        let flip = self.boolean(node, "flip_normals", false)?;
        let face_normals = self.boolean(node, "face_normals", false)?;
        let placement = Placement::new(to_world, flip, face_normals);
        for vertices in mesh {
            let triangle = Triangle {
                vertices: placement.place(vertices.map(|mut v| {
                    if let Some(to_uv) = to_uv {
                        v.uv = to_uv.transform_point3(v.uv.extend(0.0)).truncate();
                    }
                    v
                })),
                material,
            };
            self.builder.add_triangle(triangle)?;
        }
        Ok(())
    }

    /// An `instance`: each shape of the `shapegroup` it refers to, placed by its `to_world`.
    fn instance(&mut self, node: Node<'a, 'a>, outer: Mat4) -> Result<(), SceneError> {
        if outer != Mat4::IDENTITY {
            return Err(self.context.error(node, "an instance inside a shape group"));
        }
        let reference = node
            .children()
            .find(|c| c.has_tag_name("ref"))
            .ok_or_else(|| {
                self.context
                    .error(node, "an instance needs a <ref> to a shapegroup")
            })?;
        let group = self.referenced(reference, "shapegroup")?;
        let to_world = self.to_world(node)?;
        for shape in group.children().filter(|c| c.has_tag_name("shape")) {
            self.shape_within(shape, to_world)?;
        }
        Ok(())
    }

    /// The builder id of a shape's material: its BSDF's (Mitsuba's grey diffuse where it has
    /// none) with its area emitter's radiance.
    /// Also the `to_uv` its base colour's bitmap maps texture coordinates by.
    fn shape_material(&mut self, node: Node<'a, 'a>) -> Result<(u32, Option<Mat4>), SceneError> {
        for reference in node.children().filter(|c| c.has_tag_name("ref")) {
            let id = self.context.required(reference, "id")?;
            if !self.ids.contains(&id) {
                return Err(self
                    .context
                    .error(reference, format!("no element has id \"{id}\"")));
            }
        }
        let bsdf = node.children().find(|c| {
            c.has_tag_name("bsdf")
                || (c.has_tag_name("ref")
                    && c.attribute("id")
                        .is_some_and(|id| self.bsdfs.contains_key(id)))
        });
        let emitters: Vec<Node> = node
            .children()
            .filter(|c| c.has_tag_name("emitter"))
            .collect();
        let radiance = match emitters[..] {
            [] => None,
            [emitter] if self.context.attribute(emitter, "type").as_deref() == Some("area") => {
                Some(self.colour(emitter, "radiance", Vec3::ONE)?)
            }
            [emitter] => {
                self.warn(emitter, "only area emitters are read on shapes");
                None
            }
            [_, second, ..] => return Err(self.context.error(second, "a shape has one emitter")),
        };
        let shared = bsdf
            .filter(|b| b.has_tag_name("ref") && radiance.is_none())
            .and_then(|b| b.attribute("id"));
        if let Some(id) = shared.and_then(|id| self.materials.get(id)) {
            return Ok(*id);
        }
        let (mut material, members, to_uv) = match bsdf {
            Some(b) => {
                let b = self.resolve_bsdf(b)?;
                let mapped = self.material(b)?;
                (mapped.material, mapped.members, mapped.to_uv)
            }
            None => {
                let grey = Material {
                    name: "default".into(),
                    surface: Surface::Diffuse,
                    base_color: Vec3::splat(0.5),
                    ..Material::default()
                };
                (grey, Vec::new(), None)
            }
        };
        if let Some(radiance) = radiance {
            material.emission = radiance;
            material.name = format!("{} (emitter)", material.name);
        }
        let id = match members.is_empty() {
            true => self.builder.add_material(material),
            false => self.builder.add_blend(material, &members),
        };
        if let Some(shared) = shared {
            self.materials.insert(shared.to_string(), (id, to_uv));
        }
        Ok((id, to_uv))
    }

    /// An OBJ file's triangles through kousen's OBJ loader (its materials set aside; its
    /// warnings kept, naming the file).
    fn obj_mesh(&mut self, path: &std::path::Path) -> Result<Mesh, SceneError> {
        let scene = crate::obj::load(path)?;
        let name = path.display();
        (self.warnings).extend(scene.warnings.iter().map(|w| format!("{name}: {w}")));
        Ok(scene.triangles.iter().map(|t| t.vertices).collect())
    }
}

/// How a shape's triangles are placed: its transform (normals by the inverse transpose, a
/// mirroring one swapping two vertices so that the front face stays the front), turned over
/// by `flip_normals`, and with `face_normals` the triangles' own normals.
struct Placement {
    to_world: Mat4,
    normals: Mat3,
    swap: bool,
    flip: bool,
    face_normals: bool,
}

impl Placement {
    fn new(to_world: Mat4, flip: bool, face_normals: bool) -> Placement {
        let linear = Mat3::from_mat4(to_world);
        Placement {
            to_world,
            normals: linear.inverse().transpose(),
            swap: (linear.determinant() < 0.0) != flip,
            flip,
            face_normals,
        }
    }

    fn place(&self, mut vertices: [Vertex; 3]) -> [Vertex; 3] {
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

/// The triangles of an indexed mesh (indices in range). Without normals in the file, smooth
/// ones (area-weighted), as Mitsuba gives a mesh without normals.
pub(super) fn indexed_mesh(
    mut vertices: Vec<Vertex>,
    triangles: &[[u32; 3]],
    with_normals: bool,
) -> Mesh {
    if !with_normals {
        let positions: Vec<Vec3> = vertices.iter().map(|v| v.position).collect();
        let normals = crate::mesh::smooth_normals(&positions, triangles);
        for (v, n) in vertices.iter_mut().zip(normals) {
            v.normal = n;
        }
    }
    (triangles.iter())
        .map(|t| t.map(|i| vertices[i as usize]))
        .collect()
}

fn vertex(position: Vec3, normal: Vec3, uv: Vec2) -> Vertex {
    Vertex {
        position,
        normal,
        uv,
        ..Vertex::default()
    }
}

/// Two triangles (0, 1, 2) and (0, 2, 3) of a quad whose corners run counter-clockwise seen
/// from the side its normals face.
fn quad(corners: [Vertex; 4]) -> [[Vertex; 3]; 2] {
    let [a, b, c, d] = corners;
    [[a, b, c], [a, c, d]]
}

/// Mitsuba's rectangle: [−1, 1]² in the plane z = 0, facing +z.
fn rectangle() -> Mesh {
    let corner = |x: f32, y: f32| {
        let uv = Vec2::new((x + 1.0) / 2.0, (y + 1.0) / 2.0);
        vertex(Vec3::new(x, y, 0.0), Vec3::Z, uv)
    };
    let corners = [
        corner(-1.0, -1.0),
        corner(1.0, -1.0),
        corner(1.0, 1.0),
        corner(-1.0, 1.0),
    ];
    quad(corners).to_vec()
}

/// Mitsuba's cube: [−1, 1]³, each face facing out.
fn cube() -> Mesh {
    let mut mesh = Mesh::new();
    for axis in 0..3 {
        for side in [-1.0f32, 1.0] {
            let normal = Vec3::AXES[axis] * side;
            // Two axes spanning the face, counter-clockwise seen from outside.
            let u = Vec3::AXES[(axis + 1) % 3] * side;
            let v = Vec3::AXES[(axis + 2) % 3];
            let corner = |a: f32, b: f32| {
                let uv = Vec2::new((a + 1.0) / 2.0, (b + 1.0) / 2.0);
                vertex(normal + a * u + b * v, normal, uv)
            };
            let corners = [
                corner(-1.0, -1.0),
                corner(1.0, -1.0),
                corner(1.0, 1.0),
                corner(-1.0, 1.0),
            ];
            mesh.extend(quad(corners));
        }
    }
    mesh
}

/// Mitsuba's disk: the unit disk in the plane z = 0, facing +z (texture coordinates: radius
/// and turn).
fn disk() -> Mesh {
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
fn sphere(centre: Vec3, radius: f32) -> Mesh {
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

#[cfg(test)]
mod tests {
    use super::*;

    fn facing(t: &[Vertex; 3]) -> Vec3 {
        let [a, b, c] = t.map(|v| v.position);
        (b - a).cross(c - a)
    }

    #[test]
    fn tessellated_shapes_face_their_normals() {
        for (name, mesh) in [
            ("rectangle", rectangle()),
            ("cube", cube()),
            ("disk", disk()),
            ("sphere", sphere(Vec3::ONE, 2.0)),
        ] {
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
            for t in rectangle() {
                let placed = placement.place(t);
                let n = facing(&placed);
                assert!(placed.iter().all(|v| n.dot(v.normal) > 0.0));
                assert_eq!(placed[0].normal.z < 0.0, flip, "flipped: {flip}");
            }
        }
    }
}
