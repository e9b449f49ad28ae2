//! The scene's textures as both backends read them (DESIGN.md, "Textures live in one texture
//! array"): every texture resampled (bilinearly) to one common power-of-two side and stacked as a
//! layer of one RGBA8 array, colour channels sRGB-encoded, alpha linear. The GPU backend uploads
//! [`TextureArray::texels`] as a `texture_2d_array` and reads it in `textures.wgsl` with the
//! arithmetic of [`TextureArray::sample`], which the CPU backend calls.

use glam::{Vec2, Vec4};
use scene::textures::{bilinear_pair, decode_srgb8, lerp};
use scene::{Texels, Texture};

/// The largest common side unless a caller asks for less: 2048² RGBA8 is 16 MiB a layer. The
/// GPU backend passes `min(max_texture_dimension_2d, DEFAULT_MAX_SIDE)`, the CPU backend this,
/// so that both see the same array.
pub const DEFAULT_MAX_SIDE: u32 = 2048;

/// Every texture of a scene in one array of `layers` square layers of `side`² texels.
#[derive(Clone, Debug, PartialEq)]
pub struct TextureArray {
    pub side: u32,
    pub layers: u32,
    /// RGBA8 (colour sRGB-encoded, alpha linear), layer-major, rows top to bottom (v = 0 is
    /// the first row).
    pub texels: Vec<[u8; 4]>,
}

impl TextureArray {
    /// The array of `textures` (layer i is texture i) at their common side: the largest
    /// texture side rounded up to a power of two, at most `max_side`. With no textures, one
    /// 1×1 white layer, so that there is always something to bind.
    pub fn build(textures: &[Texture], max_side: u32) -> TextureArray {
        if textures.is_empty() {
            return TextureArray {
                side: 1,
                layers: 1,
                texels: vec![[255; 4]],
            };
        }
        let side = common_side(textures, max_side);
        let mut texels = Vec::with_capacity(side as usize * side as usize * textures.len());
        for texture in textures {
            resample_into(texture, side, &mut texels);
        }
        TextureArray {
            side,
            layers: textures.len() as u32,
            texels,
        }
    }

    /// The bytes the array takes (on the device, or here).
    pub fn bytes(&self) -> u64 {
        self.texels.len() as u64 * 4
    }

    /// The texels of one layer, rows top to bottom.
    pub fn layer(&self, layer: u32) -> &[[u8; 4]] {
        let n = self.side as usize * self.side as usize;
        &self.texels[layer as usize * n..(layer as usize + 1) * n]
    }

    /// The texel at integer coordinates in linear RGBA (colour decoded from sRGB).
    pub fn texel(&self, layer: u32, x: u32, y: u32) -> Vec4 {
        let side = self.side as usize;
        decode_srgb8(self.texels[(layer as usize * side + y as usize) * side + x as usize])
    }

    /// Bilinear lookup with repeat wrapping, v = 0 the top row, in linear RGBA (the four
    /// texels decoded, then blended); white for a layer past the last (`NO_TEXTURE`, u32::MAX,
    /// among them). `sample_texture` in `textures.wgsl` does the same arithmetic.
    pub fn sample(&self, layer: u32, uv: Vec2) -> Vec4 {
        if layer >= self.layers {
            return Vec4::ONE;
        }
        let side = self.side;
        let ((x0, x1, tx), (y0, y1, ty)) = (bilinear_pair(uv.x, side), bilinear_pair(uv.y, side));
        let top = lerp(self.texel(layer, x0, y0), self.texel(layer, x1, y0), tx);
        let bottom = lerp(self.texel(layer, x0, y1), self.texel(layer, x1, y1), tx);
        lerp(top, bottom, ty)
    }
}

/// The largest side of `textures` rounded up to a power of two, capped at `max_side` (at
/// least 1).
pub fn common_side(textures: &[Texture], max_side: u32) -> u32 {
    let largest = textures
        .iter()
        .map(|t| t.width.max(t.height))
        .max()
        .unwrap_or(1)
        .max(1);
    largest
        .checked_next_power_of_two()
        .unwrap_or(u32::MAX)
        .min(max_side.max(1))
}

