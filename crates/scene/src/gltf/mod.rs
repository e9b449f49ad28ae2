//! glTF 2.0 loader: `.gltf` (external `.bin` files or base64 data URIs) and `.glb`.
//!
//! What is read: the default scene's node hierarchy (`scene`, else the first scene, else every
//! root node) with matrix or TRS transforms; every TRIANGLES, TRIANGLE_STRIP and TRIANGLE_FAN
//! primitive with POSITION, NORMAL (smoothed, area-weighted, when absent) and the texture
//! coordinates its material's textures use (one set a material: TEXCOORD_0 to TEXCOORD_7, that
//! of its base colour texture, else of its emissive, normal or metallic-roughness texture),
//! indexed by u8/u16/u32 or not at all; morph targets, weighted by the node's `weights` or
//! the mesh's; skins, in the pose the nodes give their joints (`skins`); animations, sampled
//! at a moment where [`load_with`] is asked to (`animation`); material variants
//! (`KHR_materials_variants`, `variants`), the one asked for; accessors without a buffer view
//! (zeros) and sparse ones; perspective and orthographic cameras in traversal order; materials as [`materials`] describes; point, spot and directional lights
//! on nodes (`KHR_lights_punctual`): at the node's world origin, shining down its world −Z, with
//! intensity = `color` (in [0, 1]) × `intensity` (≥ 0; candela, or lux for directional ones)
//! and a spot's cone angles `0 ≤ innerConeAngle < outerConeAngle ≤ π/2`; the extensions in
//! [`SUPPORTED_EXTENSIONS`]. Skipped with a warning: point and line primitives, orthographic
//! cameras, spot and directional lights whose node's transform leaves no direction (a zero
//! scale), and every optional extension not supported. Ignored with one warning: lights'
//! `range` (kousen's lights fall off with the inverse square of distance, however far),
//! instances (`EXT_mesh_gpu_instancing`) of a skinned mesh. Refused: a required extension not
//! supported, URIs other than relative paths and data URIs.
//!
//! Files come from anywhere (DESIGN.md, "Loader robustness"). The `gltf` crate is used only to
//! deserialise the JSON; its validation and readers are not (its validation indexes arrays
//! unchecked, its readers panic on unexpected types). Instead every reference is checked
//! where it is followed, every accessor against its view and buffer, every buffer against
//! the bytes really there, the node graph for cycles and shared children before it is walked
//! (with a stack, not recursion), and values against the spec's ranges. Each error is one line
//! saying what is wrong where.

mod accessors;
mod animation;
mod buffers;
mod cameras;
mod container;
mod instancing;
mod lights;
pub mod materials;
mod meshes;
mod meshopt;
mod nodes;
mod skins;
mod spec_gloss;
mod uri;
mod variants;

use std::fmt::Display;
use std::path::Path;
use std::rc::Rc;

use glam::Affine3A;

use ::gltf::json;

use crate::{LoadOptions, Scene, SceneBuilder, SceneError};
pub use animation::AnimationTime;
use buffers::Buffers;
use materials::Materials;
use meshes::{Mesh, MeshPose, Placement};

/// Extensions read (and so accepted in `extensionsRequired`).
pub const SUPPORTED_EXTENSIONS: [&str; 22] = [
    "EXT_mesh_gpu_instancing",
    "EXT_meshopt_compression",
    "EXT_texture_webp",
    "KHR_lights_punctual",
    "KHR_materials_anisotropy",
    "KHR_materials_clearcoat",
    "KHR_materials_diffuse_transmission",
    "KHR_materials_dispersion",
    "KHR_materials_emissive_strength",
    "KHR_materials_transmission",
    "KHR_materials_ior",
    "KHR_materials_iridescence",
    "KHR_materials_pbrSpecularGlossiness",
    "KHR_materials_sheen",
    "KHR_materials_specular",
    "KHR_materials_unlit",
    "KHR_materials_variants",
    "KHR_materials_volume",
    "KHR_materials_volume_scatter",
    "KHR_mesh_quantization",
    "KHR_meshopt_compression",
    "KHR_texture_transform",
];

