//! Copies of device buffers back to the host: a staging buffer, a copy, and a blocking map.

use crate::{GpuContext, GpuError};

/// Blocks until the queue's work is done.
pub fn wait_idle(context: &GpuContext) -> Result<(), GpuError> {
    context
        .device
        .poll(wgpu::PollType::wait_indefinitely())
        .map(drop)
        .map_err(|e| GpuError::Device(e.to_string()))
}

/// The first `count` elements of `buffer` (which needs `COPY_SRC`).
pub fn read_buffer<T: bytemuck::Pod>(
    context: &GpuContext,
    buffer: &wgpu::Buffer,
    count: usize,
) -> Result<Vec<T>, GpuError> {
    let bytes = (count * size_of::<T>()) as u64;
    if bytes == 0 {
        return Ok(Vec::new());
    }
    let staging = context.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("readback"),
        size: bytes,
        usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    });
    let mut encoder = context
        .device
        .create_command_encoder(&wgpu::CommandEncoderDescriptor::default());
    encoder.copy_buffer_to_buffer(buffer, 0, &staging, 0, bytes);
    context.queue.submit([encoder.finish()]);
    map_staging(context, &staging, |bytes| {
        bytemuck::cast_slice(bytes).to_vec()
    })
}

/// Maps `staging` (a `MAP_READ` buffer whose copies were submitted), waits for the device, and
/// hands its bytes to `read`.
pub fn map_staging<R>(
    context: &GpuContext,
    staging: &wgpu::Buffer,
    read: impl FnOnce(&[u8]) -> R,
) -> Result<R, GpuError> {
    let (sender, receiver) = std::sync::mpsc::channel();
    staging.map_async(wgpu::MapMode::Read, .., move |result| {
        // The receiver waits below, so the send cannot fail.
        let _ = sender.send(result);
    });
    wait_idle(context)?;
    receiver
        .recv()
        .map_err(|e| GpuError::Device(e.to_string()))?
        .map_err(|e| GpuError::Device(e.to_string()))?;
    let view = staging
        .get_mapped_range(..)
        .map_err(|e| GpuError::Device(e.to_string()))?;
    let result = read(&view);
    drop(view);
    staging.unmap();
    Ok(result)
}
