//! The kd-tree against brute force, and its build's invariants.

use super::*;
use crate::packing::surface_normal;

/// SplitMix64: a small seeded generator for test photons.
struct Random(u64);

impl Random {
    fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }

    fn unit(&mut self) -> f32 {
        (self.next_u64() >> 40) as f32 / (1u64 << 24) as f32
    }

    fn vec3(&mut self, lo: f32, hi: f32) -> Vec3 {
        Vec3::new(self.unit(), self.unit(), self.unit()) * (hi - lo) + Vec3::splat(lo)
    }

    fn direction(&mut self) -> Vec3 {
        loop {
            let v = self.vec3(-1.0, 1.0);
            if v.length_squared() > 1e-4 && v.length_squared() <= 1.0 {
                return v.normalize();
            }
        }
    }

    fn photon(&mut self, position: Vec3) -> Photon {
        Photon {
            position: position.to_array(),
            normal: surface_normal(self.direction()),
            flux: self.vec3(0.01, 1.0).to_array(),
            pad: 0,
        }
    }
}

fn uniform(random: &mut Random, count: usize) -> Vec<Photon> {
    (0..count)
        .map(|_| {
            let p = random.vec3(-1.0, 1.0);
            random.photon(p)
        })
        .collect()
}

/// Tight clumps of very different sizes, as caustics make.
fn clustered(random: &mut Random, count: usize) -> Vec<Photon> {
    let centres: Vec<(Vec3, f32)> = (0..12)
        .map(|i| (random.vec3(-1.0, 1.0), 0.3 / 4f32.powi(i % 5)))
        .collect();
    (0..count)
        .map(|i| {
            let (centre, size) = centres[i % centres.len()];
            let p = centre + random.vec3(-size, size) * random.unit();
            random.photon(p)
        })
        .collect()
}

/// Asserts the tree's gather equals brute force for `queries` random queries around the
/// photons (found exactly; flux to summation-order rounding).
fn assert_matches_brute_force(photons: &[Photon], queries: usize, seed: u64) {
    let tree = PhotonKdTree::build(photons);
    let mut random = Random(seed);
    let mut hits = 0;
    for q in 0..queries {
        let position = match q % 3 {
            // On a photon: distance 0, the boundary cases of the split planes.
            0 if !photons.is_empty() => {
                Vec3::from(photons[random.next_u64() as usize % photons.len()].position)
            }
            _ => random.vec3(-1.2, 1.2),
        };
        let radius = 0.5 * random.unit().powi(3);
        let normal = random.direction();
        let (found, flux) = tree.query(position, radius, normal);
        let (want_found, want_flux) = gather_brute_force(photons, position, radius, normal);
        assert_eq!(found, want_found, "query {q} at {position} r {radius}");
        assert!(
            (flux - want_flux).abs().max_element() <= 1e-5 * want_flux.max_element().max(1.0),
            "query {q}: flux {flux} vs {want_flux}"
        );
        hits += found;
        // Caustic and indirect photons apart, each within its own radius.
        let radii = [radius, 0.5 * radius];
        let classes = tree.query_classes(position, radii, normal);
        let want = gather_brute_force_classes(photons, position, radii, normal);
        for ((found, flux), (want_found, want_flux)) in classes.into_iter().zip(want) {
            assert_eq!(found, want_found, "query {q}, classes");
            assert!(
                (flux - want_flux).abs().max_element() <= 1e-5 * want_flux.max_element().max(1.0)
            );
        }
    }
    if photons.len() > 100 {
        assert!(hits > 0, "the queries should find photons");
    }
}

#[test]
fn gather_matches_brute_force_on_uniform_photons() {
    let photons = uniform(&mut Random(1), 20_000);
    assert_matches_brute_force(&photons, 3000, 11);
}

#[test]
fn gather_matches_brute_force_on_clustered_photons() {
    let photons = clustered(&mut Random(2), 20_000);
    assert_matches_brute_force(&photons, 3000, 12);
}

#[test]
fn gather_matches_brute_force_with_duplicate_positions() {
    let mut random = Random(3);
    let spots: Vec<Vec3> = (0..40).map(|_| random.vec3(-1.0, 1.0)).collect();
    let photons: Vec<Photon> = (0..10_000)
        .map(|i| random.photon(spots[i % spots.len()]))
        .collect();
    assert_matches_brute_force(&photons, 2000, 13);
    // Every photon at one point: one axis has all the ties.
    let same: Vec<Photon> = (0..5000).map(|_| random.photon(Vec3::ONE)).collect();
    assert_matches_brute_force(&same, 200, 14);
}

#[test]
fn gather_matches_brute_force_on_a_plane() {
    let mut random = Random(4);
    let photons: Vec<Photon> = (0..10_000)
        .map(|_| {
            let p = random.vec3(-1.0, 1.0);
            random.photon(Vec3::new(p.x, 0.25, p.z))
        })
        .collect();
    assert_matches_brute_force(&photons, 2000, 15);
}

