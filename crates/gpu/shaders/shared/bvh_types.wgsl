// WGSL twins of bvh::pack's GPU structs; same names, same layout. tests/layout.rs checks every
// size and offset against the Rust definitions through naga, so edit both sides together.

// One node's box and contents (32 bytes). Leaf: triangles[first_or_right..][..triangle_count].
// Internal (triangle_count == 0): first_or_right is the right child; the left child is index + 1.
struct BvhNode {
    min: vec3<f32>,
    first_or_right: u32,
    max: vec3<f32>,
    triangle_count: u32,
}

// One node in one threading's pre-order (bvh::threaded, 32 bytes): entering the box goes on at
// the next record, missing it at `miss` (LINK_END ends); `leaf` is a leaf's index in the shared
// nodes (its triangles), LINK_END for an internal node.
struct ThreadedNode {
    min: vec3<f32>,
    miss: u32,
    max: vec3<f32>,
    leaf: u32,
}

// One vertex (32 bytes). signed_material = sign(normal.z) * (material + 1); the normal's z is
// rebuilt as sqrt(max(0, 1 - x^2 - y^2)) with that sign.
struct PackedVertex {
    position: vec3<f32>,
    u: f32,
    normal_xy: vec2<f32>,
    signed_material: f32,
    v: f32,
}

// Three vertices, counter-clockwise front face (96 bytes).
struct PackedTriangle {
    vertices: array<PackedVertex, 3>,
}

// The compact MTBVH's record (bvh::compact, 32 bytes): bounds_and_meta.xyz = the box, 16 bits
// per coordinate (min.x | min.y << 16, min.z | max.x << 16, max.y | max.z << 16); .w = meta
// (COMPACT_LEAF, COMPACT_FAR, a leaf's triangle count or an internal node's right-first bit
// per direction); links.x = first triangle or right child; links.yzw = six 16-bit miss
// offsets (0 = LINK_END), or for a far node links.y = its far record, whose eight words are
// the six absolute links.
struct CompactNode {
    bounds_and_meta: vec4<u32>,
    links: vec4<u32>,
}

// Decoding of the compact boxes: coordinate = origin + q * scale, scale = m * 2^k with m < 256
// (32 bytes).
struct CompactFrame {
    origin: vec3<f32>,
    root: u32,
    scale: vec3<f32>,
    node_count: u32,
}
