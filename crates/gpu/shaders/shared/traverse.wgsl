// Twins of bvh::traverse over the scene of scene_bindings.wgsl: a fixed-array stack traversal
// and the stackless threaded one (TBVH and MTBVH differ only in the link set and root).
// `stop_at_first` turns a closest-hit query into an any-hit (shadow) query.

// Tests a leaf's triangles, updating `best`; true if one was hit.
fn test_leaf(leaf: BvhNode, ray: GpuRay, best: ptr<function, GpuHit>, stop_at_first: bool) -> bool {
    var found = false;
    let end = leaf.first_or_right + leaf.triangle_count;
    for (var triangle = leaf.first_or_right; triangle < end; triangle += 1u) {
        let h = intersect_triangle(triangle, ray.origin, ray.direction, (*best).t);
        if h.hit {
            *best = GpuHit(h.t, triangle, h.u, h.v);
            found = true;
            if stop_at_first {
                break;
            }
        }
    }
    return found;
}

fn no_hit(ray: GpuRay) -> GpuHit {
    return GpuHit(ray.t_max, NO_HIT, 0.0, 0.0);
}

// Index of the MTBVH threading for a direction: 2 * major axis + (component < 0).
fn direction_index(direction: vec3<f32>) -> u32 {
    let a = abs(direction);
    var axis = 2u;
    if a.x >= a.y && a.x >= a.z {
        axis = 0u;
    } else if a.y >= a.z {
        axis = 1u;
    }
    return 2u * axis + select(0u, 1u, direction[axis] < 0.0);
}

// Stack traversal: both children's boxes tested, the nearer visited first, the farther pushed.
fn trace_stack(ray: GpuRay, stop_at_first: bool) -> GpuHit {
    let slab = make_slab_ray(ray);
    var best = no_hit(ray);
    if intersect_box(load_node(0u), slab, ray.t_max) >= NO_DISTANCE {
        return best;
    }
    var stack: array<u32, MAX_DEPTH>;
    var stack_len = 0u;
    var node = 0u;
    loop {
        let current = load_node(node);
        var next = LINK_END;
        if current.triangle_count > 0u {
            if test_leaf(current, ray, &best, stop_at_first) && stop_at_first {
                break;
            }
        } else {
            let left = node + 1u;
            let right = current.first_or_right;
            let t_left = intersect_box(load_node(left), slab, best.t);
            let t_right = intersect_box(load_node(right), slab, best.t);
            let swap = t_right < t_left;
            let near = select(left, right, swap);
            let far = select(right, left, swap);
            if select(t_left, t_right, swap) < NO_DISTANCE {
                next = near;
            }
            if select(t_right, t_left, swap) < NO_DISTANCE {
                stack[stack_len] = far;
                stack_len += 1u;
            }
        }
        if next == LINK_END {
            if stack_len == 0u {
                break;
            }
            stack_len -= 1u;
            next = stack[stack_len];
        }
        node = next;
    }
    return best;
}

// Stackless traversal over one threading's records (bvh::threaded) at record_base: the next
// record when the ray enters a box, the miss position when it does not; a position past the
// last record (LINK_END included) ends. One record a step, where nodes and links were two.
// The walk over boxes and the leaf test are two loops, not one (Aila & Laine's while-while):
// where lanes of a SIMD group run in lockstep (lavapipe, GPUs), a leaf's triangle test then
// runs once per leaf entered rather than on every box step of the group (lavapipe runs an
// `if` body whether or not a lane takes it). The nodes visited and the answer are
// bvh::traverse's, the CPU twin's.
fn trace_threaded(ray: GpuRay, record_base: u32, stop_at_first: bool) -> GpuHit {
    let slab = make_slab_ray(ray);
    let count = scene_info.node_count;
    var best = no_hit(ray);
    var position = 0u;
    loop {
        var leaf = LINK_END;
        loop {
            if position >= count || leaf != LINK_END {
                break;
            }
            let record = load_threaded(record_base + position);
            let entered = intersect_box(BvhNode(record.min, 0u, record.max, 0u), slab, best.t) < NO_DISTANCE;
            leaf = select(LINK_END, record.leaf, entered);
            position = select(record.miss, position + 1u, entered);
        }
        if leaf == LINK_END {
            break;
        }
        if test_leaf(load_node(leaf), ray, &best, stop_at_first) && stop_at_first {
            break;
        }
    }
    return best;
}

fn trace_tbvh(ray: GpuRay, stop_at_first: bool) -> GpuHit {
    return trace_threaded(ray, scene_info.tbvh_record_base, stop_at_first);
}

// MTBVH: the threading of the ray's major direction, so boxes come roughly front to back.
fn trace_mtbvh(ray: GpuRay, stop_at_first: bool) -> GpuHit {
    let d = direction_index(ray.direction);
    return trace_threaded(ray, d * scene_info.node_count, stop_at_first);
}
