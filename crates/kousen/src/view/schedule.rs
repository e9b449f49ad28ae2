//! Timed screenshots, scene opening, sky map removal and quitting (`--screenshot-after`,
//! `--open-after`, `--remove-sky-map-after`, `--quit-after`): what scripts and the end-to-end test use to drive the window without input.

use std::path::PathBuf;

use anyhow::{Context, bail, ensure};

/// Something to do at a set time.
#[derive(Clone, Debug, PartialEq)]
pub enum Timed {
    /// Save what the window shows as this PNG.
    Screenshot(PathBuf),
    /// Open this scene file as if dropped on the window.
    Open(PathBuf),
    /// Press the overlay's "remove the sky map".
    RemoveSkyMap,
}

#[derive(Debug, Default)]
pub struct Schedule {
    /// (seconds after the first frame, what), earliest first; done ones are removed.
    events: Vec<(f64, Timed)>,
    quit_after: Option<f64>,
}

impl Schedule {
    /// From `--screenshot-after SECONDS PATH` and `--open-after SECONDS PATH` pairs (flattened,
    /// as clap gives them), `--remove-sky-map-after SECONDS` and `--quit-after SECONDS`.
    pub fn new(
        screenshots: &[String],
        opens: &[String],
        remove_sky_map_after: Option<f64>,
        quit_after: Option<f64>,
    ) -> anyhow::Result<Schedule> {
        let mut events = Vec::new();
        for (flag, pairs) in [("--screenshot-after", screenshots), ("--open-after", opens)] {
            ensure!(
                pairs.len().is_multiple_of(2),
                "{flag} takes SECONDS and PATH"
            );
            for pair in pairs.chunks(2) {
                let seconds = parse_seconds(&pair[0])
                    .with_context(|| format!("{flag} {} {}", pair[0], pair[1]))?;
                let path = PathBuf::from(&pair[1]);
                let event = if flag == "--open-after" {
                    Timed::Open(path)
                } else {
                    let is_png = path
                        .extension()
                        .is_some_and(|e| e.eq_ignore_ascii_case("png"));
                    ensure!(
                        is_png,
                        "{flag} {}: screenshots are written as .png",
                        path.display()
                    );
                    Timed::Screenshot(path)
                };
                events.push((seconds, event));
            }
        }
        if let Some(seconds) = remove_sky_map_after {
            let seconds = parse_seconds(&seconds.to_string()).context("--remove-sky-map-after")?;
            events.push((seconds, Timed::RemoveSkyMap));
        }
        // Stable: events at the same time keep their command-line order.
        events.sort_by(|a, b| a.0.total_cmp(&b.0));
        if let Some(q) = quit_after {
            parse_seconds(&q.to_string()).context("--quit-after")?;
        }
        Ok(Schedule { events, quit_after })
    }

    /// What is due `elapsed` seconds after the first frame, removed from the schedule.
    pub fn take_due(&mut self, elapsed: f64) -> Vec<Timed> {
        let due = self.events.partition_point(|(t, _)| *t <= elapsed);
        self.events.drain(..due).map(|(_, event)| event).collect()
    }

    /// Whether to close the window: the quit time has come and everything else is done.
    pub fn should_quit(&self, elapsed: f64) -> bool {
        self.quit_after.is_some_and(|q| elapsed >= q) && self.events.is_empty()
    }

    /// Whether anything is left to do (the window must keep drawing frames for it).
    pub fn is_pending(&self) -> bool {
        !self.events.is_empty() || self.quit_after.is_some()
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

    fn shot(path: &str) -> Timed {
        Timed::Screenshot(PathBuf::from(path))
    }

    #[test]
    fn events_come_due_in_time_order_once() {
        let mut s = Schedule::new(
            &pairs(&["8", "b.png", "2", "a.png"]),
            &pairs(&["4", "next.glb"]),
            Some(6.0),
            Some(9.0),
        )
        .unwrap();
        assert!(s.take_due(1.0).is_empty());
        assert_eq!(s.take_due(2.5), vec![shot("a.png")]);
        assert!(s.take_due(2.6).is_empty(), "a shot is taken once");
        assert_eq!(s.take_due(4.0), vec![Timed::Open("next.glb".into())]);
        assert_eq!(s.take_due(7.0), vec![Timed::RemoveSkyMap]);
        assert!(!s.should_quit(8.5), "b.png is still due");
        assert_eq!(s.take_due(100.0), vec![shot("b.png")]);
        assert!(!s.should_quit(8.9));
        assert!(s.should_quit(9.0));
    }

    #[test]
    fn quit_waits_for_late_events() {
        let mut s = Schedule::new(&pairs(&["5", "a.png"]), &[], None, Some(1.0)).unwrap();
        assert!(!s.should_quit(2.0));
        s.take_due(5.0);
        assert!(s.should_quit(5.0));
    }

    #[test]
    fn without_flags_nothing_is_pending() {
        let s = Schedule::new(&[], &[], None, None).unwrap();
        assert!(!s.is_pending());
        assert!(!s.should_quit(1e6));
    }

    #[test]
    fn bad_arguments_are_refused() {
        assert!(Schedule::new(&pairs(&["x", "a.png"]), &[], None, None).is_err());
        assert!(Schedule::new(&pairs(&["-1", "a.png"]), &[], None, None).is_err());
        assert!(Schedule::new(&pairs(&["1", "a.exr"]), &[], None, None).is_err());
        assert!(Schedule::new(&pairs(&["inf", "a.png"]), &[], None, None).is_err());
        assert!(Schedule::new(&[], &pairs(&["soon", "a.glb"]), None, None).is_err());
        assert!(Schedule::new(&[], &[], None, Some(f64::NAN)).is_err());
        assert!(Schedule::new(&[], &[], Some(-2.0), None).is_err());
    }
}
