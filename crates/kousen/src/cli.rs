//! The command line (DESIGN.md "Command line": a contract scripts depend on).

use std::path::PathBuf;

use clap::{Args, Parser, Subcommand};

#[derive(Parser)]
#[command(
    name = "kousen",
    version,
    about = "Stochastic progressive photon mapping on the GPU"
)]
pub struct Cli {
    /// More log output (-v info, -vv debug); RUST_LOG overrides.
    #[arg(short, long, global = true, action = clap::ArgAction::Count)]
    pub verbose: u8,
    #[command(subcommand)]
    pub command: Command,
}

#[derive(Subcommand)]
pub enum Command {
    /// Render a scene to an image (.exr or .pfm linear, .png tonemapped).
    Render(RenderArgs),
    /// Triangles, materials, lights, BVH statistics and memory of a scene.
    Info(InfoArgs),
    /// An interactive window showing the GPU renderer's image as it converges.
    ///
    /// Mouse: left drag orbits, middle or shift + left drag pans, the wheel zooms, right drag
    /// looks around; W A S D move, Q E down and up. Keys: Space pause, R restart, S save
    /// (EXR and PNG), F1 hide the overlay, 1-4 show or hide the direct, indirect, caustic
    /// and volume parts of the radiance, 0 show all. Drop a scene (.gltf, .glb, .obj, .xml,
    /// .pbrt) or a sky map (.hdr, .exr, .pfm, .png) on the window to open it.
    #[command(verbatim_doc_comment)]
    View(ViewArgs),
    /// Measure speed, variants side by side in one run.
    Bench(BenchArgs),
    /// Compare an image with a reference: relMSE, RMSE and mean ratio
    ///
    /// Prints one "name value" line per figure. With A the image, B the reference, and means
    /// over every pixel and channel:
    ///   rel_mse    = mean((A - B)^2 / (B^2 + 0.01))
    ///   rmse       = sqrt(mean((A - B)^2))
    ///   mean_ratio = mean(A) / mean(B); also per channel: mean_ratio_r, _g, _b
    #[command(verbatim_doc_comment)]
    Diff(DiffArgs),
}

#[derive(Args)]
pub struct DiffArgs {
    /// The image measured (A): .exr, .pfm or .png (decoded from sRGB to linear).
    pub image: PathBuf,
    /// The reference (B), the same size.
    pub reference: PathBuf,
    /// Also write the figures as JSON (a contract for scripts).
    #[arg(long, value_name = "FILE")]
    pub json: Option<PathBuf>,
    /// Compare only this rectangle of both images: left column, top row, width, height in
    /// pixels (e.g. a caustic).
    #[arg(long, value_name = "X,Y,W,H", value_parser = parse_window)]
    pub window: Option<[u32; 4]>,
}

/// `--light-candidates`: `auto` or a count (checked against its range with the other
/// settings, `render::Settings::validate`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct LightCandidates(pub Option<u32>);

fn parse_light_candidates(text: &str) -> Result<LightCandidates, String> {
    match text.trim() {
        "auto" => Ok(LightCandidates(None)),
        count => count
            .parse::<u32>()
            .map(|n| LightCandidates(Some(n)))
            .map_err(|_| format!("expected auto or a whole number, got {text:?}")),
    }
}

fn parse_window(text: &str) -> Result<[u32; 4], String> {
    let values: Result<Vec<u32>, _> = text.split(',').map(|p| p.trim().parse::<u32>()).collect();
    match values {
        Ok(v) if v.len() == 4 && v[2] > 0 && v[3] > 0 => Ok([v[0], v[1], v[2], v[3]]),
        _ => Err(format!(
            "expected four whole numbers \"x,y,width,height\" with width and height above 0, got {text:?}"
        )),
    }
}

#[derive(Args)]
pub struct BenchArgs {
    #[command(subcommand)]
    pub command: BenchCommand,
}

#[derive(Subcommand)]
pub enum BenchCommand {
    /// Mrays/s of the stack, TBVH, MTBVH, compact MTBVH (mtbvh16) and four-wide MTBVH (mtbvh4)
    /// traversals on the GPU and the CPU twins.
    Traversal(TraversalArgs),
    /// Photon paths per second: one bounce per pass with asynchronous path regeneration against
    /// the naive scheme (every path traced to its end in one pass), with lane occupancy.
    Photons(PhotonsArgs),
    /// Random generators (PCG, the talk's float-only one, TEA, fract(sin)): photon paths per
    /// second with each, a statistical battery, and renders showing their artifacts.
    Rng(RngArgs),
    /// Density estimation: hash build and gather times per pass, and image error at equal
    /// passes and equal time, for the stochastic hash at table ratios 1:64, 1:8 and 1:1, a
    /// full spatial hash (counting sort) and a kd-tree built on the CPU.
    Density(DensityArgs),
}

/// `--tonemap`: how PNG output and the window map exposed radiance to [0, 1].
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, clap::ValueEnum)]
pub enum ToneMapChoice {
    /// Each channel clamped: exact below white, anything brighter white.
    #[default]
    Clamp,
    /// Khronos PBR Neutral: colours below white kept, highlights compressed smoothly to white.
    Neutral,
}

impl ToneMapChoice {
    pub fn tone_map(self) -> render::tonemap::ToneMap {
        match self {
            ToneMapChoice::Clamp => render::tonemap::ToneMap::Clamp,
            ToneMapChoice::Neutral => render::tonemap::ToneMap::Neutral,
        }
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum StoragePrecision {
    F32,
    F16,
}

impl StoragePrecision {
    pub fn precision(self) -> render::half_storage::Precision {
        match self {
            StoragePrecision::F32 => render::half_storage::Precision::F32,
            StoragePrecision::F16 => render::half_storage::Precision::F16,
        }
    }
}

/// How `kousen render` and `kousen view` find the photons around each visible point.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum DensityChoice {
    /// Render: full lists where the render runs on CPU cores (the CPU backend, or a CPU-type
    /// adapter such as lavapipe), the stochastic hash on a GPU: on CPU cores the lists reach a
    /// given error sooner (docs/BENCHMARKS.md §3 and §7); on GPUs the talk's hash is the
    /// design. View: the stochastic hash, whose cheaper passes show the picture sooner after
    /// each camera move.
    Auto,
    /// The stochastic spatial hash: one photon kept per table entry, weighted by the entry's
    /// count (the talk's; cheapest per pass).
    Stochastic,
    /// Every photon, in per-entry lists sorted each pass (less noise per pass).
    Full,
    /// A kd-tree over each pass's photons, built on the CPU.
    Kdtree,
}

impl DensityChoice {
    /// The estimator for a render on CPU cores (`on_cpu_cores`: the CPU backend or a CPU-type
    /// adapter) or on a GPU.
    pub fn density(self, on_cpu_cores: bool) -> render::Density {
        match self {
            DensityChoice::Auto if on_cpu_cores => render::Density::FullHash,
            DensityChoice::Auto | DensityChoice::Stochastic => render::Density::StochasticHash,
            DensityChoice::Full => render::Density::FullHash,
            DensityChoice::Kdtree => render::Density::KdTree,
        }
    }

