// render::random::Tea: TEA in TEA_ROUNDS rounds (Zafar, Olano & Curtis 2010) encrypting
// (index, draw counter) under a key made of the seed, salt and pass. Needs the TEA_*
// constants that gpu::random_variants generates from Rust.

struct TeaRng {
    key: vec3<u32>,
    index: u32,
    counter: u32,
}

alias Rng = TeaRng;

fn rng_start(seed: u32, salt: u32, pass_index: u32, index: u32) -> Rng {
    let key = TEA_KEY.xyz ^ vec3<u32>(seed, salt, pass_index);
    return TeaRng(key, index, 0u);
}

fn next_f32(state: ptr<function, Rng>) -> f32 {
    let k = vec4<u32>((*state).key, TEA_KEY.w);
    var v0 = (*state).index;
    var v1 = (*state).counter;
    var sum = 0u;
    for (var round = 0u; round < TEA_ROUNDS; round++) {
        sum += TEA_DELTA;
        v0 += ((v1 << 4u) + k.x) ^ (v1 + sum) ^ ((v1 >> 5u) + k.y);
        v1 += ((v0 << 4u) + k.z) ^ (v0 + sum) ^ ((v0 >> 5u) + k.w);
    }
    (*state).counter += 1u;
    return f32(v0 >> 8u) * (1.0 / 16777216.0);
}
