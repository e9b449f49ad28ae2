//! `kousen render --checkpoint FILE` / `--resume FILE`: a stopped render on disk.
//!
//! Layout: the magic `KOUSENCP`, a little-endian u32 format version, a little-endian u32
//! length and that many bytes of JSON ([`Header`]: what was rendered and how, and how many
//! words each part holds), then the backend's state ([`render::Snapshot`]) as little-endian
//! u32 words, part after part. The JSON lets a resume say in words which setting differs; the
//! fingerprint catches a changed scene or camera.

use std::path::Path;

use anyhow::{Context, bail};
use serde::{Deserialize, Serialize};

use render::{Checkpoint, Settings, Snapshot};

const MAGIC: &[u8; 8] = b"KOUSENCP";
/// 2: pixel statistics hold caustic and indirect sets (session 11). 3: a photon slot's state
/// word keeps the wavelength its path keeps (`render::medium::pack_slot_state`, session 29).
/// 4: pixel statistics hold a third set, the volume photons' (`render::scattering`, session
/// 39). 5: a photon slot carries its path's walk, hero and densities (session 40). 6: the
/// counters hold the volume photons' own grid, and volume visible points their depths below
/// their medium's surfaces (`render::hash`, `render::volume_boundary`, session 41).
const FORMAT: u32 = 6;

/// The settings a continued render must share with the stopped one, each with the option
/// that sets it (for messages).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Recorded {
    pub backend: String,
    pub width: u32,
    pub height: u32,
    pub photons: u32,
    pub alpha: f32,
    pub eye_every: u32,
    pub hash_ratio: f32,
    pub density: String,
    pub precision: String,
    pub direct_light: String,
    pub indirect_alpha: f32,
    pub max_depth: u32,
    pub seed: u32,
    pub initial_radius: Option<f32>,
    /// Absent from checkpoints made before `--caustic-radius` existed: they used 1.
    #[serde(default = "same_radius")]
    pub caustic_radius_share: f32,
}

fn same_radius() -> f32 {
    1.0
}

impl Recorded {
    pub fn new(backend: &str, settings: &Settings) -> Recorded {
        Recorded {
            backend: backend.to_owned(),
            width: settings.width,
            height: settings.height,
            photons: settings.photons,
            alpha: settings.alpha,
            eye_every: settings.eye_every,
            hash_ratio: settings.hash_ratio,
            density: settings.density.name().to_owned(),
            precision: settings.precision.name().to_owned(),
            direct_light: settings.direct.name().to_owned(),
            indirect_alpha: settings.indirect_alpha,
            max_depth: settings.max_depth,
            seed: settings.seed,
            initial_radius: settings.initial_radius,
            caustic_radius_share: settings.caustic_radius_share,
        }
    }

