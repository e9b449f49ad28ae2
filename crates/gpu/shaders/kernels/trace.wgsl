// Traversal kernels: one invocation per ray, rays[i] -> hits[i].

struct TraceBatch {
    ray_count: u32,
}

@group(1) @binding(0) var<storage, read> rays: array<GpuRay>;
@group(1) @binding(1) var<storage, read_write> hits: array<GpuHit>;
@group(1) @binding(2) var<uniform> batch: TraceBatch;

@compute @workgroup_size(WORKGROUP_SIZE)
fn closest_stack(@builtin(global_invocation_id) id: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let i = invocation_index(id, groups);
    if i < batch.ray_count {
        hits[i] = trace_stack(rays[i], false);
    }
}

@compute @workgroup_size(WORKGROUP_SIZE)
fn closest_tbvh(@builtin(global_invocation_id) id: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let i = invocation_index(id, groups);
    if i < batch.ray_count {
        hits[i] = trace_tbvh(rays[i], false);
    }
}

@compute @workgroup_size(WORKGROUP_SIZE)
fn closest_mtbvh(@builtin(global_invocation_id) id: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let i = invocation_index(id, groups);
    if i < batch.ray_count {
        hits[i] = trace_mtbvh(rays[i], false);
    }
}

@compute @workgroup_size(WORKGROUP_SIZE)
fn any_stack(@builtin(global_invocation_id) id: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let i = invocation_index(id, groups);
    if i < batch.ray_count {
        hits[i] = trace_stack(rays[i], true);
    }
}

@compute @workgroup_size(WORKGROUP_SIZE)
fn any_tbvh(@builtin(global_invocation_id) id: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let i = invocation_index(id, groups);
    if i < batch.ray_count {
        hits[i] = trace_tbvh(rays[i], true);
    }
}

@compute @workgroup_size(WORKGROUP_SIZE)
fn any_mtbvh(@builtin(global_invocation_id) id: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let i = invocation_index(id, groups);
    if i < batch.ray_count {
        hits[i] = trace_mtbvh(rays[i], true);
    }
}

// The compact MTBVH: bind group 2 (traverse_compact.wgsl).
@compute @workgroup_size(WORKGROUP_SIZE)
fn closest_mtbvh16(@builtin(global_invocation_id) id: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let i = invocation_index(id, groups);
    if i < batch.ray_count {
        hits[i] = trace_mtbvh16(rays[i], false);
    }
}

@compute @workgroup_size(WORKGROUP_SIZE)
fn any_mtbvh16(@builtin(global_invocation_id) id: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let i = invocation_index(id, groups);
    if i < batch.ray_count {
        hits[i] = trace_mtbvh16(rays[i], true);
    }
}

// The four-wide MTBVH: binding 2 of group 2 (traverse_wide.wgsl).
@compute @workgroup_size(WORKGROUP_SIZE)
fn closest_mtbvh4(@builtin(global_invocation_id) id: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let i = invocation_index(id, groups);
    if i < batch.ray_count {
        hits[i] = trace_mtbvh4(rays[i], false);
    }
}

@compute @workgroup_size(WORKGROUP_SIZE)
fn any_mtbvh4(@builtin(global_invocation_id) id: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let i = invocation_index(id, groups);
    if i < batch.ray_count {
        hits[i] = trace_mtbvh4(rays[i], true);
    }
}
