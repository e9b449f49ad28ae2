//! The bvh crate's integration tests, one module per file beside this one, built as one
//! test binary: each binary links the whole dependency graph, and linking forty of them was
//! a large share of a clean build (CI).

mod any_hit_where;
mod build_sah;
mod compact_mtbvh;
mod threading;
mod traversal_matches_brute_force;
mod wide_collapse;
mod wide_mtbvh;