    /// The estimator for `kousen view`, which restarts at every camera move: `auto` takes the
    /// stochastic hash, the cheapest pass, so a new view shows sooner.
    pub fn for_view(self) -> render::Density {
        match self {
            DensityChoice::Auto => render::Density::StochasticHash,
            other => other.density(false),
        }
    }
}

/// Where direct light comes from (`--direct-light`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum DirectChoice {
    /// Photons landing straight from the lights, as the talk's renderer does.
    Photons,
    /// One light sample and shadow ray per visible point and eye pass (next-event estimation);
    /// photons then carry only light that has bounced. Less noise and sharp shadows.
    Sampled,
}

impl DirectChoice {
    pub fn direct(self) -> render::direct::DirectLight {
        match self {
            DirectChoice::Photons => render::direct::DirectLight::Photons,
            DirectChoice::Sampled => render::direct::DirectLight::Sampled,
        }
    }
}

/// What lights an eye path where it meets a glossy reflection (`--glossy-light`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum GlossyLightChoice {
    /// A light sample at each rough metal or rough plastic coat reflection, weighed against
    /// the lobe's own sampling (multiple importance sampling).
    Sampled,
    /// Only what the lobe's own sampling meets (one ray along the drawn reflection).
    Lobe,
}

/// Density estimation and storage, shared by `kousen render` and `kousen view`.
#[derive(Args, Clone, Copy)]
pub struct EstimatorArgs {
    /// How photons are found around each visible point.
    #[arg(long, value_enum, default_value_t = DensityChoice::Auto)]
    pub density: DensityChoice,
    /// How photons and visible points are stored on the device (f16: half the memory).
    #[arg(long, value_enum, default_value_t = StoragePrecision::F32)]
    pub precision: StoragePrecision,
    /// Where direct light comes from (sampled: on the CPU backend it reaches Mitsuba's error
    /// over the whole Cornell-caustics image in half the time, docs/BENCHMARKS.md §3).
    #[arg(long, value_enum, default_value_t = DirectChoice::Sampled)]
    pub direct_light: DirectChoice,
    /// What lights glossy reflections that eye paths meet (sampled: far less noise on rough
    /// metal and rough plastic under small lights, docs/BENCHMARKS.md §3).
    #[arg(long, value_enum, default_value_t = GlossyLightChoice::Sampled)]
    pub glossy_light: GlossyLightChoice,
    /// Lights drawn by power for each light sample at a Lambertian-only point, one kept by
    /// what it would bring (1–64; 1: the power pick alone; more: far less noise where lights
    /// face away or hide behind the surface, docs/BENCHMARKS.md §3; auto: 8, or 1 where the
    /// only light is one flat emitter).
    #[arg(long, value_name = "auto|N", default_value = "auto", value_parser = parse_light_candidates)]
    pub light_candidates: LightCandidates,
}

/// A density-estimation method as `kousen bench density` names it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum DensityMethod {
    /// The stochastic hash with 1 table entry per 64 photon slots.
    #[value(name = "stochastic-64")]
    Stochastic64,
    /// The stochastic hash with 1 table entry per 8 photon slots.
    #[value(name = "stochastic-8")]
    Stochastic8,
    /// The stochastic hash with 1 table entry per photon slot (kousen's default).
    #[value(name = "stochastic-1")]
    Stochastic1,
    /// Every photon in per-entry lists (1 entry per slot), built by a counting sort.
    Full,
    /// A kd-tree over the pass's photons, built on the CPU.
    Kdtree,
}

impl DensityMethod {
    /// The method and its table entries per photon slot.
    pub fn density(self) -> (render::Density, f32) {
        use render::Density::*;
        match self {
            DensityMethod::Stochastic64 => (StochasticHash, 1.0 / 64.0),
            DensityMethod::Stochastic8 => (StochasticHash, 1.0 / 8.0),
            DensityMethod::Stochastic1 => (StochasticHash, 1.0),
            DensityMethod::Full => (FullHash, 1.0),
            DensityMethod::Kdtree => (KdTree, 1.0),
        }
    }

    /// The name on the command line and in reports.
    pub fn name(self) -> &'static str {
        match self {
            DensityMethod::Stochastic64 => "stochastic-64",
            DensityMethod::Stochastic8 => "stochastic-8",
            DensityMethod::Stochastic1 => "stochastic-1",
            DensityMethod::Full => "full",
            DensityMethod::Kdtree => "kdtree",
        }
    }
}

