//! The window: winit events in, SPPM passes and a drawn frame out. Each frame runs as many
//! passes as fit the frame budget, then the display pass tonemaps the accumulation buffers
//! straight into the swapchain image and egui draws the overlay on top.

use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::sync::{Mutex, mpsc};
use std::time::{Duration, Instant};

use anyhow::Context;
use glam::Vec2;
use gpu::GpuContext;
use gpu::display::DisplayPass;
use render::resolve::Parts;
use winit::application::ApplicationHandler;
use winit::event::{ElementState, MouseButton, MouseScrollDelta, WindowEvent};
use winit::event_loop::{ActiveEventLoop, ControlFlow};
use winit::keyboard::{KeyCode, ModifiersState, PhysicalKey};
use winit::window::{Window, WindowId};

use super::camera_control::{CameraController, FlyKey, drag_mode};
use super::frame_budget::{FrameBudget, TARGET_FRAME, initial_photons};
use super::overlay::{Action, Overlay, OverlayInfo};
use super::scene_choice::SceneChoice;
use super::schedule::{Schedule, Timed};
use super::session::{LoadedScene, RenderControls, Session, load_scene};
use crate::cli::{AddedLightArgs, BvhArgs, ViewArgs};

/// How often the emitted-path count (a tiny readback) and the mean radius (every pixel's
/// statistics) are refreshed for the overlay.
const PATHS_REFRESH: Duration = Duration::from_millis(500);
const RADIUS_REFRESH: Duration = Duration::from_secs(2);
/// Photon-count cuts allowed per scene and window size, and only while a render is this young.
const MAX_PHOTON_CUTS: u32 = 2;
const PHOTON_CUT_MAX_PASSES: u32 = 32;
/// Scene files a drop may open.
const SCENE_EXTENSIONS: [&str; 5] = ["gltf", "glb", "obj", "xml", "pbrt"];
/// Files dropped on the window that light the scene as its sky (`--sky-map`).
const SKY_MAP_EXTENSIONS: [&str; 4] = ["hdr", "exr", "pfm", "png"];

/// What a dropped file is taken for, by its extension.
#[derive(Clone, Copy, Debug, PartialEq)]
enum DroppedKind {
    Scene,
    SkyMap,
}

fn dropped_kind(path: &Path) -> Option<DroppedKind> {
    let name = path.file_name()?.to_string_lossy().to_ascii_lowercase();
    if name.ends_with(".pbrt.gz") {
        return Some(DroppedKind::Scene);
    }
    let extension = path.extension()?;
    let among = |known: &[&str]| known.iter().any(|k| extension.eq_ignore_ascii_case(k));
    if among(&SCENE_EXTENSIONS) {
        Some(DroppedKind::Scene)
    } else if among(&SKY_MAP_EXTENSIONS) {
        Some(DroppedKind::SkyMap)
    } else {
        None
    }
}

/// A dropped file once read: a scene to open, or a sky map for the scene shown.
enum Dropped {
    Scene(Box<LoadedScene>),
    SkyMap(scene::SkyMap),
}

/// Why the scene shown is being read again; its view, lens and title stay.
#[derive(Debug)]
enum Reload {
    /// Without its sky map (the overlay's "remove"): the map and turn it had, put back if that
    /// fails (a scene with no light of its own).
    WithoutSkyMap { map: Option<PathBuf>, turn: f32 },
    /// As the overlay's scene choice asks (another animation moment or material variant).
    Choice,
}

/// The window and what draws into it, made once the event loop has resumed.
struct Gfx {
    /// The first device error wgpu reported (it would otherwise panic).
    device_error: Arc<Mutex<Option<String>>>,
    window: Arc<Window>,
    surface: wgpu::Surface<'static>,
    config: wgpu::SurfaceConfiguration,
    context: GpuContext,
    display: DisplayPass,
    egui_ctx: egui::Context,
    egui_state: egui_winit::State,
    egui_renderer: egui_wgpu::Renderer,
}

#[derive(Default)]
struct Mouse {
    left: bool,
    middle: bool,
    right: bool,
    position: Option<Vec2>,
}

pub struct App {
    instance: wgpu::Instance,
    title: String,
    window_size: (u32, u32),
    adapter_filter: Option<String>,
    /// `--render-scale`, until the adapter is known; then the scale in use.
    render_scale: Option<f32>,
    scale: f32,
    photons_override: Option<u32>,
    bvh_args: BvhArgs,
    added_lights: AddedLightArgs,
    initial_camera: Option<scene::Camera>,
    /// The scene given on the command line, until the device exists to upload it.
    initial_scene: Option<LoadedScene>,
    gfx: Option<Gfx>,
    session: Option<Session>,
    /// A dropped file being read on another thread.
    loading: Option<(PathBuf, mpsc::Receiver<anyhow::Result<Dropped>>)>,
    /// Why the scene shown is being read again, while it is (`loading` holds the read).
    reloading: Option<Reload>,
    /// The animation moment and material variant of the scene shown (the overlay's choice may
    /// be ahead of it while the file is read again).
    shown_choice: SceneChoice,
    controller: Option<CameraController>,
    budget: FrameBudget,
    overlay: Overlay,
    mouse: Mouse,
    modifiers: ModifiersState,
    paused: bool,
    minimized: bool,
    overlay_animating: bool,
    /// The render must start again (camera, size or settings changed).
    restart: bool,
    /// Size and photons of the running render: the frame budget's estimate holds while they
    /// stay (a camera move costs the same per pass).
    render_shape: Option<((u32, u32), u32)>,
    /// Times the photon count may still be lowered for slow passes: a few, early, since each
    /// restarts the render and per-pixel work (not photons) may be what makes a pass slow.
    photon_cuts_left: u32,
    first_frame: Option<Instant>,
    last_frame: Instant,
    schedule: Schedule,
    message: Option<String>,
    paths_checked: Instant,
    radius_checked: Option<Instant>,
    paths_rate: f64,
    last_paths: (u64, f64),
    mean_radius: Option<f32>,
    /// An error that ends the program (reported after the event loop returns).
    pub fatal: Option<anyhow::Error>,
}

