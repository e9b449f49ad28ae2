//! Bad input to `kousen info` and `kousen render`: each a one-line error and a non-zero exit,
//! never a panic, never a half-written file.

use crate::common;

use common::*;
use serde_json::json;

fn info(path: &std::path::Path) -> std::process::Output {
    kousen(&["info", path.to_str().unwrap()])
}

#[test]
fn missing_file_is_a_clean_error() {
    let dir = tempfile::tempdir().unwrap();
    for name in ["absent.gltf", "absent.glb", "absent.obj"] {
        assert_clean_error(&info(&dir.path().join(name)), "absent");
    }
}

#[test]
fn empty_files_are_clean_errors() {
    let dir = tempfile::tempdir().unwrap();
    for name in ["empty.gltf", "empty.glb", "empty.obj"] {
        let path = write(dir.path(), name, b"");
        assert_clean_error(&info(&path), name);
    }
}

#[test]
fn truncated_glb_is_a_clean_error() {
    let dir = tempfile::tempdir().unwrap();
    let document = gltf(&QUAD, Some(&QUAD_INDICES), 4, json!({}));
    let whole = glb(&document, &[]);
    let path = write(dir.path(), "cut.glb", &whole[..whole.len() / 2]);
    assert_clean_error(&info(&path), "cut.glb");
    // A header that claims far more than the file holds.
    let mut lying = whole.clone();
    lying[8..12].copy_from_slice(&u32::MAX.to_le_bytes());
    let path = write(dir.path(), "lying.glb", &lying);
    assert_clean_error(&info(&path), "lying.glb");
}

#[test]
fn malformed_json_is_a_clean_error() {
    let dir = tempfile::tempdir().unwrap();
    let path = write(
        dir.path(),
        "broken.gltf",
        b"{\"asset\": {\"version\": \"2.0\"}, \"nodes\": [",
    );
    assert_clean_error(&info(&path), "broken.gltf");
}

#[test]
fn index_out_of_range_is_a_clean_error() {
    let dir = tempfile::tempdir().unwrap();
    let document = gltf(&QUAD, Some(&[0, 1, 2, 0, 2, 99]), 4, json!({}));
    let path = write(dir.path(), "index.gltf", &document);
    assert_clean_error(&info(&path), "99");
}

#[test]
fn non_finite_positions_are_clean_errors() {
    let dir = tempfile::tempdir().unwrap();
    for (name, bad) in [("nan.gltf", f32::NAN), ("inf.gltf", f32::INFINITY)] {
        let mut positions = QUAD;
        positions[2][1] = bad;
        let document = gltf(&positions, Some(&QUAD_INDICES), 4, json!({}));
        let path = write(dir.path(), name, &document);
        assert_clean_error(&info(&path), name);
    }
    let path = write(
        dir.path(),
        "nan.obj",
        b"v 0 0 0\nv 1 0 nan\nv 0 1 0\nf 1 2 3\n",
    );
    assert_clean_error(&info(&path), "nan.obj");
}

#[test]
fn non_triangle_primitive_only_is_a_clean_error() {
    let dir = tempfile::tempdir().unwrap();
    // Mode 1: lines.
    let document = gltf(&QUAD, Some(&QUAD_INDICES), 1, json!({}));
    let path = write(dir.path(), "lines.gltf", &document);
    assert_clean_error(&info(&path), "triangle");
}

#[test]
fn unknown_required_extension_is_a_clean_error() {
    let dir = tempfile::tempdir().unwrap();
    let extra = json!({
        "extensionsUsed": ["EXT_made_up_thing"],
        "extensionsRequired": ["EXT_made_up_thing"],
    });
    let document = gltf(&QUAD, Some(&QUAD_INDICES), 4, extra);
    let path = write(dir.path(), "extension.gltf", &document);
    assert_clean_error(&info(&path), "EXT_made_up_thing");
}

#[test]
fn zero_triangles_is_a_clean_error() {
    let dir = tempfile::tempdir().unwrap();
    // Every triangle degenerate: all three corners on a line.
    let line = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [2.0, 0.0, 0.0]];
    let document = gltf(&line, None, 4, json!({}));
    let path = write(dir.path(), "flat.gltf", &document);
    assert_clean_error(&info(&path), "no triangles");
    let path = write(dir.path(), "nothing.obj", b"# only a comment\nv 0 0 0\n");
    assert_clean_error(&info(&path), "no triangles");
}

