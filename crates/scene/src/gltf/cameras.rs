//! Cameras on nodes: perspective ones become [`Camera`]s, in node traversal order, looking
//! down their node's −Z with +Y up; orthographic ones are skipped with a warning.

use glam::{Affine3A, Mat4};

use ::gltf::json;
use json::camera::Type;
use json::validation::Checked;

use super::Input;
use crate::{Camera, SceneBuilder, SceneError};

/// Adds camera `index`, placed by node `node`'s `world` transform, to `builder`.
pub(super) fn place(
    input: &Input,
    builder: &mut SceneBuilder,
    node: usize,
    index: usize,
    world: &Affine3A,
) -> Result<(), SceneError> {
    let root = input.root;
    let Some(camera) = root.cameras.get(index) else {
        return Err(input.error(format!(
            "node {node}: camera {index} does not exist ({} cameras)",
            root.cameras.len()
        )));
    };
    let label = format!("camera {index} (node {node})");
    let perspective = match (camera.type_, &camera.perspective) {
        (Checked::Valid(Type::Perspective), Some(perspective)) => perspective,
        (Checked::Valid(Type::Orthographic), _) => {
            builder.warn(format!(
                "{label} is orthographic; skipped (perspective only)"
            ));
            return Ok(());
        }
        _ => {
            return Err(input.error(format!(
                "{label}: invalid type, or no perspective properties"
            )));
        }
    };
    let name = camera
        .name
        .clone()
        .or_else(|| root.nodes[node].name.clone());
    match perspective_camera(input, &label, perspective, world)? {
        Some(c) => builder.add_camera(c.named(name.unwrap_or_else(|| format!("camera {index}")))),
        None => builder.warn(format!(
            "{label}: its node's transform has no usable frame; skipped"
        )),
    }
    Ok(())
}

/// A perspective camera placed by `world`; `None` if `world` has no usable frame (a zero
/// scale, say). The field of view must be in (0, π), the aspect ratio (if given) positive.
fn perspective_camera(
    input: &Input,
    label: &str,
    perspective: &json::camera::Perspective,
    world: &Affine3A,
) -> Result<Option<Camera>, SceneError> {
    let yfov = perspective.yfov;
    if !(yfov > 0.0 && yfov < std::f32::consts::PI) {
        return Err(input.error(format!("{label}: yfov {yfov} is not in (0, π)")));
    }
    let aspect_ratio = perspective.aspect_ratio;
    if let Some(a) = aspect_ratio.filter(|a| !(a.is_finite() && *a > 0.0)) {
        return Err(input.error(format!("{label}: aspectRatio {a} is not > 0")));
    }
    let camera = Camera::from_world_matrix(Mat4::from(*world), yfov);
    Ok(camera.map(|c| Camera { aspect_ratio, ..c }))
}
