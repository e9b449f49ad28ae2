//! kousen's SPPM integrator (DESIGN.md, "What the system does", step 3): the pass schedule,
//! per-pixel statistics and resolve, driving a [`Backend`]; and what the backends share: the
//! buffers' structs, random streams, light table, hash arithmetic and specular optics.

pub mod backend;
pub mod blend;
pub mod buffers;
pub mod clearcoat;
pub mod coats;
pub mod conductor;
pub mod density;
pub mod dielectric_layer;
pub mod direct;
pub mod dispersion;
pub mod emission;
pub mod framing;
pub mod guides;
pub mod half_storage;
pub mod hash;
pub mod image;
pub mod integrator;
pub mod iridescence;
pub mod kdtree;
pub mod lens;
pub mod light_sampling;
pub mod medium;
pub mod microfacet;
pub mod nesting;
pub mod normal_map;
pub mod optics;
pub mod packing;
pub mod plastic;
pub mod radius_histogram;
pub mod random;
pub mod resampling;
pub mod resolve;
pub mod rng;
pub mod sampling;
pub mod scattering;
pub mod settings;
pub mod shadow_terminator;
pub mod sheen;
pub mod sky_map;
pub mod textures;
pub mod tonemap;
pub mod volume_boundary;

pub use backend::{Backend, BackendError, PhotonTracing, Setup, Snapshot, Statistics};
pub use density::Density;
pub use image::Image;
pub use integrator::{
    Checkpoint, Intermediate, Progress, RenderError, Rendered, RunHooks, SaveAt, Sppm,
};
pub use settings::{Budget, Settings};
