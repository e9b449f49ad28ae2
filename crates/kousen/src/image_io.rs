//! Reading and writing images, chosen by extension: .exr (linear, via the `exr` crate), .pfm
//! (linear portable float map) and .png (exposure + sRGB tonemap, 8 bits). Writes go to a
//! temporary file renamed into place, so that a failure never leaves a half-written image.

use std::io::Write;
use std::path::Path;

use anyhow::{Context, bail, ensure};
use glam::Vec3;
use render::Image;
use render::tonemap::{Look, srgb_to_linear};

use crate::output_file::PendingFile;

#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Format {
    /// Linear RGB in OpenEXR, f32 or f16 channels ([`ExrPrecision`]).
    Exr,
    /// Linear float RGB (portable float map).
    Pfm,
    /// Tonemapped 8-bit sRGB.
    Png,
}

impl Format {
    pub fn from_path(path: &Path) -> anyhow::Result<Format> {
        let extension = path
            .extension()
            .and_then(|e| e.to_str())
            .map(str::to_ascii_lowercase);
        match extension.as_deref() {
            Some("exr") => Ok(Format::Exr),
            Some("pfm") => Ok(Format::Pfm),
            Some("png") => Ok(Format::Png),
            _ => bail!(
                "{}: unknown image extension (expected .exr, .pfm or .png)",
                path.display()
            ),
        }
    }
}

/// The sample type of the channels of an EXR output.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, clap::ValueEnum)]
pub enum ExrPrecision {
    /// 16-bit half floats: half the size, about 3 significant digits, at most 65504.
    Half,
    /// 32-bit floats: exactly what was rendered.
    #[default]
    Float,
}

/// An image file being written (see [`PendingFile`]). Created before rendering so that an
/// unwritable path or unknown extension fails at once, not after the work.
pub struct Output {
    file: PendingFile,
    format: Format,
    /// Used only by [`Format::Exr`].
    precision: ExrPrecision,
}

impl Output {
    /// An output with f32 channels if it is an EXR.
    #[cfg(test)]
    pub fn create(path: &Path) -> anyhow::Result<Output> {
        Output::create_with(path, ExrPrecision::Float)
    }

    pub fn create_with(path: &Path, precision: ExrPrecision) -> anyhow::Result<Output> {
        let format = Format::from_path(path)?;
        let file = PendingFile::create(path)?;
        Ok(Output {
            file,
            format,
            precision,
        })
    }

    /// Writes the image and moves it into place. `look` (exposure, tone map) applies to PNG only; EXR
    /// and PFM hold the linear values.
    pub fn commit(mut self, image: &Image, look: Look) -> anyhow::Result<()> {
        ensure!(
            image.pixels.len() == image.width as usize * image.height as usize,
            "a {}x{} image with {} pixels cannot be written",
            image.width,
            image.height,
            image.pixels.len()
        );
        let file = self.file.file();
        match self.format {
            Format::Exr => write_exr(file, image, self.precision)?,
            Format::Pfm => write_pfm(std::io::BufWriter::new(file), image)?,
            Format::Png => write_png(std::io::BufWriter::new(file), image, look)?,
        }
        self.file.commit()
    }
}

fn write_exr(
    file: &mut std::fs::File,
    image: &Image,
    precision: ExrPrecision,
) -> anyhow::Result<()> {
    match precision {
        ExrPrecision::Half => write_exr_samples(file, image, exr::prelude::f16::from_f32),
        ExrPrecision::Float => write_exr_samples(file, image, |c| c),
    }
}

/// RGB channels, each sample `convert`ed (to f32 or f16), rows top to bottom.
fn write_exr_samples<T: exr::prelude::IntoSample>(
    file: &mut std::fs::File,
    image: &Image,
    convert: impl Fn(f32) -> T + Sync,
) -> anyhow::Result<()> {
    use exr::prelude::{SpecificChannels, Vec2, WritableImage};
    let width = image.width as usize;
    let channels = SpecificChannels::rgb(|Vec2(x, y): Vec2<usize>| {
        let p = image.pixels[y * width + x];
        (convert(p.x), convert(p.y), convert(p.z))
    });
    exr::prelude::Image::from_channels((width, image.height as usize), channels)
        .write()
        .to_unbuffered(file)
        .map_err(exr_error)
}

