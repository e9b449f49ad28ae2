//! The render's progress bar (indicatif) on a terminal; nothing otherwise, so logs and
//! scripts stay quiet.

use std::io::IsTerminal;

use indicatif::{ProgressDrawTarget, ProgressStyle};
use render::{Budget, Progress};

pub struct ProgressBar {
    bar: Option<indicatif::ProgressBar>,
}

impl ProgressBar {
    pub fn new(budget: Budget) -> ProgressBar {
        if !std::io::stderr().is_terminal() {
            return ProgressBar { bar: None };
        }
        let (length, template) = match budget {
            Budget::Passes(n) => (
                n as u64,
                "{bar:30} {pos}/{len} passes  {msg}  {elapsed_precise} ETA {eta}",
            ),
            Budget::Time(t) => (
                t.as_millis() as u64,
                "{bar:30} {msg}  {elapsed_precise} of the time asked",
            ),
        };
        let bar = indicatif::ProgressBar::with_draw_target(
            Some(length),
            ProgressDrawTarget::stderr_with_hz(4),
        );
        if let Ok(style) = ProgressStyle::with_template(template) {
            bar.set_style(style);
        }
        ProgressBar { bar: Some(bar) }
    }

    pub fn update(&mut self, progress: &Progress) {
        let Some(bar) = &self.bar else {
            return;
        };
        let seconds = progress.elapsed.as_secs_f64().max(1e-9);
        bar.set_message(format!(
            "{} passes, {:.2} M photon paths/s",
            progress.passes,
            progress.photon_paths as f64 / seconds * 1e-6
        ));
        match progress.budget {
            Budget::Passes(_) => bar.set_position(progress.passes as u64),
            Budget::Time(_) => bar.set_position(progress.elapsed.as_millis() as u64),
        }
    }

    pub fn finish(&mut self) {
        if let Some(bar) = self.bar.take() {
            bar.finish_and_clear();
        }
    }
}
