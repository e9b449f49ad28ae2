//! The node hierarchy. Before it is walked, the graph is checked to be a forest: every child
//! index exists, no node has two parents, there is no cycle. The walk uses an explicit stack,
//! never recursion, so a hierarchy a hundred thousand nodes deep is as safe as a flat one.

use glam::{Affine3A, Mat3, Mat4, Quat, Vec3, Vec4};

use super::Input;
use crate::SceneError;

const NO_PARENT: usize = usize::MAX;

/// Checks the node graph and returns the root nodes of the scene to draw, in order: the
/// document's `scene`, else its first scene, else (no scenes at all) every parentless node.
pub(super) fn scene_roots(input: &Input) -> Result<Vec<usize>, SceneError> {
    let parents = parents(input)?;
    check_acyclic(input, &parents)?;
    let root = input.root;
    let scene_index = match root.scene {
        Some(index) => Some(index.value()),
        None => (!root.scenes.is_empty()).then_some(0),
    };
    let Some(scene_index) = scene_index else {
        return Ok((0..parents.len())
            .filter(|&i| parents[i] == NO_PARENT)
            .collect());
    };
    let Some(scene) = root.scenes.get(scene_index) else {
        return Err(input.error(format!(
            "scene {scene_index} does not exist ({} scenes)",
            root.scenes.len()
        )));
    };
    let mut listed = vec![false; parents.len()];
    let mut roots = Vec::with_capacity(scene.nodes.len());
    for node in &scene.nodes {
        let i = node.value();
        let problem = match parents.get(i) {
            None => Some(format!("node {i} does not exist ({} nodes)", parents.len())),
            Some(&parent) if parent != NO_PARENT => Some(format!(
                "node {i} is listed as a root but is a child of node {parent}"
            )),
            Some(_) if listed[i] => Some(format!("node {i} is listed twice")),
            Some(_) => None,
        };
        if let Some(problem) = problem {
            return Err(input.error(format!("scene {scene_index}: {problem}")));
        }
        listed[i] = true;
        roots.push(i);
    }
    Ok(roots)
}

/// Every node's parent (`NO_PARENT` for roots), checking that children exist and that no
/// node has two parents.
fn parents(input: &Input) -> Result<Vec<usize>, SceneError> {
    let nodes = &input.root.nodes;
    let mut parents = vec![NO_PARENT; nodes.len()];
    for (i, node) in nodes.iter().enumerate() {
        for child in node.children.iter().flatten() {
            let c = child.value();
            let problem = match parents.get(c) {
                None => format!("child {c} does not exist ({} nodes)", nodes.len()),
                Some(_) if c == i => "is its own child".to_string(),
                Some(&NO_PARENT) => {
                    parents[c] = i;
                    continue;
                }
                Some(&p) => format!("child {c} already has parent node {p}"),
            };
            return Err(input.error(format!("node {i}: {problem}")));
        }
    }
    Ok(parents)
}

/// With one parent per node, a node unreachable from the parentless nodes lies on or below a
/// cycle; following its parents long enough lands on the cycle, which is reported.
fn check_acyclic(input: &Input, parents: &[usize]) -> Result<(), SceneError> {
    let nodes = &input.root.nodes;
    let mut reached = vec![false; nodes.len()];
    let mut stack: Vec<usize> = (0..nodes.len())
        .filter(|&i| parents[i] == NO_PARENT)
        .collect();
    while let Some(i) = stack.pop() {
        reached[i] = true;
        stack.extend(nodes[i].children.iter().flatten().map(|c| c.value()));
    }
    let Some(unreached) = reached.iter().position(|&r| !r) else {
        return Ok(());
    };
    let mut on_cycle = unreached;
    for _ in 0..nodes.len() {
        on_cycle = parents[on_cycle];
    }
    Err(input.error(format!(
        "the node hierarchy has a cycle through node {on_cycle}"
    )))
}

