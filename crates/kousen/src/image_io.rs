//! Writing images: chosen by extension, written to a temporary file and renamed into place so
//! that a failure never leaves a half-written image.

use std::io::{BufWriter, Write};
use std::path::Path;

use anyhow::bail;
use glam::Vec3;

use crate::output_file::PendingFile;
use crate::path_trace::Image;

#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Format {
    /// Tonemapped 8-bit sRGB.
    Png,
    /// Linear float RGB (portable float map).
    Pfm,
}

impl Format {
    pub fn from_path(path: &Path) -> anyhow::Result<Format> {
        let extension = path
            .extension()
            .and_then(|e| e.to_str())
            .map(str::to_ascii_lowercase);
        match extension.as_deref() {
            Some("png") => Ok(Format::Png),
            Some("pfm") => Ok(Format::Pfm),
            Some("exr") => bail!(
                "{}: EXR output is not supported yet (use .png or .pfm)",
                path.display()
            ),
            _ => bail!(
                "{}: unknown image extension (expected .png or .pfm)",
                path.display()
            ),
        }
    }
}

/// An image file being written (see [`PendingFile`]). Created before rendering so that an
/// unwritable path or unknown extension fails at once, not after the work.
pub struct Output {
    file: PendingFile,
    format: Format,
}

impl Output {
    pub fn create(path: &Path) -> anyhow::Result<Output> {
        let format = Format::from_path(path)?;
        let file = PendingFile::create(path)?;
        Ok(Output { file, format })
    }

    /// Writes the image and moves it into place.
    pub fn commit(mut self, image: &Image, exposure: f32) -> anyhow::Result<()> {
        let mut writer = BufWriter::new(self.file.file());
        match self.format {
            Format::Png => write_png(&mut writer, image, exposure)?,
            Format::Pfm => write_pfm(&mut writer, image)?,
        }
        writer.flush()?;
        drop(writer);
        self.file.commit()
    }
}

fn write_png(writer: &mut impl Write, image: &Image, exposure: f32) -> anyhow::Result<()> {
    let scale = 2f32.powf(exposure);
    let bytes: Vec<u8> = image
        .pixels
        .iter()
        .flat_map(|&p| (p * scale).to_array().map(linear_to_srgb8))
        .collect();
    let encoder = image::codecs::png::PngEncoder::new(writer);
    image::ImageEncoder::write_image(
        encoder,
        &bytes,
        image.width,
        image.height,
        image::ExtendedColorType::Rgb8,
    )?;
    Ok(())
}

/// PFM: a text header, then little-endian floats, rows bottom to top.
fn write_pfm(writer: &mut impl Write, image: &Image) -> anyhow::Result<()> {
    write!(writer, "PF\n{} {}\n-1.0\n", image.width, image.height)?;
    for row in image.pixels.chunks(image.width as usize).rev() {
        for p in row {
            for c in p.to_array() {
                writer.write_all(&c.to_le_bytes())?;
            }
        }
    }
    Ok(())
}

/// Clamps to [0, 1] and applies the sRGB transfer function.
pub fn linear_to_srgb8(c: f32) -> u8 {
    let c = if c.is_finite() {
        c.clamp(0.0, 1.0)
    } else {
        0.0
    };
    let s = if c <= 0.003_130_8 {
        12.92 * c
    } else {
        1.055 * c.powf(1.0 / 2.4) - 0.055
    };
    (s * 255.0 + 0.5) as u8
}

/// Mean of all channels of all pixels (for logs and tests).
pub fn mean(image: &Image) -> Vec3 {
    image.pixels.iter().copied().sum::<Vec3>() / image.pixels.len().max(1) as f32
}
