// The full spatial hash (cpu::density): every photon listed under the table entry it hashes
// to, the lists built by a counting sort — count per entry (full_count), an exclusive prefix
// sum over the counts (full_scan_blocks, then full_scan_totals over the blocks' totals), a
// scatter (full_scatter), and a sort of each list by photon index that then copies the
// list's photons into list order for the gather (full_sort_lists). Table
// words per entry: FULL_START (list start within its scan block), FULL_COUNT, FULL_FILL (the
// scatter's cursor). `kousen render --density full` and `kousen bench density` run it.

// The photon indices, entry by entry.
@group(3) @binding(0) var<storage, read_write> photon_order: array<u32>;
// Per scan block: its total, then (after full_scan_totals) the offset of its first list.
@group(3) @binding(1) var<storage, read_write> block_sums: array<u32>;
// The photons in list order: listed_photons[place] is photons[photon_order[place]].
@group(3) @binding(2) var<storage, read_write> listed_photons: array<StoredPhoton>;

// cpu::density::photon_entry: the stored photon's first table word, or NO_ENTRY.
const NO_ENTRY: u32 = 0xffffffffu;

fn photon_entry(index: u32) -> u32 {
    if index >= params.slot_count {
        return NO_ENTRY;
    }
    let photon = load_photon(index);
    if !any(photon.flux != vec3<f32>(0.0)) {
        return NO_ENTRY;
    }
    return photon_entry_of(photon) * HASH_ENTRY_WORDS;
}

@compute @workgroup_size(WORKGROUP_SIZE)
fn full_count(@builtin(global_invocation_id) id: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let word = photon_entry(invocation_index(id, groups));
    if word != NO_ENTRY {
        atomicAdd(&hash[word + FULL_COUNT], 1u);
    }
}

// The prefix sum runs SCAN_LANES invocations a block, each over SCAN_PER_LANE consecutive
// entries, so a block takes two workgroup barriers: on CPU-type adapters (lavapipe) a barrier
// switches between all of a workgroup's lane groups, and a tree scan over SCAN_BLOCK lanes
// took two per step (the scan was a third of the hash build there).
const SCAN_LANES: u32 = 64u;
const SCAN_PER_LANE: u32 = SCAN_BLOCK / SCAN_LANES;

var<workgroup> lane_totals: array<u32, SCAN_LANES>;
var<workgroup> block_total: u32;

// Each lane's exclusive prefix of `value` across the workgroup, and the workgroup's total:
// one lane adds the lanes' values in order.
fn workgroup_exclusive_scan(lane: u32, value: u32) -> vec2<u32> {
    lane_totals[lane] = value;
    workgroupBarrier();
    if lane == 0u {
        var running = 0u;
        for (var l = 0u; l < SCAN_LANES; l += 1u) {
            let total = lane_totals[l];
            lane_totals[l] = running;
            running += total;
        }
        block_total = running;
    }
    workgroupBarrier();
    return vec2<u32>(lane_totals[lane], block_total);
}

fn entry_count(entry: u32) -> u32 {
    if entry >= params.hash_size {
        return 0u;
    }
    return atomicLoad(&hash[entry * HASH_ENTRY_WORDS + FULL_COUNT]);
}

// render::density::scan_counts, first half: each block's counts scanned into the entries'
// FULL_START (block-local), the block's total into block_sums.
@compute @workgroup_size(SCAN_LANES)
fn full_scan_blocks(@builtin(workgroup_id) group: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>, @builtin(local_invocation_index) lane: u32) {
    let block = group.x + group.y * groups.x;
    let first = block * SCAN_BLOCK + lane * SCAN_PER_LANE;
    var total = 0u;
    for (var k = 0u; k < SCAN_PER_LANE; k += 1u) {
        total += entry_count(first + k);
    }
    let scanned = workgroup_exclusive_scan(lane, total);
    var start = scanned.x;
    for (var k = 0u; k < SCAN_PER_LANE; k += 1u) {
        let entry = first + k;
        if entry < params.hash_size {
            atomicStore(&hash[entry * HASH_ENTRY_WORDS + FULL_START], start);
            start += entry_count(entry);
        }
    }
    if lane == 0u && block < arrayLength(&block_sums) {
        block_sums[block] = scanned.y;
    }
}

