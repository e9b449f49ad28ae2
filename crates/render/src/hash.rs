//! The stochastic spatial hash's arithmetic (DESIGN.md, "Stochastic hash"), shared by both
//! backends' kernels: cells of side ≥ 2·R_max, so a gather sphere touches at most 2×2×2 cells;
//! each table entry keeps one photon picked uniformly among those hashed to it, and their count.
//!
//! Volume photons (kept where photons scatter in murky glass, `crate::scattering`) lie in a
//! grid of their own, sized by the volume gathers' largest radius
//! (`buffers::counter::VOLUME_CELL_SIZE`) and hashed with [`VOLUME_CELL_SALT`] into the same
//! table: only volume visible points gather them, and only those gather in spheres, whose
//! radius starts larger (`scattering::VOLUME_RADIUS_SHARE`). One grid for both would size the
//! surfaces' cells by the spheres, so that each kept photon would serve more surface
//! gathers (with the stochastic hash, the surfaces' noise +23 % on `scenes/cornell-murky.gltf`
//! at a volume share of 2.5: docs/BENCHMARKS.md, session 41). The volume grid is also finer
//! ([`VOLUME_CELL_DIVISIONS`]): its gathers read the cells their sphere reaches one by one
//! ([`volume_query_cells`]).

use bvh::bench_rays::pcg_hash;
use glam::{IVec3, Vec3};

use crate::rng::{HASH_STREAM, stream_key};

/// How much wider than 2·R a cell is, so that rounding in `floor((x ± R) / cell)` can never
/// span three cells.
pub const CELL_SLACK: f32 = 1.0001;

/// The cell side for a largest gather radius: a little over 2·R.
pub fn cell_size(max_radius: f32) -> f32 {
    (2.0 * max_radius * CELL_SLACK).max(f32::MIN_POSITIVE * 4.0)
}

/// The largest gather radius cells of `cell_size` serve (the inverse of [`cell_size`]).
pub fn largest_radius(cell_size: f32) -> f32 {
    cell_size * (0.5 / CELL_SLACK)
}

/// Volume cells per gather diameter: the volume photons' grid is `VOLUME_CELL_DIVISIONS` times
/// finer than the surfaces' (cells of side ≥ 2·R / divisions), so a gather sphere touches at
/// most `divisions + 1` cells per axis and reads only those its boundary reaches. The
/// stochastic hash keeps one photon a cell, weighted by the cell's count: the finer the cells,
/// the fewer photons share that weight and the more of a sphere's neighbourhood it reads in
/// kept photons. A sphere fills ~7 % of the 2 × 2 × 2 cells of side 2·R around it, a disc
/// ~20 % of their section, so volume gathers were far noisier than the surfaces' (docs/
/// BENCHMARKS.md, session 43).
pub const VOLUME_CELL_DIVISIONS: u32 = 2;

/// A volume cell's side over a surface cell's at the same radius: a product, not a quotient,
/// so that both backends round it alike (WGSL's division may be inexact).
pub const VOLUME_CELL_SHARE: f32 = 1.0 / VOLUME_CELL_DIVISIONS as f32;

/// The cell side of a grid (the volume photons' where `volume`) for a largest gather radius.
pub fn grid_cell_size(max_radius: f32, volume: bool) -> f32 {
    if volume {
        cell_size(max_radius) * VOLUME_CELL_SHARE
    } else {
        cell_size(max_radius)
    }
}

/// The largest gather radius cells of `cell_size` serve in a grid (the inverse of
/// [`grid_cell_size`]).
pub fn grid_largest_radius(cell_size: f32, volume: bool) -> f32 {
    if volume {
        largest_radius(cell_size * VOLUME_CELL_DIVISIONS as f32)
    } else {
        largest_radius(cell_size)
    }
}

/// The cell holding `position`. The grid is offset by half a cell so that no cell boundary
/// lies on a plane every cell size shares: scenes put walls and floors at coordinate 0, and
/// a photon on such a plane would fall on either side of it by one rounding, so the GPU
/// (fused multiply-adds) and the CPU would hash it to different cells.
pub fn cell_of(position: Vec3, cell_size: f32) -> IVec3 {
    let p = position / cell_size + 0.5;
    IVec3::new(floor_to_i32(p.x), floor_to_i32(p.y), floor_to_i32(p.z))
}

