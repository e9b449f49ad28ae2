// The stochastic spatial hash's query (cpu::kernels::stochastic_query; the loops over entries
// and cells in density_grid.wgsl): each entry read gives its kept photon, weighted by the
// entry's count, in class 0's table and each other photon class's table its count word marks
// (render::hash::photon_class, class_mark).

// cpu::kernels::add_kept_photons: the photons table entry `entry` keeps, in class 0's table and
// each other class's its count word marks, each weighted by its class's count there; for a
// volume visible point only those lying in `cell`, the cell it reads.
fn add_entry_photons(sum: ptr<function, GatherSum>, query: GatherQuery, entry: u32, cell: vec3<i32>, cell_size: f32, kinds: u32) {
    let classes = hash_classes();
    let word = entry * HASH_ENTRY_WORDS;
    // Class 0's count, and where photons are classed the other classes' marks above it.
    let count_word = atomicLoad(&hash[word + HASH_COUNT]);
    let in_entry = class_entry_count(count_word, classes);
    if in_entry != 0u && kinds_take(kinds, 0u, classes) {
        let photon = load_photon(atomicLoad(&hash[word + HASH_WINNER]));
        if in_read_cell(query, photon, cell, cell_size) {
            add_if_near(sum, query, photon, in_entry);
        }
    }
    // The marked classes only, lowest first (as the twin's loop meets them): most entries have
    // none, and lavapipe runs a loop over every class lane by lane.
    var marks = select(0u, count_word >> CLASS_MARK_SHIFT, classes > 1u);
    while marks != 0u {
        let table = firstTrailingBit(marks) + 1u;
        marks &= marks - 1u;
        if !kinds_take(kinds, table, classes) {
            continue;
        }
        let class_word = (table * params.hash_size + entry) * HASH_ENTRY_WORDS;
        let in_class = class_entry_count(atomicLoad(&hash[class_word + HASH_COUNT]), classes);
        if in_class != 0u {
            let photon = load_photon(atomicLoad(&hash[class_word + HASH_WINNER]));
            if in_read_cell(query, photon, cell, cell_size) {
                add_if_near(sum, query, photon, in_class);
            }
        }
    }
}