#[test]
fn unknown_scene_extension_is_a_clean_error() {
    let dir = tempfile::tempdir().unwrap();
    let path = write(dir.path(), "scene.fbx", b"whatever");
    assert_clean_error(&info(&path), "unknown scene format");
}

fn lit_quad_scene(dir: &std::path::Path) -> std::path::PathBuf {
    let extra = json!({
        "materials": [{"emissiveFactor": [1.0, 1.0, 1.0]}],
    });
    let mut document: serde_json::Value =
        serde_json::from_slice(&gltf(&QUAD, Some(&QUAD_INDICES), 4, extra)).unwrap();
    document["meshes"][0]["primitives"][0]["material"] = json!(0);
    write(dir, "lit.gltf", &serde_json::to_vec(&document).unwrap())
}

#[test]
fn render_refuses_a_scene_without_light() {
    let dir = tempfile::tempdir().unwrap();
    let path = write(
        dir.path(),
        "dark.gltf",
        &gltf(&QUAD, Some(&QUAD_INDICES), 4, json!({})),
    );
    let out = dir.path().join("dark.png");
    let output = kousen(&[
        "render",
        path.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
    ]);
    assert_clean_error(&output, "emissive");
    assert_no_files_but(dir.path(), &["dark.gltf"]);
}

#[test]
fn render_refuses_bad_outputs_and_leaves_no_file() {
    let dir = tempfile::tempdir().unwrap();
    let scene = lit_quad_scene(dir.path());
    let scene = scene.to_str().unwrap();
    let unwritable = dir.path().join("no/such/folder/out.png");
    let output = kousen(&[
        "render",
        scene,
        "-o",
        unwritable.to_str().unwrap(),
        "--passes",
        "1",
    ]);
    assert_clean_error(&output, "out.png");
    let unknown = dir.path().join("out.bmpx");
    let output = kousen(&[
        "render",
        scene,
        "-o",
        unknown.to_str().unwrap(),
        "--passes",
        "1",
    ]);
    assert_clean_error(&output, "extension");
    assert_no_files_but(dir.path(), &["lit.gltf"]);
}

#[test]
fn render_refuses_bad_sppm_settings_and_leaves_no_file() {
    let dir = tempfile::tempdir().unwrap();
    let scene = lit_quad_scene(dir.path());
    let out = dir.path().join("out.exr");
    for (flag, value, words) in [
        ("--photons", "0", "--photons"),
        ("--alpha", "1.5", "--alpha"),
        ("--caustic-radius", "0", "--caustic-radius"),
        ("--caustic-radius", "1.5", "--caustic-radius"),
        ("--eye-every", "0", "--eye-every"),
        ("--hash-ratio", "0", "--hash-ratio"),
        ("--max-depth", "0", "--max-depth"),
        ("--light-candidates", "0", "--light-candidates"),
        ("--light-candidates", "65", "--light-candidates"),
    ] {
        let output = kousen(&[
            "render",
            scene.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
            "--backend",
            "cpu",
            "--passes",
            "1",
            flag,
            value,
        ]);
        assert_clean_error(&output, words);
        assert_no_files_but(dir.path(), &["lit.gltf"]);
    }
}

/// A lens's radius must be ≥ 0 and its focus distance > 0, its aperture round or of 3 to 64
/// blades, a focus distance or blades need a lens, and a lens left to focus itself needs a
/// surface at the image's centre.
#[test]
fn render_refuses_bad_lenses_and_leaves_no_file() {
    let dir = tempfile::tempdir().unwrap();
    let scene = lit_quad_scene(dir.path());
    let out = dir.path().join("out.png");
    let away = ["--eye", "0.5,1,0.5", "--target", "0.5,1,-3"];
    let cases: [(&[&str], &str); 14] = [
        (
            &["--aperture-radius", "0.1", "--focus-pixel", "9,9"],
            "--focus-pixel",
        ),
        (
            &["--aperture-radius", "0.1", "--focus-pixel", "1"],
            "--focus-pixel",
        ),
        (
            &["--aperture-radius", "0.1", "--focus-pixel", "a,b"],
            "--focus-pixel",
        ),
        (&["--focus-pixel", "1,1"], "--aperture-radius"),
        (
            &[
                "--aperture-radius",
                "0.1",
                "--focus-pixel",
                "1,1",
                "--focus-distance",
                "2",
            ],
            "give one",
        ),
        (
            &["--aperture-radius", "0.1", "--aperture-blades", "2"],
            "--aperture-blades",
        ),
        (
            &["--aperture-radius", "0.1", "--aperture-blades", "65"],
            "--aperture-blades",
        ),
        (&["--aperture-blades", "6"], "--aperture-radius"),
        (&["--aperture-radius", "-0.1"], "--aperture-radius"),
        (&["--aperture-radius", "nan"], "--aperture-radius"),
        (&["--focus-distance", "2"], "--aperture-radius"),
        (
            &["--aperture-radius", "0.1", "--focus-distance", "0"],
            "--focus-distance",
        ),
        (
            &["--aperture-radius", "0.1", "--focus-distance", "inf"],
            "--focus-distance",
        ),
        (
            &[&["--aperture-radius", "0.1"][..], &away[..]].concat(),
            "--focus-distance",
        ),
    ];
    for (flags, words) in cases {
        let mut args = vec![
            "render",
            scene.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
        ];
        args.extend(["--backend", "cpu", "--passes", "1", "--width", "8"]);
        args.extend(flags);
        assert_clean_error(&kousen(&args), words);
        assert_no_files_but(dir.path(), &["lit.gltf"]);
    }
}

