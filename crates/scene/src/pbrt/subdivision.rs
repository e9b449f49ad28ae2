//! Loop subdivision (Charles Loop, "Smooth Subdivision Surfaces Based on Triangles", 1987),
//! for pbrt's `loopsubdiv` shape: each level splits every triangle in four, placing the new
//! vertex of each edge and moving each old vertex by Loop's weights (boundaries follow the
//! one-dimensional rule, so an open mesh keeps its rim), then every vertex is pushed to its
//! limit position, as pbrt does.

use std::collections::HashMap;

use glam::Vec3;

/// An edge's two vertices, smaller index first.
type Edge = (u32, u32);

fn edge(a: u32, b: u32) -> Edge {
    (a.min(b), a.max(b))
}

/// The triangles around each edge (the vertex opposite it in each), and each vertex's
/// neighbours along edges.
struct Topology {
    opposite: HashMap<Edge, Vec<u32>>,
    neighbours: Vec<Vec<u32>>,
}

impl Topology {
    fn of(vertices: usize, triangles: &[[u32; 3]]) -> Topology {
        let mut opposite: HashMap<Edge, Vec<u32>> = HashMap::new();
        for t in triangles {
            for k in 0..3 {
                let (a, b, c) = (t[k], t[(k + 1) % 3], t[(k + 2) % 3]);
                opposite.entry(edge(a, b)).or_default().push(c);
            }
        }
        let mut neighbours = vec![Vec::new(); vertices];
        for &(a, b) in opposite.keys() {
            neighbours[a as usize].push(b);
            neighbours[b as usize].push(a);
        }
        for n in &mut neighbours {
            // One order whatever the hash map's, so results repeat bit for bit.
            n.sort_unstable();
        }
        Topology {
            opposite,
            neighbours,
        }
    }

    /// The neighbours of `v` across edges with one triangle: two for a vertex on a simple
    /// boundary; none inside the mesh.
    fn boundary_neighbours(&self, v: u32) -> Vec<u32> {
        let ring = &self.neighbours[v as usize];
        (ring.iter().copied())
            .filter(|&n| self.opposite[&edge(v, n)].len() == 1)
            .collect()
    }

    /// Where vertex `v` of `positions` goes by a rule: inside the mesh (1 − n·w)·itself plus w
    /// each of its n neighbours, w = `interior(n)`; on a boundary `own`·itself plus half the
    /// rest each of its two boundary neighbours; it stays where an edge of it is shared by more
    /// than two triangles or boundaries meet at it.
    fn moved(&self, positions: &[Vec3], v: u32, interior: impl Fn(usize) -> f32, own: f32) -> Vec3 {
        let p = |i: u32| positions[i as usize];
        let ring = &self.neighbours[v as usize];
        if ring.is_empty() || self.is_singular(v) {
            return p(v);
        }
        match self.boundary_neighbours(v)[..] {
            [] => {
                let w = interior(ring.len());
                let sum: Vec3 = ring.iter().map(|&n| p(n)).sum();
                (1.0 - ring.len() as f32 * w) * p(v) + w * sum
            }
            [a, c] => own * p(v) + (1.0 - own) / 2.0 * (p(a) + p(c)),
            _ => p(v),
        }
    }

    /// Whether an edge at `v` is shared by more than two triangles: such a vertex stays.
    fn is_singular(&self, v: u32) -> bool {
        let ring = &self.neighbours[v as usize];
        ring.iter().any(|&n| self.opposite[&edge(v, n)].len() > 2)
    }
}

/// Loop's weight of each neighbour of an interior vertex of valence `n`.
fn beta(n: usize) -> f32 {
    match n {
        3 => 3.0 / 16.0,
        _ => 3.0 / (8.0 * n as f32),
    }
}

/// One level of subdivision: four triangles for each, wound as it was.
pub(super) fn subdivide_once(
    positions: &[Vec3],
    triangles: &[[u32; 3]],
) -> (Vec<Vec3>, Vec<[u32; 3]>) {
    let topology = Topology::of(positions.len(), triangles);
    let p = |i: u32| positions[i as usize];
    // Old vertices moved (even rule).
    let mut next: Vec<Vec3> = (0..positions.len() as u32)
        .map(|v| topology.moved(positions, v, beta, 0.75))
        .collect();
    // One new vertex an edge (odd rule).
    let mut middle: HashMap<Edge, u32> = HashMap::with_capacity(topology.opposite.len());
    let mut edges: Vec<(&Edge, &Vec<u32>)> = topology.opposite.iter().collect();
    edges.sort_unstable_by_key(|(e, _)| **e);
    for (&(a, b), opposite) in edges {
        let position = match opposite[..] {
            [c, d] => 0.375 * (p(a) + p(b)) + 0.125 * (p(c) + p(d)),
            _ => 0.5 * (p(a) + p(b)),
        };
        middle.insert((a, b), next.len() as u32);
        next.push(position);
    }
    let mut split = Vec::with_capacity(triangles.len() * 4);
    for &[a, b, c] in triangles {
        let (ab, bc, ca) = (
            middle[&edge(a, b)],
            middle[&edge(b, c)],
            middle[&edge(c, a)],
        );
        split.extend([[a, ab, ca], [ab, b, bc], [ca, bc, c], [ab, bc, ca]]);
    }
    (next, split)
}

