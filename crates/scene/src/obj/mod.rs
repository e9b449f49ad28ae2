//! Wavefront OBJ + MTL loader, through `tobj`.
//!
//! # How a file maps onto the scene
//! - **Geometry.** Polygons are fan-triangulated (`tobj`, `triangulate`); faces with one or two
//!   vertices and `l` polylines are ignored with a warning. Face indices are checked before
//!   parsing (`scan`): out of range is a [`SceneError::Format`] naming the line. Normals come
//!   from `vn` when every face of an object has them, else area-weighted smooth normals over
//!   the object's distinct positions. Texture coordinates come from `vt` (v flipped: OBJ's
//!   v = 0 is the image's bottom row, the scene's is its top row), else zero. Zero-area
//!   triangles are dropped and counted ([`crate::Scene::degenerate_dropped`]).
//! - **Materials** (MTL, relative to the OBJ; textures relative to the MTL):
//!   - `illum` 3 and 5 → [`Surface::Mirror`], reflectance `Ks` if not black, else `Kd` if not
//!     black, else white (both are used by exporters for the mirror colour); 3 reflects it at
//!     every angle, 5 ("Fresnel on") rises to white at grazing angles as glTF's metals
//!     (`Material::metal_edge`);
//!   - `illum` 4, 6, 7 → solid [`Surface::Dielectric`] with ior `Ni` (missing or below 1 →
//!     1.5 with a warning), transmittance tint `Tf` if given, else white;
//!   - anything else → glTF's metal and dielectric: roughness from the PBR extension's `Pr`,
//!     else from `Ns` as Blender writes it (`1 − √(Ns / 1000)`); metal part `Pm` (a blend
//!     where between 0 and 1; [`crate::metal_surface`] tinted by `Kd`); the dielectric is
//!     plastic with a coat of index `Ni` (1.5 where missing or not above 1) where `Ks` is not
//!     black or `Pr` is given, at that roughness ([`crate::coated_surface`]: Lambertian from
//!     0.5, so `Ns` below 250), and [`Surface::Diffuse`] otherwise; albedo `Kd` (missing →
//!     0.8), or the `map_Kd` image (sRGB) when it loads. The map replaces `Kd` rather than
//!     multiplying it: exporters such as 3ds Max write their default `Kd 0.588` beside every
//!     map, and glTF conversions of those scenes use a factor of 1. `map_Kd` on a mirror or
//!     glass is ignored. `Ks`'s colour and strength are not used (glTF's coat is untinted).
//!     The PBR extension's `Pc` and `Pcr` put a clear coat of that weight and roughness over
//!     it ([`crate::Clearcoat`]), and `Ps` a white sheen of that strength and roughness 0.5
//!     ([`crate::Sheen`]), as Blender writes its Principled BSDF's coat and sheen.
//!   - `Ke` → emitted radiance (front face only); `map_Ke` multiplies it (`Ke` missing → 1).
//!   - `map_d` → [`AlphaMode::Mask`] with cutoff 0.5 on the base colour texture's alpha: the
//!     `map_Kd` image itself when `map_d` names the same file and it has an alpha channel;
//!     otherwise a copy of the `map_Kd` image (or a white image) whose alpha is the mask
//!     image's alpha (or first channel when it has no alpha), nearest texel if sizes differ.
//!   - `d` → [`crate::Material::alpha`] (it multiplies the mask). `d` below 1 without `map_d`
//!     is blend opacity, which the renderer does not do: a warning, and the surface is opaque.
//!     `Tr` (written as 1 − d by some exporters and as d by others) is ignored.
//!   - Reflectances are clamped to [0, 1]; a non-finite number is a format error.
//!   - A missing or unreadable texture is a warning naming the file; the material keeps its
//!     colour. A missing MTL is a warning; faces without a known material get a default
//!     diffuse one (albedo 0.8). `map_Ka`, `map_Ks`, `map_Ns`, `bump` and texture options
//!     (`-s`, `-o`, ...) are ignored with a warning.
//! - OBJ has no cameras: [`crate::Scene::camera`] frames the scene, or the CLI adds one.
//!
//! # Robustness
//! `tobj` 4.0 panics on a relative face index reaching before the first texture coordinate or
//! normal (an integer overflow, a panic in debug builds) and on an MTL colour with fewer than
//! three numbers; the `scan` and `mtl` submodules check those inputs first, and the
//! fuzz test in `tests/obj_bad_input.rs` feeds it random statements. A non-UTF-8 file is read
//! with its invalid bytes replaced (a warning). Files a scene names must be regular files
//! (not `/dev/zero`, not a folder), MTL files at most 64 MiB and images at most 1 GiB.
//!
//! # Speed
//! The scan reads face indices as bytes without allocating; the images are decoded on other
//! threads while `tobj` parses the geometry. The Crytek Sponza (262,267 triangles, 30 MB, 20
//! textures) loads in about 0.8 s in release on a busy 2-core machine, plus the builder's light
//! collection.

