// Group 0 with nodes, triangles and threaded records in rgba32uint textures (SceneStorage::Texels): the
// same bytes as scene_bindings.wgsl's buffers, 16 per texel, TEXEL_ROW texels a row
// (gpu::scene_upload). Through lavapipe a texel fetch is a branch-free gather, where a
// storage-buffer load with a different index per lane is a scalar loop over the lanes
// (docs/BENCHMARKS.md §2, session 15). Integer texels keep every bit; bitcast makes floats.

@group(0) @binding(0) var bvh_node_texels: texture_2d<u32>;
@group(0) @binding(1) var bvh_triangle_texels: texture_2d<u32>;
@group(0) @binding(2) var bvh_threaded_texels: texture_2d<u32>;
@group(0) @binding(3) var<storage, read> scene_info: SceneInfo;
@group(0) @binding(4) var<storage, read> materials: array<GpuMaterial>;

fn texel_at(i: u32) -> vec2<u32> {
    return vec2<u32>(i & (TEXEL_ROW - 1u), i / TEXEL_ROW);
}

fn load_node(i: u32) -> BvhNode {
    let lo = textureLoad(bvh_node_texels, texel_at(2u * i), 0);
    let hi = textureLoad(bvh_node_texels, texel_at(2u * i + 1u), 0);
    return BvhNode(bitcast<vec3<f32>>(lo.xyz), lo.w, bitcast<vec3<f32>>(hi.xyz), hi.w);
}

fn load_threaded(i: u32) -> ThreadedNode {
    let lo = textureLoad(bvh_threaded_texels, texel_at(2u * i), 0);
    let hi = textureLoad(bvh_threaded_texels, texel_at(2u * i + 1u), 0);
    return ThreadedNode(bitcast<vec3<f32>>(lo.xyz), lo.w, bitcast<vec3<f32>>(hi.xyz), hi.w);
}

// A triangle is six texels, a vertex two: position and u, then normal_xy, signed_material, v.
fn vertex_texel(triangle: u32, vertex: u32) -> u32 {
    return 6u * triangle + 2u * vertex;
}

fn load_vertex(triangle: u32, vertex: u32) -> PackedVertex {
    let first = vertex_texel(triangle, vertex);
    let a = bitcast<vec4<f32>>(textureLoad(bvh_triangle_texels, texel_at(first), 0));
    let b = bitcast<vec4<f32>>(textureLoad(bvh_triangle_texels, texel_at(first + 1u), 0));
    return PackedVertex(a.xyz, a.w, b.xy, b.z, b.w);
}

fn load_position(triangle: u32, vertex: u32) -> vec3<f32> {
    // The first texel only: a traversal needs no normal or uv.
    return bitcast<vec3<f32>>(textureLoad(bvh_triangle_texels, texel_at(vertex_texel(triangle, vertex)), 0).xyz);
}

fn load_triangle(triangle: u32) -> PackedTriangle {
    return PackedTriangle(array<PackedVertex, 3>(
        load_vertex(triangle, 0u),
        load_vertex(triangle, 1u),
        load_vertex(triangle, 2u),
    ));
}
