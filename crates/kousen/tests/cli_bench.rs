//! `kousen bench traversal` end to end on a shipped scene: the JSON contract, zero mismatches
//! between every variant on the GPU adapter (lavapipe in CI) and the CPU twins; bad input.

use crate::common;

use common::{assert_clean_error, kousen_quiet as kousen, shipped, succeeded};

#[test]
fn bench_traversal_json_keeps_the_contract_with_no_mismatches() {
    let dir = tempfile::tempdir().unwrap();
    let json = dir.path().join("traversal.json");
    let output = succeeded(kousen(&[
        "bench",
        "traversal",
        &shipped("cornell-caustics.gltf"),
        "--size",
        "48",
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
    ] {
        assert!(
            report.pointer(key).is_some_and(|v| v.is_string()),
            "{key} in {report}"
        );
    }
    let results = report["results"].as_array().expect("results array");
    // 2 ray kinds × 5 variants × 2 devices (CI has lavapipe, so the GPU rows are there).
    assert_eq!(results.len(), 20, "{report}");
    let mut primary_rays = 0;
    for row in results {
        assert_eq!(row["scene"], "cornell-caustics", "{row}");
        assert!(["primary", "diffuse"].contains(&row["rays"].as_str().unwrap()));
        let variant = row["variant"].as_str().unwrap();
        assert!(["stack", "tbvh", "mtbvh", "mtbvh16", "mtbvh4"].contains(&variant));
        assert!(["gpu", "cpu"].contains(&row["device"].as_str().unwrap()));
        assert!(row["mrays_per_s"].as_f64().unwrap() > 0.0, "{row}");
        assert_eq!(row["mismatches"].as_u64(), Some(0), "{row}");
        let traced = row["rays_traced"].as_u64().unwrap();
        if row["rays"] == "primary" {
            primary_rays = traced;
        } else {
            // One diffuse ray per primary hit: fewer than the primary rays, but many.
            assert!(traced > 48 * 48 / 4 && traced < 48 * 48, "{row}");
        }
    }
    assert_eq!(primary_rays, 48 * 48);
    assert!(
        stdout.contains("mtbvh16") && stdout.contains("mtbvh4") && stdout.contains("Mrays/s"),
        "{stdout}"
    );
}

#[test]
fn bench_traversal_cpu_only_needs_no_adapter() {
    let output = succeeded(kousen(&[
        "bench",
        "traversal",
        &shipped("cornell-box.gltf"),
        "--size",
        "16",
        "--rays",
        "diffuse",
        "--devices",
        "cpu",
    ]));
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert!(stdout.contains("gpu: none"), "{stdout}");
    let rows: Vec<&str> = stdout
        .lines()
        .filter(|l| l.starts_with("cornell-box"))
        .collect();
    // stack, tbvh, mtbvh, mtbvh16 and mtbvh4.
    assert_eq!(rows.len(), 5, "{stdout}");
    assert!(
        rows.iter()
            .all(|r| r.contains("diffuse") && r.contains("cpu"))
    );
}

#[test]
fn bench_traversal_bad_input_fails_in_one_line() {
    assert_clean_error(
        &kousen(&[
            "bench",
            "traversal",
            "no/such/scene.gltf",
            "--devices",
            "cpu",
        ]),
        "scene.gltf",
    );
    assert_clean_error(
        &kousen(&[
            "bench",
            "traversal",
            &shipped("cornell-box.gltf"),
            "--adapter",
            "no-such-adapter-5c1d",
        ]),
        "no-such-adapter-5c1d",
    );
    let dir = tempfile::tempdir().unwrap();
    let unwritable = dir.path().join("missing-dir/out.json");
    assert_clean_error(
        &kousen(&[
            "bench",
            "traversal",
            &shipped("cornell-box.gltf"),
            "--devices",
            "cpu",
            "--json",
            unwritable.to_str().unwrap(),
        ]),
        "out.json",
    );
}
