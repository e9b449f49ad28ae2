//! glTF's sheen (`KHR_materials_sheen`, `scene::Sheen`): a layer of fibres over a material,
//! beneath any clear coat. Its lobe is the Charlie distribution with the Smith shadowing of
//! Estevez and Kulla (2017, "Production Friendly Microfacet Sheen BRDF"; their fitted Λ), as
//! glTF's specification suggests:
//!
//! `f(ωo, ωi) = C · D(h) · G(ωo, ωi) / (4 cos θi cos θo)`, `D(h) = (2 + 1/α) sin(θh)^(1/α) / 2π`,
//! `G = 1 / (1 + Λ(θi) + Λ(θo))`, α = roughness². (Neubelt and Pettineo's cheaper visibility,
//! the other one glTF names, returns up to 2.6× the light it receives at grazing angles when
//! smooth: not used. The fitted shadowing still lets smooth sheens seen within a few degrees of
//! grazing return up to 1.9×: there the lobe is scaled by 1 / E.)
//!
//! The layer reflects `max(C) · min(E(θ), 1)` of the light meeting it (E: the white lobe's
//! directional albedo, tabulated per roughness, [`SheenTable`]) and lets the rest through to
//! the material beneath, which it dims that way on the way in and again on the way out: the
//! base's light is scaled by `(1 − max(C) E(θi)) (1 − max(C) E(θo))`. glTF's own model scales it by the
//! smaller of the two factors instead; the product keeps the layer reciprocal, as the clear
//! coat is here (`render::clearcoat`), and the two differ only where the sheen is bright.
//!
//! The kernels (CPU, WGSL twins in `shading/sheen.wgsl`, the path tracer) meet the sheen after the
//! clear coat ([`sheen_event`]): it reflects with that probability, into a cosine-distributed
//! direction weighted by the lobe over the choice ([`SheenTable::lobe_scale`]: choice and
//! weight together return `C · E · min(1, 1/E)`, the table's error moving only the choice), or
//! lets the ray through, weight 1. An eye path it reflects takes a light
//! sample for the sheen's lobe ([`sheen_response`], weighed against its own sampling by the
//! power heuristic); light samples of the material beneath carry [`SheenTable::transmittance`]
//! for the light's direction, and what leaves it carries it for the way out.

use std::f32::consts::{FRAC_1_PI, TAU};

use glam::Vec3;

use crate::microfacet::GlossyResponse;
use crate::sampling::{about_axis, cosine_hemisphere};

/// Nodes of a [`SheenTable`]: cosines `(i / (SHEEN_NODES − 1))²`, denser towards grazing
/// where the albedo changes fastest.
pub const SHEEN_NODES: usize = 16;

/// The Charlie lobe of one roughness and its white directional albedo at the node cosines.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SheenTable {
    /// α = roughness² (`scene::Sheen::roughness`).
    pub alpha: f32,
    pub albedo_nodes: [f32; SHEEN_NODES],
}

impl SheenTable {
    /// The table of a sheen of `roughness` (glTF's `sheenRoughnessFactor`, already raised to
    /// `scene::Sheen::MIN_ROUGHNESS`).
    pub fn new(roughness: f32) -> SheenTable {
        let alpha = roughness * roughness;
        SheenTable {
            alpha,
            albedo_nodes: std::array::from_fn(|i| {
                let s = i as f32 / (SHEEN_NODES - 1) as f32;
                directional_albedo((s * s).max(GRAZING_COSINE), alpha, 96) as f32
            }),
        }
    }

    /// The white lobe's directional albedo seen at cosine `cos` (its sign ignored),
    /// interpolated linearly between the nodes.
    pub fn albedo(&self, cos: f32) -> f32 {
        let x = cos.abs().min(1.0).sqrt() * (SHEEN_NODES - 1) as f32;
        let i = (x as usize).min(SHEEN_NODES - 2);
        let t = x - i as f32;
        self.albedo_nodes[i] * (1.0 - t) + self.albedo_nodes[i + 1] * t
    }