impl App {
    pub fn new(
        args: &ViewArgs,
        instance: wgpu::Instance,
        loaded: LoadedScene,
        camera: scene::Camera,
    ) -> anyhow::Result<App> {
        let (schedule, controls) = check_arguments(args)?;
        let choice = SceneChoice::of(&loaded.scene, &args.load.options());
        let now = Instant::now();
        Ok(App {
            instance,
            title: String::new(),
            window_size: (args.width, args.height),
            adapter_filter: args.adapter.clone(),
            render_scale: args.render_scale,
            scale: 1.0,
            photons_override: args.photons,
            bvh_args: args.bvh,
            added_lights: args.added_lights.clone(),
            initial_camera: Some(camera),
            initial_scene: Some(loaded),
            gfx: None,
            session: None,
            loading: None,
            reloading: None,
            shown_choice: choice,
            controller: None,
            budget: FrameBudget::new(TARGET_FRAME),
            overlay: Overlay::new(
                !args.no_overlay,
                render::tonemap::Look {
                    exposure: args.exposure,
                    tone_map: args.tonemap.tone_map(),
                },
                controls,
                choice,
            ),
            mouse: Mouse::default(),
            modifiers: ModifiersState::empty(),
            paused: false,
            minimized: false,
            overlay_animating: false,
            restart: true,
            render_shape: None,
            photon_cuts_left: MAX_PHOTON_CUTS,
            first_frame: None,
            last_frame: now,
            schedule,
            message: None,
            paths_checked: now,
            radius_checked: None,
            paths_rate: 0.0,
            last_paths: (0, 0.0),
            mean_radius: None,
            fatal: None,
        })
    }

    /// Opens the window, the device that presents to it, and uploads the first scene.
    fn open(&mut self, event_loop: &ActiveEventLoop) -> anyhow::Result<()> {
        let loaded = self
            .initial_scene
            .take()
            .context("the scene is already open")?;
        let title = window_title(&loaded.path);
        let attributes = Window::default_attributes()
            .with_title(&title)
            .with_inner_size(winit::dpi::PhysicalSize::new(
                self.window_size.0,
                self.window_size.1,
            ));
        let window = Arc::new(
            event_loop
                .create_window(attributes)
                .context("cannot open a window (use `kousen render` without a display)")?,
        );
        let surface = self
            .instance
            .create_surface(window.clone())
            .context("cannot draw into the window")?;
        let context =
            GpuContext::for_surface(&self.instance, &surface, self.adapter_filter.as_deref())
                .context("no GPU adapter can present to the window (use `kousen render`)")?;
        eprintln!("kousen: viewing on {}", context.description());
        let device_error = Arc::new(Mutex::new(None));
        let sink = device_error.clone();
        context
            .device
            .on_uncaptured_error(Arc::new(move |e: wgpu::Error| {
                let mut first = sink.lock().unwrap_or_else(|p| p.into_inner());
                first.get_or_insert_with(|| e.to_string().replace('\n', " "));
            }));
        let config = surface_config(&surface, &context, window.inner_size())?;
        surface.configure(&context.device, &config);
        let display = DisplayPass::new(&context.device, config.format);
        let egui_ctx = egui::Context::default();
        let egui_state = egui_winit::State::new(
            egui_ctx.clone(),
            egui::ViewportId::ROOT,
            &window,
            Some(window.scale_factor() as f32),
            None,
            Some(context.limits.max_texture_dimension_2d as usize),
        );
        let egui_renderer =
            egui_wgpu::Renderer::new(&context.device, config.format, Default::default());
        self.scale = self
            .render_scale
            .unwrap_or(if context.is_cpu_device() { 0.5 } else { 1.0 });
        if self.photons_override.is_none() {
            let (w, h) = render_size(&config, self.scale);
            self.overlay.controls.photons = initial_photons(w * h, context.is_cpu_device());
        }
        let session = Session::new(&context, loaded)?;
        let camera = self.initial_camera.take().context("no camera")?;
        self.controller = Some(CameraController::new(&camera, session.scene.bounds()));
        self.overlay.controls.lens = session.starting_lens(&camera);
        self.session = Some(session);
        self.title = title;
        self.gfx = Some(Gfx {
            device_error,
            window,
            surface,
            config,
            context,
            display,
            egui_ctx,
            egui_state,
            egui_renderer,
        });
        Ok(())
    }

