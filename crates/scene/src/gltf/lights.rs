//! Lights on nodes (`KHR_lights_punctual`): point, spot and directional lights become
//! [`PunctualLight`]s at their node's world origin, shining down its world −Z. `color` must be
//! in [0, 1] and `intensity` ≥ 0 (both finite); a spot's cone must satisfy
//! `0 ≤ innerConeAngle < outerConeAngle ≤ π/2`. `range` is ignored, with one warning per file:
//! kousen's lights fall off with the inverse square of distance, however far.

use glam::{Affine3A, Vec3};

use ::gltf::json;
use json::extensions::scene::khr_lights_punctual::{Light, Spot, Type};
use json::validation::Checked;

use super::{Context, Input};
use crate::{PunctualKind, PunctualLight, SceneBuilder, SceneError, SpotFalloff};

/// Adds light `index`, placed by node `node`'s `world` transform, to `builder`. Warns about
/// an ignored `range` unless `warned_range` says that was done already (and sets it).
pub(super) fn place(
    input: &Input,
    builder: &mut SceneBuilder,
    node: usize,
    index: usize,
    world: &Affine3A,
    warned_range: &mut bool,
) -> Result<(), SceneError> {
    let lights = lights(input.root);
    let Some(light) = lights.get(index) else {
        return Err(input.error(format!(
            "node {node}: light {index} does not exist ({} lights)",
            lights.len()
        )));
    };
    let label = format!("light {index} (node {node})");
    let kind = kind(input, &label, light)?;
    let intensity = intensity(input, &label, light)?;
    if light.range.is_some() && !*warned_range {
        *warned_range = true;
        builder.warn(format!(
            "{label}: range is ignored, on this and every other light (lights fall off with \
             the inverse square of distance, however far)"
        ));
    }
    let position = world.transform_point3(Vec3::ZERO);
    let direction = world.transform_vector3(Vec3::NEG_Z);
    if kind != PunctualKind::Point && direction.try_normalize().is_none() {
        builder.warn(format!(
            "{label}: its node's transform gives it no direction; skipped"
        ));
        return Ok(());
    }
    builder
        .add_punctual_light(PunctualLight {
            kind,
            position,
            direction,
            intensity,
        })
        .context(|| label)
}

/// The document's lights (none without the extension).
fn lights(root: &json::Root) -> &[Light] {
    root.extensions
        .as_ref()
        .and_then(|e| e.khr_lights_punctual.as_ref())
        .map_or(&[], |l| l.lights.as_slice())
}

/// The light's kind; a spot's cone angles checked and turned into cosines.
fn kind(input: &Input, label: &str, light: &Light) -> Result<PunctualKind, SceneError> {
    match (light.type_, &light.spot) {
        (Checked::Valid(Type::Point), _) => Ok(PunctualKind::Point),
        (Checked::Valid(Type::Directional), _) => Ok(PunctualKind::Directional),
        (Checked::Valid(Type::Spot), Some(spot)) => spot_cone(input, label, spot),
        (Checked::Valid(Type::Spot), None) => {
            Err(input.error(format!("{label}: a spot light without its spot properties")))
        }
        (Checked::Invalid, _) => Err(input.error(format!(
            "{label}: invalid type (expected point, spot or directional)"
        ))),
    }
}

/// A spot's cone, `0 ≤ innerConeAngle < outerConeAngle ≤ π/2` (radians), as cosines.
fn spot_cone(input: &Input, label: &str, spot: &Spot) -> Result<PunctualKind, SceneError> {
    let (inner, outer) = (spot.inner_cone_angle, spot.outer_cone_angle);
    if !(0.0 <= inner && inner < outer && outer <= std::f32::consts::FRAC_PI_2) {
        return Err(input.error(format!(
            "{label}: spot cone angles {inner} (inner) and {outer} (outer) are not \
             0 ≤ inner < outer ≤ π/2"
        )));
    }
    let cos_inner = inner.cos();
    // cos(π/2) in f32 is a hair below 0.
    let mut cos_outer = outer.cos().max(0.0);
    if cos_outer >= cos_inner {
        // Angles so close that their cosines round together: a hard-edged cone.
        cos_outer = cos_inner.next_down().max(0.0);
    }
    Ok(PunctualKind::Spot {
        cos_inner,
        cos_outer,
        falloff: SpotFalloff::Gltf,
    })
}

/// Linear colour (each channel in [0, 1]) × intensity (≥ 0), both finite.
fn intensity(input: &Input, label: &str, light: &Light) -> Result<Vec3, SceneError> {
    let color = light.color;
    for (c, name) in color.iter().zip(["red", "green", "blue"]) {
        if !(0.0..=1.0).contains(c) {
            return Err(input.error(format!("{label}: color's {name} {c} is not in [0, 1]")));
        }
    }
    let intensity = light.intensity;
    if !(intensity.is_finite() && intensity >= 0.0) {
        return Err(input.error(format!(
            "{label}: intensity {intensity} is not a finite number ≥ 0"
        )));
    }
    Ok(Vec3::from_array(color) * intensity)
}
