// Benchmark ray generation, the twin of bvh::bench_rays (ANCHORS.md "Rays").

// bvh::BenchCamera plus what the diffuse rays need (64 bytes).
struct BenchCameraUniform {
    eye: vec3<f32>,
    tan_half_fov: f32,
    forward: vec3<f32>,
    side: u32,
    right: vec3<f32>,
    diagonal: f32,
    up: vec3<f32>,
    ray_count: u32,
}

@group(1) @binding(0) var<storage, read_write> rays: array<GpuRay>;
@group(1) @binding(1) var<storage, read> primary_hits: array<GpuHit>;
@group(1) @binding(2) var<uniform> camera: BenchCameraUniform;

// One ray through the centre of each pixel, row 0 at the top.
@compute @workgroup_size(WORKGROUP_SIZE)
fn primary_rays(@builtin(global_invocation_id) id: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let i = invocation_index(id, groups);
    if i >= camera.ray_count {
        return;
    }
    let x = f32(i % camera.side);
    let y = f32(i / camera.side);
    let side = f32(camera.side);
    let u = ((x + 0.5) / side * 2.0 - 1.0) * camera.tan_half_fov;
    let v = (1.0 - (y + 0.5) / side * 2.0) * camera.tan_half_fov;
    let direction = normalize(camera.forward + u * camera.right + v * camera.up);
    rays[i] = GpuRay(camera.eye, RAY_T_MAX, direction, 0u);
}


// Replaces each primary ray that hit something (primary_hits from a closest-hit trace) by
// one cosine-distributed ray from its hit point; rays that missed become unused (t_max 0).
@compute @workgroup_size(WORKGROUP_SIZE)
fn diffuse_rays(@builtin(global_invocation_id) id: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let i = invocation_index(id, groups);
    if i >= camera.ray_count {
        return;
    }
    let primary = rays[i];
    let hit = primary_hits[i];
    if hit.triangle == NO_HIT {
        rays[i] = GpuRay(primary.origin, 0.0, primary.direction, 0u);
        return;
    }
    let p0 = load_position(hit.triangle, 0u);
    let p1 = load_position(hit.triangle, 1u);
    let p2 = load_position(hit.triangle, 2u);
    var n = normalize(cross(p1 - p0, p2 - p0));
    if dot(n, primary.direction) > 0.0 {
        n = -n;
    }
    let u1 = f32(pcg_hash(2u * i)) * U32_TO_UNIT;
    let u2 = f32(pcg_hash(2u * i + 1u)) * U32_TO_UNIT;
    let phi = 2.0 * PI * u2;
    let r = sqrt(u1);
    let local = vec3<f32>(r * cos(phi), r * sin(phi), sqrt(1.0 - u1));
    // Duff et al. 2017's basis; s = copysign(1, n.z), so n.z = -0 gives -1.
    let s = select(1.0, -1.0, (bitcast<u32>(n.z) >> 31u) == 1u);
    let a = -1.0 / (s + n.z);
    let b = n.x * n.y * a;
    let t1 = vec3<f32>(1.0 + s * n.x * n.x * a, s * b, -s * n.x);
    let t2 = vec3<f32>(b, s + n.y * n.y * a, -n.y);
    let point = primary.origin + hit.t * primary.direction;
    let origin = point + 1e-4 * camera.diagonal * n;
    let direction = local.x * t1 + local.y * t2 + local.z * n;
    rays[i] = GpuRay(origin, RAY_T_MAX, direction, 0u);
}