    fn exit_with(&mut self, event_loop: &ActiveEventLoop, error: anyhow::Error) {
        self.fatal.get_or_insert(error);
        event_loop.exit();
    }

    /// Input the overlay did not take: camera moves and keys.
    fn handle_input(&mut self, event: &WindowEvent) {
        let Some(controller) = &mut self.controller else {
            return;
        };
        match event {
            WindowEvent::ModifiersChanged(m) => self.modifiers = m.state(),
            WindowEvent::MouseInput { state, button, .. } => {
                let down = *state == ElementState::Pressed;
                if down && *button == MouseButton::Left && self.modifiers.control_key() {
                    // Ctrl+click focuses the lens on the surface under the cursor.
                    if let (Some(session), Some(gfx), Some(cursor)) =
                        (&self.session, &self.gfx, self.mouse.position)
                    {
                        let size = Vec2::new(gfx.config.width as f32, gfx.config.height as f32);
                        let film = (2.0 * cursor.x / size.x - 1.0, 1.0 - 2.0 * cursor.y / size.y);
                        let camera = controller.camera();
                        let lens = &mut self.overlay.controls.lens;
                        match session.depth_at(&camera, film, size.x / size.y) {
                            _ if camera.is_orthographic() => {
                                self.message = Some("an orthographic view has no lens".into())
                            }
                            Some(depth) => {
                                lens.focus_distance = depth;
                                self.restart |= !lens.is_pinhole();
                                self.message = Some(format!("focused {depth:.4} ahead"));
                            }
                            None => self.message = Some("nothing there to focus on".into()),
                        }
                    }
                    return;
                }
                match button {
                    MouseButton::Left => self.mouse.left = down,
                    MouseButton::Middle => self.mouse.middle = down,
                    MouseButton::Right => {
                        self.mouse.right = down;
                        if !down {
                            controller.release_keys();
                        }
                    }
                    _ => {}
                }
            }
            WindowEvent::CursorMoved { position, .. } => {
                let position = Vec2::new(position.x as f32, position.y as f32);
                if let Some(last) = self.mouse.position {
                    let mode = drag_mode(
                        self.mouse.left,
                        self.mouse.middle,
                        self.mouse.right,
                        self.modifiers.shift_key(),
                    );
                    let height = self.gfx.as_ref().map_or(1, |g| g.config.height) as f32;
                    if let Some(mode) = mode {
                        self.restart |= controller.drag(mode, position - last, height);
                    }
                }
                self.mouse.position = Some(position);
            }
            WindowEvent::CursorLeft { .. } => self.mouse.position = None,
            WindowEvent::MouseWheel { delta, .. } => {
                let lines = match delta {
                    MouseScrollDelta::LineDelta(_, y) => *y,
                    MouseScrollDelta::PixelDelta(p) => p.y as f32 / 40.0,
                };
                self.restart |= controller.zoom(lines);
            }
            WindowEvent::KeyboardInput { event, .. } => {
                let PhysicalKey::Code(code) = event.physical_key else {
                    return;
                };
                let pressed = event.state == ElementState::Pressed;
                // WASD QE fly while the right button is held (S alone saves).
                if let Some(key) = fly_key(code)
                    && (self.mouse.right || !pressed)
                {
                    controller.key(key, pressed);
                    if self.mouse.right {
                        return;
                    }
                }
                if !pressed || event.repeat {
                    return;
                }
                match code {
                    KeyCode::Space => self.act(Action::TogglePause),
                    KeyCode::KeyR => self.act(Action::Restart),
                    KeyCode::KeyS => self.act(Action::Save),
                    KeyCode::F1 => self.overlay.visible = !self.overlay.visible,
                    KeyCode::Digit0 => self.overlay.parts = Parts::ALL,
                    _ => {
                        if let Some(part) = part_key(code) {
                            let parts = self.overlay.parts;
                            self.overlay.parts = parts.with(part, !parts.shows(part));
                        }
                    }
                }
            }
            _ => {}
        }
    }

    fn act(&mut self, action: Action) {
        log::debug!("view: {action:?}");
        match action {
            Action::TogglePause => self.paused = !self.paused,
            Action::Restart | Action::ControlsChanged => self.restart = true,
            Action::Save => self.save(),
            Action::RemoveSkyMap => self.remove_sky_map(),
            Action::SceneChoiceChanged => {
                // A removal of the sky map under way goes on in the new choice.
                let reason = match self.reloading.take() {
                    Some(removal @ Reload::WithoutSkyMap { .. }) => removal,
                    _ => Reload::Choice,
                };
                self.reload(reason);
            }
            Action::SelectCamera(i) => {
                let camera = self.session.as_ref().and_then(|s| s.scene.camera(Some(i)));
                if let (Some(camera), Some(controller)) = (camera, &mut self.controller) {
                    controller.set_camera(&camera);
                    self.restart = true;
                }
            }
        }
    }

    /// Shows `text` in the overlay, and on stderr for scripts.
    fn notify(&mut self, text: String) {
        eprintln!("kousen: {text}");
        self.message = Some(text);
    }

