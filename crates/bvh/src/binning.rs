//! Binned SAH split search (Wald, "On fast construction of SAH-based bounding volume
//! hierarchies", 2007).
//!
//! The centres of the triangles' boxes fall into `bins` equal-width slots along each axis of the
//! node's centre bounds; each bin keeps the union of its boxes and their count. A sweep from both
//! ends then prices every plane between two bins at `SA(left)·N(left) + SA(right)·N(right)`.
//! Big nodes are binned in parallel (one bin set per chunk, then merged). The partition that
//! follows must send each triangle to the side its bin says, so both use [`BinMapper::bins`].

use glam::{UVec3, Vec3A};
use rayon::prelude::*;

use crate::aabb::Aabb;

/// Nodes with at least this many triangles are binned by several threads.
const PARALLEL_BINNING_MIN: usize = 1 << 15;
/// Triangles per parallel binning task.
const PARALLEL_BINNING_CHUNK: usize = 1 << 13;

/// Maps a box centre to its bin on each axis.
#[derive(Clone, Copy, Debug)]
pub(crate) struct BinMapper {
    /// Lower corner of the centre bounds.
    origin: Vec3A,
    /// Bins per unit length on each axis; 0 on an axis where all centres coincide.
    scale: Vec3A,
    /// Index of the last bin, as a float for clamping.
    last: Vec3A,
    /// Bins per axis.
    pub count: usize,
}

impl BinMapper {
    pub fn new(centers: &Aabb, bins: usize) -> BinMapper {
        let scale = (bins as f32 / centers.extent())
            .to_array()
            .map(|s| if s.is_finite() && s > 0.0 { s } else { 0.0 });
        BinMapper {
            origin: centers.min,
            scale: Vec3A::from_array(scale),
            last: Vec3A::splat((bins - 1) as f32),
            count: bins,
        }
    }

    /// Bin index of `center` along x, y and z.
    #[inline]
    pub fn bins(&self, center: Vec3A) -> UVec3 {
        // `as u32` saturates, so a centre below `origin` (impossible) would land in bin 0.
        ((center - self.origin) * self.scale)
            .min(self.last)
            .as_uvec3()
    }
}

/// One bin on one axis.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Bin {
    /// Union of the boxes whose centre fell here.
    bounds: Aabb,
    /// How many did.
    count: u32,
}

impl Bin {
    const EMPTY: Bin = Bin {
        bounds: Aabb::EMPTY,
        count: 0,
    };
}

/// Per-thread memory reused from node to node, so no node allocates.
pub(crate) struct Scratch {
    /// `3 × bins` bins, axis-major, for up to `capacity` bins per axis.
    bins: Vec<Bin>,
    /// Right-side sweep result: `SA·N` of bins `[i, bins)`.
    right_cost: Vec<f32>,
}

impl Scratch {
    /// Room for up to `capacity` bins per axis.
    pub fn new(capacity: usize) -> Scratch {
        Scratch {
            bins: vec![Bin::EMPTY; 3 * capacity],
            right_cost: vec![0.0; capacity],
        }
    }
}

/// The cheapest plane found: triangles whose bin on `axis` is below `bin` go left.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Split {
    /// Axis of the plane (0 = x).
    pub axis: usize,
    /// First bin on the right side.
    pub bin: u32,
    /// `SA(left)·N(left) + SA(right)·N(right)`, with half areas.
    pub cost: f32,
    /// Box of the left side.
    pub left: Aabb,
    /// Box of the right side.
    pub right: Aabb,
    /// Triangles on the left side.
    pub left_count: usize,
}

/// The best split of `boxes` into `mapper`'s bins (at most the scratch's capacity), or `None`
/// when every centre falls in one bin on every axis.
pub(crate) fn find_split(
    boxes: &[Aabb],
    mapper: &BinMapper,
    scratch: &mut Scratch,
) -> Option<Split> {
    let bins = mapper.count;
    if boxes.len() >= PARALLEL_BINNING_MIN {
        let merged = boxes
            .par_chunks(PARALLEL_BINNING_CHUNK)
            .fold(
                || vec![Bin::EMPTY; 3 * bins],
                |mut acc, chunk| {
                    fill_bins(chunk, mapper, bins, &mut acc);
                    acc
                },
            )
            .reduce_with(merge_bins)
            .expect("a big node has chunks");
        scratch.bins[..3 * bins].copy_from_slice(&merged);
    } else {
        scratch.bins[..3 * bins].fill(Bin::EMPTY);
        fill_bins(boxes, mapper, bins, &mut scratch.bins[..3 * bins]);
    }
    (0..3)
        .filter_map(|axis| sweep_axis(scratch, bins, axis))
        .min_by(|a, b| a.cost.total_cmp(&b.cost))
}

fn fill_bins(boxes: &[Aabb], mapper: &BinMapper, bins: usize, out: &mut [Bin]) {
    let (x, rest) = out.split_at_mut(bins);
    let (y, z) = rest.split_at_mut(bins);
    for b in boxes {
        let k = mapper.bins(b.center());
        for (axis_bins, i) in [(&mut *x, k.x), (&mut *y, k.y), (&mut *z, k.z)] {
            let bin = &mut axis_bins[i as usize];
            bin.bounds = bin.bounds.union(*b);
            bin.count += 1;
        }
    }
}

fn merge_bins(mut a: Vec<Bin>, b: Vec<Bin>) -> Vec<Bin> {
    for (x, y) in a.iter_mut().zip(&b) {
        x.bounds = x.bounds.union(y.bounds);
        x.count += y.count;
    }
    a
}

/// Prices the `bins - 1` planes of one axis and returns the cheapest that leaves both sides
/// non-empty.
fn sweep_axis(scratch: &mut Scratch, bins: usize, axis: usize) -> Option<Split> {
    let axis_bins = &scratch.bins[axis * bins..(axis + 1) * bins];
    let mut right = Aabb::EMPTY;
    let mut right_count = 0u32;
    for i in (1..bins).rev() {
        right = right.union(axis_bins[i].bounds);
        right_count += axis_bins[i].count;
        scratch.right_cost[i] = right.half_area() * right_count as f32;
    }
    let total: u32 = axis_bins.iter().map(|b| b.count).sum();
    let mut left = Aabb::EMPTY;
    let mut left_count = 0u32;
    let mut best: Option<(u32, f32, Aabb, u32)> = None;
    for i in 1..bins {
        left = left.union(axis_bins[i - 1].bounds);
        left_count += axis_bins[i - 1].count;
        if left_count == 0 || left_count == total {
            continue;
        }
        let cost = left.half_area() * left_count as f32 + scratch.right_cost[i];
        if best.is_none_or(|(_, c, _, _)| cost < c) {
            best = Some((i as u32, cost, left, left_count));
        }
    }
    let (bin, cost, left, left_count) = best?;
    let right = axis_bins[bin as usize..]
        .iter()
        .fold(Aabb::EMPTY, |acc, b| acc.union(b.bounds));
    Some(Split {
        axis,
        bin,
        cost,
        left,
        right,
        left_count: left_count as usize,
    })
}
