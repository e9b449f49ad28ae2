// The kd-tree's query (cpu's Density::KdTree: render::kdtree::PhotonKdTree::visit with
// cpu::kernels::GatherSum::add_if_near): the tree is built on the CPU from this pass's photons
// and uploaded; every photon in the sphere counts. Only `kousen bench density` runs it.

// This pass's tree (render::kdtree), then its node count.
@group(3) @binding(0) var<storage, read> kd_nodes: array<KdNode>;
@group(3) @binding(1) var<storage, read> kd_node_count: array<u32>;

fn density_query(query: GatherQuery, cell_size: f32) -> GatherSum {
    return kd_gather(query, kd_node_count[0]);
}
