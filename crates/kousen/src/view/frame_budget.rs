//! How much rendering work one viewer frame does, so that the window stays responsive (about
//! 30 frames/s) on a fast GPU, where a pass takes well under a millisecond, and on lavapipe,
//! where one pass can take a tenth of a second or more.

use std::time::Duration;

/// The frame time the viewer aims for.
pub const TARGET_FRAME: Duration = Duration::from_millis(33);
/// Most SPPM passes run in one frame; more would only delay input handling for little gain.
pub const MAX_PASSES_PER_FRAME: u32 = 64;
/// Fewest photon slots per pass that `photons_advice` and `initial_photons` suggest.
pub const MIN_PHOTONS: u32 = 1024;
/// Most photon slots per pass to start with on a CPU-type adapter (lavapipe) and on a GPU.
pub const CPU_PHOTON_CAP: u32 = 1 << 14;
pub const GPU_PHOTON_CAP: u32 = 1 << 20;
/// Weight of the newest frame in the per-pass time estimate.
const SMOOTHING: f64 = 0.3;
/// A single pass slower than this many targets makes the frame count as slow.
const SLOW_PASS_TARGETS: f64 = 2.0;
/// Consecutive slow frames before advising fewer photons; one slow frame may be start-up work
/// such as shader compilation.
const SLOW_FRAMES_FOR_ADVICE: u32 = 5;

/// Chooses the number of SPPM passes per frame from measured frame times.
#[derive(Clone, Debug)]
pub struct FrameBudget {
    target: Duration,
    passes_per_frame: u32,
    /// Exponential moving average of the seconds one pass takes.
    seconds_per_pass: Option<f64>,
    /// Frames in a row whose passes each took longer than `SLOW_PASS_TARGETS` targets.
    slow_frames: u32,
}

impl FrameBudget {
    /// A budget aiming at `target` per frame; starts at one pass per frame.
    pub fn new(target: Duration) -> Self {
        FrameBudget {
            target,
            passes_per_frame: 1,
            seconds_per_pass: None,
            slow_frames: 0,
        }
    }

    /// Passes to run in the next frame, in [1, `MAX_PASSES_PER_FRAME`].
    pub fn passes_per_frame(&self) -> u32 {
        self.passes_per_frame
    }

    /// After a frame that ran `passes` passes in `elapsed` (wall time of the work, including
    /// waiting for the GPU): updates the smoothed per-pass time and picks the next count so that
    /// a frame fits the target. The count at most doubles per frame, so one fast outlier cannot
    /// cause a long stall; it drops at once when passes get slower. Frames with no passes (paused,
    /// say) tell nothing and are ignored.
    pub fn record(&mut self, passes: u32, elapsed: Duration) {
        if passes == 0 {
            return;
        }
        let per_pass = elapsed.as_secs_f64() / f64::from(passes);
        let estimate = match self.seconds_per_pass {
            Some(previous) => previous + SMOOTHING * (per_pass - previous),
            None => per_pass,
        };
        self.seconds_per_pass = Some(estimate);

        let target = self.target.as_secs_f64();
        self.slow_frames = if per_pass > SLOW_PASS_TARGETS * target {
            self.slow_frames.saturating_add(1)
        } else {
            0
        };

        let fitting = if estimate > 0.0 {
            // The tiny margin keeps an exact fit (33 ms / 1 ms) from rounding down to 32.
            (target / estimate * (1.0 + 1e-9)).floor()
        } else {
            f64::INFINITY
        };
        let ceiling = self
            .passes_per_frame
            .saturating_mul(2)
            .min(MAX_PASSES_PER_FRAME);
        // `as` saturates; the clamp keeps at least one pass even when one overruns the target.
        self.passes_per_frame = (fitting.min(f64::from(ceiling)) as u32).max(1);
    }

    /// The smoothed time of one pass, once a frame with passes has been recorded.
    pub fn seconds_per_pass(&self) -> Option<f64> {
        self.seconds_per_pass
    }

    /// Photon slots per pass for a new render when passes are too slow: once several frames in
    /// a row each took more than twice the target for a single pass, half of
    /// `current_photons` (never below `MIN_PHOTONS`); otherwise, or when `current_photons` is
    /// already at the minimum, `None`. The app calls it after `record`, restarts with the count
    /// and calls `reset`, so each further halving needs fresh evidence.
    pub fn photons_advice(&self, current_photons: u32) -> Option<u32> {
        let too_slow = self.slow_frames >= SLOW_FRAMES_FOR_ADVICE;
        (too_slow && current_photons > MIN_PHOTONS).then(|| (current_photons / 2).max(MIN_PHOTONS))
    }

