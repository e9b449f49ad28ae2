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

// Layer `id` at `uv` in linear RGBA: the nearest texel, repeat wrapping, v = 0 the top row.
// White for a layer past the last (NO_TEXTURE among them).
fn sample_texture(id: u32, uv: vec2<f32>) -> vec4<f32> {
    if id >= textureNumLayers(scene_textures) {
        return vec4<f32>(1.0);
    }
    let side = textureDimensions(scene_textures).x;
    let f = uv - floor(uv);
    let texel = min(vec2<u32>(f * f32(side)), vec2<u32>(side - 1u));
    let t = textureLoad(scene_textures, texel, id, 0);
    return vec4<f32>(srgb_decode(t.x), srgb_decode(t.y), srgb_decode(t.z), t.w);
}
