//! The state both backends keep, as `#[repr(C)]` structs the GPU mirrors in WGSL
//! (`crates/gpu/shaders/shared/sppm_types.wgsl`; `crates/gpu/tests/layout.rs` checks sizes and
//! offsets through naga). The CPU backend holds the same structs in `Vec`s, so the twins run on
//! identical data.

use bytemuck::{Pod, Zeroable};
use glam::Vec3;

/// `PathSlot::depth` of a slot whose path has ended: the next photon pass starts a new one.
pub const SLOT_IDLE: u32 = u32::MAX;

/// One photon path slot (64 bytes): a light path in flight, advanced one bounce per pass.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct PathSlot {
    /// Where the next segment starts (already offset off the surface).
    pub origin: [f32; 3],
    /// Bounces so far, or [`SLOT_IDLE`].
    pub depth: u32,
    /// Unit direction of the next segment.
    pub direction: [f32; 3],
    /// Alpha cut-outs passed through (they do not count as bounces).
    pub pass_throughs: u32,
    /// The path's flux (RGB, watts in scene units).
    pub flux: [f32; 3],
    /// Whether the path has left a diffuse surface (its later photons are indirect, not
    /// caustic: [`crate::packing::photon_normal`]) and the solid it is inside
    /// ([`crate::medium`]), packed by [`crate::medium::pack_slot_state`].
    pub state: u32,
    /// The path's walk through scattering solids ([`crate::scattering::Walk`]): each colour
    /// channel's density of drawing it over their mean, carried from step to step so that
    /// the whole path's walk is weighed as one (its weight is in `flux` already).
    pub walk_densities: [f32; 3],
    /// The walk's hero channel, or [`crate::scattering::NO_WALK`] before the path's first
    /// scattering solid.
    pub walk_hero: u32,
}

impl PathSlot {
    /// A slot with no path: the first photon pass starts one in it.
    pub const IDLE: PathSlot = PathSlot {
        origin: [0.0; 3],
        depth: SLOT_IDLE,
        direction: [0.0; 3],
        pass_throughs: 0,
        flux: [0.0; 3],
        state: 0,
        walk_densities: [1.0; 3],
        walk_hero: crate::scattering::NO_WALK,
    };
}

/// A photon stored by this pass's slot (32 bytes). Zero flux: the slot stored none. Its
/// normal's lowest bit says whether it is a caustic photon ([`crate::packing::photon_normal`]).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct Photon {
    pub position: [f32; 3],
    /// The surface normal on the side the photon arrived from, octahedral-packed
    /// ([`crate::packing::pack_normal`]).
    pub normal: u32,
    /// Flux arriving (RGB).
    pub flux: [f32; 3],
    pub pad: u32,
}

impl Photon {
    pub fn is_stored(&self) -> bool {
        self.flux != [0.0; 3]
    }
}

/// Where a pixel's eye path met its first non-specular surface (32 bytes). Zero weight: none
/// (the path escaped, or ended on a black or specular chain).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct VisiblePoint {
    pub position: [f32; 3],
    /// The shading normal on the side the eye path arrived from, octahedral-packed.
    pub normal: u32,
    /// Eye-path throughput × albedo / π: turns gathered flux into radiance.
    pub weight: [f32; 3],
    pub pad: u32,
}

impl VisiblePoint {
    pub fn is_valid(&self) -> bool {
        self.weight != [0.0; 3]
    }
}

/// A pixel's progressive statistics (80 bytes): SPPM's τ, N and R three times, for the
/// indirect photons and for the caustic ones (each set shrinks at its own α: caustics are
/// sharp, indirect light smooth) on surfaces, and for the photons scattered in murky glass
/// around visible points inside it (a sphere's volume for a disc's area,
/// `render::scattering`), and the sum of the direct light its eye passes saw. The GPU keeps
/// the first [`PIXEL_STATS_SURFACE_BYTES`] of each in one buffer and the volume photons' τ
/// (with the padding) in another, allocated only where the scene has murky glass: a buffer
/// of 80 bytes a pixel would pass a 128 MiB storage binding (lavapipe's) at 1920 × 1080.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct PixelStats {
    /// Accumulated flux of indirect photons, already scaled to the current radius.
    pub tau: [f32; 3],
    /// Accumulated indirect photon count N (fractional: α·M per update).
    pub photon_count: f32,
    /// Sum over eye passes of the emission seen through specular chains and of the sampled
    /// direct light.
    pub direct: [f32; 3],
    /// Current gather radius R of indirect photons.
    pub radius: f32,
    /// τ, N and R of the caustic photons.
    pub caustic_tau: [f32; 3],
    pub caustic_count: f32,
    pub caustic_radius: f32,
    /// 1 once an eye pass's camera ray met a mirror, glass or metal first in this pixel: later
    /// eye passes trace it more paths ([`SPECULAR_EXTRA_PATHS`]).
    pub specular_seen: u32,
    /// N, R and τ of the volume photons (τ already scaled to the current radius's volume;
    /// last, so that each τ starts a 16-byte boundary, as a WGSL vec3 must).
    pub volume_count: f32,
    pub volume_radius: f32,
    pub volume_tau: [f32; 3],
    pub pad: u32,
}