/// PFM: a text header, then little-endian floats, rows bottom to top.
fn write_pfm(mut writer: impl Write, image: &Image) -> anyhow::Result<()> {
    write!(writer, "PF\n{} {}\n-1.0\n", image.width, image.height)?;
    for row in image.pixels.chunks(image.width.max(1) as usize).rev() {
        for p in row {
            for c in p.to_array() {
                writer.write_all(&c.to_le_bytes())?;
            }
        }
    }
    writer.flush()?;
    Ok(())
}

fn write_png(mut writer: impl Write, image: &Image, look: Look) -> anyhow::Result<()> {
    let bytes: Vec<u8> = image.pixels.iter().flat_map(|&p| look.srgb8(p)).collect();
    let encoder = image::codecs::png::PngEncoder::new(&mut writer);
    image::ImageEncoder::write_image(
        encoder,
        &bytes,
        image.width,
        image.height,
        image::ExtendedColorType::Rgb8,
    )?;
    writer.flush()?;
    Ok(())
}

/// Reads an image as linear RGB: .exr (the first layer with R, G and B channels; alpha is
/// ignored), .pfm (colour "PF" or grey "Pf", either byte order) or .png (8 or 16 bits, decoded
/// from sRGB; alpha is ignored).
pub fn read_image(path: &Path) -> anyhow::Result<Image> {
    let format = Format::from_path(path)?;
    let context = || format!("cannot read {}", path.display());
    match format {
        Format::Exr => read_exr(path).with_context(context),
        Format::Pfm => std::fs::read(path)
            .map_err(anyhow::Error::from)
            .and_then(|bytes| parse_pfm(&bytes))
            .with_context(context),
        Format::Png => std::fs::read(path)
            .map_err(anyhow::Error::from)
            .and_then(|bytes| decode_png(&bytes))
            .with_context(context),
    }
}

/// Reads an environment map for the sky (`scene::SkyMap`): .hdr (Radiance RGBE) or what
/// [`read_image`] reads; one line naming the file where it is not a valid map.
pub fn read_sky_map(path: &Path) -> anyhow::Result<scene::SkyMap> {
    let is_hdr = path
        .extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| e.eq_ignore_ascii_case("hdr"));
    let image = if is_hdr {
        read_radiance_hdr(path).with_context(|| format!("cannot read {}", path.display()))?
    } else if Format::from_path(path).is_ok() {
        read_image(path)?
    } else {
        bail!(
            "{}: unknown sky map extension (expected .hdr, .exr, .pfm or .png)",
            path.display()
        )
    };
    scene::SkyMap::new(image.width, image.height, image.pixels)
        .map_err(|message| anyhow::anyhow!("{}: {message}", path.display()))
}

fn read_radiance_hdr(path: &Path) -> anyhow::Result<Image> {
    let bytes = std::fs::read(path)?;
    let decoded = image::load_from_memory_with_format(&bytes, image::ImageFormat::Hdr)?;
    let rgb = decoded.to_rgb32f();
    Ok(Image {
        width: rgb.width(),
        height: rgb.height(),
        pixels: rgb.pixels().map(|p| Vec3::from_array(p.0)).collect(),
    })
}

fn read_exr(path: &Path) -> anyhow::Result<Image> {
    use exr::prelude::Vec2;
    let read = exr::prelude::read_first_rgba_layer_from_file(
        path,
        |size: Vec2<usize>, _| Image {
            width: size.width() as u32,
            height: size.height() as u32,
            pixels: vec![Vec3::ZERO; size.area()],
        },
        |image: &mut Image, Vec2(x, y): Vec2<usize>, (r, g, b, _): (f32, f32, f32, f32)| {
            image.pixels[y * image.width as usize + x] = Vec3::new(r, g, b);
        },
    )
    .map_err(exr_error)?;
    Ok(read.layer_data.channel_data.pixels)
}

/// The `exr` error as one message: its I/O errors print their cause and also return it as
/// their source, which would show it twice in a chain.
fn exr_error(error: exr::error::Error) -> anyhow::Error {
    match error {
        exr::error::Error::Io(io) => io.into(),
        other => anyhow::anyhow!("{other}"),
    }
}

fn decode_png(bytes: &[u8]) -> anyhow::Result<Image> {
    let decoded = image::load_from_memory_with_format(bytes, image::ImageFormat::Png)?;
    // Normalised to [0, 1] whatever the bit depth; grey is expanded to RGB.
    let rgb = decoded.to_rgb32f();
    let pixels = rgb
        .pixels()
        .map(|p| Vec3::from_array(p.0.map(srgb_to_linear)))
        .collect();
    Ok(Image {
        width: rgb.width(),
        height: rgb.height(),
        pixels,
    })
}

