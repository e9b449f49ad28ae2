//! Lane occupancy of the two photon-tracing schemes: the share of lane time spent tracing a
//! path segment, the talk's figure of threads waiting for the longest path.
//!
//! Lanes run in lockstep groups of `width` consecutive invocations (a SIMD group: 8 on lavapipe
//! with 256-bit vectors, 32 on NVIDIA; or a whole workgroup). In the naive scheme a group runs
//! until its longest path ends, so a lane whose path ended early idles; lanes past the last
//! path in the last group idle throughout. In the asynchronous scheme every slot traces exactly
//! one segment per pass (an ended path is replaced in the same pass), so only those lanes past
//! the last slot idle. Both count segments, not traversal steps: within one segment, rays of a
//! group still diverge in traversal length, in either scheme alike.

/// Naive scheme: Σ segments / Σ over groups of (`width` × the group's longest path), from each
/// invocation's segment count in invocation order. 1 when no lane waits (width 1, or equal
/// lengths in every full group); 1 for no paths.
pub fn naive(segments: &[u32], width: usize) -> f64 {
    assert!(width > 0, "a lockstep group has at least one lane");
    let busy: u64 = segments.iter().map(|&s| u64::from(s)).sum();
    let lane_time: u64 = segments
        .chunks(width)
        .map(|group| width as u64 * u64::from(group.iter().copied().max().unwrap_or(0)))
        .sum();
    if lane_time == 0 {
        return 1.0;
    }
    busy as f64 / lane_time as f64
}

/// Asynchronous scheme: `slots` / (groups × `width`), groups = ⌈slots / width⌉.
pub fn asynchronous(slots: u32, width: u32) -> f64 {
    assert!(width > 0, "a lockstep group has at least one lane");
    if slots == 0 {
        return 1.0;
    }
    f64::from(slots) / (u64::from(slots.div_ceil(width)) * u64::from(width)) as f64
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn naive_occupancy_counts_lanes_waiting_for_their_groups_longest_path() {
        let segments = [1, 1, 1, 4, 2, 2, 2, 2];
        // One group of 8: 15 segments in 8 lanes × 4.
        assert_eq!(naive(&segments, 8), 15.0 / 32.0);
        // Groups of 4: (1+1+1+4) / (4 × 4) and 8 / (4 × 2).
        assert_eq!(naive(&segments, 4), 15.0 / 24.0);
        // Groups of 2: 2/2, 5/8, 4/4, 4/4.
        assert_eq!(naive(&segments, 2), 15.0 / 18.0);
        // Lanes alone never wait.
        assert_eq!(naive(&segments, 1), 1.0);
        // Equal lengths keep every lane busy.
        assert_eq!(naive(&[3; 16], 8), 1.0);
    }

    #[test]
    fn naive_occupancy_counts_lanes_past_the_last_path_as_idle() {
        // Groups of 2 over 3 paths: (2+2) / (2 × 2) and 2 / (2 × 2).
        assert_eq!(naive(&[2, 2, 2], 2), 0.75);
        assert_eq!(naive(&[], 8), 1.0);
    }

    #[test]
    fn asynchronous_occupancy_idles_only_the_lanes_past_the_last_slot() {
        assert_eq!(asynchronous(4096, 64), 1.0);
        assert_eq!(asynchronous(4096, 8), 1.0);
        assert_eq!(asynchronous(100, 64), 100.0 / 128.0);
        assert_eq!(asynchronous(7, 1), 1.0);
    }
}