const _: () = assert!(size_of::<PixelStats>() == 80);

/// The bytes of a [`PixelStats`] before its volume photons' τ: the part the GPU keeps for
/// every scene (WGSL's `PixelStats`).
pub const PIXEL_STATS_SURFACE_BYTES: usize = std::mem::offset_of!(PixelStats, volume_tau);
const _: () = assert!(PIXEL_STATS_SURFACE_BYTES == 64);
// A 1920 × 1080 image's statistics fit a 128 MiB storage binding (lavapipe's): growing this
// part would refuse full-HD renders there, as session 39's 80 bytes did.
const _: () = assert!(PIXEL_STATS_SURFACE_BYTES * 1920 * 1080 <= 128 << 20);

impl PixelStats {
    /// A pixel before any photon: nothing gathered, each class at its starting radius.
    pub fn initial(radius: f32, caustic_radius: f32, volume_radius: f32) -> PixelStats {
        PixelStats {
            radius,
            caustic_radius,
            volume_radius,
            ..PixelStats::default()
        }
    }
}

/// More camera paths an eye pass traces in a pixel where an earlier one met a specular surface
/// first. Seen through glass or in a mirror, what a pixel shows moves far with the sub-pixel
/// jitter (a light's small image, a caustic's edge, the floor or the wall), so one path a pass
/// leaves such pixels far noisier than the rest; the extra paths count the emission they meet
/// and a light sample at their diffuse surface, averaged with the first path's (the photons
/// are still gathered at the first path's visible point only). One more path cut the error of
/// cornell-caustics' caustic window by a fifth at 7 % more time (three: a fifth at 20 %).
pub const SPECULAR_EXTRA_PATHS: u32 = 1;

/// One light for photon emission (64 bytes), in a table ordered like its CDF. `kind` says
/// which and what the shared fields hold:
///
/// | kind | `v0` | `edge1` | `edge2` | `flux` (÷ probability of picking it) |
/// |---|---|---|---|---|
/// | [`LIGHT_TRIANGLE`] | first vertex | p1 − p0 | p2 − p0 | its power |
/// | [`LIGHT_POINT`] | position | — | — | 4π · intensity |
/// | [`LIGHT_SPOT`] | position | unit axis | (cos inner, cos outer, falloff shape: `scene::SpotFalloff::code`) | intensity · outer cone's solid angle |
/// | [`LIGHT_DIRECTIONAL`] | disk centre | unit direction | (disk radius, 0, 0) | illuminance · disk area |
/// | [`LIGHT_SKY`] | bounding-sphere centre | — | (its radius, 0, 0) | radiance · disk area · 4π |
///
/// A spot's photons are also weighted by [`scene::lights::spot_falloff`] at their direction;
/// a directional light's and the sky's by the area they start from over the disk's
/// ([`crate::emission::parallel_start`]).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct Light {
    pub v0: [f32; 3],
    /// Probability of picking this light or one before it (the last is exactly 1).
    pub cdf: f32,
    pub edge1: [f32; 3],
    /// 1 if a triangle light emits from both faces.
    pub double_sided: u32,
    pub edge2: [f32; 3],
    /// [`LIGHT_TRIANGLE`], [`LIGHT_POINT`], [`LIGHT_SPOT`] or [`LIGHT_DIRECTIONAL`].
    pub kind: u32,
    /// Flux a path leaving this light carries: see the table above.
    pub flux: [f32; 3],
    /// The absorbing solid its paths start in (`crate::medium::MediumLocator`), or
    /// `crate::medium::NO_MEDIUM`.
    pub medium: u32,
}

impl Default for Light {
    /// All zero, outside every solid.
    fn default() -> Light {
        Light {
            medium: crate::medium::NO_MEDIUM,
            ..Zeroable::zeroed()
        }
    }
}

/// [`Light::kind`] of an emissive triangle.
pub const LIGHT_TRIANGLE: u32 = 0;
/// [`Light::kind`] of a point light.
pub const LIGHT_POINT: u32 = 1;
/// [`Light::kind`] of a spot light.
pub const LIGHT_SPOT: u32 = 2;
/// [`Light::kind`] of a directional light.
pub const LIGHT_DIRECTIONAL: u32 = 3;
/// [`Light::kind`] of the sky: a uniform direction, then a point on the disk across the scene
/// perpendicular to it, upstream.
pub const LIGHT_SKY: u32 = 4;

