//! The stochastic spatial hash (DESIGN.md, "Stochastic hash"), driven through the CPU kernels
//! `hash_count`, `hash_select` and `gather` on hand-made photons: each entry must keep a
//! photon picked uniformly among those hashed to it, with their count, so that the gather's
//! count-weighted estimate is an unbiased estimate of the full gather.

use std::sync::atomic::{AtomicU32, Ordering::Relaxed};

use cpu::kernels::{GatherQuery, VolumeQuery};
use glam::Vec3;
use render::buffers::{
    HASH_ENTRY_WORDS, Photon, PixelStats, SppmParams, VisiblePoint, counter, hash_word,
};
use render::hash::{cell_of, cell_size, entry_of, grid_cell_size, volume_query_cells};
use render::packing::{surface_normal, unpack_normal, volume_photon_direction};
use render::scattering::henyey_greenstein_phase;

/// The counters and hash table of one pass, laid out as the backends keep them.
struct Table {
    params: SppmParams,
    counters: Vec<AtomicU32>,
    hash: Vec<AtomicU32>,
}

impl Table {
    fn new(hash_size: u32, seed: u32, cell: f32, alpha: f32) -> Table {
        Table::with_classes(hash_size, seed, cell, alpha, 1)
    }

    /// A table keeping `classes` photon classes apart (`render::hash::photon_class`).
    fn with_classes(hash_size: u32, seed: u32, cell: f32, alpha: f32, classes: u32) -> Table {
        let counters: Vec<AtomicU32> = (0..counter::COUNT).map(|_| AtomicU32::new(0)).collect();
        counters[counter::CELL_SIZE].store(cell.to_bits(), Relaxed);
        // Caustic photons, where classes keep them apart, in a grid of their own: here alike.
        counters[counter::CAUSTIC_CELL_SIZE].store(cell.to_bits(), Relaxed);
        Table {
            params: SppmParams {
                hash_size,
                seed,
                alpha,
                indirect_alpha: alpha,
                photon_classes: classes,
                ..SppmParams::default()
            },
            counters,
            hash: (0..(hash_size * classes) as usize * HASH_ENTRY_WORDS)
                .map(|_| AtomicU32::new(0))
                .collect(),
        }
    }

    /// The hash build of pass `pass`, as `CpuBackend::build_hash` runs it (every photon
    /// counted, then every photon offered as the winner), the photons visited in `order`.
    fn build(&self, pass: u32, photons: &[Photon], order: &[usize]) {
        for word in &self.hash {
            word.store(0, Relaxed);
        }
        self.counters[counter::PASS].store(pass, Relaxed);
        for &i in order {
            cpu::kernels::hash_count(
                &self.params,
                &self.counters,
                &self.hash,
                i as u32,
                &photons[i],
            );
        }
        for &i in order {
            cpu::kernels::hash_select(
                &self.params,
                &self.counters,
                &self.hash,
                i as u32,
                &photons[i],
            );
        }
    }

    /// (count, winner) of the entry holding `position`'s cell.
    fn entry(&self, position: Vec3) -> (u32, u32) {
        let cell = f32::from_bits(self.counters[counter::CELL_SIZE].load(Relaxed));
        let word =
            entry_of(cell_of(position, cell), 0, self.params.hash_size) as usize * HASH_ENTRY_WORDS;
        (
            self.hash[word + hash_word::COUNT].load(Relaxed),
            self.hash[word + hash_word::WINNER].load(Relaxed),
        )
    }
}

fn photon(position: Vec3, normal: Vec3, flux: Vec3) -> Photon {
    Photon {
        position: position.to_array(),
        normal: surface_normal(normal),
        flux: flux.to_array(),
        pad: 0,
    }
}

/// A small deterministic generator for the test's own choices (positions, fluxes), apart
/// from the kernels' streams.
struct SplitMix(u64);

