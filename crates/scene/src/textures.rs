//! Decoded textures: sRGB-tagged 8-bit colour or linear float data.

use glam::Vec4;

/// Index into [`crate::Scene::textures`].
pub type TextureId = u32;

/// The largest image file read.
pub(crate) const MAX_IMAGE_BYTES: u64 = 1 << 30;

/// The largest texture side we decode. Adapters are checked against their own limits at
/// upload; this bound only keeps a hostile header from asking for gigabytes.
pub const MAX_TEXTURE_SIDE: u32 = 16_384;

#[derive(Clone, Debug, PartialEq)]
pub enum Texels {
    /// RGBA8, colour channels sRGB-encoded, alpha linear (baseColor, emissive, map_Kd).
    Srgb8(Vec<[u8; 4]>),
    /// Linear RGBA floats (HDR images, data textures).
    LinearF32(Vec<[f32; 4]>),
}

/// A texture, rows top to bottom (texture coordinate v = 0 is the first row, glTF's convention).
#[derive(Clone, Debug, PartialEq)]
pub struct Texture {
    pub name: String,
    pub width: u32,
    pub height: u32,
    pub texels: Texels,
}

impl Texture {
    /// Decodes an image file's bytes. `srgb`: colour data in sRGB (kept as 8-bit, tagged);
    /// otherwise linear (8-bit data is widened to float). Formats are guessed from the bytes.
    pub fn decode(name: &str, bytes: &[u8], srgb: bool) -> Result<Texture, String> {
        let mut reader = image::ImageReader::new(std::io::Cursor::new(bytes))
            .with_guessed_format()
            .map_err(|e| format!("texture {name}: {e}"))?;
        let mut limits = image::Limits::default();
        limits.max_image_width = Some(MAX_TEXTURE_SIDE);
        limits.max_image_height = Some(MAX_TEXTURE_SIDE);
        limits.max_alloc = Some(1 << 30);
        reader.limits(limits);
        let image = reader
            .decode()
            .map_err(|e| format!("texture {name}: {e}"))?;
        let (width, height) = (image.width(), image.height());
        let is_float = matches!(
            image.color(),
            image::ColorType::Rgb32F | image::ColorType::Rgba32F
        );
        let texels = if srgb && !is_float {
            Texels::Srgb8(image.to_rgba8().pixels().map(|p| p.0).collect())
        } else if is_float {
            Texels::LinearF32(image.to_rgba32f().pixels().map(|p| p.0).collect())
        } else {
            // 8-bit data that is not colour: its values are linear already.
            Texels::LinearF32(image.to_rgba32f().pixels().map(|p| p.0).collect())
        };
        Ok(Texture {
            name: name.to_string(),
            width,
            height,
            texels,
        })
    }

    /// Reads and decodes image file `path` (at most [`MAX_IMAGE_BYTES`]; `name` names it in
    /// the texture), as [`Texture::decode`]: a file that cannot be read is an I/O error naming
    /// it, one that does not decode the error `decode_error` makes of the decoder's message.
    pub(crate) fn read_file(
        path: &std::path::Path,
        name: &str,
        srgb: bool,
        decode_error: impl FnOnce(String) -> crate::SceneError,
    ) -> Result<Texture, crate::SceneError> {
        let (bytes, _) = crate::files::read_regular_file(path, MAX_IMAGE_BYTES)
            .map_err(|e| crate::SceneError::io(path, e))?;
        Texture::decode(name, &bytes, srgb).map_err(decode_error)
    }

    pub fn texel_count(&self) -> usize {
        self.width as usize * self.height as usize
    }

    /// The texel at integer coordinates, in linear RGBA.
    pub fn texel_linear(&self, x: u32, y: u32) -> Vec4 {
        let i = (y.min(self.height - 1) * self.width + x.min(self.width - 1)) as usize;
        match &self.texels {
            Texels::Srgb8(t) => decode_srgb8(t[i]),
            Texels::LinearF32(t) => Vec4::from_array(t[i]),
        }
    }

    /// Bilinear lookup with repeat wrapping, in linear RGBA; v = 0 is the top row. The
    /// arithmetic of the renderers' texture array (`render::textures`).
    pub fn sample_bilinear(&self, u: f32, v: f32) -> Vec4 {
        let (x0, x1, tx) = bilinear_pair(u, self.width);
        let (y0, y1, ty) = bilinear_pair(v, self.height);
        let top = lerp(self.texel_linear(x0, y0), self.texel_linear(x1, y0), tx);
        let bottom = lerp(self.texel_linear(x0, y1), self.texel_linear(x1, y1), tx);
        lerp(top, bottom, ty)
    }

