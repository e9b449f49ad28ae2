//! The egui overlay: figures of the running render and its controls. It only reports what the
//! user asked for; the app acts on it.

use render::resolve::{COMPONENTS, Parts};
use render::tonemap::{Look, ToneMap};

use super::scene_choice::SceneChoice;
use super::session::{RenderControls, SessionStats};

/// What the overlay shows besides its own controls.
pub struct OverlayInfo<'a> {
    pub scene: &'a str,
    pub adapter: &'a str,
    pub stats: SessionStats,
    pub photon_paths_per_second: f64,
    pub mean_radius: Option<f32>,
    pub render_size: (u32, u32),
    pub passes_per_frame: u32,
    pub seconds_per_pass: Option<f64>,
    pub paused: bool,
    pub cameras: &'a [String],
    /// The last error or notice (loading failures, saved files).
    pub message: Option<&'a str>,
    /// The scene's bounding-box diagonal: the lens sliders' scale.
    pub scene_size: f32,
    /// The scene shown: the animations and material variants it offers.
    pub shown: Option<&'a scene::Scene>,
    /// Whether the view is orthographic (a lens has nothing to do then).
    pub orthographic: bool,
}

/// A request from the overlay.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Action {
    TogglePause,
    Restart,
    Save,
    SelectCamera(usize),
    /// `Overlay::controls` changed: restart with them.
    ControlsChanged,
    /// Light the scene without its sky map again (and the scenes opened after).
    RemoveSkyMap,
    /// `Overlay::scene_choice` changed: read the file again so.
    SceneChoiceChanged,
}

pub struct Overlay {
    pub visible: bool,
    /// Stops; applied by the display pass, no restart.
    pub exposure: f32,
    /// Applied by the display pass too (`--tonemap`, then the overlay's switch).
    pub tone_map: ToneMap,
    /// The parts of the radiance shown and saved (`render::resolve::COMPONENTS`), all at
    /// first; the display pass applies them, no restart.
    pub parts: Parts,
    pub controls: RenderControls,
    /// The animation moment and material variant asked for (the scene shown may still be
    /// being read so).
    pub scene_choice: SceneChoice,
}

/// Photon slots per pass offered: 2^10 … 2^22.
const PHOTONS_LOG2: std::ops::RangeInclusive<u32> = 10..=22;

impl Overlay {
    pub fn new(
        visible: bool,
        look: Look,
        controls: RenderControls,
        scene_choice: SceneChoice,
    ) -> Overlay {
        Overlay {
            visible,
            exposure: look.exposure,
            tone_map: look.tone_map,
            parts: Parts::ALL,
            controls,
            scene_choice,
        }
    }

    /// The exposure and tone map the window shows and saves with.
    pub fn look(&self) -> Look {
        Look {
            exposure: self.exposure,
            tone_map: self.tone_map,
        }
    }

    /// Lays the overlay out for this frame; returns what the user asked for.
    pub fn ui(&mut self, ctx: &egui::Context, info: &OverlayInfo) -> Vec<Action> {
        let mut actions = Vec::new();
        if !self.visible {
            return actions;
        }
        egui::Window::new("kousen")
            .default_pos([8.0, 8.0])
            .resizable(false)
            .show(ctx, |ui| {
                self.figures(ui, info);
                ui.separator();
                self.controls_ui(ui, info, &mut actions);
                if let Some(message) = info.message {
                    ui.separator();
                    ui.add(egui::Label::new(message).wrap());
                }
            });
        actions
    }

    fn figures(&self, ui: &mut egui::Ui, info: &OverlayInfo) {
        let stats = &info.stats;
        egui::Grid::new("figures").num_columns(2).show(ui, |ui| {
            let mut row = |name: &str, value: String| {
                ui.label(name);
                ui.label(value);
                ui.end_row();
            };
            row("scene", info.scene.to_owned());
            row("adapter", info.adapter.to_owned());
            row(
                "image",
                format!("{} × {}", info.render_size.0, info.render_size.1),
            );
            row(
                "estimator",
                format!(
                    "{}, {} photons, direct light: {}",
                    self.controls.density.for_view().name(),
                    self.controls.precision.name(),
                    self.controls.direct.name()
                ),
            );
            row(
                "passes",
                format!(
                    "{} ({} eye), {} per frame",
                    stats.passes, stats.eye_passes, info.passes_per_frame
                ),
            );
            row(
                "pass time",
                info.seconds_per_pass
                    .map_or_else(|| "—".to_owned(), |s| format!("{:.2} ms", s * 1e3)),
            );
            row(
                "photon paths/s",
                format!("{:.3} M", info.photon_paths_per_second / 1e6),
            );
            row(
                "mean radius",
                info.mean_radius
                    .map_or_else(|| "—".to_owned(), |r| format!("{r:.4}")),
            );
            row(
                "elapsed",
                format!(
                    "{:.1} s{}",
                    stats.seconds,
                    if info.paused { " (paused)" } else { "" }
                ),
            );
        });
    }

