//! What an SPPM render is asked to do, checked before any work.

use std::time::Duration;

use crate::density::Density;
use crate::direct::DirectLight;
use crate::half_storage::Precision;

/// α of the SPPM radius update (Hachisuka & Jensen 2009 suggest 2/3 … 0.7).
pub const DEFAULT_ALPHA: f32 = 2.0 / 3.0;
/// α of the indirect photons' radius that `kousen render` and `kousen view` use: indirect
/// light is smooth, so its radius may shrink slower, for less noise (docs/BENCHMARKS.md §3,
/// session 11). [`Settings::new`] keeps one α for both.
pub const MEASURED_INDIRECT_ALPHA: f32 = 0.8;
/// The caustic photons' first radius as a share of the indirect ones' that `kousen render`
/// and `kousen view` use with sampled direct light, where only scenes with mirrors or glass
/// have caustic photons (docs/BENCHMARKS.md §3). Session 15, eight seeds: 0.7 reached
/// Mitsuba's errors inside cornell-caustics' glass caustic 1.4–1.6× sooner than 1 and raised
/// cornell-metal's whole-image error (broad caustics of flat mirrors) by about a fifth.
/// Session 19, with the extra eye paths of specular pixels, which took much of the caustic
/// window's variance away so that its rim's bias led: 0.55 reached Mitsuba's 4096-spp error
/// there 1.16–1.19× sooner than 0.7 (two runs of eight seeds), cornell-metal's error +8 %
/// (ten seeds), cornell-rough's level. [`Settings::new`] keeps 1.
pub const MEASURED_CAUSTIC_RADIUS_SHARE: f32 = 0.55;
/// Photon passes per eye pass. Measured on lavapipe with the Cornell scenes (docs/BENCHMARKS.md
/// §3): fewer eye passes leave more time for photons, more anti-alias the edges sooner.
pub const DEFAULT_EYE_EVERY: u32 = 8;
/// Bounces before a photon or eye path is cut off. Well past glslppm's 10
/// ([`GLSLPPM_MAX_DEPTH`]): light that enters glass can reflect inside it many times, and a
/// frosted (rough) glass sphere scatters much of it back inward, so a cut at 10 lost 4 % of
/// what `scenes/cornell-frosted.gltf`'s frosted sphere shows (1 % at 32, against Mitsuba's
/// unlimited path tracer). Paths that end sooner pay nothing for it (renders of the glass
/// scenes 0–10 % slower on the CPU and through lavapipe, docs/BENCHMARKS.md §3).
pub const DEFAULT_MAX_DEPTH: u32 = 32;
/// glslppm's path length, the setting its figures were measured with (and `kousen bench
/// photons`' default, which compares against the talk's).
pub const GLSLPPM_MAX_DEPTH: u32 = 10;
/// Initial gather radius in pixel footprints (glslppm's choice).
pub const INITIAL_RADIUS_FOOTPRINTS: f32 = 2.5;

#[derive(Clone, Debug, PartialEq)]
pub struct Settings {
    pub width: u32,
    pub height: u32,
    /// Photon path slots, each advanced one bounce per pass.
    pub photons: u32,
    /// α of the caustic photons' statistics (and of the indirect ones' unless
    /// `indirect_alpha` says otherwise).
    pub alpha: f32,
    /// α of the indirect photons' statistics.
    pub indirect_alpha: f32,
    /// An eye pass before every `eye_every`-th photon pass (the first included).
    pub eye_every: u32,
    /// Hash table entries per photon slot.
    pub hash_ratio: f32,
    /// How photons are found around the visible points (benchmarks compare the methods).
    pub density: Density,
    /// How photons and visible points are stored (benchmarks compare f32 and f16).
    pub precision: Precision,
    /// Where direct light comes from: photons (the talk's scheme, and this default) or light
    /// samples at the visible points (`kousen render`'s and `kousen view`'s default).
    pub direct: DirectLight,
    /// Whether eye paths sample the lights at glossy reflections (rough metal, rough plastic
    /// coats, solid frosted glass met from outside), weighed against the lobe's own sampling (multiple importance sampling); off,
    /// a glossy reflection of a light is seen only by the paths its sampling sends there.
    /// On by default; benchmarks and tests compare.
    pub glossy_light_sampling: bool,
    /// Candidates per light sample at a Lambertian-only visible point, one kept by what it
    /// brings ([`crate::resampling`]); 1: picked by power alone; `None` (the default): as the
    /// scene's lights call for ([`crate::resampling::auto_candidates`]).
    pub light_candidates: Option<u32>,
    pub max_depth: u32,
    pub seed: u32,
    /// Every pixel's starting gather radius; `None`: from the scene's bounding box
    /// ([`crate::integrator::initial_radius`]). Renderers set it from the view
    /// ([`crate::integrator::initial_radius_from_view`]).
    pub initial_radius: Option<f32>,
    /// The caustic photons' starting radius as a share of `initial_radius` (1: the same).
    /// Caustics through glass are dense and sharp-edged, so a smaller first radius blurs their
    /// rims less at little cost in noise; caustics thrown broad by flat mirrors lose (measured
    /// in docs/BENCHMARKS.md §3, session 12).
    pub caustic_radius_share: f32,
}

