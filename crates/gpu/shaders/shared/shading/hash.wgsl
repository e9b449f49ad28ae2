// render::hash: the photon hash's cells, classes and table entries, shared by its build (the
// SPPM kernels) and its queries (density_*.wgsl).

// ---- render::hash ----
fn hash_cell_size(max_radius: f32) -> f32 {
    return max(2.0 * max_radius * CELL_SLACK, 1.17549435e-38 * 4.0);
}

// render::hash::largest_radius: the inverse of hash_cell_size.
fn largest_radius(cell_size: f32) -> f32 {
    return cell_size * (0.5 / CELL_SLACK);
}

// render::hash::grid_cell_size: the volume photons' grid VOLUME_CELL_DIVISIONS times finer.
fn grid_cell_size(max_radius: f32, volume: bool) -> f32 {
    let size = hash_cell_size(max_radius);
    return select(size, size * VOLUME_CELL_SHARE, volume);
}

// render::hash::grid_largest_radius: the inverse of grid_cell_size.
fn grid_largest_radius(cell_size: f32, volume: bool) -> f32 {
    return largest_radius(select(cell_size, cell_size * f32(VOLUME_CELL_DIVISIONS), volume));
}

// render::hash::cell_of: the grid offset by half a cell (no boundary on the plane 0).
fn cell_of(position: vec3<f32>, cell_size: f32) -> vec3<i32> {
    return vec3<i32>(floor(position / cell_size + 0.5));
}

// render::buffers::SppmParams::hash_classes.
fn hash_classes() -> u32 {
    return max(params.photon_classes, 1u);
}

// render::hash::photon_class: by hue where the classes hold hues, then caustic or not where
// they hold both kinds.
fn photon_class(flux: vec3<f32>, caustic: bool) -> u32 {
    let classes = hash_classes();
    let hues = select(1u, HUE_CLASSES, classes >= HUE_CLASSES);
    var hue = 0u;
    if hues > 1u {
        hue = hue_class(flux);
    }
    let kinds = classes / hues;
    return hue + select(0u, hues, kinds > 1u && caustic);
}

// render::hash::caustic_apart: whether the classes keep caustic photons apart (2, or every hue
// both ways), which then have a grid of their own.
fn caustic_apart(classes: u32) -> bool {
    return classes == 2u || classes == 2u * HUE_CLASSES;
}

// render::hash::class_is_caustic: the upper half of the classes where they are kept apart.
fn class_is_caustic(photon_table: u32, classes: u32) -> bool {
    return caustic_apart(classes) && photon_table >= classes / 2u;
}

// render::hash::hue_class: 1–3 for a photon with a channel of zero (its brightest channel, the
// first of equals), 0 otherwise.
fn hue_class(flux: vec3<f32>) -> u32 {
    if min(min(flux.x, flux.y), flux.z) > 0.0 {
        return 0u;
    }
    if flux.x >= flux.y && flux.x >= flux.z {
        return 1u;
    }
    return select(3u, 2u, flux.y >= flux.z);
}

// render::hash::entry_count: a count word's count, the class marks cleared.
fn class_entry_count(word: u32, classes: u32) -> u32 {
    if classes > 1u {
        return word & ((1u << CLASS_MARK_SHIFT) - 1u);
    }
    return word;
}

// render::hash::class_mark.
fn class_mark(photon_table: u32) -> u32 {
    return 1u << (CLASS_MARK_SHIFT + photon_table - 1u);
}

// render::hash::grid_salt: the volume photons' grid's (VOLUME_CELL_SALT) or the surfaces' (0).
fn grid_salt(volume: bool) -> u32 {
    return select(0u, VOLUME_CELL_SALT, volume);
}

// render::hash::entry_of: a cell's entry in the grid of `salt`.
fn entry_of(cell: vec3<i32>, salt: u32, table_size: u32) -> u32 {
    let h = pcg_hash(bitcast<u32>(cell.x) ^ pcg_hash(bitcast<u32>(cell.y) ^ pcg_hash(bitcast<u32>(cell.z) ^ salt)));
    return h % table_size;
}

// cpu::kernels' cell_size_of: this pass's cell size of the volume photons' grid or the
// surfaces'.
fn cell_size_of(volume: bool) -> f32 {
    return bitcast<f32>(atomicLoad(&counters[select(COUNTER_CELL_SIZE, COUNTER_VOLUME_CELL_SIZE, volume)]));
}

// cpu::kernels' caustic_cell_size_of: this pass's cell size of the caustic photons' own grid.
fn caustic_cell_size() -> f32 {
    return bitcast<f32>(atomicLoad(&counters[COUNTER_CAUSTIC_CELL_SIZE]));
}

