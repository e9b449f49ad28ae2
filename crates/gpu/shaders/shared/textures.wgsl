// Texture lookups for the SPPM kernels (twin of cpu::surface::texture).
// TODO(issue 4): textures are not uploaded yet; every lookup reads white (untextured scenes
// render exactly, textured ones without their textures).

fn sample_texture(id: u32, uv: vec2<f32>) -> vec4<f32> {
    return vec4<f32>(1.0);
}
