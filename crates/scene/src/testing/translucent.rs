//! Translucent solids (glTF's diffuse transmission bounding a `KHR_materials_volume`:
//! `crate::DiffuseTransmission::volume`): light passes their surface diffusely and is absorbed
//! inside until it passes out again. Two analytic cases and a Cornell room of them.

use glam::Vec3;

use super::{Fixture, LIT_PLANE_ALBEDO, cornell_room, furnace_around};
use crate::{DiffuseTransmission, Material, PunctualKind, PunctualLight, Scene, Surface};

/// [`translucent_slab_over_plane`]'s slab: its gap above the plane, its thickness and half
/// its width (the plane's too).
pub const TRANSLUCENT_SLAB_GAP: f32 = 0.02;
pub const TRANSLUCENT_SLAB_THICKNESS: f32 = 0.12;
pub const TRANSLUCENT_SLAB_HALF_SIZE: f32 = 1.5;
/// [`translucent_slab_over_plane`]'s sun, straight down (illuminance, lux).
pub const TRANSLUCENT_SLAB_ILLUMINANCE: f32 = 2.0;

/// [`lamp_in_translucent_cube`]'s cube (half its side) and lamp (candela).
pub const TRANSLUCENT_CUBE_HALF_SIDE: f32 = 0.5;
pub const TRANSLUCENT_CUBE_LAMP_INTENSITY: f32 = 2.0;

/// A translucent solid that lets all light through its surface, untinted (diffuse
/// transmission 1, white), and absorbs `absorption` inside.
fn clear_translucent(f: &mut Fixture, name: &str, absorption: Vec3) -> u32 {
    f.builder.add_material(Material {
        name: name.into(),
        base_color: Vec3::ONE,
        absorption,
        diffuse_transmission: translucent_volume(1.0, Vec3::ONE),
        ..Material::default()
    })
}

/// Diffuse transmission of `factor` and `color` bounding a volume.
fn translucent_volume(factor: f32, color: Vec3) -> Option<DiffuseTransmission> {
    DiffuseTransmission::new(factor, color).map(|t| DiffuseTransmission { volume: true, ..t })
}

/// A diffuse square of albedo [`LIT_PLANE_ALBEDO`] under a closed slab of a clear translucent
/// solid absorbing `absorption` inside, [`TRANSLUCENT_SLAB_THICKNESS`] thick,
/// [`TRANSLUCENT_SLAB_GAP`] above the plane and as wide, under a sun straight down of
/// [`TRANSLUCENT_SLAB_ILLUMINANCE`]. Light reaches the plane only through the slab, and the
/// plane's light leaves only through it: the slab's top, seen from above, shows
/// [`translucent_slab_radiance`].
pub fn translucent_slab_over_plane(absorption: Vec3) -> Scene {
    let mut f = Fixture::new("testing::translucent_slab_over_plane");
    let plane = f.material("plane", Surface::Diffuse, Vec3::splat(LIT_PLANE_ALBEDO));
    let slab = clear_translucent(&mut f, "translucent slab", absorption);
    let half = TRANSLUCENT_SLAB_HALF_SIZE;
    let corners = [[-1.0, -1.0], [1.0, -1.0], [1.0, 1.0], [-1.0, 1.0]]
        .map(|[x, z]| Vec3::new(x * half, 0.0, z * half));
    f.quad(corners, plane, Vec3::Y);
    let bottom = TRANSLUCENT_SLAB_GAP;
    let top = bottom + TRANSLUCENT_SLAB_THICKNESS;
    f.closed_box(
        Vec3::new(-half, bottom, -half),
        Vec3::new(half, top, half),
        slab,
    );
    f.builder
        .add_punctual_light(PunctualLight {
            kind: PunctualKind::Directional,
            position: Vec3::ZERO,
            direction: Vec3::NEG_Y,
            intensity: Vec3::splat(TRANSLUCENT_SLAB_ILLUMINANCE),
        })
        .expect("a valid light");
    let eye = Vec3::new(0.0, 2.0, 2.0);
    f.camera(eye, -eye, 60f32.to_radians(), None, "above");
    f.finish()
}

