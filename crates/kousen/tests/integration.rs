//! The kousen crate's integration tests, one module per file beside this one, built as one
//! test binary: each binary links the whole dependency graph, and linking forty of them was
//! a large share of a clean build (CI).

mod common;

mod cli_bad_input;
mod cli_bench;
mod cli_bench_density;
mod cli_bench_photons;
mod cli_bench_rng;
mod cli_checkpoint;
mod cli_commands;
mod cli_diff;
mod cli_punctual;
