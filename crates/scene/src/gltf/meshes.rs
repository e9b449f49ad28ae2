//! Mesh primitives: decoded and checked once per mesh, then placed in the world once per node
//! that uses the mesh, in that node's pose: its morph targets' weights, and its skin's joints
//! where it has one (`skins`). Triangle lists, strips and fans become triangles; points and
//! lines are skipped (the caller warns).

use std::borrow::Cow;

use glam::{Affine2, Affine3A, Mat3, Mat3A, Vec2, Vec3, Vec3A, Vec4};

use ::gltf::json;
use json::mesh::{Mode, Semantic as Attribute};
use json::validation::Checked;

use super::Input;
use super::accessors::{self, Semantic};
use crate::mesh::smooth_normals;
use crate::{SceneBuilder, SceneError, Triangle, Vertex};

/// A mesh's triangle primitives, decoded, with what was skipped or ignored on the way.
pub(super) struct Mesh {
    pub primitives: Vec<Primitive>,
    /// Point and line primitives, skipped.
    pub skipped_primitives: usize,
    /// Things ignored, for the scene's warnings.
    pub warnings: Vec<String>,
    /// The morph targets' weights where the node showing the mesh gives none (glTF
    /// `mesh.weights`; none: all zero).
    pub weights: Vec<f32>,
}

/// The texture-coordinate sets read (TEXCOORD_0 to TEXCOORD_7): a material's textures that
/// ask for a later one read none (`materials`' warning says so).
pub(super) const MAX_UV_SETS: usize = 8;

/// A triangle primitive in its mesh's space, every index checked against `positions`.
pub(super) struct Primitive {
    /// Its index in the mesh's `primitives`, for messages.
    pub index: usize,
    positions: Vec<Vec3>,
    normals: Option<Vec<Vec3>>,
    /// TEXCOORD_n at index n, each where the primitive has it: its material's textures read
    /// one of them ([`Primitive::instantiate`]'s `uv_set`).
    uv_sets: Vec<Option<Vec<Vec2>>>,
    /// TANGENT, read only where NORMAL is given (glTF: without normals, tangents are ignored).
    tangents: Option<Vec<Vec4>>,
    triangles: Vec<[u32; 3]>,
    /// The glTF material (checked to exist); `None` asks for the default material.
    pub material: Option<usize>,
    /// Morph targets, in order: each node's (or the mesh's) weights blend them in.
    targets: Vec<MorphTarget>,
    /// JOINTS_n with WEIGHTS_n, each set four joints of a vertex's skin and their weights.
    influences: Vec<Influences>,
}

/// A morph target's displacements of each vertex, of the attributes it moves.
struct MorphTarget {
    positions: Option<Vec<Vec3>>,
    normals: Option<Vec<Vec3>>,
    tangents: Option<Vec<Vec3>>,
}

/// One JOINTS_n / WEIGHTS_n pair: four joints a vertex (indices into its skin's joints), and
/// their weights.
struct Influences {
    joints: Vec<[u32; 4]>,
    weights: Vec<Vec4>,
}

/// How a node places its mesh: by its world transform, or, where it has a skin, by the skin's
/// joints (each a joint's world transform times its inverse bind matrix, `skins`), blended
/// per vertex by its weights. A skinned primitive without joints and weights, or a vertex
/// whose weights are all zero, is placed by the node's world transform.
#[derive(Clone, Copy)]
pub(super) enum Placement<'a> {
    Rigid(&'a Affine3A),
    Skinned {
        joints: &'a [Affine3A],
        node_world: &'a Affine3A,
    },
}

/// A placement and the morph targets' weights: what a node does to the mesh it shows.
#[derive(Clone, Copy)]
pub(super) struct MeshPose<'a> {
    pub placement: Placement<'a>,
    pub weights: &'a [f32],
}

