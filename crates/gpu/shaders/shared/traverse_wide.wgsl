// The four-wide MTBVH ("mtbvh4"), twin of bvh::wide: four children's boxes per node, the order
// to visit them in per ray direction, and a stackless traversal that keeps a trail of four
// bits per level (which entered children are still to visit) and climbs by parent links.
// Binding 2 of group 2, which only its trace kernels bind (the compact MTBVH's kernels bind
// 0 and 1 of it), one buffer of 16-byte words (WideMtbvh::gpu_words): a
// header (first leaf word, node count), the nodes (eight words), the leaves (ten words: nine
// rows of four triangles' p0, p1 - p0, p2 - p0, then first triangle and count).

@group(2) @binding(2) var<storage, read> wide_words: array<vec4<u32>>;

const WIDE_NONE: u32 = 0xffffffffu;
// The trail: four bits a level, eight levels a word, in two vec4 of words (bvh::MAX_DEPTH = 64
// levels), read and written with selects rather than a runtime index (which lavapipe would
// turn into memory).
struct Trail {
    low: vec4<u32>,
    high: vec4<u32>,
}

fn trail_set(trail: ptr<function, Trail>, level: u32, positions: u32) {
    let word = vec4<u32>(level / 8u);
    let bits = vec4<u32>(positions << (4u * (level % 8u)));
    (*trail).low |= select(vec4<u32>(0u), bits, vec4<u32>(0u, 1u, 2u, 3u) == word);
    (*trail).high |= select(vec4<u32>(0u), bits, vec4<u32>(4u, 5u, 6u, 7u) == word);
}

// Level `level`'s positions, cleared from the trail.
fn trail_take(trail: ptr<function, Trail>, level: u32) -> u32 {
    let word = vec4<u32>(level / 8u);
    let shift = 4u * (level % 8u);
    let in_low = vec4<u32>(0u, 1u, 2u, 3u) == word;
    let in_high = vec4<u32>(4u, 5u, 6u, 7u) == word;
    let zero = vec4<u32>(0u);
    let value = dot(select(zero, (*trail).low, in_low), vec4<u32>(1u))
        + dot(select(zero, (*trail).high, in_high), vec4<u32>(1u));
    let clear = vec4<u32>(~(0xfu << shift));
    (*trail).low &= select(vec4<u32>(0xffffffffu), clear, in_low);
    (*trail).high &= select(vec4<u32>(0xffffffffu), clear, in_high);
    return (value >> shift) & 0xfu;
}

// A node's child word and its last word (counts, orders, valid mask, parent).
struct WideNode {
    child: vec4<u32>,
    tail: vec4<u32>,
}