/// The radiance of [`translucent_slab_over_plane`]'s slab top for one channel's `absorption`,
/// as if slab and plane were infinite. The sun's illuminance E passes the top, all of it, as
/// radiance E/π downwards inside; the bottom receives T·E of it, T the slab's diffuse
/// transmittance ([`diffuse_slab_transmittance`] of the optical depth τ = absorption ·
/// thickness), and passes it on to the plane, which returns ρ·T·E upwards; the slab lets T of
/// that reach its top from inside, and the top shows it as radiance ρ·E·T²/π.
pub fn translucent_slab_radiance(absorption: f32) -> f32 {
    let tau = absorption as f64 * TRANSLUCENT_SLAB_THICKNESS as f64;
    let t = diffuse_slab_transmittance(tau);
    (LIT_PLANE_ALBEDO as f64 * TRANSLUCENT_SLAB_ILLUMINANCE as f64 * t * t / std::f64::consts::PI)
        as f32
}

/// What an absorbing slab of optical depth `tau` lets through of light arriving
/// cosine-distributed (a Lambertian radiance): 2∫₀¹ μ·exp(−τ/μ) dμ = 2·E₃(τ), E₃ the
/// exponential integral, by the midpoint rule.
pub fn diffuse_slab_transmittance(tau: f64) -> f64 {
    let steps = 100_000;
    let sum = (0..steps)
        .map(|i| {
            let mu = (i as f64 + 0.5) / steps as f64;
            mu * (-tau / mu).exp()
        })
        .sum::<f64>();
    2.0 * sum / steps as f64
}

/// A point light of [`TRANSLUCENT_CUBE_LAMP_INTENSITY`] candela at the centre of a closed
/// cube of a clear translucent solid absorbing `absorption` inside, the cube
/// 2 · [`TRANSLUCENT_CUBE_HALF_SIDE`] on a side with its top face at y = 0, nothing else. Paths
/// from the lamp start inside the cube (`render::medium::MediumLocator`); the top face, seen
/// from above, shows at (x, 0, z) what reaches its inside, all of it passed on:
/// I·h·exp(−σ·d)/d³/π with h the half side and d the distance to the lamp.
pub fn lamp_in_translucent_cube(absorption: Vec3) -> Scene {
    let mut f = Fixture::new("testing::lamp_in_translucent_cube");
    let cube = clear_translucent(&mut f, "translucent cube", absorption);
    lamp_in_cube(f, cube, TRANSLUCENT_CUBE_HALF_SIDE)
}

/// [`lamp_in_translucent_cube`] of half side [`SCATTERING_CUBE_HALF_SIDE`] (large against a
/// gather radius, which loses light at the face's edges) whose solid scatters `scattering`
/// inside (Henyey–Greenstein of `anisotropy`) and absorbs nothing: all the lamp's light
/// leaves through the six faces, a sixth through each by symmetry, so the top face's radiance
/// averages I / (6·h²) (its exitance 4πI / (6·(2h)²), passed on as a Lambertian surface
/// emits it).
pub fn lamp_in_scattering_cube(scattering: Vec3, anisotropy: f32) -> Scene {
    let mut f = Fixture::new("testing::lamp_in_scattering_cube");
    let cube = f.builder.add_material(Material {
        name: "scattering cube".into(),
        base_color: Vec3::ONE,
        scattering,
        scatter_anisotropy: anisotropy,
        diffuse_transmission: translucent_volume(1.0, Vec3::ONE),
        ..Material::default()
    });
    lamp_in_cube(f, cube, SCATTERING_CUBE_HALF_SIDE)
}

