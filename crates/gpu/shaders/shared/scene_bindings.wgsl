// Group 0: the packed scene, shared by every kernel (see gpu::scene_upload).

@group(0) @binding(0) var<storage, read> bvh_nodes: array<BvhNode>;
@group(0) @binding(1) var<storage, read> bvh_triangles: array<PackedTriangle>;
@group(0) @binding(2) var<storage, read> bvh_links: array<Links>;
@group(0) @binding(3) var<storage, read> scene_info: SceneInfo;
@group(0) @binding(4) var<storage, read> materials: array<GpuMaterial>;
