//! Every material's plastic coat as the kernels look it up ([`Coats`]), shared by the CPU
//! backend, the path tracer and the GPU upload (whose WGSL twins are `coat_transmittance_of`
//! and `coat_diffuse_scale_of` in `shading/coats.wgsl`).
//!
//! A coat's tables ([`Coat`]) depend on its GGX width: for ior 1.5 the base's scale falls from
//! 1.10 (smooth) to 0.83 at roughness 0.49 and the transmittance at cosine 0.05 rises from
//! 0.25 to 0.69. A coat that follows a metallic-roughness texture (`scene::TexturedLobe::
//! Coated`) changes width texel by texel, so one table cannot stand for all of it: such a
//! material gets a [`CoatGrid`], [`COAT_GRID_NODES`] tables evenly spaced in roughness (√α)
//! over the rough range, 0.01 to 0.5 (one table where its texture's range,
//! `scene::RoughnessMap::roughness_range`, has a single rough width), between which a hit's
//! coat is interpolated linearly (table entry by entry, then in the cosine as
//! [`Coat::transmittance`] does): within 0.7 % of the integrated coat between nodes away from
//! grazing, 2.5 % at cosine 0.02 (evenly in α the first interval was 8 % off). Texels
//! smoother than `scene::MIRROR_MAX_ROUGHNESS` take the smooth coat's exact Fresnel.

use std::collections::HashMap;

use rayon::prelude::*;

use scene::{DIFFUSE_MIN_ROUGHNESS, MIRROR_MAX_ROUGHNESS, Material, Surface, TexturedLobe};

use crate::plastic::{COAT_NODES, Coat};

/// The most tables a mapped coat's grid holds (fewer where its texture's rough range is a
/// single width: one).
pub const COAT_GRID_NODES: usize = 16;

/// A mapped coat's tables over its texture's range of GGX widths.
#[derive(Clone, Debug, PartialEq)]
pub struct CoatGrid {
    /// The smooth coat of the material's index (texels below `MIRROR_MAX_ROUGHNESS`).
    pub smooth: Coat,
    /// Rough coats at roughness `first_roughness + k · roughness_step` (α its square); at
    /// least one.
    pub nodes: Vec<Coat>,
    pub first_roughness: f32,
    /// 0 where there is one node.
    pub roughness_step: f32,
}

impl CoatGrid {
    /// The grid of a coat of index `ior` whose texture reads roughness within `range`: one
    /// node where the range's rough part is a single width (a uniform texture renders as its
    /// factors), else the whole rough range, so that every texture of one index shares its
    /// grid (a grid takes ~0.13 s; real textures' ranges all differ, and spanning each one's
    /// own would cost a scene of many textured materials seconds). A coat that keeps its lobe
    /// however rough (`keeps_lobe`) spans up to roughness 1.
    pub fn new(ior: f32, range: [f32; 2], keeps_lobe: bool) -> CoatGrid {
        let [first_roughness, last_roughness] = grid_range(range, keeps_lobe);
        let count = if last_roughness > first_roughness {
            COAT_GRID_NODES
        } else {
            1
        };
        let roughness_step = if count > 1 {
            (last_roughness - first_roughness) / (count - 1) as f32
        } else {
            0.0
        };
        CoatGrid {
            smooth: Coat::new(ior, 0.0),
            nodes: (0..count)
                .into_par_iter()
                .map(|k| {
                    let roughness = node_roughness(first_roughness, roughness_step, k);
                    Coat::new(ior, roughness * roughness)
                })
                .collect(),
            first_roughness,
            roughness_step,
        }
    }

    /// The coat of width `alpha`: the smooth one for 0, else the grid interpolated linearly in
    /// roughness (clamped to its ends).
    pub fn at(&self, alpha: f32) -> Coat {
        if alpha <= 0.0 {
            return self.smooth;
        }
        let last = self.nodes.len() - 1;
        let (lower, upper, t) = if last == 0 {
            (0, 0, 0.0)
        } else {
            let x = ((alpha.sqrt() - self.first_roughness) / self.roughness_step)
                .clamp(0.0, last as f32);
            let i = (x as usize).min(last - 1);
            (i, i + 1, x - i as f32)
        };
        let (a, b) = (&self.nodes[lower], &self.nodes[upper]);
        let lerp = |a: f32, b: f32| a * (1.0 - t) + b * t;
        Coat {
            ior: a.ior,
            alpha,
            transmittance_nodes: std::array::from_fn::<f32, COAT_NODES, _>(|i| {
                lerp(a.transmittance_nodes[i], b.transmittance_nodes[i])
            }),
            diffuse_scale: lerp(a.diffuse_scale, b.diffuse_scale),
        }
    }
}

