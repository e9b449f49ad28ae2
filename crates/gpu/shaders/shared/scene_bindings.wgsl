// Group 0: the packed scene, shared by every kernel (see gpu::scene_upload), in storage
// buffers (SceneStorage::Buffers; scene_texels.wgsl stands in for this file with Texels).
// Kernels read nodes, threaded records and triangles through the load_* functions, which both files
// define, never through the bindings.

@group(0) @binding(0) var<storage, read> bvh_nodes: array<BvhNode>;
@group(0) @binding(1) var<storage, read> bvh_triangles: array<PackedTriangle>;
@group(0) @binding(2) var<storage, read> bvh_threaded: array<ThreadedNode>;
@group(0) @binding(3) var<storage, read> scene_info: SceneInfo;
@group(0) @binding(4) var<storage, read> materials: array<GpuMaterial>;

fn load_node(i: u32) -> BvhNode {
    return bvh_nodes[i];
}

fn load_threaded(i: u32) -> ThreadedNode {
    return bvh_threaded[i];
}

fn load_position(triangle: u32, vertex: u32) -> vec3<f32> {
    return bvh_triangles[triangle].vertices[vertex].position;
}

fn load_triangle(triangle: u32) -> PackedTriangle {
    return bvh_triangles[triangle];
}
