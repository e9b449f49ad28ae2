//! `kousen bench density` end to end on a shipped scene: the JSON contract (five methods on
//! the GPU adapter, lavapipe in CI, and on the CPU backend), the full hash and the kd-tree
//! finding the same photons (the same error at equal passes), the GPU/CPU ratios, the images;
//! bad input.

use crate::common;

use common::{assert_clean_error, kousen_quiet as kousen, shipped, succeeded};

const METHODS: [&str; 5] = [
    "stochastic-64",
    "stochastic-8",
    "stochastic-1",
    "full",
    "kdtree",
];

#[test]
fn bench_density_json_keeps_the_contract() {
    let dir = tempfile::tempdir().unwrap();
    let json = dir.path().join("density.json");
    let images = dir.path().join("images");
    let output = succeeded(kousen(&[
        "bench",
        "density",
        &shipped("cornell-caustics.gltf"),
        "--width",
        "32",
        "--height",
        "32",
        "--photons",
        "4096",
        "--passes",
        "4",
        "--reference-passes",
        "8",
        "--images",
        images.to_str().unwrap(),
        "--json",
        json.to_str().unwrap(),
    ]));
    let stdout = String::from_utf8_lossy(&output.stdout);
    let report: serde_json::Value =
        serde_json::from_slice(&std::fs::read(&json).expect("JSON written")).expect("JSON");
    for key in ["/adapter/name", "/adapter/driver", "/cpu_model", "/command"] {
        assert!(report.pointer(key).is_some_and(|v| v.is_string()), "{key}");
    }
    let results = report["results"].as_array().expect("results");
    assert_eq!(results.len(), 10, "5 methods × 2 devices: {report}");
    for device in ["gpu", "cpu"] {
        let rows: Vec<_> = results.iter().filter(|r| r["device"] == device).collect();
        let methods: Vec<_> = rows.iter().map(|r| r["method"].as_str().unwrap()).collect();
        assert_eq!(methods, METHODS, "{device}");
        for row in &rows {
            assert_eq!(row["passes"], 4, "{row}");
            for key in ["hash_build_ms", "gather_ms", "iteration_ms", "seconds"] {
                assert!(row[key].as_f64().unwrap() > 0.0, "{key}: {row}");
            }
            let error = row["rel_mse_equal_passes"].as_f64().unwrap();
            assert!(error.is_finite() && error > 0.0, "{row}");
            assert!(row["density_bytes"].as_u64().unwrap() > 0, "{row}");
            assert_eq!(row["checkpoints"].as_array().unwrap().len(), 3, "{row}");
        }
        // The fastest method's equal-time error is its own error at equal passes.
        let fastest = rows
            .iter()
            .min_by(|a, b| {
                a["seconds"]
                    .as_f64()
                    .partial_cmp(&b["seconds"].as_f64())
                    .unwrap()
            })
            .unwrap();
        assert_eq!(
            fastest["rel_mse_equal_time"],
            fastest["rel_mse_equal_passes"]
        );
        // The full hash and the kd-tree count the same photons: the same image to rounding.
        let error = |m: &str| {
            rows.iter().find(|r| r["method"] == m).unwrap()["rel_mse_equal_passes"]
                .as_f64()
                .unwrap()
        };
        let (full, tree) = (error("full"), error("kdtree"));
        assert!(
            (full - tree).abs() <= 1e-3 * full,
            "{device}: full {full}, kd-tree {tree}"
        );
    }
    let speedups = report["gpu_over_cpu"].as_array().expect("gpu_over_cpu");
    assert_eq!(speedups.len(), 5, "{report}");
    assert!(
        speedups
            .iter()
            .all(|s| s["hash_build"].as_f64().unwrap() > 0.0)
    );
    for method in METHODS {
        let png = images.join(format!("density-cornell-caustics-{method}.png"));
        assert!(
            std::fs::metadata(&png).is_ok_and(|m| m.len() > 0),
            "{png:?}"
        );
    }
    assert!(stdout.contains("at equal time"), "{stdout}");
}

#[test]
fn bench_density_bad_input_fails_in_one_line() {
    let dir = tempfile::tempdir().unwrap();
    // A reference of another size than the bench renders.
    let reference = dir.path().join("reference.pfm");
    succeeded(kousen(&[
        "render",
        &shipped("cornell-box.gltf"),
        "-o",
        reference.to_str().unwrap(),
        "--width",
        "8",
        "--height",
        "8",
        "--passes",
        "1",
        "--backend",
        "cpu",
    ]));
    assert_clean_error(
        &kousen(&[
            "bench",
            "density",
            &shipped("cornell-box.gltf"),
            "--width",
            "16",
            "--height",
            "16",
            "--devices",
            "cpu",
            "--reference",
            reference.to_str().unwrap(),
        ]),
        "8×8",
    );
    assert_clean_error(
        &kousen(&["bench", "density", "no/such/scene.gltf", "--devices", "cpu"]),
        "scene.gltf",
    );
}
