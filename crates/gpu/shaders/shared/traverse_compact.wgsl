// The compact MTBVH ("mtbvh16"), twin of bvh::compact: one 32-byte record per node, boxes in 16
// bits per coordinate rounded outward, hit links implied, miss links as 16-bit offsets (far
// records for the few that do not fit). Bind group 2 of the trace kernels only; the triangles
// are the scene's (group 0).

@group(2) @binding(0) var<storage, read> compact_nodes: array<CompactNode>;
@group(2) @binding(1) var<uniform> compact_frame: CompactFrame;

// The record as the slab test and test_leaf read it: the box decoded exactly as
// CompactMtbvh::decode_node does (q * scale is exact, scale having at most 8 significant bits,
// so a fused multiply-add gives the same value), a leaf's triangles, triangle_count 0 for an internal node.
fn decode_compact_node(record: CompactNode) -> BvhNode {
    let b = record.bounds_and_meta;
    let q_min = vec3<f32>(vec3<u32>(b.x & 0xffffu, b.x >> 16u, b.y & 0xffffu));
    let q_max = vec3<f32>(vec3<u32>(b.y >> 16u, b.z & 0xffffu, b.z >> 16u));
    let lo = compact_frame.origin + q_min * compact_frame.scale;
    let hi = compact_frame.origin + q_max * compact_frame.scale;
    let count = select(0u, b.w & COMPACT_COUNT_MASK, (b.w & COMPACT_LEAF) != 0u);
    return BvhNode(lo, record.links.x, hi, count);
}

// Node `node`'s miss link in direction d (CompactMtbvh::miss_link).
fn compact_miss(node: u32, record: CompactNode, d: u32) -> u32 {
    if (record.bounds_and_meta.w & COMPACT_FAR) != 0u {
        let far = compact_nodes[record.links.y];
        if d < 4u {
            return far.bounds_and_meta[d];
        }
        return far.links[d - 4u];
    }
    let bits = (record.links[1u + d / 2u] >> (16u * (d % 2u))) & 0xffffu;
    let offset = bitcast<i32>(bits << 16u) >> 16u;
    return select(LINK_END, bitcast<u32>(bitcast<i32>(node) + offset), bits != 0u);
}

// Stackless traversal along the threading of the ray's major direction (trace_mtbvh_compact).
fn trace_mtbvh16(ray: GpuRay, stop_at_first: bool) -> GpuHit {
    let slab = make_slab_ray(ray);
    var best = no_hit(ray);
    let d = direction_index(ray.direction);
    var node = compact_frame.root;
    loop {
        if node == LINK_END {
            break;
        }
        let record = compact_nodes[node];
        let current = decode_compact_node(record);
        var next = LINK_END;
        var descend = false;
        if intersect_box(current, slab, best.t) < NO_DISTANCE {
            if current.triangle_count > 0u {
                if test_leaf(current, ray, &best, stop_at_first) && stop_at_first {
                    break;
                }
            } else {
                // The first child in direction d: the right one where bit d is set.
                let right_first = ((record.bounds_and_meta.w >> d) & 1u) != 0u;
                next = select(node + 1u, record.links.x, right_first);
                descend = true;
            }
        }
        if !descend {
            next = compact_miss(node, record, d);
        }
        node = next;
    }
    return best;
}
