//! kousen's scene model and loaders.
//!
//! A scene is a triangle soup (every triangle carries its three vertices and a material
//! index), the uber-materials it refers to, their textures, the cameras the file defines and
//! the list of emissive triangles. Loaders validate what they read before trusting it: scene
//! files come from anywhere, and a malformed one must end in a [`SceneError`], never a panic.
//!
//! The layout mirrors what the GPU wants later: a soup (not an indexed mesh) because the
//! packed BVH stores each triangle's three vertices next to each other, as the talk does.

pub mod builder;
pub mod camera;
pub mod error;
mod files;
pub mod gltf;
pub mod lights;
mod mapped;
pub mod material;
mod media;
pub mod mesh;
pub mod mitsuba;
pub mod model;
pub mod obj;
pub mod pbrt;
mod ply;
mod shapes;
pub mod sky_map;
pub mod testing;
pub mod textures;

pub use builder::SceneBuilder;
pub use camera::{Camera, Lens, Projection};
pub use error::SceneError;
pub use gltf::AnimationTime;
pub use lights::{
    EmissiveTriangle, Lights, PunctualEmitter, PunctualKind, PunctualLight, Sky, SpotFalloff,
};
pub use material::{
    AlphaMode, Anisotropy, Blend, Clearcoat, DIFFUSE_MIN_ROUGHNESS, DiffuseTransmission,
    Iridescence, MAX_BLEND_MEMBERS, MIN_BRUSHED_ALPHA, MIRROR_MAX_ROUGHNESS, Material,
    RoughnessMap, Sheen, SpecularLayer, Surface, TextureRoughness, TexturedLobe,
    absorption_from_attenuation, blend_members, brushed_metal_surface, coated_surface,
    dispersion_from_abbe, glass_surface, metal_surface, single_scatter_albedo,
};
pub use media::Medium;
pub use model::{AnimationClip, Bounds, Scene, Triangle, Vertex};
pub use sky_map::SkyMap;
pub use textures::{Texels, Texture, TextureId};

use std::path::Path;

/// Loads a scene, choosing the loader by the file's extension (`.gltf`, `.glb`, `.obj`,
/// Mitsuba's `.xml`, pbrt's `.pbrt`).
pub fn load(path: &Path) -> Result<Scene, SceneError> {
    load_with(path, &LoadOptions::default())
}

/// What of a glTF file to load beyond its default: a moment of one of its animations, one of
/// its material variants.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct LoadOptions {
    /// Pose the scene as this animation shows it then (`gltf::AnimationTime`).
    pub animation: Option<AnimationTime>,
    /// Dress it in this variant (`KHR_materials_variants`): its index or name.
    pub variant: Option<String>,
}

impl LoadOptions {
    /// The index, among `scene`'s animations, of the one these options pose it by (`None`:
    /// unposed, or no such animation).
    pub fn animation_index(&self, scene: &Scene) -> Option<usize> {
        let choice = self.animation.as_ref()?.animation.as_deref().unwrap_or("0");
        let names: Vec<Option<&str>> = scene.animations.iter().map(|a| a.name.as_deref()).collect();
        gltf::index_or_name("animation", choice, &names).ok()
    }

    /// The index, among `scene`'s material variants, of the one these options dress it in.
    pub fn variant_index(&self, scene: &Scene) -> Option<usize> {
        let names: Vec<Option<&str>> = scene.variants.iter().map(|v| Some(v.as_str())).collect();
        gltf::index_or_name("material variant", self.variant.as_deref()?, &names).ok()
    }
}

/// [`load`] with `options` (an OBJ file has neither animations nor variants: asking for one
/// is refused).
pub fn load_with(path: &Path, options: &LoadOptions) -> Result<Scene, SceneError> {
    let extension = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    // pbrt reads its scenes gzipped too.
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().to_ascii_lowercase());
    let extension = match name {
        Some(name) if name.ends_with(".pbrt.gz") => Some("pbrt".to_string()),
        _ => extension,
    };
    match extension.as_deref() {
        Some("gltf") | Some("glb") => gltf::load_with(path, options),
        Some("obj") if options != &LoadOptions::default() => Err(SceneError::format(
            path,
            "an OBJ file has no animations or material variants to choose from",
        )),
        Some("obj") => obj::load(path),
        Some("xml") if options != &LoadOptions::default() => Err(SceneError::format(
            path,
            "a Mitsuba scene has no animations or material variants to choose from",
        )),
        Some("xml") => mitsuba::load(path),
        Some("pbrt") if options != &LoadOptions::default() => Err(SceneError::format(
            path,
            "a pbrt scene has no animations or material variants to choose from",
        )),
        Some("pbrt") => pbrt::load(path),
        _ => Err(SceneError::format(
            path,
            "unknown scene format (expected .gltf, .glb, .obj, a Mitsuba .xml or a .pbrt)",
        )),
    }
}