    /// The share of light meeting a sheen of colour `color` at cosine `cos` that it reflects:
    /// `max(C) · min(E, 1)`. (Smooth sheens seen within a few degrees of grazing have E > 1,
    /// the fitted shadowing letting through more than arrives; there the lobe is scaled by 1/E,
    /// [`SheenTable::lobe_scale`].)
    pub fn reflectance(&self, color: Vec3, cos: f32) -> f32 {
        color.max_element() * self.albedo(cos).min(1.0)
    }

    /// What multiplies the white lobe (`f cos θi`, [`local_sheen`]) met at cosine `cos` by a
    /// path that chose the sheen there (with [`SheenTable::reflectance`]): `C / (max(C) E)`,
    /// so that the choice and the lobe together return `C · min(E, 1)`. Zero for a black sheen.
    pub fn lobe_scale(&self, color: Vec3, cos: f32) -> Vec3 {
        let denominator = color.max_element() * self.albedo(cos);
        if denominator > 0.0 {
            color / denominator
        } else {
            Vec3::ZERO
        }
    }

    /// The share it lets through to the material beneath.
    pub fn transmittance(&self, color: Vec3, cos: f32) -> f32 {
        1.0 - self.reflectance(color, cos)
    }
}

/// Roughness nodes of the grid a textured sheen's roughness reads its table from
/// ([`grid_table`]): from `scene::Sheen::MIN_ROUGHNESS` to 1, evenly in the square root of
/// the distance from the least (denser where smooth, where the albedo changes fastest).
pub const SHEEN_GRID_NODES: usize = 16;

/// The tables at the grid's roughness nodes, integrated once.
pub fn sheen_grid() -> &'static [SheenTable; SHEEN_GRID_NODES] {
    static GRID: std::sync::OnceLock<[SheenTable; SHEEN_GRID_NODES]> = std::sync::OnceLock::new();
    GRID.get_or_init(|| std::array::from_fn(|i| SheenTable::new(grid_roughness(i))))
}

/// The roughness of the grid's node `i`.
pub fn grid_roughness(i: usize) -> f32 {
    let least = scene::Sheen::MIN_ROUGHNESS;
    let s = i as f32 / (SHEEN_GRID_NODES - 1) as f32;
    least + (1.0 - least) * s * s
}

/// Where `roughness` falls in the grid: the node below it and the weight of the one above.
pub fn grid_position(roughness: f32) -> (usize, f32) {
    let least = scene::Sheen::MIN_ROUGHNESS;
    let s = ((roughness - least) / (1.0 - least)).clamp(0.0, 1.0).sqrt();
    let x = s * (SHEEN_GRID_NODES - 1) as f32;
    let i = (x as usize).min(SHEEN_GRID_NODES - 2);
    (i, x - i as f32)
}

/// The table of a sheen of `roughness` (a texel's), its nodes interpolated linearly between the
/// grid's two tables about it, its width `roughness²`.
pub fn grid_table(roughness: f32) -> SheenTable {
    let (i, t) = grid_position(roughness);
    let grid = sheen_grid();
    let (below, above) = (&grid[i].albedo_nodes, &grid[i + 1].albedo_nodes);
    SheenTable {
        alpha: roughness * roughness,
        albedo_nodes: std::array::from_fn(|k| below[k] * (1.0 - t) + above[k] * t),
    }
}

/// Each material's sheen table (`None` where it has no sheen), each roughness integrated once.
pub fn sheen_tables(materials: &[scene::Material]) -> Vec<Option<SheenTable>> {
    let mut made: std::collections::HashMap<u32, SheenTable> = Default::default();
    (materials.iter())
        .map(|m| {
            let sheen = m.sheen?;
            let key = sheen.roughness.to_bits();
            Some(
                *made
                    .entry(key)
                    .or_insert_with(|| SheenTable::new(sheen.roughness)),
            )
        })
        .collect()
}