mod geometry;
mod maps;
mod material;
mod mtl;
mod scan;

pub use material::{DEFAULT_IOR, MASK_CUTOFF};

use std::borrow::Cow;
use std::cell::Cell;
use std::path::Path;

use crate::{AlphaMode, Material, Scene, SceneBuilder, SceneError, Surface};

/// Loads an OBJ file and the MTL libraries it names.
pub fn load(path: &Path) -> Result<Scene, SceneError> {
    let bytes = read_regular_file(path, u64::MAX).map_err(|e| SceneError::io(path, e))?;
    let mut builder = SceneBuilder::new(path);
    let text = String::from_utf8_lossy(&bytes);
    if let Cow::Owned(_) = text {
        builder.warn("the file is not valid UTF-8: invalid bytes replaced");
    }
    let scan = scan::scan(&text).map_err(|message| SceneError::format(path, message))?;
    if scan.vertices == 0 && scan.faces == 0 && scan.unknown_lines > 0 {
        return Err(SceneError::format(
            path,
            "no vertex or face statements: not an OBJ file",
        ));
    }
    report_skipped(&scan, &mut builder);
    let text = match scan.needs_rewrite() {
        true => Cow::Owned(scan::rewrite(&text)),
        false => text,
    };
    let obj_dir = path.parent().unwrap_or(Path::new(""));
    let libraries = mtl::load_libraries(obj_dir, &scan.mtllibs, &mut builder);
    warn_unknown_materials(&scan, &libraries, &mut builder);

    let plans = plan_materials(path, &libraries, &mut builder)?;
    let image_paths = maps::image_paths(&plans);
    let decoder_threads = std::thread::available_parallelism().map_or(1, |n| n.get().max(2) - 1);
    let (parsed, decoded) = std::thread::scope(|scope| {
        let decoder = scope.spawn(|| maps::decode_all(&image_paths, decoder_threads));
        let parsed = parse(&text, &libraries.per_statement);
        let decoded = decoder
            .join()
            .unwrap_or_else(|panic| std::panic::resume_unwind(panic));
        (parsed, decoded)
    });
    let models = parsed.map_err(|e| SceneError::format(path, describe(&e, &text)))?;

    let material_ids = maps::add_materials(plans, decoded, &mut builder);
    add_models(&mut builder, &models, &material_ids)?;
    builder.finish()
}

/// Maps every library material (see the module manual); notes become warnings.
fn plan_materials(
    path: &Path,
    libraries: &mtl::Libraries,
    builder: &mut SceneBuilder,
) -> Result<Vec<material::Plan>, SceneError> {
    let mut notes = Vec::new();
    let plans = libraries
        .materials
        .iter()
        .map(|m| {
            material::plan(&m.material, &m.dir, &mut notes).map_err(|e| {
                SceneError::format(path, format!("material '{}': {e}", m.material.name))
            })
        })
        .collect::<Result<Vec<_>, _>>()?;
    for note in notes {
        builder.warn(note);
    }
    Ok(plans)
}

