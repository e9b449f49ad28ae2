//! `EXT_meshopt_compression`: buffer views stored compressed load as their plain twins do.
//! The streams here come from a deliberately plain encoder (every attribute byte a raw delta,
//! every index explicit), valid under the extension's bitstream rules; the decoder's own unit
//! tests check it against the reference decoder's streams.

use serde_json::{Value, json};

use crate::gltf_support::*;

/// Mode 0 with every group stored as 16 raw zigzagged byte deltas from a zero baseline.
fn encode_attributes(bytes: &[u8], stride: usize) -> Vec<u8> {
    let count = bytes.len() / stride;
    let max_block = ((8192 / stride) & !15).min(256);
    let mut out = vec![0xa0];
    let mut last = vec![0u8; stride];
    let mut start = 0;
    while start < count {
        let block = (count - start).min(max_block);
        let groups = block.div_ceil(16);
        for (k, previous) in last.iter_mut().enumerate() {
            out.extend(std::iter::repeat_n(0xff, groups.div_ceil(4)));
            for i in 0..groups * 16 {
                let value = if i < block {
                    bytes[(start + i) * stride + k]
                } else {
                    *previous
                };
                let delta = value.wrapping_sub(*previous);
                out.push(if delta & 0x80 != 0 {
                    !(delta << 1)
                } else {
                    delta << 1
                });
                *previous = value;
            }
        }
        start += block;
    }
    out.extend(std::iter::repeat_n(0, stride.max(32)));
    out
}

fn varint(mut value: u32, out: &mut Vec<u8>) {
    while value >= 0x80 {
        out.push((value as u8 & 0x7f) | 0x80);
        value >>= 7;
    }
    out.push(value as u8);
}

fn zigzag(delta: i32) -> u32 {
    ((delta << 1) ^ (delta >> 31)) as u32
}

/// Mode 1 with every triangle's three indices explicit (code 0xff, extra byte 0xff).
fn encode_triangles(indices: &[u32]) -> Vec<u8> {
    let mut out = vec![0xe1];
    out.extend(std::iter::repeat_n(0xff, indices.len() / 3));
    let mut last = 0u32;
    for triangle in indices.chunks(3) {
        out.push(0xff);
        for &index in triangle {
            varint(zigzag(index.wrapping_sub(last) as i32), &mut out);
            last = index;
        }
    }
    out.extend([0; 16]);
    out
}

/// Mode 2 with every index a delta from baseline 0.
fn encode_index_sequence(indices: &[u32]) -> Vec<u8> {
    let mut out = vec![0xd1];
    let mut last = 0u32;
    for &index in indices {
        varint(zigzag(index.wrapping_sub(last) as i32) << 1, &mut out);
        last = index;
    }
    out.extend([0; 4]);
    out
}

/// [`quad_doc`] with its position and index views compressed (`index_mode`: TRIANGLES or
/// INDICES) into buffer 0, their plain bytes left to a fallback buffer without data;
/// `spoil` may change the compressed bytes.
fn compressed_quad(index_mode: &str, spoil: impl Fn(&mut Vec<u8>)) -> Vec<u8> {
    let mut doc = quad_doc(None);
    let plain = doc.bin.clone();
    let mut fallback_length = 0;
    for (view, stride, count) in [(0usize, 12usize, 4usize), (1, 2, 6)] {
        let old = doc.json["bufferViews"][view].clone();
        let offset = old["byteOffset"].as_u64().unwrap() as usize;
        let length = old["byteLength"].as_u64().unwrap() as usize;
        let bytes = &plain[offset..offset + length];
        let (mode, mut stream) = if view == 0 {
            ("ATTRIBUTES", encode_attributes(bytes, stride))
        } else {
            let indices: Vec<u32> = (bytes.chunks(2))
                .map(|c| u32::from(u16::from_le_bytes([c[0], c[1]])))
                .collect();
            let stream = match index_mode {
                "TRIANGLES" => encode_triangles(&indices),
                _ => encode_index_sequence(&indices),
            };
            (index_mode, stream)
        };
        spoil(&mut stream);
        doc.bin.resize(doc.bin.len().next_multiple_of(4), 0);
        let compressed_offset = doc.bin.len();
        doc.bin.extend_from_slice(&stream);
        doc.json["bufferViews"][view] = json!({
            "buffer": 1,
            "byteOffset": fallback_length,
            "byteLength": length,
            "extensions": { "EXT_meshopt_compression": {
                "buffer": 0,
                "byteOffset": compressed_offset,
                "byteLength": stream.len(),
                "byteStride": stride,
                "count": count,
                "mode": mode,
            } },
        });
        fallback_length += length.next_multiple_of(4);
    }
    let mut json: Value = doc.json_for(Layout::DataUri, "");
    json["buffers"].as_array_mut().unwrap().push(json!({
        "byteLength": fallback_length,
        "extensions": { "EXT_meshopt_compression": { "fallback": true } },
    }));
    json["extensionsUsed"] = json!(["EXT_meshopt_compression"]);
    json["extensionsRequired"] = json!(["EXT_meshopt_compression"]);
    serde_json::to_vec(&json).unwrap()
}