/// Decodes mesh `index`, which must exist.
pub(super) fn decode(input: &Input, index: usize) -> Result<Mesh, SceneError> {
    let mut mesh = Mesh {
        primitives: Vec::new(),
        skipped_primitives: 0,
        warnings: Vec::new(),
        weights: input.root.meshes[index].weights.clone().unwrap_or_default(),
    };
    for (p, primitive) in input.root.meshes[index].primitives.iter().enumerate() {
        let label = format!("mesh {index} primitive {p}");
        let Some(mode) = triangle_mode(input, primitive, &label)? else {
            mesh.skipped_primitives += 1;
            continue;
        };
        let decoded = decode_primitive(input, primitive, p, &label)?;
        let (triangles, leftover) = assemble(mode, &decoded.corners);
        if leftover > 0 {
            mesh.warnings.push(format!(
                "{label}: {leftover} trailing indices do not make a triangle; ignored"
            ));
        }
        mesh.primitives.push(Primitive {
            triangles,
            ..decoded.primitive
        });
    }
    Ok(mesh)
}

/// How much a mesh places each time a node shows it.
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct Size {
    pub triangles: u64,
    /// Vertices transformed (all of each triangle primitive's, used or not).
    pub vertices: u64,
}

/// The size of mesh `index` (which must exist), from its accessors' counts, each accessor
/// checked against its buffer but not read: for the budget check before decoding.
pub(super) fn size(input: &Input, index: usize) -> Result<Size, SceneError> {
    let mut size = Size::default();
    for (p, primitive) in input.root.meshes[index].primitives.iter().enumerate() {
        let label = format!("mesh {index} primitive {p}");
        let Some(mode) = triangle_mode(input, primitive, &label)? else {
            continue;
        };
        let position = primitive
            .attributes
            .get(&Checked::Valid(Attribute::Positions));
        let Some(position) = position.map(|a| a.value()) else {
            return Err(input.error(format!("{label}: no POSITION attribute")));
        };
        let role = format!("POSITION of {label}");
        let vertices = accessors::count(input, position, Semantic::Position, &role)?;
        let corners = match primitive.indices {
            Some(i) => {
                let role = format!("indices of {label}");
                accessors::count(input, i.value(), Semantic::Indices, &role)?
            }
            None => vertices,
        };
        let triangles = match mode {
            Mode::Triangles => corners / 3,
            _ => corners.saturating_sub(2),
        };
        size.triangles += triangles as u64;
        size.vertices += vertices as u64;
    }
    Ok(size)
}

/// The primitive's mode if it makes triangles; `None` for points and lines.
fn triangle_mode(
    input: &Input,
    primitive: &json::mesh::Primitive,
    label: &str,
) -> Result<Option<Mode>, SceneError> {
    match primitive.mode {
        Checked::Valid(mode @ (Mode::Triangles | Mode::TriangleStrip | Mode::TriangleFan)) => {
            Ok(Some(mode))
        }
        Checked::Valid(_) => Ok(None),
        Checked::Invalid => Err(input.error(format!("{label}: invalid mode"))),
    }
}

struct Decoded {
    primitive: Primitive,
    /// The vertex indices in drawing order, before assembly into triangles.
    corners: Vec<u32>,
}

fn decode_primitive(
    input: &Input,
    primitive: &json::mesh::Primitive,
    index: usize,
    label: &str,
) -> Result<Decoded, SceneError> {
    let Attributes {
        positions,
        normals,
        uv_sets,
        tangents,
        influences,
    } = read_attributes(input, primitive, label)?;
    let targets = read_targets(input, primitive, label, positions.len())?;
    let corners = match primitive.indices {
        Some(i) => {
            let role = format!("indices of {label}");
            accessors::read_indices(input, i.value(), &role, positions.len())?
        }
        None => (0..positions.len() as u32).collect(),
    };
    let own = primitive.material.map(|m| m.value());
    let mapped = match input.variant {
        Some(variant) => super::variants::mapped_material(input, primitive, variant, label)?,
        None => None,
    };
    let material = mapped.or(own);
    if let Some(m) = material.filter(|&m| m >= input.root.materials.len()) {
        return Err(input.error(format!(
            "{label}: material {m} does not exist ({} materials)",
            input.root.materials.len()
        )));
    }
    let primitive = Primitive {
        index,
        positions,
        normals,
        uv_sets,
        tangents,
        triangles: Vec::new(),
        material,
        targets,
        influences,
    };
    Ok(Decoded { primitive, corners })
}