    /// Writes the image so far as `<scene>-<passes>.exr` and `.png` in the working directory;
    /// where the overlay shows only some parts of the radiance, those, named in the files
    /// (`<scene>-<passes>-direct+caustic.exr`).
    fn save(&mut self) {
        let Some(session) = &mut self.session else {
            return;
        };
        let parts = self.overlay.parts;
        let mut stem = format!("{}-{:05}", session.name(), session.stats().passes);
        if parts != Parts::ALL {
            stem = format!("{stem}-{}", parts.name());
        }
        let written = session.image_of(parts).and_then(|image| {
            for extension in ["exr", "png"] {
                let path = PathBuf::from(format!("{stem}.{extension}"));
                crate::image_io::Output::create_with(&path, Default::default())?
                    .commit(&image, self.overlay.look())?;
            }
            Ok(())
        });
        self.notify(match written {
            Ok(()) => format!("saved {stem}.exr and {stem}.png"),
            Err(e) => format!("cannot save: {e:#}"),
        });
    }

    /// Reads the scene shown again without its sky map (nor later scenes get it), keeping the
    /// view; the map stays if the scene has no light without it.
    fn remove_sky_map(&mut self) {
        if matches!(self.reloading, Some(Reload::WithoutSkyMap { .. })) {
            return; // already being removed
        }
        if self.added_lights.sky_map.is_none() {
            self.notify("there is no sky map to remove".into());
            return;
        }
        let map = self.added_lights.sky_map.take();
        let turn = self.overlay.controls.sky_rotation.take().unwrap_or(0.0);
        self.reload(Reload::WithoutSkyMap { map, turn });
    }

    /// Reads the scene shown again, in the overlay's scene choice and without the lights
    /// taken away, on another thread (the scene stays until it is ready).
    fn reload(&mut self, reason: Reload) {
        let Some(path) = self.session.as_ref().map(|s| s.path.clone()) else {
            return;
        };
        let receive = self.read_scene(&path, self.overlay.scene_choice.options());
        self.notify(format!("reading {} again …", path.display()));
        self.loading = Some((path, receive));
        self.reloading = Some(reason);
    }

    /// Gives up a reading again (it failed, or another file was dropped): a sky map it took
    /// away comes back, and the overlay's choice returns to the scene shown.
    fn abandon_reload(&mut self) {
        if let Some(reason) = self.reloading.take() {
            if let Reload::WithoutSkyMap { map, turn } = reason {
                self.added_lights.sky_map = map;
                self.overlay.controls.sky_rotation = Some(turn);
            }
            self.overlay.scene_choice = self.shown_choice;
        }
    }

    /// Reads the scene at `path` with `options` on another thread.
    fn read_scene(
        &self,
        path: &Path,
        options: scene::LoadOptions,
    ) -> mpsc::Receiver<anyhow::Result<Dropped>> {
        let (send, receive) = mpsc::channel();
        let (owned, bvh_args, added_lights) =
            (path.to_owned(), self.bvh_args, self.added_lights.clone());
        std::thread::spawn(move || {
            let loaded = load_scene(&owned, bvh_args, &added_lights, &options);
            // The receiver may be gone if another file was dropped meanwhile.
            let _ = send.send(loaded.map(|l| Dropped::Scene(Box::new(l))));
        });
        receive
    }

    /// A dropped file: read it on another thread; the current scene stays until it is ready.
    /// A scene opens; an image (.hdr, .exr, .pfm, .png) becomes the sky map, of this scene and
    /// of those opened after it.
    fn open_dropped(&mut self, path: &Path) {
        self.abandon_reload();
        let receive = match dropped_kind(path) {
            // A dropped file shows as its nodes place things, in its own materials.
            Some(DroppedKind::Scene) => self.read_scene(path, scene::LoadOptions::default()),
            Some(DroppedKind::SkyMap) => {
                let (send, receive) = mpsc::channel();
                let owned = path.to_owned();
                std::thread::spawn(move || {
                    let map = crate::image_io::read_sky_map(&owned);
                    // The receiver may be gone if another file was dropped meanwhile.
                    let _ = send.send(map.map(Dropped::SkyMap));
                });
                receive
            }
            None => {
                self.notify(format!(
                    "{}: neither a scene (.gltf, .glb, .obj, Mitsuba .xml, .pbrt) nor a sky map (.hdr, .exr, .pfm, .png)",
                    path.display()
                ));
                return;
            }
        };
        self.notify(format!("loading {} …", path.display()));
        self.loading = Some((path.to_owned(), receive));
    }

