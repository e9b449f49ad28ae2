//! Animations, sampled at one moment: `--animation-time` poses the scene as the file's
//! animation shows it then (a character mid-stride, a door half open, a shape key half way),
//! for a still image or one frame of a sequence. Each channel of the chosen animation overrides
//! its node's translation, rotation, scale or morph target weights with its sampler's value at
//! that time (glTF 2.0 §3.11): keyframes held before the first and after the last, STEP holding
//! each key, LINEAR blending (rotations along the shorter great arc), CUBICSPLINE by the
//! Hermite curve of its tangents. Channels of other animations are not applied: a file's
//! animations are often alternative clips (walk, run) of the same nodes.

use glam::{Quat, Vec3, Vec4};

use ::gltf::json;
use json::animation::{Interpolation, Property};
use json::validation::Checked;

use super::accessors::{self, Semantic};
use super::{Context, Input};
use crate::{AnimationClip, SceneError};

/// Which animation to sample, and when.
#[derive(Clone, Debug, PartialEq)]
pub struct AnimationTime {
    /// The animation's index or name; `None`: the first.
    pub animation: Option<String>,
    /// Seconds from the animation's start (glTF keyframe times are in seconds).
    pub seconds: f32,
}

/// What the chosen animation sets on each node at that time: `None` where it leaves a property
/// as the node has it.
#[derive(Clone, Debug, Default)]
pub(super) struct Pose {
    nodes: Vec<NodePose>,
}

#[derive(Clone, Debug, Default)]
pub(super) struct NodePose {
    pub translation: Option<Vec3>,
    pub rotation: Option<Quat>,
    pub scale: Option<Vec3>,
    pub weights: Option<Vec<f32>>,
}

impl Pose {
    /// What the animation sets on node `index` (nothing where it sets nothing).
    pub fn node(&self, index: usize) -> Option<&NodePose> {
        self.nodes.get(index)
    }
}

/// The file's animations, each with its length: the latest keyframe time among its samplers
/// (a sampler whose times cannot be read counts for nothing here; posing by it says why).
pub(super) fn clips(input: &Input) -> Vec<AnimationClip> {
    (input.root.animations.iter())
        .map(|animation| {
            let last_time = |sampler: &json::animation::Sampler| {
                let index = sampler.input.value();
                let times = accessors::read_floats(input, index, Semantic::KeyTimes, "input");
                times.ok().and_then(|(times, _)| times.last().copied())
            };
            let seconds = (animation.samplers.iter())
                .filter_map(last_time)
                .fold(0.0, f32::max);
            AnimationClip {
                name: animation.name.clone(),
                seconds,
            }
        })
        .collect()
}

/// The pose of the animation `time` names at its moment. Refused in one line: a file without
/// animations, an index or name that names none, and a channel that breaks the spec (times
/// not increasing, outputs of the wrong count, a node with a `matrix` animated).
pub(super) fn pose_at(input: &Input, time: &AnimationTime) -> Result<Pose, SceneError> {
    let animations = &input.root.animations;
    if !time.seconds.is_finite() {
        return Err(input.error(format!(
            "animation time {} is not a finite number of seconds",
            time.seconds
        )));
    }
    let index = match &time.animation {
        None => 0,
        Some(choice) => {
            let names: Vec<Option<&str>> = animations.iter().map(|a| a.name.as_deref()).collect();
            super::index_or_name("animation", choice, &names).map_err(|e| input.error(e))?
        }
    };
    let Some(animation) = animations.get(index) else {
        return Err(input.error("the file has no animations to pose the scene by"));
    };
    let context = || format!("animation {index}");
    let mut pose = Pose {
        nodes: vec![NodePose::default(); input.root.nodes.len()],
    };
    for (c, channel) in animation.channels.iter().enumerate() {
        let context = || format!("{} channel {c}", context());
        sample_channel(input, animation, channel, time.seconds, &mut pose).context(context)?;
    }
    Ok(pose)
}

