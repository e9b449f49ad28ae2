//! The WGSL prelude: every constant the kernels share with Rust, written from the Rust values
//! so the two can never disagree (`LINK_END`, `MAX_DEPTH`, the slab test's factors, ...).
//! Floats are printed in Rust's shortest round-trip form with WGSL's `f` suffix, which parses
//! straight to the same f32 (tests/layout.rs checks every value through naga).

use std::fmt::Write;

use render::buffers::{self, counter};
use render::{dispersion, rng};

use crate::types;

/// Invocations per workgroup of every kernel (one ray or photon each).
pub const WORKGROUP_SIZE: u32 = 64;

/// A prelude constant's value.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Value {
    U32(u32),
    F32(f32),
}

/// Every constant of the prelude: (WGSL name, value).
pub fn constants() -> Vec<(&'static str, Value)> {
    use Value::{F32, U32};
    vec![
        ("LINK_END", U32(bvh::LINK_END)),
        ("DIRECTION_COUNT", U32(bvh::DIRECTION_COUNT as u32)),
        ("MAX_DEPTH", U32(bvh::MAX_DEPTH as u32)),
        ("COMPACT_LEAF", U32(bvh::compact::COMPACT_LEAF)),
        ("COMPACT_FAR", U32(bvh::compact::COMPACT_FAR)),
        ("COMPACT_COUNT_MASK", U32(bvh::compact::COMPACT_COUNT_MASK)),
        ("NO_HIT", U32(types::NO_HIT)),
        ("TEXEL_ROW", U32(crate::scene_upload::TEXEL_ROW)),
        ("ROBUST_EXIT", F32(bvh::intersect::ROBUST_EXIT)),
        ("PARALLEL_LIMIT", F32(bvh::intersect::PARALLEL_LIMIT)),
        ("NO_DISTANCE", F32(types::NO_DISTANCE)),
        ("RAY_T_MAX", F32(types::RAY_T_MAX)),
        ("WORKGROUP_SIZE", U32(WORKGROUP_SIZE)),
        ("U32_TO_UNIT", F32(1.0 / 4_294_967_296.0)),
        ("PI", F32(std::f32::consts::PI)),
        ("SURFACE_DIFFUSE", U32(types::SURFACE_DIFFUSE)),
        ("SURFACE_MIRROR", U32(types::SURFACE_MIRROR)),
        ("SURFACE_DIELECTRIC", U32(types::SURFACE_DIELECTRIC)),
        (
            "SURFACE_ROUGH_CONDUCTOR",
            U32(types::SURFACE_ROUGH_CONDUCTOR),
        ),
        (
            "SURFACE_ROUGH_DIELECTRIC",
            U32(types::SURFACE_ROUGH_DIELECTRIC),
        ),
        ("SURFACE_PLASTIC", U32(types::SURFACE_PLASTIC)),
        ("COAT_NODES", U32(render::plastic::COAT_NODES as u32)),
        ("NO_TEXTURE", U32(types::NO_TEXTURE)),
        ("MATERIAL_DOUBLE_SIDED", U32(types::MATERIAL_DOUBLE_SIDED)),
        ("MATERIAL_THIN_WALLED", U32(types::MATERIAL_THIN_WALLED)),
        ("MATERIAL_BLEND", U32(types::MATERIAL_BLEND)),
        ("MATERIAL_BOUNDS_VOLUME", U32(types::MATERIAL_BOUNDS_VOLUME)),
        ("MATERIAL_MURKY_GLASS", U32(types::MATERIAL_MURKY_GLASS)),
        ("MATERIAL_KEEPS_LOBE", U32(types::MATERIAL_KEEPS_LOBE)),
        ("VOLUME_BIT", U32(render::packing::VOLUME_BIT)),
        (
            "SCATTERINGS_PER_STEP",
            U32(render::scattering::SCATTERINGS_PER_STEP),
        ),
        ("NO_WALK", U32(render::scattering::NO_WALK)),
        ("ROUGHNESS_METAL", U32(types::ROUGHNESS_METAL)),
        ("ROUGHNESS_UNMAPPED", U32(types::ROUGHNESS_UNMAPPED)),
        ("ROUGHNESS_GLASS", U32(types::ROUGHNESS_GLASS)),
        ("MIRROR_MAX_ROUGHNESS", F32(scene::MIRROR_MAX_ROUGHNESS)),
        ("MIN_BRUSHED_ALPHA", F32(scene::MIN_BRUSHED_ALPHA)),
        ("DIFFUSE_MIN_ROUGHNESS", F32(scene::DIFFUSE_MIN_ROUGHNESS)),
        ("CLEARCOAT_IOR", F32(scene::Clearcoat::IOR)),
        ("SHEEN_NODES", U32(render::sheen::SHEEN_NODES as u32)),
        (
            "SHEEN_GRID_NODES",
            U32(render::sheen::SHEEN_GRID_NODES as u32),
        ),
        ("SHEEN_MIN_ROUGHNESS", F32(scene::Sheen::MIN_ROUGHNESS)),
        ("SLOT_IDLE", U32(buffers::SLOT_IDLE)),
        ("LIGHT_TRIANGLE", U32(buffers::LIGHT_TRIANGLE)),
        ("LIGHT_POINT", U32(buffers::LIGHT_POINT)),
        ("LIGHT_SPOT", U32(buffers::LIGHT_SPOT)),
        ("LIGHT_DIRECTIONAL", U32(buffers::LIGHT_DIRECTIONAL)),
        ("LIGHT_SKY", U32(buffers::LIGHT_SKY)),
        (
            "SAMPLE_AT_VISIBLE_POINTS",
            U32(buffers::SAMPLE_AT_VISIBLE_POINTS),
        ),
        ("SAMPLE_AT_GLOSSY", U32(buffers::SAMPLE_AT_GLOSSY)),
        ("MAX_PASS_THROUGHS", U32(buffers::MAX_PASS_THROUGHS)),
        ("MAX_BLEND_MEMBERS", U32(scene::MAX_BLEND_MEMBERS as u32)),
        ("SPECULAR_EXTRA_PATHS", U32(buffers::SPECULAR_EXTRA_PATHS)),
        ("SHADOW_SHORTENING", F32(render::direct::SHADOW_SHORTENING)),
        ("PHOTON_STREAM", U32(rng::PHOTON_STREAM)),
        ("EYE_STREAM", U32(rng::EYE_STREAM)),
        ("JITTER_STREAM", U32(rng::JITTER_STREAM)),
        ("R2_STEP_X", U32(rng::R2_STEP[0])),
        ("R2_STEP_Y", U32(rng::R2_STEP[1])),
        ("GOLDEN_STEP", U32(rng::GOLDEN_STEP)),
        ("SIDE_STEP", U32(rng::SIDE_STEP)),
        ("LENS_STEP_X", U32(rng::LENS_STEP[0])),
        ("LENS_STEP_Y", U32(rng::LENS_STEP[1])),
        ("CLASS_MARK_SHIFT", U32(render::hash::CLASS_MARK_SHIFT)),
        ("HUE_CLASSES", U32(render::hash::HUE_CLASSES)),
        ("WAVELENGTH_SHIFT", U32(render::medium::WAVELENGTH_SHIFT)),
        ("MEDIUM_MASK", U32(render::medium::MEDIUM_MASK)),
        ("WAVELENGTH_LEVELS", U32(dispersion::WAVELENGTH_LEVELS)),
        ("WHOLE_SPECTRUM", U32(dispersion::WHOLE_SPECTRUM)),
        (
            "FILM_WAVELENGTHS",
            U32(render::iridescence::FILM_WAVELENGTHS as u32),
        ),
        (
            "FILM_WAVENUMBER_FIRST",
            F32(render::iridescence::FILM_WAVENUMBER_FIRST),
        ),
        (
            "FILM_WAVENUMBER_STEP",
            F32(render::iridescence::FILM_WAVENUMBER_STEP),
        ),
        ("HASH_STREAM", U32(rng::HASH_STREAM)),
        ("CELL_SLACK", F32(render::hash::CELL_SLACK)),
        ("HASH_ENTRY_WORDS", U32(buffers::HASH_ENTRY_WORDS as u32)),
        ("HASH_PRIORITY", U32(buffers::hash_word::PRIORITY as u32)),
        ("HASH_COUNT", U32(buffers::hash_word::COUNT as u32)),
        ("HASH_WINNER", U32(buffers::hash_word::WINNER as u32)),
        ("SCAN_BLOCK", U32(render::density::SCAN_BLOCK)),
        ("FULL_START", U32(render::density::full_word::START as u32)),
        ("FULL_COUNT", U32(render::density::full_word::COUNT as u32)),
        ("FULL_FILL", U32(render::density::full_word::FILL as u32)),
        ("KD_STACK_SIZE", U32(render::kdtree::STACK_SIZE as u32)),
        ("KD_AXIS_SHIFT", U32(render::kdtree::AXIS_SHIFT)),
        ("KD_PHOTON_MASK", U32(render::kdtree::PHOTON_MASK)),
        ("COUNTER_COUNT", U32(counter::COUNT as u32)),
        ("COUNTER_PASS", U32(counter::PASS as u32)),
        ("COUNTER_EMITTED_LO", U32(counter::EMITTED_LO as u32)),
        ("COUNTER_EMITTED_HI", U32(counter::EMITTED_HI as u32)),
        ("COUNTER_EMITTED_PASS", U32(counter::EMITTED_PASS as u32)),
        ("COUNTER_MAX_RADIUS", U32(counter::MAX_RADIUS as u32)),
        ("COUNTER_CELL_SIZE", U32(counter::CELL_SIZE as u32)),
        (
            "COUNTER_RADIUS_HISTOGRAM",
            U32(counter::RADIUS_HISTOGRAM as u32),
        ),
        (
            "COUNTER_CAUSTIC_MAX_RADIUS",
            U32(counter::CAUSTIC_MAX_RADIUS as u32),
        ),
        (
            "COUNTER_CAUSTIC_CELL_SIZE",
            U32(counter::CAUSTIC_CELL_SIZE as u32),
        ),
        (
            "COUNTER_CAUSTIC_RADIUS_HISTOGRAM",
            U32(counter::CAUSTIC_RADIUS_HISTOGRAM as u32),
        ),
        (
            "RADIUS_BUCKETS",
            U32(render::radius_histogram::RADIUS_BUCKETS as u32),
        ),
        (
            "COUNTER_VOLUME_MAX_RADIUS",
            U32(counter::VOLUME_MAX_RADIUS as u32),
        ),
        (
            "COUNTER_VOLUME_CELL_SIZE",
            U32(counter::VOLUME_CELL_SIZE as u32),
        ),
        ("VOLUME_CELL_SALT", U32(render::hash::VOLUME_CELL_SALT)),
        (
            "VOLUME_CELL_DIVISIONS",
            U32(render::hash::VOLUME_CELL_DIVISIONS),
        ),
        ("VOLUME_CELL_SHARE", F32(render::hash::VOLUME_CELL_SHARE)),
        ("CELL_BOX_MARGIN", F32(render::hash::CELL_BOX_MARGIN)),
    ]
}

/// The prelude's WGSL text: one `const` per entry of [`constants`].
pub fn wgsl() -> String {
    let mut text = String::from("// Generated from Rust by gpu::prelude; do not edit.\n");
    for (name, value) in constants() {
        let literal = match value {
            Value::U32(v) => format!("{v}u"),
            Value::F32(v) => {
                assert!(v.is_finite(), "{name}: WGSL has no literal for {v}");
                format!("{v:?}f")
            }
        };
        let ty = match value {
            Value::U32(_) => "u32",
            Value::F32(_) => "f32",
        };
        writeln!(text, "const {name}: {ty} = {literal};").expect("writing to a String");
    }
    text
}
