//! The compact MTBVH ("mtbvh16"): the same tree and the same six threadings as
//! [`PackedBvh`], in one 32-byte record per node with 16-bit boxes and 16-bit links.
//!
//! # Record (one per node, 32 bytes, read as two `vec4<u32>`)
//! ```text
//! bounds_and_meta[0]  min.x | min.y << 16      quantised box, 16 bits per coordinate
//! bounds_and_meta[1]  min.z | max.x << 16
//! bounds_and_meta[2]  max.y | max.z << 16
//! bounds_and_meta[3]  meta: bit 31 leaf, bit 30 far;
//!                     leaf: bits 0..30 = triangle count; internal: bit d = direction d
//!                     visits the right child first
//! links[0]            leaf: first triangle; internal: right child (the left is index + 1)
//! links[1..4]         the six directions' miss links, 16 bits each (direction 2k in the low
//!                     half of links[1 + k]): signed offsets from the node, 0 = LINK_END;
//!                     a far node (bit 30) instead keeps in links[1] the index of its far
//!                     record, whose eight words hold the six links as absolute u32 indices
//!                     (bounds_and_meta[0..4] = directions 0..3, links[0..2] = 4, 5)
//! ```
//! Far records follow the nodes in the same array.
//!
//! **Boxes.** Per axis, a coordinate is `origin + q · scale` with `q` in `0..=65535` and
//! `scale = m · 2^k`, `m < 256` ([`CompactFrame`]): the smallest such step that spans the scene's
//! box, within 1/128 of `extent / 65535`. `q · m < 2^24`, so `q · scale` is exact and the
//! decoded value is one rounding of `origin + q · scale`, the same whether a shader compiler
//! fuses the multiply-add or not: the GPU and this CPU twin decode identical boxes. `origin` is
//! the scene box's corner rounded down to a multiple of `2^k` (exact in f32), so every decoded
//! value is a multiple of `2^k ≥ 2^-100` and none is a denormal.
//! Each box is rounded outward — the largest `q` whose decoded value is ≤ the exact minimum,
//! the smallest whose decoded value is ≥ the exact maximum — so the decoded box contains the
//! exact one. The slab test is monotonic in the box, so the compact traversal visits every node
//! the exact MTBVH visits (and a few more) in the same order, and returns the same closest hit;
//! the only exceptions are hits that rounding puts outside their own triangle's box
//! ([`crate::testing::is_fragile_hit`]), which the larger boxes may reach where the exact ones
//! do not.
//!
//! **Links.** A hit link needs no storage: an internal node's is one of its children (bit `d`
//! of `meta` says which), a leaf's equals its miss link. A miss link is the next subtree
//! after the node's, usually near it in the depth-first array: it is stored as a 16-bit offset
//! whenever it fits in `-32768..=32767`. Otherwise the node is "far" and its six links live
//! in a far record of full u32 indices, so every scene size is handled — Crytek Sponza needs
//! far records for 445 of its 286,499 nodes (leaves of ≤ 2).
//!
//! **Why one record.** Every step of the traversal reads the node's box, its kind and one link:
//! here one aligned 32-byte read (one memory sector on GPUs that fetch 32-byte sectors), where
//! the exact MTBVH reads a 32-byte node and an 8-byte link pair from two arrays. Splitting off
//! per-direction link arrays would save 4 bytes a node (12 bytes of links per record of which a
//! ray uses 2) at the price of a second dependent read per step.
//!
//! Memory per node: 32 bytes against the exact MTBVH's 32 + 6 × 8 = 80 (the TBVH's 40); see
//! [`CompactMtbvh::memory`].

use std::fmt;
use std::mem::size_of;

use bytemuck::{Pod, Zeroable};
use glam::Vec3;
use rayon::prelude::*;

use crate::intersect::{Hit, Ray, SlabRay, intersect_box};
use crate::mtbvh::{DIRECTION_COUNT, LINK_END};
use crate::pack::{BvhNode, PackedBvh, PackedTriangle, direction_index};
use crate::traverse::{Query, Uncounted, WorkTally, every_hit, test_leaf};

