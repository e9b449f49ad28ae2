//! `kousen render --checkpoint` / `--resume`: a render stopped and continued writes the same
//! image, byte for byte, as one that was never stopped; a checkpoint that does not fit the
//! render, or is not one, is refused in one line and no image is written.

use crate::common;

use std::path::Path;

use common::*;

fn render(out: &Path, extra: &str) -> std::process::Output {
    let scene = shipped("cornell-caustics.gltf");
    let mut args = vec!["render", scene.as_str(), "-o", out.to_str().unwrap()];
    args.extend("--width 40 --height 32 --eye-every 3 --backend cpu".split_whitespace());
    args.extend(extra.split_whitespace());
    kousen(&args)
}

#[test]
fn resumed_render_writes_the_uninterrupted_image() {
    let dir = tempfile::tempdir().unwrap();
    let path = |name: &str| dir.path().join(name);
    let checkpoint = path("render.ckpt");
    let ck = checkpoint.to_str().unwrap();
    succeeded(render(&path("straight.pfm"), "--passes 7"));
    succeeded(render(
        &path("first.pfm"),
        &format!("--passes 4 --checkpoint {ck}"),
    ));
    let stats = path("stats.json");
    succeeded(render(
        &path("continued.pfm"),
        &format!(
            "--passes 7 --resume {ck} --checkpoint {ck} --stats {}",
            stats.display()
        ),
    ));
    let read = |name: &str| std::fs::read(path(name)).unwrap();
    assert_eq!(read("continued.pfm"), read("straight.pfm"));
    assert_ne!(read("first.pfm"), read("straight.pfm"));
    let stats: serde_json::Value = serde_json::from_slice(&std::fs::read(&stats).unwrap()).unwrap();
    assert_eq!(stats["resumed_passes"], 4);
    assert_eq!(stats["passes"], 7);
    // The rate is this run's: three passes' paths over this run's seconds, below the total's.
    let (paths, seconds) = (
        stats["photon_paths"].as_f64().unwrap(),
        stats["seconds"].as_f64().unwrap(),
    );
    let rate = stats["photon_paths_per_second"].as_f64().unwrap();
    assert!(
        rate > 0.0 && rate < paths / seconds,
        "{rate} {paths} {seconds}"
    );
    // The checkpoint now holds all seven passes: resuming it for seven does no more work.
    succeeded(render(
        &path("again.pfm"),
        &format!("--passes 7 --resume {ck}"),
    ));
    assert_eq!(read("again.pfm"), read("straight.pfm"));
}

#[test]
fn checkpoint_that_does_not_fit_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let checkpoint = dir.path().join("render.ckpt");
    let ck = checkpoint.to_str().unwrap();
    succeeded(render(
        &dir.path().join("a.pfm"),
        &format!("--passes 2 --checkpoint {ck}"),
    ));
    let out = dir.path().join("b.pfm");
    let default_share = format!(
        "--caustic-radius {}",
        render::settings::MEASURED_CAUSTIC_RADIUS_SHARE
    );
    let cases = [
        (format!("--passes 4 --resume {ck} --seed 5"), "--seed 0"),
        (
            format!("--passes 4 --resume {ck} --photons 4096"),
            "--photons",
        ),
        (
            format!("--passes 4 --resume {ck} --density kdtree"),
            "--density full",
        ),
        (
            format!("--passes 4 --resume {ck} --fov 30 --eye=0,300,-700 --target=0,300,0"),
            "camera",
        ),
        (
            format!("--passes 4 --resume {ck} --radius 4"),
            "initial radius",
        ),
        (
            format!("--passes 4 --resume {ck} --direct-light photons"),
            "--direct-light sampled",
        ),
        (
            format!("--passes 4 --resume {ck} --caustic-radius 0.5"),
            default_share.as_str(),
        ),
    ];
    for (extra, needle) in cases {
        assert_clean_error(&render(&out, &extra), needle);
        assert!(!out.exists(), "{extra}: an image was written");
    }
    let cut = write(
        dir.path(),
        "cut.ckpt",
        &std::fs::read(&checkpoint).unwrap()[..200],
    );
    assert_clean_error(
        &render(&out, &format!("--resume {}", cut.display())),
        "truncated",
    );
    let text = write(dir.path(), "text.ckpt", b"not a checkpoint at all");
    assert_clean_error(
        &render(&out, &format!("--resume {}", text.display())),
        "not a kousen checkpoint",
    );
    assert_clean_error(
        &render(
            &out,
            &format!("--checkpoint {ck} --integrator path --passes 1"),
        ),
        "--integrator path",
    );
    assert!(!out.exists());
}

/// Starts a long render of cornell-caustics with `extra` arguments, sends it Ctrl-C (SIGINT)
/// after two seconds and checks that it ended as interrupted (exit code 130, one line saying
/// so); returns the statistics it wrote to `stats`.
#[cfg(unix)]
fn interrupted_render(image: &Path, stats: &Path, extra: &[&str]) -> serde_json::Value {
    use std::process::{Command, Stdio};
    let scene = shipped("cornell-caustics.gltf");
    let child = Command::new(env!("CARGO_BIN_EXE_kousen"))
        .args(["render", scene.as_str(), "-o", image.to_str().unwrap()])
        .args("--width 40 --height 32 --eye-every 3 --backend cpu --time 300".split(' '))
        .args(["--stats", stats.to_str().unwrap()])
        .args(extra)
        .env("RUST_LOG", "error")
        .stderr(Stdio::piped())
        .spawn()
        .expect("the kousen binary runs");
    // Long enough for the handler (installed before the scene loads) and a few passes.
    std::thread::sleep(std::time::Duration::from_secs(2));
    let sent = Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status()
        .expect("kill runs");
    assert!(sent.success());
    let output = child.wait_with_output().unwrap();
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(130), "{stderr}");
    assert!(stderr.contains("interrupted after"), "{stderr}");
    serde_json::from_slice(&std::fs::read(stats).unwrap()).unwrap()
}

