// WGSL twins of gpu::types; tests/layout.rs checks sizes and offsets against the Rust side.

// A ray for the kernels (32 bytes). Hits count for t in [0, t_max); t_max = 0 marks an unused
// slot. `pad` keeps the struct two vec4s.
struct GpuRay {
    origin: vec3<f32>,
    t_max: f32,
    direction: vec3<f32>,
    pad: u32,
}

// A traversal's answer (16 bytes): triangle is an index into bvh_triangles, NO_HIT on a miss
// (then t is the ray's t_max).
struct GpuHit {
    t: f32,
    triangle: u32,
    u: f32,
    v: f32,
}

// The BVH's sizes and where the TBVH's threaded records start (16 bytes). Record set d (0..5,
// see direction_index) occupies bvh_threaded[d * node_count ..][..node_count], each set in its
// own pre-order from its root; the TBVH's set follows at tbvh_record_base.
struct SceneInfo {
    node_count: u32,
    triangle_count: u32,
    tbvh_record_base: u32,
    pad: u32,
    // gpu::types::SceneInfo::spectrum: per level, its wavelength and weight.
    spectrum: array<vec4<f32>, WAVELENGTH_LEVELS>,
    // gpu::types::SceneInfo::film_spectrum: per wavelength, itself and its weight.
    film_spectrum: array<vec4<f32>, FILM_WAVELENGTHS>,
}

// One material (400 bytes). surface: SURFACE_* constants; textures are indices or NO_TEXTURE;
// alpha_cutoff < 0 means opaque; flags: MATERIAL_DOUBLE_SIDED | MATERIAL_THIN_WALLED |
// MATERIAL_BLEND | MATERIAL_BOUNDS_VOLUME | MATERIAL_MURKY_GLASS;
// ior: of dielectrics and plastic coats; roughness_alpha: GGX width of rough surfaces; normal_texture: a tangent-space normal map
// (NO_TEXTURE: none), its X and Y scaled by normal_scale; coat_*: plastic's coat
// (render::plastic::Coat: its diffuse scale, a rough coat's transmittance at COAT_NODES cosines).
struct GpuMaterial {
    base_color: vec3<f32>,
    surface: u32,
    emission: vec3<f32>,
    ior: f32,
    base_color_texture: u32,
    emission_texture: u32,
    alpha_cutoff: f32,
    flags: u32,
    absorption: vec3<f32>,
    roughness_alpha: f32,
    normal_texture: u32,
    normal_scale: f32,
    light_area_density: f32,
    coat_diffuse_scale: f32,
    coat_transmittance: array<vec4<f32>, 4>,
    blend_weight: f32,
    blend_other: u32,
    blend_photon_member: u32,
    // render::nesting::Nesting::exterior.
    exterior: u32,
    // scene::Material::dispersion (render::dispersion).
    dispersion: f32,
    // scene::RoughnessMap (render::blend::mapped_material): NO_TEXTURE for none.
    roughness_texture: u32,
    roughness_factor: f32,
    roughness_lobe: u32,
    // render::coats::CoatGrid of a mapped coat (records in `materials`: its smooth coat at
    // coat_grid_first, its coat_grid_nodes rough ones after it; 0 nodes: no grid).
    coat_grid_first: u32,
    coat_grid_nodes: u32,
    coat_grid_roughness: f32,
    coat_grid_step: f32,
    // scene::Clearcoat (render::clearcoat): weight (0: none) and GGX width, and the textures
    // scaling them (NO_TEXTURE: none).
    clearcoat: f32,
    clearcoat_alpha: f32,
    clearcoat_texture: u32,
    clearcoat_roughness_texture: u32,
    // scene::Sheen (render::sheen): colour (black: none) and Charlie width, its table's albedo
    // nodes (render::sheen::SheenTable, four a row), its colour and roughness textures
    // (NO_TEXTURE: none), the record of the sheen grid's first table (with a roughness
    // texture) and its roughness.
    sheen_color: vec3<f32>,
    sheen_alpha: f32,
    sheen_albedo: array<vec4<f32>, 4>,
    sheen_color_texture: u32,
    sheen_roughness_texture: u32,
    sheen_grid_first: u32,
    sheen_roughness: f32,
    // scene::Clearcoat::normal_texture (NO_TEXTURE: none) and its scale.
    clearcoat_normal_texture: u32,
    clearcoat_normal_scale: f32,
    // scene::Material::transmission_texture (NO_TEXTURE: none).
    transmission_texture: u32,
    // scene::DiffuseTransmission: its strength texture (alpha), colour, factor (0: none) and
    // colour texture (NO_TEXTURE: none).
    diffuse_transmission_texture: u32,
    diffuse_transmission_color: vec3<f32>,
    diffuse_transmission: f32,
    diffuse_transmission_color_texture: u32,
    // scene::Anisotropy's texture (NO_TEXTURE: none) and Anisotropy::base (zero: none).
    anisotropy_texture: u32,
    anisotropy: vec2<f32>,
    // A translucent solid's scattering inside (zero: none) and its phase function's
    // asymmetry (render::scattering).
    scattering: vec3<f32>,
    scatter_anisotropy: f32,
    // scene::Iridescence: factor (0: none), film index, least and greatest thickness (nm),
    // then its factor and thickness textures (NO_TEXTURE: none).
    iridescence: vec4<f32>,
    iridescence_texture: u32,
    iridescence_thickness_texture: u32,
    // scene::SpecularLayer on the dielectric: strength and colour textures (NO_TEXTURE: none),
    // tinted F0, factor, and whether there is one (1; 0: none).
    specular_texture: u32,
    specular_color_texture: u32,
    specular_tinted_f0: vec3<f32>,
    specular_factor: f32,
    // scene::Material::metal_edge: how far a metal's reflectance rises towards white at
    // grazing angles (render::conductor).
    metal_edge: vec3<f32>,
    specular_layer: u32,
}