/// The most triangles a file may place in the world (and a third of the most vertices it may
/// transform). Instancing multiplies a mesh by every node that uses it, so a few kilobytes
/// could otherwise ask for terabytes; 2^26 triangles (about 6.4 GiB as a [`Scene`]) is far
/// beyond the scenes kousen is for.
pub const MAX_TRIANGLES: usize = 1 << 26;

/// Loads a `.gltf` or `.glb` file (told apart by their content).
pub fn load(path: &Path) -> Result<Scene, SceneError> {
    load_with(path, &LoadOptions::default())
}

/// [`load`], posed as `options.animation` shows the scene at its moment where given
/// ([`AnimationTime`]), else as its nodes place things, and dressed in `options.variant`
/// where given.
pub fn load_with(path: &Path, options: &LoadOptions) -> Result<Scene, SceneError> {
    let container = container::read(path)?;
    let root = &container.root;
    check_version(path, &root.asset)?;
    let mut builder = SceneBuilder::new(path);
    check_extensions(&mut builder, root)?;
    let mut input = Input {
        path,
        root,
        buffers: Buffers::new(path, root, container.bin_chunk()),
        pose: animation::Pose::default(),
        variant: None,
    };
    if let Some(time) = &options.animation {
        nodes::scene_roots(&input)?;
        input.pose = animation::pose_at(&input, time)?;
    }
    for clip in animation::clips(&input) {
        builder.add_animation(clip);
    }
    let variant_names = variants::names(&input)?;
    if let Some(choice) = &options.variant {
        input.variant = Some(variants::chosen(&input, &variant_names, choice)?);
    }
    builder.set_variants(variant_names);
    let roots = nodes::scene_roots(&input)?;
    check_budget(&input, &roots)?;
    let mut loader = Loader {
        input: &input,
        builder,
        materials: Materials::new(root),
        meshes: root.meshes.iter().map(|_| None).collect(),
        skins: root.skins.iter().map(|_| None).collect(),
        worlds: None,
        triangles_placed: 0,
        skipped_primitives: 0,
        warned_light_range: false,
        warnings_given: Vec::new(),
    };
    nodes::walk(&input, &roots, |index, world| loader.visit(index, world))?;
    loader.finish()
}

/// The parsed document, what every part of the loader reads from.
pub(super) struct Input<'a> {
    /// The glTF file, named in errors.
    path: &'a Path,
    root: &'a json::Root,
    buffers: Buffers<'a>,
    /// What the chosen animation sets on the nodes (nothing without one).
    pose: animation::Pose,
    /// The material variant chosen (`KHR_materials_variants`), by index.
    variant: Option<usize>,
}

impl Input<'_> {
    fn error(&self, message: impl Into<String>) -> SceneError {
        SceneError::format(self.path, message)
    }

    fn unsupported(&self, message: impl Into<String>) -> SceneError {
        SceneError::unsupported(self.path, message)
    }

    /// Whether the file lists `name` in `extensionsUsed`.
    fn uses_extension(&self, name: &str) -> bool {
        self.root.extensions_used.iter().any(|used| used == name)
    }
}

/// Prefixes an error's message with where it happened (`accessor 3 (indices of ...): ...`).
trait Context<T> {
    fn context<D: Display>(self, what: impl FnOnce() -> D) -> Result<T, SceneError>;
}

impl<T> Context<T> for Result<T, SceneError> {
    fn context<D: Display>(self, what: impl FnOnce() -> D) -> Result<T, SceneError> {
        self.map_err(|error| match error {
            SceneError::Format { path, message } => SceneError::Format {
                path,
                message: format!("{}: {message}", what()),
            },
            SceneError::Unsupported { path, message } => SceneError::Unsupported {
                path,
                message: format!("{}: {message}", what()),
            },
            SceneError::Io { path, error } => SceneError::Io {
                path,
                error: std::io::Error::new(error.kind(), format!("{}: {error}", what())),
            },
            other => other,
        })
    }
}

