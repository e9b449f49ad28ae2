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
                        add_entry_photons(&sum, query, entry, cell, cell_size);
                    }
                }
            }
        }
        return sum;
    }
    let touched = query_entries(query.position, reach(query), cell_size, query_salt(query));
    for (var slot = 0u; slot < 8u; slot += 1u) {
        let entry = query_entry(touched, slot);
        if entry != NO_CELL {
            add_entry_photons(&sum, query, entry, vec3<i32>(0), cell_size);
        }
    }
    return sum;
}

// Whether `photon` counts where a gather reads `cell`: for a volume visible point only in its
// own cell (cells sharing an entry count each photon once); for a surface one always.
fn in_read_cell(query: GatherQuery, photon: Photon, cell: vec3<i32>, cell_size: f32) -> bool {
    return !(MURKY_GLASS && query.volume) || all(cell_of(photon.position, cell_size) == cell);
}
