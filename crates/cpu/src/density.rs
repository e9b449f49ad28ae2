//! The density-estimation methods benchmarks compare with the stochastic hash (issue 6,
//! table 4), twins of `shaders/shared/density_full.wgsl`: the full spatial hash, whose table
//! entries list every photon hashed to them, built by a counting sort (count, prefix sum,
//! scatter) as the GPU builds it.

use std::sync::atomic::{AtomicU32, Ordering::Relaxed};

use rayon::prelude::*;
use render::buffers::{HASH_ENTRY_WORDS, Photon, SppmParams, vec3};
use render::density::{SCAN_BLOCK, full_word};
use render::hash::{lies_in, query_entries, volume_query_entries};

use crate::kernels::{self, GatherQuery, GatherSum};

/// The first table word of the entry a stored photon hashes to this pass; `None` if the slot
/// stored no photon.
pub fn photon_entry(params: &SppmParams, counters: &[AtomicU32], photon: &Photon) -> Option<usize> {
    photon
        .is_stored()
        .then(|| kernels::photon_entry(params, counters, photon) as usize * HASH_ENTRY_WORDS)
}

/// Counting sort, first step, photon `index`: its entry's count grows by one.
pub fn full_count(
    params: &SppmParams,
    counters: &[AtomicU32],
    hash: &[AtomicU32],
    photon: &Photon,
) {
    if let Some(word) = photon_entry(params, counters, photon) {
        hash[word + full_word::COUNT].fetch_add(1, Relaxed);
    }
}

/// Counting sort, second step: every entry's list start (block-local, in its START word) and
/// the blocks' offsets, as `full_scan_blocks` and `full_scan_totals` compute them
/// (`render::density::scan_counts`): the blocks in parallel, then their totals.
pub fn full_scan(hash: &[AtomicU32]) -> Vec<u32> {
    let totals: Vec<u32> = hash
        .par_chunks(HASH_ENTRY_WORDS * SCAN_BLOCK as usize)
        .map(|block| {
            let mut running = 0;
            for entry in block.chunks(HASH_ENTRY_WORDS) {
                entry[full_word::START].store(running, Relaxed);
                running += entry[full_word::COUNT].load(Relaxed);
            }
            running
        })
        .collect();
    let mut total = 0;
    totals
        .into_iter()
        .map(|block_total| {
            let offset = total;
            total += block_total;
            offset
        })
        .collect()
}

/// Where an entry's list begins in the photon order.
fn list_start(hash: &[AtomicU32], block_offsets: &[u32], word: usize) -> u32 {
    let entry = (word / HASH_ENTRY_WORDS) as u32;
    block_offsets[(entry / SCAN_BLOCK) as usize] + hash[word + full_word::START].load(Relaxed)
}

/// Counting sort, last step, photon `index`: it takes the next place in its entry's list.
/// Places within a list go in whatever order the photons arrive (on both backends).
pub fn full_scatter(
    params: &SppmParams,
    counters: &[AtomicU32],
    hash: &[AtomicU32],
    block_offsets: &[u32],
    order: &[AtomicU32],
    index: u32,
    photon: &Photon,
) {
    if let Some(word) = photon_entry(params, counters, photon) {
        let place = hash[word + full_word::FILL].fetch_add(1, Relaxed);
        order[(list_start(hash, block_offsets, word) + place) as usize].store(index, Relaxed);
    }
}

/// Puts every list's photons in index order, as a scatter in photon order leaves them: a
/// parallel scatter fills each list in arrival order, and with its lists sorted the gather sums
/// the same photons in the same order every run, so the CPU backend's images are reproducible.
/// Most lists hold a photon or two.
pub fn sort_lists(hash: &[AtomicU32], block_offsets: &[u32], order: &[AtomicU32]) {
    hash.par_chunks(HASH_ENTRY_WORDS * SCAN_BLOCK as usize)
        .zip(block_offsets)
        .for_each(|(block, &offset)| {
            let mut list = Vec::new();
            for entry in block.chunks(HASH_ENTRY_WORDS) {
                let count = entry[full_word::COUNT].load(Relaxed);
                if count < 2 {
                    continue;
                }
                let start = (offset + entry[full_word::START].load(Relaxed)) as usize;
                let places = &order[start..start + count as usize];
                list.clear();
                list.extend(places.iter().map(|place| place.load(Relaxed)));
                list.sort_unstable();
                for (place, &index) in places.iter().zip(&list) {
                    place.store(index, Relaxed);
                }
            }
        });
}

/// The full hash's query: every photon listed in each distinct entry the sphere overlaps.
pub fn full_query(
    params: &SppmParams,
    hash: &[AtomicU32],
    block_offsets: &[u32],
    order: &[AtomicU32],
    photons: &[Photon],
    query: &GatherQuery,
) -> GatherSum {
    full_query_with(params, hash, block_offsets, query, |place| {
        &photons[order[place as usize].load(Relaxed) as usize]
    })
}

/// The photons in list order (`listed[place]` is `photons[order[place]]`), which the CPU
/// backend's gather reads one list after another from contiguous memory.
pub fn list_photons(order: &[AtomicU32], photons: &[Photon], listed: &mut Vec<Photon>) {
    listed.clear();
    listed.par_extend(
        order
            .par_iter()
            .map(|index| photons[index.load(Relaxed) as usize]),
    );
}

/// [`full_query`] from the photons in list order ([`list_photons`]): the same sum, in the
/// same order.
pub fn full_query_listed(
    params: &SppmParams,
    hash: &[AtomicU32],
    block_offsets: &[u32],
    listed: &[Photon],
    query: &GatherQuery,
) -> GatherSum {
    full_query_with(params, hash, block_offsets, query, |place| {
        &listed[place as usize]
    })
}