impl SplitMix {
    fn next_f32(&mut self) -> f32 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        ((z ^ (z >> 31)) >> 40) as f32 / (1u64 << 24) as f32
    }

    fn vec3(&mut self) -> Vec3 {
        Vec3::new(self.next_f32(), self.next_f32(), self.next_f32())
    }
}

/// The 0.999 quantile of χ² with 4 degrees of freedom (p = 0.001).
const CHI_SQUARE_4_DOF_P001: f64 = 18.467;

/// K = 5 photons share one cell (among photons elsewhere and empty slots); over many passes
/// each is kept 1/K of the time (χ² with K − 1 degrees of freedom at p = 0.001), the entry's
/// count is always K, and the pick does not depend on the order the photons are visited in.
#[test]
fn the_kept_photon_is_a_uniform_pick() {
    const K: usize = 5;
    const TRIALS: u32 = 20_000;
    let cell = 1.0;
    // 64 entries for 4 occupied cells: cells may share an entry, so check the test's own
    // cell is alone in its entry (it is, for this layout; asserted below).
    let table = Table::new(64, 7, cell, 2.0 / 3.0);
    let up = Vec3::Y;
    let centre = Vec3::ZERO;
    // Slots 0..20: the cell's photons at scattered indices (one of them index 0, whose
    // win leaves the winner word at its initial 0), empty slots, photons in other cells.
    let mut photons = vec![Photon::default(); 20];
    let members = [0usize, 3, 4, 11, 19];
    for (k, &i) in members.iter().enumerate() {
        let offset = Vec3::new(0.1 * k as f32, -0.05 * k as f32, 0.07 * k as f32);
        photons[i] = photon(centre + offset - Vec3::splat(0.15), up, Vec3::ONE);
    }
    for (i, elsewhere) in [(1, 3.5), (7, -2.5), (8, 3.6), (15, 9.5)] {
        photons[i] = photon(Vec3::new(elsewhere - 0.5, 0.0, 0.0), up, Vec3::ONE);
    }
    let entry_of_cell = entry_of(cell_of(centre, cell), 0, 64);
    for p in photons.iter().filter(|p| p.is_stored()) {
        let position = Vec3::from_array(p.position);
        assert!(
            cell_of(position, cell) == cell_of(centre, cell)
                || entry_of(cell_of(position, cell), 0, 64) != entry_of_cell,
            "a photon outside the cell collides with it; pick another layout"
        );
    }
    let forward: Vec<usize> = (0..photons.len()).collect();
    let backward: Vec<usize> = forward.iter().rev().copied().collect();
    let mut wins = [0u32; K];
    for pass in 0..TRIALS {
        table.build(pass, &photons, &forward);
        let (count, winner) = table.entry(centre);
        assert_eq!(count, K as u32, "pass {pass}: the entry's count");
        let k = members
            .iter()
            .position(|&i| i == winner as usize)
            .unwrap_or_else(|| panic!("pass {pass}: winner {winner} is not in the cell"));
        wins[k] += 1;
        table.build(pass, &photons, &backward);
        assert_eq!(
            table.entry(centre),
            (K as u32, winner),
            "pass {pass}: the pick depends on the order of the photons"
        );
    }
    let expected = TRIALS as f64 / K as f64;
    let chi_square: f64 = wins
        .iter()
        .map(|&w| (w as f64 - expected).powi(2) / expected)
        .sum();
    println!("wins {wins:?} (expected {expected} each), χ² = {chi_square:.2}");
    assert!(
        chi_square < CHI_SQUARE_4_DOF_P001,
        "kept photons {wins:?} are not uniform: χ² = {chi_square:.2} ≥ {CHI_SQUARE_4_DOF_P001}"
    );
}