impl Settings {
    /// Default settings for an image size and a number of photon slots.
    pub fn new(width: u32, height: u32, photons: u32) -> Settings {
        Settings {
            width,
            height,
            photons,
            alpha: DEFAULT_ALPHA,
            indirect_alpha: DEFAULT_ALPHA,
            eye_every: DEFAULT_EYE_EVERY,
            hash_ratio: 1.0,
            density: Density::StochasticHash,
            precision: Precision::F32,
            direct: DirectLight::Photons,
            glossy_light_sampling: true,
            light_candidates: None,
            max_depth: DEFAULT_MAX_DEPTH,
            seed: 0,
            initial_radius: None,
            caustic_radius_share: 1.0,
        }
    }

    /// [`Settings::light_candidates`] for `scene`, `auto` resolved
    /// ([`crate::resampling::auto_candidates`]).
    pub fn light_candidates_for(&self, scene: &scene::Scene) -> u32 {
        self.light_candidates
            .unwrap_or_else(|| crate::resampling::auto_candidates(scene))
    }

    /// Hash table entries: `hash_ratio × photons`, at least 1.
    pub fn hash_size(&self) -> u32 {
        ((self.photons as f64 * self.hash_ratio as f64).round() as u64).clamp(1, u32::MAX as u64)
            as u32
    }

    pub fn validate(&self) -> Result<(), SettingsError> {
        if self.width == 0 || self.height == 0 {
            return Err(SettingsError::EmptyImage);
        }
        if self.width as u64 * self.height as u64 > u32::MAX as u64 {
            return Err(SettingsError::TooManyPixels);
        }
        if self.photons == 0 {
            return Err(SettingsError::NoPhotons);
        }
        if !(self.alpha > 0.0 && self.alpha < 1.0) {
            return Err(SettingsError::Alpha(self.alpha));
        }
        if !(self.indirect_alpha > 0.0 && self.indirect_alpha < 1.0) {
            return Err(SettingsError::IndirectAlpha(self.indirect_alpha));
        }
        if self.eye_every == 0 {
            return Err(SettingsError::EyeEvery);
        }
        if let Some(n) = self.light_candidates
            && !(1..=crate::resampling::MAX_LIGHT_CANDIDATES).contains(&n)
        {
            return Err(SettingsError::LightCandidates(n));
        }
        if !(self.hash_ratio.is_finite() && self.hash_ratio > 0.0) {
            return Err(SettingsError::HashRatio(self.hash_ratio));
        }
        if self.max_depth == 0 {
            return Err(SettingsError::MaxDepth);
        }
        if let Some(r) = self.initial_radius
            && !(r.is_finite() && r > 0.0)
        {
            return Err(SettingsError::Radius(r));
        }
        if !(self.caustic_radius_share > 0.0 && self.caustic_radius_share <= 1.0) {
            return Err(SettingsError::CausticRadiusShare(self.caustic_radius_share));
        }
        Ok(())
    }
}

/// How long to render.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Budget {
    Passes(u32),
    Time(Duration),
}

#[derive(Debug, thiserror::Error, PartialEq)]
pub enum SettingsError {
    #[error("the image must be at least 1×1 pixels")]
    EmptyImage,
    #[error("the image has more than 4294967295 pixels")]
    TooManyPixels,
    #[error("--photons must be at least 1")]
    NoPhotons,
    #[error("--alpha must lie strictly between 0 and 1, got {0}")]
    Alpha(f32),
    #[error("--indirect-alpha must lie strictly between 0 and 1, got {0}")]
    IndirectAlpha(f32),
    #[error("--eye-every must be at least 1")]
    EyeEvery,
    #[error("--light-candidates must be auto or lie between 1 and 64, got {0}")]
    LightCandidates(u32),
    #[error("--hash-ratio must be a positive number, got {0}")]
    HashRatio(f32),
    #[error("--max-depth must be at least 1")]
    MaxDepth,
    #[error("the initial radius must be a positive number, got {0}")]
    Radius(f32),
    #[error("--caustic-radius must lie in (0, 1] (a share of --radius), got {0}")]
    CausticRadiusShare(f32),
}