    /// Swaps in a dropped scene or sky map once it has been read, or reports why it cannot be.
    fn finish_loading(&mut self) {
        let Some((path, receive)) = &self.loading else {
            return;
        };
        let result = match receive.try_recv() {
            Ok(result) => result,
            Err(mpsc::TryRecvError::Empty) => return,
            Err(mpsc::TryRecvError::Disconnected) => {
                Err(anyhow::anyhow!("the loader stopped unexpectedly"))
            }
        };
        let path = path.clone();
        self.loading = None;
        let Some(gfx) = &self.gfx else {
            return;
        };
        let opened = result.and_then(|dropped| match dropped {
            Dropped::Scene(loaded) => Session::new(&gfx.context, *loaded).map(|s| (s, true)),
            Dropped::SkyMap(map) => {
                let session = self.session.as_ref().context("no scene is open")?;
                // `--sky R,G,B` scales a map, as on the command line; the overlay's turn holds.
                let scale = self
                    .added_lights
                    .sky
                    .map_or(glam::Vec3::ONE, glam::Vec3::from);
                let turn = self.overlay.controls.sky_rotation.unwrap_or(0.0);
                session
                    .with_sky_map(map, scale, turn.to_radians())
                    .map(|s| (s, false))
            }
        });
        match (opened, self.reloading.is_some()) {
            (Ok((session, _)), true) => {
                // The same scene read again: the view, lens and title stay.
                let notice = match self.reloading.take() {
                    Some(Reload::WithoutSkyMap { .. }) => {
                        self.added_lights.sky_rotate = 0.0;
                        format!("removed the sky map from {}", path.display())
                    }
                    _ => format!(
                        "showing {}: {}",
                        path.display(),
                        self.overlay.scene_choice.describe(&session.scene)
                    ),
                };
                self.shown_choice = self.overlay.scene_choice;
                self.session = Some(session);
                self.notify(notice);
                self.restart = true;
            }
            (Ok((session, new_scene)), false) => {
                if new_scene {
                    let camera = session.default_camera();
                    self.controller = Some(CameraController::new(&camera, session.scene.bounds()));
                    self.overlay.controls.lens = session.starting_lens(&camera);
                    self.overlay.scene_choice = SceneChoice::default();
                    self.shown_choice = SceneChoice::default();
                    self.title = window_title(&path);
                    gfx.window.set_title(&self.title);
                } else {
                    // The overlay's slider turns it from now on, and scenes opened later are
                    // lit by it too.
                    let turn = *self.overlay.controls.sky_rotation.get_or_insert(0.0);
                    self.added_lights.sky_map = Some(path.clone());
                    self.added_lights.sky_rotate = turn;
                }
                self.session = Some(session);
                self.photon_cuts_left = MAX_PHOTON_CUTS;
                self.notify(format!("opened {}", path.display()));
                self.restart = true;
            }
            (Err(e), true) => {
                let notice = match self.reloading {
                    Some(Reload::WithoutSkyMap { .. }) => format!("the sky map stays: {e:#}"),
                    _ => format!("cannot show {} so: {e:#}", path.display()),
                };
                self.abandon_reload();
                self.notify(notice);
            }
            (Err(e), false) => self.notify(format!("cannot open {}: {e:#}", path.display())),
        }
    }

    /// One frame: restart if due, passes within the budget, the overlay's figures, drawing,
    /// screenshots.
    fn frame(&mut self, event_loop: &ActiveEventLoop) -> anyhow::Result<()> {
        let now = Instant::now();
        let dt = now.duration_since(self.last_frame).as_secs_f32().min(0.25);
        self.last_frame = now;
        self.finish_loading();
        if let Some(controller) = &mut self.controller {
            self.restart |= controller.update(dt);
        }
        if self.restart {
            self.start_render();
        }
        if !self.paused {
            self.run_passes()?;
        }
        self.refresh_figures();
        self.draw()?;
        if let Some(gfx) = &self.gfx {
            let error = gfx.device_error.lock().unwrap_or_else(|p| p.into_inner());
            if let Some(error) = error.as_ref() {
                anyhow::bail!("the device failed: {error}");
            }
        }
        let first = *self.first_frame.get_or_insert(now);
        let elapsed = first.elapsed().as_secs_f64();
        for event in self.schedule.take_due(elapsed) {
            match event {
                Timed::Screenshot(path) => {
                    self.screenshot(&path)?;
                    eprintln!("kousen: saved {}", path.display());
                }
                Timed::Open(path) => self.open_dropped(&path),
                Timed::RemoveSkyMap => self.remove_sky_map(),
            }
        }
        if self.schedule.should_quit(elapsed) {
            event_loop.exit();
        }
        Ok(())
    }

    fn start_render(&mut self) {
        self.restart = false;
        let (Some(gfx), Some(session), Some(controller)) =
            (&self.gfx, &mut self.session, &self.controller)
        else {
            return;
        };
        let size = render_size(&gfx.config, self.scale);
        let camera = controller.camera();
        match session.restart(&camera, size, self.overlay.controls) {
            Ok(()) => {
                let shape = Some((size, self.overlay.controls.photons));
                if self.render_shape != shape {
                    self.budget.reset();
                    self.render_shape = shape;
                }
                self.mean_radius = None;
                self.radius_checked = None;
                self.paths_rate = 0.0;
                self.last_paths = (0, 0.0);
            }
            Err(e) => self.notify(format!("{e:#}")),
        }
    }

    fn run_passes(&mut self) -> anyhow::Result<()> {
        let Some(session) = &mut self.session else {
            return Ok(());
        };
        if !session.is_running() {
            return Ok(());
        }
        let passes = self.budget.passes_per_frame();
        let started = Instant::now();
        session.run_passes(passes)?;
        self.budget.record(passes, started.elapsed());
        if self.photons_override.is_none()
            && self.photon_cuts_left > 0
            && session.stats().passes <= PHOTON_CUT_MAX_PASSES
            && let Some(fewer) = self.budget.photons_advice(self.overlay.controls.photons)
        {
            log::info!("view: passes are slow; {fewer} photon slots per pass");
            self.photon_cuts_left -= 1;
            self.overlay.controls.photons = fewer;
            self.restart = true;
        }
        Ok(())
    }

