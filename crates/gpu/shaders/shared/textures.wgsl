// Texture lookups for the SPPM kernels: twin of render::textures::TextureArray::sample (which
// cpu::surface::texture calls). Every texture is one layer of this array, resampled to a common
// square side (gpu::textures). Texels are RGBA8 read as unorm, colour sRGB-encoded (decoded here
// with scene::textures::srgb_to_linear's formula, not by the hardware), alpha linear.

// Group 2: the scene's textures (gpu::textures::GpuTextures).
@group(2) @binding(0) var scene_textures: texture_2d_array<f32>;

// scene::textures::srgb_to_linear, on c = byte / 255.
fn srgb_decode(c: f32) -> f32 {
    if c <= 0.04045 {
        return c / 12.92;
    }
    return pow((c + 0.055) / 1.055, 2.4);
}

// Texel (x, y) of layer `id` in linear RGBA.
fn texel_linear(id: u32, x: u32, y: u32) -> vec4<f32> {
    let t = textureLoad(scene_textures, vec2<u32>(x, y), id, 0);
    return vec4<f32>(srgb_decode(t.x), srgb_decode(t.y), srgb_decode(t.z), t.w);
}

// render::textures::bilinear_pair: the two texels (repeat-wrapped) whose centres enclose
// coordinate c on an axis of n texels, and the second's weight.
struct BilinearPair {
    first: u32,
    second: u32,
    weight: f32,
}

fn bilinear_pair(c: f32, n: u32) -> BilinearPair {
    let p = (c - floor(c)) * f32(n) - 0.5;
    let base = floor(p);
    let m = i32(n);
    let first = u32(((i32(base) % m) + m) % m);
    return BilinearPair(first, (first + 1u) % n, p - base);
}

// render::textures::lerp, written out.
fn lerp4(a: vec4<f32>, b: vec4<f32>, t: f32) -> vec4<f32> {
    return a + (b - a) * t;
}

// Layer `id` at `uv` in linear RGBA: the four texels around uv decoded and blended, repeat
// wrapping, v = 0 the top row. White for a layer past the last (NO_TEXTURE among them).
fn sample_texture(id: u32, uv: vec2<f32>) -> vec4<f32> {
    if id >= textureNumLayers(scene_textures) {
        return vec4<f32>(1.0);
    }
    let side = textureDimensions(scene_textures).x;
    let x = bilinear_pair(uv.x, side);
    let y = bilinear_pair(uv.y, side);
    let top = lerp4(texel_linear(id, x.first, y.first), texel_linear(id, x.second, y.first), x.weight);
    let bottom = lerp4(texel_linear(id, x.first, y.second), texel_linear(id, x.second, y.second), x.weight);
    return lerp4(top, bottom, y.weight);
}