/// Sets what `channel` animates on its node to its value at `seconds`.
fn sample_channel(
    input: &Input,
    animation: &json::Animation,
    channel: &json::animation::Channel,
    seconds: f32,
    pose: &mut Pose,
) -> Result<(), SceneError> {
    let node = channel.target.node.value();
    let Some(node_pose) = pose.nodes.get_mut(node) else {
        return Err(input.error(format!("node {node} does not exist")));
    };
    if input.root.nodes[node].matrix.is_some() {
        return Err(input.error(format!(
            "node {node} has a matrix, which glTF forbids animating"
        )));
    }
    let Checked::Valid(property) = channel.target.path else {
        return Err(input.error("invalid target path"));
    };
    let s = channel.sampler.value();
    let Some(sampler) = animation.samplers.get(s) else {
        return Err(input.error(format!("sampler {s} does not exist")));
    };
    let Checked::Valid(interpolation) = sampler.interpolation else {
        return Err(input.error(format!("sampler {s}: invalid interpolation")));
    };
    let role = format!("input of sampler {s}");
    let (times, _) =
        accessors::read_floats(input, sampler.input.value(), Semantic::KeyTimes, &role)?;
    if times.is_empty() || times.windows(2).any(|w| w[1] <= w[0]) {
        return Err(input.error(format!(
            "sampler {s}: keyframe times must be one or more, strictly increasing"
        )));
    }
    let role = format!("output of sampler {s}");
    let semantic = match property {
        Property::Translation | Property::Scale => Semantic::KeyVectors,
        Property::Rotation => Semantic::KeyRotations,
        Property::MorphTargetWeights => Semantic::KeyWeights,
    };
    let (values, width) = accessors::read_floats(input, sampler.output.value(), semantic, &role)?;
    let per_key = match interpolation {
        Interpolation::CubicSpline => 3,
        _ => 1,
    };
    // Weights: one value a morph target, each key; the rest: one vector a key.
    let components = match property {
        Property::MorphTargetWeights => values.len() / (times.len() * per_key).max(1),
        _ => width,
    };
    if components == 0 || values.len() != times.len() * per_key * components {
        return Err(input.error(format!(
            "sampler {s}: {} output values for {} keys of {components} ({})",
            values.len(),
            times.len(),
            interpolation_name(interpolation)
        )));
    }
    let key = Keys {
        times: &times,
        values: &values,
        components,
        interpolation,
    };
    let value = key.at(seconds);
    match property {
        Property::Translation => node_pose.translation = Some(Vec3::from_slice(&value)),
        Property::Scale => node_pose.scale = Some(Vec3::from_slice(&value)),
        Property::Rotation => {
            let rotation = Vec4::from_slice(&value)
                .try_normalize()
                .map(Quat::from_vec4)
                .ok_or_else(|| input.error(format!("sampler {s}: a zero rotation")))?;
            node_pose.rotation = Some(rotation);
        }
        Property::MorphTargetWeights => node_pose.weights = Some(value),
    }
    Ok(())
}

fn interpolation_name(interpolation: Interpolation) -> &'static str {
    match interpolation {
        Interpolation::Linear => "LINEAR",
        Interpolation::Step => "STEP",
        Interpolation::CubicSpline => "CUBICSPLINE",
    }
}

/// A sampler's keyframes: `times` in seconds, strictly increasing, and for each key
/// `components` values (three groups of them for CUBICSPLINE: in-tangent, value, out-tangent).
struct Keys<'a> {
    times: &'a [f32],
    values: &'a [f32],
    components: usize,
    interpolation: Interpolation,
}

