//! The images materials name: decoded once each (in parallel, while `tobj` parses the
//! geometry), `map_d` masks merged into the base colour's alpha, then handed to the builder.

use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::Mutex;
use std::sync::atomic::{AtomicUsize, Ordering};

use super::material::Plan;
use crate::textures::{has_alpha, with_mask};
use crate::{AlphaMode, SceneBuilder, Texture, TextureId};

/// Decoded images by path; the error is a one-line reason naming the file.
pub(super) type Decoded = HashMap<PathBuf, Result<Texture, String>>;

/// Every distinct image the plans name, in first-use order.
pub(super) fn image_paths(plans: &[Plan]) -> Vec<PathBuf> {
    let mut seen = std::collections::HashSet::new();
    plans
        .iter()
        .flat_map(|p| [&p.base_color_map, &p.mask_map, &p.emission_map])
        .flatten()
        .filter(|path| seen.insert(*path))
        .cloned()
        .collect()
}

/// Decodes the images (as sRGB colour) on `threads` threads.
pub(super) fn decode_all(paths: &[PathBuf], threads: usize) -> Decoded {
    let next = AtomicUsize::new(0);
    let results = Mutex::new(Decoded::new());
    std::thread::scope(|scope| {
        for _ in 0..threads.clamp(1, paths.len().max(1)) {
            scope.spawn(|| {
                while let Some(path) = paths.get(next.fetch_add(1, Ordering::Relaxed)) {
                    let decoded = decode(path);
                    results.lock().unwrap().insert(path.clone(), decoded);
                }
            });
        }
    });
    results.into_inner().unwrap()
}

/// Reads and decodes one image as sRGB colour; the error names the file.
fn decode(path: &Path) -> Result<Texture, String> {
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy())
        .unwrap_or_default();
    let decode_error = |reason| crate::SceneError::format(path, reason);
    Texture::read_file(path, &name, true, decode_error).map_err(|e| e.to_string())
}

/// A texture the builder will hold: a decoded file, or a base colour with a merged mask.
#[derive(Clone, PartialEq, Eq, Hash)]
enum Source {
    File(PathBuf),
    Masked {
        base: Option<PathBuf>,
        mask: PathBuf,
    },
}

/// Which textures a material ends up with: decoded paths and the mask's source.
struct Resolved {
    base: Option<PathBuf>,
    mask: Option<Source>,
    emission: Option<PathBuf>,
}

/// Adds each plan's material to the builder with its textures; returns the material indices.
/// A texture that failed to decode is a warning: the material keeps its constant colour.
pub(super) fn add_materials(
    plans: Vec<Plan>,
    decoded: Decoded,
    builder: &mut SceneBuilder,
) -> Vec<u32> {
    let (resolved, merged) = resolve(&plans, &decoded, builder);
    let mut textures = Textures {
        ids: HashMap::new(),
        decoded,
        merged,
    };
    let mut indices = Vec::with_capacity(plans.len());
    for (
        plan,
        Resolved {
            base,
            mask,
            emission,
        },
    ) in plans.into_iter().zip(resolved)
    {
        let mut material = plan.material;
        if mask.is_none() {
            // No `map_d`, or its image failed to decode (a warning already).
            material.alpha_mode = AlphaMode::Opaque;
        }
        if let Some(source) = mask.or(base.clone().map(Source::File)) {
            material.base_color_texture = Some(textures.id(source, builder));
        }
        if base.is_some() {
            // The map replaces Kd (see the module manual).
            material.base_color = glam::Vec3::ONE;
        }
        if let Some(path) = emission {
            material.emission_texture = Some(textures.id(Source::File(path), builder));
        }
        indices.push(if plan.members.is_empty() {
            builder.add_material(material)
        } else {
            builder.add_blend(material, &plan.members)
        });
    }
    indices
}

/// Decides each material's textures (warning about those that failed to decode) and builds
/// the merged base-colour-and-mask images, each once.
fn resolve(
    plans: &[Plan],
    decoded: &Decoded,
    builder: &mut SceneBuilder,
) -> (Vec<Resolved>, HashMap<Source, Texture>) {
    let mut merged = HashMap::new();
    let resolved = plans
        .iter()
        .map(|plan| {
            let name = &plan.material.name;
            let base = usable(decoded, &plan.base_color_map, name, "map_Kd", builder);
            let emission = usable(decoded, &plan.emission_map, name, "map_Ke", builder);
            let mask = usable(decoded, &plan.mask_map, name, "map_d", builder).map(|mask| {
                let base_texture = base.as_ref().and_then(|b| decoded[b].as_ref().ok());
                if base.as_ref() == Some(&mask) && base_texture.is_some_and(has_alpha) {
                    return Source::File(mask);
                }
                let source = Source::Masked {
                    base: base.clone(),
                    mask: mask.clone(),
                };
                if let (false, Ok(mask_texture)) = (merged.contains_key(&source), &decoded[&mask]) {
                    merged.insert(source.clone(), with_mask(base_texture, mask_texture));
                }
                source
            });
            Resolved {
                base,
                mask,
                emission,
            }
        })
        .collect();
    (resolved, merged)
}

/// Hands each texture to the builder once, remembering its id.
struct Textures {
    ids: HashMap<Source, TextureId>,
    decoded: Decoded,
    merged: HashMap<Source, Texture>,
}

impl Textures {
    fn id(&mut self, source: Source, builder: &mut SceneBuilder) -> TextureId {
        if let Some(&id) = self.ids.get(&source) {
            return id;
        }
        let texture = match &source {
            Source::File(path) => self.decoded.remove(path).and_then(Result::ok),
            Source::Masked { .. } => self.merged.remove(&source),
        };
        let id = builder.add_texture(texture.expect("a resolved source has a texture"));
        self.ids.insert(source, id);
        id
    }
}

/// The path when its image decoded; a warning naming the file otherwise.
fn usable(
    decoded: &Decoded,
    path: &Option<PathBuf>,
    material: &str,
    key: &str,
    builder: &mut SceneBuilder,
) -> Option<PathBuf> {
    let path = path.as_ref()?;
    match &decoded[path] {
        Ok(_) => Some(path.clone()),
        Err(reason) => {
            let fallback = match key {
                "map_Kd" => "keeps its Kd colour",
                "map_d" => "rendered opaque",
                _ => "keeps its Ke emission",
            };
            builder.warn(format!("material '{material}': {key} {reason}; {fallback}"));
            None
        }
    }
}