/// `x.floor() as i32` for every f32 (saturating, NaN to 0) without the floor: x86-64's
/// baseline has no rounding instruction, so `floor` is a call into libm, which the photon
/// hash and every gather query made three times (1.5 % of a CPU render's time).
fn floor_to_i32(x: f32) -> i32 {
    let truncated = x as i32;
    if truncated as f32 > x {
        truncated.saturating_sub(1)
    } else {
        truncated
    }
}

/// Mixed into the hash of a volume photon's cell ([`entry_of`]), so that a volume cell and the
/// surface cell of the same coordinates (their grids differ in size) fall on unrelated entries.
pub const VOLUME_CELL_SALT: u32 = 0x9e37_79b9;

/// The grid's salt for a photon or gather of the volume photons (`volume`) or the surfaces'.
pub fn grid_salt(volume: bool) -> u32 {
    if volume { VOLUME_CELL_SALT } else { 0 }
}

/// The table entry of a cell of the grid with salt `salt` ([`grid_salt`]).
pub fn entry_of(cell: IVec3, salt: u32, table_size: u32) -> u32 {
    let h = pcg_hash(cell.x as u32 ^ pcg_hash(cell.y as u32 ^ pcg_hash(cell.z as u32 ^ salt)));
    h % table_size
}

/// Hue classes of photons the stochastic hash keeps apart where a scene disperses: photons
/// that carry every colour channel (hue 0), and those with a channel of zero, by their
/// brightest channel (1 red, 2 green, 3 blue): what dispersive glass leaves (a wavelength's
/// colour has a zero channel, `crate::dispersion::spectral_rgb`). One photon kept for a cell
/// of both kinds made the cell's whole estimate one hue's for the pass whenever a dispersed
/// photon won: a correlated colour error (±10 % a channel in the dispersive furnace at 64 and
/// 256 passes alike).
pub const HUE_CLASSES: u32 = 4;

/// The stochastic hash also keeps caustic photons apart from the others (surfaces' statistics
/// gather the two apart, `crate::buffers::PixelStats`): where one photon is kept for a cell of
/// both kinds, a caustic photon that wins stands for all the cell's photons in the caustic
/// estimate and an indirect one in the other, so a cell with few caustic photons among many
/// others adds their count to the caustic estimate now and then. Kept apart, each kind keeps
/// one of its own, weighted by its own count (docs/BENCHMARKS.md §3, session 44: the caustic
/// part's error at equal passes −30 % on cornell-caustics). Each class has its own table of
/// `hash_size` entries; any classing keeps the estimate unbiased, this one only decides which
/// photons share a table. The most classes: each hue, caustic or not.
pub const PHOTON_CLASSES: u32 = 2 * HUE_CLASSES;

/// The class of a photon of `flux`, `caustic` or not, among `classes` ([`classes_for`]: 1 all
/// in one; 2 caustic or not; 4 by hue; 8 by hue, then caustic or not).
pub fn photon_class(flux: [f32; 3], caustic: bool, classes: u32) -> u32 {
    let hues = if classes >= HUE_CLASSES {
        HUE_CLASSES
    } else {
        1
    };
    let hue = if hues > 1 { hue_class(flux) } else { 0 };
    let kinds = classes / hues;
    hue + if kinds > 1 && caustic { hues } else { 0 }
}

/// The hue class of a photon of `flux` ([`HUE_CLASSES`]).
fn hue_class(flux: [f32; 3]) -> u32 {
    let [r, g, b] = flux;
    if r.min(g).min(b) > 0.0 {
        return 0;
    }
    // The brightest channel, the first of equals.
    if r >= g && r >= b {
        1
    } else if g >= b {
        2
    } else {
        3
    }
}

/// Whether photon classes of `classes` ([`classes_for`]) keep caustic photons apart (2, or
/// [`PHOTON_CLASSES`] with hues). Then they are hashed in a grid of their own, sized by the
/// caustic radii, which start smaller than the indirect ones and stay so (cells sized for
/// both made the caustic part's error a third higher, docs/BENCHMARKS.md §3, session 45), and
/// a gather reads their classes there and the others in the surfaces' grid.
pub fn caustic_apart(classes: u32) -> bool {
    classes == 2 || classes == PHOTON_CLASSES
}

