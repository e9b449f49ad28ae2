//! How one MTL material maps onto the uber-material (the rules are listed in `obj/mod.rs`).

use std::path::{Path, PathBuf};

use glam::Vec3;

use super::mtl::resolve;
use crate::{AlphaMode, Clearcoat, Material, Sheen, Surface};

/// The index of refraction of a dielectric whose `Ni` is missing or below 1.
pub const DEFAULT_IOR: f32 = 1.5;

/// The roughness of a sheen from `Ps`: Blender's Principled BSDF's default sheen roughness
/// (its exporter writes the sheen's weight only).
pub const BLENDER_SHEEN_ROUGHNESS: f32 = 0.5;

/// The alpha cut-out threshold for `map_d` masks.
pub const MASK_CUTOFF: f32 = 0.5;

/// A material with its image files not yet decoded.
#[derive(Debug)]
pub(super) struct Plan {
    pub material: Material,
    /// `map_Kd`: sRGB base colour (its alpha may hold the `map_d` mask).
    pub base_color_map: Option<PathBuf>,
    /// `map_d`: alpha mask (the image's alpha channel if it has one, else its first channel).
    pub mask_map: Option<PathBuf>,
    /// `map_Ke`: sRGB emission.
    pub emission_map: Option<PathBuf>,
    /// A metal part (`Pm` between 0 and 1): the blend's members with their probabilities
    /// (`material.surface` is the first's); empty for one surface.
    pub members: Vec<(f32, Surface)>,
}

/// Maps an MTL material. Non-finite numbers are an error; values out of range are clamped or
/// replaced with a warning pushed to `warnings`.
pub(super) fn plan(
    m: &tobj::Material,
    dir: &Path,
    warnings: &mut Vec<String>,
) -> Result<Plan, String> {
    let mut notes = Vec::new();
    let (members, tint) = surface(m, &mut notes)?;
    let surface = members[0].1;
    let ke = finite_rgb(m.emissive, "Ke")?;
    if ke.is_some_and(|ke| ke.min_element() < 0.0) {
        notes.push("negative Ke clamped to 0".into());
    }
    let alpha = finite(m.dissolve, "d")?.unwrap_or(1.0);
    // Mirrors and glass wear no layers.
    let (clearcoat, sheen) = match m.illumination_model {
        Some(3..=7) => (None, None),
        _ => layers(m, &mut notes)?,
    };
    let mut plan = Plan {
        material: Material {
            name: m.name.clone(),
            surface,
            base_color: clamp_unit(tint, "colour", &mut notes),
            emission: ke.unwrap_or(Vec3::ZERO).max(Vec3::ZERO),
            alpha: alpha.clamp(0.0, 1.0),
            clearcoat,
            sheen,
            // MTL's illum 3 reflects Ks at every angle; 5 adds Fresnel's rise to white.
            metal_edge: match m.illumination_model {
                Some(3) => Vec3::ZERO,
                _ => Vec3::ONE,
            },
            ..Material::default()
        },
        base_color_map: texture(dir, m.diffuse_texture.as_deref(), "map_Kd", &mut notes),
        mask_map: texture(dir, m.dissolve_texture.as_deref(), "map_d", &mut notes),
        emission_map: texture(
            dir,
            m.unknown_param.get("map_Ke").map(String::as_str),
            "map_Ke",
            &mut notes,
        ),
        members: if members.len() > 1 {
            members
        } else {
            Vec::new()
        },
    };
    let coloured = matches!(
        surface,
        Surface::Diffuse | Surface::Plastic { .. } | Surface::RoughConductor { .. }
    ) || !plan.members.is_empty();
    if plan.base_color_map.is_some() && !coloured {
        notes.push("map_Kd ignored: the surface is a mirror or glass, not diffuse".into());
        plan.base_color_map = None;
    }
    if plan.mask_map.is_some() {
        plan.material.alpha_mode = AlphaMode::Mask {
            cutoff: MASK_CUTOFF,
        };
    } else if alpha < 1.0 {
        notes.push(format!(
            "d {alpha} (blend opacity) is not supported: rendered opaque"
        ));
    }
    if plan.emission_map.is_some() && ke.is_none() {
        plan.material.emission = Vec3::ONE;
    }
    notes.extend(ignored_maps(m));
    warnings.extend(
        notes
            .into_iter()
            .map(|n| format!("material '{}': {n}", m.name)),
    );
    Ok(plan)
}