/// The roughness a grid spans for a texture whose texels read within `range`: its rough part
/// (within [`MIRROR_MAX_ROUGHNESS`], [`DIFFUSE_MIN_ROUGHNESS`], or 1 for a coat that keeps its
/// lobe however rough: `scene::RoughnessMap::keeps_lobe`) where that is one width, else the
/// whole of it.
fn grid_range(range: [f32; 2], keeps_lobe: bool) -> [f32; 2] {
    let highest = if keeps_lobe {
        1.0
    } else {
        DIFFUSE_MIN_ROUGHNESS
    };
    let [low, high] = range.map(|r| r.clamp(MIRROR_MAX_ROUGHNESS, highest));
    if low == high {
        [low, high]
    } else {
        [MIRROR_MAX_ROUGHNESS, highest]
    }
}

/// Node `k`'s roughness: the last node lands on the range's end up to rounding.
fn node_roughness(first: f32, step: f32, k: usize) -> f32 {
    first + step * k as f32
}

/// Every material's coat: its own ([`Coat::of`] its stored surface) and, where a texture maps
/// it, its [`CoatGrid`]. Each distinct coat is integrated once: a table takes milliseconds, and
/// scenes repeat their materials' parameters.
#[derive(Clone, Debug, Default)]
pub struct Coats {
    own: Vec<Coat>,
    grids: Vec<Option<CoatGrid>>,
}

impl Coats {
    pub fn of(materials: &[Material]) -> Coats {
        let mut made: HashMap<(u32, u32), Coat> = HashMap::new();
        let mut coat = |ior: f32, alpha: f32| {
            *made
                .entry((ior.to_bits(), alpha.to_bits()))
                .or_insert_with(|| Coat::new(ior, alpha))
        };
        let own = materials
            .iter()
            .map(|material| match material.surface {
                Surface::Plastic { ior, alpha } => coat(ior, alpha),
                _ => Coat::default(),
            })
            .collect();
        let mut grids_made: HashMap<[u32; 3], CoatGrid> = HashMap::new();
        let grids = materials
            .iter()
            .map(|material| {
                let map = material.roughness_map?;
                let Surface::Plastic { ior, .. } = material.surface else {
                    return None;
                };
                (map.lobe == TexturedLobe::Coated).then(|| {
                    let [low, high] = grid_range(map.roughness_range, map.keeps_lobe);
                    grids_made
                        .entry([ior.to_bits(), low.to_bits(), high.to_bits()])
                        .or_insert_with(|| CoatGrid::new(ior, map.roughness_range, map.keeps_lobe))
                        .clone()
                })
            })
            .collect();
        Coats { own, grids }
    }

    /// Material `id`'s coat as stored (its surface outside a hit; ior 0 for none).
    pub fn own(&self, id: u32) -> &Coat {
        &self.own[id as usize]
    }

    /// Material `id`'s grid, where a texture maps its coat.
    pub fn grid(&self, id: u32) -> Option<&CoatGrid> {
        self.grids[id as usize].as_ref()
    }