/// A primitive's vertex attributes, all of one length.
struct Attributes {
    positions: Vec<Vec3>,
    normals: Option<Vec<Vec3>>,
    uv_sets: Vec<Option<Vec<Vec2>>>,
    tangents: Option<Vec<Vec4>>,
    influences: Vec<Influences>,
}

/// POSITION, NORMAL, every TEXCOORD_n, TANGENT (where NORMAL is given) and every JOINTS_n
/// with its WEIGHTS_n, all of the same length, below 2^32 vertices.
fn read_attributes(
    input: &Input,
    primitive: &json::mesh::Primitive,
    label: &str,
) -> Result<Attributes, SceneError> {
    let attribute = |a: Attribute| {
        primitive
            .attributes
            .get(&Checked::Valid(a))
            .map(|i| i.value())
    };
    let role = |what: &str| format!("{what} of {label}");
    let Some(position) = attribute(Attribute::Positions) else {
        return Err(input.error(format!("{label}: no POSITION attribute")));
    };
    let positions = accessors::read_vec3(input, position, Semantic::Position, &role("POSITION"))?;
    let vertex_count = positions.len();
    if u32::try_from(vertex_count).is_err() {
        return Err(input.unsupported(format!("{label}: 2^32 vertices or more")));
    }
    let check_count = |name: &str, count: usize| {
        if count == vertex_count {
            return Ok(());
        }
        Err(input.error(format!(
            "{label}: {name} has {count} elements but POSITION has {vertex_count}"
        )))
    };
    let normals = attribute(Attribute::Normals)
        .map(|a| accessors::read_vec3(input, a, Semantic::Normal, &role("NORMAL")))
        .transpose()?;
    if let Some(n) = &normals {
        check_count("NORMAL", n.len())?;
    }
    let set_count = (primitive.attributes.keys())
        .filter_map(|key| match key {
            Checked::Valid(Attribute::TexCoords(n)) if (*n as usize) < MAX_UV_SETS => {
                Some(*n as usize + 1)
            }
            _ => None,
        })
        .max()
        .unwrap_or(0);
    let mut uv_sets = Vec::new();
    for n in 0..set_count {
        let name = format!("TEXCOORD_{n}");
        let uvs = attribute(Attribute::TexCoords(n as u32))
            .map(|a| accessors::read_texcoords(input, a, &role(&name)))
            .transpose()?;
        if let Some(uv) = &uvs {
            check_count(&name, uv.len())?;
        }
        uv_sets.push(uvs);
    }
    let tangents = attribute(Attribute::Tangents)
        .filter(|_| normals.is_some())
        .map(|a| accessors::read_vec4(input, a, Semantic::Tangent, &role("TANGENT")))
        .transpose()?;
    if let Some(t) = &tangents {
        check_count("TANGENT", t.len())?;
    }
    let mut influences = Vec::new();
    for n in 0.. {
        let (joints, weights) = (Attribute::Joints(n), Attribute::Weights(n));
        let (Some(joints), Some(weights)) = (attribute(joints), attribute(weights)) else {
            break;
        };
        let joints = accessors::read_joints(input, joints, &role(&format!("JOINTS_{n}")))?;
        check_count(&format!("JOINTS_{n}"), joints.len())?;
        let name = format!("WEIGHTS_{n}");
        let weights = accessors::read_vec4(input, weights, Semantic::Weights, &role(&name))?;
        check_count(&name, weights.len())?;
        influences.push(Influences { joints, weights });
    }
    Ok(Attributes {
        positions,
        normals,
        uv_sets,
        tangents,
        influences,
    })
}

/// The primitive's morph targets, each displacement of the same length as POSITION.
fn read_targets(
    input: &Input,
    primitive: &json::mesh::Primitive,
    label: &str,
    vertex_count: usize,
) -> Result<Vec<MorphTarget>, SceneError> {
    let targets = primitive.targets.as_deref().unwrap_or_default();
    let mut read = Vec::with_capacity(targets.len());
    for (t, target) in targets.iter().enumerate() {
        let displacements = |accessor: Option<json::Index<json::Accessor>>, what: &str| {
            let Some(accessor) = accessor else {
                return Ok(None);
            };
            let role = format!("morph target {t} {what} of {label}");
            let values =
                accessors::read_vec3(input, accessor.value(), Semantic::Displacement, &role)?;
            if values.len() != vertex_count {
                return Err(input.error(format!(
                    "{label}: morph target {t} {what} has {} elements but POSITION has \
                     {vertex_count}",
                    values.len()
                )));
            }
            Ok(Some(values))
        };
        read.push(MorphTarget {
            positions: displacements(target.positions, "POSITION")?,
            normals: displacements(target.normals, "NORMAL")?,
            tangents: displacements(target.tangents, "TANGENT")?,
        });
    }
    Ok(read)
}

