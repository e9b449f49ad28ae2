//! Timed screenshots and quitting (`--screenshot-after`, `--quit-after`): what scripts and the
//! end-to-end test use to drive the window without input.

use std::path::PathBuf;

use anyhow::{Context, bail, ensure};

#[derive(Debug, Default)]
pub struct Schedule {
    /// (seconds after the first frame, PNG path), earliest first; taken ones are removed.
    shots: Vec<(f64, PathBuf)>,
    quit_after: Option<f64>,
}

impl Schedule {
    /// From `--screenshot-after SECONDS PATH` pairs (flattened, as clap gives them) and
    /// `--quit-after SECONDS`.
    pub fn new(pairs: &[String], quit_after: Option<f64>) -> anyhow::Result<Schedule> {
        ensure!(
            pairs.len().is_multiple_of(2),
            "--screenshot-after takes SECONDS and PATH"
        );
        let mut shots = Vec::new();
        for pair in pairs.chunks(2) {
            let seconds = parse_seconds(&pair[0])
                .with_context(|| format!("--screenshot-after {} {}", pair[0], pair[1]))?;
            let path = PathBuf::from(&pair[1]);
            let is_png = path
                .extension()
                .is_some_and(|e| e.eq_ignore_ascii_case("png"));
            ensure!(
                is_png,
                "--screenshot-after {}: screenshots are written as .png",
                path.display()
            );
            shots.push((seconds, path));
        }
        shots.sort_by(|a, b| a.0.total_cmp(&b.0));
        if let Some(q) = quit_after {
            parse_seconds(&q.to_string()).context("--quit-after")?;
        }
        Ok(Schedule { shots, quit_after })
    }

    /// The screenshots due `elapsed` seconds after the first frame, removed from the schedule.
    pub fn take_due(&mut self, elapsed: f64) -> Vec<PathBuf> {
        let due = self.shots.partition_point(|(t, _)| *t <= elapsed);
        self.shots.drain(..due).map(|(_, path)| path).collect()
    }

    /// Whether to close the window: the quit time has come and every screenshot is taken.
    pub fn should_quit(&self, elapsed: f64) -> bool {
        self.quit_after.is_some_and(|q| elapsed >= q) && self.shots.is_empty()
    }

    /// Whether anything is left to do (the window must keep drawing frames for it).
    pub fn is_pending(&self) -> bool {
        !self.shots.is_empty() || self.quit_after.is_some()
    }
}

fn parse_seconds(text: &str) -> anyhow::Result<f64> {
    let seconds: f64 = text
        .parse()
        .with_context(|| format!("{text:?} is not a number of seconds"))?;
    if !(seconds.is_finite() && (0.0..1e9).contains(&seconds)) {
        bail!("{text} is not a number of seconds ≥ 0");
    }
    Ok(seconds)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn pairs(items: &[&str]) -> Vec<String> {
        items.iter().map(|s| s.to_string()).collect()
    }

    #[test]
    fn shots_come_due_in_time_order_once() {
        let mut s = Schedule::new(&pairs(&["8", "b.png", "2", "a.png"]), Some(9.0)).unwrap();
        assert!(s.take_due(1.0).is_empty());
        assert_eq!(s.take_due(2.5), vec![PathBuf::from("a.png")]);
        assert!(s.take_due(2.6).is_empty(), "a shot is taken once");
        assert!(!s.should_quit(8.5), "b.png is still due");
        assert_eq!(s.take_due(100.0), vec![PathBuf::from("b.png")]);
        assert!(!s.should_quit(8.9));
        assert!(s.should_quit(9.0));
    }

    #[test]
    fn quit_waits_for_late_screenshots() {
        let mut s = Schedule::new(&pairs(&["5", "a.png"]), Some(1.0)).unwrap();
        assert!(!s.should_quit(2.0));
        s.take_due(5.0);
        assert!(s.should_quit(5.0));
    }

    #[test]
    fn without_flags_nothing_is_pending() {
        let s = Schedule::new(&[], None).unwrap();
        assert!(!s.is_pending());
        assert!(!s.should_quit(1e6));
    }

    #[test]
    fn bad_arguments_are_refused() {
        assert!(Schedule::new(&pairs(&["x", "a.png"]), None).is_err());
        assert!(Schedule::new(&pairs(&["-1", "a.png"]), None).is_err());
        assert!(Schedule::new(&pairs(&["1", "a.exr"]), None).is_err());
        assert!(Schedule::new(&pairs(&["inf", "a.png"]), None).is_err());
        assert!(Schedule::new(&[], Some(f64::NAN)).is_err());
    }
}