/// Each vertex pushed to where endless subdivision would take it (interior: weight
/// 1 / (n + 3 / (8β)) a neighbour; boundary: ⅗ itself and ⅕ each boundary neighbour).
pub(super) fn limit_positions(positions: &[Vec3], triangles: &[[u32; 3]]) -> Vec<Vec3> {
    let topology = Topology::of(positions.len(), triangles);
    let limit_weight = |n: usize| 1.0 / (n as f32 + 3.0 / (8.0 * beta(n)));
    (0..positions.len() as u32)
        .map(|v| topology.moved(positions, v, limit_weight, 0.6))
        .collect()
}

/// `levels` levels of subdivision, then the limit positions.
pub(super) fn loop_subdivide(
    positions: &[Vec3],
    triangles: &[[u32; 3]],
    levels: u32,
) -> (Vec<Vec3>, Vec<[u32; 3]>) {
    let (mut positions, mut triangles) = (positions.to_vec(), triangles.to_vec());
    for _ in 0..levels {
        (positions, triangles) = subdivide_once(&positions, &triangles);
    }
    (limit_positions(&positions, &triangles), triangles)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The regular octahedron: every vertex of valence 4.
    fn octahedron() -> (Vec<Vec3>, Vec<[u32; 3]>) {
        let positions = vec![
            Vec3::X,
            Vec3::NEG_X,
            Vec3::Y,
            Vec3::NEG_Y,
            Vec3::Z,
            Vec3::NEG_Z,
        ];
        let triangles = vec![
            [0, 2, 4],
            [2, 1, 4],
            [1, 3, 4],
            [3, 0, 4],
            [2, 0, 5],
            [1, 2, 5],
            [3, 1, 5],
            [0, 3, 5],
        ];
        (positions, triangles)
    }

    #[test]
    fn one_level_follows_loops_weights() {
        let (positions, triangles) = octahedron();
        let (next, split) = subdivide_once(&positions, &triangles);
        assert_eq!((next.len(), split.len()), (6 + 12, 32));
        // An old vertex: (1 − 4β) itself + β its ring (which sums to 0), β = 3/32.
        assert!(next[0].abs_diff_eq(Vec3::new(0.625, 0.0, 0.0), 1e-6));
        // The edge from +x to +y: ⅜ each end, ⅛ each opposite vertex (±z, summing to 0).
        assert!(
            next.iter()
                .any(|p| p.abs_diff_eq(Vec3::new(0.375, 0.375, 0.0), 1e-6))
        );
        // Windings kept: every triangle still faces out.
        for t in &split {
            let [a, b, c] = t.map(|i| next[i as usize]);
            assert!((b - a).cross(c - a).dot(a + b + c) > 0.0);
        }
    }

    /// Subdivided, the octahedron rounds: its points' distances from the centre spread far
    /// less than the octahedron's own (1/√3 to 1, a ratio of 1.73); a corner's limit is where
    /// Loop's limit rule puts it from the start, (1 − 4w)·v with w = 1/8 (its ring sums to 0).
    #[test]
    fn a_closed_mesh_becomes_smooth() {
        let (positions, triangles) = octahedron();
        let (limit, split) = loop_subdivide(&positions, &triangles, 4);
        assert_eq!(split.len(), 8 * 4usize.pow(4));
        let lengths: Vec<f32> = limit.iter().map(|p| p.length()).collect();
        let (least, most) = lengths
            .iter()
            .fold((f32::MAX, 0.0f32), |(a, b), &l| (a.min(l), b.max(l)));
        assert!(most / least < 1.25, "{least} .. {most}");
        assert!(
            limit[0].abs_diff_eq(Vec3::new(0.5, 0.0, 0.0), 1e-5),
            "{}",
            limit[0]
        );
    }

    /// An open, flat mesh stays flat, within its rim (the rim itself a curve of the boundary
    /// rule, which rounds the corners).
    #[test]
    fn boundaries_keep_their_rim() {
        let positions = vec![Vec3::ZERO, Vec3::X, Vec3::new(1.0, 1.0, 0.0), Vec3::Y];
        let triangles = vec![[0, 1, 2], [0, 2, 3]];
        let (limit, _) = loop_subdivide(&positions, &triangles, 3);
        for p in &limit {
            assert_eq!(p.z, 0.0);
            assert!(
                p.x >= -1e-6 && p.x <= 1.0 + 1e-6 && p.y >= -1e-6 && p.y <= 1.0 + 1e-6,
                "{p}"
            );
        }
    }
}