impl Keys<'_> {
    /// The value at `seconds`: the first key's before the first time, the last key's after the
    /// last, else interpolated between the two keys about it. Rotations come out unnormalised
    /// (the caller normalises): LINEAR blends them by slerp.
    fn at(&self, seconds: f32) -> Vec<f32> {
        let last = self.times.len() - 1;
        let next = self.times.partition_point(|&t| t <= seconds);
        if next == 0 {
            return self.value(0).to_vec();
        }
        if next > last {
            return self.value(last).to_vec();
        }
        let key = next - 1;
        let span = self.times[next] - self.times[key];
        let u = (seconds - self.times[key]) / span;
        let (a, b) = (self.value(key), self.value(next));
        match self.interpolation {
            Interpolation::Step => a.to_vec(),
            Interpolation::Linear if self.components == 4 => {
                let (qa, qb) = (quat(a), quat(b));
                qa.slerp(qb, u).to_array().to_vec()
            }
            Interpolation::Linear => a.iter().zip(b).map(|(a, b)| a + (b - a) * u).collect(),
            Interpolation::CubicSpline => {
                let (out_tangent, in_tangent) = (self.group(key, 2), self.group(next, 0));
                let (u2, u3) = (u * u, u * u * u);
                let (h00, h10) = (2.0 * u3 - 3.0 * u2 + 1.0, u3 - 2.0 * u2 + u);
                let (h01, h11) = (-2.0 * u3 + 3.0 * u2, u3 - u2);
                (0..self.components)
                    .map(|k| {
                        h00 * a[k]
                            + h10 * span * out_tangent[k]
                            + h01 * b[k]
                            + h11 * span * in_tangent[k]
                    })
                    .collect()
            }
        }
    }

    /// Key `key`'s value.
    fn value(&self, key: usize) -> &[f32] {
        match self.interpolation {
            Interpolation::CubicSpline => self.group(key, 1),
            _ => &self.values[key * self.components..][..self.components],
        }
    }

    /// Group `group` (0 in-tangent, 1 value, 2 out-tangent) of a CUBICSPLINE key.
    fn group(&self, key: usize, group: usize) -> &[f32] {
        &self.values[(3 * key + group) * self.components..][..self.components]
    }
}

/// Four values as a unit quaternion (x, y, z, w); identity where they vanish.
fn quat(v: &[f32]) -> Quat {
    Vec4::from_slice(v)
        .try_normalize()
        .map_or(Quat::IDENTITY, Quat::from_vec4)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn keys<'a>(
        times: &'a [f32],
        values: &'a [f32],
        components: usize,
        i: Interpolation,
    ) -> Keys<'a> {
        Keys {
            times,
            values,
            components,
            interpolation: i,
        }
    }

    #[test]
    fn keys_hold_outside_their_times_and_blend_between() {
        let times = [1.0, 3.0];
        let linear = keys(&times, &[0.0, 10.0], 1, Interpolation::Linear);
        assert_eq!(linear.at(0.0), [0.0]);
        assert_eq!(linear.at(1.5), [2.5]);
        assert_eq!(linear.at(3.0), [10.0]);
        assert_eq!(linear.at(9.0), [10.0]);
        let step = keys(&times, &[0.0, 10.0], 1, Interpolation::Step);
        assert_eq!(step.at(2.9), [0.0]);
        assert_eq!(step.at(3.0), [10.0]);
    }

    /// Zero tangents make the Hermite curve a smoothstep between the values; tangents of the
    /// line's own slope make it the line.
    #[test]
    fn cubic_splines_follow_their_tangents() {
        let times = [0.0, 2.0];
        // (in, value, out) per key.
        let flat = [0.0, 0.0, 0.0, 0.0, 4.0, 0.0];
        let u: f32 = 0.25;
        let smooth = keys(&times, &flat, 1, Interpolation::CubicSpline).at(0.5);
        assert!((smooth[0] - 4.0 * (3.0 * u * u - 2.0 * u * u * u)).abs() < 1e-6);
        let sloped = [2.0, 0.0, 2.0, 2.0, 4.0, 2.0];
        let line = keys(&times, &sloped, 1, Interpolation::CubicSpline).at(0.5);
        assert!((line[0] - 1.0).abs() < 1e-6, "{line:?}");
    }

    /// Rotations blend along the great arc: half-way from none to a quarter turn is an
    /// eighth.
    #[test]
    fn rotations_slerp() {
        let quarter = Quat::from_rotation_z(std::f32::consts::FRAC_PI_2);
        let values = [Quat::IDENTITY.to_array(), quarter.to_array()].concat();
        let half = quat(&keys(&[0.0, 1.0], &values, 4, Interpolation::Linear).at(0.5));
        let eighth = Quat::from_rotation_z(std::f32::consts::FRAC_PI_4);
        assert!(half.abs_diff_eq(eighth, 1e-6), "{half}");
    }
}