    /// Material `id`'s coat where a hit meets it as `surface` (its texel's surface,
    /// `render::blend::mapped_material`): the grid's at the surface's width where a texture maps
    /// the coat, its own otherwise.
    pub fn at(&self, id: u32, surface: Surface) -> Coat {
        match (self.grid(id), surface) {
            (Some(grid), Surface::Plastic { alpha, .. }) => grid.at(alpha),
            _ => self.own[id as usize],
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: f32, b: f32, tolerance: f32) -> bool {
        (a - b).abs() <= tolerance * b.abs().max(1e-3)
    }

    /// Each material gets the coat its own parameters make, shared tables or not.
    #[test]
    fn materials_get_their_own_coats() {
        let material = |surface| Material {
            surface,
            ..Default::default()
        };
        let rough = Surface::Plastic {
            ior: 1.5,
            alpha: 0.09,
        };
        let other = Surface::Plastic {
            ior: 1.4,
            alpha: 0.09,
        };
        let materials = [
            material(rough),
            material(Surface::Diffuse),
            material(other),
            material(rough),
        ];
        let coats = Coats::of(&materials);
        assert_eq!(*coats.own(0), Coat::new(1.5, 0.09));
        assert_eq!(*coats.own(1), Coat::default());
        assert_eq!(*coats.own(2), Coat::new(1.4, 0.09));
        assert_eq!(coats.own(3), coats.own(0));
        assert!((0..4).all(|id| coats.grid(id).is_none()));
        assert_eq!(
            coats.at(
                2,
                Surface::Plastic {
                    ior: 1.4,
                    alpha: 0.3
                }
            ),
            *coats.own(2)
        );
    }

    /// A grid's nodes are the coats of their widths exactly; between them the interpolated
    /// coat stays within 0.7 % of the one integrated at that width (transmittance at cosines
    /// from 0.1, and the base's scale), 2.5 % at cosine 0.02; a smooth texel gets the smooth
    /// coat; widths past the ends take the end nodes' tables.
    #[test]
    fn a_grid_interpolates_between_exact_coats() {
        let grid = CoatGrid::new(1.5, [0.0, 1.0], false);
        assert_eq!(grid.nodes.len(), COAT_GRID_NODES);
        assert_eq!(grid.first_roughness, MIRROR_MAX_ROUGHNESS);
        let last = node_roughness(
            grid.first_roughness,
            grid.roughness_step,
            COAT_GRID_NODES - 1,
        );
        assert!(close(last, DIFFUSE_MIN_ROUGHNESS, 1e-6), "{last}");
        for (k, node) in grid.nodes.iter().enumerate() {
            let roughness = node_roughness(grid.first_roughness, grid.roughness_step, k);
            assert_eq!(*node, Coat::new(1.5, roughness * roughness));
        }
        let (mut worst, mut worst_grazing) = (0.0f32, 0.0f32);
        for k in 0..COAT_GRID_NODES - 1 {
            let roughness = grid.first_roughness + grid.roughness_step * (k as f32 + 0.5);
            let alpha = roughness * roughness;
            let (between, exact) = (grid.at(alpha), Coat::new(1.5, alpha));
            assert_eq!(between.alpha, alpha);
            let error =
                |cos: f32| (between.transmittance(cos) / exact.transmittance(cos) - 1.0).abs();
            for cos in [0.1f32, 0.3, 0.6, 1.0] {
                worst = worst.max(error(cos));
            }
            worst = worst.max((between.diffuse_scale / exact.diffuse_scale - 1.0).abs());
            worst_grazing = worst_grazing.max(error(0.02));
        }
        assert!(worst < 0.007, "worst relative error {worst}");
        assert!(
            worst_grazing < 0.025,
            "worst relative error at grazing {worst_grazing}"
        );
        assert_eq!(grid.at(0.0), Coat::new(1.5, 0.0));
        let past = grid.at(0.3);
        let end = grid.nodes[COAT_GRID_NODES - 1];
        assert_eq!(past.transmittance_nodes, end.transmittance_nodes);
    }

    /// A texture of one roughness gets one node, the coat an unmapped material of that
    /// roughness has, so a uniform texture renders as its factors do.
    #[test]
    fn a_uniform_texture_gets_the_factors_coat() {
        let grid = CoatGrid::new(1.5, [0.3, 0.3], false);
        assert_eq!(grid.nodes.len(), 1);
        let alpha = 0.3f32 * 0.3;
        assert_eq!(grid.at(alpha), Coat::new(1.5, alpha));
    }

    /// A mapped coat's material gets a grid over its texture's range, at the hit's width.
    #[test]
    fn mapped_coats_follow_the_texel() {
        let map = scene::RoughnessMap {
            texture: 0,
            roughness_factor: 1.0,
            roughness_range: [0.1, 0.4],
            lobe: TexturedLobe::Coated,
            keeps_lobe: false,
        };
        let materials = [Material {
            surface: Surface::Plastic {
                ior: 1.5,
                alpha: 0.0625,
            },
            roughness_map: Some(map),
            ..Default::default()
        }];
        let coats = Coats::of(&materials);
        let grid = coats.grid(0).expect("a mapped coat has a grid");
        assert_eq!(
            grid.first_roughness, MIRROR_MAX_ROUGHNESS,
            "the whole rough range"
        );
        assert_eq!(grid.nodes.len(), COAT_GRID_NODES);
        let surface = Surface::Plastic {
            ior: 1.5,
            alpha: 0.16,
        };
        assert_eq!(coats.at(0, surface), grid.at(0.16));
        assert_eq!(coats.at(0, Surface::Diffuse), *coats.own(0));
    }
}
