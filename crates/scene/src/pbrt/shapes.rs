//! pbrt's shapes as triangles: meshes given inline, in PLY files or as bilinear patches, and
//! the sphere, disk and cylinder tessellated; each placed by its transform, facing the side
//! pbrt treats as its front, with its material and area light.

use std::path::Path;

use glam::{Mat3, Mat4, Vec2, Vec3};

use super::tokens::{Params, Values};
use super::{Reader, ShapeCall};
use crate::shapes::{IndexedMesh, Mesh, revolve, vertex};
use crate::{SceneError, Triangle, Vertex};

/// The most triangles `loopsubdiv` makes (fewer levels than asked where more would pass it).
const MAX_SUBDIVIDED: usize = 1 << 24;

/// How pbrt decides a shape's front: the side an area light emits from, a glass's outside.
#[derive(Clone, Copy, PartialEq)]
enum Facing {
    /// A mesh with normals: the side they point to (turned by `ReverseOrientation`).
    Normals,
    /// A mesh without: the winding's side in the world (counter-clockwise), turned by
    /// `ReverseOrientation` and by a transform that mirrors.
    Winding,
    /// A sphere, disk or cylinder: its object-space normals (outwards, the disk's +z), turned
    /// by `ReverseOrientation` and by a transform that mirrors, as pbrt does.
    Quadric,
}

impl Reader {
    /// Makes a `Shape` (placed by `outer` too: an object instance's transform).
    pub(super) fn shape(&mut self, call: &ShapeCall, outer: Mat4) -> Result<(), SceneError> {
        let file = call.file.as_path();
        let fail = |message: String| SceneError::format(file, message);
        let params = &call.params;
        // An alpha of 0 makes a shape invisible, and its area light dark (pbrt masks both).
        if matches!(params.get("alpha"), Some(p) if p.values == Values::Numbers(vec![0.0])) {
            return Ok(());
        }
        let (mesh, facing) = match call.kind.as_str() {
            "trianglemesh" => faced(inline_mesh(params, 3).map_err(fail)?),
            "loopsubdiv" => {
                let control = inline_mesh(params, 3).map_err(fail)?;
                let asked = params.integer("levels", 3).map_err(fail)?;
                // Each level quadruples the triangles: at most MAX_SUBDIVIDED of them.
                let mut levels = asked.clamp(0, 12) as u32;
                while levels > 0 && control.triangles.len() << (2 * levels) > MAX_SUBDIVIDED {
                    levels -= 1;
                }
                if levels as i64 != asked.max(0) {
                    let message =
                        format!("loopsubdiv: {levels} levels, not {asked} (too many triangles)");
                    self.warn(file, message);
                }
                (subdivided(&control, levels), Facing::Normals)
            }
            "bilinearmesh" => {
                let mesh = inline_mesh(params, 4).map_err(fail)?;
                faced(mesh)
            }
            "plymesh" => {
                let name = (params.string("filename").map_err(fail)?)
                    .ok_or_else(|| fail("a plymesh needs a \"string filename\"".into()))?;
                if params.get("displacement").is_some() {
                    self.warn(file, "a plymesh's displacement is not read");
                }
                params.get("edgelength");
                let mesh = crate::ply::read(&self.resolve(&name))?;
                faced(mesh)
            }
            "sphere" => {
                let radius = positive(params, "radius", 1.0).map_err(fail)?;
                let zmin = params.float("zmin", -radius).map_err(fail)?;
                let zmax = params.float("zmax", radius).map_err(fail)?;
                let phimax = params.float("phimax", 360.0).map_err(fail)?;
                if zmin > -radius || zmax < radius || phimax < 360.0 {
                    self.warn(file, "a partial sphere is drawn whole");
                }
                let mut mesh = crate::shapes::sphere(Vec3::ZERO, radius);
                // pbrt's v runs from −z to +z.
                for v in mesh.iter_mut().flatten() {
                    v.uv.y = 1.0 - v.uv.y;
                }
                (mesh, Facing::Quadric)
            }
            "disk" => {
                let radius = positive(params, "radius", 1.0).map_err(fail)?;
                let inner = params.float("innerradius", 0.0).map_err(fail)?;
                let height = params.float("height", 0.0).map_err(fail)?;
                if !(inner >= 0.0 && inner < radius) {
                    return Err(fail(format!(
                        "disk: innerradius {inner} not in [0, {radius})"
                    )));
                }
                self.partial_turn(params, file)?;
                let profile = [(radius, height, Vec3::Z), (inner, height, Vec3::Z)];
                (revolve(profile), Facing::Quadric)
            }
            "cylinder" => {
                let radius = positive(params, "radius", 1.0).map_err(fail)?;
                let zmin = params.float("zmin", -1.0).map_err(fail)?;
                let zmax = params.float("zmax", 1.0).map_err(fail)?;
                self.partial_turn(params, file)?;
                let profile = [(radius, zmin, Vec3::X), (radius, zmax, Vec3::X)];
                (revolve(profile), Facing::Quadric)
            }
            other => {
                self.warn(file, format!("shape \"{other}\" is not read"));
                return Ok(());
            }
        };
        let to_world = outer * call.state.ctm;
        let area_light = match (call.state.area_light, outer == Mat4::IDENTITY) {
            (Some(_), false) => {
                self.warn(
                    file,
                    "area lights in object instances do not emit (as in pbrt)",
                );
                None
            }
            (light, _) => light,
        };
        let emission = area_light.map(|light| {
            let mut radiance = light.radiance;
            if let Some(power) = light.power {
                let area: f32 = (mesh.iter())
                    .map(|t| {
                        let [a, b, c] = t.map(|v| to_world.transform_point3(v.position));
                        (b - a).cross(c - a).length() / 2.0
                    })
                    .sum();
                let sides = if light.two_sided { 2.0 } else { 1.0 };
                radiance *= power / (std::f32::consts::PI * area.max(f32::MIN_POSITIVE) * sides);
            }
            (radiance, light.two_sided)
        });
        let material = (&call.state.material, call.state.interior.as_deref());
        let made = self.shape_material(material, emission, params, file)?;
        let placement = Placement::new(self.mirror, to_world, call.state.reverse_orientation);
        for vertices in mesh {
            let mut vertices = placement.place(vertices, facing);
            for v in &mut vertices {
                v.uv = made.uv(v.uv);
            }
            let triangle = Triangle {
                vertices,
                material: made.id,
            };
            self.builder.add_triangle(triangle)?;
        }
        self.warn_unused(file, &format!("shape \"{}\"", call.kind), params);
        Ok(())
    }

