//! Threading: hit and miss links for stackless traversal, for one order (the TBVH) and for the
//! six major directions (the MTBVH, after Hachisuka's talk).
//!
//! A threading fixes, for every internal node, which child is visited first, and stores per
//! node two links (Smits 1998's skip pointers):
//! - **hit**: the node visited next when the ray hits this node's box: the next node of the
//!   order's depth-first pre-order (an internal node's first child; for a leaf, whatever follows
//!   it);
//! - **miss**: the node visited next when the ray misses the box, skipping its whole subtree: for
//!   a first-visited child its sibling, for a second-visited child its parent's miss link, for
//!   a leaf its hit link (a leaf has nothing to skip).
//!
//! [`LINK_END`] ends the traversal. Every order starts at the root, node 0.
//!
//! Orders:
//! - [`Order::LeftFirst`] (the TBVH): the build's left child first. Nodes are stored in this
//!   order, so a hit link is always "the next node in the array", as in the talk.
//! - [`Order::Direction`]`(d)`, `d` = [`crate::pack::direction_index`] of the ray: along +X
//!   (d = 0) the child whose box centre has the smaller x comes first, along −X (d = 1) the one
//!   with the larger x; +Y/−Y (2, 3) and +Z/−Z (4, 5) likewise; ties go to the build's left
//!   child. A ray then meets boxes roughly front to back, so its closest hit shrinks the search
//!   early, with one fixed order and no stack. The boxes are shared: only the links differ.
//!
//! Read per direction, in threading +X (d = 0): an internal node's hit link is its child lying
//! toward −X (smaller centre x: the one a ray heading +X usually enters first); a node's miss
//! link, and a leaf's hit link, is the next subtree toward +X: its sibling if the node is the
//! −X one of the pair, else the nearest ancestor's +X sibling. In −X the roles of the
//! children swap (the child toward +X first), and ±Y, ±Z read the same on their own axis. In
//! the TBVH, "toward −X" reads "left". A ray uses the links of [`crate::pack::direction_index`]
//! of its direction, so it sweeps the scene along its own major axis.
//!
//! Any order visits every node, so traversal is exact whichever is used; the order only
//! changes how much is culled.

use rayon::prelude::*;

use crate::pack::Links;
use crate::tree::Bvh;

/// Link value meaning "traversal is over".
pub const LINK_END: u32 = u32::MAX;

/// Number of major directions: +X −X +Y −Y +Z −Z.
pub const DIRECTION_COUNT: usize = 6;

/// Which child an order visits first.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Order {
    /// The build's left child first (the single-threaded TBVH).
    LeftFirst,
    /// The child nearer along major direction `d` first (0:+X 1:−X 2:+Y 3:−Y 4:+Z 5:−Z).
    Direction(usize),
}

impl Order {
    /// The seven orders: the TBVH's, then the six directions.
    pub fn all() -> [Order; 1 + DIRECTION_COUNT] {
        let mut orders = [Order::LeftFirst; 1 + DIRECTION_COUNT];
        for (d, order) in orders[1..].iter_mut().enumerate() {
            *order = Order::Direction(d);
        }
        orders
    }
}

/// One threading of a tree.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Threading {
    /// Links per node, indexed like [`Bvh::nodes`]; the values are node indices or [`LINK_END`].
    pub links: Vec<Links>,
    /// First node to visit: 0, or [`LINK_END`] for an empty tree.
    pub root: u32,
}

/// Bit `d` of the result is set when, along direction `d`, internal node `index`'s right child
/// comes first: along +axis when its centre is smaller than the left child's, along −axis when
/// it is larger (equal centres: the left child first in both).
fn right_first_mask(bvh: &Bvh, index: u32) -> u8 {
    let Some((left, right)) = bvh.children(index) else {
        return 0;
    };
    let left_center = bvh.nodes[left as usize].bounds.center();
    let right_center = bvh.nodes[right as usize].bounds.center();
    let mut mask = 0;
    for axis in 0..3 {
        mask |= u8::from(right_center[axis] < left_center[axis]) << (2 * axis);
        mask |= u8::from(right_center[axis] > left_center[axis]) << (2 * axis + 1);
    }
    mask
}