/// A name from the file, fit for a one-line message.
fn quoted(name: &str) -> String {
    const MAX_CHARS: usize = 64;
    let escaped: String = name.escape_debug().take(MAX_CHARS).collect();
    if name.escape_debug().count() > MAX_CHARS {
        format!("\"{escaped}...\"")
    } else {
        format!("\"{escaped}\"")
    }
}

/// `asset.version` must be 2.x, and `asset.minVersion` (if any) at most 2.0.
fn check_version(path: &Path, asset: &json::Asset) -> Result<(), SceneError> {
    let parse = |v: &str| {
        let (major, minor) = v.split_once('.')?;
        Some((major.parse::<u32>().ok()?, minor.parse::<u32>().ok()?))
    };
    if parse(&asset.version).is_none_or(|(major, _)| major != 2) {
        return Err(SceneError::unsupported(
            path,
            format!(
                "glTF version {} is not supported (expected 2.x)",
                quoted(&asset.version)
            ),
        ));
    }
    let min_version = asset.min_version.as_deref();
    if let Some(min) = min_version.filter(|min| parse(min).is_none_or(|v| v > (2, 0))) {
        return Err(SceneError::unsupported(
            path,
            format!("the file requires glTF {} (kousen reads 2.0)", quoted(min)),
        ));
    }
    Ok(())
}

/// Refuses a required extension not supported; warns once about used ones that are ignored.
fn check_extensions(builder: &mut SceneBuilder, root: &json::Root) -> Result<(), SceneError> {
    let unsupported = |names: &[String]| {
        let mut names: Vec<String> = names
            .iter()
            .filter(|n| !SUPPORTED_EXTENSIONS.contains(&n.as_str()))
            .map(|n| quoted(n))
            .collect();
        names.sort();
        names.dedup();
        names.join(", ")
    };
    let required = unsupported(&root.extensions_required);
    if !required.is_empty() {
        return Err(SceneError::unsupported(
            builder.path(),
            format!("requires unsupported glTF extension(s) {required}"),
        ));
    }
    let ignored = unsupported(&root.extensions_used);
    if !ignored.is_empty() {
        builder.warn(format!("ignoring unsupported glTF extension(s) {ignored}"));
    }
    Ok(())
}

/// Refuses a scene that would place more than [`MAX_TRIANGLES`] triangles, or transform
/// more than three vertices per triangle that many times, before anything is built: each
/// mesh's size (from checked accessor counts) × the nodes showing it.
fn check_budget(input: &Input, roots: &[usize]) -> Result<(), SceneError> {
    let root = input.root;
    let mut instances = vec![0u64; root.meshes.len()];
    for node in nodes::in_walk_order(input, roots) {
        if let Some(mesh) = root.nodes[node].mesh {
            let Some(count) = instances.get_mut(mesh.value()) else {
                return Err(missing_mesh(input, node, mesh.value()));
            };
            *count = count.saturating_add(instancing::instance_count(input, node)?);
        }
    }
    let (mut triangles, mut vertices) = (0u64, 0u64);
    for (mesh, &count) in instances.iter().enumerate().filter(|(_, c)| **c > 0) {
        let size = meshes::size(input, mesh)?;
        triangles = triangles.saturating_add(size.triangles.saturating_mul(count));
        vertices = vertices.saturating_add(size.vertices.saturating_mul(count));
    }
    let max = MAX_TRIANGLES as u64;
    for (what, planned, limit) in [
        ("triangles", triangles, max),
        ("vertices", vertices, 3 * max),
    ] {
        if planned > limit {
            return Err(input.unsupported(format!(
                "the scene would place {planned} {what}, more than the {limit} supported"
            )));
        }
    }
    Ok(())
}

fn missing_mesh(input: &Input, node: usize, mesh: usize) -> SceneError {
    input.error(format!(
        "node {node}: mesh {mesh} does not exist ({} meshes)",
        input.root.meshes.len()
    ))
}