/// `meta` bit: the node is a leaf.
pub const COMPACT_LEAF: u32 = 1 << 31;
/// `meta` bit: the node's links are in a far record (`links[1]` is its index).
pub const COMPACT_FAR: u32 = 1 << 30;
/// `meta` bits of a leaf's triangle count.
pub const COMPACT_COUNT_MASK: u32 = COMPACT_FAR - 1;
/// Largest quantised coordinate.
pub const QUANTIZED_MAX: u32 = 0xffff;
/// Largest magnitude of a box coordinate the quantisation accepts (2^120): below it every
/// decoded coordinate is finite.
pub const MAX_COORDINATE: f32 = f32::from_bits((127 + 120) << 23);
/// Smallest exponent `k` of `scale = m · 2^k`: finer steps are never needed, and with it no
/// decoded value is a denormal.
const MIN_SCALE_EXPONENT: i32 = -100;
/// Largest exponent `k`: `65535 · 255 · 2^103 < 2^127` is finite.
const MAX_SCALE_EXPONENT: i32 = 103;
/// Bound on the significand `m` of `scale = m · 2^k`: `65535 · m < 2^24`, so `q · scale` is
/// exact.
const SCALE_SIGNIFICAND_END: u32 = 256;

/// One node of the compact MTBVH, or a far record (32 bytes); see the module's documentation
/// for the words.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Pod, Zeroable)]
pub struct CompactNode {
    /// The quantised box in words 0..3, `meta` in word 3.
    pub bounds_and_meta: [u32; 4],
    /// The right child or first triangle in word 0, the miss links in words 1..4.
    pub links: [u32; 4],
}

const _: () = assert!(size_of::<CompactNode>() == 32);

/// The quantisation frame and where traversal starts (32 bytes, a uniform on the GPU).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct CompactFrame {
    /// Per axis, the decoded value of `q = 0`.
    pub origin: [f32; 3],
    /// First node: 0, or [`LINK_END`] for an empty tree.
    pub root: u32,
    /// Per axis, one step of `q`: `m · 2^k` with `m < 256`.
    pub scale: [f32; 3],
    /// Number of nodes (the far records follow them).
    pub node_count: u32,
}

const _: () = assert!(size_of::<CompactFrame>() == 32);

/// Why a tree cannot be compacted.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum CompactError {
    /// A coordinate's magnitude is above [`MAX_COORDINATE`].
    CoordinatesTooLarge(f32),
    /// A leaf holds more triangles than `meta` can count ([`COMPACT_COUNT_MASK`]).
    LeafTooLarge(u32),
}

impl fmt::Display for CompactError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            CompactError::CoordinatesTooLarge(c) => write!(
                f,
                "a BVH coordinate ({c:e}) is too large for 16-bit boxes (at most {MAX_COORDINATE:e})"
            ),
            CompactError::LeafTooLarge(n) => write!(
                f,
                "a BVH leaf holds {n} triangles, more than the compact layout counts ({COMPACT_COUNT_MASK})"
            ),
        }
    }
}

impl std::error::Error for CompactError {}

/// Device memory of a [`CompactMtbvh`] with its triangles, in bytes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct CompactMemory {
    /// Packed triangles (shared with [`PackedBvh`]).
    pub triangle_bytes: usize,
    /// One record per node.
    pub node_bytes: usize,
    /// Far records.
    pub far_bytes: usize,
    /// The frame.
    pub frame_bytes: usize,
    /// All of the above.
    pub total_bytes: usize,
}

/// A [`PackedBvh`]'s nodes and six threadings in the compact layout; the triangles stay in
/// the [`PackedBvh`].
#[derive(Clone, Debug, Default, PartialEq)]
pub struct CompactMtbvh {
    /// `frame.node_count` node records, then the far records.
    pub records: Vec<CompactNode>,
    /// Quantisation and root.
    pub frame: CompactFrame,
}

