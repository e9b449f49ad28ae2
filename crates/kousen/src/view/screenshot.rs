//! Screenshots: what the window shows, as an sRGB PNG written whole or not at all.

use std::io::Write;
use std::path::Path;

use anyhow::ensure;

use crate::output_file::PendingFile;

/// Writes tightly packed RGBA8 rows (top row first) as an RGB PNG.
pub fn write_png(path: &Path, (width, height): (u32, u32), rgba: &[u8]) -> anyhow::Result<()> {
    ensure!(
        rgba.len() == width as usize * height as usize * 4,
        "a {width}x{height} screenshot needs {} bytes, got {}",
        width as usize * height as usize * 4,
        rgba.len()
    );
    let rgb: Vec<u8> = rgba
        .chunks_exact(4)
        .flat_map(|p| [p[0], p[1], p[2]])
        .collect();
    let mut file = PendingFile::create(path)?;
    {
        let mut writer = std::io::BufWriter::new(file.file());
        let encoder = image::codecs::png::PngEncoder::new(&mut writer);
        image::ImageEncoder::write_image(
            encoder,
            &rgb,
            width,
            height,
            image::ExtendedColorType::Rgb8,
        )?;
        writer.flush()?;
    }
    file.commit()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn png_round_trips_and_refuses_wrong_sizes() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("shot.png");
        let rgba: Vec<u8> = (0..2 * 3 * 4).map(|i| (i * 10) as u8).collect();
        write_png(&path, (2, 3), &rgba).unwrap();
        let decoded = image::open(&path).unwrap().to_rgb8();
        assert_eq!(decoded.dimensions(), (2, 3));
        assert_eq!(decoded.get_pixel(1, 2).0, [200, 210, 220]);
        assert!(write_png(&dir.path().join("bad.png"), (3, 3), &rgba).is_err());
        assert!(!dir.path().join("bad.png").exists());
    }
}
