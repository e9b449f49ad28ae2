//! glTF animations sampled at a moment (`scene::gltf::load_with`): each channel of the chosen
//! animation sets its node's translation, rotation, scale or morph weights as its sampler has
//! it then.

use crate::gltf_support;

use glam::{Quat, Vec3};
use gltf_support::*;
use scene::{AnimationClip, AnimationTime, LoadOptions, Scene, SceneError};
use serde_json::{Value, json};

const EPS: f32 = 1e-5;

/// One triangle facing +z.
const TRIANGLE: [[f32; 3]; 3] = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];

fn floats(doc: &mut Doc, values: &[f32], count: usize, ty: &str) -> usize {
    let bytes: Vec<u8> = values.iter().flat_map(|x| x.to_le_bytes()).collect();
    doc.accessor(&bytes, FLOAT, count, ty)
}

/// The triangle on node 0, which sits at (0, 0, 5); `animations` are added as given (their
/// accessors made by `make`).
fn animated(make: impl FnOnce(&mut Doc) -> Vec<Value>) -> Doc {
    let mut doc = Doc::default();
    let position = doc.vec3s(&TRIANGLE);
    let mesh = doc.push(
        "meshes",
        json!({ "primitives": [{ "attributes": { "POSITION": position } }] }),
    );
    let node = doc.node(json!({ "mesh": mesh, "translation": [0, 0, 5] }));
    doc.add_root(node);
    let animations = make(&mut doc);
    doc.json["animations"] = json!(animations);
    doc
}

/// An animation of node 0's `path` by one sampler of `times` and `values` (`ty` each).
fn animation(
    doc: &mut Doc,
    name: &str,
    path: &str,
    (times, values, ty): (&[f32], &[f32], &str),
    interpolation: &str,
) -> Value {
    let input = floats(doc, times, times.len(), "SCALAR");
    let width = match ty {
        "VEC3" => 3,
        "VEC4" => 4,
        _ => 1,
    };
    let output = floats(doc, values, values.len() / width, ty);
    json!({ "name": name,
        "channels": [{ "sampler": 0, "target": { "node": 0, "path": path } }],
        "samplers": [{ "input": input, "output": output, "interpolation": interpolation }] })
}

fn load_at(doc: &Doc, animation: Option<&str>, seconds: f32) -> Result<Scene, SceneError> {
    let dir = tempfile::tempdir().expect("tempdir");
    let options = LoadOptions {
        animation: Some(AnimationTime {
            animation: animation.map(str::to_owned),
            seconds,
        }),
        ..LoadOptions::default()
    };
    scene::gltf::load_with(&doc.write(dir.path(), Layout::DataUri), &options)
}

fn first_vertex(scene: &Scene) -> Vec3 {
    scene.triangles[0].vertices[0].position
}

fn assert_close(a: Vec3, b: Vec3) {
    assert!(a.abs_diff_eq(b, EPS), "{a} != {b}");
}

/// Two clips of node 0's translation: "slide" moves it from x = 0 to x = 4 over two seconds
/// (LINEAR), "hop" steps it up to y = 3 at one second (STEP). The file's own placement stands
/// without an animation; each clip is chosen by index or name, and holds its first and last
/// keys outside its times.
#[test]
fn a_chosen_animation_moves_its_node_at_the_moment_asked() {
    let doc = animated(|doc| {
        let slide = (
            [0.0, 2.0].as_slice(),
            [0.0, 0.0, 0.0, 4.0, 0.0, 0.0].as_slice(),
            "VEC3",
        );
        let hop = (
            [0.0, 1.0].as_slice(),
            [0.0, 0.0, 0.0, 0.0, 3.0, 0.0].as_slice(),
            "VEC3",
        );
        vec![
            animation(doc, "slide", "translation", slide, "LINEAR"),
            animation(doc, "hop", "translation", hop, "STEP"),
        ]
    });
    let still = doc.load().unwrap();
    assert_close(first_vertex(&still), Vec3::new(0.0, 0.0, 5.0));
    let clip = |name: &str, seconds: f32| AnimationClip {
        name: Some(name.to_owned()),
        seconds,
    };
    assert_eq!(still.animations, [clip("slide", 2.0), clip("hop", 1.0)]);
    let at = |animation: Option<&str>, seconds: f32| {
        first_vertex(&load_at(&doc, animation, seconds).unwrap())
    };
    assert_close(at(None, 0.5), Vec3::new(1.0, 0.0, 0.0));
    assert_close(at(Some("0"), 1.5), Vec3::new(3.0, 0.0, 0.0));
    assert_close(at(Some("slide"), 9.0), Vec3::new(4.0, 0.0, 0.0));
    assert_close(at(Some("slide"), -1.0), Vec3::ZERO);
    assert_close(at(Some("hop"), 0.99), Vec3::ZERO);
    assert_close(at(Some("1"), 1.0), Vec3::new(0.0, 3.0, 0.0));

    // Which clip options pose the scene by, as the view's overlay shows it: by index or name,
    // the first where none is named, none unposed or for a name the file lacks.
    let posed_by = |animation: Option<&str>| LoadOptions {
        animation: Some(AnimationTime {
            animation: animation.map(str::to_owned),
            seconds: 0.5,
        }),
        ..LoadOptions::default()
    };
    assert_eq!(posed_by(None).animation_index(&still), Some(0));
    assert_eq!(posed_by(Some("hop")).animation_index(&still), Some(1));
    assert_eq!(posed_by(Some("1")).animation_index(&still), Some(1));
    assert_eq!(posed_by(Some("walk")).animation_index(&still), None);
    assert_eq!(LoadOptions::default().animation_index(&still), None);
}

