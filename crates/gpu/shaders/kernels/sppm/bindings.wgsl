// The SPPM kernels, twins of cpu::kernels (same names, arithmetic and random numbers), split
// by concern under kernels/sppm/. This piece: their group 1 buffers, which every piece reads.

@group(1) @binding(0) var<uniform> params: SppmParams;
@group(1) @binding(1) var<storage, read> lights: array<Light>;
@group(1) @binding(2) var<storage, read_write> slots: array<PathSlot>;
// Bindings 3 and 4 (photons, visible points) are declared by photon_storage_*.wgsl, with
// load_/store_ functions in the storage's precision.
@group(1) @binding(5) var<storage, read_write> pixels: array<PixelStats>;
@group(1) @binding(6) var<storage, read_write> hash: array<atomic<u32>>;
@group(1) @binding(7) var<storage, read_write> counters: array<atomic<u32>, COUNTER_COUNT>;
// render::sky_map's buffer: the sky's environment map, its texels and CDFs.
@group(1) @binding(8) var<storage, read> sky_map: array<f32>;
// render::normal_map::packed_tangents: the mesh's tangents, three a packed triangle (read
// only where TANGENTS).
@group(1) @binding(9) var<storage, read> vertex_tangents: array<vec4<f32>>;
// render::buffers::PixelStats::volume_tau of each pixel (w: its padding), where MURKY_GLASS;
// else one unused element.
@group(1) @binding(10) var<storage, read_write> pixel_volume_tau: array<vec4<f32>>;
