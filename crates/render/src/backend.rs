//! The kernels an SPPM backend runs (DESIGN.md, step 3). The GPU backend (crate `gpu`) and the
//! CPU backend (crate `cpu`) implement them under the same names; the integrator only decides
//! when each runs. Kernels may run asynchronously: only `synchronize` and the `read_*` methods
//! wait for them.

use crate::buffers::{Light, PixelStats, SppmParams};
use crate::density::Density;
use crate::half_storage::Precision;

/// Everything a backend needs to start a render, made by the integrator.
#[derive(Clone, Debug)]
pub struct Setup {
    pub params: SppmParams,
    pub lights: Vec<Light>,
    /// Every pixel's starting gather radius of the indirect photons.
    pub initial_radius: f32,
    /// And of the caustic photons.
    pub initial_caustic_radius: f32,
    /// And of the volume photons (`render::scattering::initial_volume_radius`).
    pub initial_volume_radius: f32,
    /// How photons are found around the visible points.
    pub density: Density,
    /// How photons and visible points are stored.
    pub precision: Precision,
}

impl Setup {
    /// Every pixel's starting statistics.
    pub fn initial_stats(&self) -> crate::buffers::PixelStats {
        crate::buffers::PixelStats::initial(
            self.initial_radius,
            self.initial_caustic_radius,
            self.initial_volume_radius,
        )
    }

    /// The counters' starting values: the first cells sized by the largest starting radius on
    /// surfaces, and the volume photons' by theirs.
    pub fn initial_counters(&self) -> [u32; crate::buffers::counter::COUNT] {
        let largest = self.initial_radius.max(self.initial_caustic_radius);
        crate::buffers::initial_counters(
            largest,
            self.initial_caustic_radius,
            self.initial_volume_radius,
        )
    }
}

/// What a backend reads back: every pixel's statistics and the paths emitted so far.
#[derive(Clone, Debug, PartialEq)]
pub struct Statistics {
    pub pixels: Vec<PixelStats>,
    pub emitted_paths: u64,
}

/// The state a render carries from one pass to the next, as the backend stores it (raw 32-bit
/// words, so a restore is exact whatever the storage precision): counters, path slots, visible
/// points and pixel statistics. Photons and the hash are rebuilt every pass and not kept.
/// Taken between passes only.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Snapshot {
    pub counters: Vec<u32>,
    pub slots: Vec<u32>,
    pub visible_points: Vec<u32>,
    pub pixels: Vec<u32>,
}

impl Snapshot {
    /// The parts with their names, in file order.
    pub fn parts(&self) -> [(&'static str, &[u32]); 4] {
        [
            ("counters", &self.counters),
            ("slots", &self.slots),
            ("visible_points", &self.visible_points),
            ("pixels", &self.pixels),
        ]
    }

    /// An error in words unless each part holds the number of words given (the backend's
    /// sizes for its render, in [`Snapshot::parts`] order).
    pub fn check_sizes(&self, expected: [usize; 4]) -> Result<(), BackendError> {
        for ((name, words), want) in self.parts().into_iter().zip(expected) {
            if words.len() != want {
                return Err(BackendError::Device(format!(
                    "the checkpoint's {name} hold {} words, this render's {want}: it was made with other settings, another backend or another version of kousen",
                    words.len()
                )));
            }
        }
        Ok(())
    }
}

#[derive(Debug, thiserror::Error)]
pub enum BackendError {
    /// The device or its driver failed (said in words).
    #[error("{0}")]
    Device(String),
    /// The render does not fit the device's limits (said in words, with what would make it
    /// fit): another backend may take it.
    #[error("{0}")]
    DoesNotFit(String),
}

pub trait Backend {
    /// "gpu" or "cpu".
    fn name(&self) -> &'static str;
    /// The adapter (GPU) or processor (CPU) doing the work.
    fn adapter(&self) -> String;

    /// Allocates and initialises the state: idle path slots, pixel statistics at the initial
    /// radius, counters at zero.
    fn start(&mut self, setup: &Setup) -> Result<(), BackendError>;
    /// Camera paths to the first non-specular surface: new visible points, direct emission.
    fn eye_pass(&mut self);
    /// Every path slot advances one bounce; idle slots start new light paths first.
    fn photon_pass(&mut self);
    /// The stochastic spatial hash of this pass's photons.
    fn build_hash(&mut self);
    /// Each visible point gathers from the hash and updates its pixel's statistics; then the
    /// pass is closed (emitted count totalled, next cell size from the largest radius).
    fn gather(&mut self);
    /// Waits until every kernel asked for so far has finished.
    fn synchronize(&mut self) -> Result<(), BackendError>;
    /// Paths emitted so far (waits for the work queued).
    fn emitted_paths(&mut self) -> Result<u64, BackendError>;
    /// Every pixel's statistics and the paths emitted (waits for the work queued).
    fn read_statistics(&mut self) -> Result<Statistics, BackendError>;
    /// The visible points of the last eye pass, one a pixel, as f32 whatever the storage
    /// (waits for the work queued).
    fn read_visible_points(&mut self) -> Result<Vec<crate::buffers::VisiblePoint>, BackendError>;
    /// Bytes the backend allocated for the render, by kind (scene, BVH, photons, hash, ...).
    fn memory(&self) -> Vec<(&'static str, u64)>;
    /// The state between passes (waits for the work queued).
    fn snapshot(&mut self) -> Result<Snapshot, BackendError>;
    /// Puts back a [`Snapshot`] this backend took of a render started with the same setup; an
    /// error in words if its sizes do not fit.
    fn restore(&mut self, snapshot: &Snapshot) -> Result<(), BackendError>;
}

/// Photon tracing alone, for `kousen bench photons` (issue 6): the photon pass without the hash
/// and gather, and the naive scheme that asynchronous path regeneration replaces.
///
/// In the naive scheme (the talk's "one pixel = one photon path") every slot starts a new
/// light path and traces it bounce after bounce to its end in one pass, so a pass lasts as long
/// as its longest path. Each path is exactly one that [`Backend::photon_pass`] would trace: slot
/// `i` in pass `p` traces path number `g = p × slots + i` (wrapping), whose `k`-th segment draws
/// the random numbers `photon_pass` draws for slot `g` in pass `k`, so path `g` is the first path
/// a slot numbered `g` traces from pass 0 under asynchronous regeneration.
pub trait PhotonTracing: Backend {
    /// Closes a pass that ran only [`Backend::photon_pass`] or
    /// [`PhotonTracing::photon_trace_naive`]: the pass's emitted paths are added to the total
    /// and the pass counter advances (the cell size stays: no pixel gathered).
    fn finish_pass(&mut self);
    /// The naive scheme: every slot traces one new light path to its end. Each path counts as
    /// emitted; each slot's segment count and its path's last stored photon are kept (the
    /// photon where `photon_pass` keeps its photon). Slots in flight are left untouched.
    fn photon_trace_naive(&mut self);
    /// Segments (rays traced: bounces and alpha pass-throughs) of each slot's path in the
    /// last [`PhotonTracing::photon_trace_naive`]; waits for the work queued.
    fn read_path_segments(&mut self) -> Result<Vec<u32>, BackendError>;
}