/// Adds the models' triangles; faces without a known material get [`default`], added once.
fn add_models(
    builder: &mut SceneBuilder,
    models: &[tobj::Model],
    material_ids: &[u32],
) -> Result<(), SceneError> {
    let mut default_material = None;
    for model in models {
        let material = match model.mesh.material_id.and_then(|i| material_ids.get(i)) {
            Some(&id) => id,
            None => *default_material.get_or_insert_with(|| builder.add_material(default())),
        };
        geometry::add_model(builder, model, material)?;
    }
    Ok(())
}

/// Reads a regular file of at most `max_bytes`; a device (`/dev/zero`), a directory or an
/// oversized file named by a scene is refused.
pub(super) fn read_regular_file(path: &Path, max_bytes: u64) -> std::io::Result<Vec<u8>> {
    let (bytes, length) = crate::files::read_regular_file(path, max_bytes)?;
    if length > max_bytes {
        let message = format!("{length} bytes, more than the {max_bytes} allowed");
        return Err(std::io::Error::new(
            std::io::ErrorKind::InvalidData,
            message,
        ));
    }
    Ok(bytes)
}

/// Runs `tobj` on the checked text, handing it the libraries already read.
fn parse(
    text: &str,
    libraries: &[tobj::MTLLoadResult],
) -> Result<Vec<tobj::Model>, tobj::LoadError> {
    let options = tobj::LoadOptions {
        triangulate: true,
        single_index: true,
        ignore_points: true,
        ignore_lines: true,
    };
    let next_library = Cell::new(0);
    let (models, _materials) = tobj::load_obj_buf(&mut text.as_bytes(), &options, |_| {
        let i = next_library.replace(next_library.get() + 1);
        libraries
            .get(i)
            .cloned()
            .unwrap_or(Err(tobj::LoadError::OpenFileFailed))
    })?;
    Ok(models)
}

/// The material of faces with no (known) `usemtl`.
fn default() -> Material {
    Material {
        name: "default".into(),
        surface: Surface::Diffuse,
        alpha_mode: AlphaMode::Opaque,
        ..Material::default()
    }
}

fn report_skipped(scan: &scan::Scan, builder: &mut SceneBuilder) {
    match scan.short_faces {
        0 => {}
        1 => builder.warn("1 face with fewer than three vertices ignored"),
        n => builder.warn(format!("{n} faces with fewer than three vertices ignored")),
    }
    match scan.polylines {
        0 => {}
        1 => builder.warn("1 polyline (l) ignored"),
        n => builder.warn(format!("{n} polylines (l) ignored")),
    }
}

fn warn_unknown_materials(
    scan: &scan::Scan,
    libraries: &mtl::Libraries,
    builder: &mut SceneBuilder,
) {
    let known: std::collections::HashSet<&str> = libraries.names().collect();
    for (name, line) in &scan.used_materials {
        if !known.contains(name.as_str()) {
            builder.warn(format!(
                "line {line}: usemtl {name}: no such material; the default material is used"
            ));
        }
    }
}

/// `tobj`'s error in words, with the line when it can be found.
fn describe(error: &tobj::LoadError, text: &str) -> String {
    use tobj::LoadError as E;
    let what = match error {
        E::PositionParseError => "a vertex position (v) needs three numbers",
        E::ScalingByZeroError => "a vertex position (v) has weight w = 0",
        E::ColorParseError => "a vertex (v) has neither 3, 4 nor 6 numbers",
        E::TexcoordParseError => "a texture coordinate (vt) needs two numbers",
        E::NormalParseError => "a normal (vn) needs three numbers",
        E::FaceColorOutOfBounds => "only some vertices have colours",
        other => return format!("malformed OBJ ({other})"),
    };
    match scan::locate(text, error) {
        Some(line) => format!("line {line}: {what}"),
        None => what.to_string(),
    }
}