    /// Warns where a disk or cylinder is asked to turn less than a whole turn.
    fn partial_turn(&mut self, params: &Params, file: &Path) -> Result<(), SceneError> {
        let phimax = params
            .float("phimax", 360.0)
            .map_err(|m| SceneError::format(file, m))?;
        if phimax < 360.0 {
            self.warn(file, "a partial disk or cylinder is drawn whole");
        }
        Ok(())
    }
}

/// How a shape's triangles are placed in kousen's world: pbrt's transform, then the mirror
/// (see the module), each triangle wound so that kousen's front is pbrt's.
struct Placement {
    to_world: Mat4,
    mirror: Mat4,
    world: Mat4,
    normals: Mat3,
    reverse: bool,
    /// Whether pbrt's transform mirrors.
    swaps: bool,
}

impl Placement {
    fn new(mirror: Mat4, to_world: Mat4, reverse: bool) -> Placement {
        let world = mirror * to_world;
        Placement {
            to_world,
            mirror,
            world,
            normals: Mat3::from_mat4(world).inverse().transpose(),
            reverse,
            swaps: Mat3::from_mat4(to_world).determinant() < 0.0,
        }
    }

    fn place(&self, object: [Vertex; 3], facing: Facing) -> [Vertex; 3] {
        let with_normals =
            facing != Facing::Winding && object.iter().all(|v| v.normal != Vec3::ZERO);
        let turned = match facing {
            Facing::Normals => self.reverse,
            _ => self.reverse != self.swaps,
        };
        let sign = if turned { -1.0 } else { 1.0 };
        let mut vertices = object.map(|v| Vertex {
            position: self.world.transform_point3(v.position),
            normal: match with_normals {
                true => (self.normals * v.normal).normalize_or_zero() * sign,
                false => Vec3::ZERO,
            },
            ..v
        });
        let front = match with_normals {
            true => vertices.iter().map(|v| v.normal).sum::<Vec3>(),
            false => {
                let [a, b, c] = object.map(|v| self.to_world.transform_point3(v.position));
                // pbrt's normal in its world, then mirrored as the scene is.
                self.mirror.transform_vector3((b - a).cross(c - a) * sign)
            }
        };
        let [a, b, c] = vertices.map(|v| v.position);
        if (b - a).cross(c - a).dot(front) < 0.0 {
            vertices.swap(1, 2);
        }
        vertices
    }
}

