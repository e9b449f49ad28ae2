//! Cameras on nodes become [`Camera`]s, in node traversal order, looking down their node's −Z
//! with +Y up: perspective ones, and orthographic ones, whose film is `ymag` above and below
//! the node's origin and whose `xmag / ymag` is their aspect ratio.

use glam::{Affine3A, Mat4};

use ::gltf::json;
use json::camera::Type;
use json::validation::Checked;

use super::Input;
use crate::camera::DEFAULT_YFOV_DEGREES;
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
    let placed = match (camera.type_, &camera.perspective, &camera.orthographic) {
        (Checked::Valid(Type::Perspective), Some(perspective), _) => {
            perspective_camera(input, &label, perspective, world)?
        }
        (Checked::Valid(Type::Orthographic), _, Some(orthographic)) => {
            orthographic_camera(input, &label, orthographic, world)?
        }
        _ => {
            return Err(input.error(format!(
                "{label}: invalid type, or no properties for its type"
            )));
        }
    };
    let name = camera
        .name
        .clone()
        .or_else(|| root.nodes[node].name.clone());
    match placed {
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

/// An orthographic camera placed by `world` (its frame only: a node's scale leaves a camera's
/// view as it is, as for perspective ones); `None` if `world` has no usable frame. Its film's
/// half height is `ymag`, its aspect ratio `xmag / ymag`; both must be finite and positive
/// (glTF forbids zero and discourages negative ones, which would mirror the image).
fn orthographic_camera(
    input: &Input,
    label: &str,
    orthographic: &json::camera::Orthographic,
    world: &Affine3A,
) -> Result<Option<Camera>, SceneError> {
    let (xmag, ymag) = (orthographic.xmag, orthographic.ymag);
    let positive = |m: f32| m.is_finite() && m > 0.0;
    if !(positive(xmag) && positive(ymag)) {
        return Err(input.error(format!(
            "{label}: xmag {xmag} and ymag {ymag} must be finite and > 0"
        )));
    }
    let camera = Camera::from_world_matrix(Mat4::from(*world), DEFAULT_YFOV_DEGREES.to_radians())
        .and_then(|c| c.orthographic(ymag));
    Ok(camera.map(|c| Camera {
        aspect_ratio: Some(xmag / ymag),
        ..c
    }))
}