/// The index of the item `choice` names among items of `names` (each its name, if it has
/// one): by index, else by name; else a line saying there is no such `what`, listing them.
pub(crate) fn index_or_name(
    what: &str,
    choice: &str,
    names: &[Option<&str>],
) -> Result<usize, String> {
    let by_index = choice.parse::<usize>().ok().filter(|&i| i < names.len());
    if let Some(index) = by_index.or_else(|| names.iter().position(|n| *n == Some(choice))) {
        return Ok(index);
    }
    let listed: Vec<String> = (names.iter().enumerate())
        .map(|(i, name)| match name {
            Some(name) => format!("{i} \"{name}\""),
            None => i.to_string(),
        })
        .collect();
    Err(match listed.is_empty() {
        true => format!("no {what} \"{choice}\": the file has none"),
        false => format!(
            "no {what} \"{choice}\" (the file has {})",
            listed.join(", ")
        ),
    })
}

/// Gives `warning` unless `given` holds it already.
fn warn_once(given: &mut Vec<&'static str>, builder: &mut SceneBuilder, warning: &'static str) {
    if !given.contains(&warning) {
        given.push(warning);
        builder.warn(warning);
    }
}

/// Walks the nodes into the builder.
struct Loader<'a> {
    input: &'a Input<'a>,
    builder: SceneBuilder,
    materials: Materials,
    /// Each glTF mesh, once decoded.
    meshes: Vec<Option<Mesh>>,
    /// Each skin's joint transforms, once made.
    skins: Vec<Option<Rc<[Affine3A]>>>,
    /// Every node's world transform, made when the first skin needs its joints'.
    worlds: Option<Vec<Affine3A>>,
    /// Triangles placed so far, degenerate ones included.
    triangles_placed: usize,
    skipped_primitives: usize,
    /// Whether the warning that lights' `range` is ignored was given.
    warned_light_range: bool,
    /// Warnings given once a file, already given.
    warnings_given: Vec<&'static str>,
}