/// `origin + q · scale`: the decoding the shader does, with `q · scale` exact.
#[inline]
fn decode(origin: f32, scale: f32, q: u32) -> f32 {
    origin + q as f32 * scale
}

/// Per axis, `(origin, scale)` for the range `lo..=hi`: the smallest `scale = m · 2^k`
/// (`m < 256`, `k ≥ MIN_SCALE_EXPONENT`) such that `decode(65535) ≥ hi`, where `origin` is `lo`
/// rounded down to a multiple of `2^k`.
fn axis_frame(lo: f32, hi: f32) -> Option<(f32, f32)> {
    let step = (f64::from(hi) - f64::from(lo)) / f64::from(QUANTIZED_MAX);
    let half = SCALE_SIGNIFICAND_END / 2;
    // The first candidate: m · 2^k just at or below the step, m in half..256.
    let (mut k, mut m) = if step > 0.0 {
        let k = step.log2().floor() as i32 - half.ilog2() as i32;
        (k, (step / 2f64.powi(k)).floor().max(1.0) as u32)
    } else {
        (MIN_SCALE_EXPONENT, half)
    };
    if k < MIN_SCALE_EXPONENT {
        (k, m) = (MIN_SCALE_EXPONENT, half);
    }
    while k <= MAX_SCALE_EXPONENT {
        if m >= SCALE_SIGNIFICAND_END {
            (k, m) = (k + 1, half);
            continue;
        }
        let unit = 2f64.powi(k);
        let origin = (f64::from(lo) / unit).floor() * unit;
        // Exact: either lo is already a multiple of the unit, or origin / unit is an integer
        // below 2^24 in magnitude.
        debug_assert_eq!(f64::from(origin as f32), origin);
        let (origin, scale) = (origin as f32, (f64::from(m) * unit) as f32);
        let top = decode(origin, scale, QUANTIZED_MAX);
        if top.is_finite() && top >= hi {
            return Some((origin, scale));
        }
        m += 1;
    }
    None
}

/// The largest `q` with `decode(q) ≤ x` (0 if none: `decode(0)` is the scene's lower bound).
fn quantize_down(origin: f32, scale: f32, x: f32) -> u32 {
    let guess = ((f64::from(x) - f64::from(origin)) / f64::from(scale))
        .floor()
        .clamp(0.0, f64::from(QUANTIZED_MAX)) as u32;
    let fits = |q: u32| decode(origin, scale, q) <= x;
    if fits(guess) && (guess == QUANTIZED_MAX || !fits(guess + 1)) {
        return guess;
    }
    // decode is monotonic in q: binary search for the last q that fits.
    let (mut lo, mut hi) = (0u32, QUANTIZED_MAX + 1);
    while hi - lo > 1 {
        let mid = (lo + hi) / 2;
        if fits(mid) { lo = mid } else { hi = mid }
    }
    lo
}

/// The smallest `q` with `decode(q) ≥ x` (65535 if none; the frame makes that ≥ every box).
fn quantize_up(origin: f32, scale: f32, x: f32) -> u32 {
    let guess = ((f64::from(x) - f64::from(origin)) / f64::from(scale))
        .ceil()
        .clamp(0.0, f64::from(QUANTIZED_MAX)) as u32;
    let fits = |q: u32| decode(origin, scale, q) >= x;
    if fits(guess) && (guess == 0 || !fits(guess - 1)) {
        return guess;
    }
    let (mut lo, mut hi) = (0u32, QUANTIZED_MAX);
    if !fits(hi) {
        return QUANTIZED_MAX;
    }
    // Invariant: fits(hi); binary search for the first q that fits.
    while lo < hi {
        let mid = (lo + hi) / 2;
        if fits(mid) { hi = mid } else { lo = mid + 1 }
    }
    hi
}

