//! Mitsuba shapes as triangles: meshes from OBJ and PLY files, and Mitsuba's rectangle, cube,
//! disk and sphere tessellated, each placed by its `to_world` and given its material.

use glam::{Mat4, Vec2, Vec3};
use roxmltree::Node;

use super::Reader;
use crate::shapes::{Mesh, Placement, disk, quad, sphere, vertex};
use crate::{Material, SceneError, Surface, Triangle};

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
                    "ply" => crate::ply::read(&path)?.smooth(),
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
            "cylinder" => self.cylinder(node)?,
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

    /// Mitsuba's `cylinder`: an open tube of `radius` from `p0` to `p1` (Mitsuba's defaults:
    /// radius 1 along +z from 0 to 1), facing out.
    fn cylinder(&mut self, node: Node<'a, 'a>) -> Result<Mesh, SceneError> {
        let p0 = self.vector(node, "p0")?.unwrap_or(Vec3::ZERO);
        let p1 = self.vector(node, "p1")?.unwrap_or(Vec3::Z);
        let radius = self.float(node, "radius", 1.0)?;
        let axis = p1 - p0;
        if !(radius > 0.0 && axis.length() > 0.0) {
            let message = format!("radius {radius} or the axis from p0 to p1 has no length");
            return Err(self.context.error(node, message));
        }
        let turn = glam::Quat::from_rotation_arc(Vec3::Z, axis.normalize());
        let tube =
            crate::shapes::revolve([(radius, 0.0, Vec3::X), (radius, axis.length(), Vec3::X)]);
        let place = |v: crate::Vertex| crate::Vertex {
            position: p0 + turn * v.position,
            normal: turn * v.normal,
            ..v
        };
        Ok(tube.into_iter().map(|t| t.map(place)).collect())
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
        let medium = self.interior_medium(node)?;
        let shared = bsdf
            .filter(|b| b.has_tag_name("ref") && radiance.is_none() && medium.is_none())
            .and_then(|b| b.attribute("id"));
        if let Some(id) = shared.and_then(|id| self.materials.get(id)) {
            return Ok(*id);
        }
        let mut mapped = match bsdf {
            Some(b) => {
                let b = self.resolve_bsdf(b)?;
                self.material(b)?
            }
            None => {
                let grey = Material {
                    name: "default".into(),
                    surface: Surface::Diffuse,
                    base_color: Vec3::splat(0.5),
                    ..Material::default()
                };
                super::bsdfs::Mapped::plain(grey, None)
            }
        };
        if let Some((medium, source)) = medium {
            match mapped.fill(medium) {
                true => self.filled_with(source),
                false => self.warn(
                    node,
                    "an interior medium is read inside solid glass or a null BSDF only: not read",
                ),
            }
        }
        if let Some(radiance) = radiance {
            for m in mapped.members_mut() {
                m.emission = radiance;
                m.name = format!("{} (emitter)", m.name);
            }
        }
        let (id, to_uv, simplified) = mapped.add_to(&mut self.builder);
        if let Some(why) = simplified {
            self.warn(node, why);
        }
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rectangles_and_cubes_face_their_normals() {
        for (name, mesh) in [("rectangle", rectangle()), ("cube", cube())] {
            for t in &mesh {
                let [a, b, c] = t.map(|v| v.position);
                let n = (b - a).cross(c - a);
                assert!(n.length() > 0.0, "{name}: a degenerate triangle");
                assert!(
                    t.iter().all(|v| n.dot(v.normal) > 0.0),
                    "{name}: a triangle faces away from its normals"
                );
            }
        }
    }
}