/// Triangles from a list, strip or fan (glTF 2.0 §3.7.2.1 orders), and the count of corners
/// left over that make no triangle.
fn assemble(mode: Mode, corners: &[u32]) -> (Vec<[u32; 3]>, usize) {
    let c = corners;
    match mode {
        Mode::TriangleStrip => {
            let triangles = (0..c.len().saturating_sub(2))
                .map(|i| match i % 2 {
                    0 => [c[i], c[i + 1], c[i + 2]],
                    _ => [c[i], c[i + 2], c[i + 1]],
                })
                .collect();
            (triangles, 0)
        }
        Mode::TriangleFan => {
            let triangles = (1..c.len().saturating_sub(1))
                .map(|i| [c[i], c[i + 1], c[0]])
                .collect();
            (triangles, 0)
        }
        _ => {
            let triangles = c.chunks_exact(3).map(|t| [t[0], t[1], t[2]]).collect();
            (triangles, c.len() % 3)
        }
    }
}

impl Primitive {
    pub fn triangle_count(&self) -> usize {
        self.triangles.len()
    }

    /// Whether the primitive has TEXCOORD_`set`.
    pub fn has_uv_set(&self, set: usize) -> bool {
        self.uv_sets.get(set).is_some_and(Option::is_some)
    }

    /// The largest joint index a vertex gives a positive weight, if any: it must name one of
    /// the skin's joints.
    pub fn largest_joint(&self) -> Option<u32> {
        (self.influences.iter())
            .flat_map(|set| set.joints.iter().zip(&set.weights))
            .flat_map(|(joints, weights)| (0..4).filter(|&k| weights[k] > 0.0).map(|k| joints[k]))
            .max()
    }

    /// How many morph targets it has.
    pub fn target_count(&self) -> usize {
        self.targets.len()
    }