/// The surface kind by `illum`, with its colour: albedo, mirror reflectance or glass tint;
/// a metal part (`Pm`) makes a blend of surfaces with their probabilities (first: the metal).
fn surface(
    m: &tobj::Material,
    notes: &mut Vec<String>,
) -> Result<(Vec<(f32, Surface)>, Vec3), String> {
    let kd = finite_rgb(m.diffuse, "Kd")?;
    let ks = finite_rgb(m.specular, "Ks")?;
    let one = |surface: Surface, tint: Vec3| (vec![(1.0, surface)], tint);
    Ok(match m.illumination_model {
        // "Reflection on, ray trace on" (5 adds Fresnel): the reflection colour is Ks.
        Some(3 | 5) => one(Surface::Mirror, mirror_tint(ks, kd)),
        // "Transparency: glass on" / "refraction on" variants: a solid dielectric.
        Some(4 | 6 | 7) => {
            let surface = Surface::Dielectric {
                ior: dielectric_ior(m.optical_density, notes)?,
                thin_walled: false,
            };
            one(surface, transmission_filter(m, notes)?.unwrap_or(Vec3::ONE))
        }
        _ => (
            glossy_members(m, ks, notes)?,
            kd.unwrap_or(Material::default().base_color),
        ),
    })
}

/// A material that is neither mirror nor glass, as glTF's metal and dielectric would have it
/// (`scene::metal_surface`, `scene::coated_surface`). Its roughness is the PBR extension's `Pr`
/// where given, else Blender's inverse of `Ns` (`1 − √(Ns / 1000)`, Ns clamped to [0, 1000]);
/// its metal part `Pm` (0 without). The dielectric wears a specular coat of index `Ni` (1.5
/// where missing or not above 1) where `Ks` is not black or `Pr` is given, and is Lambertian
/// otherwise, as it is where no roughness is given: classic MTL files (Phong's `Ks`, `Ns`)
/// below `Ns` 250 and those without a specular colour render as before.
fn glossy_members(
    m: &tobj::Material,
    ks: Option<Vec3>,
    notes: &mut Vec<String>,
) -> Result<Vec<(f32, Surface)>, String> {
    let pr = pbr_parameter(m, "Pr", notes)?;
    let metallic = pbr_parameter(m, "Pm", notes)?.unwrap_or(0.0);
    let shininess = finite(m.shininess, "Ns")?;
    let roughness = pr.or(shininess.map(|ns| 1.0 - (ns.clamp(0.0, 1000.0) / 1000.0).sqrt()));
    let specular = pr.is_some() || ks.is_some_and(|ks| ks.max_element() > 0.0);
    let dielectric = match roughness {
        Some(roughness) if specular => {
            let ior = match finite(m.optical_density, "Ni")? {
                Some(ior) if ior > 1.0 => ior,
                _ => DEFAULT_IOR,
            };
            crate::coated_surface(ior, roughness)
        }
        _ => Surface::Diffuse,
    };
    let metal = crate::metal_surface(roughness.unwrap_or(0.5));
    Ok(if metallic <= 0.0 {
        vec![(1.0, dielectric)]
    } else if metallic >= 1.0 {
        vec![(1.0, metal)]
    } else {
        vec![(metallic, metal), (1.0 - metallic, dielectric)]
    })
}

