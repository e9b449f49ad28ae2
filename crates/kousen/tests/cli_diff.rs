//! `kousen diff A B`: the figures it prints and writes as JSON, and clean errors for images that
//! cannot be compared. The images are PFM files written here by hand.

use crate::common;

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use common::*;

/// A colour PFM: little-endian, rows bottom to top as the format has them.
fn pfm(dir: &Path, name: &str, width: u32, height: u32, pixel: [f32; 3]) -> PathBuf {
    let mut bytes = format!("PF\n{width} {height}\n-1.0\n").into_bytes();
    for _ in 0..width * height {
        bytes.extend(pixel.iter().flat_map(|c| c.to_le_bytes()));
    }
    write(dir, name, &bytes)
}

/// A colour PFM whose pixel at column x, row y (row 0 at the top, as images are shown) is
/// `pixel(x, y)`.
fn pfm_with(
    dir: &Path,
    name: &str,
    (width, height): (u32, u32),
    pixel: impl Fn(u32, u32) -> [f32; 3],
) -> PathBuf {
    let mut bytes = format!("PF\n{width} {height}\n-1.0\n").into_bytes();
    for y in (0..height).rev() {
        for x in 0..width {
            bytes.extend(pixel(x, y).iter().flat_map(|c| c.to_le_bytes()));
        }
    }
    write(dir, name, &bytes)
}

fn diff(a: &Path, b: &Path, extra: &[&str]) -> std::process::Output {
    let mut args = vec!["diff", a.to_str().unwrap(), b.to_str().unwrap()];
    args.extend(extra);
    kousen(&args)
}

/// The "name value" lines of a successful run.
fn figures(output: &std::process::Output) -> BTreeMap<String, f64> {
    assert_succeeded(output);
    let stdout = String::from_utf8(output.stdout.clone()).unwrap();
    stdout
        .lines()
        .map(|line| {
            let (name, value) = line.split_once(' ').expect("\"name value\"");
            (name.to_string(), value.parse().expect("a number"))
        })
        .collect()
}

fn assert_close(figures: &BTreeMap<String, f64>, name: &str, expected: f64) {
    let value = figures[name];
    assert!(
        (value - expected).abs() <= 1e-12 * expected.abs().max(1.0),
        "{name}: {value}, expected {expected}"
    );
}

#[test]
fn diff_prints_the_closed_form_figures() {
    let dir = tempfile::tempdir().unwrap();
    // B = (0.5, 1, 2), A = B + 0.25 everywhere.
    let reference = pfm(dir.path(), "b.pfm", 3, 2, [0.5, 1.0, 2.0]);
    let image = pfm(dir.path(), "a.pfm", 3, 2, [0.75, 1.25, 2.25]);
    let json = dir.path().join("diff.json");
    let output = diff(&image, &reference, &["--json", json.to_str().unwrap()]);
    let printed = figures(&output);

    let names = [
        "mean_ratio",
        "mean_ratio_b",
        "mean_ratio_g",
        "mean_ratio_r",
        "rel_mse",
        "rmse",
    ];
    assert_eq!(printed.keys().collect::<Vec<_>>(), names);
    let rel_mse = (0.0625 / 0.26 + 0.0625 / 1.01 + 0.0625 / 4.01) / 3.0;
    assert_close(&printed, "rel_mse", rel_mse);
    assert_close(&printed, "rmse", 0.25);
    assert_close(&printed, "mean_ratio", 4.25 / 3.5);
    assert_close(&printed, "mean_ratio_r", 1.5);
    assert_close(&printed, "mean_ratio_g", 1.25);
    assert_close(&printed, "mean_ratio_b", 1.125);

    let written: serde_json::Value =
        serde_json::from_slice(&std::fs::read(&json).unwrap()).unwrap();
    for name in names {
        assert_eq!(written[name].as_f64(), Some(printed[name]), "{name}");
    }
    assert_eq!(
        (written["width"].as_u64(), written["height"].as_u64()),
        (Some(3), Some(2))
    );
}

#[test]
fn diff_in_a_window_measures_only_its_pixels() {
    let dir = tempfile::tempdir().unwrap();
    let reference = pfm(dir.path(), "b.pfm", 4, 3, [1.0; 3]);
    // Twice the reference in the top row's two middle pixels, equal elsewhere.
    let image = pfm_with(dir.path(), "a.pfm", (4, 3), |x, y| {
        if y == 0 && (1..3).contains(&x) {
            [2.0; 3]
        } else {
            [1.0; 3]
        }
    });
    let json = dir.path().join("window.json");
    let inside = figures(&diff(
        &image,
        &reference,
        &["--window", "1,0,2,1", "--json", json.to_str().unwrap()],
    ));
    assert_close(&inside, "rmse", 1.0);
    assert_close(&inside, "mean_ratio", 2.0);
    assert_close(&inside, "rel_mse", 1.0 / 1.01);
    let written: serde_json::Value =
        serde_json::from_slice(&std::fs::read(&json).unwrap()).unwrap();
    assert_eq!(written["window"], serde_json::json!([1, 0, 2, 1]));
    assert_eq!(
        (written["width"].as_u64(), written["height"].as_u64()),
        (Some(2), Some(1))
    );
    let below = figures(&diff(&image, &reference, &["--window", "0,1,4,2"]));
    assert_eq!(below["rmse"], 0.0);
    let whole = figures(&diff(&image, &reference, &[]));
    assert_close(&whole, "rmse", (2.0f64 / 12.0).sqrt());
}