/// A sheen at a hit: its colour there (the factor times its texture's texel) and its table.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SheenAt {
    pub color: Vec3,
    pub table: SheenTable,
}

impl SheenAt {
    /// `sheen` with `table` (its own roughness's) at a hit whose textures read `texel(id)`
    /// (linear RGBA); where a texture gives its roughness, the grid's table of the texel's
    /// roughness ([`grid_table`]).
    pub fn new(
        sheen: &scene::Sheen,
        table: SheenTable,
        texel: impl Fn(scene::TextureId) -> glam::Vec4,
    ) -> SheenAt {
        let scale = sheen
            .color_texture
            .map_or(Vec3::ONE, |id| texel(id).truncate());
        let table = match sheen.roughness_texture {
            Some(id) => grid_table(textured_roughness(sheen.roughness, texel(id).w)),
            None => table,
        };
        SheenAt {
            color: sheen.color * scale.clamp(Vec3::ZERO, Vec3::ONE),
            table,
        }
    }

    /// [`SheenTable::transmittance`] of this colour.
    pub fn transmittance(&self, cos: f32) -> f32 {
        self.table.transmittance(self.color, cos)
    }

    /// [`SheenTable::lobe_scale`] of this colour.
    pub fn lobe_scale(&self, cos: f32) -> Vec3 {
        self.table.lobe_scale(self.color, cos)
    }

    /// [`sheen_event`] of this sheen.
    pub fn event(&self, incoming: Vec3, normal: Vec3, u: [f32; 3]) -> SheenEvent {
        sheen_event(incoming, normal, self.color, &self.table, u)
    }
}

/// A sheen's roughness where its roughness texture's alpha reads `texel`: the product, raised
/// to `scene::Sheen::MIN_ROUGHNESS` again.
pub fn textured_roughness(roughness: f32, texel: f32) -> f32 {
    (roughness * texel.clamp(0.0, 1.0)).max(scene::Sheen::MIN_ROUGHNESS)
}

/// Where the table's first node (cosine 0) is evaluated: the lobe's visibility term is
/// singular exactly at grazing.
const GRAZING_COSINE: f32 = 1e-3;

/// The Charlie distribution of width `alpha` at a half vector of cosine `cos_h` to the normal.
pub fn charlie_distribution(alpha: f32, cos_h: f32) -> f32 {
    let sin2 = (1.0 - cos_h * cos_h).max(0.0);
    if sin2 <= 0.0 {
        return 0.0;
    }
    let inverse = 1.0 / alpha;
    (2.0 + inverse) * sin2.powf(0.5 * inverse) / TAU
}

/// Estevez and Kulla's fit of ln Λ for the Charlie distribution of width `alpha`: five
/// coefficients interpolated between their values at α = 0 and α = 1 by (1 − α)².
fn lambda_exponent(x: f32, alpha: f32) -> f32 {
    let t = (1.0 - alpha) * (1.0 - alpha);
    let mix = |at_one: f32, at_zero: f32| at_one + (at_zero - at_one) * t;
    let a = mix(21.5473, 25.3245);
    let b = mix(3.82987, 3.32435);
    let c = mix(0.19823, 0.16801);
    let d = mix(-1.97760, -1.27393);
    let e = mix(-4.32054, -4.85967);
    a / (1.0 + b * x.powf(c)) + d * x + e
}

/// The Charlie distribution's Smith Λ at cosine `cos` (Estevez and Kulla's fit, mirrored
/// about 0.5 above it so that it falls to 0 head-on).
pub fn charlie_lambda(cos: f32, alpha: f32) -> f32 {
    let cos = cos.abs();
    if cos < 0.5 {
        lambda_exponent(cos, alpha).exp()
    } else {
        (2.0 * lambda_exponent(0.5, alpha) - lambda_exponent(1.0 - cos, alpha)).exp()
    }
}

