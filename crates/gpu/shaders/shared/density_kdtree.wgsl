// The kd-tree's query (render::kdtree::PhotonKdTree::gather): the tree is built on the CPU
// from this pass's photons and uploaded; every photon in the sphere counts. Only `kousen
// bench density` runs it.

// This pass's tree (render::kdtree), then its node count.
@group(3) @binding(0) var<storage, read> kd_nodes: array<KdNode>;
@group(3) @binding(1) var<storage, read> kd_node_count: array<u32>;

fn density_query(position: vec3<f32>, normal: vec3<f32>, radii: vec2<f32>, cell_size: f32) -> GatherSum {
    let found = kd_gather(position, radii, normal, kd_node_count[0]);
    return GatherSum(found.found, found.flux, found.caustic_found, found.caustic_flux);
}
