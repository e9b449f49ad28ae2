// The query of the grid density methods (the stochastic hash, density_stochastic.wgsl, and the
// full hash, density_full.wgsl), each of which says what a table entry gives
// (`add_entry_photons`): a surface visible point reads each distinct entry its sphere's box
// touches in the surfaces' grid (render::hash::query_entries); a volume visible point reads
// the volume photons' finer grid cell by cell (render::hash::volume_query_cells), two cells
// perhaps sharing an entry, so each counts only the photons lying in it (in_read_cell).

fn density_query(query: GatherQuery, cell_size: f32) -> GatherSum {
    var sum = no_photons();
    if MURKY_GLASS && query.volume {
        let cells = volume_cell_box(query.position, query.volume_radius, cell_size);
        for (var z = cells.lo.z; z <= cells.hi.z; z += 1) {
            for (var y = cells.lo.y; y <= cells.hi.y; y += 1) {
                for (var x = cells.lo.x; x <= cells.hi.x; x += 1) {
                    let cell = vec3<i32>(x, y, z);
                    if cell_reaches(cell, query.position, query.volume_radius, cell_size) {
                        let entry = entry_of(cell, VOLUME_CELL_SALT, params.hash_size);
                        add_entry_photons(&sum, query, entry, cell, cell_size, KINDS_ALL);
                    }
                }
            }
        }
        return sum;
    }
    if !caustic_apart(hash_classes()) {
        let touched = query_entries(query.position, reach(query), cell_size, query_salt(query));
        add_touched_photons(&sum, query, touched, KINDS_ALL);
        return sum;
    }
    // cpu::kernels::stochastic_query: the other photons in the surfaces' grid, the caustic
    // ones in their own.
    let touched = query_entries(query.position, query.radius, cell_size, 0u);
    add_touched_photons(&sum, query, touched, KINDS_NOT_CAUSTIC);
    let caustic_touched = query_entries(query.position, query.caustic_radius, caustic_cell_size(), 0u);
    add_touched_photons(&sum, query, caustic_touched, KINDS_CAUSTIC);
    return sum;
}

// cpu::kernels::Kinds: which photon classes a read of a table entry takes.
const KINDS_ALL: u32 = 0u;
const KINDS_NOT_CAUSTIC: u32 = 1u;
const KINDS_CAUSTIC: u32 = 2u;

fn kinds_take(kinds: u32, photon_table: u32, classes: u32) -> bool {
    if kinds == KINDS_ALL {
        return true;
    }
    return class_is_caustic(photon_table, classes) == (kinds == KINDS_CAUSTIC);
}

// The photons of each entry a surface gather's box touches, of the classes `kinds` takes.
fn add_touched_photons(sum: ptr<function, GatherSum>, query: GatherQuery, touched: QueryEntries, kinds: u32) {
    for (var slot = 0u; slot < 8u; slot += 1u) {
        let entry = query_entry(touched, slot);
        if entry != NO_CELL {
            add_entry_photons(sum, query, entry, vec3<i32>(0), 0.0, kinds);
        }
    }
}

// Whether `photon` counts where a gather reads `cell`: for a volume visible point only in its
// own cell (cells sharing an entry count each photon once); for a surface one always.
fn in_read_cell(query: GatherQuery, photon: Photon, cell: vec3<i32>, cell_size: f32) -> bool {
    return !(MURKY_GLASS && query.volume) || all(cell_of(photon.position, cell_size) == cell);
}