/// Ctrl-C (SIGINT) ends a long render after the pass in flight: exit code 130, and the image,
/// the statistics and a checkpoint that `--resume` continues are all written.
#[cfg(unix)]
#[test]
fn ctrl_c_stops_the_render_and_saves_it() {
    let dir = tempfile::tempdir().unwrap();
    let path = |name: &str| dir.path().join(name);
    let (image, checkpoint, stats) = (path("cut.pfm"), path("cut.ckpt"), path("cut.json"));
    let stats = interrupted_render(
        &image,
        &stats,
        &["--checkpoint", checkpoint.to_str().unwrap()],
    );
    let passes = stats["passes"].as_u64().expect("passes");
    assert!(
        passes >= 1 && stats["seconds"].as_f64().unwrap() < 60.0,
        "{stats}"
    );
    assert!(image.exists() && checkpoint.exists());
    let more = (passes + 2).to_string();
    succeeded(render(
        &path("more.pfm"),
        &format!("--passes {more} --resume {}", checkpoint.display()),
    ));
}

/// The path integrator stops on Ctrl-C too, writing its image and statistics.
#[cfg(unix)]
#[test]
fn ctrl_c_stops_a_path_traced_render_and_saves_it() {
    let dir = tempfile::tempdir().unwrap();
    let (image, stats) = (dir.path().join("cut.pfm"), dir.path().join("cut.json"));
    let stats = interrupted_render(&image, &stats, &["--integrator", "path"]);
    assert_eq!(stats["integrator"], "path");
    let passes = stats["passes"].as_u64().expect("passes");
    assert!(
        passes >= 1 && stats["seconds"].as_f64().unwrap() < 60.0,
        "{stats}"
    );
    // A whole PFM: its header, then 40 × 32 RGB floats.
    let bytes = std::fs::read(&image).expect("the image was written");
    assert!(
        bytes.starts_with(b"PF\n40 32\n"),
        "{:?}",
        &bytes[..12.min(bytes.len())]
    );
    assert!(bytes.len() > 40 * 32 * 12, "{} bytes", bytes.len());
}

/// `--save-at`: the images saved on the way are those of renders stopped there, byte for
/// byte, and saving them changes nothing after; a resumed render saves only the moments
/// still ahead of it; `--stats` says how far the render had come at each.
#[test]
fn images_saved_on_the_way_are_those_of_shorter_renders() {
    let dir = tempfile::tempdir().unwrap();
    let path = |name: &str| dir.path().join(name);
    let read = |name: &str| std::fs::read(path(name)).unwrap();
    for passes in [4, 6, 7] {
        succeeded(render(
            &path(&format!("plain-{passes}.pfm")),
            &format!("--passes {passes}"),
        ));
    }
    let stats = path("stats.json");
    let stats_arg = format!("--stats {}", stats.display());
    succeeded(render(
        &path("along.pfm"),
        &format!("--passes 7 --save-at 4,7 {stats_arg}"),
    ));
    assert_eq!(read("along-4.pfm"), read("plain-4.pfm"));
    assert_eq!(read("along-7.pfm"), read("plain-7.pfm"));
    assert_eq!(read("along.pfm"), read("plain-7.pfm"));
    let stats: serde_json::Value = serde_json::from_slice(&read("stats.json")).unwrap();
    let saved = stats["saved_images"].as_array().unwrap();
    let passes: Vec<u64> = saved
        .iter()
        .map(|s| s["passes"].as_u64().unwrap())
        .collect();
    assert_eq!(passes, [4, 7]);
    assert!(saved[0]["file"].as_str().unwrap().ends_with("along-4.pfm"));

    let ck = path("render.ckpt");
    let ck = ck.to_str().unwrap();
    succeeded(render(
        &path("first.pfm"),
        &format!("--passes 4 --checkpoint {ck}"),
    ));
    succeeded(render(
        &path("continued.pfm"),
        &format!("--passes 7 --resume {ck} --save-at 2,6"),
    ));
    assert!(
        !path("continued-2.pfm").exists(),
        "a moment behind the resumed render was saved"
    );
    assert_eq!(read("continued-6.pfm"), read("plain-6.pfm"));

    // A moment past the end, or for the path tracer, is refused before any file is made.
    let late = render(&path("late.pfm"), "--passes 7 --save-at 3,9");
    assert_clean_error(&late, "--save-at 9: past the render's end");
    let traced = render(
        &path("late.pfm"),
        "--passes 7 --save-at 3 --integrator path",
    );
    assert_clean_error(&traced, "--save-at is for SPPM renders");
    let made: Vec<_> = std::fs::read_dir(dir.path()).unwrap().flatten().collect();
    assert!(
        made.iter()
            .all(|f| !f.file_name().to_string_lossy().starts_with("late"))
    );
}