    fn controls_ui(&mut self, ui: &mut egui::Ui, info: &OverlayInfo, actions: &mut Vec<Action>) {
        ui.add(egui::Slider::new(&mut self.exposure, -8.0..=8.0).text("exposure (stops)"));
        ui.horizontal(|ui| {
            ui.label("tone map");
            for tone_map in [ToneMap::Clamp, ToneMap::Neutral] {
                ui.radio_value(&mut self.tone_map, tone_map, tone_map.name());
            }
        });
        ui.horizontal(|ui| {
            ui.label("show");
            for (k, name) in COMPONENTS.iter().enumerate() {
                let mut shown = self.parts.shows(k);
                if ui.checkbox(&mut shown, *name).changed() {
                    self.parts = self.parts.with(k, shown);
                }
            }
        });

        let mut log2 = self.controls.photons.max(1).ilog2();
        let photons = ui.add(
            egui::Slider::new(&mut log2, PHOTONS_LOG2)
                .text("photons per pass")
                .custom_formatter(|v, _| format!("2^{v} = {}", 1u64 << v as u32)),
        );
        let alpha =
            ui.add(egui::Slider::new(&mut self.controls.alpha, 0.05..=0.95).text("α (caustics)"));
        let eye_every =
            ui.add(egui::Slider::new(&mut self.controls.eye_every, 1..=64).text("eye pass every"));
        let most = render::resampling::MAX_LIGHT_CANDIDATES;
        let candidates = ui.add(
            egui::Slider::new(&mut self.controls.light_candidates, 0..=most)
                .text("light candidates")
                .custom_formatter(|v, _| match v as u32 {
                    0 => "auto".to_owned(),
                    n => n.to_string(),
                }),
        );
        if photons.changed() {
            self.controls.photons = 1 << log2;
        }
        if [&photons, &alpha, &eye_every, &candidates]
            .into_iter()
            .any(settled)
        {
            actions.push(Action::ControlsChanged);
        }
        if !info.orthographic {
            self.lens_ui(ui, info, actions);
        }
        if let Some(degrees) = &mut self.controls.sky_rotation {
            let turn = ui.add(
                egui::Slider::new(degrees, -180.0..=180.0)
                    .text("sky map turn (°)")
                    .step_by(1.0),
            );
            if settled(&turn) {
                actions.push(Action::ControlsChanged);
            }
            if ui.button("remove the sky map").clicked() {
                actions.push(Action::RemoveSkyMap);
            }
        }
        if let Some(scene) = info.shown
            && self.scene_choice.ui(ui, scene)
        {
            actions.push(Action::SceneChoiceChanged);
        }

        if !info.cameras.is_empty() {
            ui.horizontal_wrapped(|ui| {
                ui.label("camera");
                for (i, name) in info.cameras.iter().enumerate() {
                    if ui.button(name).clicked() {
                        actions.push(Action::SelectCamera(i));
                    }
                }
            });
        }
        ui.horizontal(|ui| {
            let pause = if info.paused { "resume" } else { "pause" };
            if ui.button(format!("{pause} (Space)")).clicked() {
                actions.push(Action::TogglePause);
            }
            if ui.button("restart (R)").clicked() {
                actions.push(Action::Restart);
            }
            if ui.button("save EXR + PNG (S)").clicked() {
                actions.push(Action::Save);
            }
        });
        ui.small("drag: orbit · shift/middle: pan · wheel: zoom · right + WASD QE: fly · F1: hide");
    }

    /// The thin lens's sliders: aperture, then (once it is open) blades and focus.
    fn lens_ui(&mut self, ui: &mut egui::Ui, info: &OverlayInfo, actions: &mut Vec<Action>) {
        let lens = &mut self.controls.lens;
        let size = info.scene_size.max(f32::MIN_POSITIVE);
        let aperture = ui.add(
            egui::Slider::new(&mut lens.radius, 0.0..=0.05 * size)
                .logarithmic(true)
                .smallest_positive(1e-5 * size as f64)
                .text("aperture radius"),
        );
        if settled(&aperture) {
            actions.push(Action::ControlsChanged);
        }
        if !lens.is_pinhole() {
            let before = lens.blades;
            let blades = ui.add(
                egui::Slider::new(&mut lens.blades, 0..=scene::Lens::MAX_BLADES)
                    .text("aperture blades (0: round)"),
            );
            // One or two blades make no polygon: step past them, away from where it was.
            if (1..3).contains(&lens.blades) {
                lens.blades = if before == 0 { 3 } else { 0 };
            }
            if settled(&blades) {
                actions.push(Action::ControlsChanged);
            }
            let focus = ui.add(
                egui::Slider::new(&mut lens.focus_distance, 1e-3 * size..=4.0 * size)
                    .logarithmic(true)
                    .text("focus distance (Ctrl+click)"),
            );
            if settled(&focus) {
                actions.push(Action::ControlsChanged);
            }
        }
    }
}

/// Whether a slider's change should restart the render: once it is let go, not at every step
/// of a drag.
pub fn settled(r: &egui::Response) -> bool {
    r.changed() && !r.dragged() || r.drag_stopped()
}
