//! `kousen bench photons` end to end on a shipped scene: the JSON contract (both schemes on the
//! GPU adapter, lavapipe in CI, and on the CPU backend), positive rates, the naive paths equal
//! to the CPU twin's; bad input.

use crate::common;

use common::{assert_clean_error, kousen_quiet as kousen, shipped, succeeded};

#[test]
fn bench_photons_json_keeps_the_contract() {
    let dir = tempfile::tempdir().unwrap();
    let json = dir.path().join("photons.json");
    let output = succeeded(kousen(&[
        "bench",
        "photons",
        &shipped("cornell-box.gltf"),
        "--passes",
        "2",
        "--runs",
        "1",
        "--photons",
        "4096",
        "--json",
        json.to_str().unwrap(),
    ]));
    let stdout = String::from_utf8_lossy(&output.stdout);
    let report: serde_json::Value =
        serde_json::from_slice(&std::fs::read(&json).expect("JSON written")).expect("JSON");
    for key in [
        "/adapter/name",
        "/adapter/backend",
        "/adapter/driver",
        "/cpu_model",
        "/command",
    ] {
        assert!(
            report.pointer(key).is_some_and(|v| v.is_string()),
            "{key} in {report}"
        );
    }
    assert!(report["adapter"]["subgroup_size"].as_u64().unwrap() >= 1);
    let results = report["results"].as_array().expect("results array");
    // 2 schemes × 2 devices (CI has lavapipe, so the GPU rows are there).
    assert_eq!(results.len(), 4, "{report}");
    let mut seen = Vec::new();
    for row in results {
        assert_eq!(row["scene"], "cornell-box", "{row}");
        let device = row["device"].as_str().unwrap();
        let scheme = row["scheme"].as_str().unwrap();
        assert!(["gpu", "cpu"].contains(&device), "{row}");
        assert!(["async", "naive"].contains(&scheme), "{row}");
        seen.push((device, scheme));
        assert_eq!(row["photon_slots"], 4096, "{row}");
        assert!(row["photon_paths"].as_u64().unwrap() > 0, "{row}");
        for key in ["seconds", "photon_paths_per_s", "segments_per_path"] {
            assert!(row[key].as_f64().unwrap() > 0.0, "{key}: {row}");
        }
        let per_s = row["photon_paths_per_s"].as_f64().unwrap();
        let per_min = row["photon_paths_per_min"].as_f64().unwrap();
        assert!((per_min - 60.0 * per_s).abs() <= 1e-6 * per_min, "{row}");
        let occupancy = row["occupancy"].as_f64().unwrap();
        assert!(occupancy > 0.0 && occupancy <= 1.0, "{row}");
        if scheme == "naive" {
            // As many paths as slots per pass, at least one segment each.
            let passes = row["passes"].as_u64().unwrap();
            assert_eq!(row["photon_paths"].as_u64(), Some(4096 * passes), "{row}");
            assert!(row["longest_path"].as_u64().unwrap() >= 1, "{row}");
            assert!(row["occupancy_by_width"]["32"].as_f64().unwrap() > 0.0);
        } else {
            assert!(row["over_naive"].as_f64().unwrap() > 0.0, "{row}");
            assert_eq!(row["passes"], 2, "{row}");
        }
        if device == "gpu" && scheme == "naive" {
            assert_eq!(row["mismatches"].as_u64(), Some(0), "{row}");
            // Lanes wait for longer paths in their SIMD group (lavapipe: 8 lanes).
            assert!(occupancy < 1.0, "{row}");
        }
    }
    seen.sort();
    assert_eq!(
        seen,
        [
            ("cpu", "async"),
            ("cpu", "naive"),
            ("gpu", "async"),
            ("gpu", "naive")
        ]
    );
    assert!(
        stdout.contains("Mpaths/s") && stdout.contains("naive"),
        "{stdout}"
    );
}

#[test]
fn bench_photons_bad_input_fails_in_one_line() {
    assert_clean_error(
        &kousen(&["bench", "photons", "no/such/scene.gltf", "--devices", "cpu"]),
        "scene.gltf",
    );
    // A scene without an emissive surface has no photons to trace.
    let dir = tempfile::tempdir().unwrap();
    let dark = dir.path().join("dark.obj");
    std::fs::write(&dark, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n").unwrap();
    assert_clean_error(
        &kousen(&[
            "bench",
            "photons",
            dark.to_str().unwrap(),
            "--devices",
            "cpu",
        ]),
        "emissive",
    );
}
