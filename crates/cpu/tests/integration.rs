//! The cpu crate's integration tests, one module per file beside this one, built as one
//! test binary: each binary links the whole dependency graph, and linking forty of them was
//! a large share of a clean build (CI).

mod analytic;
mod checkpoint;
mod convergence;
mod denoise_guides;
mod density;
mod depth_of_field;
mod determinism;
mod eye_paths;
mod glossy_light_sampling;
mod hash;
mod metallic_roughness;
mod mitsuba_reference;
mod prism;
mod shadow_terminator;
mod walks;