/// Rotations blend along the great arc, and a scale keyed alone leaves the node's translation.
#[test]
fn rotations_slerp_and_each_property_is_set_alone() {
    let quarter = Quat::from_rotation_z(std::f32::consts::FRAC_PI_2);
    let doc = animated(|doc| {
        let rotations = [Quat::IDENTITY.to_array(), quarter.to_array()].concat();
        let turn = ([0.0, 1.0].as_slice(), rotations.as_slice(), "VEC4");
        let grow = (
            [0.0, 1.0].as_slice(),
            [1.0, 1.0, 1.0, 3.0, 3.0, 3.0].as_slice(),
            "VEC3",
        );
        vec![
            animation(doc, "turn", "rotation", turn, "LINEAR"),
            animation(doc, "grow", "scale", grow, "LINEAR"),
        ]
    });
    let turned = load_at(&doc, Some("turn"), 0.5).unwrap();
    let eighth = Quat::from_rotation_z(std::f32::consts::FRAC_PI_4);
    let expected = Vec3::new(0.0, 0.0, 5.0) + eighth * Vec3::X;
    assert_close(turned.triangles[0].vertices[1].position, expected);
    let grown = load_at(&doc, Some("grow"), 0.5).unwrap();
    assert_close(
        grown.triangles[0].vertices[1].position,
        Vec3::new(2.0, 0.0, 5.0),
    );
}

/// CUBICSPLINE keys (in-tangent, value, out-tangent) with zero tangents ease in and out: a
/// quarter of the way through, a smoothstep's 5/32 of the way.
#[test]
fn cubic_splines_ease_by_their_tangents() {
    let doc = animated(|doc| {
        let keys = [
            [0.0; 3],
            [0.0; 3],
            [0.0; 3],
            [0.0; 3],
            [4.0, 0.0, 0.0],
            [0.0; 3],
        ]
        .concat();
        let ease = ([0.0, 2.0].as_slice(), keys.as_slice(), "VEC3");
        vec![animation(doc, "ease", "translation", ease, "CUBICSPLINE")]
    });
    let scene = load_at(&doc, None, 0.5).unwrap();
    assert_close(first_vertex(&scene), Vec3::new(4.0 * 5.0 / 32.0, 0.0, 0.0));
}

/// Morph target weights are animated as the node's own weights would be.
#[test]
fn morph_weights_follow_their_channel() {
    let mut doc = Doc::default();
    let position = doc.vec3s(&TRIANGLE);
    let displacement = doc.vec3s(&[[0.0; 3], [0.0; 3], [0.0, 0.0, 2.0]]);
    let primitive = json!({ "attributes": { "POSITION": position },
        "targets": [{ "POSITION": displacement }] });
    let mesh = doc.push(
        "meshes",
        json!({ "primitives": [primitive], "weights": [0.0] }),
    );
    let node = doc.node(json!({ "mesh": mesh }));
    doc.add_root(node);
    let blink = animation(
        &mut doc,
        "blink",
        "weights",
        (&[0.0, 1.0], &[0.0, 1.0], "SCALAR"),
        "LINEAR",
    );
    doc.json["animations"] = json!([blink]);
    let scene = load_at(&doc, None, 0.25).unwrap();
    assert_close(
        scene.triangles[0].vertices[2].position,
        Vec3::new(0.0, 1.0, 0.5),
    );
}

#[test]
fn bad_animation_choices_and_keys_are_refused_in_one_line() {
    let slide = |doc: &mut Doc, times: &[f32], values: &[f32]| {
        animation(
            doc,
            "slide",
            "translation",
            (times, values, "VEC3"),
            "LINEAR",
        )
    };
    let good = animated(|doc| vec![slide(doc, &[0.0, 2.0], &[0.0; 6])]);
    assert_mentions(
        &error_of(load_at(&good, Some("run"), 1.0)),
        &["no animation \"run\" (the file has 0 \"slide\")"],
    );
    assert_mentions(&error_of(load_at(&good, None, f32::NAN)), &["not a finite"]);
    let still = quad_doc(None);
    assert_mentions(&error_of(load_at(&still, None, 1.0)), &["no animation"]);
    let backwards = animated(|doc| vec![slide(doc, &[2.0, 1.0], &[0.0; 6])]);
    assert_mentions(
        &error_of(load_at(&backwards, None, 1.0)),
        &["animation 0 channel 0", "strictly increasing"],
    );
    let short = animated(|doc| vec![slide(doc, &[0.0, 1.0], &[0.0; 3])]);
    assert_mentions(
        &error_of(load_at(&short, None, 1.0)),
        &["3 output values for 2 keys of 3 (LINEAR)"],
    );
    let mut matrix = animated(|doc| vec![slide(doc, &[0.0, 1.0], &[0.0; 6])]);
    let node = &mut matrix.json["nodes"][0];
    node.as_object_mut().unwrap().remove("translation");
    node["matrix"] = json!([1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1]);
    assert_mentions(
        &error_of(load_at(&matrix, None, 1.0)),
        &["node 0 has a matrix"],
    );
}