#[derive(Args)]
pub struct DensityArgs {
    /// Scene files (.gltf, .glb, .obj, Mitsuba .xml, .pbrt), each with at least one light
    /// (an emissive surface or a glTF punctual light) and a camera.
    #[arg(required = true)]
    pub scenes: Vec<PathBuf>,
    /// Also write the results as JSON (a contract for scripts).
    #[arg(long, value_name = "FILE")]
    pub json: Option<PathBuf>,
    /// Methods, comma-separated.
    #[arg(
        long,
        value_enum,
        value_delimiter = ',',
        default_value = "stochastic-64,stochastic-8,stochastic-1,full,kdtree"
    )]
    pub methods: Vec<DensityMethod>,
    /// How photons and visible points are stored, comma-separated: each method runs with each
    /// (f16: 16-byte packed structs instead of 32-byte f32 ones).
    #[arg(long, value_enum, value_delimiter = ',', default_value = "f32")]
    pub precision: Vec<StoragePrecision>,
    #[arg(long, default_value_t = 256, value_parser = clap::value_parser!(u32).range(1..=8192))]
    pub width: u32,
    #[arg(long, default_value_t = 256, value_parser = clap::value_parser!(u32).range(1..=8192))]
    pub height: u32,
    /// Photon path slots per pass.
    #[arg(long, value_name = "N", default_value_t = 1 << 16, value_parser = clap::value_parser!(u32).range(1..=1 << 24))]
    pub photons: u32,
    /// SPPM passes per method (timed, and the "equal passes" of the error).
    #[arg(long, value_name = "N", default_value_t = 32, value_parser = clap::value_parser!(u32).range(1..=100_000))]
    pub passes: u32,
    #[arg(long, default_value_t = 1)]
    pub seed: u32,
    /// A converged image of the same scene, size and camera to measure error against (EXR or
    /// PFM). Default: one rendered first with the full hash, --reference-passes passes, another
    /// seed.
    #[arg(long, value_name = "FILE")]
    pub reference: Option<PathBuf>,
    /// Passes of the reference rendered when no --reference is given.
    #[arg(long, value_name = "N", default_value_t = 256, value_parser = clap::value_parser!(u32).range(1..=1_000_000))]
    pub reference_passes: u32,
    /// Also write each method's image at equal passes (first device) as DIR/density-<scene>-<method>.png.
    #[arg(long, value_name = "DIR")]
    pub images: Option<PathBuf>,
    /// Exposure in stops of the PNG images.
    #[arg(long, default_value_t = 0.0, allow_negative_numbers = true)]
    pub exposure: f32,
    /// Where to run, comma-separated.
    #[arg(long, value_enum, value_delimiter = ',', default_value = "gpu,cpu")]
    pub devices: Vec<BenchDevice>,
    /// Use the GPU adapter whose name contains this (case-insensitive; default: the best).
    #[arg(long, value_name = "SUBSTRING")]
    pub adapter: Option<String>,
    #[command(flatten)]
    pub bvh: BvhArgs,
}

/// The benchmark camera of ANCHORS.md.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum BenchView {
    /// Outside the bounding box, looking at its centre (bunny, Cornell box).
    Outside,
    /// Inside, looking along the long axis (the Sponzas).
    Inside,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum BenchRays {
    /// One per pixel from the camera.
    Primary,
    /// One cosine-distributed bounce from each primary hit.
    Diffuse,
}

impl BenchRays {
    pub fn kind(self) -> gpu::traversal::RayKind {
        match self {
            BenchRays::Primary => gpu::traversal::RayKind::Primary,
            BenchRays::Diffuse => gpu::traversal::RayKind::Diffuse,
        }
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum BenchDevice {
    Gpu,
    Cpu,
}

#[derive(Args)]
pub struct TraversalArgs {
    /// Scene files (.gltf, .glb, .obj, Mitsuba .xml, .pbrt).
    #[arg(required = true)]
    pub scenes: Vec<PathBuf>,
    /// Camera placement (the same for every scene given).
    #[arg(long, value_enum, default_value_t = BenchView::Outside)]
    pub view: BenchView,
    /// Also write the results as JSON (a contract for scripts).
    #[arg(long, value_name = "FILE")]
    pub json: Option<PathBuf>,
    /// Ray kinds, comma-separated.
    #[arg(
        long,
        value_enum,
        value_delimiter = ',',
        default_value = "primary,diffuse"
    )]
    pub rays: Vec<BenchRays>,
    /// Image side: SIZE² primary rays.
    #[arg(long, value_name = "N", default_value_t = bvh::bench_rays::DEFAULT_SIDE, value_parser = clap::value_parser!(u32).range(1..=8192))]
    pub size: u32,
    /// Timed runs per measurement (after a warm-up); the median is reported.
    #[arg(long, value_name = "N", default_value_t = 5, value_parser = clap::value_parser!(u32).range(5..=1000))]
    pub runs: u32,
    /// Where to run, comma-separated.
    #[arg(long, value_enum, value_delimiter = ',', default_value = "gpu,cpu")]
    pub devices: Vec<BenchDevice>,
    /// Use the GPU adapter whose name contains this (case-insensitive; default: the best).
    #[arg(long, value_name = "SUBSTRING")]
    pub adapter: Option<String>,
    /// Where the GPU kernels read nodes, triangles and threaded records from (default: texels on a
    /// CPU-type adapter such as lavapipe, where they were measured faster; buffers on a GPU).
    #[arg(long, value_enum)]
    pub scene_storage: Option<SceneStorageChoice>,
    #[command(flatten)]
    pub bvh: BvhArgs,
}

/// `--scene-storage`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum SceneStorageChoice {
    /// Storage buffers.
    Buffers,
    /// Integer textures (rgba32uint), 16 bytes a texel.
    Texels,
}

impl SceneStorageChoice {
    pub fn storage(self) -> gpu::SceneStorage {
        match self {
            SceneStorageChoice::Buffers => gpu::SceneStorage::Buffers,
            SceneStorageChoice::Texels => gpu::SceneStorage::Texels,
        }
    }
}

#[derive(Args)]
pub struct PhotonsArgs {
    /// Scene files (.gltf, .glb, .obj, Mitsuba .xml, .pbrt), each with at least one light
    /// (an emissive surface or a glTF punctual light).
    #[arg(required = true)]
    pub scenes: Vec<PathBuf>,
    /// Also write the results as JSON (a contract for scripts).
    #[arg(long, value_name = "FILE")]
    pub json: Option<PathBuf>,
    /// Photon path slots: invocations per pass in both schemes.
    #[arg(long, value_name = "N", default_value_t = 1 << 16, value_parser = clap::value_parser!(u32).range(1..=1 << 24))]
    pub photons: u32,
    /// Photon passes per timed run of the asynchronous scheme; the naive scheme's run traces as
    /// many paths (to within half a pass of slots).
    #[arg(long, value_name = "N", default_value_t = 16, value_parser = clap::value_parser!(u32).range(1..=100_000))]
    pub passes: u32,
    /// Timed runs per scheme (after a warm-up, the schemes alternating); the median is reported.
    #[arg(long, value_name = "N", default_value_t = 5, value_parser = clap::value_parser!(u32).range(1..=1000))]
    pub runs: u32,
    /// Bounces before a photon path is cut off (default glslppm's, as the talk's figures).
    #[arg(long, value_name = "N", default_value_t = render::settings::GLSLPPM_MAX_DEPTH, value_parser = clap::value_parser!(u32).range(1..=1000))]
    pub max_depth: u32,
    /// Where to run, comma-separated.
    #[arg(long, value_enum, value_delimiter = ',', default_value = "gpu,cpu")]
    pub devices: Vec<BenchDevice>,
    /// Use the GPU adapter whose name contains this (case-insensitive; default: the best).
    #[arg(long, value_name = "SUBSTRING")]
    pub adapter: Option<String>,
    #[command(flatten)]
    pub bvh: BvhArgs,
}