    fn refresh_figures(&mut self) {
        let Some(session) = &mut self.session else {
            return;
        };
        if self.paths_checked.elapsed() >= PATHS_REFRESH {
            self.paths_checked = Instant::now();
            if session.refresh_photon_paths().is_ok() {
                let stats = session.stats();
                let (paths, seconds) = self.last_paths;
                let dt = stats.seconds - seconds;
                if dt > 0.0 && stats.photon_paths >= paths {
                    self.paths_rate = (stats.photon_paths - paths) as f64 / dt;
                }
                self.last_paths = (stats.photon_paths, stats.seconds);
            }
        }
        let radius_due = self
            .radius_checked
            .is_none_or(|t| t.elapsed() >= RADIUS_REFRESH);
        if self.overlay.visible && radius_due && session.stats().passes > 0 {
            self.radius_checked = Some(Instant::now());
            self.mean_radius = session.mean_radius().ok().flatten();
        }
    }

    fn draw(&mut self) -> anyhow::Result<()> {
        let Some(gfx) = &mut self.gfx else {
            return Ok(());
        };
        let frame = match gfx.surface.get_current_texture() {
            wgpu::CurrentSurfaceTexture::Success(frame)
            | wgpu::CurrentSurfaceTexture::Suboptimal(frame) => frame,
            wgpu::CurrentSurfaceTexture::Outdated | wgpu::CurrentSurfaceTexture::Lost => {
                // A window closed from outside loses its surface for good.
                anyhow::ensure!(
                    gfx.context.adapter.is_surface_supported(&gfx.surface),
                    "the window's surface is gone"
                );
                gfx.surface.configure(&gfx.context.device, &gfx.config);
                return Ok(());
            }
            other => {
                log::warn!("view: no frame to draw into ({other:?})");
                return Ok(());
            }
        };
        let view = frame
            .texture
            .create_view(&wgpu::TextureViewDescriptor::default());

        // The overlay's layout for this frame.
        let cameras: Vec<String> = self.session.as_ref().map_or_else(Vec::new, |s| {
            s.scene
                .cameras
                .iter()
                .enumerate()
                .map(|(i, c)| {
                    if c.name.is_empty() {
                        format!("{i}")
                    } else {
                        c.name.clone()
                    }
                })
                .collect()
        });
        let adapter = gfx.context.info.name.clone();
        let render_size = render_size(&gfx.config, self.scale);
        let info = OverlayInfo {
            scene: &self.title,
            adapter: &adapter,
            stats: self
                .session
                .as_ref()
                .map(Session::stats)
                .unwrap_or_default(),
            photon_paths_per_second: self.paths_rate,
            mean_radius: self.mean_radius,
            render_size,
            passes_per_frame: self.budget.passes_per_frame(),
            seconds_per_pass: self.budget.seconds_per_pass(),
            paused: self.paused,
            cameras: &cameras,
            message: self.message.as_deref(),
            scene_size: self.session.as_ref().map_or(1.0, Session::scene_size),
            shown: self.session.as_ref().map(|s| &s.scene),
            orthographic: self
                .controller
                .as_ref()
                .is_some_and(|c| c.camera().is_orthographic()),
        };
        let input = gfx.egui_state.take_egui_input(&gfx.window);
        let overlay = &mut self.overlay;
        let mut actions = Vec::new();
        let output = gfx.egui_ctx.run_pass(input, |ctx| {
            actions = overlay.ui(ctx, &info);
        });
        gfx.egui_state
            .handle_platform_output(&gfx.window, output.platform_output);
        // An overlay animation (a hover fading, say) wants the next frame now.
        self.overlay_animating = output
            .viewport_output
            .get(&egui::ViewportId::ROOT)
            .is_some_and(|v| v.repaint_delay.is_zero());
        let jobs = gfx
            .egui_ctx
            .tessellate(output.shapes, output.pixels_per_point);
        let screen = egui_wgpu::ScreenDescriptor {
            size_in_pixels: [gfx.config.width, gfx.config.height],
            pixels_per_point: output.pixels_per_point,
        };
        let device = &gfx.context.device;
        let queue = &gfx.context.queue;
        for (id, deltas) in &output.textures_delta.set {
            for delta in deltas {
                gfx.egui_renderer.update_texture(device, queue, *id, delta);
            }
        }
        let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
            label: Some("view frame"),
        });
        let callbacks =
            gfx.egui_renderer
                .update_buffers(device, queue, &mut encoder, &jobs, &screen);
        {
            let mut pass = encoder
                .begin_render_pass(&wgpu::RenderPassDescriptor {
                    label: Some("view frame"),
                    color_attachments: &[Some(gpu::display::cleared_attachment(&view))],
                    ..Default::default()
                })
                .forget_lifetime();
            if let Some((source, eye_passes)) =
                self.session.as_ref().and_then(Session::display_source)
            {
                gfx.display.set_tone_map(self.overlay.tone_map);
                gfx.display.set_parts(self.overlay.parts);
                gfx.display.draw(
                    device,
                    queue,
                    &mut pass,
                    &source,
                    eye_passes,
                    self.overlay.exposure,
                    (gfx.config.width, gfx.config.height),
                );
            }
            gfx.egui_renderer.render(&mut pass, &jobs, &screen);
        }
        queue.submit(callbacks.into_iter().chain([encoder.finish()]));
        gfx.window.pre_present_notify();
        queue.present(frame);
        for id in &output.textures_delta.free {
            gfx.egui_renderer.free_texture(id);
        }
        let mut applied = output.textures_delta;
        applied.clear();
        for action in actions {
            self.act(action);
        }
        Ok(())
    }

    /// What the window shows (without the overlay), as a PNG.
    fn screenshot(&mut self, path: &Path) -> anyhow::Result<()> {
        let (Some(gfx), Some(session)) = (&mut self.gfx, &self.session) else {
            return Ok(());
        };
        let (source, eye_passes) = session
            .display_source()
            .context("no render to take a screenshot of")?;
        let size = (gfx.config.width, gfx.config.height);
        gfx.display.set_tone_map(self.overlay.tone_map);
        gfx.display.set_parts(self.overlay.parts);
        let rgba = gfx.display.capture(
            &gfx.context,
            &source,
            eye_passes,
            self.overlay.exposure,
            size,
        )?;
        super::screenshot::write_png(path, size, &rgba)
    }

    /// Whether frames must keep coming without input.
    fn is_animating(&self) -> bool {
        let flying = self.controller.as_ref().is_some_and(|c| c.is_flying());
        let busy = !self.paused
            || flying
            || self.restart
            || self.loading.is_some()
            || self.overlay_animating;
        !self.minimized && (busy || self.schedule.is_pending())
    }
}