    /// Adds the primitive's triangles, in `pose`, to `builder`: the morph targets blended in
    /// first, then each vertex placed by its transform (the node's, or its skin's joints
    /// blended). Positions go through the transform, normals through its inverse transpose
    /// (then renormalised), tangents through its linear part; a triangle whose transform
    /// mirrors (at two of its vertices, for a skin) has two vertices swapped so its front face
    /// stays the front face. Missing normals are smoothed over the placed triangles.
    /// `uv_transform` is the material's `KHR_texture_transform`, applied to the texture
    /// coordinates here. Where the material `reads_frame` (a normal map or brushing) and the
    /// file gives no tangents, they are made from the texture coordinates
    /// ([`GeneratedTangents`]).
    pub fn instantiate(
        &self,
        pose: MeshPose,
        material: u32,
        (uv_set, uv_transform): (usize, Option<Affine2>),
        reads_frame: bool,
        builder: &mut SceneBuilder,
    ) -> Result<(), SceneError> {
        let set_uvs = self.uv_sets.get(uv_set).and_then(Option::as_ref);
        let morphed = self.morphed(pose.weights);
        let frames = self.vertex_frames(pose.placement);
        let positions: Vec<Vec3> = (morphed.positions.iter().enumerate())
            .map(|(i, &p)| frames.get(i).transform.transform_point3(p))
            .collect();
        let triangles: Cow<[[u32; 3]]> = match &frames {
            VertexFrames::One(frame) if frame.mirrored => {
                Cow::Owned(self.triangles.iter().map(|&[a, b, c]| [a, c, b]).collect())
            }
            VertexFrames::One(_) => Cow::Borrowed(&self.triangles),
            VertexFrames::Each(frames) => Cow::Owned(
                (self.triangles.iter())
                    .map(|&[a, b, c]| {
                        let mirrored = [a, b, c]
                            .iter()
                            .filter(|&&v| frames[v as usize].mirrored)
                            .count();
                        if mirrored >= 2 { [a, c, b] } else { [a, b, c] }
                    })
                    .collect(),
            ),
        };
        let normals = match &morphed.normals {
            Some(normals) => (normals.iter().enumerate())
                .map(|(i, &n)| (frames.get(i).normal_matrix * n).normalize_or_zero())
                .collect(),
            None => smooth_normals(&positions, &triangles),
        };
        let uvs: Vec<Vec2> = match set_uvs {
            Some(uvs) => (uvs.iter())
                .map(|&uv| uv_transform.map_or(uv, |t| t.transform_point2(uv)))
                .collect(),
            None => vec![Vec2::ZERO; positions.len()],
        };
        let generated = (reads_frame && morphed.tangents.is_none() && set_uvs.is_some())
            .then(|| GeneratedTangents::new(&positions, &normals, &uvs, &triangles));
        let vertex = |triangle: usize, i: u32| {
            let i = i as usize;
            let tangent = match (&morphed.tangents, &generated) {
                (Some(file), _) => {
                    let frame = frames.get(i);
                    placed_tangent(file[i], frame.linear, frame.mirrored)
                }
                (None, Some(made)) => made.at_corner(triangle, i),
                (None, None) => Vec4::ZERO,
            };
            Vertex {
                position: positions[i],
                normal: normals[i],
                uv: uvs[i],
                tangent,
            }
        };
        for (t, &[a, b, c]) in triangles.iter().enumerate() {
            builder.add_triangle(Triangle {
                vertices: [vertex(t, a), vertex(t, b), vertex(t, c)],
                material,
            })?;
        }
        Ok(())
    }

    /// The vertices' positions, normals and tangents with the morph targets blended in by
    /// `weights` (glTF: attribute + Σ weight · displacement; a target past the weights given
    /// weighs nothing).
    fn morphed(&self, weights: &[f32]) -> Morphed<'_> {
        let mut morphed = Morphed {
            positions: Cow::Borrowed(&self.positions),
            normals: self.normals.as_deref().map(Cow::Borrowed),
            tangents: self.tangents.as_deref().map(Cow::Borrowed),
        };
        for (target, &weight) in self.targets.iter().zip(weights) {
            if weight == 0.0 {
                continue;
            }
            let add = |values: &mut [Vec3], displacements: &[Vec3]| {
                for (v, &d) in values.iter_mut().zip(displacements) {
                    *v += weight * d;
                }
            };
            if let Some(d) = &target.positions {
                add(morphed.positions.to_mut(), d);
            }
            if let (Some(normals), Some(d)) = (&mut morphed.normals, &target.normals) {
                add(normals.to_mut(), d);
            }
            if let (Some(tangents), Some(d)) = (&mut morphed.tangents, &target.tangents) {
                for (t, &d) in tangents.to_mut().iter_mut().zip(d) {
                    *t += (weight * d).extend(0.0);
                }
            }
        }
        morphed
    }

    /// Each vertex's transform: the node's, or its skin's joints blended by its weights.
    fn vertex_frames(&self, placement: Placement) -> VertexFrames {
        match placement {
            Placement::Rigid(world) => VertexFrames::One(Frame::new(*world)),
            Placement::Skinned { node_world, .. } if self.influences.is_empty() => {
                VertexFrames::One(Frame::new(*node_world))
            }
            Placement::Skinned { joints, node_world } => VertexFrames::Each(
                (0..self.positions.len())
                    .map(|i| Frame::new(self.skinned(i, joints).unwrap_or(*node_world)))
                    .collect(),
            ),
        }
    }

    /// Vertex `i`'s joints blended by its weights (normalised to sum to one, as glTF asks of
    /// them), `None` where they are all zero. Every joint with a positive weight must exist
    /// ([`Primitive::largest_joint`]).
    fn skinned(&self, i: usize, joints: &[Affine3A]) -> Option<Affine3A> {
        let (mut matrix, mut translation, mut total) = (Mat3A::ZERO, Vec3A::ZERO, 0.0);
        for set in &self.influences {
            for k in 0..4 {
                let weight = set.weights[i][k];
                if weight > 0.0 {
                    let joint = &joints[set.joints[i][k] as usize];
                    matrix += joint.matrix3 * weight;
                    translation += joint.translation * weight;
                    total += weight;
                }
            }
        }
        (total > 0.0).then(|| Affine3A {
            matrix3: matrix * (1.0 / total),
            translation: translation * (1.0 / total),
        })
    }
}

