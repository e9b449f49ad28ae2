//! A real device. CI installs Mesa lavapipe, so finding no adapter is a failure, not a skip.

use gpu::{GpuContext, GpuError};

fn context() -> GpuContext {
    GpuContext::new(None).unwrap_or_else(|e| {
        panic!("no usable GPU adapter in the test environment (CI installs Mesa lavapipe): {e}")
    })
}

#[test]
fn gpu_context_opens_with_description_and_at_least_default_limits() {
    let context = context();
    let description = context.description();
    eprintln!("device: {description}");
    assert!(!description.trim().is_empty());
    assert!(!description.contains('\n'), "{description}");
    assert!(description.contains(&context.info.name), "{description}");

    let mut below = Vec::new();
    wgpu::Limits::default().check_limits_with_fail_fn(&context.limits, false, |name, want, got| {
        below.push(format!("{name}: {got} < default {want}"));
    });
    assert!(
        below.is_empty(),
        "{description} is below wgpu's defaults: {below:?}"
    );
    assert_eq!(
        context.device.limits(),
        context.limits,
        "device opened with the adapter's limits"
    );
}

#[test]
fn gpu_context_with_unmatched_filter_is_no_adapter() {
    let filter = "no-such-adapter-7f3a";
    let error = GpuContext::new(Some(filter)).expect_err("a filter matching nothing");
    assert!(matches!(error, GpuError::NoAdapter { .. }), "{error:?}");
    let message = error.to_string();
    assert!(message.contains(filter), "{message}");
    assert!(!message.contains('\n'), "{message}");
}

/// The error of uploading cornell-caustics stored as `storage` once `lower` has shrunk the
/// device's limits (simulating a smaller device), with its message, checked to be one line.
fn refused_upload(
    storage: gpu::SceneStorage,
    lower: impl FnOnce(&mut wgpu::Limits, &bvh::PackedBvh),
) -> (GpuError, String) {
    let mut context = context();
    context.scene_storage = storage;
    let triangles = scene::testing::cornell_caustics().triangles;
    let bvh = bvh::PackedBvh::build(&triangles, &bvh::BuildOptions::default());
    lower(&mut context.limits, &bvh);
    let error = gpu::GpuScene::upload(&context, &bvh, &[scene::Material::default()])
        .expect_err("a scene past the lowered limit");
    let message = error.to_string();
    assert!(!message.contains('\n'), "{message}");
    (error, message)
}

#[test]
fn scene_over_a_lowered_binding_limit_is_refused_in_words() {
    // The triangles no longer fit one binding.
    let (error, message) = refused_upload(gpu::SceneStorage::Buffers, |limits, bvh| {
        let triangle_bytes = std::mem::size_of_val(bvh.triangles.as_slice()) as u64;
        limits.max_storage_buffer_binding_size = triangle_bytes / 2;
    });
    assert!(
        matches!(error, GpuError::BufferTooLarge { .. }),
        "{error:?}"
    );
    assert!(message.contains("bvh_triangles"), "{message}");
    assert!(
        message.contains("max_storage_buffer_binding_size"),
        "{message}"
    );
}

#[test]
fn scene_texels_over_a_lowered_texture_side_are_refused_in_words() {
    // A texture's row no longer fits its side.
    let (error, message) = refused_upload(gpu::SceneStorage::Texels, |limits, _| {
        limits.max_texture_dimension_2d = 64;
    });
    assert!(
        matches!(error, GpuError::TexelsTooLarge { .. }),
        "{error:?}"
    );
    assert!(message.contains("bvh_nodes"), "{message}");
    assert!(
        message.contains("max_texture_dimension_2d = 64"),
        "{message}"
    );
}

#[test]
fn sppm_photons_over_a_lowered_binding_limit_are_refused_in_words() {
    let mut context = context();
    let scene = scene::testing::cornell_box();
    let bvh = bvh::PackedBvh::build(&scene.triangles, &bvh::BuildOptions::default());
    let camera = scene.camera(None).expect("the Cornell box has a camera");
    let settings = render::Settings::new(16, 16, 1 << 20);
    let slot_bytes = (settings.photons as usize * size_of::<render::buffers::PathSlot>()) as u64;
    let photon_bytes = (settings.photons as usize * size_of::<render::buffers::Photon>()) as u64;
    // Simulate a smaller device: the scene and every per-pixel buffer fit, the photon
    // buffers (1 Mi slots: 64 MiB of path slots, 32 MiB of photons) do not.
    let limit = 16 << 20;
    assert!(photon_bytes > limit && slot_bytes > limit);
    context.limits.max_storage_buffer_binding_size = limit;
    let backend =
        gpu::sppm::GpuBackend::new(context, &scene, bvh).expect("the scene fits the lowered limit");
    let error = render::Sppm::new(backend, &scene, &camera, settings)
        .err()
        .expect("photon buffers larger than the binding limit");
    let message = error.to_string();
    assert!(
        matches!(
            error,
            render::RenderError::Backend(render::BackendError::DoesNotFit(_))
        ),
        "{error:?}"
    );
    // The first buffer checked that breaks the limit: the path slots, 64 MiB.
    assert!(message.contains("photon_slots"), "{message}");
    let expected = format!("{:.1} MiB", slot_bytes as f64 / (1 << 20) as f64);
    assert!(message.contains(&expected), "{message}");
    // And what would make it fit.
    assert!(message.contains("--photons"), "{message}");
    assert!(
        message.contains("max_storage_buffer_binding_size = 16.0 MiB"),
        "{message}"
    );
    assert!(!message.contains('\n'), "{message}");
}

/// A sky map past the storage binding (simulated by lowering the limit to 1 MiB: a 512 × 256
/// map takes 2.5 MiB with its CDFs) is refused in one line naming the buffer and the limit.
#[test]
fn a_sky_map_over_a_lowered_binding_limit_is_refused_in_words() {
    let mut context = context();
    let mut scene = scene::testing::cornell_box();
    let map = scene::SkyMap::new(512, 256, vec![glam::Vec3::ONE; 512 * 256]).unwrap();
    let bounds = scene.bounds();
    let sky = scene::Sky::with_map(std::sync::Arc::new(map), glam::Vec3::ONE, 0.0, bounds);
    scene.lights.replace_sky(sky);
    let bvh = bvh::PackedBvh::build(&scene.triangles, &bvh::BuildOptions::default());
    context.limits.max_storage_buffer_binding_size = 1 << 20;
    let message = gpu::sppm::GpuBackend::new(context, &scene, bvh)
        .err()
        .expect("a sky map past the limit")
        .to_string();
    assert!(message.contains("sky_map"), "{message}");
    assert!(
        message.contains("max_storage_buffer_binding_size = 1.0 MiB"),
        "{message}"
    );
    assert!(!message.contains('\n'), "{message}");
}