/// The full hash's query with the photon at each list place from `photon_at`.
fn full_query_with<'a>(
    params: &SppmParams,
    hash: &[AtomicU32],
    block_offsets: &[u32],
    query: &GatherQuery,
    photon_at: impl Fn(u32) -> &'a Photon,
) -> GatherSum {
    let listed_in = |entry: u32| {
        let word = entry as usize * HASH_ENTRY_WORDS;
        let start = list_start(hash, block_offsets, word);
        start..start + hash[word + full_word::COUNT].load(Relaxed)
    };
    let mut sum = GatherSum::default();
    if query.volume.is_some() {
        // The volume photons' finer grid, cell by cell: each photon counted in its own cell
        // only, where two cells share an entry (`render::hash::volume_query_cells`).
        let (position, radius, cell_size) = (query.position, query.reach(), query.cell_size);
        for (cell, entry) in volume_query_entries(position, radius, cell_size, params.hash_size) {
            for place in listed_in(entry) {
                let photon = photon_at(place);
                if lies_in(vec3(photon.position), cell, cell_size) {
                    sum.add_if_near(query, photon, 1);
                }
            }
        }
        return sum;
    }
    let (entries, count) = query_entries(
        query.position,
        query.reach(),
        query.grid(),
        params.hash_size,
    );
    for &entry in &entries[..count] {
        for place in listed_in(entry) {
            sum.add_if_near(query, photon_at(place), 1);
        }
    }
    sum
}

#[cfg(test)]
mod tests {
    use super::*;
    use render::buffers::{counter, initial_counters};
    use render::density::scan_counts;

    fn atomics(n: usize) -> Vec<AtomicU32> {
        (0..n).map(|_| AtomicU32::new(0)).collect()
    }

    #[test]
    fn parallel_scan_equals_the_serial_one() {
        let entries = 3 * SCAN_BLOCK as usize + 17;
        let counts: Vec<u32> = (0..entries as u32).map(|i| (i * 7919) % 5).collect();
        let hash = atomics(entries * HASH_ENTRY_WORDS);
        for (entry, &count) in hash.chunks(HASH_ENTRY_WORDS).zip(&counts) {
            entry[full_word::COUNT].store(count, Relaxed);
        }
        let mut starts = vec![0; entries];
        let offsets = scan_counts(&counts, &mut starts);
        assert_eq!(full_scan(&hash), offsets);
        for (entry, start) in hash.chunks(HASH_ENTRY_WORDS).zip(starts) {
            assert_eq!(entry[full_word::START].load(Relaxed), start);
        }
    }

    /// The parallel scatter with its lists sorted leaves the order a scatter in photon order
    /// leaves, on photons crowded into few cells (long lists).
    #[test]
    fn sorted_parallel_scatter_equals_the_serial_scatter() {
        let params = SppmParams {
            hash_size: 300,
            ..SppmParams::default()
        };
        let counters: Vec<AtomicU32> = initial_counters(0.05, 0.05, 0.05)
            .into_iter()
            .map(AtomicU32::new)
            .collect();
        let photons: Vec<Photon> = (0..5000u32)
            .map(|i| Photon {
                position: [
                    (i * 7919 % 1000) as f32 / 1000.0,
                    (i * 104_729 % 1000) as f32 / 2000.0,
                    (i % 7) as f32 * 0.01,
                ],
                flux: if i % 11 == 0 { [0.0; 3] } else { [1.0; 3] },
                ..Photon::default()
            })
            .collect();
        let build = |parallel: bool| {
            let hash = atomics(params.hash_size as usize * HASH_ENTRY_WORDS);
            photons
                .par_iter()
                .for_each(|p| full_count(&params, &counters, &hash, p));
            let offsets = full_scan(&hash);
            let order = atomics(photons.len());
            let scatter = |(i, p): (usize, &Photon)| {
                full_scatter(&params, &counters, &hash, &offsets, &order, i as u32, p)
            };
            if parallel {
                photons.par_iter().enumerate().for_each(scatter);
                sort_lists(&hash, &offsets, &order);
            } else {
                photons.iter().enumerate().for_each(scatter);
            }
            order.iter().map(|o| o.load(Relaxed)).collect::<Vec<u32>>()
        };
        let serial = build(false);
        assert!(serial.iter().any(|&i| i > 0));
        assert_eq!(build(true), serial);

        // The gather from the photons in list order finds the same sums.
        let hash = atomics(params.hash_size as usize * HASH_ENTRY_WORDS);
        for p in &photons {
            full_count(&params, &counters, &hash, p);
        }
        let offsets = full_scan(&hash);
        let order: Vec<AtomicU32> = atomics(photons.len());
        for (i, p) in photons.iter().enumerate() {
            full_scatter(&params, &counters, &hash, &offsets, &order, i as u32, p);
        }
        let mut listed = Vec::new();
        list_photons(&order, &photons, &mut listed);
        let cell_size = f32::from_bits(counters[counter::CELL_SIZE].load(Relaxed));
        let mut found = 0;
        for i in 0..200u32 {
            let query = GatherQuery {
                volume: None,
                position: glam::Vec3::new(i as f32 / 200.0, 0.25, 0.03),
                normal: glam::Vec3::Z,
                radius: 0.05,
                caustic_radius: 0.03,
                cell_size,
                caustic_cell_size: cell_size,
            };
            let sum = full_query(&params, &hash, &offsets, &order, &photons, &query);
            assert_eq!(
                full_query_listed(&params, &hash, &offsets, &listed, &query),
                sum
            );
            found += sum.found;
        }
        assert!(found > 100, "{found} photons found");
    }
}
