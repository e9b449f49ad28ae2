// Random numbers, twins of bvh::bench_rays::pcg_hash and render::rng.

// Jarzynski & Olano's PCG hash (bvh::bench_rays::pcg_hash).
fn pcg_hash(x: u32) -> u32 {
    let state = x * 747796405u + 2891336453u;
    let word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
    return (word >> 22u) ^ word;
}

// render::rng::stream_key: the start of the stream of element `index` in `pass`.
fn stream_key(seed: u32, salt: u32, pass_index: u32, index: u32) -> u32 {
    return pcg_hash(index ^ pcg_hash(pass_index ^ pcg_hash(seed ^ salt)));
}