    /// (option, value) pairs, compared in this order.
    fn options(&self) -> [(&'static str, String); 14] {
        [
            ("--backend", self.backend.clone()),
            ("--width", self.width.to_string()),
            ("--height", self.height.to_string()),
            ("--photons", self.photons.to_string()),
            ("--alpha", self.alpha.to_string()),
            ("--indirect-alpha", self.indirect_alpha.to_string()),
            ("--eye-every", self.eye_every.to_string()),
            ("--hash-ratio", self.hash_ratio.to_string()),
            ("--density", self.density.clone()),
            ("--precision", self.precision.clone()),
            ("--direct-light", self.direct_light.clone()),
            ("--max-depth", self.max_depth.to_string()),
            ("--seed", self.seed.to_string()),
            ("--caustic-radius", self.caustic_radius_share.to_string()),
        ]
    }
}

/// The JSON after the magic.
#[derive(Debug, Serialize, Deserialize)]
pub struct Header {
    /// The scene file, as given (for messages only).
    pub scene: String,
    /// FNV-1a of the packed triangles and the camera: a changed scene or view is refused.
    pub fingerprint: String,
    pub settings: Recorded,
    pub adapter: String,
    pub passes: u32,
    pub eye_passes: u32,
    /// Seconds rendered so far, over every run that led here.
    pub seconds: f64,
    /// Words of each part of the state, in [`Snapshot::parts`] order.
    pub words: [usize; 4],
}

/// A checkpoint as read from disk.
pub struct Loaded {
    pub header: Header,
    pub checkpoint: Checkpoint,
}

/// 64-bit FNV-1a of the scene's packed triangles, the camera's description and the scene's
/// punctual lights and sky (only when it has any, so that checkpoints of scenes without them,
/// made before such lights were read, stay valid).
pub fn fingerprint(bvh: &bvh::PackedBvh, camera: &scene::Camera, lights: &scene::Lights) -> String {
    let mut hash: u64 = 0xcbf2_9ce4_8422_2325;
    let bytes: &[u8] = bytemuck::cast_slice(&bvh.triangles);
    let (punctual, sky) = (&lights.punctual, &lights.sky);
    let lights = if punctual.is_empty() && sky.is_none() {
        String::new()
    } else {
        format!("{punctual:?}{sky:?}")
    };
    let described = format!("{camera:?}") + &lights;
    for &byte in bytes.iter().chain(described.as_bytes()) {
        hash = (hash ^ u64::from(byte)).wrapping_mul(0x0000_0100_0000_01b3);
    }
    format!("{hash:016x}")
}

/// Writes `checkpoint` with `header` (its pass counts and sizes filled in here) to `path`,
/// whole or not at all.
pub fn write(path: &Path, mut header: Header, checkpoint: &Checkpoint) -> anyhow::Result<()> {
    header.passes = checkpoint.passes;
    header.eye_passes = checkpoint.eye_passes;
    header.words = checkpoint.state.parts().map(|(_, words)| words.len());
    let json = serde_json::to_vec(&header)?;
    let total: usize = header.words.iter().sum();
    let mut bytes = Vec::with_capacity(16 + json.len() + 4 * total);
    bytes.extend_from_slice(MAGIC);
    bytes.extend_from_slice(&FORMAT.to_le_bytes());
    bytes.extend_from_slice(&(json.len() as u32).to_le_bytes());
    bytes.extend_from_slice(&json);
    for (_, words) in checkpoint.state.parts() {
        bytes.extend(words.iter().flat_map(|w| w.to_le_bytes()));
    }
    crate::output_file::write_atomically(path, &bytes)
}

/// Reads a checkpoint, checking its form (not yet whether it fits a render: [`check_fits`]).
pub fn read(path: &Path) -> anyhow::Result<Loaded> {
    let bytes = std::fs::read(path).with_context(|| format!("cannot read {}", path.display()))?;
    let name = path.display();
    if bytes.len() < 16 || &bytes[..8] != MAGIC {
        bail!("{name} is not a kousen checkpoint");
    }
    let word = |at: usize| u32::from_le_bytes(bytes[at..at + 4].try_into().expect("4 bytes"));
    let format = word(8);
    if format != FORMAT {
        bail!("{name} is a checkpoint of format {format}; this kousen reads format {FORMAT}");
    }
    let json_end = 16usize.saturating_add(word(12) as usize);
    let json = bytes
        .get(16..json_end)
        .with_context(|| format!("{name} is truncated"))?;
    let header: Header =
        serde_json::from_slice(json).with_context(|| format!("{name} has a damaged header"))?;
    let total = header
        .words
        .iter()
        .try_fold(0usize, |sum, &w| sum.checked_add(w));
    if total.and_then(|t| t.checked_mul(4)) != Some(bytes.len() - json_end) {
        bail!("{name} is truncated or damaged: its header promises other sizes than it holds");
    }
    let mut words = bytes[json_end..]
        .chunks_exact(4)
        .map(|c| u32::from_le_bytes(c.try_into().expect("4 bytes")));
    let mut part = |n: usize| words.by_ref().take(n).collect::<Vec<u32>>();
    let state = Snapshot {
        counters: part(header.words[0]),
        slots: part(header.words[1]),
        visible_points: part(header.words[2]),
        pixels: part(header.words[3]),
    };
    let checkpoint = Checkpoint {
        passes: header.passes,
        eye_passes: header.eye_passes,
        state,
    };
    Ok(Loaded { header, checkpoint })
}

/// An error naming the first option in which the render differs from the checkpoint's, or
/// saying that the scene or view does.
pub fn check_fits(
    path: &Path,
    loaded: &Header,
    settings: &Recorded,
    fingerprint: &str,
) -> anyhow::Result<()> {
    let name = path.display();
    for ((option, then), (_, now)) in loaded
        .settings
        .options()
        .into_iter()
        .zip(settings.options())
    {
        if then != now {
            bail!(
                "{name} was rendered with {option} {then}, this render has {now}: resume with the options of the render it continues"
            );
        }
    }
    if loaded.fingerprint != fingerprint {
        bail!(
            "{name} was rendered from another scene or camera than this one ({}): resume with the scene and view of the render it continues",
            loaded.scene
        );
    }
    let radius = |r: Option<f32>| r.map_or_else(|| "the scene's".to_owned(), |r| r.to_string());
    if loaded.settings.initial_radius != settings.initial_radius {
        bail!(
            "{name} was rendered with an initial radius of {}, this render's is {} (from --radius): resume with the options of the render it continues",
            radius(loaded.settings.initial_radius),
            radius(settings.initial_radius)
        );
    }
    Ok(())
}
