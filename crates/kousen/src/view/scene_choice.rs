//! What of a glTF file the window shows beyond its default: a moment of one of its animations
//! and one of its material variants (`--animation-time`, `--animation`, `--variant`, then the
//! overlay's choosers). Changing it reads the file again with `scene::LoadOptions`.

use scene::{AnimationTime, LoadOptions, Scene};

#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SceneChoice {
    /// The animation (its index) and the moment of it, in seconds; `None`: the scene as its
    /// nodes place things.
    pub animation: Option<(usize, f32)>,
    /// The material variant (its index); `None`: the file's own materials.
    pub variant: Option<usize>,
}

impl SceneChoice {
    /// The choice `options` made of `scene` (loaded with them).
    pub fn of(scene: &Scene, options: &LoadOptions) -> SceneChoice {
        let seconds = options.animation.as_ref().map(|a| a.seconds);
        SceneChoice {
            animation: options.animation_index(scene).zip(seconds),
            variant: options.variant_index(scene),
        }
    }

    /// The options that load the file so (animations and variants named by index).
    pub fn options(&self) -> LoadOptions {
        LoadOptions {
            animation: self.animation.map(|(index, seconds)| AnimationTime {
                animation: Some(index.to_string()),
                seconds,
            }),
            variant: self.variant.map(|index| index.to_string()),
        }
    }

    /// The choice in words, for the overlay's notices.
    pub fn describe(&self, scene: &Scene) -> String {
        let animation = match self.animation {
            Some((index, seconds)) => {
                let name = scene.animations.get(index).and_then(|a| a.name.as_deref());
                format!("animation {} at {seconds:.2} s", labelled(index, name))
            }
            None => "no animation".to_owned(),
        };
        let variant = match self.variant {
            Some(index) => {
                let name = scene.variants.get(index).map(String::as_str);
                format!("variant {}", labelled(index, name))
            }
            None => "its own materials".to_owned(),
        };
        format!("{animation}, {variant}")
    }

    /// The overlay's choosers for `scene`'s animations and variants (none where it has
    /// neither); true once a choice is made that the file must be read again for (a time
    /// slider let go, not each step of its drag).
    pub fn ui(&mut self, ui: &mut egui::Ui, scene: &Scene) -> bool {
        let mut chosen = false;
        if !scene.animations.is_empty() {
            let before = self.animation.map(|(index, _)| index);
            let mut index = before;
            let clip_label = |index: Option<usize>| match index {
                Some(i) => labelled(i, scene.animations[i].name.as_deref()),
                None => "none (as placed)".to_owned(),
            };
            egui::ComboBox::from_label("animation")
                .selected_text(clip_label(index))
                .show_ui(ui, |ui| {
                    for option in std::iter::once(None).chain((0..scene.animations.len()).map(Some))
                    {
                        ui.selectable_value(&mut index, option, clip_label(option));
                    }
                });
            if index != before {
                let seconds = self.animation.map_or(0.0, |(_, s)| s);
                self.animation = index.map(|i| (i, seconds));
                chosen = true;
            }
            if let Some((index, seconds)) = &mut self.animation {
                let length = scene.animations[*index].seconds.max(0.0);
                let slider = ui.add_enabled(
                    length > 0.0,
                    egui::Slider::new(seconds, 0.0..=length).text("time (s)"),
                );
                chosen |= super::overlay::settled(&slider);
            }
        }
        if !scene.variants.is_empty() {
            let before = self.variant;
            let variant_label = |index: Option<usize>| match index {
                Some(i) => labelled(i, Some(&scene.variants[i])),
                None => "none (own materials)".to_owned(),
            };
            egui::ComboBox::from_label("material variant")
                .selected_text(variant_label(self.variant))
                .show_ui(ui, |ui| {
                    for option in std::iter::once(None).chain((0..scene.variants.len()).map(Some)) {
                        ui.selectable_value(&mut self.variant, option, variant_label(option));
                    }
                });
            chosen |= self.variant != before;
        }
        chosen
    }
}

/// An item's index and its name, if it has one: `1 "walk"`.
fn labelled(index: usize, name: Option<&str>) -> String {
    match name {
        Some(name) if !name.is_empty() => format!("{index} \"{name}\""),
        _ => index.to_string(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scene_with_choices() -> Scene {
        let clip = |name: Option<&str>, seconds| scene::AnimationClip {
            name: name.map(str::to_owned),
            seconds,
        };
        Scene {
            animations: vec![clip(Some("walk"), 2.0), clip(None, 1.0)],
            variants: vec!["red".to_owned(), "blue".to_owned()],
            ..Scene::default()
        }
    }

    /// The command line's choice (by name or index) shows in the overlay as the same clip and
    /// variant, and the options the overlay reloads with choose them again.
    #[test]
    fn a_choice_survives_the_trip_through_load_options() {
        let scene = scene_with_choices();
        let given = LoadOptions {
            animation: Some(AnimationTime {
                animation: Some("walk".to_owned()),
                seconds: 1.25,
            }),
            variant: Some("blue".to_owned()),
        };
        let choice = SceneChoice::of(&scene, &given);
        assert_eq!(
            choice,
            SceneChoice {
                animation: Some((0, 1.25)),
                variant: Some(1),
            }
        );
        assert_eq!(SceneChoice::of(&scene, &choice.options()), choice);
        assert_eq!(
            choice.describe(&scene),
            "animation 0 \"walk\" at 1.25 s, variant 1 \"blue\""
        );

        // The first clip where `--animation-time` names none; unnamed clips by index.
        let first = LoadOptions {
            animation: Some(AnimationTime {
                animation: None,
                seconds: 0.5,
            }),
            variant: None,
        };
        assert_eq!(SceneChoice::of(&scene, &first).animation, Some((0, 0.5)));
        let unnamed = SceneChoice {
            animation: Some((1, 0.0)),
            variant: None,
        };
        assert_eq!(SceneChoice::of(&scene, &unnamed.options()), unnamed);
        assert_eq!(
            unnamed.describe(&scene),
            "animation 1 at 0.00 s, its own materials"
        );
        let none = SceneChoice::default();
        assert_eq!(none.options(), LoadOptions::default());
        assert_eq!(SceneChoice::of(&scene, &LoadOptions::default()), none);
    }
}