/// Parses a portable float map: "PF" (RGB) or "Pf" (grey), width and height, then a scale whose
/// sign gives the byte order (negative: little-endian) and whose magnitude multiplies the
/// values (as pbrt reads it), then the floats, rows bottom to top.
fn parse_pfm(bytes: &[u8]) -> anyhow::Result<Image> {
    let mut header = PfmHeader { bytes, at: 0 };
    let channels = match header.token() {
        Some("PF") => 3,
        Some("Pf") => 1,
        _ => bail!("not a PFM file (it does not start with \"PF\" or \"Pf\")"),
    };
    let (width, height, scale) = match (
        header.number::<u32>(),
        header.number::<u32>(),
        header.number::<f32>(),
    ) {
        (Some(w), Some(h), Some(s)) => (w, h, s),
        _ => bail!("bad PFM header (expected the width, height and scale)"),
    };
    ensure!(width >= 1 && height >= 1, "bad PFM size {width}x{height}");
    ensure!(scale != 0.0 && scale.is_finite(), "bad PFM scale {scale}");
    let data = &bytes[header.at..];
    let needed = u64::from(width) * u64::from(height) * channels * 4;
    ensure!(
        data.len() as u64 >= needed,
        "truncated PFM: {width}x{height} needs {needed} bytes of pixels, the file has {}",
        data.len()
    );
    let little_endian = scale < 0.0;
    let magnitude = scale.abs();
    let floats: Vec<f32> = data[..needed as usize]
        .chunks_exact(4)
        .map(|b| {
            let b = [b[0], b[1], b[2], b[3]];
            let value = if little_endian {
                f32::from_le_bytes(b)
            } else {
                f32::from_be_bytes(b)
            };
            value * magnitude
        })
        .collect();
    let row_floats = width as usize * channels as usize;
    let pixels = floats
        .chunks_exact(row_floats)
        .rev()
        .flat_map(|row| row.chunks_exact(channels as usize))
        .map(|c| match c {
            [r, g, b] => Vec3::new(*r, *g, *b),
            _ => Vec3::splat(c[0]),
        })
        .collect();
    Ok(Image {
        width,
        height,
        pixels,
    })
}

/// The text part of a PFM file: tokens, each ended by one whitespace byte.
struct PfmHeader<'a> {
    bytes: &'a [u8],
    /// Where the next token (or, after the scale, the pixels) begins.
    at: usize,
}