#[derive(Args)]
pub struct RngArgs {
    /// Scene files (.gltf, .glb, .obj, Mitsuba .xml, .pbrt), each with at least one light
    /// (an emissive surface or a glTF punctual light).
    #[arg(required = true)]
    pub scenes: Vec<PathBuf>,
    /// Also write the results as JSON (a contract for scripts).
    #[arg(long, value_name = "FILE")]
    pub json: Option<PathBuf>,
    /// Photon path slots per pass.
    #[arg(long, value_name = "N", default_value_t = 1 << 16, value_parser = clap::value_parser!(u32).range(1..=1 << 24))]
    pub photons: u32,
    /// Photon passes per timed run.
    #[arg(long, value_name = "N", default_value_t = 16, value_parser = clap::value_parser!(u32).range(1..=100_000))]
    pub passes: u32,
    /// Timed runs per generator (after a warm-up, the generators alternating); the median is
    /// reported.
    #[arg(long, value_name = "N", default_value_t = 5, value_parser = clap::value_parser!(u32).range(1..=1000))]
    pub runs: u32,
    /// Draws per test of the statistical battery.
    #[arg(long, value_name = "N", default_value_t = 1 << 20, value_parser = clap::value_parser!(u32).range(1 << 16..=1 << 28))]
    pub battery_draws: u32,
    /// Also render the first scene on the GPU with each generator into DIR/rng-<name>.png.
    #[arg(long, value_name = "DIR")]
    pub image: Option<PathBuf>,
    /// Side of the rendered images, in pixels.
    #[arg(long, value_name = "N", default_value_t = 256, value_parser = clap::value_parser!(u32).range(8..=4096))]
    pub image_size: u32,
    /// SPPM passes per rendered image.
    #[arg(long, value_name = "N", default_value_t = 64, value_parser = clap::value_parser!(u32).range(1..=100_000))]
    pub image_passes: u32,
    /// Where to run, comma-separated.
    #[arg(long, value_enum, value_delimiter = ',', default_value = "gpu,cpu")]
    pub devices: Vec<BenchDevice>,
    /// Use the GPU adapter whose name contains this (case-insensitive; default: the best).
    #[arg(long, value_name = "SUBSTRING")]
    pub adapter: Option<String>,
    #[command(flatten)]
    pub bvh: BvhArgs,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum Backend {
    /// The GPU when an adapter exists, else the CPU.
    Auto,
    Gpu,
    Cpu,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum Integrator {
    /// Stochastic progressive photon mapping (GPU or CPU backend).
    Sppm,
    /// Unidirectional path tracing with next-event estimation (CPU only; one sample per pixel
    /// per pass).
    Path,
}

#[derive(Args, Clone)]
pub struct RenderArgs {
    /// A scene file: .gltf, .glb, .obj, Mitsuba .xml or .pbrt.
    pub scene: PathBuf,
    /// Output image: .exr or .pfm (linear radiance), .png (exposure + sRGB tonemap).
    #[arg(short, long, value_name = "OUT")]
    pub output: PathBuf,
    #[arg(long, default_value_t = 512, value_parser = clap::value_parser!(u32).range(1..=16384))]
    pub width: u32,
    /// Default: from the camera's aspect ratio, else square.
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=16384))]
    pub height: Option<u32>,
    /// Photon passes to render (default 256).
    #[arg(long, conflicts_with = "time", value_parser = clap::value_parser!(u32).range(1..))]
    pub passes: Option<u32>,
    /// Render for this many seconds instead of a number of passes.
    #[arg(long, value_name = "SECONDS", allow_negative_numbers = true)]
    pub time: Option<f64>,
    #[arg(long, default_value_t = 0)]
    pub seed: u64,
    /// Bits per channel of an .exr output.
    #[arg(long, value_enum, default_value_t = crate::image_io::ExrPrecision::Float)]
    pub exr_precision: crate::image_io::ExrPrecision,
    /// Exposure in stops applied before the PNG tonemap.
    #[arg(long, default_value_t = 0.0, allow_negative_numbers = true)]
    pub exposure: f32,
    /// How a PNG output maps exposed radiance to [0, 1] (EXR and PFM stay linear).
    #[arg(long, value_enum, default_value_t = ToneMapChoice::Clamp)]
    pub tonemap: ToneMapChoice,
    #[arg(long, value_enum, default_value_t = Backend::Auto)]
    pub backend: Backend,
    /// Use the GPU adapter whose name contains this (case-insensitive; default: the best).
    #[arg(long, value_name = "SUBSTRING")]
    pub adapter: Option<String>,
    /// Write statistics as JSON.
    #[arg(long, value_name = "FILE.json")]
    pub stats: Option<PathBuf>,
    /// Also write the image's parts beside OUT, each named before its extension
    /// (out.direct.exr, out.indirect.exr, out.caustic.exr, out.volume.exr): what the eye
    /// paths saw directly (emission, light samples), the indirect and caustic photons on
    /// surfaces, the volume photons in murky glass. They sum to the image.
    #[arg(long)]
    pub components: bool,
    /// Also write the denoising guides beside OUT (out.albedo.exr, out.normal.exr): each
    /// pixel's albedo and world-space shading normal at the surface it shows, seen through
    /// mirrors and glass with their tint, averaged over the first 64 eye passes; zero where
    /// it shows no surface (a lamp, the sky). Denoisers such as Intel Open Image Denoise take
    /// them beside the image: `oidnDenoise --hdr out.pfm --alb out.albedo.pfm --nrm
    /// out.normal.pfm -o clean.pfm`. Float images: OUT must be .exr or .pfm.
    #[arg(long)]
    pub denoise_guides: bool,
    /// Also save the image so far at these moments, each a pass count (64: once 64 passes
    /// are done) or seconds of rendering (30s), beside OUT and named by it (out-64.exr,
    /// out-30s.exr): one render's convergence. --stats lists how far it had come at each;
    /// their writing is left out of the render's time.
    #[arg(long, value_name = "LIST", value_delimiter = ',', value_parser = crate::cmd::intermediates::parse_save_at)]
    pub save_at: Vec<render::SaveAt>,
    /// Save the render's state to FILE every minute and at the end, to continue it later
    /// with --resume (may be the same file).
    #[arg(long, value_name = "FILE")]
    pub checkpoint: Option<PathBuf>,
    /// Continue the render saved in FILE (by --checkpoint), given the same scene, view and
    /// options; --passes then counts the passes already done, --time only this run's.
    #[arg(long, value_name = "FILE")]
    pub resume: Option<PathBuf>,
    /// Photon path slots per pass (default: one per pixel with the stochastic hash, four with
    /// full lists or the kd-tree; at most 2²⁰).
    #[arg(long, value_name = "N")]
    pub photons: Option<u32>,
    /// An eye pass (new visible points, and a light sample for each) every this many photon
    /// passes (default on CPU cores, the CPU backend or a CPU-type adapter such as lavapipe:
    /// 4 × pixels per photon slot, to a power of two from 1 to 8; on a GPU every 8th;
    /// measured, docs/BENCHMARKS.md §3).
    #[arg(long, value_name = "K")]
    pub eye_every: Option<u32>,
    /// Hash table entries per photon slot (1 = 1:1, 0.125 = 1:8).
    #[arg(long, value_name = "RATIO", default_value_t = 1.0)]
    pub hash_ratio: f32,
    #[command(flatten)]
    pub gather: GatherArgs,
    /// Bounces before a photon or eye path is cut off.
    #[arg(long, value_name = "N", default_value_t = render::settings::DEFAULT_MAX_DEPTH)]
    pub max_depth: u32,
    /// The integrator: SPPM, or the CPU path tracer kept as an independent reference.
    #[arg(long, value_enum, default_value_t = Integrator::Sppm)]
    pub integrator: Integrator,
    #[command(flatten)]
    pub estimator: EstimatorArgs,
    #[command(flatten)]
    pub camera: CameraArgs,
    #[command(flatten)]
    pub load: LoadArgs,
    /// Render a glTF animation frame by frame: frames FIRST-LAST (or one frame N), frame n
    /// posed n / --fps seconds into the animation (--animation chooses which), each a whole
    /// render (--passes or --time each) written beside OUT with its number: out-0001.png.
    #[arg(long, value_name = "FIRST-LAST", value_parser = crate::cmd::frames::parse_frames, group = "moment")]
    pub frames: Option<crate::cmd::frames::FrameRange>,
    /// Frames per second of --frames.
    #[arg(long, value_name = "N", default_value_t = 24.0, requires = "frames")]
    pub fps: f32,
    /// With --frames: leave out the frames whose image is already there (a sequence stopped
    /// part way goes on where it stopped).
    #[arg(long, requires = "frames")]
    pub skip_existing: bool,
    #[command(flatten)]
    pub added_lights: AddedLightArgs,
    #[command(flatten)]
    pub bvh: BvhArgs,
}

