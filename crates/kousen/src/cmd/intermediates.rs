//! `kousen render --save-at 16,64,256,30s`: images of one render as it converges, for
//! convergence plots and equal-time comparisons without rendering again. Each moment is a
//! pass count (`64`: once 64 passes are done, a resumed render's included) or this run's
//! rendering time (`30s`); its image goes beside the output, named by it (`out-64.exr`,
//! `out-30s.exr`), written whole or not at all like the output, and `--stats` lists how far
//! the render had come at each. Writing them is left out of the render's clock
//! (`render::RunHooks`), so `--time` and the seconds reported count rendering only.

use std::path::{Path, PathBuf};

use anyhow::bail;
use render::{Budget, Intermediate, SaveAt};
use serde::Serialize;

use crate::image_io::{ExrPrecision, Output};

/// One moment of --save-at: `N` passes (N ≥ 1) or `Ts` seconds (T > 0).
pub fn parse_save_at(text: &str) -> Result<SaveAt, String> {
    let text = text.trim();
    let problem = || format!("\"{text}\" is neither a pass count (64) nor seconds (30s)");
    match text.strip_suffix('s') {
        Some(seconds) => match seconds.parse::<f64>() {
            Ok(s) if s.is_finite() && s > 0.0 => Ok(SaveAt::Seconds(s)),
            _ => Err(problem()),
        },
        None => match text.parse::<u32>() {
            Ok(n) if n >= 1 => Ok(SaveAt::Passes(n)),
            _ => Err(problem()),
        },
    }
}

/// The moment as --save-at spells it, which names its file.
fn spelled(at: SaveAt) -> String {
    match at {
        SaveAt::Passes(n) => n.to_string(),
        SaveAt::Seconds(s) => format!("{s}s"),
    }
}

/// `out.exr` with the moment after its stem: `out-64.exr`.
fn path_at(output: &Path, at: SaveAt) -> PathBuf {
    super::render::beside(output, &format!("-{}", spelled(at)))
}

/// How far a render had come when an image was saved, for --stats.
#[derive(Serialize)]
pub struct SavedImage {
    pub file: String,
    pub passes: u32,
    pub eye_passes: u32,
    pub photon_paths: u64,
    pub seconds: f64,
}

/// The images --save-at asks for, each file made ready before the render starts (so a bad
/// path fails first), and those written so far.
pub struct Intermediates {
    pending: Vec<(SaveAt, PathBuf, Option<Output>)>,
    pub saved: Vec<SavedImage>,
}

impl Intermediates {
    /// The files for `moments` beside `output`, which must all lie within `budget` where it
    /// can tell (pass counts under a pass budget, seconds under a time budget).
    pub fn create(
        output: &Path,
        moments: &[SaveAt],
        precision: ExrPrecision,
        budget: Budget,
    ) -> anyhow::Result<Intermediates> {
        let mut pending: Vec<(SaveAt, PathBuf, Option<Output>)> = Vec::new();
        for &at in moments {
            let beyond = match (at, budget) {
                (SaveAt::Passes(n), Budget::Passes(total)) => n > total,
                (SaveAt::Seconds(s), Budget::Time(total)) => s > total.as_secs_f64(),
                _ => false,
            };
            if beyond {
                bail!("--save-at {}: past the render's end", spelled(at));
            }
            if pending.iter().any(|(other, ..)| *other == at) {
                continue;
            }
            let path = path_at(output, at);
            let file = Output::create_with(&path, precision)?;
            pending.push((at, path, Some(file)));
        }
        Ok(Intermediates {
            pending,
            saved: Vec::new(),
        })
    }

    /// Forgets the pass counts a resumed render has already passed (`passes`), saying so.
    pub fn skip_passed(&mut self, passes: u32) {
        self.pending.retain(|(at, ..)| match *at {
            SaveAt::Passes(n) if n <= passes => {
                log::warn!("--save-at {n}: the resumed render is past it (pass {passes})");
                false
            }
            _ => true,
        });
    }

    /// The moments still to save at.
    pub fn moments(&self) -> Vec<SaveAt> {
        self.pending.iter().map(|(at, ..)| *at).collect()
    }

    /// Says which moments the render ended before (their files are never written).
    pub fn warn_unreached(&self) {
        for (at, _, file) in &self.pending {
            if file.is_some() {
                log::warn!("--save-at {}: the render ended before it", spelled(*at));
            }
        }
    }

    /// Writes `intermediate`'s image to its moment's file (`look`: a PNG's exposure and tone
    /// map).
    pub fn save(
        &mut self,
        intermediate: &Intermediate,
        look: render::tonemap::Look,
    ) -> Result<(), String> {
        let Some((_, path, file)) =
            (self.pending.iter_mut()).find(|(at, ..)| *at == intermediate.at)
        else {
            return Ok(());
        };
        let Some(file) = file.take() else {
            return Ok(());
        };
        file.commit(intermediate.image, look)
            .map_err(|e| format!("--save-at {}: {e:#}", spelled(intermediate.at)))?;
        self.saved.push(SavedImage {
            file: path.display().to_string(),
            passes: intermediate.passes,
            eye_passes: intermediate.eye_passes,
            photon_paths: intermediate.photon_paths,
            seconds: intermediate.seconds,
        });
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn moments_are_pass_counts_or_seconds_and_name_their_files() {
        assert_eq!(parse_save_at("64"), Ok(SaveAt::Passes(64)));
        assert_eq!(parse_save_at(" 2.5s"), Ok(SaveAt::Seconds(2.5)));
        for bad in ["0", "-3", "0s", "xs", "1e99999s", "s", ""] {
            assert!(parse_save_at(bad).is_err(), "{bad}");
        }
        let out = Path::new("renders/cc.exr");
        assert_eq!(
            path_at(out, SaveAt::Passes(64)),
            Path::new("renders/cc-64.exr")
        );
        assert_eq!(
            path_at(out, SaveAt::Seconds(30.0)),
            Path::new("renders/cc-30s.exr")
        );
    }
}
