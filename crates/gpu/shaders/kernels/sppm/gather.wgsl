// The photon map's side of a pass: the stochastic hash built from its photons (hash_count,
// hash_select), each pixel's gather and update, and finish_pass.

// cpu::kernels::photon_key: slot `index`'s stored photon's first hash-entry word and its
// priority this pass; `stored` false if the slot stored none (or lies past the slots).
struct PhotonKey {
    entry: u32,
    // The class-0 entry of the same index's first word, which marks the photon's class
    // (photon_table > 0).
    class_zero_entry: u32,
    photon_table: u32,
    priority: u32,
    stored: bool,
}

fn photon_key(index: u32) -> PhotonKey {
    if index >= params.slot_count {
        return PhotonKey(0u, 0u, 0u, 0u, false);
    }
    let photon = load_photon(index);
    if !any(photon.flux != vec3<f32>(0.0)) {
        return PhotonKey(0u, 0u, 0u, 0u, false);
    }
    // A volume photon's word has no caustic class (render::packing::volume_photon_direction).
    let photon_table = photon_class(photon.flux, is_caustic(photon.normal));
    let entry = photon_entry_of(photon);
    let pass_index = atomicLoad(&counters[COUNTER_PASS]);
    let priority = stream_key(params.seed, HASH_STREAM, pass_index, index) | 1u;
    let word = (photon_table * params.hash_size + entry) * HASH_ENTRY_WORDS;
    return PhotonKey(word, entry * HASH_ENTRY_WORDS, photon_table, priority, true);
}

@compute @workgroup_size(WORKGROUP_SIZE)
fn hash_count(@builtin(global_invocation_id) id: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let key = photon_key(invocation_index(id, groups));
    if key.stored {
        atomicMax(&hash[key.entry + HASH_PRIORITY], key.priority);
        atomicAdd(&hash[key.entry + HASH_COUNT], 1u);
        if key.photon_table > 0u {
            atomicOr(&hash[key.class_zero_entry + HASH_COUNT], class_mark(key.photon_table));
        }
    }
}

@compute @workgroup_size(WORKGROUP_SIZE)
fn hash_select(@builtin(global_invocation_id) id: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let index = invocation_index(id, groups);
    let key = photon_key(index);
    if key.stored && atomicLoad(&hash[key.entry + HASH_PRIORITY]) == key.priority {
        atomicMax(&hash[key.entry + HASH_WINNER], index);
    }
}

// cpu::kernels::GatherSum: the indirect photons a gather counts (M) and their flux, the
// caustic ones, and the volume ones (their flux times the phase function towards the eye).
struct GatherSum {
    found: u32,
    flux: vec3<f32>,
    caustic_found: u32,
    caustic_flux: vec3<f32>,
    volume_found: u32,
    volume_flux: vec3<f32>,
}

fn no_photons() -> GatherSum {
    return GatherSum(0u, vec3<f32>(0.0), 0u, vec3<f32>(0.0), 0u, vec3<f32>(0.0));
}

// cpu::kernels::GatherQuery with its VolumeQuery: where and how far a visible point gathers.
// A volume visible point (volume true, inside murky glass) gathers the volume photons within
// volume_radius instead, weighed by the phase function between their way and its eye path's
// `direction` in a medium of asymmetry `anisotropy`.
struct GatherQuery {
    position: vec3<f32>,
    normal: vec3<f32>,
    radius: f32,
    caustic_radius: f32,
    volume: bool,
    direction: vec3<f32>,
    anisotropy: f32,
    volume_radius: f32,
}

// cpu::kernels::GatherQuery::reach: how far any photon may count, which the density methods
// search.
fn reach(query: GatherQuery) -> f32 {
    if MURKY_GLASS && query.volume {
        return query.volume_radius;
    }
    return max(query.radius, query.caustic_radius);
}

// cpu::kernels::GatherQuery::grid's salt: the volume photons' grid for a volume visible point.
fn query_salt(query: GatherQuery) -> u32 {
    return grid_salt(MURKY_GLASS && query.volume);
}