/// What of a glTF file to load beyond its default: a moment of its animation to pose the scene
/// by (a character mid-stride, a door half open, a shape key half way; without it, the scene
/// as its nodes place things), a material variant to dress it in.
#[derive(Args, Clone, Default)]
pub struct LoadArgs {
    /// Pose the scene as its animation shows it this many seconds in (glTF; the first
    /// animation unless --animation names another): one frame of a sequence, say.
    #[arg(
        long,
        value_name = "SECONDS",
        allow_negative_numbers = true,
        group = "moment"
    )]
    pub animation_time: Option<f32>,
    /// The animation --animation-time (or `kousen render --frames`) samples: its index or its
    /// name.
    #[arg(long, value_name = "INDEX|NAME", requires = "moment")]
    pub animation: Option<String>,
    /// The material variant to render (glTF `KHR_materials_variants`: a product's colours, say):
    /// its index or its name; `kousen info` lists them.
    #[arg(long, value_name = "INDEX|NAME")]
    pub variant: Option<String>,
}

impl LoadArgs {
    /// The scene crate's options for these.
    pub fn options(&self) -> scene::LoadOptions {
        scene::LoadOptions {
            animation: self.animation_time.map(|seconds| scene::AnimationTime {
                animation: self.animation.clone(),
                seconds,
            }),
            variant: self.variant.clone(),
        }
    }
}

/// The gather radii and how they shrink, for `kousen render` and `kousen view` alike.
#[derive(Args, Clone, Copy, Debug)]
pub struct GatherArgs {
    /// SPPM's radius reduction α, in (0, 1), of the caustic photons (those at their first
    /// diffuse surface).
    #[arg(long, default_value_t = render::settings::DEFAULT_ALPHA)]
    pub alpha: f32,
    /// SPPM's α of the indirect photons (those that bounced off a diffuse surface before):
    /// indirect light is smooth, so its radius may shrink slower, for less noise.
    #[arg(long, value_name = "ALPHA", default_value_t = render::settings::MEASURED_INDIRECT_ALPHA)]
    pub indirect_alpha: f32,
    /// Every pixel's first gather radius, in pixel footprints on the surfaces the camera sees
    /// (smaller: sharper caustics sooner, more noise).
    #[arg(long, value_name = "FOOTPRINTS", default_value_t = render::settings::INITIAL_RADIUS_FOOTPRINTS)]
    pub radius: f32,
    /// The caustic photons' first gather radius as a share of --radius, in (0, 1]. Smaller:
    /// sharper rims of glass caustics sooner, noisier broad caustics such as flat mirrors
    /// throw. Default: 0.55 with sampled direct light, 1 with --direct-light photons (whose
    /// caustic photons carry the direct light too). Measured (docs/BENCHMARKS.md §3): 0.7
    /// against 1 reached Mitsuba's errors inside cornell-caustics' glass caustic 1.4–1.6×
    /// sooner with cornell-metal's whole-image error about a fifth higher (session 15); 0.55
    /// against 0.7, 1.16–1.19× sooner there, cornell-metal +8 % (session 19); scenes without
    /// mirrors or glass unchanged.
    #[arg(long, value_name = "SHARE")]
    pub caustic_radius: Option<f32>,
}