/// The visibility term `G / (4 cos θi cos θo)` of a lobe of width `alpha`.
pub fn sheen_visibility(cos_i: f32, cos_o: f32, alpha: f32) -> f32 {
    let shadowing = 1.0 + charlie_lambda(cos_i, alpha) + charlie_lambda(cos_o, alpha);
    1.0 / (shadowing * 4.0 * cos_i * cos_o)
}

/// The white lobe of width `alpha` in the frame of its normal (+Z), seen along `view` and lit
/// along `light` (both unit, away from the surface): `f · cos θi` and the density of the
/// cosine distribution [`sheen_event`] draws from. Zero below the surface.
pub fn local_sheen(view: Vec3, light: Vec3, alpha: f32) -> GlossyResponse {
    if view.z <= 0.0 || light.z <= 0.0 {
        return GlossyResponse::default();
    }
    let half = (view + light).normalize();
    let visibility = sheen_visibility(light.z, view.z, alpha);
    let value = charlie_distribution(alpha, half.z) * visibility * light.z;
    GlossyResponse {
        value,
        pdf: light.z * FRAC_1_PI,
    }
}

/// [`local_sheen`] at a surface with unit `normal`, seen along `outgoing` and lit along
/// `incident` (world space): what a light sample for the sheen's lobe uses.
pub fn sheen_response(normal: Vec3, outgoing: Vec3, incident: Vec3, alpha: f32) -> GlossyResponse {
    let frame = crate::microfacet::Frame::about(normal);
    local_sheen(frame.to_local(outgoing), frame.to_local(incident), alpha)
}

/// The white lobe's directional albedo at cosine `cos_view`: the mean of `π f cos θi / cos θi`
/// over the cosine distribution, by the midpoint rule on an `n`×`n` grid of its numbers.
pub fn directional_albedo(cos_view: f32, alpha: f32, n: u32) -> f64 {
    let view = Vec3::new((1.0 - cos_view * cos_view).max(0.0).sqrt(), 0.0, cos_view);
    crate::sampling::midpoint_grid_mean(n, |u1, u2| {
        let response = local_sheen(view, cosine_hemisphere(u1, u2), alpha);
        if response.pdf > 0.0 {
            (response.value / response.pdf) as f64
        } else {
            0.0
        }
    })
}

/// The closed form the renderers are checked against: a Lambertian plane of albedo `albedo`
/// under a sheen of `color` and `roughness`, lit by a uniform sky of radiance `sky`, seen at
/// cosine `cos`, channel `channel`: `L·(C·E(θ) + (1 − max(C)E(θ))·ρ·(1 − max(C)Ē))`, the
/// sheen's reflection of the sky (E by quadrature) and the plane beneath lit through it (the
/// dimming by the sheen's table, Ē = 2∫min(E, 1)μ dμ by the midpoint rule).
pub fn sky_plane_radiance(
    sky: f32,
    albedo: f32,
    color: Vec3,
    roughness: f32,
    channel: usize,
) -> impl Fn(f32) -> f64 {
    let table = SheenTable::new(roughness);
    let strongest = color.max_element() as f64;
    let dimming = move |cos: f32| 1.0 - strongest * table.albedo(cos).min(1.0) as f64;
    let lit_through = scene::testing::cosine_weighted_mean(dimming);
    move |cos| {
        let reflected = color[channel] as f64 * directional_albedo(cos, table.alpha, 64);
        let beneath = dimming(cos) * albedo as f64 * lit_through;
        sky as f64 * (reflected + beneath)
    }
}

/// What the sheen does with a ray.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum SheenEvent {
    /// It reflects it into a direction with a colour weight.
    Reflected(Vec3, Vec3),
    /// It passes to the material beneath, weight 1.
    Through,
}