/// The same with K = 5 photons at consecutive indices (neighbouring priority streams), for
/// a few seeds: the pick must not favour an index position.
#[test]
fn the_pick_is_uniform_for_consecutive_indices() {
    const K: usize = 5;
    const TRIALS: u32 = 10_000;
    for seed in [0, 1, 0xdead_beef] {
        let table = Table::new(16, seed, 1.0, 2.0 / 3.0);
        let start = 1000;
        let mut photons = vec![Photon::default(); start + K];
        for slot in &mut photons[start..] {
            *slot = photon(Vec3::splat(0.25), Vec3::Y, Vec3::ONE);
        }
        let order: Vec<usize> = (0..photons.len()).collect();
        let mut wins = [0u32; K];
        for pass in 0..TRIALS {
            table.build(pass, &photons, &order);
            let (count, winner) = table.entry(Vec3::splat(0.25));
            assert_eq!(count, K as u32);
            wins[winner as usize - start] += 1;
        }
        let expected = TRIALS as f64 / K as f64;
        let chi_square: f64 = wins
            .iter()
            .map(|&w| (w as f64 - expected).powi(2) / expected)
            .sum();
        println!("seed {seed:#x}: wins {wins:?}, χ² = {chi_square:.2}");
        assert!(
            chi_square < CHI_SQUARE_4_DOF_P001,
            "seed {seed:#x}: kept photons {wins:?} are not uniform: χ² = {chi_square:.2}"
        );
    }
}

/// The gather's estimate through the stochastic hash — per entry, the kept photon's flux ×
/// the entry's count when the kept photon lies in the radius and faces the right way — is
/// unbiased: its mean over many passes equals the full gather (the plain sum over every
/// photon in the radius with a facing normal), within 4 standard errors, for the flux and for
/// the photon count M. Photons of different fluxes lie inside and outside the radius, in
/// several cells, some facing away, and the table has 3 entries for the 20 or so occupied cells,
/// so collisions (entries shared by cells, entries reached twice by one query) are certain.
///
/// The estimate is read out of the `PixelStats` that `gather` returns: from N = 0 the update
/// gives N' = αM and τ' = weight · Φ · α (ratio (N + αM)/(N + M) = α), so with weight 1
/// Φ = τ'/α and M = N'/α.
#[test]
fn the_gather_estimate_is_unbiased() {
    assert_gather_estimate_unbiased(1);
}

/// The same where the hash keeps photon classes apart (a dispersive scene's,
/// `render::hash::PHOTON_CLASSES`: by hue, then caustic or not): every other photon carries
/// one colour channel (a hue with a zero channel, as dispersive glass leaves them), kept with
/// the caustic ones in its class's own table; the estimate, summed over the classes, is still
/// the full gather's.
#[test]
fn the_gather_estimate_is_unbiased_with_photon_classes() {
    assert_gather_estimate_unbiased(render::hash::PHOTON_CLASSES);
}