impl GatherArgs {
    /// `--caustic-radius`, or its default for this direct-light mode.
    pub fn caustic_radius_share(&self, direct: render::direct::DirectLight) -> f32 {
        self.caustic_radius.unwrap_or(match direct {
            render::direct::DirectLight::Sampled => render::settings::MEASURED_CAUSTIC_RADIUS_SHARE,
            render::direct::DirectLight::Photons => 1.0,
        })
    }

    /// The first radius in pixel footprints, checked (the α and the share are checked with
    /// the rest of the settings, by `render::Settings::validate`).
    pub fn radius_footprints(&self) -> anyhow::Result<f32> {
        anyhow::ensure!(
            self.radius.is_finite() && self.radius > 0.0 && self.radius <= 1e6,
            "--radius must be a positive number of pixel footprints, got {}",
            self.radius
        );
        Ok(self.radius)
    }
}

#[derive(Args)]
pub struct ViewArgs {
    /// A scene file: .gltf, .glb, .obj, Mitsuba .xml or .pbrt.
    pub scene: PathBuf,
    /// Window width in pixels.
    #[arg(long, default_value_t = 960, value_parser = clap::value_parser!(u32).range(16..=16384))]
    pub width: u32,
    /// Window height in pixels.
    #[arg(long, default_value_t = 720, value_parser = clap::value_parser!(u32).range(16..=16384))]
    pub height: u32,
    /// Render resolution as a fraction of the window's (default: 1 on GPUs, 0.5 on CPU-type
    /// adapters such as lavapipe).
    #[arg(long, value_name = "FRACTION")]
    pub render_scale: Option<f32>,
    /// Photon path slots per pass (default: one per rendered pixel, fewer on slow adapters).
    #[arg(long, value_name = "N")]
    pub photons: Option<u32>,
    /// Exposure in stops.
    #[arg(long, default_value_t = 0.0, allow_negative_numbers = true)]
    pub exposure: f32,
    /// How the window (and its screenshots) map exposed radiance to [0, 1]; the overlay
    /// switches it.
    #[arg(long, value_enum, default_value_t = ToneMapChoice::Clamp)]
    pub tonemap: ToneMapChoice,
    #[command(flatten)]
    pub gather: GatherArgs,
    /// An eye pass every this many photon passes.
    #[arg(long, value_name = "K", default_value_t = render::settings::DEFAULT_EYE_EVERY)]
    pub eye_every: u32,
    #[command(flatten)]
    pub estimator: EstimatorArgs,
    /// Use the GPU adapter whose name contains this (case-insensitive; default: the best).
    #[arg(long, value_name = "SUBSTRING")]
    pub adapter: Option<String>,
    /// Start without the overlay (F1 shows it).
    #[arg(long)]
    pub no_overlay: bool,
    /// Save what the window shows (the image, without the overlay) as a PNG this many seconds
    /// after the first frame; may be given several times. For scripts and tests.
    #[arg(long, num_args = 2, value_names = ["SECONDS", "PATH"], action = clap::ArgAction::Append)]
    pub screenshot_after: Vec<String>,
    /// Open a file this many seconds after the first frame, as if it were dropped on the
    /// window (a scene, or an image that becomes the sky map); may be given several times. For
    /// scripts and tests.
    #[arg(long, num_args = 2, value_names = ["SECONDS", "PATH"], action = clap::ArgAction::Append)]
    pub open_after: Vec<String>,
    /// Take the sky map away this many seconds after the first frame, as the overlay's
    /// "remove the sky map" does. For scripts and tests.
    #[arg(long, value_name = "SECONDS")]
    pub remove_sky_map_after: Option<f64>,
    /// Close the window this many seconds after the first frame (exit 0).
    #[arg(long, value_name = "SECONDS")]
    pub quit_after: Option<f64>,
    #[command(flatten)]
    pub camera: CameraArgs,
    #[command(flatten)]
    pub load: LoadArgs,
    #[command(flatten)]
    pub added_lights: AddedLightArgs,
    #[command(flatten)]
    pub bvh: BvhArgs,
}

impl RenderArgs {
    /// The PNG output's exposure and tone map.
    pub fn look(&self) -> render::tonemap::Look {
        render::tonemap::Look {
            exposure: self.exposure,
            tone_map: self.tonemap.tone_map(),
        }
    }
}

/// Which camera to render from: a file's camera, or one given on the command line.
#[derive(Args, Clone)]
pub struct CameraArgs {
    /// Index of the scene file's camera (default: the first; none: a framed view).
    #[arg(long, value_name = "I", conflicts_with = "eye")]
    pub camera: Option<usize>,
    /// Camera position "x,y,z" (with --target).
    #[arg(long, value_name = "X,Y,Z", requires = "target", value_parser = parse_vec3, allow_hyphen_values = true)]
    pub eye: Option<[f32; 3]>,
    /// Point looked at "x,y,z" (with --eye).
    #[arg(long, value_name = "X,Y,Z", requires = "eye", value_parser = parse_vec3, allow_hyphen_values = true)]
    pub target: Option<[f32; 3]>,
    /// Up direction "x,y,z".
    #[arg(long, value_name = "X,Y,Z", default_value = "0,1,0", value_parser = parse_vec3, allow_hyphen_values = true)]
    pub up: [f32; 3],
    /// Vertical field of view in degrees (with --eye).
    #[arg(long, value_name = "DEGREES", default_value_t = 50.0)]
    pub fov: f32,
    /// Depth of field: the radius of a thin lens, in scene units (Mitsuba's `aperture_radius`,
    /// pbrt's `lensradius`). Default: 0, a pinhole, sharp at every depth.
    #[arg(long, value_name = "R", allow_hyphen_values = true)]
    pub aperture_radius: Option<f32>,
    /// How far ahead of the eye, along the view, the plane in focus lies (with
    /// --aperture-radius). Default: the distance to what the image's centre shows.
    #[arg(long, value_name = "D", allow_hyphen_values = true)]
    pub focus_distance: Option<f32>,
    /// Focus the lens on what pixel "x,y" of the image shows (0,0 the top-left; with
    /// --aperture-radius, instead of --focus-distance): the glass, say, in a scripted render.
    #[arg(long, value_name = "X,Y")]
    pub focus_pixel: Option<String>,
    /// The aperture's shape (with --aperture-radius): 0, round; 3 to 64, a regular polygon of
    /// that many sides inscribed in the radius, as a camera's iris blades make it (out of
    /// focus, points image as that polygon).
    #[arg(long, value_name = "N", default_value_t = 0)]
    pub aperture_blades: u32,
    /// The polygon's turn: its first vertex this many degrees from the image's right towards
    /// its top.
    #[arg(
        long,
        value_name = "DEGREES",
        default_value_t = 0.0,
        allow_hyphen_values = true
    )]
    pub aperture_rotation: f32,
}

