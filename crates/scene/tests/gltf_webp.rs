//! glTF textures in WebP (`EXT_texture_webp`): preferred to their fallback, decoded lossless
//! exactly and lossy as libwebp decodes them, bad sources refused in one line.

use crate::gltf_support;

use gltf_support::*;
use scene::{Scene, Texels};
use serde_json::{Value, json};

/// Two texels, the second half transparent: what every WebP image here shows.
const TEXELS: [[u8; 4]; 2] = [[255, 0, 0, 255], [0, 128, 255, 64]];

fn encoded(texels: &[[u8; 4]], format: image::ImageFormat) -> Vec<u8> {
    let raw = texels.iter().flatten().copied().collect();
    let image = image::RgbaImage::from_raw(texels.len() as u32, 1, raw).expect("a row");
    let mut bytes = Vec::new();
    image
        .write_to(&mut std::io::Cursor::new(&mut bytes), format)
        .expect("encode");
    bytes
}

/// [`TEXELS`] as a lossless WebP (the `image` crate's encoder).
fn lossless_webp() -> Vec<u8> {
    encoded(&TEXELS, image::ImageFormat::WebP)
}

/// A document whose images are `images` (bytes and MIME type) in buffer views, showing a
/// quad whose base colour is texture 0, described by `texture`.
fn quad_showing(images: &[(&[u8], &str)], texture: Value) -> Doc {
    let mut doc = Doc::default();
    for (bytes, mime) in images {
        let view = doc.view(bytes);
        doc.push("images", json!({ "bufferView": view, "mimeType": mime }));
    }
    doc.push("textures", texture);
    let material = doc.material(json!({
        "pbrMetallicRoughness": { "baseColorTexture": { "index": 0 } },
    }));
    let mesh = doc.mesh(&QUAD, &QUAD_INDICES, Some(material));
    doc.instance(mesh);
    doc.json["extensionsUsed"] = json!(["EXT_texture_webp"]);
    doc
}

fn only_texels(scene: &Scene) -> &[[u8; 4]] {
    assert_eq!(scene.textures.len(), 1, "one image decoded");
    match &scene.textures[0].texels {
        Texels::Srgb8(texels) => texels,
        Texels::LinearF32(_) => panic!("a base colour is sRGB colour"),
    }
}

#[test]
fn a_webp_source_is_read_in_place_of_its_fallback() {
    let fallback = encoded(&[[0, 0, 0, 255]; 2], image::ImageFormat::Png);
    let webp = lossless_webp();
    let doc = quad_showing(
        &[(&fallback, "image/png"), (&webp, "image/webp")],
        json!({ "source": 0, "extensions": { "EXT_texture_webp": { "source": 1 } } }),
    );
    for layout in [Layout::DataUri, Layout::Glb] {
        let scene = doc.load_as(layout).expect("loads");
        assert_eq!(
            only_texels(&scene),
            TEXELS,
            "the WebP, not the black fallback"
        );
        assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
    }
}

#[test]
fn a_required_webp_without_fallback_loads() {
    let webp = lossless_webp();
    let mut doc = quad_showing(
        &[(&webp, "image/webp")],
        json!({ "extensions": { "EXT_texture_webp": { "source": 0 } } }),
    );
    doc.json["extensionsRequired"] = json!(["EXT_texture_webp"]);
    let scene = doc.load().expect("loads");
    assert_eq!(only_texels(&scene), TEXELS);
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
}

/// The lossy fixture (VP8 with an ALPH chunk) against libwebp's own decoding of it, both
/// made by `scripts/make_webp_fixture.py`. Lossy decoders may round their colour conversion
/// and upsampling differently; image-webp's matches libwebp's texel for texel here.
#[test]
fn a_lossy_webp_decodes_as_libwebp_decodes_it() {
    let data = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data");
    let webp = std::fs::read(data.join("webp-lossy.webp")).expect("fixture");
    let reference = image::open(data.join("webp-lossy-libwebp.png"))
        .expect("libwebp's decoding")
        .to_rgba8();
    let doc = quad_showing(
        &[(&webp, "image/webp")],
        json!({ "extensions": { "EXT_texture_webp": { "source": 0 } } }),
    );
    let scene = doc.load().expect("loads");
    let texture = &scene.textures[0];
    assert_eq!((texture.width, texture.height), reference.dimensions());
    let libwebp: Vec<[u8; 4]> = reference.pixels().map(|p| p.0).collect();
    assert_eq!(only_texels(&scene), libwebp);
}

#[test]
fn bad_webp_sources_are_one_line_errors() {
    let webp = lossless_webp();
    // A negative index, a string, none.
    for source in [json!(-1), json!("0"), Value::Null] {
        let doc = quad_showing(
            &[(&webp, "image/webp")],
            json!({ "extensions": { "EXT_texture_webp": { "source": source } } }),
        );
        assert_mentions(
            &error_of(doc.load()),
            &["texture 0", "EXT_texture_webp", "no valid source"],
        );
    }
    let doc = quad_showing(
        &[(&webp, "image/webp")],
        json!({ "extensions": { "EXT_texture_webp": { "source": 3 } } }),
    );
    assert_mentions(&error_of(doc.load()), &["image source 3 does not exist"]);

    let truncated = &webp[..webp.len() / 2];
    let doc = quad_showing(
        &[(truncated, "image/webp")],
        json!({ "extensions": { "EXT_texture_webp": { "source": 0 } } }),
    );
    assert_mentions(&error_of(doc.load()), &["image 0"]);
}

#[test]
fn a_texture_with_only_an_undecodable_source_names_its_extension() {
    let ktx2_stand_in = [0xab, 0x4b, 0x54, 0x58, 0x20, 0x32, 0x30, 0xbb];
    let doc = quad_showing(
        &[(&ktx2_stand_in, "image/ktx2")],
        json!({ "extensions": { "KHR_texture_basisu": { "source": 0 } } }),
    );
    assert_mentions(
        &error_of(doc.load()),
        &["texture 0", "no image source", "KHR_texture_basisu"],
    );
}