/// A node's miss link as a 16-bit offset (0 = [`LINK_END`]), if it fits.
fn relative_link(node: usize, target: u32) -> Option<u32> {
    if target == LINK_END {
        return Some(0);
    }
    let offset = i64::from(target) - node as i64;
    let offset = i16::try_from(offset).ok()?;
    debug_assert_ne!(offset, 0, "a miss link never points at its own node");
    Some(u32::from(offset as u16))
}

impl CompactMtbvh {
    /// The compact layout of `bvh`'s nodes and six threadings.
    ///
    /// # Errors
    /// When a box coordinate's magnitude passes [`MAX_COORDINATE`], or a leaf holds more than
    /// [`COMPACT_COUNT_MASK`] triangles.
    pub fn new(bvh: &PackedBvh) -> Result<CompactMtbvh, CompactError> {
        let count = bvh.nodes.len();
        let Some(root) = bvh.nodes.first() else {
            return Ok(CompactMtbvh {
                records: Vec::new(),
                frame: CompactFrame {
                    root: LINK_END,
                    scale: [1.0; 3],
                    ..CompactFrame::default()
                },
            });
        };
        for c in root.min.iter().chain(&root.max) {
            if c.abs() > MAX_COORDINATE || !c.is_finite() {
                return Err(CompactError::CoordinatesTooLarge(*c));
            }
        }
        let mut origin = [0.0; 3];
        let mut scale = [0.0; 3];
        for axis in 0..3 {
            let (o, s) = axis_frame(root.min[axis], root.max[axis])
                .ok_or(CompactError::CoordinatesTooLarge(root.max[axis]))?;
            origin[axis] = o;
            scale[axis] = s;
        }
        let links: Vec<_> = (0..DIRECTION_COUNT)
            .map(|d| bvh.direction_links(d))
            .collect();
        let mut records: Vec<CompactNode> = bvh
            .nodes
            .par_iter()
            .enumerate()
            .map(|(index, node)| {
                let q_min: [u32; 3] =
                    std::array::from_fn(|a| quantize_down(origin[a], scale[a], node.min[a]));
                let q_max: [u32; 3] =
                    std::array::from_fn(|a| quantize_up(origin[a], scale[a], node.max[a]));
                let mut meta = if node.triangle_count > 0 {
                    if node.triangle_count > COMPACT_COUNT_MASK {
                        return Err(CompactError::LeafTooLarge(node.triangle_count));
                    }
                    COMPACT_LEAF | node.triangle_count
                } else {
                    let mut mask = 0;
                    for (d, links) in links.iter().enumerate() {
                        let hit = links[index].hit;
                        debug_assert!(hit == index as u32 + 1 || hit == node.first_or_right);
                        mask |= u32::from(hit != index as u32 + 1) << d;
                    }
                    mask
                };
                let relative: [Option<u32>; DIRECTION_COUNT] =
                    std::array::from_fn(|d| relative_link(index, links[d][index].miss));
                let misses = match relative {
                    [Some(r0), Some(r1), Some(r2), Some(r3), Some(r4), Some(r5)] => {
                        [r0 | r1 << 16, r2 | r3 << 16, r4 | r5 << 16]
                    }
                    _ => {
                        meta |= COMPACT_FAR;
                        [0; 3] // the far record's index, set below
                    }
                };
                Ok(CompactNode {
                    bounds_and_meta: [
                        q_min[0] | q_min[1] << 16,
                        q_min[2] | q_max[0] << 16,
                        q_max[1] | q_max[2] << 16,
                        meta,
                    ],
                    links: [node.first_or_right, misses[0], misses[1], misses[2]],
                })
            })
            .collect::<Result<_, _>>()?;
        for index in 0..count {
            if records[index].bounds_and_meta[3] & COMPACT_FAR != 0 {
                records[index].links[1] = records.len() as u32;
                let l: [u32; DIRECTION_COUNT] = std::array::from_fn(|d| links[d][index].miss);
                records.push(CompactNode {
                    bounds_and_meta: [l[0], l[1], l[2], l[3]],
                    links: [l[4], l[5], 0, 0],
                });
            }
        }
        Ok(CompactMtbvh {
            records,
            frame: CompactFrame {
                origin,
                root: 0,
                scale,
                node_count: count as u32,
            },
        })
    }