fn assert_gather_estimate_unbiased(classes: u32) {
    const TRIALS: u32 = 100_000;
    const ALPHA: f32 = 0.5;
    let radius = 0.3;
    let cell = cell_size(radius);
    let table = Table::with_classes(3, 11, cell, ALPHA, classes);
    // A visible point near a corner of its cell, so its sphere spans 2 × 2 × 2 cells.
    let position = Vec3::new(0.58 * cell, 0.97 * cell, 1.05 * cell);
    let normal = Vec3::Y;
    let point = VisiblePoint {
        position: position.to_array(),
        normal: surface_normal(normal),
        weight: [1.0; 3],
        pad: 0,
    };
    let mut rng = SplitMix(42);
    let photons: Vec<Photon> = (0..90)
        .map(|i| {
            if i % 9 == 4 {
                return Photon::default(); // a slot that stored nothing
            }
            // Two in three within ±1.2 R per axis of the point (about a third of those
            // inside the radius), the others within ±4 R, mostly in cells the query skips.
            let spread = if i % 3 == 2 { 4.0 } else { 1.2 };
            let at = position + (rng.vec3() * 2.0 - Vec3::ONE) * spread * radius;
            // One photon in six arrives on the other side of the surface.
            let facing = if i % 6 == 1 { -normal } else { normal };
            let tilt = (rng.vec3() - Vec3::splat(0.5)) * 0.5;
            let mut flux = Vec3::new(0.2, 0.5, 1.0) + 2.0 * rng.vec3();
            if classes > 1 && i % 2 == 0 {
                // One channel, three times as bright (`render::dispersion`'s weight).
                let channel = (i / 2) % 3;
                flux = Vec3::from_array(std::array::from_fn(|c| {
                    if c == channel { 3.0 * flux[c] } else { 0.0 }
                }));
            }
            photon(at, (facing + tilt).normalize(), flux)
        })
        .collect();

    // The full gather, by the kernel's own tests (distance and facing).
    let gathered: Vec<&Photon> = photons
        .iter()
        .filter(|p| {
            p.is_stored()
                && (Vec3::from_array(p.position) - position).length_squared() < radius * radius
                && unpack_normal(p.normal).dot(unpack_normal(point.normal)) > 0.0
        })
        .collect();
    let full_flux: Vec3 = gathered.iter().map(|p| Vec3::from_array(p.flux)).sum();
    let full_count = gathered.len() as f64;
    let stored = photons.iter().filter(|p| p.is_stored()).count();
    let cells = {
        let mut cells: Vec<_> = photons
            .iter()
            .filter(|p| p.is_stored())
            .map(|p| cell_of(Vec3::from_array(p.position), cell))
            .collect();
        cells.sort_by_key(|c| c.to_array());
        cells.dedup();
        cells.len()
    };
    println!(
        "{stored} photons in {cells} cells, 3 entries; {} gathered, full flux {full_flux}",
        gathered.len()
    );
    assert!(gathered.len() >= 8 && gathered.len() + 8 <= stored);
    assert!(cells > 8, "photons must lie outside the query's cells too");

    let order: Vec<usize> = (0..photons.len()).collect();
    if classes > 1 {
        // The one-channel photons filled the classes' own tables.
        table.build(0, &photons, &order);
        let class_counts: u32 = (table.hash.iter().skip(3 * HASH_ENTRY_WORDS))
            .skip(hash_word::COUNT)
            .step_by(HASH_ENTRY_WORDS)
            .map(|w| w.load(Relaxed))
            .sum();
        let one_channel = (photons.iter())
            .filter(|p| p.is_stored() && p.flux.iter().filter(|&&c| c > 0.0).count() == 1)
            .count();
        assert!(one_channel >= 10, "{one_channel} one-channel photons");
        // With the caustic photons' own classes too (`render::hash::photon_class`).
        let caustic_white = (photons.iter())
            .filter(|p| p.is_stored() && p.flux.iter().all(|&c| c > 0.0))
            .filter(|p| render::packing::is_caustic(p.normal))
            .count();
        let kinds = classes / render::hash::HUE_CLASSES.min(classes);
        let gathered_one_channel = (gathered.iter())
            .filter(|p| p.flux.iter().filter(|&&c| c > 0.0).count() == 1)
            .count();
        assert!(
            gathered_one_channel >= 2,
            "{gathered_one_channel} one-channel photons gathered"
        );
        let expected = one_channel + if kinds > 1 { caustic_white } else { 0 };
        assert_eq!(class_counts as usize, expected);
    }
    let (mut sum, mut sum_sq) = ([0f64; 4], [0f64; 4]);
    for pass in 0..TRIALS {
        table.build(pass, &photons, &order);
        let stats = cpu::kernels::gather(
            &table.params,
            &table.counters,
            &table.hash,
            &photons,
            &point,
            PixelStats::initial(radius, radius, radius),
        );
        // Both classes of photon (the packed normals' lowest bits pick them) count.
        let flux = (Vec3::from_array(stats.tau) + Vec3::from_array(stats.caustic_tau)) / ALPHA;
        let count = (stats.photon_count + stats.caustic_count) / ALPHA;
        for (k, v) in [flux.x, flux.y, flux.z, count].into_iter().enumerate() {
            sum[k] += v as f64;
            sum_sq[k] += (v as f64).powi(2);
        }
    }
    let expected = [
        full_flux.x as f64,
        full_flux.y as f64,
        full_flux.z as f64,
        full_count,
    ];
    assert_means_match(TRIALS, sum, sum_sq, expected);
}