/// Whether class `class` of `classes` holds caustic photons ([`photon_class`]: the upper
/// half where they are kept apart).
pub fn class_is_caustic(class: u32, classes: u32) -> bool {
    caustic_apart(classes) && class >= classes / 2
}

/// The entry of table `entry` in class `class`'s table (each `table_size` entries, class 0
/// first).
pub fn class_entry(entry: u32, class: u32, table_size: u32) -> u32 {
    class * table_size + entry
}

/// Where photons are kept in classes, a class-0 entry's count word keeps the count below this
/// bit and above it one mark per other class, set where that class's entry of the same index
/// holds photons: the gather reads only the classes marked (most cells have no photon of
/// one hue). Renders with classes keep fewer photon slots than 2²⁵ ([`classes_for`]).
pub const CLASS_MARK_SHIFT: u32 = 32 - (PHOTON_CLASSES - 1);

/// The count in a count word of a table of `classes` classes (the marks cleared).
pub fn entry_count(word: u32, classes: u32) -> u32 {
    if classes > 1 {
        word & ((1 << CLASS_MARK_SHIFT) - 1)
    } else {
        word
    }
}

/// The mark in a class-0 count word saying class `class` (1–7) has photons at that entry.
pub fn class_mark(class: u32) -> u32 {
    1 << (CLASS_MARK_SHIFT + class - 1)
}

/// The photon classes of a render with `slots` photon slots of a scene where glass does or
/// does not `disperse`, gathering by the `stochastic` hash or not ([`photon_class`]): hues
/// where glass disperses, and for the stochastic hash caustic photons apart; 1 where the
/// counts would not fit below the marks.
pub fn classes_for(disperses: bool, stochastic: bool, slots: u32) -> u32 {
    let hues = if disperses { HUE_CLASSES } else { 1 };
    let kinds = if stochastic { 2 } else { 1 };
    if slots < 1 << CLASS_MARK_SHIFT {
        hues * kinds
    } else {
        1
    }
}

/// The random priority of photon `index` in pass `pass`: never 0, so an entry whose priority
/// is 0 holds no photon. The largest priority wins an entry, a uniform pick.
pub fn priority(seed: u32, pass: u32, index: u32) -> u32 {
    stream_key(seed, HASH_STREAM, pass, index) | 1
}

/// The distinct table entries a gather sphere at `position` with `radius` reads in the grid of
/// `cell_size` and `salt`: the cells its bounding box touches (at most 8), entries reached
/// twice (collisions) listed once.
pub fn query_entries(
    position: Vec3,
    radius: f32,
    (cell_size, salt): (f32, u32),
    table_size: u32,
) -> ([u32; 8], usize) {
    let lo = cell_of(position - Vec3::splat(radius), cell_size);
    let hi = cell_of(position + Vec3::splat(radius), cell_size).min(lo + IVec3::ONE);
    let mut entries = [0u32; 8];
    let mut count = 0;
    for z in lo.z..=hi.z {
        for y in lo.y..=hi.y {
            for x in lo.x..=hi.x {
                let entry = entry_of(IVec3::new(x, y, z), salt, table_size);
                if !entries[..count].contains(&entry) {
                    entries[count] = entry;
                    count += 1;
                }
            }
        }
    }
    (entries, count)
}

/// How far, in cell sides, [`cell_reaches`] grows a cell's box: far more than the rounding of
/// `position / cell_size` wherever a grid's coordinates stay below 2¹⁷ cells.
pub const CELL_BOX_MARGIN: f32 = 1.0 / 64.0;

