// The kernels' default generator, render::rng::KernelRng (render::random::Pcg). Needs
// random.wgsl. Each shared/random_<name>.wgsl defines the same three names.

// The kernels' random stream (render::rng::KernelRng): a PCG state. Kernels name only `Rng`,
// `rng_start` and `next_f32`, so another generator can stand in for this one.
alias Rng = u32;

// render::rng::KernelRng::new: the stream of element `index` in `pass_index` of kernel `salt`.
fn rng_start(seed: u32, salt: u32, pass_index: u32, index: u32) -> Rng {
    return stream_key(seed, salt, pass_index, index);
}

// render::rng::KernelRng::next_f32: uniform in [0, 1) from the top 24 bits.
fn next_f32(state: ptr<function, Rng>) -> f32 {
    let old = *state;
    *state = old * 747796405u + 2891336453u;
    return f32(pcg_hash(old) >> 8u) * (1.0 / 16777216.0);
}