/// The triangles of `levels` levels of Loop subdivision of `control` at their limit
/// positions, with smooth normals (pbrt gives the limit surface's).
fn subdivided(control: &IndexedMesh, levels: u32) -> Mesh {
    let positions: Vec<Vec3> = control.vertices.iter().map(|v| v.position).collect();
    let (positions, triangles) =
        super::subdivision::loop_subdivide(&positions, &control.triangles, levels);
    let normals = crate::mesh::smooth_normals(&positions, &triangles);
    let vertices = (positions.into_iter().zip(normals))
        .map(|(p, n)| vertex(p, n, Vec2::ZERO))
        .collect();
    let mesh = IndexedMesh {
        vertices,
        triangles,
        with_normals: true,
    };
    mesh.flat()
}

/// A mesh's triangles as pbrt shades them (flat where it has no normals), and how pbrt
/// finds their fronts.
fn faced(mesh: IndexedMesh) -> (Mesh, Facing) {
    let facing = match mesh.with_normals {
        true => Facing::Normals,
        false => Facing::Winding,
    };
    (mesh.flat(), facing)
}

/// A positive float parameter.
fn positive(params: &Params, name: &str, default: f32) -> Result<f32, String> {
    let value = params.float(name, default)?;
    match value > 0.0 {
        true => Ok(value),
        false => Err(format!("\"{name}\" {value} is not positive")),
    }
}