// cpu::kernels::GatherSum::add_if_near: `count` photons of `photon`'s flux to its class when
// it lies inside that class's sphere and on the visible point's side of the surface; a volume
// visible point counts only volume photons, each times the phase function towards the eye,
// and a surface one none of them.
fn add_if_near(sum: ptr<function, GatherSum>, query: GatherQuery, photon: Photon, count: u32) {
    let offset = photon.position - query.position;
    if MURKY_GLASS {
        if query.volume {
            let radius = query.volume_radius;
            if is_volume(photon.normal) && dot(offset, offset) < radius * radius {
                let cos = -dot(unpack_normal(photon.normal), query.direction);
                let phase = henyey_greenstein_phase(query.anisotropy, cos);
                (*sum).volume_found += count;
                (*sum).volume_flux += (f32(count) * phase) * photon.flux;
            }
            return;
        }
        if is_volume(photon.normal) {
            return;
        }
    }
    let caustic = is_caustic(photon.normal);
    let radius = select(query.radius, query.caustic_radius, caustic);
    if dot(offset, offset) < radius * radius && dot(unpack_normal(photon.normal), query.normal) > 0.0 {
        let flux = f32(count) * photon.flux;
        if caustic {
            (*sum).caustic_found += count;
            (*sum).caustic_flux += flux;
        } else {
            (*sum).found += count;
            (*sum).flux += flux;
        }
    }
}

// The query of visible point `point` with its pixel's radii (cpu::kernels::gather_update): a
// volume visible point's word holds its eye path's way and its medium's asymmetry.
fn gather_query(point: VisiblePoint, radius: f32, caustic_radius: f32, volume_radius: f32) -> GatherQuery {
    var query = GatherQuery(point.position, vec3<f32>(0.0), radius, caustic_radius, false, vec3<f32>(0.0), 0.0, volume_radius);
    if MURKY_GLASS && is_volume(point.normal) {
        let unpacked = unpack_volume_point(point.normal);
        query.volume = true;
        query.direction = unpacked.xyz;
        query.anisotropy = unpacked.w;
        query.normal = -unpacked.xyz;
    } else {
        query.normal = unpack_normal(point.normal);
    }
    return query;
}

// One class's statistics (PixelStats' τ, N and R of the indirect, caustic or volume photons).
struct Estimate {
    tau: vec3<f32>,
    count: f32,
    radius: f32,
}

// cpu::kernels' dimensions a set of statistics gathers over: a disc's on surfaces, a sphere's
// in murky glass.
const AREA: u32 = 2u;
const VOLUME: u32 = 3u;

// cpu::kernels::shrink_to_fit: a radius larger than the cells allow shrinks to `largest`, τ
// scaled with the disc's area or the sphere's volume (Rust's powi: (s·s)·s).
fn shrink_to_fit(e: Estimate, largest: f32, dimensions: u32) -> Estimate {
    let shrink = largest / e.radius;
    var scale = shrink * shrink;
    if dimensions == VOLUME {
        scale *= shrink;
    }
    return Estimate(e.tau * scale, e.count, largest);
}

// f32::cbrt of x in (0, 1]: pow's estimate, a few ulp off on GPUs, and one Newton step.
fn cube_root(x: f32) -> f32 {
    let c = pow(x, 1.0 / 3.0);
    if c <= 0.0 {
        return c;
    }
    return c - (c * c * c - x) / (3.0 * c * c);
}

// cpu::kernels::update: one class's statistics after M > 0 photons of weighted flux `flux`,
// the radius shrinking by the square root of the count's ratio on a disc, the cube root in a
// sphere.
fn update(e: Estimate, found: u32, flux: vec3<f32>, alpha: f32, dimensions: u32) -> Estimate {
    let n = e.count;
    let m = f32(found);
    let n_next = n + alpha * m;
    let ratio = n_next / (n + m);
    var shrink = sqrt(ratio);
    if dimensions == VOLUME {
        shrink = cube_root(ratio);
    }
    return Estimate((e.tau + flux) * ratio, n_next, e.radius * shrink);
}

// `e` shrunk to `largest` where it is larger; `changed` set where it was.
fn fitted(e: Estimate, largest: f32, dimensions: u32, changed: ptr<function, bool>) -> Estimate {
    if e.radius > largest {
        *changed = true;
        return shrink_to_fit(e, largest, dimensions);
    }
    return e;
}

// `e` updated with `found` photons of weighted flux `flux` where there are any; `changed` set
// where it was.
fn updated(e: Estimate, found: u32, flux: vec3<f32>, alpha: f32, dimensions: u32, changed: ptr<function, bool>) -> Estimate {
    if found > 0u {
        *changed = true;
        return update(e, found, flux, alpha, dimensions);
    }
    return e;
}

