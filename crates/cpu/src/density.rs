//! The density-estimation methods benchmarks compare with the stochastic hash (issue 6,
//! table 4), twins of `shaders/shared/density_full.wgsl`: the full spatial hash, whose table
//! entries list every photon hashed to them, built by a counting sort (count, prefix sum,
//! scatter) as the GPU builds it.

use std::sync::atomic::{AtomicU32, Ordering::Relaxed};

use render::buffers::{HASH_ENTRY_WORDS, Photon, SppmParams, counter, vec3};
use render::density::{SCAN_BLOCK, full_word, scan_counts};
use render::hash::{cell_of, entry_of, query_entries};

use crate::kernels::{GatherQuery, GatherSum};

/// The first table word of the entry a stored photon hashes to this pass; `None` if the slot
/// stored no photon.
pub fn photon_entry(params: &SppmParams, counters: &[AtomicU32], photon: &Photon) -> Option<usize> {
    if !photon.is_stored() {
        return None;
    }
    let cell_size = f32::from_bits(counters[counter::CELL_SIZE].load(Relaxed));
    let cell = cell_of(vec3(photon.position), cell_size);
    Some(entry_of(cell, params.hash_size) as usize * HASH_ENTRY_WORDS)
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
/// the blocks' offsets, as `full_scan_blocks` and `full_scan_totals` compute them.
pub fn full_scan(hash: &[AtomicU32]) -> Vec<u32> {
    let counts: Vec<u32> = hash
        .chunks(HASH_ENTRY_WORDS)
        .map(|entry| entry[full_word::COUNT].load(Relaxed))
        .collect();
    let mut starts = vec![0; counts.len()];
    let offsets = scan_counts(&counts, &mut starts);
    for (entry, start) in hash.chunks(HASH_ENTRY_WORDS).zip(starts) {
        entry[full_word::START].store(start, Relaxed);
    }
    offsets
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

/// The full hash's query: every photon listed in each distinct entry the sphere overlaps.
pub fn full_query(
    params: &SppmParams,
    hash: &[AtomicU32],
    block_offsets: &[u32],
    order: &[AtomicU32],
    photons: &[Photon],
    query: &GatherQuery,
) -> GatherSum {
    let (entries, count) = query_entries(
        query.position,
        query.radius,
        query.cell_size,
        params.hash_size,
    );
    let mut sum = GatherSum::default();
    for &entry in &entries[..count] {
        let word = entry as usize * HASH_ENTRY_WORDS;
        let start = list_start(hash, block_offsets, word);
        let listed = hash[word + full_word::COUNT].load(Relaxed);
        for place in start..start + listed {
            let photon = &photons[order[place as usize].load(Relaxed) as usize];
            sum.add_if_near(query, photon, 1);
        }
    }
    sum
}