// render::density::scan_counts, second half (one workgroup): the blocks' totals scanned into
// their offsets, each lane taking a run of blocks.
@compute @workgroup_size(SCAN_LANES)
fn full_scan_totals(@builtin(local_invocation_index) lane: u32) {
    let blocks = (params.hash_size + SCAN_BLOCK - 1u) / SCAN_BLOCK;
    let run = (blocks + SCAN_LANES - 1u) / SCAN_LANES;
    let first = min(lane * run, blocks);
    let last = min(first + run, blocks);
    var total = 0u;
    for (var b = first; b < last; b += 1u) {
        total += block_sums[b];
    }
    var offset = workgroup_exclusive_scan(lane, total).x;
    for (var b = first; b < last; b += 1u) {
        let sum = block_sums[b];
        block_sums[b] = offset;
        offset += sum;
    }
}

// Where an entry's list begins in photon_order.
fn list_start(word: u32) -> u32 {
    let entry = word / HASH_ENTRY_WORDS;
    return block_sums[entry / SCAN_BLOCK] + atomicLoad(&hash[word + FULL_START]);
}

@compute @workgroup_size(WORKGROUP_SIZE)
fn full_scatter(@builtin(global_invocation_id) id: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let index = invocation_index(id, groups);
    let word = photon_entry(index);
    if word != NO_ENTRY {
        let place = atomicAdd(&hash[word + FULL_FILL], 1u);
        photon_order[list_start(word) + place] = index;
    }
}

// The scatter lists each entry's photons in arrival order, which differs run to run; sorted by
// photon index the lists are the same every run, so the gather adds the same numbers in the
// same order and the image is reproducible; they then also equal the CPU twin's lists (filled
// in photon order). Shell sort with Ciura's gaps, one invocation per entry: most lists hold
// a photon or two, a focused caustic's can hold thousands. The sorted list's photons are then
// copied into list order (cpu::density::list_photons), so that the gather reads each list
// from consecutive memory instead of through the order's indirection.
@compute @workgroup_size(WORKGROUP_SIZE)
fn full_sort_lists(@builtin(global_invocation_id) id: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let entry = invocation_index(id, groups);
    if entry >= params.hash_size {
        return;
    }
    let word = entry * HASH_ENTRY_WORDS;
    let count = atomicLoad(&hash[word + FULL_COUNT]);
    let start = list_start(word);
    var gaps = array<u32, 8>(701u, 301u, 132u, 57u, 23u, 10u, 4u, 1u);
    for (var g = 0u; g < 8u && count >= 2u; g += 1u) {
        let gap = gaps[g];
        for (var i = gap; i < count; i += 1u) {
            let value = photon_order[start + i];
            var j = i;
            loop {
                if j < gap || photon_order[start + j - gap] <= value {
                    break;
                }
                photon_order[start + j] = photon_order[start + j - gap];
                j -= gap;
            }
            photon_order[start + j] = value;
        }
    }
    for (var place = start; place < start + count; place += 1u) {
        listed_photons[place] = photons[photon_order[place]];
    }
}

// cpu::density::full_query_listed (the loops over entries and cells in density_grid.wgsl):
// the photons entry `entry` lists (for a volume visible point those lying in `cell`).
fn add_entry_photons(sum: ptr<function, GatherSum>, query: GatherQuery, entry: u32, cell: vec3<i32>, cell_size: f32, kinds: u32) {
    let word = entry * HASH_ENTRY_WORDS;
    let start = list_start(word);
    let listed = atomicLoad(&hash[word + FULL_COUNT]);
    for (var place = start; place < start + listed; place += 1u) {
        let photon = unpack_photon(listed_photons[place]);
        if in_read_cell(query, photon, cell, cell_size) {
            add_if_near(sum, query, photon, 1u);
        }
    }
}
