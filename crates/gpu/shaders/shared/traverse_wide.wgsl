// The four-wide MTBVH ("mtbvh4"), twin of bvh::wide: four children's boxes per node, the order
// to visit them in per ray direction, and a stackless traversal that keeps a trail of four
// bits per level (which entered children are still to visit) and climbs by parent links.
// Binding 2 of group 2, which only its trace kernels bind (the compact MTBVH's kernels bind
// 0 and 1 of it), one buffer of 16-byte words (WideMtbvh::gpu_words): a
// header (first leaf word, node count), the nodes (eight words), the leaves (ten words: nine
// rows of four triangles' p0, p1 - p0, p2 - p0, then first triangle and count).

@group(2) @binding(2) var<storage, read> wide_words: array<vec4<u32>>;

const WIDE_NONE: u32 = 0xffffffffu;
// Levels the trail holds: bvh::MAX_DEPTH, eight levels a word.
const WIDE_TRAIL_WORDS: u32 = 8u;

// A node's child word and its last word (counts, orders, valid mask, parent).
struct WideNode {
    child: vec4<u32>,
    tail: vec4<u32>,
}

fn wide_node(node: u32) -> WideNode {
    let base = 1u + 8u * node;
    return WideNode(wide_words[base + 6u], wide_words[base + 7u]);
}

// WideNode::count[slot]: the leaf's triangle count, 0 for an inner child.
fn wide_count(n: WideNode, slot: u32) -> u32 {
    return (n.tail.x >> (8u * slot)) & 0xffu;
}

// WideNode::order[d]: the slot visited k-th in bits 2k..2k+2.
fn wide_order(n: WideNode, d: u32) -> u32 {
    let word = select(n.tail.z, n.tail.y, d < 4u);
    return (word >> (8u * (d % 4u))) & 0xffu;
}

fn wide_slot(order: u32, position: u32) -> u32 {
    return (order >> (2u * position)) & 3u;
}

// Bit s set when the ray enters slot s's box before t_far: intersect_box on each valid slot
// (WideRay::entered), as positions in `order` (the POSITIONS table of bvh::wide).
fn wide_positions(node: u32, n: WideNode, order: u32, slab: SlabRay, t_far: f32) -> u32 {
    let base = 1u + 8u * node;
    let lo_x = bitcast<vec4<f32>>(wide_words[base]);
    let lo_y = bitcast<vec4<f32>>(wide_words[base + 1u]);
    let lo_z = bitcast<vec4<f32>>(wide_words[base + 2u]);
    let hi_x = bitcast<vec4<f32>>(wide_words[base + 3u]);
    let hi_y = bitcast<vec4<f32>>(wide_words[base + 4u]);
    let hi_z = bitcast<vec4<f32>>(wide_words[base + 5u]);
    let valid = (n.tail.z >> 16u) & 0xfu;
    var positions = 0u;
    for (var k = 0u; k < 4u; k += 1u) {
        let s = wide_slot(order, k);
        if ((valid >> s) & 1u) != 0u {
            let b = BvhNode(vec3<f32>(lo_x[s], lo_y[s], lo_z[s]), 0u, vec3<f32>(hi_x[s], hi_y[s], hi_z[s]), 0u);
            if intersect_box(b, slab, t_far) < NO_DISTANCE {
                positions |= 1u << k;
            }
        }
    }
    return positions;
}

// WideRay::test_leaf: the leaf's records of four triangles, the nearer hit winning (the first
// of equals); true if one was hit.
fn wide_test_leaf(leaf: u32, count: u32, ray: GpuRay, best: ptr<function, GpuHit>, stop_at_first: bool) -> bool {
    let leaf_base = wide_words[0].x;
    var found = false;
    for (var r = 0u; r < (count + 3u) / 4u; r += 1u) {
        let base = leaf_base + 10u * (leaf + r);
        var rows: array<vec4<f32>, 9>;
        for (var i = 0u; i < 9u; i += 1u) {
            rows[i] = bitcast<vec4<f32>>(wide_words[base + i]);
        }
        let info = wide_words[base + 9u];
        for (var lane = 0u; lane < info.y; lane += 1u) {
            let p0 = vec3<f32>(rows[0][lane], rows[1][lane], rows[2][lane]);
            let e0 = vec3<f32>(rows[3][lane], rows[4][lane], rows[5][lane]);
            let e1 = vec3<f32>(rows[6][lane], rows[7][lane], rows[8][lane]);
            let h = intersect_edges(p0, e0, e1, ray.origin, ray.direction, (*best).t);
            if h.hit {
                *best = GpuHit(h.t, info.x + lane, h.u, h.v);
                found = true;
                if stop_at_first {
                    return true;
                }
            }
        }
    }
    return found;
}

// bvh::wide::trace_wide.
fn trace_mtbvh4(ray: GpuRay, stop_at_first: bool) -> GpuHit {
    var best = no_hit(ray);
    if wide_words[0].y == 0u {
        return best;
    }
    let slab = make_slab_ray(ray);
    let d = direction_index(ray.direction);
    var trail: array<u32, WIDE_TRAIL_WORDS>;
    var level = 0u;
    // Levels below this one made their positions before the last hit.
    var fresh_from = 0u;
    var node = 0u;
    var current = wide_node(0u);
    var positions = wide_positions(0u, current, wide_order(current, d), slab, ray.t_max);
    loop {
        let order = wide_order(current, d);
        var next = WIDE_NONE;
        while positions != 0u {
            let slot = wide_slot(order, countTrailingZeros(positions));
            positions &= positions - 1u;
            let count = wide_count(current, slot);
            if count == 0u {
                next = current.child[slot];
                break;
            }
            if wide_test_leaf(current.child[slot], count, ray, &best, stop_at_first) {
                if stop_at_first {
                    return best;
                }
                // Cull the siblings still to come against the nearer hit.
                positions &= wide_positions(node, current, order, slab, best.t);
                fresh_from = level;
            }
        }
        if next != WIDE_NONE {
            trail[level / 8u] |= positions << (4u * (level % 8u));
            level += 1u;
            node = next;
            current = wide_node(node);
            positions = wide_positions(node, current, wide_order(current, d), slab, best.t);
            continue;
        }
        // Up to the nearest level with children left to visit.
        var finished = false;
        loop {
            if level == 0u {
                finished = true;
                break;
            }
            level -= 1u;
            node = current.tail.w;
            current = wide_node(node);
            let shift = 4u * (level % 8u);
            positions = (trail[level / 8u] >> shift) & 0xfu;
            trail[level / 8u] &= ~(0xfu << shift);
            if positions != 0u && level < fresh_from {
                // A hit since these were made: re-cull them.
                positions &= wide_positions(node, current, wide_order(current, d), slab, best.t);
                fresh_from = level;
            }
            if positions != 0u {
                break;
            }
        }
        if finished {
            break;
        }
    }
    return best;
}
