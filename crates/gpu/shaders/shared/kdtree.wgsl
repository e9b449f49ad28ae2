// Fixed-radius photon gather in a left-balanced kd-tree: twin of render::kdtree
// (PhotonKdTree::query), node for node in the same order, so found counts agree exactly and
// flux sums in the same order. Needs, declared by the module that includes it:
// `kd_nodes: array<KdNode>` (render::kdtree::PhotonKdTree::nodes, heap order),
// `unpack_normal` and `is_caustic`, and the prelude's KD_STACK_SIZE and KD_AXIS_SHIFT.

// render::kdtree::KdNode (32 bytes): a photon in tree order.
struct KdNode {
    position: vec3<f32>,
    normal: u32,
    flux: vec3<f32>,
    // Bits 0-29: the photon's index in the pass's photons; bits 30-31: the split axis (0 x,
    // 1 y, 2 z).
    photon_axis: u32,
}

// The indirect photons found and their flux, and the caustic ones.
struct KdGather {
    found: u32,
    flux: vec3<f32>,
    caustic_found: u32,
    caustic_flux: vec3<f32>,
}

// The photons within `radius` of `position` (squared distance < radius²) whose normal faces
// `normal`: how many and their summed flux. Depth first, the node itself, then the side of its
// split plane holding `position`, then the other side when the plane is nearer than `radius`.
// A complete tree of node_count < 2^27 nodes is at most KD_STACK_SIZE + 1 levels deep, and the
// stack holds at most one entry per level below the root (render::kdtree::STACK_SIZE).
// Caustic and indirect photons count within their own radius (radii: x caustic, y
// indirect; render::kdtree::PhotonKdTree::query_classes).
fn kd_gather(position: vec3<f32>, radii: vec2<f32>, normal: vec3<f32>, node_count: u32) -> KdGather {
    let radius = max(radii.x, radii.y);
    let radius_sq = radius * radius;
    var result = KdGather(0u, vec3<f32>(0.0), 0u, vec3<f32>(0.0));
    var stack: array<u32, KD_STACK_SIZE>;
    var top = 0u;
    var node = 0u;
    loop {
        while node < node_count {
            let kd = kd_nodes[node];
            let offset = kd.position - position;
            let caustic = is_caustic(kd.normal);
            let own = select(radii.y, radii.x, caustic);
            if dot(offset, offset) < own * own && dot(unpack_normal(kd.normal), normal) > 0.0 {
                if caustic {
                    result.caustic_found += 1u;
                    result.caustic_flux += kd.flux;
                } else {
                    result.found += 1u;
                    result.flux += kd.flux;
                }
            }
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
    return result;
}
