//! `EXT_mesh_gpu_instancing`: a node that draws its mesh once per instance, each instance's
//! transform (its TRANSLATION, ROTATION and SCALE accessors, each optional, as T·R·S) applied
//! in the node's space, before the node's own world transform. Blender and gltfpack write it
//! for repeated objects (a forest, a crowd of chairs); placed here as that many copies.

use glam::{Affine3A, Quat, Vec3};
use serde_json::Value;

use super::Input;
use super::accessors::{self, Semantic};
use crate::SceneError;

/// The extension's name.
pub(super) const INSTANCING: &str = "EXT_mesh_gpu_instancing";

/// The instancing attributes of node `index`: (TRANSLATION, ROTATION, SCALE) accessor
/// indices, `None` where the node does not use the extension.
fn attributes(input: &Input, index: usize) -> Result<Option<[Option<usize>; 3]>, SceneError> {
    let node = &input.root.nodes[index];
    let Some(extension) = node
        .extensions
        .as_ref()
        .and_then(|e| e.others.get(INSTANCING))
    else {
        return Ok(None);
    };
    let error = |what: String| input.error(format!("node {index}: {INSTANCING} {what}"));
    let Some(attributes) = extension.get("attributes").and_then(Value::as_object) else {
        return Err(error("has no attributes".into()));
    };
    let accessor = |name: &str| -> Result<Option<usize>, SceneError> {
        match attributes.get(name) {
            None => Ok(None),
            Some(v) => v
                .as_u64()
                .map(|i| Some(i as usize))
                .ok_or_else(|| error(format!("{name} is not an accessor index"))),
        }
    };
    Ok(Some([
        accessor("TRANSLATION")?,
        accessor("ROTATION")?,
        accessor("SCALE")?,
    ]))
}

/// How many times node `index` draws its mesh: its instances (the attributes' common count,
/// checked without reading them), or 1 without the extension.
pub(super) fn instance_count(input: &Input, index: usize) -> Result<u64, SceneError> {
    let Some(attributes) = attributes(input, index)? else {
        return Ok(1);
    };
    let semantics = [
        ("TRANSLATION", Semantic::InstanceVector),
        ("ROTATION", Semantic::InstanceRotation),
        ("SCALE", Semantic::InstanceVector),
    ];
    let mut count = None;
    for (accessor, (name, semantic)) in attributes.iter().zip(semantics) {
        let Some(accessor) = *accessor else {
            continue;
        };
        let role = format!("{name} of node {index}'s instances");
        let n = accessors::count(input, accessor, semantic, &role)?;
        match count {
            Some(c) if c != n => {
                return Err(input.error(format!(
                    "node {index}: {INSTANCING} attributes have {c} and {n} elements"
                )));
            }
            _ => count = Some(n),
        }
    }
    Ok(count.unwrap_or(1) as u64)
}

/// Node `index`'s instance transforms in its own space, `None` where it does not use the
/// extension. A zero rotation quaternion is an error.
pub(super) fn instances(input: &Input, index: usize) -> Result<Option<Vec<Affine3A>>, SceneError> {
    let Some([translation, rotation, scale]) = attributes(input, index)? else {
        return Ok(None);
    };
    let count = instance_count(input, index)? as usize;
    let role = |name: &str| format!("{name} of node {index}'s instances");
    let vectors = |accessor: Option<usize>, name: &str, default: Vec3| match accessor {
        Some(a) => accessors::read_vec3(input, a, Semantic::InstanceVector, &role(name)),
        None => Ok(vec![default; count]),
    };
    let translations = vectors(translation, "TRANSLATION", Vec3::ZERO)?;
    let scales = vectors(scale, "SCALE", Vec3::ONE)?;
    let rotations = match rotation {
        Some(a) => accessors::read_vec4(input, a, Semantic::InstanceRotation, &role("ROTATION"))?,
        None => vec![Quat::IDENTITY.into(); count],
    };
    let mut transforms = Vec::with_capacity(count);
    for (i, ((t, r), s)) in translations.iter().zip(&rotations).zip(&scales).enumerate() {
        let Some(r) = r.try_normalize().map(Quat::from_vec4) else {
            return Err(input.error(format!(
                "node {index}: {INSTANCING} instance {i} has a zero rotation quaternion"
            )));
        };
        transforms.push(Affine3A::from_scale_rotation_translation(*s, r, *t));
    }
    Ok(Some(transforms))
}