#[test]
fn compressed_views_load_as_their_plain_twins() {
    let plain = quad_doc(None).load().expect("plain loads");
    for mode in ["TRIANGLES", "INDICES"] {
        let bytes = compressed_quad(mode, |_| {});
        let scene = load_bytes("compressed.gltf", &bytes).expect(mode);
        assert!(scene.warnings.is_empty(), "{mode}: {:?}", scene.warnings);
        let positions =
            |s: &scene::Scene| -> Vec<_> { s.triangles.iter().map(|t| t.positions()).collect() };
        assert_eq!(positions(&scene), positions(&plain), "{mode}");
    }
}

#[test]
fn a_corrupt_compressed_view_is_a_clear_error() {
    for mode in ["TRIANGLES", "INDICES"] {
        // Cut short: the tail no longer where the stream says.
        let bytes = compressed_quad(mode, |stream| stream.truncate(stream.len() / 2));
        let message = error_of(load_bytes("corrupt.gltf", &bytes));
        assert_mentions(&message, &["bufferView", "EXT_meshopt_compression"]);
        // A wrong header byte.
        let bytes = compressed_quad(mode, |stream| stream[0] ^= 0x40);
        let message = error_of(load_bytes("corrupt.gltf", &bytes));
        assert_mentions(&message, &["EXT_meshopt_compression", "header"]);
    }
}

/// `tests/data/meshopt-sphere.gltf` and `meshopt-sphere-khr.gltf`
/// (`scripts/make_meshopt_fixture.py`): a sphere and three instances of it whose views
/// meshoptimizer's own encoder compressed (positions, normalized u16 texture coordinates,
/// octahedral normals, u16 TRIANGLES and u32 INDICES, exponential translations and quaternion
/// rotations), as `EXT_meshopt_compression` (attribute codec version 0) and as
/// `KHR_meshopt_compression` (version 1: its positions in 16-bit channel deltas), beside a
/// fallback buffer holding the plain bytes its reference decoder and filters give (the
/// TRIANGLES view's each triangle started at the corner that decoder starts it). Loaded as it
/// is (decoding every view) and with the extension taken off the views (reading the
/// fallback), every triangle is the same, bit for bit; a decoder that started triangles
/// elsewhere, or whose filters rounded otherwise, would fail it.
#[test]
fn the_reference_encoder_s_views_decode_to_its_plain_bytes() {
    for (name, extension) in [
        ("meshopt-sphere", "EXT_meshopt_compression"),
        ("meshopt-sphere-khr", "KHR_meshopt_compression"),
    ] {
        assert_loads_as_its_fallback(name, extension);
    }
}

fn assert_loads_as_its_fallback(name: &str, extension: &str) {
    let folder = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data");
    let path = folder.join(format!("{name}.gltf"));
    let compressed = scene::gltf::load(&path).expect("loads compressed");
    assert!(
        compressed.warnings.is_empty(),
        "{name}: {:?}",
        compressed.warnings
    );

    let mut json: Value =
        serde_json::from_slice(&std::fs::read(&path).expect("read")).expect("JSON");
    for view in json["bufferViews"].as_array_mut().expect("views") {
        view.as_object_mut().expect("view").remove("extensions");
    }
    for key in ["extensionsUsed", "extensionsRequired"] {
        let list = json[key].as_array_mut().expect(key);
        list.retain(|used| used != extension);
    }
    let dir = tempfile::tempdir().expect("tempdir");
    let fallback = format!("{name}-fallback.bin");
    std::fs::copy(folder.join(&fallback), dir.path().join(&fallback)).expect("copy the fallback");
    let plain_path = dir.path().join("plain.gltf");
    std::fs::write(&plain_path, serde_json::to_vec(&json).expect("JSON")).expect("write");
    let plain = scene::gltf::load(&plain_path).expect("loads plain");

    // 12 × 20 quads, two primitives, three instances, less the poles' degenerate triangles.
    assert!(
        compressed.triangles.len() > 2500,
        "{name}: {}",
        compressed.triangles.len()
    );
    assert_eq!(compressed.triangles.len(), plain.triangles.len(), "{name}");
    let pairs = compressed.triangles.iter().zip(&plain.triangles);
    let differ: Vec<usize> = (pairs.enumerate())
        .filter(|(_, (a, b))| a != b)
        .map(|(i, _)| i)
        .collect();
    if let Some(&first) = differ.first() {
        panic!(
            "{name}: {} of {} triangles differ; the first, {first}: {:?} against {:?}",
            differ.len(),
            plain.triangles.len(),
            compressed.triangles[first],
            plain.triangles[first]
        );
    }
}