// The bits of `e`'s radius where it has met photons, else 0 (cpu::kernels::LitRadii).
fn lit_bits(e: Estimate) -> u32 {
    return select(0u, bitcast<u32>(e.radius), e.count > 0.0);
}

// render::radius_histogram::radius_bucket: eighths of an octave below `largest`.
fn radius_bucket(radius: f32, largest: f32) -> u32 {
    let key = bitcast<u32>(largest) >> 20u;
    let radius_key = bitcast<u32>(radius) >> 20u;
    return min(select(0u, key - radius_key, key > radius_key), RADIUS_BUCKETS - 1u);
}

// render::radius_histogram::bucket_top.
fn bucket_top(bucket: u32, largest: f32) -> f32 {
    let key = bitcast<u32>(largest) >> 20u;
    let top_key = select(0u, key - bucket, key > bucket);
    return min(bitcast<f32>(((top_key + 1u) << 20u) - 1u), largest);
}

// cpu::kernels::gather_with: the update is the same for every density method; the module's
// `density_query` (density_*.wgsl) finds the photons.
@compute @workgroup_size(WORKGROUP_SIZE)
fn gather(@builtin(global_invocation_id) id: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let index = invocation_index(id, groups);
    if index >= params.width * params.height {
        return;
    }
    var stats = pixels[index];
    let point = load_visible_point(index);
    let cell_size = cell_size_of(false);
    let volume_cell_size = cell_size_of(true);
    // A radius larger than the cells allow shrinks to fit.
    let largest = grid_largest_radius(cell_size, false);
    var changed = false;
    var indirect = fitted(Estimate(stats.tau, stats.photon_count, stats.radius), largest, AREA, &changed);
    // Caustic photons kept apart have cells of their own (render::hash::caustic_apart).
    let apart = caustic_apart(hash_classes());
    let caustic_largest = grid_largest_radius(caustic_cell_size(), false);
    let caustic_fit = select(largest, caustic_largest, apart);
    var caustic = fitted(Estimate(stats.caustic_tau, stats.caustic_count, stats.caustic_radius), caustic_fit, AREA, &changed);
    // Without murky glass no volume photon is kept: τ stays 0 (not stored), R shrinks alone.
    var volume_tau = vec3<f32>(0.0);
    if MURKY_GLASS {
        volume_tau = pixel_volume_tau[index].xyz;
    }
    var volume = fitted(Estimate(volume_tau, stats.volume_count, stats.volume_radius), grid_largest_radius(volume_cell_size, true), VOLUME, &changed);
    if any(point.weight != vec3<f32>(0.0)) {
        let query = gather_query(point, indirect.radius, caustic.radius, volume.radius);
        let sum = density_query(query, select(cell_size, volume_cell_size, query.volume));
        indirect = updated(indirect, sum.found, point.weight * sum.flux, params.indirect_alpha, AREA, &changed);
        caustic = updated(caustic, sum.caustic_found, point.weight * sum.caustic_flux, params.alpha, AREA, &changed);
        // Divided by the share of the sphere inside the medium: none is found outside (only
        // murky glass has volume points: elsewhere the share is 1, and not computed).
        var volume_flux = point.weight * sum.volume_flux;
        if MURKY_GLASS {
            volume_flux /= share_inside(point.pad, volume.radius);
        }
        volume = updated(volume, sum.volume_found, volume_flux, params.alpha, VOLUME, &changed);
        // Lit radii size each grid's next cells (render::hash): the surfaces' and the caustic
        // photons' (where they have their own) by the pass's histograms and largest, the volume
        // photons' by their largest.
        let caustic_bits = lit_bits(caustic);
        let surfaces = select(max(lit_bits(indirect), caustic_bits), lit_bits(indirect), apart);
        if surfaces != 0u {
            atomicMax(&counters[COUNTER_MAX_RADIUS], surfaces);
            let bucket = radius_bucket(bitcast<f32>(surfaces), largest);
            atomicAdd(&counters[COUNTER_RADIUS_HISTOGRAM + bucket], 1u);
        }
        if apart && caustic_bits != 0u {
            atomicMax(&counters[COUNTER_CAUSTIC_MAX_RADIUS], caustic_bits);
            let bucket = radius_bucket(bitcast<f32>(caustic_bits), caustic_largest);
            atomicAdd(&counters[COUNTER_CAUSTIC_RADIUS_HISTOGRAM + bucket], 1u);
        }
        let volume_bits = lit_bits(volume);
        if volume_bits != 0u {
            atomicMax(&counters[COUNTER_VOLUME_MAX_RADIUS], volume_bits);
        }
    }
    if changed {
        stats.tau = indirect.tau;
        stats.photon_count = indirect.count;
        stats.radius = indirect.radius;
        stats.caustic_tau = caustic.tau;
        stats.caustic_count = caustic.count;
        stats.caustic_radius = caustic.radius;
        stats.volume_count = volume.count;
        stats.volume_radius = volume.radius;
        pixels[index] = stats;
        if MURKY_GLASS {
            pixel_volume_tau[index] = vec4<f32>(volume.tau, 0.0);
        }
    }
}