#[test]
fn gather_handles_no_and_one_photon() {
    let normal = Vec3::Z;
    let empty = PhotonKdTree::build(&[]);
    assert!(empty.is_empty());
    assert_eq!(empty.depth(), 0);
    assert_eq!(empty.query(Vec3::ZERO, 1.0, normal), (0, Vec3::ZERO));
    let photon = Photon {
        position: [0.5, 0.0, 0.0],
        normal: surface_normal(Vec3::Z),
        flux: [1.0, 2.0, 3.0],
        pad: 0,
    };
    let one = PhotonKdTree::build(&[photon]);
    assert_eq!(one.depth(), 1);
    let at = |radius| one.query(Vec3::ZERO, radius, normal);
    assert_eq!(at(0.6), (1, Vec3::new(1.0, 2.0, 3.0)));
    assert_eq!(at(0.5), (0, Vec3::ZERO), "the radius is exclusive");
    assert_eq!(one.query(Vec3::ZERO, 0.6, -normal), (0, Vec3::ZERO));
}

#[test]
fn build_leaves_out_photons_without_flux() {
    let mut photons = uniform(&mut Random(5), 3000);
    for photon in photons.iter_mut().step_by(3) {
        photon.flux = [0.0; 3];
    }
    let tree = PhotonKdTree::build(&photons);
    assert_eq!(tree.len(), 2000);
    let mut indices: Vec<u32> = tree.nodes().iter().map(KdNode::photon).collect();
    indices.sort_unstable();
    let stored: Vec<u32> = (0..3000).filter(|i| i % 3 != 0).collect();
    assert_eq!(indices, stored, "each stored photon once, no other");
    for node in tree.nodes() {
        let photon = &photons[node.photon() as usize];
        assert_eq!(
            (node.position, node.normal, node.flux),
            (photon.position, photon.normal, photon.flux),
            "a node holds its photon"
        );
    }
    // A radius covering everything: every facing stored photon, none of the empty slots.
    let (found, _) = tree.query(Vec3::ZERO, 10.0, Vec3::Y);
    assert_eq!(
        found,
        gather_brute_force(&photons, Vec3::ZERO, 10.0, Vec3::Y).0
    );
    assert!(found > 500 && found < 1500, "{found}");
    assert_matches_brute_force(&photons, 1000, 16);
}

#[test]
fn build_orders_every_subtree_by_its_split_plane() {
    let photons = clustered(&mut Random(6), 5000);
    let tree = PhotonKdTree::build(&photons);
    let nodes = tree.nodes();
    // Each node's coordinate on every ancestor's axis lies on that ancestor's side.
    for i in 1..nodes.len() {
        let mut child = i;
        while child > 0 {
            let parent = (child - 1) / 2;
            let axis = nodes[parent].axis();
            let (c, p) = (nodes[i].position[axis], nodes[parent].position[axis]);
            if child % 2 == 1 {
                assert!(c <= p, "node {i} left of ancestor {parent}");
            } else {
                assert!(c >= p, "node {i} right of ancestor {parent}");
            }
            child = parent;
        }
    }
    assert_eq!(tree.depth(), 13, "⌊log₂ 5000⌋ + 1 levels");
}

#[test]
fn build_is_deterministic_whatever_the_thread_count() {
    let photons = clustered(&mut Random(7), 50_000);
    let on = |threads| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .expect("thread pool")
            .install(|| PhotonKdTree::build(&photons))
    };
    let one = on(1);
    assert_eq!(one, on(4));
    assert_eq!(one, PhotonKdTree::build(&photons));
}

#[test]
fn left_subtree_sizes_make_a_complete_tree() {
    // Heap order has no holes exactly when every subtree is left-balanced: check the
    // sizes against a complete tree's, counted node by node.
    for count in 1..600usize {
        let in_left = |root: usize| {
            let mut size = 0;
            let mut level = vec![root];
            while !level.is_empty() {
                level.retain(|&i| i < count);
                size += level.len();
                level = level.iter().flat_map(|&i| [2 * i + 1, 2 * i + 2]).collect();
            }
            size
        };
        assert_eq!(left_subtree_size(count), in_left(1), "{count} nodes");
    }
}

#[test]
fn stack_holds_the_deepest_tree() {
    assert_eq!(depth_of(MAX_PHOTONS), MAX_DEPTH);
    assert_eq!(STACK_SIZE, MAX_DEPTH as usize - 1);
    assert!(MAX_PHOTONS <= PHOTON_MASK as usize + 1);
    // A query whose radius spans the whole tree pushes at every level: it must fit.
    let photons = uniform(&mut Random(8), (1 << 14) - 1);
    let tree = PhotonKdTree::build(&photons);
    let (found, _) = tree.query(Vec3::ZERO, 10.0, Vec3::X);
    assert_eq!(
        found,
        gather_brute_force(&photons, Vec3::ZERO, 10.0, Vec3::X).0
    );
}
