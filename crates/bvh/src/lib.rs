//! kousen's bounding volume hierarchy: a binned SAH build, its threading for stackless
//! traversal (the multiple-threaded BVH of Hachisuka's talk "Implementing a practical rendering
//! system using GLSL", 2015), the GPU layout, and CPU traversals that mirror the WGSL kernels.
//!
//! - [`mod@build_sah`]: binned SAH build over the triangles' boxes, parallel with rayon.
//! - [`mtbvh`]: hit/miss links for the TBVH (one order) and the MTBVH (six directions).
//! - [`pack`]: `#[repr(C)]` Pod nodes, links and triangles ([`PackedBvh`]).
//! - [`traverse`]: stack, TBVH and MTBVH traversal, closest and any hit, and brute force.
//! - [`threaded`]: one threading's nodes in its own pre-order, box and miss link a record
//!   (what the GPU's stackless kernels walk).
//! - [`compact`]: the MTBVH in 32-byte records with 16-bit boxes and links, and its traversal.
//! - [`probe`]: keeping split triangles only where sample rays say they pay.
//! - [`wide`]: the MTBVH four-wide with a stackless trail traversal, for the CPU backend.
//! - [`testing`]: random triangle soups and rays from a seed.
//!
//! Default leaf size: at most two triangles (the talk uses one); measured against 1, 4 and 8
//! with the MTBVH traversal by `examples/leaf_size.rs`, see [`BuildOptions::default`].
//! Build speed: `examples/build_time.rs`.

mod aabb;
pub mod bench_rays;
mod binning;
pub mod build_sah;
pub mod compact;
pub mod intersect;
pub mod mtbvh;
pub mod pack;
mod packed_triangle;
mod presplit;
pub mod probe;
pub mod sbvh;
pub mod testing;
pub mod threaded;
pub mod traverse;
pub mod tree;
pub mod wide;

pub use build_sah::{BuildOptions, build_sah};
pub use compact::{
    CompactError, CompactFrame, CompactMemory, CompactMtbvh, CompactNode, any_hit_mtbvh_compact,
    closest_hit_mtbvh_compact, trace_mtbvh_compact,
};
pub use intersect::{Hit, Ray, SlabRay};
pub use mtbvh::{DIRECTION_COUNT, LINK_END, Order, Threading, Threadings};
pub use pack::{BvhNode, Links, Memory, PackedBvh, PackedTriangle, PackedVertex, direction_index};
pub use threaded::{ThreadedNode, threaded_nodes};
pub use traverse::{
    Query, TraversalCounters, Uncounted, WorkTally, any_hit_brute_force, any_hit_mtbvh,
    any_hit_mtbvh_where, any_hit_stack, any_hit_tbvh, closest_hit_brute_force, closest_hit_mtbvh,
    closest_hit_stack, closest_hit_tbvh,
};
pub use tree::{Bvh, MAX_DEPTH, Node};
pub use wide::{
    WideMtbvh, any_hit_cpu, any_hit_cpu_where, any_hit_wide, closest_hit_cpu, closest_hit_wide,
    trace_wide,
};