/// A primitive's attributes after its morph targets.
struct Morphed<'a> {
    positions: Cow<'a, [Vec3]>,
    normals: Option<Cow<'a, [Vec3]>>,
    tangents: Option<Cow<'a, [Vec4]>>,
}

/// A vertex's transform, with what placing normals and tangents needs of it.
struct Frame {
    transform: Affine3A,
    linear: Mat3,
    mirrored: bool,
    normal_matrix: Mat3,
}

impl Frame {
    fn new(transform: Affine3A) -> Frame {
        let linear = Mat3::from(transform.matrix3);
        let mirrored = linear.determinant() < 0.0;
        Frame {
            transform,
            linear,
            mirrored,
            normal_matrix: normal_matrix(linear, mirrored),
        }
    }
}

/// One frame for all of a primitive's vertices, or one each (a skin).
enum VertexFrames {
    One(Frame),
    Each(Vec<Frame>),
}

impl VertexFrames {
    fn get(&self, i: usize) -> &Frame {
        match self {
            VertexFrames::One(frame) => frame,
            VertexFrames::Each(frames) => &frames[i],
        }
    }
}

/// Tangents where a file gives none (glTF asks for MikkTSpace's): at each vertex the
/// triangles' texture frames around it (their directions of increasing u and of the image's
/// top, `render::normal_map::texture_frame`'s), weighted by the corner's angle, summed; the
/// tangent is the u-direction made perpendicular to the vertex normal, its handedness the
/// one that puts w · normal × tangent towards the summed top. Smooth across triangles where
/// the coordinates are. As MikkTSpace does, a vertex is split at a mirror seam: the triangles
/// whose coordinates turn counter-clockwise and those whose turn clockwise each sum their own
/// frame there, so both sides of the seam stay smooth up to it. A vertex whose sum vanishes
/// gets none, and its triangles take their own texture frames there.
pub(super) struct GeneratedTangents {
    /// Per vertex, the tangent its counter-clockwise triangles share, then its clockwise
    /// ones' (zero where it has none of that turn).
    by_turn: Vec<[Vec4; 2]>,
    /// Per triangle, which of its vertices' two tangents it takes: 0 counter-clockwise, 1
    /// clockwise; a triangle of degenerate coordinates takes whichever its vertex has,
    /// counter-clockwise first (`None`).
    turn: Vec<Option<u8>>,
}

impl GeneratedTangents {
    pub(super) fn new(
        positions: &[Vec3],
        normals: &[Vec3],
        uvs: &[Vec2],
        triangles: &[[u32; 3]],
    ) -> GeneratedTangents {
        let mut along = vec![[Vec3::ZERO; 2]; positions.len()];
        let mut top = vec![[Vec3::ZERO; 2]; positions.len()];
        let mut turn = Vec::with_capacity(triangles.len());
        for &corners in triangles {
            let [a, b, c] = corners.map(|i| i as usize);
            let (e1, e2) = (positions[b] - positions[a], positions[c] - positions[a]);
            let (d1, d2) = (uvs[b] - uvs[a], uvs[c] - uvs[a]);
            let determinant = d1.x * d2.y - d2.x * d1.y;
            if determinant == 0.0 || !determinant.is_finite() {
                turn.push(None);
                continue;
            }
            let sign = determinant.signum();
            let side = usize::from(sign < 0.0);
            turn.push(Some(side as u8));
            let along_u = (sign * (e1 * d2.y - e2 * d1.y)).normalize_or_zero();
            let towards_top = (-sign * (e2 * d1.x - e1 * d2.x)).normalize_or_zero();
            for (k, &i) in [a, b, c].iter().enumerate() {
                let p = |j: usize| positions[[a, b, c][(k + j) % 3]];
                let angle = (p(1) - p(0)).angle_between(p(2) - p(0));
                if angle.is_finite() {
                    along[i][side] += angle * along_u;
                    top[i][side] += angle * towards_top;
                }
            }
        }
        let by_turn = (0..positions.len())
            .map(|i| [0, 1].map(|side| vertex_tangent(normals[i], along[i][side], top[i][side])))
            .collect();
        GeneratedTangents { by_turn, turn }
    }