/// Lights added to the scene: a sun (a directional light) and a sky (uniform radiance from
/// every direction, or an environment map's), so that scenes without lights of their own
/// (Sponza, the bunny) can be rendered as they are; and fog filling the space they light.
#[derive(Args, Clone)]
pub struct AddedLightArgs {
    /// Fill all space outside the solids with a homogeneous fog (the scene's atmosphere, as a
    /// Mitsuba sensor medium or a pbrt camera medium gives it, replacing any): its extinction
    /// per unit of the scene's length, one number or "r,g,b". It reaches to infinity, so it
    /// hides the sky and the sun in every channel where this is above 0.
    #[arg(long, value_name = "SIGMA_T", value_parser = parse_grey_or_rgb)]
    pub fog: Option<[f32; 3]>,
    /// The share of the fog's extinction that scatters (the rest absorbs): one number or
    /// "r,g,b" in [0, 1].
    #[arg(long, value_name = "ALBEDO", value_parser = parse_grey_or_rgb, default_value = "0.75", requires = "fog")]
    pub fog_albedo: [f32; 3],
    /// The fog's Henyey–Greenstein anisotropy g in (−1, 1): 0 scatters alike every way,
    /// towards 1 onwards (a sunbeam's glow around the sun).
    #[arg(
        long,
        value_name = "G",
        default_value_t = 0.0,
        requires = "fog",
        allow_hyphen_values = true
    )]
    pub fog_anisotropy: f32,
    /// Add a sun: a directional light travelling along "x,y,z" (0.3,-1,0.2 shines down).
    #[arg(long, value_name = "X,Y,Z", value_parser = parse_vec3, allow_hyphen_values = true)]
    pub sun: Option<[f32; 3]>,
    /// The sun's illuminance on a surface facing it (lux: the units of emitted radiance × sr).
    #[arg(long, value_name = "E", default_value_t = 3.0, requires = "sun")]
    pub sun_illuminance: f32,
    /// Add a sky: radiance "r,g,b" from every direction, seen by camera rays that leave the
    /// scene (a white sky of radiance L lights an open floor to ρ·L).
    /// With --sky-map, the factor its radiance is scaled by.
    #[arg(long, value_name = "R,G,B", value_parser = parse_vec3)]
    pub sky: Option<[f32; 3]>,
    /// Add a sky from an environment map: an equirectangular (latitude-longitude) image of
    /// linear radiance, .hdr, .exr or .pfm (.png is read as sRGB); its top row straight up
    /// (+Y), its centre column facing −Z.
    #[arg(long, value_name = "FILE")]
    pub sky_map: Option<std::path::PathBuf>,
    /// Turn the sky map about the up axis (+Y) by this many degrees, counter-clockwise seen
    /// from above.
    #[arg(
        long,
        value_name = "DEGREES",
        default_value_t = 0.0,
        requires = "sky_map",
        allow_hyphen_values = true
    )]
    pub sky_rotate: f32,
}

impl AddedLightArgs {
    /// Adds the sun and the sky to `scene` (read from `path`), those asked for; an atmosphere
    /// hides them as it hides the file's own (`scene::Scene::dim_far_lights`).
    pub fn add_to(&self, scene: &mut scene::Scene, path: &std::path::Path) -> anyhow::Result<()> {
        self.add_sky_and_sun(scene)?;
        self.add_fog(scene)?;
        if self.sky.is_some() || self.sky_map.is_some() || self.sun.is_some() || self.fog.is_some()
        {
            scene.dim_far_lights(path);
        }
        Ok(())
    }

    /// The atmosphere `--fog` asks for, replacing the scene's.
    fn add_fog(&self, scene: &mut scene::Scene) -> anyhow::Result<()> {
        let Some(extinction) = self.fog.map(glam::Vec3::from) else {
            return Ok(());
        };
        let albedo = glam::Vec3::from(self.fog_albedo);
        if extinction.min_element() < 0.0 || extinction.max_element() <= 0.0 {
            anyhow::bail!("--fog needs an extinction ≥ 0 and not all 0, got {extinction}");
        }
        if !(albedo.min_element() >= 0.0 && albedo.max_element() <= 1.0) {
            anyhow::bail!("--fog-albedo must be in [0, 1], got {albedo}");
        }
        let g = self.fog_anisotropy;
        if !(-1.0 < g && g < 1.0) {
            anyhow::bail!("--fog-anisotropy must be in (−1, 1), got {g}");
        }
        let fog = scene::Medium {
            absorption: extinction * (glam::Vec3::ONE - albedo),
            scattering: extinction * albedo,
            anisotropy: g,
        };
        scene.atmosphere = Some(scene.materials.len() as u32);
        scene.materials.push(fog.atmosphere());
        Ok(())
    }

