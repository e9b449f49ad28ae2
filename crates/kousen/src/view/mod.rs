//! `kousen view`: the GPU renderer's progressive image in a window (issue 5).

mod app;
pub mod camera_control;
pub mod frame_budget;
mod overlay;
mod scene_choice;
mod schedule;
mod screenshot;
mod session;

use anyhow::Context;

use crate::cli::ViewArgs;

pub fn run(args: &ViewArgs) -> anyhow::Result<()> {
    // Bad arguments and scenes fail before a window opens.
    app::check_arguments(args)?;
    let options = args.load.options();
    let loaded = session::load_scene(&args.scene, args.bvh, &args.added_lights, &options)?;
    let camera = crate::cmd::render::choose_camera(&loaded.scene, &args.camera)?
        .unwrap_or_else(|| render::framing::framed_view(&loaded.bvh, loaded.scene.bounds()));
    let size = (args.width, args.height);
    let camera = crate::cmd::render::with_lens(camera, &args.camera, &loaded.bvh, size)?;
    let event_loop = winit::event_loop::EventLoop::new().map_err(|e| {
        log::debug!("view: no event loop: {e}");
        anyhow::anyhow!(
            "no display to open a window on (DISPLAY and WAYLAND_DISPLAY unset or unreachable); render to a file instead: `kousen render {} -o image.png`",
            args.scene.display()
        )
    })?;
    let instance = wgpu::Instance::new(gpu::instance_descriptor(Some(Box::new(
        event_loop.owned_display_handle(),
    ))));
    let mut app = app::App::new(args, instance, loaded, camera)?;
    event_loop
        .run_app(&mut app)
        .context("the window's event loop failed")?;
    match app.fatal.take() {
        Some(error) => Err(error),
        None => Ok(()),
    }
}