    /// The tangent of `vertex` as a corner of `triangle` (zero: none).
    pub(super) fn at_corner(&self, triangle: usize, vertex: usize) -> Vec4 {
        let tangents = self.by_turn[vertex];
        let [ccw, cw] = tangents;
        match self.turn[triangle] {
            Some(side) => tangents[side as usize],
            None if ccw != Vec4::ZERO => ccw,
            None => cw,
        }
    }
}

/// The tangent of a vertex of normal `n` from its triangles' summed u-direction `along` and
/// image top `top`: `along` made perpendicular to `n`, the handedness putting w · n × tangent
/// towards `top`; zero where `along` vanishes there.
fn vertex_tangent(n: Vec3, along: Vec3, top: Vec3) -> Vec4 {
    let tangent = (along - n * n.dot(along)).normalize_or_zero();
    if tangent == Vec3::ZERO {
        return Vec4::ZERO;
    }
    let handedness = if n.cross(tangent).dot(top) < 0.0 {
        -1.0
    } else {
        1.0
    };
    tangent.extend(handedness)
}

/// A TANGENT placed by the linear part `m` of a node's transform: its direction through `m`,
/// its handedness turned where `m` mirrors (the bitangent, w · normal × tangent, must stay
/// the image of the file's). Zero (none) where it is not finite or vanishes.
fn placed_tangent(tangent: Vec4, m: Mat3, mirrored: bool) -> Vec4 {
    let direction = (m * tangent.truncate()).normalize_or_zero();
    if !tangent.is_finite() || direction == Vec3::ZERO {
        return Vec4::ZERO;
    }
    let handedness = if (tangent.w < 0.0) != mirrored {
        -1.0
    } else {
        1.0
    };
    direction.extend(handedness)
}

/// The inverse transpose of `m` up to a positive factor, defined even when `m` is singular:
/// its cofactor matrix (det·m⁻ᵀ), negated when `m` mirrors so normals keep their side.
fn normal_matrix(m: Mat3, mirrored: bool) -> Mat3 {
    let [c0, c1, c2] = [m.x_axis, m.y_axis, m.z_axis];
    let cofactor = Mat3::from_cols(c1.cross(c2), c2.cross(c0), c0.cross(c1));
    if mirrored { -cofactor } else { cofactor }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn strips_and_fans_keep_the_first_triangles_orientation() {
        let (strip, _) = assemble(Mode::TriangleStrip, &[0, 1, 2, 3, 4]);
        assert_eq!(strip, vec![[0, 1, 2], [1, 3, 2], [2, 3, 4]]);
        let (fan, _) = assemble(Mode::TriangleFan, &[0, 1, 2, 3]);
        assert_eq!(fan, vec![[1, 2, 0], [2, 3, 0]]);
        let (list, leftover) = assemble(Mode::Triangles, &[0, 1, 2, 3]);
        assert_eq!((list, leftover), (vec![[0, 1, 2]], 1));
        assert!(assemble(Mode::TriangleStrip, &[0, 1]).0.is_empty());
    }

    #[test]
    fn normal_matrix_is_the_inverse_transpose_up_to_scale() {
        let m = Mat3::from_cols_array(&[2.0, 0.5, 0.0, 0.0, 3.0, 1.0, 1.0, 0.0, -4.0]);
        let mirrored = m.determinant() < 0.0;
        let expected = m.inverse().transpose();
        let got = normal_matrix(m, mirrored);
        for n in [Vec3::X, Vec3::Y, Vec3::new(1.0, -2.0, 0.5)] {
            let (a, b) = ((expected * n).normalize(), (got * n).normalize());
            assert!(a.abs_diff_eq(b, 1e-5), "{a} vs {b}");
        }
    }
}
