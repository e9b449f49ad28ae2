//! `kousen bench rng` end to end at tiny sizes: the JSON contract (every generator on the GPU
//! adapter, lavapipe in CI, and on the CPU twins; the battery's verdicts; the images); bad
//! input.

use crate::common;

use common::{assert_clean_error, kousen_quiet as kousen, shipped, succeeded};

const GENERATORS: [&str; 4] = ["pcg", "talk", "tea", "fract_sin"];

#[test]
fn bench_rng_json_keeps_the_contract() {
    let dir = tempfile::tempdir().unwrap();
    let json = dir.path().join("rng.json");
    let images = dir.path().join("images");
    let output = succeeded(kousen(&[
        "bench",
        "rng",
        &shipped("cornell-caustics.gltf"),
        "--passes",
        "2",
        "--runs",
        "1",
        "--photons",
        "1024",
        "--battery-draws",
        "65536",
        "--image",
        images.to_str().unwrap(),
        "--image-size",
        "16",
        "--image-passes",
        "2",
        "--json",
        json.to_str().unwrap(),
    ]));
    let stdout = String::from_utf8_lossy(&output.stdout);
    let report: serde_json::Value =
        serde_json::from_slice(&std::fs::read(&json).expect("JSON written")).expect("JSON");
    for key in [
        "/adapter/name",
        "/adapter/backend",
        "/cpu_model",
        "/command",
    ] {
        assert!(
            report.pointer(key).is_some_and(|v| v.is_string()),
            "{key} in {report}"
        );
    }
    let battery = report["battery"].as_array().expect("battery array");
    assert_eq!(battery.len(), 4 * 5, "{report}");
    for row in battery {
        let statistic = row["statistic"].as_f64().unwrap();
        let limit = row["limit"].as_f64().unwrap();
        assert!(statistic >= 0.0 && limit > 0.0, "{row}");
        assert_eq!(row["passed"].as_bool(), Some(statistic < limit), "{row}");
    }
    // The noise function's coarse output fails the fine uniformity bins.
    assert!(battery.iter().any(|r| r["generator"] == "fract_sin"
        && r["test"] == "uniformity"
        && r["passed"] == false));

    let results = report["results"].as_array().expect("results array");
    assert_eq!(results.len(), 8, "4 generators × 2 devices: {report}");
    let mut seen = Vec::new();
    for row in results {
        assert_eq!(row["scene"], "cornell-caustics", "{row}");
        let device = row["device"].as_str().unwrap();
        let generator = row["generator"].as_str().unwrap();
        seen.push((device.to_owned(), generator.to_owned()));
        assert!(row["photon_paths"].as_u64().unwrap() > 0, "{row}");
        let per_s = row["photon_paths_per_s"].as_f64().unwrap();
        assert!(
            per_s > 0.0 && row["seconds"].as_f64().unwrap() > 0.0,
            "{row}"
        );
        if generator == "pcg" {
            assert_eq!(row["over_pcg"].as_f64(), Some(1.0), "{row}");
        }
        if device == "gpu" && generator != "fract_sin" {
            // At most 1 % of the slots may differ (else the bench fails); at this size, none.
            assert!(row["diverged"].as_u64().unwrap() <= 10, "{row}");
        } else {
            assert!(row["diverged"].is_null(), "{row}");
        }
    }
    seen.sort();
    let mut expected: Vec<(String, String)> = ["cpu", "gpu"]
        .iter()
        .flat_map(|d| GENERATORS.map(|g| (d.to_string(), g.to_string())))
        .collect();
    expected.sort();
    assert_eq!(seen, expected);

    let rendered = report["images"].as_array().expect("images array");
    assert_eq!(rendered.len(), 4);
    for generator in GENERATORS {
        let png = images.join(format!("rng-{generator}.png"));
        let bytes = std::fs::read(&png).expect("image written");
        assert!(bytes.starts_with(b"\x89PNG"), "{}", png.display());
    }
    assert!(
        stdout.contains("Mpaths/s") && stdout.contains("uniformity"),
        "{stdout}"
    );
}

#[test]
fn bench_rng_bad_input_fails_in_one_line() {
    assert_clean_error(
        &kousen(&["bench", "rng", "no/such/scene.gltf", "--devices", "cpu"]),
        "scene.gltf",
    );
    // Images need the GPU.
    let dir = tempfile::tempdir().unwrap();
    assert_clean_error(
        &kousen(&[
            "bench",
            "rng",
            &shipped("cornell-caustics.gltf"),
            "--devices",
            "cpu",
            "--image",
            dir.path().to_str().unwrap(),
            "--battery-draws",
            "65536",
        ]),
        "--image",
    );
}
