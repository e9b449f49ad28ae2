//! The radius the next pass's surface cells are sized for (`crate::hash`: cells of side
//! ≥ 2·R serve gathers of radius up to R), from the radii of the pixels that have met photons.
//!
//! With full lists or the kd-tree the cells' size costs time only, and they serve every lit
//! radius: the largest. The stochastic hash keeps one photon a cell, weighted by the cell's
//! count, so the larger a cell against a gather's disc, the rarer and heavier the photon
//! that falls in the disc: its variance grows with the cell's area over the disc's. The
//! largest radius belongs to a few pixels that meet photons seldom (dark corners), while most
//! have shrunk well below it (cornell-caustics at 128², pass 200: median 3.8, 90th percentile
//! 4.4, largest 7.4), so the stochastic hash sizes its cells for eight tenths of the lit
//! radii, and the largest two tenths shrink to fit, their flux scaled with the area (the SPPM
//! update's own rule). The cells still serve every radius gathered with, as DESIGN.md asks.
//! Measured (docs/BENCHMARKS.md §3, session 45): at equal passes the caustic and indirect
//! parts' errors fall 5–20 %, the image's up to 9 %; one tenth gained about half as much,
//! five tenths traded indirect error for caustic.
//!
//! The radii are counted in a histogram of buckets 1/8 octave wide below the largest radius
//! the current cells serve (a float's exponent and top three mantissa bits), added to by
//! each lit pixel and read by the pass's closing invocation: integers, so both backends
//! reach the same bucket, whatever order the pixels come in.

/// Buckets of the histogram: 8 octaves below the largest radius served (radii further below
/// count in the last).
pub const RADIUS_BUCKETS: usize = 64;

/// The bits of a float from its mantissa's top three: one step of the bucket key.
const KEY_SHIFT: u32 = 20;

/// Tenths of the lit radii the stochastic hash's cells may leave above the radius they serve,
/// to shrink to fit (`SppmParams::shrunk_tenths`); full lists and the kd-tree leave none.
pub const STOCHASTIC_SHRUNK_TENTHS: u32 = 2;

/// The bucket of a lit radius `radius` ≤ `largest`, the largest radius this pass's cells serve:
/// 0 for the top eighth of an octave, one more for each eighth below.
pub fn radius_bucket(radius: f32, largest: f32) -> u32 {
    let steps = (largest.to_bits() >> KEY_SHIFT).saturating_sub(radius.to_bits() >> KEY_SHIFT);
    steps.min(RADIUS_BUCKETS as u32 - 1)
}

/// The largest radius bucket `bucket` holds below `largest` (bucket 0: `largest` itself).
pub fn bucket_top(bucket: u32, largest: f32) -> f32 {
    let key = (largest.to_bits() >> KEY_SHIFT).saturating_sub(bucket);
    f32::from_bits(((key + 1) << KEY_SHIFT) - 1).min(largest)
}

/// The radius the next pass's cells serve: the top of the bucket holding the radius above
/// which no more than `shrunk_tenths` tenths of the `histogram`'s radii lie, and no more
/// than `largest_lit`, the largest of them. `None` where no pixel has met a photon.
pub fn served_radius(
    histogram: &[u32; RADIUS_BUCKETS],
    shrunk_tenths: u32,
    largest: f32,
    largest_lit: f32,
) -> Option<f32> {
    let total: u32 = histogram.iter().sum();
    if total == 0 || largest_lit <= 0.0 {
        return None;
    }
    // Radii allowed above the one served (u64: a count times ten overflows u32 past 4e8).
    let above = (total as u64 * shrunk_tenths.min(10) as u64 / 10) as u32;
    let mut counted = 0;
    let mut bucket = RADIUS_BUCKETS as u32 - 1;
    for (b, &count) in histogram.iter().enumerate() {
        counted += count;
        if counted > above {
            bucket = b as u32;
            break;
        }
    }
    Some(bucket_top(bucket, largest).min(largest_lit))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Buckets are eighths of an octave below the largest radius: the largest in bucket 0, half
    /// of it in bucket 8; each bucket's top lies in it, and the next bucket starts just below.
    #[test]
    fn buckets_step_down_by_eighths_of_an_octave() {
        let largest = 7.36f32;
        assert_eq!(radius_bucket(largest, largest), 0);
        assert_eq!(radius_bucket(largest / 2.0, largest), 8);
        assert_eq!(radius_bucket(largest / 4.0, largest), 16);
        assert_eq!(radius_bucket(1e-30, largest), RADIUS_BUCKETS as u32 - 1);
        assert_eq!(bucket_top(0, largest), largest);
        for bucket in 1..RADIUS_BUCKETS as u32 {
            let top = bucket_top(bucket, largest);
            assert_eq!(radius_bucket(top, largest), bucket, "bucket {bucket}");
            let above = f32::from_bits(top.to_bits() + 1);
            assert_eq!(radius_bucket(above, largest), bucket - 1, "bucket {bucket}");
        }
        // An eighth of an octave each: the tops fall by 2^(1/8) on average.
        let ratio = bucket_top(8, largest) / bucket_top(16, largest);
        assert!((ratio - 2.0).abs() < 1e-5, "{ratio}");
    }

    /// One tenth shrunk: the radius below which at least nine tenths lie (rounded up to its
    /// bucket's top); none shrunk: the largest lit radius exactly; none lit: none.
    #[test]
    fn the_served_radius_leaves_the_largest_tenth_above_it() {
        let largest = 8.0f32;
        let mut histogram = [0u32; RADIUS_BUCKETS];
        // 100 radii: 5 in bucket 2, 10 in bucket 5, 85 in bucket 12.
        histogram[2] = 5;
        histogram[5] = 10;
        histogram[12] = 85;
        let largest_lit = bucket_top(2, largest) * 0.99;
        let served = |tenths| served_radius(&histogram, tenths, largest, largest_lit);
        // 10 may lie above: the 5 of bucket 2 and 5 of bucket 5's 10, so bucket 5 is served.
        assert_eq!(served(1), Some(bucket_top(5, largest)));
        // 20 may: all of buckets 2 and 5 (15), so bucket 12.
        assert_eq!(served(2), Some(bucket_top(12, largest)));
        assert_eq!(served(0), Some(largest_lit));
        assert_eq!(served_radius(&[0; RADIUS_BUCKETS], 1, largest, 0.0), None);
        // Never above the largest lit radius, though its bucket's top is.
        histogram = [0; RADIUS_BUCKETS];
        histogram[3] = 1;
        let lit = bucket_top(3, largest) * 0.999;
        assert_eq!(served_radius(&histogram, 1, largest, lit), Some(lit));
    }
}
