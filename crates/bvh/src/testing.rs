//! Geometry and rays made in code from a seed, for tests and benchmarks.
//!
//! [`random_soup`] mixes the cases a BVH gets wrong first: general triangles over a range of
//! sizes, slivers, exactly degenerate triangles, triangles sharing edges, and axis-aligned
//! triangles on a coarse grid (so that rays graze shared edges and box faces exactly).
//! [`random_rays`] aims many rays at the soup, some parallel to an axis, some in a coordinate
//! plane, some starting on a triangle or inside the boxes.

use glam::{Vec2, Vec3};
use scene::{Triangle, Vertex};

use crate::intersect::{Hit, Ray, SlabRay, intersect_box};
use crate::pack::{BvhNode, PackedBvh};

/// A small deterministic generator (SplitMix64), so fixtures need no `rand`.
#[derive(Clone, Debug)]
pub struct Rng {
    /// Current state.
    state: u64,
}

impl Rng {
    /// A generator whose sequence is fixed by `seed`.
    pub fn new(seed: u64) -> Rng {
        Rng { state: seed }
    }

    /// The next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        self.state = self.state.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.state;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }

    /// Uniform in `[0, 1)`.
    pub fn unit(&mut self) -> f32 {
        (self.next_u64() >> 40) as f32 / (1u64 << 24) as f32
    }

    /// Uniform in `[lo, hi)`.
    pub fn range(&mut self, lo: f32, hi: f32) -> f32 {
        lo + (hi - lo) * self.unit()
    }

    /// Uniform in `0..n` (`n > 0`).
    pub fn below(&mut self, n: usize) -> usize {
        (self.next_u64() % n as u64) as usize
    }

    /// Uniform in the cube `[-1, 1)³`.
    pub fn cube(&mut self) -> Vec3 {
        Vec3::new(
            self.range(-1.0, 1.0),
            self.range(-1.0, 1.0),
            self.range(-1.0, 1.0),
        )
    }

    /// A direction uniform on the unit sphere.
    pub fn direction(&mut self) -> Vec3 {
        loop {
            let p = self.cube();
            let length_sq = p.length_squared();
            if length_sq > 1e-4 && length_sq <= 1.0 {
                return p / length_sq.sqrt();
            }
        }
    }
}

/// Half-size of the region the soups fill.
pub const SOUP_EXTENT: f32 = 10.0;
/// Grid spacing of the axis-aligned triangles.
const GRID: f32 = 0.5;

/// `count` triangles from `seed`, a mixture of general, sliver, degenerate, edge-sharing and
/// axis-aligned ones; sizes from 1e-3 to about [`SOUP_EXTENT`]. Normals are the geometric
/// normal (unit, +Z where undefined), materials 0 to 7.
pub fn random_soup(seed: u64, count: usize) -> Vec<Triangle> {
    let mut rng = Rng::new(seed);
    let mut triangles: Vec<Triangle> = Vec::with_capacity(count);
    for _ in 0..count {
        let positions = match rng.below(10) {
            0..=3 => general(&mut rng),
            4 => sliver(&mut rng),
            5 => degenerate(&mut rng),
            6 | 7 if !triangles.is_empty() => {
                let other = &triangles[rng.below(triangles.len())];
                sharing_an_edge(&mut rng, other.positions())
            }
            _ => axis_aligned(&mut rng),
        };
        triangles.push(triangle(&mut rng, positions));
    }
    triangles
}

fn size(rng: &mut Rng) -> f32 {
    // Log-uniform from 1e-3 to 5.
    1e-3 * 5000f32.powf(rng.unit())
}

fn center(rng: &mut Rng) -> Vec3 {
    SOUP_EXTENT * rng.cube()
}

fn general(rng: &mut Rng) -> [Vec3; 3] {
    let (c, s) = (center(rng), size(rng));
    [c + s * rng.cube(), c + s * rng.cube(), c + s * rng.cube()]
}

fn sliver(rng: &mut Rng) -> [Vec3; 3] {
    let (c, s) = (center(rng), size(rng));
    let (a, b) = (c + s * rng.cube(), c + s * rng.cube());
    [a, b, a.lerp(b, rng.unit()) + 1e-4 * s * rng.cube()]
}

fn degenerate(rng: &mut Rng) -> [Vec3; 3] {
    let (c, s) = (center(rng), size(rng));
    let (a, b) = (c + s * rng.cube(), c + s * rng.cube());
    if rng.below(2) == 0 {
        [a, a, b]
    } else {
        [a, b, a.lerp(b, 0.5)]
    }
}

fn sharing_an_edge(rng: &mut Rng, other: [Vec3; 3]) -> [Vec3; 3] {
    let k = rng.below(3);
    let (a, b) = (other[k], other[(k + 1) % 3]);
    let apex = if rng.below(2) == 0 {
        // Coplanar neighbour: mirror the third vertex across the edge's midpoint.
        a + b - other[(k + 2) % 3]
    } else {
        a.lerp(b, 0.5) + size(rng) * rng.cube()
    };
    // Reversed edge, as in a consistently wound mesh.
    [b, a, apex]
}

fn axis_aligned(rng: &mut Rng) -> [Vec3; 3] {
    let snap = |x: f32| (x / GRID).round() * GRID;
    let axis = rng.below(3);
    let plane = snap(SOUP_EXTENT * rng.range(-1.0, 1.0));
    let base = center(rng).to_array().map(snap);
    let extent = 1 + rng.below(8);
    let mut vertex = |_| {
        let mut p = base;
        for (i, x) in p.iter_mut().enumerate() {
            *x = if i == axis {
                plane
            } else {
                *x + GRID * rng.below(extent) as f32
            };
        }
        Vec3::from_array(p)
    };
    [vertex(0), vertex(1), vertex(2)]
}

