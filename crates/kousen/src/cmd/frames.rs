//! `kousen render --frames FIRST-LAST [--fps N]`: a glTF animation rendered frame by frame,
//! each frame a whole render of the scene posed at its moment (`--animation-time`), written
//! beside the output named by its number: `out.png` → `out-0001.png`, `out-0002.png`, …

use std::path::PathBuf;
use std::sync::Arc;
use std::sync::atomic::AtomicBool;

use anyhow::bail;

use crate::cli::RenderArgs;

/// Frames `first` to `last`, both included.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct FrameRange {
    pub first: u32,
    pub last: u32,
}

/// At least this many digits in a frame's number (more where the last frame needs them), as
/// Blender and most compositors number image sequences.
const FRAME_DIGITS: usize = 4;

/// Parses `FIRST-LAST` or a single frame `N` (frames from 0).
pub fn parse_frames(text: &str) -> Result<FrameRange, String> {
    let number = |part: &str| {
        part.trim()
            .parse::<u32>()
            .map_err(|_| format!("\"{part}\" is not a frame number (0, 1, 2, …)"))
    };
    let (first, last) = match text.split_once('-') {
        Some((first, last)) => (number(first)?, number(last)?),
        None => number(text).map(|frame| (frame, frame))?,
    };
    if last < first {
        return Err(format!(
            "the last frame ({last}) comes before the first ({first})"
        ));
    }
    Ok(FrameRange { first, last })
}

impl FrameRange {
    /// The file frame `frame` is written to, beside `output`.
    pub fn path_of(&self, output: &std::path::Path, frame: u32) -> PathBuf {
        let digits = FRAME_DIGITS.max(self.last.to_string().len());
        super::render::beside(output, &format!("-{frame:0digits$}"))
    }
}

/// Renders each frame of `frames` as `kousen render` renders one image, stopping at the first
/// that fails or is interrupted (Ctrl-C: that frame's image is still written, as a render's
/// is, and no later frame is started).
pub fn run(args: &RenderArgs, frames: FrameRange, stop: Arc<AtomicBool>) -> anyhow::Result<()> {
    if !(args.fps.is_finite() && args.fps > 0.0) {
        bail!(
            "--fps must be a positive number of frames per second, got {}",
            args.fps
        );
    }
    if args.checkpoint.is_some() || args.resume.is_some() {
        bail!(
            "--checkpoint and --resume are for one image, not --frames (a sequence stopped part way goes on with --skip-existing)"
        );
    }
    let count = frames.last - frames.first + 1;
    for (k, frame) in (frames.first..=frames.last).enumerate() {
        let seconds = frame as f32 / args.fps;
        let output = frames.path_of(&args.output, frame);
        // Images are written whole or not at all, so one that is there is finished.
        if args.skip_existing && output.exists() {
            eprintln!(
                "kousen: frame {frame}: {} is there, left out",
                output.display()
            );
            continue;
        }
        let mut one = args.clone();
        one.frames = None;
        one.load.animation_time = Some(seconds);
        one.output = output;
        one.stats = (args.stats.as_deref()).map(|stats| frames.path_of(stats, frame));
        eprintln!(
            "kousen: frame {frame} ({} of {count}, {seconds:.3} s) → {}",
            k + 1,
            one.output.display()
        );
        super::render::run_until(&one, stop.clone())?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frame_ranges_parse_or_say_why_not() {
        assert_eq!(parse_frames("1-48"), Ok(FrameRange { first: 1, last: 48 }));
        assert_eq!(parse_frames("7"), Ok(FrameRange { first: 7, last: 7 }));
        assert!(parse_frames("9-3").unwrap_err().contains("comes before"));
        assert!(
            parse_frames("a-3")
                .unwrap_err()
                .contains("not a frame number")
        );
        assert!(parse_frames("-3").is_err());
    }

    #[test]
    fn frames_are_numbered_beside_the_output() {
        let short = FrameRange { first: 0, last: 48 };
        let path = short.path_of(std::path::Path::new("shots/walk.png"), 7);
        assert_eq!(path, PathBuf::from("shots/walk-0007.png"));
        let long = FrameRange {
            first: 0,
            last: 12_000,
        };
        let path = long.path_of(std::path::Path::new("walk.exr"), 7);
        assert_eq!(path, PathBuf::from("walk-00007.exr"));
    }
}
