//! How each pass's photons are found around the visible points (DESIGN.md, "Stochastic hash";
//! issue 6, table 4). The stochastic spatial hash is kousen's; the full spatial hash and the
//! kd-tree exist to measure it against (`kousen bench density`).

/// The density-estimation method of a render.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Density {
    /// One uniformly picked photon per table entry, weighted by the entry's count.
    #[default]
    StochasticHash,
    /// Every photon, in per-entry lists built by a counting sort (count, prefix sum, scatter).
    FullHash,
    /// A kd-tree over the pass's photons, built on the CPU (`render::kdtree`).
    KdTree,
}

impl Density {
    pub const ALL: [Density; 3] = [Density::StochasticHash, Density::FullHash, Density::KdTree];

    /// The name benchmarks print ("stochastic", "full", "kdtree").
    pub fn name(self) -> &'static str {
        match self {
            Density::StochasticHash => "stochastic",
            Density::FullHash => "full",
            Density::KdTree => "kdtree",
        }
    }
}

/// The full hash's table words per entry (the stochastic hash's three words, other meanings):
/// the entry's list start within its scan block, its photon count, and the scatter's fill
/// cursor.
pub mod full_word {
    pub const START: usize = 0;
    pub const COUNT: usize = 1;
    pub const FILL: usize = 2;
}

/// Entries per block of the full hash's prefix sum (one GPU workgroup each): an entry's list
/// begins at its block's offset plus its start within the block.
pub const SCAN_BLOCK: u32 = 256;

/// Blocks of the prefix sum over `hash_size` entries.
pub fn scan_blocks(hash_size: u32) -> u32 {
    hash_size.div_ceil(SCAN_BLOCK)
}

/// The full hash's prefix sum, as the GPU computes it: each block's counts scanned exclusively
/// into `starts` (block-local), and the blocks' totals scanned exclusively into the returned
/// block offsets.
pub fn scan_counts(counts: &[u32], starts: &mut [u32]) -> Vec<u32> {
    let mut offsets = Vec::with_capacity(counts.len().div_ceil(SCAN_BLOCK as usize));
    let mut total = 0u32;
    for (block, out) in counts
        .chunks(SCAN_BLOCK as usize)
        .zip(starts.chunks_mut(SCAN_BLOCK as usize))
    {
        offsets.push(total);
        let mut running = 0u32;
        for (&count, start) in block.iter().zip(out) {
            *start = running;
            running += count;
        }
        total += running;
    }
    offsets
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn scan_gives_every_entry_its_own_range() {
        let counts: Vec<u32> = (0..1000u32).map(|i| (i * 7919) % 5).collect();
        let mut starts = vec![0; counts.len()];
        let offsets = scan_counts(&counts, &mut starts);
        assert_eq!(offsets.len(), scan_blocks(1000) as usize);
        let mut expected = 0;
        for (i, &count) in counts.iter().enumerate() {
            let start = offsets[i / SCAN_BLOCK as usize] + starts[i];
            assert_eq!(start, expected, "entry {i}");
            expected += count;
        }
    }
}
