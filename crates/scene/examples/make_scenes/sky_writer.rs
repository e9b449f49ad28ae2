//! The sky maps shipped in `scenes/skies/` (Radiance .hdr), written from `scene::testing`.

use std::path::Path;

/// A shipped sky's fixture.
pub type SkyFixture = fn() -> scene::SkyMap;

/// Each shipped sky: its file stem and the fixture it is written from.
pub const SKIES: [(&str, SkyFixture); 1] = [("sunset", || scene::testing::sunset_sky(256))];

/// Writes `map` as `dir/skies/{stem}.hdr` (RGBE: 8-bit mantissas sharing an exponent).
pub fn write(map: &scene::SkyMap, stem: &str, dir: &Path) -> Result<(), String> {
    let skies = dir.join("skies");
    std::fs::create_dir_all(&skies).map_err(|e| e.to_string())?;
    let texels: Vec<image::Rgb<f32>> = map
        .texels()
        .iter()
        .map(|t| image::Rgb(t.to_array()))
        .collect();
    let mut bytes = Vec::new();
    image::codecs::hdr::HdrEncoder::new(&mut bytes)
        .encode(&texels, map.width() as usize, map.height() as usize)
        .map_err(|e| e.to_string())?;
    std::fs::write(skies.join(format!("{stem}.hdr")), bytes).map_err(|e| e.to_string())
}
