// The naive photon-tracing scheme that asynchronous path regeneration replaces (the talk's
// "one pixel = one photon path"): every invocation starts a new light path and loops bounce
// after bounce until it ends, so its SIMD group waits for the group's longest path. Twin of
// cpu::kernels::photon_trace_naive; measured by `kousen bench photons` (render::PhotonTracing).
// The bounce is sppm/photon_pass.wgsl's photon_step, the one photon_pass runs.

// Per slot, the segments its path took (bounces and alpha pass-throughs).
@group(3) @binding(0) var<storage, read_write> path_segments: array<u32>;

// cpu::kernels::naive_path: slot `index` in pass `pass_index` traces path
// pass_index × slots + index (wrapping), so every pass traces new paths.
fn naive_path(pass_index: u32, index: u32) -> u32 {
    return pass_index * params.slot_count + index;
}

// cpu::kernels::naive_segment_limit: max_depth + MAX_PASS_THROUGHS + 1, saturating (a path
// always ends by then; the loop's bound is a guard).
fn naive_segment_limit() -> u32 {
    let extra = MAX_PASS_THROUGHS + 1u;
    return min(params.max_depth, 0xffffffffu - extra) + extra;
}

@compute @workgroup_size(WORKGROUP_SIZE)
fn photon_trace_naive(@builtin(global_invocation_id) id: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let index = invocation_index(id, groups);
    if index >= params.slot_count {
        return;
    }
    let path = naive_path(atomicLoad(&counters[COUNTER_PASS]), index);
    let limit = naive_segment_limit();
    var slot = PathSlot(vec3<f32>(0.0), SLOT_IDLE, vec3<f32>(0.0), 0u, vec3<f32>(0.0), 0u, vec3<f32>(1.0), NO_WALK);
    var photon = Photon(vec3<f32>(0.0), 0u, vec3<f32>(0.0), 0u);
    var segments = 0u;
    loop {
        // Segment k draws the numbers photon_pass draws for slot `path` in pass k.
        let step = photon_step(slot, segments, path);
        segments += 1u;
        if any(step.photon.flux != vec3<f32>(0.0)) {
            photon = step.photon;
        }
        slot = step.slot;
        if slot.depth == SLOT_IDLE || segments >= limit {
            break;
        }
    }
    atomicAdd(&counters[COUNTER_EMITTED_PASS], 1u);
    path_segments[index] = segments;
    store_photon(index, photon);
}