    /// The mean linear RGBA over all texels (used to estimate a textured light's power).
    pub fn mean_linear(&self) -> Vec4 {
        let mut sum = glam::DVec4::ZERO;
        for y in 0..self.height {
            for x in 0..self.width {
                sum += self.texel_linear(x, y).as_dvec4();
            }
        }
        (sum / self.texel_count().max(1) as f64).as_vec4()
    }
}

/// Whether any texel is less than fully opaque.
pub(crate) fn has_alpha(texture: &Texture) -> bool {
    match &texture.texels {
        Texels::Srgb8(t) => t.iter().any(|p| p[3] < 255),
        Texels::LinearF32(t) => t.iter().any(|p| p[3] < 1.0),
    }
}

/// A copy of `base` (or a white image the mask's size) whose alpha is the mask: the mask
/// image's alpha channel if it has one, else its first channel; nearest texel if sizes differ.
pub(crate) fn with_mask(base: Option<&Texture>, mask: &Texture) -> Texture {
    let channel = if has_alpha(mask) { 3 } else { 0 };
    let mask_value = |x: u32, y: u32| -> u8 {
        let i = (y * mask.width + x) as usize;
        match &mask.texels {
            Texels::Srgb8(t) => t[i][channel],
            Texels::LinearF32(t) => (t[i][channel].clamp(0.0, 1.0) * 255.0).round() as u8,
        }
    };
    let white;
    let base = match base {
        Some(base) => base,
        None => {
            white = Texture {
                name: String::new(),
                width: mask.width,
                height: mask.height,
                texels: Texels::Srgb8(vec![[255; 4]; mask.texel_count()]),
            };
            &white
        }
    };
    // Nearest texel: the mask texel under the centre of each base texel.
    let scale =
        |i: u32, from: u32, to: u32| ((2 * i as u64 + 1) * to as u64 / (2 * from as u64)) as u32;
    let alpha_at = |i: usize| {
        let (x, y) = (i as u32 % base.width, i as u32 / base.width);
        mask_value(
            scale(x, base.width, mask.width),
            scale(y, base.height, mask.height),
        )
    };
    let texels = match &base.texels {
        Texels::Srgb8(t) => Texels::Srgb8(
            t.iter()
                .enumerate()
                .map(|(i, &[r, g, b, _])| [r, g, b, alpha_at(i)])
                .collect(),
        ),
        Texels::LinearF32(t) => Texels::LinearF32(
            t.iter()
                .enumerate()
                .map(|(i, &[r, g, b, _])| [r, g, b, alpha_at(i) as f32 / 255.0])
                .collect(),
        ),
    };
    let name = match base.name.as_str() {
        "" => format!("mask {}", mask.name),
        base_name => format!("{base_name} + mask {}", mask.name),
    };
    Texture {
        name,
        width: base.width,
        height: base.height,
        texels,
    }
}

/// The two texels (repeat-wrapped) whose centres enclose texture coordinate `c` on an axis of
/// `n` (≥ 1) texels, and the weight of the second: texel `i`'s centre lies at `(i + ½) / n`.
pub fn bilinear_pair(c: f32, n: u32) -> (u32, u32, f32) {
    let p = (c - c.floor()) * n as f32 - 0.5;
    let base = p.floor();
    let first = (base as i32).rem_euclid(n as i32) as u32;
    (first, (first + 1) % n, p - base)
}

/// `a` blended towards `b` by `t`, written out as the WGSL twin (`textures.wgsl`) writes it.
pub fn lerp(a: Vec4, b: Vec4, t: f32) -> Vec4 {
    // Exact where a = b (a · (1 − t) + b · t is not): a uniform texture reads its texel's
    // value everywhere, as the factors it stands for would give.
    a + (b - a) * t
}

/// An RGBA8 texel in linear RGBA: colour decoded from sRGB, alpha linear.
pub fn decode_srgb8([r, g, b, a]: [u8; 4]) -> Vec4 {
    Vec4::new(
        srgb_to_linear(r),
        srgb_to_linear(g),
        srgb_to_linear(b),
        a as f32 / 255.0,
    )
}

/// The sRGB transfer function's inverse (IEC 61966-2-1).
pub fn srgb_to_linear(c: u8) -> f32 {
    let c = c as f32 / 255.0;
    if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}
