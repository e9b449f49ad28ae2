//! The scene crate's integration tests, one module per file beside this one, built as one
//! test binary: each binary links the whole dependency graph, and linking forty of them was
//! a large share of a clean build (CI).

mod files_support;
mod gltf_support;
#[path = "../examples/make_scenes/gltf_writer.rs"]
#[allow(dead_code)] // each test module uses a different part
mod gltf_writer;
#[path = "../examples/make_scenes/sky_writer.rs"]
#[allow(dead_code)] // each test module uses a different part
mod sky_writer;

mod gltf_animations;
mod gltf_bad_input;
mod gltf_cameras;
mod gltf_containers;
mod gltf_geometry;
mod gltf_lights;
mod gltf_materials;
mod gltf_meshopt;
mod gltf_skins;
mod gltf_variants;
mod gltf_webp;
mod mitsuba;
mod obj_bad_input;
mod obj_geometry;
mod obj_materials;
mod obj_shared_scenes;
mod obj_shipped_scenes;
mod pbrt;