/// [`SppmParams::sample_lights`] bit: a light sample at every visible point.
pub const SAMPLE_AT_VISIBLE_POINTS: u32 = 1;
/// [`SppmParams::sample_lights`] bit: a light sample at every glossy reflection an eye path
/// meets (rough metal, a rough plastic coat, solid frosted glass from outside), weighed against
/// the lobe's own sampling.
pub const SAMPLE_AT_GLOSSY: u32 = 2;

/// Render-wide constants (uniform buffer, 160 bytes).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct SppmParams {
    pub eye: [f32; 3],
    pub width: u32,
    pub forward: [f32; 3],
    pub height: u32,
    /// The film's half extents (`scene::Camera::film_half_extents`): for a perspective camera
    /// right × tan(yfov/2) × aspect, so film x = ±1 lies at forward ± this; for an
    /// orthographic one right × half height × aspect, across the film about the eye.
    pub right: [f32; 3],
    pub slot_count: u32,
    /// Up × tan(yfov/2), or up × half height.
    pub up: [f32; 3],
    /// Entries in the stochastic hash table.
    pub hash_size: u32,
    /// SPPM's α for the caustic photons.
    pub alpha: f32,
    /// Bounces before a path (photon or eye) is cut off.
    pub max_depth: u32,
    pub light_count: u32,
    pub seed: u32,
    /// Offset of a continuation ray's origin off a surface (scene-relative).
    pub epsilon: f32,
    /// Where f16 storage measures positions from: the scene's centre
    /// ([`crate::half_storage`]).
    pub storage_origin: [f32; 3],
    /// What f16 storage multiplies fluxes by: 1 / the largest light's flux, which bounds every
    /// photon's (Russian roulette on the largest channel never raises one), so stored fluxes
    /// lie in [0, 1] and keep f16's relative precision. (A sky map's photons may carry a few
    /// times its table flux in one channel, `render::sky_map`: still far inside f16's range.)
    pub storage_flux_scale: f32,
    /// Radiance of the sky (zero without one): what camera paths that leave the scene see.
    pub sky: [f32; 3],
    /// Where eye passes sample the lights, bits: [`SAMPLE_AT_VISIBLE_POINTS`] (and photons
    /// are then stored from their second hit on, [`crate::direct::DirectLight::Sampled`];
    /// without it photons carry direct light) and [`SAMPLE_AT_GLOSSY`].
    pub sample_lights: u32,
    /// 1 if some material is an alpha cut-out, so shadow rays must look at what they hit
    /// (0: any hit blocks them).
    pub cut_outs: u32,
    /// Photon passes per eye pass: eye pass `pass / eye_every` picks its pixels' jitter
    /// ([`crate::rng::pixel_jitter`]).
    pub eye_every: u32,
    /// SPPM's α for the indirect photons (`alpha` is the caustic photons').
    pub indirect_alpha: f32,
    /// The absorbing solid the camera is in (`crate::medium::MediumLocator`), where eye paths
    /// start, or `crate::medium::NO_MEDIUM`.
    pub camera_medium: u32,
    /// Photon classes the stochastic hash keeps apart, each in its own table of `hash_size`
    /// entries (`crate::hash::photon_class`): [`crate::hash::PHOTON_CLASSES`] where some
    /// glass disperses, else 1.
    pub photon_classes: u32,
    /// The camera's thin lens (`scene::Lens`): the radius of the disk eye paths start on, 0
    /// for a pinhole, and the distance ahead of the eye of the plane in focus
    /// ([`crate::lens::camera_ray`]).
    pub lens_radius: f32,
    pub focus_distance: f32,
    /// Half the sides of the scene's bounding box, 1 % longer, about its centre (the bounding
    /// sphere's): photons of a directional light or the sky start in the rectangle bounding
    /// the box's shadow across their direction where it is smaller than the sphere's disk
    /// ([`crate::emission::parallel_start`]). Zero: always the disk.
    pub scene_half_extent: [f32; 3],
    /// The lens's aperture (`scene::Lens::blades`, `rotation`): 0 round, else a regular
    /// polygon with a vertex `aperture_rotation` radians from right towards up.
    pub aperture_blades: u32,
    pub aperture_rotation: f32,
    /// Light samples drawn per light sample at a visible point whose only lobe is Lambertian,
    /// one kept ([`crate::resampling`]); 0 or 1: the plain sample.
    pub light_candidates: u32,
    /// 1 for an orthographic camera (`scene::Projection`): its rays leave the film point
    /// `eye + sx·right + sy·up` along `forward` ([`crate::lens::camera_ray`]), `right` and
    /// `up` the film's half extents; 0 for a perspective one.
    pub orthographic: u32,
    /// Tenths of the lit pixels whose radii may lie above the one the next pass's surface
    /// cells are sized for, shrinking to fit ([`crate::radius_histogram`]): 2 for the
    /// stochastic hash, 0 (cells for the largest radius) for full lists and the kd-tree.
    pub shrunk_tenths: u32,
}