impl ApplicationHandler for App {
    fn resumed(&mut self, event_loop: &ActiveEventLoop) {
        if self.gfx.is_some() {
            return;
        }
        if let Err(e) = self.open(event_loop) {
            self.exit_with(event_loop, e);
        }
    }

    fn window_event(&mut self, event_loop: &ActiveEventLoop, _: WindowId, event: WindowEvent) {
        let Some(gfx) = &mut self.gfx else {
            return;
        };
        let response = gfx.egui_state.on_window_event(&gfx.window, &event);
        // egui asks to repaint after every redraw too; that would never let the loop sleep.
        if response.repaint && event != WindowEvent::RedrawRequested {
            gfx.window.request_redraw();
        }
        match &event {
            WindowEvent::CloseRequested | WindowEvent::Destroyed => event_loop.exit(),
            WindowEvent::Resized(size) => {
                self.minimized = size.width == 0 || size.height == 0;
                let changed = (size.width, size.height) != (gfx.config.width, gfx.config.height);
                if !self.minimized && changed {
                    gfx.config.width = size.width;
                    gfx.config.height = size.height;
                    gfx.surface.configure(&gfx.context.device, &gfx.config);
                    self.restart = true;
                    self.photon_cuts_left = MAX_PHOTON_CUTS;
                }
            }
            WindowEvent::Occluded(occluded) => self.minimized = *occluded,
            WindowEvent::DroppedFile(path) => {
                let path = path.clone();
                self.open_dropped(&path);
            }
            WindowEvent::RedrawRequested => {
                if !self.minimized
                    && let Err(e) = self.frame(event_loop)
                {
                    self.exit_with(event_loop, e);
                }
            }
            // Releases always reach the camera, so a drag or a fly key let go over the
            // overlay does not stick.
            _ if !response.consumed || is_release(&event) => self.handle_input(&event),
            _ => {}
        }
    }

    fn about_to_wait(&mut self, event_loop: &ActiveEventLoop) {
        // Draw continuously while converging; sleep until the next event when paused or
        // minimised (no busy loop).
        if self.is_animating() {
            if let Some(gfx) = &self.gfx {
                gfx.window.request_redraw();
            }
            event_loop.set_control_flow(ControlFlow::Poll);
        } else {
            event_loop.set_control_flow(ControlFlow::Wait);
        }
    }
}

/// Every argument checked before a window opens: the schedule and the render's controls.
pub fn check_arguments(args: &ViewArgs) -> anyhow::Result<(Schedule, RenderControls)> {
    let schedule = Schedule::new(
        &args.screenshot_after,
        &args.open_after,
        args.remove_sky_map_after,
        args.quit_after,
    )?;
    if let Some(s) = args.render_scale {
        anyhow::ensure!(
            s.is_finite() && s > 0.0 && s <= 4.0,
            "--render-scale must be in (0, 4], got {s}"
        );
    }
    anyhow::ensure!(args.photons != Some(0), "--photons must be at least 1");
    let controls = RenderControls {
        photons: args.photons.unwrap_or(1 << 16),
        alpha: args.gather.alpha,
        eye_every: args.eye_every,
        indirect_alpha: args.gather.indirect_alpha,
        radius_footprints: args.gather.radius_footprints()?,
        caustic_radius_share: args
            .gather
            .caustic_radius_share(args.estimator.direct_light.direct()),
        density: args.estimator.density,
        precision: args.estimator.precision.precision(),
        direct: args.estimator.direct_light.direct(),
        glossy_light_sampling: args.estimator.glossy_light
            == crate::cli::GlossyLightChoice::Sampled,
        light_candidates: args.estimator.light_candidates.0.unwrap_or(0),
        sky_rotation: args
            .added_lights
            .sky_map
            .is_some()
            .then(|| wrapped_degrees(args.added_lights.sky_rotate)),
        // The chosen camera's, once the scene is loaded (`Session::starting_lens`).
        lens: scene::Lens::PINHOLE,
    };
    render::Settings {
        alpha: controls.alpha,
        indirect_alpha: controls.indirect_alpha,
        caustic_radius_share: controls.caustic_radius_share,
        eye_every: controls.eye_every,
        light_candidates: args.estimator.light_candidates.0,
        ..render::Settings::new(1, 1, controls.photons)
    }
    .validate()?;
    Ok((schedule, controls))
}