// render::radius_histogram::served_radius for the grid whose histogram starts at counter
// `histogram`, whose largest lit radius is counter `max` and whose cells are `cell_size`: the
// next cells' size, serving all but `shrunk_tenths` of the lit radii (the largest, where that
// is 0); 0 where no pixel met a photon. The histogram and the largest are cleared.
fn served_cell_size(histogram: u32, max: u32, cell_size: f32) -> f32 {
    var total = 0u;
    for (var b = 0u; b < RADIUS_BUCKETS; b++) {
        total += atomicLoad(&counters[histogram + b]);
    }
    let largest_lit = bitcast<f32>(atomicExchange(&counters[max], 0u));
    var size = 0.0;
    if total > 0u && largest_lit > 0.0 {
        // The count allowed above, as the twin's u64 product: total × tenths / 10 exactly.
        let tenths = min(params.shrunk_tenths, 10u);
        let above = (total / 10u) * tenths + ((total % 10u) * tenths) / 10u;
        var counted = 0u;
        var bucket = RADIUS_BUCKETS - 1u;
        for (var b = 0u; b < RADIUS_BUCKETS; b++) {
            counted += atomicLoad(&counters[histogram + b]);
            if counted > above {
                bucket = b;
                break;
            }
        }
        let served = min(bucket_top(bucket, grid_largest_radius(cell_size, false)), largest_lit);
        size = grid_cell_size(served, false);
    }
    for (var b = 0u; b < RADIUS_BUCKETS; b++) {
        atomicStore(&counters[histogram + b], 0u);
    }
    return size;
}

// One invocation: the pass's emitted paths into the 64-bit total, each grid's next cell size
// from its lit radii (served_cell_size; the volume photons' from their largest), the pass
// counter advanced (cpu::kernels::finish_pass).
@compute @workgroup_size(1)
fn finish_pass() {
    let emitted = atomicExchange(&counters[COUNTER_EMITTED_PASS], 0u);
    let low = atomicLoad(&counters[COUNTER_EMITTED_LO]);
    let sum = low + emitted;
    atomicStore(&counters[COUNTER_EMITTED_LO], sum);
    atomicAdd(&counters[COUNTER_EMITTED_HI], select(0u, 1u, sum < low));
    // Each grid's cells by its own radii (cpu::kernels::finish_pass).
    let surfaces = served_cell_size(COUNTER_RADIUS_HISTOGRAM, COUNTER_MAX_RADIUS, cell_size_of(false));
    let caustic = served_cell_size(COUNTER_CAUSTIC_RADIUS_HISTOGRAM, COUNTER_CAUSTIC_MAX_RADIUS, caustic_cell_size());
    if surfaces > 0.0 {
        atomicStore(&counters[COUNTER_CELL_SIZE], bitcast<u32>(surfaces));
    }
    if caustic > 0.0 {
        atomicStore(&counters[COUNTER_CAUSTIC_CELL_SIZE], bitcast<u32>(caustic));
    }
    let volume_max_radius = bitcast<f32>(atomicExchange(&counters[COUNTER_VOLUME_MAX_RADIUS], 0u));
    if volume_max_radius > 0.0 {
        atomicStore(&counters[COUNTER_VOLUME_CELL_SIZE], bitcast<u32>(grid_cell_size(volume_max_radius, true)));
    }
    atomicAdd(&counters[COUNTER_PASS], 1u);
}
