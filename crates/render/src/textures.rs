//! The scene's textures as both backends read them (DESIGN.md, "Textures live in one texture
//! array"): every texture resampled (nearest) to one common power-of-two side and stacked as a
//! layer of one RGBA8 array, colour channels sRGB-encoded, alpha linear. The GPU backend uploads
//! [`TextureArray::texels`] as a `texture_2d_array` and reads it in `textures.wgsl` with the
//! arithmetic of [`TextureArray::sample`], which the CPU backend calls.

use glam::{Vec2, Vec4};
use scene::textures::srgb_to_linear;
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
        let [r, g, b, a] = self.texels[(layer as usize * side + y as usize) * side + x as usize];
        Vec4::new(
            srgb_to_linear(r),
            srgb_to_linear(g),
            srgb_to_linear(b),
            a as f32 / 255.0,
        )
    }

    /// Nearest-texel lookup with repeat wrapping, v = 0 the top row, in linear RGBA; white for
    /// a layer past the last (`NO_TEXTURE`, u32::MAX, among them). `sample_texture` in
    /// `textures.wgsl` does the same arithmetic.
    pub fn sample(&self, layer: u32, uv: Vec2) -> Vec4 {
        if layer >= self.layers {
            return Vec4::ONE;
        }
        let side = self.side;
        let wrap = |c: f32| {
            let f = c - c.floor();
            ((f * side as f32) as u32).min(side - 1)
        };
        self.texel(layer, wrap(uv.x), wrap(uv.y))
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

/// Appends `texture` resampled to `side`² by nearest texel: destination texel centre
/// (x + ½) / side maps to source texel ⌊(x + ½)·width / side⌋, in exact integer arithmetic.
fn resample_into(texture: &Texture, side: u32, out: &mut Vec<[u8; 4]>) {
    let (width, height) = (texture.width, texture.height);
    if width == 0 || height == 0 || texture.texel_count() == 0 {
        out.extend(std::iter::repeat_n([255; 4], side as usize * side as usize));
        return;
    }
    let source = |d: u32, n: u32| ((2 * d as u64 + 1) * n as u64 / (2 * side as u64)) as usize;
    let columns: Vec<usize> = (0..side).map(|x| source(x, width)).collect();
    for y in 0..side {
        let row = source(y, height) * width as usize;
        match &texture.texels {
            Texels::Srgb8(t) => out.extend(columns.iter().map(|&x| t[row + x])),
            Texels::LinearF32(t) => out.extend(columns.iter().map(|&x| encode_linear(t[row + x]))),
        }
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
        // Edges: u = 1 wraps to 0, a tiny negative to the last texel.
        assert_eq!(array.sample(0, Vec2::new(1.0, 0.0)), black);
        assert_eq!(array.sample(0, Vec2::new(-1e-9, 0.0)), white);
        // Agrees with the scene's own nearest lookup.
        let texture = checker();
        for i in -8..8 {
            for j in -8..8 {
                let uv = Vec2::new(i as f32 * 0.23 + 0.01, j as f32 * 0.31 + 0.02);
                assert_eq!(
                    array.sample(0, uv),
                    texture.sample_nearest(uv.x, uv.y),
                    "{uv}"
                );
            }
        }
    }

    #[test]
    fn textures_resample_non_square_to_common_power_of_two() {
        // 3 wide, 2 high: the common side is 4 (next power of two of 3).
        let a = [10, 0, 0, 255];
        let b = [20, 0, 0, 255];
        let c = [30, 0, 0, 255];
        let d = [40, 0, 0, 255];
        let e = [50, 0, 0, 255];
        let f = [60, 0, 0, 255];
        let wide = srgb8("wide", 3, 2, vec![a, b, c, d, e, f]);
        let small = srgb8("small", 1, 1, vec![WHITE]);
        let array = TextureArray::build(&[wide, small], DEFAULT_MAX_SIDE);
        assert_eq!((array.side, array.layers), (4, 2));
        assert_eq!(array.bytes(), 2 * 16 * 4);
        // Columns: centres 1/8, 3/8, 5/8, 7/8 of 3 texels → 0, 1, 1, 2; rows of 2 → 0, 0, 1, 1.
        #[rustfmt::skip]
        let expected = vec![
            a, b, b, c,
            a, b, b, c,
            d, e, e, f,
            d, e, e, f,
        ];
        assert_eq!(array.layer(0), expected.as_slice());
        assert!(array.layer(1).iter().all(|&t| t == WHITE));
        assert_eq!(array.sample(0, Vec2::new(0.9, 0.9)), linear(f));
        assert_eq!(array.sample(0, Vec2::new(0.1, 0.6)), linear(d));
        assert_eq!(array.sample(1, Vec2::new(0.9, 0.9)), Vec4::ONE);
    }

    #[test]
    fn textures_side_is_capped_and_downsampled() {
        let texels = (0..64u32)
            .map(|i| [(i * 4) as u8, 0, 0, 255])
            .collect::<Vec<_>>();
        let big = srgb8("big", 8, 8, texels);
        assert_eq!(common_side(std::slice::from_ref(&big), 2048), 8);
        let array = TextureArray::build(&[big], 2);
        assert_eq!(array.side, 2);
        // Centres 1/4 and 3/4 of 8 texels: columns and rows 2 and 6.
        let red = |x: u32, y: u32| [((y * 8 + x) * 4) as u8, 0, 0, 255];
        assert_eq!(
            array.texels,
            vec![red(2, 2), red(6, 2), red(2, 6), red(6, 6)]
        );
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