/// [`lamp_in_scattering_cube`]'s half side.
pub const SCATTERING_CUBE_HALF_SIDE: f32 = 2.0;

/// A cube of material `cube`, half side `h`, its top face at y = 0, and the lamp at its
/// centre ([`lamp_in_translucent_cube`]).
fn lamp_in_cube(mut f: Fixture, cube: u32, h: f32) -> Scene {
    f.closed_box(Vec3::new(-h, -2.0 * h, -h), Vec3::new(h, 0.0, h), cube);
    f.builder
        .add_punctual_light(PunctualLight {
            kind: PunctualKind::Point,
            position: Vec3::new(0.0, -h, 0.0),
            direction: Vec3::NEG_Y,
            intensity: Vec3::splat(TRANSLUCENT_CUBE_LAMP_INTENSITY),
        })
        .expect("a valid light");
    let eye = Vec3::new(0.0, 2.0, 2.0);
    f.camera(eye, -eye, 60f32.to_radians(), None, "above");
    f.finish()
}

/// [`crate::testing::furnace_sphere`] with a lossless scattering translucent solid in view (a
/// ball of radius 0.3 half a unit ahead of the camera: its surface passes all light, white;
/// inside, `scattering` σs, no absorption, Henyey–Greenstein of `anisotropy`): light walks
/// through it and out, none lost, so in the furnace it is invisible.
pub fn furnace_with_scattering_solid(scattering: Vec3, anisotropy: f32) -> Scene {
    furnace_around(
        "testing::furnace_with_scattering_solid",
        Material {
            name: "scattering solid".into(),
            base_color: Vec3::ONE,
            scattering,
            scatter_anisotropy: anisotropy,
            diffuse_transmission: translucent_volume(1.0, Vec3::ONE),
            ..Material::default()
        },
    )
}

/// [`crate::testing::cornell_caustics`]'s room with translucent solids: a wax sphere front
/// right (warm white, 80 % of its Lambertian lobe passing the surface; inside, scattering
/// about 4 times over its radius, forward-leaning, and absorbing blue most) with a small lamp
/// inside it, low, and a jade block back left (pale green, 60 % through; scattering
/// isotropically, absorbing red most), lit by the ceiling light.
pub fn cornell_translucent_solids() -> Scene {
    let mut f = Fixture::new("testing::cornell_translucent_solids");
    cornell_room(&mut f);
    let wax = f.builder.add_material(Material {
        name: "wax".into(),
        base_color: Vec3::new(0.9, 0.85, 0.75),
        absorption: Vec3::new(0.001, 0.003, 0.008),
        scattering: Vec3::new(0.04, 0.04, 0.035),
        scatter_anisotropy: 0.3,
        diffuse_transmission: translucent_volume(0.8, Vec3::new(1.0, 0.95, 0.85)),
        ..Material::default()
    });
    let jade = f.builder.add_material(Material {
        name: "jade".into(),
        base_color: Vec3::new(0.45, 0.7, 0.5),
        absorption: Vec3::new(0.01, 0.002, 0.006),
        scattering: Vec3::new(0.02, 0.03, 0.025),
        diffuse_transmission: translucent_volume(0.6, Vec3::new(0.6, 0.95, 0.7)),
        ..Material::default()
    });
    let centre = Vec3::new(380.0, 110.0, 370.0);
    f.sphere(centre, 110.0, wax, false);
    f.builder
        .add_punctual_light(PunctualLight {
            kind: PunctualKind::Point,
            position: centre - Vec3::new(0.0, 60.0, 0.0),
            // glTF's: a point light's node looks down −z.
            direction: Vec3::NEG_Z,
            intensity: Vec3::new(2.0e4, 1.5e4, 0.8e4),
        })
        .expect("a valid light");
    f.closed_box(
        Vec3::new(120.0, 0.0, 120.0),
        Vec3::new(260.0, 200.0, 260.0),
        jade,
    );
    f.finish()
}
