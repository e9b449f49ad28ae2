//! The gpu crate's integration tests, one module per file beside this one, built as one
//! test binary: each binary links the whole dependency graph, and linking forty of them was
//! a large share of a clean build (CI).

mod checkpoint;
mod denoise_guides;
mod density_twins;
mod device;
mod display;
mod half_storage;
mod kdtree;
mod layout;
mod packing_twins;
mod photon_trace_naive;
mod random_variants;
mod sky_map;
mod sppm_textures;
mod sppm_twins;
mod traversal;