    fn add_sky_and_sun(&self, scene: &mut scene::Scene) -> anyhow::Result<()> {
        let radiance = self.sky.map(glam::Vec3::from);
        if let Some(radiance) = radiance
            && (radiance.min_element() < 0.0
                || radiance.max_element() <= 0.0
                || !radiance.is_finite())
        {
            anyhow::bail!("--sky needs a radiance r,g,b ≥ 0 and not all 0, got {radiance}");
        }
        if !self.sky_rotate.is_finite() {
            anyhow::bail!(
                "--sky-rotate must be a number of degrees, got {}",
                self.sky_rotate
            );
        }
        let bounds = scene.bounds();
        match (&self.sky_map, radiance) {
            (Some(path), scale) => {
                let map = crate::image_io::read_sky_map(path)?;
                let scale = scale.unwrap_or(glam::Vec3::ONE);
                if (scale * map.integral()).max_element() <= 0.0 {
                    anyhow::bail!(
                        "--sky {} scales the sky map {} to black: its light is all in the channels set to 0",
                        self.sky
                            .map_or(String::new(), |[r, g, b]| format!("{r},{g},{b}")),
                        path.display()
                    );
                }
                let rotation = self.sky_rotate.to_radians();
                let sky = scene::Sky::with_map(std::sync::Arc::new(map), scale, rotation, bounds);
                scene.lights.replace_sky(sky);
            }
            (None, Some(radiance)) => scene.lights.set_sky(radiance, bounds),
            (None, None) => {}
        }
        let Some(direction) = self.sun else {
            return Ok(());
        };
        let Some(direction) = glam::Vec3::from(direction).try_normalize() else {
            anyhow::bail!("--sun needs a direction, not the zero vector");
        };
        let illuminance = self.sun_illuminance;
        if !(illuminance.is_finite() && illuminance > 0.0) {
            anyhow::bail!("--sun-illuminance must be a positive number, got {illuminance}");
        }
        let sun = scene::PunctualLight {
            kind: scene::PunctualKind::Directional,
            position: glam::Vec3::ZERO,
            direction,
            intensity: glam::Vec3::splat(illuminance),
        };
        let bounds = scene.bounds();
        scene.lights.add_punctual(sun, bounds);
        Ok(())
    }
}

/// One number for all three channels, or "r,g,b".
fn parse_grey_or_rgb(text: &str) -> Result<[f32; 3], String> {
    match text.trim().parse::<f32>() {
        Ok(v) if v.is_finite() => Ok([v; 3]),
        _ => parse_vec3(text)
            .map_err(|_| format!("expected one finite number or three \"r,g,b\", got {text:?}")),
    }
}

fn parse_vec3(text: &str) -> Result<[f32; 3], String> {
    let parts: Vec<&str> = text.split(',').map(str::trim).collect();
    let values: Result<Vec<f32>, _> = parts.iter().map(|p| p.parse::<f32>()).collect();
    match values {
        Ok(v) if v.len() == 3 && v.iter().all(|x| x.is_finite()) => Ok([v[0], v[1], v[2]]),
        _ => Err(format!(
            "expected three finite numbers \"x,y,z\", got {text:?}"
        )),
    }
}

#[derive(Args)]
pub struct InfoArgs {
    /// A scene file: .gltf, .glb, .obj, Mitsuba .xml or .pbrt.
    pub scene: PathBuf,
    /// Print JSON (a contract for scripts) instead of a table.
    #[arg(long)]
    pub json: bool,
    #[command(flatten)]
    pub load: LoadArgs,
    #[command(flatten)]
    pub bvh: BvhArgs,
}

#[derive(Args, Clone, Copy)]
pub struct BvhArgs {
    /// Most triangles per BVH leaf (the talk uses 1).
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(1..=64))]
    pub leaf_size: Option<u32>,
    /// Most extra BVH references that spatial splits may add (a triangle cut by a node's plane
    /// is referenced on both sides), in percent of the triangle count; 0 turns them off.
    /// Default: 30 where probe rays find the split tree cheaper to traverse; a number given
    /// here is forced.
    #[arg(long, value_name = "PERCENT", value_parser = clap::value_parser!(u32).range(0..=400))]
    pub split_percent: Option<u32>,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn auto_density_is_full_lists_on_cpu_cores_and_the_hash_on_gpus() {
        use render::Density::*;
        assert_eq!(DensityChoice::Auto.density(true), FullHash);
        assert_eq!(DensityChoice::Auto.density(false), StochasticHash);
        for on_cpu_cores in [false, true] {
            assert_eq!(
                DensityChoice::Stochastic.density(on_cpu_cores),
                StochasticHash
            );
            assert_eq!(DensityChoice::Full.density(on_cpu_cores), FullHash);
            assert_eq!(DensityChoice::Kdtree.density(on_cpu_cores), KdTree);
        }
        assert_eq!(DensityChoice::Auto.for_view(), StochasticHash);
        assert_eq!(DensityChoice::Full.for_view(), FullHash);
    }

    /// `--fog` fills the space outside the solids (the scene's atmosphere: extinction split
    /// by the albedo into scattering and absorption), which hides `--sky` in every channel
    /// where it has extinction; bad values are refused naming their option.
    #[test]
    fn fog_fills_the_space_outside_the_solids_and_hides_the_sky() {
        let added = AddedLightArgs {
            fog: Some([0.5, 0.5, 0.0]),
            fog_albedo: [0.8; 3],
            fog_anisotropy: 0.3,
            sun: None,
            sun_illuminance: 3.0,
            sky: Some([1.0, 2.0, 3.0]),
            sky_map: None,
            sky_rotate: 0.0,
        };
        let path = std::path::Path::new("cornell-caustics");
        let mut scene = scene::testing::cornell_caustics();
        added.add_to(&mut scene, path).unwrap();
        let air = &scene.materials[scene.atmosphere.unwrap() as usize];
        assert!(
            air.absorption
                .abs_diff_eq(glam::Vec3::new(0.1, 0.1, 0.0), 1e-6)
        );
        assert!(
            air.scattering
                .abs_diff_eq(glam::Vec3::new(0.4, 0.4, 0.0), 1e-6)
        );
        assert_eq!(air.scatter_anisotropy, 0.3);
        let sky = scene.lights.sky.as_ref().unwrap();
        assert_eq!(sky.radiance, glam::Vec3::new(0.0, 0.0, 3.0));
        for (bad, option) in [
            (
                AddedLightArgs {
                    fog: Some([-1.0, 0.0, 0.0]),
                    ..added.clone()
                },
                "--fog ",
            ),
            (
                AddedLightArgs {
                    fog_albedo: [1.5; 3],
                    ..added.clone()
                },
                "--fog-albedo",
            ),
            (
                AddedLightArgs {
                    fog_anisotropy: 1.0,
                    ..added.clone()
                },
                "--fog-anisotropy",
            ),
        ] {
            let mut scene = scene::testing::cornell_caustics();
            let error = bad.add_to(&mut scene, path).unwrap_err().to_string();
            assert!(error.starts_with(option), "{error}");
        }
    }
}
