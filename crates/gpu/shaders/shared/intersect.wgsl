// Twins of bvh::intersect: the talk's Moller-Trumbore test and the slab test, with the same
// arithmetic in the same order. No inf or NaN is ever made on purpose: WGSL lets the compiler
// assume there are none, so divisions by zero and 0 * inf are avoided explicitly.

// A ray prepared for slab tests (bvh::SlabRay): parallel axes have inverse 0 and only ask that
// the origin lie between the planes.
struct SlabRay {
    origin: vec3<f32>,
    inv_direction: vec3<f32>,
    parallel: vec3<bool>,
    any_parallel: bool,
}

fn make_slab_ray(ray: GpuRay) -> SlabRay {
    let parallel = abs(ray.direction) < vec3<f32>(PARALLEL_LIMIT);
    let safe_direction = select(ray.direction, vec3<f32>(1.0), parallel);
    let inv_direction = select(vec3<f32>(1.0) / safe_direction, vec3<f32>(0.0), parallel);
    return SlabRay(ray.origin, inv_direction, parallel, any(parallel));
}

// Entry distance into the node's box, or NO_DISTANCE if the ray misses it or enters beyond
// t_far. The exit is widened by ROBUST_EXIT (1 + 2 gamma_3) against rounding.
fn intersect_box(node: BvhNode, ray: SlabRay, t_far: f32) -> f32 {
    let t_lo = (node.min - ray.origin) * ray.inv_direction;
    let t_hi = (node.max - ray.origin) * ray.inv_direction;
    let t_near = min(t_lo, t_hi);
    let t_far_axes = select(max(t_lo, t_hi), vec3<f32>(NO_DISTANCE), ray.parallel);
    let t_enter = max(max(max(t_near.x, t_near.y), t_near.z), 0.0);
    let t_exit = min(min(min(t_far_axes.x, t_far_axes.y), t_far_axes.z), t_far) * ROBUST_EXIT;
    var outside_parallel_slab = false;
    if ray.any_parallel {
        let outside = (ray.origin < node.min) | (ray.origin > node.max);
        outside_parallel_slab = any(ray.parallel & outside);
    }
    return select(NO_DISTANCE, t_enter, t_enter <= t_exit && !outside_parallel_slab);
}

// (u, v, t) of a hit at 0 <= t < t_best; `hit` false otherwise. u, v, w = 1 - u - v and t
// exactly 0 count (shared edges hit both triangles); det == 0 never does.
struct TriangleHit {
    u: f32,
    v: f32,
    t: f32,
    hit: bool,
}

fn intersect_triangle(triangle: u32, origin: vec3<f32>, direction: vec3<f32>, t_best: f32) -> TriangleHit {
    let p0 = load_position(triangle, 0u);
    let p1 = load_position(triangle, 1u);
    let p2 = load_position(triangle, 2u);
    return intersect_edges(p0, p1 - p0, p2 - p0, origin, direction, t_best);
}

// The same test on a triangle given as p0 and its two edges (the four-wide MTBVH's leaves
// store them so).
fn intersect_edges(p0: vec3<f32>, e0: vec3<f32>, e1: vec3<f32>, origin: vec3<f32>, direction: vec3<f32>, t_best: f32) -> TriangleHit {
    let pv = cross(direction, e1);
    let det = dot(e0, pv);
    let tv = origin - p0;
    let qv = cross(tv, e0);
    let safe_det = select(1.0, det, det != 0.0);
    let u = dot(tv, pv) / safe_det;
    let v = dot(direction, qv) / safe_det;
    let t = dot(e1, qv) / safe_det;
    let w = 1.0 - u - v;
    let hit = det != 0.0 && u >= 0.0 && v >= 0.0 && w >= 0.0 && t >= 0.0 && t < t_best;
    return TriangleHit(u, v, t, hit);
}