/// The sheen of colour `color` (its texture's texel included) and `table` for a ray along
/// `incoming` at a surface with unit `normal` (facing the ray): `u[0]` chooses, `u[1]` and
/// `u[2]` draw the reflected direction about the normal.
pub fn sheen_event(
    incoming: Vec3,
    normal: Vec3,
    color: Vec3,
    table: &SheenTable,
    u: [f32; 3],
) -> SheenEvent {
    let cos_view = -incoming.dot(normal);
    let chance = table.reflectance(color, cos_view);
    if cos_view <= 0.0 || u[0] >= chance {
        return SheenEvent::Through;
    }
    let frame = crate::microfacet::Frame::about(normal);
    let light = cosine_hemisphere(u[1], u[2]);
    let response = local_sheen(frame.to_local(-incoming), light, table.alpha);
    if response.pdf <= 0.0 {
        return SheenEvent::Reflected(about_axis(normal, light), Vec3::ZERO);
    }
    let weight = table.lobe_scale(color, cos_view) * (response.value / response.pdf);
    SheenEvent::Reflected(about_axis(normal, light), weight)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f32::consts::PI;

    /// The Charlie distribution is normalised: ∫ D(h) cos θh dω = 1 over the hemisphere.
    #[test]
    fn the_distribution_is_normalised() {
        for alpha in [0.0049f32, 0.09, 0.36, 1.0] {
            let n = 4000;
            let integral: f64 = (0..n)
                .map(|i| {
                    let cos = (i as f64 + 0.5) / n as f64;
                    let d = charlie_distribution(alpha, cos as f32) as f64;
                    d * cos * std::f64::consts::TAU / n as f64
                })
                .sum();
            assert!((integral - 1.0).abs() < 2e-3, "α {alpha}: {integral}");
        }
    }

    /// The table matches a fine quadrature between its nodes (within 4 % from cosine 0.1,
    /// 15 % nearer grazing, where the albedo curves fastest); the albedo is at most 1 from
    /// roughness 0.3 at every angle, and averaged over the hemisphere at every roughness.
    #[test]
    fn the_table_interpolates_the_albedo() {
        for roughness in [scene::Sheen::MIN_ROUGHNESS, 0.15, 0.3, 0.6, 1.0] {
            let table = SheenTable::new(roughness);
            let mut hemispherical = 0.0;
            for i in 0..50 {
                let cos = (i as f32 + 0.5) / 50.0;
                hemispherical +=
                    2.0 * cos as f64 * directional_albedo(cos, table.alpha, 200) / 50.0;
            }
            assert!(
                hemispherical < 1.0,
                "roughness {roughness}: {hemispherical}"
            );
            for cos in [0.02f32, 0.15, 0.4, 0.75, 1.0] {
                let exact = directional_albedo(cos, table.alpha, 400);
                let tabled = table.albedo(cos) as f64;
                let tolerance = if cos < 0.1 { 0.15 } else { 0.04 };
                assert!(
                    (tabled - exact).abs() < tolerance * exact.max(0.05),
                    "roughness {roughness}, cos {cos}: {tabled} vs {exact}"
                );
                assert!(exact > 0.0 && (exact <= 1.0 || roughness < 0.3), "{exact}");
                assert!(table.reflectance(Vec3::ONE, cos) <= 1.0);
            }
        }
        // Rough sheens reflect more head-on than smooth ones, which keep to grazing.
        let (smooth, rough) = (SheenTable::new(0.1), SheenTable::new(1.0));
        assert!(rough.albedo(1.0) > 2.0 * smooth.albedo(1.0));
        assert!(smooth.albedo(0.05) > smooth.albedo(1.0));
    }

    /// A textured roughness's table, interpolated over the grid, stays within 3 % (or 0.003)
    /// of its own from cosine 0.1 (and at the grid's nodes equals it).
    #[test]
    fn the_grid_interpolates_tables_between_roughnesses() {
        for roughness in [0.1f32, 0.23, 0.45, 0.8] {
            let (own, grid) = (SheenTable::new(roughness), grid_table(roughness));
            assert_eq!(grid.alpha, roughness * roughness);
            for cos in [0.1f32, 0.3, 0.6, 1.0] {
                let (a, b) = (own.albedo(cos), grid.albedo(cos));
                assert!(
                    (a - b).abs() < 0.03 * a.max(0.1),
                    "r {roughness}, cos {cos}: {a} vs {b}"
                );
            }
        }
        let node = grid_roughness(5);
        assert_eq!(
            grid_table(node).albedo_nodes,
            SheenTable::new(node).albedo_nodes
        );
        assert_eq!(textured_roughness(0.5, 0.5), 0.25);
        assert_eq!(textured_roughness(0.5, 0.0), scene::Sheen::MIN_ROUGHNESS);
    }

    /// The lobe is reciprocal, and `π f cos θi` stays moderate (the events' weights).
    #[test]
    fn the_lobe_is_reciprocal_and_bounded() {
        let alpha = 0.16;
        let directions = [
            Vec3::new(0.3, 0.2, 0.93),
            Vec3::new(-0.9, 0.1, 0.42),
            Vec3::new(0.1, -0.99, 0.05),
        ]
        .map(Vec3::normalize);
        for a in directions {
            for b in directions {
                let ab = local_sheen(a, b, alpha);
                let ba = local_sheen(b, a, alpha);
                // f = value / cos θi is symmetric.
                assert!((ab.value / b.z - ba.value / a.z).abs() < 1e-5 * (ab.value / b.z));
                assert!(ab.value * PI < 4.0, "{}", ab.value * PI);
            }
        }
    }

    /// The event reflects with its probability, and its expected reflected weight is the
    /// sheen's colour times its albedo: what the lobe returns, whatever the choice.
    #[test]
    fn events_return_the_lobes_albedo() {
        let color = Vec3::new(0.9, 0.6, 0.3);
        let normal = Vec3::new(0.0, 0.6, 0.8);
        // Past grazing on a smooth sheen, where E > 1, the lobe returns C, no more.
        for (roughness, cos) in [(0.5, 0.2f32), (0.5, 0.9), (0.1, 0.03)] {
            let table = SheenTable::new(roughness);
            let view = about_axis(normal, Vec3::new((1.0 - cos * cos).sqrt(), 0.0, cos));
            let incoming = -view;
            let chance = table.reflectance(color, cos);
            let event = |u| sheen_event(incoming, normal, color, &table, u);
            assert!(matches!(
                event([chance * 0.99, 0.5, 0.5]),
                SheenEvent::Reflected(..)
            ));
            assert_eq!(event([chance * 1.01, 0.5, 0.5]), SheenEvent::Through);
            // The mean weight of a reflection over a grid of directions, times its chance.
            let n = 400;
            let mut returned = Vec3::ZERO;
            for i in 0..n {
                for j in 0..n {
                    let u = [
                        0.0,
                        (i as f32 + 0.5) / n as f32,
                        (j as f32 + 0.5) / n as f32,
                    ];
                    let SheenEvent::Reflected(direction, weight) = event(u) else {
                        panic!("a choice of 0 reflects");
                    };
                    assert!(direction.dot(normal) > 0.0);
                    returned += weight;
                }
            }
            let mean = returned / (n * n) as f32 * chance;
            let albedo = directional_albedo(cos, table.alpha, 400) as f32;
            let exact = color * albedo * (1.0 / table.albedo(cos)).min(1.0);
            assert!(
                mean.abs_diff_eq(exact, 0.01 * exact.max_element()),
                "cos {cos}: {mean} vs {exact}"
            );
        }
        let table = SheenTable::new(0.5);
        let behind = sheen_event(Vec3::Z, Vec3::Z, color, &table, [0.0; 3]);
        assert_eq!(behind, SheenEvent::Through, "a ray from behind passes");
    }
}
