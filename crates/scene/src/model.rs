//! The scene as the renderer sees it: a triangle soup with materials, textures, cameras and lights.

use glam::{Vec2, Vec3, Vec4};

use crate::{Camera, Lights, Material, Texture};

/// One corner of a triangle: position, unit shading normal, texture coordinate and the mesh's
/// own tangent, if it gives one.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Vertex {
    pub position: Vec3,
    /// Unit length. The builder replaces a missing or degenerate normal by the geometric one.
    pub normal: Vec3,
    pub uv: Vec2,
    /// glTF's TANGENT: xyz along increasing u in the world, w = ±1 the handedness (the
    /// bitangent is w · normal × tangent), the frame normal maps and brushing are given in.
    /// Zero where the mesh gives none: the triangle's texture-coordinate frame serves then.
    pub tangent: Vec4,
}

/// A triangle in world space. Its front face is the one from which the vertices run
/// counter-clockwise (glTF's and OBJ's convention); a mirroring transform has already been
/// compensated by the loader swapping two vertices.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Triangle {
    pub vertices: [Vertex; 3],
    /// Index into [`Scene::materials`].
    pub material: u32,
}

impl Triangle {
    pub fn positions(&self) -> [Vec3; 3] {
        self.vertices.map(|v| v.position)
    }

    /// `(p1 - p0) × (p2 - p0)`: points to the front face, length twice the area.
    pub fn geometric_normal_unnormalized(&self) -> Vec3 {
        let [p0, p1, p2] = self.positions();
        (p1 - p0).cross(p2 - p0)
    }

    pub fn area(&self) -> f32 {
        0.5 * self.geometric_normal_unnormalized().length()
    }

    pub fn bounds(&self) -> Bounds {
        let [p0, p1, p2] = self.positions();
        Bounds {
            min: p0.min(p1).min(p2),
            max: p0.max(p1).max(p2),
        }
    }
}

/// An axis-aligned box. [`Bounds::EMPTY`] is the identity of [`Bounds::union`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Bounds {
    pub min: Vec3,
    pub max: Vec3,
}

impl Bounds {
    pub const EMPTY: Bounds = Bounds {
        min: Vec3::splat(f32::INFINITY),
        max: Vec3::splat(f32::NEG_INFINITY),
    };

    pub fn union(self, other: Bounds) -> Bounds {
        Bounds {
            min: self.min.min(other.min),
            max: self.max.max(other.max),
        }
    }

    pub fn grow(self, p: Vec3) -> Bounds {
        Bounds {
            min: self.min.min(p),
            max: self.max.max(p),
        }
    }

    pub fn is_empty(&self) -> bool {
        self.min.cmpgt(self.max).any()
    }

    pub fn center(&self) -> Vec3 {
        0.5 * (self.min + self.max)
    }

    pub fn extent(&self) -> Vec3 {
        self.max - self.min
    }

    /// Surface area; zero for an empty box.
    pub fn surface_area(&self) -> f32 {
        if self.is_empty() {
            return 0.0;
        }
        let e = self.extent();
        2.0 * (e.x * e.y + e.y * e.z + e.z * e.x)
    }
}

/// A loaded scene. Built through [`crate::SceneBuilder`], which keeps its invariants: at least
/// one triangle, every position finite, every material index valid, unit normals.
#[derive(Clone, Debug, Default)]
pub struct Scene {
    pub triangles: Vec<Triangle>,
    pub materials: Vec<Material>,
    pub textures: Vec<Texture>,
    /// Cameras the file defines, in file order; may be empty (then [`Scene::camera`] frames one).
    pub cameras: Vec<Camera>,
    pub lights: Lights,
    /// Zero-area triangles the loader dropped.
    pub degenerate_dropped: usize,
    /// Things the loader ignored, in words (unsupported optional extensions, say).
    pub warnings: Vec<String>,
    /// The file's animations (glTF), which `crate::load_with` can pose the scene by.
    pub animations: Vec<AnimationClip>,
    /// The names of the file's material variants (glTF `KHR_materials_variants`), which
    /// `crate::load_with` can dress the scene in.
    pub variants: Vec<String>,
    /// The material whose medium fills all space outside the solids (a foggy scene's air, as
    /// Mitsuba's sensor medium and pbrt's camera medium give it), if any: no triangle uses it
    /// (`crate::media`).
    pub atmosphere: Option<u32>,
}

/// One of a file's animations: its name, if it has one, and its length (its last keyframe's
/// time, in seconds).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct AnimationClip {
    pub name: Option<String>,
    pub seconds: f32,
}

impl Scene {
    pub fn bounds(&self) -> Bounds {
        self.triangles
            .iter()
            .fold(Bounds::EMPTY, |b, t| b.union(t.bounds()))
    }

    /// Whether some vertex carries the mesh's own tangent ([`Vertex::tangent`]).
    pub fn has_vertex_tangents(&self) -> bool {
        self.triangles
            .iter()
            .any(|t| t.vertices.iter().any(|v| v.tangent.w != 0.0))
    }

    /// The camera to render from: the file's camera `index` (default the first), or, when the
    /// file has none, a view of the bounding box from outside. `None` if `index` is out of range.
    pub fn camera(&self, index: Option<usize>) -> Option<Camera> {
        match index {
            Some(i) => self.cameras.get(i).cloned(),
            None => Some(
                self.cameras
                    .first()
                    .cloned()
                    .unwrap_or_else(|| Camera::outside_view(self.bounds())),
            ),
        }
    }
}
