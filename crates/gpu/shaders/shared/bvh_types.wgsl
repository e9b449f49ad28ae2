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

// A node's next node when the ray hits / misses its box, in one threading (8 bytes).
// LINK_END ends the traversal.
struct Links {
    hit: u32,
    miss: u32,
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