impl Default for SppmParams {
    /// All zero, the camera outside every solid.
    fn default() -> SppmParams {
        SppmParams {
            camera_medium: crate::medium::NO_MEDIUM,
            photon_classes: 1,
            ..Zeroable::zeroed()
        }
    }
}

impl SppmParams {
    /// The stochastic hash's photon classes ([`SppmParams::photon_classes`]; params made
    /// without them, all zero, have one).
    pub fn hash_classes(&self) -> u32 {
        self.photon_classes.max(1)
    }

    /// Entries of the stochastic hash's tables, all classes.
    pub fn hash_entries(&self) -> usize {
        self.hash_size as usize * self.hash_classes() as usize
    }

    pub fn pixel_count(&self) -> u32 {
        self.width * self.height
    }
}

/// Indices into the counters buffer (u32 atomics on the GPU).
pub mod counter {
    /// Photon passes finished.
    pub const PASS: usize = 0;
    /// Emitted photon paths, low and high words of a u64.
    pub const EMITTED_LO: usize = 1;
    pub const EMITTED_HI: usize = 2;
    /// Paths emitted by the pass in flight (folded into the total by `finish_pass`).
    pub const EMITTED_PASS: usize = 3;
    /// Bits of the largest surface radius (indirect, and caustic where caustic photons share
    /// the surfaces' grid), after this pass's update, of the pixels that have met photons
    /// (f32, positive, so u32 order; 0: none has).
    pub const MAX_RADIUS: usize = 4;
    /// Bits of the hash cell size for this pass (f32).
    pub const CELL_SIZE: usize = 5;
    /// The same two for the volume photons' own grid (`crate::hash`): the largest volume
    /// radius that has met photons, and their cells' size.
    pub const VOLUME_MAX_RADIUS: usize = 6;
    pub const VOLUME_CELL_SIZE: usize = 7;
    /// The pass's lit surface radii counted by bucket (`crate::radius_histogram`), then
    /// read and cleared by `finish_pass`.
    pub const RADIUS_HISTOGRAM: usize = 8;
    /// The caustic photons' own grid, where the stochastic hash keeps them apart
    /// (`crate::hash::caustic_apart`): their largest lit radius, their cells' size and their
    /// radii's histogram, as the surfaces' above (which then serve the indirect radii only).
    pub const CAUSTIC_MAX_RADIUS: usize =
        RADIUS_HISTOGRAM + crate::radius_histogram::RADIUS_BUCKETS;
    pub const CAUSTIC_CELL_SIZE: usize = CAUSTIC_MAX_RADIUS + 1;
    pub const CAUSTIC_RADIUS_HISTOGRAM: usize = CAUSTIC_CELL_SIZE + 1;
    pub const COUNT: usize = CAUSTIC_RADIUS_HISTOGRAM + crate::radius_histogram::RADIUS_BUCKETS;
}

/// Words per hash entry: the kept photon's priority, the cell's photon count, the kept photon.
pub const HASH_ENTRY_WORDS: usize = 3;
pub mod hash_word {
    pub const PRIORITY: usize = 0;
    pub const COUNT: usize = 1;
    pub const WINNER: usize = 2;
}

/// Emitted photon paths so far, from the counters' two words.
pub fn emitted_total(low: u32, high: u32) -> u64 {
    ((high as u64) << 32) | low as u64
}

/// The counters' starting values for a render whose largest gather radius on surfaces starts
/// at `radius`, whose caustic photons' at `caustic_radius` (their own grid's, where they
/// have one) and whose volume photons' at `volume_radius`.
pub fn initial_counters(
    radius: f32,
    caustic_radius: f32,
    volume_radius: f32,
) -> [u32; counter::COUNT] {
    let mut counters = [0; counter::COUNT];
    counters[counter::CELL_SIZE] = crate::hash::grid_cell_size(radius, false).to_bits();
    counters[counter::CAUSTIC_CELL_SIZE] =
        crate::hash::grid_cell_size(caustic_radius, false).to_bits();
    counters[counter::VOLUME_CELL_SIZE] =
        crate::hash::grid_cell_size(volume_radius, true).to_bits();
    counters
}

pub fn vec3(a: [f32; 3]) -> Vec3 {
    Vec3::from_array(a)
}

/// The far end of an unbounded ray (finite, so the kernels never meet inf).
pub const RAY_T_MAX: f32 = f32::MAX / 2.0;
/// Alpha cut-outs a path may pass through before it is cut off.
pub const MAX_PASS_THROUGHS: u32 = 16;