    /// Number of nodes.
    pub fn node_count(&self) -> usize {
        self.frame.node_count as usize
    }

    /// Number of far records.
    pub fn far_count(&self) -> usize {
        self.records.len() - self.node_count()
    }

    /// What the records, the frame and `triangle_count` packed triangles take on the device.
    pub fn memory(&self, triangle_count: usize) -> CompactMemory {
        let triangle_bytes = triangle_count * size_of::<PackedTriangle>();
        let node_bytes = self.node_count() * size_of::<CompactNode>();
        let far_bytes = self.far_count() * size_of::<CompactNode>();
        let frame_bytes = size_of::<CompactFrame>();
        CompactMemory {
            triangle_bytes,
            node_bytes,
            far_bytes,
            frame_bytes,
            total_bytes: triangle_bytes + node_bytes + far_bytes + frame_bytes,
        }
    }

    /// Node `index` as the traversal sees it: its decoded box, and for a leaf its triangles
    /// (`triangle_count` 0 for an internal node, whose `first_or_right` is its right child).
    pub fn decode_node(&self, index: u32) -> BvhNode {
        self.decode(&self.records[index as usize])
    }

    /// [`CompactMtbvh::decode_node`] of a record in hand.
    #[inline]
    fn decode(&self, record: &CompactNode) -> BvhNode {
        let [b0, b1, b2, meta] = record.bounds_and_meta;
        let q_min = Vec3::new(
            (b0 & 0xffff) as f32,
            (b0 >> 16) as f32,
            (b1 & 0xffff) as f32,
        );
        let q_max = Vec3::new((b1 >> 16) as f32, (b2 & 0xffff) as f32, (b2 >> 16) as f32);
        let origin = Vec3::from(self.frame.origin);
        let scale = Vec3::from(self.frame.scale);
        BvhNode {
            min: (origin + q_min * scale).to_array(),
            first_or_right: record.links[0],
            max: (origin + q_max * scale).to_array(),
            triangle_count: if meta & COMPACT_LEAF != 0 {
                meta & COMPACT_COUNT_MASK
            } else {
                0
            },
        }
    }

    /// Node `index`'s hit link in direction `d`: for an internal node its first child, for a
    /// leaf its miss link.
    pub fn hit_link(&self, index: u32, d: usize) -> u32 {
        let record = &self.records[index as usize];
        let meta = record.bounds_and_meta[3];
        if meta & COMPACT_LEAF != 0 {
            self.miss_link(index, d)
        } else if (meta >> d) & 1 != 0 {
            record.links[0]
        } else {
            index + 1
        }
    }

    /// Node `index`'s miss link in direction `d` (a node index or [`LINK_END`]).
    pub fn miss_link(&self, index: u32, d: usize) -> u32 {
        self.miss(index, &self.records[index as usize], d)
    }

    /// [`CompactMtbvh::miss_link`] of node `index` whose record is in hand.
    #[inline]
    fn miss(&self, index: u32, record: &CompactNode, d: usize) -> u32 {
        if record.bounds_and_meta[3] & COMPACT_FAR != 0 {
            let far = &self.records[record.links[1] as usize];
            return if d < 4 {
                far.bounds_and_meta[d]
            } else {
                far.links[d - 4]
            };
        }
        let bits = (record.links[1 + d / 2] >> (16 * (d % 2))) & 0xffff;
        let offset = i32::from(bits as u16 as i16);
        if bits == 0 {
            LINK_END
        } else {
            index.wrapping_add_signed(offset)
        }
    }
}