// cpu::kernels::photon_entry: the class-0 entry of a stored photon's cell, in the volume
// photons' grid for a volume photon, in the caustic photons' for a caustic one where they are
// kept apart.
fn photon_entry_of(photon: Photon) -> u32 {
    let volume = MURKY_GLASS && is_volume(photon.normal);
    var cell_size = cell_size_of(volume);
    if caustic_apart(hash_classes()) && is_caustic(photon.normal) {
        cell_size = caustic_cell_size();
    }
    return entry_of(cell_of(photon.position, cell_size), grid_salt(volume), params.hash_size);
}

// The table entry of the 2×2×2 block's cell `lo + d`, or NO_CELL where that cell lies past
// the gather sphere's box (`span`: 0 or 1 per axis).
const NO_CELL: u32 = 0xffffffffu;

fn block_entry(lo: vec3<i32>, span: vec3<i32>, d: vec3<i32>, salt: u32) -> u32 {
    if any(d > span) {
        return NO_CELL;
    }
    return entry_of(lo + d, salt, params.hash_size);
}

// render::hash::query_entries: the distinct table entries a gather sphere's box touches, in the
// twin's order (x fastest, then y, then z; an entry reached again by a collision kept at its
// first cell). The eight cells of the block from the box's lowest cell, each NO_CELL where
// it is past the box or repeats an earlier entry: fixed slots in two vectors rather than a
// list grown per invocation, which CPU-type adapters (lavapipe) store and read lane by lane
// (the gather took a third less time through lavapipe).
struct QueryEntries {
    low: vec4<u32>,
    high: vec4<u32>,
}

fn query_entries(position: vec3<f32>, radius: f32, cell_size: f32, salt: u32) -> QueryEntries {
    let lo = cell_of(position - vec3<f32>(radius), cell_size);
    let span = min(cell_of(position + vec3<f32>(radius), cell_size) - lo, vec3<i32>(1));
    let a = vec4<u32>(
        block_entry(lo, span, vec3<i32>(0, 0, 0), salt),
        block_entry(lo, span, vec3<i32>(1, 0, 0), salt),
        block_entry(lo, span, vec3<i32>(0, 1, 0), salt),
        block_entry(lo, span, vec3<i32>(1, 1, 0), salt),
    );
    let b = vec4<u32>(
        block_entry(lo, span, vec3<i32>(0, 0, 1), salt),
        block_entry(lo, span, vec3<i32>(1, 0, 1), salt),
        block_entry(lo, span, vec3<i32>(0, 1, 1), salt),
        block_entry(lo, span, vec3<i32>(1, 1, 1), salt),
    );
    // Whether each slot repeats an entry of a slot before it.
    let a_seen = vec4<bool>(false, a.y == a.x, any(a.zz == a.xy), any(a.www == a.xyz));
    let b_seen = vec4<bool>(
        any(b.xxxx == a),
        any(b.yyyy == a) || b.y == b.x,
        any(b.zzzz == a) || any(b.zz == b.xy),
        any(b.wwww == a) || any(b.www == b.xyz),
    );
    let none = vec4<u32>(NO_CELL);
    return QueryEntries(select(a, none, a_seen), select(b, none, b_seen));
}

// The entry in slot `slot` (0–7) of a query, or NO_CELL.
fn query_entry(query: QueryEntries, slot: u32) -> u32 {
    if slot < 4u {
        return query.low[slot];
    }
    return query.high[slot - 4u];
}

// render::hash::volume_query_cells' bounds: the cells of a volume gather sphere's box, at most
// VOLUME_CELL_DIVISIONS + 1 per axis, from `lo` to `hi`.
struct CellBox {
    lo: vec3<i32>,
    hi: vec3<i32>,
}

fn volume_cell_box(position: vec3<f32>, radius: f32, cell_size: f32) -> CellBox {
    let lo = cell_of(position - vec3<f32>(radius), cell_size);
    let hi = min(cell_of(position + vec3<f32>(radius), cell_size), lo + vec3<i32>(i32(VOLUME_CELL_DIVISIONS)));
    return CellBox(lo, hi);
}

// render::hash::cell_reaches: whether the sphere reaches the cell's box, grown by
// CELL_BOX_MARGIN of a side (rounding in cell_of), so the query skips the cell.
fn cell_reaches(cell: vec3<i32>, position: vec3<f32>, radius: f32, cell_size: f32) -> bool {
    let low = (vec3<f32>(cell) - (0.5 + CELL_BOX_MARGIN)) * cell_size;
    let high = (vec3<f32>(cell) + (0.5 + CELL_BOX_MARGIN)) * cell_size;
    let offset = position - clamp(position, low, high);
    return dot(offset, offset) <= radius * radius;
}