fn triangle(rng: &mut Rng, positions: [Vec3; 3]) -> Triangle {
    let [p0, p1, p2] = positions;
    let normal = (p1 - p0).cross(p2 - p0).try_normalize().unwrap_or(Vec3::Z);
    let mut vertex = |position| Vertex {
        position,
        normal,
        uv: Vec2::new(rng.unit(), rng.unit()),
        ..Vertex::default()
    };
    Triangle {
        vertices: [vertex(p0), vertex(p1), vertex(p2)],
        material: rng.below(8) as u32,
    }
}

/// `count` rays from `seed` aimed at `triangles` (which must not be empty): random rays,
/// rays at a point of a triangle (often a vertex or an edge), axis-parallel rays through
/// vertices, rays in a coordinate plane, rays starting on a triangle; mostly `t_max = ∞`,
/// some shorter.
pub fn random_rays(seed: u64, count: usize, triangles: &[Triangle]) -> Vec<Ray> {
    let mut rng = Rng::new(seed);
    (0..count)
        .map(|_| {
            let aim = rng.below(triangles.len());
            let target = point_on(&mut rng, &triangles[aim]);
            let origin = match rng.below(4) {
                0 => target,
                1 => {
                    let (k, corner) = (rng.below(triangles.len()), rng.below(3));
                    triangles[k].vertices[corner].position
                }
                _ => 1.5 * SOUP_EXTENT * rng.cube(),
            };
            let direction = match rng.below(5) {
                0 => rng.direction(),
                1 => axis_direction(&mut rng),
                2 => {
                    let mut d = rng.direction();
                    d[rng.below(3)] = 0.0;
                    d
                }
                _ => target - origin,
            };
            let direction = if direction == Vec3::ZERO {
                Vec3::X
            } else {
                direction
            };
            let origin = if direction.abs().max_element() == 1.0 && rng.below(2) == 0 {
                // Axis-parallel through the target: back up along the axis only.
                target - rng.range(0.0, 2.0 * SOUP_EXTENT) * direction
            } else {
                origin
            };
            let t_max = if rng.below(4) == 0 {
                rng.range(0.0, 2.0)
            } else {
                f32::INFINITY
            };
            Ray {
                origin,
                direction,
                t_max,
            }
        })
        .collect()
}

fn axis_direction(rng: &mut Rng) -> Vec3 {
    let mut d = Vec3::ZERO;
    d[rng.below(3)] = if rng.below(2) == 0 { 1.0 } else { -1.0 };
    d
}

/// A vertex, an edge midpoint or a random point of `triangle`.
fn point_on(rng: &mut Rng, triangle: &Triangle) -> Vec3 {
    let [a, b, c] = triangle.positions();
    match rng.below(4) {
        0 => [a, b, c][rng.below(3)],
        1 => a.lerp(b, 0.5),
        _ => {
            let (u, v) = (rng.unit(), rng.unit());
            let (u, v) = if u + v > 1.0 {
                (1.0 - u, 1.0 - v)
            } else {
                (u, v)
            };
            a + u * (b - a) + v * (c - a)
        }
    }
}

/// Whether `hit` (from the triangle test) lies outside its own triangle's box as the slab test
/// sees it: [`intersect_box`] on the triangle's bounds, with `t_far = hit.t`, says miss.
///
/// Rounding makes this possible: at an edge or vertex the test can accept a point just outside
/// the triangle, and on a thin triangle met obliquely its `t` can fall short of the plane by
/// more than the slab test's margin (two coplanar triangles then "tie" at slightly different
/// `t`). Every box that holds the triangle holds its box, and the slab test is monotonic in
/// the box and in `t_far`, so a hit that passes this test is always reached: where brute
/// force's closest hit is not fragile, every traversal returns its `t`. The tests allow a
/// traversal to differ only where this says so.
pub fn is_fragile_hit(bvh: &PackedBvh, ray: &Ray, hit: &Hit) -> bool {
    let [a, b, c] = bvh.triangles[hit.triangle as usize].positions();
    let own_box = BvhNode {
        min: a.min(b).min(c).to_array(),
        max: a.max(b).max(c).to_array(),
        ..BvhNode::default()
    };
    intersect_box(&own_box, &SlabRay::new(ray), hit.t) == f32::INFINITY
}

/// Whether two traversals' different answers are explained by rounding: the nearer of them
/// (a miss counting as farthest) is a fragile hit, which one tree's boxes may reach and
/// another's, visited in another order, may rightly cull.
pub fn nearer_is_fragile(bvh: &PackedBvh, ray: &Ray, a: Option<Hit>, b: Option<Hit>) -> bool {
    let nearer = match (a, b) {
        (Some(a), Some(b)) => Some(if b.t < a.t { b } else { a }),
        (a, b) => a.or(b),
    };
    nearer.is_some_and(|h| is_fragile_hit(bvh, ray, &h))
}

/// Whether two traversals' answers are the same hit: equal, or at exactly the same `t` (a
/// split triangle is packed once per piece, and triangles meeting at an edge or at the ray's
/// origin tie; traversals that reach boxes in different orders may find a different one of
/// them first). On copies of one input triangle the barycentrics must agree too.
pub fn same_hit(bvh: &PackedBvh, a: Option<Hit>, b: Option<Hit>) -> bool {
    match (a, b) {
        (Some(a), Some(b)) => {
            let input = |h: &Hit| bvh.triangle_ids[h.triangle as usize];
            a.t == b.t && (input(&a) != input(&b) || (a.u, a.v) == (b.u, b.v))
        }
        _ => a == b,
    }
}