/// Compact MTBVH traversal of `compact` (made from `bvh`, whose triangles it tests); the
/// twin of `trace_mtbvh16` in `traverse_compact.wgsl`. `counters` accumulate the work done.
pub fn trace_mtbvh_compact<W: WorkTally>(
    bvh: &PackedBvh,
    compact: &CompactMtbvh,
    ray: &Ray,
    query: Query,
    counters: &mut W,
) -> Option<Hit> {
    let slab_ray = SlabRay::new(ray);
    let d = direction_index(ray.direction);
    let mut best: Option<Hit> = None;
    let mut node = compact.frame.root;
    while node != LINK_END {
        let record = &compact.records[node as usize];
        let current = compact.decode(record);
        let t_best = best.map_or(ray.t_max, |h| h.t);
        counters.add_boxes(1);
        let mut next = None;
        if intersect_box(&current, &slab_ray, t_best) < f32::INFINITY {
            if current.triangle_count > 0 {
                if test_leaf(bvh, &current, ray, query, &mut best, counters, &every_hit)
                    && query == Query::Any
                {
                    return best;
                }
            } else {
                // The first child in direction d: the right one where bit d is set.
                let right_first = (record.bounds_and_meta[3] >> d) & 1 != 0;
                next = Some(if right_first {
                    record.links[0]
                } else {
                    node + 1
                });
            }
        }
        node = next.unwrap_or_else(|| compact.miss(node, record, d));
    }
    best
}

/// Closest hit, compact MTBVH traversal.
pub fn closest_hit_mtbvh_compact(
    bvh: &PackedBvh,
    compact: &CompactMtbvh,
    ray: &Ray,
) -> Option<Hit> {
    trace_mtbvh_compact(bvh, compact, ray, Query::Closest, &mut Uncounted)
}