// Word `word` as four floats (a row of boxes or of triangle coordinates).
fn wide_row(word: u32) -> vec4<f32> {
    return bitcast<vec4<f32>>(wide_words[word]);
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

// Bit s set when the ray enters slot s's box before t_far: intersect_box's arithmetic on the
// four boxes at once, as vec4 rows (WideRay::entered), then as positions in `order` (the
// POSITIONS table of bvh::wide). No component is picked by a runtime index: lavapipe turns
// those into memory.
fn wide_positions(node: u32, n: WideNode, order: u32, slab: SlabRay, t_far: f32) -> u32 {
    let base = 1u + 8u * node;
    let lo_x = wide_row(base);
    let lo_y = wide_row(base + 1u);
    let lo_z = wide_row(base + 2u);
    let hi_x = wide_row(base + 3u);
    let hi_y = wide_row(base + 4u);
    let hi_z = wide_row(base + 5u);
    let o = slab.origin;
    let inv = slab.inv_direction;
    let x0 = (lo_x - vec4<f32>(o.x)) * inv.x;
    let x1 = (hi_x - vec4<f32>(o.x)) * inv.x;
    let y0 = (lo_y - vec4<f32>(o.y)) * inv.y;
    let y1 = (hi_y - vec4<f32>(o.y)) * inv.y;
    let z0 = (lo_z - vec4<f32>(o.z)) * inv.z;
    let z1 = (hi_z - vec4<f32>(o.z)) * inv.z;
    let none = vec4<f32>(NO_DISTANCE);
    let far_x = select(max(x0, x1), none, slab.parallel.x);
    let far_y = select(max(y0, y1), none, slab.parallel.y);
    let far_z = select(max(z0, z1), none, slab.parallel.z);
    let t_enter = max(max(max(min(x0, x1), min(y0, y1)), min(z0, z1)), vec4<f32>(0.0));
    let t_exit = min(min(min(far_x, far_y), far_z), vec4<f32>(t_far)) * ROBUST_EXIT;
    var inside = t_enter <= t_exit;
    if slab.any_parallel {
        let outside_x = (vec4<f32>(o.x) < lo_x) | (vec4<f32>(o.x) > hi_x);
        let outside_y = (vec4<f32>(o.y) < lo_y) | (vec4<f32>(o.y) > hi_y);
        let outside_z = (vec4<f32>(o.z) < lo_z) | (vec4<f32>(o.z) > hi_z);
        let outside = (outside_x & vec4<bool>(slab.parallel.x))
            | (outside_y & vec4<bool>(slab.parallel.y))
            | (outside_z & vec4<bool>(slab.parallel.z));
        inside = inside & !outside;
    }
    let valid = (n.tail.z >> 16u) & 0xfu;
    let entered = dot(select(vec4<u32>(0u), vec4<u32>(1u, 2u, 4u, 8u), inside), vec4<u32>(1u)) & valid;
    var positions = 0u;
    for (var k = 0u; k < 4u; k += 1u) {
        positions |= ((entered >> wide_slot(order, k)) & 1u) << k;
    }
    return positions;
}

// Component `lane` of `v`, by selects rather than a runtime index.
fn wide_lane(v: vec4<f32>, lane: u32) -> f32 {
    return select(select(select(v.x, v.y, lane == 1u), v.z, lane == 2u), v.w, lane == 3u);
}

fn wide_child(v: vec4<u32>, slot: u32) -> u32 {
    return select(select(select(v.x, v.y, slot == 1u), v.z, slot == 2u), v.w, slot == 3u);
}

// WideRay::test_leaf: the leaf's records of four triangles, the nearer hit winning (the first
// of equals); true if one was hit.
fn wide_test_leaf(leaf: u32, count: u32, ray: GpuRay, best: ptr<function, GpuHit>, stop_at_first: bool) -> bool {
    let leaf_base = wide_words[0].x;
    var found = false;
    for (var r = 0u; r < (count + 3u) / 4u; r += 1u) {
        let base = leaf_base + 10u * (leaf + r);
        let r0 = wide_row(base);
        let r1 = wide_row(base + 1u);
        let r2 = wide_row(base + 2u);
        let r3 = wide_row(base + 3u);
        let r4 = wide_row(base + 4u);
        let r5 = wide_row(base + 5u);
        let r6 = wide_row(base + 6u);
        let r7 = wide_row(base + 7u);
        let r8 = wide_row(base + 8u);
        let info = wide_words[base + 9u];
        for (var lane = 0u; lane < info.y; lane += 1u) {
            let p0 = vec3<f32>(wide_lane(r0, lane), wide_lane(r1, lane), wide_lane(r2, lane));
            let e0 = vec3<f32>(wide_lane(r3, lane), wide_lane(r4, lane), wide_lane(r5, lane));
            let e1 = vec3<f32>(wide_lane(r6, lane), wide_lane(r7, lane), wide_lane(r8, lane));
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
    var trail = Trail(vec4<u32>(0u), vec4<u32>(0u));
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
                next = wide_child(current.child, slot);
                break;
            }
            if wide_test_leaf(wide_child(current.child, slot), count, ray, &best, stop_at_first) {
                if stop_at_first {
                    return best;
                }
                // Cull the siblings still to come against the nearer hit.
                positions &= wide_positions(node, current, order, slab, best.t);
                fresh_from = level;
            }
        }
        if next != WIDE_NONE {
            trail_set(&trail, level, positions);
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
            positions = trail_take(&trail, level);
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
