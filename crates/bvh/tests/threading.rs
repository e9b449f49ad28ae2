//! The seven threadings (TBVH and six directions) against an independent recursive walk.

use bvh::mtbvh::{Order, thread, thread_all, visit_order};
use bvh::testing::random_soup;
use bvh::{BuildOptions, Bvh, LINK_END, build_sah};

/// Pre-order of `order`, by recursion: the reference the links must reproduce.
fn pre_order(bvh: &Bvh, node: u32, order: Order, out: &mut Vec<u32>) {
    out.push(node);
    if bvh.children(node).is_some() {
        let (first, second) = visit_order(bvh, node, order);
        pre_order(bvh, first, order, out);
        pre_order(bvh, second, order, out);
    }
}

fn subtree_size(bvh: &Bvh, node: u32) -> usize {
    match bvh.children(node) {
        None => 1,
        Some((l, r)) => 1 + subtree_size(bvh, l) + subtree_size(bvh, r),
    }
}

fn trees() -> Vec<Bvh> {
    let mut trees = Vec::new();
    for (seed, count) in [(1, 1), (2, 2), (3, 17), (4, 300), (5, 2000)] {
        for max_leaf_size in [1, 3, 8] {
            let options = BuildOptions {
                max_leaf_size,
                ..BuildOptions::default()
            };
            trees.push(build_sah(&random_soup(seed, count), &options));
        }
    }
    trees
}

#[test]
fn hit_links_visit_every_node_once_in_pre_order() {
    for bvh in trees() {
        for order in Order::all() {
            let threading = thread(&bvh, order);
            let mut expected = Vec::new();
            pre_order(&bvh, 0, order, &mut expected);
            let mut visited = Vec::new();
            let mut node = threading.root;
            while node != LINK_END {
                assert!(
                    visited.len() < bvh.node_count(),
                    "{order:?}: hit links loop"
                );
                visited.push(node);
                node = threading.links[node as usize].hit;
            }
            assert_eq!(visited, expected, "{order:?}");
            assert_eq!(visited.len(), bvh.node_count());
        }
    }
}

#[test]
fn miss_links_skip_exactly_the_subtree() {
    for bvh in trees() {
        for order in Order::all() {
            let threading = thread(&bvh, order);
            let mut sequence = Vec::new();
            pre_order(&bvh, 0, order, &mut sequence);
            for (position, &node) in sequence.iter().enumerate() {
                let after = position + subtree_size(&bvh, node);
                let expected = sequence.get(after).copied().unwrap_or(LINK_END);
                assert_eq!(
                    threading.links[node as usize].miss, expected,
                    "{order:?} node {node}"
                );
            }
        }
    }
}

#[test]
fn first_child_is_the_nearer_along_the_direction() {
    for bvh in trees() {
        for d in 0..6 {
            let threading = thread(&bvh, Order::Direction(d));
            let axis = d / 2;
            for index in 0..bvh.node_count() as u32 {
                let Some((left, right)) = bvh.children(index) else {
                    continue;
                };
                let center = |n: u32| bvh.nodes[n as usize].bounds.center()[axis];
                let (l, r) = (center(left), center(right));
                let right_nearer = if d % 2 == 0 { r < l } else { r > l };
                let first = if right_nearer { right } else { left };
                assert_eq!(
                    threading.links[index as usize].hit, first,
                    "direction {d} node {index}"
                );
            }
        }
    }
}

#[test]
fn tbvh_visits_left_children_first() {
    for bvh in trees() {
        let threading = thread(&bvh, Order::LeftFirst);
        for index in 0..bvh.node_count() as u32 {
            if let Some((left, _)) = bvh.children(index) {
                assert_eq!(threading.links[index as usize].hit, left);
            }
        }
    }
}

#[test]
fn empty_tree_threads_to_the_end() {
    let bvh = build_sah(&[], &BuildOptions::default());
    for order in Order::all() {
        let threading = thread(&bvh, order);
        assert_eq!(threading.root, LINK_END);
        assert!(threading.links.is_empty());
    }
}

#[test]
fn thread_all_matches_one_order_at_a_time() {
    for bvh in trees() {
        let all = thread_all(&bvh);
        let count = bvh.node_count();
        assert_eq!(all.tbvh, thread(&bvh, Order::LeftFirst).links);
        for d in 0..6 {
            let one = thread(&bvh, Order::Direction(d));
            assert_eq!(
                &all.mtbvh[d * count..(d + 1) * count],
                &one.links[..],
                "direction {d}"
            );
            assert_eq!(all.root, one.root);
        }
    }
}
