// Fixed-radius photon gather in a left-balanced kd-tree: twin of render::kdtree
// (PhotonKdTree::visit), node for node in the same order, so found counts agree exactly and
// flux sums in the same order. Needs, declared by the module that includes it (the SPPM
// module): `kd_nodes: array<KdNode>` (render::kdtree::PhotonKdTree::nodes, heap order),
// `GatherQuery`, `GatherSum`, `no_photons`, `reach` and `add_if_near`, and the prelude's
// KD_STACK_SIZE and KD_AXIS_SHIFT.

// render::kdtree::KdNode (32 bytes): a photon in tree order.
struct KdNode {
    position: vec3<f32>,
    normal: u32,
    flux: vec3<f32>,
    // Bits 0-29: the photon's index in the pass's photons; bits 30-31: the split axis (0 x,
    // 1 y, 2 z).
    photon_axis: u32,
}

// Every node the search around the query's position within its reach visits goes through
// add_if_near (render::kdtree::PhotonKdTree::visit with cpu::kernels::GatherSum::add_if_near):
// caustic and indirect photons within their own radius facing the query's normal, or for a
// volume visible point the volume photons in its sphere. Depth first, the node itself, then
// the side of its split plane holding the position, then the other side when the plane is
// nearer than the reach. A complete tree of node_count < 2^27 nodes is at most
// KD_STACK_SIZE + 1 levels deep, and the stack holds at most one entry per level below the
// root (render::kdtree::STACK_SIZE).
fn kd_gather(query: GatherQuery, node_count: u32) -> GatherSum {
    let radius = reach(query);
    let radius_sq = radius * radius;
    var sum = no_photons();
    var stack: array<u32, KD_STACK_SIZE>;
    var top = 0u;
    var node = 0u;
    loop {
        while node < node_count {
            let kd = kd_nodes[node];
            let offset = kd.position - query.position;
            add_if_near(&sum, query, Photon(kd.position, kd.normal, kd.flux, 0u), 1u);
            let to_plane = offset[kd.photon_axis >> KD_AXIS_SHIFT];
            let left = 2u * node + 1u;
            let near = select(left + 1u, left, to_plane > 0.0);
            let far = select(left, left + 1u, to_plane > 0.0);
            if far < node_count && to_plane * to_plane < radius_sq {
                stack[top] = far;
                top += 1u;
            }
            node = near;
        }
        if top == 0u {
            break;
        }
        top -= 1u;
        node = stack[top];
    }
    return sum;
}