/// An orthographic glTF camera 2 above the glowing quad looking down, its film a quarter of
/// the quad's side about its centre: every pixel sees the quad (a perspective camera there
/// would see past its edges). It has no lens: `--aperture-radius` is refused in one line.
#[test]
fn render_sees_through_an_orthographic_camera_which_has_no_lens() {
    let dir = tempfile::tempdir().unwrap();
    let scene = lit_quad_scene(dir.path());
    let mut document: serde_json::Value =
        serde_json::from_slice(&std::fs::read(&scene).unwrap()).unwrap();
    document["cameras"] = json!([{ "type": "orthographic",
        "orthographic": { "xmag": 0.25, "ymag": 0.25, "znear": 0.01, "zfar": 10 } }]);
    let down = [
        -std::f32::consts::FRAC_1_SQRT_2,
        0.0,
        0.0,
        std::f32::consts::FRAC_1_SQRT_2,
    ];
    document["nodes"]
        .as_array_mut()
        .unwrap()
        .push(json!({ "camera": 0, "translation": [0.5, 2, 0.5], "rotation": down }));
    document["scenes"][0]["nodes"] = json!([0, 1]);
    let scene = write(
        dir.path(),
        "lit.gltf",
        &serde_json::to_vec(&document).unwrap(),
    );
    let out = dir.path().join("out.png");
    let render = |extra: &[&str]| render_small(&scene, &out, extra);
    assert_clean_error(
        &render(&["--aperture-radius", "0.1"]),
        "orthographic and has no lens",
    );
    assert_no_files_but(dir.path(), &["lit.gltf"]);
    assert_succeeded(&render(&[]));
    let image = image::open(&out).unwrap().to_rgb8();
    assert_eq!(
        image.dimensions(),
        (16, 16),
        "xmag / ymag sets the aspect ratio"
    );
    assert!(
        image.pixels().all(|p| p.0.iter().all(|&c| c >= 250)),
        "a pixel missed the quad"
    );
}

/// [`lit_quad_scene`] with an animation "lift" raising the glowing quad from y = 0 to 3 over a
/// second, written as `lift.gltf`; `edit` changes the document first.
fn lifted_quad_scene(
    dir: &std::path::Path,
    edit: impl FnOnce(&mut serde_json::Value),
) -> std::path::PathBuf {
    let still = lit_quad_scene(dir);
    let mut document: serde_json::Value =
        serde_json::from_slice(&std::fs::read(&still).unwrap()).unwrap();
    let keys: Vec<u8> = [0.0f32, 1.0, 0.0, 0.0, 0.0, 0.0, 3.0, 0.0]
        .iter()
        .flat_map(|x| x.to_le_bytes())
        .collect();
    document["buffers"]
        .as_array_mut()
        .unwrap()
        .push(json!({ "byteLength": keys.len(), "uri": data_uri(&keys) }));
    let views = document["bufferViews"].as_array_mut().unwrap();
    views.push(json!({ "buffer": 1, "byteOffset": 0, "byteLength": 8 }));
    views.push(json!({ "buffer": 1, "byteOffset": 8, "byteLength": 24 }));
    let (times_view, values_view) = (views.len() - 2, views.len() - 1);
    let accessors = document["accessors"].as_array_mut().unwrap();
    accessors.push(
        json!({ "bufferView": times_view, "componentType": 5126, "count": 2,
        "type": "SCALAR", "min": [0.0], "max": [1.0] }),
    );
    accessors.push(
        json!({ "bufferView": values_view, "componentType": 5126, "count": 2,
        "type": "VEC3" }),
    );
    let (times, values) = (accessors.len() - 2, accessors.len() - 1);
    document["animations"] = json!([{ "name": "lift",
        "channels": [{ "sampler": 0, "target": { "node": 0, "path": "translation" } }],
        "samplers": [{ "input": times, "output": values }] }]);
    edit(&mut document);
    write(dir, "lift.gltf", &serde_json::to_vec(&document).unwrap())
}

