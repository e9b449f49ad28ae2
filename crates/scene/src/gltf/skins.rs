//! Skins, in the pose the file's nodes give their joints: a skinned mesh is drawn where its
//! joints hold it, as a viewer shows the file before any animation plays (animations are not
//! read). Each joint's transform is its node's world transform times its inverse bind matrix
//! (glTF 2.0 §3.7.3); a vertex is placed by its joints' transforms blended by its weights
//! (`meshes::Placement::Skinned`), and the skinned node's own transform is not applied, as the
//! spec asks.

use glam::{Affine3A, Mat4, Vec4};

use super::{Context, Input, accessors};
use crate::SceneError;

/// Skin `skin`'s joint transforms, in the order of its `joints`, from every node's world
/// transform (`worlds`). The skin must exist.
pub(super) fn joint_transforms(
    input: &Input,
    skin: usize,
    worlds: &[Affine3A],
) -> Result<Vec<Affine3A>, SceneError> {
    let context = || format!("skin {skin}");
    let definition = &input.root.skins[skin];
    let joints: Vec<usize> = definition.joints.iter().map(|j| j.value()).collect();
    if let Some(&joint) = joints.iter().find(|&&j| j >= worlds.len()) {
        return Err(input.error(format!(
            "{}: joint node {joint} does not exist ({} nodes)",
            context(),
            worlds.len()
        )));
    }
    let inverse_binds = match definition.inverse_bind_matrices {
        Some(accessor) => {
            let role = format!("inverseBindMatrices of skin {skin}");
            let matrices = accessors::read_matrices(input, accessor.value(), &role)?;
            if matrices.len() < joints.len() {
                return Err(input.error(format!(
                    "{}: {} inverse bind matrices for {} joints",
                    context(),
                    matrices.len(),
                    joints.len()
                )));
            }
            matrices
        }
        None => vec![Mat4::IDENTITY; joints.len()],
    };
    joints
        .iter()
        .zip(&inverse_binds)
        .enumerate()
        .map(|(j, (&node, inverse_bind))| {
            let inverse_bind = affine(inverse_bind)
                .ok_or_else(|| input.error(format!("inverse bind matrix {j} is not affine")))
                .context(context)?;
            Ok(worlds[node] * inverse_bind)
        })
        .collect()
}

/// `m` as an affine transform, if its last row is (0, 0, 0, 1).
fn affine(m: &Mat4) -> Option<Affine3A> {
    m.row(3)
        .abs_diff_eq(Vec4::W, 1e-5)
        .then(|| Affine3A::from_mat4(*m))
}