/// A number of the PBR extension (`Pr`, `Pm`, `Pc`, ...), which `tobj` keeps as text: `None`
/// where missing, clamped to [0, 1] with a note.
fn pbr_parameter(
    m: &tobj::Material,
    key: &str,
    notes: &mut Vec<String>,
) -> Result<Option<f32>, String> {
    let Some(text) = m.unknown_param.get(key) else {
        return Ok(None);
    };
    let value: f32 = text
        .split_whitespace()
        .next()
        .and_then(|w| w.parse().ok())
        .ok_or_else(|| format!("{key} '{text}' is not a number"))?;
    let value = finite(Some(value), key)?.unwrap_or(0.0);
    if !(0.0..=1.0).contains(&value) {
        notes.push(format!("{key} {value} clamped to [0, 1]"));
    }
    Ok(Some(value.clamp(0.0, 1.0)))
}

/// The PBR extension's clear coat (`Pc` its weight, `Pcr` its roughness) and sheen (`Ps` its
/// weight, a white sheen of Blender's default roughness, [`BLENDER_SHEEN_ROUGHNESS`]), as
/// Blender's exporter writes its Principled BSDF's coat and sheen.
fn layers(
    m: &tobj::Material,
    notes: &mut Vec<String>,
) -> Result<(Option<Clearcoat>, Option<Sheen>), String> {
    let coat = pbr_parameter(m, "Pc", notes)?.unwrap_or(0.0);
    let coat_roughness = pbr_parameter(m, "Pcr", notes)?.unwrap_or(0.0);
    let sheen = pbr_parameter(m, "Ps", notes)?.unwrap_or(0.0);
    Ok((
        Clearcoat::new(coat, coat_roughness),
        Sheen::new(Vec3::splat(sheen), BLENDER_SHEEN_ROUGHNESS),
    ))
}

/// The maps that are read but not supported, as one note.
fn ignored_maps(m: &tobj::Material) -> Option<String> {
    let ignored: Vec<&str> = [
        ("map_Ka", m.ambient_texture.is_some()),
        ("map_Ks", m.specular_texture.is_some()),
        ("map_Ns", m.shininess_texture.is_some()),
        ("bump", m.normal_texture.is_some()),
    ]
    .into_iter()
    .filter_map(|(key, present)| present.then_some(key))
    .collect();
    (!ignored.is_empty()).then(|| format!("{} ignored (not supported)", ignored.join(", ")))
}

/// A mirror's reflectance: Ks when it is not black, else Kd when that is not black (some
/// exporters put the mirror colour there), else white.
fn mirror_tint(ks: Option<Vec3>, kd: Option<Vec3>) -> Vec3 {
    [ks, kd]
        .into_iter()
        .flatten()
        .find(|c| c.max_element() > 0.0)
        .unwrap_or(Vec3::ONE)
}

fn dielectric_ior(ni: Option<f32>, notes: &mut Vec<String>) -> Result<f32, String> {
    match finite(ni, "Ni")? {
        Some(ior) if ior >= 1.0 => Ok(ior),
        Some(ior) => {
            notes.push(format!("Ni {ior} is below 1: glass with ior {DEFAULT_IOR}"));
            Ok(DEFAULT_IOR)
        }
        None => Ok(DEFAULT_IOR),
    }
}

/// `Tf` (transmission filter), which `tobj` keeps as text: one or three numbers.
fn transmission_filter(
    m: &tobj::Material,
    notes: &mut Vec<String>,
) -> Result<Option<Vec3>, String> {
    let Some(text) = m.unknown_param.get("Tf") else {
        return Ok(None);
    };
    let numbers: Result<Vec<f32>, _> = text
        .split_whitespace()
        .take_while(|w| !w.starts_with('#'))
        .map(str::parse)
        .collect();
    let rgb = match numbers.as_deref() {
        Ok([v]) => [*v; 3],
        Ok([r, g, b, ..]) => [*r, *g, *b],
        _ => {
            notes.push(format!("Tf '{text}' is not an RGB colour: ignored"));
            return Ok(None);
        }
    };
    finite_rgb(Some(rgb), "Tf")
}

