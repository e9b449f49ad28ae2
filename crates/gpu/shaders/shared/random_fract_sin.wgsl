// render::random::FractSin: the fract(sin(dot(...)) * 43758.5453) noise function the talk
// warns about, over (index, pass * FRACT_SIN_DRAWS_PER_PASS + counter, seed ^ salt). GPU
// `sin` is approximate, so its draws match the CPU's in distribution only. Needs the
// FRACT_SIN_* constants that gpu::random_variants generates from Rust.

alias Rng = vec3<u32>;

fn rng_start(seed: u32, salt: u32, pass_index: u32, index: u32) -> Rng {
    return vec3<u32>(index, pass_index * FRACT_SIN_DRAWS_PER_PASS, (seed ^ salt) & 0xffffu);
}

fn next_f32(state: ptr<function, Rng>) -> f32 {
    let s = *state;
    let d = f32(s.x) * FRACT_SIN_K.x + f32(s.y) * FRACT_SIN_K.y + f32(s.z) * FRACT_SIN_K.z;
    (*state).y = s.y + 1u;
    let x = sin(d) * FRACT_SIN_SCALE;
    return min(x - floor(x), ONE_BELOW);
}