/// An inline mesh: `P`, `indices` in groups of `corners` (3: triangles, 4: bilinear patches;
/// optional where `P` has exactly that many points), `N` and `uv` (pbrt-v3's `float uv` or
/// `st` too) per point.
fn inline_mesh(params: &Params, corners: usize) -> Result<IndexedMesh, String> {
    let positions = params.triples("P")?.ok_or("a mesh needs \"point3 P\"")?;
    let indices = match params.integers("indices")? {
        Some(indices) => indices,
        None if positions.len() == corners => (0..corners as i64).collect(),
        None => {
            return Err(format!(
                "a mesh of {} points needs \"integer indices\"",
                positions.len()
            ));
        }
    };
    if indices.len() % corners != 0 {
        return Err(format!(
            "{} indices are not a whole number of {corners}-gons",
            indices.len()
        ));
    }
    let count = positions.len();
    let index = |i: i64| match i >= 0 && (i as usize) < count {
        true => Ok(i as u32),
        false => Err(format!("index {i} is not one of the {count} points")),
    };
    let indices: Vec<u32> = indices.into_iter().map(index).collect::<Result<_, _>>()?;
    let per_point = |values: Option<Vec<Vec3>>, what: &str| match values {
        Some(v) if v.len() == count => Ok(Some(v)),
        Some(v) => Err(format!("{} {what} for {count} points", v.len())),
        None => Ok(None),
    };
    let normals = per_point(params.triples("N")?, "normals")?;
    let uvs = match params.pairs("uv")?.or(params.pairs("st")?) {
        Some(uv) if uv.len() == count => Some(uv),
        Some(uv) => {
            return Err(format!(
                "{} texture coordinates for {count} points",
                uv.len()
            ));
        }
        None => None,
    };
    // Tangents and face indices change nothing kousen draws.
    params.get("S");
    params.get("faceIndices");
    let vertices = (0..count)
        .map(|i| {
            let normal = normals.as_ref().map_or(Vec3::ZERO, |n| n[i]);
            let uv = uvs.as_ref().map_or(Vec2::ZERO, |uv| uv[i]);
            vertex(positions[i], normal, uv)
        })
        .collect();
    let triangles = match corners {
        3 => (indices.chunks_exact(3))
            .map(|c| [c[0], c[1], c[2]])
            .collect(),
        // Bilinear patches p00 p10 p01 p11: two triangles round p00 p10 p11 p01.
        _ => (indices.chunks_exact(4))
            .flat_map(|q| [[q[0], q[1], q[3]], [q[0], q[3], q[2]]])
            .collect(),
    };
    Ok(IndexedMesh {
        vertices,
        triangles,
        with_normals: normals.is_some(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::pbrt::tokens::Tokens;

    fn params(text: &str) -> Params {
        Tokens::new(text).params().unwrap()
    }

    #[test]
    fn inline_meshes_check_their_indices_and_counts() {
        let mesh = inline_mesh(&params("\"point3 P\" [0 0 0 1 0 0 0 1 0]"), 3).unwrap();
        assert_eq!(mesh.triangles, vec![[0, 1, 2]]);
        for (text, why) in [
            ("\"integer indices\" [0 1 2]", "needs \"point3 P\""),
            (
                "\"point3 P\" [0 0 0 1 0 0 0 1 0 1 1 0]",
                "needs \"integer indices\"",
            ),
            (
                "\"point3 P\" [0 0 0 1 0 0 0 1 0] \"integer indices\" [0 1 3]",
                "index 3",
            ),
            (
                "\"point3 P\" [0 0 0 1 0 0 0 1 0] \"integer indices\" [0 1]",
                "whole number",
            ),
            (
                "\"point3 P\" [0 0 0 1 0 0 0 1 0] \"normal N\" [0 0 1]",
                "1 normals for 3",
            ),
        ] {
            let error = inline_mesh(&params(text), 3).err().unwrap_or_default();
            assert!(error.contains(why), "{why}: {error}");
        }
    }

    /// A triangle wound counter-clockwise seen from +z, without normals: pbrt's front is +z;
    /// mirrored into kousen's world it stays towards +z, whatever the winding says.
    #[test]
    fn placement_keeps_pbrt_fronts_through_the_mirror() {
        let mirror = Mat4::from_scale(Vec3::new(-1.0, 1.0, 1.0));
        let triangle = [Vec3::ZERO, Vec3::X, Vec3::Y].map(|p| vertex(p, Vec3::ZERO, Vec2::ZERO));
        let front = |t: [Vertex; 3]| {
            let [a, b, c] = t.map(|v| v.position);
            (b - a).cross(c - a).z.signum()
        };
        let flip_x = Mat4::from_scale(Vec3::new(-1.0, 1.0, 1.0));
        for (scene_mirror, to_world, reverse, expected) in [
            (Mat4::IDENTITY, Mat4::IDENTITY, false, 1.0),
            (mirror, Mat4::IDENTITY, false, 1.0),
            (mirror, Mat4::IDENTITY, true, -1.0),
            // pbrt turns a mirroring transform's winding normal back: still +z.
            (mirror, flip_x, false, 1.0),
        ] {
            let placed =
                Placement::new(scene_mirror, to_world, reverse).place(triangle, Facing::Winding);
            assert_eq!(front(placed), expected, "reverse {reverse}");
        }
        // With normals the front follows them, reversed by ReverseOrientation only.
        let with_normals = triangle.map(|v| Vertex {
            normal: Vec3::NEG_Z,
            ..v
        });
        let placed = Placement::new(mirror, flip_x, false).place(with_normals, Facing::Normals);
        assert_eq!(front(placed), -1.0);
        assert!(placed.iter().all(|v| v.normal.z < 0.0));
    }
}