/// Appends `texture` resampled to `side`²: each destination texel is the source's bilinear
/// lookup (repeat-wrapped, in linear colour, as [`TextureArray::sample`] blends) at the
/// destination texel's centre, so a small texture stretched over a large layer stays as smooth
/// as it would be sampled at its own size. A texture already `side`² is copied as it is.
fn resample_into(texture: &Texture, side: u32, out: &mut Vec<[u8; 4]>) {
    let (width, height) = (texture.width, texture.height);
    if width == 0 || height == 0 || texture.texel_count() == 0 {
        out.extend(std::iter::repeat_n([255; 4], side as usize * side as usize));
        return;
    }
    if (width, height) == (side, side) {
        match &texture.texels {
            Texels::Srgb8(t) => out.extend_from_slice(t),
            Texels::LinearF32(t) => out.extend(t.iter().map(|&c| encode_linear(c))),
        }
        return;
    }
    let centre = |i: u32| (i as f32 + 0.5) / side as f32;
    for y in 0..side {
        out.extend(
            (0..side)
                .map(|x| encode_linear(texture.sample_bilinear(centre(x), centre(y)).to_array())),
        );
    }
}

/// A linear RGBA float texel as RGBA8: colour sRGB-encoded, alpha linear, both clamped to
/// [0, 1] (NaN reads 0).
fn encode_linear([r, g, b, a]: [f32; 4]) -> [u8; 4] {
    let quantize = |c: f32| (c.clamp(0.0, 1.0) * 255.0).round() as u8;
    let srgb = |c: f32| {
        let c = if c.is_nan() { 0.0 } else { c.clamp(0.0, 1.0) };
        quantize(if c <= 0.003_130_8 {
            12.92 * c
        } else {
            1.055 * c.powf(1.0 / 2.4) - 0.055
        })
    };
    [
        srgb(r),
        srgb(g),
        srgb(b),
        quantize(if a.is_nan() { 0.0 } else { a }),
    ]
}

#[cfg(test)]
mod tests {
    use super::*;
    use scene::textures::srgb_to_linear;

    fn srgb8(name: &str, width: u32, height: u32, texels: Vec<[u8; 4]>) -> Texture {
        assert_eq!(texels.len(), (width * height) as usize);
        Texture {
            name: name.into(),
            width,
            height,
            texels: Texels::Srgb8(texels),
        }
    }

    fn linear(c: [u8; 4]) -> Vec4 {
        Vec4::new(
            srgb_to_linear(c[0]),
            srgb_to_linear(c[1]),
            srgb_to_linear(c[2]),
            c[3] as f32 / 255.0,
        )
    }

    const BLACK: [u8; 4] = [0, 0, 0, 255];
    const WHITE: [u8; 4] = [255, 255, 255, 255];

    /// A 2×2 checker: black top left and bottom right.
    fn checker() -> Texture {
        srgb8("checker", 2, 2, vec![BLACK, WHITE, WHITE, BLACK])
    }

    #[test]
    fn textures_none_is_one_white_texel() {
        let array = TextureArray::build(&[], DEFAULT_MAX_SIDE);
        assert_eq!((array.side, array.layers), (1, 1));
        assert_eq!(array.texels, vec![[255; 4]]);
        assert_eq!(array.bytes(), 4);
        assert_eq!(array.sample(0, Vec2::new(0.3, 0.7)), Vec4::ONE);
        assert_eq!(array.sample(u32::MAX, Vec2::ZERO), Vec4::ONE);
    }

    #[test]
    fn textures_one_by_one_reads_its_texel_everywhere() {
        let colour = [200, 100, 50, 128];
        let array = TextureArray::build(&[srgb8("one", 1, 1, vec![colour])], DEFAULT_MAX_SIDE);
        assert_eq!((array.side, array.layers), (1, 1));
        for uv in [
            Vec2::ZERO,
            Vec2::new(0.5, 0.5),
            Vec2::new(0.999, 1.0),
            Vec2::new(-3.2, 7.9),
        ] {
            assert_eq!(array.sample(0, uv), linear(colour), "{uv}");
        }
        let decoded = array.sample(0, Vec2::ZERO);
        assert!((decoded.w - 128.0 / 255.0).abs() < 1e-7, "alpha is linear");
        assert!((decoded.x - srgb_to_linear(200)).abs() < 1e-7);
        // Past the last layer (and NO_TEXTURE): white.
        assert_eq!(array.sample(1, Vec2::ZERO), Vec4::ONE);
        assert_eq!(array.sample(u32::MAX, Vec2::ZERO), Vec4::ONE);
    }

