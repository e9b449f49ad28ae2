// render::random::TalkFloat: the talk's float-only generator (GPURnd, Hachisuka 2015), four
// Schrage-stepped multiplicative generators in f32. Needs random.wgsl and the TALK_*
// constants that gpu::random_variants generates from Rust.

alias Rng = vec4<f32>;

// Lanes start from the stream's key hashed once more per lane, in [1, m - 1].
fn rng_start(seed: u32, salt: u32, pass_index: u32, index: u32) -> Rng {
    let key = stream_key(seed, salt, pass_index, index);
    let h = vec4<u32>(pcg_hash(key), pcg_hash(key + 1u), pcg_hash(key + 2u), pcg_hash(key + 3u));
    return vec4<f32>(1u + h % (vec4<u32>(TALK_M) - 1u));
}

fn next_f32(state: ptr<function, Rng>) -> f32 {
    let s = *state;
    // WGSL's division may be off by 2.5 ULP: the exact remainder corrects the quotient, so
    // the integer states stay the CPU's.
    var beta = floor(s / TALK_Q);
    let rem = s - beta * TALK_Q;
    beta = beta - select(vec4(0.0), vec4(1.0), rem < vec4(0.0))
        + select(vec4(0.0), vec4(1.0), rem >= TALK_Q);
    let p = TALK_A * (s - beta * TALK_Q) - beta * TALK_R;
    let next = p + select(vec4(0.0), TALK_M, p < vec4(0.0));
    *state = next;
    let x = next.x * TALK_INV_M.x - next.y * TALK_INV_M.y + next.z * TALK_INV_M.z
        - next.w * TALK_INV_M.w;
    return min(x - floor(x), ONE_BELOW);
}