/// Whether `order` visits the right child first, given the node's [`right_first_mask`].
fn right_first(mask: u8, order: Order) -> bool {
    match order {
        Order::LeftFirst => false,
        Order::Direction(d) => {
            assert!(d < DIRECTION_COUNT, "direction {d}");
            mask & (1 << d) != 0
        }
    }
}

/// `(first, second)` children of internal node `index` in `order`.
///
/// # Panics
/// If `index` is a leaf, or the direction is not below [`DIRECTION_COUNT`].
pub fn visit_order(bvh: &Bvh, index: u32, order: Order) -> (u32, u32) {
    let (left, right) = bvh.children(index).expect("an internal node");
    if right_first(right_first_mask(bvh, index), order) {
        (right, left)
    } else {
        (left, right)
    }
}

/// Threads `bvh` for one order.
pub fn thread(bvh: &Bvh, order: Order) -> Threading {
    let mut links = vec![Links::default(); bvh.nodes.len()];
    thread_into(&right_children(bvh), &mut links, |index| {
        right_first(right_first_mask(bvh, index as u32), order)
    });
    Threading {
        links,
        root: root(bvh),
    }
}

fn root(bvh: &Bvh) -> u32 {
    if bvh.nodes.is_empty() { LINK_END } else { 0 }
}

/// Per node, its right child's index, or [`LINK_END`] for a leaf: the tree's shape in 4 bytes
/// a node, which the seven threading passes stream through.
fn right_children(bvh: &Bvh) -> Vec<u32> {
    bvh.nodes
        .par_iter()
        .map(|n| {
            if n.is_leaf() {
                LINK_END
            } else {
                n.first_or_right
            }
        })
        .collect()
}

/// Writes the links of the order that visits internal node `i`'s right child first where
/// `right_first(i)`; `right_children` is [`right_children`], `links` has one entry per node.
fn thread_into(right_children: &[u32], links: &mut [Links], right_first: impl Fn(usize) -> bool) {
    // Parents precede their children in the stored pre-order, so a node's miss link is final
    // before the loop reaches it.
    if let Some(root) = links.first_mut() {
        root.miss = LINK_END;
    }
    for (index, &right) in right_children.iter().enumerate() {
        if right == LINK_END {
            links[index].hit = links[index].miss;
        } else {
            let left = index as u32 + 1;
            let (first, second) = if right_first(index) {
                (right, left)
            } else {
                (left, right)
            };
            links[index].hit = first;
            links[first as usize].miss = second;
            links[second as usize].miss = links[index].miss;
        }
    }
}

/// All seven threadings of a tree.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Threadings {
    /// The TBVH's links ([`Order::LeftFirst`]), one per node.
    pub tbvh: Vec<Links>,
    /// The six directions' links, direction-major: `mtbvh[d * node_count + node]`.
    pub mtbvh: Vec<Links>,
    /// First node of every order: 0, or [`LINK_END`] for an empty tree.
    pub root: u32,
}

/// The TBVH's threading and the six directions', threaded in parallel. Each node's child
/// order in all six directions is worked out once, in one pass over the boxes.
pub fn thread_all(bvh: &Bvh) -> Threadings {
    let count = bvh.nodes.len();
    let masks: Vec<u8> = (0..count as u32)
        .into_par_iter()
        .map(|index| right_first_mask(bvh, index))
        .collect();
    let right = right_children(bvh);
    let mut tbvh = vec![Links::default(); count];
    let mut mtbvh = vec![Links::default(); DIRECTION_COUNT * count];
    rayon::join(
        || thread_into(&right, &mut tbvh, |_| false),
        || {
            mtbvh
                .par_chunks_mut(count.max(1))
                .enumerate()
                .for_each(|(d, links)| thread_into(&right, links, |i| masks[i] & (1 << d) != 0));
        },
    );
    Threadings {
        tbvh,
        mtbvh,
        root: root(bvh),
    }
}