    /// After a restart: forgets the estimate and the slow-frame evidence, back to one pass per
    /// frame.
    pub fn reset(&mut self) {
        *self = FrameBudget::new(self.target);
    }
}

/// Photon slots per pass to start with: one per pixel, clamped to [`MIN_PHOTONS`, cap] where
/// the cap is `CPU_PHOTON_CAP` on CPU-type adapters (lavapipe) and `GPU_PHOTON_CAP` on GPUs.
pub fn initial_photons(pixels: u32, cpu_adapter: bool) -> u32 {
    let cap = if cpu_adapter {
        CPU_PHOTON_CAP
    } else {
        GPU_PHOTON_CAP
    };
    pixels.clamp(MIN_PHOTONS, cap)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ms(millis: u64) -> Duration {
        Duration::from_millis(millis)
    }

    /// Runs one frame of the planned passes at `per_pass` each; returns the passes it ran.
    fn frame(budget: &mut FrameBudget, per_pass: Duration) -> u32 {
        let passes = budget.passes_per_frame();
        budget.record(passes, per_pass * passes);
        passes
    }

    #[test]
    fn starts_at_one_pass_without_an_estimate() {
        let budget = FrameBudget::new(TARGET_FRAME);
        assert_eq!(budget.passes_per_frame(), 1);
        assert_eq!(budget.seconds_per_pass(), None);
        assert_eq!(budget.photons_advice(1 << 20), None);
    }

    #[test]
    fn fast_passes_grow_by_at_most_double_up_to_the_fit() {
        let mut budget = FrameBudget::new(TARGET_FRAME);
        let counts: Vec<u32> = (0..8).map(|_| frame(&mut budget, ms(1))).collect();
        assert_eq!(counts, [1, 2, 4, 8, 16, 32, 33, 33]);
        let estimate = budget.seconds_per_pass().unwrap();
        assert!((estimate - 0.001).abs() < 1e-12);
    }

    #[test]
    fn very_fast_passes_saturate_at_the_cap() {
        let mut budget = FrameBudget::new(TARGET_FRAME);
        for _ in 0..20 {
            frame(&mut budget, Duration::from_micros(10));
            assert!(budget.passes_per_frame() <= MAX_PASSES_PER_FRAME);
        }
        assert_eq!(budget.passes_per_frame(), MAX_PASSES_PER_FRAME);
    }

    #[test]
    fn instant_frames_do_not_break_the_estimate() {
        let mut budget = FrameBudget::new(TARGET_FRAME);
        for _ in 0..10 {
            frame(&mut budget, Duration::ZERO);
        }
        assert_eq!(budget.passes_per_frame(), MAX_PASSES_PER_FRAME);
        assert_eq!(budget.seconds_per_pass(), Some(0.0));
    }

    #[test]
    fn slow_passes_keep_one_per_frame() {
        let mut budget = FrameBudget::new(TARGET_FRAME);
        for _ in 0..20 {
            assert_eq!(frame(&mut budget, ms(100)), 1);
        }
        assert_eq!(budget.passes_per_frame(), 1);
    }

    #[test]
    fn a_zero_target_still_runs_one_pass() {
        let mut budget = FrameBudget::new(Duration::ZERO);
        frame(&mut budget, ms(1));
        assert_eq!(budget.passes_per_frame(), 1);
    }

    #[test]
    fn follows_a_change_in_speed() {
        let mut budget = FrameBudget::new(TARGET_FRAME);
        for _ in 0..10 {
            frame(&mut budget, ms(100));
        }
        assert_eq!(budget.passes_per_frame(), 1);

        for _ in 0..40 {
            frame(&mut budget, ms(1));
        }
        let fast = budget.passes_per_frame();
        assert!((30..=33).contains(&fast), "{fast}");

        // Slow again: the very next frame cuts back to a single pass.
        frame(&mut budget, ms(100));
        assert_eq!(budget.passes_per_frame(), 1);
        for _ in 0..10 {
            frame(&mut budget, ms(100));
        }
        assert_eq!(budget.passes_per_frame(), 1);
    }

    #[test]
    fn one_fast_outlier_only_doubles() {
        let mut budget = FrameBudget::new(TARGET_FRAME);
        for _ in 0..5 {
            frame(&mut budget, ms(20));
        }
        assert_eq!(budget.passes_per_frame(), 1);
        budget.record(1, Duration::from_micros(1));
        assert_eq!(budget.passes_per_frame(), 2);
    }

    #[test]
    fn zero_pass_frames_change_nothing() {
        let mut budget = FrameBudget::new(TARGET_FRAME);
        for _ in 0..3 {
            frame(&mut budget, ms(2));
        }
        let passes = budget.passes_per_frame();
        let estimate = budget.seconds_per_pass();
        budget.record(0, ms(500));
        budget.record(0, Duration::ZERO);
        assert_eq!(budget.passes_per_frame(), passes);
        assert_eq!(budget.seconds_per_pass(), estimate);

        // Nor do they count towards or break a run of slow frames.
        let mut budget = FrameBudget::new(TARGET_FRAME);
        for _ in 0..SLOW_FRAMES_FOR_ADVICE - 1 {
            frame(&mut budget, ms(100));
            budget.record(0, ms(1));
        }
        assert_eq!(budget.photons_advice(1 << 14), None);
        frame(&mut budget, ms(100));
        assert_eq!(budget.photons_advice(1 << 14), Some(1 << 13));
    }

    #[test]
    fn no_photon_advice_for_fast_passes() {
        let mut budget = FrameBudget::new(TARGET_FRAME);
        for _ in 0..50 {
            frame(&mut budget, ms(1));
            assert_eq!(budget.photons_advice(1 << 20), None);
        }
        // Slow but within twice the target: one pass per frame, no advice.
        for _ in 0..50 {
            frame(&mut budget, ms(60));
            assert_eq!(budget.photons_advice(1 << 20), None);
        }
        assert_eq!(budget.passes_per_frame(), 1);
    }

    #[test]
    fn photon_advice_halves_after_consistently_slow_frames() {
        let mut budget = FrameBudget::new(TARGET_FRAME);
        for _ in 0..SLOW_FRAMES_FOR_ADVICE - 1 {
            frame(&mut budget, ms(150));
            assert_eq!(budget.photons_advice(1 << 14), None, "too early");
        }
        frame(&mut budget, ms(150));
        assert_eq!(budget.photons_advice(1 << 14), Some(1 << 13));
        assert_eq!(budget.photons_advice(1500), Some(MIN_PHOTONS));
        assert_eq!(budget.photons_advice(MIN_PHOTONS), None);
        assert_eq!(budget.photons_advice(10), None);

        // After the restart the evidence starts over.
        budget.reset();
        assert_eq!(budget.photons_advice(1 << 13), None);
    }

    #[test]
    fn a_slow_start_up_frame_gives_no_photon_advice() {
        let mut budget = FrameBudget::new(TARGET_FRAME);
        // Shader compilation makes the first frame take seconds.
        budget.record(1, Duration::from_secs(5));
        assert_eq!(budget.photons_advice(1 << 20), None);
        for _ in 0..30 {
            frame(&mut budget, ms(1));
            assert_eq!(budget.photons_advice(1 << 20), None);
        }
        assert!(budget.passes_per_frame() > 1);
    }

    #[test]
    fn a_fast_frame_breaks_a_run_of_slow_ones() {
        let mut budget = FrameBudget::new(TARGET_FRAME);
        for _ in 0..SLOW_FRAMES_FOR_ADVICE - 1 {
            frame(&mut budget, ms(150));
        }
        frame(&mut budget, ms(10));
        for _ in 0..SLOW_FRAMES_FOR_ADVICE - 1 {
            frame(&mut budget, ms(150));
            assert_eq!(budget.photons_advice(1 << 14), None);
        }
        frame(&mut budget, ms(150));
        assert!(budget.photons_advice(1 << 14).is_some());
    }

    #[test]
    fn reset_forgets_the_estimate() {
        let mut budget = FrameBudget::new(TARGET_FRAME);
        for _ in 0..10 {
            frame(&mut budget, ms(1));
        }
        assert!(budget.passes_per_frame() > 1);
        budget.reset();
        assert_eq!(budget.passes_per_frame(), 1);
        assert_eq!(budget.seconds_per_pass(), None);

        // The first frame after the reset sets the estimate outright.
        budget.record(1, ms(7));
        assert_eq!(budget.seconds_per_pass(), Some(0.007));
    }

    #[test]
    fn initial_photons_is_one_per_pixel_within_the_caps() {
        assert_eq!(initial_photons(0, false), MIN_PHOTONS);
        assert_eq!(initial_photons(10, true), MIN_PHOTONS);
        assert_eq!(initial_photons(5000, true), 5000);
        assert_eq!(initial_photons(5000, false), 5000);
        assert_eq!(initial_photons(1920 * 1080, true), CPU_PHOTON_CAP);
        assert_eq!(initial_photons(1920 * 1080, false), GPU_PHOTON_CAP);
        assert_eq!(initial_photons(640 * 480, false), 640 * 480);
        assert_eq!(initial_photons(u32::MAX, false), GPU_PHOTON_CAP);
    }
}
