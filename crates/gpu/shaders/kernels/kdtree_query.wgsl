// kdtree_query: one kd_gather per query, for tests and benchmarks of the photon kd-tree
// (gpu::kdtree::KdTreeQuery; twin of render::kdtree::PhotonKdTree::query). It follows the
// SPPM module (for `add_if_near` and what it needs), binds nothing of it, and takes bindings
// of group 1 past the SPPM kernels'.

// gpu::kdtree::KdQuery
struct KdQuery {
    position: vec3<f32>,
    radius: f32,
    normal: vec3<f32>,
    pad: u32,
}

// gpu::kdtree::KdResult
struct KdResult {
    flux: vec3<f32>,
    found: u32,
}

// gpu::kdtree::KdQueryParams
struct KdQueryParams {
    query_count: u32,
    node_count: u32,
    pad0: u32,
    pad1: u32,
}

@group(1) @binding(16) var<storage, read> kd_nodes: array<KdNode>;
@group(1) @binding(17) var<storage, read> kd_queries: array<KdQuery>;
@group(1) @binding(18) var<storage, read_write> kd_results: array<KdResult>;
@group(1) @binding(19) var<uniform> kd_params: KdQueryParams;

@compute @workgroup_size(WORKGROUP_SIZE)
fn kdtree_query(@builtin(global_invocation_id) id: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let index = invocation_index(id, groups);
    if index >= kd_params.query_count {
        return;
    }
    let query = kd_queries[index];
    // render::kdtree::PhotonKdTree::query: both surface classes within the one radius.
    let around = GatherQuery(query.position, query.normal, query.radius, query.radius, false, vec3<f32>(0.0), 0.0, 0.0);
    let gathered = kd_gather(around, kd_params.node_count);
    kd_results[index] = KdResult(gathered.caustic_flux + gathered.flux, gathered.caustic_found + gathered.found);
}
