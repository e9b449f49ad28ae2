// Invocation index of a (possibly two-dimensional) dispatch: kernels launch one invocation per
// item and spread past the per-dimension workgroup limit over y (gpu::traversal::workgroups).
fn invocation_index(id: vec3<u32>, groups: vec3<u32>) -> u32 {
    return id.x + id.y * groups.x * WORKGROUP_SIZE;
}