/// The volume photons' cells a gather sphere at `position` with `radius` reads, in the grid of
/// `cell_size`: the cells of its bounding box (at most `VOLUME_CELL_DIVISIONS + 1` per axis)
/// whose box the sphere reaches, x fastest, then y, then z. Two of them may share a table
/// entry (a collision), so each counts only the photons of its own cell ([`cell_of`]): no
/// photon counted twice, and no list of entries seen.
pub fn volume_query_cells(
    position: Vec3,
    radius: f32,
    cell_size: f32,
) -> impl Iterator<Item = IVec3> {
    let lo = cell_of(position - Vec3::splat(radius), cell_size);
    let hi = cell_of(position + Vec3::splat(radius), cell_size)
        .min(lo + IVec3::splat(VOLUME_CELL_DIVISIONS as i32));
    (lo.z..=hi.z)
        .flat_map(move |z| {
            (lo.y..=hi.y).flat_map(move |y| (lo.x..=hi.x).map(move |x| IVec3::new(x, y, z)))
        })
        .filter(move |&cell| cell_reaches(cell, position, radius, cell_size))
}

/// [`volume_query_cells`], each with its entry in the volume photons' grid, for a table of
/// `table_size` entries.
pub fn volume_query_entries(
    position: Vec3,
    radius: f32,
    cell_size: f32,
    table_size: u32,
) -> impl Iterator<Item = (IVec3, u32)> {
    volume_query_cells(position, radius, cell_size)
        .map(move |cell| (cell, entry_of(cell, VOLUME_CELL_SALT, table_size)))
}

/// Whether a photon at `position` counts where a volume query reads `cell`: it lies in that
/// cell ([`cell_of`]), so cells sharing an entry count it once.
pub fn lies_in(position: Vec3, cell: IVec3, cell_size: f32) -> bool {
    cell_of(position, cell_size) == cell
}

