//! kousen's wgpu backend.
//!
//! - [`GpuContext`]: a headless device opened with the adapter's own limits;
//! - [`limits`] and [`scene_upload::check_scene_fits`]: sizes checked against those limits
//!   before anything is allocated, failing in words;
//! - [`types`]: the `#[repr(C)]` structs the kernels share with Rust (mirrored in WGSL, checked
//!   by `tests/layout.rs`), [`prelude`]: the constants they share, generated from Rust;
//! - [`shader`]: WGSL modules assembled from `shaders/`;
//! - [`scene_upload`]: the packed BVH and materials in storage buffers;
//! - [`textures`]: the scene's textures as one texture array (`render::textures`);
//! - [`traversal`]: closest- and any-hit kernels (stack, TBVH, MTBVH) and benchmark ray
//!   generation, twins of `bvh::traverse` and `bvh::bench_rays`;
//! - [`display`]: the progressive image drawn straight from the SPPM statistics on the device
//!   (a render pass for the viewer) and captured as RGBA8.

pub mod device;
pub mod display;
pub mod kdtree;
pub mod limits;
pub mod prelude;
pub mod random_variants;
pub mod readback;
pub mod scene_upload;
pub mod shader;
pub mod sppm;
pub mod textures;
pub mod traversal;
pub mod types;

pub use device::{GpuContext, instance_descriptor};
pub use limits::check_buffer_fits;
pub use scene_upload::{GpuScene, SceneStorage};
pub use traversal::{RayBatch, TraversalKernels, Variant};

/// What can go wrong opening or using the device. Display is one line.
#[derive(Debug, thiserror::Error)]
pub enum GpuError {
    /// No adapter matched (or wgpu found none at all).
    #[error(
        "no GPU adapter{}; adapters seen: [{seen}] (install a Vulkan driver such as Mesa lavapipe, or check WGPU_BACKEND)",
        filter.as_ref().map(|f| format!(" matching \"{f}\"")).unwrap_or_default()
    )]
    NoAdapter {
        /// The name filter in force, if any.
        filter: Option<String>,
        /// Names of every adapter enumerated, comma-separated.
        seen: String,
    },
    /// The adapter refused to open a device.
    #[error("adapter {adapter} refused a device: {reason}")]
    RequestDevice {
        /// Adapter name.
        adapter: String,
        /// wgpu's reason.
        reason: String,
    },
    /// A buffer is larger than the device allows.
    #[error("buffer {label} needs {size} but the device allows {limit_name} = {limit}")]
    BufferTooLarge {
        /// The buffer's label.
        label: String,
        /// Its size in words, e.g. "300.0 MiB (314572800 bytes)".
        size: String,
        /// Which limit it broke.
        limit_name: &'static str,
        /// The limit in words.
        limit: String,
    },
    /// A render's buffer is larger than the device allows, with what would make it fit.
    #[error("{error} ({remedy})")]
    RenderBufferTooLarge {
        /// The [`GpuError::BufferTooLarge`].
        error: Box<GpuError>,
        /// The setting that sizes the buffer, in words.
        remedy: &'static str,
    },
    /// Scene records stored as texels need more texture rows than the device allows.
    #[error(
        "texture {label} needs {size}: {rows} rows of {row} texels, but the device allows max_texture_dimension_2d = {limit}"
    )]
    TexelsTooLarge {
        /// The texture's label.
        label: String,
        /// Its size in words.
        size: String,
        /// Rows it needs.
        rows: u64,
        /// Texels a row.
        row: u32,
        /// The device's limit on a texture's side.
        limit: u32,
    },
    /// The kernels bind more storage buffers than the device allows per shader stage.
    #[error(
        "the kernels bind {needed} storage buffers per shader stage but the device allows max_storage_buffers_per_shader_stage = {limit}"
    )]
    TooFewStorageBuffers {
        /// What the kernels need.
        needed: u32,
        /// The device's limit.
        limit: u32,
    },
    /// The scene's texture array is larger than the device allows.
    #[error("the scene's textures need {needed} but the device allows {limit_name} = {limit}")]
    TexturesTooLarge {
        /// What the array needs, in words.
        needed: String,
        /// Which limit it broke.
        limit_name: &'static str,
        /// The limit.
        limit: u32,
    },
    /// More rays than a u32 can index.
    #[error("{0} rays in one batch; at most 4294967295")]
    TooManyRays(usize),
    /// The device failed while waiting for or reading back work.
    #[error("GPU device error: {0}")]
    Device(String),
}

impl GpuError {
    /// Whether the work is larger than the device's limits allow (not that the device failed):
    /// the CPU backend may take it instead.
    pub fn is_limit(&self) -> bool {
        matches!(
            self,
            GpuError::BufferTooLarge { .. }
                | GpuError::RenderBufferTooLarge { .. }
                | GpuError::TexelsTooLarge { .. }
                | GpuError::TooFewStorageBuffers { .. }
                | GpuError::TexturesTooLarge { .. }
                | GpuError::TooManyRays(_)
        )
    }
}