/// Each of flux r, g, b and the count: the mean over `trials` within 4 standard errors of the
/// full gather's.
fn assert_means_match(trials: u32, sum: [f64; 4], sum_sq: [f64; 4], expected: [f64; 4]) {
    let n = trials as f64;
    for (k, name) in ["flux.r", "flux.g", "flux.b", "count"].iter().enumerate() {
        let mean = sum[k] / n;
        let variance = (sum_sq[k] / n - mean * mean) * n / (n - 1.0);
        let standard_error = (variance / n).sqrt();
        let z = (mean - expected[k]) / standard_error;
        println!(
            "{name}: mean {mean:.4} ± {standard_error:.4} against full gather {:.4} (z = {z:.2})",
            expected[k]
        );
        assert!(
            z.abs() < 4.0,
            "{name}: the stochastic hash's mean {mean} differs from the full gather {} by \
             {z:.2} standard errors",
            expected[k]
        );
    }
}

/// The same for a volume visible point, which reads the volume photons' finer grid cell by
/// cell (`render::hash::volume_query_cells`) through a table of three entries, so that the
/// ~20 cells its sphere reaches share them: each cell counts only the kept photon lying in it,
/// and the estimate (flux times the phase function towards the eye, and the count) is still
/// the full gather's, no photon counted twice.
#[test]
fn the_volume_gather_estimate_is_unbiased_where_cells_share_entries() {
    const TRIALS: u32 = 60_000;
    let radius = 0.3;
    let cell = grid_cell_size(radius, true);
    let table = Table::new(3, 5, cell_size(radius), 0.5);
    table.counters[counter::VOLUME_CELL_SIZE].store(cell.to_bits(), Relaxed);
    let position = Vec3::new(0.58, 0.97, 1.05) * cell;
    let mut rng = SplitMix(7);
    let photons: Vec<Photon> = (0..120)
        .map(|i| {
            if i % 11 == 4 {
                return Photon::default();
            }
            let spread = if i % 4 == 3 { 4.0 } else { 1.3 };
            let at = position + (rng.vec3() * 2.0 - Vec3::ONE) * spread * radius;
            let direction = (rng.vec3() * 2.0 - Vec3::ONE + Vec3::new(0.0, 0.0, 0.01)).normalize();
            Photon {
                position: at.to_array(),
                normal: volume_photon_direction(direction),
                flux: (Vec3::new(0.2, 0.5, 1.0) + 2.0 * rng.vec3()).to_array(),
                pad: 0,
            }
        })
        .collect();
    let query = GatherQuery {
        position,
        normal: Vec3::NEG_Z,
        radius,
        caustic_radius: radius,
        cell_size: cell,
        caustic_cell_size: cell,
        volume: Some(VolumeQuery {
            direction: Vec3::Z,
            anisotropy: 0.6,
            radius,
        }),
    };

    // The full gather, by the kernel's own test (distance) and weight (the phase function).
    let (mut full_flux, mut full_count) = (Vec3::ZERO, 0.0);
    for p in photons.iter().filter(|p| p.is_stored()) {
        if (Vec3::from_array(p.position) - position).length_squared() < radius * radius {
            let cos = -unpack_normal(p.normal).dot(Vec3::Z);
            full_flux += henyey_greenstein_phase(0.6, cos) * Vec3::from_array(p.flux);
            full_count += 1.0;
        }
    }
    let read: Vec<_> = volume_query_cells(position, radius, cell).collect();
    println!("{full_count} photons gathered in {} cells read", read.len());
    assert!(full_count >= 10.0);
    assert!(read.len() > 8, "the cells read share the three entries");

    let order: Vec<usize> = (0..photons.len()).collect();
    let (mut sum, mut sum_sq) = ([0f64; 4], [0f64; 4]);
    for pass in 0..TRIALS {
        table.build(pass, &photons, &order);
        let found = cpu::kernels::stochastic_query(&table.params, &table.hash, &photons, &query);
        let f = found.volume_flux;
        for (k, v) in [f.x, f.y, f.z, found.volume_found as f32]
            .into_iter()
            .enumerate()
        {
            sum[k] += v as f64;
            sum_sq[k] += (v as f64).powi(2);
        }
    }
    let expected = [full_flux.x, full_flux.y, full_flux.z, full_count];
    assert_means_match(TRIALS, sum, sum_sq, expected.map(f64::from));
}

