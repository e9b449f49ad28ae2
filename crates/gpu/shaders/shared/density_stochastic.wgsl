// The stochastic spatial hash's query (cpu::kernels::stochastic_query): each distinct table
// entry the gather sphere's box touches gives its kept photon, weighted by the entry's count,
// in class 0's table and each other photon class's table its count word marks
// (render::hash::photon_class, class_mark).

fn density_query(query: GatherQuery, cell_size: f32) -> GatherSum {
    var sum = no_photons();
    let touched = query_entries(query.position, reach(query), cell_size, query_salt(query));
    let classes = hash_classes();
    for (var slot = 0u; slot < 8u; slot += 1u) {
        let entry = query_entry(touched, slot);
        if entry == NO_CELL {
            continue;
        }
        let word = entry * HASH_ENTRY_WORDS;
        // Class 0's count, and where glass disperses the other classes' marks above it.
        let count_word = atomicLoad(&hash[word + HASH_COUNT]);
        var in_entry = count_word;
        if DISPERSION {
            in_entry = class_entry_count(count_word, classes);
        }
        if in_entry != 0u {
            let photon = load_photon(atomicLoad(&hash[word + HASH_WINNER]));
            add_if_near(&sum, query, photon, in_entry);
        }
        if DISPERSION {
            for (var table = 1u; table < classes; table += 1u) {
                if (count_word & class_mark(table)) == 0u {
                    continue;
                }
                let class_word = (table * params.hash_size + entry) * HASH_ENTRY_WORDS;
                let in_class = class_entry_count(atomicLoad(&hash[class_word + HASH_COUNT]), classes);
                if in_class != 0u {
                    let photon = load_photon(atomicLoad(&hash[class_word + HASH_WINNER]));
                    add_if_near(&sum, query, photon, in_class);
                }
            }
        }
    }
    return sum;
}