impl Loader<'_> {
    fn visit(&mut self, index: usize, world: &Affine3A) -> Result<(), SceneError> {
        let node = &self.input.root.nodes[index];
        if let Some(camera) = node.camera {
            cameras::place(self.input, &mut self.builder, index, camera.value(), world)?;
        }
        if let Some(light) = node
            .extensions
            .as_ref()
            .and_then(|e| e.khr_lights_punctual.as_ref())
        {
            let light = light.light.value();
            let warned = &mut self.warned_light_range;
            lights::place(self.input, &mut self.builder, index, light, world, warned)?;
        }
        let Some(mesh) = node.mesh else {
            return Ok(());
        };
        let animated = self
            .input
            .pose
            .node(index)
            .and_then(|p| p.weights.as_deref());
        let weights = animated.or(node.weights.as_deref());
        if let Some(skin) = node.skin {
            let skin = skin.value();
            let joints = self.skin_joints(index, skin)?;
            if instancing::instances(self.input, index)?.is_some() {
                warn_once(
                    &mut self.warnings_given,
                    &mut self.builder,
                    "instances of a skinned mesh are ignored: it is drawn once, where its \
                     joints hold it",
                );
            }
            let placement = Placement::Skinned {
                joints: &joints,
                node_world: world,
            };
            return self.mesh(index, mesh.value(), placement, weights, Some(skin));
        }
        match instancing::instances(self.input, index)? {
            Some(instances) => {
                for instance in instances {
                    let placed = *world * instance;
                    self.mesh(
                        index,
                        mesh.value(),
                        Placement::Rigid(&placed),
                        weights,
                        None,
                    )?;
                }
            }
            None => self.mesh(index, mesh.value(), Placement::Rigid(world), weights, None)?,
        }
        Ok(())
    }

    /// Skin `skin`'s joint transforms (node `node` shows a mesh with it), made once.
    fn skin_joints(&mut self, node: usize, skin: usize) -> Result<Rc<[Affine3A]>, SceneError> {
        let Some(slot) = self.skins.get(skin) else {
            return Err(self.input.error(format!(
                "node {node}: skin {skin} does not exist ({} skins)",
                self.skins.len()
            )));
        };
        if let Some(joints) = slot {
            return Ok(joints.clone());
        }
        if self.worlds.is_none() {
            self.worlds = Some(nodes::world_transforms(self.input)?);
        }
        let worlds = self.worlds.as_deref().unwrap_or_default();
        let joints: Rc<[Affine3A]> = skins::joint_transforms(self.input, skin, worlds)?.into();
        self.skins[skin] = Some(joints.clone());
        Ok(joints)
    }

    /// Places mesh `index` as node `node` shows it: by `placement`, its morph targets weighted
    /// by the node's `weights` (else the mesh's); `skin` names the skin a skinned placement's
    /// joints come from, for messages.
    fn mesh(
        &mut self,
        node: usize,
        index: usize,
        placement: Placement,
        weights: Option<&[f32]>,
        skin: Option<usize>,
    ) -> Result<(), SceneError> {
        let Self {
            input,
            builder,
            materials,
            meshes,
            triangles_placed,
            skipped_primitives,
            warnings_given,
            ..
        } = self;
        let Some(slot) = meshes.get_mut(index) else {
            return Err(missing_mesh(input, node, index));
        };
        if slot.is_none() {
            let decoded = meshes::decode(input, index)?;
            for warning in &decoded.warnings {
                builder.warn(warning.clone());
            }
            *skipped_primitives += decoded.skipped_primitives;
            *slot = Some(decoded);
        }
        let Some(mesh) = slot.as_ref() else {
            return Ok(());
        };
        let weights = weights.unwrap_or(&mesh.weights);
        for primitive in &mesh.primitives {
            let targets = primitive.target_count();
            if targets > 0 && weights.len() != targets {
                warn_once(
                    warnings_given,
                    builder,
                    "a mesh's morph target weights do not match its targets in number: \
                     the targets past the weights weigh nothing",
                );
            }
            if let (Placement::Skinned { joints, .. }, Some(skin)) = (placement, skin) {
                if let Some(joint) = primitive.largest_joint() {
                    if joint as usize >= joints.len() {
                        return Err(input.error(format!(
                            "node {node}: mesh {index} primitive {} names joint {joint} of skin \
                             {skin}, which has {} joints",
                            primitive.index,
                            joints.len()
                        )));
                    }
                } else {
                    warn_once(
                        warnings_given,
                        builder,
                        "a skinned mesh's primitive has no JOINTS_0 and WEIGHTS_0: it is \
                         placed by its node's transform",
                    );
                }
            }
            let material = materials.id(input, builder, primitive.material)?;
            let uv_transform = materials.uv_transform(primitive.material);
            let uv_set = materials.uv_set(primitive.material);
            if uv_set != 0 && !primitive.has_uv_set(uv_set) {
                builder.warn(format!(
                    "mesh {index} primitive {} has no TEXCOORD_{uv_set}, which its material's \
                     textures use: they read (0, 0)",
                    primitive.index
                ));
            }
            *triangles_placed += primitive.triangle_count();
            let reads_frame = crate::blend_members(builder.materials(), material)
                .any(|m| builder.materials()[m as usize].reads_tangent_frame());
            primitive
                .instantiate(
                    MeshPose { placement, weights },
                    material,
                    (uv_set, uv_transform),
                    reads_frame,
                    builder,
                )
                .context(|| format!("mesh {index} primitive {} (node {node})", primitive.index))?;
        }
        Ok(())
    }

    fn finish(mut self) -> Result<Scene, SceneError> {
        let skipped = self.skipped_primitives;
        if skipped > 0 {
            self.builder
                .warn(format!("skipped {skipped} point or line primitive(s)"));
        }
        if self.triangles_placed == 0 && skipped > 0 {
            return Err(SceneError::NoTriangles {
                path: self.builder.path().to_path_buf(),
                detail: format!(" (only point or line primitives: {skipped} skipped)"),
            });
        }
        self.builder.finish()
    }
}