fn finite(value: Option<f32>, key: &str) -> Result<Option<f32>, String> {
    match value {
        Some(v) if !v.is_finite() => Err(format!("{key} {v} is not a finite number")),
        v => Ok(v),
    }
}

fn finite_rgb(value: Option<[f32; 3]>, key: &str) -> Result<Option<Vec3>, String> {
    match value.map(Vec3::from_array) {
        Some(c) if !c.is_finite() => Err(format!("{key} {c} is not a finite colour")),
        c => Ok(c),
    }
}

/// Reflectances above 1 would create energy; they are clamped with a note.
fn clamp_unit(c: Vec3, what: &str, notes: &mut Vec<String>) -> Vec3 {
    let clamped = c.clamp(Vec3::ZERO, Vec3::ONE);
    if clamped != c {
        notes.push(format!("{what} {c} clamped to [0, 1]"));
    }
    clamped
}

/// The image a `map_*` statement names, relative to the library's folder. Options before the
/// file name (`-s 1 1 1`, `-bm 0.5`, ...) are skipped with a note: none is supported.
fn texture(
    dir: &Path,
    argument: Option<&str>,
    key: &str,
    notes: &mut Vec<String>,
) -> Option<PathBuf> {
    let argument = argument?;
    let (options, file) = split_options(argument);
    if !options.is_empty() {
        notes.push(format!("{key} options '{options}' ignored"));
    }
    if file.is_empty() {
        notes.push(format!("{key} '{argument}' names no file"));
        return None;
    }
    Some(resolve(dir, file))
}

/// Splits `-opt args... file name` into the options' text and the file name (which may hold
/// spaces). Options take one argument except `-mm` (two) and `-o`, `-s`, `-t` (up to three
/// numbers).
fn split_options(argument: &str) -> (&str, &str) {
    let mut rest = argument.trim();
    let mut consumed = 0;
    while let Some(option) = rest
        .split_whitespace()
        .next()
        .filter(|w| w.starts_with('-'))
    {
        let mut words = 1;
        let mut after = rest[option.len()..].split_whitespace();
        match option {
            "-mm" => words += 2,
            "-o" | "-s" | "-t" => {
                words += after
                    .by_ref()
                    .take(3)
                    .take_while(|w| w.parse::<f32>().is_ok())
                    .count()
            }
            _ => words += 1,
        }
        for _ in 0..words {
            let trimmed = rest.trim_start();
            let word_end = trimmed.find(char::is_whitespace).unwrap_or(trimmed.len());
            rest = &trimmed[word_end..];
        }
        rest = rest.trim_start();
        consumed = argument.trim().len() - rest.len();
    }
    let trimmed = argument.trim();
    (trimmed[..consumed].trim_end(), rest.trim_end())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn split_options_skips_options_and_keeps_spaces_in_names() {
        assert_eq!(split_options("a b.png"), ("", "a b.png"));
        assert_eq!(
            split_options("-s 2 2 1 -bm 0.3 tex.png"),
            ("-s 2 2 1 -bm 0.3", "tex.png")
        );
        assert_eq!(split_options("-o 0.5 tex.png"), ("-o 0.5", "tex.png"));
        assert_eq!(split_options("-clamp on"), ("-clamp on", ""));
    }

    #[test]
    fn mirror_tint_prefers_ks_then_kd_then_white() {
        let grey = Some(Vec3::splat(0.5));
        assert_eq!(mirror_tint(Some(Vec3::ONE), grey), Vec3::ONE);
        assert_eq!(mirror_tint(Some(Vec3::ZERO), grey), Vec3::splat(0.5));
        assert_eq!(mirror_tint(None, Some(Vec3::ZERO)), Vec3::ONE);
    }
}