#[test]
fn diff_window_outside_the_images_is_a_clean_error() {
    let dir = tempfile::tempdir().unwrap();
    let image = pfm(dir.path(), "a.pfm", 4, 3, [1.0; 3]);
    let outside = diff(&image, &image, &["--window", "3,0,2,1"]);
    assert_clean_error(&outside, "outside the 4x3 images");
    // Malformed rectangles are usage errors from the argument parser (exit 2).
    for bad in ["0,0,0,1", "1,2", "a,b,c,d"] {
        let output = diff(&image, &image, &["--window", bad]);
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert_eq!(output.status.code(), Some(2), "{bad}: {stderr}");
        assert!(stderr.contains("x,y,width,height"), "{bad}: {stderr}");
    }
}

#[test]
fn diff_of_an_image_with_itself_is_zero() {
    let dir = tempfile::tempdir().unwrap();
    let image = pfm(dir.path(), "a.pfm", 4, 4, [0.1, 0.2, 0.3]);
    let printed = figures(&diff(&image, &image, &[]));
    assert_eq!(printed["rel_mse"], 0.0);
    assert_eq!(printed["rmse"], 0.0);
    for name in ["mean_ratio", "mean_ratio_r", "mean_ratio_g", "mean_ratio_b"] {
        assert_eq!(printed[name], 1.0, "{name}");
    }
}

#[test]
fn diff_of_different_sizes_names_both() {
    let dir = tempfile::tempdir().unwrap();
    let image = pfm(dir.path(), "a.pfm", 4, 2, [1.0; 3]);
    let reference = pfm(dir.path(), "b.pfm", 2, 4, [1.0; 3]);
    let json = dir.path().join("diff.json");
    let output = diff(&image, &reference, &["--json", json.to_str().unwrap()]);
    assert_clean_error(&output, "4x2");
    assert_clean_error(&output, "2x4");
    assert!(output.stdout.is_empty());
    assert!(!json.exists(), "no JSON after a failure");
}

#[test]
fn diff_of_unreadable_images_is_a_clean_error() {
    let dir = tempfile::tempdir().unwrap();
    let good = pfm(dir.path(), "good.pfm", 2, 2, [1.0; 3]);
    let whole = std::fs::read(&good).unwrap();
    let cases = [
        ("cut.pfm", &whole[..whole.len() - 3], "truncated"),
        ("header.pfm", &b"PF\n2 two\n-1.0\n"[..], "header"),
        ("text.pfm", &b"hello"[..], "not a PFM"),
        ("empty.exr", &b""[..], "empty.exr"),
        ("bad.png", &b"\x89PNG\r\n\x1a\nbroken"[..], "bad.png"),
        ("image.tif", &b"II*\0"[..], ".exr"),
    ];
    for (name, bytes, needle) in cases {
        let path = write(dir.path(), name, bytes);
        assert_clean_error(&diff(&path, &good, &[]), needle);
        assert_clean_error(&diff(&good, &path, &[]), needle);
    }
    assert_clean_error(
        &diff(&dir.path().join("absent.pfm"), &good, &[]),
        "absent.pfm",
    );
}

/// `kousen diff A B | head -1`: the reader closes the pipe after one line; kousen must end
/// quietly (SIGPIPE, as any Unix tool), not panic on the next print.
#[cfg(unix)]
#[test]
fn diff_into_a_closed_pipe_ends_without_a_panic() {
    use std::process::Command;
    let dir = tempfile::tempdir().unwrap();
    let a = pfm(dir.path(), "a.pfm", 4, 4, [1.0; 3]);
    let b = pfm(dir.path(), "b.pfm", 4, 4, [0.5; 3]);
    // The reading end is closed before kousen starts: its first print meets a closed pipe.
    let (reader, writer) = std::io::pipe().unwrap();
    drop(reader);
    let output = Command::new(env!("CARGO_BIN_EXE_kousen"))
        .args(["diff", a.to_str().unwrap(), b.to_str().unwrap()])
        .stdout(writer)
        .output()
        .expect("the kousen binary runs");
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(stderr.is_empty(), "kousen wrote to stderr: {stderr}");
    use std::os::unix::process::ExitStatusExt;
    assert_eq!(
        output.status.signal(),
        Some(libc::SIGPIPE),
        "{:?}",
        output.status
    );
}