    #[test]
    fn textures_checker_at_texel_centres_and_wrapped() {
        let array = TextureArray::build(&[checker()], DEFAULT_MAX_SIDE);
        assert_eq!((array.side, array.layers), (2, 1));
        assert_eq!(array.texels, vec![BLACK, WHITE, WHITE, BLACK]);
        let (black, white) = (linear(BLACK), linear(WHITE));
        // Texel centres; v = 0 is the top row.
        assert_eq!(array.sample(0, Vec2::new(0.25, 0.25)), black);
        assert_eq!(array.sample(0, Vec2::new(0.75, 0.25)), white);
        assert_eq!(array.sample(0, Vec2::new(0.25, 0.75)), white);
        assert_eq!(array.sample(0, Vec2::new(0.75, 0.75)), black);
        // Repeat wrapping, negative and past 1.
        assert_eq!(array.sample(0, Vec2::new(-0.75, 0.25)), black);
        assert_eq!(array.sample(0, Vec2::new(-0.25, 0.25)), white);
        assert_eq!(array.sample(0, Vec2::new(1.25, 2.25)), black);
        assert_eq!(array.sample(0, Vec2::new(1.75, -1.75)), white);
        assert_eq!(array.sample(0, Vec2::new(-1.25, -1.25)), black);
        assert_eq!(array.sample(0, Vec2::new(3.25, -0.25)), white);
        // Between centres the four texels blend in linear colour: at a corner, and at u = 1
        // (wrapping to 0) or a tiny negative, half black and half white.
        let grey = (black + white) * 0.5;
        for uv in [
            Vec2::ZERO,
            Vec2::new(1.0, 0.0),
            Vec2::new(-1e-9, 0.0),
            Vec2::new(0.5, 0.5),
        ] {
            assert!(
                (array.sample(0, uv) - grey).abs().max_element() < 1e-6,
                "{uv}"
            );
        }
        // A quarter of the way from a black centre to the white one beside it.
        let quarter = array.sample(0, Vec2::new(0.375, 0.25));
        assert!(
            (quarter - (black * 0.75 + white * 0.25))
                .abs()
                .max_element()
                < 1e-6
        );
        // Agrees with the scene's own bilinear lookup on the texture (the array holds it at its
        // own size, so the two read the same texels).
        let texture = checker();
        for i in -8..8 {
            for j in -8..8 {
                let uv = Vec2::new(i as f32 * 0.23 + 0.01, j as f32 * 0.31 + 0.02);
                assert_eq!(
                    array.sample(0, uv),
                    texture.sample_bilinear(uv.x, uv.y),
                    "{uv}"
                );
            }
        }
    }

    /// An independent bilinear lookup in f64 (repeat wrapping, linear colour) of a texture
    /// `width` × `height` of sRGB8 `texels`: what the resampling should produce, before
    /// its 8-bit encoding.
    fn bilinear_reference(
        texels: &[[u8; 4]],
        width: usize,
        height: usize,
        u: f64,
        v: f64,
    ) -> [f64; 4] {
        let decode = |c: u8, channel: usize| {
            let c = c as f64 / 255.0;
            if channel == 3 {
                c
            } else if c <= 0.04045 {
                c / 12.92
            } else {
                ((c + 0.055) / 1.055).powf(2.4)
            }
        };
        let axis = |c: f64, n: usize| {
            let p = c.rem_euclid(1.0) * n as f64 - 0.5;
            let i = p.floor();
            let first = (i as i64).rem_euclid(n as i64) as usize;
            (first, (first + 1) % n, p - i)
        };
        let (x0, x1, tx) = axis(u, width);
        let (y0, y1, ty) = axis(v, height);
        std::array::from_fn(|ch| {
            let at = |x: usize, y: usize| decode(texels[y * width + x][ch], ch);
            let top = at(x0, y0) * (1.0 - tx) + at(x1, y0) * tx;
            let bottom = at(x0, y1) * (1.0 - tx) + at(x1, y1) * tx;
            top * (1.0 - ty) + bottom * ty
        })
    }