/// `--animation-time` poses the scene by its animation (here one lifting the glowing quad from
/// y = 0 to 3 over a second): `info` sees it half way up; a name that names no animation, or
/// a file without animations, is refused in one line, leaving no file.
#[test]
fn animation_times_pose_the_scene_or_are_refused_in_one_line() {
    let dir = tempfile::tempdir().unwrap();
    let lifted = lifted_quad_scene(dir.path(), |_| {});
    let still = dir.path().join("lit.gltf");
    let info = |scene: &std::path::Path, extra: &[&str]| {
        let mut args = vec!["info", scene.to_str().unwrap(), "--json"];
        args.extend(extra);
        kousen(&args)
    };
    let output = succeeded(info(
        &lifted,
        &["--animation-time", "0.5", "--animation", "lift"],
    ));
    let json: serde_json::Value = serde_json::from_slice(&output.stdout).unwrap();
    assert_eq!(json["bounds"]["min"][1], json!(1.5), "{}", json["bounds"]);
    assert_eq!(
        json["animations"],
        json!([{ "name": "lift", "seconds": 1.0 }])
    );
    let out = dir.path().join("out.png");
    let render = |scene: &std::path::Path, extra: &[&str]| render_small(scene, &out, extra);
    let wrong = render(&lifted, &["--animation-time", "0.5", "--animation", "walk"]);
    assert_clean_error(&wrong, "no animation \"walk\" (the file has 0 \"lift\")");
    assert_clean_error(&render(&still, &["--animation-time", "1"]), "no animations");
    assert_no_files_but(dir.path(), &["lift.gltf", "lit.gltf"]);
}

/// `--frames 1-2 --fps 2` renders the lifted quad at 0.5 s and 1 s, seen from a camera above
/// it looking down: `seq-0001.png` is byte for byte the render with `--animation-time 0.5`
/// (the glowing quad fills the view), `seq-0002.png` the one at 1 s (the quad has risen past
/// the camera: black), each with its own `--stats`; bad frame lists and a checkpoint are
/// refused in one line, leaving no file.
#[test]
fn frames_render_an_animation_frame_by_frame() {
    let dir = tempfile::tempdir().unwrap();
    let lifted = lifted_quad_scene(dir.path(), |document| {
        document["cameras"] = json!([{ "type": "perspective",
            "perspective": { "yfov": 0.8, "znear": 0.01 } }]);
        // At (0.5, 2, 0.5), turned −90° about x: looking down −y onto the quad.
        let camera = json!({ "camera": 0, "translation": [0.5, 2.0, 0.5],
            "rotation": [-std::f32::consts::FRAC_1_SQRT_2, 0.0, 0.0, std::f32::consts::FRAC_1_SQRT_2] });
        document["nodes"].as_array_mut().unwrap().push(camera);
        document["scenes"][0]["nodes"]
            .as_array_mut()
            .unwrap()
            .push(json!(1));
    });
    let sequence = dir.path().join("seq.png");
    let stats = dir.path().join("seq.json");
    let stats_arg = ["--stats", stats.to_str().unwrap()];
    let frames = ["--frames", "1-2", "--fps", "2"];
    assert_succeeded(&render_small(
        &lifted,
        &sequence,
        &[&frames[..], &stats_arg].concat(),
    ));
    let single = dir.path().join("single.png");
    assert_succeeded(&render_small(
        &lifted,
        &single,
        &["--animation-time", "0.5"],
    ));
    let read = |name: &str| std::fs::read(dir.path().join(name)).unwrap();
    assert_eq!(read("seq-0001.png"), read("single.png"));
    assert_ne!(read("seq-0001.png"), read("seq-0002.png"));
    let radiance = |name: &str| {
        let json: serde_json::Value = serde_json::from_slice(&read(name)).unwrap();
        json["mean_radiance"][0].as_f64().unwrap()
    };
    assert!(
        radiance("seq-0001.json") > 0.5,
        "the quad fills the view at 0.5 s"
    );
    assert_eq!(radiance("seq-0002.json"), 0.0, "and has left it at 1 s");
    // --skip-existing renders only the frames missing: frame 2's image, removed, comes back
    // as it was; frame 1's, replaced by another file, stays that file.
    let second = read("seq-0002.png");
    std::fs::remove_file(dir.path().join("seq-0002.png")).unwrap();
    std::fs::write(dir.path().join("seq-0001.png"), b"kept").unwrap();
    let skipping = [&frames[..], &stats_arg, &["--skip-existing"]].concat();
    assert_succeeded(&render_small(&lifted, &sequence, &skipping));
    assert_eq!(read("seq-0002.png"), second);
    assert_eq!(read("seq-0001.png"), b"kept");
    assert_no_files_but(
        dir.path(),
        &[
            "lift.gltf",
            "lit.gltf",
            "seq-0001.json",
            "seq-0001.png",
            "seq-0002.json",
            "seq-0002.png",
            "single.png",
        ],
    );

    let out = dir.path().join("bad.png");
    let refused = |more: &[&str], words: &str| {
        assert_clean_error(&render_small(&lifted, &out, more), words);
    };
    // Malformed or conflicting frames are usage errors from the argument parser (exit 2).
    for (more, words) in [
        (&["--frames", "3-1"][..], "comes before"),
        (&["--frames", "1-x"], "not a frame number"),
        (
            &["--frames", "1-2", "--animation-time", "1"],
            "cannot be used with",
        ),
        (&["--fps", "30"], "--frames"),
    ] {
        let output = render_small(&lifted, &out, more);
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert_eq!(output.status.code(), Some(2), "{more:?}: {stderr}");
        assert!(stderr.contains(words), "{more:?}: {stderr}");
    }
    let checkpoint = dir.path().join("bad.ckpt");
    refused(
        &[
            "--frames",
            "1-2",
            "--checkpoint",
            checkpoint.to_str().unwrap(),
        ],
        "--checkpoint and --resume are for one image",
    );
    refused(&["--frames", "0", "--fps", "0"], "--fps must be a positive");
    assert!(!out.exists() && !checkpoint.exists());
}