/// The cells of the next pass (`finish_pass`, `render::radius_histogram`): with none shrunk,
/// sized for the largest lit radius exactly; with two tenths shrunk (the stochastic hash),
/// for a radius no more than an eighth of an octave above the one that eight tenths of the
/// lit radii do not exceed, so that at most two tenths (and their bucket) lie above it.
#[test]
fn the_next_cells_serve_all_lit_radii_or_all_but_the_largest_tenths() {
    let largest = 10.0f32;
    // 1,000 lit radii spread over three octaves below the largest, in a scrambled order.
    let radii: Vec<f32> = (0..1000u32)
        .map(|i| {
            let u = (i.wrapping_mul(2_654_435_761) >> 8) as f32 / (1u32 << 24) as f32;
            largest * (-3.0 * u).exp2()
        })
        .collect();
    for shrunk_tenths in [0, 2] {
        let table = Table::new(64, 1, cell_size(largest), 2.0 / 3.0);
        let params = SppmParams {
            shrunk_tenths,
            ..table.params
        };
        let served = cpu::kernels::served_largest(&table.counters);
        // Offered in two summaries, as two threads would.
        let (first, second) = radii.split_at(400);
        let summary = |part: &[f32]| {
            part.iter()
                .fold(cpu::kernels::LitSummary::default(), |s, &r| {
                    // The caustic photons' own grid, whose cells start alike, takes the
                    // same radii and must come to the same size.
                    let lit = cpu::kernels::LitRadii {
                        surfaces: r.to_bits(),
                        caustic: r.to_bits(),
                        volume: 0,
                    };
                    s.add(lit, served)
                })
        };
        summary(first).merge(summary(second)).offer(&table.counters);
        cpu::kernels::finish_pass(&params, &table.counters);
        let cell = f32::from_bits(table.counters[counter::CELL_SIZE].load(Relaxed));
        let caustic_cell = table.counters[counter::CAUSTIC_CELL_SIZE].load(Relaxed);
        assert_eq!(caustic_cell, cell.to_bits());
        let buckets = render::radius_histogram::RADIUS_BUCKETS;
        for start in [counter::RADIUS_HISTOGRAM, counter::CAUSTIC_RADIUS_HISTOGRAM] {
            assert!(
                (start..start + buckets).all(|i| table.counters[i].load(Relaxed) == 0),
                "the histograms are cleared for the next pass"
            );
        }
        let mut sorted = radii.clone();
        sorted.sort_by(f32::total_cmp);
        let largest_lit = sorted[999];
        if shrunk_tenths == 0 {
            assert_eq!(cell, cell_size(largest_lit));
            continue;
        }
        let eight_tenths = sorted[799];
        assert!(cell >= cell_size(eight_tenths), "{cell}");
        let bucket_above = eight_tenths * 2f32.powf(1.0 / 8.0) * 1.0001;
        assert!(cell <= cell_size(bucket_above), "{cell}");
        let above = sorted.iter().filter(|&&r| cell_size(r) > cell).count();
        assert!(above <= 200, "{above} radii above the cells");
        assert!(
            cell < 0.9 * cell_size(largest_lit),
            "the largest tenths shrink"
        );
    }
}