/// `degrees` turned into (−180, 180], the overlay slider's range.
fn wrapped_degrees(degrees: f32) -> f32 {
    let wrapped = (degrees + 180.0).rem_euclid(360.0) - 180.0;
    if wrapped == -180.0 { 180.0 } else { wrapped }
}

fn window_title(path: &Path) -> String {
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    format!("kousen — {name}")
}

fn is_release(event: &WindowEvent) -> bool {
    match event {
        WindowEvent::MouseInput { state, .. } => *state == ElementState::Released,
        WindowEvent::KeyboardInput { event, .. } => event.state == ElementState::Released,
        WindowEvent::ModifiersChanged(_) => true,
        _ => false,
    }
}

/// The part of the radiance (`render::resolve::COMPONENTS`) keys 1 to 4 show or hide.
fn part_key(code: KeyCode) -> Option<usize> {
    Some(match code {
        KeyCode::Digit1 => 0,
        KeyCode::Digit2 => 1,
        KeyCode::Digit3 => 2,
        KeyCode::Digit4 => 3,
        _ => return None,
    })
}

fn fly_key(code: KeyCode) -> Option<FlyKey> {
    Some(match code {
        KeyCode::KeyW => FlyKey::Forward,
        KeyCode::KeyS => FlyKey::Back,
        KeyCode::KeyA => FlyKey::Left,
        KeyCode::KeyD => FlyKey::Right,
        KeyCode::KeyE => FlyKey::Up,
        KeyCode::KeyQ => FlyKey::Down,
        _ => return None,
    })
}

/// The render's size: the window's scaled, at least 1×1.
fn render_size(config: &wgpu::SurfaceConfiguration, scale: f32) -> (u32, u32) {
    let scaled = |n: u32| ((n as f32 * scale).round() as u32).max(1);
    (scaled(config.width), scaled(config.height))
}

/// A gamma-space (non-sRGB) 8-bit format where the surface has one: egui blends in gamma
/// space, and the display pass then applies the sRGB transfer itself.
fn surface_config(
    surface: &wgpu::Surface,
    context: &GpuContext,
    size: winit::dpi::PhysicalSize<u32>,
) -> anyhow::Result<wgpu::SurfaceConfiguration> {
    let caps = surface.get_capabilities(&context.adapter);
    let format = caps
        .formats
        .iter()
        .copied()
        .find(|f| {
            matches!(
                f,
                wgpu::TextureFormat::Bgra8Unorm | wgpu::TextureFormat::Rgba8Unorm
            )
        })
        .or_else(|| caps.formats.first().copied())
        .context("the window's surface offers no format")?;
    Ok(wgpu::SurfaceConfiguration {
        usage: wgpu::TextureUsages::RENDER_ATTACHMENT,
        format,
        color_space: wgpu::SurfaceColorSpace::Auto,
        width: size.width.max(1),
        height: size.height.max(1),
        present_mode: wgpu::PresentMode::AutoVsync,
        desired_maximum_frame_latency: 2,
        alpha_mode: caps
            .alpha_modes
            .first()
            .copied()
            .unwrap_or(wgpu::CompositeAlphaMode::Auto),
        view_formats: vec![],
    })
}

#[cfg(test)]
mod tests {
    use super::{DroppedKind, dropped_kind, wrapped_degrees};
    use std::path::Path;

    #[test]
    fn dropped_files_are_scenes_or_sky_maps_by_extension() {
        for (name, kind) in [
            ("a/room.gltf", Some(DroppedKind::Scene)),
            ("room.GLB", Some(DroppedKind::Scene)),
            ("room.obj", Some(DroppedKind::Scene)),
            ("room.xml", Some(DroppedKind::Scene)),
            ("room.pbrt", Some(DroppedKind::Scene)),
            ("room.pbrt.gz", Some(DroppedKind::Scene)),
            ("sky.gz", None),
            ("sky.hdr", Some(DroppedKind::SkyMap)),
            ("sky.EXR", Some(DroppedKind::SkyMap)),
            ("sky.pfm", Some(DroppedKind::SkyMap)),
            ("sky.png", Some(DroppedKind::SkyMap)),
            ("notes.txt", None),
            ("no_extension", None),
        ] {
            assert_eq!(dropped_kind(Path::new(name)), kind, "{name}");
        }
    }

    #[test]
    fn sky_turns_wrap_into_the_sliders_range() {
        for (given, wrapped) in [
            (0.0, 0.0),
            (150.0, 150.0),
            (180.0, 180.0),
            (-180.0, 180.0),
            (400.0, 40.0),
            (-190.0, 170.0),
            (720.0, 0.0),
        ] {
            assert_eq!(wrapped_degrees(given), wrapped, "{given}");
        }
    }
}
