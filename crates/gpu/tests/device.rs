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
