//! Which binary nodes become the four-wide tree's nodes, slots and leaves: the collapse of
//! least surface-area cost, found by dynamic programming over the binary tree (the method of
//! Ylitie, Karras and Laine 2017 for wide BVHs, here for four slots and [`Tri4`] leaves).
//!
//! A binary subtree may be spent as **one slot** (a wide leaf, if its triangles fit one
//! leaf, or a wide node of its own) or, inside its parent's wide node, spread over **several
//! slots** (its binary children's subtrees, each again as one slot or several). The cost of a
//! choice is the SAH's: a wide node costs [`NODE_COST`] and a leaf [`LEAF_COST`] per
//! [`Tri4`] record, each weighted by its box's surface area (the chance a ray through the
//! root reaches it). Going bottom-up, every node keeps its cheapest choice for a budget of
//! 1 to 4 slots; the root's wide node is then read off top-down.
//!
//! [`Tri4`]: super::Tri4

use super::{LEAF_WIDTH, WIDTH, half_area, leaf_range};
use crate::pack::PackedBvh;

/// Cost of testing one wide node (its four boxes at once), the unit.
pub const NODE_COST: f64 = 1.0;
/// Cost of testing one [`super::Tri4`] record (four triangles at once), against a wide node's
/// 1: the four-lane triangle test does more arithmetic than the four-box test (three
/// divisions among it). Chosen, then checked: 2.5 tested ~2 % fewer triangles again and was
/// no faster (docs/BENCHMARKS.md §2, session 14).
pub const LEAF_COST: f64 = 1.5;

/// How a binary node's subtree is spent on a budget of slots.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
enum Spend {
    /// One slot: the subtree is a wide leaf (see [`Plan::is_leaf`]) or a wide node of its own.
    #[default]
    One,
    /// Its left child's subtree on `.0` slots and its right child's on `.1`.
    Split(u8, u8),
}

/// The cheapest way to spend each binary node's subtree on 1..=4 slots.
pub(super) struct Plan {
    /// `cost[b][i - 1]`: the least cost of `b`'s subtree on at most `i` slots.
    cost: Vec<[f64; WIDTH]>,
    spend: Vec<[Spend; WIDTH]>,
    /// As one slot, `b` is a wide leaf (else a wide node).
    leaf: Vec<bool>,
    /// As a wide node, how `b`'s children share its four slots, and what that costs
    /// (infinite for a binary leaf).
    node: Vec<(u8, u8)>,
    node_cost: Vec<f64>,
    /// The root, which is always a wide node, holds itself as its one leaf slot.
    root_leaf: bool,
}

impl Plan {
    /// The plan for `bvh` (not empty), children before parents.
    pub(super) fn new(bvh: &PackedBvh, ranges: &[(u32, u32, u32)]) -> Plan {
        let n = bvh.nodes.len();
        let mut plan = Plan {
            cost: vec![[0.0; WIDTH]; n],
            spend: vec![[Spend::One; WIDTH]; n],
            leaf: vec![false; n],
            node: vec![(0, 0); n],
            node_cost: vec![f64::INFINITY; n],
            root_leaf: false,
        };
        // Children follow their parents in pre-order: fill from the back.
        for b in (0..n).rev() {
            let node = &bvh.nodes[b];
            let area = f64::from(half_area(node));
            let as_leaf = leaf_range(bvh, ranges, b as u32)
                .map(|(_, count)| area * LEAF_COST * f64::from(count.div_ceil(LEAF_WIDTH as u32)));
            if node.triangle_count > 0 {
                let cost = as_leaf.expect("a binary leaf is a wide leaf");
                plan.cost[b] = [cost; WIDTH];
                plan.leaf[b] = true;
                continue;
            }
            let (left, right) = (b + 1, node.first_or_right as usize);
            let (as_node, split) = plan.spread(left, right, WIDTH);
            let as_node = as_node + area * NODE_COST;
            plan.node[b] = split;
            plan.node_cost[b] = as_node;
            plan.leaf[b] = as_leaf.is_some_and(|c| c <= as_node);
            plan.cost[b][0] = as_leaf.map_or(as_node, |c| c.min(as_node));
            for slots in 2..=WIDTH {
                let (spread, (l, r)) = plan.spread(left, right, slots);
                let fewer = plan.cost[b][slots - 2];
                (plan.cost[b][slots - 1], plan.spend[b][slots - 1]) = if spread < fewer {
                    (spread, Spend::Split(l, r))
                } else {
                    (fewer, plan.spend[b][slots - 2])
                };
            }
        }
        // The root pays for a wide node either way.
        let root_area = f64::from(half_area(&bvh.nodes[0])) * NODE_COST;
        plan.root_leaf = plan.leaf[0] && plan.cost[0][0] + root_area <= plan.node_cost[0];
        plan
    }

    /// The least cost of spreading `left`'s and `right`'s subtrees over `slots` slots (at
    /// least one each), and how many each gets.
    fn spread(&self, left: usize, right: usize, slots: usize) -> (f64, (u8, u8)) {
        (1..slots)
            .map(|l| {
                let r = slots - l;
                let cost = self.cost[left][l - 1] + self.cost[right][r - 1];
                (cost, (l as u8, r as u8))
            })
            .min_by(|x, y| x.0.total_cmp(&y.0))
            .expect("two slots or more")
    }

    /// Whether binary node `b`, as a slot, is a wide leaf.
    pub(super) fn is_leaf(&self, b: u32) -> bool {
        self.leaf[b as usize] && (b != 0 || self.root_leaf)
    }

    /// The slots of the wide node made for binary node `b` (the root, or an inner node
    /// whose plan is a wide node), in the binary tree's left-to-right order.
    pub(super) fn node_slots(&self, bvh: &PackedBvh, b: u32) -> Vec<u32> {
        if b == 0 && self.root_leaf {
            return vec![0];
        }
        let (l, r) = self.node[b as usize];
        let mut slots = Vec::with_capacity(WIDTH);
        self.push_slots(bvh, b + 1, l, &mut slots);
        self.push_slots(bvh, bvh.nodes[b as usize].first_or_right, r, &mut slots);
        slots
    }

    fn push_slots(&self, bvh: &PackedBvh, b: u32, budget: u8, slots: &mut Vec<u32>) {
        match self.spend[b as usize][budget as usize - 1] {
            Spend::One => slots.push(b),
            Spend::Split(l, r) => {
                self.push_slots(bvh, b + 1, l, slots);
                self.push_slots(bvh, bvh.nodes[b as usize].first_or_right, r, slots);
            }
        }
    }

    /// The SAH cost of the whole wide tree, its root's box weighing 1.
    pub(super) fn root_cost(&self, bvh: &PackedBvh) -> f64 {
        let area = f64::from(half_area(&bvh.nodes[0]));
        let cost = if self.root_leaf {
            self.cost[0][0] + area * NODE_COST
        } else {
            self.node_cost[0]
        };
        cost / area.max(f64::MIN_POSITIVE)
    }
}