impl<'a> PfmHeader<'a> {
    fn token(&mut self) -> Option<&'a str> {
        while self.bytes.get(self.at)?.is_ascii_whitespace() {
            self.at += 1;
        }
        let start = self.at;
        while !self.bytes.get(self.at)?.is_ascii_whitespace() {
            self.at += 1;
        }
        let token = std::str::from_utf8(&self.bytes[start..self.at]).ok()?;
        // The single whitespace byte that ends the token.
        self.at += 1;
        Some(token)
    }

    fn number<T: std::str::FromStr>(&mut self) -> Option<T> {
        self.token()?.parse().ok()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use render::tonemap::linear_to_srgb;

    /// Distinct values in every channel, from below 1e-3 to above 100, no two pixels alike.
    fn test_image(width: u32, height: u32) -> Image {
        let pixels = (0..width * height)
            .map(|i| {
                let i = i as f32;
                Vec3::new(0.37 * i + 0.01, 1e-3 * (i + 1.0), 100.0 + 3.3 * i)
            })
            .collect();
        Image::new(width, height, pixels)
    }

    fn write_and_read(name: &str, image: &Image, precision: ExrPrecision) -> Image {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join(name);
        Output::create_with(&path, precision)
            .unwrap()
            .commit(image, Look::default())
            .unwrap();
        read_image(&path).unwrap()
    }

    fn pfm_bytes(header: &str, floats: &[f32], little_endian: bool) -> Vec<u8> {
        let mut bytes = header.as_bytes().to_vec();
        for f in floats {
            let b = if little_endian {
                f.to_le_bytes()
            } else {
                f.to_be_bytes()
            };
            bytes.extend(b);
        }
        bytes
    }

    #[test]
    fn exr_float_round_trip_is_exact() {
        let image = test_image(5, 3);
        assert_eq!(write_and_read("a.exr", &image, ExrPrecision::Float), image);
    }

    #[test]
    fn exr_half_round_trip_is_within_half_precision() {
        let image = test_image(5, 3);
        let read = write_and_read("a.EXR", &image, ExrPrecision::Half);
        assert_eq!((read.width, read.height), (5, 3));
        for (r, p) in read.pixels.iter().zip(&image.pixels) {
            // Half has 11 significant bits: rounding is within 2^-11 relative (normal values).
            let error = ((*r - *p) / *p).abs().max_element();
            assert!(error <= 2f32.powi(-11), "{r} vs {p}");
        }
    }

    #[test]
    fn pfm_round_trip_is_exact() {
        let image = test_image(4, 3);
        assert_eq!(write_and_read("a.pfm", &image, ExrPrecision::Float), image);
    }

    #[test]
    fn pfm_grey_big_endian_is_read_bottom_to_top() {
        // Scale +2: big-endian, values doubled. The bottom row comes first in the file.
        let bytes = pfm_bytes("Pf\n2 2\n2.0\n", &[1.0, 2.0, 3.0, 4.0], false);
        let image = parse_pfm(&bytes).unwrap();
        let expected = [3.0, 4.0, 1.0, 2.0].map(|v| Vec3::splat(2.0 * v));
        assert_eq!((image.width, image.height), (2, 2));
        assert_eq!(image.pixels, expected);
    }

    #[test]
    fn pfm_malformed_is_a_clean_error() {
        let whole = pfm_bytes("PF\n2 1\n-1.0\n", &[0.5; 6], true);
        assert!(parse_pfm(&whole).is_ok());
        for end in 0..whole.len() {
            assert!(parse_pfm(&whole[..end]).is_err(), "prefix of {end} bytes");
        }
        let error = parse_pfm(&whole[..whole.len() - 1]).unwrap_err();
        assert!(error.to_string().contains("truncated"), "{error}");
        for header in [
            "P6\n2 1\n-1\n",
            "PF\n2 x\n-1\n",
            "PF\n0 1\n-1\n",
            "PF\n2 1\n0\n",
        ] {
            let bytes = pfm_bytes(header, &[0.5; 6], true);
            assert!(parse_pfm(&bytes).is_err(), "{header:?}");
        }
    }

    #[test]
    fn png_round_trip_is_within_one_step_after_srgb() {
        let pixels = (0..64)
            .map(|i| Vec3::new(i as f32 / 63.0, (i as f32 / 63.0).powi(3), 0.002 * i as f32))
            .collect();
        let image = Image::new(8, 8, pixels);
        let read = write_and_read("a.png", &image, ExrPrecision::Float);
        for (r, p) in read.pixels.iter().zip(&image.pixels) {
            for c in 0..3 {
                let step = (linear_to_srgb(r[c]) - linear_to_srgb(p[c])).abs() * 255.0;
                assert!(step <= 1.0, "{r} vs {p}");
            }
        }
    }

    #[test]
    fn png_16_bit_is_decoded_from_srgb() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("deep.png");
        let values = [0u16, 1000, 30000, 65535];
        let buffer =
            image::ImageBuffer::from_fn(2, 2, |x, y| image::Luma([values[(y * 2 + x) as usize]]));
        image::DynamicImage::ImageLuma16(buffer)
            .save(&path)
            .unwrap();
        let read = read_image(&path).unwrap();
        for (r, v) in read.pixels.iter().zip(values) {
            let expected = srgb_to_linear(v as f32 / 65535.0);
            assert!(
                (*r - Vec3::splat(expected)).abs().max_element() < 1e-6,
                "{r}"
            );
        }
    }

    #[test]
    fn unknown_extension_lists_the_formats() {
        for error in [
            Output::create(Path::new("out.tif")).err().unwrap(),
            read_image(Path::new("in")).unwrap_err(),
        ] {
            let message = error.to_string();
            for extension in [".exr", ".pfm", ".png"] {
                assert!(message.contains(extension), "{message}");
            }
        }
    }

    #[test]
    fn truncated_exr_is_a_clean_error() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("a.exr");
        Output::create(&path)
            .unwrap()
            .commit(&test_image(16, 16), Look::default())
            .unwrap();
        let whole = std::fs::read(&path).unwrap();
        for end in [0, 4, 40, whole.len() / 2, whole.len() - 1] {
            std::fs::write(&path, &whole[..end]).unwrap();
            let error = read_image(&path).unwrap_err();
            assert!(format!("{error:#}").contains("a.exr"), "{error:#}");
        }
    }
}