/// Visits every node below `roots` with its world transform, depth first in pre-order (the
/// order a recursive walk takes). The graph must have passed [`scene_roots`].
pub(super) fn walk(
    input: &Input,
    roots: &[usize],
    mut visit: impl FnMut(usize, &Affine3A) -> Result<(), SceneError>,
) -> Result<(), SceneError> {
    let nodes = &input.root.nodes;
    let mut stack: Vec<(usize, Affine3A)> = roots
        .iter()
        .rev()
        .map(|&r| (r, Affine3A::IDENTITY))
        .collect();
    while let Some((index, parent)) = stack.pop() {
        let node = &nodes[index];
        let world = parent * local_transform(input, index, node)?;
        visit(index, &world)?;
        let children = node.children.iter().flatten().rev();
        stack.extend(children.map(|c| (c.value(), world)));
    }
    Ok(())
}

/// Every node's world transform, whether or not the scene drawn shows it (a skin's joints may
/// lie anywhere in the hierarchy). The graph must have passed [`scene_roots`].
pub(super) fn world_transforms(input: &Input) -> Result<Vec<Affine3A>, SceneError> {
    let parents = parents(input)?;
    let roots: Vec<usize> = (0..parents.len())
        .filter(|&i| parents[i] == NO_PARENT)
        .collect();
    let mut worlds = vec![Affine3A::IDENTITY; parents.len()];
    walk(input, &roots, |index, world| {
        worlds[index] = *world;
        Ok(())
    })?;
    Ok(worlds)
}

/// Every node below `roots`, in the order [`walk`] visits them.
pub(super) fn in_walk_order(input: &Input, roots: &[usize]) -> Vec<usize> {
    let nodes = &input.root.nodes;
    let mut order = Vec::new();
    let mut stack: Vec<usize> = roots.iter().rev().copied().collect();
    while let Some(index) = stack.pop() {
        order.push(index);
        stack.extend(
            nodes[index]
                .children
                .iter()
                .flatten()
                .rev()
                .map(|c| c.value()),
        );
    }
    order
}

/// A node's transform relative to its parent: `matrix` if given, else T·R·S, each of T, R and
/// S as the chosen animation sets it where it does.
fn local_transform(
    input: &Input,
    index: usize,
    node: &::gltf::json::Node,
) -> Result<Affine3A, SceneError> {
    let error = |what: &str| input.error(format!("node {index}: {what}"));
    if let Some(m) = node.matrix {
        if !m.iter().all(|x| x.is_finite()) {
            return Err(error("matrix has a non-finite element"));
        }
        let m = Mat4::from_cols_array(&m);
        if !m.row(3).abs_diff_eq(Vec4::W, 1e-5) {
            return Err(error(&format!(
                "matrix is not affine (last row {})",
                m.row(3)
            )));
        }
        return Ok(Affine3A::from_mat3_translation(
            Mat3::from_mat4(m),
            m.w_axis.truncate(),
        ));
    }
    // What an animation sets at its moment replaces the node's own (`animation`).
    let posed = input.pose.node(index);
    let translation = (posed.and_then(|p| p.translation))
        .unwrap_or_else(|| Vec3::from_array(node.translation.unwrap_or([0.0; 3])));
    let scale = (posed.and_then(|p| p.scale))
        .unwrap_or_else(|| Vec3::from_array(node.scale.unwrap_or([1.0; 3])));
    let rotation = (posed.and_then(|p| p.rotation)).map_or_else(
        || Vec4::from_array(node.rotation.unwrap_or_default().0),
        Vec4::from,
    );
    if !translation.is_finite() || !scale.is_finite() || !rotation.is_finite() {
        return Err(error("translation, rotation or scale is not finite"));
    }
    let Some(rotation) = rotation.try_normalize().map(Quat::from_vec4) else {
        return Err(error("rotation is a zero quaternion"));
    };
    Ok(Affine3A::from_scale_rotation_translation(
        scale,
        rotation,
        translation,
    ))
}