/// Whether anything is hit at `t` in `[0, t_max)`, compact MTBVH traversal.
pub fn any_hit_mtbvh_compact(bvh: &PackedBvh, compact: &CompactMtbvh, ray: &Ray) -> bool {
    trace_mtbvh_compact(bvh, compact, ray, Query::Any, &mut Uncounted).is_some()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::build_sah::BuildOptions;
    use crate::testing::random_soup;

    fn build(seed: u64, count: usize, leaf: usize) -> (PackedBvh, CompactMtbvh) {
        let options = BuildOptions {
            max_leaf_size: leaf,
            ..BuildOptions::default()
        };
        let bvh = PackedBvh::build(&random_soup(seed, count), &options);
        let compact = CompactMtbvh::new(&bvh).expect("compactable");
        (bvh, compact)
    }

    #[test]
    fn decoded_boxes_contain_the_exact_ones_and_are_tight() {
        for (seed, leaf) in [(1, 1), (2, 2), (3, 4)] {
            let (bvh, compact) = build(seed, 2000, leaf);
            let scale = Vec3::from(compact.frame.scale);
            for (i, exact) in bvh.nodes.iter().enumerate() {
                let got = compact.decode_node(i as u32);
                for a in 0..3 {
                    assert!(got.min[a] <= exact.min[a], "node {i} axis {a}");
                    assert!(got.max[a] >= exact.max[a], "node {i} axis {a}");
                    // Outward by less than one step (plus the decode's rounding).
                    assert!(exact.min[a] - got.min[a] <= 1.01 * scale[a], "node {i}");
                    assert!(got.max[a] - exact.max[a] <= 1.01 * scale[a], "node {i}");
                }
                assert_eq!(got.triangle_count, exact.triangle_count);
                assert_eq!(got.first_or_right, exact.first_or_right);
            }
        }
    }

    #[test]
    fn links_decode_to_the_packed_threadings() {
        for (seed, leaf) in [(4, 1), (5, 2)] {
            let (bvh, compact) = build(seed, 1500, leaf);
            for d in 0..DIRECTION_COUNT {
                for (i, links) in bvh.direction_links(d).iter().enumerate() {
                    assert_eq!(
                        compact.miss_link(i as u32, d),
                        links.miss,
                        "node {i} dir {d}"
                    );
                    assert_eq!(compact.hit_link(i as u32, d), links.hit, "node {i} dir {d}");
                }
            }
        }
    }

    #[test]
    fn far_links_are_used_when_offsets_pass_16_bits() {
        // 40k triangles make ~80k nodes (leaf 1): the upper levels' links are far.
        let (bvh, compact) = build(6, 40_000, 1);
        assert!(compact.far_count() > 0);
        assert!(compact.far_count() * 100 < compact.node_count());
        for d in 0..DIRECTION_COUNT {
            for (i, links) in bvh.direction_links(d).iter().enumerate() {
                assert_eq!(
                    compact.miss_link(i as u32, d),
                    links.miss,
                    "node {i} dir {d}"
                );
                assert_eq!(compact.hit_link(i as u32, d), links.hit, "node {i} dir {d}");
            }
        }
        let m = compact.memory(bvh.triangles.len());
        assert_eq!(m.node_bytes, 32 * bvh.nodes.len());
        assert_eq!(m.far_bytes, 32 * compact.far_count());
        assert_eq!(
            m.total_bytes,
            96 * bvh.triangles.len() + 32 * (bvh.nodes.len() + compact.far_count()) + 32
        );
    }

    #[test]
    fn quantisation_is_exact_on_awkward_frames() {
        // Far from the origin, tiny, flat, negative and huge ranges.
        for (lo, hi) in [
            (1.0e6f32, 1.0e6 + 1.0),
            (-3.0e-30, 5.0e-30),
            (2.5, 2.5),
            (-7.0e4, -6.0e4),
            (-1.0e35, 1.2e36),
            (0.0, 1.0),
        ] {
            let (origin, scale) = axis_frame(lo, hi).expect("a frame");
            assert!(origin <= lo && decode(origin, scale, QUANTIZED_MAX) >= hi);
            // m · 2^k with m < 256: at most 8 significant bits, so q · scale is exact.
            assert_eq!(scale.to_bits() & 0xffff, 0, "{scale} has more than 8 bits");
            let step = (f64::from(hi) - f64::from(lo)) / f64::from(QUANTIZED_MAX);
            if step > 1e-27 {
                assert!(
                    f64::from(scale) <= 1.02 * step,
                    "{lo}..{hi}: {scale} for {step}"
                );
            }
            let mut rng = crate::testing::Rng::new(7);
            for _ in 0..200 {
                let x = rng.range(lo, hi).clamp(lo, hi);
                let (down, up) = (
                    quantize_down(origin, scale, x),
                    quantize_up(origin, scale, x),
                );
                assert!(decode(origin, scale, down) <= x, "{lo}..{hi}: {x}");
                assert!(decode(origin, scale, up) >= x, "{lo}..{hi}: {x}");
                assert!(down == QUANTIZED_MAX || decode(origin, scale, down + 1) > x);
                assert!(up == 0 || decode(origin, scale, up - 1) < x);
            }
        }
    }

    #[test]
    fn too_large_coordinates_are_refused_in_words() {
        let mut bvh = PackedBvh::build(&random_soup(8, 10), &BuildOptions::default());
        bvh.nodes[0].max[1] = 1.0e37;
        let error = CompactMtbvh::new(&bvh).unwrap_err();
        assert!(error.to_string().contains("too large"), "{error}");
    }

    #[test]
    fn an_empty_tree_traverses_to_nothing() {
        let bvh = PackedBvh::default();
        let compact = CompactMtbvh::new(&bvh).expect("empty is fine");
        let ray = Ray {
            origin: Vec3::ZERO,
            direction: Vec3::X,
            t_max: f32::INFINITY,
        };
        assert_eq!(closest_hit_mtbvh_compact(&bvh, &compact, &ray), None);
        assert_eq!(compact.memory(0).total_bytes, 32);
    }
}
