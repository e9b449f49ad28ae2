//! kousen's wgpu backend.
//!
//! So far: a headless [`GpuContext`] opened with the adapter's own limits, buffer-size checks
//! against those limits ([`limits`]), and the WGSL twins of `bvh`'s GPU structs
//! (`shaders/shared/bvh_types.wgsl`, kept in sync by `tests/layout.rs`). Next (issue 3): the
//! shader assembler, uploads of a `bvh::PackedBvh`, and the kernels with their CPU twins.

pub mod device;
pub mod limits;

pub use device::GpuContext;
pub use limits::check_buffer_fits;

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
}