/// Whether the sphere at `position` with `radius` may reach a photon of cell `cell` (the grid
/// offset by half a cell, as [`cell_of`] places it): the cell's box grown by
/// [`CELL_BOX_MARGIN`] of a side, so that a photon that [`cell_of`]'s rounding puts in the
/// cell lies in it, and a cell skipped holds no photon within the radius on either backend.
pub fn cell_reaches(cell: IVec3, position: Vec3, radius: f32, cell_size: f32) -> bool {
    let low = (cell.as_vec3() - (0.5 + CELL_BOX_MARGIN)) * cell_size;
    let high = (cell.as_vec3() + (0.5 + CELL_BOX_MARGIN)) * cell_size;
    let nearest = position.clamp(low, high);
    position.distance_squared(nearest) <= radius * radius
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Classes: hues where glass disperses, caustic photons apart for the stochastic hash,
    /// both at once after the hues; all in one where counts would reach the marks.
    #[test]
    fn photons_are_classed_by_hue_and_kind() {
        let (white, red) = ([1.0, 1.0, 1.0], [0.8, 0.0, 0.1]);
        assert_eq!(classes_for(false, false, 1 << 20), 1);
        assert_eq!(classes_for(false, true, 1 << 20), 2);
        assert_eq!(classes_for(true, false, 1 << 20), HUE_CLASSES);
        assert_eq!(classes_for(true, true, 1 << 20), PHOTON_CLASSES);
        assert_eq!(classes_for(true, true, 1 << CLASS_MARK_SHIFT), 1);
        for caustic in [false, true] {
            assert_eq!(photon_class(red, caustic, 1), 0);
            assert_eq!(photon_class(red, caustic, HUE_CLASSES), 1);
        }
        assert_eq!(photon_class(white, true, 2), 1);
        assert_eq!(photon_class(red, false, 2), 0);
        assert_eq!(photon_class(red, true, PHOTON_CLASSES), 1 + HUE_CLASSES);
        assert_eq!(photon_class(white, false, PHOTON_CLASSES), 0);
        // The last class's mark is the word's top bit.
        assert_eq!(class_mark(PHOTON_CLASSES - 1), 1 << 31);
    }

    #[test]
    fn a_sphere_touches_at_most_two_cells_per_axis() {
        let radius = 0.37;
        let cell = cell_size(radius);
        for i in 0..1000 {
            let p = Vec3::new(
                i as f32 * 0.0131 - 5.0,
                i as f32 * -0.007 + 2.0,
                0.5 * i as f32,
            );
            let lo = cell_of(p - Vec3::splat(radius), cell);
            let hi = cell_of(p + Vec3::splat(radius), cell);
            assert!((hi - lo).max_element() <= 1, "{p}");
        }
    }

    /// Every point within the radius lies in a cell the volume query reads, the cells are
    /// distinct and at most `VOLUME_CELL_DIVISIONS + 1` per axis, and the query skips the
    /// box's corner cells the sphere does not reach.
    #[test]
    fn volume_queries_read_every_cell_within_the_radius() {
        let radius = 0.37;
        let cell = grid_cell_size(radius, true);
        assert_eq!(
            grid_largest_radius(cell, true),
            largest_radius(cell_size(radius))
        );
        let side = VOLUME_CELL_DIVISIONS as usize + 1;
        let mut skipped = 0;
        for i in 0..2000u32 {
            let unit = |k: u32| pcg_hash(i * 8 + k) as f32 / u32::MAX as f32;
            let p = Vec3::new(unit(0), unit(1), unit(2)) * 20.0 - 10.0;
            let cells: Vec<IVec3> = volume_query_cells(p, radius, cell).collect();
            let mut distinct = cells.clone();
            distinct.sort_by_key(|c| c.to_array());
            distinct.dedup();
            assert_eq!(distinct.len(), cells.len());
            let lo = cells.iter().fold(IVec3::MAX, |a, &c| a.min(c));
            let hi = cells.iter().fold(IVec3::MIN, |a, &c| a.max(c));
            assert!((hi - lo).max_element() < side as i32, "{p}");
            skipped += side.pow(3) - cells.len();
            // Points along a random direction from the centre to just inside the surface.
            let direction =
                (Vec3::new(unit(3), unit(4), unit(5)) * 2.0 - 1.0).normalize_or(Vec3::X);
            for t in [0.0, 0.5, 0.9, 0.9999, unit(6)] {
                let q = p + direction * (radius * t);
                assert!(cells.contains(&cell_of(q, cell)), "{p} {q}");
            }
        }
        assert!(skipped > 2000, "{skipped} cells skipped");
    }

    #[test]
    fn floor_to_i32_equals_the_floor_cast() {
        let special = [
            0.0,
            -0.0,
            0.5,
            -0.5,
            -1.0,
            1.0,
            -1.5,
            16_777_217.0,
            -16_777_217.0,
            2_147_483_648.0,
            -2_147_483_648.0,
            -2_147_483_904.0,
            3.0e9,
            -3.0e9,
            f32::MIN_POSITIVE,
            -f32::MIN_POSITIVE,
            f32::MAX,
            f32::MIN,
            f32::INFINITY,
            f32::NEG_INFINITY,
            f32::NAN,
        ];
        let spread = (0..200_000u32).map(|i| f32::from_bits(pcg_hash(i)));
        for x in special.into_iter().chain(spread) {
            assert_eq!(floor_to_i32(x), x.floor() as i32, "{x:e}");
        }
    }

    #[test]
    fn query_lists_each_entry_once() {
        let (entries, count) = query_entries(Vec3::new(0.5, 0.5, 0.5), 0.1, (1.0, 0), 1);
        assert_eq!((count, entries[0]), (1, 0));
        let (entries, count) = query_entries(Vec3::splat(0.5), 0.1, (1.0, 0), 1 << 20);
        assert_eq!(count, 8);
        let mut sorted = entries.to_vec();
        sorted.sort();
        sorted.dedup();
        assert_eq!(sorted.len(), 8);
    }

    #[test]
    fn volume_cells_fall_on_other_entries_than_the_surfaces_cells() {
        let size = 1 << 20;
        let cells = (-8..8).flat_map(|x| (-8..8).map(move |y| IVec3::new(x, y, x ^ y)));
        let shared = cells
            .filter(|&c| entry_of(c, grid_salt(true), size) == entry_of(c, grid_salt(false), size))
            .count();
        assert_eq!(shared, 0);
        // The surfaces' grid hashes as it always has (no salt).
        let c = IVec3::new(3, -2, 7);
        let plain = pcg_hash(c.x as u32 ^ pcg_hash(c.y as u32 ^ pcg_hash(c.z as u32))) % size;
        assert_eq!(entry_of(c, grid_salt(false), size), plain);
    }
}