#[test]
fn render_refuses_a_camera_index_out_of_range() {
    let dir = tempfile::tempdir().unwrap();
    let scene = lit_quad_scene(dir.path());
    let out = dir.path().join("out.png");
    let output = kousen(&[
        "render",
        scene.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
        "--camera",
        "3",
    ]);
    assert_clean_error(&output, "camera");
    assert_no_files_but(dir.path(), &["lit.gltf"]);
}

fn assert_no_files_but(dir: &std::path::Path, expected: &[&str]) {
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    assert_eq!(names, expected, "stray files left behind");
}

/// `kousen view` where no display can be reached: one line that points to `kousen render`.
#[test]
fn view_without_a_display_suggests_render() {
    let output = std::process::Command::new(env!("CARGO_BIN_EXE_kousen"))
        .args([
            "view",
            &format!(
                "{}/../../scenes/cornell-box.gltf",
                env!("CARGO_MANIFEST_DIR")
            ),
        ])
        .env_remove("DISPLAY")
        .env_remove("WAYLAND_DISPLAY")
        .env_remove("WAYLAND_SOCKET")
        .output()
        .unwrap();
    assert_clean_error(&output, "kousen render");
}

/// Bad `kousen view` arguments fail before a window is asked for.
#[test]
fn view_bad_arguments_are_clean_errors() {
    let scene = format!(
        "{}/../../scenes/cornell-box.gltf",
        env!("CARGO_MANIFEST_DIR")
    );
    let dir = tempfile::tempdir().unwrap();
    let absent = dir.path().join("absent.gltf");
    assert_clean_error(&kousen(&["view", absent.to_str().unwrap()]), "absent");
    assert_clean_error(
        &kousen(&["view", &scene, "--screenshot-after", "1", "shot.exr"]),
        "png",
    );
    assert_clean_error(
        &kousen(&["view", &scene, "--render-scale", "0"]),
        "render-scale",
    );
    assert_clean_error(&kousen(&["view", &scene, "--alpha", "1.5"]), "alpha");
    // The gather options `kousen render` takes, checked the same way.
    assert_clean_error(&kousen(&["view", &scene, "--indirect-alpha", "1"]), "alpha");
    assert_clean_error(&kousen(&["view", &scene, "--radius", "0"]), "--radius");
    assert_clean_error(
        &kousen(&["view", &scene, "--caustic-radius", "1.5"]),
        "caustic",
    );
}