    /// `layer`'s texels against [`bilinear_reference`] of `texels` at each destination centre,
    /// within one 8-bit step.
    fn assert_resampled(
        array: &TextureArray,
        layer: u32,
        texels: &[[u8; 4]],
        width: usize,
        height: usize,
    ) {
        let side = array.side as usize;
        for (i, got) in array.layer(layer).iter().enumerate() {
            let (u, v) = ((i % side) as f64 + 0.5, (i / side) as f64 + 0.5);
            let want = bilinear_reference(texels, width, height, u / side as f64, v / side as f64);
            let got = linear(*got);
            for (ch, (g, w)) in got.to_array().into_iter().zip(want).enumerate() {
                // An 8-bit sRGB step is at most ~0.0055 in linear terms (near white).
                assert!(
                    (g as f64 - w).abs() < 6e-3,
                    "texel {i} channel {ch}: {g} vs {w}"
                );
            }
        }
    }

    #[test]
    fn textures_resample_non_square_to_common_power_of_two() {
        // 3 wide, 2 high: the common side is 4 (next power of two of 3).
        let texels: Vec<[u8; 4]> = (1..=6).map(|i| [i * 10, 255 - i * 30, 0, 40 * i]).collect();
        let wide = srgb8("wide", 3, 2, texels.clone());
        let small = srgb8("small", 1, 1, vec![WHITE]);
        let array = TextureArray::build(&[wide, small], DEFAULT_MAX_SIDE);
        assert_eq!((array.side, array.layers), (4, 2));
        assert_eq!(array.bytes(), 2 * 16 * 4);
        assert_resampled(&array, 0, &texels, 3, 2);
        assert!(array.layer(1).iter().all(|&t| t == WHITE));
        assert_eq!(array.sample(1, Vec2::new(0.9, 0.9)), Vec4::ONE);
    }

    #[test]
    fn textures_side_is_capped_and_downsampled() {
        let texels = (0..64u32)
            .map(|i| [(i * 4) as u8, 0, 0, 255])
            .collect::<Vec<_>>();
        let big = srgb8("big", 8, 8, texels.clone());
        assert_eq!(common_side(std::slice::from_ref(&big), 2048), 8);
        let array = TextureArray::build(&[big], 2);
        assert_eq!(array.side, 2);
        // Centres 1/4 and 3/4 of 8 texels fall between texels 1 and 2, and 5 and 6.
        assert_resampled(&array, 0, &texels, 8, 8);
    }

    /// A texture at the common side is kept byte for byte (no re-encoding).
    #[test]
    fn textures_at_the_common_side_are_copied() {
        let texels: Vec<[u8; 4]> = (0..16u8)
            .map(|i| [i * 16, 255 - i, i, 255 - i * 16])
            .collect();
        let array = TextureArray::build(&[srgb8("exact", 4, 4, texels.clone())], DEFAULT_MAX_SIDE);
        assert_eq!(array.texels, texels);
    }

    #[test]
    fn textures_linear_floats_are_encoded_to_srgb() {
        let texture = Texture {
            name: "hdr".into(),
            width: 2,
            height: 1,
            texels: Texels::LinearF32(vec![[0.0, 0.5, 1.0, 0.5], [4.0, -1.0, 0.2, 1.0]]),
        };
        let array = TextureArray::build(&[texture], DEFAULT_MAX_SIDE);
        assert_eq!(array.side, 2);
        let left = array.sample(0, Vec2::new(0.25, 0.5));
        let right = array.sample(0, Vec2::new(0.75, 0.5));
        // One 8-bit sRGB step near 0.5 is about 0.004 in linear terms.
        for (got, want) in left.to_array().into_iter().zip([0.0, 0.5, 1.0, 0.5]) {
            assert!((got - want).abs() < 4e-3, "{left} vs {want}");
        }
        for (got, want) in right.to_array().into_iter().zip([1.0, 0.0, 0.2, 1.0]) {
            assert!((got - want).abs() < 4e-3, "{right} vs {want}");
        }
    }
}
